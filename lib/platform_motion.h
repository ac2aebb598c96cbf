// Forward kinematics of a spatial platform held by five dyads (SS, PS or SP; see
// spatial_dyad.h), and the branch check of a motion task against it.
//
// Five constraints on a rigid body leave a one-degree-of-freedom motion: a curve in SE(3).
// TracePlatform starts at the first task pose (projected onto the constraints by Newton), and
// follows the curve by pseudo-arclength continuation in both directions until it closes on
// itself (a loop), reaches a singular configuration or runs out of steps. Singular means: the
// smallest singular value of the 5x6 constraint Jacobian falls below options.singular_tolerance,
// the step collapses, or the curve would cross a bifurcation point (det [J; t^T], t the tangent,
// changes sign; the step is then halved down to the collapse size, so the curve ends within about
// 1e-6 L of the bifurcation point and does not continue past it). It then locates every task
// pose on the traced curve: its pose error (design.md, "Conventions") is the distance to the
// nearest point of the curve, found by root finding of the distance's derivative along the curve
// between samples (not just the nearest sample).
//
// Coordinates: everything is computed with the fixed frame centered at the centroid of the task
// poses' origins and all lengths divided by L (`length`), so that the result does not depend on
// units or on where the fixed frame is. Near pose (R_k, d_k) a pose is parameterized by a twist
// (w, v): R = exp([w]) R_k, d = d_k + v, with the metric sqrt(|v|^2 + |w|^2) (that is,
// sqrt(|dd|^2 + (L dtheta)^2) in length units), which is the pose error's metric. Each
// constraint is the dyad's signed distance (unit gradient in the constrained point), evaluated
// relative to the first pose so that SS dyads of huge radius (1e6 L) keep full precision.
//
// Conventions of the report:
//   Direction: of the two directions along the curve from the first pose, the reported one is
//     the direction in which task pose 1 is met earlier in the order (ties, e.g. 2 poses on a
//     loop, go to the shorter arc length to pose 1). A task given in order along the motion thus
//     gets order 0, 1, ..., n-1.
//   Order: on a closed curve, the poses met in that direction going once around from pose 0. On
//     an open curve (ends at singular configurations or the step limit), the poses met on the
//     chosen side from pose 0 to the end, then (the motion reversing) those on the other side,
//     nearest to pose 0 first. Poses not met are left out.
//   Met: a task pose is met when the curve passes within options.pose_tolerance * L of it.
#ifndef LINKFIT_LIB_PLATFORM_MOTION_H_
#define LINKFIT_LIB_PLATFORM_MOTION_H_

#include <string>
#include <vector>

#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"

namespace linkfit {

struct PlatformMotionOptions {
  // Largest predictor step, in units of L (arc length in the metric sqrt(|dd|^2 + (L dtheta)^2)).
  double step = 0.1;
  int max_steps = 20000;  // continuation steps per direction
  // Relative to L: every dyad's residual (signed distance) at the first pose must be within this.
  double assembly_tolerance = 1e-6;
  // Smallest singular value of the 5x6 constraint Jacobian (unit-gradient rows, twist coordinates
  // scaled by L) below which the curve is at a singular (bifurcation) configuration.
  double singular_tolerance = 1e-8;
  // Relative to L: a task pose is met by the curve when its pose error is within this. Raise it to
  // judge least-squares designs whose poses are only nearly on the motion.
  double pose_tolerance = 1e-3;
};

struct PlatformMotionReport {
  bool assembles = false;   // the first task pose satisfies all five dyads (then Newton-projected)
  bool one_branch = false;  // every task pose is met on the traced curve through the first pose,
                            // with no singular configuration crossed in between
  bool closed = false;      // the traced curve closed on itself (a loop) rather than stopping at a
                            // singularity or the step limit
  // Largest of pose_errors, in length units (0 when the platform does not assemble).
  double max_pose_error = 0.0;
  // Task pose indices in the order the curve meets them (see the file comment; pose 0 first).
  std::vector<int> order;
  // Per task pose, in length units: the pose error from the nearest point of the traced curve
  // (refined between samples; a pose nearest to an end of an open curve gets its distance to that
  // end). Empty when the platform does not assemble.
  std::vector<double> pose_errors;
  // Sampled poses along the traced curve in the reported direction (at most 721): a loop starts
  // and ends at the first pose; an open curve runs from one end to the other.
  std::vector<DualQuaternion> path;
  std::string note;  // why something is false, in one plain sentence (empty when all are true)
  int steps = 0;     // continuation steps taken (both directions)
};

// Traces the motion of the platform `dyads` (exactly five) through task_poses[0] and checks the
// task poses against it. `length` is the task's characteristic length L (> 0). Never throws;
// bad input (wrong number of dyads, no poses, non-finite numbers, L <= 0) is reported in `note`
// with assembles = false.
PlatformMotionReport TracePlatform(const std::vector<SpatialDyad>& dyads,
                                   const std::vector<DualQuaternion>& task_poses, double length,
                                   const PlatformMotionOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_LIB_PLATFORM_MOTION_H_
