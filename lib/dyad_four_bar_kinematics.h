// Kinematic and static analysis of a planar four-bar of any type (lib/mechanism.h: two dyads, RR,
// PR or RP, acting on the coupler E) driven by its input dyad's joint at a constant rate: a
// crank's angle (RR), a slider's position (PR) or the coupler's angle (RP, the slider block
// turning about its fixed pivot). lib/four_bar_kinematics.h covers the 4R and the slider-crank
// driven by their crank in closed form; this covers the rest: inverted slider-cranks, double
// sliders, RPRP, and any four-bar driven by a slider.
//
// The coupler's configuration z = (c, theta): a point p of E is at P(p) = c + R(theta) p, its
// derivatives P_z = [I, perp(R p)] and P_theta theta = -R p. Each dyad is one closure equation,
//   RR: |P(m) - f|^2 - r^2 = 0,  PR: n . (P(m) - q) = 0,  RP: (R n_E) . (f - P(a_E)) = 0,
// and the input's joint value one more: an RR input's pin P(m) = f + r u(phi) (two rows with its
// circle), a PR input's P(m) = q + s d, an RP input's theta = its value. Differentiated at the
// input's rate (no input acceleration), J z' = b and J z'' = -(each row's second-order part in
// z'), J (3 x 3) singular at the input's dead points. Positions come from AssembleFourBar, each
// step on the assembly nearest the last.
#ifndef LINKFIT_LIB_DYAD_FOUR_BAR_KINEMATICS_H_
#define LINKFIT_LIB_DYAD_FOUR_BAR_KINEMATICS_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

// A load the input holds (all optional): a force at the coupler point, a torque on an RR
// output's rocker (counter-clockwise), a force on a slider along its line (a PR output's along
// the fixed line; an RP output's on the block along the coupler's line, as a cylinder pushes).
struct DyadFourBarLoad {
  Eigen::Vector2d coupler_force = Eigen::Vector2d::Zero();
  double output_torque = 0.0;
  double slider_force = 0.0;
};

// The links' masses (kg), for the effort that drives them at the constant input rate (their
// inertia) and, with `gravity`, holds their weight: an RR link a uniform bar from its pivot to its
// pin, a PR's block a mass moving with its pin, an RP's block on its ground pivot (its centre
// still: no energy), the coupler uniform over its pins (an RP's line point) and coupler point (a
// bar, a plate, a point mass). The result's lengths are `length_unit_m` metres each.
struct DyadFourBarMasses {
  double input = 0.0, coupler = 0.0, output = 0.0;
  double length_unit_m = 1.0;
  bool gravity = false;
  bool Any() const { return input > 0.0 || coupler > 0.0 || output > 0.0; }
};

struct DyadFourBarKinematicsOptions {
  double input_speed = 1.0;  // the input joint's constant rate: rad/s, or length/s for a slider
  int steps = 360;
  // A part of the input's range instead (input joint values: radians, or lengths), from < to,
  // both ends sampled, on the first configuration's assembly.
  std::optional<std::pair<double, double>> range;
  DyadFourBarLoad load;
  DyadFourBarMasses masses;
};

struct DyadFourBarState {
  double input = 0.0;  // the input joint's value (radians, or the slider's position)
  PlanarPose coupler;  // E in Sigma (theta continued over the range)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // (c', theta')
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // (c'', theta'')
  // The output joint: an RR rocker's angle (atan2 of its pin from its pivot), a PR slider's
  // position along its line, an RP block's slide (where the fixed pivot is along the coupler's
  // line, from the line's point in E); and its rates.
  double output = 0.0, output_velocity = 0.0, output_acceleration = 0.0;
  Eigen::Vector2d coupler_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d coupler_point_velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d coupler_point_acceleration = Eigen::Vector2d::Zero();
  // Between the line along which the coupler passes force to the output (from its pin at the
  // input, or normal to its line at an RP input's block) and the output's own path's normal
  // (a rocker's line, a slider line's normal), or for an RP output between the coupler's line
  // and the input joint's path (a crank pin's, or the slider line): 0..180, 0 or 180 at a dead
  // point, 90 best.
  double transmission_angle_deg = 90.0;
  std::optional<double> mechanical_advantage;  // input rate over output rate; none where still
  // The input torque (or a slider input's force) holding the load, plus with masses the links'
  // inertia and weight (their parts below).
  double input_effort = 0.0;
  double inertial_effort = 0.0, weight_effort = 0.0;
};

struct DyadFourBarKinematics {
  bool input_rotates_fully = false;  // an angle input with no dead point in a whole turn
  double range_start = 0.0, range_end = 0.0;
  // Both ends are dead points (else one is where a slider left its +-10 lengths from the first
  // value, or where the coupler runs off toward infinity).
  bool range_bounded = true;
  std::vector<DyadFourBarState> states;
  std::vector<DyadFourBarState> dead_points;  // positions only
  double peak_input_effort = 0.0;
  std::string note;
};

// `input`, `output`: the dyads with E the coupler's frame (the identity pose is the first
// configuration where they are given in Sigma at it); `coupler_point` in E; `length` sets the
// tolerances and a slider's search.
DyadFourBarKinematics AnalyzeDyadFourBarKinematics(
    const PlanarDyad& input, const PlanarDyad& output,
    const std::optional<Eigen::Vector2d>& coupler_point, const PlanarPose& first,
    const DyadFourBarKinematicsOptions& options, double length);

}  // namespace linkfit

#endif  // LINKFIT_LIB_DYAD_FOUR_BAR_KINEMATICS_H_
