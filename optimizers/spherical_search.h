// Global search for spherical RR dyads (lib/spherical_dyad.h) that fit six or more orientations
// (NLopt), covering what the algebraic seeds and the five-orientation subsets miss.
//
// The search space is the moving axis v alone, on the hemisphere z >= 0 of E (v and -v are one
// axis): coordinates (z, phi), v = (sqrt(1 - z^2) cos phi, sqrt(1 - z^2) sin phi, z), an
// equal-area map of the box [0, 1] x [0, 2 pi]. For a given v the positions x_j = R_j v (unit,
// Sigma) of a dyad's moving axis lie on a circle of the sphere, the plane u . x = cos(alpha):
// the fixed axis u is that plane's normal fitted by weighted least squares (the eigenvector of
// the smallest eigenvalue of sum_j w_j (x_j - c)(x_j - c)^T, c = sum_j w_j x_j, turned so that
// u . c >= 0), and alpha the weighted mean of the angles theta_j = angle(u, x_j), optimal for
// that u. The objective is the cone residual the refiner minimizes (spherical_dyad_refiner.h),
//   f(v) = sum_j w_j (theta_j - alpha)^2,
// weights normalized to sum 1 (orientations marked exact weigh 100 times more); a point it
// cannot evaluate gets a large finite value, never NaN.
//
// The archive (the best point seen in each cell of an equal-area grid of cells about 0.15 rad
// a side, neighbours across the equator mirrored) is first filled with every cell's centre, so
// that no basin goes unseen; the NLopt run then spends half the evaluations and half the time.
// The archive's local minima, best first, start damped Gauss-Newton descents of f on the
// sphere (tangent steps; u and alpha eliminated by variable projection, Kaufman's Jacobian)
// with the rest of the budget; a descent that runs into an optimum already found is dropped.
// Up to polish_count distinct optima (axes or angles more than 1e-3 rad apart) are polished by
// RefineSphericalDyad (weights, exact orientations met), repeats after the polish dropped, the
// rest sorted by cost. NLopt's exceptions are caught: the best point found counts.
#ifndef LINKFIT_OPTIMIZERS_SPHERICAL_SEARCH_H_
#define LINKFIT_OPTIMIZERS_SPHERICAL_SEARCH_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "lib/spherical_dyad.h"
#include "optimizers/global_search.h"
#include "optimizers/spherical_dyad_refiner.h"

namespace linkfit {

struct SphericalSearchOptions {
  GlobalAlgorithm algorithm = GlobalAlgorithm::kCrs2;  // NLopt algorithm
  int max_evaluations = 2000;  // objective evaluations (cell centres, NLopt run and descents)
  double time_limit = 0.5;     // seconds for the evaluations (the polish comes on top)
  int polish_count = 4;        // best distinct optima polished by RefineSphericalDyad
  std::uint64_t seed = 1;      // NLopt's random seed (results are reproducible)
  SphericalDyadRefinerOptions refiner;  // the polish's options
};

struct SphericalSearchSummary {
  std::string algorithm;   // GlobalAlgorithmName
  int evaluations = 0;     // objective evaluations
  int optima = 0;          // distinct local optima the descents reached (before the polish)
  double seconds = 0.0;    // wall time including the polish
  double best_cost = 0.0;  // 1/2 sum w e^2 of the best polished dyad, weights divided by their
                           // mean, radians squared (0 when no dyad is returned)
};

// Searches the orientations' rotations (about the centre, lib/spherical_dyad.h SphericalMotion)
// and returns the polished dyads found (canonical, best first, distinct). `weights`/`exact` may
// be empty. Returns the number of dyads written: 0 for fewer than five rotations (a dyad has
// five parameters). Throws std::invalid_argument for weights or exact flags of the wrong count,
// non-positive weights, non-finite rotations, or options out of range (max_evaluations < 1,
// time_limit <= 0, polish_count < 1). The same seed gives the same result when the evaluations,
// not the clock, end the run.
int SearchSphericalDyads(const std::vector<Eigen::Matrix3d>& rotations,
                         const std::vector<double>& weights, const std::vector<bool>& exact,
                         const SphericalSearchOptions& options, std::vector<SphericalDyad>* dyads,
                         SphericalSearchSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_SPHERICAL_SEARCH_H_
