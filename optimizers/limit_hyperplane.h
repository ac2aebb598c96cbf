// The line (planar) or plane (spatial) that a circle or sphere flattens into as its radius grows:
// the slider limit of an RR or SS dyad, fitted to the positions its constrained point takes.
#ifndef LINKFIT_OPTIMIZERS_LIMIT_HYPERPLANE_H_
#define LINKFIT_OPTIMIZERS_LIMIT_HYPERPLANE_H_

#include <Eigen/Core>
#include <vector>

namespace linkfit {

template <int N>
struct Hyperplane {
  Eigen::Matrix<double, N, 1> normal;  // unit
  double offset = 0.0;                 // the hyperplane is normal . x = offset
};

// Normal along the direction from `center` to the weighted mean of `points` (from the mean to
// `center` when `toward_points` is false), `fallback` when the two coincide; offset the
// weighted mean of normal . p, the best offset for that normal. `weights` may be empty (all 1).
template <int N>
Hyperplane<N> LimitHyperplane(const std::vector<Eigen::Matrix<double, N, 1>>& points,
                              const std::vector<double>& weights,
                              const Eigen::Matrix<double, N, 1>& center, bool toward_points,
                              const Eigen::Matrix<double, N, 1>& fallback) {
  const auto weight = [&](size_t j) { return weights.empty() ? 1.0 : weights[j]; };
  Eigen::Matrix<double, N, 1> mean = Eigen::Matrix<double, N, 1>::Zero();
  double weight_sum = 0.0;
  for (size_t j = 0; j < points.size(); ++j) {
    mean += weight(j) * points[j];
    weight_sum += weight(j);
  }
  mean /= weight_sum;
  Hyperplane<N> plane;
  plane.normal = toward_points ? Eigen::Matrix<double, N, 1>(mean - center)
                               : Eigen::Matrix<double, N, 1>(center - mean);
  if (!(plane.normal.norm() > 0.0) || !plane.normal.allFinite()) plane.normal = fallback;
  plane.normal.normalize();
  for (size_t j = 0; j < points.size(); ++j) {
    plane.offset += weight(j) * plane.normal.dot(points[j]);
  }
  plane.offset /= weight_sum;
  return plane;
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_LIMIT_HYPERPLANE_H_
