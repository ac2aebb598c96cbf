// Five-pose six-bar synthesis on a 3R chain (fitting/six_bar_synthesis.h): random six-bars of
// each layout (tests/support/random_six_bar.h) give five poses; the synthesis returns the
// generating six-bar, once, among every six-bar of that chain (within 1e-7 L), and each six-bar
// it returns reaches the five poses on the chain's elbow.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "fitting/six_bar_synthesis.h"
#include "lib/six_bar.h"
#include "tests/support/random_six_bar.h"

namespace linkfit {
namespace {

double Angle(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// The six-bar's turns at task pose k, from the chain's inverse kinematics (ChainElbows) and its
// RR links' joints placed on their bodies.
SixBarAngles AnglesAt(const SixBar& six_bar, const std::vector<PlanarPose>& poses,
                      const std::vector<Eigen::Vector2d>& elbows, int k) {
  SixBarAngles angles = SixBarAngles::Zero();
  const Eigen::Vector2d wrist = poses[k].ToFixed(six_bar.reference_pose.ToMoving(six_bar.wrist));
  angles[0] = Angle(elbows[k] - six_bar.ground_pivot) - Angle(six_bar.elbow - six_bar.ground_pivot);
  angles[1] = Angle(wrist - elbows[k]) - Angle(six_bar.wrist - six_bar.elbow);
  angles[2] = poses[k].theta - poses[0].theta;
  for (int l = 0; l < 2; ++l) {
    const SixBarRRLink& link = six_bar.links[l];
    const Eigen::Vector2d from =
        SixBarBodyDisplacement(six_bar, angles, link.from_body).ToFixed(link.from_joint);
    const Eigen::Vector2d to =
        SixBarBodyDisplacement(six_bar, angles, link.to_body).ToFixed(link.to_joint);
    angles[3 + l] = Angle(to - from) - Angle(link.to_joint - link.from_joint);
  }
  return angles;
}

bool SameSixBar(const SixBar& a, const SixBar& b, double tolerance) {
  if (a.topology != b.topology) return false;
  for (int l = 0; l < 2; ++l) {
    if (a.links[l].from_body != b.links[l].from_body || a.links[l].to_body != b.links[l].to_body ||
        (a.links[l].from_joint - b.links[l].from_joint).norm() > tolerance ||
        (a.links[l].to_joint - b.links[l].to_joint).norm() > tolerance) {
      return false;
    }
  }
  return true;
}

TEST(SixBarSynthesis, EveryLayoutGivesItsGeneratorBack) {
  std::mt19937_64 rng(3601);
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    for (int trial = 0; trial < 20; ++trial) {
      const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, layout);
      SCOPED_TRACE(std::string(SixBarTopologyName(layout.topology)) + " link 1 from body " +
                   std::to_string(layout.from1) + ", trial " + std::to_string(trial));
      std::vector<SixBar> six_bars;
      SixBarSynthesisSummary summary;
      SynthesizeSixBars(task.poses, task.chain, {}, &six_bars, &summary);
      EXPECT_EQ(summary.unreachable_pose, -1);
      // The chain's own links are roots of ground-forearm and upper link-task body.
      EXPECT_GE(summary.roots_trivial, 2);
      EXPECT_EQ(summary.roots_total, 4 * summary.burmester_problems);
      int found = 0;
      for (const SixBar& six_bar : six_bars) found += SameSixBar(six_bar, task.six_bar, 1e-7);
      double nearest = 1e300;
      for (const SixBar& six_bar : six_bars) {
        if (six_bar.topology != task.six_bar.topology ||
            six_bar.links[1].from_body != task.six_bar.links[1].from_body) {
          continue;
        }
        double apart = 0.0;
        for (int l = 0; l < 2; ++l) {
          apart = std::max({apart,
                            (six_bar.links[l].from_joint - task.six_bar.links[l].from_joint).norm(),
                            (six_bar.links[l].to_joint - task.six_bar.links[l].to_joint).norm()});
        }
        nearest = std::min(nearest, apart);
      }
      EXPECT_EQ(found, 1) << six_bars.size() << " six-bars, nearest " << nearest;
      // Every six-bar returned reaches the five poses on the chain's elbow.
      std::vector<Eigen::Vector2d> elbows;
      int unreachable = -1;
      ASSERT_TRUE(ChainElbows(task.poses, task.chain, &elbows, &unreachable));
      for (const SixBar& six_bar : six_bars) {
        for (int k = 0; k < 5; ++k) {
          const SixBarAngles angles = AnglesAt(six_bar, task.poses, elbows, k);
          EXPECT_LT(SixBarClosure(six_bar, angles).norm(), 1e-8) << "pose " << k;
          EXPECT_LT(PoseError(SixBarTaskPose(six_bar, angles), task.poses[k], 1.0), 1e-9);
        }
      }
    }
  }
}

TEST(SixBarSynthesis, APoseOutOfTheChainsReachIsNamed) {
  std::mt19937_64 rng(3602);
  testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, testing::SixBarLayouts()[0]);
  // The third pose moved far away: its wrist beyond the two links.
  task.poses[2].origin_in_fixed += Eigen::Vector2d(50.0, 0.0);
  std::vector<SixBar> six_bars;
  SixBarSynthesisSummary summary;
  EXPECT_EQ(SynthesizeSixBars(task.poses, task.chain, {}, &six_bars, &summary), 0);
  EXPECT_EQ(summary.unreachable_pose, 2);
}

}  // namespace
}  // namespace linkfit
