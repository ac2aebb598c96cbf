// The spherical Burmester problem (fitting/spherical_burmester.h) and spherical motion end to end
// (fitting/spherical_motion.h through SolveSpatialMotion): random spherical four-bars make five
// orientations, given as spatial poses about a centre off the origin, and both generating dyads
// must come back, with their four-bar ranked defect-free; the frames' rotation moves the answer
// with them; fewer orientations give the dyads of chosen axes and the axis cones.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "fitting/spatial_motion.h"
#include "fitting/spherical_burmester.h"
#include "fitting/spherical_motion.h"
#include "lib/task.h"
#include "tests/support/random_spatial.h"
#include "tests/support/random_spherical.h"

namespace linkfit {
namespace {

constexpr double kRecovered = 1e-8;  // axes (unit vectors) and angle (radians)
constexpr double kOnDyad = 1e-11;    // a returned dyad's residual, radians

// Whether one of `dyads` is `dyad`.
bool Contains(const std::vector<SphericalDyad>& dyads, const SphericalDyad& dyad,
              double tolerance = kRecovered) {
  for (const SphericalDyad& candidate : dyads) {
    if (SameSphericalDyad(candidate, dyad, tolerance)) return true;
  }
  return false;
}

Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  return testing::RandomSpatialPose(rng).Rotation();
}

TEST(SphericalBurmester, FiveOrientationsGiveBothGeneratingDyads) {
  std::mt19937_64 rng(1711);
  constexpr int kTasks = 150;
  int recovered = 0, real_total = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    std::vector<SphericalDyad> dyads;
    SphericalBurmesterSummary summary;
    SolveSphericalBurmester(rotations, {}, {}, &dyads, &summary);
    EXPECT_EQ(summary.roots_total, 6) << trial;
    EXPECT_FALSE(summary.degenerate) << trial;
    EXPECT_EQ(summary.roots_real % 2, 0) << trial;  // complex roots come in pairs
    real_total += summary.roots_real;
    for (const SphericalDyad& dyad : dyads) {
      EXPECT_LT(dyad.MaxResidual(rotations), kOnDyad) << trial;
    }
    const bool both = Contains(dyads, four_bar.input) && Contains(dyads, four_bar.output);
    EXPECT_TRUE(both) << "trial " << trial << " (seed 1711): " << dyads.size() << " dyads";
    recovered += both;
  }
  EXPECT_EQ(recovered, kTasks);
  // Both generating dyads are real, often more.
  EXPECT_GT(real_total, 2 * kTasks);
}

TEST(SphericalBurmester, RotatingTheFramesRotatesTheDyads) {
  std::mt19937_64 rng(1712);
  for (int trial = 0; trial < 30; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const std::vector<Eigen::Matrix3d>& rotations = drawn.rotations;
    // Sigma turned by Q, E by S: R' = Q R S^T, u' = Q u, v' = S v.
    const Eigen::Matrix3d q = RandomRotation(rng), s = RandomRotation(rng);
    std::vector<Eigen::Matrix3d> turned;
    for (const Eigen::Matrix3d& r : rotations) turned.push_back(q * r * s.transpose());
    std::vector<SphericalDyad> dyads, turned_dyads;
    SolveSphericalBurmester(rotations, {}, {}, &dyads);
    SolveSphericalBurmester(turned, {}, {}, &turned_dyads);
    ASSERT_EQ(dyads.size(), turned_dyads.size()) << trial;
    for (const SphericalDyad& dyad : dyads) {
      const SphericalDyad moved =
          SphericalDyad::Make(q * dyad.fixed_axis, s * dyad.moving_axis, dyad.angle);
      EXPECT_TRUE(Contains(turned_dyads, moved)) << trial;
    }
  }
}

TEST(SphericalBurmester, MoreOrientationsSeedTheGeneratingDyads) {
  std::mt19937_64 rng(1713);
  for (int trial = 0; trial < 30; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 9, 4.0);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    std::vector<SphericalDyad> seeds;
    SphericalBurmesterSummary summary;
    SphericalSeeds(rotations, {}, {}, 4, &seeds, &summary);
    // The five-orientation subsets are exact on exact data.
    EXPECT_TRUE(Contains(seeds, four_bar.input)) << trial;
    EXPECT_TRUE(Contains(seeds, four_bar.output)) << trial;
  }
}

TEST(SphericalBurmester, ChosenAxesGiveTheirDyads) {
  std::mt19937_64 rng(1714);
  for (int trial = 0; trial < 40; ++trial) {
    for (int count : {3, 4}) {
      const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, count);
      const SphericalFourBar& four_bar = drawn.four_bar;
      const std::vector<Eigen::Matrix3d>& rotations = drawn.rotations;
      SphericalDyad dyad;
      double moved = -1.0;
      ASSERT_TRUE(
          SphericalDyadFromMovingAxis(rotations, {}, four_bar.input.moving_axis, &dyad, &moved));
      EXPECT_TRUE(SameSphericalDyad(dyad, four_bar.input, kRecovered)) << trial << " " << count;
      EXPECT_LT(moved, 1e-6);
      ASSERT_TRUE(
          SphericalDyadFromFixedAxis(rotations, {}, four_bar.output.fixed_axis, &dyad, &moved));
      EXPECT_TRUE(SameSphericalDyad(dyad, four_bar.output, kRecovered)) << trial << " " << count;
      if (count == 4) {
        // An axis off the circle-axis cone is moved onto it: the dyad then fits all four.
        const Eigen::Vector3d off =
            (four_bar.input.moving_axis + 0.02 * testing::RandomUnitVector(rng)).normalized();
        ASSERT_TRUE(SphericalDyadFromMovingAxis(rotations, {}, off, &dyad, &moved));
        EXPECT_GT(moved, 0.0);
        EXPECT_LT(moved, 5.0);
        EXPECT_LT(dyad.MaxResidual(rotations), 1e-10) << trial;
      }
    }
  }
}

TEST(SphericalBurmester, FourOrientationsTraceTheAxisCones) {
  std::mt19937_64 rng(1715);
  for (int trial = 0; trial < 20; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 4);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    SphericalBurmesterCones cones;
    ASSERT_TRUE(SampleSphericalBurmesterCones(rotations, 720, &cones)) << trial;
    // Every sampled moving axis has a dyad through the four orientations; the generating axes
    // lie on the cones, next to a sample.
    const auto nearest = [](const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                            const Eigen::Vector3d& axis) {
      double best = M_PI;
      for (const auto& line : polylines) {
        for (const Eigen::Vector3d& x : line) {
          best = std::min({best, DirectionAngle(x, axis), DirectionAngle(-x, axis)});
        }
      }
      return best;
    };
    for (const SphericalDyad* dyad : {&four_bar.input, &four_bar.output}) {
      EXPECT_LT(nearest(cones.circle_axes, dyad->moving_axis), 0.05) << trial;
      EXPECT_LT(nearest(cones.center_axes, dyad->fixed_axis), 0.05) << trial;
    }
    int checked = 0;
    for (const auto& line : cones.circle_axes) {
      for (size_t k = 0; k < line.size(); k += 37) {
        SphericalDyad dyad;
        double moved = 0.0;
        if (!SphericalDyadFromMovingAxis(rotations, {}, line[k], &dyad, &moved)) continue;
        EXPECT_LT(moved, 1e-6) << trial;
        ++checked;
      }
    }
    EXPECT_GT(checked, 5) << trial;
  }
}

// End to end: spatial poses about a centre off the origin (five orientations) are solved as
// spherical; both generating dyads come back and their four-bar is listed without defect.
TEST(SphericalMotion, SpatialPosesAboutACentreGiveTheFourBarBack) {
  std::mt19937_64 rng(1716);
  constexpr int kTasks = 40;
  int first_defect_free = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    const Eigen::Vector3d center_in_moving(0.4, -1.1, 0.7), center_in_fixed(2.0, 1.0, -3.0);
    const Task task =
        SpatialMotionTask(testing::PosesAboutCenter(rotations, center_in_moving, center_in_fixed));
    const SpatialMotionResult result = SolveSpatialMotion(task);
    ASSERT_EQ(result.model, "spherical") << trial;
    ASSERT_TRUE(result.spherical);
    EXPECT_LT((result.spherical->in_fixed - center_in_fixed).norm(), 1e-9);
    EXPECT_LT((result.spherical->in_moving - center_in_moving).norm(), 1e-9);
    EXPECT_EQ(result.method, "exact");
    std::vector<SphericalDyad> dyads;
    for (const SphericalDyadReport& report : result.spherical_dyads) dyads.push_back(report.dyad);
    int input = -1, output = -1;
    for (size_t i = 0; i < dyads.size(); ++i) {
      if (SameSphericalDyad(dyads[i], four_bar.input, kRecovered)) input = static_cast<int>(i);
      if (SameSphericalDyad(dyads[i], four_bar.output, kRecovered)) output = static_cast<int>(i);
    }
    ASSERT_GE(input, 0) << trial;
    ASSERT_GE(output, 0) << trial;
    bool listed = false;
    for (const MechanismReport& mechanism : result.spherical_mechanisms) {
      const bool generating = (mechanism.input_dyad == input && mechanism.output_dyad == output) ||
                              (mechanism.input_dyad == output && mechanism.output_dyad == input);
      if (!generating) continue;
      listed = true;
      ASSERT_TRUE(mechanism.max_pose_error) << trial;
      EXPECT_LT(*mechanism.max_pose_error, 1e-9) << trial;
      EXPECT_FALSE(HasKinematicDefect(mechanism.defects)) << trial;
    }
    EXPECT_TRUE(listed) << trial;
    ASSERT_FALSE(result.spherical_mechanisms.empty());
    first_defect_free += !HasKinematicDefect(result.spherical_mechanisms.front().defects);
  }
  EXPECT_EQ(first_defect_free, kTasks);
}

// End to end: moving both frames (Sigma' = Q Sigma + t, E' = S E + s) moves the centre and every
// dyad with them, R' = Q R S^T, d' = Q d + t - R' s.
TEST(SphericalMotion, MovingTheFramesMovesTheAnswer) {
  std::mt19937_64 rng(1717);
  for (int trial = 0; trial < 20; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const Eigen::Vector3d center_in_moving(0.6, 0.1, -0.4), center_in_fixed(-1.0, 0.5, 2.0);
    const std::vector<DualQuaternion> poses =
        testing::PosesAboutCenter(drawn.rotations, center_in_moving, center_in_fixed);
    const Eigen::Matrix3d q = RandomRotation(rng), s = RandomRotation(rng);
    const Eigen::Vector3d t(3.0, -1.0, 0.5), shift(-0.7, 0.2, 1.1);
    std::vector<DualQuaternion> moved;
    for (const DualQuaternion& pose : poses) {
      const Eigen::Matrix3d r = q * pose.Rotation() * s.transpose();
      moved.push_back(
          DualQuaternion::FromRotationTranslation(r, q * pose.Translation() + t - r * shift));
    }
    const SpatialMotionResult before = SolveSpatialMotion(SpatialMotionTask(poses));
    const SpatialMotionResult after = SolveSpatialMotion(SpatialMotionTask(moved));
    ASSERT_EQ(before.model, "spherical") << trial;
    ASSERT_EQ(after.model, "spherical") << trial;
    EXPECT_LT((after.spherical->in_fixed - (q * before.spherical->in_fixed + t)).norm(), 1e-9);
    EXPECT_LT((after.spherical->in_moving - (s * before.spherical->in_moving + shift)).norm(),
              1e-9);
    ASSERT_EQ(before.spherical_dyads.size(), after.spherical_dyads.size()) << trial;
    std::vector<SphericalDyad> moved_dyads;
    for (const SphericalDyadReport& report : after.spherical_dyads) {
      moved_dyads.push_back(report.dyad);
    }
    for (const SphericalDyadReport& report : before.spherical_dyads) {
      const SphericalDyad expected = SphericalDyad::Make(
          q * report.dyad.fixed_axis, s * report.dyad.moving_axis, report.dyad.angle);
      EXPECT_TRUE(Contains(moved_dyads, expected)) << trial;
    }
    EXPECT_EQ(before.spherical_mechanisms.size(), after.spherical_mechanisms.size());
  }
}

}  // namespace
}  // namespace linkfit
