// Tests of optimizers/planar_dyad_refiner.h: least-squares refinement of one planar dyad (RR, PR,
// RP) on its geometric residual. Each test draws a random dyad, makes poses on it (exact or
// noisy), refines a perturbed seed and requires the generating dyad (or the least-squares
// optimum) back; then turns huge circles into sliders, pins exact poses, scales, moves, reorders
// and feeds pathological seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "optimizers/planar_dyad_refiner.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

using testing::DyadDistance;
using testing::DyadScale;

constexpr unsigned kSeed = 20240717;  // every random test here starts from kSeed + k
constexpr int kTrials = 25;
constexpr int kMinPoses = 6;
constexpr int kMaxPoses = 50;
constexpr double kSeedOffset = 1e-2;  // distance of a seed from the true dyad, in L
// Refined vs true dyad on exact data: DyadDistance relative to DyadScale.
constexpr double kExactParameter = 1e-9;
constexpr double kExactResidual = 1e-10;  // max |residual| on exact data, in L
constexpr double kCostSlack = 1e-12;      // relative rounding allowed in a cost comparison
// The same noisy optimum reached twice (scaled, moved, reordered, restarted): the cost agrees to
// rounding, the parameters only to about sqrt(machine epsilon) times the conditioning, since the
// cost is flat (quadratic) about the minimum.
constexpr double kSameCost = 1e-10;
constexpr double kSameOptimum = 1e-6;
constexpr double kReportedAgreement = 1e-12;  // summary vs recomputed statistics, relative

std::string SeedTrace(unsigned seed, int trial) {
  return "seed " + std::to_string(seed) + ", trial " + std::to_string(trial);
}

struct RandomSource {
  explicit RandomSource(unsigned seed) : engine(seed) {}

  Eigen::Vector2d Point(double half_width) {
    return half_width * Eigen::Vector2d(Uniform(), Uniform());
  }
  Eigen::Vector2d Gaussian(double sigma) { return sigma * Eigen::Vector2d(Normal(), Normal()); }
  Eigen::Vector2d UnitVector() {
    const double angle = M_PI * Uniform();
    return Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }
  int Count(int low, int high) { return std::uniform_int_distribution<int>(low, high)(engine); }
  double Uniform() { return uniform(engine); }  // in [-1, 1)
  double Normal() { return normal(engine); }

  std::mt19937_64 engine;
  std::normal_distribution<double> normal{0.0, 1.0};
  std::uniform_real_distribution<double> uniform{-1.0, 1.0};
};

// Pivots in a box of half-width 1 about the origin, radius in [0.5, 2]; lines through a point
// of that box in a random direction.
PlanarDyad RandomDyad(RandomSource& source, DyadType type) {
  switch (type) {
    case DyadType::kRR:
      return PlanarDyad::RR(source.Point(1.0), source.Point(1.0), 1.25 + 0.75 * source.Uniform());
    case DyadType::kPR:
      return PlanarDyad::PR(source.Point(1.0), source.Point(1.0), source.UnitVector());
    case DyadType::kRP:
      return PlanarDyad::RP(source.Point(1.0), source.Point(1.0), source.UnitVector());
  }
  return PlanarDyad();
}

// `count` poses that satisfy the dyad: theta random, then the origin chosen so that the
// constrained point is a random point of the circle (RR: M at F + r u) or of a stretch 4 long
// of the line about its line point (PR: M in Sigma; RP: F seen from E).
std::vector<PlanarPose> PosesOnDyad(RandomSource& source, const PlanarDyad& dyad, int count) {
  std::vector<PlanarPose> poses;
  for (int j = 0; j < count; ++j) {
    PlanarPose pose;
    pose.theta = M_PI * source.Uniform();
    const Eigen::Matrix2d rotation = Rotation2(pose.theta);
    const Eigen::Vector2d along = dyad.line_point + 2.0 * source.Uniform() * dyad.line_direction;
    switch (dyad.type) {
      case DyadType::kRR:
        pose.origin_in_fixed =
            dyad.fixed_pivot + dyad.radius * source.UnitVector() - rotation * dyad.moving_pivot;
        break;
      case DyadType::kPR:
        pose.origin_in_fixed = along - rotation * dyad.moving_pivot;
        break;
      case DyadType::kRP:
        pose.origin_in_fixed = dyad.fixed_pivot - rotation * along;
        break;
    }
    poses.push_back(pose);
  }
  return poses;
}

// Each pose moved by sigma L per origin component and sigma rad in angle.
std::vector<PlanarPose> Noisy(RandomSource& source, const std::vector<PlanarPose>& poses,
                              double sigma, double length) {
  std::vector<PlanarPose> noisy = poses;
  for (PlanarPose& pose : noisy) {
    pose.origin_in_fixed += source.Gaussian(sigma * length);
    pose.theta += sigma * source.Normal();
  }
  return noisy;
}

// Every parameter moved by `offset` (points in a random direction, lines turned by offset / L
// and shifted by offset).
PlanarDyad Perturbed(RandomSource& source, const PlanarDyad& dyad, double offset, double length) {
  PlanarDyad seed = dyad;
  seed.fixed_pivot += offset * source.UnitVector();
  seed.moving_pivot += offset * source.UnitVector();
  seed.radius += offset * (source.Uniform() < 0.0 ? -1.0 : 1.0);
  seed.line_point += offset * source.UnitVector();
  seed.line_direction = Rotation2(offset / length) * seed.line_direction;
  return seed;
}

// sqrt(sum w e^2 / sum w) and 1/2 sum w e^2 of a dyad (weights empty: all 1).
double Rms(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
           const std::vector<double>& weights = {}) {
  double sum = 0.0, weight_sum = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double w = weights.empty() ? 1.0 : weights[j];
    const double e = dyad.Residual(poses[j]);
    sum += w * e * e;
    weight_sum += w;
  }
  return std::sqrt(sum / weight_sum);
}
double Cost(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
            const std::vector<double>& weights = {}) {
  double cost = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double e = dyad.Residual(poses[j]);
    cost += 0.5 * (weights.empty() ? 1.0 : weights[j]) * e * e;
  }
  return cost;
}

bool AllFinite(const PlanarDyad& dyad) {
  return dyad.fixed_pivot.allFinite() && dyad.moving_pivot.allFinite() &&
         std::isfinite(dyad.radius) && dyad.line_point.allFinite() &&
         dyad.line_direction.allFinite();
}
bool AllFinite(const RefinerSummary& summary) {
  return std::isfinite(summary.initial_cost) && std::isfinite(summary.final_cost) &&
         std::isfinite(summary.initial_rms) && std::isfinite(summary.final_rms) &&
         std::isfinite(summary.initial_max) && std::isfinite(summary.final_max) &&
         std::isfinite(summary.seconds);
}

// |reported - expected| within `relative` of |expected| plus an absolute `floor`.
bool Near(double reported, double expected, double relative, double floor) {
  return std::abs(reported - expected) <= relative * std::abs(expected) + floor;
}
// Rounding floor of a residual of a dyad of size up to 1e6 L (the huge seeds below), in L.
constexpr double kResidualFloor = 1e-9;

// The rounding allowed between two evaluations of costs 1/2 sum w e^2 (weights of mean about 1,
// up to kMaxPoses poses, L = 1) whose residuals agree within `relative` plus `floor` each: the
// cost moves by about sum w |e| de <= sqrt(2 n cost) de.
double CostSlack(double cost, double expected_cost, double relative, double floor) {
  const double bound = std::sqrt(2.0 * kMaxPoses * std::max(cost, expected_cost));
  return 2.0 * relative * std::abs(expected_cost) + bound * floor + kMaxPoses * floor * floor;
}
bool SameCost(double cost, double expected_cost, double relative) {
  return std::abs(cost - expected_cost) <= CostSlack(cost, expected_cost, relative, 1e-14);
}
bool NotWorse(double cost, double reference_cost, double relative) {
  return cost <= reference_cost + CostSlack(cost, reference_cost, relative, 1e-14);
}

// The summary's statistics agree with the dyads they describe (poses of L = 1).
void ExpectSummaryMatches(const RefinerSummary& summary, const PlanarDyad& seed,
                          const PlanarDyad& refined, const std::vector<PlanarPose>& poses,
                          double floor = 1e-14) {
  const double r = kReportedAgreement;
  EXPECT_PRED4(Near, summary.initial_rms, Rms(seed, poses), r, floor);
  EXPECT_PRED4(Near, summary.final_rms, Rms(refined, poses), r, floor);
  EXPECT_PRED4(Near, summary.initial_max, seed.MaxResidual(poses), r, floor);
  EXPECT_PRED4(Near, summary.final_max, refined.MaxResidual(poses), r, floor);
  EXPECT_LE(std::abs(summary.initial_cost - Cost(seed, poses)),
            CostSlack(summary.initial_cost, Cost(seed, poses), r, floor));
  EXPECT_LE(std::abs(summary.final_cost - Cost(refined, poses)),
            CostSlack(summary.final_cost, Cost(refined, poses), r, floor));
}

constexpr DyadType kTypes[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};

void CheckExactRecovery(DyadType type, unsigned seed) {
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, type);
    const std::vector<PlanarPose> poses =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(poses);
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    PlanarDyad refined = seed_dyad;
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, type);
    EXPECT_FALSE(summary.model_changed);
    EXPECT_LT(DyadDistance(refined, truth, DyadScale(truth, poses)), kExactParameter);
    EXPECT_LT(refined.MaxResidual(poses), kExactResidual * length);
    EXPECT_LT(summary.final_max, kExactResidual * length);
    EXPECT_LT(summary.final_cost, summary.initial_cost);
    EXPECT_GT(summary.iterations, 0);
    EXPECT_FALSE(summary.message.empty());
    ExpectSummaryMatches(summary, seed_dyad, refined, poses);
  }
}

TEST(PlanarDyadRefiner, RecoversExactRRDyad) { CheckExactRecovery(DyadType::kRR, kSeed); }
TEST(PlanarDyadRefiner, RecoversExactPRDyad) { CheckExactRecovery(DyadType::kPR, kSeed + 1); }
TEST(PlanarDyadRefiner, RecoversExactRPDyad) { CheckExactRecovery(DyadType::kRP, kSeed + 2); }

// The dyads of random four-bars, slider-cranks and inverted slider-cranks, from the poses their
// couplers reach (6 to 9 of them, tests/support/random_mechanism.h).
TEST(PlanarDyadRefiner, RecoversDyadsOfGeneratedMechanisms) {
  const unsigned seed = kSeed + 3;
  std::mt19937_64 rng(seed);
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const DyadType output = kTypes[trial % 3];
    const testing::GeneratedTask task =
        testing::RandomTask(rng, DyadType::kRR, output, source.Count(kMinPoses, 9));
    const double length = CharacteristicLength(task.poses);
    for (const PlanarDyad& truth : {task.input, task.output}) {
      SCOPED_TRACE(DyadTypeName(truth.type));
      PlanarDyad refined = Perturbed(source, truth, kSeedOffset * length, length);
      const RefinerSummary summary = RefinePlanarDyad(task.poses, {}, {}, length, &refined);
      SCOPED_TRACE(summary.message);
      EXPECT_EQ(refined.type, truth.type);
      EXPECT_LT(DyadDistance(refined, truth, DyadScale(truth, task.poses)), kExactParameter);
      EXPECT_LT(refined.MaxResidual(task.poses), kExactResidual * length);
    }
  }
}

void CheckNoisyMinimum(DyadType type, double noise, unsigned seed) {
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, type);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, noise, length);
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    PlanarDyad refined = seed_dyad;
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, type);
    const double true_rms = Rms(truth, poses);
    EXPECT_LE(summary.final_rms, true_rms * (1.0 + kCostSlack));
    EXPECT_LE(summary.final_rms, summary.initial_rms);
    EXPECT_LE(Rms(refined, poses), true_rms * (1.0 + kCostSlack));
    ExpectSummaryMatches(summary, seed_dyad, refined, poses);
  }
}

TEST(PlanarDyadRefiner, NoisyDataReachLeastSquaresMinimum) {
  unsigned seed = kSeed + 10;
  for (double noise : {1e-3, 1e-2}) {
    for (DyadType type : kTypes) {
      SCOPED_TRACE(std::string(DyadTypeName(type)) + ", noise " + std::to_string(noise));
      CheckNoisyMinimum(type, noise, seed++);
    }
  }
}

TEST(PlanarDyadRefiner, OptimalSeedIsNotMadeWorse) {
  const unsigned seed = kSeed + 20;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, kTypes[trial % 3]);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
    PlanarDyad optimum = Perturbed(source, truth, kSeedOffset * length, length);
    RefinePlanarDyad(poses, {}, {}, length, &optimum);
    PlanarDyad again = optimum;
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &again);
    SCOPED_TRACE(summary.message);
    EXPECT_LE(summary.final_cost, summary.initial_cost);
    EXPECT_PRED3(NotWorse, Cost(again, poses), Cost(optimum, poses), kCostSlack);
    EXPECT_LT(DyadDistance(again, optimum, DyadScale(optimum, poses)), kSameOptimum);
    EXPECT_FALSE(summary.model_changed);
  }
}

// An RR seed of radius `radius` that touches the slider's line where the data are: for a PR
// dyad, the circle in Sigma tangent to the line at the foot of the moving pivot's mean
// position; for an RP dyad, the circle in E tangent to the line at the foot of the fixed
// pivot's mean position seen from E (the moving pivot at its centre, far out in E). The other
// pivot is perturbed by kSeedOffset L.
PlanarDyad TangentCircleSeed(RandomSource& source, const PlanarDyad& slider,
                             const std::vector<PlanarPose>& poses, double radius, double length) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) {
    mean += slider.type == DyadType::kPR ? pose.ToFixed(slider.moving_pivot)
                                         : pose.ToMoving(slider.fixed_pivot);
  }
  mean /= static_cast<double>(poses.size());
  const Eigen::Vector2d normal(-slider.line_direction.y(), slider.line_direction.x());
  const Eigen::Vector2d foot = mean - normal.dot(mean - slider.line_point) * normal;
  const Eigen::Vector2d centre = foot + (source.Uniform() < 0.0 ? -radius : radius) * normal;
  const Eigen::Vector2d offset = kSeedOffset * length * source.UnitVector();
  return slider.type == DyadType::kPR ? PlanarDyad::RR(centre, slider.moving_pivot + offset, radius)
                                      : PlanarDyad::RR(slider.fixed_pivot + offset, centre, radius);
}

TEST(PlanarDyadRefiner, HugeCircleSeedOnSliderDataBecomesSlider) {
  const unsigned seed = kSeed + 30;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    for (DyadType type : {DyadType::kPR, DyadType::kRP}) {
      const PlanarDyad truth = RandomDyad(source, type);
      const std::vector<PlanarPose> poses =
          PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
      const double length = CharacteristicLength(poses);
      for (double radius : {1e3, 1e6}) {
        SCOPED_TRACE(std::string(DyadTypeName(type)) + ", seed radius " + std::to_string(radius));
        PlanarDyad refined = TangentCircleSeed(source, truth, poses, radius * length, length);
        const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
        SCOPED_TRACE(summary.message);
        EXPECT_EQ(refined.type, type);
        EXPECT_TRUE(summary.model_changed);
        EXPECT_LT(DyadDistance(refined, truth, DyadScale(truth, poses)), kExactParameter);
        EXPECT_LT(summary.final_max, kExactResidual * length);
        EXPECT_LT(refined.MaxResidual(poses), kExactResidual * length);
      }
    }
  }
}

// Noisy slider data: the circle's extra parameter fits noise only, so the F test keeps the
// slider except in about 5 % of the tasks (its false-alarm rate).
TEST(PlanarDyadRefiner, HugeCircleSeedOnNoisySliderDataMostlyBecomesSlider) {
  const unsigned seed = kSeed + 31;
  RandomSource source(seed);
  constexpr int kTasks = 80;
  constexpr double kMinSliderShare = 0.85;  // expected 0.95
  int sliders = 0;
  for (int trial = 0; trial < kTasks; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const DyadType type = trial % 2 == 0 ? DyadType::kPR : DyadType::kRP;
    const PlanarDyad truth = RandomDyad(source, type);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses + 4, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
    const PlanarDyad seed_dyad = TangentCircleSeed(source, truth, poses, 1e3 * length, length);
    PlanarDyad refined = seed_dyad;
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_TRUE(AllFinite(refined));
    EXPECT_EQ(summary.model_changed, refined.type != DyadType::kRR);
    if (refined.type == type) ++sliders;
    // A slider fits no better than the RR it nests in, and is kept only when the RR is not
    // significantly better: never far above the true slider's cost.
    EXPECT_LE(summary.final_rms, 2.0 * Rms(truth, poses));
  }
  EXPECT_GE(sliders, kMinSliderShare * kTasks);
}

// Poses on a circle of radius `radius` L, the moving pivot on an arc about 4 L long, noise 1e-3
// L: the arc's sagitta (about (4 L)^2 / (8 radius)) is far above the noise, so the circle
// fits significantly better than any line and stays RR, whether its radius is below
// slider_radius_ratio L (3 L: no slider tried) or above it (30 L: the limits are refined and
// rejected by the F test).
TEST(PlanarDyadRefiner, LargeCircleWithCurvatureStaysRR) {
  const unsigned seed = kSeed + 32;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    for (double radius : {3.0, 30.0}) {
      SCOPED_TRACE("radius " + std::to_string(radius));
      const Eigen::Vector2d up = source.UnitVector();
      const PlanarDyad truth =
          PlanarDyad::RR(source.Point(1.0) - radius * up, source.Point(1.0), radius);
      std::vector<PlanarPose> exact;
      const int count = source.Count(kMinPoses + 4, kMaxPoses);
      for (int j = 0; j < count; ++j) {
        PlanarPose pose;
        pose.theta = M_PI * source.Uniform();
        const double angle = 2.0 * source.Uniform() / radius;
        const Eigen::Vector2d point = truth.fixed_pivot + radius * (Rotation2(angle) * up);
        pose.origin_in_fixed = point - Rotation2(pose.theta) * truth.moving_pivot;
        exact.push_back(pose);
      }
      const double length = CharacteristicLength(exact);
      const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
      PlanarDyad refined = Perturbed(source, truth, kSeedOffset * length, length);
      const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
      SCOPED_TRACE(summary.message);
      EXPECT_EQ(refined.type, DyadType::kRR);
      EXPECT_FALSE(summary.model_changed);
      EXPECT_LE(summary.final_rms, Rms(truth, poses) * (1.0 + kCostSlack));
    }
  }
}

// A dyad near `truth` that meets poses a and b exactly: RR keeps M and moves F to the nearest
// point of the perpendicular bisector of its two positions P_a, P_b (r = |P_a - F|); PR keeps M
// and takes the line through P_a and P_b; RP keeps F and takes the line of E through the points
// e_a, e_b where E sees F.
PlanarDyad ThroughTwoPoses(const PlanarDyad& truth, const PlanarPose& a, const PlanarPose& b) {
  if (truth.type == DyadType::kRP) {
    const Eigen::Vector2d ea = a.ToMoving(truth.fixed_pivot), eb = b.ToMoving(truth.fixed_pivot);
    return PlanarDyad::RP(truth.fixed_pivot, ea, eb - ea);
  }
  const Eigen::Vector2d pa = a.ToFixed(truth.moving_pivot), pb = b.ToFixed(truth.moving_pivot);
  if (truth.type == DyadType::kPR) return PlanarDyad::PR(truth.moving_pivot, pa, pb - pa);
  const Eigen::Vector2d middle = 0.5 * (pa + pb);
  const Eigen::Vector2d along = Eigen::Vector2d(-(pb - pa).y(), (pb - pa).x()).normalized();
  const Eigen::Vector2d fixed_pivot = middle + along.dot(truth.fixed_pivot - middle) * along;
  return PlanarDyad::RR(fixed_pivot, truth.moving_pivot, (pa - fixed_pivot).norm());
}

// Noisy data with two poses marked exact: those two are met to exact_tolerance L, and the others
// fit at least as well as a dyad near the truth that meets the two poses (ThroughTwoPoses), and
// no better than the free least-squares optimum.
TEST(PlanarDyadRefiner, ExactPosesAreMet) {
  const unsigned seed = kSeed + 40;
  RandomSource source(seed);
  const PlanarDyadRefinerOptions options;
  for (double noise : {1e-3, 1e-2}) {
    for (int trial = 0; trial < kTrials; ++trial) {
      SCOPED_TRACE(SeedTrace(seed, trial) + ", noise " + std::to_string(noise));
      const DyadType type = kTypes[trial % 3];
      const PlanarDyad truth = RandomDyad(source, type);
      const int count = source.Count(kMinPoses + 4, kMaxPoses);
      const std::vector<PlanarPose> exact_poses = PosesOnDyad(source, truth, count);
      const double length = CharacteristicLength(exact_poses);
      const std::vector<PlanarPose> poses = Noisy(source, exact_poses, noise, length);
      std::vector<bool> exact(count, false);
      const int first = source.Count(0, count - 1);
      const int second = (first + source.Count(1, count - 1)) % count;
      exact[first] = exact[second] = true;
      const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);

      PlanarDyad free = seed_dyad;
      const RefinerSummary free_summary = RefinePlanarDyad(poses, {}, {}, length, &free);
      PlanarDyad pinned = seed_dyad;
      const RefinerSummary summary = RefinePlanarDyad(poses, {}, exact, length, &pinned, options);
      SCOPED_TRACE(summary.message);
      EXPECT_EQ(pinned.type, type);
      EXPECT_TRUE(AllFinite(pinned));
      EXPECT_LE(std::abs(pinned.Residual(poses[first])), options.exact_tolerance * length);
      EXPECT_LE(std::abs(pinned.Residual(poses[second])), options.exact_tolerance * length);
      EXPECT_EQ(summary.message.find("not met"), std::string::npos);
      const PlanarDyad reference = ThroughTwoPoses(truth, poses[first], poses[second]);
      EXPECT_LE(summary.final_cost, Cost(reference, poses) * (1.0 + kCostSlack));
      EXPECT_GE(summary.final_cost, free_summary.final_cost * (1.0 - kCostSlack));
      ExpectSummaryMatches(summary, seed_dyad, pinned, poses);
    }
  }
}

// More exact poses than the dyad has parameters, on noisy data: they cannot all be met; the
// summary says so, and the result is finite and no worse than the seed.
TEST(PlanarDyadRefiner, UnreachableExactPosesAreReported) {
  const unsigned seed = kSeed + 41;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const DyadType type = kTypes[trial % 3];
    const PlanarDyad truth = RandomDyad(source, type);
    const std::vector<PlanarPose> exact_poses = PosesOnDyad(source, truth, 12);
    const double length = CharacteristicLength(exact_poses);
    const std::vector<PlanarPose> poses = Noisy(source, exact_poses, 1e-2, length);
    std::vector<bool> exact(12, false);
    for (int j = 0; j < 7; ++j) exact[j] = true;
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    PlanarDyad refined = seed_dyad;
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, exact, length, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, type);
    EXPECT_TRUE(AllFinite(refined));
    EXPECT_TRUE(AllFinite(summary));
    EXPECT_NE(summary.message.find("exact poses not met"), std::string::npos);
    EXPECT_LE(summary.final_cost, summary.initial_cost);
    EXPECT_PRED3(NotWorse, Cost(refined, poses), Cost(seed_dyad, poses), kCostSlack);
  }
}

// Exact poses on exact data: the generating dyad back, as without them.
TEST(PlanarDyadRefiner, ExactPosesOnExactData) {
  const unsigned seed = kSeed + 42;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, kTypes[trial % 3]);
    const int count = source.Count(kMinPoses, kMaxPoses);
    const std::vector<PlanarPose> poses = PosesOnDyad(source, truth, count);
    const double length = CharacteristicLength(poses);
    std::vector<bool> exact(count, false);
    exact[0] = exact[count - 1] = true;
    PlanarDyad refined = Perturbed(source, truth, kSeedOffset * length, length);
    const RefinerSummary summary = RefinePlanarDyad(poses, {}, exact, length, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_LT(DyadDistance(refined, truth, DyadScale(truth, poses)), kExactParameter);
    EXPECT_LT(summary.final_max, kExactResidual * length);
  }
}

TEST(PlanarDyadRefiner, PathologicalSeedsGiveNoNaN) {
  const unsigned seed = kSeed + 50;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, DyadType::kRR);
    const std::vector<PlanarPose> poses =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(poses);
    const Eigen::Vector2d first_point = poses[0].ToFixed(truth.moving_pivot);
    const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
    std::vector<bool> exact(poses.size(), false);
    exact[0] = true;
    const std::vector<PlanarDyad> seeds = {
        PlanarDyad::RR(zero, zero, 0.0),
        PlanarDyad::RR(truth.fixed_pivot, truth.moving_pivot, 0.0),
        // The fixed pivot exactly on the first pose's moving pivot: |P_0 - F| = 0.
        PlanarDyad::RR(first_point, truth.moving_pivot, 0.0),
        PlanarDyad::RR(first_point, truth.moving_pivot, truth.radius),
        // Coincident pivots: F in Sigma and M in E given the same coordinates.
        PlanarDyad::RR(truth.fixed_pivot, truth.fixed_pivot, truth.radius),
        PlanarDyad::RR(truth.fixed_pivot, truth.moving_pivot, -length),
        PlanarDyad::RR(truth.fixed_pivot, truth.moving_pivot, 1e12 * length),
        PlanarDyad::RR(1e12 * length * Eigen::Vector2d::UnitX(),
                       1e12 * length * Eigen::Vector2d::UnitY(), 1e12 * length),
        PlanarDyad::PR(zero, zero, Eigen::Vector2d::UnitX()),
        PlanarDyad::RP(zero, zero, Eigen::Vector2d::UnitY()),
        PlanarDyad::PR(1e9 * length * Eigen::Vector2d::UnitX(), zero, Eigen::Vector2d::UnitX()),
    };
    for (size_t k = 0; k < seeds.size(); ++k) {
      for (bool with_exact : {false, true}) {
        SCOPED_TRACE("pathological seed " + std::to_string(k) + (with_exact ? ", exact" : ""));
        PlanarDyad refined = seeds[k];
        const RefinerSummary summary =
            RefinePlanarDyad(poses, {}, with_exact ? exact : std::vector<bool>(), length, &refined);
        SCOPED_TRACE(summary.message);
        EXPECT_TRUE(AllFinite(refined));
        EXPECT_TRUE(AllFinite(summary));
        if (refined.type == seeds[k].type) {
          EXPECT_LE(summary.final_cost, summary.initial_cost);
          EXPECT_LE(Cost(refined, poses),
                    Cost(seeds[k], poses) +
                        CostSlack(Cost(refined, poses), Cost(seeds[k], poses), kCostSlack,
                                  kResidualFloor * std::max(1.0, seeds[k].radius / length)));
        }
      }
    }
  }
}

// A line seed without a direction (a zero vector) cannot be refined: it comes back unchanged.
TEST(PlanarDyadRefiner, DegenerateSeedIsReturnedUnchanged) {
  RandomSource source(kSeed + 51);
  const PlanarDyad truth = RandomDyad(source, DyadType::kPR);
  const std::vector<PlanarPose> poses = PosesOnDyad(source, truth, 10);
  const double length = CharacteristicLength(poses);
  PlanarDyad dyad = truth;
  dyad.line_direction = Eigen::Vector2d::Zero();
  RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &dyad);
  EXPECT_EQ(dyad.line_direction, Eigen::Vector2d::Zero());
  EXPECT_EQ(summary.iterations, 0);
  EXPECT_FALSE(summary.model_changed);
  EXPECT_FALSE(summary.message.empty());

  dyad = truth;
  dyad.moving_pivot.x() = std::numeric_limits<double>::quiet_NaN();
  summary = RefinePlanarDyad(poses, {}, {}, length, &dyad);
  EXPECT_TRUE(std::isnan(dyad.moving_pivot.x()));
  EXPECT_EQ(summary.iterations, 0);
}

// The task and dyad scaled by `scale` about the origin (Sigma and E alike).
std::vector<PlanarPose> ScaledPoses(const std::vector<PlanarPose>& poses, double scale) {
  std::vector<PlanarPose> scaled = poses;
  for (PlanarPose& pose : scaled) pose.origin_in_fixed *= scale;
  return scaled;
}
PlanarDyad ScaledDyad(const PlanarDyad& dyad, double scale) {
  Similarity2 similarity;
  similarity.scale = scale;
  return TransformDyad(dyad, similarity, similarity);
}

TEST(PlanarDyadRefiner, ResultDoesNotDependOnUnits) {
  const unsigned seed = kSeed + 60;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, kTypes[trial % 3]);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    PlanarDyad reference = seed_dyad;
    const RefinerSummary reference_summary = RefinePlanarDyad(poses, {}, {}, length, &reference);
    for (double scale : {1e-3, 1e3}) {
      SCOPED_TRACE("scale " + std::to_string(scale));
      PlanarDyad refined = ScaledDyad(seed_dyad, scale);
      const RefinerSummary summary =
          RefinePlanarDyad(ScaledPoses(poses, scale), {}, {}, scale * length, &refined);
      EXPECT_EQ(refined.type, reference.type);
      EXPECT_LT(
          DyadDistance(ScaledDyad(refined, 1.0 / scale), reference, DyadScale(reference, poses)),
          kSameOptimum);
      EXPECT_PRED3(SameCost, summary.final_cost / (scale * scale), reference_summary.final_cost,
                   kSameCost);
      EXPECT_PRED4(Near, summary.final_rms / scale, reference_summary.final_rms, kSameCost, 1e-14);
      EXPECT_PRED4(Near, summary.initial_max / scale, reference_summary.initial_max, kSameCost,
                   1e-14);

      // Exact data: the generating dyad back, scaled.
      PlanarDyad exact_refined =
          ScaledDyad(Perturbed(source, truth, kSeedOffset * length, length), scale);
      const RefinerSummary exact_summary =
          RefinePlanarDyad(ScaledPoses(exact, scale), {}, {}, scale * length, &exact_refined);
      EXPECT_LT(
          DyadDistance(exact_refined, ScaledDyad(truth, scale), scale * DyadScale(truth, exact)),
          kExactParameter);
      EXPECT_LT(exact_summary.final_max, kExactResidual * scale * length);
    }
  }
}

// Moving the fixed frame (a rotation and a far translation) and the moving frame (a rotation and
// a translation) moves the answer with them.
TEST(PlanarDyadRefiner, ResultDoesNotDependOnFrames) {
  const unsigned seed = kSeed + 61;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, kTypes[trial % 3]);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    PlanarDyad reference = seed_dyad;
    const RefinerSummary reference_summary = RefinePlanarDyad(poses, {}, {}, length, &reference);

    Similarity2 sigma, epsilon;
    sigma.angle = M_PI * source.Uniform();
    sigma.translation = source.Point(1e3);
    epsilon.angle = M_PI * source.Uniform();
    epsilon.translation = source.Point(3.0);
    std::vector<PlanarPose> moved;
    for (const PlanarPose& pose : poses) moved.push_back(TransformPose(pose, sigma, epsilon));
    PlanarDyad refined = TransformDyad(seed_dyad, sigma, epsilon);
    const RefinerSummary summary = RefinePlanarDyad(moved, {}, {}, length, &refined);
    const PlanarDyad back = TransformDyad(refined, sigma.Inverse(), epsilon.Inverse());
    // The far translation costs its relative rounding (1e3 L times machine epsilon) in every
    // coordinate.
    EXPECT_LT(DyadDistance(back, reference, DyadScale(reference, poses)), kSameOptimum);
    EXPECT_PRED3(SameCost, summary.final_cost, reference_summary.final_cost, kSameCost);
  }
}

TEST(PlanarDyadRefiner, ResultDoesNotDependOnOrderOrWeightScale) {
  const unsigned seed = kSeed + 62;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const PlanarDyad truth = RandomDyad(source, kTypes[trial % 3]);
    const std::vector<PlanarPose> exact =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const double length = CharacteristicLength(exact);
    const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
    std::vector<double> weights;
    for (size_t j = 0; j < poses.size(); ++j) weights.push_back(1.5 + source.Uniform());
    const PlanarDyad seed_dyad = Perturbed(source, truth, kSeedOffset * length, length);
    const double scale = DyadScale(truth, poses);
    PlanarDyad reference = seed_dyad;
    const RefinerSummary reference_summary =
        RefinePlanarDyad(poses, weights, {}, length, &reference);
    EXPECT_LE(Cost(reference, poses, weights), Cost(truth, poses, weights) * (1.0 + kCostSlack));
    EXPECT_PRED3(SameCost, reference_summary.final_cost, Cost(reference, poses, weights),
                 kReportedAgreement);
    EXPECT_PRED4(Near, reference_summary.final_rms, Rms(reference, poses, weights),
                 kReportedAgreement, 1e-14);

    // Weights times 1e6: same dyad, cost times 1e6.
    std::vector<double> heavy = weights;
    for (double& w : heavy) w *= 1e6;
    PlanarDyad heavy_dyad = seed_dyad;
    const RefinerSummary heavy_summary = RefinePlanarDyad(poses, heavy, {}, length, &heavy_dyad);
    EXPECT_LT(DyadDistance(heavy_dyad, reference, scale), kSameOptimum);
    EXPECT_PRED3(SameCost, heavy_summary.final_cost / 1e6, reference_summary.final_cost, kSameCost);

    // Reversed order.
    const std::vector<PlanarPose> reversed_poses(poses.rbegin(), poses.rend());
    const std::vector<double> reversed_weights(weights.rbegin(), weights.rend());
    PlanarDyad reversed = seed_dyad;
    RefinePlanarDyad(reversed_poses, reversed_weights, {}, length, &reversed);
    EXPECT_LT(DyadDistance(reversed, reference, scale), kSameOptimum);

    // Empty weights and exact flags are all 1 and none.
    PlanarDyad unweighted = seed_dyad, ones = seed_dyad;
    RefinePlanarDyad(poses, {}, {}, length, &unweighted);
    RefinePlanarDyad(poses, std::vector<double>(poses.size(), 1.0),
                     std::vector<bool>(poses.size(), false), length, &ones);
    EXPECT_LT(DyadDistance(unweighted, ones, scale), kSameOptimum);
  }
}

TEST(PlanarDyadRefiner, RejectsBadArguments) {
  RandomSource source(kSeed + 70);
  const PlanarDyad truth = RandomDyad(source, DyadType::kRR);
  const std::vector<PlanarPose> poses = PosesOnDyad(source, truth, kMinPoses);
  PlanarDyad dyad = truth;
  EXPECT_THROW(RefinePlanarDyad(poses, {}, {}, 0.0, &dyad), std::invalid_argument);
  EXPECT_THROW(RefinePlanarDyad(poses, {1.0, 2.0}, {}, 1.0, &dyad), std::invalid_argument);
  EXPECT_THROW(RefinePlanarDyad(poses, {}, {true}, 1.0, &dyad), std::invalid_argument);
  EXPECT_THROW(RefinePlanarDyad(poses, std::vector<double>(poses.size(), -1.0), {}, 1.0, &dyad),
               std::invalid_argument);
  const RefinerSummary summary = RefinePlanarDyad({}, {}, {}, 1.0, &dyad);
  EXPECT_EQ(summary.iterations, 0);
  EXPECT_FALSE(summary.message.empty());
}

// Prints the median, 90th percentile and worst time per refine (RR, PR, RP; noisy data, seeds
// 1e-2 L off).
TEST(PlanarDyadRefiner, ReportsTimePerRefine) {
  const unsigned seed = kSeed + 80;
  RandomSource source(seed);
  constexpr int kRuns = 300;
  std::printf("%-6s %6s %10s %10s %10s %10s\n", "model", "poses", "median_us", "p90_us", "worst_us",
              "mean_iter");
  for (DyadType type : kTypes) {
    for (int count : {6, 20, 50}) {
      std::vector<double> seconds;
      double iterations = 0.0;
      for (int run = 0; run < kRuns; ++run) {
        const PlanarDyad truth = RandomDyad(source, type);
        const std::vector<PlanarPose> exact = PosesOnDyad(source, truth, count);
        const double length = CharacteristicLength(exact);
        const std::vector<PlanarPose> poses = Noisy(source, exact, 1e-3, length);
        PlanarDyad refined = Perturbed(source, truth, kSeedOffset * length, length);
        const RefinerSummary summary = RefinePlanarDyad(poses, {}, {}, length, &refined);
        seconds.push_back(summary.seconds);
        iterations += summary.iterations;
      }
      std::sort(seconds.begin(), seconds.end());
      EXPECT_GT(seconds.front(), 0.0);
      std::printf("%-6s %6d %10.1f %10.1f %10.1f %10.1f\n", DyadTypeName(type), count,
                  1e6 * seconds[kRuns / 2], 1e6 * seconds[kRuns * 9 / 10], 1e6 * seconds.back(),
                  iterations / kRuns);
    }
  }
}

}  // namespace
}  // namespace linkfit
