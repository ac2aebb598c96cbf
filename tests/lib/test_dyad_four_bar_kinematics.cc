// Tests of lib/dyad_four_bar_kinematics.h on random four-bars of all nine input/output dyad
// types (RR, PR, RP): the coupler's and the output's rates and the coupler point's against
// Richardson-extrapolated central differences of the position analysis (AssembleFourBar), the
// input effort against the load's work, the 4R and the slider-crank against their closed form
// (lib/four_bar_kinematics.h), and a range's ends where the transmission angle is 0 or 180.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "lib/dyad_four_bar_kinematics.h"
#include "lib/four_bar_kinematics.h"
#include "lib/mechanism.h"
#include "lib/uniform_body.h"
#include "tests/support/richardson.h"

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
          std::array<Sample, 5> s;
          const double offsets[5] = {-h, -0.5 * h, 0.0, 0.5 * h, h};
          bool placed = true;
          for (int k = 0; k < 5; ++k) placed = placed && at(state.input + offsets[k], &s[k]);
          if (!placed) continue;
          if (out == DyadType::kRR) {
            for (int k = 0; k < 5; ++k) {
              s[k].output += 2.0 * M_PI * std::round((s[2].output - s[k].output) / (2.0 * M_PI));
            }
          }
          // Richardson-extrapolated central differences in the input's value, times w (w^2).
          const auto first = [&](auto get) {
            return decltype(get(s[0]))(testing::RichardsonFirst(testing::EachOf(s, get), h) * w);
          };
          const auto second = [&](auto get) {
            return decltype(get(s[0]))(testing::RichardsonSecond(testing::EachOf(s, get), h) * w *
                                       w);
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
      EXPECT_EQ(general.input_rotates_fully, closed.input_rotates_fully);
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

// With the links' masses, the inertial and the weight's efforts are the rates of the links'
// kinetic and potential energy over the input's value: against nested central differences of
// the positions alone, for all nine type pairs.
TEST(DyadFourBarKinematics, InertialEffortIsTheRateOfTheLinksEnergy) {
  std::mt19937_64 rng(kSeed + 3);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  int checked = 0;
  double worst = 0.0;
  for (const DyadType in : types) {
    for (const DyadType out : types) {
      for (int trial = 0; trial < 15; ++trial) {
        const PlanarDyad input = RandomDyad(rng, in), output = RandomDyad(rng, out);
        const Eigen::Vector2d point(0.3, -0.5);
        DyadFourBarKinematicsOptions options;
        options.steps = 10;
        options.input_speed = 2.0;
        options.masses.input = 0.6;
        options.masses.coupler = 1.3;
        options.masses.output = 0.8;
        options.masses.gravity = true;
        const DyadFourBarKinematics kinematics =
            AnalyzeDyadFourBarKinematics(input, output, point, PlanarPose(), options, 1.0);
        std::vector<Eigen::Vector2d> on_coupler;
        for (const PlanarDyad* dyad : {&input, &output}) {
          on_coupler.push_back(dyad->type == DyadType::kRP ? dyad->line_point : dyad->moving_pivot);
        }
        on_coupler.push_back(point);
        Eigen::Vector2d centre;
        double moment = 0.0;
        UniformBody(on_coupler, &centre, &moment);
        const double w = options.input_speed;
        for (const DyadFourBarState& state : kinematics.states) {
          if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 15) {
            continue;
          }
          if (state.velocity.cwiseAbs().maxCoeff() > 10.0 * std::abs(w)) continue;
          const auto pose_at = [&](double value, PlanarPose* pose) {
            std::vector<PlanarPose> poses;
            if (AssembleFourBar(input, output, value, 0.0, &poses) == 0) return false;
            double best = std::numeric_limits<double>::infinity();
            for (PlanarPose candidate : poses) {
              candidate.theta +=
                  2.0 * M_PI * std::round((state.coupler.theta - candidate.theta) / (2.0 * M_PI));
              const double distance =
                  (candidate.origin_in_fixed - state.coupler.origin_in_fixed).norm() +
                  std::abs(candidate.theta - state.coupler.theta);
              if (distance < best) {
                best = distance;
                *pose = candidate;
              }
            }
            return true;
          };
          // The energies at input value u from positions at u +- h.
          const auto energies = [&](double u, double* kinetic, double* potential) {
            const double h = 1e-5;
            PlanarPose plus, minus, here;
            if (!pose_at(u + h, &plus) || !pose_at(u - h, &minus) || !pose_at(u, &here)) {
              return false;
            }
            const auto rate = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
              return Eigen::Vector2d((a - b) / (2.0 * h) * w);
            };
            *kinetic = *potential = 0.0;
            const double g = 9.80665;
            for (const auto& [dyad, m] : {std::pair{&input, options.masses.input},
                                          std::pair{&output, options.masses.output}}) {
              if (dyad->type == DyadType::kRR) {
                const Eigen::Vector2d pin_plus = plus.ToFixed(dyad->moving_pivot);
                const Eigen::Vector2d pin_minus = minus.ToFixed(dyad->moving_pivot);
                const Eigen::Vector2d v = 0.5 * rate(pin_plus, pin_minus);
                const double turn =
                    std::remainder(std::atan2((pin_plus - dyad->fixed_pivot).y(),
                                              (pin_plus - dyad->fixed_pivot).x()) -
                                       std::atan2((pin_minus - dyad->fixed_pivot).y(),
                                                  (pin_minus - dyad->fixed_pivot).x()),
                                   2.0 * M_PI) /
                    (2.0 * h) * w;
                *kinetic +=
                    0.5 * m * (v.squaredNorm() + dyad->radius * dyad->radius / 12.0 * turn * turn);
                *potential +=
                    m * g * 0.5 * (here.ToFixed(dyad->moving_pivot) + dyad->fixed_pivot).y();
              } else if (dyad->type == DyadType::kPR) {
                const Eigen::Vector2d v =
                    rate(plus.ToFixed(dyad->moving_pivot), minus.ToFixed(dyad->moving_pivot));
                *kinetic += 0.5 * m * v.squaredNorm();
                *potential += m * g * here.ToFixed(dyad->moving_pivot).y();
              }
            }
            const Eigen::Vector2d v = rate(plus.ToFixed(centre), minus.ToFixed(centre));
            const double turn = (plus.theta - minus.theta) / (2.0 * h) * w;
            *kinetic += 0.5 * options.masses.coupler * (v.squaredNorm() + moment * turn * turn);
            *potential += options.masses.coupler * g * here.ToFixed(centre).y();
            return true;
          };
          // H = 2.5e-4: near dead points the energy's higher derivatives grow.
          double inertial = 0.0, weight = 0.0;
          if (!testing::EnergyRates(state.input, 2.5e-4, energies, &inertial, &weight)) continue;
          const double scale = 1.0 + std::abs(inertial) + std::abs(weight);
          worst = std::max({worst, std::abs(state.inertial_effort - inertial) / scale,
                            std::abs(state.weight_effort - weight) / scale});
          EXPECT_NEAR(state.inertial_effort, inertial, 1e-5 * scale)
              << DyadTypeName(in) << " + " << DyadTypeName(out);
          EXPECT_NEAR(state.weight_effort, weight, 1e-5 * scale)
              << DyadTypeName(in) << " + " << DyadTypeName(out);
          ++checked;
        }
      }
    }
  }
  std::cout << checked << " states checked; worst difference " << worst << " (relative)\n";
  EXPECT_GT(checked, 500);
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
