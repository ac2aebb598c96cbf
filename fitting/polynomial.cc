#include "fitting/polynomial.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace linkfit {

namespace {

// Newton's method on the cubic from t, keeping only steps that lower |f|.
double PolishCubicRoot(double c3, double c2, double c1, double c0, double t) {
  auto value = [&](double x) { return ((c3 * x + c2) * x + c1) * x + c0; };
  double f = value(t);
  for (int iteration = 0; iteration < 8 && f != 0.0; ++iteration) {
    const double df = (3.0 * c3 * t + 2.0 * c2) * t + c1;
    if (df == 0.0) break;
    const double next = t - f / df;
    const double next_f = value(next);
    if (!(std::abs(next_f) < std::abs(f))) break;
    t = next;
    f = next_f;
  }
  return t;
}

}  // namespace

int SolveCubicReal(double c3, double c2, double c1, double c0, double roots[3]) {
  // Monic form t^3 + a t^2 + b t + c.
  const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
  if (a == 0.0 && b == 0.0 && c == 0.0) {
    roots[0] = roots[1] = roots[2] = 0.0;
    return 3;
  }
  // 1. The real root of largest magnitude, which is well determined even where the
  // discriminant cancels (widely spread or repeated roots): Cardano or the trigonometric
  // form (Numerical Recipes 5.6), whichever applies, then Newton.
  const double q = (a * a - 3.0 * b) / 9.0;
  const double r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
  double largest = 0.0;
  if (r * r < q * q * q) {
    const double theta = std::acos(std::clamp(r / std::sqrt(q * q * q), -1.0, 1.0));
    const double sq = -2.0 * std::sqrt(q);
    for (double shift : {0.0, 2.0 * M_PI, -2.0 * M_PI}) {
      const double t = sq * std::cos((theta + shift) / 3.0) - a / 3.0;
      if (std::abs(t) > std::abs(largest)) largest = t;
    }
  } else {
    const double big = -std::copysign(std::cbrt(std::abs(r) + std::sqrt(r * r - q * q * q)), r);
    largest = big + (big == 0.0 ? 0.0 : q / big) - a / 3.0;
  }
  const double t1 = PolishCubicRoot(1.0, a, b, c, largest);
  // 2. Deflate: t^3 + a t^2 + b t + c = (t - t1)(t^2 + p1 t + p0). Backward (p0 = -c/t1)
  // when t1 dominates the other roots (|t1|^3 >= |c|), forward (p1 = a + t1) otherwise, so
  // that the small coefficients do not come from a cancelling difference.
  double p1, p0;
  if (t1 != 0.0 && std::abs(t1) * t1 * t1 >= std::abs(c)) {
    p0 = -c / t1;
    p1 = (p0 - b) / t1;
  } else {
    p1 = a + t1;
    p0 = b + t1 * p1;
  }
  // 3. The quadratic, without cancellation; a discriminant that is zero to rounding is a
  // double root.
  int count = 0;
  roots[count++] = t1;
  double discriminant = p1 * p1 - 4.0 * p0;
  const double rounding =
      16.0 * std::numeric_limits<double>::epsilon() * (p1 * p1 + 4.0 * std::abs(p0));
  if (discriminant < 0.0 && discriminant >= -rounding) discriminant = 0.0;
  if (discriminant >= 0.0) {
    const double w = -0.5 * (p1 + std::copysign(std::sqrt(discriminant), p1));
    if (w != 0.0) {
      roots[count++] = PolishCubicRoot(c3, c2, c1, c0, w);
      roots[count++] = PolishCubicRoot(c3, c2, c1, c0, p0 / w);
    } else {
      roots[count++] = 0.0;
      roots[count++] = 0.0;
    }
  }
  roots[0] = PolishCubicRoot(c3, c2, c1, c0, t1);
  std::sort(roots, roots + count);
  return count;
}

void SolveBinaryQuadratic(std::complex<double> a, std::complex<double> b, std::complex<double> c,
                          std::complex<double> alpha[2], std::complex<double> beta[2]) {
  using Complex = std::complex<double>;
  // Roots of a x^2 + 2 b x + c with x = alpha / beta: x = (-b -+ sqrt(b^2 - a c)) / a. Take the
  // sign that avoids cancellation, w = -(b + sign * s); then the roots are w / a and c / w.
  // Both are returned as homogeneous pairs (w : a) and (c : w), which stay valid when a -> 0.
  const Complex s = std::sqrt(b * b - a * c);
  const Complex w = (std::real(std::conj(b) * s) >= 0.0) ? -(b + s) : -(b - s);
  if (std::abs(w) == 0.0) {
    // b = 0 and a c = 0: a double root at x = 0 (c = 0) or at infinity (a = 0).
    const bool at_zero = std::abs(c) <= std::abs(a);
    alpha[0] = alpha[1] = at_zero ? Complex(0.0) : Complex(1.0);
    beta[0] = beta[1] = at_zero ? Complex(1.0) : Complex(0.0);
    return;
  }
  alpha[0] = w;
  beta[0] = a;
  alpha[1] = c;
  beta[1] = w;
}

}  // namespace linkfit
