// Planar poses (x, y, theta): the moving frame E has its origin at (x, y) in the fixed frame
// Sigma and is turned by theta counter-clockwise; a body point p_E is at R(theta) p_E + (x, y).
#ifndef LINKFIT_LIB_PLANAR_POSE_H_
#define LINKFIT_LIB_PLANAR_POSE_H_

#include <Eigen/Core>
#include <vector>

namespace linkfit {

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle);

// 2x2 rotation matrix of angle theta (counter-clockwise).
Eigen::Matrix2d Rotation2(double theta);

struct PlanarPose {
  Eigen::Vector2d origin_in_fixed = Eigen::Vector2d::Zero();  // origin of E in Sigma
  double theta = 0.0;                                         // rotation of E, radians

  PlanarPose() = default;
  PlanarPose(double x, double y, double theta_rad) : origin_in_fixed(x, y), theta(theta_rad) {}

  // Maps a point given in E to Sigma: R(theta) p + origin.
  Eigen::Vector2d ToFixed(const Eigen::Vector2d& point_in_moving) const;
  // Maps a point given in Sigma to E: R(theta)^T (p - origin).
  Eigen::Vector2d ToMoving(const Eigen::Vector2d& point_in_fixed) const;
  // Maps a direction (free vector) from E to Sigma.
  Eigen::Vector2d DirectionToFixed(const Eigen::Vector2d& direction_in_moving) const;

  // The inverse displacement: the pose of Sigma seen from E.
  PlanarPose Inverse() const;
};

// Composition: (a * b).ToFixed(p) == a.ToFixed(b.ToFixed(p)).
PlanarPose operator*(const PlanarPose& a, const PlanarPose& b);

// Pose error of the design: sqrt(|delta position|^2 + (L * delta angle)^2), delta angle
// wrapped to (-pi, pi]; `length` is the task's characteristic length L.
double PoseError(const PlanarPose& a, const PlanarPose& b, double length);

// Characteristic length of a planar task: the RMS distance of the pose origins from their
// centroid. Zero when all origins coincide.
double CharacteristicLength(const std::vector<PlanarPose>& poses);

// A similarity of the fixed plane, x -> scale * R(angle) x + translation. Solvers centre and
// scale the data with one (see NormalizePoses) and map their answers back with its inverse.
struct Similarity2 {
  double scale = 1.0;
  double angle = 0.0;
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();

  Eigen::Vector2d Apply(const Eigen::Vector2d& point) const;
  Eigen::Vector2d ApplyToDirection(const Eigen::Vector2d& direction) const;  // rotation only
  Similarity2 Inverse() const;
};

// Transforms a pose when the fixed frame is mapped by `sigma` and the moving frame by
// `epsilon` (both similarities with the same scale): the returned pose maps epsilon(p) to
// sigma(pose(p)).
PlanarPose TransformPose(const PlanarPose& pose, const Similarity2& sigma,
                         const Similarity2& epsilon);

}  // namespace linkfit

#endif  // LINKFIT_LIB_PLANAR_POSE_H_
