#include "lib/spherical_dyad.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace linkfit {

double DirectionAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

SphericalDyad SphericalDyad::Make(const Eigen::Vector3d& fixed_axis,
                                  const Eigen::Vector3d& moving_axis, double angle) {
  SphericalDyad dyad;
  dyad.fixed_axis = fixed_axis.normalized();
  dyad.moving_axis = moving_axis.normalized();
  dyad.angle = angle;
  if (dyad.angle > 0.5 * M_PI) {
    dyad.moving_axis = -dyad.moving_axis;
    dyad.angle = M_PI - dyad.angle;
  }
  Eigen::Index largest = 0;
  dyad.fixed_axis.cwiseAbs().maxCoeff(&largest);
  if (dyad.fixed_axis(largest) < 0.0) {
    dyad.fixed_axis = -dyad.fixed_axis;
    dyad.moving_axis = -dyad.moving_axis;
  }
  return dyad;
}

double SphericalDyadDistance(const SphericalDyad& a, const SphericalDyad& b) {
  double best = std::numeric_limits<double>::infinity();
  for (const double fixed_sign : {1.0, -1.0}) {
    for (const double moving_sign : {1.0, -1.0}) {
      // One axis turned over makes the cone angle pi - alpha; both keep it.
      const double angle = fixed_sign * moving_sign > 0.0 ? b.angle : M_PI - b.angle;
      best = std::min(best, std::max({DirectionAngle(a.fixed_axis, fixed_sign * b.fixed_axis),
                                      DirectionAngle(a.moving_axis, moving_sign * b.moving_axis),
                                      std::abs(a.angle - angle)}));
    }
  }
  return best;
}

double SphericalDyad::MaxResidual(const std::vector<Eigen::Matrix3d>& rotations) const {
  double worst = 0.0;
  for (const Eigen::Matrix3d& rotation : rotations) {
    worst = std::max(worst, std::abs(Residual(rotation)));
  }
  return worst;
}

bool SphericalDyad::AllFinite() const {
  return fixed_axis.allFinite() && moving_axis.allFinite() && std::isfinite(angle);
}

DualQuaternion SphericalMotion::Pose(const Eigen::Matrix3d& rotation) const {
  return DualQuaternion::FromRotationTranslation(rotation,
                                                 center_in_fixed - rotation * center_in_moving);
}

double SphericalMotion::PoseError(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) const {
  const Eigen::Vector3d shift = (a - b) * center_in_moving;
  const double turn = Eigen::AngleAxisd(a * b.transpose()).angle();
  return std::sqrt(shift.squaredNorm() + length * length * turn * turn);
}

double SphericalMotion::TaskPoseError(const Eigen::Matrix3d& rotation, size_t j) const {
  if (j >= translations.size()) return PoseError(rotation, rotations[j]);
  const Eigen::Vector3d shift = center_in_fixed - rotation * center_in_moving - translations[j];
  // The angle of R R_j^T from its trace and its skew part (atan2: accurate near 0 and pi), a
  // third of the time Eigen's AngleAxis takes (the analyses call this per pose and assembly).
  const Eigen::Matrix3d relative = rotation * rotations[j].transpose();
  const Eigen::Vector3d skew(relative(2, 1) - relative(1, 2), relative(0, 2) - relative(2, 0),
                             relative(1, 0) - relative(0, 1));
  const double turn = std::atan2(0.5 * skew.norm(), 0.5 * (relative.trace() - 1.0));
  return std::sqrt(shift.squaredNorm() + length * length * turn * turn);
}

SphericalMotion MakeSphericalMotion(const std::vector<DualQuaternion>& poses,
                                    const Eigen::Vector3d& center_in_moving,
                                    const Eigen::Vector3d& center_in_fixed, double length) {
  SphericalMotion motion;
  for (const DualQuaternion& pose : poses) {
    motion.rotations.push_back(pose.Rotation());
    motion.translations.push_back(pose.Translation());
  }
  motion.center_in_moving = center_in_moving;
  motion.center_in_fixed = center_in_fixed;
  motion.length = length;
  return motion;
}

}  // namespace linkfit
