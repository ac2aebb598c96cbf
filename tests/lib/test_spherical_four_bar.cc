// Spherical dyads and four-bars (lib/spherical_dyad.h, lib/spherical_four_bar.h): the assembly
// meets both dyads, the closed-form closure agrees with the assembly at every sampled input,
// the Grashof class with the joints' sampled rotatability, the closed-form transmission angle
// with the sampled one, and the defects with what the task poses are made to be.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/spherical_four_bar.h"
#include "tests/support/random_spherical.h"

namespace linkfit {
namespace {

constexpr double kAssemblyTolerance = 1e-12;  // radians, a dyad's residual at an assembly
constexpr int kInputSamples = 2000;

TEST(SphericalDyad, CanonicalFormIsOneDyad) {
  std::mt19937_64 rng(1701);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d u = testing::RandomUnitVector(rng), v = testing::RandomUnitVector(rng);
    const double alpha = DirectionAngle(u, v);
    const SphericalDyad a = SphericalDyad::Make(u, v, alpha);
    const SphericalDyad b = SphericalDyad::Make(-u, v, M_PI - alpha);
    const SphericalDyad c = SphericalDyad::Make(-3.0 * u, -v, alpha);
    EXPECT_LE(a.angle, 0.5 * M_PI);
    for (const SphericalDyad* other : {&b, &c}) {
      EXPECT_LT((a.fixed_axis - other->fixed_axis).norm(), 1e-14);
      EXPECT_LT((a.moving_axis - other->moving_axis).norm(), 1e-14);
      EXPECT_NEAR(a.angle, other->angle, 1e-14);
    }
    // The identity keeps v on its cone.
    EXPECT_NEAR(a.Residual(Eigen::Matrix3d::Identity()), 0.0, 1e-14);
  }
}

TEST(SphericalFourBar, AssembliesMeetBothDyadsAndTheClosure) {
  std::mt19937_64 rng(1702);
  int assembled = 0, limited = 0, full = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const SphericalFourBar four_bar = testing::RandomSphericalFourBar(rng);
    const FourBarClosure closure = SphericalClosure(four_bar);
    (closure.full_turn ? full : limited) += 1;
    Eigen::Matrix3d rotations[2];
    for (int k = 0; k < kInputSamples; ++k) {
      const double phi = -M_PI + 2.0 * M_PI * (k + 0.5) / kInputSamples;
      const int count = AssembleSphericalFourBar(four_bar, phi, 0.0, rotations);
      const int interval = ClosureIntervalOf(closure, phi);
      // Within 1e-9 of an arc's end rounding may go either way.
      if (interval < 0 && ClosureIntervalOf(closure, phi, 1e-9) >= 0) {
        continue;
      }
      ASSERT_EQ(count > 0, interval >= 0) << "trial " << trial << " phi " << phi;
      for (int l = 0; l < count; ++l) {
        ++assembled;
        const Eigen::Matrix3d& r = rotations[l];
        EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-13);
        EXPECT_NEAR(r.determinant(), 1.0, 1e-13);
        EXPECT_LT(std::abs(four_bar.input.Residual(r)), kAssemblyTolerance) << trial;
        EXPECT_LT(std::abs(four_bar.output.Residual(r)), kAssemblyTolerance) << trial;
        EXPECT_NEAR(std::remainder(SphericalInputAngle(four_bar, r) - phi, 2.0 * M_PI), 0.0, 1e-12);
      }
    }
  }
  EXPECT_GT(assembled, 10000);
  EXPECT_GT(limited, 5);
  EXPECT_GT(full, 5);
}

TEST(SphericalFourBar, GrashofClassAgreesWithSampledRotatability) {
  std::mt19937_64 rng(1703);
  int seen_classes = 0;
  std::vector<std::string> classes;
  for (int trial = 0; trial < 200; ++trial) {
    const SphericalFourBar four_bar = testing::RandomSphericalFourBar(rng);
    const SphericalFourBar swapped = MakeSphericalFourBar(four_bar.output, four_bar.input);
    // Sampled: does every input angle assemble (input a crank), every output angle (output)?
    const auto turns = [](const SphericalFourBar& fb) {
      Eigen::Matrix3d rotations[2];
      for (int k = 0; k < kInputSamples; ++k) {
        if (AssembleSphericalFourBar(fb, -M_PI + 2.0 * M_PI * k / kInputSamples, 0.0, rotations) ==
            0) {
          return false;
        }
      }
      return true;
    };
    const std::string grashof = SphericalGrashofType(four_bar);
    const SphericalRotatability joints = SphericalJointsRotate(four_bar, 1e-9);
    if (joints.change_point) continue;
    EXPECT_EQ(joints.input, turns(four_bar)) << trial << " " << grashof;
    EXPECT_EQ(joints.output, turns(swapped)) << trial << " " << grashof;
    EXPECT_EQ(joints.input, SphericalClosure(four_bar).full_turn);
    // Swapping input and output mirrors the class.
    const std::string mirrored = SphericalGrashofType(swapped);
    if (grashof == "crank-rocker") {
      EXPECT_EQ(mirrored, "rocker-crank");
    } else if (grashof != "rocker-crank") {
      EXPECT_EQ(mirrored, grashof);
    }
    if (std::find(classes.begin(), classes.end(), grashof) == classes.end()) {
      classes.push_back(grashof);
      ++seen_classes;
    }
  }
  EXPECT_GE(seen_classes, 4);
}

// A four-bar's own rotations: no defect, no pose error, the transmission angle of the samples.
TEST(SphericalFourBar, ItsOwnMotionHasNoDefectAndTheSampledTransmissionAngle) {
  std::mt19937_64 rng(1704);
  for (int trial = 0; trial < 50; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    SphericalMotion motion;
    motion.rotations = rotations;
    motion.center_in_moving = Eigen::Vector3d(0.3, -0.2, 0.5);
    motion.center_in_fixed = Eigen::Vector3d(1.0, 2.0, -1.0);
    motion.length = 1.0;
    const SphericalFourBarAnalysis analysis = AnalyzeSphericalFourBar(four_bar, motion, 400);
    EXPECT_TRUE(analysis.defects.empty()) << trial;
    ASSERT_TRUE(analysis.max_pose_error) << trial;
    EXPECT_LT(*analysis.max_pose_error, 1e-12) << trial;
    EXPECT_FALSE(analysis.cycle.empty());
    // The transmission angle sampled between the first and the last rotation's inputs.
    ASSERT_TRUE(analysis.transmission_min_deg && analysis.transmission_max_deg) << trial;
    const double start = analysis.locations.front().input;
    double extent = analysis.locations.back().input - start;
    extent -= 2.0 * M_PI * std::floor(extent / (2.0 * M_PI));
    double low = 90.0, high = 0.0;
    Eigen::Matrix3d configurations[2];
    double value = 0.0;
    ASSERT_EQ(AssembleSphericalFourBarAt(four_bar, rotations[0], 1e-9, configurations, &value), 2);
    const int label =
        (configurations[0] - rotations[0]).norm() <= (configurations[1] - rotations[0]).norm() ? 0
                                                                                               : 1;
    for (int k = 0; k <= 4000; ++k) {
      const double phi = start + extent * k / 4000.0;
      const int count = AssembleSphericalFourBar(four_bar, phi, 1e-9, configurations);
      ASSERT_EQ(count, 2) << trial;
      const double mu = *SphericalTransmissionAngleDeg(four_bar, configurations[label]);
      low = std::min(low, mu);
      high = std::max(high, mu);
    }
    EXPECT_NEAR(*analysis.transmission_min_deg, low, 0.05) << trial;
    EXPECT_NEAR(*analysis.transmission_max_deg, high, 0.05) << trial;

    // Reversed, the poses are visited by a decreasing input: still no defect. Two swapped: an
    // order defect.
    SphericalMotion reversed = motion;
    std::reverse(reversed.rotations.begin(), reversed.rotations.end());
    EXPECT_TRUE(AnalyzeSphericalFourBar(four_bar, reversed).defects.empty()) << trial;
    SphericalMotion shuffled = motion;
    std::swap(shuffled.rotations[1], shuffled.rotations[3]);
    const std::vector<std::string> defects = AnalyzeSphericalFourBar(four_bar, shuffled).defects;
    EXPECT_EQ(defects, std::vector<std::string>{"order"}) << trial;
  }
}

// A pose on the other assembly of the same input: a circuit defect for a crank (its labels are
// separate circuits), a branch defect for a limited input (one circuit, two branches).
TEST(SphericalFourBar, APoseOnTheOtherAssemblyIsACircuitOrBranchDefect) {
  std::mt19937_64 rng(1705);
  int circuits = 0, branches = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const testing::SphericalTask drawn = testing::RandomSphericalTask(rng, 5);
    const SphericalFourBar& four_bar = drawn.four_bar;
    std::vector<Eigen::Matrix3d> rotations = drawn.rotations;
    Eigen::Matrix3d configurations[2];
    double value = 0.0;
    ASSERT_EQ(AssembleSphericalFourBarAt(four_bar, rotations[2], 1e-9, configurations, &value), 2);
    const int other =
        (configurations[0] - rotations[2]).norm() < (configurations[1] - rotations[2]).norm() ? 1
                                                                                              : 0;
    if ((configurations[other] - rotations[2]).norm() < 1e-3) continue;  // nearly stationary
    rotations[2] = configurations[other];
    SphericalMotion motion;
    motion.rotations = rotations;
    const SphericalFourBarAnalysis analysis = AnalyzeSphericalFourBar(four_bar, motion);
    const bool crank = SphericalClosure(four_bar).full_turn;
    EXPECT_EQ(analysis.defects, std::vector<std::string>{crank ? "circuit" : "branch"}) << trial;
    (crank ? circuits : branches) += 1;
  }
  EXPECT_GT(circuits, 5);
  EXPECT_GT(branches, 5);
}

}  // namespace
}  // namespace linkfit
