// Tests of fitting/planar_burmester_curves.h: the dyad of a chosen pivot for three and more
// poses (FewPoses*) and the sampled Burmester curves of four poses (BurmesterCurves*).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <random>
#include <string>

#include "fitting/planar_burmester_curves.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

using testing::DyadDistance;
using testing::DyadScale;
using testing::GeneratedTask;
using testing::NearestDyadDistance;
using testing::RandomTask;

// Relative error of a dyad recovered from its own pivot (DyadDistance over DyadScale).
constexpr double kRecoveryTolerance = 1e-9;
// Largest residual of any returned dyad at any pose, relative to L.
constexpr double kResidualTolerance = 1e-9;
// The sampled curve must pass this close (relative to L, DyadDistance) to every dyad of the
// task: the sampling density.
constexpr double kDensityTolerance = 2e-2;
constexpr int kPivotTrials = 100;
constexpr int kCurveTrials = 40;

std::string Trace(uint64_t seed, int trial) {
  return "seed " + std::to_string(seed) + " trial " + std::to_string(trial);
}

// ---------------------------------------------------------------------------------------------
// Dyads of chosen pivots.

TEST(FewPosesMovingPivot, ThreePosesGiveTheGeneratingDyads) {
  const uint64_t seed = 101;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 3);
    const double length = CharacteristicLength(task.poses);
    for (const PlanarDyad& expected : {task.input, task.output}) {
      PlanarDyad dyad;
      std::string note = "stale";
      ASSERT_TRUE(DyadFromMovingPivot(task.poses, expected.moving_pivot, &dyad, &note));
      EXPECT_TRUE(note.empty()) << note;
      EXPECT_EQ(dyad.type, DyadType::kRR);
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), kRecoveryTolerance);
      EXPECT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * length);
    }
  }
}

TEST(FewPosesMovingPivot, CollinearPositionsGiveASlider) {
  // The moving pivot of a slider-crank's PR dyad has three collinear positions.
  const uint64_t seed = 102;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kPR, 3);
    PlanarDyad dyad;
    std::string note;
    ASSERT_TRUE(DyadFromMovingPivot(task.poses, task.output.moving_pivot, &dyad, &note));
    EXPECT_EQ(dyad.type, DyadType::kPR);
    EXPECT_FALSE(note.empty());
    EXPECT_LE(DyadDistance(dyad, task.output, DyadScale(task.output, task.poses)),
              kRecoveryTolerance);
  }
}

TEST(FewPosesFixedPivot, ThreePosesGiveTheGeneratingDyads) {
  const uint64_t seed = 103;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 3);
    for (const PlanarDyad& expected : {task.input, task.output}) {
      PlanarDyad dyad;
      std::string note;
      ASSERT_TRUE(DyadFromFixedPivot(task.poses, expected.fixed_pivot, &dyad, &note));
      EXPECT_TRUE(note.empty()) << note;
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), kRecoveryTolerance);
    }
  }
}

TEST(FewPosesFixedPivot, CollinearPositionsInTheBodyGiveRP) {
  const uint64_t seed = 104;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRP, 3);
    PlanarDyad dyad;
    std::string note;
    ASSERT_TRUE(DyadFromFixedPivot(task.poses, task.output.fixed_pivot, &dyad, &note));
    EXPECT_EQ(dyad.type, DyadType::kRP);
    EXPECT_FALSE(note.empty());
    EXPECT_LE(DyadDistance(dyad, task.output, DyadScale(task.output, task.poses)),
              kRecoveryTolerance);
  }
}

TEST(FewPosesMovingPivot, FourPosesKeepAPivotOnTheCirclePointCurve) {
  const uint64_t seed = 105;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    for (const PlanarDyad& expected : {task.input, task.output}) {
      PlanarDyad dyad;
      std::string note;
      ASSERT_TRUE(DyadFromMovingPivot(task.poses, expected.moving_pivot, &dyad, &note));
      EXPECT_TRUE(note.empty()) << note;
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), kRecoveryTolerance);
      ASSERT_TRUE(DyadFromFixedPivot(task.poses, expected.fixed_pivot, &dyad, &note));
      EXPECT_TRUE(note.empty()) << note;
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), kRecoveryTolerance);
    }
  }
}

TEST(FewPosesMovingPivot, FourPosesMoveAPivotOntoTheCirclePointCurve) {
  // A pivot off the curve is moved onto it (by at most its distance from a known curve point)
  // and then gives an exact dyad of all four poses.
  const uint64_t seed = 106;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    const double length = CharacteristicLength(task.poses);
    const Eigen::Vector2d shift = length * Eigen::Vector2d(offset(rng), offset(rng));
    PlanarDyad dyad;
    std::string note;
    ASSERT_TRUE(DyadFromMovingPivot(task.poses, task.input.moving_pivot + shift, &dyad, &note));
    EXPECT_NE(note.find("circle-point curve"), std::string::npos) << note;
    EXPECT_LE((dyad.moving_pivot - task.input.moving_pivot - shift).norm(),
              shift.norm() * (1.0 + 1e-9));
    EXPECT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * DyadScale(dyad, task.poses));
    ASSERT_TRUE(DyadFromFixedPivot(task.poses, task.input.fixed_pivot + shift, &dyad, &note));
    EXPECT_NE(note.find("center-point curve"), std::string::npos) << note;
    EXPECT_LE((dyad.fixed_pivot - task.input.fixed_pivot - shift).norm(),
              shift.norm() * (1.0 + 1e-9));
    EXPECT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * DyadScale(dyad, task.poses));
  }
}

TEST(FewPosesMovingPivot, MorePosesFitTheCircle) {
  // Exact data: the generating dyad back; noisy data: a circle close to it.
  const uint64_t seed = 107;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1e-4);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 7);
    const double length = CharacteristicLength(task.poses);
    PlanarDyad dyad;
    std::string note;
    ASSERT_TRUE(DyadFromMovingPivot(task.poses, task.output.moving_pivot, &dyad, &note));
    EXPECT_LE(DyadDistance(dyad, task.output, DyadScale(task.output, task.poses)),
              kRecoveryTolerance);
    std::vector<PlanarPose> noisy = task.poses;
    for (PlanarPose& pose : noisy) {
      pose.origin_in_fixed += length * Eigen::Vector2d(noise(rng), noise(rng));
    }
    ASSERT_TRUE(DyadFromMovingPivot(noisy, task.output.moving_pivot, &dyad, &note));
    EXPECT_LE(dyad.MaxResidual(noisy), 1e-3 * length);
  }
}

TEST(FewPosesMovingPivot, TooFewPosesOrCoincidentPositionsFail) {
  std::vector<PlanarPose> poses = {PlanarPose(0.0, 0.0, 0.0), PlanarPose(1.0, 0.0, 0.5)};
  PlanarDyad dyad;
  std::string note;
  EXPECT_FALSE(DyadFromMovingPivot(poses, Eigen::Vector2d(0.3, 0.2), &dyad, &note));
  EXPECT_FALSE(note.empty());
  // Poses 0 and 1 turn about the point (0, 0) of Sigma, which is E's origin at pose 0: that
  // pivot's first two positions coincide.
  poses = {PlanarPose(0.0, 0.0, 0.0), PlanarPose(0.0, 0.0, 0.7), PlanarPose(1.0, 0.5, 1.2)};
  EXPECT_FALSE(DyadFromMovingPivot(poses, Eigen::Vector2d::Zero(), &dyad, &note));
  EXPECT_FALSE(note.empty());
}

TEST(FewPosesDefaultPivots, GiveValidDyadsAndSayWhy) {
  const uint64_t seed = 108;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kPivotTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 3);
    const double length = CharacteristicLength(task.poses);
    Eigen::Vector2d pivots[2];
    std::string explanation;
    DefaultMovingPivots(task.poses, pivots, &explanation);
    EXPECT_FALSE(explanation.empty());
    EXPECT_EQ(explanation.find('\n'), std::string::npos);
    EXPECT_GE((pivots[0] - pivots[1]).norm(), length * (1.0 - 1e-12));
    for (const Eigen::Vector2d& pivot : pivots) {
      PlanarDyad dyad;
      std::string note;
      ASSERT_TRUE(DyadFromMovingPivot(task.poses, pivot, &dyad, &note));
      EXPECT_EQ(dyad.type, DyadType::kRR);
      EXPECT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * length);
      // Something a designer builds: a crank within a few L, or no longer than the cranks of
      // the mechanism that made the task (a small motion of a large mechanism has a small L).
      EXPECT_LE(dyad.radius, std::max({10.0 * length, task.input.radius, task.output.radius}));
    }
    // Deterministic.
    Eigen::Vector2d again[2];
    std::string explanation_again;
    DefaultMovingPivots(task.poses, again, &explanation_again);
    EXPECT_EQ(pivots[0], again[0]);
    EXPECT_EQ(pivots[1], again[1]);
    EXPECT_EQ(explanation, explanation_again);
  }
}

// ---------------------------------------------------------------------------------------------
// Sampled curves.

std::vector<PlanarDyad> AllSamples(const BurmesterCurves& curves) {
  std::vector<PlanarDyad> all;
  for (const auto& branch : curves.branches) all.insert(all.end(), branch.begin(), branch.end());
  return all;
}

TEST(BurmesterCurves, EverySampleSatisfiesAllFourPoses) {
  const uint64_t seed = 201;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const DyadType second = trial % 3 == 0   ? DyadType::kRR
                            : trial % 3 == 1 ? DyadType::kPR
                                             : DyadType::kRP;
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, second, 4);
    const double length = CharacteristicLength(task.poses);
    BurmesterCurves curves;
    const int count = SampleBurmesterCurves(task.poses, BurmesterCurveOptions(), &curves);
    EXPECT_GT(count, 1000);
    int listed = 0;
    for (const PlanarDyad& dyad : AllSamples(curves)) {
      ++listed;
      ASSERT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * length)
          << DyadTypeName(dyad.type);
    }
    EXPECT_GE(listed, count);  // closed branches repeat their first sample
  }
}

// How far a dyad's pivots are from the pose-origin centroid (the moving pivot at the first
// pose), relative to L: the curve is sampled densely within BurmesterCurveOptions::refine_radius.
double PivotReach(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed / poses.size();
  return std::max((dyad.fixed_pivot - centroid).norm(),
                  (poses[0].ToFixed(dyad.moving_pivot) - centroid).norm()) /
         CharacteristicLength(poses);
}

TEST(BurmesterCurves, GeneratingDyadsLieOnTheCurve) {
  const uint64_t seed = 202;
  std::mt19937_64 rng(seed);
  const BurmesterCurveOptions options;
  int checked = 0, total = 0;
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    const double length = CharacteristicLength(task.poses);
    BurmesterCurves curves;
    SampleBurmesterCurves(task.poses, options, &curves);
    const std::vector<PlanarDyad> all = AllSamples(curves);
    for (const PlanarDyad& expected : {task.input, task.output}) {
      ++total;
      // Beyond the refine radius (a large mechanism making a small motion) the curve is only
      // sketched; about 1 in 100 random generating dyads lies there.
      if (PivotReach(expected, task.poses) <= options.refine_radius) {
        ++checked;
        EXPECT_LE(NearestDyadDistance(all, expected, length), kDensityTolerance);
      }
      PlanarDyad dyad;
      std::string note;
      ASSERT_TRUE(DyadFromMovingPivot(task.poses, expected.moving_pivot, &dyad, &note));
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), kRecoveryTolerance);
    }
  }
  EXPECT_GE(checked, 0.9 * total);
  RecordProperty("density_checked", checked);
  RecordProperty("density_total", total);
}

TEST(BurmesterCurves, BranchesAreContinuous) {
  const uint64_t seed = 203;
  std::mt19937_64 rng(seed);
  const BurmesterCurveOptions options;
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    const double length = CharacteristicLength(task.poses);
    BurmesterCurves curves;
    SampleBurmesterCurves(task.poses, options, &curves);
    for (const auto& branch : curves.branches) {
      for (size_t i = 1; i < branch.size(); ++i) {
        ASSERT_EQ(branch[i].type, branch[i - 1].type);
        // Pivots of consecutive samples within the break distance (the linking key is the
        // pair of pivots, fixed in Sigma and moving in E).
        EXPECT_LE((branch[i].fixed_pivot - branch[i - 1].fixed_pivot).norm(),
                  options.break_distance * length * (1.0 + 1e-9));
        EXPECT_LE((branch[i].moving_pivot - branch[i - 1].moving_pivot).norm(),
                  options.break_distance * length * (1.0 + 1e-9));
      }
    }
  }
}

TEST(BurmesterCurves, SliderCrankHasItsSliderOnTheCurve) {
  const uint64_t seed = 204;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kPR, 4);
    const double length = CharacteristicLength(task.poses);
    BurmesterCurves curves;
    SampleBurmesterCurves(task.poses, BurmesterCurveOptions(), &curves);
    const std::vector<PlanarDyad> all = AllSamples(curves);
    // The pencil contains the slider plane z0 = 0, so the PR dyad is sampled exactly.
    EXPECT_LE(NearestDyadDistance(all, task.output, DyadScale(task.output, task.poses)), 1e-6);
    if (PivotReach(task.input, task.poses) <= BurmesterCurveOptions().refine_radius) {
      EXPECT_LE(NearestDyadDistance(all, task.input, length), kDensityTolerance);
    }
  }
}

TEST(BurmesterCurves, InvariantToUnitsAndPlacement) {
  // The same curve in other units, with the fixed and moving frames moved: still exact dyads,
  // still through the (transformed) generating dyads.
  const uint64_t seed = 207;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    for (double scale : {1e-3, 1e3}) {
      Similarity2 sigma, epsilon;
      sigma.scale = epsilon.scale = scale;
      sigma.angle = M_PI * uniform(rng);
      sigma.translation = scale * Eigen::Vector2d(5.0 * uniform(rng), 5.0 * uniform(rng));
      epsilon.angle = M_PI * uniform(rng);
      epsilon.translation = scale * Eigen::Vector2d(uniform(rng), uniform(rng));
      std::vector<PlanarPose> moved;
      for (const PlanarPose& pose : task.poses)
        moved.push_back(TransformPose(pose, sigma, epsilon));
      const double length = CharacteristicLength(moved);
      BurmesterCurves curves;
      EXPECT_GT(SampleBurmesterCurves(moved, BurmesterCurveOptions(), &curves), 1000);
      const std::vector<PlanarDyad> all = AllSamples(curves);
      for (const PlanarDyad& dyad : all) {
        ASSERT_LE(dyad.MaxResidual(moved), kResidualTolerance * length);
      }
      for (const PlanarDyad& generating : {task.input, task.output}) {
        const PlanarDyad expected = TransformDyad(generating, sigma, epsilon);
        if (PivotReach(expected, moved) <= BurmesterCurveOptions().refine_radius) {
          EXPECT_LE(NearestDyadDistance(all, expected, length), kDensityTolerance)
              << "scale " << scale;
        }
      }
    }
  }
}

TEST(BurmesterCurves, OtherPoseCountsGiveNothing) {
  std::mt19937_64 rng(205);
  for (int count : {3, 5}) {
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, count);
    BurmesterCurves curves;
    curves.branches.resize(2);
    EXPECT_EQ(SampleBurmesterCurves(task.poses, BurmesterCurveOptions(), &curves), 0);
    EXPECT_TRUE(curves.branches.empty());
  }
}

TEST(BurmesterCurves, SamplingIsFast) {
  std::mt19937_64 rng(206);
  std::vector<double> seconds;
  for (int trial = 0; trial < 20; ++trial) {
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
    BurmesterCurves curves;
    const auto start = std::chrono::steady_clock::now();
    SampleBurmesterCurves(task.poses, BurmesterCurveOptions(), &curves);
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  RecordProperty("median_ms", std::to_string(1e3 * seconds[seconds.size() / 2]));
  RecordProperty("worst_ms", std::to_string(1e3 * seconds.back()));
  // Generous against loaded machines and unoptimized builds; Release takes a few ms.
  EXPECT_LT(seconds[seconds.size() / 2], 0.5);
}

}  // namespace
}  // namespace linkfit
