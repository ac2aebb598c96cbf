#include "fitting/planar_constraint_space.h"

namespace linkfit {
namespace internal {

std::vector<PoseFrame> MakeFrames(const std::vector<PlanarPose>& poses) {
  std::vector<PoseFrame> frames(poses.size());
  for (size_t j = 0; j < poses.size(); ++j) {
    frames[j].rotation = Rotation2(poses[j].theta);
    frames[j].origin = poses[j].origin_in_fixed;
  }
  return frames;
}

NormalizedMotion Normalize(const std::vector<PlanarPose>& poses) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  centroid /= static_cast<double>(poses.size());
  double length = CharacteristicLength(poses);
  if (!(length > 0.0)) length = 1.0;
  NormalizedMotion out;
  out.length = length;
  out.to_original_fixed.scale = length;
  out.to_original_fixed.translation = centroid;
  out.to_original_moving.scale = length;
  const Similarity2 to_fixed = out.to_original_fixed.Inverse();
  const Similarity2 to_moving = out.to_original_moving.Inverse();
  out.poses.reserve(poses.size());
  for (const PlanarPose& pose : poses) {
    out.poses.push_back(TransformPose(pose, to_fixed, to_moving));
  }
  return out;
}

double PolishRealRoot(const Eigen::Matrix3d& m1, const Eigen::Matrix3d& m2, int iterations,
                      Eigen::Vector3d* a) {
  const Eigen::Vector3d a0 = a->normalized();
  *a = a0;
  const double scale1 = m1.norm(), scale2 = m2.norm();
  if (!(scale1 > 0.0) || !(scale2 > 0.0)) return std::numeric_limits<double>::infinity();
  auto residual = [&](const Eigen::Vector3d& x) {
    return std::hypot(x.dot(m1 * x) / scale1, x.dot(m2 * x) / scale2) / x.squaredNorm();
  };
  double current = residual(*a);
  for (int iteration = 0; iteration < iterations && current > 1e-16; ++iteration) {
    Eigen::Matrix3d jacobian;
    jacobian.row(0) = 2.0 * (m1 * *a).transpose() / scale1;
    jacobian.row(1) = 2.0 * (m2 * *a).transpose() / scale2;
    jacobian.row(2) = a0.transpose();
    const Eigen::Vector3d f(a->dot(m1 * *a) / scale1, a->dot(m2 * *a) / scale2, 0.0);
    const Eigen::Vector3d step = jacobian.partialPivLu().solve(f);
    if (!step.allFinite()) break;
    const Eigen::Vector3d next = *a - step;
    const double next_residual = residual(next);
    if (!(next_residual < current)) break;
    *a = next;
    current = next_residual;
  }
  *a = a->normalized();
  return current;
}

int ReadingsOf(const ConstraintVector& z, const std::vector<PoseFrame>& frames, bool sliders,
               DyadReading readings[3]) {
  const double k0 = z[0];
  const Eigen::Vector2d k(z[3], z[4]);
  const Eigen::Vector2d n(z[1], z[2]);
  int count = 0;
  auto add = [&](const PlanarDyad& dyad) {
    readings[count].dyad = dyad;
    readings[count].max_residual = MaxResidual(dyad, frames);
    ++count;
  };
  Eigen::Matrix2d kmat;
  kmat << k.x(), k.y(), k.y(), -k.x();
  if (sliders && k.norm() > 0.0) {
    // PR: the line 2 K . P + K3 = 0, K3 = z7; moving pivot from [[K1, K2], [K2, -K1]] m =
    // (z5, z6).
    const Eigen::Vector2d moving_pivot = kmat * Eigen::Vector2d(z[5], z[6]) / k.squaredNorm();
    const Eigen::Vector2d normal = k.normalized();
    add(PlanarDyad::PR(moving_pivot, (-z[7] / (2.0 * k.norm())) * normal,
                       Eigen::Vector2d(-normal.y(), normal.x())));
  }
  if (sliders && n.norm() > 0.0) {
    // RP: (z5, z6) = (-F . n, Fx ny - Fy nx) = [[-nx, -ny], [ny, -nx]] F, whose inverse is
    // its transpose over |n|^2; the line of E is n . p = z7 / 2.
    Eigen::Matrix2d nmat;
    nmat << -n.x(), n.y(), -n.y(), -n.x();
    const Eigen::Vector2d fixed_pivot = nmat * Eigen::Vector2d(z[5], z[6]) / n.squaredNorm();
    const Eigen::Vector2d normal = n.normalized();
    add(PlanarDyad::RP(fixed_pivot, (0.5 * z[7] / n.norm()) * normal,
                       Eigen::Vector2d(-normal.y(), normal.x())));
  }
  if (k0 != 0.0) {
    // RR: fixed pivot -K/K0 (seed 001 eq. 10); moving pivot from the least-squares
    // combination of z0 m = (z1, z2) and [[K1, K2], [K2, -K1]] m = (z5, z6), exact at a root
    // and well conditioned whether the fixed pivot is near (|K0| large) or far (|K| large).
    // The radius is the mean pivot distance over the poses (equal at every pose for an exact
    // root), free of the cancellation in |F|^2 - K3/K0.
    const Eigen::Vector2d moving_pivot =
        (k0 * n + kmat * Eigen::Vector2d(z[5], z[6])) / (k0 * k0 + k.squaredNorm());
    const Eigen::Vector2d fixed_pivot = -k / k0;
    double radius = 0.0;
    for (const PoseFrame& frame : frames) {
      radius += (frame.rotation * moving_pivot + frame.origin - fixed_pivot).norm();
    }
    radius /= static_cast<double>(frames.size());
    add(PlanarDyad::RR(fixed_pivot, moving_pivot, radius));
  }
  return count;
}

int ChooseReading(const DyadReading readings[3], int count, double slider_tolerance) {
  // A circle of radius r is itself evaluated to about 4 eps r (its centre is stored to
  // ulp(r)): a slider fitting within that is as good as the circle can be.
  for (int i = 0; i < count; ++i) {
    if (readings[i].dyad.type == DyadType::kRR) {
      slider_tolerance = std::max(
          slider_tolerance, 4.0 * std::numeric_limits<double>::epsilon() * readings[i].dyad.radius);
    }
  }
  int best = -1;
  for (int i = 0; i < count; ++i) {
    if (best < 0 || (readings[i].max_residual < readings[best].max_residual &&
                     readings[best].max_residual > slider_tolerance)) {
      best = i;
    }
  }
  return best;
}

}  // namespace internal
}  // namespace linkfit
