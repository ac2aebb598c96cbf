// Least-squares refinement of one spherical RR dyad (lib/spherical_dyad.h) on its geometric
// residual.
//
// Given the rotations R_j of a spherical motion (about its centre), weights w_j > 0 and a seed
// dyad (the algebraic least-squares fit or an exact five-orientation dyad,
// fitting/spherical_burmester.h), minimizes
//   1/2 sum_j w_j e_j^2,   e_j = angle(u, R_j v) - alpha,
// the angle by which the moving axis misses its cone about the fixed axis, by Levenberg-Marquardt
// (Ceres, automatic derivatives), u and v kept unit on the sphere manifold. The weights are
// divided by their mean. Orientations marked exact are met to exact_tolerance (radians) by the
// penalty continuation of optimizers/exact_poses.h. Never worse than the seed (exact_poses.h
// Better): the seed is returned when it is.
//
// Preconditions: at least five rotations (the dyad has five parameters), the seed finite.
// Throws std::invalid_argument on wrong weights or exact flags.
#ifndef LINKFIT_OPTIMIZERS_SPHERICAL_DYAD_REFINER_H_
#define LINKFIT_OPTIMIZERS_SPHERICAL_DYAD_REFINER_H_

#include <Eigen/Core>
#include <vector>

#include "lib/spherical_dyad.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct SphericalDyadRefinerOptions {
  // Levenberg-Marquardt iterations. Flat valleys of noisy orientations take more than 50 (which
  // stopped short of 1-3 % of the generating dyads' optima in linkfit_bench --only spherical);
  // 200 lists 99.0 / 97.5 / 99.8 % of them at balanced instead of 98.0 / 96.2 / 99.0 %, in the
  // same median time.
  int max_iterations = 200;
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  double exact_tolerance = 1e-9;       // exact orientations are met to this (radians)
  int max_penalty_rounds = 8;          // penalty continuation: exact weights x 1e3 per round
};

// Refines `dyad` in place (canonical form kept). Costs and residuals of the summary in radians.
RefinerSummary RefineSphericalDyad(const std::vector<Eigen::Matrix3d>& rotations,
                                   const std::vector<double>& weights,
                                   const std::vector<bool>& exact, SphericalDyad* dyad,
                                   const SphericalDyadRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_SPHERICAL_DYAD_REFINER_H_
