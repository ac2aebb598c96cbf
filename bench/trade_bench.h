// `linkfit bench`: the speed/accuracy trade of every solver path at every effort level, on
// generated task families (random mechanisms, their exact tasks, with noise), and the stability
// sweep at the numerical extremes (bench/extremes_bench.h).
//
// Families: planar motion (5, 10, 50, 200 poses from a random four-bar), spatial motion (7, 10,
// 30 poses of a random 5-SS platform), timed path (5, 10, 20 points of a random crank-driven
// four-bar, prescribed timing; 10 and 20 also with free timing); noise 0, 1e-3 L and 1e-2 L
// (positions, and L times the angles); spherical motion (5, 10, 20 orientations of a random
// spherical four-bar, as spatial poses about a centre off both frames' origins, noise in radians
// of each orientation; the poses still fix the centre); function generation (3 and 12 absolute
// pairs, 5 and 12 relative pairs of a random four-bar, noise in radians of the output angle,
// errors in radians). Each task is solved end to end (SolvePlanarTask, SolveSpatialTask,
// SolvePathTask, SolveFunctionTask) at each effort level; minimal data are solved exactly.
//
// Final error: noise 0, in units of L: the best four-bar's pose or point error (planar, spherical
// and path: RMS over the task, the largest for minimal data; only four-bars without a circuit or
// branch defect count; a spherical task whose result is not spherical is a miss), or for spatial
// tasks the largest over the five generating dyads of the RMS residual of the returned dyad
// nearest it. With noise, the same measure divided by the generating mechanism's own on the same
// noisy data (below 1: the fit beats the truth, as a least-squares optimum should). Success: the
// generating mechanism, or a better one, is found: error <= 1e-9 (exact data; free timing 1e-6),
// or <= 1.10 with noise.
//
// At its optimum (least squares: planar motion and paths): the share of the listed four-bars,
// over a cell's tasks, that `linkfit refine` (RefineTask on the result as written) improves by
// less than 1 % of their RMS error, or by less than 1e-9 L (an exact fit's rounding; issue 35:
// at balanced and thorough, every one).
#ifndef LINKFIT_BENCH_TRADE_BENCH_H_
#define LINKFIT_BENCH_TRADE_BENCH_H_

#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "lib/task.h"

namespace linkfit {

struct BenchOptions {
  bool quick = false;            // few tasks per cell, at every effort: about a minute, one core
  std::string output_dir = ".";  // trade.csv, trade.svg, extremes.csv, constrained.csv go here
  uint64_t seed = 2026;          // random task families
  bool trade = true;             // the speed/accuracy table
  bool extremes = true;          // the extremes sweep
  bool constrained = true;       // the constrained families (constrained_bench.h)
  int constrained_tasks = 0;     // tasks per random constrained family (0: 40, quick 3)
  // When set, the extremes sweep writes each wrongly answered task that has a task file (the
  // rounded-data family) here, as <row>-<task>.json (noted ones as <row>-<task>-noted.json),
  // with the generating mechanism beside it, to reproduce it with `linkfit solve`; the
  // constrained families write each task a target missed at some effort, as
  // constrained_<family>-<task>.json.
  std::string wrong_dir;
  // When set, the extremes sweep runs only this family ("rounded"), or only its rows whose
  // variant contains a text ("rounded:path 5 points"); the trade runs only this family
  // ("untimed path"), or only its rows of a number of items ("untimed path:10"); the constrained
  // part runs only with "constrained", or "constrained:<part of a family name>".
  std::string family;
};

// One cell of the trade table: a task family at one noise level, solved by one solver path at
// one effort level.
struct TradeRow {
  std::string family;  // "planar motion", "spatial motion", "spherical motion", "timed path", ...
  int items = 0;       // poses or points per task
  double noise = 0.0;  // sigma / L (spherical motion, function generation: radians)
  std::string path;    // the solver path, e.g. "planar least squares"
  std::string effort;  // "exact" (minimal data) | "fast" | "balanced" | "thorough"
  int tasks = 0;
  double median_ms = 0.0, worst_ms = 0.0;
  double median_error = 0.0, worst_error = 0.0;  // see the header comment
  double success_share = 0.0;
  // Listed four-bars `linkfit refine` improves by less than 1 % (see the header comment); -1:
  // not measured (minimal data, or a family `linkfit refine` does not take).
  double optimum_share = -1.0;
};

// One task of a cell: its time and final error (see the header comment).
struct TradeOutcome {
  double ms = 0.0;
  double error = std::numeric_limits<double>::infinity();
  int listed = 0;      // least squares, planar motion and paths: four-bars listed
  int at_optimum = 0;  // of them, those `linkfit refine` improves by less than 1 %
};

// Draws the next task of a family ("planar motion", "spatial motion", "spherical motion", "timed
// path", "untimed path", "function abs", "function rel") with `items` poses, points or pairs and
// noise sigma / L (radians for spherical motion and function generation) from `rng`, and solves
// it at `effort` (minimal data: exactly, whatever the effort). The same state of `rng` gives the
// same task at every effort level.
TradeOutcome RunTradeTask(const std::string& family, int items, double noise, Effort effort,
                          std::mt19937_64& rng);

// A number as the CSV files write it: 6 significant digits, "inf" for infinity.
std::string FormatNumber(double value);

// Runs every cell, printing each row to `table` (if not null) as it finishes.
std::vector<TradeRow> RunTradeBench(const BenchOptions& options, std::FILE* table);

// The table as CSV: family, path, effort, tasks, median_ms, worst_ms, median_error,
// worst_error, success_share, items, noise, error_unit ("L" for noise 0, "ratio" otherwise),
// optimum_share (empty where not measured).
std::string TradeCsv(const std::vector<TradeRow>& rows);

// The trade as an SVG plot: one panel per noise level, median time (log axis) against median
// final error (log axis), one curve per solver path and task size through its effort levels.
std::string TradeSvg(const std::vector<TradeRow>& rows);

// `linkfit bench`: runs what `options` asks, prints the tables to stdout and writes the files.
// Returns the exit status (2 when the output directory cannot be written).
int RunBench(const BenchOptions& options);

}  // namespace linkfit

#endif  // LINKFIT_BENCH_TRADE_BENCH_H_
