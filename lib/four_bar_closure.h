// The closure condition of a planar four-bar in closed form: the input values at which it
// assembles, for every pair of dyad types (issue 16; the sampled motion of four_bar_motion.h is
// its oracle).
//
// With the input at value u (mechanism.h: a crank angle, a slider position, or for an RP input
// the coupler's angle), AssembleFourBar solves the output's condition; it has solutions exactly
// where one scalar S(u) lies in a range [lo, hi]:
//   input RR (u the crank angle; the input pin M1(u) = F1 + r1 (cos u, sin u)):
//     RR output: S = |M1 - F2|^2 in [(|v| - r2)^2, (|v| + r2)^2], v the coupler side m2 - m1
//       (the triangle M1, M2, F2 closes);
//     PR output: S = n . M1 in [n . q - |v|, n . q + |v|], n the slider line's normal;
//     RP output: S = |F2 - M1|^2 >= (n_E . (q_E - m1))^2 (the line of E reaches F2);
//   input PR (u the slider position, M1(u) = q1 + u d1): the same S, quadratic (or linear) in u;
//   input RP (u the coupler angle): RR output: S = (R(u) n_E) . (F1 - F2) in
//     [-r2 - k, r2 - k], k = n_E . (m2 - q_E); PR and RP outputs: one linear solution wherever
//     the two lines are not parallel.
// S is a sinusoid p + q cos u + r sin u of an angle input and a polynomial of degree <= 2 of a
// slider input, so the feasible set is a few intervals whose ends solve cos(u - phi) = const or
// a quadratic: exact, where a sampled trace can step over a narrow interval. At an interval's
// finite end the two assembly solutions meet (a stationary configuration: the input reverses).
#ifndef LINKFIT_LIB_FOUR_BAR_CLOSURE_H_
#define LINKFIT_LIB_FOUR_BAR_CLOSURE_H_

#include <vector>

#include "lib/dyad.h"

namespace linkfit {

// Input values [start, end] at which the four-bar assembles. Angle inputs: start in [-pi, pi),
// end - start at most 2 pi (the interval may pass pi). Slider inputs: an unbounded side has
// open_start (start = -infinity) or open_end (end = infinity).
struct ClosureInterval {
  double start = 0.0;
  double end = 0.0;
  bool open_start = false;
  bool open_end = false;
  double Extent() const { return end - start; }
};

struct FourBarClosure {
  bool angle_input = true;  // the input is an angle (RR crank, RP coupler angle)
  bool full_turn = false;   // an angle input assembles at every value
  // Assembly solutions where it assembles: 2 (the output's condition is quadratic or
  // trigonometric), or 1 (RP input with a PR or RP output: linear).
  int labels = 2;
  // Disjoint, in increasing start; empty when it never assembles. A full turn is one interval
  // [-pi, pi).
  std::vector<ClosureInterval> intervals;
  // A linear assembly (labels 1) fails at isolated values: where the two slider lines are
  // parallel (RP input, PR output). Not an interval end: the coupler runs off to infinity there.
  std::vector<double> singular;
};

// The closure of the four-bar driven by `input`.
FourBarClosure SolveFourBarClosure(const PlanarDyad& input, const PlanarDyad& output);

// The interval holding input value `value` (angle inputs: any real value, taken modulo a turn),
// within `slack` (an input distance) of its ends; -1 when none does.
int ClosureIntervalOf(const FourBarClosure& closure, double value, double slack = 0.0);

}  // namespace linkfit

#endif  // LINKFIT_LIB_FOUR_BAR_CLOSURE_H_
