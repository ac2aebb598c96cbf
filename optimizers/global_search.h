// Global search for planar dyads that fit many poses (NLopt), covering what the algebraic seeds
// miss (a poor local minimum, a bad pose spoiling every seed).
//
// The search space is the dyad's pivots: RR over (F, M) in a box of half-width box_scale * L about
// the pose-origin centroid (F, in Sigma) and about E's origin (M), the radius eliminated in closed
// form (the weighted mean distance, optimal for fixed pivots); PR over (M, line angle in [0, pi)),
// the offset eliminated likewise; RP over (F, line angle in E). The objective is the weighted sum
// of squared geometric residuals (poses marked exact weigh 100 times more), in data centred and
// scaled by L; a point it cannot evaluate gets a large finite value, never NaN.
//
// Per dyad type, half the evaluations and half the time go to the NLopt run, which also fills an
// archive: the best point seen in each cell of a grid over the box. The archive's local minima
// (cells better than all their neighbours), best first, start damped Gauss-Newton descents of the
// reduced least-squares problem with the rest of the budget; a descent that runs into an optimum
// already found is dropped. Up to polish_count distinct optima per type (pivots and lines more
// than 1e-3 L apart) are polished by RefinePlanarDyad, duplicates after the polish are dropped
// and the rest sorted by cost. NLopt's exceptions (roundoff_limited, forced_stop, failures) are
// caught: the best point found counts. Pivots far outside the box are found only when the polish
// walks out to them.
#ifndef LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_
#define LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_

#include <cstdint>
#include <nlopt.hpp>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/planar_dyad_refiner.h"

namespace linkfit {

enum class GlobalAlgorithm {
  kCrs2,    // NLOPT_GN_CRS2_LM: controlled random search with local mutation
  kMlsl,    // NLOPT_G_MLSL_LDS: multi-level single linkage, low-discrepancy starts, local BOBYQA
  kIsres,   // NLOPT_GN_ISRES: improved stochastic ranking evolution strategy
  kDirect,  // NLOPT_GN_DIRECT_L: locally biased DIRECT
};

const char* GlobalAlgorithmName(GlobalAlgorithm algorithm);  // "crs2", "mlsl", "isres", "direct"
// The NLopt algorithm of each (shared by the planar and spherical searches).
nlopt::algorithm NloptAlgorithm(GlobalAlgorithm algorithm);
// Runs `optimizer` from x, swallowing NLopt's exceptions (roundoff_limited, forced_stop and
// plain failures): the run's best point is what counts.
void RunNlopt(nlopt::opt& optimizer, std::vector<double> x);

struct GlobalSearchOptions {
  GlobalAlgorithm algorithm = GlobalAlgorithm::kCrs2;  // NLopt algorithm
  int max_evaluations = 20000;  // objective evaluations per dyad type searched (NLopt + descents)
  double time_limit = 1.0;      // seconds per dyad type searched (the polish comes on top)
  double box_scale = 3.0;       // half-width of the pivot boxes, times L
  int polish_count = 4;         // best distinct optima polished by RefinePlanarDyad, per type
  std::uint64_t seed = 1;       // NLopt's random seed (results are reproducible)
  std::vector<DyadType> types = {DyadType::kRR, DyadType::kPR, DyadType::kRP};  // searched
  // The polish's options; its constraints also bound the search: the pivots' boxes within the
  // task's boxes (fixed_pivots_box, moving_pivots_box, where they overlap the search box, else
  // the task's), an RR's radius within [min_link_length, max_link_length].
  PlanarDyadRefinerOptions refiner;
};

struct GlobalSearchSummary {
  std::string algorithm;   // GlobalAlgorithmName
  int evaluations = 0;     // objective evaluations, all types
  double seconds = 0.0;    // wall time including the polish
  double best_cost = 0.0;  // 1/2 sum w e^2 of the best polished dyad, length units squared
                           // (0 when no dyad is returned)
};

// Searches and returns the polished dyads found (best first, distinct). `weights`/`exact` may be
// empty; `length` is the task's L. Returns the number of dyads written (0 without poses). Throws
// std::invalid_argument for a non-positive or non-finite length, weights or exact flags of the
// wrong count, non-positive weights, non-finite poses, or options out of range
// (max_evaluations < 1, time_limit <= 0, box_scale <= 0, polish_count < 1). The same seed gives
// the same result when the evaluations, not the clock, end the runs.
int SearchPlanarDyads(const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
                      const std::vector<bool>& exact, double length,
                      const GlobalSearchOptions& options, std::vector<PlanarDyad>* dyads,
                      GlobalSearchSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_
