// Tests of optimizers/four_bar_refiner.h: mechanism-level least squares of a planar four-bar on
// the design's pose error. Each test draws a random four-bar, makes poses it reaches on one
// branch (exact or noisy), refines a perturbed seed and requires the generating four-bar (or a
// fit at least as good as it) back, on one circuit; then re-refines, feeds seeds that do not
// assemble, marks poses exact and changes the units.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"
#include "lib/planar_pose.h"
#include "optimizers/four_bar_refiner.h"
#include "tests/support/random_mechanism.h"

namespace {

using linkfit::AnalyzeFourBar;
using linkfit::AssembleFourBar;
using linkfit::CharacteristicLength;
using linkfit::DyadType;
using linkfit::DyadTypeName;
using linkfit::FourBarAnalysis;
using linkfit::FourBarCircuit;
using linkfit::FourBarLocation;
using linkfit::FourBarMotion;
using linkfit::FourBarSample;
using linkfit::PlanarDyad;
using linkfit::PlanarPose;
using linkfit::PoseError;
using linkfit::RefineFourBar;
using linkfit::RefinerSummary;
using linkfit::WrapAngle;
using linkfit::testing::DyadDistance;
using linkfit::testing::DyadScale;
using linkfit::testing::GeneratedTask;

constexpr std::uint64_t kSeed = 20240612;  // every random test here starts from kSeed + k
constexpr int kTrials = 6;
constexpr double kSeedOffset = 1e-2;          // every seed parameter moved by this, times L
constexpr double kExactPoseError = 1e-9;      // refined max pose error on exact data, times L
constexpr double kExactParameter = 1e-8;      // refined vs generating dyads on exact data, relative
constexpr double kRmsSlack = 1.0001;          // refined RMS vs the generator's on noisy poses
constexpr double kExactTolerance = 1e-9;      // poses marked exact, times L
constexpr double kReportedAgreement = 1e-12;  // summary vs AnalyzeFourBar, relative
constexpr double kCostRounding = 1e-12;       // relative rounding allowed in a cost comparison
// The same noisy optimum reached twice (other units, a second refine): costs agree to rounding,
// parameters to about sqrt(machine epsilon) times the conditioning (the cost is flat about it).
constexpr double kSameCost = 1e-10;
constexpr double kSameOptimum = 1e-6;
// Generated tasks: at least this much input travel (radians, or L for a slider), and a limited
// input's branch trimmed by this share at either end (its limits are stationary configurations).
constexpr double kMinTravel = 1.0;
constexpr double kBranchTrim = 0.05;

std::string Trace(std::uint64_t seed, int trial, DyadType input, DyadType output, int count) {
  return "seed " + std::to_string(seed) + ", trial " + std::to_string(trial) + ", " +
         DyadTypeName(input) + "+" + DyadTypeName(output) + ", " + std::to_string(count) + " poses";
}

// A random four-bar of the given dyad types (RandomTask draws it) and `count` poses it reaches on
// the branch of its start configuration, at input values evenly spread over that branch (nine
// tenths of a turn for a crank; the branch less kBranchTrim at either end for a limited input):
// exact poses, in input order, on one branch, without a defect.
GeneratedTask TaskOnBranch(std::mt19937_64& rng, DyadType input, DyadType output, int count) {
  while (true) {
    GeneratedTask task = linkfit::testing::RandomTask(rng, input, output, 2);
    const std::vector<PlanarPose> start = {task.poses[0]};
    const FourBarMotion motion = linkfit::TraceFourBar(task.input, task.output, start, 1.0);
    const FourBarLocation location =
        linkfit::LocatePose(motion, task.input, task.output, task.poses[0], 1.0);
    if (location.circuit < 0) continue;
    const FourBarCircuit& circuit = motion.circuits[location.circuit];
    std::vector<double> values;  // input values along the branch, unwrapped
    for (const FourBarSample& sample : circuit.samples) {
      if (sample.branch != location.branch) continue;
      const double value = sample.input;
      values.push_back(values.empty() || input == DyadType::kPR
                           ? value
                           : values.back() + WrapAngle(value - values.back()));
    }
    if (values.size() < 10) continue;
    double first = values.front(), last = values.back();
    const double extent = last - first;
    if (circuit.input_rotates_fully) {
      last = first + 0.9 * extent;
    } else {
      first += kBranchTrim * extent;
      last -= kBranchTrim * extent;
    }
    if (!(std::abs(last - first) >= kMinTravel)) continue;
    const int label = circuit.label >= 0 ? circuit.label : location.branch;
    task.poses.clear();
    std::vector<PlanarPose> configurations;
    for (int j = 0; j < count; ++j) {
      const double value = first + (last - first) * j / (count - 1);
      if (AssembleFourBar(task.input, task.output, value, 0.0, &configurations) <= label) break;
      task.poses.push_back(configurations[label]);
    }
    if (static_cast<int>(task.poses.size()) != count) continue;
    const double length = CharacteristicLength(task.poses);
    if (!(length > 0.2)) continue;
    const FourBarAnalysis analysis = AnalyzeFourBar(task.input, task.output, task.poses, length);
    if (!analysis.defects.empty() || !analysis.max_pose_error ||
        *analysis.max_pose_error > 1e-12 * length) {
      continue;
    }
    return task;
  }
}

Eigen::Vector2d UnitVector(std::mt19937_64& rng) {
  const double angle = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
  return Eigen::Vector2d(std::cos(angle), std::sin(angle));
}
double Sign(std::mt19937_64& rng) { return std::bernoulli_distribution(0.5)(rng) ? 1.0 : -1.0; }

// Every parameter moved by `offset`: pivots in a random direction, the radius and the line's
// offset by +-offset, the line's direction by +-offset / L radians.
PlanarDyad Perturbed(std::mt19937_64& rng, const PlanarDyad& dyad, double offset, double length) {
  PlanarDyad seed = dyad;
  seed.fixed_pivot += offset * UnitVector(rng);
  seed.moving_pivot += offset * UnitVector(rng);
  seed.radius += offset * Sign(rng);
  const Eigen::Vector2d normal(-dyad.line_direction.y(), dyad.line_direction.x());
  seed.line_point += offset * Sign(rng) * normal;
  seed.line_direction = linkfit::Rotation2(Sign(rng) * offset / length) * dyad.line_direction;
  return seed;
}

// The generating four-bar with every parameter moved by kSeedOffset L (Perturbed), drawn again
// until it still assembles at the first pose (a seed that does not is returned unchanged, by
// contract; near a stationary configuration a 1e-2 L move can lose the assembly).
struct Seed {
  PlanarDyad input;
  PlanarDyad output;
};

Seed PerturbedSeed(std::mt19937_64& rng, const GeneratedTask& task,
                   const std::vector<PlanarPose>& poses, double length) {
  Seed seed;
  for (int attempt = 0; attempt < 100; ++attempt) {
    seed.input = Perturbed(rng, task.input, kSeedOffset * length, length);
    seed.output = Perturbed(rng, task.output, kSeedOffset * length, length);
    if (AnalyzeFourBar(seed.input, seed.output, poses, length).max_pose_error) break;
  }
  return seed;
}

// Each pose moved by N(0, sigma L) on each coordinate and N(0, sigma) on the angle.
std::vector<PlanarPose> Noisy(std::mt19937_64& rng, const std::vector<PlanarPose>& poses,
                              double sigma, double length) {
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<PlanarPose> noisy;
  for (const PlanarPose& pose : poses) {
    const double x = pose.origin_in_fixed.x() + length * normal(rng);
    const double y = pose.origin_in_fixed.y() + length * normal(rng);
    noisy.emplace_back(x, y, WrapAngle(pose.theta + normal(rng)));
  }
  return noisy;
}

// A four-bar's fit as AnalyzeFourBar sees it: pose errors of the poses on the first pose's
// circuit (a pose off it makes `one_circuit` false and counts with the analysis' max).
struct Fit {
  bool one_circuit = false;
  double rms = 0.0;   // sqrt(sum w e^2 / sum w)
  double cost = 0.0;  // 1/2 sum w e^2
  double max = 0.0;   // AnalyzeFourBar's max_pose_error
  std::vector<double> errors;
};

Fit Evaluate(const PlanarDyad& input, const PlanarDyad& output,
             const std::vector<PlanarPose>& poses, double length,
             const std::vector<double>& weights = {}) {
  const FourBarAnalysis analysis = AnalyzeFourBar(input, output, poses, length);
  Fit fit;
  if (!analysis.max_pose_error) {
    fit.rms = fit.cost = fit.max = std::numeric_limits<double>::infinity();
    return fit;
  }
  fit.max = *analysis.max_pose_error;
  fit.one_circuit = std::find(analysis.defects.begin(), analysis.defects.end(), "circuit") ==
                    analysis.defects.end();
  double sum = 0.0, weight_sum = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const FourBarLocation& location = analysis.locations[j];
    const double e = location.circuit == analysis.circuit ? location.pose_error : fit.max;
    const double w = weights.empty() ? 1.0 : weights[j];
    fit.errors.push_back(e);
    sum += w * e * e;
    weight_sum += w;
  }
  fit.cost = 0.5 * sum;
  fit.rms = std::sqrt(sum / weight_sum);
  return fit;
}

bool Near(double reported, double expected, double relative, double floor) {
  return std::abs(reported - expected) <= relative * std::abs(expected) + floor;
}

// The summary's final statistics agree with AnalyzeFourBar on the returned design.
void ExpectSummaryMatches(const RefinerSummary& summary, const PlanarDyad& input,
                          const PlanarDyad& output, const std::vector<PlanarPose>& poses,
                          double length, const std::vector<double>& weights = {}) {
  const Fit fit = Evaluate(input, output, poses, length, weights);
  ASSERT_TRUE(fit.one_circuit);
  const double floor = 1e-15 * length;
  EXPECT_PRED4(Near, summary.final_max, fit.max, kReportedAgreement, floor);
  EXPECT_PRED4(Near, summary.final_rms, fit.rms, kReportedAgreement, floor);
  EXPECT_PRED4(Near, summary.final_cost, fit.cost, kReportedAgreement, floor * floor);
}

double Distance(const PlanarDyad& found, const PlanarDyad& expected,
                const std::vector<PlanarPose>& poses) {
  return DyadDistance(found, expected, DyadScale(expected, poses));
}

struct Pair {
  DyadType input;
  DyadType output;
};
constexpr Pair kFourBar = {DyadType::kRR, DyadType::kRR};
constexpr Pair kSliderCrank = {DyadType::kRR, DyadType::kPR};

// PR+PR (Cardan motion: every point of the moving circle runs on a line) and RP+RP (its
// inverse) make their motion with a one-parameter family of dyad pairs: only the motion can be
// recovered.
bool DyadsIdentifiable(Pair pair) {
  return !(pair.input == pair.output && pair.input != DyadType::kRR);
}

void CheckExactRecovery(Pair pair, std::uint64_t seed, const std::vector<int>& counts) {
  std::mt19937_64 rng(seed);
  for (int count : counts) {
    for (int trial = 0; trial < kTrials; ++trial) {
      SCOPED_TRACE(Trace(seed, trial, pair.input, pair.output, count));
      const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, count);
      const double length = CharacteristicLength(task.poses);
      const Seed seed_design = PerturbedSeed(rng, task, task.poses, length);
      PlanarDyad input = seed_design.input, output = seed_design.output;
      const RefinerSummary summary = RefineFourBar(task.poses, {}, {}, length, &input, &output);
      SCOPED_TRACE(summary.message);
      EXPECT_EQ(input.type, pair.input);
      EXPECT_EQ(output.type, pair.output);
      EXPECT_LE(summary.final_max, kExactPoseError * length);
      EXPECT_LT(summary.final_cost, summary.initial_cost);
      if (DyadsIdentifiable(pair)) {
        EXPECT_LT(Distance(input, task.input, task.poses), kExactParameter);
        EXPECT_LT(Distance(output, task.output, task.poses), kExactParameter);
      }
      EXPECT_GT(summary.iterations, 0);
      ExpectSummaryMatches(summary, input, output, task.poses, length);
    }
  }
}

TEST(FourBarRefiner, RecoversExactFourBar) { CheckExactRecovery(kFourBar, kSeed, {6, 20, 50}); }

TEST(FourBarRefiner, RecoversExactSliderCrank) {
  CheckExactRecovery(kSliderCrank, kSeed + 1, {6, 20, 50});
}

// Every pair of dyad types, which exercises each assembly of the residuals (slider inputs, RP
// dyads).
TEST(FourBarRefiner, RecoversExactFourBarsOfEveryDyadPair) {
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  std::uint64_t seed = kSeed + 2;
  for (DyadType input : types) {
    for (DyadType output : types) {
      CheckExactRecovery({input, output}, seed++, {8, 30});
    }
  }
}

// A generator is a fair reference on noisy poses when it still reaches them on one branch and
// in order, and its pose errors stay within this many times the noise (sigma L per
// coordinate): the pose error is taken at the input value read off each pose, which a short
// crank, or a pin far from E's origin, can make far more sensitive to the noise than the poses.
constexpr double kFairNoiseGain = 10.0;

void CheckNoisyFit(Pair pair, std::uint64_t seed, double sigma) {
  std::mt19937_64 rng(seed);
  for (int count : {12, 40}) {
    int skipped = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
      SCOPED_TRACE(Trace(seed, trial, pair.input, pair.output, count));
      const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, count);
      const double length = CharacteristicLength(task.poses);
      const std::vector<PlanarPose> poses = Noisy(rng, task.poses, sigma, length);
      const Fit generator = Evaluate(task.input, task.output, poses, length);
      if (!AnalyzeFourBar(task.input, task.output, poses, length).defects.empty() ||
          generator.max > kFairNoiseGain * sigma * length) {
        ASSERT_LT(++skipped, 3 * kTrials) << "too many unfair generators";
        --trial;
        continue;
      }
      const Seed seed_design = PerturbedSeed(rng, task, poses, length);
      PlanarDyad input = seed_design.input, output = seed_design.output;
      const RefinerSummary summary = RefineFourBar(poses, {}, {}, length, &input, &output);
      SCOPED_TRACE(summary.message);
      const Fit refined = Evaluate(input, output, poses, length);
      EXPECT_TRUE(refined.one_circuit);
      EXPECT_LE(refined.rms, generator.rms * kRmsSlack);
      EXPECT_LE(summary.final_rms, generator.rms * kRmsSlack);
      EXPECT_LE(summary.final_cost, summary.initial_cost);
      ExpectSummaryMatches(summary, input, output, poses, length);
    }
  }
}

TEST(FourBarRefiner, NoisyFourBarFitsAtLeastAsWellAsItsGenerator) {
  CheckNoisyFit(kFourBar, kSeed + 20, 1e-3);
  CheckNoisyFit(kFourBar, kSeed + 21, 1e-2);
}

TEST(FourBarRefiner, NoisySliderCrankFitsAtLeastAsWellAsItsGenerator) {
  CheckNoisyFit(kSliderCrank, kSeed + 22, 1e-3);
  CheckNoisyFit(kSliderCrank, kSeed + 23, 1e-2);
}

// Whether a refine ended at a local minimum: not stopped by max_iterations while creeping along
// a valley toward a degenerate four-bar (a crank running off toward a slider), nor short of
// coincident dyads (toward which the cost on noisy poses can keep falling). Where it did not,
// the design it returns is where it stopped, and another start or other units stop elsewhere.
bool Converged(const RefinerSummary& summary) {
  return summary.message.find("Maximum number of iterations") == std::string::npos &&
         summary.message.find("short of coincident") == std::string::npos;
}

// A second refine of a refined design does not make it worse, and where the first one converged
// it returns the same design.
TEST(FourBarRefiner, AlreadyRefinedDesignStays) {
  const std::uint64_t seed = kSeed + 30;
  std::mt19937_64 rng(seed);
  int converged = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Pair pair = trial % 2 == 0 ? kFourBar : kSliderCrank;
    SCOPED_TRACE(Trace(seed, trial, pair.input, pair.output, 20));
    const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, 20);
    const double length = CharacteristicLength(task.poses);
    const std::vector<PlanarPose> poses = Noisy(rng, task.poses, 1e-2, length);
    const Seed seed_design = PerturbedSeed(rng, task, poses, length);
    PlanarDyad input = seed_design.input, output = seed_design.output;
    const RefinerSummary first = RefineFourBar(poses, {}, {}, length, &input, &output);
    PlanarDyad input_again = input, output_again = output;
    const RefinerSummary again = RefineFourBar(poses, {}, {}, length, &input_again, &output_again);
    SCOPED_TRACE(first.message + " / " + again.message);
    EXPECT_LE(again.final_cost, first.final_cost * (1.0 + kCostRounding));
    EXPECT_PRED4(Near, again.initial_cost, first.final_cost, kCostRounding, 0.0);
    EXPECT_FALSE(again.model_changed);
    if (!Converged(first)) continue;
    ++converged;
    EXPECT_LT(Distance(input_again, input, poses), kSameOptimum);
    EXPECT_LT(Distance(output_again, output, poses), kSameOptimum);
  }
  EXPECT_GE(converged, kTrials / 2);
}

// Two copies of one dyad are no four-bar (the coupler keeps a second freedom): returned as given.
TEST(FourBarRefiner, CoincidentDyadsAreReturnedUnchanged) {
  std::mt19937_64 rng(kSeed + 34);
  const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kRR, 10);
  const double length = CharacteristicLength(task.poses);
  PlanarDyad input = task.input, output = task.input;
  const RefinerSummary summary = RefineFourBar(task.poses, {}, {}, length, &input, &output);
  EXPECT_NE(summary.message.find("coincide"), std::string::npos) << summary.message;
  EXPECT_EQ(output.fixed_pivot, task.input.fixed_pivot);
  EXPECT_EQ(output.moving_pivot, task.input.moving_pivot);
  EXPECT_EQ(output.radius, task.input.radius);
}

TEST(FourBarRefiner, SeedThatDoesNotAssembleIsReturnedUnchanged) {
  const std::uint64_t seed = kSeed + 31;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, DyadType::kRR, 10));
    const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kRR, 10);
    const double length = CharacteristicLength(task.poses);
    // An output crank far too long to close the loop anywhere.
    PlanarDyad input = task.input, output = task.output;
    output.radius = 100.0 * length;
    const PlanarDyad input_seed = input, output_seed = output;
    const RefinerSummary summary = RefineFourBar(task.poses, {}, {}, length, &input, &output);
    EXPECT_NE(summary.message.find("assemble"), std::string::npos) << summary.message;
    EXPECT_EQ(input.fixed_pivot, input_seed.fixed_pivot);
    EXPECT_EQ(input.moving_pivot, input_seed.moving_pivot);
    EXPECT_EQ(input.radius, input_seed.radius);
    EXPECT_EQ(output.fixed_pivot, output_seed.fixed_pivot);
    EXPECT_EQ(output.moving_pivot, output_seed.moving_pivot);
    EXPECT_EQ(output.radius, output_seed.radius);
    EXPECT_FALSE(std::isnan(summary.final_cost));
    EXPECT_FALSE(std::isnan(summary.final_rms));
    EXPECT_FALSE(std::isnan(summary.final_max));
  }
}

TEST(FourBarRefiner, NonFiniteSeedIsReturnedUnchanged) {
  std::mt19937_64 rng(kSeed + 32);
  const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kPR, 10);
  const double length = CharacteristicLength(task.poses);
  PlanarDyad input = task.input, output = task.output;
  input.radius = std::numeric_limits<double>::quiet_NaN();
  const RefinerSummary summary = RefineFourBar(task.poses, {}, {}, length, &input, &output);
  EXPECT_TRUE(std::isnan(input.radius));
  EXPECT_EQ(output.line_point, task.output.line_point);
  EXPECT_FALSE(summary.message.empty());
  EXPECT_FALSE(std::isnan(summary.final_cost));
}

TEST(FourBarRefiner, RejectsBadArguments) {
  std::mt19937_64 rng(kSeed + 33);
  const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kRR, 8);
  PlanarDyad input = task.input, output = task.output;
  EXPECT_THROW(RefineFourBar(task.poses, {}, {}, 0.0, &input, &output), std::invalid_argument);
  EXPECT_THROW(RefineFourBar(task.poses, {1.0}, {}, 1.0, &input, &output), std::invalid_argument);
  EXPECT_THROW(RefineFourBar(task.poses, {}, {true}, 1.0, &input, &output), std::invalid_argument);
  std::vector<double> weights(task.poses.size(), 1.0);
  weights[2] = -1.0;
  EXPECT_THROW(RefineFourBar(task.poses, weights, {}, 1.0, &input, &output), std::invalid_argument);
}

// Two poses marked exact are met to kExactTolerance L on noisy data, on one circuit.
TEST(FourBarRefiner, ExactPosesAreMet) {
  const std::uint64_t seed = kSeed + 40;
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 2 * kTrials; ++trial) {
    const Pair pair = trial % 2 == 0 ? kFourBar : kSliderCrank;
    const int count = 15;
    SCOPED_TRACE(Trace(seed, trial, pair.input, pair.output, count));
    const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, count);
    const double length = CharacteristicLength(task.poses);
    const std::vector<PlanarPose> poses = Noisy(rng, task.poses, 1e-2, length);
    std::vector<bool> exact(count, false);
    exact[0] = exact[count / 2] = true;
    const Seed seed_design = PerturbedSeed(rng, task, poses, length);
    PlanarDyad input = seed_design.input, output = seed_design.output;
    const RefinerSummary summary = RefineFourBar(poses, {}, exact, length, &input, &output);
    SCOPED_TRACE(summary.message);
    const Fit fit = Evaluate(input, output, poses, length);
    EXPECT_TRUE(fit.one_circuit);
    EXPECT_LE(fit.errors[0], kExactTolerance * length);
    EXPECT_LE(fit.errors[count / 2], kExactTolerance * length);
    ExpectSummaryMatches(summary, input, output, poses, length);
  }
}

// Weights count as given: a weighted refine reports 1/2 sum w e^2 and beats the generator on it.
TEST(FourBarRefiner, WeightsEnterTheCost) {
  const std::uint64_t seed = kSeed + 41;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> weight(0.2, 5.0);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(Trace(seed, trial, DyadType::kRR, DyadType::kRR, 20));
    const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kRR, 20);
    const double length = CharacteristicLength(task.poses);
    const std::vector<PlanarPose> poses = Noisy(rng, task.poses, 1e-2, length);
    std::vector<double> weights;
    for (size_t j = 0; j < poses.size(); ++j) weights.push_back(weight(rng));
    const Seed seed_design = PerturbedSeed(rng, task, poses, length);
    PlanarDyad input = seed_design.input, output = seed_design.output;
    const RefinerSummary summary = RefineFourBar(poses, weights, {}, length, &input, &output);
    SCOPED_TRACE(summary.message);
    const Fit generator = Evaluate(task.input, task.output, poses, length, weights);
    EXPECT_LE(summary.final_cost, generator.cost * kRmsSlack);
    ExpectSummaryMatches(summary, input, output, poses, length, weights);
  }
}

PlanarDyad Scaled(const PlanarDyad& dyad, double scale) {
  linkfit::Similarity2 similarity;
  similarity.scale = scale;
  return linkfit::TransformDyad(dyad, similarity, similarity);
}

// The same noisy task (sigma 1e-3) in other units (times 1e-3 and 1e3) gives the same design,
// scaled, and costs times scale^2 (where the refine converged; see Converged).
TEST(FourBarRefiner, ResultDoesNotDependOnUnits) {
  const std::uint64_t seed = kSeed + 50;
  std::mt19937_64 rng(seed);
  int converged = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Pair pair = trial % 2 == 0 ? kFourBar : kSliderCrank;
    SCOPED_TRACE(Trace(seed, trial, pair.input, pair.output, 20));
    const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, 20);
    const double length = CharacteristicLength(task.poses);
    const std::vector<PlanarPose> poses = Noisy(rng, task.poses, 1e-3, length);
    const Seed seed_design = PerturbedSeed(rng, task, poses, length);
    const PlanarDyad input_seed = seed_design.input, output_seed = seed_design.output;
    PlanarDyad input = input_seed, output = output_seed;
    const RefinerSummary reference = RefineFourBar(poses, {}, {}, length, &input, &output);
    converged += Converged(reference);
    for (double scale : {1e-3, 1e3}) {
      SCOPED_TRACE("scale " + std::to_string(scale));
      std::vector<PlanarPose> scaled_poses;
      for (const PlanarPose& pose : poses) {
        scaled_poses.emplace_back(scale * pose.origin_in_fixed.x(),
                                  scale * pose.origin_in_fixed.y(), pose.theta);
      }
      PlanarDyad scaled_input = Scaled(input_seed, scale);
      PlanarDyad scaled_output = Scaled(output_seed, scale);
      const RefinerSummary summary =
          RefineFourBar(scaled_poses, {}, {}, scale * length, &scaled_input, &scaled_output);
      const double squared = scale * scale;
      EXPECT_PRED4(Near, summary.initial_cost / squared, reference.initial_cost, kSameCost, 0.0);
      EXPECT_LE(summary.final_cost, summary.initial_cost);
      if (!Converged(reference)) continue;
      EXPECT_PRED4(Near, summary.final_cost / squared, reference.final_cost, kSameCost, 0.0);
      EXPECT_PRED4(Near, summary.final_max / scale, reference.final_max, kSameOptimum, 0.0);
      EXPECT_LT(Distance(Scaled(scaled_input, 1.0 / scale), input, poses), kSameOptimum);
      EXPECT_LT(Distance(Scaled(scaled_output, 1.0 / scale), output, poses), kSameOptimum);
    }
  }
  EXPECT_GE(converged, kTrials / 2);
}

// Prints the median, 90th percentile and worst time per refine (noisy poses, sigma 1e-3 L, seeds
// 1e-2 L off).
TEST(FourBarRefiner, ReportsTimePerRefine) {
  const std::uint64_t seed = kSeed + 60;
  std::mt19937_64 rng(seed);
  constexpr int kRuns = 30;
  std::printf("%-6s %6s %10s %10s %10s %10s\n", "pair", "poses", "median_ms", "p90_ms", "worst_ms",
              "mean_iter");
  for (Pair pair : {kFourBar, kSliderCrank}) {
    for (int count : {10, 50, 200}) {
      std::vector<double> seconds;
      double iterations = 0.0;
      for (int run = 0; run < kRuns; ++run) {
        const GeneratedTask task = TaskOnBranch(rng, pair.input, pair.output, count);
        const double length = CharacteristicLength(task.poses);
        const std::vector<PlanarPose> poses = Noisy(rng, task.poses, 1e-3, length);
        const Seed seed_design = PerturbedSeed(rng, task, poses, length);
        PlanarDyad input = seed_design.input, output = seed_design.output;
        const RefinerSummary summary = RefineFourBar(poses, {}, {}, length, &input, &output);
        seconds.push_back(summary.seconds);
        iterations += summary.iterations;
      }
      std::sort(seconds.begin(), seconds.end());
      EXPECT_GT(seconds.front(), 0.0);
      const std::string name = std::string(DyadTypeName(pair.input)) + DyadTypeName(pair.output);
      std::printf("%-6s %6d %10.2f %10.2f %10.2f %10.1f\n", name.c_str(), count,
                  1e3 * seconds[kRuns / 2], 1e3 * seconds[kRuns * 9 / 10], 1e3 * seconds.back(),
                  iterations / kRuns);
    }
  }
}

// Held transmission angle (FourBarRefinerOptions::min_transmission_deg): exact poses of a 4R
// whose transmission angle over the motion dips to 8-25 degrees, refined from the generator
// holding it 10 degrees higher. Without the option the generator is the optimum and stays;
// with it, the refined four-bar's transmission angle over the motion (AnalyzeFourBar, sampled
// finely, not the refiner's samples) is at least the one asked, and it still assembles on one
// circuit with a finite pose error.
TEST(FourBarRefiner, HeldTransmissionAngleIsKept) {
  const std::uint64_t seed = kSeed + 90;
  std::mt19937_64 rng(seed);
  int tried = 0;
  for (int draw = 0; draw < 400 && tried < kTrials; ++draw) {
    const GeneratedTask task = TaskOnBranch(rng, DyadType::kRR, DyadType::kRR, 10);
    const double length = CharacteristicLength(task.poses);
    const FourBarAnalysis generator = AnalyzeFourBar(task.input, task.output, task.poses, length);
    if (!generator.transmission_min_deg || *generator.transmission_min_deg < 8.0 ||
        *generator.transmission_min_deg > 25.0) {
      continue;
    }
    SCOPED_TRACE(Trace(seed, draw, DyadType::kRR, DyadType::kRR, 10));
    ++tried;
    const double held = *generator.transmission_min_deg + 10.0;
    PlanarDyad input = task.input, output = task.output;
    RefineFourBar(task.poses, {}, {}, length, &input, &output);
    const FourBarAnalysis plain = AnalyzeFourBar(input, output, task.poses, length);
    ASSERT_TRUE(plain.transmission_min_deg.has_value());
    EXPECT_LT(*plain.transmission_min_deg, held - 5.0);
    linkfit::FourBarRefinerOptions options;
    options.min_transmission_deg = held;
    input = task.input;
    output = task.output;
    const RefinerSummary summary =
        RefineFourBar(task.poses, {}, {}, length, &input, &output, options);
    SCOPED_TRACE(summary.message);
    const FourBarAnalysis refined = AnalyzeFourBar(input, output, task.poses, length);
    ASSERT_TRUE(refined.transmission_min_deg.has_value());
    EXPECT_GE(*refined.transmission_min_deg, held);
    ASSERT_TRUE(refined.max_pose_error.has_value());
    EXPECT_TRUE(std::isfinite(*refined.max_pose_error));
  }
  EXPECT_EQ(tried, kTrials);
}

}  // namespace
