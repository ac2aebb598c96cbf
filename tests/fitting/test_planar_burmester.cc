#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "fitting/planar_burmester.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

using testing::DyadScale;
using testing::GeneratedTask;
using testing::NearestDyadDistance;
using testing::RandomTask;

// Relative error of a recovered dyad: pivot, radius and line differences over the dyad's own
// size (DyadScale: its largest pivot distance from the poses, never less than L).
constexpr double kRecoveryTolerance = 1e-9;
constexpr double kResidualTolerance = 1e-9;  // relative to L, every returned dyad
constexpr int kTasksPerType = 200;

// The constraint vector z of a known dyad (planar_burmester.h file comment).
ConstraintVector ConstraintOf(const PlanarDyad& dyad) {
  ConstraintVector z;
  const Eigen::Vector2d m = dyad.moving_pivot;
  if (dyad.type == DyadType::kRR) {
    const Eigen::Vector2d k = -dyad.fixed_pivot;  // K0 = 1
    const double k3 = k.squaredNorm() - dyad.radius * dyad.radius;
    z << 1.0, m.x(), m.y(), k.x(), k.y(), k.dot(m), k.y() * m.x() - k.x() * m.y(),
        k3 + m.squaredNorm();
  } else {
    // Line n . P = h as 2 K . P + K3 = 0 with K = n / 2, K3 = -h.
    const Eigen::Vector2d n(-dyad.line_direction.y(), dyad.line_direction.x());
    const Eigen::Vector2d k = 0.5 * n;
    z << 0.0, 0.0, 0.0, k.x(), k.y(), k.dot(m), k.y() * m.x() - k.x() * m.y(),
        -n.dot(dyad.line_point);
  }
  return z;
}

TEST(PlanarBurmester, ConstraintRowVanishesOnGeneratingDyads) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kPR);
    for (const PlanarDyad& dyad : {task.input, task.output}) {
      const ConstraintVector z = ConstraintOf(dyad);
      for (const PlanarPose& pose : task.poses) {
        EXPECT_NEAR(ConstraintRow(pose).dot(z), 0.0, 1e-12 * z.norm()) << "trial " << trial;
      }
    }
  }
}

// Solves random exact five-pose tasks of one mechanism type and requires both generating
// dyads back and every returned dyad on its circle or line at every pose.
void ExpectRecovery(DyadType input, DyadType output, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < kTasksPerType; ++trial) {
    const GeneratedTask task = RandomTask(rng, input, output);
    const double length = CharacteristicLength(task.poses);
    std::vector<PlanarDyad> dyads;
    PlanarBurmesterSummary summary;
    SolvePlanarBurmester(task.poses, PlanarBurmesterOptions(), &dyads, &summary);
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    EXPECT_EQ(summary.roots_total, 4);
    EXPECT_LE(summary.roots_real, 4);
    EXPECT_LE(NearestDyadDistance(dyads, task.input, DyadScale(task.input, task.poses)),
              kRecoveryTolerance);
    EXPECT_LE(NearestDyadDistance(dyads, task.output, DyadScale(task.output, task.poses)),
              kRecoveryTolerance);
    for (const PlanarDyad& dyad : dyads) {
      EXPECT_LE(dyad.MaxResidual(task.poses), kResidualTolerance * length)
          << DyadTypeName(dyad.type);
    }
  }
}

TEST(PlanarBurmester, RecoversFourBars) { ExpectRecovery(DyadType::kRR, DyadType::kRR, 1); }
TEST(PlanarBurmester, RecoversSliderCranks) { ExpectRecovery(DyadType::kRR, DyadType::kPR, 2); }
TEST(PlanarBurmester, RecoversInvertedSliderCranks) {
  ExpectRecovery(DyadType::kRR, DyadType::kRP, 3);
}
TEST(PlanarBurmester, DoubleSliderMotionIsReportedDegenerate) {
  // An elliptic trammel moves E by the Cardan motion: every point of a circle of E runs on a
  // line, so there is a curve of PR dyads, not four isolated ones. The solver must say so.
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 50; ++trial) {
    const GeneratedTask task = RandomTask(rng, DyadType::kPR, DyadType::kPR);
    std::vector<PlanarDyad> dyads;
    PlanarBurmesterSummary summary;
    SolvePlanarBurmester(task.poses, PlanarBurmesterOptions(), &dyads, &summary);
    EXPECT_TRUE(summary.degenerate) << "trial " << trial;
    EXPECT_TRUE(dyads.empty()) << "trial " << trial;
  }
}
TEST(PlanarBurmester, RecoversRPRP) { ExpectRecovery(DyadType::kPR, DyadType::kRP, 5); }

// How far the exact answer of `poses` moves when every input number changes by one unit in
// the last place (the rounding any transformation of the data brings): the largest relative
// change of any dyad over a few random perturbations.
double OneUlpSensitivity(const std::vector<PlanarPose>& poses, std::mt19937_64& rng) {
  std::vector<PlanarDyad> reference;
  SolvePlanarBurmester(poses, PlanarBurmesterOptions(), &reference);
  std::uniform_int_distribution<int> sign(0, 1);
  const double ulp = std::numeric_limits<double>::epsilon();
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) {
    std::vector<PlanarPose> perturbed = poses;
    for (PlanarPose& pose : perturbed) {
      pose.origin_in_fixed.x() *= 1.0 + (sign(rng) ? ulp : -ulp);
      pose.origin_in_fixed.y() *= 1.0 + (sign(rng) ? ulp : -ulp);
      pose.theta *= 1.0 + (sign(rng) ? ulp : -ulp);
    }
    std::vector<PlanarDyad> dyads;
    SolvePlanarBurmester(perturbed, PlanarBurmesterOptions(), &dyads);
    if (dyads.size() != reference.size()) return std::numeric_limits<double>::infinity();
    for (const PlanarDyad& dyad : reference) {
      worst = std::max(worst, NearestDyadDistance(dyads, dyad, DyadScale(dyad, poses)));
    }
  }
  return worst;
}

// Tasks whose exact answer moves by more than this under a 1-ulp change of the data cannot be
// compared at kRecoveryTolerance after a transformation that rounds the data (by a few ulps);
// the invariance tests skip them and require that they stay a small minority. The sensitivity
// covers all four dyads, whose far-pivot or near-double members are less well conditioned
// than the generating pair: 3 to 5 of 100 random tasks are skipped (recorded as test
// properties), so the cap below is a guard against skipping wholesale, not an accuracy bound.
constexpr double kDataLimitedSensitivity = 1e-10;
constexpr double kMaxDataLimitedShare = 0.10;

// The answer must transform with the data: the dyads of the transformed task are the
// transformed dyads, one to one. Returns false when the task was skipped as data-limited.
bool ExpectSameAnswer(const std::vector<PlanarPose>& poses, const Similarity2& sigma,
                      const Similarity2& epsilon, uint64_t trial, std::mt19937_64& rng) {
  if (OneUlpSensitivity(poses, rng) > kDataLimitedSensitivity) return false;
  std::vector<PlanarPose> moved;
  for (const PlanarPose& pose : poses) moved.push_back(TransformPose(pose, sigma, epsilon));
  std::vector<PlanarDyad> original, transformed;
  SolvePlanarBurmester(poses, PlanarBurmesterOptions(), &original);
  SolvePlanarBurmester(moved, PlanarBurmesterOptions(), &transformed);
  EXPECT_EQ(original.size(), transformed.size()) << "trial " << trial;
  for (const PlanarDyad& dyad : original) {
    const PlanarDyad expected = TransformDyad(dyad, sigma, epsilon);
    EXPECT_LE(NearestDyadDistance(transformed, expected, DyadScale(expected, moved)),
              kRecoveryTolerance)
        << "trial " << trial << " " << DyadTypeName(dyad.type);
  }
  return true;
}

constexpr int kInvarianceTrials = 100;

TEST(PlanarBurmester, InvariantToRigidMotionOfTheFixedFrame) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < kInvarianceTrials; ++trial) {
    const DyadType second = trial % 3 == 0   ? DyadType::kRR
                            : trial % 3 == 1 ? DyadType::kPR
                                             : DyadType::kRP;
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, second);
    Similarity2 sigma;
    sigma.angle = M_PI * uniform(rng);
    sigma.translation = Eigen::Vector2d(5.0 * uniform(rng), 5.0 * uniform(rng));
    compared += ExpectSameAnswer(task.poses, sigma, Similarity2(), trial, rng);
  }
  EXPECT_GE(compared, (1.0 - kMaxDataLimitedShare) * kInvarianceTrials);
  RecordProperty("data_limited_skipped", kInvarianceTrials - compared);
}

TEST(PlanarBurmester, InvariantToUnits) {
  std::mt19937_64 rng(22);
  for (double scale : {1e-3, 1e3}) {
    int compared = 0;
    for (int trial = 0; trial < kInvarianceTrials; ++trial) {
      const GeneratedTask task =
          RandomTask(rng, DyadType::kRR, trial % 2 ? DyadType::kRP : DyadType::kPR);
      Similarity2 units;
      units.scale = scale;
      compared += ExpectSameAnswer(task.poses, units, units, trial, rng);
    }
    EXPECT_GE(compared, (1.0 - kMaxDataLimitedShare) * kInvarianceTrials) << "scale " << scale;
    RecordProperty(scale < 1.0 ? "data_limited_skipped_milli" : "data_limited_skipped_kilo",
                   kInvarianceTrials - compared);
  }
}

TEST(PlanarBurmester, InvariantToPoseOrder) {
  std::mt19937_64 rng(23);
  for (int trial = 0; trial < 50; ++trial) {
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR);
    std::vector<PlanarPose> shuffled = task.poses;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    std::vector<PlanarDyad> original, reordered;
    SolvePlanarBurmester(task.poses, PlanarBurmesterOptions(), &original);
    SolvePlanarBurmester(shuffled, PlanarBurmesterOptions(), &reordered);
    ASSERT_EQ(original.size(), reordered.size()) << "trial " << trial;
    for (const PlanarDyad& dyad : original) {
      EXPECT_LE(NearestDyadDistance(reordered, dyad, DyadScale(dyad, task.poses)),
                kRecoveryTolerance)
          << "trial " << trial;
    }
  }
}

TEST(PlanarBurmester, CurvilinearTranslationIsDegenerate) {
  // All poses of one orientation: every point of E moves on a congruent curve, the rows are
  // dependent and there is a family of dyads, not four.
  std::vector<PlanarPose> poses;
  for (int j = 0; j < 5; ++j) {
    poses.emplace_back(std::cos(0.4 * j), std::sin(0.4 * j), 0.3);
  }
  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary summary;
  EXPECT_EQ(SolvePlanarBurmester(poses, PlanarBurmesterOptions(), &dyads, &summary), 0);
  EXPECT_TRUE(summary.degenerate);
}

TEST(PlanarBurmester, LeastSquaresSeedIsExactOnExactData) {
  // More than five exact poses of a 4R: the seed space still contains both generating dyads.
  std::mt19937_64 rng(31);
  for (int trial = 0; trial < 20; ++trial) {
    const GeneratedTask task = RandomTask(rng, DyadType::kRR, DyadType::kRR, 9);
    const double length = CharacteristicLength(task.poses);
    std::vector<PlanarDyad> dyads;
    SolvePlanarBurmester(task.poses, PlanarBurmesterOptions(), &dyads);
    EXPECT_LE(NearestDyadDistance(dyads, task.input, length), 1e-8) << "trial " << trial;
    EXPECT_LE(NearestDyadDistance(dyads, task.output, length), 1e-8) << "trial " << trial;
  }
}

}  // namespace
}  // namespace linkfit
