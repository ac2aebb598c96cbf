#include "lib/path_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// Where the output closes, as a condition on the crank angle alone: a sinusoid
// f(alpha) = c0 + c1 cos(alpha) + c2 sin(alpha) that must stay in [low, high]. With the crank
// pin P(alpha) = B + r (cos, sin) and the coupler link from the pin to the output pin of length
// l = |m2 - m1|:
//   RR output (F, r2):    f = |P - F|,  within [|l - r2|, l + r2]  (f squared is the sinusoid)
//   PR output (line n.X = h): f = n.P - h, within [-l, l]
//   RP output (F on a line of E at distance d from the pin): f = |P - F| >= |d|
struct ClosureCondition {
  double c0 = 0.0, c1 = 0.0, c2 = 0.0;
  bool squared = false;  // the sinusoid is f^2 (a distance), not f
  double low = -kInfinity, high = kInfinity;

  double amplitude = 0.0;  // hypot(c1, c2)
  double peak = 0.0;       // atan2(c2, c1): where the sinusoid is largest

  // Sets amplitude and peak from the coefficients.
  void Finish() {
    amplitude = std::hypot(c1, c2);
    peak = std::atan2(c2, c1);
  }
  // Smallest and largest f over the crank angles from `start` over `sweep` (either sign).
  void Range(double start, double sweep, double* smallest, double* largest) const {
    double low_s, high_s;
    if (std::abs(sweep) >= 2.0 * kPi) {
      low_s = c0 - amplitude;
      high_s = c0 + amplitude;
    } else {
      const double a = std::min(start, start + sweep), b = std::max(start, start + sweep);
      const double at_a = c0 + c1 * std::cos(a) + c2 * std::sin(a);
      const double at_b = c0 + c1 * std::cos(b) + c2 * std::sin(b);
      low_s = std::min(at_a, at_b);
      high_s = std::max(at_a, at_b);
      // The extremes of the sinusoid: the peak (maximum) and the peak + pi.
      for (int k = 0; k < 2; ++k) {
        const double extreme = peak + k * kPi;
        // The first angle >= a congruent to the extreme.
        const double turns = std::ceil((a - extreme) / (2.0 * kPi));
        const double candidate = extreme + turns * 2.0 * kPi;
        if (candidate <= b) {
          if (k == 0) high_s = c0 + amplitude;
          if (k == 1) low_s = c0 - amplitude;
        }
      }
    }
    if (squared) {
      *smallest = std::sqrt(std::max(low_s, 0.0));
      *largest = std::sqrt(std::max(high_s, 0.0));
    } else {
      *smallest = low_s;
      *largest = high_s;
    }
  }
  // Whether f stays within [low - slack, high + slack] over the sweep.
  bool Holds(double start, double sweep, double slack) const {
    double smallest, largest;
    Range(start, sweep, &smallest, &largest);
    return smallest >= low - slack && largest <= high + slack;
  }
};

ClosureCondition Closure(const PathFourBar& four_bar) {
  const PlanarDyad& input = four_bar.input;
  const PlanarDyad& output = four_bar.output;
  ClosureCondition condition;
  const double r = input.radius;
  if (output.type == DyadType::kPR) {
    const Eigen::Vector2d n = Perp(output.line_direction);
    const double link = (output.moving_pivot - input.moving_pivot).norm();
    condition.c0 = n.dot(input.fixed_pivot - output.line_point);
    condition.c1 = r * n.x();
    condition.c2 = r * n.y();
    condition.low = -link;
    condition.high = link;
    condition.Finish();
    return condition;
  }
  const Eigen::Vector2d offset = input.fixed_pivot - output.fixed_pivot;
  condition.squared = true;
  condition.c0 = offset.squaredNorm() + r * r;
  condition.c1 = 2.0 * r * offset.x();
  condition.c2 = 2.0 * r * offset.y();
  if (output.type == DyadType::kRR) {
    const double link = (output.moving_pivot - input.moving_pivot).norm();
    condition.low = std::abs(link - output.radius);
    condition.high = link + output.radius;
  } else {
    condition.low =
        std::abs(Perp(output.line_direction).dot(input.moving_pivot - output.line_point));
  }
  condition.Finish();
  return condition;
}

// The coupler's turns (cos(theta), sin(theta)) that close the output with the crank pin at `pin`
// (Sigma): AssembleFourBar's equation a cos + b sin = c (OutputTurnEquation) and its label order
// (label 0: theta = atan2(b, a) + acos(c / rho)), solved for the unit vectors without angles,
//   (a c -+ b s, b c +- a s) / rho^2,  s = sqrt(rho^2 - c^2),
// with AssembleFourBar's tangency slack. Returns 0 or 2.
int TurnsAtPin(const PathFourBar& four_bar, const Eigen::Vector2d& pin, double tolerance,
               Eigen::Vector2d turns[2]) {
  double a = 0.0, b = 0.0, c = 0.0, scale = 1.0;
  OutputTurnEquation(four_bar.output, four_bar.input.moving_pivot, pin, &a, &b, &c, &scale);
  const double rho_squared = a * a + b * b;
  if (!(rho_squared > 0.0) || !std::isfinite(rho_squared)) return 0;
  const double rho = std::sqrt(rho_squared);
  double ratio = c / rho;
  if (std::abs(ratio) > 1.0) {
    if (std::abs(ratio) - 1.0 > tolerance / scale) return 0;
    ratio = std::copysign(1.0, ratio);
  }
  const double across = std::sqrt(std::max(1.0 - ratio * ratio, 0.0));
  const double ua = a / rho, ub = b / rho;
  turns[0] = Eigen::Vector2d(ua * ratio - ub * across, ub * ratio + ua * across);
  turns[1] = Eigen::Vector2d(ua * ratio + ub * across, ub * ratio - ua * across);
  return 2;
}

// R(theta) v for the unit vector (cos(theta), sin(theta)).
Eigen::Vector2d Turn(const Eigen::Vector2d& unit, const Eigen::Vector2d& v) {
  return Eigen::Vector2d(unit.x() * v.x() - unit.y() * v.y(), unit.y() * v.x() + unit.x() * v.y());
}

// The configuration with assembly label `label` at crank angle `alpha`, if it assembles.
std::optional<PlanarPose> Configuration(const PathFourBar& four_bar, double alpha, int label,
                                        double tolerance) {
  std::vector<PlanarPose> poses;
  const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha, tolerance, &poses);
  if (count == 0) return std::nullopt;
  return poses[std::min(label, count - 1)];
}

}  // namespace

double FirstCrankAngle(const PathFourBar& four_bar) {
  const Eigen::Vector2d arm = four_bar.input.moving_pivot - four_bar.input.fixed_pivot;
  return std::atan2(arm.y(), arm.x());
}

PathFourBarAnalysis AnalyzePathFourBar(const PathFourBar& four_bar,
                                       const std::vector<Eigen::Vector2d>& points,
                                       const std::vector<double>& input_angles, double length,
                                       const PathAnalysisOptions& options) {
  PathFourBarAnalysis analysis;
  if (points.empty() || points.size() != input_angles.size() ||
      four_bar.input.type != DyadType::kRR) {
    analysis.error_note = "not a crank-driven four-bar with one input angle per point";
    return analysis;
  }
  const double tolerance = options.assembly_tolerance * length;
  const double alpha0 = FirstCrankAngle(four_bar);
  const ClosureCondition closure = Closure(four_bar);
  analysis.input_rotates_fully = closure.Holds(alpha0, 2.0 * kPi, tolerance);

  // The crank pin at each point: the arm B -> A turned by psi_j - psi_0.
  const Eigen::Vector2d pivot = four_bar.input.fixed_pivot;
  const Eigen::Vector2d arm = four_bar.input.moving_pivot - pivot;
  const Eigen::Vector2d& m1 = four_bar.input.moving_pivot;        // the pin, in E
  const Eigen::Vector2d point_arm = four_bar.coupler_point - m1;  // pin -> coupler point, in E
  const auto pin_at = [&](size_t j) {
    const double turn = input_angles[j] - input_angles[0];
    return Eigen::Vector2d(pivot + Turn(Eigen::Vector2d(std::cos(turn), std::sin(turn)), arm));
  };

  // The first point's assembly: the configuration nearest E = Sigma (turn nearest 0, the pin
  // being where E has it).
  Eigen::Vector2d turns[2];
  if (TurnsAtPin(four_bar, m1, tolerance, turns) == 0) {
    analysis.error_note = "does not assemble at the first point";
    return analysis;
  }
  analysis.assembles = true;
  analysis.label = 0;
  const auto pose_of = [&](const Eigen::Vector2d& pin, const Eigen::Vector2d& unit) {
    PlanarPose pose;
    pose.theta = std::atan2(unit.y(), unit.x());
    pose.origin_in_fixed = pin - Turn(unit, m1);
    return pose;
  };
  if (PoseError(pose_of(m1, turns[1]), PlanarPose(), length) <
      PoseError(pose_of(m1, turns[0]), PlanarPose(), length)) {
    analysis.label = 1;
  }

  double alpha = alpha0;
  bool branch = false, circuit = false;
  double sum_squared = 0.0, largest = 0.0, nearest_largest = 0.0;
  analysis.point_errors.reserve(points.size());
  analysis.configurations.reserve(points.size());
  for (size_t j = 0; j < points.size(); ++j) {
    const double step = j == 0 ? 0.0 : input_angles[j] - input_angles[j - 1];
    if (j > 0 && !closure.Holds(alpha, step, tolerance)) branch = true;
    alpha += step;
    const Eigen::Vector2d pin = j == 0 ? m1 : pin_at(j);
    if (j > 0 && TurnsAtPin(four_bar, pin, tolerance, turns) == 0) {
      analysis.error_note =
          "cannot be assembled at the input angle of points[" + std::to_string(j) + "]";
      analysis.point_errors.clear();
      analysis.configurations.clear();
      break;
    }
    const Eigen::Vector2d& tracked = turns[analysis.label];
    const Eigen::Vector2d& other = turns[1 - analysis.label];
    const double error = (pin + Turn(tracked, point_arm) - points[j]).norm();
    const double other_error = (pin + Turn(other, point_arm) - points[j]).norm();
    nearest_largest = std::max(nearest_largest, std::min(error, other_error));
    // Met on the other assembly only (at less than half the error).
    if (error > tolerance && other_error < 0.5 * error) {
      if (analysis.input_rotates_fully) {
        circuit = true;
      } else {
        branch = true;
      }
    }
    analysis.point_errors.push_back(error);
    analysis.configurations.push_back(pose_of(pin, tracked));
    sum_squared += error * error;
    largest = std::max(largest, error);
  }
  if (branch) analysis.defects.push_back("branch");
  if (circuit) analysis.defects.push_back("circuit");
  if (analysis.point_errors.size() == points.size()) {
    analysis.max_point_error = largest;
    analysis.rms_point_error = std::sqrt(sum_squared / static_cast<double>(points.size()));
    analysis.nearest_max_error = nearest_largest;
  }

  if (options.transmission_samples > 0 && !branch && analysis.max_point_error) {
    double sweep = 0.0;
    for (size_t j = 1; j < input_angles.size(); ++j) sweep += input_angles[j] - input_angles[j - 1];
    const int steps = options.transmission_samples;
    TransmissionRangeDeg(
        four_bar.input, four_bar.output, steps,
        [&](int k) {
          return Configuration(four_bar, alpha0 + sweep * k / steps, analysis.label, tolerance);
        },
        &analysis.transmission_min_deg, &analysis.transmission_max_deg);
  }
  return analysis;
}

std::vector<PlanarPose> CouplerCycle(const PathFourBar& four_bar, double length, int samples) {
  std::vector<PlanarPose> curve;
  if (four_bar.input.type != DyadType::kRR || samples < 4) return curve;
  const double tolerance = 1e-9 * length;
  const double alpha0 = FirstCrankAngle(four_bar);
  std::vector<PlanarPose> first;
  const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha0, tolerance, &first);
  if (count == 0) return curve;
  const int label = count == 2 && PoseError(first[1], PlanarPose(), length) <
                                      PoseError(first[0], PlanarPose(), length)
                        ? 1
                        : 0;
  const double step = 2.0 * kPi / samples;
  // Forward from the first point's crank angle while the output closes.
  int forward = 0;
  while (forward < samples &&
         Configuration(four_bar, alpha0 + (forward + 1) * step, label, tolerance)) {
    ++forward;
  }
  if (forward == samples) {
    for (int k = 0; k <= samples; ++k) {
      curve.push_back(*Configuration(four_bar, alpha0 + k * step, label, tolerance));
    }
    return curve;
  }
  int backward = 0;
  while (backward < samples &&
         Configuration(four_bar, alpha0 - (backward + 1) * step, label, tolerance)) {
    ++backward;
  }
  // The crank's reachable arc on this assembly, then back on the other one.
  for (int k = -backward; k <= forward; ++k) {
    curve.push_back(*Configuration(four_bar, alpha0 + k * step, label, tolerance));
  }
  for (int k = forward; k >= -backward; --k) {
    const std::optional<PlanarPose> pose =
        Configuration(four_bar, alpha0 + k * step, 1 - label, tolerance);
    if (pose) curve.push_back(*pose);
  }
  if (!curve.empty()) curve.push_back(curve.front());
  return curve;
}

Similarity2 ScaledPointFrame(const std::vector<Eigen::Vector2d>& points, double length) {
  Similarity2 frame;
  frame.scale = length;
  for (const Eigen::Vector2d& point : points) {
    frame.translation += point / static_cast<double>(points.size());
  }
  return frame;
}

PathFourBar MoveToFirstConfiguration(const PathFourBar& four_bar, const PlanarPose& first_pose) {
  PathFourBar moved = four_bar;
  moved.input.moving_pivot = first_pose.ToFixed(four_bar.input.moving_pivot);
  if (four_bar.output.type == DyadType::kRP) {
    moved.output.line_point = first_pose.ToFixed(four_bar.output.line_point);
    moved.output.line_direction = first_pose.DirectionToFixed(four_bar.output.line_direction);
  } else {
    moved.output.moving_pivot = first_pose.ToFixed(four_bar.output.moving_pivot);
  }
  moved.coupler_point = first_pose.ToFixed(four_bar.coupler_point);
  return moved;
}

}  // namespace linkfit
