// Tests of lib/planar_pose.h: planar poses (x, y, theta), similarities of the plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/planar_pose.h"

namespace {

using linkfit::PlanarPose;
using linkfit::Similarity2;

constexpr double kTight = 1e-12;      // exact algebra on O(1) numbers
constexpr double kRoundTrip = 1e-10;  // round trips through trigonometry
constexpr unsigned kSeed = 31415926;  // fixed seed of every random test here
constexpr int kTrials = 200;

struct RandomPlanarSource {
  explicit RandomPlanarSource(unsigned seed) : engine(seed) {}

  double Angle() { return angle(engine); }
  Eigen::Vector2d Point(double scale = 5.0) {
    return scale * Eigen::Vector2d(uniform(engine), uniform(engine));
  }
  PlanarPose Pose() {
    const Eigen::Vector2d origin = Point();
    return PlanarPose(origin.x(), origin.y(), Angle());
  }
  Similarity2 Similarity(double scale) {
    Similarity2 s;
    s.scale = scale;
    s.angle = Angle();
    s.translation = Point(10.0);
    return s;
  }

  std::mt19937 engine;
  std::uniform_real_distribution<double> uniform{-1.0, 1.0};
  std::uniform_real_distribution<double> angle{-M_PI, M_PI};
};

// Angles equal modulo 2 pi.
double AngleDifference(double a, double b) { return std::abs(linkfit::WrapAngle(a - b)); }

void ExpectSamePose(const PlanarPose& a, const PlanarPose& b, double tolerance,
                    const std::string& what) {
  EXPECT_LT((a.origin_in_fixed - b.origin_in_fixed).norm(), tolerance) << what;
  EXPECT_LT(AngleDifference(a.theta, b.theta), tolerance) << what;
}

TEST(PlanarPoseWrapAngle, RangeIsHalfOpen) {
  EXPECT_EQ(linkfit::WrapAngle(M_PI), M_PI);
  EXPECT_EQ(linkfit::WrapAngle(-M_PI), M_PI);
  EXPECT_EQ(linkfit::WrapAngle(0.0), 0.0);
  EXPECT_NEAR(linkfit::WrapAngle(2.0 * M_PI), 0.0, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(-2.0 * M_PI), 0.0, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(3.0 * M_PI), M_PI, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(-3.0 * M_PI), M_PI, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(7.0), 7.0 - 2.0 * M_PI, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(-7.0), -7.0 + 2.0 * M_PI, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(M_PI + 1e-9), -M_PI + 1e-9, kTight);
  EXPECT_NEAR(linkfit::WrapAngle(-M_PI - 1e-9), M_PI - 1e-9, kTight);
  EXPECT_EQ(linkfit::WrapAngle(1.0), 1.0);
  EXPECT_EQ(linkfit::WrapAngle(-1.0), -1.0);

  std::mt19937 engine(kSeed);
  SCOPED_TRACE("seed " + std::to_string(kSeed));
  std::uniform_real_distribution<double> wide(-100.0, 100.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const double angle = wide(engine);
    const double wrapped = linkfit::WrapAngle(angle);
    EXPECT_GT(wrapped, -M_PI) << "angle " << angle;
    EXPECT_LE(wrapped, M_PI) << "angle " << angle;
    EXPECT_NEAR(std::cos(wrapped), std::cos(angle), kRoundTrip) << "angle " << angle;
    EXPECT_NEAR(std::sin(wrapped), std::sin(angle), kRoundTrip) << "angle " << angle;
  }
  // Odd multiples of pi all land on +pi (or within rounding of it, never below -pi).
  for (int k = -9; k <= 9; k += 2) {
    const double wrapped = linkfit::WrapAngle(k * M_PI);
    EXPECT_GT(wrapped, -M_PI) << "k " << k;
    EXPECT_LE(wrapped, M_PI) << "k " << k;
    EXPECT_NEAR(std::abs(wrapped), M_PI, 1e-14 * std::abs(k)) << "k " << k;
  }
}

TEST(PlanarPoseRotation2, MatchesDefinition) {
  const Eigen::Matrix2d r = linkfit::Rotation2(M_PI / 2.0);
  EXPECT_LT((r * Eigen::Vector2d(1, 0) - Eigen::Vector2d(0, 1)).norm(), kTight);
  const PlanarPose pose(1.0, 2.0, M_PI / 2.0);
  // A body point on E's x-axis turns counter-clockwise onto the direction of Sigma's y-axis.
  EXPECT_LT((pose.ToFixed(Eigen::Vector2d(3, 0)) - Eigen::Vector2d(1, 5)).norm(), kTight);
  EXPECT_LT((pose.DirectionToFixed(Eigen::Vector2d(3, 0)) - Eigen::Vector2d(0, 3)).norm(), kTight);
}

TEST(PlanarPoseMapping, ToFixedAndToMovingAreInverse) {
  RandomPlanarSource source(kSeed + 1);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 1));
  for (int trial = 0; trial < kTrials; ++trial) {
    const PlanarPose pose = source.Pose();
    const Eigen::Vector2d p = source.Point();
    EXPECT_LT((pose.ToMoving(pose.ToFixed(p)) - p).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((pose.ToFixed(pose.ToMoving(p)) - p).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((pose.ToFixed(Eigen::Vector2d::Zero()) - pose.origin_in_fixed).norm(), kTight);
    // Directions ignore the translation.
    const Eigen::Vector2d v = source.Point();
    EXPECT_LT((pose.DirectionToFixed(v) - (pose.ToFixed(p + v) - pose.ToFixed(p))).norm(),
              kRoundTrip)
        << "trial " << trial;
    // Distances are kept.
    EXPECT_NEAR((pose.ToFixed(p) - pose.ToFixed(p + v)).norm(), v.norm(), kRoundTrip);
  }
}

TEST(PlanarPoseInverse, UndoesThePose) {
  RandomPlanarSource source(kSeed + 2);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 2));
  const PlanarPose identity;
  for (int trial = 0; trial < kTrials; ++trial) {
    const PlanarPose pose = source.Pose();
    const PlanarPose inverse = pose.Inverse();
    const Eigen::Vector2d p = source.Point();
    EXPECT_LT((inverse.ToFixed(p) - pose.ToMoving(p)).norm(), kRoundTrip) << "trial " << trial;
    ExpectSamePose(pose * inverse, identity, kRoundTrip, "trial " + std::to_string(trial));
    ExpectSamePose(inverse * pose, identity, kRoundTrip, "trial " + std::to_string(trial));
    ExpectSamePose(inverse.Inverse(), pose, kRoundTrip, "trial " + std::to_string(trial));
  }
}

TEST(PlanarPoseCompose, IdentityAndAssociativity) {
  RandomPlanarSource source(kSeed + 3);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 3));
  const PlanarPose identity;
  for (int trial = 0; trial < kTrials; ++trial) {
    const PlanarPose a = source.Pose(), b = source.Pose(), c = source.Pose();
    const std::string what = "trial " + std::to_string(trial);
    ExpectSamePose(identity * a, a, kTight, what);
    ExpectSamePose(a * identity, a, kTight, what);
    ExpectSamePose((a * b) * c, a * (b * c), kRoundTrip, what);
    const Eigen::Vector2d p = source.Point();
    EXPECT_LT(((a * b).ToFixed(p) - a.ToFixed(b.ToFixed(p))).norm(), kRoundTrip) << what;
    const double theta = (a * b).theta;
    EXPECT_GT(theta, -M_PI) << what;
    EXPECT_LE(theta, M_PI) << what;
  }
}

TEST(PlanarPoseError, WrapsTheAngle) {
  constexpr double kLength = 3.0;
  const PlanarPose a(1.0, 2.0, M_PI - 0.1);
  const PlanarPose b(1.0, 2.0, -M_PI + 0.1);
  EXPECT_NEAR(linkfit::PoseError(a, b, kLength), kLength * 0.2, kRoundTrip);
  EXPECT_NEAR(linkfit::PoseError(b, a, kLength), kLength * 0.2, kRoundTrip);
  // Angles differing by a full turn are the same pose.
  EXPECT_NEAR(linkfit::PoseError(PlanarPose(0, 0, 0.3), PlanarPose(0, 0, 0.3 + 2 * M_PI), 5.0), 0.0,
              kRoundTrip);
  // Position and angle together: 3-4-5 shift plus 0.5 rad with L = 2 (sqrt(25 + 1)).
  EXPECT_NEAR(linkfit::PoseError(PlanarPose(0, 0, 0.25), PlanarPose(3, 4, -0.25), 2.0),
              std::sqrt(26.0), kRoundTrip);
  // A half turn difference counts as pi, never more.
  EXPECT_NEAR(linkfit::PoseError(PlanarPose(0, 0, 0.0), PlanarPose(0, 0, M_PI), 1.0), M_PI,
              kRoundTrip);
  EXPECT_EQ(linkfit::PoseError(a, a, kLength), 0.0);
}

TEST(PlanarPoseCharacteristicLength, KnownSets) {
  // Corners of a 2 x 2 square: every origin is sqrt(2) from the centroid.
  const std::vector<PlanarPose> square = {PlanarPose(0, 0, 0.1), PlanarPose(2, 0, 0.2),
                                          PlanarPose(0, 2, 0.3), PlanarPose(2, 2, 0.4)};
  EXPECT_NEAR(linkfit::CharacteristicLength(square), std::sqrt(2.0), kTight);
  // Two points 6 apart: each 3 from the centroid.
  EXPECT_NEAR(linkfit::CharacteristicLength({PlanarPose(-1, 5, 0), PlanarPose(5, 5, 1)}), 3.0,
              kTight);
  // Origins (0,0), (0,0), (3,0): centroid (1,0), squared distances 1, 1, 4, mean 2.
  EXPECT_NEAR(linkfit::CharacteristicLength(
                  {PlanarPose(0, 0, 0), PlanarPose(0, 0, 1), PlanarPose(3, 0, 2)}),
              std::sqrt(2.0), kTight);
  EXPECT_EQ(linkfit::CharacteristicLength({}), 0.0);
  EXPECT_EQ(linkfit::CharacteristicLength({PlanarPose(4, 5, 6)}), 0.0);
  EXPECT_NEAR(linkfit::CharacteristicLength({PlanarPose(4, 5, 6), PlanarPose(4, 5, -1)}), 0.0,
              kTight);

  // Units: scales with the data; does not depend on a rigid motion of the fixed frame.
  RandomPlanarSource source(kSeed + 4);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 4));
  std::vector<PlanarPose> poses;
  for (int i = 0; i < 7; ++i) poses.push_back(source.Pose());
  const double length = linkfit::CharacteristicLength(poses);
  const Similarity2 sigma = source.Similarity(1000.0);
  // The moving frame is only rescaled about its origin, so the new origins are sigma(origins).
  Similarity2 epsilon;
  epsilon.scale = 1000.0;
  std::vector<PlanarPose> moved;
  for (const PlanarPose& pose : poses) {
    moved.push_back(linkfit::TransformPose(pose, sigma, epsilon));
    EXPECT_LT((moved.back().origin_in_fixed - sigma.Apply(pose.origin_in_fixed)).norm(), 1e-9);
  }
  EXPECT_NEAR(linkfit::CharacteristicLength(moved), 1000.0 * length, 1e-9 * 1000.0 * length);
}

TEST(PlanarPoseSimilarity, ApplyAndInverse) {
  RandomPlanarSource source(kSeed + 5);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 5));
  std::uniform_real_distribution<double> log_scale(-3.0, 3.0);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Similarity2 s = source.Similarity(std::exp(log_scale(source.engine)));
    const Similarity2 inverse = s.Inverse();
    const Eigen::Vector2d p = source.Point();
    const double tolerance = kRoundTrip * (1.0 + s.scale + 1.0 / s.scale) * 10.0;
    EXPECT_LT((inverse.Apply(s.Apply(p)) - p).norm(), tolerance) << "trial " << trial;
    EXPECT_LT((s.Apply(inverse.Apply(p)) - p).norm(), tolerance) << "trial " << trial;
    // Definition: scale * R(angle) p + translation.
    EXPECT_LT((s.Apply(p) - (s.scale * linkfit::Rotation2(s.angle) * p + s.translation)).norm(),
              tolerance)
        << "trial " << trial;
    // Directions are rotated only.
    const Eigen::Vector2d v = source.Point();
    EXPECT_LT((s.ApplyToDirection(v) - linkfit::Rotation2(s.angle) * v).norm(), kRoundTrip);
    EXPECT_LT((inverse.ApplyToDirection(s.ApplyToDirection(v)) - v).norm(), kRoundTrip);
    // Distances scale by `scale`.
    EXPECT_NEAR((s.Apply(p) - s.Apply(p + v)).norm(), s.scale * v.norm(), tolerance);
  }
}

TEST(PlanarPoseTransformPose, ConsistentWithBothSimilarities) {
  RandomPlanarSource source(kSeed + 6);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 6));
  std::uniform_real_distribution<double> log_scale(-2.0, 2.0);
  for (int trial = 0; trial < kTrials; ++trial) {
    const double scale = std::exp(log_scale(source.engine));
    const Similarity2 sigma = source.Similarity(scale), epsilon = source.Similarity(scale);
    const PlanarPose pose = source.Pose();
    const PlanarPose transformed = linkfit::TransformPose(pose, sigma, epsilon);
    const double tolerance = kRoundTrip * 10.0 * (1.0 + scale);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d p = source.Point();
      EXPECT_LT((transformed.ToFixed(epsilon.Apply(p)) - sigma.Apply(pose.ToFixed(p))).norm(),
                tolerance)
          << "trial " << trial;
    }
    EXPECT_GT(transformed.theta, -M_PI) << "trial " << trial;
    EXPECT_LE(transformed.theta, M_PI) << "trial " << trial;
    // Mapping back with the inverses gives the pose back.
    ExpectSamePose(linkfit::TransformPose(transformed, sigma.Inverse(), epsilon.Inverse()), pose,
                   tolerance, "trial " + std::to_string(trial));
  }
  // Identity similarities leave the pose alone.
  const PlanarPose pose(1.5, -2.5, 0.7);
  ExpectSamePose(linkfit::TransformPose(pose, Similarity2(), Similarity2()), pose, kTight,
                 "identity");
}

}  // namespace
