// Tests of lib/dyad_four_bar_kinematics.h on random four-bars of all nine input/output dyad
// types (RR, PR, RP): the coupler's and the output's rates and the coupler point's against
// Richardson-extrapolated central differences of the position analysis (AssembleFourBar), the
// input effort against the load's work, the 4R and the slider-crank against their closed form
// (lib/four_bar_kinematics.h), and a range's ends where the transmission angle is 0 or 180.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "lib/dyad_four_bar_kinematics.h"
#include "lib/four_bar_kinematics.h"
#include "lib/mechanism.h"

namespace linkfit {
namespace {

constexpr uint64_t kSeed = 3719;

Eigen::Vector2d Unit(double angle) { return Eigen::Vector2d(std::cos(angle), std::sin(angle)); }

// A random dyad of `type` at the first configuration (E = Sigma there).
PlanarDyad RandomDyad(std::mt19937_64& rng, DyadType type) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector2d fixed(unit(rng), unit(rng)), moving(unit(rng) + 0.3, unit(rng) + 0.8);
  const Eigen::Vector2d direction = Unit(M_PI * unit(rng));
  switch (type) {
    case DyadType::kRR:
      return PlanarDyad::RR(fixed, moving, (moving - fixed).norm());
    case DyadType::kPR:
      return PlanarDyad::PR(moving, moving - 0.4 * unit(rng) * direction, direction);
    case DyadType::kRP:
      return PlanarDyad::RP(fixed, fixed - 0.4 * unit(rng) * direction, direction);
  }
  return PlanarDyad();
}

// The output joint's value at coupler pose `pose` (the header's definitions).
double OutputValue(const PlanarDyad& output, const PlanarPose& pose) {
  switch (output.type) {
    case DyadType::kRR: {
      const Eigen::Vector2d arm = pose.ToFixed(output.moving_pivot) - output.fixed_pivot;
      return std::atan2(arm.y(), arm.x());
    }
    case DyadType::kPR:
      return output.line_direction.dot(pose.ToFixed(output.moving_pivot) - output.line_point);
    case DyadType::kRP:
      return output.line_direction.dot(pose.ToMoving(output.fixed_pivot) - output.line_point);
  }
  return 0.0;
}

struct Sample {
  Eigen::Vector3d z;  // c, theta
  Eigen::Vector2d point;
  double output = 0.0;
};

TEST(DyadFourBarKinematics, RatesAreTheDerivativesOfThePositions) {
  std::mt19937_64 rng(kSeed);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  int checked = 0, combinations = 0;
  double worst = 0.0;
  for (const DyadType in : types) {
    for (const DyadType out : types) {
      int states_of_this = 0;
      for (int trial = 0; trial < 60; ++trial) {
        const PlanarDyad input = RandomDyad(rng, in), output = RandomDyad(rng, out);
        const Eigen::Vector2d point(0.3, -0.5);
        DyadFourBarKinematicsOptions options;
        options.steps = 16;
        options.input_speed = trial % 2 ? 1.3 : -0.6;
        options.load.coupler_force = Eigen::Vector2d(2.0, -1.0);
        options.load.output_torque = 0.7;
        options.load.slider_force = -1.1;
        const DyadFourBarKinematics kinematics =
            AnalyzeDyadFourBarKinematics(input, output, point, PlanarPose(), options, 1.0);
        const double w = options.input_speed;
        for (const DyadFourBarState& state : kinematics.states) {
          if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 10) {
            continue;
          }
          if (state.velocity.cwiseAbs().maxCoeff() > 20.0 * std::abs(w)) continue;
          const auto at = [&](double value, Sample* sample) {
            std::vector<PlanarPose> poses;
            if (AssembleFourBar(input, output, value, 0.0, &poses) == 0) return false;
            double best = std::numeric_limits<double>::infinity();
            for (PlanarPose pose : poses) {
              pose.theta +=
                  2.0 * M_PI * std::round((state.coupler.theta - pose.theta) / (2.0 * M_PI));
              const double distance =
                  (pose.origin_in_fixed - state.coupler.origin_in_fixed).norm() +
                  std::abs(pose.theta - state.coupler.theta);
              if (distance < best) {
                best = distance;
                sample->z << pose.origin_in_fixed, pose.theta;
                sample->point = pose.ToFixed(point);
                sample->output = OutputValue(output, pose);
              }
            }
            return true;
          };
          const double h = 2.5e-4;
          Sample s[5];
          const double offsets[5] = {-h, -0.5 * h, 0.0, 0.5 * h, h};
          bool placed = true;
          for (int k = 0; k < 5; ++k) placed = placed && at(state.input + offsets[k], &s[k]);
          if (!placed) continue;
          if (out == DyadType::kRR) {
            for (int k = 0; k < 5; ++k) {
              s[k].output += 2.0 * M_PI * std::round((s[2].output - s[k].output) / (2.0 * M_PI));
            }
          }
          const auto first = [&](auto get) {
            using Value = decltype(get(s[0]));
            const Value d1 = (get(s[4]) - get(s[0])) / (2.0 * h);
            const Value d2 = (get(s[3]) - get(s[1])) / h;
            return Value((4.0 * d2 - d1) / 3.0 * w);
          };
          const auto second = [&](auto get) {
            using Value = decltype(get(s[0]));
            const Value d1 = (get(s[4]) - 2.0 * get(s[2]) + get(s[0])) / (h * h);
            const Value d2 = (get(s[3]) - 2.0 * get(s[2]) + get(s[1])) / (0.25 * h * h);
            return Value((4.0 * d2 - d1) / 3.0 * w * w);
          };
          const auto expect = [&](double got, double want, double tolerance, const char* what) {
            const double scaled = tolerance * std::max(1.0, std::abs(want));
            worst = std::max(worst, std::abs(got - want) / scaled);
            EXPECT_NEAR(got, want, scaled)
                << what << " of " << DyadTypeName(in) << " + " << DyadTypeName(out);
          };
          const auto z = [](const Sample& x) -> Eigen::Vector3d { return x.z; };
          const auto p = [](const Sample& x) -> Eigen::Vector2d { return x.point; };
          const auto o = [](const Sample& x) -> double { return x.output; };
          const Eigen::Vector3d z_rate = first(z), z_acc = second(z);
          const Eigen::Vector2d p_rate = first(p), p_acc = second(p);
          for (int c = 0; c < 3; ++c) {
            expect(state.velocity[c], z_rate[c], 1e-6, "coupler rate");
            expect(state.acceleration[c], z_acc[c], 1e-4, "coupler acceleration");
          }
          for (int c = 0; c < 2; ++c) {
            expect(state.coupler_point_velocity[c], p_rate[c], 1e-6, "point velocity");
            expect(state.coupler_point_acceleration[c], p_acc[c], 1e-4, "point acceleration");
          }
          expect(state.output_velocity, first(o), 1e-6, "output rate");
          expect(state.output_acceleration, second(o), 1e-4, "output acceleration");
          const double work =
              options.load.coupler_force.dot(p_rate) +
              (out == DyadType::kRR ? options.load.output_torque : options.load.slider_force) *
                  first(o);
          expect(state.input_effort, -work / w, 1e-6, "input effort");
          ++checked;
          ++states_of_this;
        }
      }
      EXPECT_GT(states_of_this, 100) << DyadTypeName(in) << " + " << DyadTypeName(out);
      ++combinations;
    }
  }
  std::cout << checked << " states of " << combinations << " type pairs checked; worst difference "
            << worst << " of its tolerance\n";
}

// The 4R and the slider-crank driven by their crank: the same as the closed form.
TEST(DyadFourBarKinematics, AgreesWithTheClosedFormFourBar) {
  std::mt19937_64 rng(kSeed + 1);
  int compared = 0;
  for (const DyadType out : {DyadType::kRR, DyadType::kPR}) {
    for (int trial = 0; trial < 40; ++trial) {
      const PlanarDyad input = RandomDyad(rng, DyadType::kRR), output = RandomDyad(rng, out);
      const Eigen::Vector2d point(0.3, -0.5);
      FourBarJoints joints;
      joints.input_pivot = input.fixed_pivot;
      joints.input_pin = input.moving_pivot;
      joints.output_pin = output.moving_pivot;
      joints.coupler_point = point;
      if (out == DyadType::kRR) {
        joints.output_pivot = output.fixed_pivot;
      } else {
        joints.slider = true;
        joints.slider_point = output.line_point;
        joints.slider_direction = output.line_direction;
      }
      FourBarKinematicsOptions closed_options;
      closed_options.steps = 20;
      closed_options.input_speed = 1.4;
      const FourBarKinematics closed = AnalyzeFourBarKinematics(joints, closed_options, 1.0);
      DyadFourBarKinematicsOptions options;
      options.steps = 20;
      options.input_speed = 1.4;
      const DyadFourBarKinematics general =
          AnalyzeDyadFourBarKinematics(input, output, point, PlanarPose(), options, 1.0);
      EXPECT_EQ(general.input_turns_fully, closed.input_rotates_fully);
      EXPECT_NEAR(general.range_start, closed.range_start, 1e-9);
      EXPECT_NEAR(general.range_end, closed.range_end, 1e-9);
      if (general.states.size() != closed.states.size()) continue;  // a dead point sampled
      for (size_t k = 0; k < closed.states.size(); ++k) {
        const FourBarState& a = closed.states[k];
        const DyadFourBarState& b = general.states[k];
        const double scale =
            1.0 + std::abs(a.output_acceleration) + std::abs(a.coupler_acceleration);
        EXPECT_NEAR(b.velocity[2], a.coupler_velocity, 1e-9 * scale);
        EXPECT_NEAR(b.acceleration[2], a.coupler_acceleration, 1e-8 * scale);
        EXPECT_NEAR(b.output_velocity, a.output_velocity, 1e-9 * scale);
        EXPECT_NEAR(b.output_acceleration, a.output_acceleration, 1e-8 * scale);
        EXPECT_NEAR((b.coupler_point - a.coupler_point).norm(), 0.0, 1e-9);
        EXPECT_NEAR(b.transmission_angle_deg, a.transmission_angle_deg, 1e-7);
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 800);
}

// Where an input's range ends (the four-bar stops assembling), the transmission angle is 0 or
// 180 degrees: the definitions in the header are the input's dead points, for every type pair.
TEST(DyadFourBarKinematics, RangesEndWhereTheTransmissionAngleVanishes) {
  std::mt19937_64 rng(kSeed + 2);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  for (const DyadType in : types) {
    for (const DyadType out : types) {
      int ends = 0;
      for (int trial = 0; trial < 40; ++trial) {
        const PlanarDyad input = RandomDyad(rng, in), output = RandomDyad(rng, out);
        DyadFourBarKinematicsOptions options;
        options.steps = 10;
        const DyadFourBarKinematics kinematics = AnalyzeDyadFourBarKinematics(
            input, output, Eigen::Vector2d(0.3, -0.5), PlanarPose(), options, 1.0);
        for (const DyadFourBarState& dead : kinematics.dead_points) {
          EXPECT_LT(std::min(dead.transmission_angle_deg, 180.0 - dead.transmission_angle_deg),
                    1e-3)
              << DyadTypeName(in) << " + " << DyadTypeName(out) << " at " << dead.input;
          ++ends;
        }
      }
      // (An RP input with an RP output turns without dead points: its lines keep their angle;
      // with a PR output its coupler runs off where the lines turn parallel, no dead point.)
      if (in != DyadType::kRP || out == DyadType::kRR) {
        EXPECT_GT(ends, 10) << DyadTypeName(in) << " + " << DyadTypeName(out);
      }
    }
  }
}

}  // namespace
}  // namespace linkfit
