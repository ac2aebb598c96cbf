#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

constexpr double kExact = 1e-9;  // pose errors relative to L
constexpr double kDegree = M_PI / 180.0;

// A 4R with ground pivots (0,0) and (ground,0), E at the input pin with its x-axis toward the
// output pin.
struct FourBar {
  PlanarDyad input;
  PlanarDyad output;
};

FourBar MakeFourBar(double ground, double crank, double coupler, double rocker) {
  return {PlanarDyad::RR(Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 0), crank),
          PlanarDyad::RR(Eigen::Vector2d(ground, 0), Eigen::Vector2d(coupler, 0), rocker)};
}

// The coupler pose at input angle `angle` in assembly label `label`.
PlanarPose At(const FourBar& mechanism, double angle, int label) {
  std::vector<PlanarPose> configurations;
  const int count = AssembleFourBar(mechanism.input, mechanism.output, angle, 0.0, &configurations);
  EXPECT_GT(count, label) << "angle " << angle / kDegree;
  return configurations[std::min(label, count - 1)];
}

std::vector<PlanarPose> Poses(const FourBar& mechanism, const std::vector<double>& degrees,
                              const std::vector<int>& labels) {
  std::vector<PlanarPose> poses;
  for (size_t j = 0; j < degrees.size(); ++j) {
    poses.push_back(At(mechanism, degrees[j] * kDegree, labels[j]));
  }
  return poses;
}

// Grashof crank-rocker: shortest link (1) is the input crank; 1 + 4 < 3 + 3.5.
const FourBar kCrankRocker = MakeFourBar(4.0, 1.0, 3.5, 3.0);
// Non-Grashof (triple-rocker): 1.5 + 4 > 2.5 + 2.8.
const FourBar kTripleRocker = MakeFourBar(4.0, 2.5, 1.5, 2.8);

TEST(FourBarMotion, CrankOfACrankRockerHasTwoFullTurnCircuits) {
  const FourBarMotion motion = TraceFourBar(kCrankRocker.input, kCrankRocker.output, {}, 1.0);
  ASSERT_EQ(motion.circuits.size(), 2u);
  for (const FourBarCircuit& circuit : motion.circuits) {
    EXPECT_TRUE(circuit.input_rotates_fully);
    EXPECT_EQ(circuit.branches, 1);
    // Every sample closes the loop.
    for (const FourBarSample& sample : circuit.samples) {
      EXPECT_NEAR(kCrankRocker.input.Residual(sample.coupler), 0.0, 1e-12);
      EXPECT_NEAR(kCrankRocker.output.Residual(sample.coupler), 0.0, 1e-12);
    }
  }
}

TEST(FourBarMotion, RockerOfACrankRockerHasTwoCircuitsOfTwoBranches) {
  // Driven by the rocker, each circuit (open, crossed) covers its own range of rocker angles,
  // and the rocker reverses at its limits.
  const FourBarMotion motion = TraceFourBar(kCrankRocker.output, kCrankRocker.input, {}, 1.0);
  ASSERT_EQ(motion.circuits.size(), 2u);
  for (const FourBarCircuit& circuit : motion.circuits) {
    EXPECT_FALSE(circuit.input_rotates_fully);
    EXPECT_EQ(circuit.branches, 2);
  }
}

TEST(FourBarMotion, TripleRockerHasOneCircuitOfTwoBranches) {
  const FourBarMotion motion = TraceFourBar(kTripleRocker.input, kTripleRocker.output, {}, 1.0);
  ASSERT_EQ(motion.circuits.size(), 1u);
  EXPECT_FALSE(motion.circuits[0].input_rotates_fully);
  EXPECT_EQ(motion.circuits[0].branches, 2);
}

TEST(FourBarAnalysis, CrankRockerTaskHasNoDefect) {
  const std::vector<PlanarPose> poses =
      Poses(kCrankRocker, {-150, -80, 10, 95, 170}, {0, 0, 0, 0, 0});
  const double length = CharacteristicLength(poses);
  const FourBarAnalysis analysis =
      AnalyzeFourBar(kCrankRocker.input, kCrankRocker.output, poses, length);
  EXPECT_TRUE(analysis.defects.empty());
  EXPECT_TRUE(analysis.input_rotates_fully);
  ASSERT_TRUE(analysis.max_pose_error.has_value());
  EXPECT_LE(*analysis.max_pose_error, kExact * length);
  ASSERT_TRUE(analysis.transmission_min_deg.has_value());
  EXPECT_GT(*analysis.transmission_min_deg, 0.0);
  EXPECT_LE(*analysis.transmission_max_deg, 90.0);
  // Driven backwards through the same poses: still ordered.
  std::vector<PlanarPose> reversed(poses.rbegin(), poses.rend());
  EXPECT_TRUE(
      AnalyzeFourBar(kCrankRocker.input, kCrankRocker.output, reversed, length).defects.empty());
}

TEST(FourBarAnalysis, PosesOnTwoCircuitsHaveTheCircuitDefect) {
  const std::vector<PlanarPose> poses =
      Poses(kCrankRocker, {-150, -80, 10, 95, 170}, {0, 0, 0, 1, 1});
  const double length = CharacteristicLength(poses);
  const FourBarAnalysis analysis =
      AnalyzeFourBar(kCrankRocker.input, kCrankRocker.output, poses, length);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"circuit"});
  // On the first pose's circuit the last two poses are missed.
  ASSERT_TRUE(analysis.max_pose_error.has_value());
  EXPECT_GT(*analysis.max_pose_error, 1e-3 * length);
}

TEST(FourBarAnalysis, PosesOutOfCrankOrderHaveTheOrderDefect) {
  const std::vector<PlanarPose> poses =
      Poses(kCrankRocker, {-150, 10, -80, 95, 170}, {0, 0, 0, 0, 0});
  const double length = CharacteristicLength(poses);
  const FourBarAnalysis analysis =
      AnalyzeFourBar(kCrankRocker.input, kCrankRocker.output, poses, length);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"order"});
  EXPECT_LE(*analysis.max_pose_error, kExact * length);
}

TEST(FourBarAnalysis, PosesOnTwoBranchesHaveTheBranchDefect) {
  // The triple-rocker's input swings between its limits; poses on both assembly labels lie on
  // the two branches of its single circuit.
  const FourBarMotion motion = TraceFourBar(kTripleRocker.input, kTripleRocker.output, {}, 1.0);
  ASSERT_EQ(motion.circuits.size(), 1u);
  const FourBarCircuit& circuit = motion.circuits[0];
  // Input angles well inside the swing.
  const double start = circuit.input_start, extent = circuit.input_extent;
  std::vector<double> degrees;
  for (double f : {0.2, 0.35, 0.5, 0.65, 0.8}) degrees.push_back((start + f * extent) / kDegree);
  const std::vector<PlanarPose> poses = Poses(kTripleRocker, degrees, {0, 0, 0, 1, 1});
  const double length = CharacteristicLength(poses);
  const FourBarAnalysis analysis =
      AnalyzeFourBar(kTripleRocker.input, kTripleRocker.output, poses, length);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"branch"});
  EXPECT_LE(*analysis.max_pose_error, kExact * length);  // one circuit: all reachable
  // The same angles on one branch: no defect.
  const std::vector<PlanarPose> one_branch = Poses(kTripleRocker, degrees, {1, 1, 1, 1, 1});
  EXPECT_TRUE(AnalyzeFourBar(kTripleRocker.input, kTripleRocker.output, one_branch,
                             CharacteristicLength(one_branch))
                  .defects.empty());
}

TEST(FourBarAnalysis, TransmissionAngleOfAHandMadeConfiguration) {
  // Coupler perpendicular to the rocker: 90 degrees; along it: 0.
  const PlanarDyad input = PlanarDyad::RR(Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 0), 1.0);
  const PlanarDyad output = PlanarDyad::RR(Eigen::Vector2d(2, -1), Eigen::Vector2d(2, 0), 1.0);
  const PlanarPose at(0.0, 1.0, 0.0);  // input pin (0,1), output pin (2,1), rocker up from (2,0)
  EXPECT_NEAR(*TransmissionAngleDeg(input, output, at), 90.0, 1e-12);
  const PlanarDyad along = PlanarDyad::RR(Eigen::Vector2d(3, 1), Eigen::Vector2d(2, 0), 1.0);
  EXPECT_NEAR(*TransmissionAngleDeg(input, along, at), 0.0, 1e-6);
  // A slider whose line is along the coupler transmits perfectly.
  const PlanarDyad slider =
      PlanarDyad::PR(Eigen::Vector2d(2, 0), Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 0));
  EXPECT_NEAR(*TransmissionAngleDeg(input, slider, at), 90.0, 1e-12);
  EXPECT_FALSE(TransmissionAngleDeg(input, slider.Inverted(), at).has_value());
}

TEST(FourBarAnalysis, GeneratingMechanismsReachTheirTasksOnOneCircuit) {
  // Random four-bars of every type pair walked through five poses on one branch: wherever the
  // analysis finds no circuit defect, the mechanism reaches every pose on its circuit.
  std::mt19937_64 rng(77);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  int analysed = 0;
  for (DyadType a : types) {
    for (DyadType b : types) {
      for (int trial = 0; trial < 20; ++trial) {
        const testing::GeneratedTask task = testing::RandomTask(rng, a, b);
        const double length = CharacteristicLength(task.poses);
        const FourBarAnalysis analysis =
            AnalyzeFourBar(task.input, task.output, task.poses, length);
        ASSERT_TRUE(analysis.max_pose_error.has_value());
        if (std::find(analysis.defects.begin(), analysis.defects.end(), "circuit") ==
            analysis.defects.end()) {
          EXPECT_LE(*analysis.max_pose_error, kExact * length)
              << DyadTypeName(a) << DyadTypeName(b) << " trial " << trial;
          ++analysed;
        }
      }
    }
  }
  EXPECT_GE(analysed, 150);
}

}  // namespace
}  // namespace linkfit
