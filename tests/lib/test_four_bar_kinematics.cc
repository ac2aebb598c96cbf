// Tests of lib/four_bar_kinematics.h: random 4Rs and slider-cranks; the closed-form velocities
// and accelerations against central differences of the position analysis, the textbook
// slider-crank, the input torque from virtual work against a free-body statics solve (joint
// forces), dead points at transmission angles of 0 or 180 degrees.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include "lib/four_bar_kinematics.h"

namespace linkfit {
namespace {

// Relative (to the larger of 1 and the value): the closed form against Richardson-extrapolated
// central differences, velocities and accelerations.
constexpr double kVelocityTolerance = 1e-8;
constexpr double kRateTolerance = 1e-6;
constexpr uint64_t kSeed = 3701;

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// A random 4R (or slider-crank) at a random crank angle, its coupler point off the coupler.
FourBarJoints RandomFourBar(std::mt19937_64& rng, bool slider) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.3, 1.5);
  for (;;) {
    FourBarJoints joints;
    joints.input_pivot = Eigen::Vector2d(unit(rng), unit(rng));
    const double crank = size(rng), coupler = size(rng) + 0.5, angle = M_PI * unit(rng);
    joints.input_pin =
        joints.input_pivot + crank * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    joints.coupler_point = joints.input_pin + Eigen::Vector2d(unit(rng), unit(rng));
    const double turn = M_PI * unit(rng);
    joints.output_pin =
        joints.input_pin + coupler * Eigen::Vector2d(std::cos(turn), std::sin(turn));
    if (slider) {
      joints.slider = true;
      const double line = M_PI * unit(rng);
      joints.slider_direction = Eigen::Vector2d(std::cos(line), std::sin(line));
      joints.slider_point = joints.output_pin - 0.7 * unit(rng) * joints.slider_direction;
    } else {
      const double rocker = size(rng), at = M_PI * unit(rng);
      joints.output_pivot =
          joints.output_pin - rocker * Eigen::Vector2d(std::cos(at), std::sin(at));
    }
    // Away from a dead point at the reference (the range's ends are tested apart).
    const Eigen::Vector2d r3 = joints.output_pin - joints.input_pin;
    const Eigen::Vector2d other =
        slider ? Perp(joints.slider_direction) : joints.output_pin - joints.output_pivot;
    if (std::abs(r3.normalized().x() * other.normalized().y() -
                 r3.normalized().y() * other.normalized().x()) > 0.2) {
      return joints;
    }
  }
}

TEST(FourBarKinematics, RatesAreTheDerivativesOfThePositions) {
  std::mt19937_64 rng(kSeed);
  int checked = 0, checks = 0;
  double worst = 0.0;
  for (const bool slider : {false, true}) {
    for (int trial = 0; trial < 60; ++trial) {
      SCOPED_TRACE(std::string(slider ? "slider-crank" : "4R") + " trial " + std::to_string(trial) +
                   ", seed " + std::to_string(kSeed));
      const FourBarJoints joints = RandomFourBar(rng, slider);
      FourBarKinematicsOptions options;
      options.input_speed = 2.5;
      options.steps = 90;
      const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, options, 1.0);
      ASSERT_FALSE(kinematics.states.empty()) << kinematics.note;
      // Central differences over neighbouring samples of a dense analysis (0.01 degrees apart).
      FourBarKinematicsOptions dense = options;
      dense.steps = 36000;
      const FourBarKinematics fine = AnalyzeFourBarKinematics(joints, dense, 1.0);
      for (size_t k = 20; k + 20 < fine.states.size(); k += 997) {
        const FourBarState& at = fine.states[k];
        if (at.transmission_angle_deg < 10.0 || at.transmission_angle_deg > 170.0) continue;
        // Richardson's extrapolation of central differences at steps h and 2h (error h^4).
        const double dt = (fine.states[k + 1].input_angle - at.input_angle) / options.input_speed;
        bool oracle = true;
        // Velocities from the nearest samples (0.01 degrees apart); accelerations from samples
        // ten apart (the positions' rounding, 1e-15, over the step squared stays below 1e-9).
        const auto rate = [&](const auto& of) {
          using Value = decltype(of(at));
          const Value first = (of(fine.states[k + 1]) - of(fine.states[k - 1])) / (2.0 * dt);
          const Value wide = (of(fine.states[k + 2]) - of(fine.states[k - 2])) / (4.0 * dt);
          return Value((4.0 * first - wide) / 3.0);
        };
        const auto second = [&](const auto& of) {
          using Value = decltype(of(at));
          const double h = 10.0 * dt;
          const Value first =
              (of(fine.states[k + 10]) - 2.0 * of(at) + of(fine.states[k - 10])) / (h * h);
          const Value wide =
              (of(fine.states[k + 20]) - 2.0 * of(at) + of(fine.states[k - 20])) / (4.0 * h * h);
          // Where the two steps disagree by more than 1e-3 the extrapolation's own error (about
          // the square of that) exceeds the tolerance: no oracle (near a dead point the rates'
          // derivatives grow without bound), skipped.
          if ((first - wide).norm() > 1e-3 * std::max(1.0, first.norm())) {
            oracle = false;
          }
          return Value((4.0 * first - wide) / 3.0);
        };
        const auto check = [&](const auto& closed, const auto& central, double tolerance) {
          const double scale = std::max(1.0, central.norm());
          const double error = (closed - central).norm() / scale;
          if (!oracle) return;
          worst = std::max(worst, error / tolerance * kRateTolerance);
          EXPECT_LT(error, tolerance) << closed.transpose() << " against " << central.transpose();
          ++checks;
        };
        using Scalar = Eigen::Matrix<double, 1, 1>;
        const auto coupler = [](const FourBarState& x) { return Scalar(x.coupler_angle); };
        const auto output = [](const FourBarState& x) { return Scalar(x.output); };
        const auto point = [](const FourBarState& x) { return Eigen::Vector2d(x.coupler_point); };
        check(Scalar(at.coupler_velocity), rate(coupler), kVelocityTolerance);
        check(Scalar(at.coupler_acceleration), second(coupler), kRateTolerance);
        check(Scalar(at.output_velocity), rate(output), kVelocityTolerance);
        check(Scalar(at.output_acceleration), second(output), kRateTolerance);
        check(at.coupler_point_velocity, rate(point), kVelocityTolerance);
        check(at.coupler_point_acceleration, second(point), kRateTolerance);
        ++checked;
      }
    }
  }
  EXPECT_GT(checks, 5 * checked);  // six rates a state, few near dead points skipped
  std::cout << checked << " states, " << checks << " rates checked; worst difference "
            << worst / kRateTolerance << " of its tolerance\n";
}

// The textbook in-line slider-crank (crank a, coupler b, no offset, the line through the crank's
// pivot): x = a cos t + sqrt(b^2 - a^2 sin^2 t), x' = -a w sin t (1 + a cos t / sqrt(...)).
TEST(FourBarKinematics, TheInLineSliderCrankOfTheTextbooks) {
  const double a = 0.4, b = 1.3, w = 3.0;
  FourBarJoints joints;
  joints.slider = true;
  joints.input_pivot = Eigen::Vector2d(0.2, -0.1);
  joints.input_pin = joints.input_pivot + a * Eigen::Vector2d(1.0, 0.0);
  joints.output_pin = joints.input_pivot + Eigen::Vector2d(a + b, 0.0);
  joints.slider_point = joints.input_pivot;
  joints.slider_direction = Eigen::Vector2d::UnitX();
  FourBarKinematicsOptions options;
  options.input_speed = w;
  options.steps = 72;
  options.load.slider_force = -10.0;  // pushing back against the slider's motion along +x
  const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, options, 1.0);
  ASSERT_TRUE(kinematics.input_rotates_fully);
  ASSERT_EQ(kinematics.states.size(), 72u);
  EXPECT_TRUE(kinematics.dead_points.empty());
  for (const FourBarState& state : kinematics.states) {
    const double t = state.input_angle, root = std::sqrt(b * b - a * a * std::sin(t) * std::sin(t));
    EXPECT_NEAR(state.output, a * std::cos(t) + root, 1e-12);
    const double velocity = -a * w * std::sin(t) * (1.0 + a * std::cos(t) / root);
    EXPECT_NEAR(state.output_velocity, velocity, 1e-12);
    // x'' = -a w^2 [cos t + a (b^2 cos 2t + a^2 sin^4 t) / root^3].
    const double acceleration =
        -a * w * w *
        (std::cos(t) +
         a * (b * b * std::cos(2.0 * t) + a * a * std::pow(std::sin(t), 4)) / (root * root * root));
    EXPECT_NEAR(state.output_acceleration, acceleration, 1e-11);
    // The input holds the slider force: T w = -F x'.
    EXPECT_NEAR(state.input_torque, 10.0 * velocity / w, 1e-12);
  }
  double peak = 0.0;
  for (const FourBarState& state : kinematics.states)
    peak = std::max(peak, std::abs(state.input_torque));
  EXPECT_EQ(kinematics.peak_input_torque, peak);
  EXPECT_GT(peak, 10.0 * a * 0.9);  // about F a at the crank's quarter turns
}

// The input torque from virtual work against the joint forces: each link in equilibrium under
// the load (a force at the coupler point, a torque on the rocker or a force on the slider), the
// pin forces and the input torque, solved as one linear system per state.
TEST(FourBarKinematics, InputTorqueBalancesTheLoadAsTheJointForcesDo) {
  std::mt19937_64 rng(kSeed + 1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (const bool slider : {false, true}) {
    for (int trial = 0; trial < 100; ++trial) {
      const FourBarJoints joints = RandomFourBar(rng, slider);
      FourBarKinematicsOptions options;
      options.steps = 24;
      options.input_speed = unit(rng) > 0.0 ? 1.7 : -0.6;
      options.load.coupler_force = Eigen::Vector2d(5.0 * unit(rng), 5.0 * unit(rng));
      options.load.output_torque = 2.0 * unit(rng);
      options.load.slider_force = 3.0 * unit(rng);
      const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, options, 1.0);
      for (const FourBarState& state : kinematics.states) {
        if (state.transmission_angle_deg < 5.0 || state.transmission_angle_deg > 175.0) continue;
        // Unknowns: F_A (the crank's force on the coupler at A), F_B (the output's force on the
        // coupler at B), T_in. Coupler: F_A + F_B + F = 0; moments about A:
        // cross(B - A, F_B) + cross(P - A, F) = 0. Crank (about A0): T_in + cross(A - A0, -F_A)
        // = 0. Rocker (about B0): T_out + cross(B - B0, -F_B) = 0; a slider: the force along
        // the line -F_B . u + F_s = 0 (the line takes the normal force).
        const Eigen::Vector2d a = state.input_pin, b = state.output_pin, p = state.coupler_point;
        const Eigen::Vector2d r2 = a - joints.input_pivot;
        const Eigen::Vector2d& force = options.load.coupler_force;
        Eigen::Matrix<double, 5, 5> system = Eigen::Matrix<double, 5, 5>::Zero();
        Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
        system(0, 0) = system(0, 2) = 1.0;
        rhs(0) = -force.x();
        system(1, 1) = system(1, 3) = 1.0;
        rhs(1) = -force.y();
        const Eigen::Vector2d ab = b - a, ap = p - a;
        system(2, 2) = -ab.y();
        system(2, 3) = ab.x();
        rhs(2) = -(ap.x() * force.y() - ap.y() * force.x());
        system(3, 4) = 1.0;
        system(3, 0) = r2.y();
        system(3, 1) = -r2.x();
        if (slider) {
          system(4, 2) = -joints.slider_direction.x();
          system(4, 3) = -joints.slider_direction.y();
          rhs(4) = -options.load.slider_force;
        } else {
          const Eigen::Vector2d r4 = b - joints.output_pivot;
          system(4, 2) = r4.y();
          system(4, 3) = -r4.x();
          rhs(4) = -options.load.output_torque;
        }
        const Eigen::Matrix<double, 5, 1> solved = system.fullPivLu().solve(rhs);
        EXPECT_NEAR(state.input_torque, solved(4), 1e-9 * (1.0 + std::abs(solved(4))));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

// With the links' masses, the input torque at constant speed is the one the joint forces give
// when each link also carries its d'Alembert force -m a_G at its centre of mass G, its couple
// -I alpha and its weight (Newton-Euler): the same 5x5 solve as above with those loads. The same
// mechanism drawn in millimetres (length_unit_m = 0.001) needs the same torque in N mm.
TEST(FourBarKinematics, InputTorqueDrivesTheLinksMassesAsNewtonEulerDoes) {
  std::mt19937_64 rng(kSeed + 3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), mass(0.1, 2.0);
  int checked = 0;
  for (const bool slider : {false, true}) {
    for (int trial = 0; trial < 60; ++trial) {
      const FourBarJoints joints = RandomFourBar(rng, slider);
      FourBarKinematicsOptions options;
      options.steps = 24;
      options.input_speed = unit(rng) > 0.0 ? 12.0 : -7.0;
      options.load.coupler_force = Eigen::Vector2d(5.0 * unit(rng), 5.0 * unit(rng));
      options.load.output_torque = 2.0 * unit(rng);
      options.load.slider_force = 3.0 * unit(rng);
      options.masses.input = mass(rng);
      options.masses.coupler = mass(rng);
      options.masses.output = mass(rng);
      options.masses.gravity = trial % 2 == 0;
      const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, options, 1.0);
      const double g = options.masses.gravity ? 9.80665 : 0.0;
      const double w2 = options.input_speed;
      double largest_inertial = 0.0;
      for (const FourBarState& state : kinematics.states) {
        if (state.transmission_angle_deg < 5.0 || state.transmission_angle_deg > 175.0) continue;
        const Eigen::Vector2d a = state.input_pin, b = state.output_pin, p = state.coupler_point;
        const Eigen::Vector2d r2 = a - joints.input_pivot, r3 = b - a, rho = p - a;
        const double w3 = state.coupler_velocity, a3 = state.coupler_acceleration;
        // Each link's effective load at G: -m a_G + m (0, -g), and couple -I alpha.
        const auto effective = [&](double m, const Eigen::Vector2d& acceleration) {
          return Eigen::Vector2d(-m * acceleration.x(), -m * acceleration.y() - m * g);
        };
        const Eigen::Vector2d g2 = 0.5 * r2;  // from A0
        const Eigen::Vector2d load2 = effective(options.masses.input, -w2 * w2 * g2);
        const Eigen::Vector2d g3 = (r3 + rho) / 3.0;  // from A
        const Eigen::Vector2d acc3 = -w2 * w2 * r2 + a3 * Perp(g3) - w3 * w3 * g3;
        const Eigen::Vector2d load3 = effective(options.masses.coupler, acc3);
        const double inertia3 = options.masses.coupler *
                                (r3.squaredNorm() + rho.squaredNorm() + (rho - r3).squaredNorm()) /
                                36.0;
        const Eigen::Vector2d& force = options.load.coupler_force;
        Eigen::Matrix<double, 5, 5> system = Eigen::Matrix<double, 5, 5>::Zero();
        Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
        // Coupler: F_A + F_B + F + load3 = 0, moments about A.
        system(0, 0) = system(0, 2) = 1.0;
        rhs(0) = -force.x() - load3.x();
        system(1, 1) = system(1, 3) = 1.0;
        rhs(1) = -force.y() - load3.y();
        system(2, 2) = -r3.y();
        system(2, 3) = r3.x();
        rhs(2) = -(rho.x() * force.y() - rho.y() * force.x()) -
                 (g3.x() * load3.y() - g3.y() * load3.x()) + inertia3 * a3;
        // Crank about A0: T_in - cross(r2, F_A) + cross(g2, load2) = 0.
        system(3, 4) = 1.0;
        system(3, 0) = r2.y();
        system(3, 1) = -r2.x();
        rhs(3) = -(g2.x() * load2.y() - g2.y() * load2.x());
        if (slider) {
          const Eigen::Vector2d& u = joints.slider_direction;
          const Eigen::Vector2d load4 =
              effective(options.masses.output, state.output_acceleration * u);
          system(4, 2) = -u.x();
          system(4, 3) = -u.y();
          rhs(4) = -options.load.slider_force - load4.dot(u);
        } else {
          const Eigen::Vector2d r4 = b - joints.output_pivot, g4 = 0.5 * r4;
          const double w4 = state.output_velocity, a4 = state.output_acceleration;
          const Eigen::Vector2d load4 =
              effective(options.masses.output, a4 * Perp(g4) - w4 * w4 * g4);
          const double inertia4 = options.masses.output * r4.squaredNorm() / 12.0;
          system(4, 2) = r4.y();
          system(4, 3) = -r4.x();
          rhs(4) = -options.load.output_torque - (g4.x() * load4.y() - g4.y() * load4.x()) +
                   inertia4 * a4;
        }
        const Eigen::Matrix<double, 5, 1> solved = system.fullPivLu().solve(rhs);
        EXPECT_NEAR(state.input_torque, solved(4), 1e-9 * (1.0 + std::abs(solved(4))));
        EXPECT_NEAR(state.input_torque - state.inertial_torque - state.weight_torque,
                    -(force.dot(state.coupler_point_velocity) +
                      (slider ? options.load.slider_force : options.load.output_torque) *
                          state.output_velocity) /
                        w2,
                    1e-9 * (1.0 + std::abs(solved(4))));
        if (!options.masses.gravity) {
          EXPECT_EQ(state.weight_torque, 0.0);
        }
        largest_inertial = std::max(largest_inertial, std::abs(state.inertial_torque));
        ++checked;
      }
      // At these speeds the inertia is no rounding error: the check above weighs it.
      if (!kinematics.states.empty()) {
        EXPECT_GT(largest_inertial, 1.0);
      }

      // The same mechanism in millimetres: every torque times 1000 (N mm).
      FourBarJoints millimetres = joints;
      for (Eigen::Vector2d* point :
           {&millimetres.input_pivot, &millimetres.input_pin, &millimetres.output_pin,
            &millimetres.output_pivot, &millimetres.slider_point, &*millimetres.coupler_point}) {
        *point *= 1000.0;
      }
      FourBarKinematicsOptions in_mm = options;
      in_mm.masses.length_unit_m = 0.001;
      in_mm.load.output_torque *= 1000.0;
      const FourBarKinematics scaled = AnalyzeFourBarKinematics(millimetres, in_mm, 1000.0);
      ASSERT_EQ(scaled.states.size(), kinematics.states.size());
      for (size_t k = 0; k < scaled.states.size(); ++k) {
        const double expected = 1000.0 * kinematics.states[k].input_torque;
        EXPECT_NEAR(scaled.states[k].input_torque, expected, 1e-7 * (1.0 + std::abs(expected)));
      }
    }
  }
  EXPECT_GT(checked, 1500);
}

// A rocker's range ends at its dead points: the loop closes up to them and not beyond, the
// transmission angle there is 0 or 180 degrees, and the states lie between them.
TEST(FourBarKinematics, ARockersRangeEndsAtItsDeadPoints) {
  std::mt19937_64 rng(kSeed + 2);
  int rockers = 0, cranks = 0;
  for (const bool slider : {false, true}) {
    for (int trial = 0; trial < 200; ++trial) {
      const FourBarJoints joints = RandomFourBar(rng, slider);
      const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, {}, 1.0);
      if (kinematics.input_rotates_fully) {
        ++cranks;
        EXPECT_TRUE(kinematics.dead_points.empty());
        continue;
      }
      ++rockers;
      ASSERT_EQ(kinematics.dead_points.size(), 2u);
      for (const FourBarState& dead : kinematics.dead_points) {
        const double folded =
            std::min(dead.transmission_angle_deg, 180.0 - dead.transmission_angle_deg);
        EXPECT_LT(folded, 1e-3) << dead.transmission_angle_deg;
      }
      EXPECT_LT(kinematics.dead_points[0].input_angle, kinematics.states.front().input_angle);
      EXPECT_GT(kinematics.dead_points[1].input_angle, kinematics.states.back().input_angle);
      // Just beyond either end the loop does not close: a finer analysis finds the same ends.
      FourBarKinematicsOptions fine;
      fine.steps = 3600;
      const FourBarKinematics dense = AnalyzeFourBarKinematics(joints, fine, 1.0);
      EXPECT_NEAR(dense.range_start, kinematics.range_start, 1e-12);
      EXPECT_NEAR(dense.range_end, kinematics.range_end, 1e-12);
      EXPECT_EQ(dense.states.size(), 3600u);
    }
  }
  EXPECT_GT(rockers, 50);
  EXPECT_GT(cranks, 20);
}

}  // namespace
}  // namespace linkfit
