// A function y = f(x) given as samples, for function-generation tasks (issue 17, item 7): the
// spacing of precision points over a range, and f between the samples.
#ifndef LINKFIT_LIB_FUNCTION_SAMPLES_H_
#define LINKFIT_LIB_FUNCTION_SAMPLES_H_

#include <vector>

namespace linkfit {

// Chebyshev spacing of `count` precision points over [start, end]:
//   x_k = (start + end) / 2 - (end - start) / 2 cos((2k - 1) pi / (2 count)),  k = 1..count,
// in increasing order (the spacing that minimizes the largest interpolation error's bound).
std::vector<double> ChebyshevPoints(double start, double end, int count);

// The natural cubic spline through samples (x_i, y_i), x increasing (two samples: the line).
// Outside [x_0, x_last] it continues the end cubics.
class NaturalCubicSpline {
 public:
  NaturalCubicSpline(const std::vector<double>& x, const std::vector<double>& y);
  double operator()(double x) const;

 private:
  std::vector<double> x_, y_;
  std::vector<double> second_;  // y'' at the samples (0 at both ends)
};

}  // namespace linkfit

#endif  // LINKFIT_LIB_FUNCTION_SAMPLES_H_
