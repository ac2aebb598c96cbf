#include "lib/spherical_four_bar.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lib/design_constraints.h"

namespace linkfit {
namespace {

// A crank, coupler or ground shorter than this (radians) is an axis pair along one line.
constexpr double kDegenerateAngle = 1e-9;
// Assembly: a Gram determinant down to -kGramTolerance is a tangent configuration.
constexpr double kGramTolerance = 1e-9;

double Degrees(double radians) { return radians * 180.0 / M_PI; }

// The transmission angle mu folded into [0, 90] degrees.
double Fold(double mu_deg) { return 90.0 - std::abs(90.0 - mu_deg); }

// The rotations with crank pin w1 (unit, Sigma): file comment of the header.
int AssembleFromPin(const SphericalFourBar& four_bar, const Eigen::Vector3d& w1, double tolerance,
                    Eigen::Matrix3d rotations[2]) {
  const Eigen::Vector3d& u2 = four_bar.output.fixed_axis;
  const double c2 = std::cos(four_bar.output.angle), cb = std::cos(four_bar.coupler);
  const double g = u2.dot(w1);
  const double den = 1.0 - g * g;
  if (!(den > 1e-14)) return 0;  // the pin on the output's axis: the two circles are concentric
  const double gram = 1.0 + 2.0 * g * c2 * cb - g * g - c2 * c2 - cb * cb;
  if (!(gram >= -tolerance)) return 0;
  const double a = (c2 - g * cb) / den, b = (cb - g * c2) / den;
  const double c = std::sqrt(std::max(gram, 0.0)) / den;
  const Eigen::Vector3d cross = u2.cross(w1);
  for (int label = 0; label < 2; ++label) {
    const Eigen::Vector3d w2 = (a * u2 + b * w1 + (label == 0 ? c : -c) * cross).normalized();
    const Eigen::Vector3d n = (w2 - w2.dot(w1) * w1).normalized();
    Eigen::Matrix3d frame;
    frame << w1, n, w1.cross(n);
    rotations[label] = frame * four_bar.body_frame.transpose();
  }
  return 2;
}

// Whether the joint between links a and b turns fully, the other two links c and d closing the
// triangle across it (header: SphericalJointsRotate).
bool JointTurnsFully(double a, double b, double c, double d, double tolerance, bool* change_point) {
  const double diagonal_low = std::abs(a - b);
  const double diagonal_high = std::min(a + b, 2.0 * M_PI - a - b);
  const double closes_low = std::abs(c - d);
  const double closes_high = std::min(c + d, 2.0 * M_PI - c - d);
  if (std::abs(diagonal_low - closes_low) <= tolerance ||
      std::abs(diagonal_high - closes_high) <= tolerance) {
    *change_point = true;
  }
  return diagonal_low >= closes_low - tolerance && diagonal_high <= closes_high + tolerance;
}

// g = u2 . w1 = cos(gamma) cos(alpha1) + sin(gamma) sin(alpha1) cos(phi) as a crank's closure
// scalar (four_bar_closure.h): the closure condition's and the transmission angle's variable.
ClosureScalar PinToOutputAxis(const SphericalFourBar& four_bar) {
  ClosureScalar scalar;
  scalar.crank = true;
  scalar.c0 = std::cos(four_bar.ground) * std::cos(four_bar.input.angle);
  scalar.c1 = std::sin(four_bar.ground) * std::sin(four_bar.input.angle);
  scalar.amplitude = std::abs(scalar.c1);
  scalar.peak = scalar.c1 >= 0.0 ? 0.0 : M_PI;
  return scalar;
}

}  // namespace

SphericalFourBar MakeSphericalFourBar(const SphericalDyad& input, const SphericalDyad& output) {
  SphericalFourBar four_bar;
  four_bar.input = input;
  four_bar.output = output;
  const Eigen::Vector3d& u1 = input.fixed_axis;
  const Eigen::Vector3d& v1 = input.moving_axis;
  four_bar.ground = DirectionAngle(u1, output.fixed_axis);
  four_bar.coupler = DirectionAngle(v1, output.moving_axis);
  Eigen::Vector3d e1 = output.fixed_axis - u1.dot(output.fixed_axis) * u1;
  // Coaxial fixed axes: the input angle is measured from any direction normal to them.
  e1 = e1.norm() > 1e-12 ? e1.normalized() : u1.unitOrthogonal();
  four_bar.e1 = e1;
  four_bar.e2 = u1.cross(e1);
  if (!(input.angle > kDegenerateAngle && input.angle < M_PI - kDegenerateAngle) ||
      !(output.angle > kDegenerateAngle && output.angle < M_PI - kDegenerateAngle)) {
    four_bar.invalid_note = "a crank's axes lie along one line (no crank)";
    return four_bar;
  }
  if (!(four_bar.coupler > kDegenerateAngle && four_bar.coupler < M_PI - kDegenerateAngle)) {
    four_bar.invalid_note = "the moving axes lie along one line (no coupler)";
    return four_bar;
  }
  const Eigen::Vector3d n = (output.moving_axis - v1.dot(output.moving_axis) * v1).normalized();
  four_bar.body_frame << v1, n, v1.cross(n);
  four_bar.valid = true;
  return four_bar;
}

double SphericalInputAngle(const SphericalFourBar& four_bar, const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d w1 = rotation * four_bar.input.moving_axis;
  return std::atan2(w1.dot(four_bar.e2), w1.dot(four_bar.e1));
}

int AssembleSphericalFourBar(const SphericalFourBar& four_bar, double input_angle, double tolerance,
                             Eigen::Matrix3d rotations[2]) {
  if (!four_bar.valid) return 0;
  const double alpha = four_bar.input.angle;
  const Eigen::Vector3d w1 =
      std::cos(alpha) * four_bar.input.fixed_axis +
      std::sin(alpha) * (std::cos(input_angle) * four_bar.e1 + std::sin(input_angle) * four_bar.e2);
  return AssembleFromPin(four_bar, w1, tolerance, rotations);
}

int AssembleSphericalFourBarAt(const SphericalFourBar& four_bar, const Eigen::Matrix3d& rotation,
                               double tolerance, Eigen::Matrix3d rotations[2],
                               double* input_angle) {
  *input_angle = SphericalInputAngle(four_bar, rotation);
  if (!four_bar.valid) return 0;
  // The pin on the input's cone, in the direction about u1 of R v1 (as the planar
  // AssembleFourBarAtPose takes it on the crank's circle): R v1 itself would let a pose that
  // misses the input dyad assemble as if the crank met it.
  const Eigen::Vector3d& u1 = four_bar.input.fixed_axis;
  const Eigen::Vector3d pin = rotation * four_bar.input.moving_axis;
  const Eigen::Vector3d across = pin - u1.dot(pin) * u1;
  if (!(across.norm() > 1e-12 * pin.norm())) {
    return AssembleSphericalFourBar(four_bar, *input_angle, tolerance, rotations);
  }
  const double alpha = four_bar.input.angle;
  return AssembleFromPin(four_bar, std::cos(alpha) * u1 + std::sin(alpha) * across.normalized(),
                         tolerance, rotations);
}

FourBarClosure SphericalClosure(const SphericalFourBar& four_bar) {
  FourBarClosure closure;
  closure.angle_input = true;
  closure.labels = 2;
  if (!four_bar.valid) return closure;
  const double alpha2 = four_bar.output.angle, beta = four_bar.coupler;
  // g = u2 . w1 in [cos(alpha2 + beta), cos(alpha2 - beta)].
  const ClosureScalar g = PinToOutputAxis(four_bar);
  SinusoidClosure(g.c0, g.c1, 0.0, std::cos(alpha2 + beta), std::cos(alpha2 - beta), &closure);
  std::sort(closure.intervals.begin(), closure.intervals.end(),
            [](const ClosureInterval& a, const ClosureInterval& b) { return a.start < b.start; });
  return closure;
}

SphericalRotatability SphericalJointsRotate(const SphericalFourBar& four_bar, double tolerance) {
  const double ground = four_bar.ground, input = four_bar.input.angle;
  const double coupler = four_bar.coupler, output = four_bar.output.angle;
  SphericalRotatability joints;
  joints.input = JointTurnsFully(ground, input, coupler, output, tolerance, &joints.change_point);
  joints.output = JointTurnsFully(ground, output, input, coupler, tolerance, &joints.change_point);
  joints.input_coupler =
      JointTurnsFully(input, coupler, ground, output, tolerance, &joints.change_point);
  joints.coupler_output =
      JointTurnsFully(coupler, output, ground, input, tolerance, &joints.change_point);
  return joints;
}

std::string SphericalGrashofType(const SphericalFourBar& four_bar, double tolerance) {
  const SphericalRotatability joints = SphericalJointsRotate(four_bar, tolerance);
  if (joints.change_point) return "change-point";
  if (joints.input && joints.output) return "double-crank";
  if (joints.input) return "crank-rocker";
  if (joints.output) return "rocker-crank";
  if (joints.input_coupler || joints.coupler_output) return "double-rocker";
  return "triple-rocker";
}

std::optional<double> SphericalTransmissionAngleDeg(const SphericalFourBar& four_bar,
                                                    const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d w1 = rotation * four_bar.input.moving_axis;
  const Eigen::Vector3d w2 = rotation * four_bar.output.moving_axis;
  const Eigen::Vector3d& u2 = four_bar.output.fixed_axis;
  // The arcs' tangents at w2, toward the crank pin and toward the output's axis.
  const Eigen::Vector3d to_coupler = w1 - w1.dot(w2) * w2, to_output = u2 - u2.dot(w2) * w2;
  if (!(to_coupler.norm() > 1e-12 && to_output.norm() > 1e-12)) return std::nullopt;
  return Fold(Degrees(DirectionAngle(to_coupler, to_output)));
}

SphericalFourBarAnalysis AnalyzeSphericalFourBar(const SphericalFourBar& four_bar,
                                                 const SphericalMotion& motion, int cycle_samples) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  SphericalFourBarAnalysis analysis;
  const FourBarClosure closure = SphericalClosure(four_bar);
  Eigen::Matrix3d configurations[2];
  std::vector<double> inputs;
  std::vector<std::array<double, 2>> label_errors;
  for (size_t j = 0; j < motion.rotations.size(); ++j) {
    double value = 0.0;
    const int count = AssembleSphericalFourBarAt(four_bar, motion.rotations[j], kGramTolerance,
                                                 configurations, &value);
    std::array<double, 2> errors = {kInfinity, kInfinity};
    for (int l = 0; l < count; ++l) errors[l] = motion.TaskPoseError(configurations[l], j);
    inputs.push_back(value);
    label_errors.push_back(errors);
  }
  const ClosureJudgment judgment = JudgeOnClosure(
      closure, inputs, label_errors, 0.0, 1.0, [&](size_t j, double value, int label) {
        const int count = AssembleSphericalFourBar(four_bar, value, kGramTolerance, configurations);
        if (count == 0) return kInfinity;
        return motion.TaskPoseError(configurations[std::min(label, count - 1)], j);
      });
  if (!TakeJudgment(judgment, &analysis)) return analysis;
  if (cycle_samples > 0) {
    analysis.cycle = CircuitConfigurations<Eigen::Matrix3d>(
        closure, judgment.circuits[judgment.circuit], judgment.lo, judgment.hi, cycle_samples,
        [&](double value, std::vector<Eigen::Matrix3d>* rotations) {
          const int count =
              AssembleSphericalFourBar(four_bar, value, kGramTolerance, configurations);
          rotations->assign(configurations, configurations + count);
          return count;
        });
  }
  if (!OnOneBranch(analysis.defects)) {
    analysis.transmission_note = "the poses are not on one branch";
    return analysis;
  }
  // cos(mu) = (g - cos(beta) cos(alpha2)) / (sin(beta) sin(alpha2)): mu falls as g grows, and
  // g = c0 + c1 cos(phi) has its exact range over the sweep (ClosureScalar::Range).
  double g_low = 0.0, g_high = 0.0;
  PinToOutputAxis(four_bar).Range(judgment.sweep_start, judgment.sweep_extent, &g_low, &g_high);
  const double alpha2 = four_bar.output.angle, beta = four_bar.coupler;
  const auto mu = [&](double g) {
    const double x = (g - std::cos(beta) * std::cos(alpha2)) / (std::sin(beta) * std::sin(alpha2));
    return Degrees(std::acos(std::clamp(x, -1.0, 1.0)));
  };
  const double mu_high = mu(g_low), mu_low = mu(g_high);
  analysis.transmission_min_deg = std::min(Fold(mu_low), Fold(mu_high));
  analysis.transmission_max_deg =
      mu_low <= 90.0 && mu_high >= 90.0 ? 90.0 : std::max(Fold(mu_low), Fold(mu_high));
  return analysis;
}

}  // namespace linkfit
