#include "optimizers/function_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "optimizers/exact_poses.h"

namespace linkfit {
namespace {

// A miss of the crank's reach weighs like this many radians of output error per unit of
// |C| / hypot(A, B) - 1.
constexpr double kMissWeight = 10.0;

// One pair's residuals, with s = sqrt(w):
//   r0 = s wrap(t4 - o4 - psi),  t4 = OutputCrankAngle(a, b, c, 1, o2 + phi; sigma)
//   r1 = s kMissWeight miss        (0 where the input is within the crank's reach)
// wrap(x) = atan2(sin x, cos x). lengths = (a, b, c) / d; offsets = (o2, o4).
// The transmission penalty's threshold: cos of the smallest transmission angle allowed (plus a
// 1 degree margin), or 2 (no penalty) without one.
double TransmissionCosine(std::optional<double> min_transmission_deg) {
  if (!min_transmission_deg) return 2.0;
  return std::cos(std::min(*min_transmission_deg + 1.0, 90.0) * M_PI / 180.0);
}

// The transmission penalty at crank angle t2 (lengths scaled by d = `ground`):
// max(0, |cos mu| - limit), cos mu = (b^2 + c^2 - |P - B|^2) / (2bc).
template <typename T>
T TransmissionExcess(const T& a, const T& b, const T& c, const T& ground, const T& t2,
                     double limit) {
  using std::abs;
  using std::cos;
  if (limit >= 1.0) return T(0.0);
  const T s = a * a + ground * ground - T(2.0) * a * ground * cos(t2);
  const T excess = abs((b * b + c * c - s) / (T(2.0) * b * c)) - T(limit);
  return excess > T(0.0) ? excess : T(0.0);
}

struct OutputAngleResidual {
  OutputAngleResidual(const FunctionPair& pair, int sigma, double weight, double limit)
      : pair_(pair), sigma_(sigma), scale_(std::sqrt(weight)), limit_(limit) {}

  template <typename T>
  bool operator()(const T* lengths, const T* offsets, T* residuals) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    T t4, miss;
    OutputCrankAngle<T>(lengths[0], lengths[1], lengths[2], T(1.0), offsets[0] + T(pair_.input),
                        sigma_, &t4, &miss);
    const T error = t4 - offsets[1] - T(pair_.output);
    residuals[0] = T(scale_) * atan2(sin(error), cos(error));
    residuals[1] = T(scale_ * kMissWeight) * miss;
    residuals[2] =
        T(scale_ * kMissWeight) * TransmissionExcess<T>(lengths[0], lengths[1], lengths[2], T(1.0),
                                                        offsets[0] + T(pair_.input), limit_);
    return true;
  }

  static ceres::CostFunction* Create(const FunctionPair& pair, int sigma, double weight,
                                     double limit) {
    return new ceres::AutoDiffCostFunction<OutputAngleResidual, 3, 3, 2>(
        new OutputAngleResidual(pair, sigma, weight, limit));
  }

 private:
  FunctionPair pair_;
  int sigma_;
  double scale_;
  double limit_;
};

// The four-bar's fit with the task's weights: errors at the nearest stationary configuration
// where an input is beyond reach (and the miss in the cost).
internal::DyadFit Fit(const FunctionFourBar& f, const std::vector<FunctionPair>& pairs,
                      double exact_tolerance, std::optional<double> min_transmission_deg) {
  std::vector<double> weights;
  std::vector<bool> exact;
  for (const FunctionPair& pair : pairs) {
    weights.push_back(pair.weight);
    exact.push_back(pair.exact);
  }
  internal::DyadFit fit = internal::EvaluateFit(weights, exact, exact_tolerance, [&](size_t j) {
    return ReachedOutputError(f, pairs[j], f.assembly);
  });
  fit.cost = FunctionCost(f, pairs, min_transmission_deg);
  return fit;
}

}  // namespace

double FunctionCost(const FunctionFourBar& f, const std::vector<FunctionPair>& pairs,
                    std::optional<double> min_transmission_deg) {
  const double limit = TransmissionCosine(min_transmission_deg);
  double cost = 0.0;
  for (const FunctionPair& pair : pairs) {
    double miss;
    const double error = ReachedOutputError(f, pair, f.assembly, &miss);
    const double excess =
        TransmissionExcess<double>(f.input_length, f.coupler_length, f.output_length, f.ground,
                                   f.input_offset + pair.input, limit);
    cost += 0.5 * pair.weight *
            (error * error + kMissWeight * kMissWeight * (miss * miss + excess * excess));
  }
  return std::isfinite(cost) ? cost : std::numeric_limits<double>::infinity();
}

RefinerSummary RefineFunctionFourBar(const std::vector<FunctionPair>& pairs,
                                     FunctionFourBar* four_bar,
                                     const FunctionRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (pairs.size() < 2) throw std::invalid_argument("RefineFunctionFourBar: fewer than 2 pairs");
  if (!four_bar->Valid()) throw std::invalid_argument("RefineFunctionFourBar: invalid four-bar");
  const double d = four_bar->ground;
  const internal::DyadFit seed_fit =
      Fit(*four_bar, pairs, options.exact_tolerance, options.min_transmission_deg);
  RefinerSummary summary;
  summary.initial_cost = seed_fit.cost;
  summary.initial_max = seed_fit.max;

  double lengths[3] = {four_bar->input_length / d, four_bar->coupler_length / d,
                       four_bar->output_length / d};
  double offsets[2] = {four_bar->input_offset, four_bar->output_offset};
  const bool any_exact =
      std::any_of(pairs.begin(), pairs.end(), [](const FunctionPair& p) { return p.exact; });
  double penalty = 1.0;
  FunctionFourBar best = *four_bar;
  internal::DyadFit best_fit = seed_fit;
  for (int round = 0; round < (any_exact ? options.max_penalty_rounds : 1); ++round) {
    ceres::Problem problem;
    for (const FunctionPair& pair : pairs) {
      problem.AddResidualBlock(
          OutputAngleResidual::Create(pair, four_bar->assembly,
                                      pair.weight * (pair.exact ? penalty : 1.0),
                                      TransmissionCosine(options.min_transmission_deg)),
          nullptr, lengths, offsets);
    }
    for (int i = 0; i < 3; ++i) {
      problem.SetParameterLowerBound(lengths, i, 1e-6);
      if (std::isfinite(options.max_link_length)) {
        problem.SetParameterUpperBound(lengths, i, std::max(options.max_link_length, 2e-6));
      }
    }
    if (!options.free_offsets) problem.SetParameterBlockConstant(offsets);
    ceres::Solver::Options solver;
    solver.max_num_iterations = options.max_iterations;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.function_tolerance = 1e-15;
    solver.parameter_tolerance = 1e-14;
    solver.num_threads = 1;
    ceres::Solver::Summary ceres_summary;
    ceres::Solve(solver, &problem, &ceres_summary);
    summary.iterations += static_cast<int>(ceres_summary.iterations.size());
    summary.message = ceres_summary.message;
    FunctionFourBar candidate = *four_bar;
    candidate.input_length = lengths[0] * d;
    candidate.coupler_length = lengths[1] * d;
    candidate.output_length = lengths[2] * d;
    candidate.input_offset = WrapToPi(offsets[0]);
    candidate.output_offset = WrapToPi(offsets[1]);
    if (candidate.Valid()) {
      const internal::DyadFit fit =
          Fit(candidate, pairs, options.exact_tolerance, options.min_transmission_deg);
      if (internal::Better(fit, best_fit)) {
        best = candidate;
        best_fit = fit;
      }
      if (fit.meets_exact) break;
    }
    penalty *= internal::kPenaltyGrowth;
  }
  *four_bar = best;
  summary.final_cost = best_fit.cost;
  summary.final_max = best_fit.max;
  double weights = 0.0;
  for (const FunctionPair& pair : pairs) weights += pair.weight;
  summary.initial_rms = std::sqrt(2.0 * summary.initial_cost / weights);
  summary.final_rms = std::sqrt(2.0 * summary.final_cost / weights);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace linkfit
