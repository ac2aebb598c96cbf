#include "lib/four_bar_kinematics.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "lib/input_range.h"

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }
double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
Eigen::Vector2d Direction(double angle) {
  return Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

// A determinant of the velocity equations below this share of the product of its columns'
// lengths is a dead point (the transmission angle within 1e-10 rad of 0 or 180 degrees).
constexpr double kDeadPoint = 1e-10;

// The four-bar's dimensions and the assembly it is in at the reference configuration.
struct Loop {
  FourBarJoints joints;
  double crank = 0.0;    // a = |A - A0|
  double coupler = 0.0;  // b = |B - A|
  double rocker = 0.0;   // c = |B - B0| (a 4R)
  int side = 1;          // which of the loop's two closures: the side B is on
  Eigen::Vector2d coupler_point_on_coupler = Eigen::Vector2d::Zero();  // P - A at reference
  double coupler_reference_angle = 0.0;                                // of B - A at reference

  // The output pin at the crank angle `input_angle` (and a slider's position s), on `side`; with
  // `clamp`, a closure just past a dead point is taken at it. False where the loop does not
  // close.
  bool Close(double input_angle, bool clamp, Eigen::Vector2d* input_pin,
             Eigen::Vector2d* output_pin, double* slider) const {
    *input_pin = joints.input_pivot + crank * Direction(input_angle);
    if (joints.slider) {
      // B = Q + s u with |B - A| = b: s = u.w +- sqrt(b^2 - cross(u, w)^2), w = A - Q.
      const Eigen::Vector2d& u = joints.slider_direction;
      const Eigen::Vector2d w = *input_pin - joints.slider_point;
      const double off = Cross(u, w);
      double squared = coupler * coupler - off * off;
      if (squared < 0.0 && !clamp) return false;
      squared = std::max(squared, 0.0);
      *slider = u.dot(w) + side * std::sqrt(squared);
      *output_pin = joints.slider_point + *slider * u;
      return true;
    }
    // B at distance b from A and c from B0 (d = B0 - A): B = A + p d + side q perp(d),
    // p = (b^2 - c^2 + |d|^2) / (2 |d|^2), q = sqrt(D) / (2 |d|^2),
    // D = (|d|^2 - (b - c)^2) ((b + c)^2 - |d|^2).
    const Eigen::Vector2d d = joints.output_pivot - *input_pin;
    const double d2 = d.squaredNorm();
    const double b = coupler, c = rocker;
    double discriminant = (d2 - (b - c) * (b - c)) * ((b + c) * (b + c) - d2);
    if ((discriminant < 0.0 && !clamp) || !(d2 > 0.0)) return false;
    discriminant = std::max(discriminant, 0.0);
    const double p = (b * b - c * c + d2) / (2.0 * d2);
    const double q = side * std::sqrt(discriminant) / (2.0 * d2);
    *output_pin = *input_pin + p * d + q * Perp(d);
    *slider = 0.0;
    return true;
  }

  // The crank angles where the loop stops closing: a 4R where |A - B0| reaches b + c or |b - c|
  // (cos(theta - phi) = k, phi the direction of B0 - A0); a slider-crank where A's distance from
  // the line reaches b (sin(theta - psi) = k, psi the line's direction).
  std::vector<double> CriticalAngles() const {
    std::vector<double> angles;
    const double a = crank;
    if (joints.slider) {
      const Eigen::Vector2d& u = joints.slider_direction;
      const double psi = std::atan2(u.y(), u.x());
      const double h = Cross(u, joints.input_pivot - joints.slider_point);
      for (const double k : {(coupler - h) / a, (-coupler - h) / a}) {
        if (std::abs(k) > 1.0) continue;
        angles.push_back(psi + std::asin(k));
        angles.push_back(psi + M_PI - std::asin(k));
      }
      return angles;
    }
    const Eigen::Vector2d ground = joints.output_pivot - joints.input_pivot;
    const double g = ground.norm(), phi = std::atan2(ground.y(), ground.x());
    for (const double reach : {coupler + rocker, std::abs(coupler - rocker)}) {
      const double k = (g * g + a * a - reach * reach) / (2.0 * a * g);
      if (std::abs(k) > 1.0) continue;
      angles.push_back(phi + std::acos(k));
      angles.push_back(phi - std::acos(k));
    }
    return angles;
  }
};

// The angle `angle` continued from `previous` (whole turns off the change).
double Continued(double angle, double previous) {
  return previous + std::remainder(angle - previous, 2.0 * M_PI);
}

// The loop of `joints` (its dimensions and the assembly of its reference configuration), or
// none with the reason in *note.
std::optional<Loop> MakeLoop(const FourBarJoints& joints, double length, std::string* note) {
  Loop loop;
  loop.joints = joints;
  loop.crank = (joints.input_pin - joints.input_pivot).norm();
  loop.coupler = (joints.output_pin - joints.input_pin).norm();
  const double shortest = 1e-9 * length;
  if (!(loop.crank > shortest) || !(loop.coupler > shortest)) {
    *note = "the input crank or the coupler has no length";
    return std::nullopt;
  }
  if (joints.slider) {
    const Eigen::Vector2d& u = joints.slider_direction;
    const Eigen::Vector2d w = joints.input_pin - joints.slider_point;
    if (std::abs(Cross(u, joints.output_pin - joints.slider_point)) > 1e-6 * length) {
      *note = "the output pin is off its slider line";
      return std::nullopt;
    }
    const double s = u.dot(joints.output_pin - joints.slider_point);
    loop.side = s - u.dot(w) >= 0.0 ? 1 : -1;
  } else {
    loop.rocker = (joints.output_pin - joints.output_pivot).norm();
    if (!(loop.rocker > shortest)) {
      *note = "the output rocker has no length";
      return std::nullopt;
    }
    loop.side =
        Cross(joints.output_pivot - joints.input_pin, joints.output_pin - joints.input_pin) >= 0.0
            ? 1
            : -1;
  }
  const Eigen::Vector2d r3_reference = joints.output_pin - joints.input_pin;
  loop.coupler_reference_angle = std::atan2(r3_reference.y(), r3_reference.x());
  if (joints.coupler_point) {
    loop.coupler_point_on_coupler = *joints.coupler_point - joints.input_pin;
  }
  return loop;
}

// The positions at a crank angle (clamped at a dead point just past it with `clamp`), the
// coupler's angle continued from `previous_coupler` and the rocker's from `previous_output`
// (where given); false where the loop does not close.
bool PlaceOnLoop(const Loop& loop, double input_angle, bool clamp, double previous_coupler,
                 const std::optional<double>& previous_output, FourBarState* state) {
  const FourBarJoints& joints = loop.joints;
  Eigen::Vector2d a, b;
  double s = 0.0;
  if (!loop.Close(input_angle, clamp, &a, &b, &s)) return false;
  state->input_angle = input_angle;
  state->input_pin = a;
  state->output_pin = b;
  const Eigen::Vector2d r3 = b - a;
  state->coupler_angle = Continued(std::atan2(r3.y(), r3.x()), previous_coupler);
  if (joints.slider) {
    state->output = s;
    const Eigen::Vector2d normal = Perp(joints.slider_direction);
    state->transmission_angle_deg =
        std::acos(std::clamp(r3.dot(normal) / r3.norm(), -1.0, 1.0)) * 180.0 / M_PI;
  } else {
    const Eigen::Vector2d r4 = b - joints.output_pivot;
    const double angle = std::atan2(r4.y(), r4.x());
    state->output = previous_output ? Continued(angle, *previous_output) : angle;
    // The angle at B between the coupler (toward A) and the rocker (toward B0).
    state->transmission_angle_deg =
        std::acos(std::clamp((-r3).dot(-r4) / (r3.norm() * r4.norm()), -1.0, 1.0)) * 180.0 / M_PI;
  }
  if (joints.coupler_point) {
    const double turn = state->coupler_angle - loop.coupler_reference_angle;
    state->coupler_point =
        a + Eigen::Rotation2Dd(turn).toRotationMatrix() * loop.coupler_point_on_coupler;
  }
  return true;
}

// The input's range about the reference crank angle: to the nearest critical angle each way, or
// a whole turn from it.
void InputRange(const Loop& loop, double* start, double* end, bool* full) {
  const Eigen::Vector2d r2_reference = loop.joints.input_pin - loop.joints.input_pivot;
  RangeAbout(std::atan2(r2_reference.y(), r2_reference.x()), loop.CriticalAngles(), start, end,
             full);
}

// The links' inertia and weight at a state whose rates are known: each link's centre of mass G
// moves with v_G and a_G, and T_in w2 = dT/dt - P_weight with the kinetic energy's rate
// dT/dt = sum m a_G . v_G + I alpha omega (constant w2: the crank's own a_G . v_G is 0).
void AddMassTorques(const Loop& loop, const FourBarMasses& masses, double w2, FourBarState* state) {
  const FourBarJoints& joints = loop.joints;
  const double unit = masses.length_unit_m;
  const Eigen::Vector2d weight(0.0, masses.gravity ? -kStandardGravity : 0.0);  // N per kg
  double energy_rate = 0.0, weight_power = 0.0;  // kg L^2 / s^3 and N L / s
  const auto body = [&](double mass, double inertia, const Eigen::Vector2d& velocity,
                        const Eigen::Vector2d& acceleration, double omega, double alpha) {
    energy_rate += mass * acceleration.dot(velocity) + inertia * alpha * omega;
    weight_power += mass * weight.dot(velocity);
  };
  // The crank: a bar about A0 (G its middle), turning at w2.
  const Eigen::Vector2d r2 = state->input_pin - joints.input_pivot;
  body(masses.input, masses.input * loop.crank * loop.crank / 12.0, 0.5 * w2 * Perp(r2),
       -0.5 * w2 * w2 * r2, w2, 0.0);
  // The coupler: G = A + g, the centroid of A, B (and P); a uniform triangle's polar moment
  // about its centroid is m (a^2 + b^2 + c^2) / 36, a bar's m b^2 / 12.
  const Eigen::Vector2d r3 = state->output_pin - state->input_pin;
  const double w3 = state->coupler_velocity, a3 = state->coupler_acceleration;
  Eigen::Vector2d g = 0.5 * r3;
  double coupler_inertia = masses.coupler * r3.squaredNorm() / 12.0;
  if (joints.coupler_point) {
    const Eigen::Vector2d rho = state->coupler_point - state->input_pin;
    g = (r3 + rho) / 3.0;
    coupler_inertia =
        masses.coupler * (r3.squaredNorm() + rho.squaredNorm() + (rho - r3).squaredNorm()) / 36.0;
  }
  body(masses.coupler, coupler_inertia, w2 * Perp(r2) + w3 * Perp(g),
       -w2 * w2 * r2 + a3 * Perp(g) - w3 * w3 * g, w3, a3);
  if (joints.slider) {
    // The slider: a block moving with B along the line.
    const Eigen::Vector2d& u = joints.slider_direction;
    body(masses.output, 0.0, state->output_velocity * u, state->output_acceleration * u, 0.0, 0.0);
  } else {
    // The rocker: a bar about B0.
    const Eigen::Vector2d r4 = state->output_pin - joints.output_pivot;
    const double w4 = state->output_velocity, a4 = state->output_acceleration;
    body(masses.output, masses.output * loop.rocker * loop.rocker / 12.0, 0.5 * w4 * Perp(r4),
         0.5 * (a4 * Perp(r4) - w4 * w4 * r4), w4, a4);
  }
  // kg L^2 / s^3 is `unit` N L / s.
  state->inertial_torque = energy_rate * unit / w2;
  state->weight_torque = -weight_power / w2;
  state->input_torque += state->inertial_torque + state->weight_torque;
}

}  // namespace

bool PlaceFourBar(const FourBarJoints& joints, double input_angle, double length,
                  FourBarState* state) {
  std::string note;
  const std::optional<Loop> loop = MakeLoop(joints, length, &note);
  if (!loop) return false;
  // On the reference's circuit: a rocker's angle within its range about the reference.
  double start = 0.0, end = 0.0;
  bool full = false;
  InputRange(*loop, &start, &end, &full);
  const double offset = TurnAhead(input_angle, start);
  if (!full && offset > end - start) return false;
  return PlaceOnLoop(*loop, start + offset, false, loop->coupler_reference_angle, std::nullopt,
                     state);
}

FourBarKinematics AnalyzeFourBarKinematics(const FourBarJoints& joints,
                                           const FourBarKinematicsOptions& options, double length) {
  FourBarKinematics kinematics;
  const std::optional<Loop> made = MakeLoop(joints, length, &kinematics.note);
  if (!made) return kinematics;
  const Loop& loop = *made;
  const double w2 = options.input_speed;

  InputRange(loop, &kinematics.range_start, &kinematics.range_end, &kinematics.input_rotates_fully);
  const int steps = std::max(1, options.steps);
  double first = kinematics.range_start, span = kinematics.range_end - kinematics.range_start;
  if (options.range) {
    // The part asked for, on the circuit: its start within the range, its end too.
    if (!PartOfRange(*options.range, kinematics.range_start, &first, &span)) {
      kinematics.note = "the range asked for leaves the input's range on its circuit";
      return kinematics;
    }
  }

  // Positions at a crank angle (clamped at the range's ends), the angles continued.
  double previous_coupler = loop.coupler_reference_angle;
  std::optional<double> previous_output;
  const auto place = [&](double input_angle, bool clamp, FourBarState* state) {
    return PlaceOnLoop(loop, input_angle, clamp, previous_coupler, previous_output, state);
  };
  // The rates at a placed state: false at a dead point.
  const auto rates = [&](FourBarState* state) {
    const Eigen::Vector2d r2 = state->input_pin - joints.input_pivot;
    const Eigen::Vector2d r3 = state->output_pin - state->input_pin;
    Eigen::Matrix2d system;
    Eigen::Vector2d velocity_rhs, acceleration_rhs;
    if (joints.slider) {
      // s' u - w3 perp(r3) = w2 perp(r2);  s'' u - a3 perp(r3) = -w2^2 r2 - w3^2 r3.
      const Eigen::Vector2d& u = joints.slider_direction;
      system.col(0) = u;
      system.col(1) = -Perp(r3);
      velocity_rhs = w2 * Perp(r2);
    } else {
      // w3 perp(r3) - w4 perp(r4) = -w2 perp(r2);
      // a3 perp(r3) - a4 perp(r4) = w2^2 r2 + w3^2 r3 - w4^2 r4.
      const Eigen::Vector2d r4 = state->output_pin - joints.output_pivot;
      system.col(0) = Perp(r3);
      system.col(1) = -Perp(r4);
      velocity_rhs = -w2 * Perp(r2);
    }
    const double determinant = system.determinant();
    if (!(std::abs(determinant) > kDeadPoint * system.col(0).norm() * system.col(1).norm())) {
      return false;
    }
    const Eigen::Matrix2d inverse = system.inverse();
    const Eigen::Vector2d velocity = inverse * velocity_rhs;
    double w3 = 0.0;
    if (joints.slider) {
      state->output_velocity = velocity[0];
      w3 = state->coupler_velocity = velocity[1];
      acceleration_rhs = -w2 * w2 * r2 - w3 * w3 * r3;
    } else {
      w3 = state->coupler_velocity = velocity[0];
      state->output_velocity = velocity[1];
      const Eigen::Vector2d r4 = state->output_pin - joints.output_pivot;
      const double w4 = velocity[1];
      acceleration_rhs = w2 * w2 * r2 + w3 * w3 * r3 - w4 * w4 * r4;
    }
    const Eigen::Vector2d acceleration = inverse * acceleration_rhs;
    if (joints.slider) {
      state->output_acceleration = acceleration[0];
      state->coupler_acceleration = acceleration[1];
    } else {
      state->coupler_acceleration = acceleration[0];
      state->output_acceleration = acceleration[1];
    }
    if (joints.coupler_point) {
      // P = A + rho: v_P = v_A + w3 perp(rho), a_P = a_A + a3 perp(rho) - w3^2 rho.
      const Eigen::Vector2d rho = state->coupler_point - state->input_pin;
      const double a3 = state->coupler_acceleration;
      state->coupler_point_velocity = w2 * Perp(r2) + w3 * Perp(rho);
      state->coupler_point_acceleration = -w2 * w2 * r2 + a3 * Perp(rho) - w3 * w3 * rho;
    }
    // Power balance: T_in w2 + F . v_P + T_out w4 (or F_s s') = 0 for the load the input holds.
    const FourBarLoad& load = options.load;
    const double out = state->output_velocity;
    const double load_power = load.coupler_force.dot(state->coupler_point_velocity) +
                              (joints.slider ? load.slider_force : load.output_torque) * out;
    state->input_torque = -load_power / w2 + 0.0;  // (no load: 0, not -0)
    if (options.masses.Any()) AddMassTorques(loop, options.masses, w2, state);
    const double still = joints.slider ? 1e-12 * std::abs(w2) * length : 1e-12 * std::abs(w2);
    if (std::abs(out) > still) state->mechanical_advantage = w2 / out;
    return true;
  };

  if (!(w2 != 0.0) || !std::isfinite(w2)) {
    kinematics.note = "the input speed is 0";
    return kinematics;
  }
  if (!kinematics.input_rotates_fully) {
    FourBarState dead;
    if (place(kinematics.range_start, true, &dead)) kinematics.dead_points.push_back(dead);
  }
  for (int k = 0; k < steps; ++k) {
    // A crank from the reference through a whole turn; a rocker's range inside its dead points;
    // a part asked for from end to end.
    const double input_angle = SampledInput(k, steps, options.range.has_value(),
                                            kinematics.input_rotates_fully, first, span);
    FourBarState state;
    if (!place(input_angle, false, &state)) continue;
    previous_coupler = state.coupler_angle;
    previous_output = state.output;
    if (!rates(&state)) {
      kinematics.dead_points.push_back(state);  // a change point on a turning crank
      continue;
    }
    kinematics.peak_input_torque =
        std::max(kinematics.peak_input_torque, std::abs(state.input_torque));
    kinematics.states.push_back(state);
  }
  if (!kinematics.input_rotates_fully) {
    FourBarState dead;
    if (place(kinematics.range_end, true, &dead)) kinematics.dead_points.push_back(dead);
  }
  if (kinematics.states.empty() && kinematics.note.empty()) {
    kinematics.note = "the loop does not close over the input's range";
  }
  return kinematics;
}

}  // namespace linkfit
