// The stability sweep of `linkfit bench`: tasks at the numerical extremes, each classified as
//   right         the generating mechanism comes back within the case's stated tolerance (after
//                 undoing the case's transformation), typed as the case demands;
//   noted         the result carries an explicit "ill-conditioned" note with a condition
//                 estimate (the answer may then be less accurate than the tolerance);
//   wrong         neither: a silently wrong, missing or mistyped mechanism;
//   non-finite    a NaN or infinite number in the result, or an exception.
// Cases (random mechanisms, fixed seeds):
//   - scale: planar five poses, a ten-pose least-squares fit, seven spatial poses and five timed
//     points at L = 1e-3, 1, 1e3, 1e5, and with the fixed frame translated by 1e4 L;
//   - sliders: five poses of slider-cranks, and of 4Rs whose output radius is 1e2 .. 1e8 L
//     (typed PR, or RR with that radius);
//   - rotations near +-180 degrees (the moving frame turned so that a pose's angle is within
//     1e-12 .. 1e-3 of 180 degrees, both sides), planar and spatial;
//   - nearly coincident poses (two of five within 1e-3 .. 1e-9 L), nearly collinear points
//     (timed points of a slider-crank whose coupler point is within 1e-3 .. 1e-9 L of its
//     slider line);
//   - spatial poses of a planar four-bar tilted 1e-9 .. 1e-3 off their plane (solved as planar
//     below the tolerance, as spatial above, with no flapping between neighbouring tilts), and
//     spatial poses with quaternions of both signs;
//   - rounded data: generated tasks printed to 8, 6 and 4 significant digits as tables print
//     them and read back through the task parser (precision inferred from the digits). Right:
//     the generating dyads back within twice the error bound the result states for them, typed
//     as the data allow (a circle the rounded poses cannot tell from its slider may come back as
//     the slider); noted: the result says the data are too coarse (a family within precision,
//     an error bound beyond the dyads' size, nearly real complex roots, or a stated bound above
//     a quarter of the dyad's size).
#ifndef LINKFIT_BENCH_EXTREMES_BENCH_H_
#define LINKFIT_BENCH_EXTREMES_BENCH_H_

#include <cstdio>
#include <string>
#include <vector>

#include "bench/trade_bench.h"

namespace linkfit {

struct ExtremeRow {
  std::string family;      // "scale", "slider", "rotation", "coincident", "collinear", "planarity",
                           // "quaternion sign"
  std::string variant;     // e.g. "planar 5 poses, L = 1e5"
  double tolerance = 0.0;  // what "right" demands (relative error of the mechanism)
  int tasks = 0;
  int right = 0;
  int noted = 0;
  int wrong = 0;
  int non_finite = 0;
  double worst_error = 0.0;  // largest relative error among the tasks counted right or wrong
  std::string detail;        // e.g. the types returned, or the model chosen
};

std::vector<ExtremeRow> RunExtremesBench(const BenchOptions& options, std::FILE* table);

// family, variant, tolerance, tasks, right, noted, wrong, non_finite, worst_error, detail.
std::string ExtremesCsv(const std::vector<ExtremeRow>& rows);

}  // namespace linkfit

#endif  // LINKFIT_BENCH_EXTREMES_BENCH_H_
