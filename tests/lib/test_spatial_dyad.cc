#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "lib/spatial_dyad.h"

namespace linkfit {
namespace {

constexpr double kTolerance = 1e-12;

const DualQuaternion kPose =
    DualQuaternion::FromAxisAngle(Eigen::Vector3d(1, 2, 3), 0.7, Eigen::Vector3d(0.5, -1.0, 2.0));

TEST(SpatialDyad, ResidualsAreSignedDistances) {
  const Eigen::Vector3d moving(0.3, 0.1, -0.2);
  const Eigen::Vector3d point = kPose.ToFixed(moving);
  const Eigen::Vector3d center(1.0, 1.0, 1.0);
  const double distance = (point - center).norm();
  EXPECT_NEAR(SpatialDyad::SS(center, moving, distance - 0.25).Residual(kPose), 0.25, kTolerance);
  // A plane 0.5 below the point along its normal.
  const Eigen::Vector3d normal = Eigen::Vector3d(1, -1, 2).normalized();
  EXPECT_NEAR(
      SpatialDyad::PS(moving, 3.0 * normal, 3.0 * (normal.dot(point) - 0.5)).Residual(kPose), 0.5,
      kTolerance);
  // SP: the fixed point seen from E, against a plane of E.
  const Eigen::Vector3d fixed(2.0, 0.0, -1.0);
  const Eigen::Vector3d in_moving = kPose.Rotation().transpose() * (fixed - kPose.Translation());
  EXPECT_NEAR(SpatialDyad::SP(fixed, normal, normal.dot(in_moving) + 0.125).Residual(kPose), -0.125,
              kTolerance);
}

TEST(SpatialDyad, TransformsWithTheFrames) {
  // A dyad exact at a pose stays exact at the transformed pose, for every type.
  Similarity3 sigma, epsilon;
  sigma.scale = epsilon.scale = 2.5;
  sigma.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  sigma.translation = Eigen::Vector3d(3, -2, 1);
  epsilon.rotation =
      Eigen::AngleAxisd(-1.1, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
  epsilon.translation = Eigen::Vector3d(-0.5, 0.25, 4);
  const Eigen::Vector3d moving(0.3, 0.1, -0.2), fixed(1.0, 1.0, 1.0);
  const Eigen::Vector3d normal = Eigen::Vector3d(1, -1, 2).normalized();
  const Eigen::Vector3d point = kPose.ToFixed(moving);
  const Eigen::Vector3d in_moving = kPose.Rotation().transpose() * (fixed - kPose.Translation());
  // The pose and dyads live in the transformed frames; map both back.
  const DualQuaternion original = TransformSpatialPose(kPose, sigma.Inverse(), epsilon.Inverse());
  for (const SpatialDyad& dyad : {SpatialDyad::SS(fixed, moving, (point - fixed).norm()),
                                  SpatialDyad::PS(moving, normal, normal.dot(point)),
                                  SpatialDyad::SP(fixed, normal, normal.dot(in_moving))}) {
    SCOPED_TRACE(SpatialDyadTypeName(dyad.type));
    ASSERT_NEAR(dyad.Residual(kPose), 0.0, kTolerance);
    const SpatialDyad mapped = TransformSpatialDyad(dyad, sigma, epsilon);
    EXPECT_NEAR(mapped.Residual(original), 0.0, 1e-11);
  }
}

TEST(Similarity3, InverseUndoes) {
  Similarity3 s;
  s.scale = 0.1;
  s.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 2).normalized()).toRotationMatrix();
  s.translation = Eigen::Vector3d(7, 8, 9);
  const Eigen::Vector3d p(1, -2, 3);
  EXPECT_LT((s.Inverse()(s(p)) - p).norm(), 1e-12);
}

}  // namespace
}  // namespace linkfit
