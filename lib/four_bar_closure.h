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

#include <algorithm>
#include <cmath>
#include <limits>
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

// The output's closure as one scalar of an RR or PR input's pin M1 (the file comment): f in
// [low, high], with
//   RR output: f = |M1 - F2| in [|l - r2|, l + r2], l = |m2 - m1| (squared: S = f^2);
//   PR output: f = n . (M1 - q) in [-l, l];
//   RP output: f = |M1 - F2| >= |n_E . (m1 - q_E)| (squared);
// and S (f^2 or f) = c0 + c1 cos u + c2 sin u of a crank angle u, c0 + c1 u + c2 u^2 of a
// slider position u.
struct ClosureScalar {
  bool crank = true;  // RR input (S a sinusoid), else PR (S a polynomial)
  double c0 = 0.0, c1 = 0.0, c2 = 0.0;
  bool squared = false;  // S is f^2 (a distance), not f
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  // A crank's sinusoid: hypot(c1, c2) and atan2(c2, c1), where it is largest (set by
  // InputClosureScalar: Range runs at every step of a path's drive).
  double amplitude = 0.0;
  double peak = 0.0;

  // S at input value u.
  double S(double u) const;
  // Smallest and largest f over the input values from `start` over `sweep` (either sign; a crank
  // sweep of a turn or more covers the whole sinusoid): S at the ends and at its extremes within
  // (a sinusoid's at atan2(c2, c1) and that plus pi, a parabola's vertex).
  void Range(double start, double sweep, double* smallest, double* largest) const;
  // Whether f stays within [low - slack, high + slack] over the sweep.
  bool Holds(double start, double sweep, double slack) const;
};

// Inline: the path solver's drive checks the closure at every step.
inline constexpr double kClosurePi = 3.14159265358979323846;
inline constexpr double kClosureTwoPi = 2.0 * kClosurePi;

inline double ClosureScalar::S(double u) const {
  return crank ? c0 + c1 * std::cos(u) + c2 * std::sin(u) : c0 + (c1 + c2 * u) * u;
}

inline void ClosureScalar::Range(double start, double sweep, double* smallest,
                                 double* largest) const {
  const double a = std::min(start, start + sweep), b = std::max(start, start + sweep);
  double low_s = std::min(S(a), S(b)), high_s = std::max(S(a), S(b));
  const auto consider = [&](double u) {
    if (u < a || u > b) return;
    low_s = std::min(low_s, S(u));
    high_s = std::max(high_s, S(u));
  };
  if (crank) {
    if (std::abs(sweep) >= kClosureTwoPi) {
      low_s = c0 - amplitude;
      high_s = c0 + amplitude;
    } else {
      // The sinusoid's largest value at its peak, its smallest at the peak + pi.
      for (int k = 0; k < 2; ++k) {
        const double extreme = peak + k * kClosurePi;
        // The first angle >= a congruent to the extreme.
        const double candidate = extreme + std::ceil((a - extreme) / kClosureTwoPi) * kClosureTwoPi;
        if (candidate <= b) (k == 0 ? high_s : low_s) = c0 + (k == 0 ? amplitude : -amplitude);
      }
    }
  } else if (c2 != 0.0) {
    consider(-c1 / (2.0 * c2));  // the parabola's vertex
  }
  if (squared) {
    *smallest = std::sqrt(std::max(low_s, 0.0));
    *largest = std::sqrt(std::max(high_s, 0.0));
  } else {
    *smallest = low_s;
    *largest = high_s;
  }
}

inline bool ClosureScalar::Holds(double start, double sweep, double slack) const {
  double smallest, largest;
  Range(start, sweep, &smallest, &largest);
  return smallest >= low - slack && largest <= high + slack;
}

// Angle in [0, 2 pi).
inline double PositiveAngle(double angle) {
  double wrapped = std::fmod(angle, kClosureTwoPi);
  if (wrapped < 0.0) wrapped += kClosureTwoPi;
  return wrapped;
}

// Appends to closure->intervals the angles {u : lo <= p + q cos u + r sin u <= hi} (lo may be
// -infinity, hi +infinity), setting full_turn when that is every angle: one or two arcs, whose
// ends solve cos(u - atan2(r, q)) = const. Shared by the planar four-bars' sinusoidal closures
// and the spherical four-bar's (lib/spherical_four_bar.h).
void SinusoidClosure(double p, double q, double r, double lo, double hi, FourBarClosure* closure);

// The closure scalar of the four-bar driven by `input` (RR or PR; not RP).
ClosureScalar InputClosureScalar(const PlanarDyad& input, const PlanarDyad& output);

// The closure of the four-bar driven by `input`.
FourBarClosure SolveFourBarClosure(const PlanarDyad& input, const PlanarDyad& output);

// The interval holding input value `value` (angle inputs: any real value, taken modulo a turn),
// within `slack` (an input distance) of its ends; -1 when none does.
int ClosureIntervalOf(const FourBarClosure& closure, double value, double slack = 0.0);

// A circuit of the closed-form motion: an interval of the closure, and the assembly label it
// keeps (0 or 1), or -1 for both (the two branches of a limited input, joined at a finite end).
struct ClosedCircuit {
  int interval = 0;
  int label = -1;
  bool rotates_fully = false;
};

// The circuits as TraceFourBar forms them: a full turn (or a slider range open at both ends)
// gives a circuit per label; an interval with a finite end joins its two labels there.
std::vector<ClosedCircuit> ClosedCircuits(const FourBarClosure& closure);

// The interval holding `value`, or (an assembly admitted by the assembly's tolerance just
// beyond an end) the one with the nearest end; -1 when there is none.
int NearestInterval(const FourBarClosure& closure, double value);

}  // namespace linkfit

#endif  // LINKFIT_LIB_FOUR_BAR_CLOSURE_H_
