// The constrained part of `linkfit bench`: tasks whose design constraints bind at the optimum,
// solved at the default efforts and by a long search, to measure issue 14's targets (user
// guide, "Ranking and design constraints"): the first listed design keeps the constraints and fits
// within 10 % of the best a long search finds, and it is the best-fitting defect-free keeper of its
// list up to the near-tie rule.
//
// Families (random mechanisms, fixed seeds):
//   - timed path, 10 points of a random crank-driven 4R (RandomPathTask), with every link held to
//     80 % of the shortest longest link of the exact four-bars (the generating one and its cognate
//     of the same timing); with both fixed pivots in a box whose one side cuts off a fixed pivot of
//     every exact four-bar; with both;
//   - planar motion, 10 poses of a random 4R (RandomFourBarTask), with the links held to 80 % of
//     the generating four-bar's longest; with a fixed pivots' box that cuts off one of its fixed
//     pivots; with a moving pivots' box (in E) that cuts off one of its moving pivots;
//   - the classic bounded path-synthesis problems of the literature, bundled as task files
//     (data/classic_path_*.json, compiled in; their source is cited in constrained_bench.cc and
//     the user guide, docs/benchmarks/constrained.md).
// Every exact design breaks the bound, so the constrained optimum lies on it unless another
// local optimum inside the bounds fits better: share_bound_active says how often the reference
// design is on a bound.
//
// Each task is solved at effort balanced and thorough (default options, as `linkfit solve`), and
// by the long search: effort thorough with the NLopt budgets (path crank search, planar dyad
// search) 25 times larger, their time limits raised so that the evaluations end the runs, and
// more starts (seed subsets, refined seeds and searched basins). Designs are compared as the
// ranking rule groups them: keepers first, defect-free before those whose only defect is the
// transmission angle (lib/design_constraints.h DefectLevel; a kinematic defect or a violated
// constraint does not count). The reference of a task is the best keeper found by the long search
// or either effort: of the best group any of them reached, the smallest RMS error (points or
// poses). Only where no defect-free keeper is found at all is the reference one with a
// transmission defect (the detail counts those tasks). A task where no solve finds a keeper at
// all has nothing to rank first: it is left out of the shares and ratios (not of the times) and
// listed in the detail.
//
// Per row (family and effort): tasks; median and worst time of the solve; share_within_10pct:
// the first listed keeps every constraint, has no kinematic defect and fits within 10 % of the
// reference (fits within kExactFit L count as equal, and so do two fits within the data's
// precision); share_first_is_best: the first listed is a keeper of the best group of its own list
// and, unless it meets the task within the data's precision, fits within 10 % of the best of that
// group there (the ranking rule's near tie); the median and worst ratio first / reference
// (infinity where the first violates a constraint or has a kinematic defect);
// share_bound_active: the reference design has a bound's slack within 1e-3 L; the long search's
// median time; and a detail that counts the misses by cause, with their task numbers (causes in
// parentheses are counted for information, not as misses).
#ifndef LINKFIT_BENCH_CONSTRAINED_BENCH_H_
#define LINKFIT_BENCH_CONSTRAINED_BENCH_H_

#include <cstdio>
#include <string>
#include <vector>

#include "bench/trade_bench.h"
#include "optimizers/task_solver.h"

namespace linkfit {

struct ConstrainedRow {
  std::string family;  // e.g. "timed path 10 points, link bound", "classic: 18 points closed"
  std::string effort;  // "balanced" | "thorough"
  int tasks = 0;
  double median_ms = 0.0, worst_ms = 0.0;  // the effort's solve
  double share_within_10pct = 0.0;
  double share_first_is_best = 0.0;
  double median_ratio = 0.0, worst_ratio = 0.0;  // first / reference
  double share_bound_active = 0.0;
  double long_median_ms = 0.0;  // the long search's solve
  std::string detail;           // misses by cause, with their task numbers
};

// The long search's options (file comment): `multiplier` times the default NLopt budgets.
TaskSolverOptions LongSearchOptions(double multiplier = 25.0);

// Runs the constrained families (BenchOptions::family "constrained" or
// "constrained:<part of a family name>" picks rows; constrained_tasks overrides the tasks per
// family), printing each row to `table` (if not null) as it finishes.
std::vector<ConstrainedRow> RunConstrainedBench(const BenchOptions& options, std::FILE* table);

// family, effort, tasks, median_ms, worst_ms, share_within_10pct, share_first_is_best,
// median_ratio, worst_ratio, share_bound_active, long_median_ms, detail.
std::string ConstrainedCsv(const std::vector<ConstrainedRow>& rows);

}  // namespace linkfit

#endif  // LINKFIT_BENCH_CONSTRAINED_BENCH_H_
