// Tests of optimizers/path_refiner.h: least squares of a crank-driven four-bar on timed points.
// Each test draws a random four-bar (RandomPathTask), makes its exact or noisy points, refines a
// perturbed seed and requires the generating four-bar (or a fit at least as good as it) back;
// then frees the timing, marks points exact, feeds bad seeds and bad arguments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/dyad.h"
#include "lib/path_motion.h"
#include "lib/planar_pose.h"
#include "optimizers/path_refiner.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_path.h"
#include "tests/support/rounded_task.h"

namespace {

using linkfit::AnalyzePathFourBar;
using linkfit::DyadType;
using linkfit::DyadTypeName;
using linkfit::PathFourBar;
using linkfit::PathFourBarAnalysis;
using linkfit::PlanarDyad;
using linkfit::RefinePathFourBar;
using linkfit::RefinerSummary;
using linkfit::Rotation2;
using linkfit::testing::GeneratedPathTask;
using linkfit::testing::PathFourBarDistance;
using linkfit::testing::PathLength;
using linkfit::testing::RandomPathTask;

constexpr std::uint64_t kSeed = 20240701;  // every random test here starts from kSeed + k
constexpr int kTrials = 6;                 // random four-bars per case
constexpr double kPi = 3.14159265358979323846;
constexpr double kSeedOffset = 1e-2;       // every seed parameter moved by up to this, times L
constexpr double kExactPointError = 1e-9;  // refined max point error on exact points, times L
constexpr double kRecovered = 1e-6;        // PathFourBarDistance to the generating four-bar
constexpr double kRmsSlack = 1.10;         // refined RMS vs the generator's on noisy points
constexpr double kFreeTimingError = 1e-8;  // free timing on exact points, times L
constexpr double kAngleNoiseDeg = 5.0;     // free timing: start angles off by up to this
constexpr double kExactTolerance = 1e-9;   // points marked exact, times L
constexpr double kExactAmongNoise = 1e-3;  // noise of the other points, times L
constexpr double kCostRounding = 1e-12;    // relative rounding allowed in a cost comparison
constexpr int kSeedDraws = 100;            // perturbations drawn until one reaches every point

std::string Trace(std::uint64_t seed, int trial, DyadType output, int count) {
  return "seed " + std::to_string(seed) + ", trial " + std::to_string(trial) + ", RR+" +
         DyadTypeName(output) + ", " + std::to_string(count) + " points";
}

double Uniform(std::mt19937_64& rng, double amount) {
  return std::uniform_real_distribution<double>(-amount, amount)(rng);
}

Eigen::Vector2d Offset(std::mt19937_64& rng, double amount) {
  return Eigen::Vector2d(Uniform(rng, amount), Uniform(rng, amount));
}

// Every parameter of the four-bar moved by up to `amount` (lengths) or `amount / length`
// radians (line directions); the crank radius stays |A - B| (the first-point convention).
PathFourBar Perturb(const PathFourBar& four_bar, double amount, double length,
                    std::mt19937_64& rng) {
  PathFourBar seed = four_bar;
  seed.input.fixed_pivot += Offset(rng, amount);
  seed.input.moving_pivot += Offset(rng, amount);
  seed.input.radius = (seed.input.moving_pivot - seed.input.fixed_pivot).norm();
  PlanarDyad& output = seed.output;
  if (output.type == DyadType::kRR) {
    output.fixed_pivot += Offset(rng, amount);
    output.moving_pivot += Offset(rng, amount);
    output.radius += Uniform(rng, amount);
  } else {
    (output.type == DyadType::kPR ? output.moving_pivot : output.fixed_pivot) +=
        Offset(rng, amount);
    output.line_point += Offset(rng, amount);
    output.line_direction = Rotation2(Uniform(rng, amount / length)) * output.line_direction;
  }
  seed.coupler_point += Offset(rng, amount);
  return seed;
}

// A perturbed seed that reaches every point on one assembly (AnalyzePathFourBar).
PathFourBar ReachingSeed(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                         const std::vector<double>& angles, double amount, double length,
                         std::mt19937_64& rng) {
  for (int draw = 0; draw < kSeedDraws; ++draw) {
    const PathFourBar seed = Perturb(four_bar, amount, length, rng);
    if (AnalyzePathFourBar(seed, points, angles, length).max_point_error) return seed;
  }
  ADD_FAILURE() << "no perturbed seed reaches every point";
  return four_bar;
}

std::vector<Eigen::Vector2d> Noisy(const std::vector<Eigen::Vector2d>& points, double sigma,
                                   std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector2d> noisy = points;
  for (Eigen::Vector2d& point : noisy) point += Eigen::Vector2d(noise(rng), noise(rng));
  return noisy;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

void ReportTimes(const std::string& name, const std::vector<double>& seconds) {
  std::cout << "[ timing   ] " << name << ": median " << 1e3 * Median(seconds) << " ms over "
            << seconds.size() << " refinements" << std::endl;
  ::testing::Test::RecordProperty(name + "_median_ms", std::to_string(1e3 * Median(seconds)));
}

TEST(PathRefinerTest, ExactPointsRecoverTheGeneratingFourBar) {
  std::uint64_t seed = kSeed;
  for (DyadType output : {DyadType::kRR, DyadType::kPR}) {
    for (int count : {6, 10, 20}) {
      std::vector<double> seconds;
      for (int trial = 0; trial < kTrials; ++trial, ++seed) {
        SCOPED_TRACE(Trace(seed, trial, output, count));
        std::mt19937_64 rng(seed);
        const GeneratedPathTask task = RandomPathTask(rng, output, count);
        const double length = PathLength(task.points);
        PathFourBar four_bar = ReachingSeed(task.four_bar, task.points, task.input_angles,
                                            kSeedOffset * length, length, rng);
        std::vector<double> angles = task.input_angles;
        const RefinerSummary summary =
            RefinePathFourBar(task.points, {}, {}, length, false, &angles, &four_bar);
        seconds.push_back(summary.seconds);
        EXPECT_LE(summary.final_max, kExactPointError * length) << summary.message;
        EXPECT_LE(PathFourBarDistance(four_bar, task.four_bar, length), kRecovered);
        EXPECT_EQ(angles, task.input_angles);  // prescribed timing: read only
        // The summary reports what AnalyzePathFourBar measures on the returned design.
        const PathFourBarAnalysis analysis =
            AnalyzePathFourBar(four_bar, task.points, angles, length);
        ASSERT_TRUE(analysis.max_point_error.has_value());
        EXPECT_DOUBLE_EQ(*analysis.max_point_error, summary.final_max);
        EXPECT_TRUE(analysis.defects.empty());
      }
      if (count >= 10) {
        ReportTimes(std::string("prescribed_") + DyadTypeName(output) + "_" + std::to_string(count),
                    seconds);
      }
    }
  }
}

TEST(PathRefinerTest, NoisyPointsFitAsWellAsTheGeneratingFourBar) {
  // Known limitation: a fit can stop against a stationary configuration (a point at the edge of
  // the crank's reach, which the fixed assembly cannot cross; no second start yet): 1 of these
  // 24 random cases (seed 20240809, twice the generator's RMS). At most kMaxStuck are allowed.
  constexpr int kMaxStuck = 1;
  int stuck = 0;
  std::uint64_t seed = kSeed + 100;
  for (double sigma : {1e-3, 1e-2}) {
    for (int count : {10, 20}) {
      for (int trial = 0; trial < kTrials; ++trial, ++seed) {
        SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, count) + ", noise " + std::to_string(sigma) +
                     " L");
        std::mt19937_64 rng(seed);
        const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, count);
        const double length = PathLength(task.points);
        const std::vector<Eigen::Vector2d> points = Noisy(task.points, sigma * length, rng);
        const PathFourBarAnalysis generator =
            AnalyzePathFourBar(task.four_bar, points, task.input_angles, length);
        ASSERT_TRUE(generator.rms_point_error.has_value());
        PathFourBar four_bar = ReachingSeed(task.four_bar, points, task.input_angles,
                                            kSeedOffset * length, length, rng);
        std::vector<double> angles = task.input_angles;
        const RefinerSummary summary =
            RefinePathFourBar(points, {}, {}, length, false, &angles, &four_bar);
        if (summary.final_rms > kRmsSlack * *generator.rms_point_error) {
          ++stuck;
          std::cout << "[ stuck    ] seed " << seed << ": rms " << summary.final_rms / length
                    << " L vs the generator's " << *generator.rms_point_error / length
                    << " L: " << summary.message << std::endl;
        }
        EXPECT_LE(summary.final_cost, summary.initial_cost);
      }
    }
  }
  EXPECT_LE(stuck, kMaxStuck);
}

TEST(PathRefinerTest, FreeTimingRecoversTheAngles) {
  std::uint64_t seed = kSeed + 200;
  // Twenty points: with fewer, the nearly square problem (2n equations, n + 9 unknowns) is
  // often ill-conditioned, and Levenberg-Marquardt creeps (in 12 random tasks, 100 iterations
  // left 3 of 12 above 1e-8 L with 10 points, 4 with 12, 1 with 15, none with 20).
  std::vector<double> seconds;
  for (int count : {20}) {
    for (int trial = 0; trial < kTrials; ++trial, ++seed) {
      SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, count) + ", free timing");
      std::mt19937_64 rng(seed);
      const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, count);
      const double length = PathLength(task.points);
      // Start angles off by up to kAngleNoiseDeg, redrawn until they keep the true direction.
      const double direction = task.input_angles.back() > task.input_angles.front() ? 1.0 : -1.0;
      std::vector<double> angles;
      bool monotonic = false;
      while (!monotonic) {
        angles = task.input_angles;
        for (double& angle : angles) angle += Uniform(rng, kAngleNoiseDeg * kPi / 180.0);
        monotonic = true;
        for (int j = 1; j < count; ++j) monotonic &= direction * (angles[j] - angles[j - 1]) > 0.0;
      }
      PathFourBar four_bar =
          ReachingSeed(task.four_bar, task.points, angles, kSeedOffset * length, length, rng);
      const RefinerSummary summary =
          RefinePathFourBar(task.points, {}, {}, length, true, &angles, &four_bar);
      seconds.push_back(summary.seconds);
      EXPECT_LE(summary.final_max, kFreeTimingError * length) << summary.message;
      for (int j = 1; j < count; ++j) {
        EXPECT_GE(direction * (angles[j] - angles[j - 1]), 0.0) << "step " << j;
      }
      // The fitted angles are the generating four-bar's (relative to the first).
      for (int j = 1; j < count; ++j) {
        EXPECT_NEAR(angles[j] - angles[0], task.input_angles[j] - task.input_angles[0], kRecovered)
            << "point " << j;
      }
    }
  }
  ReportTimes("free_timing_RR_20", seconds);
}

// Free timing keeps the points in order whatever the iteration budget: dense noisy points
// (neighbours swapped by the noise at the unconstrained optimum) refined with a budget too small
// for the first, unwindowed solve to converge. That solve used to be returned out of order when
// it ran out of iterations; it is redone in order (from its four-bar) instead.
TEST(PathRefinerTest, FreeTimingKeepsTheOrderWhenTheIterationsRunOut) {
  std::uint64_t seed = kSeed + 250;
  int out_of_order_optima = 0;  // tasks whose unconstrained optimum swaps neighbours
  for (int trial = 0; trial < kTrials; ++trial, ++seed) {
    SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, 100) + ", free timing, noise 3e-2 L");
    std::mt19937_64 rng(seed);
    const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, 100);
    const double length = PathLength(task.points);
    const std::vector<Eigen::Vector2d> points = Noisy(task.points, 3e-2 * length, rng);
    const double direction = task.input_angles.back() > task.input_angles.front() ? 1.0 : -1.0;
    const auto in_order = [&](const std::vector<double>& angles) {
      for (size_t j = 1; j < angles.size(); ++j) {
        if (direction * (angles[j] - angles[j - 1]) < 0.0) return false;
      }
      return true;
    };
    for (const int iterations : {3, 10, 400}) {
      linkfit::PathRefinerOptions options;
      options.max_iterations = iterations;
      std::vector<double> angles = task.input_angles;
      PathFourBar four_bar = task.four_bar;
      RefinePathFourBar(points, {}, {}, length, true, &angles, &four_bar, options);
      EXPECT_TRUE(in_order(angles)) << iterations << " iterations";
    }
    // The case is the one meant: free of the order, the optimum swaps neighbours (the
    // refinement without the order's windows: every point's nearest crank angle, projected
    // from the generator's).
    std::vector<double> nearest = task.input_angles;
    for (size_t j = 1; j < points.size(); ++j) {
      double best = std::numeric_limits<double>::infinity();
      for (int k = -200; k <= 200; ++k) {
        const double angle = task.input_angles[j] + 0.002 * k;
        const PathFourBarAnalysis at = AnalyzePathFourBar(
            task.four_bar, {task.points[0], points[j]}, {task.input_angles[0], angle}, length);
        if (at.point_errors.size() == 2 && at.point_errors[1] < best) {
          best = at.point_errors[1];
          nearest[j] = angle;
        }
      }
    }
    out_of_order_optima += !in_order(nearest);
  }
  EXPECT_GT(out_of_order_optima, kTrials / 2);
}

TEST(PathRefinerTest, ExactPointsAreMetAmongNoisyOnes) {
  std::uint64_t seed = kSeed + 300;
  for (int count : {10, 20}) {
    for (int trial = 0; trial < kTrials; ++trial, ++seed) {
      SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, count) + ", two exact points");
      std::mt19937_64 rng(seed);
      const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, count);
      const double length = PathLength(task.points);
      // (Noise of 1e-2 L lets some fits run off toward a degenerate four-bar, a crank of
      // thousands of L, where 1e-9 L is below the rounding of the design's coordinates.)
      std::vector<Eigen::Vector2d> points = Noisy(task.points, kExactAmongNoise * length, rng);
      std::vector<bool> exact(count, false);
      exact[0] = exact[count / 2] = true;
      PathFourBar four_bar =
          ReachingSeed(task.four_bar, points, task.input_angles, kSeedOffset * length, length, rng);
      std::vector<double> angles = task.input_angles;
      const RefinerSummary summary =
          RefinePathFourBar(points, {}, exact, length, false, &angles, &four_bar);
      const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, angles, length);
      ASSERT_TRUE(analysis.max_point_error.has_value()) << summary.message;
      for (int j = 0; j < count; ++j) {
        if (exact[j]) {
          EXPECT_LE(analysis.point_errors[j], kExactTolerance * length)
              << "point " << j << ": " << summary.message;
        }
      }
    }
  }
}

TEST(PathRefinerTest, NeverWorseThanTheSeed) {
  std::uint64_t seed = kSeed + 400;
  for (int trial = 0; trial < 2 * kTrials; ++trial, ++seed) {
    SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, 10) + ", far seed");
    std::mt19937_64 rng(seed);
    const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, 10);
    const double length = PathLength(task.points);
    const std::vector<Eigen::Vector2d> points = Noisy(task.points, 1e-2 * length, rng);
    // A far seed (0.3 L off), and weights that favour some points.
    PathFourBar four_bar =
        ReachingSeed(task.four_bar, points, task.input_angles, 0.3 * length, length, rng);
    const PathFourBar before = four_bar;
    std::vector<double> weights(points.size());
    for (double& weight : weights) weight = 1.0 + Uniform(rng, 0.5);
    std::vector<double> angles = task.input_angles;
    const RefinerSummary summary =
        RefinePathFourBar(points, weights, {}, length, false, &angles, &four_bar);
    EXPECT_LE(summary.final_cost, summary.initial_cost * (1.0 + kCostRounding));
    const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, angles, length);
    ASSERT_TRUE(analysis.max_point_error.has_value());
    EXPECT_DOUBLE_EQ(*analysis.max_point_error, summary.final_max);
    const PathFourBarAnalysis seed_analysis = AnalyzePathFourBar(before, points, angles, length);
    for (const std::string& defect : analysis.defects) {
      EXPECT_NE(std::find(seed_analysis.defects.begin(), seed_analysis.defects.end(), defect),
                seed_analysis.defects.end())
          << "new defect " << defect;
    }
  }
  // A seed that cannot reach the points comes back unchanged.
  std::mt19937_64 rng(seed);
  const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, 6);
  const double length = PathLength(task.points);
  PathFourBar broken = task.four_bar;
  broken.output.radius = 1e-3 * length;  // a tiny rocker: the output cannot close
  const PathFourBar before = broken;
  std::vector<double> angles = task.input_angles;
  const RefinerSummary summary =
      RefinePathFourBar(task.points, {}, {}, length, false, &angles, &broken);
  EXPECT_EQ(PathFourBarDistance(broken, before, length), 0.0) << summary.message;
  EXPECT_FALSE(std::isfinite(summary.final_cost));
}

// Held transmission angle (PathRefinerOptions::min_transmission_deg): ten exact timed points of
// a 4R whose transmission angle over the crank's sweep dips to 8-25 degrees, refined from the
// generator holding it 10 degrees higher. Without the option the generator is the optimum and
// stays; with it, the transmission angle over the sweep (AnalyzePathFourBar, 64 samples, not the
// refiner's) is at least the one asked, on a four-bar that still reaches every point.
TEST(PathRefinerTest, HeldTransmissionAngleIsKept) {
  const std::uint64_t seed = kSeed + 900;
  std::mt19937_64 rng(seed);
  linkfit::PathAnalysisOptions sampled;
  sampled.transmission_samples = linkfit::kPathTransmissionSamples;
  int tried = 0;
  for (int draw = 0; draw < 400 && tried < kTrials; ++draw) {
    const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, 10);
    const double length = PathLength(task.points);
    const PathFourBarAnalysis generator =
        AnalyzePathFourBar(task.four_bar, task.points, task.input_angles, length, sampled);
    if (!generator.transmission_min_deg || *generator.transmission_min_deg < 8.0 ||
        *generator.transmission_min_deg > 25.0 || !generator.defects.empty()) {
      continue;
    }
    SCOPED_TRACE(Trace(seed, draw, DyadType::kRR, 10));
    ++tried;
    const double held = *generator.transmission_min_deg + 10.0;
    std::vector<double> angles = task.input_angles;
    PathFourBar plain = task.four_bar;
    RefinePathFourBar(task.points, {}, {}, length, false, &angles, &plain);
    const PathFourBarAnalysis plain_analysis =
        AnalyzePathFourBar(plain, task.points, angles, length, sampled);
    ASSERT_TRUE(plain_analysis.transmission_min_deg.has_value());
    EXPECT_LT(*plain_analysis.transmission_min_deg, held - 5.0);
    linkfit::PathRefinerOptions options;
    options.min_transmission_deg = held;
    PathFourBar holding = task.four_bar;
    const RefinerSummary summary =
        RefinePathFourBar(task.points, {}, {}, length, false, &angles, &holding, options);
    SCOPED_TRACE(summary.message);
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(holding, task.points, angles, length, sampled);
    ASSERT_TRUE(analysis.transmission_min_deg.has_value());
    EXPECT_GE(*analysis.transmission_min_deg, held);
    ASSERT_TRUE(analysis.max_point_error.has_value());
    EXPECT_TRUE(std::isfinite(*analysis.max_point_error));
  }
  EXPECT_EQ(tried, kTrials);
}

TEST(PathRefinerTest, BadArgumentsThrow) {
  std::mt19937_64 rng(kSeed + 500);
  const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, 6);
  const double length = PathLength(task.points);
  const auto refine = [&](std::vector<Eigen::Vector2d> points, std::vector<double> weights,
                          std::vector<bool> exact, double scale, bool free_timing,
                          std::vector<double> angles, PathFourBar four_bar) {
    RefinePathFourBar(points, weights, exact, scale, free_timing, &angles, &four_bar);
  };
  const std::vector<Eigen::Vector2d>& points = task.points;
  const std::vector<double>& angles = task.input_angles;
  const PathFourBar& four_bar = task.four_bar;
  EXPECT_NO_THROW(refine(points, {}, {}, length, false, angles, four_bar));
  EXPECT_THROW(refine(points, {}, {}, 0.0, false, angles, four_bar), std::invalid_argument);
  EXPECT_THROW(refine(points, {}, {}, -length, false, angles, four_bar), std::invalid_argument);
  EXPECT_THROW(refine(points, {1.0}, {}, length, false, angles, four_bar), std::invalid_argument);
  EXPECT_THROW(refine(points, std::vector<double>(6, -1.0), {}, length, false, angles, four_bar),
               std::invalid_argument);
  EXPECT_THROW(refine(points, {}, {true}, length, false, angles, four_bar), std::invalid_argument);
  EXPECT_THROW(refine(points, {}, {}, length, false, {0.0, 1.0}, four_bar), std::invalid_argument);
  EXPECT_THROW(refine({points[0]}, {}, {}, length, false, {angles[0]}, four_bar),
               std::invalid_argument);
  std::vector<Eigen::Vector2d> bad_points = points;
  bad_points[2].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(refine(bad_points, {}, {}, length, false, angles, four_bar), std::invalid_argument);
  std::vector<double> bad_angles = angles;
  bad_angles[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(refine(points, {}, {}, length, false, bad_angles, four_bar), std::invalid_argument);
  PathFourBar slider_input = four_bar;
  slider_input.input = PlanarDyad::PR(four_bar.input.moving_pivot, four_bar.input.fixed_pivot,
                                      Eigen::Vector2d::UnitX());
  EXPECT_THROW(refine(points, {}, {}, length, false, angles, slider_input), std::invalid_argument);
  // Free timing needs monotonic angles; prescribed timing does not.
  std::vector<double> back_and_forth = angles;
  std::swap(back_and_forth[2], back_and_forth[3]);
  EXPECT_THROW(refine(points, {}, {}, length, true, back_and_forth, four_bar),
               std::invalid_argument);
  EXPECT_NO_THROW(refine(points, {}, {}, length, false, back_and_forth, four_bar));
}

}  // namespace

// ---- closed paths, solved end to end (optimizers/path_task_solver.cc) ----

namespace linkfit {
namespace {

constexpr double kClosedFit = 1e-6;  // point error of the first four-bar, times L
constexpr double kSameCurve = 1e-5;  // coupler point over a whole turn, times L
constexpr int kClosedDigits = 12;    // the task text's significant digits
constexpr int kClosedPoints = 9;     // distinct points over the whole turn

// The coupler point of `four_bar` at the input angles, driven from the first configuration.
std::vector<Eigen::Vector2d> DrivenPoints(const PathFourBar& four_bar,
                                          const std::vector<double>& angles, double length) {
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(
      four_bar, std::vector<Eigen::Vector2d>(angles.size(), Eigen::Vector2d::Zero()), angles,
      length);
  std::vector<Eigen::Vector2d> points;
  for (const PlanarPose& pose : analysis.configurations) {
    points.push_back(pose.ToFixed(four_bar.coupler_point));
  }
  return points;
}

// A random four-bar whose crank turns fully (`crank` true) or not, and its coupler point at
// `count` input angles: evenly over a whole turn in `direction` (a crank), or the generated
// task's own angles within the input's reach.
GeneratedPathTask DrawClosed(std::mt19937_64& rng, bool crank, int count, double direction) {
  for (;;) {
    GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR, count);
    const double length = PathLength(task.points);
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(task.four_bar, task.points, task.input_angles, length);
    if (analysis.input_rotates_fully != crank) continue;
    if (!crank) return task;
    std::vector<double> angles;
    for (int j = 0; j < count; ++j) {
      angles.push_back(task.input_angles[0] + direction * 2.0 * kPi * j / count);
    }
    task.points = DrivenPoints(task.four_bar, angles, length);
    task.input_angles = angles;
    if (static_cast<int>(task.points.size()) == count) return task;
  }
}

// The task text of a closed path: the points, then the first point again (at the first input
// angle plus a turn in the timing's direction); no angles for free timing. No minimum
// transmission angle: a random crank-rocker's may be poor over the whole turn, and the ranking
// would put any defect-free four-bar, however far off the curve, ahead of it.
Task ClosedTask(const GeneratedPathTask& generated, bool free_timing) {
  std::vector<Eigen::Vector2d> points = generated.points;
  std::vector<double> angles = generated.input_angles;
  points.push_back(points.front());
  angles.push_back(ClosingInputAngle(angles));
  Task task = testing::ReadRounded(
      testing::PathText(points, free_timing ? std::vector<double>() : angles, kClosedDigits));
  task.constraints.min_transmission_angle_deg = 0.0;
  return task;
}

bool SaysClosed(const PathResult& result) {
  return std::any_of(result.notes.begin(), result.notes.end(), [](const std::string& note) {
    return note.find("solved as a closed path") != std::string::npos;
  });
}

TEST(ClosedPath, CrankRockerCurveComesBackWithTheCrankTurningFully) {
  std::mt19937_64 rng(kSeed + 40);
  for (int t = 0; t < 4; ++t) {
    const double direction = t % 2 == 0 ? 1.0 : -1.0;
    const GeneratedPathTask generated = DrawClosed(rng, true, kClosedPoints, direction);
    const double length = PathLength(generated.points);
    for (bool free_timing : {false, true}) {
      SCOPED_TRACE("seed " + std::to_string(kSeed + 40) + ", task " + std::to_string(t) +
                   (free_timing ? ", free timing" : ", prescribed timing"));
      const Task task = ClosedTask(generated, free_timing);
      ASSERT_TRUE(task.closed);
      ASSERT_EQ(task.points.size(), generated.points.size());
      const PathResult result = SolvePathTask(task);
      EXPECT_TRUE(result.closed);
      EXPECT_TRUE(SaysClosed(result));
      ASSERT_FALSE(result.mechanisms.empty());
      const PathMechanismReport& first = result.mechanisms.front();
      EXPECT_TRUE(first.defects.empty());
      EXPECT_TRUE(first.input_rotates_fully);
      ASSERT_TRUE(first.max_point_error);
      EXPECT_LE(*first.max_point_error, kClosedFit * length);
      if (free_timing) {
        // The fitted angles turn one way and span less than a turn.
        const std::vector<double>& angles = first.input_angles;
        ASSERT_EQ(angles.size(), generated.points.size());
        const double sign = angles.back() > angles.front() ? 1.0 : -1.0;
        for (size_t j = 1; j < angles.size(); ++j)
          EXPECT_GT(sign * (angles[j] - angles[j - 1]), 0.0);
        EXPECT_LT(sign * (angles.back() - angles.front()), 2.0 * kPi);
        continue;
      }
      // Prescribed: the same coupler curve with the same timing over the whole turn.
      std::vector<double> turn;
      for (int k = 0; k < 24; ++k) {
        turn.push_back(generated.input_angles[0] + direction * 2.0 * kPi * k / 24.0);
      }
      const std::vector<Eigen::Vector2d> expected = DrivenPoints(generated.four_bar, turn, length);
      const std::vector<Eigen::Vector2d> found = DrivenPoints(first.design, turn, length);
      ASSERT_EQ(found.size(), expected.size());
      for (size_t k = 0; k < found.size(); ++k) {
        EXPECT_LE((found[k] - expected[k]).norm(), kSameCurve * length) << "angle " << k;
      }
    }
  }
}

TEST(ClosedPath, LimitedInputIsABranchDefect) {
  std::mt19937_64 rng(kSeed + 41);
  for (int t = 0; t < 4; ++t) {
    SCOPED_TRACE("seed " + std::to_string(kSeed + 41) + ", task " + std::to_string(t));
    const GeneratedPathTask generated = DrawClosed(rng, false, 7, 1.0);
    const double length = PathLength(generated.points);
    const Task task = ClosedTask(generated, false);
    ASSERT_TRUE(task.closed);
    const PathResult result = SolvePathTask(task);
    EXPECT_TRUE(SaysClosed(result));
    // The generating four-bar meets the points but cannot close the path.
    PathAnalysisOptions closed;
    closed.closed = true;
    const PathFourBarAnalysis analysis = AnalyzePathFourBar(generated.four_bar, generated.points,
                                                            generated.input_angles, length, closed);
    ASSERT_TRUE(analysis.max_point_error);
    EXPECT_LE(*analysis.max_point_error, 1e-9 * length);
    EXPECT_EQ(analysis.defects, std::vector<std::string>{"branch"});
    for (const PathMechanismReport& mechanism : result.mechanisms) {
      // A crank that cannot turn fully cannot close the path (the generating four-bar among
      // them, when it is reported).
      if (!mechanism.input_rotates_fully) {
        EXPECT_FALSE(mechanism.defects.empty());
      }
      if (PathFourBarDistance(mechanism.design, generated.four_bar, length) <= 1e-6) {
        EXPECT_EQ(mechanism.defects, std::vector<std::string>{"branch"});
      }
    }
  }
}

}  // namespace
}  // namespace linkfit
