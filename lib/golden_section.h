// Golden-section search for a minimum of a function of one variable within a bracket, shared by
// the four-bar analysis (a pose's nearest configuration on a circuit) and the path solver (a
// point's nearest crank angle).
#ifndef LINKFIT_LIB_GOLDEN_SECTION_H_
#define LINKFIT_LIB_GOLDEN_SECTION_H_

#include <algorithm>
#include <cmath>

namespace linkfit {

struct GoldenSection {
  double low = 0.0, high = 0.0;  // the final bracket
  double least = 0.0;            // the smallest value evaluated at its interior points
};

// Shrinks [low, high] `shrinks` times by the golden ratio about the smaller of two interior
// values of f, each interior value kept for the next bracket: f is evaluated twice, then once
// per shrink but the last (which only narrows the bracket).
template <typename F>
GoldenSection GoldenSectionSearch(const F& f, double low, double high, int shrinks) {
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = low, b = high;
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  double at_c = f(c), at_d = f(d);
  for (int shrink = 0; shrink < shrinks; ++shrink) {
    const bool last = shrink + 1 == shrinks;
    if (at_c < at_d) {
      b = d;
      if (last) break;
      d = c;
      at_d = at_c;
      c = b - ratio * (b - a);
      at_c = f(c);
    } else {
      a = c;
      if (last) break;
      c = d;
      at_c = at_d;
      d = a + ratio * (b - a);
      at_d = f(d);
    }
  }
  return {a, b, std::min(at_c, at_d)};
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_GOLDEN_SECTION_H_
