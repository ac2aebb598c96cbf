// The input's range of an analysis (lib/four_bar_kinematics.h, lib/spherical_four_bar_kinematics.h,
// lib/six_bar_kinematics.h): where a rotating input turns from its reference, the part of it a
// caller asks for, and the input's values sampled over it.
#ifndef LINKFIT_LIB_INPUT_RANGE_H_
#define LINKFIT_LIB_INPUT_RANGE_H_

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace linkfit {

// How far `angle` lies ahead of `start`, in [0, 2 pi); an angle a rounding error (1e-9 rad)
// before `start` is at it.
inline double TurnAhead(double angle, double start) {
  double offset = std::fmod(angle - start, 2.0 * M_PI);
  if (offset < 0.0) offset += 2.0 * M_PI;
  return offset > 2.0 * M_PI - 1e-9 ? 0.0 : offset;
}

// The input's range about `reference` between the angles where the loop stops closing
// (`critical`): a whole turn from the reference where there are none (*full), else from the
// nearest behind it to the nearest ahead.
inline void RangeAbout(double reference, const std::vector<double>& critical, double* start,
                       double* end, bool* full) {
  double ahead = 2.0 * M_PI, behind = 2.0 * M_PI;
  for (const double angle : critical) {
    // Its offset ahead of the reference in [0, 2 pi): 0 puts the reference at the range's start.
    double offset = std::fmod(angle - reference, 2.0 * M_PI);
    if (offset < 0.0) offset += 2.0 * M_PI;
    if (offset < 1e-12) {
      behind = 0.0;
      continue;
    }
    ahead = std::min(ahead, offset);
    behind = std::min(behind, 2.0 * M_PI - offset);
  }
  *full = ahead == 2.0 * M_PI && behind == 2.0 * M_PI;
  *start = reference - (*full ? 0.0 : behind);
  *end = reference + ahead;
}

// The part `asked` (from < to) of the range from `start` over `span`, its start moved by whole
// turns into the range: *first and *span; false where it leaves the range.
inline bool PartOfRange(const std::pair<double, double>& asked, double start, double* first,
                        double* span) {
  const double offset = TurnAhead(asked.first, start);
  const double part = asked.second - asked.first;
  if (!(part > 0.0) || offset + part > *span + 1e-12) return false;
  *first = start + offset;
  *span = part;
  return true;
}

// The input's value at sample k of `steps` over [first, first + span]: a part asked for from end
// to end, a whole turn from its start, a range between dead points at the midpoints of equal
// parts (inside them).
inline double SampledInput(int k, int steps, bool asked, bool full_turn, double first,
                           double span) {
  if (asked) return first + (steps > 1 ? span * k / (steps - 1) : 0.0);
  return full_turn ? first + span * k / steps : first + span * (k + 0.5) / steps;
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_INPUT_RANGE_H_
