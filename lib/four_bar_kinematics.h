// Kinematic and static analysis of a planar four-bar driven by its input crank at a constant
// speed: every link's angle, angular velocity and angular acceleration, the coupler point's
// position, velocity and acceleration, the transmission angle and the mechanical advantage, and
// the input torque that holds a load (virtual work), in closed form from the loop equation and
// its first two derivatives (not finite differences).
//
// A 4R (input crank A0 A, coupler A B, output rocker B0 B) closes A0 + r2 + r3 = B0 + r4 with
// r2 = A - A0, r3 = B - A, r4 = B - B0. Differentiated at the input rate w2 (a2 = 0):
//   w3 perp(r3) - w4 perp(r4) = -w2 perp(r2),
//   a3 perp(r3) - a4 perp(r4) = w2^2 r2 + w3^2 r3 - w4^2 r4,
// two linear systems in (w3, w4) and (a3, a4) whose determinant cross(r3, r4) vanishes where the
// transmission angle (between the coupler and the rocker at B) is 0 or 180 degrees: the input's
// dead points. A slider-crank (the output pin B on a line through Q along u on ground,
// B = Q + s u) closes the same way with s in place of the rocker's turn:
//   s' u - w3 perp(r3) = w2 perp(r2),   s'' u - a3 perp(r3) = -w2^2 r2 - w3^2 r3,
// singular where the coupler is normal to the line.
//
// The input's range: a whole turn where the loop closes at every crank angle (a crank), else
// the interval between the two dead points about the first task pose's crank angle (a rocker),
// sampled inside them; the dead points themselves are listed with their configuration.
#ifndef LINKFIT_LIB_FOUR_BAR_KINEMATICS_H_
#define LINKFIT_LIB_FOUR_BAR_KINEMATICS_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace linkfit {

// A four-bar's joints at its reference configuration (the first task pose), in Sigma.
struct FourBarJoints {
  Eigen::Vector2d input_pivot = Eigen::Vector2d::Zero();  // A0
  Eigen::Vector2d input_pin = Eigen::Vector2d::Zero();    // A
  Eigen::Vector2d output_pin = Eigen::Vector2d::Zero();   // B
  // A 4R: the output pivot B0. A slider-crank: B slides on the line through slider_point along
  // slider_direction (a unit vector), on ground.
  bool slider = false;
  Eigen::Vector2d output_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d slider_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d slider_direction = Eigen::Vector2d::UnitX();
  // The coupler point (or the tool frame's origin), rigid with the coupler; none for a function
  // generator.
  std::optional<Eigen::Vector2d> coupler_point;
};

// A load the input holds at every step (applied to the mechanism; all optional).
struct FourBarLoad {
  Eigen::Vector2d coupler_force = Eigen::Vector2d::Zero();  // at the coupler point (N)
  double output_torque = 0.0;  // on the output rocker, counter-clockwise (N m)
  double slider_force = 0.0;   // on the slider along slider_direction (N)
};

// The links' masses, for the torque that drives them at the constant input speed (their
// inertia) and, with `gravity`, holds their weight. Each link a uniform body: the crank and the
// rocker bars between their joints, the coupler a plate on A, B and the coupler point (a bar
// from A to B without one), a slider a block moving with B. Masses in kg; the result's lengths
// are `length_unit_m` metres each, so that the torques come out in newtons times that length.
struct FourBarMasses {
  double input = 0.0, coupler = 0.0, output = 0.0;  // kg (output: the rocker, or the slider)
  double length_unit_m = 1.0;                       // metres per length unit of the result
  bool gravity = false;                             // weight along -y of Sigma, g = 9.80665
  bool Any() const { return input > 0.0 || coupler > 0.0 || output > 0.0; }
};

// Standard gravity (m/s^2).
inline constexpr double kStandardGravity = 9.80665;

struct FourBarKinematicsOptions {
  double input_speed = 1.0;  // the input crank's constant angular velocity (rad/s, not 0)
  int steps = 360;           // samples over the input's range
  // A part of the input's range to sample instead (crank angles in radians, from < to, both
  // ends sampled), on the reference's circuit: the task's motion, away from a rocker's dead
  // points where the rates grow without bound.
  std::optional<std::pair<double, double>> range;
  FourBarLoad load;
  FourBarMasses masses;
};

// One configuration: angles in Sigma (radians, continued along the range), rates per second.
struct FourBarState {
  double input_angle = 0.0;  // the crank's angle, atan2 of A - A0
  // The coupler's and the output rocker's angles (atan2 of B - A and B - B0), angular velocities
  // and accelerations; a slider-crank's output is the slider's position s along its line (from
  // slider_point), its velocity and acceleration.
  double coupler_angle = 0.0, coupler_velocity = 0.0, coupler_acceleration = 0.0;
  double output = 0.0, output_velocity = 0.0, output_acceleration = 0.0;
  Eigen::Vector2d input_pin = Eigen::Vector2d::Zero(), output_pin = Eigen::Vector2d::Zero();
  Eigen::Vector2d coupler_point = Eigen::Vector2d::Zero();  // (zero without one)
  Eigen::Vector2d coupler_point_velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d coupler_point_acceleration = Eigen::Vector2d::Zero();
  // Between the coupler and the rocker at B (a slider: the coupler and the line's normal),
  // 0..180 degrees; 0 or 180 at a dead point.
  double transmission_angle_deg = 90.0;
  // Output torque over input torque (a slider: output force over input torque, per length),
  // from the power balance w2 / w4; none where the output stands still (its own limits).
  std::optional<double> mechanical_advantage;
  // The input torque that drives the mechanism at the constant input speed against the load:
  // the load's part (virtual work), plus with masses the links' inertia (the rate of their
  // kinetic energy over the input speed) and, with gravity, their weight. N times the length.
  double input_torque = 0.0;
  double inertial_torque = 0.0;  // the links' inertia's part of it
  double weight_torque = 0.0;    // their weight's part
};

struct FourBarKinematics {
  bool input_rotates_fully = false;
  double range_start = 0.0, range_end = 0.0;  // the input's range (radians)
  std::vector<FourBarState> states;
  // The input's dead points at the ends of a rocker's range: positions and transmission angle
  // only (the rates are unbounded there).
  std::vector<FourBarState> dead_points;
  double peak_input_torque = 0.0;  // the largest |input_torque| over the states
  std::string note;                // where the analysis could not be done: why (states empty)
};

// Analyzes the four-bar (FourBarJoints at its reference configuration, the assembly it is in
// there followed). `length` sets the tolerances.
FourBarKinematics AnalyzeFourBarKinematics(const FourBarJoints& joints,
                                           const FourBarKinematicsOptions& options, double length);

// The four-bar at the crank angle `input_angle` (radians), on the circuit of its reference
// configuration: its pins, coupler point, the coupler's and the output's angles and the
// transmission angle (no rates). False outside the input's range about the reference (where the
// loop does not close, or closes only on another circuit).
bool PlaceFourBar(const FourBarJoints& joints, double input_angle, double length,
                  FourBarState* state);

}  // namespace linkfit

#endif  // LINKFIT_LIB_FOUR_BAR_KINEMATICS_H_
