#include "optimizers/spherical_dyad_refiner.h"

#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <string>

#include "optimizers/exact_poses.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

// Residual of a spherical dyad at rotation R with the current weight w, parameters u, v (unit)
// and alpha:
//   e = sqrt(w) (atan2(|u x R v|, u . R v) - alpha).
// At u x R v = 0 the angle is not differentiable; its subgradient 0 is used there.
class ConeResidual {
 public:
  ConeResidual(const Eigen::Matrix3d& rotation, const double* sqrt_weight)
      : rotation_(rotation), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* fixed_axis, const T* moving_axis, const T* angle, T* residual) const {
    T turned[3];
    for (int i = 0; i < 3; ++i) {
      turned[i] = rotation_(i, 0) * moving_axis[0] + rotation_(i, 1) * moving_axis[1] +
                  rotation_(i, 2) * moving_axis[2];
    }
    const T cross[3] = {fixed_axis[1] * turned[2] - fixed_axis[2] * turned[1],
                        fixed_axis[2] * turned[0] - fixed_axis[0] * turned[2],
                        fixed_axis[0] * turned[1] - fixed_axis[1] * turned[0]};
    const T dot = fixed_axis[0] * turned[0] + fixed_axis[1] * turned[1] + fixed_axis[2] * turned[2];
    const T squared = cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2];
    using std::atan2;
    using std::sqrt;
    const T sine = squared > T(0.0) ? T(sqrt(squared)) : T(0.0);
    residual[0] = *sqrt_weight_ * (atan2(sine, dot) - angle[0]);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& rotation, const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<ConeResidual, 1, 3, 3, 1>(
        new ConeResidual(rotation, sqrt_weight));
  }

 private:
  Eigen::Matrix3d rotation_;
  const double* sqrt_weight_;  // changed between penalty rounds
};

}  // namespace

RefinerSummary RefineSphericalDyad(const std::vector<Eigen::Matrix3d>& rotations,
                                   const std::vector<double>& weights_in,
                                   const std::vector<bool>& exact_in, SphericalDyad* dyad,
                                   const SphericalDyadRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const size_t n = rotations.size();
  const double mean = CheckRefinerInput("RefineSphericalDyad", n, 1.0, weights_in, &exact_in);
  std::vector<double> weights(n, 1.0);
  for (size_t j = 0; j < n && !weights_in.empty(); ++j) weights[j] = weights_in[j] / mean;
  const std::vector<bool> exact = exact_in.empty() ? std::vector<bool>(n, false) : exact_in;
  int exact_count = 0;
  for (const bool flag : exact) exact_count += flag;
  const auto fit_of = [&](const SphericalDyad& candidate) {
    return internal::EvaluateFit(weights, exact, options.exact_tolerance,
                                 [&](size_t j) { return candidate.Residual(rotations[j]); });
  };
  const SphericalDyad seed = *dyad;
  const internal::DyadFit seed_fit = fit_of(seed);

  Eigen::Vector3d u = seed.fixed_axis, v = seed.moving_axis;
  double alpha = seed.angle;
  std::vector<double> sqrt_weights(n);
  for (size_t j = 0; j < n; ++j) sqrt_weights[j] = std::sqrt(weights[j]);
  ceres::Problem problem;
  for (size_t j = 0; j < n; ++j) {
    problem.AddResidualBlock(ConeResidual::Create(rotations[j], &sqrt_weights[j]), nullptr,
                             u.data(), v.data(), &alpha);
  }
  problem.SetManifold(u.data(), new ceres::SphereManifold<3>());
  problem.SetManifold(v.data(), new ceres::SphereManifold<3>());
  const ceres::Solver::Options solver_options = RefinerSolverOptions(
      options.max_iterations, options.function_tolerance, options.parameter_tolerance, 1e-16);
  RefinerSummary summary;
  SphericalDyad best = seed;
  internal::DyadFit best_fit = seed_fit;
  double growth = 1.0;
  for (int round = 0; round <= (exact_count > 0 ? options.max_penalty_rounds : 0); ++round) {
    ceres::Solver::Summary ceres_summary;
    ceres::Solve(solver_options, &problem, &ceres_summary);
    summary.iterations += static_cast<int>(ceres_summary.iterations.size());
    summary.message = ceres_summary.message;
    const SphericalDyad refined = SphericalDyad::Make(u, v, alpha);
    const internal::DyadFit fit = fit_of(refined);
    if (refined.AllFinite() && internal::Better(fit, best_fit)) {
      best = refined;
      best_fit = fit;
    }
    if (fit.meets_exact) break;
    growth *= internal::kPenaltyGrowth;
    for (size_t j = 0; j < n; ++j) {
      if (exact[j]) sqrt_weights[j] = std::sqrt(weights[j] * growth);
    }
  }
  *dyad = best;
  double total = 0.0;
  for (const double weight : weights) total += weight;
  summary.initial_cost = seed_fit.cost;
  summary.final_cost = best_fit.cost;
  summary.initial_rms = std::sqrt(2.0 * seed_fit.cost / total);
  summary.final_rms = std::sqrt(2.0 * best_fit.cost / total);
  summary.initial_max = seed_fit.max;
  summary.final_max = best_fit.max;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace linkfit
