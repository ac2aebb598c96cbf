// Global search for planar dyads that fit many poses (NLopt), covering what the algebraic seeds
// miss (a poor local minimum, a bad pose spoiling every seed).
//
// The search space is the dyad's pivots: RR over (F, M) in a box of half-width box_scale * L about
// the pose-origin centroid (F, in Sigma) and about E's origin (M), the radius eliminated in closed
// form (the weighted mean distance, optimal for fixed pivots); PR over (M, line angle), the offset
// eliminated likewise; RP over (F, line angle in E). The objective is the weighted sum of squared
// geometric residuals. The best distinct local optima found are polished by RefinePlanarDyad.
#ifndef LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_
#define LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_

#include <cstdint>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

enum class GlobalAlgorithm {
  kCrs2,    // NLOPT_GN_CRS2_LM: controlled random search with local mutation
  kMlsl,    // NLOPT_G_MLSL_LDS: multi-level single linkage, low-discrepancy starts, local BOBYQA
  kIsres,   // NLOPT_GN_ISRES: improved stochastic ranking evolution strategy
  kDirect,  // NLOPT_GN_DIRECT_L: locally biased DIRECT
};

const char* GlobalAlgorithmName(GlobalAlgorithm algorithm);  // "crs2", "mlsl", "isres", "direct"

struct GlobalSearchOptions {
  GlobalAlgorithm algorithm = GlobalAlgorithm::kCrs2;  // NLopt algorithm
  int max_evaluations = 20000;   // objective evaluations per dyad type searched
  double time_limit = 1.0;       // seconds per dyad type searched
  double box_scale = 3.0;        // half-width of the pivot boxes, times L
  int polish_count = 4;          // best distinct optima polished by RefinePlanarDyad, per type
  std::uint64_t seed = 1;        // NLopt's random seed (results are reproducible)
  std::vector<DyadType> types = {DyadType::kRR, DyadType::kPR, DyadType::kRP};  // searched
};

struct GlobalSearchSummary {
  std::string algorithm;     // GlobalAlgorithmName
  int evaluations = 0;       // objective evaluations, all types
  double seconds = 0.0;      // wall time including the polish
  double best_cost = 0.0;    // 1/2 sum w e^2 of the best polished dyad, length units squared
};

// Searches and returns the polished dyads found (best first, distinct). `weights`/`exact` may be
// empty. Returns the number of dyads written.
int SearchPlanarDyads(const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
                      const std::vector<bool>& exact, double length,
                      const GlobalSearchOptions& options, std::vector<PlanarDyad>* dyads,
                      GlobalSearchSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_GLOBAL_SEARCH_H_
