// Spherical RR dyads: two revolute joints whose axes pass through one point, the centre of a
// spherical motion (every displacement of the task fixes it; fitting/spatial_motion.h
// DetectSphericalMotion). In the centre frames (Sigma's axes about the centre P, E's about the
// centre p of the body) a pose is a rotation R, and the dyad keeps the angle alpha between its
// fixed axis u (unit, Sigma) and its moving axis v (unit, E):
//   u . R v = cos(alpha),
// the spherical form of |R m + d - F| = r (seed 000, section 7: as poses in a plane are planar
// motion, poses that fix one point are spherical motion, whose constraints are cones). An axis
// is a line through the centre, so (u, v, alpha), (-u, v, pi - alpha), (u, -v, pi - alpha) and
// (-u, -v, alpha) are one dyad; the canonical form has alpha in [0, pi/2] and the largest
// component of u positive.
#ifndef LINKFIT_LIB_SPHERICAL_DYAD_H_
#define LINKFIT_LIB_SPHERICAL_DYAD_H_

#include <Eigen/Core>
#include <vector>

#include "lib/spatial_pose.h"

namespace linkfit {

// The angle between two directions, atan2(|a x b|, a . b): accurate near 0 and pi.
double DirectionAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

struct SphericalDyad {
  Eigen::Vector3d fixed_axis = Eigen::Vector3d::UnitZ();   // u, unit, in Sigma
  Eigen::Vector3d moving_axis = Eigen::Vector3d::UnitZ();  // v, unit, in E
  double angle = 0.0;                                      // alpha, radians

  // The canonical dyad (file comment) of axes u and v (normalized here) and angle alpha.
  static SphericalDyad Make(const Eigen::Vector3d& fixed_axis, const Eigen::Vector3d& moving_axis,
                            double angle);

  // The angle by which R v misses its cone about u, angle(u, R v) - alpha, radians.
  double Residual(const Eigen::Matrix3d& rotation) const {
    return DirectionAngle(fixed_axis, rotation * moving_axis) - angle;
  }
  // Largest |Residual| over the rotations, radians.
  double MaxResidual(const std::vector<Eigen::Matrix3d>& rotations) const;
  bool AllFinite() const;
};

// How far apart two spherical dyads are: the largest of the angles between their fixed axes and
// between their moving axes and the difference of their cone angles (radians), the least over
// the four sign forms of one dyad (file comment), so that a dyad near alpha = pi/2, whose
// canonical form may flip an axis, is near itself.
double SphericalDyadDistance(const SphericalDyad& a, const SphericalDyad& b);

// A spherical motion in its centre frames: the task's poses (R_j, d_j) with R_j p + d_j = P.
// A body point p + y (E) is at P + R_j y (Sigma).
struct SphericalMotion {
  std::vector<Eigen::Matrix3d> rotations;
  // The task poses' translations d_j, when made from spatial poses (MakeSphericalMotion): a pose
  // error is then measured against the pose as given, its deviation from the sphere included.
  std::vector<Eigen::Vector3d> translations;
  Eigen::Vector3d center_in_fixed = Eigen::Vector3d::Zero();   // P
  Eigen::Vector3d center_in_moving = Eigen::Vector3d::Zero();  // p
  double length = 1.0;                                         // the task's characteristic length L

  // The spatial pose of rotation R: (R, P - R p).
  DualQuaternion Pose(const Eigen::Matrix3d& rotation) const;
  // The spatial pose error (lib/spatial_pose.h PoseError) of two rotations' poses:
  // sqrt(|(R_a - R_b) p|^2 + (L angle(R_a R_b^T))^2).
  double PoseError(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) const;
  // The spatial pose error of rotation R's pose from task pose j: against (R_j, d_j) when the
  // translations are known, else PoseError(R, R_j).
  double TaskPoseError(const Eigen::Matrix3d& rotation, size_t j) const;
};

// The motion of `poses` about the centre (p in E, P in Sigma): the rotations of the poses.
SphericalMotion MakeSphericalMotion(const std::vector<DualQuaternion>& poses,
                                    const Eigen::Vector3d& center_in_moving,
                                    const Eigen::Vector3d& center_in_fixed, double length);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SPHERICAL_DYAD_H_
