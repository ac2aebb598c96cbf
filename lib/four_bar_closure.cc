#include "lib/four_bar_closure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// As AssembleFourBar: a linear assembly's lines closer to parallel than this have no solution.
constexpr double kParallel = 1e-12;

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// Angle in [-pi, pi).
double StartAngle(double angle) {
  double wrapped = std::fmod(angle + kPi, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  return wrapped - kPi;
}

using Span = std::pair<double, double>;  // [first, second], either may be infinite

// {s : a s^2 + b s + c >= 0}, a, b or both exactly 0 for a linear or constant function.
std::vector<Span> NonNegative(double a, double b, double c) {
  if (a == 0.0) {
    if (b == 0.0)
      return c >= 0.0 ? std::vector<Span>{{-kInfinity, kInfinity}} : std::vector<Span>{};
    const double root = -c / b;
    return {b > 0.0 ? Span(root, kInfinity) : Span(-kInfinity, root)};
  }
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) {
    return a > 0.0 ? std::vector<Span>{{-kInfinity, kInfinity}} : std::vector<Span>{};
  }
  // Roots without cancellation: q = -(b + sign(b) sqrt(D)) / 2, roots q / a and c / q.
  const double half = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  double r1 = half / a, r2 = half != 0.0 ? c / half : r1;
  if (r1 > r2) std::swap(r1, r2);
  if (a > 0.0) return {{-kInfinity, r1}, {r2, kInfinity}};
  return {{r1, r2}};
}

std::vector<Span> Intersect(const std::vector<Span>& x, const std::vector<Span>& y) {
  std::vector<Span> both;
  for (const Span& a : x) {
    for (const Span& b : y) {
      const double first = std::max(a.first, b.first), second = std::min(a.second, b.second);
      if (first <= second) both.push_back({first, second});
    }
  }
  std::sort(both.begin(), both.end());
  return both;
}

// {s : lo <= a s^2 + b s + c <= hi}.
void QuadraticSet(double a, double b, double c, double lo, double hi, FourBarClosure* closure) {
  std::vector<Span> set = {{-kInfinity, kInfinity}};
  if (std::isfinite(lo)) set = Intersect(set, NonNegative(a, b, c - lo));
  if (std::isfinite(hi)) set = Intersect(set, NonNegative(-a, -b, hi - c));
  for (const Span& span : set) {
    ClosureInterval interval;
    interval.open_start = !std::isfinite(span.first);
    interval.open_end = !std::isfinite(span.second);
    interval.start = span.first;
    interval.end = span.second;
    closure->intervals.push_back(interval);
  }
}

}  // namespace

namespace {

// InputClosureScalar's coefficients and range.
ClosureScalar ScalarOf(const PlanarDyad& input, const PlanarDyad& output) {
  ClosureScalar scalar;
  scalar.crank = input.type == DyadType::kRR;
  const double link = (output.moving_pivot - input.moving_pivot).norm();
  // f = |M1 - F2| or n . (M1 - q): with M1 = B + r (cos u, sin u) (crank) or q1 + u d1
  // (slider) and w = B - point (or q1 - point), S = |w|^2 + r^2 + 2 r w . (cos, sin) or
  // |w|^2 + 2 u w . d1 + u^2 |d1|^2 (squared); n . w + r n . (cos, sin) or n . w + u n . d1.
  const Eigen::Vector2d base = scalar.crank ? input.fixed_pivot : input.line_point;
  const double r = input.radius;
  const Eigen::Vector2d& d1 = input.line_direction;
  if (output.type == DyadType::kPR) {
    const Eigen::Vector2d n = Perp(output.line_direction);
    const double w = n.dot(base - output.line_point);
    scalar.c0 = w;
    scalar.c1 = scalar.crank ? r * n.x() : n.dot(d1);
    scalar.c2 = scalar.crank ? r * n.y() : 0.0;
    scalar.low = -link;
    scalar.high = link;
    return scalar;
  }
  const Eigen::Vector2d w = base - output.fixed_pivot;
  scalar.squared = true;
  if (scalar.crank) {
    scalar.c0 = w.squaredNorm() + r * r;
    scalar.c1 = 2.0 * r * w.x();
    scalar.c2 = 2.0 * r * w.y();
  } else {
    scalar.c0 = w.squaredNorm();
    scalar.c1 = 2.0 * d1.dot(w);
    scalar.c2 = d1.squaredNorm();
  }
  if (output.type == DyadType::kRR) {
    scalar.low = std::abs(link - output.radius);
    scalar.high = link + output.radius;
  } else {
    scalar.low = std::abs(Perp(output.line_direction).dot(input.moving_pivot - output.line_point));
  }
  return scalar;
}

}  // namespace

ClosureScalar InputClosureScalar(const PlanarDyad& input, const PlanarDyad& output) {
  ClosureScalar scalar = ScalarOf(input, output);
  scalar.amplitude = std::sqrt(scalar.c1 * scalar.c1 + scalar.c2 * scalar.c2);
  scalar.peak = std::atan2(scalar.c2, scalar.c1);
  return scalar;
}

FourBarClosure SolveFourBarClosure(const PlanarDyad& input, const PlanarDyad& output) {
  FourBarClosure closure;
  closure.angle_input = input.type != DyadType::kPR;
  if (input.type == DyadType::kRP) {
    const Eigen::Vector2d n1 = Perp(input.line_direction);  // in E
    if (output.type == DyadType::kRR) {
      // |S + k| <= r2 with S = (R n1) . (F1 - F2), k = n1 . (m2 - q1).
      const Eigen::Vector2d f = input.fixed_pivot - output.fixed_pivot;
      const double k = n1.dot(output.moving_pivot - input.line_point);
      SinusoidClosure(0.0, n1.dot(f), n1.x() * f.y() - n1.y() * f.x(), -output.radius - k,
                      output.radius - k, &closure);
    } else {
      // One linear solution wherever the lines are not parallel: the input's line runs along
      // -R(u) d1 in Sigma.
      closure.labels = 1;
      const Eigen::Vector2d& d1 = input.line_direction;
      if (output.type == DyadType::kPR) {
        // Parallel where R(u) d1 = +-d2: two isolated values.
        closure.full_turn = true;
        closure.intervals.push_back({-kPi, kPi, false, false});
        const double u = std::atan2(output.line_direction.y(), output.line_direction.x()) -
                         std::atan2(d1.y(), d1.x());
        closure.singular = {StartAngle(u), StartAngle(u + kPi)};
        std::sort(closure.singular.begin(), closure.singular.end());
      } else if (std::abs(Perp(output.line_direction).dot(d1)) > kParallel) {
        // Both lines turn with E: parallel always or never.
        closure.full_turn = true;
        closure.intervals.push_back({-kPi, kPi, false, false});
      }
    }
    return closure;
  }
  // RR or PR input: f of the input pin in [low, high] (InputClosureScalar); S's range.
  const ClosureScalar scalar = InputClosureScalar(input, output);
  double lo = scalar.low, hi = scalar.high;
  if (scalar.squared) {
    lo = std::max(lo, 0.0) * std::max(lo, 0.0);
    hi = hi * hi;
  }
  if (scalar.crank) {
    SinusoidClosure(scalar.c0, scalar.c1, scalar.c2, lo, hi, &closure);
  } else {
    QuadraticSet(scalar.c2, scalar.c1, scalar.c0, lo, hi, &closure);
  }
  std::sort(closure.intervals.begin(), closure.intervals.end(),
            [](const ClosureInterval& a, const ClosureInterval& b) { return a.start < b.start; });
  return closure;
}

// With rho = hypot(q, r) and phi = atan2(r, q): cos(u - phi) in [m, M], so u - phi in [x0, x1]
// or [-x1, -x0] with x0 = acos(M), x1 = acos(m); the two arcs join across 0 or pi when they touch.
void SinusoidClosure(double p, double q, double r, double lo, double hi, FourBarClosure* closure) {
  const double rho = std::sqrt(q * q + r * r);  // hypot is slow, and no length overflows
  if (!(rho > 0.0)) {
    if (lo <= p && p <= hi) {
      closure->full_turn = true;
      closure->intervals.push_back({-kPi, kPi, false, false});
    }
    return;
  }
  const double phi = std::atan2(r, q);
  const double m = (lo - p) / rho, big_m = (hi - p) / rho;
  if (m > 1.0 || big_m < -1.0 || !(m <= big_m)) return;
  if (m <= -1.0 && big_m >= 1.0) {
    closure->full_turn = true;
    closure->intervals.push_back({-kPi, kPi, false, false});
    return;
  }
  const double x0 = std::acos(std::min(big_m, 1.0)), x1 = std::acos(std::max(m, -1.0));
  if (big_m >= 1.0) {  // one arc about phi
    const double start = StartAngle(phi - x1);
    closure->intervals.push_back({start, start + 2.0 * x1, false, false});
  } else if (m <= -1.0) {  // one arc about phi + pi
    const double start = StartAngle(phi + x0);
    closure->intervals.push_back({start, start + kTwoPi - 2.0 * x0, false, false});
  } else {
    for (const double start : {StartAngle(phi + x0), StartAngle(phi - x1)}) {
      closure->intervals.push_back({start, start + x1 - x0, false, false});
    }
  }
}

int ClosureIntervalOf(const FourBarClosure& closure, double value, double slack) {
  for (size_t i = 0; i < closure.intervals.size(); ++i) {
    const ClosureInterval& interval = closure.intervals[i];
    if (closure.angle_input) {
      if (closure.full_turn) return static_cast<int>(i);
      const double offset = PositiveAngle(value - interval.start);
      if (offset <= interval.Extent() + slack || offset >= kTwoPi - slack) {
        return static_cast<int>(i);
      }
    } else if ((interval.open_start || value >= interval.start - slack) &&
               (interval.open_end || value <= interval.end + slack)) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::vector<ClosedCircuit> ClosedCircuits(const FourBarClosure& closure) {
  std::vector<ClosedCircuit> circuits;
  for (size_t i = 0; i < closure.intervals.size(); ++i) {
    const ClosureInterval& interval = closure.intervals[i];
    const bool joined =
        closure.labels == 2 && !closure.full_turn && !(interval.open_start && interval.open_end);
    if (joined) {
      circuits.push_back({static_cast<int>(i), -1, false});
      continue;
    }
    for (int label = 0; label < closure.labels; ++label) {
      circuits.push_back({static_cast<int>(i), label, closure.angle_input && closure.full_turn});
    }
  }
  return circuits;
}

int NearestInterval(const FourBarClosure& closure, double value) {
  const int inside = ClosureIntervalOf(closure, value);
  if (inside >= 0 || closure.intervals.empty()) return inside;
  int nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < closure.intervals.size(); ++i) {
    const ClosureInterval& interval = closure.intervals[i];
    for (const double end : {interval.start, interval.end}) {
      if (!std::isfinite(end)) continue;
      double distance = std::abs(value - end);
      if (closure.angle_input) {
        distance = PositiveAngle(distance);
        distance = std::min(distance, kTwoPi - distance);
      }
      if (distance < best) {
        best = distance;
        nearest = static_cast<int>(i);
      }
    }
  }
  return nearest;
}

}  // namespace linkfit
