// The nested-model test the refiners use to report the simpler joint (a slider, a plane) unless
// the richer one (a circle, a sphere) fits significantly better.
#ifndef LINKFIT_OPTIMIZERS_NESTED_MODEL_TEST_H_
#define LINKFIT_OPTIMIZERS_NESTED_MODEL_TEST_H_

namespace linkfit {

// The 95th percentile of the F(1, m) distribution, the square of Student's t quantile
// t_{0.975}(m): tabulated for m <= 10, beyond from the four-term Cornish-Fisher expansion of t
// about the normal quantile (relative error below 1e-4 for m > 10).
inline double FQuantile95(int m) {
  static constexpr double kTable[] = {161.4476387975, 18.5128205128, 10.1279644860, 7.7086474222,
                                      6.6078909737,   5.9873776073,  5.5914478512,  5.3176550716,
                                      5.1173550292,   4.9646027437};
  if (m >= 1 && m <= 10) return kTable[m - 1];
  const double z = 1.959963984540054;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  const double k = static_cast<double>(m);
  const double t = z + (z3 + z) / (4.0 * k) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * k * k) +
                   (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * k * k * k);
  return t * t;
}

// Whether a model with one parameter fewer suffices: its least-squares cost is not
// significantly above the richer model's, (simple - rich) / (rich / m) <= F_0.95(1, m), with m the
// richer model's residual degrees of freedom. With m < 1 or a zero rich cost: simple <= rich.
inline bool SimplerModelSuffices(double simple_cost, double rich_cost, int m) {
  if (m < 1 || !(rich_cost > 0.0)) return simple_cost <= rich_cost;
  return (simple_cost - rich_cost) / (rich_cost / m) <= FQuantile95(m);
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_NESTED_MODEL_TEST_H_
