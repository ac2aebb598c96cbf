// Tests of lib/mechanism.h: four-bar classification, Grashof types, input joint values and
// assembly (forward kinematics) of planar four-bars made of two dyads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/mechanism.h"
#include "lib/planar_pose.h"
#include "tests/support/random_mechanism.h"

namespace {

using linkfit::AssembleFourBar;
using linkfit::DyadType;
using linkfit::InputValue;
using linkfit::PlanarDyad;
using linkfit::PlanarPose;
namespace lt = linkfit::testing;

constexpr double kExact = 1e-12;           // relative to L: exact assembly / closure
constexpr double kAngleExact = 1e-12;      // radians: input angle round trip
constexpr double kWrongDyad = 1e-3;        // relative to L: a wrong mechanism misses by more
constexpr double kWellConditioned = 10.0;  // |d pose / d input| / L below which kExact holds
constexpr double kSensitivityStep = 1e-7;  // finite-difference step of the input (rad, or L)
constexpr double kDeadPointFactor = 1e4;   // relaxation of kExact exactly at a dead point
constexpr double kGrashofLength = 1.0;     // the length passed to GrashofType
constexpr uint64_t kSeed = 8675309;        // base of the fixed seeds of the random tests here
constexpr int kTasksPerPair = 1000;

const DyadType kAllTypes[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};

std::string PairName(DyadType input, DyadType output) {
  return std::string(linkfit::DyadTypeName(input)) + "+" + linkfit::DyadTypeName(output);
}

std::string Trace(uint64_t seed, int trial, DyadType input, DyadType output) {
  return "seed " + std::to_string(seed) + " trial " + std::to_string(trial) + " pair " +
         PairName(input, output);
}

uint64_t PairSeed(DyadType input, DyadType output) {
  return kSeed + 10 * static_cast<uint64_t>(input) + static_cast<uint64_t>(output);
}

// A 4R in a hand-made configuration: ground pivots F1 = (0, 0), F2 = (ground, 0); the coupler
// frame E has the input's moving pivot at its origin and the output's at (coupler, 0).
struct HandFourBar {
  PlanarDyad input;
  PlanarDyad output;
};

HandFourBar MakeFourBar(double ground, double input_crank, double coupler, double output_crank) {
  return {PlanarDyad::RR({0.0, 0.0}, {0.0, 0.0}, input_crank),
          PlanarDyad::RR({ground, 0.0}, {coupler, 0.0}, output_crank)};
}

// The accuracy to expect of an assembled pose. The input value read back from a task pose
// carries rounding, and the assembled pose moves by S times that, S = |d pose / d input| (pose
// error per unit input, relative to L). Near a dead point (two branches meeting) or a
// near-singular slider configuration S is large. kExact * L is required wherever
// S <= kWellConditioned, and the bound grows as S beyond that (a budget of a few hundred
// rounding errors times S; 2 % of the generated poses need it, 0.2 % by more than 10x). S is taken
// by a finite difference of step kSensitivityStep to whichever side assembles; at an exact dead
// point (neither side assembles) the bound is kExact * L * kDeadPointFactor.
double AssemblyTolerance(const PlanarDyad& input, const PlanarDyad& output, double value,
                         const PlanarPose& target, double length) {
  const double step = input.type == DyadType::kPR ? kSensitivityStep * length : kSensitivityStep;
  double sensitivity = -1.0;
  for (const double side : {1.0, -1.0}) {
    std::vector<PlanarPose> nearby;
    AssembleFourBar(input, output, value + side * step, 0.0, &nearby);
    for (const PlanarPose& pose : nearby) {
      const double moved = linkfit::PoseError(pose, target, length) / (step * length);
      if (sensitivity < 0.0 || moved < sensitivity) sensitivity = moved;
    }
    if (sensitivity >= 0.0) break;
  }
  if (sensitivity < 0.0) return kExact * length * kDeadPointFactor;
  // `moved` is the pose error over L per radian of input; for a slider make it per L of travel.
  if (input.type == DyadType::kPR) sensitivity *= length;
  return kExact * length * std::max(1.0, sensitivity / kWellConditioned);
}

// ---------------------------------------------------------------------------------------------
// Classification.

TEST(MechanismClassify, AllCombinations) {
  struct Case {
    DyadType a, b;
    linkfit::FourBarType type;
    const char* name;
  };
  using linkfit::FourBarType;
  const Case cases[] = {
      {DyadType::kRR, DyadType::kRR, FourBarType::k4R, "4R"},
      {DyadType::kRR, DyadType::kPR, FourBarType::kSliderCrank, "slider-crank"},
      {DyadType::kPR, DyadType::kRR, FourBarType::kSliderCrank, "slider-crank"},
      {DyadType::kRR, DyadType::kRP, FourBarType::kInvertedSliderCrank, "inverted slider-crank"},
      {DyadType::kRP, DyadType::kRR, FourBarType::kInvertedSliderCrank, "inverted slider-crank"},
      {DyadType::kPR, DyadType::kPR, FourBarType::kDoubleSlider, "double slider"},
      {DyadType::kPR, DyadType::kRP, FourBarType::kRPRP, "RPRP"},
      {DyadType::kRP, DyadType::kPR, FourBarType::kRPRP, "RPRP"},
      {DyadType::kRP, DyadType::kRP, FourBarType::kInvertedDoubleSlider, "inverted double slider"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(linkfit::ClassifyFourBar(c.a, c.b), c.type) << PairName(c.a, c.b);
    EXPECT_STREQ(linkfit::FourBarTypeName(linkfit::ClassifyFourBar(c.a, c.b)), c.name)
        << PairName(c.a, c.b);
  }
}

TEST(MechanismGrashof, HandMadeFourBars) {
  struct Case {
    double ground, input, coupler, output;
    const char* type;
  };
  const Case cases[] = {
      {4.0, 1.0, 3.5, 3.0, "crank-rocker"},          // shortest = input crank, 1 + 4 < 3 + 3.5
      {1.0, 3.0, 3.5, 4.0, "double-crank"},          // shortest = ground
      {4.0, 3.0, 1.0, 3.5, "double-rocker"},         // shortest = coupler
      {4.0, 3.0, 3.5, 1.0, "rocker-crank"},          // shortest = output
      {4.0, 2.0, 1.5, 3.0, "triple-rocker"},         // 1.5 + 4 > 2 + 3
      {4.0, 1.0, 3.0, 2.0, "change-point"},          // 1 + 4 = 3 + 2
      {2.0, 1.0, 2.0, 1.0, "change-point"},          // parallelogram
      {4.0, 1.0, 3.0, 2.0 + 1e-11, "change-point"},  // within 1e-9 * length
      {4.0, 1.0, 3.0, 2.0 + 1e-6, "crank-rocker"},   // beyond it, Grashof
      {4.0, 1.0, 3.0, 2.0 - 1e-6, "triple-rocker"},  // beyond it, non-Grashof
  };
  for (const Case& c : cases) {
    const HandFourBar bar = MakeFourBar(c.ground, c.input, c.coupler, c.output);
    EXPECT_EQ(linkfit::GrashofType(bar.input, bar.output, kGrashofLength), c.type)
        << "links " << c.ground << " " << c.input << " " << c.coupler << " " << c.output;
  }
  // Driving the other crank swaps crank-rocker and rocker-crank.
  const HandFourBar bar = MakeFourBar(4.0, 1.0, 3.5, 3.0);
  EXPECT_EQ(linkfit::GrashofType(bar.output, bar.input, kGrashofLength), "rocker-crank");
  // The type does not depend on where the pivots sit, only on the link lengths.
  // Ground |(2.4, -3.2)| = 4, coupler |(3.5, 0)| = 3.5, cranks 1 and 3.
  const PlanarDyad input = PlanarDyad::RR({1.0, 2.0}, {-0.3, 0.4}, 1.0);
  const PlanarDyad output = PlanarDyad::RR({1.0 + 4.0 * 0.6, 2.0 - 4.0 * 0.8}, {3.2, 0.4}, 3.0);
  EXPECT_EQ(linkfit::GrashofType(input, output, kGrashofLength), "crank-rocker");
}

// ---------------------------------------------------------------------------------------------
// Input values.

TEST(MechanismInputValue, HandMadeDyads) {
  const PlanarPose pose(1.0, 2.0, 0.5);
  // RR: the angle of the arm from the fixed pivot to the moving pivot in Sigma.
  const Eigen::Vector2d fixed_pivot(-1.0, 1.0);
  const Eigen::Vector2d arm(-0.6, -0.8);
  const PlanarDyad rr = PlanarDyad::RR(fixed_pivot, pose.ToMoving(fixed_pivot + 2.0 * arm), 2.0);
  EXPECT_NEAR(InputValue(rr, pose), std::atan2(-0.8, -0.6), kAngleExact);
  // PR: the position along the slider line from its line point.
  const PlanarDyad pr = PlanarDyad::PR(pose.ToMoving({4.0, 3.0}), {1.0, 3.0}, {-1.0, 0.0});
  EXPECT_NEAR(InputValue(pr, pose), -3.0, kExact);
  // RP: the coupler angle.
  const PlanarDyad rp = PlanarDyad::RP({0, 0}, {0, 0}, {1, 0});
  EXPECT_NEAR(InputValue(rp, pose), 0.5, kAngleExact);
}

TEST(MechanismInputValue, RoundTripThroughAssemblyOf4R) {
  const uint64_t seed = kSeed + 1;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  int assembled = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const lt::GeneratedTask task = lt::RandomFourBarTask(rng);
    for (int k = 0; k < 10; ++k) {
      const double input_angle = angle(rng);
      std::vector<PlanarPose> poses;
      AssembleFourBar(task.input, task.output, input_angle, 0.0, &poses);
      for (const PlanarPose& pose : poses) {
        ++assembled;
        const double back = InputValue(task.input, pose);
        EXPECT_LE(std::abs(linkfit::WrapAngle(back - input_angle)), kAngleExact)
            << Trace(seed, trial, DyadType::kRR, DyadType::kRR) << " angle " << input_angle;
      }
    }
  }
  EXPECT_GT(assembled, 1000);
}

// ---------------------------------------------------------------------------------------------
// Assembly of random tasks, every pair of dyad types.

void ExpectAssemblyReproducesTask(DyadType input_type, DyadType output_type) {
  const uint64_t seed = PairSeed(input_type, output_type);
  std::mt19937_64 rng(seed);
  const int expected_max = (input_type == DyadType::kRP && output_type != DyadType::kRR) ? 1 : 2;
  for (int trial = 0; trial < kTasksPerPair; ++trial) {
    const lt::GeneratedTask task = lt::RandomTask(rng, input_type, output_type, 5);
    const std::string where = Trace(seed, trial, input_type, output_type);
    ASSERT_EQ(task.input.type, input_type) << where;
    ASSERT_EQ(task.output.type, output_type) << where;
    const double length = linkfit::CharacteristicLength(task.poses);
    ASSERT_GT(length, 0.0) << where;
    for (size_t j = 0; j < task.poses.size(); ++j) {
      const PlanarPose& target = task.poses[j];
      const double value = InputValue(task.input, target);
      std::vector<PlanarPose> assembled;
      const int count = AssembleFourBar(task.input, task.output, value, 0.0, &assembled);
      EXPECT_EQ(count, static_cast<int>(assembled.size())) << where << " pose " << j;
      ASSERT_GE(count, 1) << where << " pose " << j;
      EXPECT_LE(count, expected_max) << where << " pose " << j;
      double nearest = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < assembled.size(); ++i) {
        const PlanarPose& pose = assembled[i];
        nearest = std::min(nearest, linkfit::PoseError(pose, target, length));
        // Closure: both dyads hold in every configuration returned.
        EXPECT_LE(std::abs(task.input.Residual(pose)), kExact * length)
            << where << " pose " << j << " configuration " << i;
        EXPECT_LE(std::abs(task.output.Residual(pose)), kExact * length)
            << where << " pose " << j << " configuration " << i;
        // The input joint is where it was asked to be.
        const double back = InputValue(task.input, pose);
        const double input_error = input_type == DyadType::kPR
                                       ? std::abs(back - value) / length
                                       : std::abs(linkfit::WrapAngle(back - value));
        EXPECT_LE(input_error, kAngleExact) << where << " pose " << j << " configuration " << i;
        EXPECT_GT(pose.theta, -M_PI) << where;
        EXPECT_LE(pose.theta, M_PI) << where;
      }
      EXPECT_LE(nearest, AssemblyTolerance(task.input, task.output, value, target, length))
          << where << " pose " << j;
    }
  }
}

TEST(MechanismAssemble, ReproducesTaskPosesForEveryPairOfDyadTypes) {
  for (const DyadType input : kAllTypes) {
    for (const DyadType output : kAllTypes) {
      SCOPED_TRACE(PairName(input, output));
      ExpectAssemblyReproducesTask(input, output);
    }
  }
}

TEST(MechanismAssemble, CrankOfCrankRockerAssemblesAtEveryAngle) {
  const HandFourBar bar = MakeFourBar(4.0, 1.0, 3.5, 3.0);
  for (int k = 0; k < 360; ++k) {
    const double angle = linkfit::WrapAngle(k * M_PI / 180.0);
    std::vector<PlanarPose> poses;
    EXPECT_EQ(AssembleFourBar(bar.input, bar.output, angle, 0.0, &poses), 2) << "angle " << k;
    for (const PlanarPose& pose : poses) {
      EXPECT_LE(std::abs(bar.input.Residual(pose)), kExact) << "angle " << k;
      EXPECT_LE(std::abs(bar.output.Residual(pose)), kExact) << "angle " << k;
    }
  }
}

TEST(MechanismAssemble, NoAssemblyWhenRockerIsDrivenBeyondItsSwing) {
  // Crank-rocker: ground 4, crank 1, coupler 3.5, rocker 3. Drive the rocker (about F2 =
  // (4, 0)) at angle phi: its tip is at distance sqrt(25 + 24 cos phi) from F1, which must lie
  // in [3.5 - 1, 3.5 + 1], i.e. cos phi in [-0.78125, -0.197916...].
  const HandFourBar bar = MakeFourBar(4.0, 1.0, 3.5, 3.0);
  const PlanarDyad& rocker = bar.output;
  const PlanarDyad& crank = bar.input;
  std::vector<PlanarPose> poses;
  for (const double phi : {0.0, 0.5, M_PI / 2.0, M_PI, -M_PI / 2.0, 3.0, -3.0}) {
    EXPECT_EQ(AssembleFourBar(rocker, crank, phi, 0.0, &poses), 0) << "phi " << phi;
    EXPECT_TRUE(poses.empty()) << "phi " << phi;
  }
  const double phi_low = std::acos(-4.75 / 24.0);    // tip at distance 4.5 (folded out)
  const double phi_high = std::acos(-18.75 / 24.0);  // tip at distance 2.5 (folded in)
  for (const double sign : {1.0, -1.0}) {
    for (const double phi : {phi_low + 1e-6, 0.5 * (phi_low + phi_high), phi_high - 1e-6}) {
      EXPECT_EQ(AssembleFourBar(rocker, crank, sign * phi, 0.0, &poses), 2) << "phi " << phi;
      for (const PlanarPose& pose : poses) {
        EXPECT_LE(std::abs(rocker.Residual(pose)), kExact) << "phi " << phi;
        EXPECT_LE(std::abs(crank.Residual(pose)), kExact) << "phi " << phi;
      }
    }
    for (const double phi : {phi_low - 1e-6, phi_high + 1e-6}) {
      EXPECT_EQ(AssembleFourBar(rocker, crank, sign * phi, 0.0, &poses), 0) << "phi " << phi;
    }
  }
}

TEST(MechanismAssemble, NoAssemblyForSliderOutOfReach) {
  // Slider-crank driven by its slider: crank 1 about the origin, coupler 2, slider on the x
  // axis; the slider block reaches |s| <= 3 only.
  const PlanarDyad crank = PlanarDyad::RR({0, 0}, {0, 0}, 1.0);
  const PlanarDyad slider = PlanarDyad::PR({2.0, 0.0}, {0.0, 0.0}, {1.0, 0.0});
  std::vector<PlanarPose> poses;
  EXPECT_EQ(AssembleFourBar(slider, crank, 3.5, 0.0, &poses), 0);
  EXPECT_EQ(AssembleFourBar(slider, crank, -3.01, 0.0, &poses), 0);
  EXPECT_EQ(AssembleFourBar(slider, crank, 0.5, 0.0, &poses), 0);  // below 2 - 1
  EXPECT_EQ(AssembleFourBar(slider, crank, 2.0, 0.0, &poses), 2);
  for (const PlanarPose& pose : poses) {
    EXPECT_LE(std::abs(slider.Residual(pose)), kExact);
    EXPECT_LE(std::abs(crank.Residual(pose)), kExact);
    EXPECT_NEAR(InputValue(slider, pose), 2.0, kExact);
  }
}

// Near a dead point, `tolerance` is a length: a mechanism that misses assembly by e assembles
// with tolerance 2 e and not with tolerance e / 2, in any unit.
TEST(MechanismAssemble, TangentToleranceIsALength) {
  const double miss = 1e-7;
  for (const DyadType output_type : kAllTypes) {
    for (const double unit : {1.0, 1000.0, 0.001}) {
      SCOPED_TRACE(std::string("output ") + linkfit::DyadTypeName(output_type) + " unit " +
                   std::to_string(unit));
      // Input: crank of radius 1 about the origin with its moving pivot at E's origin, driven
      // at angle 0 (pivot at (1, 0)); the coupler turns about that pivot. Each output misses
      // the reach of the coupler by `miss` (all lengths times `unit`).
      const PlanarDyad input = PlanarDyad::RR({0, 0}, {0, 0}, unit);
      PlanarDyad output;
      if (output_type == DyadType::kRR) {
        // The point (2, 0) of E reaches at most x = 3 from F2 = (6 + miss, 0): radius 3.
        output = PlanarDyad::RR({unit * (6.0 + miss), 0.0}, {2.0 * unit, 0.0}, 3.0 * unit);
      } else if (output_type == DyadType::kPR) {
        // The point (2, 0) of E reaches at most x = 3: slider line x = 3 + miss.
        output = PlanarDyad::PR({2.0 * unit, 0.0}, {unit * (3.0 + miss), 0.0}, {0.0, 1.0});
      } else {
        // The line of E through (0, 2) along +x passes 2 away from the pivot (1, 0): it never
        // reaches a fixed pivot at distance 2 - miss from (1, 0).
        output = PlanarDyad::RP({unit * (3.0 - miss), 0.0}, {0.0, 2.0 * unit}, {1.0, 0.0});
      }
      std::vector<PlanarPose> poses;
      EXPECT_EQ(AssembleFourBar(input, output, 0.0, 0.0, &poses), 0);
      EXPECT_EQ(AssembleFourBar(input, output, 0.0, 0.5 * miss * unit, &poses), 0);
      EXPECT_GE(AssembleFourBar(input, output, 0.0, 2.0 * miss * unit, &poses), 1);
      for (const PlanarPose& pose : poses) {
        EXPECT_LE(std::abs(output.Residual(pose)), 2.0 * miss * unit);
      }
    }
  }
}

TEST(MechanismAssemble, TangentToleranceIsALengthForRPInput) {
  const double miss = 1e-7;
  for (const double unit : {1.0, 1000.0, 0.001}) {
    SCOPED_TRACE("unit " + std::to_string(unit));
    // Input RP at coupler angle 0: the line of E along its x axis passes through F1 = 0, so
    // E's origin runs along Sigma's x axis. Output RR: E's origin on a circle of radius 3
    // about (0, 3 + miss), which misses the x axis by miss.
    const PlanarDyad input = PlanarDyad::RP({0, 0}, {0, 0}, {1, 0});
    const PlanarDyad output = PlanarDyad::RR({0.0, unit * (3.0 + miss)}, {0, 0}, 3.0 * unit);
    std::vector<PlanarPose> poses;
    EXPECT_EQ(AssembleFourBar(input, output, 0.0, 0.0, &poses), 0);
    EXPECT_EQ(AssembleFourBar(input, output, 0.0, 0.5 * miss * unit, &poses), 0);
    EXPECT_GE(AssembleFourBar(input, output, 0.0, 2.0 * miss * unit, &poses), 1);
    for (const PlanarPose& pose : poses) {
      EXPECT_LE(std::abs(output.Residual(pose)), 2.0 * miss * unit);
      EXPECT_NEAR(pose.theta, 0.0, kAngleExact);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Pose error of an assembled mechanism.

TEST(MechanismMaxAssembledPoseError, GeneratingMechanismReproducesItsTask) {
  for (const DyadType input_type : kAllTypes) {
    for (const DyadType output_type : kAllTypes) {
      const uint64_t seed = PairSeed(input_type, output_type) + 1000;
      std::mt19937_64 rng(seed);
      for (int trial = 0; trial < kTasksPerPair; ++trial) {
        const lt::GeneratedTask task = lt::RandomTask(rng, input_type, output_type, 5);
        const std::string where = Trace(seed, trial, input_type, output_type);
        const double length = linkfit::CharacteristicLength(task.poses);
        const std::optional<double> error =
            linkfit::MaxAssembledPoseError(task.input, task.output, task.poses, length);
        ASSERT_TRUE(error.has_value()) << where;
        EXPECT_GE(*error, 0.0) << where;
        double tolerance = kExact * length;
        for (const PlanarPose& pose : task.poses) {
          tolerance =
              std::max(tolerance, AssemblyTolerance(task.input, task.output,
                                                    InputValue(task.input, pose), pose, length));
        }
        EXPECT_LE(*error, tolerance) << where;
      }
    }
  }
}

TEST(MechanismMaxAssembledPoseError, WrongDyadIsRejected) {
  for (const DyadType input_type : kAllTypes) {
    for (const DyadType output_type : kAllTypes) {
      const uint64_t seed = PairSeed(input_type, output_type) + 2000;
      std::mt19937_64 rng(seed);
      for (int trial = 0; trial < kTasksPerPair; ++trial) {
        const lt::GeneratedTask task = lt::RandomTask(rng, input_type, output_type, 5);
        const std::string where = Trace(seed, trial, input_type, output_type);
        const double length = linkfit::CharacteristicLength(task.poses);
        PlanarDyad wrong = task.output;
        if (output_type == DyadType::kRR) {
          wrong.radius *= 1.1;                        // 10 % longer output crank
          if (wrong.radius < 0.1 * length) continue;  // too short to be a clear change
        } else {
          // The line moved sideways by 0.1 L (in the frame it lives in).
          wrong.line_point +=
              0.1 * length * Eigen::Vector2d(-wrong.line_direction.y(), wrong.line_direction.x());
        }
        const std::optional<double> error =
            linkfit::MaxAssembledPoseError(task.input, wrong, task.poses, length);
        if (error.has_value()) {
          EXPECT_GT(*error, kWrongDyad * length) << where;
        }
      }
    }
  }
}

TEST(MechanismMaxAssembledPoseError, NulloptWhenAPoseCannotBeReached) {
  // The crank-rocker of the hand-made tests driven by its rocker: a task pose taken at a rocker
  // angle beyond the swing (tip away from the crank) cannot be assembled.
  const HandFourBar bar = MakeFourBar(4.0, 1.0, 3.5, 3.0);
  std::vector<PlanarPose> reachable;
  ASSERT_EQ(AssembleFourBar(bar.output, bar.input, 2.0, 0.0, &reachable), 2);
  std::vector<PlanarPose> task = {reachable[0]};
  // A pose whose rocker angle is 0: F2 + (3, 0) = (7, 0) is the output pivot; the coupler is
  // anywhere consistent with that (E's x axis from the input pivot to the output pivot).
  task.push_back(PlanarPose(7.0 - 3.5, 0.0, 0.0));
  EXPECT_NEAR(InputValue(bar.output, task.back()), 0.0, kAngleExact);
  EXPECT_FALSE(linkfit::MaxAssembledPoseError(bar.output, bar.input, task, 1.0).has_value());
  // The reachable pose alone is reproduced.
  const std::optional<double> error =
      linkfit::MaxAssembledPoseError(bar.output, bar.input, {reachable[0]}, 1.0);
  ASSERT_TRUE(error.has_value());
  EXPECT_LE(*error, kExact);
}

}  // namespace
