// Poses marked exact in the dyad refiners (planar_dyad_refiner, spatial_dyad_refiner): they are
// met by a penalty continuation (solve; while an exact pose misses, multiply the exact poses'
// weights by kPenaltyGrowth and solve again from where the last solve ended). The pieces both
// refiners share: the growth per round, how well a design fits, and the order of designs.
#ifndef LINKFIT_OPTIMIZERS_EXACT_POSES_H_
#define LINKFIT_OPTIMIZERS_EXACT_POSES_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace linkfit::internal {

// Penalty continuation: the exact poses' weights grow by this factor per round.
inline constexpr double kPenaltyGrowth = 1e3;

// How well a dyad fits, in a refiner's scaled frames, with the task's own weights (no penalty).
struct DyadFit {
  double cost = std::numeric_limits<double>::infinity();       // 1/2 sum w' e'^2
  double max = std::numeric_limits<double>::infinity();        // max |e'|
  double exact_max = std::numeric_limits<double>::infinity();  // max |e'| over the exact poses
  bool meets_exact = false;                                    // exact_max <= exact_tolerance
  bool keeps_bounds = true;  // keeps the design bounds (planar: design_bounds.h)
};

// The order of designs: one that meets the exact poses beats one that does not; then one that
// keeps the design bounds; then the lower cost wins.
inline bool Better(const DyadFit& a, const DyadFit& b) {
  if (a.meets_exact != b.meets_exact) return a.meets_exact;
  if (a.keeps_bounds != b.keeps_bounds) return a.keeps_bounds;
  return a.cost < b.cost;
}

// The fit of residual(j), j < weights.size(), with those weights; exact_max is 0 without exact
// poses. A non-finite cost or maximum gives the default (infinite) fit.
template <typename Residual>
DyadFit EvaluateFit(const std::vector<double>& weights, const std::vector<bool>& exact,
                    double exact_tolerance, const Residual& residual) {
  DyadFit fit;
  fit.cost = fit.max = fit.exact_max = 0.0;
  for (size_t j = 0; j < weights.size(); ++j) {
    const double e = std::abs(residual(j));
    fit.cost += 0.5 * weights[j] * e * e;
    fit.max = std::max(fit.max, e);
    if (exact[j]) fit.exact_max = std::max(fit.exact_max, e);
  }
  if (!std::isfinite(fit.cost) || !std::isfinite(fit.max)) return DyadFit();
  fit.meets_exact = fit.exact_max <= exact_tolerance;
  return fit;
}

}  // namespace linkfit::internal

#endif  // LINKFIT_OPTIMIZERS_EXACT_POSES_H_
