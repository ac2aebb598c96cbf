// Small polynomial root finders used by the exact solvers.
#ifndef LINKFIT_FITTING_POLYNOMIAL_H_
#define LINKFIT_FITTING_POLYNOMIAL_H_

#include <complex>

namespace linkfit {

// Real roots of c3 t^3 + c2 t^2 + c1 t + c0 = 0 (c3 != 0), each polished by Newton's method
// on the given coefficients. Returns the count (1 or 3; a double root is listed twice), roots
// ascending. Stable for widely spread and repeated roots: the largest root first, then a
// cancellation-free deflation and quadratic.
int SolveCubicReal(double c3, double c2, double c1, double c0, double roots[3]);

// Both roots (alpha : beta) of the binary quadratic a alpha^2 + 2 b alpha beta + c beta^2 = 0,
// in complex arithmetic, without cancellation. At least one of a, b, c must be non-zero.
// Written as homogeneous pairs so that a root at beta = 0 is representable.
void SolveBinaryQuadratic(std::complex<double> a, std::complex<double> b, std::complex<double> c,
                          std::complex<double> alpha[2], std::complex<double> beta[2]);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_POLYNOMIAL_H_
