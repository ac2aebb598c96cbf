// Path generation with prescribed timing (seed 002): every four-bar whose coupler point R passes
// five points R_0..R_4 while its input crank is at angles psi_0..psi_4.
//
// The crank (fixed pivot B, pin A_0 at the first point). Seed 002's synthesis equations of the
// crank dyad, eq. 9 (with eq. 17 its quadratic term is (1 - cos beta_j) |b|^2), are linear in a_0
// and quadratic in b. Written in the crank vector u = A_0 - B instead of a_0 the quadratic terms
// cancel and each becomes BILINEAR in (B, u): the pin A_j = B + R(beta_j) u (eq. 2, beta_j =
// psi_j - psi_0) and R_j must keep the coupler's distance |A_0 - R_0|, so
//   B . (R_j - 1) u - B . (R_j - R_0) - (R_j^T R_j - R_0) . u + (|R_j|^2 - |R_0|^2) / 2 = 0,
// j = 1..4 (R_j also the point's vector; the matrix R_j the rotation by beta_j). Homogenised in
// P^2 x P^2, four bilinear forms have 6 common roots; two lie at the circular points
// (B, u) = ((1, +-i, 0), (1, +-i, 0)), which satisfy every such form, leaving 4 cranks: seed 002's
// Bezout bound 12 (eq. 21) counts the four-bars, 4 cranks x 3 output dyads. The 6 roots are
// found as the null space of the 12 x 18 Macaulay matrix of bidegree (1, 2) (each form times
// u1, u2, u0) and an eigenvalue problem for the ratio of two random linear forms in B, then
// polished by Newton's method; complex cranks are kept until no real four-bar can come of them.
//
// The coupler (eqs 4-8): a real crank fixes the coupler's rotation at every point (the line from
// A_j to R_j), so the coupler has five poses, and the output dyad is a Burmester problem
// (fitting/planar_burmester.h, eqs 1b and 11 of seed 002 solved as such): of its 4 roots one is
// the crank itself, the other 3 are the output dyads (RR, or a slider PR / RP where the root
// says so).
//
// Preconditions: five points, not all coincident, with input angles that do not all agree
// modulo a turn. Data are centred and scaled by L before the algebra and mapped back after.
#ifndef LINKFIT_FITTING_TIMED_PATH_H_
#define LINKFIT_FITTING_TIMED_PATH_H_

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

#include "fitting/planar_burmester.h"
#include "lib/path_motion.h"

namespace linkfit {

// A root of the crank equations: fixed pivot and crank vector u = A_0 - B, in the task's frame.
// Complex crank roots tried by their real part for data coarser than rounding
// (TimedPathSummary::to_fit): imaginary part at most this share of the crank's size (at least
// L). Generous: the joint fit decides (measured on random 4R printed to 4 digits, linkfit bench:
// 0.05 rescued none of six lost generating cranks, 0.5 two).
inline constexpr double kNearRealShare = 0.5;

struct TimedCrank {
  Eigen::Vector2cd fixed_pivot = Eigen::Vector2cd::Zero();
  Eigen::Vector2cd crank = Eigen::Vector2cd::Zero();
  bool real = false;
  int multiplicity = 1;   // 2 for a double root (one crank, counted twice in the totals)
  double residual = 0.0;  // largest |equation| after polishing, scaled data (L = 1)
};

struct TimedPathOptions {
  // A root whose imaginary part is below this (relative to its size) is taken to real arithmetic
  // and accepted as real if Newton's method then converges.
  double real_tolerance = 1e-5;
  int newton_iterations = 6;  // per root, complex or real
  // A homogeneous coordinate below this (relative) puts a root at infinity (the circular
  // points, or a crank with B or A at infinity): no crank.
  double infinity_tolerance = 1e-8;
  // Singular value ratio below which the 12 x 18 Macaulay matrix is taken as rank-deficient
  // (a family of cranks, not four).
  double rank_tolerance = 1e-10;
  // The output dyads' five-pose problem. One Newton step per root: the coupler poses are exact
  // to rounding, so the conic intersection is already close and one step reaches rounding
  // (the assembly check below guards it); it saves a fifth of the time.
  PlanarBurmesterOptions burmester = [] {
    PlanarBurmesterOptions options;
    options.newton_iterations = 1;
    return options;
  }();
  // Every four-bar is assembled at the five input angles; one that misses a point by more than
  // this (times L), or for data coarser than rounding by more than their precision allows
  // (delta + alpha times the crank), on both assemblies is dropped as ill-conditioned (cranks
  // or output pivots thousands of L away, where the coupler barely turns), with a note.
  double verify_tolerance = 1e-8;
  // The precision of the points (length) and of the input angles (angle, radians); zero:
  // rounding level (lib/precision.h). The coupler poses of a crank inherit it (SolveTimedPath):
  // the crank pin A_j is known to delta_A = delta + 2 alpha |u| (the point's delta, and both
  // input angles of beta_j = psi_j - psi_0 turning the crank u), and the coupler's turn, the
  // direction of the line A_j R_j, to (delta + delta_A) / |R_0 - A_0|. The output dyad is typed
  // at that precision (PlanarBurmesterOptions::precision: a circle whose slider reading fits the
  // coupler poses within it is the slider), and a four-bar whose output was so simplified may
  // miss the points by what its output's uncertainty moves the coupler point: kModelUnits times
  // the output pin's uncertainty, times |R_0 - A_0| / |M_0 - A_0| (the coupler turns about the
  // crank pin) when that exceeds 1; where it misses by more, the exact circle is returned.
  DataPrecision precision;
};

struct TimedPathSummary {
  int crank_roots_total = 0;       // finite roots of the crank equations (4 when generic)
  int crank_roots_real = 0;        // of which real
  int four_bars_total = 0;         // 3 per crank root, complex ones included (12 when generic)
  int four_bars_real = 0;          // real four-bars returned
  int four_bars_dropped = 0;       // real four-bars that failed the assembly check
  double analysis_seconds = 0.0;   // of the solve, the assembly check (AnalyzePathFourBar)
  double condition = 0.0;          // sigma_1 / sigma_12 of the Macaulay matrix
  bool degenerate = false;         // the crank equations have a family of solutions
  std::vector<std::string> notes;  // cranks skipped and why
  // Data coarser than rounding: four-bars that may pass the points within their precision once
  // crank and output are fitted to them together (least squares), the caller's to try: (1)
  // dropped four-bars whose output circle's slider reading fits the coupler poses within their
  // precision but, with this crank, misses the points by more than they allow (and so does the
  // circle); (2) the four-bars of the real part of a complex crank root whose imaginary part is
  // below kNearRealShare (rounding can turn two real cranks into a complex pair).
  std::vector<PathFourBar> to_fit;
};

// All finite roots of the crank equations (complex included). Returns their count, or -1 when
// degenerate.
int SolveTimedCranks(const std::vector<Eigen::Vector2d>& points,
                     const std::vector<double>& input_angles, const TimedPathOptions& options,
                     std::vector<TimedCrank>* cranks, TimedPathSummary* summary = nullptr);

// The precision of a crank's coupler poses from points of precision `points` (the points'
// length and input-angle precision; TimedPathOptions::precision): the crank pin is known to
// delta_A = delta + 2 alpha crank, the coupler's turn to (delta + delta_A) / link, with `crank`
// the crank's length and `link` = |R_0 - A_0| (point to crank pin).
DataPrecision CouplerPosePrecision(const DataPrecision& points, double crank, double link);

// Every real four-bar through the five timed points, in the first point's configuration
// (lib/path_motion.h), each assembled and driven through the points (AnalyzePathFourBar; the
// analyses are returned in `analyses` when given, one per four-bar). Returns the count.
int SolveTimedPath(const std::vector<Eigen::Vector2d>& points,
                   const std::vector<double>& input_angles, const TimedPathOptions& options,
                   std::vector<PathFourBar>* four_bars, TimedPathSummary* summary = nullptr,
                   std::vector<PathFourBarAnalysis>* analyses = nullptr);

// The second half of SolveTimedPath: the four-bars of given crank roots (SolveTimedCranks, whose
// roots do not depend on options.precision), so that one set of roots serves several
// precisions. The summary's crank counts are left as they are.
int TimedPathFourBars(const std::vector<Eigen::Vector2d>& points,
                      const std::vector<double>& input_angles,
                      const std::vector<TimedCrank>& cranks, const TimedPathOptions& options,
                      std::vector<PathFourBar>* four_bars, TimedPathSummary* summary = nullptr,
                      std::vector<PathFourBarAnalysis>* analyses = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_TIMED_PATH_H_
