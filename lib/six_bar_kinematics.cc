#include "lib/six_bar_kinematics.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lib/input_range.h"
#include "lib/six_bar_frames.h"

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }
double Direction(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// A pivot of the free turns' Jacobian below this share of the largest is a dead point (as
// lib/six_bar.cc's continuation judges one).
constexpr double kDeadPivot = 1e-10;

// Each body's centre of mass (at the reference configuration, in Sigma) and polar moment of
// inertia about it per unit mass (SixBarMasses' shapes).
struct BodyShapes {
  std::array<Eigen::Vector2d, 5> centre;
  std::array<double, 5> inertia;
};
BodyShapes Shapes(const SixBar& six_bar) {
  BodyShapes shapes;
  const std::array<std::vector<Eigen::Vector2d>, 6> joints = SixBarBodyJoints(six_bar);
  for (int body = 1; body <= 5; ++body) {
    std::vector<Eigen::Vector2d> points = joints[body];
    if (body == kSixBarTaskBody) points.push_back(six_bar.reference_pose.origin_in_fixed);
    UniformBody(points, &shapes.centre[body - 1], &shapes.inertia[body - 1]);
  }
  return shapes;
}

// The rates at a placed configuration (state->turns): false at a dead point of the input.
bool Rates(const SixBar& six_bar, int input, double w, const SixBarLoad& load,
           const SixBarMasses& masses, const BodyShapes& shapes, SixBarState* state) {
  const std::array<double, kSixBarJointCount> joints = SixBarJointNumbers(six_bar);
  const SixBarFrames<double> frames({six_bar.links[0].from_body, six_bar.links[1].from_body},
                                    {six_bar.links[0].to_body, six_bar.links[1].to_body},
                                    joints.data(), state->turns.data());
  const Eigen::Matrix<double, 4, 5> jacobian = frames.ClosureJacobian();
  const int in = input - 1;
  int free[4];
  Eigen::Matrix4d square;
  for (int k = 0, c = 0; k < 5; ++k) {
    if (k != in) free[c++] = k;
  }
  for (int c = 0; c < 4; ++c) square.col(c) = jacobian.col(free[c]);
  const Eigen::PartialPivLU<Eigen::Matrix4d> lu(square);
  const Eigen::Vector4d pivots = lu.matrixLU().diagonal().cwiseAbs();
  if (!(pivots.minCoeff() > kDeadPivot * pivots.maxCoeff())) return false;

  // J_free omega_free = -J_input w.
  SixBarAngles& omega = state->angular_velocity;
  omega.setZero();
  omega[in] = w;
  const Eigen::Vector4d omega_free = lu.solve(-jacobian.col(in) * w);
  for (int c = 0; c < 4; ++c) omega[free[c]] = omega_free[c];
  // J_free alpha_free = -sum_j omega_j^2 perp(J_j), per closure (the input's alpha is 0).
  Eigen::Vector4d centripetal = Eigen::Vector4d::Zero();
  for (int j = 0; j < 5; ++j) {
    for (int l = 0; l < 2; ++l) {
      centripetal.segment<2>(2 * l) +=
          omega[j] * omega[j] * Perp(jacobian.col(j).segment<2>(2 * l));
    }
  }
  SixBarAngles& alpha = state->angular_acceleration;
  alpha.setZero();
  const Eigen::Vector4d alpha_free = lu.solve(-centripetal);
  for (int c = 0; c < 4; ++c) alpha[free[c]] = alpha_free[c];

  // The tool frame's origin: v = G omega, a = G alpha + sum_j omega_j^2 perp(G_j).
  const Eigen::Matrix<double, 2, 5> gradient = frames.Gradient(kSixBarTaskBody, state->tool_point);
  state->tool_velocity = gradient * omega;
  state->tool_acceleration = gradient * alpha;
  for (int j = 0; j < 5; ++j) {
    state->tool_acceleration += omega[j] * omega[j] * Perp(gradient.col(j));
  }
  // Power balance: T_in w + F . v_P + T w_task = 0.
  const double task_turn = omega[kSixBarTaskBody - 1];
  state->input_torque =
      -(load.tool_force.dot(state->tool_velocity) + load.task_body_torque * task_turn) / w +
      0.0;  // (no load: 0, not -0)
  state->mechanical_advantage.reset();
  if (std::abs(task_turn) > 1e-12 * std::abs(w)) state->mechanical_advantage = w / task_turn;
  if (masses.Any()) {
    // T_in w = dT/dt - P_weight: dT/dt = sum m a_G . v_G + I alpha omega, each centre of mass G
    // moving as a point of its body (v = G omega, a = G alpha + sum omega_j^2 perp(G_j)).
    const Eigen::Vector2d weight(0.0, masses.gravity ? -9.80665 : 0.0);
    double energy_rate = 0.0, weight_power = 0.0;
    for (int body = 1; body <= 5; ++body) {
      const double m = masses.mass[body - 1];
      if (!(m > 0.0)) continue;
      const Eigen::Vector2d g = frames.At(body, shapes.centre[body - 1]);
      const Eigen::Matrix<double, 2, 5> lever = frames.Gradient(body, g);
      const Eigen::Vector2d v = lever * omega;
      Eigen::Vector2d a = lever * alpha;
      for (int j = 0; j < 5; ++j) a += omega[j] * omega[j] * Perp(lever.col(j));
      energy_rate += m * (a.dot(v) + shapes.inertia[body - 1] * alpha[body - 1] * omega[body - 1]);
      weight_power += m * weight.dot(v);
    }
    // kg L^2 / s^3 is length_unit_m N L / s.
    state->inertial_torque = energy_rate * masses.length_unit_m / w;
    state->weight_torque = -weight_power / w + 0.0;
    state->input_torque += state->inertial_torque + state->weight_torque;
  }
  return true;
}

// The positions of a configuration (turns set): the tool point, the input's direction and the
// loops' transmission angles.
void Positions(const SixBar& six_bar, int input, double reference, SixBarState* state) {
  state->tool_point = SixBarBodyDisplacement(six_bar, state->turns, kSixBarTaskBody)
                          .ToFixed(six_bar.reference_pose.origin_in_fixed);
  state->input_angle = reference + state->turns[input - 1];
  state->transmission_deg = SixBarTransmissionDeg(six_bar, state->turns);
}

}  // namespace

double SixBarInputReferenceAngle(const SixBar& six_bar, int input) {
  if (input == kSixBarUpperLink) return Direction(six_bar.elbow - six_bar.ground_pivot);
  const SixBarRRLink& link = six_bar.links[input - kSixBarFirstLink];
  return Direction(link.to_joint - link.from_joint);
}

SixBarKinematics AnalyzeSixBarKinematics(const SixBar& six_bar, int input,
                                         const SixBarKinematicsOptions& options, double length) {
  SixBarKinematics kinematics;
  if (!SixBarGroundedLink(six_bar, input)) {
    kinematics.note = "the input is not a link turning about ground";
    return kinematics;
  }
  const double w = options.input_speed;
  if (!(w != 0.0) || !std::isfinite(w)) {
    kinematics.note = "the input speed is 0";
    return kinematics;
  }
  const int in = input - 1;
  const double reference = SixBarInputReferenceAngle(six_bar, input);
  const SixBarDriver driver(six_bar, input, length);
  const SixBarAngles start = SixBarAngles::Zero();
  if (SixBarClosure(six_bar, start).norm() > 1e-6 * length) {
    kinematics.note = "the six-bar does not close at its first pose";
    return kinematics;
  }

  // The input's range in turns from the reference: a whole turn, or between the dead points
  // met driving forward and back.
  double low = 0.0, high = 2.0 * M_PI;
  SixBarAngles ahead = start;
  kinematics.input_rotates_fully = driver.Drive(2.0 * M_PI, &ahead, kSixBarDriveStep);
  if (!kinematics.input_rotates_fully) {
    SixBarAngles behind = start;
    driver.Drive(-2.0 * M_PI, &behind, kSixBarDriveStep);
    low = behind[in];
    high = ahead[in];
    for (const SixBarAngles* end : {&behind, &ahead}) {
      SixBarState dead;
      dead.turns = *end;
      Positions(six_bar, input, reference, &dead);
      kinematics.dead_points.push_back(dead);
    }
  }
  kinematics.range_start = reference + low;
  kinematics.range_end = reference + high;

  const int steps = std::max(1, options.steps);
  double first = low, span = high - low;
  if (options.range) {
    // The part asked for, within the range (a whole turn: wherever it starts).
    // (In turns from the reference: the directions asked for less the reference's.)
    const std::pair<double, double> asked = {options.range->first - reference,
                                             options.range->second - reference};
    if (!PartOfRange(asked, low, &first, &span)) {
      kinematics.note = "the range asked for leaves the input's range on its circuit";
      return kinematics;
    }
  }

  const BodyShapes shapes = Shapes(six_bar);
  SixBarAngles angles = start;
  for (int k = 0; k < steps; ++k) {
    const double turn = SampledInput(k, steps, options.range.has_value(),
                                     kinematics.input_rotates_fully, first, span);
    if (!driver.Drive(turn, &angles, kSixBarDriveStep)) {
      kinematics.note = "a dead point inside the input's range stopped the analysis";
      break;
    }
    SixBarState state;
    state.turns = angles;
    Positions(six_bar, input, reference, &state);
    if (!Rates(six_bar, input, w, options.load, options.masses, shapes, &state)) {
      kinematics.dead_points.push_back(state);
      continue;
    }
    kinematics.peak_input_torque =
        std::max(kinematics.peak_input_torque, std::abs(state.input_torque));
    kinematics.states.push_back(state);
  }
  if (kinematics.states.empty() && kinematics.note.empty()) {
    kinematics.note = "the six-bar does not move over the input's range";
  }
  return kinematics;
}

}  // namespace linkfit
