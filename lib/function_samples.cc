#include "lib/function_samples.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace linkfit {

std::vector<double> ChebyshevPoints(double start, double end, int count) {
  constexpr double kPi = 3.14159265358979323846;
  std::vector<double> points;
  const double mid = 0.5 * (start + end), half = 0.5 * (end - start);
  for (int k = 1; k <= count; ++k) {
    points.push_back(mid - half * std::cos((2.0 * k - 1.0) * kPi / (2.0 * count)));
  }
  return points;
}

NaturalCubicSpline::NaturalCubicSpline(const std::vector<double>& x, const std::vector<double>& y)
    : x_(x), y_(y), second_(x.size(), 0.0) {
  const int n = static_cast<int>(x.size());
  if (n < 3) return;
  // The tridiagonal system of the interior second derivatives M_i:
  //   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (s_i - s_{i-1}),
  // s_i = (y_{i+1} - y_i) / h_i, M_0 = M_{n-1} = 0 (Thomas algorithm).
  const int m = n - 2;
  std::vector<double> diagonal(m), upper(m), right(m);
  for (int i = 1; i <= m; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    diagonal[i - 1] = 2.0 * (h0 + h1);
    upper[i - 1] = h1;
    right[i - 1] = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
  }
  for (int i = 1; i < m; ++i) {
    const double lower = x[i + 1] - x[i];  // h_i, the sub-diagonal of row i
    const double factor = lower / diagonal[i - 1];
    diagonal[i] -= factor * upper[i - 1];
    right[i] -= factor * right[i - 1];
  }
  for (int i = m - 1; i >= 0; --i) {
    const double next = i + 1 < m ? second_[i + 2] : 0.0;
    second_[i + 1] = (right[i] - (i + 1 < m ? upper[i] * next : 0.0)) / diagonal[i];
  }
}

double NaturalCubicSpline::operator()(double x) const {
  const int n = static_cast<int>(x_.size());
  // The interval [x_i, x_{i+1}] holding x (the end intervals beyond the range).
  int i = static_cast<int>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
  i = std::clamp(i, 0, n - 2);
  const double h = x_[i + 1] - x_[i];
  const double a = (x_[i + 1] - x) / h, b = (x - x_[i]) / h;
  return a * y_[i] + b * y_[i + 1] +
         ((a * a * a - a) * second_[i] + (b * b * b - b) * second_[i + 1]) * h * h / 6.0;
}

}  // namespace linkfit
