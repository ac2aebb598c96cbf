#include "lib/planar_pose.h"

#include <cmath>

namespace linkfit {

double WrapAngle(double angle) {
  // Most angles are already wrapped (atan2's, and sums of two): std::remainder is slow.
  if (angle > -M_PI && angle <= M_PI) return angle;
  double wrapped = std::remainder(angle, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI) wrapped += 2.0 * M_PI;
  return wrapped;
}

Eigen::Matrix2d Rotation2(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Eigen::Vector2d PlanarPose::ToFixed(const Eigen::Vector2d& point_in_moving) const {
  return Rotation2(theta) * point_in_moving + origin_in_fixed;
}

Eigen::Vector2d PlanarPose::ToMoving(const Eigen::Vector2d& point_in_fixed) const {
  return Rotation2(theta).transpose() * (point_in_fixed - origin_in_fixed);
}

Eigen::Vector2d PlanarPose::DirectionToFixed(const Eigen::Vector2d& direction_in_moving) const {
  return Rotation2(theta) * direction_in_moving;
}

PlanarPose PlanarPose::Inverse() const {
  PlanarPose inverse;
  inverse.theta = WrapAngle(-theta);
  inverse.origin_in_fixed = -(Rotation2(theta).transpose() * origin_in_fixed);
  return inverse;
}

PlanarPose operator*(const PlanarPose& a, const PlanarPose& b) {
  PlanarPose ab;
  ab.theta = WrapAngle(a.theta + b.theta);
  ab.origin_in_fixed = a.ToFixed(b.origin_in_fixed);
  return ab;
}

double PoseError(const PlanarPose& a, const PlanarPose& b, double length) {
  const double dangle = WrapAngle(a.theta - b.theta);
  // Not std::hypot: several times slower, and no length squared overflows (called per
  // assembly in the analyses' inner loops).
  const double turn = length * dangle;
  return std::sqrt((a.origin_in_fixed - b.origin_in_fixed).squaredNorm() + turn * turn);
}

double CharacteristicLength(const std::vector<PlanarPose>& poses) {
  if (poses.empty()) return 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  centroid /= static_cast<double>(poses.size());
  double sum = 0.0;
  for (const PlanarPose& pose : poses) sum += (pose.origin_in_fixed - centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(poses.size()));
}

Eigen::Vector2d Similarity2::Apply(const Eigen::Vector2d& point) const {
  return scale * (Rotation2(angle) * point) + translation;
}

Eigen::Vector2d Similarity2::ApplyToDirection(const Eigen::Vector2d& direction) const {
  return Rotation2(angle) * direction;
}

Similarity2 Similarity2::Inverse() const {
  Similarity2 inverse;
  inverse.scale = 1.0 / scale;
  inverse.angle = -angle;
  inverse.translation = -(inverse.scale * (Rotation2(-angle) * translation));
  return inverse;
}

PlanarPose TransformPose(const PlanarPose& pose, const Similarity2& sigma,
                         const Similarity2& epsilon) {
  // New pose maps q -> sigma(pose(epsilon^-1(q))); its rotation is angle_s + theta - angle_e.
  const Similarity2 epsilon_inverse = epsilon.Inverse();
  PlanarPose out;
  out.theta = WrapAngle(sigma.angle + pose.theta - epsilon.angle);
  out.origin_in_fixed = sigma.Apply(pose.ToFixed(epsilon_inverse.Apply(Eigen::Vector2d::Zero())));
  return out;
}

}  // namespace linkfit
