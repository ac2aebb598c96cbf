// Mechanism-level refinement of a planar four-bar for a motion task: the pose error of the
// design, not the dyads' residuals.
//
// Unknowns: both dyads' parameters (as in planar_dyad_refiner.h) and the coupler pose q_j the
// mechanism takes for each task pose j. Minimizes
//   1/2 sum_j w_j (|d(q_j) - d_j|^2 + (L dtheta(q_j, pose_j))^2)
// subject to both dyads being satisfied at every q_j (their residuals are equality constraints,
// enforced by a penalty continuation to 1e-12 L). Starting from the configurations on the
// circuit of the first pose (lib/four_bar_motion.h), the q_j stay on that circuit: the refined
// design is re-analysed with AnalyzeFourBar and rejected (the seed returned) if it is not better
// on one circuit. Poses marked exact get their pose error driven to exact_tolerance * L the same
// way. Data are centred and scaled by L internally.
#ifndef LINKFIT_OPTIMIZERS_FOUR_BAR_REFINER_H_
#define LINKFIT_OPTIMIZERS_FOUR_BAR_REFINER_H_

#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct FourBarRefinerOptions {
  int max_iterations = 100;            // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  double constraint_tolerance = 1e-12; // dyad residuals at the q_j, times L
  double exact_tolerance = 1e-9;       // exact poses' pose error, times L
  int max_penalty_rounds = 8;          // penalty continuation rounds
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
