#include "optimizers/function_search.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <optional>

#include "fitting/function_generation.h"
#include "lib/four_bar_closure.h"

namespace linkfit {
namespace {

struct Candidate {
  std::vector<double> x;
  double cost = std::numeric_limits<double>::infinity();
  FunctionFourBar four_bar;
};

struct SearchState {
  const std::vector<FunctionPair>* pairs = nullptr;
  double ground = 1.0;
  bool relative = false;
  std::optional<double> min_transmission_deg;
  double no_four_bar = 0.0;  // the objective where there is no four-bar
  int evaluations = 0;
  std::vector<Candidate> archive;  // every evaluated point with a four-bar
};

// The four-bar at search point x (file comment), on the better assembly; false without one.
bool FourBarAt(const SearchState& state, const std::vector<double>& x, FunctionFourBar* best,
               double* best_cost) {
  FunctionFourBar four_bar;
  if (state.relative) {
    std::vector<FunctionFourBar> found;
    if (FreudensteinWithOffsets(*state.pairs, state.ground, x[0], x[1], &found) == 0) return false;
    four_bar = found[0];
  } else {
    four_bar.ground = state.ground;
    four_bar.input_length = state.ground * std::exp(x[0]);
    four_bar.coupler_length = state.ground * std::exp(x[1]);
    four_bar.output_length = state.ground * std::exp(x[2]);
  }
  *best_cost = std::numeric_limits<double>::infinity();
  for (int sigma : {1, -1}) {
    four_bar.assembly = sigma;
    const double cost = FunctionCost(four_bar, *state.pairs, state.min_transmission_deg);
    if (cost < *best_cost) {
      *best_cost = cost;
      *best = four_bar;
    }
  }
  return std::isfinite(*best_cost);
}

double Objective(unsigned n, const double* x, double* /*gradient*/, void* data) {
  auto* state = static_cast<SearchState*>(data);
  ++state->evaluations;
  Candidate candidate;
  candidate.x.assign(x, x + n);
  if (!FourBarAt(*state, candidate.x, &candidate.four_bar, &candidate.cost)) {
    return state->no_four_bar;
  }
  state->archive.push_back(candidate);
  return candidate.cost;
}

}  // namespace

int SearchFunctionFourBars(const std::vector<FunctionPair>& pairs, double ground,
                           const FunctionSearchOptions& options,
                           std::vector<FunctionFourBar>* four_bars,
                           FunctionSearchSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  SearchState state;
  state.pairs = &pairs;
  state.ground = ground;
  state.relative = options.relative;
  state.min_transmission_deg = options.refiner.min_transmission_deg;
  double weights = 0.0;
  for (const FunctionPair& pair : pairs) weights += pair.weight;
  // Worse than any four-bar's output errors (at most pi each) and its misses.
  state.no_four_bar = 1e3 * weights;
  const unsigned dimension = options.relative ? 2 : 3;
  std::vector<double> lower(dimension), upper(dimension), x(dimension);
  for (unsigned i = 0; i < dimension; ++i) {
    lower[i] = options.relative ? -kClosurePi : std::log(1e-2);
    upper[i] = options.relative ? kClosurePi : std::log(std::max(options.max_link_length, 2e-2));
    x[i] = 0.5 * (lower[i] + upper[i]);
  }
  nlopt::srand(options.seed);
  nlopt::opt optimizer(nlopt::GN_CRS2_LM, dimension);
  optimizer.set_lower_bounds(lower);
  optimizer.set_upper_bounds(upper);
  optimizer.set_min_objective(Objective, &state);
  optimizer.set_maxeval(options.max_evaluations);
  optimizer.set_maxtime(options.time_limit);
  double value = 0.0;
  try {
    optimizer.optimize(x, value);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  // The best distinct points of the archive.
  std::sort(state.archive.begin(), state.archive.end(),
            [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  std::vector<const Candidate*> chosen;
  for (const Candidate& candidate : state.archive) {
    if (static_cast<int>(chosen.size()) >= options.refine_count) break;
    const bool distinct = std::all_of(chosen.begin(), chosen.end(), [&](const Candidate* other) {
      double squared = 0.0;
      for (unsigned i = 0; i < dimension; ++i) {
        double step = candidate.x[i] - other->x[i];
        if (options.relative) step = WrapToPi(step);
        squared += step * step;
      }
      return squared > 0.2 * 0.2;
    });
    if (distinct) chosen.push_back(&candidate);
  }
  FunctionRefinerOptions refiner = options.refiner;
  refiner.free_offsets = options.relative;
  std::vector<FunctionFourBar> found;
  for (const Candidate* candidate : chosen) {
    FunctionFourBar four_bar = candidate->four_bar;
    RefineFunctionFourBar(pairs, &four_bar, refiner);
    found.push_back(four_bar);
  }
  std::sort(found.begin(), found.end(), [&](const FunctionFourBar& a, const FunctionFourBar& b) {
    return FunctionCost(a, pairs, refiner.min_transmission_deg) <
           FunctionCost(b, pairs, refiner.min_transmission_deg);
  });
  four_bars->insert(four_bars->end(), found.begin(), found.end());
  if (summary != nullptr) {
    summary->evaluations = state.evaluations;
    summary->best_cost =
        found.empty() ? 0.0 : FunctionCost(found[0], pairs, refiner.min_transmission_deg);
    summary->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return static_cast<int>(found.size());
}

}  // namespace linkfit
