// Global search for four-bar function generators (NLopt), for effort thorough: covers what the
// linear and exact seeds of fitting/function_generation.h miss.
//
// Absolute angles: the search space is the link lengths (log a, log b, log c) / d in
// [log 1e-2, log max_link_length]; relative angles: the cranks' offsets (o2, o4) in [-pi, pi]^2,
// each with the lengths of Freudenstein's linear least squares at those offsets
// (FreudensteinWithOffsets: a 2-D search, the lengths in closed form). The objective is the
// weighted output-angle cost FunctionCost on the better assembly; a point without a four-bar gets
// a large finite value, never NaN. NLopt (GN_CRS2_LM) runs until max_evaluations or time_limit;
// the refine_count best distinct points (more than 0.2 apart in the search space) are refined by
// RefineFunctionFourBar and returned best first.
#ifndef LINKFIT_OPTIMIZERS_FUNCTION_SEARCH_H_
#define LINKFIT_OPTIMIZERS_FUNCTION_SEARCH_H_

#include <cstdint>
#include <string>
#include <vector>

#include "lib/function_four_bar.h"
#include "optimizers/function_refiner.h"

namespace linkfit {

struct FunctionSearchOptions {
  int max_evaluations = 6000;      // objective evaluations
  double time_limit = 0.5;         // seconds for the NLopt run (the refinement comes on top)
  int refine_count = 4;            // best distinct points refined as four-bars
  std::uint64_t seed = 1;          // NLopt's random seed (results are reproducible)
  bool relative = false;           // relative angles: search the offsets (file comment)
  double max_link_length = 100.0;  // the lengths' box (times d); absolute angles
  FunctionRefinerOptions refiner;  // for the refinement of the found four-bars
};

struct FunctionSearchSummary {
  int evaluations = 0;     // objective evaluations
  double seconds = 0.0;    // wall time including the refinement
  double best_cost = 0.0;  // FunctionCost of the best returned four-bar (0 when none)
};

// Searches and appends the refined four-bars found (best first); returns how many.
int SearchFunctionFourBars(const std::vector<FunctionPair>& pairs, double ground,
                           const FunctionSearchOptions& options,
                           std::vector<FunctionFourBar>* four_bars,
                           FunctionSearchSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_FUNCTION_SEARCH_H_
