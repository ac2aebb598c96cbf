#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "fitting/spatial_motion.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_spatial.h"

namespace linkfit {
namespace {

constexpr double kRecoveryTolerance = 1e-8;  // relative dyad error, issue 4

Task SpatialTask(const std::vector<DualQuaternion>& poses) { return SpatialMotionTask(poses); }

// The planar poses placed in space on the plane through `origin` with unit normal `normal`;
// E's plane frame is turned by `body` inside E.
std::vector<DualQuaternion> Embed(const std::vector<PlanarPose>& planar,
                                  const Eigen::Matrix3d& plane_axes, const Eigen::Vector3d& origin,
                                  const Eigen::Matrix3d& body) {
  std::vector<DualQuaternion> poses;
  for (const PlanarPose& pose : planar) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // x_E = body * (p, z) maps to plane_axes * (R(theta) p + o, z) + origin.
    const Eigen::Matrix3d rotation = plane_axes * turn * body.transpose();
    const Eigen::Vector3d translation =
        plane_axes * Eigen::Vector3d(pose.origin_in_fixed.x(), pose.origin_in_fixed.y(), 0.0) +
        origin;
    poses.push_back(DualQuaternion::FromRotationTranslation(rotation, translation));
  }
  return poses;
}

TEST(SpatialMotion, FivePlanarPosesAreSolvedAsAPlanarFourBar) {
  for (int seed = 0; seed < 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 5);
    const Eigen::Matrix3d plane_axes = testing::RandomSpatialPose(rng).Rotation();
    const Eigen::Matrix3d body = testing::RandomSpatialPose(rng).Rotation();
    const Eigen::Vector3d origin(2.0, -1.0, 5.0);
    const Task task = SpatialTask(Embed(generated.poses, plane_axes, origin, body));
    const SpatialMotionResult result = SolveSpatialMotion(task);
    ASSERT_EQ(result.model, "planar");
    ASSERT_TRUE(result.planar && result.plane);
    EXPECT_LT(result.plane->planarity, 1e-12);
    // The generating dyads come back, as RR dyads whose pivots, mapped to space, are the
    // generating pivots (fixed pivot on the plane of motion, moving pivot on E's plane).
    for (const PlanarDyad& expected : {generated.input, generated.output}) {
      const Eigen::Vector3d fixed_expected =
          plane_axes * Eigen::Vector3d(expected.fixed_pivot.x(), expected.fixed_pivot.y(), 0) +
          origin;
      const Eigen::Vector3d moving_expected =
          body * Eigen::Vector3d(expected.moving_pivot.x(), expected.moving_pivot.y(), 0);
      double best = 1e300;
      for (const DyadReport& report : result.planar->dyads) {
        if (report.dyad.type != DyadType::kRR) continue;
        const Eigen::Vector3d fixed =
            result.plane->origin_in_fixed +
            result.plane->axes_in_fixed.leftCols<2>() * report.dyad.fixed_pivot;
        const Eigen::Vector3d moving =
            result.plane->axes_in_moving.leftCols<2>() * report.dyad.moving_pivot;
        best = std::min(
            best, std::max((fixed - fixed_expected).norm(), (moving - moving_expected).norm()) /
                      testing::DyadScale(expected, generated.poses));
      }
      EXPECT_LT(best, kRecoveryTolerance);
    }
    EXPECT_FALSE(result.planar->mechanisms.empty());
  }
}

TEST(SpatialMotion, NearlyPlanarPosesStaySpatial) {
  // Tilted by 1e-3 L out of the plane: far beyond the planarity tolerance.
  std::mt19937_64 rng(3);
  const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 7);
  std::vector<DualQuaternion> poses = Embed(generated.poses, Eigen::Matrix3d::Identity(),
                                            Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  poses[3] = DualQuaternion::FromRotationTranslation(
      poses[3].Rotation(), poses[3].Translation() + 1e-3 * Eigen::Vector3d::UnitZ());
  const SpatialMotionResult result = SolveSpatialMotion(SpatialTask(poses));
  EXPECT_EQ(result.model, "spatial");
}

TEST(SpatialMotion, SevenPlanarPosesReportThePlaneFamily) {
  std::mt19937_64 rng(4);
  const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 7);
  const SpatialMotionResult result = SolveSpatialMotion(
      SpatialTask(Embed(generated.poses, testing::RandomSpatialPose(rng).Rotation(),
                        Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity())));
  EXPECT_EQ(result.model, "planar");
  EXPECT_EQ(result.method, "least-squares");
  bool family = false;
  for (const std::string& note : result.notes) family |= note.find("PS dyads") != std::string::npos;
  EXPECT_TRUE(family);
  // Exact planar data from a four-bar: its two dyads are among the least-squares seeds, and
  // fit every pose.
  ASSERT_TRUE(result.planar);
  int exact = 0;
  for (const DyadReport& report : result.planar->dyads) {
    exact += report.dyad.type == DyadType::kRR && report.max_residual < 1e-9 * result.scale;
  }
  EXPECT_EQ(exact, 2);
}

TEST(SpatialMotion, FewerThanSevenPosesGiveTheFamilyDimension) {
  std::mt19937_64 rng(5);
  std::vector<DualQuaternion> poses;
  for (int j = 0; j < 5; ++j) poses.push_back(testing::RandomSpatialPose(rng));
  const SpatialMotionResult result = SolveSpatialMotion(SpatialTask(poses));
  EXPECT_TRUE(result.dyads.empty());
  ASSERT_FALSE(result.notes.empty());
  EXPECT_NE(result.notes[0].find("2-parameter family"), std::string::npos) << result.notes[0];
}

TEST(SpatialMotion, GivenPivotsDetermineDyadsWithFourToSixPoses) {
  for (int count : {4, 5, 6}) {
    SCOPED_TRACE("poses " + std::to_string(count));
    std::mt19937_64 rng(20 + count);
    const DualQuaternion start = testing::RandomSpatialPose(rng);
    const std::vector<SpatialDyad> planted =
        testing::DyadsThroughPose(rng, start, {SpatialDyadType::kSS, SpatialDyadType::kSS});
    Task task = SpatialTask(testing::PosesOnDyads(rng, planted, start, count));
    task.spatial_moving_pivots = {planted[0].moving_pivot};
    task.spatial_fixed_pivots = {planted[1].fixed_pivot};
    const SpatialMotionResult result = SolveSpatialMotion(task);
    ASSERT_EQ(result.dyads.size(), 2u);
    EXPECT_LT(testing::SpatialDyadDistance(result.dyads[0].dyad, planted[0]), kRecoveryTolerance);
    EXPECT_LT(testing::SpatialDyadDistance(result.dyads[1].dyad, planted[1]), kRecoveryTolerance);
  }
}

TEST(SpatialMotion, GivenPivotOnAPlaneGivesAPSDyad) {
  std::mt19937_64 rng(31);
  const DualQuaternion start = testing::RandomSpatialPose(rng);
  const std::vector<SpatialDyad> planted =
      testing::DyadsThroughPose(rng, start, {SpatialDyadType::kPS});
  Task task = SpatialTask(testing::PosesOnDyads(rng, planted, start, 5));
  task.spatial_moving_pivots = {planted[0].moving_pivot};
  const SpatialMotionResult result = SolveSpatialMotion(task);
  ASSERT_EQ(result.dyads.size(), 1u);
  EXPECT_LT(testing::SpatialDyadDistance(result.dyads[0].dyad, planted[0]), kRecoveryTolerance);
}

TEST(SpatialMotion, SevenPosesListDyadsBySmallestRadius) {
  std::mt19937_64 rng(40);
  std::vector<DualQuaternion> poses;
  for (int j = 0; j < 7; ++j) poses.push_back(testing::RandomSpatialPose(rng));
  const SpatialMotionResult result = SolveSpatialMotion(SpatialTask(poses));
  EXPECT_EQ(result.roots_total, 20);
  for (size_t i = 1; i < result.dyads.size(); ++i) {
    if (result.dyads[i].dyad.type == SpatialDyadType::kSS) {
      EXPECT_LE(result.dyads[i - 1].dyad.radius, result.dyads[i].dyad.radius);
    }
  }
}

}  // namespace
}  // namespace linkfit
