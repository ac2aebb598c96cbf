// Tests of lib/spherical_four_bar_kinematics.h on random spherical four-bars: the closed-form
// output rates and the coupler's angular velocity and acceleration against Richardson-extrapolated
// central differences of the position analysis (three points of the coupler: its pins and their
// cross product), the input torque against the load's work, a rocker's range ending at its dead
// points (transmission angle 0 or 180 degrees).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>

#include "lib/spherical_four_bar_kinematics.h"
#include "tests/support/richardson.h"

namespace linkfit {
namespace {

constexpr uint64_t kSeed = 3711;

Eigen::Vector3d RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

// A random spherical four-bar at a random configuration: its links at least 15 degrees and its
// transmission angle there at least 12 degrees from a dead point.
SphericalFourBarJoints RandomSphericalFourBar(std::mt19937_64& rng) {
  for (;;) {
    SphericalFourBarJoints joints;
    joints.input_pivot = RandomUnit(rng);
    joints.input_pin = RandomUnit(rng);
    joints.output_pin = RandomUnit(rng);
    joints.output_pivot = RandomUnit(rng);
    const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
    };
    const double links[] = {angle(joints.input_pivot, joints.input_pin),
                            angle(joints.input_pin, joints.output_pin),
                            angle(joints.output_pin, joints.output_pivot),
                            angle(joints.input_pivot, joints.output_pivot)};
    if (*std::min_element(std::begin(links), std::end(links)) < 15.0 ||
        *std::max_element(std::begin(links), std::end(links)) > 165.0) {
      continue;
    }
    SphericalFourBarState state;
    const Eigen::Vector3d& u1 = joints.input_pivot;
    const Eigen::Vector3d e1 =
        (joints.output_pivot - joints.output_pivot.dot(u1) * u1).normalized();
    const double phi = std::atan2(joints.input_pin.dot(u1.cross(e1)), joints.input_pin.dot(e1));
    if (!PlaceSphericalFourBar(joints, phi, &state)) continue;
    if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) > 12.0) {
      return joints;
    }
  }
}

TEST(SphericalFourBarKinematics, RatesAreTheDerivativesOfThePositions) {
  std::mt19937_64 rng(kSeed);
  int checked = 0, cranks = 0, rockers = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 150; ++trial) {
    const SphericalFourBarJoints joints = RandomSphericalFourBar(rng);
    SphericalFourBarKinematicsOptions options;
    options.steps = 24;
    options.input_speed = trial % 2 ? 1.6 : -0.7;
    options.output_torque = 2.5;
    const SphericalFourBarKinematics kinematics =
        AnalyzeSphericalFourBarKinematics(joints, options);
    ASSERT_FALSE(kinematics.states.empty()) << kinematics.note;
    (kinematics.input_rotates_fully ? cranks : rockers)++;
    const double w = options.input_speed;
    for (const SphericalFourBarState& state : kinematics.states) {
      if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 10.0) {
        continue;
      }
      // Positions at phi + k h: psi and three coupler points.
      struct Sample {
        double psi;
        Eigen::Vector3d points[3];
      };
      const auto at = [&](double phi, Sample* sample) {
        SphericalFourBarState placed;
        if (!PlaceSphericalFourBar(joints, phi, &placed)) return false;
        sample->psi = placed.output_angle;
        sample->points[0] = placed.input_pin;
        sample->points[1] = placed.output_pin;
        sample->points[2] = placed.input_pin.cross(placed.output_pin);
        return true;
      };
      const double h = 2e-4, phi = state.input_angle;
      std::array<Sample, 5> s;  // phi - h, phi - h/2, phi, phi + h/2, phi + h
      const double offsets[5] = {-h, -0.5 * h, 0.0, 0.5 * h, h};
      bool placed = true;
      for (int k = 0; k < 5; ++k) placed = placed && at(phi + offsets[k], &s[k]);
      if (!placed) continue;
      // psi continued across the samples.
      for (int k = 0; k < 5; ++k) {
        s[k].psi += 2.0 * M_PI * std::round((s[2].psi - s[k].psi) / (2.0 * M_PI));
      }
      // Richardson-extrapolated central differences in the input angle, times w (w^2).
      const auto first = [&](auto get) {
        return decltype(get(s[0]))(testing::RichardsonFirst(testing::EachOf(s, get), h) * w);
      };
      const auto second = [&](auto get) {
        return decltype(get(s[0]))(testing::RichardsonSecond(testing::EachOf(s, get), h) * w * w);
      };
      const auto expect = [&](double got, double want, double tolerance, const char* what) {
        const double scaled = tolerance * std::max(1.0, std::abs(want));
        worst = std::max(worst, std::abs(got - want) / scaled);
        EXPECT_NEAR(got, want, scaled)
            << what << " at transmission angle " << state.transmission_angle_deg;
      };
      const auto psi = [](const Sample& sample) -> double { return sample.psi; };
      expect(state.output_velocity, first(psi), 1e-6, "psi'");
      expect(state.output_acceleration, second(psi), 1e-4, "psi''");
      // The coupler's points: v = omega3 x p, a = alpha3 x p + omega3 x (omega3 x p).
      const Eigen::Vector3d& omega = state.coupler_velocity;
      const Eigen::Vector3d& alpha = state.coupler_acceleration;
      for (int p = 0; p < 3; ++p) {
        const auto point = [p](const Sample& sample) -> Eigen::Vector3d {
          return sample.points[p];
        };
        const Eigen::Vector3d here = s[2].points[p];
        const Eigen::Vector3d velocity = omega.cross(here);
        const Eigen::Vector3d acceleration = alpha.cross(here) + omega.cross(omega.cross(here));
        const Eigen::Vector3d velocity_difference = first(point);
        const Eigen::Vector3d acceleration_difference = second(point);
        for (int c = 0; c < 3; ++c) {
          expect(velocity[c], velocity_difference[c], 1e-6, "coupler point velocity");
          expect(acceleration[c], acceleration_difference[c], 1e-4, "coupler point acceleration");
        }
      }
      // The input torque: minus the output load's work per radian of the input.
      expect(state.input_torque, -options.output_torque * first(psi) / w, 1e-6, "torque");
      ++checked;
    }
  }
  std::cout << checked << " states checked (" << cranks << " cranks, " << rockers
            << " rockers); worst difference " << worst << " of its tolerance\n";
  EXPECT_GT(checked, 1500);
  EXPECT_GT(cranks, 5);
  EXPECT_GT(rockers, 20);
}

// With the links' masses (thin arcs of the sphere), the inertial and the weight's torques are
// the rates of the links' kinetic and potential energy over the input angle: against nested
// central differences of the positions alone (the output's angle and the coupler's rotation at
// phi +- h give their angular velocities; the energies at phi +- H, H / 2 their rates). The arcs'
// moments against a quadrature.
TEST(SphericalFourBarKinematics, InertialTorqueIsTheRateOfTheLinksEnergy) {
  std::mt19937_64 rng(kSeed + 2);
  {
    const Eigen::Vector3d a = RandomUnit(rng), b = RandomUnit(rng);
    Eigen::Matrix3d mean_outer;
    Eigen::Vector3d mean_direction;
    SphericalArcMoments(a, b, &mean_outer, &mean_direction);
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    const int n = 20000;
    const double t = std::atan2(a.cross(b).norm(), a.dot(b));
    for (int k = 0; k < n; ++k) {
      const double s = (k + 0.5) / n;
      const Eigen::Vector3d d = (std::sin((1.0 - s) * t) * a + std::sin(s * t) * b) / std::sin(t);
      outer += d * d.transpose() / n;
      direction += d / n;
    }
    EXPECT_LT((outer - mean_outer).norm(), 1e-8);
    EXPECT_LT((direction - mean_direction).norm(), 1e-8);
  }
  int checked = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 60; ++trial) {
    const SphericalFourBarJoints joints = RandomSphericalFourBar(rng);
    SphericalFourBarKinematicsOptions options;
    options.steps = 12;
    options.input_speed = 2.5;
    options.masses.input = 0.4;
    options.masses.coupler = 1.2;
    options.masses.output = 0.7;
    options.masses.radius = 0.8;
    options.masses.gravity = true;
    const SphericalFourBarKinematics kinematics =
        AnalyzeSphericalFourBarKinematics(joints, options);
    const double w = options.input_speed, r = options.masses.radius;
    const auto inertia = [&](double m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             Eigen::Vector3d* centre) {
      Eigen::Matrix3d mean_outer;
      Eigen::Vector3d mean_direction;
      SphericalArcMoments(a, b, &mean_outer, &mean_direction);
      *centre = r * mean_direction;
      return Eigen::Matrix3d(m * r * r * (Eigen::Matrix3d::Identity() - mean_outer));
    };
    for (const SphericalFourBarState& state : kinematics.states) {
      if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 15.0) {
        continue;
      }
      // The energies at input angle u from positions at u +- h.
      const auto energies = [&](double u, double* kinetic, double* potential) {
        const double h = 1e-5;
        SphericalFourBarState plus, minus, here;
        if (!PlaceSphericalFourBar(joints, u + h, &plus) ||
            !PlaceSphericalFourBar(joints, u - h, &minus) ||
            !PlaceSphericalFourBar(joints, u, &here)) {
          return false;
        }
        const double psi_turn =
            std::remainder(plus.output_angle - minus.output_angle, 2.0 * M_PI) / (2.0 * h) * w;
        const Eigen::Matrix3d rate =
            (plus.coupler_rotation_matrix - minus.coupler_rotation_matrix) / (2.0 * h) * w;
        const Eigen::Matrix3d spin = rate * here.coupler_rotation_matrix.transpose();
        const Eigen::Vector3d coupler(spin(2, 1), spin(0, 2), spin(1, 0));
        const Eigen::Vector3d u1 = joints.input_pivot.normalized();
        const Eigen::Vector3d u2 = joints.output_pivot.normalized();
        Eigen::Vector3d g_in, g_coupler, g_out;
        const Eigen::Matrix3d i_in = inertia(options.masses.input, u1, here.input_pin, &g_in);
        const Eigen::Matrix3d i_coupler =
            inertia(options.masses.coupler, here.input_pin, here.output_pin, &g_coupler);
        const Eigen::Matrix3d i_out = inertia(options.masses.output, here.output_pin, u2, &g_out);
        const Eigen::Vector3d omega_in = w * u1, omega_out = psi_turn * u2;
        *kinetic = 0.5 * (omega_in.dot(i_in * omega_in) + coupler.dot(i_coupler * coupler) +
                          omega_out.dot(i_out * omega_out));
        *potential =
            9.80665 * (options.masses.input * g_in.z() + options.masses.coupler * g_coupler.z() +
                       options.masses.output * g_out.z());
        return true;
      };
      double inertial = 0.0, weight = 0.0;
      if (!testing::EnergyRates(state.input_angle, 2.5e-4, energies, &inertial, &weight)) continue;
      const double scale = 1.0 + std::abs(inertial) + std::abs(weight);
      worst = std::max({worst, std::abs(state.inertial_torque - inertial) / scale,
                        std::abs(state.weight_torque - weight) / scale});
      EXPECT_NEAR(state.inertial_torque, inertial, 1e-5 * scale);
      EXPECT_NEAR(state.weight_torque, weight, 1e-5 * scale);
      EXPECT_NEAR(state.input_torque, state.inertial_torque + state.weight_torque, 1e-12 * scale);
      ++checked;
    }
  }
  std::cout << checked << " states checked; worst difference " << worst << " (relative)\n";
  EXPECT_GT(checked, 300);
}

// A rocker's range ends at its dead points: the transmission angle there is 0 or 180 degrees,
// the loop does not close a little beyond, the states lie between them.
TEST(SphericalFourBarKinematics, ARockersRangeEndsAtItsDeadPoints) {
  std::mt19937_64 rng(kSeed + 1);
  int rockers = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const SphericalFourBarJoints joints = RandomSphericalFourBar(rng);
    const SphericalFourBarKinematics kinematics = AnalyzeSphericalFourBarKinematics(joints, {});
    if (kinematics.input_rotates_fully) {
      EXPECT_TRUE(kinematics.dead_points.empty());
      continue;
    }
    ++rockers;
    ASSERT_EQ(kinematics.dead_points.size(), 2u);
    for (const SphericalFourBarState& dead : kinematics.dead_points) {
      EXPECT_LT(std::min(dead.transmission_angle_deg, 180.0 - dead.transmission_angle_deg), 1e-3);
    }
    EXPECT_LT(kinematics.dead_points[0].input_angle, kinematics.states.front().input_angle);
    EXPECT_GT(kinematics.dead_points[1].input_angle, kinematics.states.back().input_angle);
    SphericalFourBarState beyond;
    EXPECT_FALSE(PlaceSphericalFourBar(joints, kinematics.range_end + 1e-6, &beyond));
    EXPECT_FALSE(PlaceSphericalFourBar(joints, kinematics.range_start - 1e-6, &beyond));
  }
  EXPECT_GT(rockers, 20);
}

}  // namespace
}  // namespace linkfit
