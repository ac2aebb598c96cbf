#include "lib/spatial_dyad.h"

#include <algorithm>
#include <cmath>

namespace linkfit {

const char* SpatialDyadTypeName(SpatialDyadType type) {
  switch (type) {
    case SpatialDyadType::kSS:
      return "SS";
    case SpatialDyadType::kPS:
      return "PS";
    case SpatialDyadType::kSP:
      return "SP";
  }
  return "SS";
}

SpatialDyad SpatialDyad::SS(const Eigen::Vector3d& fixed_pivot, const Eigen::Vector3d& moving_pivot,
                            double radius) {
  SpatialDyad dyad;
  dyad.type = SpatialDyadType::kSS;
  dyad.fixed_pivot = fixed_pivot;
  dyad.moving_pivot = moving_pivot;
  dyad.radius = radius;
  return dyad;
}

SpatialDyad SpatialDyad::PS(const Eigen::Vector3d& moving_pivot,
                            const Eigen::Vector3d& plane_normal, double plane_offset) {
  SpatialDyad dyad;
  dyad.type = SpatialDyadType::kPS;
  dyad.moving_pivot = moving_pivot;
  const double norm = plane_normal.norm();
  dyad.plane_normal = plane_normal / norm;
  dyad.plane_offset = plane_offset / norm;
  return dyad;
}

SpatialDyad SpatialDyad::SP(const Eigen::Vector3d& fixed_pivot, const Eigen::Vector3d& plane_normal,
                            double plane_offset) {
  SpatialDyad dyad;
  dyad.type = SpatialDyadType::kSP;
  dyad.fixed_pivot = fixed_pivot;
  const double norm = plane_normal.norm();
  dyad.plane_normal = plane_normal / norm;
  dyad.plane_offset = plane_offset / norm;
  return dyad;
}

bool SpatialDyad::AllFinite() const {
  return moving_pivot.allFinite() && fixed_pivot.allFinite() && std::isfinite(radius) &&
         plane_normal.allFinite() && std::isfinite(plane_offset);
}

double SpatialDyad::MaxResidual(const std::vector<DualQuaternion>& poses) const {
  double worst = 0.0;
  for (const DualQuaternion& pose : poses) worst = std::max(worst, std::abs(Residual(pose)));
  return worst;
}

Similarity3 Similarity3::Inverse() const {
  Similarity3 inverse;
  inverse.scale = 1.0 / scale;
  inverse.rotation = rotation.transpose();
  inverse.translation = -(inverse.scale * (inverse.rotation * translation));
  return inverse;
}

SpatialDyad TransformSpatialDyad(const SpatialDyad& dyad, const Similarity3& sigma,
                                 const Similarity3& epsilon) {
  SpatialDyad out = dyad;
  out.moving_pivot = epsilon(dyad.moving_pivot);
  out.fixed_pivot = sigma(dyad.fixed_pivot);
  if (dyad.type == SpatialDyadType::kSS) {
    out.radius = sigma.scale * dyad.radius;
  } else if (dyad.type == SpatialDyadType::kSP) {
    // The plane lives in E: n . x' = h with x' = epsilon^-1(x).
    out.plane_normal = epsilon.rotation * dyad.plane_normal;
    out.plane_offset =
        epsilon.scale * dyad.plane_offset + out.plane_normal.dot(epsilon.translation);
  } else {
    // n . X' = h with X' = sigma^-1(X): (R n) . X = s h + (R n) . t.
    out.plane_normal = sigma.rotation * dyad.plane_normal;
    out.plane_offset = sigma.scale * dyad.plane_offset + out.plane_normal.dot(sigma.translation);
  }
  return out;
}

DualQuaternion TransformSpatialPose(const DualQuaternion& pose, const Similarity3& sigma,
                                    const Similarity3& epsilon) {
  // X = R c + d; X = sigma(X'), c = epsilon(c'):
  // X' = sigma^-1(R epsilon(c') + d) = Rs^T R Re c' + (Rs^T (R te + d - ts)) / s.
  const Eigen::Matrix3d rotation = pose.Rotation();
  const Eigen::Vector3d translation = pose.Translation();
  const Eigen::Matrix3d new_rotation = sigma.rotation.transpose() * rotation * epsilon.rotation;
  const Eigen::Vector3d new_translation =
      sigma.rotation.transpose() *
      (rotation * epsilon.translation + translation - sigma.translation) / sigma.scale;
  return DualQuaternion::FromRotationTranslation(new_rotation, new_translation);
}

}  // namespace linkfit
