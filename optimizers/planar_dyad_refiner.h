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
//
// Which model is refined: a PR or RP seed stays PR or RP. An RR seed is refined as RR; if the
// refined radius (else the seed's) exceeds slider_radius_ratio * L, that circle's PR limit (line
// normal from F towards the weighted mean of the moving pivot's positions) and, when its moving
// pivot is more than slider_radius_ratio * L from E's origin, its RP limit (the same in E, with
// the fixed pivot seen from E) are refined too, and the better slider is kept unless the RR fits
// significantly better: with n poses and m = n - 5, the slider is kept iff
// (cost_slider - cost_RR) / (cost_RR / m) <= F_0.95(1, m) (if m < 1 or cost_RR = 0: iff
// cost_slider <= cost_RR). A design that meets the exact poses beats one that does not, in this
// choice as everywhere.
//
// "Worse" compares, in this order, whether the exact poses are met and the weighted cost without
// the penalty factors. Within a type the returned design is never worse than the seed; an RR seed
// may come back as a slider whose cost is above the seed's, but never significantly (the F test
// above, against a refined RR that is itself no worse than the seed). summary.message carries the
// Ceres message and notes: the models refined and kept, a seed kept, exact poses not met.
#ifndef LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_
#define LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_

#include <vector>

#include "lib/design_constraints.h"
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
  // The task's design constraints that bound one dyad (its crank's length, its fixed pivot's
  // box, its moving pivot's box; lib/design_constraints.h) as penalties raised until kept
  // (optimizers/design_bounds.h); the link bound applies by default (100 L). A design that
  // keeps them is better than one that does not (after the exact poses).
  DesignConstraints constraints;
};

// Refines `dyad` in place. `weights` and `exact` may be empty (all 1, none exact). `length` is
// the task's L (> 0). summary.model_changed says whether the dyad changed type.
RefinerSummary RefinePlanarDyad(const std::vector<PlanarPose>& poses,
                                const std::vector<double>& weights, const std::vector<bool>& exact,
                                double length, PlanarDyad* dyad,
                                const PlanarDyadRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PLANAR_DYAD_REFINER_H_
