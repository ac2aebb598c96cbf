// Tests of optimizers/global_search.h: the NLopt search for planar dyads over the pivot box.
// Each test draws a random mechanism (seeds fixed, printed on failure), makes its task, searches
// and requires the generating dyads back after the polish; then spoils the algebraic seeds,
// repeats a run, bounds its time, rescales the data and feeds bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fitting/planar_burmester.h"
#include "lib/four_bar_motion.h"
#include "optimizers/global_search.h"
#include "optimizers/planar_dyad_refiner.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

using testing::DyadScale;
using testing::GeneratedTask;
using testing::NearestDyadDistance;

constexpr std::uint64_t kSeed = 20240717;  // every random test here starts from kSeed + k
// A generating dyad found after the polish, relative to its DyadScale (exact data).
constexpr double kRecovered = 1e-8;
// Tasks are drawn with their generating pivots inside this share of the search box: the search
// looks only there (pivots farther out are reached only when the polish walks out to them).
constexpr double kInsideBox = 0.9;
// Evaluations per dyad type: enough for every algorithm to find both generating dyads of the
// tasks below (measured: all of 45 ten-pose and 50 fifty-pose in-box tasks at 20000).
constexpr int kBudget = 20000;
constexpr double kGenerousTime = 30.0;   // seconds: never the binding limit in these tests
constexpr double kRelativeCost = 1e-9;   // reported vs recomputed cost; a cost compared to another
constexpr double kSpoiledWeight = 1e-8;  // weight of the corrupted poses of the spoiled tasks
// Costs are compared to rounding: residuals of this times L are noise (an exact fit's are ~1e-15).
constexpr double kResidualNoise = 1e-12;

const std::vector<GlobalAlgorithm> kAlgorithms = {GlobalAlgorithm::kCrs2, GlobalAlgorithm::kMlsl,
                                                  GlobalAlgorithm::kIsres,
                                                  GlobalAlgorithm::kDirect};

std::string Trace(std::uint64_t seed, const std::string& what) {
  return "seed " + std::to_string(seed) + ", " + what;
}

Eigen::Vector2d Centroid(const std::vector<PlanarPose>& poses) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  return centroid / static_cast<double>(poses.size());
}

// Whether the search's coordinates of `dyad` lie in `share` of the box of half-width
// box_scale * L: F about the pose-origin centroid, M about E's origin (a line's angle always
// does).
bool InsideBox(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses, double box_scale,
               double share) {
  const double half_width = share * box_scale * CharacteristicLength(poses);
  const Eigen::Vector2d centroid = Centroid(poses);
  if (dyad.type != DyadType::kPR &&
      (dyad.fixed_pivot - centroid).cwiseAbs().maxCoeff() > half_width) {
    return false;
  }
  return dyad.type == DyadType::kRP || dyad.moving_pivot.cwiseAbs().maxCoeff() <= half_width;
}

// `count` poses of a random mechanism whose both dyads lie inside the search box. Up to ten
// poses come from testing::RandomTask; more are spread evenly along the longest circuit of the
// traced motion (RandomTask's random steps would come back to poses already taken).
GeneratedTask InBoxTask(std::mt19937_64& rng, DyadType output, int count) {
  const double box_scale = GlobalSearchOptions().box_scale;
  while (true) {
    GeneratedTask task = testing::RandomTask(rng, DyadType::kRR, output, std::min(count, 10));
    if (count > 10) {
      const FourBarMotion motion =
          TraceFourBar(task.input, task.output, task.poses, CharacteristicLength(task.poses));
      const FourBarCircuit* longest = nullptr;
      for (const FourBarCircuit& circuit : motion.circuits) {
        if (longest == nullptr || circuit.samples.size() > longest->samples.size()) {
          longest = &circuit;
        }
      }
      if (longest == nullptr || static_cast<int>(longest->samples.size()) < 2 * count) continue;
      task.poses.clear();
      for (int i = 0; i < count; ++i) {
        task.poses.push_back(longest->samples[i * longest->samples.size() / count].coupler);
      }
    }
    if (InsideBox(task.input, task.poses, box_scale, kInsideBox) &&
        InsideBox(task.output, task.poses, box_scale, kInsideBox)) {
      return task;
    }
  }
}

// 1/2 sum w e^2 of a dyad (weights may be empty).
double Cost(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
            const std::vector<double>& weights) {
  double cost = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double residual = dyad.Residual(poses[j]);
    cost += 0.5 * (weights.empty() ? 1.0 : weights[j]) * residual * residual;
  }
  return cost;
}

GlobalSearchOptions BudgetOptions(GlobalAlgorithm algorithm) {
  GlobalSearchOptions options;
  options.algorithm = algorithm;
  options.max_evaluations = kBudget;
  options.time_limit = kGenerousTime;
  return options;
}

// What every search returns: finite dyads, best first, the summary consistent with them.
void ExpectWellFormed(const std::vector<PlanarDyad>& dyads, const GlobalSearchSummary& summary,
                      const GlobalSearchOptions& options, const std::vector<PlanarPose>& poses,
                      const std::vector<double>& weights) {
  EXPECT_EQ(summary.algorithm, GlobalAlgorithmName(options.algorithm));
  EXPECT_GT(summary.evaluations, 0);
  EXPECT_LE(summary.evaluations, static_cast<int>(options.types.size()) * options.max_evaluations);
  EXPECT_TRUE(std::isfinite(summary.seconds) && summary.seconds >= 0.0);
  ASSERT_FALSE(dyads.empty());
  const double noise = kResidualNoise * CharacteristicLength(poses);
  const double cost_noise = 0.5 * noise * noise * static_cast<double>(poses.size());
  double previous = 0.0;
  for (const PlanarDyad& dyad : dyads) {
    EXPECT_TRUE(dyad.fixed_pivot.allFinite() && dyad.moving_pivot.allFinite() &&
                std::isfinite(dyad.radius) && dyad.line_point.allFinite() &&
                dyad.line_direction.allFinite());
    const double cost = Cost(dyad, poses, weights);
    EXPECT_GE(cost, previous * (1.0 - kRelativeCost) - cost_noise) << "not sorted by cost";
    previous = cost;
  }
  const double best = Cost(dyads.front(), poses, weights);
  EXPECT_NEAR(summary.best_cost, best, kRelativeCost * best + cost_noise);
}

std::vector<PlanarDyad> Search(const std::vector<PlanarPose>& poses,
                               const std::vector<double>& weights,
                               const GlobalSearchOptions& options, GlobalSearchSummary* summary) {
  std::vector<PlanarDyad> dyads;
  const int count =
      SearchPlanarDyads(poses, weights, {}, CharacteristicLength(poses), options, &dyads, summary);
  EXPECT_EQ(count, static_cast<int>(dyads.size()));
  return dyads;
}

// Exact poses of random four-bars (10, and 50 spread along the motion): every algorithm returns
// both generating RR dyads after the polish.
TEST(GlobalSearch, ExactFourBarGivesBothGeneratingDyads) {
  for (int trial = 0; trial < 4; ++trial) {
    const std::uint64_t seed = kSeed + trial;
    const int count = trial < 3 ? 10 : 50;
    std::mt19937_64 rng(seed);
    const GeneratedTask task = InBoxTask(rng, DyadType::kRR, count);
    for (GlobalAlgorithm algorithm : kAlgorithms) {
      SCOPED_TRACE(
          Trace(seed, std::to_string(count) + " poses, " + GlobalAlgorithmName(algorithm)));
      const GlobalSearchOptions options = BudgetOptions(algorithm);
      GlobalSearchSummary summary;
      const std::vector<PlanarDyad> dyads = Search(task.poses, {}, options, &summary);
      ExpectWellFormed(dyads, summary, options, task.poses, {});
      EXPECT_LE(NearestDyadDistance(dyads, task.input, DyadScale(task.input, task.poses)),
                kRecovered);
      EXPECT_LE(NearestDyadDistance(dyads, task.output, DyadScale(task.output, task.poses)),
                kRecovered);
    }
  }
}

// Slider-crank data: the slider comes back as a PR dyad (DyadDistance of another type is
// infinite), the crank as RR; inverted slider-crank data: the RP dyad as RP.
TEST(GlobalSearch, SlidersAreFoundAsSliders) {
  for (int trial = 0; trial < 4; ++trial) {
    const std::uint64_t seed = kSeed + 100 + trial;
    const DyadType output = trial % 2 == 0 ? DyadType::kPR : DyadType::kRP;
    std::mt19937_64 rng(seed);
    const GeneratedTask task = InBoxTask(rng, output, 10);
    for (GlobalAlgorithm algorithm : kAlgorithms) {
      SCOPED_TRACE(
          Trace(seed, std::string(DyadTypeName(output)) + ", " + GlobalAlgorithmName(algorithm)));
      const GlobalSearchOptions options = BudgetOptions(algorithm);
      GlobalSearchSummary summary;
      const std::vector<PlanarDyad> dyads = Search(task.poses, {}, options, &summary);
      ExpectWellFormed(dyads, summary, options, task.poses, {});
      EXPECT_LE(NearestDyadDistance(dyads, task.output, DyadScale(task.output, task.poses)),
                kRecovered);
      EXPECT_LE(NearestDyadDistance(dyads, task.input, DyadScale(task.input, task.poses)),
                kRecovered);
    }
  }
}

struct SpoiledTask : GeneratedTask {
  std::vector<double> weights;
};

// Twelve poses of a four-bar, four of them moved kFarOff * L and turned by up to pi, with weight
// kSpoiledWeight; drawn again until the generating dyads lie inside the search box.
SpoiledTask DrawSpoiledTask(std::mt19937_64& rng) {
  constexpr double kFarOff = 2.0;
  const double box_scale = GlobalSearchOptions().box_scale;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  while (true) {
    SpoiledTask task;
    static_cast<GeneratedTask&>(task) = testing::RandomFourBarTask(rng, 12);
    const double original_length = CharacteristicLength(task.poses);
    task.weights.assign(task.poses.size(), 1.0);
    for (int j = 1; j < 9; j += 2) {
      const double angle = M_PI * uniform(rng);
      task.poses[j].origin_in_fixed +=
          kFarOff * original_length * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      task.poses[j].theta = WrapAngle(task.poses[j].theta + M_PI * uniform(rng));
      task.weights[j] = kSpoiledWeight;
    }
    if (InsideBox(task.input, task.poses, box_scale, kInsideBox) &&
        InsideBox(task.output, task.poses, box_scale, kInsideBox)) {
      return task;
    }
  }
}

// Twelve poses of a four-bar, four of them replaced by poses far off (a robust fit has weighted
// them down to kSpoiledWeight). The algebraic least-squares fit (SolvePlanarBurmester) does not
// weigh poses, so the bad poses spoil its seeds, and RefinePlanarDyad started from them can stay
// in a poor local minimum. The search reaches the weighted optimum next to the generating dyads
// (the refinement of the generating dyads) in every task and never does worse than the refined
// seeds; where the seeds land in a poor minimum it beats them by orders of magnitude. Measured
// on these seeds: 3 of the 10 tasks (7 of 30 with seeds 200..229; 2 more had no real seed).
TEST(GlobalSearch, BeatsTheAlgebraicSeedsWhenDownWeightedPosesSpoilThem) {
  constexpr int kTasks = 10;
  constexpr double kMuchBetter = 100.0;  // "beats": a cost this many times lower
  constexpr int kMinBeaten = 2;          // of the tasks with seeds (measured: 3)
  int beaten = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    const std::uint64_t seed = kSeed + 200 + trial;
    SCOPED_TRACE(Trace(seed, "spoiled seeds"));
    std::mt19937_64 rng(seed);
    const SpoiledTask task = DrawSpoiledTask(rng);
    const std::vector<double>& weights = task.weights;
    const double length = CharacteristicLength(task.poses);

    std::vector<PlanarDyad> seeds;
    SolvePlanarBurmester(task.poses, {}, &seeds);
    double seeded = std::numeric_limits<double>::infinity();
    for (PlanarDyad dyad : seeds) {
      seeded =
          std::min(seeded, RefinePlanarDyad(task.poses, weights, {}, length, &dyad).final_cost);
    }
    double reference = std::numeric_limits<double>::infinity();
    for (PlanarDyad dyad : {task.input, task.output}) {
      reference =
          std::min(reference, RefinePlanarDyad(task.poses, weights, {}, length, &dyad).final_cost);
    }

    const GlobalSearchOptions options = BudgetOptions(GlobalAlgorithm::kCrs2);
    GlobalSearchSummary summary;
    const std::vector<PlanarDyad> dyads = Search(task.poses, weights, options, &summary);
    ExpectWellFormed(dyads, summary, options, task.poses, weights);
    EXPECT_LE(summary.best_cost, reference * (1.0 + kRelativeCost));
    EXPECT_LE(summary.best_cost, seeded * (1.0 + kRelativeCost));
    if (!seeds.empty() && summary.best_cost * kMuchBetter < seeded) ++beaten;
    std::printf("[ spoiled  ] seed %llu: %zu seeds, refined seeds %.3e, search %.3e\n",
                static_cast<unsigned long long>(seed), seeds.size(), seeded, summary.best_cost);
  }
  EXPECT_GE(beaten, kMinBeaten);
}

// Noisy poses, two of them marked exact: the search weighs them up and the polish meets them, so
// the best dyad passes through them to the refiner's exact tolerance.
TEST(GlobalSearch, ExactPosesAreMet) {
  constexpr double kNoise = 1e-3;          // pose noise: L in translation, rad in rotation
  constexpr double kExactResidual = 1e-9;  // PlanarDyadRefinerOptions::exact_tolerance, in L
  const std::uint64_t seed = kSeed + 250;
  std::mt19937_64 rng(seed);
  GeneratedTask task = InBoxTask(rng, DyadType::kRR, 10);
  std::normal_distribution<double> normal(0.0, kNoise);
  const double length = CharacteristicLength(task.poses);
  std::vector<bool> exact(task.poses.size(), false);
  exact[2] = exact[7] = true;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    if (exact[j]) continue;
    task.poses[j].origin_in_fixed += length * Eigen::Vector2d(normal(rng), normal(rng));
    task.poses[j].theta += normal(rng);
  }
  for (GlobalAlgorithm algorithm : kAlgorithms) {
    SCOPED_TRACE(Trace(seed, GlobalAlgorithmName(algorithm)));
    std::vector<PlanarDyad> dyads;
    GlobalSearchSummary summary;
    SearchPlanarDyads(task.poses, {}, exact, length, BudgetOptions(algorithm), &dyads, &summary);
    ASSERT_FALSE(dyads.empty());
    EXPECT_LE(std::abs(dyads.front().Residual(task.poses[2])), kExactResidual * length);
    EXPECT_LE(std::abs(dyads.front().Residual(task.poses[7])), kExactResidual * length);
  }
}

// The same options give the same dyads, bit for bit, and the same evaluation count (a run bound
// by its evaluations, not by the clock).
TEST(GlobalSearch, SameSeedSameResult) {
  const std::uint64_t seed = kSeed + 300;
  std::mt19937_64 rng(seed);
  const GeneratedTask task = InBoxTask(rng, DyadType::kRR, 10);
  for (GlobalAlgorithm algorithm : kAlgorithms) {
    SCOPED_TRACE(Trace(seed, GlobalAlgorithmName(algorithm)));
    GlobalSearchOptions options = BudgetOptions(algorithm);
    options.seed = 7;
    GlobalSearchSummary first_summary, second_summary;
    const std::vector<PlanarDyad> first = Search(task.poses, {}, options, &first_summary);
    const std::vector<PlanarDyad> second = Search(task.poses, {}, options, &second_summary);
    EXPECT_EQ(first_summary.evaluations, second_summary.evaluations);
    EXPECT_EQ(first_summary.best_cost, second_summary.best_cost);
    ASSERT_EQ(first.size(), second.size());
    for (size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ(first[i].type, second[i].type);
      EXPECT_EQ(first[i].fixed_pivot, second[i].fixed_pivot);
      EXPECT_EQ(first[i].moving_pivot, second[i].moving_pivot);
      EXPECT_EQ(first[i].radius, second[i].radius);
      EXPECT_EQ(first[i].line_point, second[i].line_point);
      EXPECT_EQ(first[i].line_direction, second[i].line_direction);
    }
  }
}

// With an evaluation budget far beyond what the clock allows, a run over the three types with
// time_limit 0.05 s (per type) ends in about 3 x 0.05 s, polish included, and still returns
// dyads.
TEST(GlobalSearch, HonoursTheTimeLimit) {
  constexpr double kTimeLimit = 0.05;
  constexpr double kSlack = 0.05;  // seconds for the polish and the bookkeeping
  const std::uint64_t seed = kSeed + 400;
  std::mt19937_64 rng(seed);
  const GeneratedTask task = InBoxTask(rng, DyadType::kRR, 50);
  for (GlobalAlgorithm algorithm : kAlgorithms) {
    SCOPED_TRACE(Trace(seed, GlobalAlgorithmName(algorithm)));
    GlobalSearchOptions options;
    options.algorithm = algorithm;
    options.max_evaluations = 1000000000;
    options.time_limit = kTimeLimit;
    GlobalSearchSummary summary;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<PlanarDyad> dyads = Search(task.poses, {}, options, &summary);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_FALSE(dyads.empty());
    EXPECT_LE(seconds, options.types.size() * kTimeLimit + kSlack);
    EXPECT_LE(summary.seconds, seconds);
  }
}

// The answer does not depend on units or on where the fixed frame is: the same task in
// millimetres, moved far off, gives the generating dyads in millimetres.
TEST(GlobalSearch, UnitsAndFrameDoNotMatter) {
  constexpr double kScale = 1000.0;
  const Eigen::Vector2d kShift(2.5e4, -4.0e3);
  const std::uint64_t seed = kSeed + 500;
  std::mt19937_64 rng(seed);
  const GeneratedTask task = InBoxTask(rng, DyadType::kRR, 10);
  std::vector<PlanarPose> moved = task.poses;
  for (PlanarPose& pose : moved) pose.origin_in_fixed = kScale * pose.origin_in_fixed + kShift;
  Similarity2 sigma, epsilon;
  sigma.scale = epsilon.scale = kScale;
  sigma.translation = kShift;
  for (const PlanarDyad& expected : {task.input, task.output}) {
    const PlanarDyad moved_expected = TransformDyad(expected, sigma, epsilon);
    SCOPED_TRACE(Trace(seed, "moved task"));
    GlobalSearchSummary summary;
    const std::vector<PlanarDyad> dyads =
        Search(moved, {}, BudgetOptions(GlobalAlgorithm::kCrs2), &summary);
    EXPECT_LE(NearestDyadDistance(dyads, moved_expected, DyadScale(moved_expected, moved)),
              kRecovered);
  }
}

// Bad input throws std::invalid_argument; no poses give no dyads; a degenerate task (pure
// translations: every point of E moves on the same path) returns finite dyads, never NaN.
TEST(GlobalSearch, BadInputAndDegenerateTasks) {
  const std::vector<PlanarPose> poses = {{0.0, 0.0, 0.1},  {1.0, 0.2, 0.5},   {0.3, 1.1, 0.9},
                                         {-0.7, 0.4, 1.4}, {-0.2, -0.9, 2.0}, {0.8, -0.6, 2.6}};
  GlobalSearchOptions options;
  options.max_evaluations = 2000;
  std::vector<PlanarDyad> dyads;
  EXPECT_THROW(SearchPlanarDyads(poses, {}, {}, 0.0, options, &dyads), std::invalid_argument);
  EXPECT_THROW(SearchPlanarDyads(poses, {}, {}, std::nan(""), options, &dyads),
               std::invalid_argument);
  EXPECT_THROW(SearchPlanarDyads(poses, {1.0, 2.0}, {}, 1.0, options, &dyads),
               std::invalid_argument);
  EXPECT_THROW(
      SearchPlanarDyads(poses, std::vector<double>(poses.size(), -1.0), {}, 1.0, options, &dyads),
      std::invalid_argument);
  EXPECT_THROW(SearchPlanarDyads(poses, {}, {true}, 1.0, options, &dyads), std::invalid_argument);
  std::vector<PlanarPose> infinite = poses;
  infinite[2].theta = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SearchPlanarDyads(infinite, {}, {}, 1.0, options, &dyads), std::invalid_argument);
  GlobalSearchOptions no_box = options;
  no_box.box_scale = 0.0;
  EXPECT_THROW(SearchPlanarDyads(poses, {}, {}, 1.0, no_box, &dyads), std::invalid_argument);

  GlobalSearchSummary summary;
  EXPECT_EQ(SearchPlanarDyads({}, {}, {}, 1.0, options, &dyads, &summary), 0);
  EXPECT_TRUE(dyads.empty());
  EXPECT_EQ(summary.algorithm, "crs2");

  std::vector<PlanarPose> translations = poses;
  for (PlanarPose& pose : translations) pose.theta = 0.3;
  for (GlobalAlgorithm algorithm : kAlgorithms) {
    SCOPED_TRACE(GlobalAlgorithmName(algorithm));
    options.algorithm = algorithm;
    SearchPlanarDyads(translations, {}, {}, CharacteristicLength(translations), options, &dyads,
                      &summary);
    EXPECT_TRUE(std::isfinite(summary.best_cost));
    for (const PlanarDyad& dyad : dyads) {
      EXPECT_TRUE(dyad.fixed_pivot.allFinite() && dyad.moving_pivot.allFinite() &&
                  std::isfinite(dyad.radius) && dyad.line_point.allFinite() &&
                  dyad.line_direction.allFinite());
    }
  }
}

}  // namespace
}  // namespace linkfit
