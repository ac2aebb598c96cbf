#include "optimizers/four_bar_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"
#include "optimizers/design_bounds.h"
#include "optimizers/planar_dyad_blocks.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Ceres's projected-gradient stop, in the scaled problem (L = 1, mean weight 1): low enough
// that only function_tolerance and parameter_tolerance decide, except at an exact optimum.
constexpr double kGradientTolerance = 1e-16;
// Penalty stage (scaled problem, mean pose weight 1): the dyads' weight, the stopping
// tolerances (relative cost change and step) of this start-finding solve, and a cap on
// Levenberg-Marquardt's trust region (a floor under its damping).
constexpr double kPenaltyWeight = 1e2;
constexpr double kPenaltyTolerance = 1e-8;
constexpr double kPenaltyMaxTrustRegion = 1e8;
// Exact poses: their weight (times the pose's own) in the exact elimination, whose method of
// multipliers then shifts their targets round by round until they are met.
constexpr double kExactWeight = 1e6;
// Then at most this many Gauss-Newton steps onto the exact poses (ProjectOntoExactPoses).
constexpr int kProjectionSteps = 5;
// Two dyads closer than this (times L, in every parameter) are one constraint, not a four-bar:
// the coupler keeps a second freedom, which fits anything and which AssembleFourBar cannot
// resolve. Least squares on noisy poses can run toward that limit.
constexpr double kCoincidentDyads = 1e-3;
// An RR radius beyond this (times L) is reported: the fit runs toward a slider.
constexpr double kSliderRadius = 1e3;
// A linear assembly (RP input with a PR or RP output) whose two lines are closer to parallel
// than this (sine of their angle) has no configuration; AssembleFourBar's threshold.
constexpr double kParallelLines = 1e-12;

// Penalty stage, task pose j = (D, Theta) with weight w and its free configuration
// q = (d, theta), dyad penalty weight mu, scaled frames (L = 1):
//   e[0..2] = sqrt(w) (d - D, wrap(theta - Theta))                      the pose error
//   e[3..4] = sqrt(mu) (input dyad holds at q with the joint value of the task pose):
//     RR (F, m, r): R(theta) m + d - F - r (M - F) / |M - F|,  M = R(Theta) m + D
//     PR (m, n, h): R(theta) m + d - M + (n . M - h) n         (the foot of M on the line)
//     RP (F, n, h): (n . R(theta)^T (F - d) - h, wrap(theta - Theta))
//   e[5]    = sqrt(mu) (output dyad at q, PlanarDyad::Residual):
//     RR: |R(theta) m + d - F| - r;  PR: n . (R(theta) m + d) - h;  RP: n . R(theta)^T (F - d) - h
// With e[3..5] = 0, q is the four-bar's configuration at the task pose's input value
// (InputValue, lib/mechanism.h), and e[0..2] the pose error AnalyzeFourBar measures. Unlike
// that configuration in closed form, the residual is smooth through the stationary
// configurations (where the input value alone does not fix q) and where the input cannot reach
// the task's value. At R m + d = F the RR distance is not differentiable; its subgradient 0 is
// used there.
class ConfigurationResidual {
 public:
  ConfigurationResidual(DyadType input_type, DyadType output_type, const PlanarPose& pose,
                        double sqrt_weight, double sqrt_penalty)
      : input_type_(input_type),
        output_type_(output_type),
        x_(pose.origin_in_fixed.x()),
        y_(pose.origin_in_fixed.y()),
        theta_(pose.theta),
        cos_(std::cos(pose.theta)),
        sin_(std::sin(pose.theta)),
        sqrt_weight_(sqrt_weight),
        sqrt_penalty_(sqrt_penalty) {}

  template <typename T>
  bool operator()(const T* configuration, const T* input_point, const T* input_second,
                  const T* input_scalar, const T* output_point, const T* output_second,
                  const T* output_scalar, T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    const T c = cos(configuration[2]), s = sin(configuration[2]);
    const T turn = configuration[2] - theta_;
    const T wrapped_turn = atan2(sin(turn), cos(turn));
    residual[0] = sqrt_weight_ * (configuration[0] - x_);
    residual[1] = sqrt_weight_ * (configuration[1] - y_);
    residual[2] = sqrt_weight_ * wrapped_turn;
    return InputJoint(configuration, c, s, wrapped_turn, input_point, input_second, input_scalar,
                      residual + 3) &&
           OutputDyad(configuration, c, s, output_point, output_second, output_scalar,
                      residual + 5);
  }

  static ceres::CostFunction* Create(DyadType input_type, DyadType output_type,
                                     const PlanarPose& pose, double sqrt_weight,
                                     double sqrt_penalty) {
    return new ceres::AutoDiffCostFunction<ConfigurationResidual, 6, 3, 2, 2, 1, 2, 2, 1>(
        new ConfigurationResidual(input_type, output_type, pose, sqrt_weight, sqrt_penalty));
  }

 private:
  template <typename T>
  bool InputJoint(const T* configuration, const T& c, const T& s, const T& wrapped_turn,
                  const T* point, const T* second, const T* scalar, T* residual) const {
    using std::sqrt;
    if (input_type_ == DyadType::kRP) {
      T nx, ny;
      if (!UnitNormal(second, &nx, &ny)) return false;
      const T ux = point[0] - configuration[0], uy = point[1] - configuration[1];
      residual[0] = sqrt_penalty_ * (nx * (c * ux + s * uy) + ny * (c * uy - s * ux) - scalar[0]);
      residual[1] = sqrt_penalty_ * wrapped_turn;
      return true;
    }
    const T* pin = input_type_ == DyadType::kRR ? second : point;  // m, in E
    // The pin at q, and where the task pose has it.
    const T px = c * pin[0] - s * pin[1] + configuration[0];
    const T py = s * pin[0] + c * pin[1] + configuration[1];
    const T mx = cos_ * pin[0] - sin_ * pin[1] + x_;
    const T my = sin_ * pin[0] + cos_ * pin[1] + y_;
    if (input_type_ == DyadType::kRR) {
      const T ax = mx - point[0], ay = my - point[1];
      const T arm_squared = ax * ax + ay * ay;
      if (!(arm_squared > T(0.0))) return false;
      const T scale = scalar[0] / sqrt(arm_squared);
      residual[0] = sqrt_penalty_ * (px - point[0] - scale * ax);
      residual[1] = sqrt_penalty_ * (py - point[1] - scale * ay);
    } else {
      T nx, ny;
      if (!UnitNormal(second, &nx, &ny)) return false;
      const T height = nx * mx + ny * my - scalar[0];
      residual[0] = sqrt_penalty_ * (px - mx + height * nx);
      residual[1] = sqrt_penalty_ * (py - my + height * ny);
    }
    return true;
  }

  template <typename T>
  bool OutputDyad(const T* configuration, const T& c, const T& s, const T* point, const T* second,
                  const T* scalar, T* residual) const {
    using std::sqrt;
    if (output_type_ == DyadType::kRR) {
      const T ox = c * second[0] - s * second[1] + configuration[0] - point[0];
      const T oy = s * second[0] + c * second[1] + configuration[1] - point[1];
      const T squared = ox * ox + oy * oy;
      const T distance = squared > T(0.0) ? T(sqrt(squared)) : T(0.0);
      residual[0] = sqrt_penalty_ * (distance - scalar[0]);
      return true;
    }
    T nx, ny;
    if (!UnitNormal(second, &nx, &ny)) return false;
    if (output_type_ == DyadType::kPR) {
      const T px = c * point[0] - s * point[1] + configuration[0];
      const T py = s * point[0] + c * point[1] + configuration[1];
      residual[0] = sqrt_penalty_ * (nx * px + ny * py - scalar[0]);
    } else {
      const T ux = point[0] - configuration[0], uy = point[1] - configuration[1];
      residual[0] = sqrt_penalty_ * (nx * (c * ux + s * uy) + ny * (c * uy - s * ux) - scalar[0]);
    }
    return true;
  }

  DyadType input_type_;
  DyadType output_type_;
  double x_, y_, theta_, cos_, sin_;  // the task pose
  double sqrt_weight_;
  double sqrt_penalty_;
};

// Where an RR or PR input puts its pin at the input value of coupler pose (D, Theta) (cos and
// sin of Theta given): M = R(Theta) m1 + D, the pin of the pose, goes to
// P = F + r (M - F) / |M - F| (RR) or to its foot on the slider line, M - (n . M - h) n (PR).
template <typename T>
bool InputPinAt(DyadType input_type, double x, double y, double cos_theta, double sin_theta,
                const T* input_point, const T* input_second, const T* input_scalar, T* px, T* py) {
  using std::sqrt;
  const T* m1 = input_type == DyadType::kRR ? input_second : input_point;
  const T mx = cos_theta * m1[0] - sin_theta * m1[1] + x;
  const T my = sin_theta * m1[0] + cos_theta * m1[1] + y;
  if (input_type == DyadType::kRR) {
    const T ax = mx - input_point[0], ay = my - input_point[1];
    const T arm_squared = ax * ax + ay * ay;
    if (!(arm_squared > T(0.0))) return false;
    const T scale = input_scalar[0] / sqrt(arm_squared);
    *px = input_point[0] + scale * ax;
    *py = input_point[1] + scale * ay;
  } else {
    T nx, ny;
    if (!UnitNormal(input_second, &nx, &ny)) return false;
    const T height = nx * mx + ny * my - input_scalar[0];
    *px = mx - height * nx;
    *py = my - height * ny;
  }
  return true;
}

// The configuration (d, theta) of the coupler of an RR or PR input whose pin m1 (E) is at P
// (Sigma) and which the output dyad holds, on assembly sign `sign`: the output dyad reads
// a cos(theta) + b sin(theta) = c (the coefficients of AssembleFourBar), solved as
// (cos(theta), sin(theta)) ~ c (a, b) + sign sqrt(a^2 + b^2 - c^2) (-b, a), d = P - R(theta) m1.
// False past the input's reach (negative discriminant) or at a degenerate output.
template <typename T>
bool AssembleAtPin(DyadType output_type, double sign, const T* m1, const T& px, const T& py,
                   const T* output_point, const T* output_second, const T* output_scalar, T* x,
                   T* y, T* cos_theta, T* sin_theta) {
  using std::sqrt;
  T a, b, c;
  if (output_type == DyadType::kRR) {
    // |R v + w| = r2, v = m2 - m1 (E), w = P - F2 (Sigma): 2 w . R v = r2^2 - |v|^2 - |w|^2.
    const T vx = output_second[0] - m1[0], vy = output_second[1] - m1[1];
    const T wx = px - output_point[0], wy = py - output_point[1];
    a = T(2.0) * (wx * vx + wy * vy);
    b = T(2.0) * (wy * vx - wx * vy);
    c = output_scalar[0] * output_scalar[0] - (vx * vx + vy * vy) - (wx * wx + wy * wy);
  } else if (output_type == DyadType::kPR) {
    // n . (R v + P) = h, v = m2 - m1 (E).
    T nx, ny;
    if (!UnitNormal(output_second, &nx, &ny)) return false;
    const T vx = output_point[0] - m1[0], vy = output_point[1] - m1[1];
    a = nx * vx + ny * vy;
    b = ny * vx - nx * vy;
    c = output_scalar[0] - (nx * px + ny * py);
  } else {
    // F2 on the line of E: (R n) . (F2 - P) = h - n . m1.
    T nx, ny;
    if (!UnitNormal(output_second, &nx, &ny)) return false;
    const T ux = output_point[0] - px, uy = output_point[1] - py;
    a = nx * ux + ny * uy;
    b = nx * uy - ny * ux;
    c = output_scalar[0] - (nx * m1[0] + ny * m1[1]);
  }
  const T rho_squared = a * a + b * b;
  if (!(rho_squared > T(0.0))) return false;
  const T spread_squared = rho_squared - c * c;
  if (spread_squared < T(0.0)) return false;  // past the input's reach
  const T spread = spread_squared > T(0.0) ? T(sign * sqrt(spread_squared)) : T(0.0);
  const T ux = c * a - spread * b, uy = c * b + spread * a;
  const T u_squared = ux * ux + uy * uy;
  if (!(u_squared > T(0.0))) return false;
  const T u_norm = sqrt(u_squared);
  *cos_theta = ux / u_norm;
  *sin_theta = uy / u_norm;
  *x = px - (*cos_theta * m1[0] - *sin_theta * m1[1]);
  *y = py - (*sin_theta * m1[0] + *cos_theta * m1[1]);
  return true;
}

// Pose error of the four-bar at task pose j = (D, Theta) with weight w, the configuration q
// eliminated: the four-bar assembled at the input value the task pose gives (InputValue,
// lib/mechanism.h) on assembly label s (+1 for label 0, -1 for label 1), scaled frames (L = 1):
//   e = sqrt(w) ((x(q) - D_x, y(q) - D_y, wrap(theta(q) - Theta)) + s_j)
// (s_j = 0 but for exact poses: the shift of the method of multipliers), where q = (d, theta)
// satisfies both dyads:
//   input RR or PR: the input pin goes to P = F + r (M - F) / |M - F| (RR) or to the foot of M
//     on the slider line, M - (n . M - h) n (PR), M = R(Theta) m1 + D the pin of the task pose;
//     E turns about P, d = P - R(theta) m1, and the output dyad reads
//     a cos(theta) + b sin(theta) = c (the coefficients of AssembleFourBar), solved as
//       (cos(theta), sin(theta)) ~ c (a, b) + s sqrt(a^2 + b^2 - c^2) (-b, a);
//   input RP: theta = Theta, d = d0 + t e on the input's line (normal N = R n1, offset
//     N . F1 - h1, direction e = perp(N)), t = -g . e + s sqrt((g . e)^2 - |g|^2 + r2^2) with
//     g = R m2 + d0 - F2 for an RR output; linear in t for a PR or RP output.
// Past the input's reach (negative discriminant) there is no such q: the residual fails, and
// the solver does not step there (a start with a pose past reach is left as it is; the penalty
// stage, above, moves such poses within reach when it can).
class AssembledPoseResidual {
 public:
  AssembledPoseResidual(DyadType input_type, DyadType output_type, int label,
                        const PlanarPose& pose, double sqrt_weight,
                        const Eigen::Vector3d& shift = Eigen::Vector3d::Zero())
      : input_type_(input_type),
        output_type_(output_type),
        sign_(label == 1 ? -1.0 : 1.0),
        x_(pose.origin_in_fixed.x()),
        y_(pose.origin_in_fixed.y()),
        cos_(std::cos(pose.theta)),
        sin_(std::sin(pose.theta)),
        sqrt_weight_(sqrt_weight),
        shift_(shift) {}

  template <typename T>
  bool operator()(const T* input_point, const T* input_second, const T* input_scalar,
                  const T* output_point, const T* output_second, const T* output_scalar,
                  T* residual) const {
    T x, y, cos_theta, sin_theta;
    const bool assembled =
        input_type_ == DyadType::kRP
            ? AssembleSliderInput(input_point, input_second, input_scalar, output_point,
                                  output_second, output_scalar, &x, &y, &cos_theta, &sin_theta)
            : AssemblePinInput(input_point, input_second, input_scalar, output_point, output_second,
                               output_scalar, &x, &y, &cos_theta, &sin_theta);
    if (!assembled) return false;
    using std::atan2;
    residual[0] = sqrt_weight_ * (x - x_ + shift_[0]);
    residual[1] = sqrt_weight_ * (y - y_ + shift_[1]);
    residual[2] = sqrt_weight_ *
                  (atan2(sin_theta * cos_ - cos_theta * sin_, cos_theta * cos_ + sin_theta * sin_) +
                   shift_[2]);
    return true;
  }

  static ceres::CostFunction* Create(DyadType input_type, DyadType output_type, int label,
                                     const PlanarPose& pose, double sqrt_weight,
                                     const Eigen::Vector3d& shift) {
    return new ceres::AutoDiffCostFunction<AssembledPoseResidual, 3, 2, 2, 1, 2, 2, 1>(
        new AssembledPoseResidual(input_type, output_type, label, pose, sqrt_weight, shift));
  }

 private:
  // Input RR or PR: the input pin is placed, the coupler turns about it.
  template <typename T>
  bool AssemblePinInput(const T* input_point, const T* input_second, const T* input_scalar,
                        const T* output_point, const T* output_second, const T* output_scalar, T* x,
                        T* y, T* cos_theta, T* sin_theta) const {
    const T* m1 = input_type_ == DyadType::kRR ? input_second : input_point;
    T px, py;  // the input pin at the task's input value
    if (!InputPinAt(input_type_, x_, y_, cos_, sin_, input_point, input_second, input_scalar, &px,
                    &py)) {
      return false;
    }
    return AssembleAtPin(output_type_, sign_, m1, px, py, output_point, output_second,
                         output_scalar, x, y, cos_theta, sin_theta);
  }

  // Input RP: the coupler angle is the task's; the origin slides on the input's line.
  template <typename T>
  bool AssembleSliderInput(const T* input_point, const T* input_second, const T* input_scalar,
                           const T* output_point, const T* output_second, const T* output_scalar,
                           T* x, T* y, T* cos_theta, T* sin_theta) const {
    using std::sqrt;
    T n1x, n1y;
    if (!UnitNormal(input_second, &n1x, &n1y)) return false;
    const T normal_x = cos_ * n1x - sin_ * n1y, normal_y = sin_ * n1x + cos_ * n1y;
    const T offset = normal_x * input_point[0] + normal_y * input_point[1] - input_scalar[0];
    const T d0x = offset * normal_x, d0y = offset * normal_y;
    const T ex = -normal_y, ey = normal_x;
    T t;
    if (output_type_ == DyadType::kRR) {
      // |R m2 + d0 + t e - F2| = r2.
      const T gx = cos_ * output_second[0] - sin_ * output_second[1] + d0x - output_point[0];
      const T gy = sin_ * output_second[0] + cos_ * output_second[1] + d0y - output_point[1];
      const T half_b = ex * gx + ey * gy;
      const T discriminant =
          half_b * half_b - (gx * gx + gy * gy - output_scalar[0] * output_scalar[0]);
      if (discriminant < T(0.0)) return false;  // past the input's reach
      t = -half_b + (discriminant > T(0.0) ? T(sign_ * sqrt(discriminant)) : T(0.0));
    } else {
      // N2 . d = k. PR (normal n2 in Sigma): N2 = n2, k = h2 - n2 . R m2; RP (normal n2 in E):
      // N2 = R n2, k = N2 . F2 - h2.
      T n2x, n2y;
      if (!UnitNormal(output_second, &n2x, &n2y)) return false;
      T big_x, big_y, k;
      if (output_type_ == DyadType::kPR) {
        big_x = n2x;
        big_y = n2y;
        k = output_scalar[0] - (n2x * (cos_ * output_point[0] - sin_ * output_point[1]) +
                                n2y * (sin_ * output_point[0] + cos_ * output_point[1]));
      } else {
        big_x = cos_ * n2x - sin_ * n2y;
        big_y = sin_ * n2x + cos_ * n2y;
        k = big_x * output_point[0] + big_y * output_point[1] - output_scalar[0];
      }
      const T denominator = big_x * ex + big_y * ey;
      if (!(denominator > T(kParallelLines) || denominator < T(-kParallelLines))) return false;
      t = (k - (big_x * d0x + big_y * d0y)) / denominator;
    }
    *x = d0x + t * ex;
    *y = d0y + t * ey;
    *cos_theta = T(cos_);
    *sin_theta = T(sin_);
    return true;
  }

  DyadType input_type_;
  DyadType output_type_;
  double sign_;
  double x_, y_, cos_, sin_;  // the task pose
  double sqrt_weight_;
  Eigen::Vector3d shift_;  // multiplier shift of an exact pose (zero otherwise)
};

// The design bounds of the four-bar (design_bounds.h): sqrt(mu) max(0, g) for every g of
// MotionBoundGeometry, mu read through `sqrt_weight` (raised round by round).
class MotionBoundsResidual {
 public:
  MotionBoundsResidual(DyadType input_type, DyadType output_type, const ScaledBounds* bounds,
                       const double* sqrt_weight)
      : input_type_(input_type),
        output_type_(output_type),
        bounds_(bounds),
        sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* input_point, const T* input_second, const T* input_scalar,
                  const T* output_point, const T* output_second, const T* output_scalar,
                  T* residual) const {
    const BoundGeometry<T> geometry =
        MotionBoundGeometry(input_type_, input_point, input_second, input_scalar, true,
                            output_type_, output_point, output_second, output_scalar);
    BoundPenalties(*bounds_, geometry, *sqrt_weight_, residual);
    return true;
  }

  static ceres::CostFunction* Create(DyadType input_type, DyadType output_type,
                                     const ScaledBounds* bounds, const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<MotionBoundsResidual, kBoundResiduals, 2, 2, 1, 2, 2, 1>(
        new MotionBoundsResidual(input_type, output_type, bounds, sqrt_weight));
  }

 private:
  DyadType input_type_, output_type_;
  const ScaledBounds* bounds_;
  const double* sqrt_weight_;
};

// The transmission angle (TransmissionAngleDeg, lib/four_bar_motion.h) of the four-bar
// assembled (AssembleAtPin, assembly sign s of task pose j's label) with its input pin at
// P(t) between where task poses j and j + 1 put it (InputPinAt): an RR input's crank angle
// interpolated the short way, t in [0, 1); a PR input's pin along its line. With the coupler
// at (d, theta): input pin A = P, output pin B = R(theta) m2 + d, coupler line B - A, the output
// pin's direction of motion u = perp(B - F2) (RR output) or along its line (PR output);
// sin(mu) = |(B - A) . u| / (|B - A| |u|) and e = sqrt(mu_w) max(0, sin(mu_min) - sin(mu)),
// mu_w read through `sqrt_weight` (raised round by round with the design bounds' weight).
// Zero where the four-bar does not assemble there (the pose error's business). Not for an RP
// dyad (no transmission angle defined).
class TransmissionResidual {
 public:
  TransmissionResidual(DyadType input_type, DyadType output_type, int label, const PlanarPose& pose,
                       const PlanarPose& next, double t, double sin_min, const double* sqrt_weight)
      : input_type_(input_type),
        output_type_(output_type),
        sign_(label == 1 ? -1.0 : 1.0),
        pose_(pose),
        next_(next),
        t_(t),
        sin_min_(sin_min),
        sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* input_point, const T* input_second, const T* input_scalar,
                  const T* output_point, const T* output_second, const T* output_scalar,
                  T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    residual[0] = T(0.0);
    T px, py;
    if (!Pin(pose_, input_point, input_second, input_scalar, &px, &py)) return true;
    if (t_ > 0.0) {
      T qx, qy;
      if (!Pin(next_, input_point, input_second, input_scalar, &qx, &qy)) return true;
      if (input_type_ == DyadType::kRR) {
        const T ax = px - input_point[0], ay = py - input_point[1];
        const T bx = qx - input_point[0], by = qy - input_point[1];
        const T turn = atan2(ax * by - ay * bx, ax * bx + ay * by);  // short way
        const T c = cos(T(t_) * turn), s = sin(T(t_) * turn);
        px = input_point[0] + c * ax - s * ay;
        py = input_point[1] + s * ax + c * ay;
      } else {
        px = (1.0 - t_) * px + t_ * qx;
        py = (1.0 - t_) * py + t_ * qy;
      }
    }
    const T* m1 = input_type_ == DyadType::kRR ? input_second : input_point;
    T x, y, cos_theta, sin_theta;
    if (!AssembleAtPin(output_type_, sign_, m1, px, py, output_point, output_second, output_scalar,
                       &x, &y, &cos_theta, &sin_theta)) {
      return true;
    }
    const T* m2 = output_type_ == DyadType::kRR ? output_second : output_point;
    const T bx = cos_theta * m2[0] - sin_theta * m2[1] + x;
    const T by = sin_theta * m2[0] + cos_theta * m2[1] + y;
    residual[0] = *sqrt_weight_ * TransmissionShortfallAt(output_type_, px, py, bx, by,
                                                          output_point, output_second, sin_min_);
    return true;
  }

 private:
  template <typename T>
  bool Pin(const PlanarPose& pose, const T* input_point, const T* input_second,
           const T* input_scalar, T* px, T* py) const {
    return InputPinAt(input_type_, pose.origin_in_fixed.x(), pose.origin_in_fixed.y(),
                      std::cos(pose.theta), std::sin(pose.theta), input_point, input_second,
                      input_scalar, px, py);
  }

  DyadType input_type_, output_type_;
  double sign_;
  PlanarPose pose_, next_;  // task poses j and j + 1
  double t_;
  double sin_min_;
  const double* sqrt_weight_;
};

// The task in the scaled frames: Sigma' = (Sigma - centroid) / L, E' = E / L.
struct ScaledTask {
  std::vector<PlanarPose> poses;
  std::vector<double> weights;  // divided by their mean
  std::vector<bool> exact;
  ScaledBounds bounds;  // the design bounds (design_bounds.h)
  // Whether the transmission angle is held (TransmissionResidual), and the sine of its least.
  bool transmission = false;
  double transmission_sin_min = 0.0;
};

// Calls `add(residual)` for each TransmissionResidual of `task` (none when it holds none): at
// each task pose and kTransmissionSamples - 1 input values between it and the next, assembled
// on the pose's label.
template <typename Add>
void ForEachTransmission(const ScaledTask& task, const std::vector<int>& labels, DyadType input,
                         DyadType output, const double* sqrt_weight, const Add& add) {
  if (!task.transmission) return;
  const size_t n = task.poses.size();
  for (size_t j = 0; j < n; ++j) {
    const int samples = j + 1 < n ? kTransmissionSamples : 1;
    for (int k = 0; k < samples; ++k) {
      add(TransmissionResidual(
          input, output, labels[j], task.poses[j], task.poses[std::min(j + 1, n - 1)],
          static_cast<double>(k) / kTransmissionSamples, task.transmission_sin_min, sqrt_weight));
    }
  }
}

// Adds the transmission angle's penalties of `task`.
void AddTransmission(const ScaledTask& task, const std::vector<int>& labels,
                     const double* sqrt_weight, DyadBlocks* input, DyadBlocks* output,
                     ceres::Problem* problem) {
  ForEachTransmission(
      task, labels, input->type, output->type, sqrt_weight,
      [&](const TransmissionResidual& residual) {
        problem->AddResidualBlock(
            new ceres::AutoDiffCostFunction<TransmissionResidual, 1, 2, 2, 1, 2, 2, 1>(
                new TransmissionResidual(residual)),
            nullptr, input->point, input->second, input->scalar, output->point, output->second,
            output->scalar);
      });
}

// The largest shortfall of the transmission angle's sine at the task's samples.
double TransmissionShortfall(const ScaledTask& task, const std::vector<int>& labels,
                             const DyadBlocks& input, const DyadBlocks& output) {
  const double unit = 1.0;
  double worst = 0.0;
  ForEachTransmission(task, labels, input.type, output.type, &unit,
                      [&](const TransmissionResidual& residual) {
                        double value = 0.0;
                        if (residual(input.point, input.second, input.scalar, output.point,
                                     output.second, output.scalar, &value)) {
                          worst = std::max(worst, value);
                        }
                      });
  return worst;
}

// The largest violation of the design bounds by the dyads' blocks (scaled units).
double Violation(const ScaledBounds& bounds, const DyadBlocks& input, const DyadBlocks& output) {
  return BoundViolation(
      bounds, MotionBoundGeometry(input.type, input.point, input.second, input.scalar, true,
                                  output.type, output.point, output.second, output.scalar));
}

// Whether the two dyads are (nearly) the same constraint: same type, pivots and radius or line.
bool Coincident(const PlanarDyad& a, const PlanarDyad& b, double length) {
  if (a.type != b.type) return false;
  const double tolerance = kCoincidentDyads * length;
  const auto same_line = [&]() {
    const Eigen::Vector2d normal = Perp(a.line_direction.normalized());
    return std::abs(normal.dot(b.line_direction.normalized())) < kCoincidentDyads &&
           std::abs(normal.dot(b.line_point - a.line_point)) < tolerance;
  };
  switch (a.type) {
    case DyadType::kRR:
      return (a.fixed_pivot - b.fixed_pivot).norm() < tolerance &&
             (a.moving_pivot - b.moving_pivot).norm() < tolerance &&
             std::abs(a.radius - b.radius) < tolerance;
    case DyadType::kPR:
      return (a.moving_pivot - b.moving_pivot).norm() < tolerance && same_line();
    case DyadType::kRP:
      return (a.fixed_pivot - b.fixed_pivot).norm() < tolerance && same_line();
  }
  return false;
}

// A four-bar judged as AnalyzeFourBar judges it (lib/four_bar_motion.cc), in task units: the
// circuit of the first pose, each pose's error on that circuit and the configuration of the
// circuit that error is measured to.
struct Judgement {
  bool coincident = false;                 // the dyads coincide: no four-bar (see above)
  bool assembles = false;                  // a four-bar that assembles at the first pose
  bool circuit_defect = false;             // some pose is not on the first pose's circuit
  std::vector<double> errors;              // pose errors on that circuit
  std::vector<PlanarPose> configurations;  // the configurations measured to
  // The configuration nearest each pose on any circuit: at its input value, or (where the
  // four-bar does not reach that value) along the traced motion.
  std::vector<PlanarPose> nearest;
  double cost = kInfinity;  // 1/2 sum w e^2 (w as given)
  double rms = kInfinity;   // sqrt(sum w e^2 / sum w)
  double max = kInfinity;   // max e
  double exact_max = 0.0;   // max e over the exact poses
  double violation = 0.0;   // of the design bounds, times L
  // The transmission angle over the motion (AnalyzeFourBar) below a held minimum
  // (FourBarRefinerOptions::min_transmission_deg).
  bool transmission_short = false;
};

Judgement Judge(const PlanarDyad& input, const PlanarDyad& output,
                const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
                const std::vector<bool>& exact, double length,
                const FourBarRefinerOptions& options) {
  Judgement judgement;
  if (!input.AllFinite() || !output.AllFinite()) return judgement;
  judgement.violation =
      Violation(ScaleBounds(options.constraints, length, Similarity2(), Similarity2()),
                ToBlocks(input), ToBlocks(output)) /
      length;
  judgement.coincident = Coincident(input, output, length);
  if (judgement.coincident) return judgement;
  if (options.min_transmission_deg) {
    const std::optional<double> least =
        AnalyzeFourBar(input, output, poses, length).transmission_min_deg;
    judgement.transmission_short = least && *least < *options.min_transmission_deg;
  }
  const FourBarMotion motion = TraceFourBar(input, output, poses, length);
  std::vector<FourBarLocation> locations;
  for (const PlanarPose& pose : poses) {
    locations.push_back(LocatePose(motion, input, output, pose, length));
  }
  if (locations[0].circuit < 0) return judgement;
  judgement.assembles = true;
  const int circuit_index = locations[0].circuit;
  const FourBarCircuit& circuit = motion.circuits[circuit_index];
  const double tolerance = 1e-9 * length;  // LocatePose's assembly tolerance
  std::vector<PlanarPose> assembled;
  double weighted = 0.0, weight_sum = 0.0;
  judgement.max = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const FourBarLocation& location = locations[j];
    double value = 0.0;  // location.input again
    const int count = AssembleFourBarAtPose(input, output, poses[j], tolerance, &assembled, &value);
    double error = kInfinity;
    PlanarPose configuration = circuit.samples.front().coupler;
    if (location.circuit == circuit_index) {
      // The configuration LocatePose measured to: the nearest at the pose's input value.
      for (const PlanarPose& candidate : assembled) {
        const double candidate_error = PoseError(candidate, poses[j], length);
        if (candidate_error < error) {
          error = candidate_error;
          configuration = candidate;
        }
      }
      error = location.pose_error;
    } else {
      // As AnalyzeFourBar: the configuration of the circuit's label at the same input value,
      // or the nearest configuration of the circuit.
      judgement.circuit_defect = true;
      if (circuit.label >= 0 && circuit.label < count) {
        error = PoseError(assembled[circuit.label], poses[j], length);
        configuration = assembled[circuit.label];
      }
      for (const FourBarSample& sample : circuit.samples) {
        const double sample_error = PoseError(sample.coupler, poses[j], length);
        if (sample_error < error) {
          error = sample_error;
          configuration = sample.coupler;
        }
      }
    }
    PlanarPose nearest = configuration;
    double nearest_error = kInfinity;
    for (const PlanarPose& candidate : assembled) {
      const double candidate_error = PoseError(candidate, poses[j], length);
      if (candidate_error < nearest_error) {
        nearest_error = candidate_error;
        nearest = candidate;
      }
    }
    if (count == 0) {
      for (const FourBarCircuit& any_circuit : motion.circuits) {
        for (const FourBarSample& sample : any_circuit.samples) {
          const double sample_error = PoseError(sample.coupler, poses[j], length);
          if (sample_error < nearest_error) {
            nearest_error = sample_error;
            nearest = sample.coupler;
          }
        }
      }
    }
    judgement.nearest.push_back(nearest);
    const double weight = weights.empty() ? 1.0 : weights[j];
    judgement.errors.push_back(error);
    judgement.configurations.push_back(configuration);
    weighted += weight * error * error;
    weight_sum += weight;
    judgement.max = std::max(judgement.max, error);
    if (!exact.empty() && exact[j]) judgement.exact_max = std::max(judgement.exact_max, error);
  }
  judgement.cost = 0.5 * weighted;
  judgement.rms = std::sqrt(weighted / weight_sum);
  if (!std::isfinite(judgement.cost)) {
    judgement.cost = judgement.rms = judgement.max = kInfinity;
  }
  return judgement;
}

// A start: both dyads and one configuration per task pose (the free unknowns of the penalty
// stage; for the exact elimination they only pick each pose's assembly label).
struct Unknowns {
  DyadBlocks input;
  DyadBlocks output;
  std::vector<Eigen::Vector3d> configurations;  // (x, y, theta) of E
};

// Stops a solve where its iterates reach coincident dyads (Coincident): the cost can keep
// falling toward that limit (the coupler's second freedom fits anything), which is no
// four-bar. Keeps the last iterate before it.
class CoincidenceGuard : public ceres::IterationCallback {
 public:
  CoincidenceGuard(DyadBlocks* input, DyadBlocks* output)
      : input_(input), output_(output), last_input_(*input), last_output_(*output) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (!summary.step_is_successful) return ceres::SOLVER_CONTINUE;
    if (Coincident(FromBlocks(*input_), FromBlocks(*output_), 1.0)) {
      stopped_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    last_input_ = *input_;
    last_output_ = *output_;
    return ceres::SOLVER_CONTINUE;
  }

  // After the solve: back to the last iterate before coincidence, if it was reached.
  bool Restore() {
    if (stopped_) {
      *input_ = last_input_;
      *output_ = last_output_;
    }
    return stopped_;
  }

 private:
  DyadBlocks* input_;
  DyadBlocks* output_;
  DyadBlocks last_input_;
  DyadBlocks last_output_;
  bool stopped_ = false;
};

// Penalty stage, one round: pose errors at free configurations, dyads (with the input-value
// condition) weighted by `penalty`. The configurations are eliminated first (Schur).
void SolvePenalty(const ScaledTask& task, double penalty, const double* bounds_weight,
                  const ceres::Solver::Options& base_options, Unknowns* unknowns, int* iterations,
                  std::string* message) {
  ceres::Problem problem;
  DyadBlocks& input = unknowns->input;
  DyadBlocks& output = unknowns->output;
  const double sqrt_penalty = std::sqrt(penalty);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t j = 0; j < task.poses.size(); ++j) {
    double* configuration = unknowns->configurations[j].data();
    problem.AddResidualBlock(
        ConfigurationResidual::Create(input.type, output.type, task.poses[j],
                                      std::sqrt(task.weights[j]), sqrt_penalty),
        nullptr, configuration, input.point, input.second, input.scalar, output.point,
        output.second, output.scalar);
    ordering->AddElementToGroup(configuration, 0);
  }
  problem.AddResidualBlock(
      MotionBoundsResidual::Create(input.type, output.type, &task.bounds, bounds_weight), nullptr,
      input.point, input.second, input.scalar, output.point, output.second, output.scalar);
  for (DyadBlocks* blocks : {&input, &output}) {
    for (double* block : {blocks->point, blocks->second, blocks->scalar}) {
      ordering->AddElementToGroup(block, 1);
    }
    if (blocks->type != DyadType::kRR) problem.SetManifold(blocks->second, UnitCircle());
  }
  CoincidenceGuard guard(&input, &output);
  ceres::Solver::Options solver_options = base_options;
  solver_options.update_state_every_iteration = true;  // the guard reads the iterates
  solver_options.callbacks.push_back(&guard);
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  // A floor under Levenberg-Marquardt's damping: the penalty problem can be nearly singular
  // (a drift toward coincident dyads), where an undamped Schur complement loses definiteness.
  solver_options.max_trust_region_radius = kPenaltyMaxTrustRegion;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  *iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
  *message = summary.message;
  guard.Restore();  // the configurations stay those of the last iterate: a start only
}

// Exact elimination: pose errors of the assembled four-bar, pose weights `weights`, shifts
// `shifts`. Returns whether it stopped short of coincident dyads; `converged` says whether the
// solve ended on a tolerance (or at that stop), not on its iteration limit.
bool SolveAssembled(const ScaledTask& task, const std::vector<int>& labels,
                    const std::vector<double>& weights, const std::vector<Eigen::Vector3d>& shifts,
                    const double* bounds_weight, const ceres::Solver::Options& base_options,
                    DyadBlocks* input, DyadBlocks* output, int* iterations, std::string* message,
                    bool* converged) {
  ceres::Problem problem;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    problem.AddResidualBlock(
        AssembledPoseResidual::Create(input->type, output->type, labels[j], task.poses[j],
                                      std::sqrt(weights[j]), shifts[j]),
        nullptr, input->point, input->second, input->scalar, output->point, output->second,
        output->scalar);
  }
  problem.AddResidualBlock(
      MotionBoundsResidual::Create(input->type, output->type, &task.bounds, bounds_weight), nullptr,
      input->point, input->second, input->scalar, output->point, output->second, output->scalar);
  AddTransmission(task, labels, bounds_weight, input, output, &problem);
  for (DyadBlocks* blocks : {input, output}) {
    if (blocks->type != DyadType::kRR) problem.SetManifold(blocks->second, UnitCircle());
  }
  CoincidenceGuard guard(input, output);
  ceres::Solver::Options solver_options = base_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.update_state_every_iteration = true;  // the guard reads the iterates
  solver_options.callbacks.push_back(&guard);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  *iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
  *message = summary.message;
  *converged = summary.termination_type != ceres::NO_CONVERGENCE;
  return guard.Restore();
}

// The assembly label of each pose for the exact elimination: the one whose configuration at the
// pose's input value is nearest the penalty stage's configuration (label 0 where none
// assembles).
std::vector<int> LabelsNear(const ScaledTask& task, const Unknowns& unknowns) {
  const PlanarDyad input = FromBlocks(unknowns.input);
  const PlanarDyad output = FromBlocks(unknowns.output);
  std::vector<int> labels(task.poses.size(), 0);
  std::vector<PlanarPose> assembled;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    const Eigen::Vector3d& q = unknowns.configurations[j];
    const PlanarPose configuration(q.x(), q.y(), q.z());
    double value = 0.0;
    const int count = AssembleFourBarAtPose(input, output, task.poses[j], 1e-9, &assembled, &value);
    if (count == 2 &&
        PoseError(assembled[1], configuration, 1.0) < PoseError(assembled[0], configuration, 1.0)) {
      labels[j] = 1;
    }
  }
  return labels;
}

// The pose errors (x, y, angle) of the exact elimination, scaled units; false where the
// four-bar does not assemble at some pose.
bool AssembledErrors(const ScaledTask& task, const std::vector<int>& labels,
                     const DyadBlocks& input, const DyadBlocks& output,
                     std::vector<Eigen::Vector3d>* errors) {
  errors->assign(task.poses.size(), Eigen::Vector3d::Zero());
  for (size_t j = 0; j < task.poses.size(); ++j) {
    const AssembledPoseResidual residual(input.type, output.type, labels[j], task.poses[j], 1.0);
    if (!residual(input.point, input.second, input.scalar, output.point, output.second,
                  output.scalar, (*errors)[j].data()) ||
        !(*errors)[j].allFinite()) {
      return false;
    }
  }
  return true;
}

// Largest error norm over the exact poses.
double WorstExact(const ScaledTask& task, const std::vector<Eigen::Vector3d>& errors) {
  double worst = 0.0;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    if (task.exact[j]) worst = std::max(worst, errors[j].norm());
  }
  return worst;
}

// Gauss-Newton steps of least norm onto the exact poses' conditions e_j = 0 (exact elimination,
// scaled units), from a least-squares solution that nearly meets them: the multipliers leave
// them off by rounding of the weighted problem, and the steps finish the job while moving the
// design least. Normals step along their tangent and are renormalized. Stops after
// kProjectionSteps, or where a step does not assemble.
void ProjectOntoExactPoses(const ScaledTask& task, const std::vector<int>& labels, double tolerance,
                           DyadBlocks* input, DyadBlocks* output) {
  std::vector<size_t> exact_poses;
  for (size_t j = 0; j < task.poses.size(); ++j) {
    if (task.exact[j]) exact_poses.push_back(j);
  }
  if (exact_poses.empty()) return;
  const int rows = 3 * static_cast<int>(exact_poses.size());
  for (int step = 0; step < kProjectionSteps; ++step) {
    // Columns: input point (2), input second (2 or 1 tangent), input scalar, same for output.
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(rows, 12);
    Eigen::VectorXd error(rows);
    for (size_t k = 0; k < exact_poses.size(); ++k) {
      const size_t j = exact_poses[k];
      std::unique_ptr<ceres::CostFunction> cost(AssembledPoseResidual::Create(
          input->type, output->type, labels[j], task.poses[j], 1.0, Eigen::Vector3d::Zero()));
      const double* parameters[6] = {input->point,  input->second,  input->scalar,
                                     output->point, output->second, output->scalar};
      Eigen::Matrix<double, 3, 2, Eigen::RowMajor> block[4];
      Eigen::Vector3d scalar_block[2];
      double* jacobians[6] = {block[0].data(), block[1].data(), scalar_block[0].data(),
                              block[2].data(), block[3].data(), scalar_block[1].data()};
      if (!cost->Evaluate(parameters, error.data() + 3 * k, jacobians)) return;
      jacobian.block(3 * k, 0, 3, 2) = block[0];
      jacobian.block(3 * k, 2, 3, 2) = block[1];
      jacobian.block(3 * k, 4, 3, 1) = scalar_block[0];
      jacobian.block(3 * k, 6, 3, 2) = block[2];
      jacobian.block(3 * k, 8, 3, 2) = block[3];
      jacobian.block(3 * k, 10, 3, 1) = scalar_block[1];
    }
    if (!error.allFinite() || !jacobian.allFinite()) return;
    double worst = 0.0;
    for (size_t k = 0; k < exact_poses.size(); ++k) {
      worst = std::max(worst, error.segment<3>(3 * k).norm());
    }
    if (worst <= tolerance) return;
    // A normal moves along its tangent only: its two columns become one.
    for (int offset : {0, 6}) {
      const DyadBlocks& blocks = offset == 0 ? *input : *output;
      if (blocks.type == DyadType::kRR) continue;
      const Eigen::Vector2d tangent(-blocks.second[1], blocks.second[0]);
      jacobian.col(offset + 2) = jacobian.block(0, offset + 2, rows, 2) * tangent;
      jacobian.col(offset + 3).setZero();
    }
    const Eigen::VectorXd delta = -jacobian.completeOrthogonalDecomposition().solve(error);
    if (!delta.allFinite()) return;
    DyadBlocks next_input = *input, next_output = *output;
    for (int offset : {0, 6}) {
      DyadBlocks& blocks = offset == 0 ? next_input : next_output;
      blocks.point[0] += delta[offset];
      blocks.point[1] += delta[offset + 1];
      blocks.scalar[0] += delta[offset + 4];
      if (blocks.type == DyadType::kRR) {
        blocks.second[0] += delta[offset + 2];
        blocks.second[1] += delta[offset + 3];
      } else {
        Eigen::Map<Eigen::Vector2d> normal(blocks.second);
        normal =
            (normal + delta[offset + 2] * Eigen::Vector2d(-normal.y(), normal.x())).normalized();
      }
    }
    std::vector<Eigen::Vector3d> errors;
    if (!AssembledErrors(task, labels, next_input, next_output, &errors)) return;
    *input = next_input;
    *output = next_output;
  }
}

bool AllFinite(const Unknowns& unknowns) {
  for (const DyadBlocks* blocks : {&unknowns.input, &unknowns.output}) {
    if (!std::isfinite(blocks->point[0]) || !std::isfinite(blocks->point[1]) ||
        !std::isfinite(blocks->second[0]) || !std::isfinite(blocks->second[1]) ||
        !std::isfinite(blocks->scalar[0])) {
      return false;
    }
  }
  for (const Eigen::Vector3d& q : unknowns.configurations) {
    if (!q.allFinite()) return false;
  }
  return true;
}

// A refined design and how it was found.
struct Candidate {
  PlanarDyad input;
  PlanarDyad output;
  Judgement judgement;    // does not assemble unless refined
  bool converged = true;  // its last solve ended on a tolerance, not on max_iterations
  std::string origin;     // which start it came from
  std::string message;    // Ceres's, of its last solve
  int exact_rounds = 0;
  int bound_rounds = 0;               // rounds of a raised penalty onto the design bounds
  bool short_of_coincidence = false;  // stopped where the dyads were about to coincide
};

// Whether design `a` is better than design `b` as a solution of the task: it assembles at the
// first pose, then has no circuit defect, then meets the exact poses (or comes nearer), then
// keeps the design bounds (within kConstraintSlack) and a held transmission angle, then has the
// lower cost.
bool Better(const Judgement& a, const Judgement& b, double exact_limit) {
  if (a.assembles != b.assembles) return a.assembles;
  if (!a.assembles) return false;
  if (a.circuit_defect != b.circuit_defect) return !a.circuit_defect;
  const double a_exact = a.exact_max > exact_limit ? a.exact_max : 0.0;
  const double b_exact = b.exact_max > exact_limit ? b.exact_max : 0.0;
  if (a_exact != b_exact) return a_exact < b_exact;
  const bool a_keeps = a.violation <= kConstraintSlack && !a.transmission_short;
  const bool b_keeps = b.violation <= kConstraintSlack && !b.transmission_short;
  if (a_keeps != b_keeps) return a_keeps;
  return a.cost < b.cost;
}

std::string Format(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", value);
  return buffer;
}

std::string Describe(const Judgement& judgement, double exact_limit) {
  if (judgement.coincident) return "coincident dyads";
  if (!judgement.assembles) return "no assembly at the first pose";
  std::string text = judgement.circuit_defect ? "circuit defect, " : "";
  if (judgement.exact_max > exact_limit) {
    text += "exact poses missed by " + Format(judgement.exact_max) + ", ";
  }
  return text + "cost " + Format(judgement.cost);
}

}  // namespace

RefinerSummary RefineFourBar(const std::vector<PlanarPose>& poses,
                             const std::vector<double>& weights, const std::vector<bool>& exact,
                             double length, PlanarDyad* input, PlanarDyad* output,
                             const FourBarRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double weight_mean =
      CheckRefinerInput("RefineFourBar", poses.size(), length, weights, &exact);
  for (const PlanarPose& pose : poses) {
    if (!pose.origin_in_fixed.allFinite() || !std::isfinite(pose.theta)) {
      throw std::invalid_argument("RefineFourBar: poses must be finite");
    }
  }

  RefinerSummary summary;
  const auto give_up = [&](const std::string& message) {
    summary.initial_cost = summary.final_cost = kInfinity;
    summary.initial_rms = summary.final_rms = kInfinity;
    summary.initial_max = summary.final_max = kInfinity;
    summary.message = message;
    summary.seconds = elapsed();
    return summary;
  };
  if (poses.empty()) {
    summary.message = "no poses: seed returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }
  if (!input->AllFinite() || !output->AllFinite()) {
    return give_up("seed not finite: returned unchanged");
  }
  const Judgement initial = Judge(*input, *output, poses, weights, exact, length, options);
  if (!initial.assembles) {
    return give_up(initial.coincident
                       ? "seed dyads coincide (no four-bar): returned unchanged"
                       : "seed does not assemble at the first pose: returned unchanged");
  }

  // Sigma' = (Sigma - centroid) / L and E' = E / L; `sigma` and `epsilon` map them back.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  centroid /= static_cast<double>(poses.size());
  Similarity2 sigma;
  sigma.scale = length;
  sigma.translation = centroid;
  Similarity2 epsilon;
  epsilon.scale = length;
  const Similarity2 to_sigma = sigma.Inverse(), to_epsilon = epsilon.Inverse();
  ScaledTask task;
  Unknowns seed;
  for (size_t j = 0; j < poses.size(); ++j) {
    task.poses.push_back(TransformPose(poses[j], to_sigma, to_epsilon));
    task.weights.push_back(weights.empty() ? 1.0 : weights[j] / weight_mean);
    task.exact.push_back(!exact.empty() && exact[j]);
    // The seed's configuration on the first pose's circuit, its angle taken next to the pose's.
    const PlanarPose configuration = TransformPose(initial.configurations[j], to_sigma, to_epsilon);
    seed.configurations.emplace_back(
        configuration.origin_in_fixed.x(), configuration.origin_in_fixed.y(),
        poses[j].theta + WrapAngle(configuration.theta - poses[j].theta));
  }
  task.bounds = ScaleBounds(options.constraints, length, to_sigma, to_epsilon);
  if (options.min_transmission_deg && input->type != DyadType::kRP &&
      output->type != DyadType::kRP) {
    task.transmission = true;
    task.transmission_sin_min = HeldTransmissionSine(*options.min_transmission_deg);
  }
  seed.input = ToBlocks(TransformDyad(*input, to_sigma, to_epsilon));
  seed.output = ToBlocks(TransformDyad(*output, to_sigma, to_epsilon));

  ceres::Solver::Options solver_options =
      RefinerSolverOptions(options.max_iterations, options.function_tolerance,
                           options.parameter_tolerance, kGradientTolerance);

  // The exact elimination from a start (the seed itself, or where the penalty stage took it),
  // with its assembly labels read off the start's configurations; exact poses met by
  // multipliers and projection; judged in task units.
  const double exact_limit = options.exact_tolerance * length;
  std::string note;
  const auto refine_from = [&](const Unknowns& start, const char* origin) {
    Candidate candidate;
    candidate.origin = origin;
    task.bounds.inset = 0.0;  // each start held to the bounds themselves at first
    if (!AllFinite(start)) return candidate;
    const std::vector<int> labels = LabelsNear(task, start);
    DyadBlocks input_blocks = start.input, output_blocks = start.output;
    // Exact poses: weight kExactWeight times theirs, and the method of multipliers' shifts.
    std::vector<double> pose_weights = task.weights;
    std::vector<Eigen::Vector3d> shifts(task.poses.size(), Eigen::Vector3d::Zero());
    for (size_t j = 0; j < task.poses.size(); ++j) {
      if (task.exact[j]) pose_weights[j] *= kExactWeight;
    }
    // A start with a pose past the input's reach cannot be refined this way: it is judged as
    // it is. The design bounds: their penalty raised until the design keeps them
    // (design_bounds.h).
    double bounds_weight = std::sqrt(kBoundFirstWeight);
    std::vector<Eigen::Vector3d> errors;
    const bool reachable = AssembledErrors(task, labels, input_blocks, output_blocks, &errors);
    if (reachable) {
      candidate.short_of_coincidence = SolveAssembled(
          task, labels, pose_weights, shifts, &bounds_weight, solver_options, &input_blocks,
          &output_blocks, &summary.iterations, &candidate.message, &candidate.converged);
      const auto kept = [&]() {
        return Violation(task.bounds, input_blocks, output_blocks) <= kBoundSlack &&
               TransmissionShortfall(task, labels, input_blocks, output_blocks) <=
                   kTransmissionSlack;
      };
      for (int bound_round = 0; bound_round < kBoundRounds && !kept(); ++bound_round) {
        NextBoundRound(Violation(task.bounds, input_blocks, output_blocks), &task.bounds,
                       &bounds_weight);
        candidate.short_of_coincidence |= SolveAssembled(
            task, labels, pose_weights, shifts, &bounds_weight, solver_options, &input_blocks,
            &output_blocks, &summary.iterations, &candidate.message, &candidate.converged);
        candidate.bound_rounds = bound_round + 1;
      }
    } else {
      candidate.message = "start past the input's reach";
    }
    int round = 0;
    while (reachable && round < options.max_penalty_rounds &&
           AssembledErrors(task, labels, input_blocks, output_blocks, &errors) &&
           WorstExact(task, errors) > options.exact_tolerance) {
      for (size_t j = 0; j < task.poses.size(); ++j) {
        if (task.exact[j]) shifts[j] += errors[j];
      }
      candidate.short_of_coincidence |= SolveAssembled(
          task, labels, pose_weights, shifts, &bounds_weight, solver_options, &input_blocks,
          &output_blocks, &summary.iterations, &candidate.message, &candidate.converged);
      ++round;
    }
    if (reachable) {
      ProjectOntoExactPoses(task, labels, 1e-3 * options.exact_tolerance, &input_blocks,
                            &output_blocks);
    }
    candidate.exact_rounds = round;
    candidate.input = TransformDyad(FromBlocks(input_blocks), sigma, epsilon);
    candidate.output = TransformDyad(FromBlocks(output_blocks), sigma, epsilon);
    candidate.judgement =
        Judge(candidate.input, candidate.output, poses, weights, exact, length, options);
    return candidate;
  };
  Candidate best = refine_from(seed, "exact elimination from the seed");
  // Penalty stage: free configurations started on the seed's nearest each pose (on any
  // circuit), the dyads weighted by kPenaltyWeight; it crosses where the exact elimination
  // cannot (stationary configurations, gaps in the input's range that split the task over two
  // circuits), but may also drift toward two coincident dyads, so it only proposes a start.
  Unknowns relaxed = seed;
  for (size_t j = 0; j < poses.size(); ++j) {
    const PlanarPose configuration = TransformPose(initial.nearest[j], to_sigma, to_epsilon);
    relaxed.configurations[j] =
        Eigen::Vector3d(configuration.origin_in_fixed.x(), configuration.origin_in_fixed.y(),
                        poses[j].theta + WrapAngle(configuration.theta - poses[j].theta));
  }
  ceres::Solver::Options penalty_options = solver_options;
  penalty_options.function_tolerance = kPenaltyTolerance;
  penalty_options.parameter_tolerance = kPenaltyTolerance;
  std::string penalty_message;
  const double first_bounds_weight = std::sqrt(kBoundFirstWeight);
  task.bounds.inset = 0.0;
  SolvePenalty(task, kPenaltyWeight, &first_bounds_weight, penalty_options, &relaxed,
               &summary.iterations, &penalty_message);
  Candidate relaxed_candidate = refine_from(relaxed, "exact elimination after a penalty stage");
  if (Better(relaxed_candidate.judgement, best.judgement, exact_limit)) {
    best = std::move(relaxed_candidate);
  }

  // The refined design is kept only if it is not worse than the seed: no new circuit defect,
  // exact poses met (or nearer), then the cost.
  summary.message = best.message;
  note = best.origin;
  if (best.exact_rounds > 0) {
    note += "; exact poses: " + std::to_string(best.exact_rounds) + " multiplier rounds";
  }
  if (best.bound_rounds > 0) {
    note += "; " + std::to_string(best.bound_rounds) + " rounds onto the design bounds";
  }
  if (best.short_of_coincidence) {
    note += "; stopped short of coincident dyads, toward which the cost keeps falling";
  }
  const bool accept = best.judgement.assembles && !Better(initial, best.judgement, exact_limit);
  const Judgement& final = accept ? best.judgement : initial;
  if (accept) {
    *input = best.input;
    *output = best.output;
    summary.converged = best.converged;
  } else {
    note += "; seed kept: the refined design is worse (" + Describe(best.judgement, exact_limit) +
            " vs " + Describe(initial, exact_limit) + ")";
  }
  for (const PlanarDyad* dyad : {input, output}) {
    if (dyad->type == DyadType::kRR && std::abs(dyad->radius) > kSliderRadius * length) {
      note += std::string("; ") + (dyad == input ? "input" : "output") + " RR radius " +
              Format(std::abs(dyad->radius) / length) + " L: the fit runs toward a slider";
    }
  }
  if (final.exact_max > exact_limit) {
    note += "; exact poses not met: pose error " + Format(final.exact_max / length) + " L";
  }
  summary.message += " [" + note + "]";

  summary.initial_cost = initial.cost;
  summary.final_cost = final.cost;
  summary.initial_rms = initial.rms;
  summary.final_rms = final.rms;
  summary.initial_max = initial.max;
  summary.final_max = final.max;
  summary.seconds = elapsed();
  return summary;
}

}  // namespace linkfit
