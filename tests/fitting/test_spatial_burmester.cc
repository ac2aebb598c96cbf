#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "fitting/model_choice.h"
#include "fitting/spatial_burmester.h"
#include "tests/support/bilinear_homotopy.h"
#include "tests/support/random_spatial.h"

namespace linkfit {
namespace {

constexpr double kRecoveryTolerance = 1e-8;   // relative dyad error, issue 4
constexpr double kResidualTolerance = 1e-10;  // dyad residual, units of L (L ~ 1 here)

TEST(SpatialConstraintRow, VanishesOnTheDyadParameters) {
  // Eq. 10 with P0 = A0 c4 - A4 |c|^2 / c4 and P = a (x) c holds at every pose of the dyad.
  std::mt19937_64 rng(11);
  const DualQuaternion start = testing::RandomSpatialPose(rng);
  const SpatialDyad dyad = testing::DyadsThroughPose(rng, start, {SpatialDyadType::kSS})[0];
  const std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, {dyad}, start, 5);
  const Eigen::Vector3d a = dyad.fixed_pivot, c = dyad.moving_pivot;
  Eigen::Matrix<double, 17, 1> p;
  // A0 from eq. 9 with A4 = 1: r^2 - A0 = |A|^2.
  const double a0 = dyad.radius * dyad.radius - a.squaredNorm();
  p[0] = a0 - c.squaredNorm();
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) p[1 + 4 * j + i] = (i < 3 ? a[i] : 1.0) * (j < 3 ? c[j] : 1.0);
  }
  for (const DualQuaternion& pose : poses) {
    EXPECT_NEAR(SpatialConstraintRow(pose.Rotation(), pose.Translation()).dot(p), 0.0, 1e-12);
  }
}

TEST(SpatialBurmester, RandomSevenPosesGiveTwentyVerifiedRoots) {
  for (int seed = 0; seed < 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::vector<DualQuaternion> poses;
    for (int j = 0; j < 7; ++j) poses.push_back(testing::RandomSpatialPose(rng));
    std::vector<BilinearRoot> roots;
    BilinearSolverSummary bilinear;
    ASSERT_EQ(SolveBilinearSystem(SpatialBilinearMatrices(poses, {}), {}, &roots, &bilinear), 20);
    EXPECT_EQ(bilinear.unconverged, 0);
    EXPECT_EQ(bilinear.real_roots % 2, 0);  // complex roots come in conjugate pairs
    for (const BilinearRoot& root : roots) EXPECT_LT(root.residual, 1e-11);

    std::vector<SpatialDyad> dyads;
    SpatialBurmesterSummary summary;
    SolveSpatialBurmester(poses, {}, {}, &dyads, &summary);
    EXPECT_EQ(summary.roots_total, 20);
    EXPECT_EQ(summary.roots_verified, 20);
    EXPECT_EQ(static_cast<int>(dyads.size()) + summary.imaginary_spheres, summary.roots_real);
    for (const SpatialDyad& dyad : dyads) EXPECT_LT(dyad.MaxResidual(poses), kResidualTolerance);
  }
}

TEST(SpatialBurmester, LeastSquaresFitOfADyadReturnsTheExactOneFromNearby) {
  // The fit the real part of a complex root gets (fitting/model_choice.h): from an SS, PS or SP
  // dyad moved by 1e-3, Levenberg-Marquardt on seven exact poses of the dyad returns it.
  std::mt19937_64 rng(31);
  for (const SpatialDyadType type :
       {SpatialDyadType::kSS, SpatialDyadType::kPS, SpatialDyadType::kSP}) {
    SCOPED_TRACE(SpatialDyadTypeName(type));
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    const SpatialDyad dyad = testing::DyadsThroughPose(rng, start, {type})[0];
    const std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, {dyad}, start, 7);
    SpatialDyad moved = dyad;
    moved.fixed_pivot += Eigen::Vector3d(1e-3, -1e-3, 1e-3);
    moved.moving_pivot += Eigen::Vector3d(-1e-3, 1e-3, 1e-3);
    moved.radius += 1e-3;
    moved.plane_normal = (moved.plane_normal + Eigen::Vector3d(1e-3, 0.0, -1e-3)).normalized();
    moved.plane_offset += 1e-3;
    const SpatialDyad fitted = FitDyadLeastSquares(moved, poses, 50);
    EXPECT_LT(fitted.MaxResidual(poses), kResidualTolerance);
    EXPECT_LT(testing::SpatialDyadDistance(fitted, dyad), kRecoveryTolerance);
  }
}

TEST(SpatialBurmester, RecoversPlantedSSPSAndSPDyads) {
  for (int seed = 0; seed < 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(100 + seed);
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    // Half the tasks plant an SP dyad (a moving point at infinity) instead of an SS one.
    const std::vector<SpatialDyad> planted = testing::DyadsThroughPose(
        rng, start,
        {SpatialDyadType::kSS, SpatialDyadType::kSS,
         seed % 2 ? SpatialDyadType::kSP : SpatialDyadType::kSS, SpatialDyadType::kPS});
    const std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, planted, start, 7);
    std::vector<SpatialDyad> dyads;
    SpatialBurmesterSummary summary;
    SolveSpatialBurmester(poses, {}, {}, &dyads, &summary);
    EXPECT_EQ(summary.roots_verified, summary.roots_total);
    for (const SpatialDyad& expected : planted) {
      EXPECT_LT(testing::NearestSpatialDyadDistance(dyads, expected), kRecoveryTolerance)
          << SpatialDyadTypeName(expected.type);
    }
  }
}

// Projective distance of two complex points (sine of the angle between them).
double Distance(const Eigen::Vector4cd& u, const Eigen::Vector4cd& v) {
  const double overlap = std::abs(u.dot(v)) / (u.norm() * v.norm());
  return std::sqrt(std::max(0.0, 1.0 - overlap * overlap));
}

TEST(SpatialBurmester, EigenvalueRootsAgreeWithTheHomotopy) {
  // A second, independent method: the 20-path multihomogeneous homotopy of the test support.
  constexpr double kAgreement = 1e-7;  // projective distance between the two methods' roots
  for (int seed = 0; seed < 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(500 + seed);
    std::vector<DualQuaternion> poses;
    for (int j = 0; j < 7; ++j) poses.push_back(testing::RandomSpatialPose(rng));
    const BilinearMatrices matrices = SpatialBilinearMatrices(poses, {});
    std::vector<BilinearRoot> roots;
    ASSERT_EQ(SolveBilinearSystem(matrices, {}, &roots), 20);
    std::vector<testing::HomotopyRoot> paths;
    ASSERT_EQ(testing::SolveBilinearByHomotopy(matrices, 77 + seed, &paths), 20);
    for (const testing::HomotopyRoot& path : paths) {
      double nearest = 1.0;
      for (const BilinearRoot& root : roots) {
        nearest = std::min(nearest, std::max(Distance(root.a, path.a), Distance(root.c, path.c)));
      }
      EXPECT_LT(nearest, kAgreement);
    }
  }
}

// The dyads of `poses` after mapping the fixed frame by (scale, rotation, shift) and the
// moving frame by the same scale, mapped back.
std::vector<SpatialDyad> SolveTransformed(const std::vector<DualQuaternion>& poses, double scale,
                                          const Eigen::Matrix3d& rotation,
                                          const Eigen::Vector3d& shift, bool reverse) {
  Similarity3 sigma;  // new fixed frame -> old
  sigma.scale = 1.0 / scale;
  sigma.rotation = rotation.transpose();
  sigma.translation = -sigma.scale * (sigma.rotation * shift);
  Similarity3 epsilon;
  epsilon.scale = 1.0 / scale;
  std::vector<DualQuaternion> transformed;
  for (const DualQuaternion& pose : poses) {
    transformed.push_back(TransformSpatialPose(pose, sigma, epsilon));
  }
  if (reverse) std::reverse(transformed.begin(), transformed.end());
  std::vector<SpatialDyad> dyads;
  SolveSpatialBurmester(transformed, {}, {}, &dyads);
  for (SpatialDyad& dyad : dyads) dyad = TransformSpatialDyad(dyad, sigma, epsilon);
  return dyads;
}

TEST(SpatialBurmester, InvariantToUnitsOrderAndTheFixedFrame) {
  constexpr double kInvariance = 1e-8;  // relative dyad difference after mapping back
  for (int seed = 0; seed < 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(900 + seed);
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    const std::vector<SpatialDyad> planted = testing::DyadsThroughPose(
        rng, start, {SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kPS});
    const std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, planted, start, 7);
    std::vector<SpatialDyad> reference;
    SolveSpatialBurmester(poses, {}, {}, &reference);
    const Eigen::Matrix3d turn = testing::RandomSpatialPose(rng).Rotation();
    const Eigen::Vector3d shift(3.0, -7.0, 11.0);
    for (const auto& [scale, rotation, translation, reverse] :
         {std::tuple{1e-3, Eigen::Matrix3d::Identity().eval(), Eigen::Vector3d::Zero().eval(),
                     false},
          std::tuple{1e3, Eigen::Matrix3d::Identity().eval(), Eigen::Vector3d::Zero().eval(),
                     false},
          std::tuple{1.0, Eigen::Matrix3d::Identity().eval(), Eigen::Vector3d::Zero().eval(), true},
          std::tuple{1.0, turn, shift, false}}) {
      SCOPED_TRACE("scale " + std::to_string(scale) + (reverse ? " reversed" : ""));
      const std::vector<SpatialDyad> dyads =
          SolveTransformed(poses, scale, rotation, translation, reverse);
      EXPECT_EQ(dyads.size(), reference.size());
      for (const SpatialDyad& expected : reference) {
        EXPECT_LT(testing::NearestSpatialDyadDistance(dyads, expected), kInvariance);
      }
    }
  }
}

TEST(SpatialBurmester, MoreThanSevenExactPosesGiveThePlantedDyads) {
  // Exact data beyond seven poses: the planted dyads make the centered rows vanish exactly, so
  // they lie in the span of the smallest singular vectors and the seed recovers them.
  for (int count : {8, 12, 30}) {
    SCOPED_TRACE("poses " + std::to_string(count));
    std::mt19937_64 rng(1300 + count);
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    const std::vector<SpatialDyad> planted = testing::DyadsThroughPose(
        rng, start, {SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kPS});
    const std::vector<DualQuaternion> poses = testing::PosesOnDyads(rng, planted, start, count);
    std::vector<SpatialDyad> dyads;
    SpatialBurmesterSummary summary;
    SolveSpatialBurmester(poses, {}, {}, &dyads, &summary);
    EXPECT_GT(summary.fit_residual, 0.0);  // the other dyads of the seed are only fitted
    for (const SpatialDyad& expected : planted) {
      EXPECT_LT(testing::NearestSpatialDyadDistance(dyads, expected), kRecoveryTolerance);
    }
  }
}

TEST(SpatialBurmester, PlanarPosesAreRankDeficient) {
  // Seven poses of a planar motion: families of dyads, reported as degenerate, never garbage.
  std::vector<DualQuaternion> poses;
  for (int j = 0; j < 7; ++j) {
    poses.push_back(DualQuaternion::FromAxisAngle(Eigen::Vector3d::UnitZ(), 0.4 * j,
                                                  Eigen::Vector3d(std::cos(j), 0.3 * j, 0.0)));
  }
  std::vector<SpatialDyad> dyads;
  SpatialBurmesterSummary summary;
  EXPECT_EQ(SolveSpatialBurmester(poses, {}, {}, &dyads, &summary), 0);
  EXPECT_TRUE(summary.degenerate);
}

}  // namespace
}  // namespace linkfit
