// Richardson-extrapolated central differences, the tests' reference for closed-form rates: a
// function sampled at t - h, t - h/2, t, t + h/2 and t + h (in that order) gives its first and
// second derivatives at t to O(h^4).
#ifndef LINKFIT_TESTS_SUPPORT_RICHARDSON_H_
#define LINKFIT_TESTS_SUPPORT_RICHARDSON_H_

#include <array>

namespace linkfit::testing {

// Value: a number or an Eigen vector (each difference evaluated into a Value: Eigen's
// expressions would keep references to temporaries).
template <typename Value>
Value RichardsonFirst(const std::array<Value, 5>& f, double h) {
  const Value wide = (f[4] - f[0]) / (2.0 * h);
  const Value narrow = (f[3] - f[1]) / h;
  return Value((4.0 * narrow - wide) / 3.0);
}

template <typename Value>
Value RichardsonSecond(const std::array<Value, 5>& f, double h) {
  const Value wide = (f[4] - 2.0 * f[2] + f[0]) / (h * h);
  const Value narrow = (f[3] - 2.0 * f[2] + f[1]) / (0.25 * h * h);
  return Value((4.0 * narrow - wide) / 3.0);
}

// `get` of each of five samples (t - h .. t + h), as RichardsonFirst and RichardsonSecond take
// them.
template <typename Sample, typename Get>
auto EachOf(const std::array<Sample, 5>& samples, const Get& get)
    -> std::array<decltype(get(samples[0])), 5> {
  return {get(samples[0]), get(samples[1]), get(samples[2]), get(samples[3]), get(samples[4])};
}

// The rates of a mechanism's kinetic and potential energy in its input at t: `energies(t, &k,
// &p)` (false where the mechanism does not assemble) at t - h, t - h/2, t + h/2 and t + h,
// Richardson-extrapolated (the inertial and the weight torque a constant input speed needs, per
// unit speed). False where any of the four does not assemble.
template <typename Energies>
bool EnergyRates(double t, double h, const Energies& energies, double* inertial, double* weight) {
  std::array<double, 5> k = {}, p = {};  // (t itself: not read)
  const double offsets[5] = {-h, -0.5 * h, 0.0, 0.5 * h, h};
  for (int i : {0, 1, 3, 4}) {
    if (!energies(t + offsets[i], &k[i], &p[i])) return false;
  }
  *inertial = RichardsonFirst(k, h);
  *weight = RichardsonFirst(p, h);
  return true;
}

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RICHARDSON_H_
