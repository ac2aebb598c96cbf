#include "lib/dyad_four_bar_kinematics.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lib/mechanism.h"
#include "lib/uniform_body.h"

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }
Eigen::Matrix2d Rotation(double theta) {
  Eigen::Matrix2d rotation;
  rotation << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  return rotation;
}
double AngleBetween(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(std::abs(a.x() * b.y() - a.y() * b.x()), a.dot(b)) * 180.0 / M_PI;
}

// A pivot of J below this share of its largest is a dead point.
constexpr double kDeadPoint = 1e-10;

// The closure rows of one configuration: J (3 x 3), the velocity right-hand side per unit input
// rate, and the second-order parts that need the rates.
class Closure {
 public:
  Closure(const PlanarDyad& input, const PlanarDyad& output, const PlanarPose& coupler,
          double input_value)
      : input_(input),
        output_(output),
        coupler_(coupler),
        value_(input_value),
        rotation_(Rotation(coupler.theta)) {}

  // J and the velocity right-hand side b (J z' = b w).
  void Rows(Eigen::Matrix3d* jacobian, Eigen::Vector3d* rhs) const {
    rhs->setZero();
    int row = 0;
    switch (input_.type) {
      case DyadType::kRR:
        // P(m) - f - r u(phi) = 0: P_z z' = r perp(u) phi'.
        jacobian->block<2, 3>(0, 0) = PointJacobian(input_.moving_pivot);
        rhs->head<2>() = input_.radius * Perp(Direction(value_));
        row = 2;
        break;
      case DyadType::kPR:
        // P(m) - q - s d = 0: P_z z' = d s'.
        jacobian->block<2, 3>(0, 0) = PointJacobian(input_.moving_pivot);
        rhs->head<2>() = input_.line_direction;
        row = 2;
        break;
      case DyadType::kRP:
        jacobian->row(0) = LineGradient(input_);
        jacobian->row(1) << 0.0, 0.0, 1.0;  // theta = the input
        (*rhs)[1] = 1.0;
        row = 2;
        break;
    }
    jacobian->row(row) = OutputGradient();
  }

  // The second-order parts (each row's d^2/dt^2 less J z''), at the rates z' and input rate w.
  Eigen::Vector3d SecondOrder(const Eigen::Vector3d& rate, double w) const {
    Eigen::Vector3d second = Eigen::Vector3d::Zero();
    const double theta_rate = rate[2];
    switch (input_.type) {
      case DyadType::kRR:
        // d^2/dt^2 of P(m) - r u(phi): P_thetatheta theta'^2 + r u(phi) w^2.
        second.head<2>() = -rotation_ * input_.moving_pivot * theta_rate * theta_rate +
                           input_.radius * Direction(value_) * w * w;
        break;
      case DyadType::kPR:
        second.head<2>() = -rotation_ * input_.moving_pivot * theta_rate * theta_rate;
        break;
      case DyadType::kRP:
        second[0] = LineSecondOrder(input_, rate);
        break;
    }
    second[2] = OutputSecondOrder(rate);
    return second;
  }

  Eigen::Vector2d At(const Eigen::Vector2d& point_in_coupler) const {
    return coupler_.origin_in_fixed + rotation_ * point_in_coupler;
  }
  const Eigen::Matrix2d& rotation() const { return rotation_; }

 private:
  static Eigen::Vector2d Direction(double angle) {
    return Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }
  // d P(p) / d z = [I, perp(R p)].
  Eigen::Matrix<double, 2, 3> PointJacobian(const Eigen::Vector2d& p) const {
    Eigen::Matrix<double, 2, 3> jacobian;
    jacobian << 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;
    jacobian.col(2) = Perp(rotation_ * p);
    return jacobian;
  }
  // An RP dyad's closure g = V . (f - P(a)), V = R n_E: its gradient in z.
  Eigen::RowVector3d LineGradient(const PlanarDyad& dyad) const {
    const Eigen::Vector2d v = rotation_ * Perp(dyad.line_direction);
    const Eigen::Vector2d gap = dyad.fixed_pivot - At(dyad.line_point);
    Eigen::RowVector3d gradient;
    gradient << -v.x(), -v.y(), Perp(v).dot(gap) - v.dot(Perp(rotation_ * dyad.line_point));
    return gradient;
  }
  // Its second-order part: V'' . (f - P) - 2 V' . P' - V . P'' less the terms in z''.
  double LineSecondOrder(const PlanarDyad& dyad, const Eigen::Vector3d& rate) const {
    const double w = rate[2];
    const Eigen::Vector2d v = rotation_ * Perp(dyad.line_direction);
    const Eigen::Vector2d gap = dyad.fixed_pivot - At(dyad.line_point);
    const Eigen::Vector2d point_rate = PointJacobian(dyad.line_point) * rate;
    return -v.dot(gap) * w * w - 2.0 * w * Perp(v).dot(point_rate) +
           v.dot(rotation_ * dyad.line_point) * w * w;
  }
  Eigen::RowVector3d OutputGradient() const {
    switch (output_.type) {
      case DyadType::kRR:
        return 2.0 * (At(output_.moving_pivot) - output_.fixed_pivot).transpose() *
               PointJacobian(output_.moving_pivot);
      case DyadType::kPR:
        return Perp(output_.line_direction).transpose() * PointJacobian(output_.moving_pivot);
      case DyadType::kRP:
        return LineGradient(output_);
    }
    return Eigen::RowVector3d::Zero();
  }
  double OutputSecondOrder(const Eigen::Vector3d& rate) const {
    const double w = rate[2];
    switch (output_.type) {
      case DyadType::kRR: {
        // 2 |P'|^2 + 2 (P - f) . P_thetatheta theta'^2.
        const Eigen::Vector2d point_rate = PointJacobian(output_.moving_pivot) * rate;
        return 2.0 * point_rate.squaredNorm() - 2.0 *
                                                    (At(output_.moving_pivot) - output_.fixed_pivot)
                                                        .dot(rotation_ * output_.moving_pivot) *
                                                    w * w;
      }
      case DyadType::kPR:
        return -Perp(output_.line_direction).dot(rotation_ * output_.moving_pivot) * w * w;
      case DyadType::kRP:
        return LineSecondOrder(output_, rate);
    }
    return 0.0;
  }

  const PlanarDyad& input_;
  const PlanarDyad& output_;
  PlanarPose coupler_;
  double value_;
  Eigen::Matrix2d rotation_;
};

double Continued(double angle, double previous) {
  return angle + 2.0 * M_PI * std::round((previous - angle) / (2.0 * M_PI));
}

// The assembly at input value `value` nearest `previous` (theta continued from it): false where
// the four-bar does not assemble there.
bool Assemble(const PlanarDyad& input, const PlanarDyad& output, double value,
              const PlanarPose& previous, double length, PlanarPose* pose) {
  std::vector<PlanarPose> poses;
  if (AssembleFourBar(input, output, value, 0.0, &poses) == 0) return false;
  double best = std::numeric_limits<double>::infinity();
  for (PlanarPose candidate : poses) {
    candidate.theta = Continued(candidate.theta, previous.theta);
    const double distance = (candidate.origin_in_fixed - previous.origin_in_fixed).norm() +
                            length * std::abs(candidate.theta - previous.theta);
    if (distance < best) {
      best = distance;
      *pose = candidate;
    }
  }
  return true;
}

}  // namespace

DyadFourBarKinematics AnalyzeDyadFourBarKinematics(
    const PlanarDyad& input, const PlanarDyad& output,
    const std::optional<Eigen::Vector2d>& coupler_point, const PlanarPose& first,
    const DyadFourBarKinematicsOptions& options, double length) {
  DyadFourBarKinematics kinematics;
  const double w = options.input_speed;
  if (!(w != 0.0) || !std::isfinite(w)) {
    kinematics.note = "the input speed is 0";
    return kinematics;
  }
  const bool angle_input = input.type != DyadType::kPR;
  const double reference = InputValue(input, first);
  // Steps small enough to stay on one assembly; a slider searched over +-10 lengths.
  const double step = angle_input ? 2.0 * M_PI / 720.0 : length / 200.0;
  const double reach = angle_input ? 2.0 * M_PI : 10.0 * length;

  // Advances from (value, pose) toward `to` in steps: false (value, pose the last reached) where
  // it stops assembling, or where the coupler runs off (a step moves it by more than a length:
  // toward a configuration at infinity, as an RP input's line turning parallel to a PR output's
  // slides the coupler without bound; *runaway set, no dead point).
  bool runaway = false;
  const auto advance = [&](double* value, PlanarPose* pose, double to) {
    while (*value != to) {
      const double next =
          std::abs(to - *value) <= step ? to : *value + std::copysign(step, to - *value);
      PlanarPose placed;
      if (!Assemble(input, output, next, *pose, length, &placed)) {
        // The end between *value and next, by bisection.
        double inside = *value, outside = next;
        for (int k = 0; k < 60; ++k) {
          const double middle = 0.5 * (inside + outside);
          PlanarPose at;
          if (Assemble(input, output, middle, *pose, length, &at)) {
            inside = middle;
            *pose = at;
          } else {
            outside = middle;
          }
        }
        *value = inside;
        return false;
      }
      if ((placed.origin_in_fixed - pose->origin_in_fixed).norm() +
              length * std::abs(placed.theta - pose->theta) >
          length) {
        runaway = true;
        return false;
      }
      *value = next;
      *pose = placed;
    }
    return true;
  };

  // The range about the first configuration.
  double high = reference, low = reference;
  PlanarPose high_pose = first, low_pose = first;
  bool ahead = advance(&high, &high_pose, reference + reach);
  const bool ahead_runs_off = runaway;
  runaway = false;
  bool behind = true;
  if (ahead && angle_input) {
    kinematics.input_rotates_fully = true;
  } else {
    behind = advance(&low, &low_pose, reference - reach);
  }
  // An end where the coupler runs off is no dead point (nothing is listed there).
  const bool dead_ahead = !ahead && !ahead_runs_off, dead_behind = !behind && !runaway;
  ahead = ahead || ahead_runs_off;
  behind = behind || runaway;
  if (kinematics.input_rotates_fully) {
    kinematics.range_start = reference;
    kinematics.range_end = reference + 2.0 * M_PI;
  } else {
    kinematics.range_start = low;
    kinematics.range_end = high;
    kinematics.range_bounded = dead_ahead && dead_behind;
  }

  const int steps = std::max(1, options.steps);
  double start = kinematics.range_start, span = kinematics.range_end - kinematics.range_start;
  if (options.range) {
    double from = options.range->first;
    if (kinematics.input_rotates_fully) {
      from = start + std::fmod(from - start, 2.0 * M_PI);
      if (from < start) from += 2.0 * M_PI;
      if (from > start + 2.0 * M_PI - 1e-9) from = start;  // (just before the start: rounding)
    }
    const double part = options.range->second - options.range->first;
    if (!(part > 0.0) || from < start - 1e-12 || from + part > start + span + 1e-12) {
      kinematics.note = "the range asked for leaves the input's range on its circuit";
      return kinematics;
    }
    start = from;
    span = part;
  }

  const auto place = [&](double value, const PlanarPose& pose, DyadFourBarState* state) {
    state->input = value;
    state->coupler = pose;
    const Closure closure(input, output, pose, value);
    if (coupler_point) state->coupler_point = closure.At(*coupler_point);
    const Eigen::Matrix2d& rotation = closure.rotation();
    // The transmission angle (see the header).
    Eigen::Vector2d force;
    if (input.type == DyadType::kRP) {
      force = rotation * Perp(input.line_direction);
    } else {
      force = closure.At(output.type == DyadType::kRP ? input.moving_pivot : output.moving_pivot) -
              closure.At(input.moving_pivot);
    }
    switch (output.type) {
      case DyadType::kRR:
        state->transmission_angle_deg =
            AngleBetween(force, closure.At(output.moving_pivot) - output.fixed_pivot);
        state->output = std::atan2((closure.At(output.moving_pivot) - output.fixed_pivot).y(),
                                   (closure.At(output.moving_pivot) - output.fixed_pivot).x());
        break;
      case DyadType::kPR:
        state->transmission_angle_deg = AngleBetween(force, Perp(output.line_direction));
        state->output =
            output.line_direction.dot(closure.At(output.moving_pivot) - output.line_point);
        break;
      case DyadType::kRP:
        // The block at B0 pushes the coupler along the line's normal V; the coupler turns about
        // the input pin A (an RR or PR input) and stalls where V points at A (J singular:
        // d . (A - B0) = 0); an RP input's line against this one (parallel: stalled).
        state->transmission_angle_deg =
            input.type == DyadType::kRP
                ? AngleBetween(rotation * Perp(output.line_direction),
                               rotation * Perp(input.line_direction))
                : AngleBetween(rotation * Perp(output.line_direction),
                               closure.At(input.moving_pivot) - output.fixed_pivot);
        state->output = output.line_direction.dot(
            rotation.transpose() * (output.fixed_pivot - pose.origin_in_fixed) - output.line_point);
        break;
    }
  };
  // The coupler's points (in E): its pins, an RP's line point, the coupler point.
  std::vector<Eigen::Vector2d> coupler_points;
  for (const PlanarDyad* dyad : {&input, &output}) {
    coupler_points.push_back(dyad->type == DyadType::kRP ? dyad->line_point : dyad->moving_pivot);
  }
  if (coupler_point) coupler_points.push_back(*coupler_point);
  std::optional<double> previous_output;
  const auto rates = [&](DyadFourBarState* state) {
    const Closure closure(input, output, state->coupler, state->input);
    Eigen::Matrix3d jacobian;
    Eigen::Vector3d rhs;
    closure.Rows(&jacobian, &rhs);
    const Eigen::PartialPivLU<Eigen::Matrix3d> lu(jacobian);
    const Eigen::Vector3d pivots = lu.matrixLU().diagonal().cwiseAbs();
    if (!(pivots.minCoeff() > kDeadPoint * std::max(pivots.maxCoeff(), 1e-300))) return false;
    state->velocity = lu.solve(rhs * w);
    state->acceleration = lu.solve(-closure.SecondOrder(state->velocity, w));
    const Eigen::Vector2d c_rate = state->velocity.head<2>(), c_acc = state->acceleration.head<2>();
    const double theta_rate = state->velocity[2], theta_acc = state->acceleration[2];
    const Eigen::Matrix2d& rotation = closure.rotation();
    if (coupler_point) {
      const Eigen::Vector2d arm = rotation * *coupler_point;
      state->coupler_point_velocity = c_rate + theta_rate * Perp(arm);
      state->coupler_point_acceleration =
          c_acc + theta_acc * Perp(arm) - theta_rate * theta_rate * arm;
    }
    switch (output.type) {
      case DyadType::kRR: {
        const Eigen::Vector2d arm = rotation * output.moving_pivot;
        const Eigen::Vector2d r4 = closure.At(output.moving_pivot) - output.fixed_pivot;
        const Eigen::Vector2d v = c_rate + theta_rate * Perp(arm);
        const Eigen::Vector2d a = c_acc + theta_acc * Perp(arm) - theta_rate * theta_rate * arm;
        // On the rocker's circle: v = w4 perp(r4), a = a4 perp(r4) - w4^2 r4.
        state->output_velocity = (r4.x() * v.y() - r4.y() * v.x()) / r4.squaredNorm();
        state->output_acceleration = (r4.x() * a.y() - r4.y() * a.x()) / r4.squaredNorm();
        break;
      }
      case DyadType::kPR: {
        const Eigen::Vector2d arm = rotation * output.moving_pivot;
        state->output_velocity = output.line_direction.dot(c_rate + theta_rate * Perp(arm));
        state->output_acceleration = output.line_direction.dot(c_acc + theta_acc * Perp(arm) -
                                                               theta_rate * theta_rate * arm);
        break;
      }
      case DyadType::kRP: {
        // The fixed pivot in E, q = R^T (f - c): q' = -theta' R^T perp(f - c) - R^T c',
        // q'' = -theta'' R^T perp(f - c) - theta'^2 R^T (f - c) + 2 theta' R^T perp(c') - R^T c''.
        const Eigen::Vector2d gap = output.fixed_pivot - state->coupler.origin_in_fixed;
        const Eigen::Matrix2d back = rotation.transpose();
        const Eigen::Vector2d q_rate = -theta_rate * back * Perp(gap) - back * c_rate;
        const Eigen::Vector2d q_acc = -theta_acc * back * Perp(gap) -
                                      theta_rate * theta_rate * back * gap +
                                      2.0 * theta_rate * back * Perp(c_rate) - back * c_acc;
        state->output_velocity = output.line_direction.dot(q_rate);
        state->output_acceleration = output.line_direction.dot(q_acc);
        break;
      }
    }
    // Power balance: E w + F . v_P + T_out w_out (or F_s s') = 0.
    const DyadFourBarLoad& load = options.load;
    const double load_power =
        load.coupler_force.dot(state->coupler_point_velocity) +
        (output.type == DyadType::kRR ? load.output_torque : load.slider_force) *
            state->output_velocity;
    state->input_effort = -load_power / w + 0.0;
    if (options.masses.Any()) {
      // E w = dT/dt - P_weight, dT/dt = sum m a_G . v_G + I alpha omega.
      const DyadFourBarMasses& masses = options.masses;
      const Eigen::Vector2d gravity(0.0, masses.gravity ? -9.80665 : 0.0);
      double energy_rate = 0.0, weight_power = 0.0;
      const auto body = [&](double m, double inertia, const Eigen::Vector2d& v,
                            const Eigen::Vector2d& a, double omega, double alpha) {
        energy_rate += m * (a.dot(v) + inertia * alpha * omega);
        weight_power += m * gravity.dot(v);
      };
      // A point of the coupler (in E): its velocity and acceleration.
      const auto moving = [&](const Eigen::Vector2d& p, Eigen::Vector2d* v, Eigen::Vector2d* a) {
        const Eigen::Vector2d arm = rotation * p;
        *v = c_rate + theta_rate * Perp(arm);
        *a = c_acc + theta_acc * Perp(arm) - theta_rate * theta_rate * arm;
      };
      for (const auto& [dyad, m] :
           {std::pair{&input, masses.input}, std::pair{&output, masses.output}}) {
        if (!(m > 0.0)) continue;
        Eigen::Vector2d v, a;
        if (dyad->type == DyadType::kRR) {
          // A bar about its pivot: its middle moves at half its pin's rates.
          moving(dyad->moving_pivot, &v, &a);
          const Eigen::Vector2d r = closure.At(dyad->moving_pivot) - dyad->fixed_pivot;
          const double omega = (r.x() * v.y() - r.y() * v.x()) / r.squaredNorm();
          const double alpha = (r.x() * a.y() - r.y() * a.x()) / r.squaredNorm();
          body(m, r.squaredNorm() / 12.0, 0.5 * v, 0.5 * a, omega, alpha);
        } else if (dyad->type == DyadType::kPR) {
          moving(dyad->moving_pivot, &v, &a);
          body(m, 0.0, v, a, 0.0, 0.0);
        }
      }
      if (masses.coupler > 0.0) {
        Eigen::Vector2d centre;
        double inertia = 0.0;
        UniformBody(coupler_points, &centre, &inertia);
        Eigen::Vector2d v, a;
        moving(centre, &v, &a);
        body(masses.coupler, inertia, v, a, theta_rate, theta_acc);
      }
      state->inertial_effort = energy_rate * masses.length_unit_m / w;
      state->weight_effort = -weight_power / w + 0.0;
      state->input_effort += state->inertial_effort + state->weight_effort;
    }
    state->mechanical_advantage.reset();
    const double still = 1e-12 * std::abs(w) * (output.type == DyadType::kRR ? 1.0 : length);
    if (std::abs(state->output_velocity) > still) {
      state->mechanical_advantage = w / state->output_velocity;
    }
    return true;
  };

  if (!kinematics.input_rotates_fully && dead_behind) {
    DyadFourBarState dead;
    place(low, low_pose, &dead);
    kinematics.dead_points.push_back(dead);
  }
  // From the first configuration to the first sample, then sample to sample.
  double value = reference;
  PlanarPose pose = first;
  for (int k = 0; k < steps; ++k) {
    const double at = options.range ? start + (steps > 1 ? span * k / (steps - 1) : 0.0)
                      : kinematics.input_rotates_fully ? start + span * k / steps
                                                       : start + span * (k + 0.5) / steps;
    if (!advance(&value, &pose, at)) {
      kinematics.note = "a dead point inside the input's range stopped the analysis";
      break;
    }
    DyadFourBarState state;
    place(value, pose, &state);
    if (output.type == DyadType::kRR && previous_output) {
      state.output = Continued(state.output, *previous_output);
    }
    previous_output = state.output;
    if (!rates(&state)) {
      kinematics.dead_points.push_back(state);
      continue;
    }
    kinematics.peak_input_effort =
        std::max(kinematics.peak_input_effort, std::abs(state.input_effort));
    kinematics.states.push_back(state);
  }
  if (!kinematics.input_rotates_fully && dead_ahead) {
    DyadFourBarState dead;
    place(high, high_pose, &dead);
    kinematics.dead_points.push_back(dead);
  }
  if (kinematics.states.empty() && kinematics.note.empty()) {
    kinematics.note = "the four-bar does not move over the input's range";
  }
  return kinematics;
}

}  // namespace linkfit
