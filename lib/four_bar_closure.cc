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

double PositiveAngle(double angle) {
  double wrapped = std::fmod(angle, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  return wrapped;
}

// {u : lo <= p + q cos u + r sin u <= hi} (lo may be -infinity, hi +infinity): with
// rho = hypot(q, r) and phi = atan2(r, q), cos(u - phi) in [m, M], so u - phi in [x0, x1] or
// [-x1, -x0] with x0 = acos(M), x1 = acos(m); the two arcs join across 0 or pi when they touch.
void SinusoidSet(double p, double q, double r, double lo, double hi, FourBarClosure* closure) {
  const double rho = std::hypot(q, r);
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

FourBarClosure SolveFourBarClosure(const PlanarDyad& input, const PlanarDyad& output) {
  FourBarClosure closure;
  closure.angle_input = input.type != DyadType::kPR;
  if (input.type == DyadType::kRP) {
    const Eigen::Vector2d n1 = Perp(input.line_direction);  // in E
    if (output.type == DyadType::kRR) {
      // |S + k| <= r2 with S = (R n1) . (F1 - F2), k = n1 . (m2 - q1).
      const Eigen::Vector2d f = input.fixed_pivot - output.fixed_pivot;
      const double k = n1.dot(output.moving_pivot - input.line_point);
      SinusoidSet(0.0, n1.dot(f), n1.x() * f.y() - n1.y() * f.x(), -output.radius - k,
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
  // RR or PR input: S of the input pin M1(u), p + q cos u + r sin u (crank) or a u^2 + b u + c
  // (slider); `range` the S range that closes the output.
  const Eigen::Vector2d v = output.moving_pivot - input.moving_pivot;
  double lo = -kInfinity, hi = kInfinity;
  // S = |M1 - P|^2 (squared) or S = n . M1 (linear, n = `normal`), P = `point`.
  bool squared = true;
  Eigen::Vector2d point = Eigen::Vector2d::Zero(), normal = Eigen::Vector2d::Zero();
  switch (output.type) {
    case DyadType::kRR:
      point = output.fixed_pivot;
      lo = (v.norm() - output.radius) * (v.norm() - output.radius);
      hi = (v.norm() + output.radius) * (v.norm() + output.radius);
      break;
    case DyadType::kPR:
      squared = false;
      normal = Perp(output.line_direction);
      lo = normal.dot(output.line_point) - v.norm();
      hi = normal.dot(output.line_point) + v.norm();
      break;
    case DyadType::kRP: {
      point = output.fixed_pivot;
      const double c = Perp(output.line_direction).dot(output.line_point - input.moving_pivot);
      lo = c * c;
      break;
    }
  }
  if (input.type == DyadType::kRR) {
    // M1(u) = F1 + r1 (cos u, sin u).
    const double r1 = input.radius;
    if (squared) {
      const Eigen::Vector2d w0 = input.fixed_pivot - point;
      SinusoidSet(w0.squaredNorm() + r1 * r1, 2.0 * r1 * w0.x(), 2.0 * r1 * w0.y(), lo, hi,
                  &closure);
    } else {
      SinusoidSet(normal.dot(input.fixed_pivot), r1 * normal.x(), r1 * normal.y(), lo, hi,
                  &closure);
    }
  } else {
    // M1(s) = q1 + s d1.
    const Eigen::Vector2d& d1 = input.line_direction;
    if (squared) {
      const Eigen::Vector2d w0 = input.line_point - point;
      QuadraticSet(d1.squaredNorm(), 2.0 * d1.dot(w0), w0.squaredNorm(), lo, hi, &closure);
    } else {
      QuadraticSet(0.0, normal.dot(d1), normal.dot(input.line_point), lo, hi, &closure);
    }
  }
  std::sort(closure.intervals.begin(), closure.intervals.end(),
            [](const ClosureInterval& a, const ClosureInterval& b) { return a.start < b.start; });
  return closure;
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

}  // namespace linkfit
