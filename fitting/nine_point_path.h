// Path generation with free timing through nine points (Alt's problem): every four-bar whose
// coupler curve passes nine given points, by a parameter homotopy from a generic instance whose
// every solution is known (Wampler, Morgan & Sommese 1992 counted them: 1442 Roberts classes).
//
// Formulation (isotropic coordinates, the first point R_0 as origin; a hat marks the
// independent "conjugate" of a complex unknown, equal to its conjugate on real four-bars):
// the crank dyad has its fixed pivot at a = A_0 - R_0 and its coupler pin at x = A - R_0 in the
// first configuration, the output dyad b and y likewise. At point j (displacement
// d_j = R_j - R_0) the coupler has turned by theta_j = 1 + g_j; the crank keeps its length,
// |d_j + theta_j x - a| = |x - a|, which with theta_j conj(theta_j) = 1 reads
//   g_j x (a^ - d^_j) + g^_j x^ (a - d_j) + d_j (a^ - x^) + d^_j (a - x) - d_j d^_j = 0,    (D1)
// the same in (y, b) for the output dyad (D2), and
//   g_j g^_j + g_j + g^_j = 0                                                           (D3)
// for j = 1..8: 24 equations in the 24 unknowns (x, x^, a, a^, y, y^, b, b^, g_j, g^_j). The
// solutions come in orbits of six: the swap of the two dyads and the Roberts-Chebyshev cognates
// (two more four-bars tracing the same curve). 1442 orbits of isolated nondegenerate solutions,
// one representative each, are tracked from a generic complex instance (the start system,
// computed once by monodromy: ComputeNinePointStart) to the task's points; a real endpoint
// (x^ = conj(x), ...) is a four-bar.
//
// The coupler point's crank angles are not unknowns: the result gives each four-bar in the
// first point's configuration (lib/path_motion.h); the caller reads the timing (and drives the
// four-bar through the points, which is where circuit and branch defects show).
#ifndef LINKFIT_FITTING_NINE_POINT_PATH_H_
#define LINKFIT_FITTING_NINE_POINT_PATH_H_

#include <Eigen/Core>
#include <complex>
#include <cstdint>
#include <vector>

#include "lib/path_motion.h"

namespace linkfit {

// A point of the 24 unknowns (ordering in the file comment: x, x^, a, a^, y, y^, b, b^, then
// g_1..g_8, then g^_1..g^_8) and of the 16 parameters (d_1..d_8, d^_1..d^_8).
using NinePointState = Eigen::Matrix<std::complex<double>, 24, 1>;
using NinePointParameters = Eigen::Matrix<std::complex<double>, 16, 1>;

// The start system: generic complex parameters and one solution of each orbit.
struct NinePointStart {
  NinePointParameters parameters;
  std::vector<NinePointState> solutions;
};

struct NinePointTrackOptions {
  // Measured on random 4R with nine points (2026-11-24; tighter settings cost up to twice the
  // time for no more four-bars found; a predictor tolerance of 1e-2 or 3e-2 saves under 10 %
  // and fails more paths, a corrector tolerance of 1e-6 lost the generating four-bar in 1 of
  // 10 tasks): about 0.6 s per task on one core, a few paths in 1442 failing, the generating
  // four-bar found.
  double initial_step = 0.02;  // of the homotopy parameter s in [0, 1]
  double max_step = 0.5;
  double min_step = 1e-7;             // a path that needs a smaller step has failed
  int max_steps = 3000;               // per path
  double corrector_tolerance = 1e-7;  // Newton update, relative to 1 + |state|
  // Step control: the first Newton update after a step (the predictor's error, relative)
  // aimed at.
  double predictor_tolerance = 3e-3;
  int corrector_iterations = 5;
  double infinity = 1e7;  // |state| beyond this: the path goes to infinity (failed)
};

struct NinePointOptions {
  NinePointTrackOptions track;
  // An endpoint is real when every hatted unknown is the conjugate of its partner within this
  // (relative to 1 + |unknown|), after polishing.
  double real_tolerance = 1e-6;
  // Both labelings of every real four-bar (either dyad as the crank), and its cognates.
  bool swap_dyads = true;
  bool cognates = false;
  // Threads the paths are tracked on (lib/parallel.h; 0: the machine's). The result does not
  // depend on them.
  int threads = 0;
};

struct NinePointSummary {
  int paths = 0;           // tracked (one per orbit)
  int paths_failed = 0;    // step too small, too many steps, or off to infinity
  int real_solutions = 0;  // real endpoints (orbits)
  double seconds = 0.0;
};

// The built-in start system (fitting/nine_point_start.inc, made by ComputeNinePointStart).
const NinePointStart& BuiltInNinePointStart();

// The residuals (D1, D2, D3 for j = 1..8) at `state` and `parameters`.
NinePointState NinePointResidual(const NinePointState& state,
                                 const NinePointParameters& parameters);

// The crank rotations g_j, g^_j that go with the dyad unknowns (the first 8 entries of
// `state`): D1 and D2 at each point are linear in them. Returns false where they are not
// determined (the two dyads' equations dependent).
bool CompleteNinePointState(const NinePointParameters& parameters, NinePointState* state);

// The other five solutions of the orbit of `state` (the dyads swapped, the two cognates and
// their swaps). Empty entries are left out where a cognate is undefined (x = y).
std::vector<NinePointState> NinePointOrbit(const NinePointState& state,
                                           const NinePointParameters& parameters);

// Tracks `state` from `from` to `to` along the straight line of parameters. Returns false when
// the path fails; `state` is then unspecified.
bool TrackNinePoint(const NinePointParameters& from, const NinePointParameters& to,
                    const NinePointTrackOptions& options, NinePointState* state);

// The start system by monodromy: a random complex instance with one solution made for it, then
// loops of parameter homotopies (start -> two random instances -> start) whose endpoints add
// new orbits, until `orbits` orbits are known or `max_loops` loops add nothing new.
NinePointStart ComputeNinePointStart(std::uint64_t seed, int orbits, int max_loops);

// Every real four-bar whose coupler point passes the nine `points` (any timing), in the first
// point's configuration (the coupler point is points[0]), the crank the first dyad (and, with
// options.swap_dyads, each also with the dyads swapped). Returns the count.
int SolveNinePointPath(const std::vector<Eigen::Vector2d>& points, const NinePointOptions& options,
                       std::vector<PathFourBar>* four_bars, NinePointSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_NINE_POINT_PATH_H_
