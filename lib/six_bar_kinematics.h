// Kinematic and static analysis of a planar six-bar (lib/six_bar.h) driven by one of its
// grounded links at a constant speed: every body's angle, angular velocity and angular
// acceleration, the tool frame's origin's position, velocity and acceleration, the two loops'
// transmission angles, the mechanical advantage and the input torque that holds a load.
//
// Positions come from SixBarDriver (closed form where the input leaves two dyads, else
// continuation). The rates are the closure's derivatives, not finite differences: a point p of
// body k moves with v = G omega, G = SixBarFrames::Gradient (2 x 5), whose column j is
// perp(d_j) for each body j on the path from ground to k (d_j the body's lever from the joint
// it hangs by toward p); differentiated again, a = G alpha + sum_j omega_j^2 perp(G_j) (the
// centripetal -omega_j^2 d_j). The two loop closures C = OnLink - OnBody give, with the input's
// rate w and no input acceleration,
//   J_free omega_free = -J_input w,
//   J_free alpha_free = -sum_j omega_j^2 perp(J_j)   (each closure's 2 rows),
// J the closure's Jacobian (SixBarFrames::ClosureJacobian); J_free is singular at the input's
// dead points.
#ifndef LINKFIT_LIB_SIX_BAR_KINEMATICS_H_
#define LINKFIT_LIB_SIX_BAR_KINEMATICS_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lib/six_bar.h"
#include "lib/uniform_body.h"

namespace linkfit {

// A load the input holds: a force at the tool frame's origin (the task body's point the task
// moves) and a torque on the task body, counter-clockwise.
struct SixBarLoad {
  Eigen::Vector2d tool_force = Eigen::Vector2d::Zero();
  double task_body_torque = 0.0;
};

// The bodies' masses (kg), for the torque that drives them at the constant input speed (their
// inertia) and, with `gravity`, holds their weight. Each body is uniform over its points (its
// joints, the task body's with the tool frame's origin): a bar between two, a plate on three or
// more (the polygon through them in order), a point mass alone. The result's lengths are
// `length_unit_m` metres each: the torques come out in N times that length.
struct SixBarMasses {
  SixBarAngles mass = SixBarAngles::Zero();  // bodies 1 to 5
  double length_unit_m = 1.0;
  bool gravity = false;  // along -y of Sigma, g = 9.80665
  bool Any() const { return (mass.array() > 0.0).any(); }
};

struct SixBarKinematicsOptions {
  double input_speed = 1.0;  // the input link's constant angular velocity (rad/s, not 0)
  int steps = 360;           // samples over the input's range
  // A part of the input's range instead: the input link's directions in Sigma (radians, from <
  // to, both ends sampled), on the reference's assembly.
  std::optional<std::pair<double, double>> range;
  SixBarLoad load;
  SixBarMasses masses;
};

// One configuration. Bodies are numbered as in lib/six_bar.h (1 .. 5 at index 0 .. 4).
struct SixBarState {
  SixBarAngles turns = SixBarAngles::Zero();  // each body's turn from the reference (radians)
  SixBarAngles angular_velocity = SixBarAngles::Zero();      // rad/s
  SixBarAngles angular_acceleration = SixBarAngles::Zero();  // rad/s^2
  double input_angle = 0.0;  // the input link's direction in Sigma (radians, continued)
  Eigen::Vector2d tool_point = Eigen::Vector2d::Zero();  // the tool frame's origin
  Eigen::Vector2d tool_velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d tool_acceleration = Eigen::Vector2d::Zero();
  std::array<double, 2> transmission_deg = {90.0,
                                            90.0};  // each loop's, 0..90 (SixBarTransmissionDeg)
  // The task body's torque over the input's (w_input / w_task_body); none where the task body
  // does not turn.
  std::optional<double> mechanical_advantage;
  // Holding the load (virtual work), plus with masses the bodies' inertia and weight (their
  // parts below).
  double input_torque = 0.0;
  double inertial_torque = 0.0, weight_torque = 0.0;
};

struct SixBarKinematics {
  bool input_rotates_fully = false;
  double range_start = 0.0, range_end = 0.0;  // the input link's directions (radians)
  std::vector<SixBarState> states;
  // Where a rocking input's range ends (the input's dead points): positions and transmission
  // angles only.
  std::vector<SixBarState> dead_points;
  double peak_input_torque = 0.0;
  std::string note;  // where the analysis could not be done: why (states empty)
};

// The input link's direction in Sigma at the reference configuration (radians): the upper link
// from the ground pivot to the elbow, an RR link from its first joint to its second.
double SixBarInputReferenceAngle(const SixBar& six_bar, int input);

// Analyzes the six-bar driven by body `input` (a grounded link: 1, 4 or 5) from its reference
// configuration (turns 0), on that assembly. `length` sets the tolerances.
SixBarKinematics AnalyzeSixBarKinematics(const SixBar& six_bar, int input,
                                         const SixBarKinematicsOptions& options, double length);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SIX_BAR_KINEMATICS_H_
