// Tests of optimizers/spatial_dyad_refiner.h: least-squares refinement of one spatial dyad on
// its geometric residual. Each test draws a random dyad, makes poses on it (exact or noisy),
// refines a perturbed seed and requires the generating dyad (or the least-squares optimum)
// back; then scales, reweights, reorders, pins poses marked exact and feeds pathological seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "optimizers/spatial_dyad_refiner.h"
#include "tests/support/random_spatial.h"

namespace {

using linkfit::DualQuaternion;
using linkfit::RefinerSummary;
using linkfit::RefineSpatialDyad;
using linkfit::SpatialDyad;
using linkfit::SpatialDyadType;

constexpr unsigned kSeed = 20240611;  // every random test here starts from kSeed + k
constexpr int kTrials = 25;
constexpr int kMinPoses = 7;
constexpr int kMaxPoses = 30;
constexpr double kLength = 1.0;           // L of the generated tasks
constexpr double kSeedOffset = 1e-2;      // distance of a seed from the true dyad, in L
constexpr double kNoise = 1e-3;           // pose noise: L in translation, rad in rotation
constexpr double kExactParameter = 1e-9;  // refined vs true dyad on exact data, relative
constexpr double kExactResidual = 1e-10;  // max |residual| on exact data, in L
constexpr double kNoisyDrift = 1.0;       // noisy optimum vs true dyad, relative
constexpr double kCostSlack = 1e-12;      // relative rounding allowed in a cost comparison
// The same noisy optimum reached twice (scaled, reweighted, reordered, restarted), relative: its
// cost agrees to rounding, its parameters only to about sqrt(machine epsilon) times the
// conditioning, since the cost is flat (quadratic) about the minimum.
constexpr double kSameCost = 1e-12;
constexpr double kSameOptimum = 1e-7;
constexpr double kReportedAgreement = 1e-12;  // summary vs recomputed statistics, relative

std::string SeedTrace(unsigned seed, int trial) {
  return "seed " + std::to_string(seed) + ", trial " + std::to_string(trial);
}

struct RandomSource {
  explicit RandomSource(unsigned seed) : engine(seed) {}

  Eigen::Matrix3d Rotation() {
    // A uniformly random rotation from a normalized Gaussian quaternion.
    Eigen::Quaterniond quaternion(Normal(), Normal(), Normal(), Normal());
    quaternion.normalize();
    return quaternion.toRotationMatrix();
  }
  Eigen::Vector3d Vector(double half_width) {
    return half_width * Eigen::Vector3d(Uniform(), Uniform(), Uniform());
  }
  Eigen::Vector3d Gaussian(double sigma) {
    return sigma * Eigen::Vector3d(Normal(), Normal(), Normal());
  }
  Eigen::Vector3d UnitVector() { return Gaussian(1.0).normalized(); }
  int Count(int low, int high) { return std::uniform_int_distribution<int>(low, high)(engine); }
  double Uniform() { return uniform(engine); }
  double Normal() { return normal(engine); }

  std::mt19937 engine;
  std::normal_distribution<double> normal{0.0, 1.0};
  std::uniform_real_distribution<double> uniform{-1.0, 1.0};
};

// Pivots in a box of half-width L about the origin, radius in [L/2, 2L].
SpatialDyad RandomSphereDyad(RandomSource& source) {
  return SpatialDyad::SS(source.Vector(kLength), source.Vector(kLength),
                         kLength * (1.25 + 0.75 * source.Uniform()));
}

SpatialDyad RandomPlaneDyad(RandomSource& source) {
  return SpatialDyad::PS(source.Vector(kLength), source.UnitVector(), kLength * source.Uniform());
}

// `count` poses with the moving pivot on the dyad's sphere or plane: R random, then d chosen
// so that C = R c + d is a random point of the sphere (d = A + r u - R c, u a random unit
// vector) or of a 4L x 4L square of the plane about its foot point h n.
std::vector<DualQuaternion> PosesOnDyad(RandomSource& source, const SpatialDyad& dyad, int count) {
  std::vector<DualQuaternion> poses;
  for (int j = 0; j < count; ++j) {
    const Eigen::Matrix3d rotation = source.Rotation();
    Eigen::Vector3d point;
    if (dyad.type == SpatialDyadType::kSS) {
      point = dyad.fixed_pivot + dyad.radius * source.UnitVector();
    } else {
      const Eigen::Vector3d tangent = dyad.plane_normal.unitOrthogonal();
      const Eigen::Vector3d bitangent = dyad.plane_normal.cross(tangent);
      point = dyad.plane_offset * dyad.plane_normal +
              2.0 * kLength * (source.Uniform() * tangent + source.Uniform() * bitangent);
    }
    poses.push_back(
        DualQuaternion::FromRotationTranslation(rotation, point - rotation * dyad.moving_pivot));
  }
  return poses;
}

// Each pose moved by sigma L (translation, per component) and sigma rad (rotation vector).
std::vector<DualQuaternion> Noisy(RandomSource& source, const std::vector<DualQuaternion>& poses,
                                  double sigma) {
  std::vector<DualQuaternion> noisy;
  for (const DualQuaternion& pose : poses) {
    const Eigen::Vector3d rotation_vector = source.Gaussian(sigma);
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix();
    noisy.push_back(DualQuaternion::FromRotationTranslation(
        turn * pose.Rotation(), pose.Translation() + source.Gaussian(sigma * kLength)));
  }
  return noisy;
}

// Every parameter moved by `offset` (vectors in a random direction).
SpatialDyad Perturbed(RandomSource& source, const SpatialDyad& dyad, double offset) {
  SpatialDyad seed = dyad;
  seed.moving_pivot += offset * source.UnitVector();
  if (dyad.type == SpatialDyadType::kSS) {
    seed.fixed_pivot += offset * source.UnitVector();
    seed.radius += offset * (source.Uniform() < 0.0 ? -1.0 : 1.0);
  } else {
    seed.plane_normal = (seed.plane_normal + offset * source.UnitVector()).normalized();
    seed.plane_offset += offset;
  }
  return seed;
}

// Largest parameter difference relative to max(L, the parameters' size); a plane is compared
// as a plane ((n, h) and (-n, -h) are the same). Infinity for different types.
double DyadDistance(const SpatialDyad& found, const SpatialDyad& expected, double length) {
  if (found.type != expected.type) return std::numeric_limits<double>::infinity();
  const double pivot_scale = std::max(length, expected.moving_pivot.norm());
  double distance = (found.moving_pivot - expected.moving_pivot).norm() / pivot_scale;
  if (expected.type == SpatialDyadType::kSS) {
    const double scale = std::max({length, expected.fixed_pivot.norm(), std::abs(expected.radius)});
    distance = std::max({distance, (found.fixed_pivot - expected.fixed_pivot).norm() / scale,
                         std::abs(found.radius - expected.radius) / scale});
  } else {
    const double sign = found.plane_normal.dot(expected.plane_normal) < 0.0 ? -1.0 : 1.0;
    const double scale = std::max(length, std::abs(expected.plane_offset));
    distance = std::max({distance, (sign * found.plane_normal - expected.plane_normal).norm(),
                         std::abs(sign * found.plane_offset - expected.plane_offset) / scale});
  }
  return distance;
}

// sqrt(sum w e^2 / sum w) and 1/2 sum w e^2 of a dyad (weights empty: all 1).
double Rms(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
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
double Cost(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
            const std::vector<double>& weights = {}) {
  double cost = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double e = dyad.Residual(poses[j]);
    cost += 0.5 * (weights.empty() ? 1.0 : weights[j]) * e * e;
  }
  return cost;
}

bool AllFinite(const SpatialDyad& dyad) {
  return dyad.moving_pivot.allFinite() && dyad.fixed_pivot.allFinite() &&
         std::isfinite(dyad.radius) && dyad.plane_normal.allFinite() &&
         std::isfinite(dyad.plane_offset);
}
bool AllFinite(const RefinerSummary& summary) {
  return std::isfinite(summary.initial_cost) && std::isfinite(summary.final_cost) &&
         std::isfinite(summary.initial_rms) && std::isfinite(summary.final_rms) &&
         std::isfinite(summary.initial_max) && std::isfinite(summary.final_max);
}

// |reported - expected| within `relative` of |expected| plus an absolute `floor` (an exact
// fit's cost is rounding noise, of any relative size).
bool Near(double reported, double expected, double relative, double floor) {
  return std::abs(reported - expected) <= relative * std::abs(expected) + floor;
}
constexpr double kResidualFloor = 1e-14 * kLength;  // rounding floor of a residual

// The rounding allowed between two evaluations of costs 1/2 sum w e^2 (weights of mean about
// 1, up to kMaxPoses poses) whose residuals agree within `relative` plus kResidualFloor each:
// the cost moves by about sum w |e| de <= sqrt(2 n cost) de.
double CostSlack(double cost, double expected_cost, double relative) {
  const double bound = std::sqrt(2.0 * kMaxPoses * std::max(cost, expected_cost));
  return 2.0 * relative * std::abs(expected_cost) + bound * kResidualFloor +
         kMaxPoses * kResidualFloor * kResidualFloor;
}
bool SameCost(double cost, double expected_cost, double relative) {
  return std::abs(cost - expected_cost) <= CostSlack(cost, expected_cost, relative);
}
bool NotWorse(double cost, double reference_cost, double relative) {
  return cost <= reference_cost + CostSlack(cost, reference_cost, relative);
}

// The summary's statistics agree with the dyads they describe.
void ExpectSummaryMatches(const RefinerSummary& summary, const SpatialDyad& seed,
                          const SpatialDyad& refined, const std::vector<DualQuaternion>& poses) {
  const double r = kReportedAgreement;
  EXPECT_PRED4(Near, summary.initial_rms, Rms(seed, poses), r, kResidualFloor);
  EXPECT_PRED4(Near, summary.final_rms, Rms(refined, poses), r, kResidualFloor);
  EXPECT_PRED4(Near, summary.initial_max, seed.MaxResidual(poses), r, kResidualFloor);
  EXPECT_PRED4(Near, summary.final_max, refined.MaxResidual(poses), r, kResidualFloor);
  EXPECT_PRED3(SameCost, summary.initial_cost, Cost(seed, poses), r);
  EXPECT_PRED3(SameCost, summary.final_cost, Cost(refined, poses), r);
}

void CheckExactRecovery(SpatialDyadType type, unsigned seed) {
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth =
        type == SpatialDyadType::kSS ? RandomSphereDyad(source) : RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const SpatialDyad seed_dyad = Perturbed(source, truth, kSeedOffset * kLength);
    SpatialDyad refined = seed_dyad;
    const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, type);
    EXPECT_FALSE(summary.model_changed);
    EXPECT_LT(DyadDistance(refined, truth, kLength), kExactParameter);
    EXPECT_LT(refined.MaxResidual(poses), kExactResidual * kLength);
    EXPECT_LT(summary.final_max, kExactResidual * kLength);
    EXPECT_LT(summary.final_cost, summary.initial_cost);
    EXPECT_GT(summary.iterations, 0);
    EXPECT_FALSE(summary.message.empty());
    ExpectSummaryMatches(summary, seed_dyad, refined, poses);
  }
}

TEST(SpatialDyadRefiner, RecoversExactSphereDyad) {
  CheckExactRecovery(SpatialDyadType::kSS, kSeed);
}

TEST(SpatialDyadRefiner, RecoversExactPlaneDyad) {
  CheckExactRecovery(SpatialDyadType::kPS, kSeed + 1);
}

void CheckNoisyMinimum(SpatialDyadType type, unsigned seed) {
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth =
        type == SpatialDyadType::kSS ? RandomSphereDyad(source) : RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        Noisy(source, PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses)), kNoise);
    SpatialDyad refined = Perturbed(source, truth, kSeedOffset * kLength);
    const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, type);
    const double true_rms = Rms(truth, poses);
    EXPECT_LE(summary.final_rms, true_rms * (1.0 + kCostSlack));
    EXPECT_LE(summary.final_rms, summary.initial_rms);
    EXPECT_LE(Rms(refined, poses), true_rms * (1.0 + kCostSlack));
    // The optimum stays on the truth's branch (a 7-pose SS task, exactly determined, can
    // amplify the noise a hundredfold).
    EXPECT_LT(DyadDistance(refined, truth, kLength), kNoisyDrift);
  }
}

TEST(SpatialDyadRefiner, NoisySphereReachesLeastSquaresMinimum) {
  CheckNoisyMinimum(SpatialDyadType::kSS, kSeed + 2);
}

TEST(SpatialDyadRefiner, NoisyPlaneReachesLeastSquaresMinimum) {
  CheckNoisyMinimum(SpatialDyadType::kPS, kSeed + 3);
}

TEST(SpatialDyadRefiner, OptimalSeedIsNotMadeWorse) {
  const unsigned seed = kSeed + 4;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth = trial % 2 == 0 ? RandomSphereDyad(source) : RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        Noisy(source, PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses)), kNoise);
    SpatialDyad optimum = Perturbed(source, truth, kSeedOffset * kLength);
    RefineSpatialDyad(poses, {}, {}, kLength, &optimum);
    SpatialDyad again = optimum;
    const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &again);
    SCOPED_TRACE(summary.message);
    EXPECT_LE(summary.final_cost, summary.initial_cost);
    EXPECT_PRED3(NotWorse, Cost(again, poses), Cost(optimum, poses), kCostSlack);
    EXPECT_LT(DyadDistance(again, optimum, kLength), kSameOptimum);
    EXPECT_FALSE(summary.model_changed);
  }
}

TEST(SpatialDyadRefiner, PathologicalSeedsGiveNoNaN) {
  const unsigned seed = kSeed + 5;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth = RandomSphereDyad(source);
    const std::vector<DualQuaternion> poses =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    const Eigen::Vector3d first_point = poses[0].ToFixed(truth.moving_pivot);
    const std::vector<SpatialDyad> seeds = {
        SpatialDyad::SS(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0),
        SpatialDyad::SS(truth.fixed_pivot, truth.moving_pivot, 0.0),
        // The fixed pivot exactly on the first pose's moving point: |C_0 - A| = 0.
        SpatialDyad::SS(first_point, truth.moving_pivot, 0.0),
        SpatialDyad::SS(truth.fixed_pivot, truth.moving_pivot, -kLength),
        SpatialDyad::PS(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.0),
    };
    for (size_t k = 0; k < seeds.size(); ++k) {
      SCOPED_TRACE("pathological seed " + std::to_string(k));
      SpatialDyad refined = seeds[k];
      const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &refined);
      SCOPED_TRACE(summary.message);
      EXPECT_TRUE(AllFinite(refined));
      EXPECT_TRUE(AllFinite(summary));
      EXPECT_LE(summary.final_cost, summary.initial_cost);
      EXPECT_PRED3(NotWorse, Cost(refined, poses), Cost(seeds[k], poses), kCostSlack);
    }
  }
}

// The task and dyad scaled by `scale` about the origin (Sigma and E alike).
std::vector<DualQuaternion> ScaledPoses(const std::vector<DualQuaternion>& poses, double scale) {
  std::vector<DualQuaternion> scaled;
  for (const DualQuaternion& pose : poses) {
    scaled.push_back(
        DualQuaternion::FromRotationTranslation(pose.Rotation(), scale * pose.Translation()));
  }
  return scaled;
}
SpatialDyad ScaledDyad(const SpatialDyad& dyad, double scale) {
  SpatialDyad scaled = dyad;
  scaled.fixed_pivot *= scale;
  scaled.moving_pivot *= scale;
  scaled.radius *= scale;
  scaled.plane_offset *= scale;
  return scaled;
}

TEST(SpatialDyadRefiner, ResultDoesNotDependOnUnits) {
  const unsigned seed = kSeed + 6;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth = trial % 2 == 0 ? RandomSphereDyad(source) : RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        Noisy(source, PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses)), kNoise);
    const SpatialDyad seed_dyad = Perturbed(source, truth, kSeedOffset * kLength);
    SpatialDyad reference = seed_dyad;
    const RefinerSummary reference_summary = RefineSpatialDyad(poses, {}, {}, kLength, &reference);
    for (double scale : {1e-3, 1e3}) {
      SCOPED_TRACE("scale " + std::to_string(scale));
      SpatialDyad refined = ScaledDyad(seed_dyad, scale);
      const RefinerSummary summary =
          RefineSpatialDyad(ScaledPoses(poses, scale), {}, {}, scale * kLength, &refined);
      EXPECT_LT(DyadDistance(ScaledDyad(refined, 1.0 / scale), reference, kLength), kSameOptimum);
      EXPECT_PRED3(SameCost, summary.final_cost / (scale * scale), reference_summary.final_cost,
                   kSameCost);
      EXPECT_PRED4(Near, summary.final_rms / scale, reference_summary.final_rms, kSameCost,
                   kResidualFloor);
      EXPECT_PRED4(Near, summary.initial_max / scale, reference_summary.initial_max, kSameCost,
                   kResidualFloor);

      // Exact data: the generating dyad back, scaled, as in the unit-length tests.
      const std::vector<DualQuaternion> exact_poses = PosesOnDyad(source, truth, kMinPoses + 3);
      SpatialDyad exact = ScaledDyad(Perturbed(source, truth, kSeedOffset * kLength), scale);
      const RefinerSummary exact_summary =
          RefineSpatialDyad(ScaledPoses(exact_poses, scale), {}, {}, scale * kLength, &exact);
      EXPECT_LT(DyadDistance(exact, ScaledDyad(truth, scale), scale * kLength), kExactParameter);
      EXPECT_LT(exact_summary.final_max, kExactResidual * scale * kLength);
    }
  }
}

TEST(SpatialDyadRefiner, ResultDoesNotDependOnOrderOrWeightScale) {
  const unsigned seed = kSeed + 7;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth = trial % 2 == 0 ? RandomSphereDyad(source) : RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        Noisy(source, PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses)), kNoise);
    std::vector<double> weights;
    for (size_t j = 0; j < poses.size(); ++j) weights.push_back(1.5 + source.Uniform());
    const SpatialDyad seed_dyad = Perturbed(source, truth, kSeedOffset * kLength);
    SpatialDyad reference = seed_dyad;
    const RefinerSummary reference_summary =
        RefineSpatialDyad(poses, weights, {}, kLength, &reference);
    EXPECT_LE(Cost(reference, poses, weights), Cost(truth, poses, weights));
    EXPECT_PRED3(SameCost, reference_summary.final_cost, Cost(reference, poses, weights),
                 kReportedAgreement);
    EXPECT_PRED4(Near, reference_summary.final_rms, Rms(reference, poses, weights),
                 kReportedAgreement, kResidualFloor);

    // Weights times 1e6: same dyad, cost times 1e6.
    std::vector<double> heavy = weights;
    for (double& w : heavy) w *= 1e6;
    SpatialDyad heavy_dyad = seed_dyad;
    const RefinerSummary heavy_summary = RefineSpatialDyad(poses, heavy, {}, kLength, &heavy_dyad);
    EXPECT_LT(DyadDistance(heavy_dyad, reference, kLength), kSameOptimum);
    EXPECT_PRED3(SameCost, heavy_summary.final_cost / 1e6, reference_summary.final_cost, kSameCost);
    EXPECT_PRED4(Near, heavy_summary.final_rms, reference_summary.final_rms, kSameCost,
                 kResidualFloor);

    // Reversed order.
    std::vector<DualQuaternion> reversed_poses(poses.rbegin(), poses.rend());
    std::vector<double> reversed_weights(weights.rbegin(), weights.rend());
    SpatialDyad reversed = seed_dyad;
    RefineSpatialDyad(reversed_poses, reversed_weights, {}, kLength, &reversed);
    EXPECT_LT(DyadDistance(reversed, reference, kLength), kSameOptimum);

    // Empty weights are all 1.
    SpatialDyad unweighted = seed_dyad, ones = seed_dyad;
    RefineSpatialDyad(poses, {}, {}, kLength, &unweighted);
    RefineSpatialDyad(poses, std::vector<double>(poses.size(), 1.0), {}, kLength, &ones);
    EXPECT_LT(DyadDistance(unweighted, ones, kLength), kSameOptimum);
  }
}

// A sphere seed of radius `radius` tangent to the plane of `plane` near the data, on the side
// opposite to n (so its outward normal there is n), with a perturbed moving pivot.
SpatialDyad TangentSphereSeed(RandomSource& source, const SpatialDyad& plane,
                              const std::vector<DualQuaternion>& poses, double radius) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : poses) centroid += pose.ToFixed(plane.moving_pivot);
  centroid /= static_cast<double>(poses.size());
  const Eigen::Vector3d foot =
      centroid - (plane.plane_normal.dot(centroid) - plane.plane_offset) * plane.plane_normal;
  return SpatialDyad::SS(foot - radius * plane.plane_normal,
                         plane.moving_pivot + kSeedOffset * kLength * source.UnitVector(), radius);
}

TEST(SpatialDyadRefiner, HugeSphereSeedOnPlaneDataIsRefinedAsPlane) {
  const unsigned seed = kSeed + 8;
  RandomSource source(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    const SpatialDyad truth = RandomPlaneDyad(source);
    const std::vector<DualQuaternion> poses =
        PosesOnDyad(source, truth, source.Count(kMinPoses, kMaxPoses));
    SpatialDyad refined = TangentSphereSeed(source, truth, poses, 1e6 * kLength);
    const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &refined);
    SCOPED_TRACE(summary.message);
    EXPECT_EQ(refined.type, SpatialDyadType::kPS);
    EXPECT_TRUE(summary.model_changed);
    EXPECT_LT(DyadDistance(refined, truth, kLength), kExactParameter);
    EXPECT_LT(refined.MaxResidual(poses), kExactResidual * kLength);
    EXPECT_LT(summary.final_max, kExactResidual * kLength);
  }
}

TEST(SpatialDyadRefiner, LargeSphereSeedIsComparedWithItsLimitPlane) {
  const unsigned seed = kSeed + 9;
  RandomSource source(seed);
  constexpr double kLargeRadius = 1e3 * kLength;  // between 1e2 L and max_radius_ratio L
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE(SeedTrace(seed, trial));
    // Plane data: the plane fits exactly, the sphere cannot: PS kept.
    const SpatialDyad plane = RandomPlaneDyad(source);
    const std::vector<DualQuaternion> plane_poses =
        PosesOnDyad(source, plane, source.Count(kMinPoses, kMaxPoses));
    SpatialDyad from_sphere = TangentSphereSeed(source, plane, plane_poses, kLargeRadius);
    const RefinerSummary plane_summary =
        RefineSpatialDyad(plane_poses, {}, {}, kLength, &from_sphere);
    SCOPED_TRACE(plane_summary.message);
    EXPECT_EQ(from_sphere.type, SpatialDyadType::kPS);
    EXPECT_TRUE(plane_summary.model_changed);
    EXPECT_LT(DyadDistance(from_sphere, plane, kLength), kExactParameter);

    // Data on a sphere of radius 3e2 L (a cap about 2 L across): the sphere fits exactly, the
    // plane cannot: SS kept.
    const double radius = 3e2 * kLength;
    const Eigen::Vector3d up = source.UnitVector();
    const SpatialDyad sphere =
        SpatialDyad::SS(source.Vector(kLength) - radius * up, source.Vector(kLength), radius);
    std::vector<DualQuaternion> sphere_poses;
    const int count = source.Count(kMinPoses, kMaxPoses);
    for (int j = 0; j < count; ++j) {
      const Eigen::Matrix3d rotation = source.Rotation();
      const Eigen::Vector3d direction = (up + source.Vector(kLength) / radius).normalized();
      const Eigen::Vector3d point = sphere.fixed_pivot + radius * direction;
      sphere_poses.push_back(DualQuaternion::FromRotationTranslation(
          rotation, point - rotation * sphere.moving_pivot));
    }
    SpatialDyad from_large = Perturbed(source, sphere, kSeedOffset * kLength);
    const RefinerSummary sphere_summary =
        RefineSpatialDyad(sphere_poses, {}, {}, kLength, &from_large);
    SCOPED_TRACE(sphere_summary.message);
    EXPECT_EQ(from_large.type, SpatialDyadType::kSS);
    EXPECT_FALSE(sphere_summary.model_changed);
    EXPECT_LT(sphere_summary.final_max, 1e-3 * sphere_summary.initial_max);
  }
}

TEST(SpatialDyadRefiner, RejectsBadArguments) {
  RandomSource source(kSeed + 10);
  const SpatialDyad truth = RandomSphereDyad(source);
  const std::vector<DualQuaternion> poses = PosesOnDyad(source, truth, kMinPoses);
  SpatialDyad dyad = truth;
  EXPECT_THROW(RefineSpatialDyad(poses, {}, {}, 0.0, &dyad), std::invalid_argument);
  EXPECT_THROW(RefineSpatialDyad(poses, {1.0, 2.0}, {}, kLength, &dyad), std::invalid_argument);
  EXPECT_THROW(
      RefineSpatialDyad(poses, std::vector<double>(poses.size(), -1.0), {}, kLength, &dyad),
      std::invalid_argument);
  EXPECT_THROW(RefineSpatialDyad(poses, {}, std::vector<bool>(2, true), kLength, &dyad),
               std::invalid_argument);
}

TEST(SpatialDyadRefiner, NonFiniteSeedIsReturnedUnchanged) {
  RandomSource source(kSeed + 12);
  const SpatialDyad truth = RandomSphereDyad(source);
  const std::vector<DualQuaternion> poses = PosesOnDyad(source, truth, kMinPoses);
  SpatialDyad dyad = truth;
  dyad.radius = std::numeric_limits<double>::quiet_NaN();
  const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &dyad);
  EXPECT_TRUE(std::isnan(dyad.radius));
  EXPECT_EQ(dyad.fixed_pivot, truth.fixed_pivot);
  EXPECT_FALSE(summary.model_changed);
  EXPECT_EQ(summary.iterations, 0);
  EXPECT_FALSE(summary.message.empty());
}

// ---- Poses marked exact ----

constexpr int kPlatformPoses = 12;
constexpr double kPlatformNoise = 1e-3;       // pose noise (PerturbSpatialPoses) but on exact poses
constexpr double kExactTolerance = 1e-9;      // exact poses met to this times L (the default)
constexpr double kPlatformSeedOffset = 1e-2;  // seed offset, times L: the seed misses them too
constexpr int kExactPoseA = 3, kExactPoseB = 8;

// Twelve poses of a random platform of the given dyads (tests/support/random_spatial.h), all
// perturbed but poses kExactPoseA and kExactPoseB, which stay on the platform and are flagged.
struct PinnedPlatformTask {
  std::vector<SpatialDyad> planted;
  std::vector<DualQuaternion> poses;
  std::vector<bool> exact;
  double length = 1.0;  // RMS distance of the pose origins from their centroid
};

PinnedPlatformTask MakePinnedPlatformTask(std::mt19937_64& rng,
                                          const std::vector<SpatialDyadType>& types) {
  PinnedPlatformTask task;
  const linkfit::testing::PlantedSpatialTask platform =
      linkfit::testing::RandomPlatformTask(rng, kPlatformPoses, types);
  task.planted = platform.planted;
  task.poses = platform.poses;
  const std::vector<DualQuaternion> clean = task.poses;
  linkfit::testing::PerturbSpatialPoses(rng, kPlatformNoise, &task.poses);
  task.exact.assign(task.poses.size(), false);
  for (int j : {kExactPoseA, kExactPoseB}) {
    task.poses[j] = clean[j];
    task.exact[j] = true;
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : task.poses) centroid += pose.Translation();
  centroid /= static_cast<double>(task.poses.size());
  double sum = 0.0;
  for (const DualQuaternion& pose : task.poses) {
    sum += (pose.Translation() - centroid).squaredNorm();
  }
  task.length = std::sqrt(sum / static_cast<double>(task.poses.size()));
  return task;
}

// Largest and smallest |residual| over the poses flagged `flagged` (exact or not).
double MaxResidualWhere(const SpatialDyad& dyad, const PinnedPlatformTask& task, bool flagged) {
  double most = 0.0;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    if (task.exact[j] == flagged) most = std::max(most, std::abs(dyad.Residual(task.poses[j])));
  }
  return most;
}
double MinResidualWhere(const SpatialDyad& dyad, const PinnedPlatformTask& task, bool flagged) {
  double least = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < task.poses.size(); ++j) {
    if (task.exact[j] == flagged) least = std::min(least, std::abs(dyad.Residual(task.poses[j])));
  }
  return least;
}

// A 5-SS platform and a mixed one (four SS, one PS), twelve noisy poses, two of them exact:
// each planted dyad, moved off by 1e-2 L, refined with the exact flags meets the two exact poses
// to 1e-9 L and no non-exact pose; it fits no worse than the planted dyad (which meets the exact
// poses too: the constrained optimum is at most its cost) and no better than the refinement
// without flags (the unconstrained optimum), which misses the exact poses; refined again with
// the flags, that optimum gives way to one that meets them, at a higher cost.
TEST(SpatialDyadRefiner, ExactPosesAreMetOnANoisyPlatform) {
  constexpr unsigned kPlatformSeed = kSeed + 13;
  constexpr int kPlatforms = 6;
  std::mt19937_64 rng(kPlatformSeed);
  RandomSource source(kPlatformSeed);
  for (int trial = 0; trial < kPlatforms; ++trial) {
    SCOPED_TRACE(SeedTrace(kPlatformSeed, trial));
    std::vector<SpatialDyadType> types(5, SpatialDyadType::kSS);
    if (trial % 2) types.back() = SpatialDyadType::kPS;
    const PinnedPlatformTask task = MakePinnedPlatformTask(rng, types);
    const double length = task.length;
    for (size_t k = 0; k < task.planted.size(); ++k) {
      SCOPED_TRACE("planted dyad " + std::to_string(k));
      const SpatialDyad& planted = task.planted[k];
      ASSERT_LT(MaxResidualWhere(planted, task, true), 1e-12 * length);
      const SpatialDyad seed_dyad = Perturbed(source, planted, kPlatformSeedOffset * length);

      SpatialDyad free = seed_dyad;
      RefineSpatialDyad(task.poses, {}, {}, length, &free);
      SpatialDyad pinned = seed_dyad;
      const RefinerSummary summary = RefineSpatialDyad(task.poses, {}, task.exact, length, &pinned);
      SCOPED_TRACE(summary.message);
      EXPECT_EQ(pinned.type, planted.type);
      EXPECT_LE(MaxResidualWhere(pinned, task, true), kExactTolerance * length);
      EXPECT_GT(MinResidualWhere(pinned, task, false), kExactTolerance * length);
      EXPECT_EQ(summary.message.find("not met"), std::string::npos);
      EXPECT_PRED3(NotWorse, Cost(pinned, task.poses), Cost(planted, task.poses), kCostSlack);
      EXPECT_PRED3(NotWorse, Cost(free, task.poses), Cost(pinned, task.poses), kCostSlack);
      EXPECT_PRED4(Near, summary.final_max, pinned.MaxResidual(task.poses), kReportedAgreement,
                   kResidualFloor);
      // The flags make the difference: the unconstrained optimum misses the exact poses.
      EXPECT_GT(MaxResidualWhere(free, task, true), 1e3 * kExactTolerance * length);

      // From the unconstrained optimum as the seed: a lower cost, but missing the exact poses,
      // the seed gives way to a design that meets them.
      SpatialDyad from_free = free;
      RefineSpatialDyad(task.poses, {}, task.exact, length, &from_free);
      EXPECT_LE(MaxResidualWhere(from_free, task, true), kExactTolerance * length);
      EXPECT_GT(Cost(from_free, task.poses), Cost(free, task.poses));
    }
  }
}

// Without exact flags the refinement is the one it always was: an all-false vector gives
// bit for bit what an empty one gives, dyad and summary.
TEST(SpatialDyadRefiner, NoExactFlagsIsTheSameAsEmptyFlags) {
  constexpr unsigned kPlatformSeed = kSeed + 14;
  std::mt19937_64 rng(kPlatformSeed);
  RandomSource source(kPlatformSeed);
  for (int trial = 0; trial < 4; ++trial) {
    SCOPED_TRACE(SeedTrace(kPlatformSeed, trial));
    std::vector<SpatialDyadType> types(5, SpatialDyadType::kSS);
    if (trial % 2) types.back() = SpatialDyadType::kPS;
    const PinnedPlatformTask task = MakePinnedPlatformTask(rng, types);
    const std::vector<bool> none(task.poses.size(), false);
    for (const SpatialDyad& planted : task.planted) {
      const SpatialDyad seed_dyad = Perturbed(source, planted, kPlatformSeedOffset * task.length);
      SpatialDyad with_empty = seed_dyad, with_none = seed_dyad;
      const RefinerSummary empty_summary =
          RefineSpatialDyad(task.poses, {}, {}, task.length, &with_empty);
      const RefinerSummary none_summary =
          RefineSpatialDyad(task.poses, {}, none, task.length, &with_none);
      EXPECT_EQ(with_none.type, with_empty.type);
      EXPECT_EQ(with_none.fixed_pivot, with_empty.fixed_pivot);
      EXPECT_EQ(with_none.moving_pivot, with_empty.moving_pivot);
      EXPECT_EQ(with_none.radius, with_empty.radius);
      EXPECT_EQ(with_none.plane_normal, with_empty.plane_normal);
      EXPECT_EQ(with_none.plane_offset, with_empty.plane_offset);
      EXPECT_EQ(none_summary.final_cost, empty_summary.final_cost);
      EXPECT_EQ(none_summary.iterations, empty_summary.iterations);
      EXPECT_EQ(none_summary.message, empty_summary.message);
    }
  }
}

// More exact poses than an SS dyad has parameters (nine of twelve, noisy): they cannot all be
// met; the summary says so and by how much, and the numbers stay finite.
TEST(SpatialDyadRefiner, TooManyExactPosesAreReportedNotMet) {
  constexpr unsigned kPlatformSeed = kSeed + 15;
  std::mt19937_64 rng(kPlatformSeed);
  RandomSource source(kPlatformSeed);
  PinnedPlatformTask task =
      MakePinnedPlatformTask(rng, std::vector<SpatialDyadType>(5, SpatialDyadType::kSS));
  linkfit::testing::PerturbSpatialPoses(rng, kPlatformNoise, &task.poses);  // the pinned ones too
  task.exact.assign(task.poses.size(), true);
  for (int j : {0, 5, 11}) task.exact[j] = false;
  SpatialDyad dyad = Perturbed(source, task.planted[0], kPlatformSeedOffset * task.length);
  const RefinerSummary summary = RefineSpatialDyad(task.poses, {}, task.exact, task.length, &dyad);
  SCOPED_TRACE(summary.message);
  EXPECT_TRUE(AllFinite(dyad));
  EXPECT_TRUE(AllFinite(summary));
  EXPECT_GT(MaxResidualWhere(dyad, task, true), kExactTolerance * task.length);
  EXPECT_NE(summary.message.find("exact poses not met"), std::string::npos);
  EXPECT_NE(summary.message.find("more than the dyad's 7 parameters"), std::string::npos);
}

// Prints the median, 90th percentile and worst time per refine (SS and PS, noisy data, seeds 1e-2 L
// off).
TEST(SpatialDyadRefiner, ReportsTimePerRefine) {
  const unsigned seed = kSeed + 11;
  RandomSource source(seed);
  constexpr int kRuns = 200;
  std::printf("%-6s %6s %10s %10s %10s %10s\n", "model", "poses", "median_us", "p90_us", "worst_us",
              "mean_iter");
  for (SpatialDyadType type : {SpatialDyadType::kSS, SpatialDyadType::kPS}) {
    for (int count : {kMinPoses, kMaxPoses}) {
      std::vector<double> seconds;
      double iterations = 0.0;
      for (int run = 0; run < kRuns; ++run) {
        const SpatialDyad truth =
            type == SpatialDyadType::kSS ? RandomSphereDyad(source) : RandomPlaneDyad(source);
        const std::vector<DualQuaternion> poses =
            Noisy(source, PosesOnDyad(source, truth, count), kNoise);
        SpatialDyad refined = Perturbed(source, truth, kSeedOffset * kLength);
        const RefinerSummary summary = RefineSpatialDyad(poses, {}, {}, kLength, &refined);
        seconds.push_back(summary.seconds);
        iterations += summary.iterations;
      }
      std::sort(seconds.begin(), seconds.end());
      EXPECT_GT(seconds.front(), 0.0);
      std::printf("%-6s %6d %10.1f %10.1f %10.1f %10.1f\n", linkfit::SpatialDyadTypeName(type),
                  count, 1e6 * seconds[kRuns / 2], 1e6 * seconds[kRuns * 9 / 10],
                  1e6 * seconds.back(), iterations / kRuns);
    }
  }
}

}  // namespace
