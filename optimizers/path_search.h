// Global search for crank-driven four-bars through many timed points (NLopt), for effort
// thorough: covers what the exact five-point subsets miss.
//
// The search space is the crank alone, (B, A) in Sigma in a box of half-width box_scale * L about
// the point centroid: with the timing, the crank places its pin A_j = B + R(psi_j - psi_0)(A - B)
// at every point, and the coupler line from A_j to the point R_j fixes the coupler pose q_j
// (seed 002, eqs 2-8: the crank's rotations give the coupler's). The objective is
//   sum_j w_j (|R_j - A_j| - l)^2      (the coupler link A-R must keep its length l,
//                                        the weighted mean, optimal for fixed B, A)
// + the best output dyad's cost on the poses q_j (the algebraic least-squares dyads of
//   fitting/planar_burmester.h for the poses, measured by their geometric residuals),
// in data centred and scaled by L; a point it cannot evaluate gets a large finite value, never
// NaN. NLopt (algorithm from GlobalSearchOptions) runs `runs` times from seeds seed, seed + 1,
// ..., each with an equal share of the evaluations and of the time left (one run of CRS2 can
// collapse onto a poor basin early and spend its budget there; runs from other seeds reach other
// basins), filling one archive of the best crank of each basin (cranks more than 0.1 L apart);
// the best refine_count of them, each with every output dyad of its coupler poses and the coupler
// point R_0, are refined by RefinePathFourBar and returned best first (four-bars within 1e-3 L
// after refinement are one). An output circle the crank cannot close at some point (a
// least-squares radius out of reach near a toggle: a four-bar the refiner cannot drive) is
// refined with its radius moved into the range every point allows.
#ifndef LINKFIT_OPTIMIZERS_PATH_SEARCH_H_
#define LINKFIT_OPTIMIZERS_PATH_SEARCH_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "lib/path_motion.h"
#include "optimizers/global_search.h"
#include "optimizers/path_refiner.h"

namespace linkfit {

struct PathSearchOptions {
  GlobalAlgorithm algorithm = GlobalAlgorithm::kCrs2;  // NLopt algorithm
  int max_evaluations = 20000;                         // objective evaluations
  double time_limit = 1.0;     // seconds for the NLopt run (the refinement comes on top)
  double box_scale = 3.0;      // half-width of the crank's box, times L
  int refine_count = 4;        // best distinct cranks refined as four-bars
  int runs = 8;                // NLopt runs from seeds seed, seed + 1, ..., sharing the budget
  std::uint64_t seed = 1;      // NLopt's random seed (results are reproducible)
  PathRefinerOptions refiner;  // for the refinement of the found four-bars
};

struct PathSearchSummary {
  std::string algorithm;   // GlobalAlgorithmName
  int evaluations = 0;     // objective evaluations
  double seconds = 0.0;    // wall time including the refinement
  double best_cost = 0.0;  // 1/2 sum w e^2 of the best returned four-bar (0 when none)
};

// An output circle the crank cannot close at some point (e.g. its least-squares radius, fitted to
// the coupler poses, is out of reach there near a toggle) makes a four-bar that cannot be driven
// through the points, and the refiner keeps such a seed unchanged. With its radius moved into the
// range every point allows (the crank turned by `turns` from `crank_pin` about `crank_pivot`; the
// output's moving pivot keeps its distance from the pin), a thousandth of that range inside it,
// the four-bar assembles at every point and the refinement can start. False for another output
// type or an empty range.
bool DrivableOutput(const PlanarDyad& output, const Eigen::Vector2d& crank_pivot,
                    const Eigen::Vector2d& crank_pin, const std::vector<double>& turns,
                    PlanarDyad* drivable);

// Prescribed timing only. Returns the number of four-bars written to `four_bars` (best first).
// Throws std::invalid_argument as RefinePathFourBar does, and for options out of range.
int SearchPathFourBars(const std::vector<Eigen::Vector2d>& points,
                       const std::vector<double>& weights, const std::vector<bool>& exact,
                       const std::vector<double>& input_angles, double length,
                       const PathSearchOptions& options, std::vector<PathFourBar>* four_bars,
                       PathSearchSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PATH_SEARCH_H_
