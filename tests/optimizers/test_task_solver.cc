#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "lib/path_motion.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spatial.h"

namespace linkfit {
namespace {

// A path task of `count` points of a random crank-driven four-bar, with noise sigma * L on the
// points; without input angles when `free_timing`.
Task PathTask(const testing::GeneratedPathTask& generated, double sigma, bool free_timing,
              std::mt19937_64& rng, std::vector<Eigen::Vector2d>* noisy) {
  Task task;
  task.problem = ProblemKind::kPath;
  const double length = testing::PathLength(generated.points);
  std::normal_distribution<double> normal;
  noisy->clear();
  for (size_t j = 0; j < generated.points.size(); ++j) {
    TimedPoint point;
    point.point_in_fixed =
        generated.points[j] + sigma * length * Eigen::Vector2d(normal(rng), normal(rng));
    if (!free_timing) point.input_angle = generated.input_angles[j];
    noisy->push_back(point.point_in_fixed);
    task.points.push_back(point);
  }
  return task;
}

// The best RMS (or largest) point error of a defect-free listed four-bar.
double BestError(const PathResult& result, bool rms) {
  double best = std::numeric_limits<double>::infinity();
  for (const PathMechanismReport& mechanism : result.mechanisms) {
    const std::optional<double>& error =
        rms ? mechanism.rms_point_error : mechanism.max_point_error;
    if (error && !HasKinematicDefect(mechanism.defects)) best = std::min(best, *error);
  }
  return best;
}

TEST(TaskSolver, FiveTimedPointsGiveTheGeneratingFourBarFirstAmongTheExact) {
  std::mt19937_64 rng(81);
  for (int t = 0; t < 20; ++t) {
    SCOPED_TRACE("seed 81, task " + std::to_string(t));
    const testing::GeneratedPathTask generated = testing::RandomPathTask(rng, DyadType::kRR);
    std::vector<Eigen::Vector2d> points;
    const Task task = PathTask(generated, 0.0, false, rng, &points);
    const TaskResult any = SolveTask(task);
    ASSERT_TRUE(std::holds_alternative<PathResult>(any));
    const PathResult& result = std::get<PathResult>(any);
    const double length = testing::PathLength(points);
    EXPECT_EQ(result.method, "exact");
    EXPECT_EQ(result.crank_roots_total, 4);
    EXPECT_LE(result.mechanisms.size(), 12u);
    double nearest = std::numeric_limits<double>::infinity();
    for (const PathMechanismReport& mechanism : result.mechanisms) {
      nearest = std::min(
          nearest, testing::PathFourBarDistance(mechanism.design, generated.four_bar, length));
    }
    EXPECT_LE(nearest, 1e-8);
    // Ranked: the defect-free four-bars first, each through every point.
    ASSERT_FALSE(result.mechanisms.empty());
    EXPECT_FALSE(HasKinematicDefect(result.mechanisms.front().defects));
    EXPECT_LE(*result.mechanisms.front().max_point_error, 1e-8 * length);
  }
}

TEST(TaskSolver, MoreTimedPointsAreFittedExactlyWhenExact) {
  std::mt19937_64 rng(82);
  for (int count : {10, 20}) {
    for (int t = 0; t < 4; ++t) {
      SCOPED_TRACE("seed 82, " + std::to_string(count) + " points, task " + std::to_string(t));
      const testing::GeneratedPathTask generated =
          testing::RandomPathTask(rng, DyadType::kRR, count);
      std::vector<Eigen::Vector2d> points;
      Task task = PathTask(generated, 0.0, false, rng, &points);
      const PathResult result = SolvePathTask(task);
      EXPECT_EQ(result.method, "least-squares");
      EXPECT_LE(BestError(result, false), 1e-9 * testing::PathLength(points));
    }
  }
}

TEST(TaskSolver, NoisyTimedPointsFitAsWellAsTheGeneratingFourBar) {
  std::mt19937_64 rng(83);
  int within = 0, cases = 0;
  for (double sigma : {1e-3, 1e-2}) {
    for (int count : {10, 20}) {
      for (int t = 0; t < 3; ++t) {
        SCOPED_TRACE("seed 83, sigma " + std::to_string(sigma) + ", " + std::to_string(count) +
                     " points, task " + std::to_string(t));
        const testing::GeneratedPathTask generated =
            testing::RandomPathTask(rng, DyadType::kRR, count);
        std::vector<Eigen::Vector2d> points;
        const Task task = PathTask(generated, sigma, false, rng, &points);
        const PathResult result = SolvePathTask(task);
        const double length = testing::PathLength(points);
        const double reference =
            *AnalyzePathFourBar(generated.four_bar, points, generated.input_angles, length)
                 .rms_point_error;
        const double best = BestError(result, true);
        ++cases;
        within += best <= 1.10 * reference;
      }
    }
  }
  // Every case within 10 % of the generating four-bar (balanced effort).
  EXPECT_EQ(within, cases);
}

TEST(TaskSolver, UntimedPointsAreFittedWithTheirAngles) {
  std::mt19937_64 rng(84);
  const testing::GeneratedPathTask generated = testing::RandomPathTask(rng, DyadType::kRR, 12);
  std::vector<Eigen::Vector2d> points;
  const Task task = PathTask(generated, 1e-3, true, rng, &points);
  const PathResult result = SolvePathTask(task);
  EXPECT_EQ(result.timing, "free");
  ASSERT_FALSE(result.mechanisms.empty());
  const PathMechanismReport& best = result.mechanisms.front();
  ASSERT_EQ(best.input_angles.size(), points.size());
  // Monotonic fitted angles, and a fit at least as good as the generating four-bar's (whose
  // timing is one of the admissible ones).
  const double direction = best.input_angles.back() > best.input_angles.front() ? 1.0 : -1.0;
  for (size_t j = 1; j < best.input_angles.size(); ++j) {
    EXPECT_GE(direction * (best.input_angles[j] - best.input_angles[j - 1]), 0.0);
  }
  const double length = testing::PathLength(points);
  const double reference =
      *AnalyzePathFourBar(generated.four_bar, points, generated.input_angles, length)
           .rms_point_error;
  EXPECT_LE(*best.rms_point_error, 1.10 * reference);
  // Noise of 1e-3 L on points given to full precision: no four-bar passes them within their
  // precision, and the result says so. Without noise it does not.
  const auto says_missed = [](const PathResult& solved) {
    return std::any_of(solved.notes.begin(), solved.notes.end(), [](const std::string& note) {
      return note.find("no four-bar found passes every point") != std::string::npos;
    });
  };
  EXPECT_TRUE(says_missed(result));
  std::vector<Eigen::Vector2d> exact_points;
  const PathResult exact = SolvePathTask(PathTask(generated, 0.0, true, rng, &exact_points));
  EXPECT_LE(BestError(exact, false), 1e-8 * testing::PathLength(exact_points));
  EXPECT_FALSE(says_missed(exact));
}

TEST(TaskSolver, FewerThanFiveTimedPointsGiveANote) {
  std::mt19937_64 rng(85);
  const testing::GeneratedPathTask generated = testing::RandomPathTask(rng, DyadType::kRR, 4);
  std::vector<Eigen::Vector2d> points;
  const PathResult result = SolvePathTask(PathTask(generated, 0.0, false, rng, &points));
  EXPECT_TRUE(result.mechanisms.empty());
  ASSERT_EQ(result.notes.size(), 1u);
  EXPECT_NE(result.notes[0].find("family"), std::string::npos);
}

// Ten noisy poses on three planted dyads: the least-squares seeds are refined, every refined
// dyad fits no worse than its seed, and the planted dyads' refinements fit the noisy poses at
// least as well as the planted dyads themselves (they are least-squares optima).
TEST(TaskSolver, SpatialLeastSquaresRefinesEverySeed) {
  for (int seed = 0; seed < 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    // Odd seeds plant an SP dyad (refined as a PS dyad of the inverted motion).
    const std::vector<SpatialDyad> planted =
        testing::DyadsThroughPose(rng, start,
                                  {SpatialDyadType::kSS, SpatialDyadType::kSS,
                                   seed % 2 ? SpatialDyadType::kSP : SpatialDyadType::kSS});
    std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, planted, start, 10);
    constexpr double kNoise = 1e-3;
    testing::PerturbSpatialPoses(rng, kNoise, &poses);
    const SpatialMotionResult result = SolveSpatialTask(SpatialMotionTask(poses));
    EXPECT_EQ(result.method, "least-squares");
    ASSERT_FALSE(result.dyads.empty());
    for (const SpatialDyadReport& report : result.dyads) {
      ASSERT_TRUE(report.rms_residual && report.seed_rms_residual);
      EXPECT_LE(*report.rms_residual, *report.seed_rms_residual * (1 + 1e-12));
    }
    for (const SpatialDyad& expected : planted) {
      double planted_rms = 0.0;
      for (const DualQuaternion& pose : poses) planted_rms += std::pow(expected.Residual(pose), 2);
      planted_rms = std::sqrt(planted_rms / poses.size());
      double best = 1e300;
      const SpatialDyadReport* nearest = nullptr;
      for (const SpatialDyadReport& report : result.dyads) {
        const double distance = testing::SpatialDyadDistance(report.dyad, expected);
        if (distance < best) {
          best = distance;
          nearest = &report;
        }
      }
      ASSERT_NE(nearest, nullptr);
      EXPECT_LT(best, 0.2);  // the noisy optimum is near the planted dyad
      EXPECT_LE(*nearest->rms_residual, planted_rms * (1 + 1e-9));
    }
    EXPECT_GT(result.refine_seconds, 0.0);
  }
}

// Twelve poses of a random 5-SS platform, noisy but for two exact ones that stay on it: every
// refined dyad meets the exact poses to 1e-9 L, and those near a planted dyad (the optima the
// algebraic seeds reach, at least four of five) meet no other pose. Without the flags (all
// false, or none given: the same result) the same dyads miss the exact poses. With nine noisy
// poses exact (more than a dyad's parameters) the dyads miss them, each with a note naming it.
TEST(TaskSolver, SpatialExactPosesAreMetByTheRefinedDyads) {
  constexpr double kExactTolerance = 1e-9;  // times L: the refiner's default exact_tolerance
  constexpr double kNear = 0.2;             // a refined dyad this near a planted one is its optimum
  constexpr int kExactA = 3, kExactB = 8;
  for (int seed = 900; seed < 903; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    testing::PlantedSpatialTask platform = testing::RandomPlatformTask(rng, 12);
    const std::vector<SpatialDyad>& planted = platform.planted;
    std::vector<DualQuaternion>& poses = platform.poses;
    const std::vector<DualQuaternion> clean = poses;
    testing::PerturbSpatialPoses(rng, 1e-3, &poses);
    Task task = SpatialMotionTask(poses);
    for (int j : {kExactA, kExactB}) {
      task.spatial_poses[j] = clean[j];
      task.pose_exact[j] = true;
    }
    // The largest |residual| over the poses `flagged` marks exact.
    const auto exact_miss = [](const SpatialDyad& dyad, const Task& flagged) {
      double miss = 0.0;
      for (size_t j = 0; j < flagged.spatial_poses.size(); ++j) {
        if (flagged.pose_exact[j]) {
          miss = std::max(miss, std::abs(dyad.Residual(flagged.spatial_poses[j])));
        }
      }
      return miss;
    };
    const auto other_least = [&task](const SpatialDyad& dyad) {
      double least = 1e300;
      for (size_t j = 0; j < task.spatial_poses.size(); ++j) {
        if (!task.pose_exact[j]) {
          least = std::min(least, std::abs(dyad.Residual(task.spatial_poses[j])));
        }
      }
      return least;
    };
    // The dyad of `solved` nearest `expected`, and how near.
    const auto nearest = [](const SpatialMotionResult& solved, const SpatialDyad& expected,
                            double* distance) {
      SpatialDyad dyad;
      *distance = 1e300;
      for (const SpatialDyadReport& report : solved.dyads) {
        const double d = testing::SpatialDyadDistance(report.dyad, expected);
        if (d < *distance) {
          *distance = d;
          dyad = report.dyad;
        }
      }
      return dyad;
    };
    const auto count_notes = [](const SpatialMotionResult& solved, const std::string& prefix) {
      int count = 0;
      for (const std::string& note : solved.notes) {
        count +=
            note.rfind(prefix, 0) == 0 && note.find("exact poses not met") != std::string::npos;
      }
      return count;
    };

    const SpatialMotionResult result = SolveSpatialTask(task);
    ASSERT_EQ(result.method, "least-squares");
    ASSERT_FALSE(result.dyads.empty());
    const double limit = kExactTolerance * result.scale;
    for (const SpatialDyadReport& report : result.dyads) {
      EXPECT_LE(exact_miss(report.dyad, task), limit);
    }
    EXPECT_EQ(count_notes(result, "dyad "), 0);

    Task unflagged = task;
    unflagged.pose_exact.assign(task.spatial_poses.size(), false);
    const SpatialMotionResult free = SolveSpatialTask(unflagged);
    int reached = 0;
    for (const SpatialDyad& expected : planted) {
      double free_distance = 0.0, distance = 0.0;
      const SpatialDyad free_dyad = nearest(free, expected, &free_distance);
      if (free_distance >= kNear) continue;  // not a local optimum the seeds reach
      ++reached;
      const SpatialDyad dyad = nearest(result, expected, &distance);
      EXPECT_LT(distance, kNear);
      EXPECT_LE(exact_miss(dyad, task), limit);
      EXPECT_GT(other_least(dyad), limit);
      EXPECT_GT(exact_miss(free_dyad, task), 1e3 * limit);
    }
    EXPECT_GE(reached, 4);
    EXPECT_EQ(count_notes(free, "dyad "), 0);
    unflagged.pose_exact.clear();
    const SpatialMotionResult none = SolveSpatialTask(unflagged);
    ASSERT_EQ(none.dyads.size(), free.dyads.size());
    for (size_t i = 0; i < free.dyads.size(); ++i) {
      EXPECT_EQ(testing::SpatialDyadDistance(none.dyads[i].dyad, free.dyads[i].dyad), 0.0);
    }

    // Nine exact poses, seven of them noisy: a note for each dyad that misses them, and only
    // for those.
    Task overpinned = task;
    overpinned.pose_exact.assign(task.spatial_poses.size(), true);
    for (int j : {0, 5, 11}) overpinned.pose_exact[j] = false;
    const SpatialMotionResult pinned = SolveSpatialTask(overpinned);
    int missing = 0;
    for (size_t i = 0; i < pinned.dyads.size(); ++i) {
      const bool misses =
          exact_miss(pinned.dyads[i].dyad, overpinned) > kExactTolerance * pinned.scale;
      missing += misses;
      EXPECT_EQ(count_notes(pinned, "dyad " + std::to_string(i) + " ("), misses ? 1 : 0) << i;
    }
    EXPECT_GT(missing, 0);
  }
}

Task PlanarTask(const std::vector<PlanarPose>& poses, Effort effort) {
  return PlanarMotionTask(poses, effort);
}

// RMS pose error of a four-bar at the poses (each at its nearest configuration).
double RmsPoseError(const PlanarDyad& input, const PlanarDyad& output,
                    const std::vector<PlanarPose>& poses, double length) {
  const FourBarAnalysis analysis = AnalyzeFourBar(input, output, poses, length);
  double sum = 0.0;
  for (const FourBarLocation& location : analysis.locations) {
    sum += location.pose_error * location.pose_error;
  }
  return std::sqrt(sum / poses.size());
}

TEST(TaskSolver, PlanarExactTasksWithManyPosesGiveTheirMechanism) {
  constexpr double kPoseErrorTolerance = 1e-9;  // times L
  constexpr double kRecovery = 1e-8;            // relative dyad error
  int seed = 0;
  for (int count : {6, 10, 20, 50}) {
    for (DyadType output : {DyadType::kRR, DyadType::kPR}) {
      SCOPED_TRACE("poses " + std::to_string(count) + " output " + DyadTypeName(output));
      std::mt19937_64 rng(700 + seed++);
      const testing::GeneratedTask generated =
          testing::RandomTask(rng, DyadType::kRR, output, count);
      const PlanarMotionResult result =
          SolvePlanarTask(PlanarTask(generated.poses, Effort::kBalanced));
      EXPECT_EQ(result.method, "least-squares");
      std::vector<PlanarDyad> dyads;
      for (const DyadReport& report : result.dyads) dyads.push_back(report.dyad);
      for (const PlanarDyad& expected : {generated.input, generated.output}) {
        EXPECT_LT(testing::NearestDyadDistance(dyads, expected,
                                               testing::DyadScale(expected, generated.poses)),
                  kRecovery);
      }
      double best = 1e300;
      for (const MechanismReport& mechanism : result.mechanisms) {
        if (mechanism.max_pose_error) best = std::min(best, *mechanism.max_pose_error);
      }
      EXPECT_LE(best, kPoseErrorTolerance * result.scale);
    }
  }
}

TEST(TaskSolver, PlanarNoisyTasksFitAsWellAsTheGeneratingMechanism) {
  // Within 10 % of the generating mechanism's RMS pose error on the same noisy poses (issue 5).
  constexpr double kWithin = 1.10;
  int seed = 0;
  for (double noise : {1e-3, 1e-2}) {
    for (int count : {10, 30}) {
      SCOPED_TRACE("noise " + std::to_string(noise) + " poses " + std::to_string(count));
      std::mt19937_64 rng(800 + seed++);
      const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, count);
      const double length = CharacteristicLength(generated.poses);
      std::vector<PlanarPose> noisy = generated.poses;
      testing::PerturbPlanarPoses(rng, noise, length, &noisy);
      const PlanarMotionResult result = SolvePlanarTask(PlanarTask(noisy, Effort::kBalanced));
      const double generating = RmsPoseError(generated.input, generated.output, noisy, length);
      double best = 1e300;
      for (const MechanismReport& mechanism : result.mechanisms) {
        if (mechanism.rms_pose_error && !HasKinematicDefect(mechanism.defects)) {
          best = std::min(best, *mechanism.rms_pose_error);
        }
      }
      EXPECT_LE(best, kWithin * generating) << "generating " << generating;
      // The stages are reported, each with its time.
      ASSERT_GE(result.stages.size(), 3u);
      EXPECT_EQ(result.stages.front().name, "seed");
    }
  }
}

// Twelve poses of a four-bar, four of them replaced by outliers of negligible weight (1e-8):
// the algebraic seeds (which ignore weights) and their refinements land in poor local minima,
// so `balanced` misses the generating four-bar; `thorough`'s global search finds it. The seeds
// were chosen from a scan (3000 + 0..39) where this happens; the test fails if `balanced`
// starts finding it (then the task no longer shows the point) or `thorough` stops.
TEST(TaskSolver, ThoroughFindsWhatTheSeedsMiss) {
  for (int seed : {3000, 3003}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 12);
    Task task = PlanarTask(generated.poses, Effort::kBalanced);
    const double length = CharacteristicLength(generated.poses);
    std::uniform_real_distribution<double> uniform(-1, 1);
    for (int k : {2, 5, 8, 11}) {
      task.planar_poses[k].origin_in_fixed +=
          2.0 * length * Eigen::Vector2d(uniform(rng), uniform(rng)).normalized();
      task.planar_poses[k].theta += M_PI * uniform(rng);
      task.pose_weights[k] = 1e-8;
    }
    const auto recovery = [&](const PlanarMotionResult& result) {
      std::vector<PlanarDyad> dyads;
      for (const DyadReport& report : result.dyads) dyads.push_back(report.dyad);
      return std::max(
          testing::NearestDyadDistance(dyads, generated.input,
                                       testing::DyadScale(generated.input, generated.poses)),
          testing::NearestDyadDistance(dyads, generated.output,
                                       testing::DyadScale(generated.output, generated.poses)));
    };
    const double balanced = recovery(SolvePlanarTask(task));
    task.effort = Effort::kThorough;
    const double thorough = recovery(SolvePlanarTask(task));
    // The outliers' weight 1e-8 moves the optimum by about 1e-8 of their pull: 1e-4 is ample.
    EXPECT_LT(thorough, 1e-4);
    EXPECT_GT(balanced, 0.1);
  }
}

TEST(TaskSolver, SpatialFastEffortKeepsTheSeeds) {
  std::mt19937_64 rng(9);
  Task task;
  task.space = Space::kSpatial;
  for (int j = 0; j < 9; ++j) task.spatial_poses.push_back(testing::RandomSpatialPose(rng));
  task.pose_weights.assign(9, 1.0);
  task.pose_exact.assign(9, false);
  task.effort = Effort::kFast;
  const SpatialMotionResult result = SolveSpatialTask(task);
  for (const SpatialDyadReport& report : result.dyads) EXPECT_FALSE(report.rms_residual);
  EXPECT_EQ(result.refine_seconds, 0.0);
}

// Effort like for like in space (issue 14): balanced refines fast's least-squares seeds, so
// every dyad fast lists is matched or bettered by one balanced lists (its refinement, or the
// better of two refinements that reached one optimum), and thorough (no search in space) is
// balanced. Balanced lists no dyad twice: two refinements of one optimum, or one plane with its
// normal either way, are one. Random 5-SS platforms, 10 and 30 poses, noise 0, 1e-3 and 1e-2.
// (The trade bench's spatial measure, the RMS of the dyad nearest each generating one, can
// still rise from fast to balanced: on 10 noisy poses a refined dyad leaves the generator's
// neighbourhood for an optimum that fits better than the generator itself.)
TEST(TaskSolver, SpatialBalancedMatchesEveryFastDyad) {
  int tasks = 0;
  for (const int count : {10, 30}) {
    for (const double noise : {0.0, 1e-3, 1e-2}) {
      for (uint64_t seed = 1; seed <= 4; ++seed) {
        SCOPED_TRACE(std::to_string(count) + " poses, noise " + std::to_string(noise) + ", seed " +
                     std::to_string(seed));
        std::mt19937_64 rng(seed);
        testing::PlantedSpatialTask platform = testing::RandomPlatformTask(rng, count);
        testing::PerturbSpatialPoses(rng, noise, &platform.poses);
        const auto rms = [&](const SpatialDyad& dyad) {
          double sum = 0.0;
          for (const DualQuaternion& pose : platform.poses) sum += std::pow(dyad.Residual(pose), 2);
          return std::sqrt(sum / platform.poses.size());
        };
        Task task = SpatialMotionTask(platform.poses);
        task.effort = Effort::kFast;
        const SpatialMotionResult fast = SolveSpatialTask(task);
        task.effort = Effort::kBalanced;
        const SpatialMotionResult balanced = SolveSpatialTask(task);
        task.effort = Effort::kThorough;
        const SpatialMotionResult thorough = SolveSpatialTask(task);
        if (balanced.method != "least-squares") continue;
        ++tasks;
        for (const SpatialDyadReport& seed_report : fast.dyads) {
          const double own = rms(seed_report.dyad);
          double best = std::numeric_limits<double>::infinity();
          for (const SpatialDyadReport& report : balanced.dyads)
            best = std::min(best, rms(report.dyad));
          EXPECT_LE(best, own * (1.0 + 1e-9) + 1e-15 * balanced.scale);
        }
        ASSERT_EQ(thorough.dyads.size(), balanced.dyads.size());
        for (size_t i = 0; i < balanced.dyads.size(); ++i) {
          EXPECT_EQ(rms(thorough.dyads[i].dyad), rms(balanced.dyads[i].dyad));
          for (size_t k = 0; k < i; ++k) {
            const SpatialDyad& a = balanced.dyads[i].dyad;
            const SpatialDyad& b = balanced.dyads[k].dyad;
            if (a.type != b.type) continue;
            EXPECT_GT(testing::SpatialDyadDistance(a, b), 1e-5) << "dyads " << k << " and " << i;
          }
        }
      }
    }
  }
  EXPECT_GE(tasks, 20);
}

}  // namespace
}  // namespace linkfit
