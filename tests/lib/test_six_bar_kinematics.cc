// Tests of lib/six_bar_kinematics.h on random six-bars of every layout (tests/support/
// random_six_bar.h) under each grounded input: the closed-form rates against central differences
// of the position analysis (SixBarDriver::Place), the input torque against the load's work over
// the input's turn, a rocking input's range ending where the input cannot drive on.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>

#include "lib/six_bar.h"
#include "lib/six_bar_kinematics.h"
#include "tests/support/random_six_bar.h"
#include "tests/support/richardson.h"

namespace linkfit {
namespace {

constexpr uint64_t kSeed = 3707;

// Every generating six-bar of `per_layout` random tasks of each layout, under each grounded
// input.
template <typename Judge>
void ForEachDrivenSixBar(uint64_t seed, int per_layout, const Judge& judge) {
  std::mt19937_64 rng(seed);
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    for (int trial = 0; trial < per_layout; ++trial) {
      const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(rng, layout);
      for (const int input : {kSixBarUpperLink, kSixBarFirstLink, kSixBarSecondLink}) {
        if (SixBarGroundedLink(task.six_bar, input)) judge(task.six_bar, input);
      }
    }
  }
}

// f(t + h), f(t - h) etc. of a configuration's numbers at input turn t on one assembly.
struct Sampled {
  SixBarAngles turns;
  Eigen::Vector2d tool;
};

TEST(SixBarKinematics, RatesAreTheDerivativesOfThePositions) {
  int checked = 0, crank = 0, rocker = 0;
  double worst = 0.0;  // the largest difference as a share of its tolerance
  ForEachDrivenSixBar(kSeed, 8, [&](const SixBar& six_bar, int input) {
    SixBarKinematicsOptions options;
    options.steps = 30;
    options.input_speed = input == kSixBarUpperLink ? 1.7 : -0.8;
    options.load.tool_force = Eigen::Vector2d(3.0, -4.0);
    options.load.task_body_torque = 0.7;
    const SixBarKinematics kinematics = AnalyzeSixBarKinematics(six_bar, input, options, 1.0);
    ASSERT_FALSE(kinematics.states.empty()) << kinematics.note;
    (kinematics.input_rotates_fully ? crank : rocker)++;
    const SixBarDriver driver(six_bar, input, 1.0);
    const double w = options.input_speed;
    const int in = input - 1;
    for (const SixBarState& state : kinematics.states) {
      // Away from dead points, where the differences lose their digits.
      if (std::min(state.transmission_deg[0], state.transmission_deg[1]) < 10.0) continue;
      if (state.angular_velocity.cwiseAbs().maxCoeff() > 20.0 * std::abs(w)) continue;
      SixBarAssembly assembly;
      ASSERT_TRUE(driver.AssemblyOf(state.turns, &assembly));
      const auto at = [&](double turn, Sampled* sampled) {
        sampled->turns = state.turns;
        if (!driver.Place(assembly, turn, &sampled->turns, 1e-13)) return false;
        sampled->tool = SixBarBodyDisplacement(six_bar, sampled->turns, kSixBarTaskBody)
                            .ToFixed(six_bar.reference_pose.origin_in_fixed);
        return true;
      };
      const double t = state.turns[in], h = 2.5e-4;
      std::array<Sampled, 5> s;  // t - h, t - h/2, t, t + h/2, t + h
      const double offsets[5] = {-h, -0.5 * h, 0.0, 0.5 * h, h};
      bool placed = true;
      for (int k = 0; k < 5; ++k) placed = placed && at(t + offsets[k], &s[k]);
      if (!placed) continue;
      // Richardson-extrapolated central differences in the input's turn, times w (w^2).
      const auto first = [&](auto get) {
        return decltype(get(s[0]))(testing::RichardsonFirst(testing::EachOf(s, get), h) * w);
      };
      const auto second = [&](auto get) {
        return decltype(get(s[0]))(testing::RichardsonSecond(testing::EachOf(s, get), h) * w * w);
      };
      const auto turns = [](const Sampled& s) -> SixBarAngles { return s.turns; };
      const auto tool = [](const Sampled& s) -> Eigen::Vector2d { return s.tool; };
      const SixBarAngles omega = first(turns), alpha = second(turns);
      const Eigen::Vector2d velocity = first(tool), acceleration = second(tool);
      const auto expect = [&](double got, double want, double tolerance, const char* what,
                              int index) {
        const double scaled = tolerance * std::max(1.0, std::abs(want));
        worst = std::max(worst, std::abs(got - want) / scaled);
        EXPECT_NEAR(got, want, scaled)
            << what << " " << index << " of " << SixBarTopologyName(six_bar.topology)
            << " driven by body " << input << (driver.closed_form() ? " (closed form)" : "")
            << " at transmission angles " << state.transmission_deg[0] << ", "
            << state.transmission_deg[1];
      };
      for (int j = 0; j < 5; ++j) {
        expect(state.angular_velocity[j], omega[j], 1e-6, "angular velocity", j + 1);
        expect(state.angular_acceleration[j], alpha[j], 1e-4, "angular acceleration", j + 1);
      }
      for (int c = 0; c < 2; ++c) {
        expect(state.tool_velocity[c], velocity[c], 1e-6, "tool velocity", c);
        expect(state.tool_acceleration[c], acceleration[c], 1e-4, "tool acceleration", c);
      }
      // The input torque: minus the load's work per radian of the input's turn.
      const double work = options.load.tool_force.dot(velocity) +
                          options.load.task_body_torque * omega[kSixBarTaskBody - 1];
      expect(state.input_torque, -work / w, 1e-6, "input torque", 0);
      EXPECT_EQ(state.turns[in] + SixBarInputReferenceAngle(six_bar, input), state.input_angle);
      ++checked;
    }
  });
  std::cout << checked << " states checked (" << crank << " cranks, " << rocker
            << " rockers); worst difference " << worst << " of its tolerance\n";
  EXPECT_GT(checked, 1000);
  EXPECT_GT(crank, 3);
  EXPECT_GT(rocker, 10);
}

// With the bodies' masses, the inertial torque at constant input speed is the rate of their
// kinetic energy over the input's turn, and the weight's that of their potential energy: both
// against nested central differences of the positions alone (each body's centre of mass and turn
// at input turns t +- h give its velocity; the energies at t +- H their rates). Uniform bodies:
// a triangle's polar moment is m (a^2 + b^2 + c^2) / 36.
TEST(SixBarKinematics, InertialTorqueIsTheRateOfTheBodiesEnergy) {
  Eigen::Vector2d centre;
  double inertia = 0.0;
  const std::vector<Eigen::Vector2d> triangle = {{0.0, 0.0}, {2.0, 0.0}, {0.5, 1.5}};
  UniformBody(triangle, &centre, &inertia);
  EXPECT_NEAR((centre - Eigen::Vector2d(2.5 / 3.0, 0.5)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(inertia, (4.0 + (0.25 + 2.25) + (2.25 + 2.25)) / 36.0, 1e-15);
  UniformBody({{0.0, 0.0}, {3.0, 4.0}}, &centre, &inertia);
  EXPECT_NEAR(inertia, 25.0 / 12.0, 1e-15);

  int checked = 0;
  double worst = 0.0;
  ForEachDrivenSixBar(kSeed + 2, 3, [&](const SixBar& six_bar, int input) {
    SixBarKinematicsOptions options;
    options.steps = 12;
    options.input_speed = 3.0;
    options.masses.mass << 0.7, 1.1, 1.6, 0.4, 0.9;
    options.masses.gravity = true;
    const SixBarKinematics kinematics = AnalyzeSixBarKinematics(six_bar, input, options, 1.0);
    const SixBarDriver driver(six_bar, input, 1.0);
    // Each body's centre of mass (in its reference place) and moment per mass.
    const std::array<std::vector<Eigen::Vector2d>, 6> joints = SixBarBodyJoints(six_bar);
    std::array<Eigen::Vector2d, 5> centres;
    std::array<double, 5> moments;
    for (int body = 1; body <= 5; ++body) {
      std::vector<Eigen::Vector2d> points = joints[body];
      if (body == kSixBarTaskBody) points.push_back(six_bar.reference_pose.origin_in_fixed);
      UniformBody(points, &centres[body - 1], &moments[body - 1]);
    }
    const double w = options.input_speed;
    for (const SixBarState& state : kinematics.states) {
      if (std::min(state.transmission_deg[0], state.transmission_deg[1]) < 15.0) continue;
      if (state.angular_velocity.cwiseAbs().maxCoeff() > 10.0 * w) continue;
      SixBarAssembly assembly;
      ASSERT_TRUE(driver.AssemblyOf(state.turns, &assembly));
      const double t = state.turns[input - 1];
      // Kinetic and potential energy at input turn u, from positions at u +- h only.
      const auto energies = [&](double u, double* kinetic, double* potential) {
        const double h = 1e-5;
        SixBarAngles plus = state.turns, minus = state.turns, here = state.turns;
        if (!driver.Place(assembly, u + h, &plus, 1e-14) ||
            !driver.Place(assembly, u - h, &minus, 1e-14) ||
            !driver.Place(assembly, u, &here, 1e-14)) {
          return false;
        }
        *kinetic = *potential = 0.0;
        for (int body = 1; body <= 5; ++body) {
          const double m = options.masses.mass[body - 1];
          const auto at = [&](const SixBarAngles& turns) {
            return SixBarBodyDisplacement(six_bar, turns, body).ToFixed(centres[body - 1]);
          };
          const Eigen::Vector2d v = (at(plus) - at(minus)) / (2.0 * h) * w;
          const double turn_rate = (plus[body - 1] - minus[body - 1]) / (2.0 * h) * w;
          *kinetic += 0.5 * m * (v.squaredNorm() + moments[body - 1] * turn_rate * turn_rate);
          *potential += m * 9.80665 * at(here).y();
        }
        return true;
      };
      // Richardson-extrapolated central differences over H = 1e-3 and H / 2.
      double inertial = 0.0, weight = 0.0;
      if (!testing::EnergyRates(t, 1e-3, energies, &inertial, &weight)) continue;
      const double scale = 1.0 + std::abs(inertial) + std::abs(weight);
      worst = std::max({worst, std::abs(state.inertial_torque - inertial) / scale,
                        std::abs(state.weight_torque - weight) / scale});
      EXPECT_NEAR(state.inertial_torque, inertial, 1e-4 * scale);
      EXPECT_NEAR(state.weight_torque, weight, 1e-4 * scale);
      EXPECT_NEAR(state.input_torque, state.inertial_torque + state.weight_torque, 1e-12 * scale);
      ++checked;
    }
  });
  std::cout << checked << " states checked; worst difference " << worst << " (relative)\n";
  EXPECT_GT(checked, 300);
}

// A rocking input's range ends at its dead points: the six-bar drives up to each and not past it
// on the same assembly, and the states lie between them; the ends are the same at 30 and 600
// steps; a crank has none and its states run a whole turn.
TEST(SixBarKinematics, ARockersRangeEndsWhereItCannotDriveOn) {
  int rockers = 0;
  ForEachDrivenSixBar(kSeed + 1, 4, [&](const SixBar& six_bar, int input) {
    SixBarKinematicsOptions options;
    options.steps = 30;
    const SixBarKinematics kinematics = AnalyzeSixBarKinematics(six_bar, input, options, 1.0);
    ASSERT_FALSE(kinematics.states.empty()) << kinematics.note;
    const double reference = SixBarInputReferenceAngle(six_bar, input);
    if (kinematics.input_rotates_fully) {
      EXPECT_TRUE(kinematics.dead_points.empty());
      EXPECT_NEAR(kinematics.range_end - kinematics.range_start, 2.0 * M_PI, 1e-12);
      EXPECT_EQ(kinematics.states.front().input_angle, reference);
      return;
    }
    ++rockers;
    ASSERT_GE(kinematics.dead_points.size(), 2u);
    EXPECT_LT(kinematics.range_start, reference);
    EXPECT_GT(kinematics.range_end, reference);
    EXPECT_GT(kinematics.states.front().input_angle, kinematics.range_start);
    EXPECT_LT(kinematics.states.back().input_angle, kinematics.range_end);
    const SixBarDriver driver(six_bar, input, 1.0);
    for (int end = 0; end < 2; ++end) {
      const SixBarState& dead = kinematics.dead_points[end];
      EXPECT_NEAR(dead.input_angle, end == 0 ? kinematics.range_start : kinematics.range_end,
                  1e-12);
      // A little past it the six-bar does not drive on.
      SixBarAngles past = dead.turns;
      const double beyond = (end == 0 ? -1.0 : 1.0) * 1e-3;
      EXPECT_FALSE(driver.Drive(dead.turns[input - 1] + beyond, &past, kSixBarDriveStep));
    }
    options.steps = 600;
    const SixBarKinematics fine = AnalyzeSixBarKinematics(six_bar, input, options, 1.0);
    EXPECT_NEAR(fine.range_start, kinematics.range_start, 1e-7);
    EXPECT_NEAR(fine.range_end, kinematics.range_end, 1e-7);
  });
  EXPECT_GT(rockers, 5);
}

}  // namespace
}  // namespace linkfit
