// The order statistic both benchmark programs print (median, worst, 99th percentile).
#ifndef LINKFIT_BENCH_PERCENTILE_H_
#define LINKFIT_BENCH_PERCENTILE_H_

#include <algorithm>
#include <vector>

namespace linkfit {

// The value at `fraction` (0 = smallest, 1 = largest) of the sorted values; 0 for none.
inline double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(fraction * values.size()));
  return values[index];
}

}  // namespace linkfit

#endif  // LINKFIT_BENCH_PERCENTILE_H_
