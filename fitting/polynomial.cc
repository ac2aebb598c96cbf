#include "fitting/polynomial.h"

#include <algorithm>
#include <cmath>

namespace linkfit {

int SolveCubicReal(double c3, double c2, double c1, double c0, double roots[3]) {
  // Monic form t^3 + a t^2 + b t + c; trigonometric or Cardano branch (Numerical Recipes
  // 5.6), then Newton polish on the original coefficients.
  const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
  const double q = (a * a - 3.0 * b) / 9.0;
  const double r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
  int count = 0;
  if (r * r < q * q * q) {
    const double theta = std::acos(std::clamp(r / std::sqrt(q * q * q), -1.0, 1.0));
    const double sq = -2.0 * std::sqrt(q);
    roots[0] = sq * std::cos(theta / 3.0) - a / 3.0;
    roots[1] = sq * std::cos((theta + 2.0 * M_PI) / 3.0) - a / 3.0;
    roots[2] = sq * std::cos((theta - 2.0 * M_PI) / 3.0) - a / 3.0;
    count = 3;
  } else {
    const double big = -std::copysign(std::cbrt(std::abs(r) + std::sqrt(r * r - q * q * q)), r);
    const double small = big == 0.0 ? 0.0 : q / big;
    roots[0] = big + small - a / 3.0;
    count = 1;
  }
  for (int i = 0; i < count; ++i) {
    double t = roots[i];
    for (int iteration = 0; iteration < 3; ++iteration) {
      const double f = ((c3 * t + c2) * t + c1) * t + c0;
      const double df = (3.0 * c3 * t + 2.0 * c2) * t + c1;
      if (df == 0.0) break;
      const double step = f / df;
      t -= step;
      if (std::abs(step) <= 1e-16 * std::abs(t)) break;
    }
    roots[i] = t;
  }
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
