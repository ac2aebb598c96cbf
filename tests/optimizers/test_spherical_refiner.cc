// Spherical least squares (optimizers/spherical_dyad_refiner.h, SolveSpatialTask's spherical
// branch): noisy orientations of a random spherical four-bar, given as spatial poses about a
// centre, give both generating dyads back within the noise and fit no worse than they do; exact
// orientations are met; fast keeps the seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "fitting/spherical_motion.h"
#include "lib/design_constraints.h"
#include "lib/task.h"
#include "optimizers/spherical_dyad_refiner.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_spherical.h"

namespace linkfit {
namespace {

double Rms(const SphericalDyad& dyad, const std::vector<Eigen::Matrix3d>& rotations) {
  double sum = 0.0;
  for (const Eigen::Matrix3d& r : rotations) sum += dyad.Residual(r) * dyad.Residual(r);
  return std::sqrt(sum / static_cast<double>(rotations.size()));
}

// Noise 1e-3 rad on every orientation. For each generating dyad, the optimum it refines to (the
// least-squares dyad of the noisy data near the truth) is listed, or a dyad that fits better:
// the generating design or a better one (as linkfit bench counts success).
TEST(SphericalRefiner, NoisyOrientationsGiveTheGeneratingDyadsBack) {
  std::mt19937_64 rng(1721);
  constexpr double kNoise = 1e-3;  // radians
  constexpr int kTasks = 25;
  int listed = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 10);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    testing::JitterRotations(rng, kNoise, &rotations);
    const Eigen::Vector3d center_in_moving(-0.5, 0.2, 0.9), center_in_fixed(0.1, -2.0, 1.5);
    const Task task =
        SpatialMotionTask(testing::PosesAboutCenter(rotations, center_in_moving, center_in_fixed));
    const SpatialMotionResult result = SolveSpatialTask(task);
    ASSERT_EQ(result.model, "spherical") << trial;
    EXPECT_EQ(result.method, "least-squares");
    ASSERT_FALSE(result.spherical_dyads.empty()) << trial;
    ASSERT_FALSE(result.spherical_mechanisms.empty()) << trial;
    for (const SphericalDyad* generating : {&four_bar.input, &four_bar.output}) {
      SphericalDyad optimum = *generating;
      RefineSphericalDyad(rotations, {}, {}, &optimum);
      ASSERT_LE(Rms(optimum, rotations), Rms(*generating, rotations)) << trial;
      bool found = false;
      for (const SphericalDyadReport& report : result.spherical_dyads) {
        ASSERT_TRUE(report.rms_residual);
        found = found || SameSphericalDyad(report.dyad, optimum, 1e-6) ||
                Rms(report.dyad, rotations) <= Rms(optimum, rotations);
      }
      EXPECT_TRUE(found) << "trial " << trial << " (seed 1721)";
      listed += found;
    }
  }
  EXPECT_EQ(listed, 2 * kTasks);
}

TEST(SphericalRefiner, ExactOrientationsAreMet) {
  std::mt19937_64 rng(1722);
  for (int trial = 0; trial < 10; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 8);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    testing::JitterRotations(rng, 1e-2, &rotations);
    std::vector<bool> exact(rotations.size(), false);
    exact[3] = true;
    SphericalDyad dyad = four_bar.input;
    const RefinerSummary summary = RefineSphericalDyad(rotations, {}, exact, &dyad);
    EXPECT_LT(std::abs(dyad.Residual(rotations[3])), 1e-9) << trial;
    EXPECT_TRUE(std::isfinite(summary.final_cost));
    // Without the exact flag the fit is the least-squares one, no worse than the seed.
    SphericalDyad free = four_bar.input;
    const RefinerSummary free_summary = RefineSphericalDyad(rotations, {}, {}, &free);
    EXPECT_LE(free_summary.final_cost, free_summary.initial_cost);
    EXPECT_LE(free_summary.final_cost, summary.final_cost * (1.0 + 1e-12));
  }
}

TEST(SphericalRefiner, FastKeepsTheSeeds) {
  std::mt19937_64 rng(1723);
  const std::vector<Eigen::Matrix3d> rotations = testing::RandomSphericalTask(rng, 8).rotations;
  Task task = SpatialMotionTask(
      testing::PosesAboutCenter(rotations, Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 3)));
  task.effort = Effort::kFast;
  const SpatialMotionResult fast = SolveSpatialTask(task);
  ASSERT_EQ(fast.model, "spherical");
  for (const SphericalDyadReport& report : fast.spherical_dyads) {
    EXPECT_FALSE(report.seed_rms_residual);
  }
  task.effort = Effort::kBalanced;
  const SpatialMotionResult balanced = SolveSpatialTask(task);
  for (const SphericalDyadReport& report : balanced.spherical_dyads) {
    EXPECT_TRUE(report.rms_residual);
  }
}

// The best defect-free four-bar's RMS pose error, infinity when there is none.
double BestFourBar(const SpatialMotionResult& result) {
  double best = std::numeric_limits<double>::infinity();
  for (const MechanismReport& mechanism : result.spherical_mechanisms) {
    if (mechanism.rms_pose_error && !HasKinematicDefect(mechanism.defects)) {
      best = std::min(best, *mechanism.rms_pose_error);
    }
  }
  return best;
}

// A higher effort never answers worse: balanced keeps the seed dyads of fast's four-bars that fit
// better than the refined dyads' beside the refined ones (each refined on its own cone residual,
// which alone lost a better four-bar in 12-20 of 24 noisy tasks of linkfit bench), thorough adds
// the search's. Fast lists at most max_dyads seeds and reported_mechanisms four-bars (and the best
// of each group beyond them, RankMechanisms).
TEST(SphericalRefiner, HigherEffortNeverAnswersWorse) {
  std::mt19937_64 rng(1724);
  const TaskSolverOptions options;
  int balanced_better = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const int count = trial % 2 == 0 ? 10 : 20;
    testing::SphericalTask drawn = testing::RandomSphericalTask(rng, count);
    testing::JitterRotations(rng, trial % 3 == 0 ? 1e-2 : 1e-3, &drawn.rotations);
    Task task = SpatialMotionTask(testing::PosesAboutCenter(
        drawn.rotations, Eigen::Vector3d(0.3, 0.2, -0.5), Eigen::Vector3d(1, 2, 3)));
    double best[3];
    int level = 0;
    for (const Effort effort : {Effort::kFast, Effort::kBalanced, Effort::kThorough}) {
      task.effort = effort;
      const SpatialMotionResult result = SolveSpatialTask(task, options);
      ASSERT_EQ(result.model, "spherical") << trial;
      if (effort == Effort::kFast) {
        EXPECT_LE(result.spherical_dyads.size(), static_cast<size_t>(options.max_dyads));
        // RankMechanisms: the bound, and beyond it the best fit of each group (keeping or
        // violating the constraints, three defect levels: six groups).
        EXPECT_LE(result.spherical_mechanisms.size(),
                  static_cast<size_t>(options.reported_mechanisms) + 6);
      }
      best[level++] = BestFourBar(result);
    }
    EXPECT_LE(best[1], best[0] * (1.0 + 1e-9)) << trial;
    EXPECT_LE(best[2], best[1] * (1.0 + 1e-9)) << trial;
    balanced_better += best[1] < best[0] * (1.0 - 1e-6);
  }
  // The refinement does find better four-bars than the seeds' (counted, at least a few).
  EXPECT_GT(balanced_better, 0);
}

}  // namespace
}  // namespace linkfit
