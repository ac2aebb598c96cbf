// Items a task marks exact, met by the least change of a seed: the projection of an algebraic
// least-squares dyad onto the poses (orientations) marked "exact". Gauss-Newton steps of minimum
// norm in the dyad's parameters on the residuals at the exact poses alone, until they vanish
// (to 1e-12 L, or 1e-12 rad): among the dyads that meet the exact poses, nearly the nearest to
// the seed. Effort fast's answer for spatial and spherical motion, whose algebraic seeds weigh
// every pose alike (balanced refines every dyad with the exact poses held by Ceres; planar
// motion and paths take their fast seeds from subsets that hold the exact items).
#ifndef LINKFIT_FITTING_EXACT_ITEMS_H_
#define LINKFIT_FITTING_EXACT_ITEMS_H_

#include <Eigen/Core>
#include <vector>

#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"
#include "lib/spherical_dyad.h"

namespace linkfit {

// Projects `dyad` (SS: A, c, r; PS: c and the plane; SP: A and the plane in E) onto the poses
// `exact` marks (one flag per pose). Returns whether it then meets them within 1e-12 `length`
// (unchanged, and false, when it cannot: then at most as many exact poses as parameters, or a
// rank-deficient Jacobian).
bool ProjectOntoExactPoses(const std::vector<DualQuaternion>& poses, const std::vector<bool>& exact,
                           double length, SpatialDyad* dyad);

// The same for a spherical dyad (axes u, v and the angle alpha) and the rotations `exact` marks,
// within 1e-12 rad.
bool ProjectOntoExactOrientations(const std::vector<Eigen::Matrix3d>& rotations,
                                  const std::vector<bool>& exact, SphericalDyad* dyad);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_EXACT_ITEMS_H_
