// Tests of optimizers/spherical_search.h, the NLopt search for spherical dyads over the moving
// axis, and of effort thorough on spherical tasks (SolveSpatialTask): noisy orientations of a
// random spherical four-bar give both generating dyads back from the search alone (no seeds),
// exact orientations are met, weights are honoured, thorough never fits worse than balanced.
// Seeds are fixed and printed on failure.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fitting/spherical_motion.h"
#include "lib/task.h"
#include "optimizers/spherical_dyad_refiner.h"
#include "optimizers/spherical_search.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_spherical.h"

namespace linkfit {
namespace {

constexpr std::uint64_t kSeed = 20250917;  // every random test here starts from kSeed + k
constexpr double kNoise = 1e-3;            // radians: the orientations' noise
// The least-squares optimum of noisy data moves from the generating dyad by the noise times the
// problem's conditioning, FirstOrderReach to first order (measured: up to 1.1 times it on the
// draws below), allowed kReachFactor times it. Random spherical four-bars on 10-12 orientations
// are often poorly conditioned: 15 of the 40 optima below are more than kNearGenerator (30 times
// the noise, radians) from their generating dyads, which the test counts but does not require.
constexpr double kReachFactor = 3.0;
constexpr double kNearGenerator = 30.0 * kNoise;
// Two polishes of one optimum agree to this (radians): the refiner's tolerances leave ~1e-8.
constexpr double kSameOptimum = 1e-6;
constexpr double kGenerousTime = 30.0;  // seconds: never the binding limit in these tests
constexpr double kExactMiss = 1e-9;     // radians: the refiner's exact_tolerance
constexpr double kRelative = 1e-12;     // cost comparisons, to rounding

std::string Trace(std::uint64_t seed, int trial) {
  return "seed " + std::to_string(seed) + ", trial " + std::to_string(trial);
}

// How far two dyads are apart: the larger of their axes' distance (either sign) and their
// angles' difference, radians.
double DyadDistance(const SphericalDyad& a, const SphericalDyad& b) {
  const double same =
      std::max((a.fixed_axis - b.fixed_axis).norm(), (a.moving_axis - b.moving_axis).norm());
  const double flipped =
      std::max((a.fixed_axis + b.fixed_axis).norm(), (a.moving_axis + b.moving_axis).norm());
  return std::max(std::min(same, flipped), std::abs(a.angle - b.angle));
}

double NearestDistance(const SphericalDyad& dyad, const std::vector<SphericalDyad>& found) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const SphericalDyad& other : found) nearest = std::min(nearest, DyadDistance(dyad, other));
  return nearest;
}

double WeightedRms(const SphericalDyad& dyad, const std::vector<Eigen::Matrix3d>& rotations,
                   const std::vector<double>& weights) {
  double sum = 0.0, total = 0.0;
  for (size_t j = 0; j < rotations.size(); ++j) {
    const double weight = weights.empty() ? 1.0 : weights[j];
    sum += weight * dyad.Residual(rotations[j]) * dyad.Residual(rotations[j]);
    total += weight;
  }
  return std::sqrt(sum / total);
}

// How far the noise can move a dyad's least-squares optimum, to first order: |J^+| |e|, with e
// the dyad's residuals at the rotations and J their Jacobian in the dyad's five parameters (the
// tangent planes of both axes and the angle; central differences). The optimum of the noisy
// data is at -J^+ e from the dyad, to first order.
double FirstOrderReach(const SphericalDyad& dyad, const std::vector<Eigen::Matrix3d>& rotations) {
  const int n = static_cast<int>(rotations.size());
  const auto tangent = [](const Eigen::Vector3d& axis, int k) {
    const Eigen::Vector3d other =
        std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d first = (other - other.dot(axis) * axis).normalized();
    return k == 0 ? first : Eigen::Vector3d(axis.cross(first));
  };
  const auto moved = [&](int parameter, double h) {
    SphericalDyad changed = dyad;
    if (parameter < 2) {
      changed.fixed_axis = (dyad.fixed_axis + h * tangent(dyad.fixed_axis, parameter)).normalized();
    } else if (parameter < 4) {
      changed.moving_axis =
          (dyad.moving_axis + h * tangent(dyad.moving_axis, parameter - 2)).normalized();
    } else {
      changed.angle += h;
    }
    return changed;
  };
  constexpr double kStep = 1e-6;
  Eigen::MatrixXd jacobian(n, 5);
  Eigen::VectorXd residuals(n);
  for (int j = 0; j < n; ++j) residuals[j] = dyad.Residual(rotations[j]);
  for (int parameter = 0; parameter < 5; ++parameter) {
    const SphericalDyad plus = moved(parameter, kStep), minus = moved(parameter, -kStep);
    for (int j = 0; j < n; ++j) {
      jacobian(j, parameter) =
          (plus.Residual(rotations[j]) - minus.Residual(rotations[j])) / (2.0 * kStep);
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian);
  return residuals.norm() / svd.singularValues()[4];
}

// The refiner's options run to convergence: its default iterations can end early in the flat
// valleys of ill-conditioned tasks (seen with 50: stopped at RMS 4.8e-4 rad on its way to an
// optimum of RMS 3.1e-4).
SphericalDyadRefinerOptions Converged() {
  SphericalDyadRefinerOptions options;
  options.max_iterations = 1000;
  return options;
}

SphericalSearchOptions GenerousOptions() {
  SphericalSearchOptions options;
  options.time_limit = kGenerousTime;
  return options;
}

// A random spherical four-bar and 10 to 12 of its orientations, each turned by noise kNoise.
testing::SphericalTask NoisyTask(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> count(10, 12);
  testing::SphericalTask task = testing::RandomSphericalTask(rng, count(rng));
  testing::JitterRotations(rng, kNoise, &task.rotations);
  return task;
}

// The search lists the least-squares optimum each generating dyad refines to (the generating
// dyad as the noisy data determine it), and that optimum is within the noise's reach of the
// generating dyad (kReachFactor times FirstOrderReach). Returns how many of the two are also
// within kNearGenerator of it (well-conditioned draws).
int ExpectGeneratorsFound(const testing::SphericalTask& task, const std::vector<double>& weights,
                          const std::vector<SphericalDyad>& found, const std::string& trace) {
  int near = 0;
  for (const SphericalDyad* generating : {&task.four_bar.input, &task.four_bar.output}) {
    SphericalDyad optimum = *generating;
    RefineSphericalDyad(task.rotations, weights, {}, &optimum, Converged());
    const double moved = DyadDistance(optimum, *generating);
    EXPECT_LE(moved, kReachFactor * FirstOrderReach(*generating, task.rotations) + kSameOptimum)
        << trace;
    EXPECT_LE(NearestDistance(optimum, found), kSameOptimum) << trace;
    near += moved <= kNearGenerator;
  }
  return near;
}

// The search alone, without seeds, lists both generating dyads.
TEST(SphericalSearch, FindsBothGeneratingDyadsWithoutSeeds) {
  constexpr int kTasks = 20;
  const std::uint64_t seed = kSeed;
  std::mt19937_64 rng(seed);
  int near = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    const testing::SphericalTask task = NoisyTask(rng);
    std::vector<SphericalDyad> found;
    SphericalSearchSummary summary;
    ASSERT_GT(SearchSphericalDyads(task.rotations, {}, {}, GenerousOptions(), &found, &summary), 0)
        << Trace(seed, trial);
    EXPECT_GT(summary.evaluations, 0);
    EXPECT_LE(static_cast<int>(found.size()), SphericalSearchOptions().polish_count);
    near += ExpectGeneratorsFound(task, {}, found, Trace(seed, trial));
    // Best first, and the summary's cost is the first dyad's.
    for (size_t k = 1; k < found.size(); ++k) {
      EXPECT_LE(WeightedRms(found[k - 1], task.rotations, {}),
                WeightedRms(found[k], task.rotations, {}) * (1.0 + kRelative))
          << Trace(seed, trial);
    }
    const double rms = WeightedRms(found.front(), task.rotations, {});
    EXPECT_NEAR(summary.best_cost, 0.5 * task.rotations.size() * rms * rms,
                1e-9 * summary.best_cost)
        << Trace(seed, trial);
  }
  std::printf("%d of %d generating dyads' optima within %g rad of them\n", near, 2 * kTasks,
              kNearGenerator);
}

// Every algorithm finds them too (a smaller draw).
TEST(SphericalSearch, EveryAlgorithmFindsTheGeneratingDyads) {
  const std::uint64_t seed = kSeed + 1;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 5; ++trial) {
    const testing::SphericalTask task = NoisyTask(rng);
    for (GlobalAlgorithm algorithm : {GlobalAlgorithm::kCrs2, GlobalAlgorithm::kMlsl,
                                      GlobalAlgorithm::kIsres, GlobalAlgorithm::kDirect}) {
      SphericalSearchOptions options = GenerousOptions();
      options.algorithm = algorithm;
      std::vector<SphericalDyad> found;
      SphericalSearchSummary summary;
      SearchSphericalDyads(task.rotations, {}, {}, options, &found, &summary);
      EXPECT_EQ(summary.algorithm, GlobalAlgorithmName(algorithm));
      ExpectGeneratorsFound(task, {}, found,
                            Trace(seed, trial) + ", " + GlobalAlgorithmName(algorithm));
    }
  }
}

// An orientation marked exact is met by every dyad returned.
TEST(SphericalSearch, MeetsExactOrientations) {
  const std::uint64_t seed = kSeed + 2;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 8; ++trial) {
    testing::SphericalTask task = testing::RandomSphericalTask(rng, 10);
    testing::JitterRotations(rng, 1e-2, &task.rotations);
    std::vector<bool> exact(task.rotations.size(), false);
    exact[4] = true;
    std::vector<SphericalDyad> found;
    SearchSphericalDyads(task.rotations, {}, exact, GenerousOptions(), &found);
    ASSERT_FALSE(found.empty()) << Trace(seed, trial);
    for (const SphericalDyad& dyad : found) {
      EXPECT_LE(std::abs(dyad.Residual(task.rotations[4])), kExactMiss) << Trace(seed, trial);
    }
  }
}

// Two orientations replaced by wild ones (turned by about a radian), weighted kWildWeight: the
// search lists the weighted least-squares optimum of each generating dyad, which the exact good
// orientations put within kWildReach of it.
TEST(SphericalSearch, HonoursWeights) {
  constexpr double kWildWeight = 1e-10;
  // The wild orientations' weighted residuals (~1e-10 rad) times the conditioning (up to ~1e5
  // on these draws: measured up to 2e-5).
  constexpr double kWildReach = 1e-4;
  const std::uint64_t seed = kSeed + 3;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 8; ++trial) {
    testing::SphericalTask task = testing::RandomSphericalTask(rng, 10);
    std::vector<double> weights(task.rotations.size(), 1.0);
    for (int spoiled : {2, 7}) {
      task.rotations[spoiled] = testing::RandomSmallRotation(rng, 1.0) * task.rotations[spoiled];
      weights[spoiled] = kWildWeight;
    }
    std::vector<SphericalDyad> found;
    SearchSphericalDyads(task.rotations, weights, {}, GenerousOptions(), &found);
    for (const SphericalDyad* generating : {&task.four_bar.input, &task.four_bar.output}) {
      SphericalDyad optimum = *generating;
      RefineSphericalDyad(task.rotations, weights, {}, &optimum, Converged());
      EXPECT_LE(DyadDistance(optimum, *generating), kWildReach) << Trace(seed, trial);
      EXPECT_LE(NearestDistance(optimum, found), kSameOptimum) << Trace(seed, trial);
    }
  }
}

TEST(SphericalSearch, IsReproducibleAndChecksItsInput) {
  std::mt19937_64 rng(kSeed + 4);
  const testing::SphericalTask task = NoisyTask(rng);
  std::vector<SphericalDyad> first, second;
  SearchSphericalDyads(task.rotations, {}, {}, GenerousOptions(), &first);
  SearchSphericalDyads(task.rotations, {}, {}, GenerousOptions(), &second);
  ASSERT_EQ(first.size(), second.size());
  for (size_t k = 0; k < first.size(); ++k) EXPECT_EQ(DyadDistance(first[k], second[k]), 0.0);

  // Fewer than five orientations leave a family: nothing.
  std::vector<SphericalDyad> found;
  const std::vector<Eigen::Matrix3d> four(task.rotations.begin(), task.rotations.begin() + 4);
  EXPECT_EQ(SearchSphericalDyads(four, {}, {}, {}, &found), 0);
  EXPECT_TRUE(found.empty());

  const std::vector<Eigen::Matrix3d>& rotations = task.rotations;
  EXPECT_THROW(SearchSphericalDyads(rotations, {1.0}, {}, {}, &found), std::invalid_argument);
  std::vector<double> negative(rotations.size(), 1.0);
  negative[0] = -1.0;
  EXPECT_THROW(SearchSphericalDyads(rotations, negative, {}, {}, &found), std::invalid_argument);
  EXPECT_THROW(SearchSphericalDyads(rotations, {}, {true}, {}, &found), std::invalid_argument);
  std::vector<Eigen::Matrix3d> bad = rotations;
  bad[1](0, 0) = std::nan("");
  EXPECT_THROW(SearchSphericalDyads(bad, {}, {}, {}, &found), std::invalid_argument);
  SphericalSearchOptions options;
  options.max_evaluations = 0;
  EXPECT_THROW(SearchSphericalDyads(rotations, {}, {}, options, &found), std::invalid_argument);
  options = {};
  options.time_limit = 0.0;
  EXPECT_THROW(SearchSphericalDyads(rotations, {}, {}, options, &found), std::invalid_argument);
  options = {};
  options.polish_count = 0;
  EXPECT_THROW(SearchSphericalDyads(rotations, {}, {}, options, &found), std::invalid_argument);
}

// The task of noisy orientations about a centre away from both frames' origins.
Task SphericalTaskOf(const std::vector<Eigen::Matrix3d>& rotations, Effort effort) {
  Task task = SpatialMotionTask(testing::PosesAboutCenter(
      rotations, Eigen::Vector3d(0.4, -0.3, 0.7), Eigen::Vector3d(-1.0, 2.0, 0.5)));
  task.effort = effort;
  return task;
}

double BestRms(const SpatialMotionResult& result) {
  double best = std::numeric_limits<double>::infinity();
  for (const SphericalDyadReport& report : result.spherical_dyads) {
    best = std::min(best, report.rms_residual.value_or(best));
  }
  return best;
}

// The smallest RMS pose error of a listed defect-free four-bar (the bounded list keeps the best
// fit of each defect level).
double BestMechanismRms(const SpatialMotionResult& result) {
  double best = std::numeric_limits<double>::infinity();
  for (const MechanismReport& mechanism : result.spherical_mechanisms) {
    if (mechanism.defects.empty()) best = std::min(best, mechanism.rms_pose_error.value_or(best));
  }
  return best;
}

// End to end: thorough lists every dyad balanced lists and the search's optima, so its best
// dyad and its best four-bar never fit worse; it reports the search.
TEST(ThoroughSpherical, NeverFitsWorseThanBalanced) {
  const std::uint64_t seed = kSeed + 5;
  std::mt19937_64 rng(seed);
  int better = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const testing::SphericalTask drawn = NoisyTask(rng);
    const SpatialMotionResult balanced =
        SolveSpatialTask(SphericalTaskOf(drawn.rotations, Effort::kBalanced));
    const SpatialMotionResult thorough =
        SolveSpatialTask(SphericalTaskOf(drawn.rotations, Effort::kThorough));
    ASSERT_EQ(thorough.model, "spherical") << Trace(seed, trial);
    EXPECT_LE(BestRms(thorough), BestRms(balanced) * (1.0 + kRelative)) << Trace(seed, trial);
    EXPECT_LE(BestMechanismRms(thorough), BestMechanismRms(balanced) * (1.0 + kRelative))
        << Trace(seed, trial);
    for (const SphericalDyadReport& report : balanced.spherical_dyads) {
      bool listed = false;
      for (const SphericalDyadReport& other : thorough.spherical_dyads) {
        listed = listed || (SameSphericalDyad(report.dyad, other.dyad, 1e-7) &&
                            *other.rms_residual <= *report.rms_residual * (1.0 + kRelative));
      }
      EXPECT_TRUE(listed) << Trace(seed, trial);
    }
    // And every dyad the search finds on the task's motion.
    std::vector<SphericalDyad> searched;
    const Task task = SphericalTaskOf(drawn.rotations, Effort::kThorough);
    SearchSphericalDyads(TaskSphericalMotion(task, *thorough.spherical, thorough.scale).rotations,
                         {}, {}, TaskSolverOptions().spherical_search, &searched);
    for (const SphericalDyad& dyad : searched) {
      bool listed = false;
      for (const SphericalDyadReport& other : thorough.spherical_dyads) {
        listed = listed || SameSphericalDyad(dyad, other.dyad, 1e-7);
      }
      EXPECT_TRUE(listed) << Trace(seed, trial);
    }
    EXPECT_GT(thorough.search_seconds, 0.0);
    EXPECT_EQ(balanced.search_seconds, 0.0);
    const bool noted =
        std::any_of(thorough.notes.begin(), thorough.notes.end(), [](const std::string& note) {
          return note.rfind("search (thorough): NLopt crs2", 0) == 0;
        });
    EXPECT_TRUE(noted) << Trace(seed, trial);
    better += BestRms(thorough) < BestRms(balanced) * (1.0 - 1e-9);
  }
  std::printf("thorough fitted better than balanced on %d of 12 tasks\n", better);
}

// End to end: with an orientation marked exact, thorough's dyads meet it as balanced's do,
// those the search adds (some on these tasks) included.
TEST(ThoroughSpherical, MeetsExactOrientations) {
  const std::uint64_t seed = kSeed + 6;
  std::mt19937_64 rng(seed);
  size_t added = 0;
  for (int trial = 0; trial < 6; ++trial) {
    testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 10);
    testing::JitterRotations(rng, 1e-2, &drawn.rotations);
    Task task = SphericalTaskOf(drawn.rotations, Effort::kThorough);
    task.pose_exact.assign(drawn.rotations.size(), false);
    task.pose_exact[6] = true;
    const SpatialMotionResult result = SolveSpatialTask(task);
    ASSERT_EQ(result.model, "spherical") << Trace(seed, trial);
    ASSERT_FALSE(result.spherical_dyads.empty()) << Trace(seed, trial);
    task.effort = Effort::kBalanced;
    added += result.spherical_dyads.size() - SolveSpatialTask(task).spherical_dyads.size();
    const SphericalMotion motion = TaskSphericalMotion(task, *result.spherical, result.scale);
    for (const SphericalDyadReport& report : result.spherical_dyads) {
      EXPECT_LE(std::abs(report.dyad.Residual(motion.rotations[6])), 10.0 * kExactMiss)
          << Trace(seed, trial);
    }
  }
  EXPECT_GT(added, 0u);
}

}  // namespace
}  // namespace linkfit
