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

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RICHARDSON_H_
