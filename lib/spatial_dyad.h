// Spatial dyads of seed 000 §3 and their residuals.
//   SS: the moving point c (in E) stays on a sphere of radius r about the center A (in Sigma).
//   PS: the moving point c (in E) stays on a plane n . X = h fixed in Sigma (|n| = 1).
//   SP: the fixed point A (in Sigma) stays on a plane n . x = h fixed in E: the inversion of PS,
//       the limit of an SS dyad whose moving point runs to infinity.
// A dyad's residual at a pose is the signed distance of C = R c + d from its sphere or plane,
// in length units (positive outside the sphere, on the side n points to).
#ifndef LINKFIT_LIB_SPATIAL_DYAD_H_
#define LINKFIT_LIB_SPATIAL_DYAD_H_

#include <Eigen/Core>
#include <vector>

#include "lib/spatial_pose.h"

namespace linkfit {

enum class SpatialDyadType { kSS, kPS, kSP };

const char* SpatialDyadTypeName(SpatialDyadType type);  // "SS", "PS", "SP"

struct SpatialDyad {
  SpatialDyadType type = SpatialDyadType::kSS;
  // SS and PS: the constrained point c, in E.
  Eigen::Vector3d moving_pivot = Eigen::Vector3d::Zero();
  // SS: the sphere center A, in Sigma, and the radius r. SP: the point A of Sigma.
  Eigen::Vector3d fixed_pivot = Eigen::Vector3d::Zero();
  double radius = 0.0;
  // PS: unit plane normal n and offset h of the plane n . X = h, in Sigma. SP: of the plane
  // n . x = h in E.
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();
  double plane_offset = 0.0;

  static SpatialDyad SS(const Eigen::Vector3d& fixed_pivot, const Eigen::Vector3d& moving_pivot,
                        double radius);
  // The normal is normalized here.
  static SpatialDyad PS(const Eigen::Vector3d& moving_pivot, const Eigen::Vector3d& plane_normal,
                        double plane_offset);
  static SpatialDyad SP(const Eigen::Vector3d& fixed_pivot, const Eigen::Vector3d& plane_normal,
                        double plane_offset);

  // Signed distance of C = R c + d from the sphere or plane.
  double Residual(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) const {
    if (type == SpatialDyadType::kSP) {
      return plane_normal.dot(rotation.transpose() * (fixed_pivot - translation)) - plane_offset;
    }
    const Eigen::Vector3d point_in_fixed = rotation * moving_pivot + translation;
    if (type == SpatialDyadType::kSS) return (point_in_fixed - fixed_pivot).norm() - radius;
    return plane_normal.dot(point_in_fixed) - plane_offset;
  }
  double Residual(const DualQuaternion& pose) const {
    return Residual(pose.Rotation(), pose.Translation());
  }
  // Largest |residual| over the poses.
  double MaxResidual(const std::vector<DualQuaternion>& poses) const;
  // Every number of the dyad (pivots, radius, plane) is finite.
  bool AllFinite() const;
};

// A rigid motion with uniform scale, X -> scale * R X + t, used to undo the centering and
// scaling of the data before the algebra.
struct Similarity3 {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& point) const {
    return scale * (rotation * point) + translation;
  }
  Similarity3 Inverse() const;
};

// Maps a dyad found in similarity-transformed frames back: `sigma` maps the transformed fixed
// frame to the original one, `epsilon` the transformed moving frame to the original one (both
// with the same scale).
SpatialDyad TransformSpatialDyad(const SpatialDyad& dyad, const Similarity3& sigma,
                                 const Similarity3& epsilon);

// The pose seen in transformed frames: if `pose` maps E to Sigma, the result maps E' to Sigma'
// where sigma: Sigma' -> Sigma and epsilon: E' -> E (same scale; translation scaled).
DualQuaternion TransformSpatialPose(const DualQuaternion& pose, const Similarity3& sigma,
                                    const Similarity3& epsilon);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SPATIAL_DYAD_H_
