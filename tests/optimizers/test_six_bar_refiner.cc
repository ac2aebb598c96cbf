// The six-bar refiner (optimizers/six_bar_refiner.h): a random six-bar of each layout driven
// through nine poses; its joints and E's place moved by a few hundredths of L, it meets the poses
// again; with noise on the poses, the fit is no worse than the generator's own error.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "lib/six_bar.h"
#include "optimizers/six_bar_refiner.h"
#include "tests/support/random_six_bar.h"

namespace linkfit {
namespace {

// The six-bar with every joint and E's place moved by up to `by` at random.
SixBar Moved(const SixBar& six_bar, double by, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> shift(-by, by);
  const auto move = [&](Eigen::Vector2d* p) { *p += Eigen::Vector2d(shift(rng), shift(rng)); };
  SixBar moved = six_bar;
  move(&moved.ground_pivot);
  move(&moved.elbow);
  move(&moved.wrist);
  for (SixBarRRLink& link : moved.links) {
    move(&link.from_joint);
    move(&link.to_joint);
  }
  move(&moved.reference_pose.origin_in_fixed);
  moved.reference_pose.theta += shift(rng);
  return moved;
}

// From a six-bar moved by up to 0.02 L, the refinement meets the nine exact poses again. The
// joints themselves are weakly determined by poses over 40 to 100 degrees of a turn: the pose
// errors' Jacobian in the 17 parameters has singular values from about 5 down to 1e-7 .. 1e-9
// (measured), so six-bars a few hundredths of L from the generator meet the poses within 1e-8 L,
// and Levenberg-Marquardt descends that flat valley slowly: the fit is asked of it, not the
// generator's joints.
TEST(SixBarRefiner, AMovedSixBarMeetsTheExactPosesAgain) {
  std::mt19937_64 rng(3610);
  int met = 0, tasks = 0;
  double worst = 0.0;
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    for (int trial = 0; trial < 2; ++trial) {
      const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, layout, 9);
      SCOPED_TRACE(std::string(SixBarTopologyName(layout.topology)) + " trial " +
                   std::to_string(trial));
      const SixBar seed = Moved(task.six_bar, 0.02, rng);
      SixBarFit fit;
      ASSERT_TRUE(FitSixBarToPoses(seed, task.poses, {}, 1.0, task.configurations, &fit));
      const double before = fit.rms_pose_error;
      EXPECT_GT(before, 1e-3);
      const RefinerSummary summary = RefineSixBar(task.poses, {}, 1.0, &fit);
      EXPECT_NEAR(summary.initial_rms, before, 1e-12);
      EXPECT_EQ(summary.final_rms, fit.rms_pose_error);
      EXPECT_LE(fit.rms_pose_error, before);
      ++tasks;
      met += fit.max_pose_error < 1e-6;
      worst = std::max(worst, fit.max_pose_error);
      // The configurations are the six-bar's, at the first pose its reference.
      ASSERT_EQ(fit.at_poses.size(), task.poses.size());
      EXPECT_LT(fit.at_poses[0].cwiseAbs().maxCoeff(), 1e-12);
      for (const SixBarAngles& angles : fit.at_poses) {
        EXPECT_LT(SixBarClosure(fit.six_bar, angles).norm(), 1e-10);
      }
    }
  }
  // Measured: 12 of 12 within 1e-6 L, the worst 2.3e-7 L.
  EXPECT_GE(met, tasks - 2);
  std::cout << met << " of " << tasks
            << " moved six-bars refined to meet the poses within 1e-6 L (worst " << worst << ")\n";
}

// Noise of 0.002 L on the nine poses' coordinates (and 0.002 rad on their angles): the refined fit
// is no worse than the generator's own error on the noisy poses (and within 10 % of it at worst,
// were it a local optimum: measured, it is below it in every task).
TEST(SixBarRefiner, NoisyPosesFitNoWorseThanTheGenerator) {
  std::mt19937_64 rng(3611);
  std::normal_distribution<double> noise(0.0, 0.002);
  double worst_ratio = 0.0;
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, layout, 9);
    SCOPED_TRACE(SixBarTopologyName(layout.topology));
    std::vector<PlanarPose> noisy = task.poses;
    for (PlanarPose& pose : noisy) {
      pose.origin_in_fixed += Eigen::Vector2d(noise(rng), noise(rng));
      pose.theta += noise(rng);
    }
    SixBarFit generator;
    ASSERT_TRUE(FitSixBarToPoses(task.six_bar, noisy, {}, 1.0, task.configurations, &generator));
    SixBarFit fit = generator;
    fit.six_bar = Moved(task.six_bar, 0.01, rng);
    ASSERT_TRUE(FitSixBarToPoses(fit.six_bar, noisy, {}, 1.0, task.configurations, &fit));
    RefineSixBar(noisy, {}, 1.0, &fit);
    const double ratio = fit.rms_pose_error / generator.rms_pose_error;
    worst_ratio = std::max(worst_ratio, ratio);
    EXPECT_LE(ratio, 1.0) << fit.rms_pose_error << " against the generator's "
                          << generator.rms_pose_error;
  }
  std::cout << "refined RMS pose error at most " << worst_ratio
            << " times the generator's on the noisy poses\n";
}

}  // namespace
}  // namespace linkfit
