// Tests of lib/kinematic_mapping.h: the planar kinematic mapping of seed 001 eqs 2-5.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/kinematic_mapping.h"
#include "lib/planar_pose.h"

namespace {

using linkfit::PlanarPose;

constexpr double kTight = 1e-12;      // exact algebra on O(1) numbers
constexpr double kRoundTrip = 1e-10;  // round trips through trigonometry
constexpr unsigned kSeed = 27182818;  // fixed seed of every random test here
constexpr int kTrials = 300;

// Random poses with theta uniform in (-pi, pi], plus theta within 1e-9 .. 1e-15 of +-pi.
std::vector<PlanarPose> TestPoses(unsigned seed) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::vector<PlanarPose> poses;
  for (int trial = 0; trial < kTrials; ++trial) {
    poses.emplace_back(coordinate(engine), coordinate(engine), angle(engine));
  }
  for (const double delta : {0.0, 1e-15, 1e-12, 1e-9, 1e-6}) {
    poses.emplace_back(coordinate(engine), coordinate(engine), M_PI - delta);
    poses.emplace_back(coordinate(engine), coordinate(engine), -M_PI + delta);
  }
  poses.emplace_back(0.0, 0.0, 0.0);
  poses.emplace_back(3.0, -4.0, 0.0);
  return poses;
}

// Seed 001 eq. 4: lambda (X, Y, Z) = T (x, y, z), T quadratic in the image coordinates.
Eigen::Matrix3d TransformationMatrix(const Eigen::Vector4d& image) {
  const double x1 = image[0], x2 = image[1], x3 = image[2], x4 = image[3];
  Eigen::Matrix3d t;
  t << x4 * x4 - x3 * x3, -2.0 * x3 * x4, 2.0 * (x1 * x3 + x2 * x4),  //
      2.0 * x3 * x4, x4 * x4 - x3 * x3, 2.0 * (x2 * x3 - x1 * x4),    //
      0.0, 0.0, x3 * x3 + x4 * x4;
  return t;
}

// Seed 001 eq. 5: the inverse transformation, up to a factor.
Eigen::Matrix3d InverseTransformationMatrix(const Eigen::Vector4d& image) {
  const double x1 = image[0], x2 = image[1], x3 = image[2], x4 = image[3];
  Eigen::Matrix3d t;
  t << x4 * x4 - x3 * x3, 2.0 * x3 * x4, 2.0 * (x1 * x3 - x2 * x4),  //
      -2.0 * x3 * x4, x4 * x4 - x3 * x3, 2.0 * (x2 * x3 + x1 * x4),  //
      0.0, 0.0, x3 * x3 + x4 * x4;
  return t;
}

void ExpectSamePose(const PlanarPose& a, const PlanarPose& b, double tolerance,
                    const std::string& what) {
  EXPECT_LT((a.origin_in_fixed - b.origin_in_fixed).norm(), tolerance) << what;
  EXPECT_LT(std::abs(linkfit::WrapAngle(a.theta - b.theta)), tolerance) << what;
}

std::string Describe(const PlanarPose& pose) {
  return "seed " + std::to_string(kSeed) + " pose (" + std::to_string(pose.origin_in_fixed.x()) +
         ", " + std::to_string(pose.origin_in_fixed.y()) + ", " + std::to_string(pose.theta) + ")";
}

TEST(KinematicMappingImage, MatchesEq2OnAKnownPose) {
  // a = 1, b = 2, phi = pi/2: sin = cos = sqrt(2)/2.
  const double h = std::sqrt(0.5);
  const Eigen::Vector4d image = linkfit::ImageCoordinates(PlanarPose(1.0, 2.0, M_PI / 2.0));
  EXPECT_LT((image - Eigen::Vector4d(-h, 3.0 * h, 2.0 * h, 2.0 * h)).norm(), kTight);
  // The identity maps to (0 : 0 : 0 : 2).
  EXPECT_LT((linkfit::ImageCoordinates(PlanarPose()) - Eigen::Vector4d(0, 0, 0, 2)).norm(), kTight);
  // A half turn lies in X4 = 0 (seed 001, assumption 2).
  EXPECT_NEAR(linkfit::ImageCoordinates(PlanarPose(1.0, 1.0, M_PI))[3], 0.0, kTight);
}

TEST(KinematicMappingImage, RoundTripIncludingHalfTurns) {
  for (const PlanarPose& pose : TestPoses(kSeed)) {
    const Eigen::Vector4d image = linkfit::ImageCoordinates(pose);
    EXPECT_NEAR(image[2] * image[2] + image[3] * image[3], 4.0, kTight) << Describe(pose);
    const PlanarPose back = linkfit::PoseFromImage(image);
    ExpectSamePose(back, pose, kRoundTrip, Describe(pose));
    EXPECT_GT(back.theta, -M_PI) << Describe(pose);
    EXPECT_LE(back.theta, M_PI) << Describe(pose);
  }
}

TEST(KinematicMappingImage, HomogeneousScalingInvariance) {
  for (const double factor : {-3.7, 2.5, -1.0, 1e-3, -1e4}) {
    for (const PlanarPose& pose : TestPoses(kSeed + 1)) {
      const Eigen::Vector4d image = linkfit::ImageCoordinates(pose);
      const PlanarPose scaled = linkfit::PoseFromImage(factor * image);
      ExpectSamePose(scaled, linkfit::PoseFromImage(image), kRoundTrip,
                     Describe(pose) + " factor " + std::to_string(factor));
      ExpectSamePose(scaled, pose, kRoundTrip,
                     Describe(pose) + " factor " + std::to_string(factor));
    }
  }
}

TEST(KinematicMappingImage, TransformationMatrixOfEq4MapsLikeThePose) {
  std::mt19937 engine(kSeed + 2);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  for (const double factor : {1.0, -3.7}) {
    for (const PlanarPose& pose : TestPoses(kSeed + 2)) {
      const Eigen::Vector4d image = factor * linkfit::ImageCoordinates(pose);
      const Eigen::Matrix3d t = TransformationMatrix(image);
      const Eigen::Matrix3d t_inverse = InverseTransformationMatrix(image);
      const double w = image[2] * image[2] + image[3] * image[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d p(coordinate(engine), coordinate(engine));
        const Eigen::Vector3d mapped = t * p.homogeneous();
        EXPECT_NEAR(mapped[2], w, kTight * w) << Describe(pose);
        EXPECT_LT((mapped.head<2>() / w - pose.ToFixed(p)).norm(), kRoundTrip)
            << Describe(pose) << " factor " << factor;
        // Eq. 5 undoes eq. 4.
        const Eigen::Vector3d back = t_inverse * mapped;
        EXPECT_LT((back.head<2>() / back[2] - p).norm(), kRoundTrip)
            << Describe(pose) << " factor " << factor;
        EXPECT_LT(((t_inverse * pose.ToFixed(p).homogeneous()).head<2>() / w - p).norm(),
                  kRoundTrip)
            << Describe(pose) << " factor " << factor;
      }
    }
  }
}

TEST(KinematicMappingImage, PoleIsFixed) {
  // (X1 : X2 : X3) are the homogeneous coordinates of the pole, the same in E and Sigma.
  for (const PlanarPose& pose : TestPoses(kSeed + 3)) {
    const Eigen::Vector4d image = linkfit::ImageCoordinates(pose);
    if (std::abs(image[2]) < 1e-3) continue;  // (near-)translations: pole at infinity
    const Eigen::Vector2d pole(image[0] / image[2], image[1] / image[2]);
    const double tolerance = kRoundTrip * (1.0 + pole.norm());
    EXPECT_LT((pose.ToFixed(pole) - pole).norm(), tolerance) << Describe(pose);
  }
}

}  // namespace
