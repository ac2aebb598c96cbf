// Five-pose six-bar synthesis on a 3R chain (fitting/six_bar_synthesis.h): random six-bars of
// each layout (tests/support/random_six_bar.h) give five poses; the synthesis returns the
// generating six-bar, once, among every six-bar of that chain (within 1e-7 L), and each six-bar
// it returns reaches the five poses on the chain's elbow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>

#include "fitting/six_bar_chains.h"
#include "fitting/six_bar_synthesis.h"
#include "lib/six_bar.h"
#include "tests/support/random_six_bar.h"

namespace linkfit {
namespace {

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
        const std::vector<SixBarAngles> at_poses = SixBarAnglesAtPoses(six_bar, task.poses, elbows);
        for (int k = 0; k < 5; ++k) {
          EXPECT_LT(SixBarClosure(six_bar, at_poses[k]).norm(), 1e-8) << "pose " << k;
          EXPECT_LT(PoseError(SixBarTaskPose(six_bar, at_poses[k]), task.poses[k], 1.0), 1e-9);
        }
        // The generator, driven by its upper link as it was made, has no defect.
        if (SameSixBar(six_bar, task.six_bar, 1e-7)) {
          const SixBarAnalysis analysis = AnalyzeSixBar(six_bar, at_poses, kSixBarUpperLink, 1.0);
          EXPECT_TRUE(analysis.defects.empty()) << analysis.defects.front();
          for (int k = 0; k < 5; ++k) {
            EXPECT_NEAR(analysis.input_angles[k],
                        task.configurations[k][0] - task.configurations[0][0], 1e-9);
          }
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

// Defects by continuation along the upper link (lib/six_bar.h AnalyzeSixBar): the poses in
// another order are an order defect; a last pose in the other assembly of the first loop (the
// forearm's joint with the first RR link reflected across the line from the elbow to that link's
// ground pivot, the second loop closed by Newton's method) is reached on another circuit.
TEST(SixBarAnalysis, PosesOutOfOrderAndAnotherAssemblyAreDefects) {
  std::mt19937_64 rng(3603);
  int circuits = 0;
  for (int trial = 0; trial < 10; ++trial) {
    // Watt I: the first RR link joins ground and the forearm.
    const testing::GeneratedSixBarTask task =
        testing::RandomSixBarTask(rng, testing::SixBarLayouts()[0]);
    const SixBar& six_bar = task.six_bar;
    std::vector<SixBarAngles> swapped = task.configurations;
    std::swap(swapped[2], swapped[3]);
    EXPECT_EQ(AnalyzeSixBar(six_bar, swapped, kSixBarUpperLink, 1.0).defects,
              std::vector<std::string>{"order"});
    std::vector<SixBarAngles> other = task.configurations;
    SixBarAngles start = other[4];
    const SixBarRRLink& link = six_bar.links[0];
    const Eigen::Vector2d elbow =
        SixBarBodyDisplacement(six_bar, start, kSixBarUpperLink).ToFixed(six_bar.elbow);
    const Eigen::Vector2d joint =
        SixBarBodyDisplacement(six_bar, start, kSixBarForearm).ToFixed(link.to_joint);
    const Eigen::Vector2d axis = (link.from_joint - elbow).normalized();
    const Eigen::Vector2d reflected =
        elbow + 2.0 * (joint - elbow).dot(axis) * axis - (joint - elbow);
    const auto angle = [](const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); };
    start[1] = angle(reflected - elbow) - angle(link.to_joint - six_bar.elbow);
    start[3] = angle(reflected - link.from_joint) - angle(link.to_joint - link.from_joint);
    if (!AssembleSixBar(six_bar, kSixBarUpperLink, other[4][0], &start, 1e-12)) continue;
    if (!(std::abs(std::remainder(start[1] - other[4][1], 2.0 * M_PI)) > 1e-3)) continue;
    other[4] = start;
    const SixBarAnalysis analysis = AnalyzeSixBar(six_bar, other, kSixBarUpperLink, 1.0);
    EXPECT_NE(std::find(analysis.defects.begin(), analysis.defects.end(), "circuit"),
              analysis.defects.end());
    ++circuits;
  }
  EXPECT_GE(circuits, 5);
}

// A six-bar that comes twice (within the tolerance: a double root) is listed once, its error
// bounds kept alongside; one a little further apart is another six-bar.
TEST(SixBarSynthesis, ASixBarThatComesTwiceIsListedOnce) {
  std::mt19937_64 rng(3606);
  const testing::GeneratedSixBarTask task =
      testing::RandomSixBarTask(rng, testing::SixBarLayouts()[0]);
  std::vector<SixBar> six_bars;
  std::vector<std::array<double, 2>> bounds;
  SynthesizeSixBars(task.poses, task.chain, {}, &six_bars, nullptr, &bounds);
  ASSERT_GE(six_bars.size(), 2u);
  const size_t count = six_bars.size();
  const double tolerance = 1e-6;
  SixBar again = six_bars[0], apart = six_bars[1];
  again.links[1].to_joint += Eigen::Vector2d(0.5 * tolerance, 0.0);
  apart.links[0].from_joint += Eigen::Vector2d(0.0, 2.0 * tolerance);
  six_bars.push_back(again);
  bounds.push_back({-1.0, -1.0});
  six_bars.push_back(apart);
  bounds.push_back({-2.0, -2.0});
  EXPECT_EQ(RemoveRepeatedSixBars(tolerance, &six_bars, &bounds), 1);
  ASSERT_EQ(six_bars.size(), count + 1);
  ASSERT_EQ(bounds.size(), count + 1);
  EXPECT_EQ(bounds.back()[0], -2.0);
  EXPECT_EQ((six_bars.back().links[0].from_joint - apart.links[0].from_joint).norm(), 0.0);
  // The synthesis itself lists none twice.
  std::vector<SixBar> synthesized(six_bars.begin(), six_bars.begin() + count);
  EXPECT_EQ(RemoveRepeatedSixBars(tolerance, &synthesized), 0);
}

// Every six-bar of three random tasks of each layout (tests/support/random_six_bar.h), under each
// of its grounded inputs, with its turns at the task's poses: `judge(six_bar, at_poses, input)`.
void ForEachGroundedInput(
    uint64_t seed,
    const std::function<void(const SixBar&, const std::vector<SixBarAngles>&, int)>& judge) {
  std::mt19937_64 rng(seed);
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    for (int trial = 0; trial < 3; ++trial) {
      const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, layout);
      std::vector<SixBar> six_bars;
      SynthesizeSixBars(task.poses, task.chain, {}, &six_bars);
      std::vector<Eigen::Vector2d> elbows;
      int unreachable = -1;
      ASSERT_TRUE(ChainElbows(task.poses, task.chain, &elbows, &unreachable));
      for (const SixBar& six_bar : six_bars) {
        const std::vector<SixBarAngles> at_poses = SixBarAnglesAtPoses(six_bar, task.poses, elbows);
        for (const int input : {kSixBarUpperLink, kSixBarFirstLink, kSixBarSecondLink}) {
          if (SixBarGroundedLink(six_bar, input)) judge(six_bar, at_poses, input);
        }
      }
    }
  }
}

// Two analyses of one six-bar judge it alike: the same defects and whole turn, and where it is
// driven through the poses on one assembly (where a circuit defect restarts it, the angles depend
// on the path) the least transmission angles within 0.1 degrees; *worst keeps the largest gap.
void ExpectSameJudgement(const SixBarAnalysis& a, const SixBarAnalysis& b, double* worst) {
  EXPECT_EQ(a.defects, b.defects);
  EXPECT_EQ(a.input_rotates_fully, b.input_rotates_fully);
  for (int l = 0; l < 2 && b.defects.empty(); ++l) {
    *worst = std::max(*worst, std::abs(a.transmission_min_deg[l] - b.transmission_min_deg[l]));
    EXPECT_NEAR(a.transmission_min_deg[l], b.transmission_min_deg[l], 0.1);
  }
}

// The analysis's four-degree continuation steps (kSixBarDriveStep) against half-degree ones, on
// every six-bar of random tasks of each layout and each of its grounded inputs: the same defects
// and whole turns, and without defects the least transmission angles within 0.1 degrees (measured:
// 0.025; against the former acceptance rule at steps of 0.025 degrees, the same defects too).
TEST(SixBarAnalysis, FourDegreeStepsJudgeAsHalfDegreeSteps) {
  const double half_degree = 0.5 * M_PI / 180.0;
  int analyses = 0, defective = 0, whole_turns = 0;
  double worst = 0.0;
  ForEachGroundedInput(
      3604, [&](const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses, int input) {
        const SixBarAnalysis coarse = AnalyzeSixBar(six_bar, at_poses, input, 1.0);
        const SixBarAnalysis fine = AnalyzeSixBar(six_bar, at_poses, input, 1.0, half_degree);
        ExpectSameJudgement(coarse, fine, &worst);
        ++analyses;
        defective += !fine.defects.empty();
        whole_turns += fine.input_rotates_fully;
      });
  // Both kinds are among them.
  EXPECT_GT(defective, analyses / 10);
  EXPECT_GT(whole_turns, 0);
  std::cout << analyses << " analyses, " << defective << " with defects, " << whole_turns
            << " whole turns; transmission angles apart by at most " << worst << " degrees\n";
}

// Positions in closed form (lib/six_bar.h SixBarDriver: two dyads placed one after the other)
// against continuation, on every six-bar of random tasks of each layout and each grounded input:
// at each pose the closed form places the pose's own configuration from its assembly; the
// analyses give the same defects and whole turns, and without defects the least transmission
// angles within 0.1 degrees. The topologies the closed form takes: Watt I under every input,
// Stephenson I and II under the upper and first links, never Stephenson III (a triad).
TEST(SixBarAnalysis, ClosedFormJudgesAsContinuation) {
  int analyses = 0, closed = 0, defective = 0, whole_turns = 0;
  double worst_angle = 0.0, worst_place = 0.0;
  ForEachGroundedInput(
      3605, [&](const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses, int input) {
        const SixBarDriver driver(six_bar, input, 1.0);
        const bool triad =
            six_bar.topology == SixBarTopology::kStephensonIII ||
            (six_bar.topology == SixBarTopology::kStephensonII && input == kSixBarSecondLink);
        EXPECT_EQ(driver.closed_form(), !triad)
            << SixBarTopologyName(six_bar.topology) << " under body " << input;
        closed += driver.closed_form();
        for (const SixBarAngles& at_pose : at_poses) {
          if (!driver.closed_form()) break;
          SixBarAssembly assembly;
          ASSERT_TRUE(driver.AssemblyOf(at_pose, &assembly));
          SixBarAngles placed = SixBarAngles::Zero();
          ASSERT_TRUE(driver.Place(assembly, at_pose[input - 1], &placed));
          for (int j = 0; j < 5; ++j) {
            worst_place =
                std::max(worst_place, std::abs(std::remainder(placed[j] - at_pose[j], 2.0 * M_PI)));
          }
          EXPECT_LT(SixBarClosure(six_bar, placed).norm(), 1e-12);
        }
        const SixBarAnalysis closed_form = AnalyzeSixBar(six_bar, at_poses, input, 1.0);
        const SixBarAnalysis continuation =
            AnalyzeSixBar(six_bar, at_poses, input, 1.0, kSixBarDriveStep, true, true,
                          SixBarPositions::kContinuation);
        ExpectSameJudgement(closed_form, continuation, &worst_angle);
        ++analyses;
        defective += !continuation.defects.empty();
        whole_turns += continuation.input_rotates_fully;
      });
  EXPECT_LT(worst_place, 1e-9);
  EXPECT_GT(closed, analyses / 3);
  EXPECT_GT(defective, analyses / 10);
  EXPECT_GT(whole_turns, 0);
  std::cout << analyses << " analyses, " << closed << " in closed form, " << defective
            << " with defects, " << whole_turns << " whole turns; transmission angles apart by at "
            << "most " << worst_angle << " degrees; poses placed within " << worst_place
            << " radians\n";
}

// The chain search (fitting/six_bar_chains.h): every candidate reaches every pose on its elbow with
// elbow angles and joint travels within the options, recomputed here from its joints; candidates
// come best first, none near an earlier one; a tighter elbow-angle bound only removes candidates,
// and a fixed-pivot box keeps every ground pivot inside it.
TEST(SixBarChains, CandidatesKeepTheirBoundsAndComeBestFirst) {
  std::mt19937_64 rng(3661);
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    const testing::GeneratedSixBarTask generated = testing::RandomSixBarTask(rng, layout);
    const double length = CharacteristicLength(generated.poses);
    SixBarChainSearchOptions options;
    options.max_candidates = 1000;
    const std::vector<SixBarChainCandidate> candidates =
        SixBarChainCandidates(generated.poses, DesignConstraints(), length, options);
    ASSERT_GT(candidates.size(), 10u);
    for (size_t i = 0; i < candidates.size(); ++i) {
      const SixBarChainCandidate& candidate = candidates[i];
      const SixBarChain& chain = candidate.chain;
      std::vector<Eigen::Vector2d> elbows;
      int unreachable = -1;
      ASSERT_TRUE(ChainElbows(generated.poses, chain, &elbows, &unreachable));
      double least = 180.0, low = 0.0, high = 0.0, first = 0.0;
      for (size_t k = 0; k < elbows.size(); ++k) {
        const Eigen::Vector2d wrist = generated.poses[k].ToFixed(chain.wrist_in_moving);
        const Eigen::Vector2d u = chain.ground_pivot - elbows[k], v = wrist - elbows[k];
        const double beta = std::acos(u.dot(v) / (u.norm() * v.norm())) * 180.0 / M_PI;
        least = std::min({least, beta, 180.0 - beta});
        const Eigen::Vector2d upper = elbows[k] - chain.ground_pivot;
        const double turn = std::atan2(upper.y(), upper.x()) * 180.0 / M_PI;
        if (k == 0) first = turn;
        const double from_first = std::remainder(turn - first, 360.0);
        low = std::min(low, from_first);
        high = std::max(high, from_first);
      }
      EXPECT_NEAR(least, candidate.min_elbow_angle_deg, 1e-9);
      EXPECT_GE(least, options.min_elbow_angle_deg);
      EXPECT_LE(high - low, options.max_joint_travel_deg + 1e-9);
      EXPECT_LE(candidate.score, candidate.min_elbow_angle_deg);
      if (i > 0) {
        EXPECT_LE(candidate.score, candidates[i - 1].score);
      }
      for (size_t j = 0; j < i; ++j) {
        const SixBarChain& before = candidates[j].chain;
        EXPECT_FALSE(before.elbow_left == chain.elbow_left &&
                     (before.ground_pivot - chain.ground_pivot).norm() < options.apart * length &&
                     (before.wrist_in_moving - chain.wrist_in_moving).norm() <
                         options.apart * length);
      }
    }
    SixBarChainSearchOptions tighter = options;
    tighter.min_elbow_angle_deg = 40.0;
    const std::vector<SixBarChainCandidate> fewer =
        SixBarChainCandidates(generated.poses, DesignConstraints(), length, tighter);
    EXPECT_LT(fewer.size(), candidates.size());
    for (const SixBarChainCandidate& candidate : fewer) {
      EXPECT_GE(candidate.min_elbow_angle_deg, 40.0);
    }
    DesignConstraints boxed;
    boxed.fixed_pivots_box = PlanarBox{candidates[0].chain.ground_pivot - Eigen::Vector2d(1, 1),
                                       candidates[0].chain.ground_pivot};
    const std::vector<SixBarChainCandidate> inside =
        SixBarChainCandidates(generated.poses, boxed, length, options);
    ASSERT_FALSE(inside.empty());
    for (const SixBarChainCandidate& candidate : inside) {
      EXPECT_TRUE(
          (candidate.chain.ground_pivot.array() <= boxed.fixed_pivots_box->max.array() + 1e-12)
              .all() &&
          (candidate.chain.ground_pivot.array() >= boxed.fixed_pivots_box->min.array() - 1e-12)
              .all());
    }
  }
}

}  // namespace
}  // namespace linkfit
