#include "fitting/exact_items.h"

#include <Eigen/SVD>
#include <cmath>

namespace linkfit {
namespace {

constexpr int kIterations = 20;
constexpr double kTolerance = 1e-12;

// Minimum-norm Gauss-Newton on r(x) = 0 (the residuals at the exact items), from `x`, with
// `residuals(x)` and central differences of step `step`. Returns whether |r| ends within
// `tolerance`; `x` keeps the last step that lowered |r|.
template <typename Residuals>
bool MinimumNormNewton(const Residuals& residuals, double step, double tolerance,
                       Eigen::VectorXd* x) {
  Eigen::VectorXd r = residuals(*x);
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    if (!r.allFinite()) return false;
    if (r.cwiseAbs().maxCoeff() <= tolerance) return true;
    Eigen::MatrixXd jacobian(r.size(), x->size());
    for (Eigen::Index p = 0; p < x->size(); ++p) {
      Eigen::VectorXd plus = *x, minus = *x;
      plus[p] += step;
      minus[p] -= step;
      jacobian.col(p) = (residuals(plus) - residuals(minus)) / (2.0 * step);
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian,
                                                Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    if (!(sigma[sigma.size() - 1] > 1e-12 * sigma[0])) return false;
    const Eigen::VectorXd next = *x - svd.solve(r);  // the minimum-norm step
    const Eigen::VectorXd next_r = residuals(next);
    if (!next_r.allFinite() || !(next_r.norm() < r.norm())) {
      return r.cwiseAbs().maxCoeff() <= tolerance;
    }
    *x = next;
    r = next_r;
  }
  return r.cwiseAbs().maxCoeff() <= tolerance;
}

std::vector<size_t> ExactIndices(size_t count, const std::vector<bool>& exact) {
  std::vector<size_t> indices;
  for (size_t j = 0; j < count && j < exact.size(); ++j) {
    if (exact[j]) indices.push_back(j);
  }
  return indices;
}

}  // namespace

bool ProjectOntoExactPoses(const std::vector<DualQuaternion>& poses, const std::vector<bool>& exact,
                           double length, SpatialDyad* dyad) {
  const std::vector<size_t> indices = ExactIndices(poses.size(), exact);
  if (indices.empty()) return true;
  // Parameters: SS (A, c, r); PS (c, n, h); SP (A, n, h), with n normalized when read.
  const bool sphere = dyad->type == SpatialDyadType::kSS;
  Eigen::VectorXd x(7);
  const Eigen::Vector3d& point =
      dyad->type == SpatialDyadType::kSP ? dyad->fixed_pivot : dyad->moving_pivot;
  x.head<3>() = point;
  if (sphere) {
    x.segment<3>(3) = dyad->fixed_pivot;
    x[6] = dyad->radius;
  } else {
    x.segment<3>(3) = dyad->plane_normal;
    x[6] = dyad->plane_offset;
  }
  const SpatialDyadType type = dyad->type;
  const auto make = [type](const Eigen::VectorXd& v) {
    const Eigen::Vector3d head = v.head<3>(), middle = v.segment<3>(3);
    switch (type) {
      case SpatialDyadType::kSS:
        return SpatialDyad::SS(middle, head, v[6]);
      case SpatialDyadType::kPS:
        return SpatialDyad::PS(head, middle, v[6]);
      case SpatialDyadType::kSP:
        return SpatialDyad::SP(head, middle, v[6]);
    }
    return SpatialDyad();
  };
  const auto residuals = [&](const Eigen::VectorXd& v) {
    const SpatialDyad candidate = make(v);
    Eigen::VectorXd r(indices.size());
    for (size_t k = 0; k < indices.size(); ++k) r[k] = candidate.Residual(poses[indices[k]]);
    return r;
  };
  if (indices.size() >= 7) return residuals(x).cwiseAbs().maxCoeff() <= kTolerance * length;
  if (!MinimumNormNewton(residuals, 1e-7 * length, kTolerance * length, &x)) return false;
  *dyad = make(x);
  return dyad->AllFinite();
}

bool ProjectOntoExactOrientations(const std::vector<Eigen::Matrix3d>& rotations,
                                  const std::vector<bool>& exact, SphericalDyad* dyad) {
  const std::vector<size_t> indices = ExactIndices(rotations.size(), exact);
  if (indices.empty()) return true;
  Eigen::VectorXd x(7);
  x << dyad->fixed_axis, dyad->moving_axis, dyad->angle;
  const auto make = [](const Eigen::VectorXd& v) {
    return SphericalDyad::Make(v.head<3>(), v.segment<3>(3), v[6]);
  };
  // The raw axes and angle (SphericalDyad::Make's canonical form flips a sign at 90 degrees,
  // which central differences must not straddle).
  const auto residuals = [&](const Eigen::VectorXd& v) {
    const Eigen::Vector3d u = v.head<3>().normalized(), w = v.segment<3>(3).normalized();
    Eigen::VectorXd r(indices.size());
    for (size_t k = 0; k < indices.size(); ++k) {
      r[k] = DirectionAngle(u, rotations[indices[k]] * w) - v[6];
    }
    return r;
  };
  if (indices.size() >= 5) return residuals(x).cwiseAbs().maxCoeff() <= kTolerance;
  if (!MinimumNormNewton(residuals, 1e-7, kTolerance, &x)) return false;
  *dyad = make(x);
  return dyad->AllFinite();
}

}  // namespace linkfit
