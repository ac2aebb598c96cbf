// Planar four-bars made of two dyads sharing the coupler E, and their assembly (forward
// kinematics) for a given value of the input joint.
//
// The input joint value of a dyad is:
//   RR: the crank angle, atan2 of (moving pivot in Sigma - fixed pivot), radians;
//   PR: the slider position s along the line, moving pivot = line_point + s * direction;
//   RP: the coupler angle theta (the slider block turns with E about the fixed pivot).
#ifndef LINKFIT_LIB_MECHANISM_H_
#define LINKFIT_LIB_MECHANISM_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

enum class FourBarType {
  k4R,                    // RR + RR
  kSliderCrank,           // RR + PR (RRRP)
  kInvertedSliderCrank,   // RR + RP
  kDoubleSlider,          // PR + PR (elliptic trammel, PRRP)
  kRPRP,                  // PR + RP, prismatic joints alternate around the loop
  kInvertedDoubleSlider,  // RP + RP (both prismatic joints on the coupler)
};

const char* FourBarTypeName(FourBarType type);
FourBarType ClassifyFourBar(DyadType a, DyadType b);

// Grashof type of a 4R, with `input` as the driven link:
// "crank-rocker", "double-crank", "double-rocker", "rocker-crank" (Grashof linkages),
// "triple-rocker" (non-Grashof) or "change-point". `length` sets the tolerance of the
// change-point test (|s + l - p - q| <= 1e-9 * length).
std::string GrashofType(const PlanarDyad& input, const PlanarDyad& output, double length);

// The input joint value of `dyad` when the coupler is at `pose` (see the file comment).
double InputValue(const PlanarDyad& dyad, const PlanarPose& pose);

// Assembles the four-bar: all coupler poses (0, 1 or 2) at which `input` has joint value
// `input_value` and `output` is satisfied. `tolerance` (a length) admits near-tangent
// configurations where rounding would otherwise lose the assembly.
int AssembleFourBar(const PlanarDyad& input, const PlanarDyad& output, double input_value,
                    double tolerance, std::vector<PlanarPose>* coupler_poses);

// AssembleFourBar at the input value `pose` gives (InputValue, returned in *input_value); for an
// RR input the crank pin is taken on the pose's own crank direction, without the round trip
// through the angle (the analyses assemble every task pose of every dyad pair).
int AssembleFourBarAtPose(const PlanarDyad& input, const PlanarDyad& output, const PlanarPose& pose,
                          double tolerance, std::vector<PlanarPose>* coupler_poses,
                          double* input_value);

// The output dyad's condition on the coupler's turn theta about the input pin: with the input
// pin at `pivot` (Sigma) and m1 its point of E, the coupler at R(theta) (p_E - m1) + pivot closes
// the output when a cos(theta) + b sin(theta) = c. `scale` converts a slack in length into one
// relative to hypot(a, b) (AssembleFourBar's tangency tolerance).
void OutputTurnEquation(const PlanarDyad& output, const Eigen::Vector2d& m1,
                        const Eigen::Vector2d& pivot, double* a, double* b, double* c,
                        double* scale);

// For each task pose: assemble at the input value taken from that pose and keep the
// configuration nearest the pose. Returns the largest pose error (see PoseError), or nothing
// when the mechanism does not assemble at some pose.
std::optional<double> MaxAssembledPoseError(const PlanarDyad& input, const PlanarDyad& output,
                                            const std::vector<PlanarPose>& poses, double length);

}  // namespace linkfit

#endif  // LINKFIT_LIB_MECHANISM_H_
