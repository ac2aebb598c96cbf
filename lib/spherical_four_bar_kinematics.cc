#include "lib/spherical_four_bar_kinematics.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "lib/input_range.h"

namespace linkfit {
namespace {

// A determinant of [w1, -u2, -w2] below this is a dead point (its columns are unit vectors).
constexpr double kDeadPoint = 1e-10;

double Continued(double angle, double previous) {
  return angle + 2.0 * M_PI * std::round((previous - angle) / (2.0 * M_PI));
}

// The coupler's frame at its pins: (w1, n, w1 x n), n the unit component of w2 normal to w1.
Eigen::Matrix3d CouplerFrame(const Eigen::Vector3d& w1, const Eigen::Vector3d& w2) {
  const Eigen::Vector3d n = (w2 - w2.dot(w1) * w1).normalized();
  Eigen::Matrix3d frame;
  frame << w1, n, w1.cross(n);
  return frame;
}

// The four-bar's dimensions and the assembly it is in at the first pose.
struct Loop {
  Eigen::Vector3d u1, u2, e1, e2, f1, f2;
  double cos_a1 = 1.0, sin_a1 = 0.0, cos_beta = 1.0, cos_a2 = 1.0, a2 = 0.0, beta = 0.0;
  double cos_gamma = 1.0, sin_gamma = 0.0;
  double side = 1.0;       // the sign of w2 . (u2 x w1) at the first pose
  double reference = 0.0;  // phi at the first pose
  Eigen::Matrix3d reference_frame = Eigen::Matrix3d::Identity();

  // The pins at input angle phi; with `clamp`, a closure just past a dead point is taken at it.
  bool Close(double phi, bool clamp, Eigen::Vector3d* w1, Eigen::Vector3d* w2) const {
    *w1 = cos_a1 * u1 + sin_a1 * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const double g = u2.dot(*w1), normal = 1.0 - g * g;
    if (!(normal > 1e-14)) return false;
    const double a = (cos_a2 - g * cos_beta) / normal, b = (cos_beta - g * cos_a2) / normal;
    double squared = (1.0 - a * a - b * b - 2.0 * a * b * g) / normal;
    if (squared < 0.0 && !clamp) return false;
    squared = std::max(squared, 0.0);
    *w2 = a * u2 + b * *w1 + side * std::sqrt(squared) * u2.cross(*w1);
    w2->normalize();
    return true;
  }

  // The input angles where g = u2 . w1 reaches cos(alpha2 + beta) or cos(alpha2 - beta): where
  // the loop stops closing.
  std::vector<double> CriticalAngles() const {
    std::vector<double> angles;
    for (const double bound : {std::cos(a2 + beta), std::cos(a2 - beta)}) {
      const double k = (bound - cos_gamma * cos_a1) / (sin_gamma * sin_a1);
      if (std::abs(k) > 1.0) continue;
      const double at = std::acos(k);
      angles.push_back(at);
      angles.push_back(-at);
    }
    return angles;
  }
};

std::optional<Loop> MakeLoop(const SphericalFourBarJoints& joints, std::string* note) {
  Loop loop;
  loop.u1 = joints.input_pivot.normalized();
  loop.u2 = joints.output_pivot.normalized();
  const Eigen::Vector3d w1 = joints.input_pin.normalized(), w2 = joints.output_pin.normalized();
  loop.cos_a1 = loop.u1.dot(w1);
  loop.sin_a1 = loop.u1.cross(w1).norm();
  loop.cos_beta = w1.dot(w2);
  loop.beta = std::atan2(w1.cross(w2).norm(), loop.cos_beta);
  loop.cos_a2 = loop.u2.dot(w2);
  loop.a2 = std::atan2(loop.u2.cross(w2).norm(), loop.cos_a2);
  loop.cos_gamma = loop.u1.dot(loop.u2);
  loop.sin_gamma = loop.u1.cross(loop.u2).norm();
  if (!(loop.sin_a1 > 1e-9 && std::sin(loop.beta) > 1e-9 && std::sin(loop.a2) > 1e-9 &&
        loop.sin_gamma > 1e-9)) {
    *note = "a link of the four-bar has no length (two of its axes along one line)";
    return std::nullopt;
  }
  loop.e1 = (loop.u2 - loop.cos_gamma * loop.u1).normalized();
  loop.e2 = loop.u1.cross(loop.e1);
  loop.f1 = (loop.u1 - loop.cos_gamma * loop.u2).normalized();
  loop.f2 = loop.u2.cross(loop.f1);
  loop.reference = std::atan2(w1.dot(loop.e2), w1.dot(loop.e1));
  loop.side = w2.dot(loop.u2.cross(w1)) < 0.0 ? -1.0 : 1.0;
  loop.reference_frame = CouplerFrame(w1, w2);
  return loop;
}

// The input's range about the first pose (as lib/four_bar_kinematics.cc's planar one).
void InputRange(const Loop& loop, double* start, double* end, bool* full) {
  RangeAbout(loop.reference, loop.CriticalAngles(), start, end, full);
}

// Positions at input angle phi (angles continued from `previous_output`).
bool PlaceOnLoop(const Loop& loop, double phi, bool clamp, std::optional<double> previous_output,
                 SphericalFourBarState* state) {
  Eigen::Vector3d w1, w2;
  if (!loop.Close(phi, clamp, &w1, &w2)) return false;
  state->input_angle = phi;
  state->input_pin = w1;
  state->output_pin = w2;
  const double psi = std::atan2(w2.dot(loop.f2), w2.dot(loop.f1));
  state->output_angle = previous_output ? Continued(psi, *previous_output) : psi;
  state->coupler_rotation_matrix = CouplerFrame(w1, w2) * loop.reference_frame.transpose();
  const double trace = state->coupler_rotation_matrix.trace();
  state->coupler_rotation = std::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0));
  // At w2, between the tangents toward w1 and toward u2.
  const Eigen::Vector3d to_w1 = w1 - w1.dot(w2) * w2, to_u2 = loop.u2 - loop.u2.dot(w2) * w2;
  state->transmission_angle_deg =
      std::atan2(to_w1.cross(to_u2).norm(), to_w1.dot(to_u2)) * 180.0 / M_PI;
  return true;
}

}  // namespace

void SphericalArcMoments(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         Eigen::Matrix3d* mean_outer, Eigen::Vector3d* mean_direction) {
  // n(s) = cos(s) e1 + sin(s) e2, s in [0, t]: <cos^2> = 1/2 + sin(2t)/(4t),
  // <sin^2> = 1/2 - sin(2t)/(4t), <cos sin> = sin^2(t)/(2t), <n> = (sin t e1 + (1 - cos t) e2)/t.
  const Eigen::Vector3d e1 = a.normalized();
  const Eigen::Vector3d across = b - b.dot(e1) * e1;
  const double t = std::atan2(across.norm(), b.dot(e1));
  if (!(t > 1e-9)) {
    *mean_outer = e1 * e1.transpose();
    *mean_direction = e1;
    return;
  }
  const Eigen::Vector3d e2 = across.normalized();
  const double cc = 0.5 + std::sin(2.0 * t) / (4.0 * t), ss = 0.5 - std::sin(2.0 * t) / (4.0 * t);
  const double cs = std::sin(t) * std::sin(t) / (2.0 * t);
  *mean_outer = cc * e1 * e1.transpose() + ss * e2 * e2.transpose() +
                cs * (e1 * e2.transpose() + e2 * e1.transpose());
  *mean_direction = (std::sin(t) * e1 + (1.0 - std::cos(t)) * e2) / t;
}

bool PlaceSphericalFourBar(const SphericalFourBarJoints& joints, double input_angle,
                           SphericalFourBarState* state) {
  std::string note;
  const std::optional<Loop> loop = MakeLoop(joints, &note);
  if (!loop) return false;
  double start = 0.0, end = 0.0;
  bool full = false;
  InputRange(*loop, &start, &end, &full);
  const double offset = TurnAhead(input_angle, start);
  if (!full && offset > end - start) return false;
  return PlaceOnLoop(*loop, start + offset, false, std::nullopt, state);
}

SphericalFourBarKinematics AnalyzeSphericalFourBarKinematics(
    const SphericalFourBarJoints& joints, const SphericalFourBarKinematicsOptions& options) {
  SphericalFourBarKinematics kinematics;
  const std::optional<Loop> made = MakeLoop(joints, &kinematics.note);
  if (!made) return kinematics;
  const Loop& loop = *made;
  const double w = options.input_speed;
  if (!(w != 0.0) || !std::isfinite(w)) {
    kinematics.note = "the input speed is 0";
    return kinematics;
  }
  InputRange(loop, &kinematics.range_start, &kinematics.range_end, &kinematics.input_rotates_fully);
  const int steps = std::max(1, options.steps);
  double first = kinematics.range_start, span = kinematics.range_end - kinematics.range_start;
  if (options.range) {
    if (!PartOfRange(*options.range, kinematics.range_start, &first, &span)) {
      kinematics.note = "the range asked for leaves the input's range on its circuit";
      return kinematics;
    }
  }

  std::optional<double> previous_output;
  // The rates at a placed state: false at a dead point.
  const auto rates = [&](SphericalFourBarState* state) {
    const Eigen::Vector3d& w1 = state->input_pin;
    const Eigen::Vector3d& w2 = state->output_pin;
    Eigen::Matrix3d system;
    system << w1, -loop.u2, -w2;
    const double determinant = system.determinant();
    if (!(std::abs(determinant) > kDeadPoint)) return false;
    const Eigen::Matrix3d inverse = system.inverse();
    // [w1, -u2, -w2] (lambda, psi', mu) = -phi' u1.
    const Eigen::Vector3d velocity = inverse * (-w * loop.u1);
    const double lambda = velocity[0], psi_rate = velocity[1], mu = velocity[2];
    state->output_velocity = psi_rate;
    state->coupler_velocity = w * loop.u1 + lambda * w1;
    // [w1, -u2, -w2] (lambda', psi'', mu') = mu psi' u2 x w2 - lambda phi' u1 x w1.
    const Eigen::Vector3d acceleration =
        inverse * (mu * psi_rate * loop.u2.cross(w2) - lambda * w * loop.u1.cross(w1));
    state->output_acceleration = acceleration[1];
    state->coupler_acceleration = acceleration[0] * w1 + lambda * w * loop.u1.cross(w1);
    // Power balance: T_in phi' + T_out psi' = 0.
    state->input_torque = -options.output_torque * psi_rate / w + 0.0;
    if (options.masses.Any()) {
      // dT/dt = omega^T I alpha per link (I about the centre, in its current place), the weight's
      // power m g . (omega x r_G).
      const SphericalFourBarMasses& masses = options.masses;
      const double r2 = masses.radius * masses.radius;
      const Eigen::Vector3d gravity(0.0, 0.0, masses.gravity ? -9.80665 : 0.0);
      double energy_rate = 0.0, weight_power = 0.0;
      const auto link = [&](double m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& omega, const Eigen::Vector3d& alpha) {
        if (!(m > 0.0)) return;
        Eigen::Matrix3d mean_outer;
        Eigen::Vector3d mean_direction;
        SphericalArcMoments(a, b, &mean_outer, &mean_direction);
        const Eigen::Matrix3d inertia = m * r2 * (Eigen::Matrix3d::Identity() - mean_outer);
        energy_rate += omega.dot(inertia * alpha);
        weight_power += m * gravity.dot(omega.cross(masses.radius * mean_direction));
      };
      link(masses.input, loop.u1, w1, w * loop.u1, Eigen::Vector3d::Zero());
      link(masses.coupler, w1, w2, state->coupler_velocity, state->coupler_acceleration);
      link(masses.output, w2, loop.u2, psi_rate * loop.u2, state->output_acceleration * loop.u2);
      state->inertial_torque = energy_rate * masses.length_unit_m / w;
      state->weight_torque = -weight_power / w + 0.0;
      state->input_torque += state->inertial_torque + state->weight_torque;
    }
    state->mechanical_advantage.reset();
    if (std::abs(psi_rate) > 1e-12 * std::abs(w)) state->mechanical_advantage = w / psi_rate;
    return true;
  };

  if (!kinematics.input_rotates_fully) {
    SphericalFourBarState dead;
    if (PlaceOnLoop(loop, kinematics.range_start, true, std::nullopt, &dead)) {
      kinematics.dead_points.push_back(dead);
    }
  }
  for (int k = 0; k < steps; ++k) {
    const double phi = SampledInput(k, steps, options.range.has_value(),
                                    kinematics.input_rotates_fully, first, span);
    SphericalFourBarState state;
    if (!PlaceOnLoop(loop, phi, false, previous_output, &state)) continue;
    previous_output = state.output_angle;
    if (!rates(&state)) {
      kinematics.dead_points.push_back(state);
      continue;
    }
    kinematics.peak_input_torque =
        std::max(kinematics.peak_input_torque, std::abs(state.input_torque));
    kinematics.states.push_back(state);
  }
  if (!kinematics.input_rotates_fully) {
    SphericalFourBarState dead;
    if (PlaceOnLoop(loop, kinematics.range_end, true, previous_output, &dead)) {
      kinematics.dead_points.push_back(dead);
    }
  }
  if (kinematics.states.empty() && kinematics.note.empty()) {
    kinematics.note = "the loop does not close over the input's range";
  }
  return kinematics;
}

}  // namespace linkfit
