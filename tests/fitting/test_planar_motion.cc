#include <gtest/gtest.h>

#include <random>

#include "fitting/planar_motion.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

using testing::DyadDistance;
using testing::GeneratedTask;
using testing::RandomTask;

constexpr double kRecoveryTolerance = 1e-9;   // relative to L
constexpr double kPoseErrorTolerance = 1e-9;  // relative to L
constexpr int kTrials = 100;

Task TaskOf(const std::vector<PlanarPose>& poses) {
  Task task;
  task.planar_poses = poses;
  return task;
}

// The mechanism made of the two generating dyads must be listed, typed, and must reach every
// pose when assembled; every listed mechanism made of exact dyads assembles too.
void ExpectGeneratingMechanism(DyadType input, DyadType output, FourBarType type, uint64_t seed) {
  std::mt19937_64 rng(seed);
  int found = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const GeneratedTask generated = RandomTask(rng, input, output);
    const PlanarMotionResult result = SolvePlanarMotion(TaskOf(generated.poses));
    const double length = result.scale;
    EXPECT_EQ(result.method, "exact");
    bool listed = false;
    for (const MechanismReport& mechanism : result.mechanisms) {
      const PlanarDyad& a = result.dyads[mechanism.input_dyad].dyad;
      const PlanarDyad& b = result.dyads[mechanism.output_dyad].dyad;
      EXPECT_EQ(mechanism.type, ClassifyFourBar(a.type, b.type));
      ASSERT_TRUE(mechanism.max_pose_error.has_value()) << "trial " << trial;
      EXPECT_LE(*mechanism.max_pose_error, kPoseErrorTolerance * length) << "trial " << trial;
      const bool same = (DyadDistance(a, generated.input, length) <= kRecoveryTolerance &&
                         DyadDistance(b, generated.output, length) <= kRecoveryTolerance) ||
                        (DyadDistance(b, generated.input, length) <= kRecoveryTolerance &&
                         DyadDistance(a, generated.output, length) <= kRecoveryTolerance);
      if (same) {
        listed = true;
        EXPECT_EQ(mechanism.type, type) << "trial " << trial;
      }
    }
    found += listed;
  }
  // Data-limited tasks (see the benchmark) may miss 1e-9; nearly all must pass.
  EXPECT_GE(found, kTrials - 1);
}

TEST(PlanarMotion, ListsTheGeneratingFourBar) {
  ExpectGeneratingMechanism(DyadType::kRR, DyadType::kRR, FourBarType::k4R, 101);
}
TEST(PlanarMotion, ListsTheGeneratingSliderCrank) {
  ExpectGeneratingMechanism(DyadType::kRR, DyadType::kPR, FourBarType::kSliderCrank, 102);
}
TEST(PlanarMotion, ListsTheGeneratingInvertedSliderCrank) {
  ExpectGeneratingMechanism(DyadType::kRR, DyadType::kRP, FourBarType::kInvertedSliderCrank, 103);
}

TEST(PlanarMotion, RPDyadsAgreeWithTheInvertedMotion) {
  // An RP dyad of a motion is a PR dyad of the inverted motion (Sigma seen from E): solving
  // the inverted poses must give the same dyads, inverted.
  std::mt19937_64 rng(104);
  for (int trial = 0; trial < kTrials; ++trial) {
    const GeneratedTask generated = RandomTask(rng, DyadType::kRR, DyadType::kRP);
    std::vector<PlanarPose> inverted;
    for (const PlanarPose& pose : generated.poses) inverted.push_back(pose.Inverse());
    std::vector<PlanarDyad> direct, from_inverted;
    SolvePlanarBurmester(generated.poses, PlanarBurmesterOptions(), &direct);
    SolvePlanarBurmester(inverted, PlanarBurmesterOptions(), &from_inverted);
    const double length = CharacteristicLength(generated.poses);
    int rp_count = 0;
    for (const PlanarDyad& dyad : direct) {
      if (dyad.type != DyadType::kRP) continue;
      ++rp_count;
      EXPECT_LE(testing::NearestDyadDistance(from_inverted, dyad.Inverted(), length), 1e-8)
          << "trial " << trial;
    }
    EXPECT_GE(rp_count, 1) << "trial " << trial;
  }
}

TEST(PlanarMotion, MoreThanFivePosesGiveTheLeastSquaresSeed) {
  std::mt19937_64 rng(105);
  const GeneratedTask generated = RandomTask(rng, DyadType::kRR, DyadType::kRR, 8);
  const PlanarMotionResult result = SolvePlanarMotion(TaskOf(generated.poses));
  EXPECT_EQ(result.method, "least-squares");
  ASSERT_FALSE(result.notes.empty());
  EXPECT_NE(result.notes.front().find("least-squares"), std::string::npos);
  // Exact data: the seed contains the generating dyads, and their 4R reaches every pose.
  bool reached = false;
  for (const MechanismReport& mechanism : result.mechanisms) {
    reached =
        reached || (mechanism.max_pose_error && *mechanism.max_pose_error <= 1e-8 * result.scale);
  }
  EXPECT_TRUE(reached);
}

TEST(PlanarMotion, DegenerateTaskSaysSo) {
  std::vector<PlanarPose> poses;
  for (int j = 0; j < 5; ++j) poses.emplace_back(std::cos(0.4 * j), std::sin(0.4 * j), 0.3);
  const PlanarMotionResult result = SolvePlanarMotion(TaskOf(poses));
  EXPECT_TRUE(result.dyads.empty());
  EXPECT_TRUE(result.mechanisms.empty());
  ASSERT_FALSE(result.notes.empty());
  EXPECT_NE(result.notes.front().find("family of dyads"), std::string::npos);
}

TEST(PlanarMotion, UnsupportedKindsReturnANote) {
  Task task;
  task.problem = ProblemKind::kPath;
  const PlanarMotionResult result = SolveTask(task);
  EXPECT_TRUE(result.dyads.empty());
  ASSERT_EQ(result.notes.size(), 1u);
}

}  // namespace
}  // namespace linkfit
