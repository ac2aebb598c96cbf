// Spherical four-bars: two spherical RR dyads (lib/spherical_dyad.h) acting on one body, the
// input dyad driven. The links are arcs of the unit sphere about the centre: the ground gamma
// (u1 to u2), the input crank alpha1, the coupler beta (v1 to v2) and the output crank alpha2.
//
// Input angle phi: the crank pin w1 = R v1 turned about u1, counter-clockwise about u1 from the
// ground's direction e1 (u2's component normal to u1):
//   w1(phi) = cos(alpha1) u1 + sin(alpha1) (cos(phi) e1 + sin(phi) e2),  e2 = u1 x e1.
// Closure (the spherical form of the four-bar's triangle condition): the coupler pin w2 must
// satisfy |w2| = 1, u2 . w2 = cos(alpha2) and w1 . w2 = cos(beta), which it can exactly where
// the Gram determinant of (u2, w1, w2) is not negative,
//   g = u2 . w1 = cos(gamma) cos(alpha1) + sin(gamma) sin(alpha1) cos(phi)
//     in [cos(alpha2 + beta), cos(alpha2 - beta)],
// a sinusoid in phi: the input's feasible arcs in closed form (four_bar_closure.h). There
//   w2 = a u2 + b w1 + c (u2 x w1),  a = (cos(alpha2) - g cos(beta)) / (1 - g^2),
//   b = (cos(beta) - g cos(alpha2)) / (1 - g^2),  c = +-sqrt(Gram) / (1 - g^2),
// the two assembly labels (0: c >= 0, 1: c < 0), which meet at the arcs' ends. The rotation
// takes (v1, v2) to (w1, w2). Circuits, branches and defects follow as for planar four-bars
// (four_bar_motion.h JudgeOnClosure); the transmission angle mu at the coupler-output joint
// obeys cos(delta) = cos(beta) cos(alpha2) + sin(beta) sin(alpha2) cos(mu) with cos(delta) = g,
// so its extremes over a motion come from g's.
#ifndef LINKFIT_LIB_SPHERICAL_FOUR_BAR_H_
#define LINKFIT_LIB_SPHERICAL_FOUR_BAR_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "lib/four_bar_closure.h"
#include "lib/four_bar_motion.h"
#include "lib/spherical_dyad.h"

namespace linkfit {

// A dyad pair's geometry, computed once for its assemblies.
struct SphericalFourBar {
  SphericalDyad input, output;
  double ground = 0.0;   // gamma, the angle between the fixed axes
  double coupler = 0.0;  // beta, the angle between the moving axes
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();  // phi's frame
  // (v1, n, v1 x n), n the unit component of v2 normal to v1: the body frame that the assembled
  // rotation takes to (w1, ., .).
  Eigen::Matrix3d body_frame = Eigen::Matrix3d::Identity();
  // The pair makes a four-bar: neither crank nor the coupler has zero length (axes along one
  // line), so the input angle and the assembled rotation are defined.
  bool valid = false;
  std::string invalid_note;  // why not
};

SphericalFourBar MakeSphericalFourBar(const SphericalDyad& input, const SphericalDyad& output);

// The input angle phi of the body's rotation R (file comment).
double SphericalInputAngle(const SphericalFourBar& four_bar, const Eigen::Matrix3d& rotation);

// The rotations (0, 1 or 2, in label order) at which the input has angle phi and the output is
// satisfied. `tolerance` admits a Gram determinant down to -tolerance (near-tangent
// configurations that rounding would otherwise lose).
int AssembleSphericalFourBar(const SphericalFourBar& four_bar, double input_angle, double tolerance,
                             Eigen::Matrix3d rotations[2]);

// The same at the input angle of `rotation` (in *input_angle), with the crank pin taken on the
// input's cone in the direction of R v1 (no round trip through the angle).
int AssembleSphericalFourBarAt(const SphericalFourBar& four_bar, const Eigen::Matrix3d& rotation,
                               double tolerance, Eigen::Matrix3d rotations[2], double* input_angle);

// The input angles at which the four-bar assembles (file comment): an angle input, two labels.
FourBarClosure SphericalClosure(const SphericalFourBar& four_bar);

// Whether each joint turns fully: the ground-input joint (the input is a crank), the
// ground-output joint (the output is), and the coupler's two joints. A joint between links of
// angles a and b turns fully when the diagonal across it, which runs over
// [|a - b|, min(a + b, 2 pi - a - b)], stays where the other two links c and d close the
// triangle, [|c - d|, min(c + d, 2 pi - c - d)]. `change_point` is set when one of those ends
// coincides within `tolerance` (radians): the four axes can lie in one plane.
struct SphericalRotatability {
  bool input = false, output = false, input_coupler = false, coupler_output = false;
  bool change_point = false;
};
SphericalRotatability SphericalJointsRotate(const SphericalFourBar& four_bar, double tolerance);

// The Grashof class in its spherical form, with the names of lib/mechanism.h GrashofType: from
// the joints that turn fully, "double-crank" (input and output), "crank-rocker" (input),
// "rocker-crank" (output), "double-rocker" (only the coupler's), "triple-rocker" (none), or
// "change-point".
std::string SphericalGrashofType(const SphericalFourBar& four_bar, double tolerance = 1e-9);

// The transmission angle at the coupler-output joint, folded into [0, 90] degrees (90: the
// coupler pushes the output crank square); nothing where the pins are degenerate.
std::optional<double> SphericalTransmissionAngleDeg(const SphericalFourBar& four_bar,
                                                    const Eigen::Matrix3d& rotation);

// A spherical four-bar judged as a solution of a spherical motion task, driven by its input.
struct SphericalFourBarAnalysis {
  std::vector<FourBarLocation> locations;  // one per task rotation (input angles, radians)
  std::vector<std::string> defects;        // "circuit", "branch", "order"
  int circuit = -1;                        // the first pose's
  // Largest spatial pose error (SphericalMotion::PoseError) on that circuit; absent when the
  // first pose cannot be assembled.
  std::optional<double> max_pose_error;
  bool input_rotates_fully = false;
  // Transmission angle, min and max over the motion from the first to the last pose on one
  // branch (absent otherwise).
  std::optional<double> transmission_min_deg;
  std::optional<double> transmission_max_deg;
  std::string transmission_note;
  std::vector<Eigen::Matrix3d> cycle;  // rotations along the circuit (pictures)
  bool order_within_noise = false;     // as FourBarAnalysis's
};

// In closed form, as AnalyzeFourBar: the closure's arcs and labels give circuits and branches,
// the poses' input angles the defects, g's range the transmission angle. `cycle_samples` > 0
// traces the circuit with that many rotations.
SphericalFourBarAnalysis AnalyzeSphericalFourBar(const SphericalFourBar& four_bar,
                                                 const SphericalMotion& motion,
                                                 int cycle_samples = 0);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SPHERICAL_FOUR_BAR_H_
