// Least-squares refinement of a planar six-bar (lib/six_bar.h) on its pose errors: more poses than
// five, with noise (issue 36), and `linkfit refine` of a six-bar.
//
// Minimizes 1/2 sum_k w_k |e_k|^2 with e_k = (x_k - x*_k, y_k - y*_k, L (theta_k - theta*_k)), the
// task body's pose at configuration k against task pose k (|e_k| is PoseError). Parameters: the
// six-bar's joints at its reference configuration (14 numbers, lib/six_bar_frames.h: the chain's
// and both RR links'), E's place on the task body (its pose at the reference configuration) and
// each pose's turn of the upper link; each configuration's other four turns are the loop closures'
// solution by Newton's method, inside the cost for Ceres's Jets (one Newton step in Jets from the
// converged double solution carries the implicit function's exact derivatives). The first pose's
// turn is held: the reference configuration may otherwise slide along the six-bar's motion, a
// freedom of the parameters that changes nothing. Returned with the reference configuration at
// the first pose (its joints "at the first task pose").
#ifndef LINKFIT_OPTIMIZERS_SIX_BAR_REFINER_H_
#define LINKFIT_OPTIMIZERS_SIX_BAR_REFINER_H_

#include <optional>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/planar_pose.h"
#include "lib/six_bar.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct SixBarRefinerOptions {
  int max_iterations = 500;            // Levenberg-Marquardt iterations per round
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  double gradient_tolerance = 1e-16;
  // The task's bounds on the six-bar (lib/design_constraints.h SixBarViolations: the longest and
  // shortest link, the fixed pivots' box, the task body's joints' box in E) as penalties raised
  // until kept (optimizers/design_bounds.h's rounds); the link bound applies by default (100 L):
  // the pose errors fix a six-bar weakly, and without it a fit drifts toward links of hundreds
  // of L (a slider's limit) for a sliver of error.
  DesignConstraints constraints;
  // A transmission angle held (degrees): each loop's, at the configuration of every pose (the
  // analysis judges it between them), a penalty raised with the bounds' (optimizers/design_bounds.h
  // HeldTransmissionSine: a degree's margin) until within kTransmissionSlack of the held sine; a
  // fit is taken over a better one only where it keeps the minimum itself. None by default: the
  // fit alone.
  std::optional<double> min_transmission_deg;
  // A chain held (lib/six_bar.h SixBarChain::hold): the six-bar's ground pivot at the chain's, its
  // upper link and forearm of the chain's lengths and its wrist at the chain's place in E, each a
  // penalty of weight kChainHoldWeight (deviations of order 1e-8 L). None by default: every joint
  // free, the chain's too.
  std::optional<SixBarChain> held_chain;
};

inline constexpr double kChainHoldWeight = 1e10;

// A six-bar placed at the task poses: its configuration at each (the turns AnalyzeSixBar drives
// through) and its pose errors there (PoseError with L).
struct SixBarFit {
  SixBar six_bar;
  std::vector<SixBarAngles> at_poses;
  std::vector<double> pose_errors;
  double rms_pose_error = 0.0;  // weighted: sqrt(sum w e^2 / sum w)
  double max_pose_error = 0.0;
};

// Places `six_bar` at each pose: from `start[k]` (turns near the pose's configuration, e.g. its
// chain's inverse kinematics there; without it, the nearest of the configurations over the upper
// link's range from the reference one, lib/six_bar.h SixBarSweep), the upper link turned to where
// the task body comes nearest the pose (Gauss-Newton on its turn, the other turns by assembly).
// Returns false (and leaves *fit incomplete) where a pose cannot be assembled near its start.
// `weights` may be empty.
bool FitSixBarToPoses(const SixBar& six_bar, const std::vector<PlanarPose>& poses,
                      const std::vector<double>& weights, double length,
                      const std::vector<SixBarAngles>& start, SixBarFit* fit);

// The same six-bar with its reference configuration moved to `angles` (the turns from the
// present one): every joint where it is there, E's place on the task body kept.
SixBar ReReferenceSixBar(const SixBar& six_bar, const SixBarAngles& angles);

// Refines fit->six_bar (from its configurations fit->at_poses) on the pose errors, and rewrites
// *fit; never returns a worse fit than it was given. `weights` may be empty (all 1); `length` is
// the task's L (> 0).
RefinerSummary RefineSixBar(const std::vector<PlanarPose>& poses,
                            const std::vector<double>& weights, double length, SixBarFit* fit,
                            const SixBarRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_SIX_BAR_REFINER_H_
