// Kinematic and static analysis of a spherical four-bar (lib/spherical_four_bar.h: its joints are
// unit axes through the centre) driven by its input crank at a constant speed, in closed form.
//
// The input crank turns about u1 at phi' (alpha = 0), the output about u2 at psi'; the coupler
// carries the pins w1 (shared with the input) and w2 (with the output). A pin's velocity is the
// same on both links it joins: omega3 x w1 = phi' u1 x w1 and omega3 x w2 = psi' u2 x w2, so
//   omega3 = phi' u1 + lambda w1 = psi' u2 + mu w2,
// three equations in (lambda, psi', mu):  [w1, -u2, -w2] (lambda, psi', mu) = -phi' u1.
// Differentiated (w1' = phi' u1 x w1, w2' = psi' u2 x w2):
//   [w1, -u2, -w2] (lambda', psi'', mu') = mu psi' u2 x w2 - lambda phi' u1 x w1,
// and the coupler's angular acceleration alpha3 = lambda' w1 + lambda phi' u1 x w1. The matrix is
// singular where w1, w2 and u2 lie in one plane: the transmission angle (at w2, between the arcs
// to w1 and to u2) is 0 or 180 degrees, the input's dead points.
//
// Positions (lib/spherical_four_bar.h): w1(phi) = cos(alpha1) u1 + sin(alpha1) (cos(phi) e1 +
// sin(phi) e2), e1 the unit component of u2 normal to u1, e2 = u1 x e1; w2 = a u2 + b w1 +
// c (u2 x w1) on the side (the sign of c) it is on at the first pose. The output's angle psi is
// measured the same way about u2, from the unit component of u1 normal to u2.
#ifndef LINKFIT_LIB_SPHERICAL_FOUR_BAR_KINEMATICS_H_
#define LINKFIT_LIB_SPHERICAL_FOUR_BAR_KINEMATICS_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace linkfit {

// The joints at the first pose: unit axes through the centre, in Sigma.
struct SphericalFourBarJoints {
  Eigen::Vector3d input_pivot = Eigen::Vector3d::UnitZ();   // u1
  Eigen::Vector3d input_pin = Eigen::Vector3d::UnitZ();     // w1
  Eigen::Vector3d output_pin = Eigen::Vector3d::UnitZ();    // w2
  Eigen::Vector3d output_pivot = Eigen::Vector3d::UnitZ();  // u2
};

// The links' masses (kg), for the torque that drives them at the constant input speed (their
// inertia) and, with `gravity`, holds their weight. Each link is a uniform thin arc of the sphere
// of `radius` between its two axes (the input from u1 to w1, the coupler from w1 to w2, the
// output from w2 to u2): about the centre its inertia tensor is m r^2 (I - <n n^T>), the mean of
// n n^T over the arc's directions n, and its centre of mass r <n>. A body turning about the
// fixed centre has dT/dt = omega^T I alpha. The result's lengths are `length_unit_m` metres.
struct SphericalFourBarMasses {
  double input = 0.0, coupler = 0.0, output = 0.0;
  double radius = 1.0;
  double length_unit_m = 1.0;
  bool gravity = false;  // along -z of Sigma, g = 9.80665
  bool Any() const { return input > 0.0 || coupler > 0.0 || output > 0.0; }
};

// A uniform thin arc of the unit sphere from direction a to b: the mean of n n^T over its
// directions, and the mean direction (its centre of mass on the unit sphere's scale).
void SphericalArcMoments(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         Eigen::Matrix3d* mean_outer, Eigen::Vector3d* mean_direction);

struct SphericalFourBarKinematicsOptions {
  double input_speed = 1.0;  // rad/s, not 0
  int steps = 360;
  // A part of the input's range instead (input angles phi in radians, from < to, both ends
  // sampled), on the first pose's circuit.
  std::optional<std::pair<double, double>> range;
  double output_torque = 0.0;  // a load on the output crank, about u2 (right hand)
  SphericalFourBarMasses masses;
};

struct SphericalFourBarState {
  double input_angle = 0.0;                                                     // phi
  double output_angle = 0.0, output_velocity = 0.0, output_acceleration = 0.0;  // psi and rates
  Eigen::Vector3d input_pin = Eigen::Vector3d::Zero(), output_pin = Eigen::Vector3d::Zero();
  // The coupler's angular velocity and acceleration vectors (rad/s, rad/s^2, in Sigma) and the
  // angle of its rotation from the first pose (radians, 0 .. pi).
  Eigen::Vector3d coupler_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d coupler_acceleration = Eigen::Vector3d::Zero();
  double coupler_rotation = 0.0;
  Eigen::Matrix3d coupler_rotation_matrix = Eigen::Matrix3d::Identity();
  double transmission_angle_deg = 90.0;        // at w2, 0 .. 180
  std::optional<double> mechanical_advantage;  // phi' / psi'; none where the output stands still
  // Holding the output torque (virtual work), plus with masses the links' inertia and weight
  // (their parts below).
  double input_torque = 0.0;
  double inertial_torque = 0.0, weight_torque = 0.0;
};

struct SphericalFourBarKinematics {
  bool input_rotates_fully = false;
  double range_start = 0.0, range_end = 0.0;  // the input's range (phi, radians)
  std::vector<SphericalFourBarState> states;
  std::vector<SphericalFourBarState> dead_points;  // a rocker's range ends (positions only)
  double peak_input_torque = 0.0;
  std::string note;  // where the analysis could not be done: why (states empty)
};

SphericalFourBarKinematics AnalyzeSphericalFourBarKinematics(
    const SphericalFourBarJoints& joints, const SphericalFourBarKinematicsOptions& options);

// The four-bar at input angle `input_angle` on the first pose's circuit (positions, no rates):
// false outside the input's range there.
bool PlaceSphericalFourBar(const SphericalFourBarJoints& joints, double input_angle,
                           SphericalFourBarState* state);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SPHERICAL_FOUR_BAR_KINEMATICS_H_
