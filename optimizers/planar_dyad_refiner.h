// Least-squares refinement of one planar dyad (RR, PR or RP; lib/dyad.h) on its geometric
// residual, for approximate motion synthesis (more poses than five, with noise).
//
// Minimizes 1/2 sum_j w_j e_j^2 with e_j = PlanarDyad::Residual(pose_j): the signed distance of
// the moving pivot from its circle (RR) or line (PR), or of the fixed pivot from its line in E
// (RP). Parameters: RR (F, M, r); PR (M, unit normal n of the line on a sphere manifold, offset);
// RP (F, unit normal in E, offset): a line is never a circle of huge radius and a circle never
// flips to a line inside the solver. Poses marked exact must be met to exact_tolerance * L: their
// weights are raised by a penalty continuation until they are (or the summary says they could not
// be). Data are centred and scaled by L internally. Never returns a worse design than its seed.
#ifndef LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_
#define LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_

#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct PlanarDyadRefinerOptions {
  int max_iterations = 50;             // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  // An RR radius beyond this times L (seed or refined) is also refined as its slider limit (PR;
  // RP when the moving pivot runs off in E) and the slider kept unless the circle fits
  // significantly better (nested F test at 5 %): a slider is reported as a slider.
  double slider_radius_ratio = 10.0;
  double exact_tolerance = 1e-9;  // poses marked exact are met to this times L
  int max_penalty_rounds = 8;     // penalty continuation: exact weights x 1e3 per round
};

// Refines `dyad` in place. `weights` and `exact` may be empty (all 1, none exact). `length` is
// the task's L (> 0). summary.model_changed says whether the dyad changed type.
RefinerSummary RefinePlanarDyad(const std::vector<PlanarPose>& poses,
                                const std::vector<double>& weights,
                                const std::vector<bool>& exact, double length, PlanarDyad* dyad,
                                const PlanarDyadRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_
