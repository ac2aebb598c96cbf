// Tests of lib/dyad.h: planar RR / PR / RP dyads, their signed residuals, inversion, the
// canonical line description and the similarity transform of a dyad.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "tests/support/random_mechanism.h"

namespace {

using linkfit::DyadType;
using linkfit::PlanarDyad;
using linkfit::PlanarPose;
using linkfit::Similarity2;
namespace lt = linkfit::testing;

constexpr double kTight = 1e-12;          // exact algebra on O(1) numbers
constexpr double kSatisfied = 1e-12;      // relative to L: residual of a generating dyad
constexpr double kAngleDegTight = 1e-10;  // degrees, atan2 round trip
constexpr uint64_t kSeed = 20240611;      // fixed seed of every random test here
constexpr int kTasksPerType = 100;

const DyadType kAllTypes[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};

std::string Trace(uint64_t seed, int trial, DyadType type) {
  return "seed " + std::to_string(seed) + " trial " + std::to_string(trial) + " type " +
         linkfit::DyadTypeName(type);
}

// Random dyads of every type satisfied by the poses of a random task: the input dyad of a
// task of input type `type` (the output type cycles through all three).
struct SatisfiedDyad {
  PlanarDyad dyad;
  std::vector<PlanarPose> poses;
};

SatisfiedDyad RandomSatisfiedDyad(std::mt19937_64& rng, DyadType type, int trial) {
  const lt::GeneratedTask task = lt::RandomTask(rng, type, kAllTypes[trial % 3], 5);
  return {task.input, task.poses};
}

// ---------------------------------------------------------------------------------------------
// Names and constructors.

TEST(DyadTypeName, Names) {
  EXPECT_STREQ(linkfit::DyadTypeName(DyadType::kRR), "RR");
  EXPECT_STREQ(linkfit::DyadTypeName(DyadType::kPR), "PR");
  EXPECT_STREQ(linkfit::DyadTypeName(DyadType::kRP), "RP");
}

TEST(DyadConstructors, NormalizeLineDirection) {
  const PlanarDyad pr = PlanarDyad::PR({1, 2}, {3, 4}, {3, 4});
  EXPECT_EQ(pr.type, DyadType::kPR);
  EXPECT_NEAR(pr.line_direction.norm(), 1.0, kTight);
  EXPECT_NEAR(pr.line_direction.x(), 0.6, kTight);
  EXPECT_NEAR(pr.line_direction.y(), 0.8, kTight);
  const PlanarDyad rp = PlanarDyad::RP({1, 2}, {3, 4}, {0, -5});
  EXPECT_EQ(rp.type, DyadType::kRP);
  EXPECT_NEAR(rp.line_direction.x(), 0.0, kTight);
  EXPECT_NEAR(rp.line_direction.y(), -1.0, kTight);
  const PlanarDyad rr = PlanarDyad::RR({1, 2}, {3, 4}, 2.5);
  EXPECT_EQ(rr.type, DyadType::kRR);
  EXPECT_EQ(rr.radius, 2.5);
  EXPECT_EQ(rr.fixed_pivot, Eigen::Vector2d(1, 2));
  EXPECT_EQ(rr.moving_pivot, Eigen::Vector2d(3, 4));
}

// ---------------------------------------------------------------------------------------------
// Residual signs and values on hand-made cases.

TEST(DyadResidual, RRIsDistanceMinusRadius) {
  const PlanarPose pose(0.5, 0.3, 0.7);
  const Eigen::Vector2d fixed_pivot(1.0, -2.0);
  const double radius = 2.0;
  const Eigen::Vector2d ray(std::cos(0.4), std::sin(0.4));
  // Moving pivot (given in E) that lands at distance r + 0.1, r - 0.1 and r from F.
  for (const double offset : {0.1, -0.1, 0.0, 1.5}) {
    const Eigen::Vector2d in_fixed = fixed_pivot + (radius + offset) * ray;
    const PlanarDyad dyad = PlanarDyad::RR(fixed_pivot, pose.ToMoving(in_fixed), radius);
    EXPECT_NEAR(dyad.Residual(pose), offset, kTight) << "offset " << offset;
  }
  // The moving pivot is a point of E: the same dyad at another pose sees another distance.
  const PlanarDyad dyad = PlanarDyad::RR({0, 0}, {1, 0}, 1.0);
  EXPECT_NEAR(dyad.Residual(PlanarPose(0, 0, 0)), 0.0, kTight);
  EXPECT_NEAR(dyad.Residual(PlanarPose(0, 0, 1.3)), 0.0, kTight);  // rotation about F
  EXPECT_NEAR(dyad.Residual(PlanarPose(2, 0, 0)), 2.0, kTight);    // point at (3, 0)
  EXPECT_NEAR(dyad.Residual(PlanarPose(-1, 0, 0)), -1.0, kTight);  // point at F
}

TEST(DyadResidual, PRIsPositiveLeftOfDirection) {
  // Line through (1, 1) along +x: left is +y.
  {
    const PlanarPose pose(0.0, 0.0, 0.0);
    const PlanarDyad above = PlanarDyad::PR({5.0, 1.3}, {1, 1}, {1, 0});
    const PlanarDyad below = PlanarDyad::PR({-5.0, 0.6}, {1, 1}, {1, 0});
    EXPECT_NEAR(above.Residual(pose), 0.3, kTight);
    EXPECT_NEAR(below.Residual(pose), -0.4, kTight);
    // Reversing the direction flips the sign.
    const PlanarDyad reversed = PlanarDyad::PR({5.0, 1.3}, {1, 1}, {-1, 0});
    EXPECT_NEAR(reversed.Residual(pose), -0.3, kTight);
  }
  // Line along +y: left is -x. The moving pivot is given in E of a turned pose.
  {
    const PlanarPose pose(2.0, -1.0, 2.1);
    const Eigen::Vector2d target(0.5, 7.0);  // in Sigma, 0.5 to the left of x = 1
    const PlanarDyad dyad = PlanarDyad::PR(pose.ToMoving(target), {1, 1}, {0, 3});
    EXPECT_NEAR(dyad.Residual(pose), 0.5, kTight);
    const PlanarDyad right = PlanarDyad::PR(pose.ToMoving({1.25, -3.0}), {1, 1}, {0, 1});
    EXPECT_NEAR(right.Residual(pose), -0.25, kTight);
  }
  // A diagonal line: the residual is measured perpendicular to it, not along an axis.
  {
    const PlanarDyad dyad = PlanarDyad::PR({0, 1}, {0, 0}, {1, 1});
    EXPECT_NEAR(dyad.Residual(PlanarPose()), std::sqrt(0.5), kTight);
    EXPECT_NEAR(dyad.Residual(PlanarPose(1, 0, 0)), 0.0, kTight);  // pivot at (1, 1)
  }
}

TEST(DyadResidual, RPMapsFixedPivotIntoE) {
  // Pose turned by 90 degrees: E's x-axis points along Sigma's +y.
  const PlanarPose pose(1.0, 2.0, M_PI / 2.0);
  // Fixed pivot at E-coordinates (3, 0.25), i.e. 0.25 left of E's x-axis.
  const Eigen::Vector2d fixed_pivot = pose.ToFixed({3.0, 0.25});
  EXPECT_NEAR(fixed_pivot.x(), 0.75, kTight);
  EXPECT_NEAR(fixed_pivot.y(), 5.0, kTight);
  const PlanarDyad dyad = PlanarDyad::RP(fixed_pivot, {0, 0}, {1, 0});
  EXPECT_NEAR(dyad.Residual(pose), 0.25, kTight);
  // The line is in E, not in Sigma: read in Sigma (through (0, 0) along +x) the fixed pivot
  // would be 5 to the left; the residual must not be that.
  EXPECT_GT(std::abs(dyad.Residual(pose) - 5.0), 1.0);
  // The same dyad at the identity pose: now the line is Sigma's x-axis.
  EXPECT_NEAR(dyad.Residual(PlanarPose()), 5.0, kTight);
  // Line in E through (0, -1) along -x: left of -x is -y, the pivot is 1.25 to its right.
  const PlanarDyad other = PlanarDyad::RP(fixed_pivot, {7, -1}, {-2, 0});
  EXPECT_NEAR(other.Residual(pose), -1.25, kTight);
}

TEST(DyadMaxResidual, LargestAbsoluteValue) {
  const PlanarDyad dyad = PlanarDyad::PR({0, 0}, {0, 0}, {1, 0});
  // Residual = y of the pose origin (moving pivot at E's origin).
  const std::vector<PlanarPose> poses = {PlanarPose(0, 0.1, 0), PlanarPose(3, -0.7, 1),
                                         PlanarPose(-2, 0.5, 2), PlanarPose(1, 0, 3)};
  EXPECT_NEAR(dyad.MaxResidual(poses), 0.7, kTight);
  EXPECT_EQ(dyad.MaxResidual({}), 0.0);
  EXPECT_NEAR(dyad.MaxResidual({PlanarPose(0, -0.2, 0)}), 0.2, kTight);
}

TEST(DyadMaxResidual, RandomDyadsSatisfiedByTheirTask) {
  std::mt19937_64 rng(kSeed);
  for (const DyadType type : kAllTypes) {
    for (int trial = 0; trial < kTasksPerType; ++trial) {
      const SatisfiedDyad sample = RandomSatisfiedDyad(rng, type, trial);
      const double length = linkfit::CharacteristicLength(sample.poses);
      EXPECT_LE(sample.dyad.MaxResidual(sample.poses), kSatisfied * length)
          << Trace(kSeed, trial, type);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Inversion.

TEST(DyadInverted, SwapsTypesAndPivots) {
  const PlanarDyad rr = PlanarDyad::RR({1, 2}, {3, 4}, 5);
  const PlanarDyad rr_inverted = rr.Inverted();
  EXPECT_EQ(rr_inverted.type, DyadType::kRR);
  EXPECT_EQ(rr_inverted.fixed_pivot, Eigen::Vector2d(3, 4));
  EXPECT_EQ(rr_inverted.moving_pivot, Eigen::Vector2d(1, 2));
  EXPECT_EQ(rr_inverted.radius, 5.0);

  const PlanarDyad pr = PlanarDyad::PR({1, 2}, {3, 4}, {0, 1});
  const PlanarDyad pr_inverted = pr.Inverted();
  EXPECT_EQ(pr_inverted.type, DyadType::kRP);
  EXPECT_EQ(pr_inverted.fixed_pivot, Eigen::Vector2d(1, 2));
  EXPECT_EQ(pr_inverted.line_point, Eigen::Vector2d(3, 4));
  EXPECT_EQ(pr_inverted.line_direction, Eigen::Vector2d(0, 1));

  const PlanarDyad rp = PlanarDyad::RP({1, 2}, {3, 4}, {0, 1});
  const PlanarDyad rp_inverted = rp.Inverted();
  EXPECT_EQ(rp_inverted.type, DyadType::kPR);
  EXPECT_EQ(rp_inverted.moving_pivot, Eigen::Vector2d(1, 2));
  EXPECT_EQ(rp_inverted.line_point, Eigen::Vector2d(3, 4));
  EXPECT_EQ(rp_inverted.line_direction, Eigen::Vector2d(0, 1));
}

TEST(DyadInverted, SatisfiedByInvertedPoses) {
  std::mt19937_64 rng(kSeed + 1);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0), angle(-M_PI, M_PI);
  for (const DyadType type : kAllTypes) {
    const DyadType inverted_type = type == DyadType::kRR   ? DyadType::kRR
                                   : type == DyadType::kPR ? DyadType::kRP
                                                           : DyadType::kPR;
    for (int trial = 0; trial < kTasksPerType; ++trial) {
      const SatisfiedDyad sample = RandomSatisfiedDyad(rng, type, trial);
      const double length = linkfit::CharacteristicLength(sample.poses);
      const PlanarDyad inverted = sample.dyad.Inverted();
      EXPECT_EQ(inverted.type, inverted_type) << Trace(kSeed + 1, trial, type);
      std::vector<PlanarPose> inverted_poses;
      for (const PlanarPose& pose : sample.poses) inverted_poses.push_back(pose.Inverse());
      EXPECT_LE(inverted.MaxResidual(inverted_poses), kSatisfied * length)
          << Trace(kSeed + 1, trial, type);
      // Not only zero residuals: inversion keeps every residual, satisfied or not.
      for (int k = 0; k < 5; ++k) {
        const PlanarPose pose(coordinate(rng), coordinate(rng), angle(rng));
        EXPECT_NEAR(inverted.Residual(pose.Inverse()), sample.dyad.Residual(pose), kTight)
            << Trace(kSeed + 1, trial, type) << " pose " << k;
      }
      // Inverting twice gives the dyad back.
      const PlanarDyad twice = inverted.Inverted();
      EXPECT_EQ(twice.type, type) << Trace(kSeed + 1, trial, type);
      EXPECT_LE(lt::DyadDistance(twice, sample.dyad, 1.0), kTight) << Trace(kSeed + 1, trial, type);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Line description.

TEST(DyadLineAngleDeg, AllQuadrantsInHalfOpenRange) {
  struct Case {
    Eigen::Vector2d direction;
    double expected_deg;
  };
  const Case cases[] = {
      {{1, 0}, 0.0},
      {{-1, 0}, 0.0},
      {{-1, -0.0}, 0.0},  // atan2(-0, -1) = -pi
      {{0, 1}, 90.0},
      {{0, -1}, 90.0},
      {{1, 1}, 45.0},
      {{-1, 1}, 135.0},
      {{-1, -1}, 45.0},
      {{1, -1}, 135.0},
      {{std::cos(M_PI / 6), std::sin(M_PI / 6)}, 30.0},
      {{-std::cos(M_PI / 6), -std::sin(M_PI / 6)}, 30.0},
      {{std::cos(-M_PI / 6), std::sin(-M_PI / 6)}, 150.0},
      {{-std::cos(-M_PI / 6), -std::sin(-M_PI / 6)}, 150.0},
  };
  for (const Case& c : cases) {
    for (const DyadType type : {DyadType::kPR, DyadType::kRP}) {
      const PlanarDyad dyad = type == DyadType::kPR ? PlanarDyad::PR({0, 0}, {0, 0}, c.direction)
                                                    : PlanarDyad::RP({0, 0}, {0, 0}, c.direction);
      const double angle = dyad.LineAngleDeg();
      EXPECT_GE(angle, 0.0) << "direction " << c.direction.transpose();
      EXPECT_LT(angle, 180.0) << "direction " << c.direction.transpose();
      EXPECT_NEAR(angle, c.expected_deg, kAngleDegTight) << "direction " << c.direction.transpose();
    }
  }
  // Directions just below the x-axis, on either side: the angle must stay in [0, 180).
  for (const double tiny : {1e-20, 1e-17, 1e-15, 1e-9}) {
    for (const double sx : {1.0, -1.0}) {
      PlanarDyad dyad = PlanarDyad::PR({0, 0}, {0, 0}, {1, 0});
      dyad.line_direction = Eigen::Vector2d(sx, -tiny).normalized();
      const double angle = dyad.LineAngleDeg();
      EXPECT_GE(angle, 0.0) << "tiny " << tiny << " sx " << sx;
      EXPECT_LT(angle, 180.0) << "tiny " << tiny << " sx " << sx;
      // As a line, the angle is within tiny of 0 or 180 (= 0).
      EXPECT_LT(std::min(angle, 180.0 - angle), 1e-6) << "tiny " << tiny << " sx " << sx;
    }
  }
  // Random directions: [0, 180) and the direction is +-(cos, sin) of the angle.
  std::mt19937_64 rng(kSeed + 2);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int trial = 0; trial < 1000; ++trial) {
    const double a = angle(rng);
    const PlanarDyad dyad = PlanarDyad::PR({0, 0}, {0, 0}, {std::cos(a), std::sin(a)});
    const double deg = dyad.LineAngleDeg();
    ASSERT_GE(deg, 0.0) << "seed " << kSeed + 2 << " trial " << trial;
    ASSERT_LT(deg, 180.0) << "seed " << kSeed + 2 << " trial " << trial;
    const double rad = deg * M_PI / 180.0;
    const double cross =
        std::cos(rad) * dyad.line_direction.y() - std::sin(rad) * dyad.line_direction.x();
    EXPECT_NEAR(cross, 0.0, kTight) << "seed " << kSeed + 2 << " trial " << trial;
  }
}

TEST(DyadLineFoot, OnTheLineAndPerpendicularFromOrigin) {
  // Hand case: line through (3, 5) along +x: foot (0, 5).
  {
    const PlanarDyad dyad = PlanarDyad::PR({0, 0}, {3, 5}, {-2, 0});
    EXPECT_NEAR(dyad.LineFoot().x(), 0.0, kTight);
    EXPECT_NEAR(dyad.LineFoot().y(), 5.0, kTight);
  }
  // Line through (2, 0) along (1, 1): foot (1, -1).
  {
    const PlanarDyad dyad = PlanarDyad::RP({0, 0}, {2, 0}, {1, 1});
    EXPECT_NEAR(dyad.LineFoot().x(), 1.0, kTight);
    EXPECT_NEAR(dyad.LineFoot().y(), -1.0, kTight);
  }
  std::mt19937_64 rng(kSeed + 3);
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0), angle(-M_PI, M_PI);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector2d point(coordinate(rng), coordinate(rng));
    const double a = angle(rng);
    const Eigen::Vector2d direction(std::cos(a), std::sin(a));
    for (const DyadType type : {DyadType::kPR, DyadType::kRP}) {
      const PlanarDyad dyad = type == DyadType::kPR ? PlanarDyad::PR({0, 0}, point, direction)
                                                    : PlanarDyad::RP({0, 0}, point, direction);
      const Eigen::Vector2d foot = dyad.LineFoot();
      const std::string where = Trace(kSeed + 3, trial, type);
      // On the line: zero signed distance.
      const Eigen::Vector2d offset = foot - point;
      EXPECT_NEAR(direction.x() * offset.y() - direction.y() * offset.x(), 0.0,
                  kTight * point.norm())
          << where;
      // Perpendicular from the origin.
      EXPECT_NEAR(foot.dot(direction), 0.0, kTight * point.norm()) << where;
      // Its length is the distance of the origin from the line.
      const double distance = std::abs(direction.x() * point.y() - direction.y() * point.x());
      EXPECT_NEAR(foot.norm(), distance, kTight * point.norm()) << where;
      // The residual of a PR dyad whose pivot sits at the foot (identity pose) is zero.
      if (type == DyadType::kPR) {
        PlanarDyad at_foot = dyad;
        at_foot.moving_pivot = foot;
        EXPECT_NEAR(at_foot.Residual(PlanarPose()), 0.0, kTight * point.norm()) << where;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Similarity transforms.

// A change of units by `scale` with a random turn and a shift of up to 10 old units.
Similarity2 RandomSimilarity(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0), angle(-M_PI, M_PI);
  Similarity2 s;
  s.scale = scale;
  s.angle = angle(rng);
  s.translation = scale * Eigen::Vector2d(coordinate(rng), coordinate(rng));
  return s;
}

TEST(DyadTransformDyad, SatisfiedDyadStaysSatisfied) {
  std::mt19937_64 rng(kSeed + 4);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0), angle(-M_PI, M_PI);
  for (const double scale : {1.0, 0.001, 3.7, 1000.0}) {
    for (const DyadType type : kAllTypes) {
      for (int trial = 0; trial < kTasksPerType; ++trial) {
        const std::string where = Trace(kSeed + 4, trial, type) + " scale " + std::to_string(scale);
        const SatisfiedDyad sample = RandomSatisfiedDyad(rng, type, trial);
        const double length = linkfit::CharacteristicLength(sample.poses);
        const Similarity2 sigma = RandomSimilarity(rng, scale);
        const Similarity2 epsilon = RandomSimilarity(rng, scale);
        const PlanarDyad transformed = linkfit::TransformDyad(sample.dyad, sigma, epsilon);
        EXPECT_EQ(transformed.type, type) << where;
        std::vector<PlanarPose> transformed_poses;
        for (const PlanarPose& pose : sample.poses) {
          transformed_poses.push_back(linkfit::TransformPose(pose, sigma, epsilon));
        }
        // Shifts of up to 10 * scale enter the rounding of the transformed coordinates.
        const double transformed_length = scale * std::max(length, 10.0);
        EXPECT_LE(transformed.MaxResidual(transformed_poses), kSatisfied * transformed_length)
            << where;
        // Residuals of an unsatisfied pose scale by sigma.scale, with their sign.
        for (int k = 0; k < 5; ++k) {
          const PlanarPose pose(coordinate(rng), coordinate(rng), angle(rng));
          const double original = sample.dyad.Residual(pose);
          const double mapped = transformed.Residual(linkfit::TransformPose(pose, sigma, epsilon));
          EXPECT_NEAR(mapped, scale * original, kSatisfied * scale * 20.0)
              << where << " pose " << k;
        }
        // Line directions stay unit and line angles turn with the frame of the line.
        if (type != DyadType::kRR) {
          EXPECT_NEAR(transformed.line_direction.norm(), 1.0, kTight) << where;
          const double turn = type == DyadType::kPR ? sigma.angle : epsilon.angle;
          const Eigen::Vector2d expected = linkfit::Rotation2(turn) * sample.dyad.line_direction;
          EXPECT_LE((transformed.line_direction - expected).norm(), kTight) << where;
        } else {
          EXPECT_NEAR(transformed.radius, scale * sample.dyad.radius, kTight * scale) << where;
        }
      }
    }
  }
}

TEST(DyadTransformDyad, RoundTripWithInverse) {
  std::mt19937_64 rng(kSeed + 5);
  for (const DyadType type : kAllTypes) {
    for (int trial = 0; trial < kTasksPerType; ++trial) {
      const SatisfiedDyad sample = RandomSatisfiedDyad(rng, type, trial);
      const Similarity2 sigma = RandomSimilarity(rng, 2.5);
      const Similarity2 epsilon = RandomSimilarity(rng, 2.5);
      const PlanarDyad there = linkfit::TransformDyad(sample.dyad, sigma, epsilon);
      const PlanarDyad back = linkfit::TransformDyad(there, sigma.Inverse(), epsilon.Inverse());
      EXPECT_LE(lt::DyadDistance(back, sample.dyad, 1.0), 1e-11) << Trace(kSeed + 5, trial, type);
    }
  }
}

}  // namespace
