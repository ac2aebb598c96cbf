// Mechanism-level refinement of a planar four-bar for a motion task: the pose error of the
// design, not the dyads' residuals.
//
// Minimizes 1/2 sum_j w_j PoseError_j^2, PoseError_j = sqrt(|d(q_j) - d_j|^2 + (L dtheta_j)^2)
// (planar_pose.h), where q_j is the coupler pose of the four-bar assembled at the input value
// the task pose gives (InputValue, mechanism.h) on the assembly branch of the first pose's
// circuit: the pose error AnalyzeFourBar measures (four_bar_motion.h). Unknowns: both dyads'
// parameters (RR: F, M, r; PR: M, unit line normal, offset; RP: F, unit line normal in E, offset;
// normals on a sphere manifold). The q_j are eliminated exactly (closed-form assembly, so both
// dyads hold at every q_j to rounding); the solver does not step where a pose goes past the
// input's reach. Two starts are refined and the better kept: the seed itself, and the seed after
// a penalty stage in which the q_j are free unknowns and the dyads (with the input-value
// condition) weighted residuals, which crosses stationary configurations and gaps of the input's
// range that the exact elimination cannot. Poses marked exact get a large weight, then the
// method of multipliers and a few least-norm Gauss-Newton steps until their pose error is within
// exact_tolerance * L. Data are centred (pose origins' centroid) and scaled by L internally.
//
// The task's design constraints (options.constraints; the link bound of 100 L by default) are
// quadratic penalties on the dyads, raised round by round until the design keeps them
// (optimizers/design_bounds.h); so is a held transmission angle (options.min_transmission_deg),
// and a design that keeps it counts as keeping the bounds below. The result is re-analysed as
// AnalyzeFourBar does, and the seed returned unchanged unless the result is not worse: it assembles
// at the first pose, has no circuit defect the seed did not have, meets the exact poses (or comes
// nearer), keeps the design bounds when the seed does not (or both do or both do not), and has no
// higher cost. A seed that does not assemble at the first pose, or whose two dyads coincide (no
// four-bar), is returned with a message. On noisy poses the cost can keep falling toward a
// degenerate four-bar (a crank running off toward a slider, or the two dyads toward one); the
// refiner then stops (at max_iterations, or just short of coincident dyads) and says so in the
// message. PR+PR and RP+RP four-bars (Cardan motion and its inverse) are reached as motions only: a
// one-parameter family of dyad pairs gives the same motion.
#ifndef LINKFIT_OPTIMIZERS_FOUR_BAR_REFINER_H_
#define LINKFIT_OPTIMIZERS_FOUR_BAR_REFINER_H_

#include <optional>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct FourBarRefinerOptions {
  int max_iterations = 100;            // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  // Dyad residuals at the q_j, times L. Unused: the exact elimination satisfies both dyads at
  // every q_j to rounding (kept for interface stability).
  double constraint_tolerance = 1e-12;
  double exact_tolerance = 1e-9;  // exact poses' pose error, times L
  int max_penalty_rounds = 8;     // method-of-multipliers rounds for exact poses, per start
  // The task's design constraints (lib/design_constraints.h) as penalties raised until kept
  // (optimizers/design_bounds.h); the link bound applies by default (100 L).
  DesignConstraints constraints;
  // When set, the transmission angle (lib/four_bar_motion.h TransmissionAngleDeg) is held at or
  // above it (degrees, plus a 1 degree margin) as the design bounds are: a penalty raised with
  // theirs, read at the task's coupler poses and between each two (interpolated), where the
  // four-bar's configurations lie near them. No RP dyad.
  std::optional<double> min_transmission_deg;
};

// Refines the four-bar (input, output) in place. `weights`/`exact` may be empty. Costs in the
// summary are 1/2 sum w_j PoseError_j^2 (length units squared); initial_max / final_max the
// largest pose error on the first pose's circuit (AnalyzeFourBar), rms likewise.
RefinerSummary RefineFourBar(const std::vector<PlanarPose>& poses,
                             const std::vector<double>& weights, const std::vector<bool>& exact,
                             double length, PlanarDyad* input, PlanarDyad* output,
                             const FourBarRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_FOUR_BAR_REFINER_H_
