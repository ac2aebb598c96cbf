#include "lib/function_four_bar.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "lib/dyad.h"
#include "lib/four_bar_closure.h"
#include "lib/mechanism.h"
#include "lib/text_format.h"

namespace linkfit {
namespace {

constexpr double kRadToDeg = 180.0 / kClosurePi;

// The closure of (F) over the crank angle t2: |P - B|^2 = a^2 + d^2 - 2ad cos t2 within
// [(b - c)^2, (b + c)^2].
FourBarClosure Closure(const FunctionFourBar& f) {
  FourBarClosure closure;
  const double a = f.input_length, b = f.coupler_length, c = f.output_length, d = f.ground;
  SinusoidClosure(a * a + d * d, -2.0 * a * d, 0.0, (b - c) * (b - c), (b + c) * (b + c), &closure);
  return closure;
}

// The output error of `pair` on assembly sigma (wrapped), or nullopt where it does not assemble.
std::optional<double> PairError(const FunctionFourBar& f, const FunctionPair& pair, int sigma) {
  double psi;
  if (!f.Output(pair.input, sigma, &psi)) return std::nullopt;
  return WrapToPi(psi - pair.output);
}

}  // namespace

double WrapToPi(double angle) {
  double wrapped = std::remainder(angle, kClosureTwoPi);
  if (wrapped <= -kClosurePi) wrapped += kClosureTwoPi;
  return wrapped;
}

double ReachedOutputError(const FunctionFourBar& f, const FunctionPair& pair, int sigma,
                          double* miss) {
  double t4, reach_miss;
  OutputCrankAngle<double>(f.input_length, f.coupler_length, f.output_length, f.ground,
                           f.input_offset + pair.input, sigma, &t4, &reach_miss);
  if (miss != nullptr) *miss = reach_miss;
  return WrapToPi(t4 - f.output_offset - pair.output);
}

bool FunctionFourBar::Output(double phi, int sigma, double* psi) const {
  double t4, miss;
  const bool assembles = OutputCrankAngle<double>(input_length, coupler_length, output_length,
                                                  ground, input_offset + phi, sigma, &t4, &miss);
  if (!assembles) return false;
  *psi = WrapToPi(t4 - output_offset);
  return true;
}

bool FunctionFourBar::Valid() const {
  for (double length : {ground, input_length, coupler_length, output_length}) {
    if (!std::isfinite(length) || !(length > 0.0)) return false;
  }
  return std::isfinite(input_offset) && std::isfinite(output_offset) &&
         (assembly == 1 || assembly == -1);
}

std::optional<FunctionConfiguration> ConfigurationAt(const FunctionFourBar& four_bar, double phi,
                                                     const Eigen::Vector2d& input_pivot,
                                                     const Eigen::Vector2d& output_pivot) {
  double psi;
  if (!four_bar.Output(phi, &psi)) return std::nullopt;
  const Eigen::Vector2d line = output_pivot - input_pivot;
  const double gamma = std::atan2(line.y(), line.x());
  const double t2 = gamma + four_bar.input_offset + phi;
  const double t4 = gamma + four_bar.output_offset + psi;
  FunctionConfiguration configuration;
  configuration.input_pivot = input_pivot;
  configuration.output_pivot = output_pivot;
  configuration.input_moving =
      input_pivot + four_bar.input_length * Eigen::Vector2d(std::cos(t2), std::sin(t2));
  configuration.output_moving =
      output_pivot + four_bar.output_length * Eigen::Vector2d(std::cos(t4), std::sin(t4));
  return configuration;
}

int NearestAssembly(const FunctionFourBar& four_bar, const FunctionPair& pair) {
  const std::optional<double> plus = PairError(four_bar, pair, 1);
  const std::optional<double> minus = PairError(four_bar, pair, -1);
  if (!plus || !minus) return 0;
  return std::abs(*plus) <= std::abs(*minus) ? 1 : -1;
}

FunctionAnalysis AnalyzeFunctionFourBar(const FunctionFourBar& four_bar,
                                        const std::vector<FunctionPair>& pairs) {
  FunctionAnalysis analysis;
  const FunctionFourBar& f = four_bar;
  const double a = f.input_length, b = f.coupler_length, c = f.output_length, d = f.ground;
  // The Grashof class with the input driven: the four-bar as two RR dyads of a coupler frame
  // with the pins at (0, 0) and (b, 0).
  const PlanarDyad input = PlanarDyad::RR(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), a);
  const PlanarDyad output = PlanarDyad::RR(Eigen::Vector2d(d, 0.0), Eigen::Vector2d(b, 0.0), c);
  analysis.grashof = GrashofType(input, output, d);
  analysis.output_rotates_fully =
      analysis.grashof == "double-crank" || analysis.grashof == "rocker-crank";
  const FourBarClosure closure = Closure(f);
  analysis.input_rotates_fully = closure.full_turn;
  if (pairs.empty()) return analysis;

  // Slack for the interval test: an input a rounding step past a stationary configuration.
  constexpr double kInputSlack = 1e-9;
  const int first = ClosureIntervalOf(closure, f.input_offset + pairs[0].input, kInputSlack);
  if (first < 0 || !PairError(f, pairs[0], f.assembly)) {
    analysis.error_note = "does not assemble at the first pair's input angle";
    analysis.defects.push_back("assembly");
    return analysis;
  }
  analysis.assembles_first = true;
  const bool limited = !closure.full_turn;
  const auto defect = [&](const char* name) {
    if (std::find(analysis.defects.begin(), analysis.defects.end(), name) ==
        analysis.defects.end()) {
      analysis.defects.push_back(name);
    }
  };
  double largest = 0.0, sum = 0.0, weights = 0.0;
  double smallest_input = pairs[0].input, largest_input = pairs[0].input;
  for (const FunctionPair& pair : pairs) {
    smallest_input = std::min(smallest_input, pair.input);
    largest_input = std::max(largest_input, pair.input);
    const int interval = ClosureIntervalOf(closure, f.input_offset + pair.input, kInputSlack);
    std::optional<double> error = PairError(f, pair, f.assembly);
    if (interval < 0 || !error) {
      // Out of the input's reach: the output at the nearest stationary configuration.
      defect("circuit");
      error = ReachedOutputError(f, pair, f.assembly);
    } else {
      const std::optional<double> other = PairError(f, pair, -f.assembly);
      // The pair calls for the other assembly: a limited input reaches it only by reversing
      // at a stationary configuration (a branch), a full turn not at all (a circuit).
      if (interval != first) {
        defect("circuit");
      } else if (other && std::abs(*other) < 0.5 * std::abs(*error)) {
        defect(limited ? "branch" : "circuit");
      }
    }
    analysis.errors.push_back(*error);
    largest = std::max(largest, std::abs(*error));
    sum += pair.weight * *error * *error;
    weights += pair.weight;
  }
  analysis.max_error = largest;
  analysis.rms_error = std::sqrt(sum / std::max(weights, 1e-300));

  // The transmission angle mu at Q: cos mu = (b^2 + c^2 - s) / (2bc), s = |P - B|^2 over the
  // inputs from the smallest pair input to the largest.
  ClosureScalar s;
  s.c0 = a * a + d * d;
  s.c1 = -2.0 * a * d;
  s.c2 = 0.0;
  s.amplitude = std::abs(s.c1);
  s.peak = std::atan2(s.c2, s.c1);
  double s_low, s_high;
  s.Range(f.input_offset + smallest_input, largest_input - smallest_input, &s_low, &s_high);
  const auto cos_mu = [&](double value) {
    return std::clamp((b * b + c * c - value) / (2.0 * b * c), -1.0, 1.0);
  };
  const double at_low = cos_mu(s_low), at_high = cos_mu(s_high);
  analysis.transmission_min_deg =
      kRadToDeg * std::acos(std::max(std::abs(at_low), std::abs(at_high)));
  analysis.transmission_max_deg =
      (at_low >= 0.0) != (at_high >= 0.0)
          ? 90.0
          : kRadToDeg * std::acos(std::min(std::abs(at_low), std::abs(at_high)));
  return analysis;
}

FunctionRangeAnalysis AnalyzeFunctionRange(const FunctionFourBar& four_bar,
                                           const FunctionPair& first,
                                           const std::vector<FunctionPair>& samples) {
  FunctionRangeAnalysis range;
  std::vector<FunctionPair> pairs = {first};
  pairs.insert(pairs.end(), samples.begin(), samples.end());
  const FunctionAnalysis over = AnalyzeFunctionFourBar(four_bar, pairs);
  range.transmission_min_deg = over.transmission_min_deg;
  range.transmission_max_deg = over.transmission_max_deg;
  if (!over.assembles_first) {
    range.note = over.error_note;
    return range;
  }
  if (over.defects.empty()) {
    double largest = 0.0;
    for (size_t k = 1; k < over.errors.size(); ++k) {
      largest = std::max(largest, std::abs(over.errors[k]));
    }
    range.max_error = largest;
    return range;
  }
  // Where it stops: the first sample off the first pair's interval or assembly.
  const FunctionFourBar& f = four_bar;
  const FourBarClosure closure = Closure(f);
  constexpr double kInputSlack = 1e-9;
  const int circuit = ClosureIntervalOf(closure, f.input_offset + first.input, kInputSlack);
  const auto degrees = [](double angle) { return Format("%.4g", angle * kRadToDeg); };
  for (size_t k = 0; k < samples.size(); ++k) {
    const FunctionPair& sample = samples[k];
    const std::string where = "at input " + degrees(sample.input) + " deg (sample " +
                              std::to_string(k + 1) + " of the function)";
    const int interval = ClosureIntervalOf(closure, f.input_offset + sample.input, kInputSlack);
    const std::optional<double> error = PairError(f, sample, f.assembly);
    if (interval != circuit || !error) {
      range.note =
          "does not run over the function's input range from the first pair: it does "
          "not reach the output " +
          where;
      return range;
    }
    const std::optional<double> other = PairError(f, sample, -f.assembly);
    if (other && std::abs(*other) < 0.5 * std::abs(*error)) {
      range.note =
          "does not run over the function's input range from the first pair: it needs "
          "the other assembly " +
          where;
      return range;
    }
  }
  range.note = "does not run over the function's input range from the first pair";
  return range;
}

std::optional<double> LargestOutputError(const FunctionFourBar& four_bar,
                                         const std::vector<FunctionPair>& samples) {
  double largest = 0.0;
  for (const FunctionPair& sample : samples) {
    const std::optional<double> error = PairError(four_bar, sample, four_bar.assembly);
    if (!error) return std::nullopt;
    largest = std::max(largest, std::abs(*error));
  }
  return largest;
}

double FunctionErrorBound(const FunctionFourBar& four_bar, const std::vector<FunctionPair>& pairs,
                          bool free_offsets, double angle_precision) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const int parameters = free_offsets ? 5 : 3;
  const int n = static_cast<int>(pairs.size());
  if (n < parameters) return kInfinity;
  const auto with = [&](int k, double step) {
    FunctionFourBar f = four_bar;
    double* fields[5] = {&f.input_length, &f.coupler_length, &f.output_length, &f.input_offset,
                         &f.output_offset};
    *fields[k] += step;
    return f;
  };
  // Residuals of a four-bar at the pairs; false where one does not assemble.
  const auto residuals = [&](const FunctionFourBar& f, Eigen::VectorXd* r) {
    r->resize(n);
    for (int j = 0; j < n; ++j) {
      double psi;
      if (!f.Output(pairs[j].input, &psi)) return false;
      (*r)(j) = WrapToPi(psi - pairs[j].output);
    }
    return true;
  };
  const double h = 1e-6 * four_bar.ground;
  Eigen::MatrixXd jacobian(n, parameters);
  for (int k = 0; k < parameters; ++k) {
    const double step = k < 3 ? h : 1e-6;
    Eigen::VectorXd plus, minus;
    if (!residuals(with(k, step), &plus) || !residuals(with(k, -step), &minus)) return kInfinity;
    jacobian.col(k) = (plus - minus) / (2.0 * step);
  }
  // Each pair's error moves by its output's rounding and its input's times the slope.
  Eigen::VectorXd moves(n), weights(n);
  for (int j = 0; j < n; ++j) {
    double psi_plus, psi_minus;
    const double step = 1e-6;
    if (!four_bar.Output(pairs[j].input + step, &psi_plus) ||
        !four_bar.Output(pairs[j].input - step, &psi_minus)) {
      return kInfinity;
    }
    const double slope = WrapToPi(psi_plus - psi_minus) / (2.0 * step);
    moves(j) = (1.0 + std::abs(slope)) * angle_precision;
    weights(j) = pairs[j].weight;
  }
  const Eigen::MatrixXd normal = jacobian.transpose() * weights.asDiagonal() * jacobian;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(normal, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd sigma = svd.singularValues();
  if (!(sigma(parameters - 1) > 1e-14 * sigma(0))) return kInfinity;
  const Eigen::MatrixXd sensitivity =
      svd.solve(Eigen::MatrixXd(jacobian.transpose() * weights.asDiagonal()));
  const Eigen::VectorXd bound = sensitivity.cwiseAbs() * moves;
  double largest = bound.head(3).maxCoeff();
  if (free_offsets) {
    largest =
        std::max({largest, four_bar.input_length * bound(3), four_bar.output_length * bound(4)});
  }
  return std::isfinite(largest) ? largest : kInfinity;
}

}  // namespace linkfit
