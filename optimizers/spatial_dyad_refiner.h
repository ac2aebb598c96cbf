// Least-squares refinement of one spatial dyad (seed 000 §3) on its geometric residual.
//
// Given poses (R_j, d_j), j = 1..n, with weights w_j > 0 and a seed dyad (SS or PS, e.g. the
// algebraic least-squares fit), minimizes
//   1/2 sum_j w_j e_j^2,   e_j = SpatialDyad::Residual(R_j, d_j),
// the signed distance of C_j = R_j c + d_j from the sphere |X - A| = r (SS) or from the plane
// n . X = h (PS), by Levenberg-Marquardt (Ceres, automatic derivatives). Parameters: SS
// (A, c, r); PS (c, n, h) with n kept unit on the sphere manifold.
//
// The data are centred (pose-origin centroid of Sigma to 0) and divided by the task's
// characteristic length L before the solve, and the answer is mapped back, so the result does
// not depend on units; the weights are divided by their mean (their overall scale does not
// matter either).
//
// Poses marked exact must be met to exact_tolerance * L: after the solve, while an exact pose
// misses, the exact poses' weights are multiplied by 1e3 and the model solved again from where
// it stopped (a penalty continuation, at most max_penalty_rounds rounds; the first round that
// meets them is kept, else the round of lowest cost). "Better" compares, in this order, whether
// the exact poses are met and the weighted cost without the penalty factors: a design that
// meets the exact poses beats one that does not, in the model choice and against the seed.
//
// Which model is refined (r0 the seed radius, r the refined SS radius):
//   - a PS seed is refined as PS;
//   - an SS seed with r0 > max_radius_ratio L is replaced by its limit plane (normal from A
//     towards the weighted centroid of the C_j, offset the weighted mean of n . C_j, same c)
//     and refined as PS;
//   - otherwise the seed is refined as SS; if r0 or r exceeds kBothModelsRadiusRatio L (1e2 L)
//     the limit plane of the refined SS is also refined as PS, and PS is kept if it meets the
//     exact poses when SS does not; when both or neither meet them, if it fits at least as well
//     (cost_PS <= cost_SS) or if r > max_radius_ratio L (the SS ran off to a plane); otherwise
//     SS is kept.
// model_changed says whether the returned dyad's type differs from the seed's; the message
// says which models were refined and which was kept, and when the exact poses are not met, by
// how much.
// Never worse than the seed: if the seed is better than the returned design would be (see
// "Better" above), the seed is returned unchanged (model_changed false).
//
// Preconditions: n >= 7 poses (SS has 7 parameters, PS 6), length > 0, weights empty or one
// positive weight per pose, exact empty or one flag per pose; the seed finite (PS: non-zero
// normal). Throws std::invalid_argument on a wrong length, weights or exact flags.
#ifndef LINKFIT_OPTIMIZERS_SPATIAL_DYAD_REFINER_H_
#define LINKFIT_OPTIMIZERS_SPATIAL_DYAD_REFINER_H_

#include <vector>

#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

// An SS seed or refined SS whose radius exceeds this times L is also refined as PS and the
// better model kept (see the file comment).
inline constexpr double kBothModelsRadiusRatio = 1e2;

struct SpatialDyadRefinerOptions {
  int max_iterations = 50;             // Levenberg-Marquardt iterations
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  double max_radius_ratio = 1e4;       // an SS radius beyond this times L is refined as PS
  double exact_tolerance = 1e-9;       // poses marked exact are met to this times L
  int max_penalty_rounds = 8;          // penalty continuation: exact weights x 1e3 per round
};

// Refines `dyad` in place. `weights` and `exact` may be empty (all 1, none exact). `length` is
// the task's L (> 0).
RefinerSummary RefineSpatialDyad(const std::vector<DualQuaternion>& poses,
                                 const std::vector<double>& weights, const std::vector<bool>& exact,
                                 double length, SpatialDyad* dyad,
                                 const SpatialDyadRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_SPATIAL_DYAD_REFINER_H_
