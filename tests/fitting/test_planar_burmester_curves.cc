// Tests of fitting/planar_burmester_curves.h: the dyad of a chosen pivot for three and more
// poses (FewPoses*) and the sampled Burmester curves of four poses (BurmesterCurves*).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <limits>
#include <random>
#include <string>

#include "fitting/planar_burmester_curves.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/rounded_task.h"

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

TEST(FewPosesMovingPivot, FourPosesKeepAFarPivotOnTheCurve) {
  // A small motion of a large four-bar: pivots 50 to a few hundred L from the poses, where the
  // concyclic determinant's rounding floor is above 1e-11 L. The generator's pivots (exact) are
  // on the curves and give its dyads back (a PR pivot was once refused as off the curve).
  const uint64_t seed = 109;
  std::mt19937_64 rng(seed);
  int far = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task =
        RandomTask(rng, DyadType::kRR, trial % 2 ? DyadType::kPR : DyadType::kRR, 4);
    const double length = CharacteristicLength(task.poses);
    for (const PlanarDyad& expected : {task.input, task.output}) {
      if (!((expected.moving_pivot - task.poses[0].ToMoving(task.poses[0].origin_in_fixed)).norm() >
            50.0 * length)) {
        continue;
      }
      ++far;
      PlanarDyad dyad;
      std::string note;
      ASSERT_TRUE(DyadFromMovingPivot(task.poses, expected.moving_pivot, &dyad, &note)) << note;
      EXPECT_EQ(dyad.type, expected.type);
      EXPECT_LE(DyadDistance(dyad, expected, DyadScale(expected, task.poses)), 1e-6);
    }
  }
  EXPECT_GE(far, 10);
  RecordProperty("far_pivots", far);
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

// The second dyad of trial `trial`'s four-bar: RR, PR and RP in turn.
DyadType SecondDyadType(int trial) {
  return trial % 3 == 0 ? DyadType::kRR : trial % 3 == 1 ? DyadType::kPR : DyadType::kRP;
}

TEST(BurmesterCurves, EverySampleSatisfiesAllFourPoses) {
  const uint64_t seed = 201;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, SecondDyadType(trial), 4);
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

// The center-point condition evaluated directly: the determinant of [|q_j|^2, q_j, 1] over the
// positions q_j in E of the fixed pivot at the four poses (zero when they are concyclic).
double CenterPointCondition(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& fixed) {
  Eigen::Matrix4d rows;
  for (int j = 0; j < 4; ++j) {
    const Eigen::Vector2d q = poses[j].ToMoving(fixed);
    rows.row(j) << q.squaredNorm(), q.x(), q.y(), 1.0;
  }
  return rows.determinant();
}

TEST(BurmesterCurves, EveryCurvePointOfALineIsSampled) {
  // No component missed, whatever its size: random lines near the poses are scanned for sign
  // changes of the center-point condition every 0.002 L (an oval crossing a line is found by
  // the scan as two sign changes); every crossing whose dyad lies within the refine radius must
  // be next to a sample. Independent of the parametrization: a determinant and bisection.
  const uint64_t seed = 208;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const BurmesterCurveOptions options;
  int crossings = 0;
  for (int trial = 0; trial < kCurveTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial));
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, SecondDyadType(trial), 4);
    const double length = CharacteristicLength(task.poses);
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const PlanarPose& pose : task.poses) centroid += 0.25 * pose.origin_in_fixed;
    BurmesterCurves curves;
    SampleBurmesterCurves(task.poses, options, &curves);
    const std::vector<PlanarDyad> all = AllSamples(curves);
    for (int line = 0; line < 10; ++line) {
      const Eigen::Vector2d through =
          centroid + 3.0 * length * Eigen::Vector2d(uniform(rng), uniform(rng));
      const double angle = M_PI * uniform(rng);
      const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
      auto condition = [&](double t) {
        return CenterPointCondition(task.poses, through + t * length * direction);
      };
      constexpr double kSpacing = 0.002;
      double previous = condition(-10.0);
      for (double t = -10.0 + kSpacing; t <= 10.0; t += kSpacing) {
        const double value = condition(t);
        if ((previous < 0.0) != (value < 0.0)) {
          double lo = t - kSpacing, hi = t;
          for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            ((condition(lo) < 0.0) == (condition(mid) < 0.0) ? lo : hi) = mid;
          }
          PlanarDyad dyad;
          std::string note;
          if (DyadFromFixedPivot(task.poses, through + 0.5 * (lo + hi) * length * direction, &dyad,
                                 &note) &&
              dyad.type == DyadType::kRR && PivotReach(dyad, task.poses) <= 20.0) {
            ++crossings;
            EXPECT_LE(NearestDyadDistance(all, dyad, length), kDensityTolerance)
                << "crossing at t = " << 0.5 * (lo + hi) << " of line " << line;
          }
        }
        previous = value;
      }
    }
  }
  EXPECT_GE(crossings, 200);
  RecordProperty("crossings", crossings);
}

TEST(BurmesterCurves, RoundedPosesGiveTheirOwnCurve) {
  // Poses printed to 8, 6 and 4 significant digits, read as a user's file: the curve is that of
  // the rounded poses (every sample fits them, and the dyad of each generating moving pivot on
  // them lies on it), and those dyads are near the generator: median relative error within
  // 200 times the printed precision (measured about 40 over 600 dyads at each precision; the
  // tail is the conditioning of small motions, up to 1e4 times it).
  const uint64_t seed = 209;
  std::mt19937_64 rng(seed);
  const BurmesterCurveOptions options;
  for (int digits : {8, 6, 4}) {
    std::vector<double> errors;
    for (int trial = 0; trial < 30; ++trial) {
      SCOPED_TRACE(Trace(seed, trial) + " digits " + std::to_string(digits));
      const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
      const Task rounded = testing::ReadRounded(testing::PlanarMotionText(task.poses, digits));
      const std::vector<PlanarPose>& poses = rounded.planar_poses;
      const double length = CharacteristicLength(poses);
      BurmesterCurves curves;
      EXPECT_GT(SampleBurmesterCurves(poses, options, &curves), 1000);
      const std::vector<PlanarDyad> all = AllSamples(curves);
      for (const PlanarDyad& sample : all) {
        ASSERT_LE(sample.MaxResidual(poses), kResidualTolerance * length);
      }
      for (const PlanarDyad& expected : {task.input, task.output}) {
        PlanarDyad dyad;
        std::string note;
        ASSERT_TRUE(DyadFromMovingPivot(poses, expected.moving_pivot, &dyad, &note)) << note;
        ASSERT_EQ(dyad.type, DyadType::kRR);
        if (PivotReach(dyad, poses) <= options.refine_radius) {
          EXPECT_LE(NearestDyadDistance(all, dyad, length), kDensityTolerance);
        }
        errors.push_back(DyadDistance(dyad, expected, DyadScale(expected, task.poses)));
      }
    }
    std::sort(errors.begin(), errors.end());
    EXPECT_LE(errors[errors.size() / 2], 200.0 * std::pow(10.0, -digits)) << digits << " digits";
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
