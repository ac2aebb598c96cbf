#include "lib/kinematic_mapping.h"

#include <cmath>

namespace linkfit {

Eigen::Vector4d ImageCoordinates(const PlanarPose& pose) {
  // Seed 001 eq. 2.
  const double a = pose.origin_in_fixed.x(), b = pose.origin_in_fixed.y();
  const double s = std::sin(0.5 * pose.theta), c = std::cos(0.5 * pose.theta);
  return Eigen::Vector4d(a * s - b * c, a * c + b * s, 2.0 * s, 2.0 * c);
}

PlanarPose PoseFromImage(const Eigen::Vector4d& image) {
  // Seed 001 eq. 3, written for homogeneous input: tan(phi/2) = X3/X4 and
  // a = 2(X1 X3 + X2 X4)/(X3^2 + X4^2) for the scale X3^2 + X4^2 = 4; for a general multiple
  // lambda * X the right-hand sides pick up lambda^2 / lambda^2 and stay the same.
  const double x1 = image[0], x2 = image[1], x3 = image[2], x4 = image[3];
  const double w = x3 * x3 + x4 * x4;
  PlanarPose pose;
  pose.theta = 2.0 * std::atan2(x3, x4);
  pose.theta = WrapAngle(pose.theta);
  pose.origin_in_fixed =
      Eigen::Vector2d(2.0 * (x1 * x3 + x2 * x4) / w, 2.0 * (x2 * x3 - x1 * x4) / w);
  return pose;
}

}  // namespace linkfit
