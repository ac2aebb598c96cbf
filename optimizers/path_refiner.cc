#include "optimizers/path_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/design_bounds.h"
#include "optimizers/planar_dyad_blocks.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Ceres's projected-gradient stop, in the scaled problem (L = 1, mean weight 1): low enough
// that only function_tolerance and parameter_tolerance decide, except at an exact optimum.
constexpr double kGradientTolerance = 1e-16;
// Exact points: their weight (times the point's own), then the method of multipliers.
constexpr double kExactWeight = 1e3;
// The projection onto the exact points: relative step to stop.
constexpr double kProjectionTolerance = 1e-20;
// Free timing: the windowed solves of one Solve (see there), at most.
constexpr int kWindowRounds = 8;
// A crank or RR output radius beyond this (times L) is reported: on noisy points the cost can
// keep falling toward a slider, which a crank-driven RR four-bar only approaches.
constexpr double kRunawayRadius = 1e3;

// The coupler's turn theta about the crank pin that closes the output dyad, from
// p cos(theta) + q sin(theta) = k:
//   (cos(theta), sin(theta)) = (k (p, q) + sign sqrt(p^2 + q^2 - k^2) (-q, p)) / (p^2 + q^2),
// sign +1 the assembly AssembleFourBar lists first (label 0). Fails past the crank's reach.
template <typename T>
bool SolveTurn(const T& p, const T& q, const T& k, double sign, T* cos_theta, T* sin_theta) {
  using std::sqrt;
  const T rho_squared = p * p + q * q;
  if (!(rho_squared > T(0.0))) return false;
  const T gap = rho_squared - k * k;
  if (gap < T(0.0)) return false;
  const T root = gap > T(0.0) ? T(sign * sqrt(gap)) : T(0.0);
  *cos_theta = (k * p - root * q) / rho_squared;
  *sin_theta = (k * q + root * p) / rho_squared;
  return true;
}

// Residual of timed point j (scaled frames, L = 1), crank pivot B (Sigma), crank pin A (E; at
// the first point's crank angle also its Sigma position), output blocks, coupler point c (E):
//   P_j = B + R(t_j) (A - B)                   the crank pin, t_j = psi_j - psi_0
//   theta_j closes the output with E turning about P_j (x maps to P_j + R(theta_j) (x - A)):
//     RR (F, m, r): |R v + w| = r,  v = m - A, w = P_j - F:
//                   (w . v) cos + (w . perp v) sin = (r^2 - |v|^2 - |w|^2) / 2
//     PR (m, n, h): n . (R v + P_j) = h:  (n . v) cos + (n . perp v) sin = h - n . P_j
//     RP (F, n, h): n . R^T (F - P_j) + n . A = h, u = F - P_j:
//                   (n . u) cos + (perp n . u) sin = h - n . A
//   e = sqrt(w_j) (P_j + R(theta_j) (c - A) - R_j + s_j)
// (s_j = 0 but for exact points: the shift of the method of multipliers). Prescribed timing:
// t_j is data; free timing: t_j is point j's own parameter block, after the first six.
class PathPointResidual {
 public:
  PathPointResidual(DyadType output_type, double sign, const Eigen::Vector2d& target,
                    double sqrt_weight, double turn, const Eigen::Vector2d& shift)
      : output_type_(output_type),
        sign_(sign),
        target_(target),
        sqrt_weight_(sqrt_weight),
        turn_(turn),
        shift_(shift) {}

  // Prescribed timing (and the first point).
  template <typename T>
  bool operator()(const T* crank_pivot, const T* crank_pin, const T* output_point,
                  const T* output_second, const T* output_scalar, const T* coupler_point,
                  T* residual) const {
    return Evaluate(crank_pivot, crank_pin, output_point, output_second, output_scalar,
                    coupler_point, T(turn_), residual);
  }

  // Free timing: the six blocks above, then the turn t_j, a parameter of its own.
  template <typename T>
  bool operator()(const T* crank_pivot, const T* crank_pin, const T* output_point,
                  const T* output_second, const T* output_scalar, const T* coupler_point,
                  const T* turn, T* residual) const {
    return Evaluate(crank_pivot, crank_pin, output_point, output_second, output_scalar,
                    coupler_point, turn[0], residual);
  }

  // The coupler point's position at turn t, and the coupler's (cos, sin) of theta.
  template <typename T>
  bool Evaluate(const T* crank_pivot, const T* crank_pin, const T* output_point,
                const T* output_second, const T* output_scalar, const T* coupler_point,
                const T& turn, T* residual) const {
    T cos_theta, sin_theta, pin[2];
    if (!Assemble(crank_pivot, crank_pin, output_point, output_second, output_scalar, turn, pin,
                  &cos_theta, &sin_theta)) {
      return false;
    }
    const T dx = coupler_point[0] - crank_pin[0], dy = coupler_point[1] - crank_pin[1];
    residual[0] =
        sqrt_weight_ * (pin[0] + cos_theta * dx - sin_theta * dy - target_.x() + shift_.x());
    residual[1] =
        sqrt_weight_ * (pin[1] + sin_theta * dx + cos_theta * dy - target_.y() + shift_.y());
    return true;
  }

  // The crank pin P (Sigma) at turn t and the coupler's turn about it (see above).
  template <typename T>
  bool Assemble(const T* crank_pivot, const T* crank_pin, const T* output_point,
                const T* output_second, const T* output_scalar, const T& turn, T* pin, T* cos_theta,
                T* sin_theta) const {
    using std::cos;
    using std::sin;
    const T c = cos(turn), s = sin(turn);
    const T arm_x = crank_pin[0] - crank_pivot[0], arm_y = crank_pin[1] - crank_pivot[1];
    pin[0] = crank_pivot[0] + c * arm_x - s * arm_y;
    pin[1] = crank_pivot[1] + s * arm_x + c * arm_y;
    T p, q, k;
    if (output_type_ == DyadType::kRR) {
      const T vx = output_second[0] - crank_pin[0], vy = output_second[1] - crank_pin[1];
      const T wx = pin[0] - output_point[0], wy = pin[1] - output_point[1];
      p = wx * vx + wy * vy;
      q = wy * vx - wx * vy;
      k = T(0.5) * (output_scalar[0] * output_scalar[0] - vx * vx - vy * vy - wx * wx - wy * wy);
      return SolveTurn(p, q, k, sign_, cos_theta, sin_theta);
    }
    T nx, ny;
    if (!UnitNormal(output_second, &nx, &ny)) return false;
    if (output_type_ == DyadType::kPR) {
      const T vx = output_point[0] - crank_pin[0], vy = output_point[1] - crank_pin[1];
      p = nx * vx + ny * vy;
      q = ny * vx - nx * vy;
      k = output_scalar[0] - nx * pin[0] - ny * pin[1];
    } else {
      const T ux = output_point[0] - pin[0], uy = output_point[1] - pin[1];
      p = nx * ux + ny * uy;
      q = nx * uy - ny * ux;
      k = output_scalar[0] - nx * crank_pin[0] - ny * crank_pin[1];
    }
    return SolveTurn(p, q, k, sign_, cos_theta, sin_theta);
  }

  // The function of the first overload (prescribed turn), or with `free_turn` of the second
  // (the turn a parameter block of size 1).
  static ceres::CostFunction* Create(DyadType output_type, double sign,
                                     const Eigen::Vector2d& target, double sqrt_weight, double turn,
                                     const Eigen::Vector2d& shift, bool free_turn);

 private:
  DyadType output_type_;
  double sign_;  // +1: assembly label 0, -1: label 1
  Eigen::Vector2d target_;
  double sqrt_weight_;
  double turn_;  // prescribed psi_j - psi_0
  Eigen::Vector2d shift_;
};

ceres::CostFunction* PathPointResidual::Create(DyadType output_type, double sign,
                                               const Eigen::Vector2d& target, double sqrt_weight,
                                               double turn, const Eigen::Vector2d& shift,
                                               bool free_turn) {
  auto* functor = new PathPointResidual(output_type, sign, target, sqrt_weight, turn, shift);
  if (!free_turn) {
    return new ceres::AutoDiffCostFunction<PathPointResidual, 2, 2, 2, 2, 2, 1, 2>(functor);
  }
  return new ceres::AutoDiffCostFunction<PathPointResidual, 2, 2, 2, 2, 2, 1, 2, 1>(functor);
}

// The coupler's turn at the first point, which the first-point convention makes 0 (the
// parameters leave it free: E turned about the crank pin A at the first point changes no
// point), so that the solver has no null direction:
//   e = atan2(sin(theta_0), cos(theta_0)),  theta_0 the turn of PathPointResidual at t = 0.
class GaugeResidual {
 public:
  GaugeResidual(DyadType output_type, double sign)
      : assembly_(output_type, sign, Eigen::Vector2d::Zero(), 1.0, 0.0, Eigen::Vector2d::Zero()) {}

  template <typename T>
  bool operator()(const T* crank_pivot, const T* crank_pin, const T* output_point,
                  const T* output_second, const T* output_scalar, T* residual) const {
    using std::atan2;
    T pin[2], cos_theta, sin_theta;
    if (!assembly_.Assemble(crank_pivot, crank_pin, output_point, output_second, output_scalar,
                            T(0.0), pin, &cos_theta, &sin_theta)) {
      return false;
    }
    residual[0] = atan2(sin_theta, cos_theta);
    return true;
  }

  static ceres::CostFunction* Create(DyadType output_type, double sign) {
    return new ceres::AutoDiffCostFunction<GaugeResidual, 1, 2, 2, 2, 2, 1>(
        new GaugeResidual(output_type, sign));
  }

 private:
  PathPointResidual assembly_;
};

// The design bounds of a path four-bar (design_bounds.h), blocks as PathPointResidual's:
//   e_k = sqrt(mu) max(0, g_k).
class PathBoundsResidual {
 public:
  PathBoundsResidual(DyadType output_type, const ScaledBounds* bounds, const double* sqrt_weight)
      : output_type_(output_type), bounds_(bounds), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* crank_pivot, const T* crank_pin, const T* output_point,
                  const T* output_second, const T* output_scalar, const T* coupler_point,
                  T* residual) const {
    const BoundGeometry<T> geometry =
        PathBoundGeometry(output_type_, crank_pivot, crank_pin, output_point, output_second,
                          output_scalar, coupler_point);
    BoundPenalties(*bounds_, geometry, *sqrt_weight_, residual);
    return true;
  }

  static ceres::CostFunction* Create(DyadType output_type, const ScaledBounds* bounds,
                                     const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<PathBoundsResidual, kBoundResiduals, 2, 2, 2, 2, 1, 2>(
        new PathBoundsResidual(output_type, bounds, sqrt_weight));
  }

 private:
  DyadType output_type_;
  const ScaledBounds* bounds_;
  const double* sqrt_weight_;
};

// The transmission angle (lib/four_bar_motion.h TransmissionAngleDeg) of the four-bar at crank
// turn t, assembled as PathPointResidual assembles it (crank pin P, coupler turn theta about it):
// output pin B = P + R(theta) (m - A) (m the output's moving pivot: an RR's second block, a PR's
// point), coupler line B - P, the output pin's direction of motion u = perp(B - F) (RR) or along
// the line (PR); sin(mu) = |(B - P) . u| / (|B - P| |u|), e = sqrt(mu_w) max(0, sin(mu_min) -
// sin(mu)), mu_w read through `sqrt_weight` (raised with the bounds' weight). Zero where the
// four-bar does not assemble (the point errors' business). Not for an RP output.
class PathTransmissionResidual {
 public:
  PathTransmissionResidual(DyadType output_type, double sign, double turn, double sin_min,
                           const double* sqrt_weight)
      : assembly_(output_type, sign, Eigen::Vector2d::Zero(), 1.0, turn, Eigen::Vector2d::Zero()),
        output_type_(output_type),
        turn_(turn),
        sin_min_(sin_min),
        sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* crank_pivot, const T* crank_pin, const T* output_point,
                  const T* output_second, const T* output_scalar, T* residual) const {
    residual[0] = T(0.0);
    T pin[2], cos_theta, sin_theta;
    if (!assembly_.Assemble(crank_pivot, crank_pin, output_point, output_second, output_scalar,
                            T(turn_), pin, &cos_theta, &sin_theta)) {
      return true;
    }
    const T* moving = output_type_ == DyadType::kRR ? output_second : output_point;
    const T mx = moving[0] - crank_pin[0], my = moving[1] - crank_pin[1];
    const T bx = pin[0] + cos_theta * mx - sin_theta * my;
    const T by = pin[1] + sin_theta * mx + cos_theta * my;
    residual[0] = *sqrt_weight_ * TransmissionShortfallAt(output_type_, pin[0], pin[1], bx, by,
                                                          output_point, output_second, sin_min_);
    return true;
  }

 private:
  PathPointResidual assembly_;
  DyadType output_type_;
  double turn_;
  double sin_min_;
  const double* sqrt_weight_;
};

// The task in the scaled frames: Sigma' = E' = (Sigma - centroid) / L (E = Sigma at the first
// point, so the first-point convention holds in the scaled frames too).
struct ScaledTask {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;  // divided by their mean
  std::vector<bool> exact;
  std::vector<double> turns;   // psi_j - psi_0 (the prescribed timing, or the start's)
  ScaledBounds bounds;         // the design bounds (design_bounds.h)
  double bounds_weight = 0.0;  // sqrt(mu) of their penalty
  // A held transmission angle (PathTransmissionResidual): the crank turns sampled, and the sine
  // of the least angle; empty when none is held.
  std::vector<double> transmission_turns;
  double transmission_sin_min = 0.0;
};

// The unknowns (scaled frames).
struct State {
  double crank_pivot[2] = {0.0, 0.0};
  double crank_pin[2] = {0.0, 0.0};
  DyadBlocks output;
  double coupler_point[2] = {0.0, 0.0};
  std::vector<double> turns;  // free timing: t_1 .. t_{n-1} (t_0 = 0), monotonic
};

double Turn(const ScaledTask& task, const State& state, size_t j) {
  if (state.turns.empty()) return task.turns[j];
  return j == 0 ? 0.0 : state.turns[j - 1];
}

// Coupler pose of the assembly `sign` at turn 0 (the first point), or nothing.
bool FirstConfiguration(const State& state, double sign, PlanarPose* pose) {
  const PathPointResidual functor(state.output.type, sign, Eigen::Vector2d::Zero(), 1.0, 0.0,
                                  Eigen::Vector2d::Zero());
  double pin[2], cos_theta, sin_theta;
  if (!functor.Assemble(state.crank_pivot, state.crank_pin, state.output.point, state.output.second,
                        state.output.scalar, 0.0, pin, &cos_theta, &sin_theta)) {
    return false;
  }
  pose->theta = std::atan2(sin_theta, cos_theta);
  const Eigen::Vector2d crank_pin(state.crank_pin[0], state.crank_pin[1]);
  pose->origin_in_fixed = crank_pin - Rotation2(pose->theta) * crank_pin;
  return true;
}

// The point errors C_j - R_j (scaled, unshifted); false where a point does not assemble.
bool PointErrors(const ScaledTask& task, const State& state, double sign,
                 std::vector<Eigen::Vector2d>* errors) {
  errors->assign(task.points.size(), Eigen::Vector2d::Zero());
  for (size_t j = 0; j < task.points.size(); ++j) {
    const PathPointResidual functor(state.output.type, sign, task.points[j], 1.0,
                                    Turn(task, state, j), Eigen::Vector2d::Zero());
    if (!functor.Evaluate(state.crank_pivot, state.crank_pin, state.output.point,
                          state.output.second, state.output.scalar, state.coupler_point,
                          Turn(task, state, j), (*errors)[j].data())) {
      return false;
    }
  }
  return true;
}

// The largest violation of the design bounds by `state` (scaled units).
double Violation(const ScaledTask& task, const State& state) {
  return BoundViolation(
      task.bounds,
      PathBoundGeometry(state.output.type, state.crank_pivot, state.crank_pin, state.output.point,
                        state.output.second, state.output.scalar, state.coupler_point));
}

// The largest shortfall of the transmission angle's sine at the task's sampled turns.
double TransmissionShortfall(const ScaledTask& task, const State& state, double sign) {
  const double unit = 1.0;
  double worst = 0.0;
  for (const double turn : task.transmission_turns) {
    const PathTransmissionResidual residual(state.output.type, sign, turn,
                                            task.transmission_sin_min, &unit);
    double value = 0.0;
    residual(state.crank_pivot, state.crank_pin, state.output.point, state.output.second,
             state.output.scalar, &value);
    worst = std::max(worst, value);
  }
  return worst;
}

// One Levenberg-Marquardt solve, point weights `weights` (points of weight 0 left out: they
// need not assemble), shifts `shifts`.
//
// Free timing: each point's turn t_j is a parameter of its own (point j's residual alone holds
// it), which Ceres eliminates in its Schur complement: time and memory linear in the points
// (written as steps t_j - t_{j-1}, every residual held every earlier step, a dense triangle of
// the Jacobian that made 2000 points take minutes). Every turn stays within one turn of the first
// point's, ahead of it (0 <= d t_j <= 2 pi). A solve whose turns come out of order is redone
// keeping the order by box bounds: each turn within the window halfway to its neighbours'
// turns; a turn the optimum would move past its window stops at its edge, and the windows are
// then re-centred and the solve repeated (at most kWindowRounds times, all within the options'
// iterations). `converged`: whether its last solve ended on a tolerance, not on the iteration
// limit.
void Solve(const ScaledTask& task, double sign, const std::vector<double>& weights,
           const std::vector<Eigen::Vector2d>& shifts, const ceres::Solver::Options& options,
           State* state, int* iterations, std::string* message, bool* converged) {
  const bool free_timing = !state->turns.empty();
  const double direction =
      free_timing && Turn(task, *state, task.points.size() - 1) < 0.0 ? -1.0 : 1.0;
  int budget = options.max_num_iterations;  // shared by the windowed rounds
  *converged = true;
  const State start = *state;
  // Round 0: the turns free within [0, 2 pi] of the first point's: at an optimum the ordering
  // rarely binds, and when the turns come out in order they are the constrained optimum too.
  // Otherwise the windowed rounds, from the start.
  for (int round = 0; round <= (free_timing ? kWindowRounds : 0); ++round) {
    const bool windowed = round > 0;
    ceres::Problem problem;
    problem.AddResidualBlock(
        PathBoundsResidual::Create(state->output.type, &task.bounds, &task.bounds_weight), nullptr,
        state->crank_pivot, state->crank_pin, state->output.point, state->output.second,
        state->output.scalar, state->coupler_point);
    for (const double turn : task.transmission_turns) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<PathTransmissionResidual, 1, 2, 2, 2, 2, 1>(
              new PathTransmissionResidual(state->output.type, sign, turn,
                                           task.transmission_sin_min, &task.bounds_weight)),
          nullptr, state->crank_pivot, state->crank_pin, state->output.point, state->output.second,
          state->output.scalar);
    }
    // The window of each free turn (in the direction of travel d: d t grows with j).
    const size_t count = task.points.size();
    std::vector<double> low(count, 0.0), high(count, 0.0);
    for (size_t j = 1; free_timing && j < count; ++j) {
      const double t = direction * state->turns[j - 1];
      const double before = j == 1 || !windowed ? 0.0 : 0.5 * (direction * state->turns[j - 2] + t);
      const double after =
          j + 1 == count || !windowed ? 2.0 * kPi : 0.5 * (t + direction * state->turns[j]);
      low[j] = direction > 0.0 ? before : -after;
      high[j] = direction > 0.0 ? after : -before;
    }
    for (size_t j = 0; j < count; ++j) {
      if (weights[j] == 0.0) continue;  // left out (the projection onto the exact points)
      const bool free_turn = free_timing && j > 0;
      std::vector<double*> blocks = {state->crank_pivot,   state->crank_pin,
                                     state->output.point,  state->output.second,
                                     state->output.scalar, state->coupler_point};
      if (free_turn) blocks.push_back(&state->turns[j - 1]);
      problem.AddResidualBlock(
          PathPointResidual::Create(state->output.type, sign, task.points[j], std::sqrt(weights[j]),
                                    task.turns[j], shifts[j], free_turn),
          nullptr, blocks);
      if (!free_turn) continue;
      // Bounds only on a block the problem has (Ceres aborts otherwise): a turn of a point left
      // out is not one.
      double* turn = &state->turns[j - 1];
      if (!(high[j] - low[j] > 1e-12)) {
        problem.SetParameterBlockConstant(turn);
      } else {
        *turn = std::clamp(*turn, low[j], high[j]);
        problem.SetParameterLowerBound(turn, 0, low[j]);
        problem.SetParameterUpperBound(turn, 0, high[j]);
      }
    }
    problem.AddResidualBlock(GaugeResidual::Create(state->output.type, sign), nullptr,
                             state->crank_pivot, state->crank_pin, state->output.point,
                             state->output.second, state->output.scalar);
    if (state->output.type != DyadType::kRR) {
      problem.SetManifold(state->output.second, UnitCircle());
    }
    // A start past the crank's reach at some point cannot be evaluated: Ceres would stop at
    // once (and say so on stderr, whatever its logging type); leave it as it is.
    double start_cost = 0.0;
    if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &start_cost, nullptr, nullptr,
                          nullptr)) {
      *message = "the start does not assemble at every point";
      *converged = true;  // nothing more this solve can do from here
      return;
    }
    ceres::Solver::Options solve_options = options;
    if (free_timing) solve_options.linear_solver_type = ceres::DENSE_SCHUR;
    solve_options.max_num_iterations = budget;
    ceres::Solver::Summary summary;
    ceres::Solve(solve_options, &problem, &summary);
    *converged = summary.termination_type != ceres::NO_CONVERGENCE;
    const int used = summary.num_successful_steps + summary.num_unsuccessful_steps;
    *iterations += used;
    *message = summary.message;
    budget -= std::max(used, 1);
    if (!free_timing) return;
    if (!windowed) {
      // In order: every point solved for at or ahead of the one before it (checked before the
      // budget: a round 0 that runs out of iterations out of order is redone in order, never
      // returned).
      bool in_order = true;
      double previous = 0.0;
      for (size_t j = 1; j < count; ++j) {
        if (weights[j] == 0.0) continue;
        in_order &= direction * (state->turns[j - 1] - previous) >= 0.0;
        previous = state->turns[j - 1];
      }
      if (in_order || summary.termination_type == ceres::FAILURE) return;
      // Out of order: the windowed rounds, which keep the order, from the start; from this
      // round's four-bar at the start's (ordered) turns when it ran out of iterations (it was
      // still on its way, not at an optimum out of order).
      if (budget > 0) {
        *state = start;
      } else {
        state->turns = start.turns;
      }
      budget = options.max_num_iterations;
      continue;
    }
    if (budget <= 0) return;
    // Another round when a turn stopped at a window's edge that is not a real limit (the first
    // point's turn behind, one turn ahead).
    bool at_edge = false;
    for (size_t j = 1; free_timing && j < count && !at_edge; ++j) {
      if (weights[j] == 0.0 || !(high[j] - low[j] > 1e-12)) continue;
      const double t = state->turns[j - 1];
      const double margin = 1e-9 * (high[j] - low[j]);
      const bool at_low = t <= low[j] + margin, at_high = t >= high[j] - margin;
      const bool real_low = direction > 0.0 ? j == 1 : j + 1 == count;
      const bool real_high = direction > 0.0 ? j + 1 == count : j == 1;
      at_edge = (at_low && !real_low) || (at_high && !real_high);
    }
    if (!at_edge || summary.termination_type == ceres::FAILURE) return;
  }
}

// A design judged as AnalyzePathFourBar judges it, in task units.
struct Judgement {
  bool assembles = false;  // at every point, on the first point's assembly
  std::vector<std::string> defects;
  double cost = kInfinity;  // 1/2 sum w e^2
  double rms = kInfinity;   // sqrt(sum w e^2 / sum w)
  double max = kInfinity;
  double exact_max = 0.0;  // over the exact points
  double violation = 0.0;  // of the design bounds, times L
  // The transmission angle over the sweep below a held minimum
  // (PathRefinerOptions::min_transmission_deg).
  bool transmission_short = false;
};

Judgement Judge(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                const std::vector<double>& weights, const std::vector<bool>& exact,
                const std::vector<double>& input_angles, double length, bool closed,
                const PathRefinerOptions& options) {
  Judgement judgement;
  const ScaledBounds bounds = ScaleBounds(options.constraints, length, Similarity2());
  const DyadBlocks output = ToBlocks(four_bar.output);
  judgement.violation =
      BoundViolation(
          bounds, PathBoundGeometry(output.type, four_bar.input.fixed_pivot.data(),
                                    four_bar.input.moving_pivot.data(), output.point, output.second,
                                    output.scalar, four_bar.coupler_point.data())) /
      length;
  PathAnalysisOptions analysis_options;
  analysis_options.closed = closed;
  if (options.min_transmission_deg)
    analysis_options.transmission_samples = kPathTransmissionSamples;
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(four_bar, points, input_angles, length, analysis_options);
  if (!analysis.max_point_error) return judgement;
  judgement.transmission_short = options.min_transmission_deg && analysis.transmission_min_deg &&
                                 *analysis.transmission_min_deg < *options.min_transmission_deg;
  double weighted = 0.0, weight_sum = 0.0;
  for (size_t j = 0; j < points.size(); ++j) {
    const double weight = weights.empty() ? 1.0 : weights[j];
    const double error = analysis.point_errors[j];
    weighted += weight * error * error;
    weight_sum += weight;
    if (!exact.empty() && exact[j]) judgement.exact_max = std::max(judgement.exact_max, error);
  }
  if (!std::isfinite(weighted)) return judgement;
  judgement.assembles = true;
  judgement.defects = analysis.defects;
  judgement.cost = 0.5 * weighted;
  judgement.rms = std::sqrt(weighted / weight_sum);
  judgement.max = *analysis.max_point_error;
  return judgement;
}

// Whether `result` may replace `seed`: it assembles at every point, has no defect the seed did
// not have, meets the exact points (or comes nearer), keeps the design bounds when the seed does
// not (and does not break them when the seed keeps them), and, all that alike, costs no more.
bool NotWorse(const Judgement& result, const Judgement& seed, double exact_limit) {
  if (!result.assembles) return false;
  if (!seed.assembles) return true;
  for (const std::string& defect : result.defects) {
    if (std::find(seed.defects.begin(), seed.defects.end(), defect) == seed.defects.end()) {
      return false;
    }
  }
  const double result_exact = result.exact_max > exact_limit ? result.exact_max : 0.0;
  const double seed_exact = seed.exact_max > exact_limit ? seed.exact_max : 0.0;
  if (result_exact != seed_exact) return result_exact < seed_exact;
  const bool result_keeps = result.violation <= kConstraintSlack && !result.transmission_short;
  const bool seed_keeps = seed.violation <= kConstraintSlack && !seed.transmission_short;
  if (result_keeps != seed_keeps) return result_keeps;
  return result.cost <= seed.cost;
}

std::string Format(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", value);
  return buffer;
}

// The header's argument checks; returns the mean weight.
double CheckInput(const std::vector<Eigen::Vector2d>& points, const std::vector<double>& weights,
                  const std::vector<bool>& exact, double length, bool free_timing,
                  const std::vector<double>* input_angles, const PathFourBar& four_bar) {
  const std::string where = "RefinePathFourBar: ";
  const double weight_mean =
      CheckRefinerInput("RefinePathFourBar", points.size(), length, weights, &exact);
  if (input_angles == nullptr || input_angles->size() != points.size()) {
    throw std::invalid_argument(where + "one input angle per point is needed");
  }
  if (points.size() < 2) throw std::invalid_argument(where + "at least two points are needed");
  for (size_t j = 0; j < points.size(); ++j) {
    if (!points[j].allFinite() || !std::isfinite((*input_angles)[j])) {
      throw std::invalid_argument(where + "points and input angles must be finite");
    }
  }
  if (four_bar.input.type != DyadType::kRR) {
    throw std::invalid_argument(where + "the input must be an RR crank");
  }
  if (!free_timing) return weight_mean;
  const double total = input_angles->back() - input_angles->front();
  for (size_t j = 1; j < points.size(); ++j) {
    const double step = (*input_angles)[j] - (*input_angles)[j - 1];
    if (total == 0.0 || step * total < 0.0) {
      throw std::invalid_argument(where + "free timing needs monotonic input angles");
    }
  }
  return weight_mean;
}

}  // namespace

RefinerSummary RefinePathFourBar(const std::vector<Eigen::Vector2d>& points,
                                 const std::vector<double>& weights, const std::vector<bool>& exact,
                                 double length, bool free_timing, std::vector<double>* input_angles,
                                 PathFourBar* four_bar, const PathRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double weight_mean =
      CheckInput(points, weights, exact, length, free_timing, input_angles, *four_bar);

  RefinerSummary summary;
  const Judgement initial =
      Judge(*four_bar, points, weights, exact, *input_angles, length, options.closed, options);
  summary.initial_cost = summary.final_cost = initial.cost;
  summary.initial_rms = summary.final_rms = initial.rms;
  summary.initial_max = summary.final_max = initial.max;
  if (!initial.assembles) {
    summary.message = "the seed does not reach every point on one assembly: returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }

  // Sigma' = E' = (Sigma - centroid) / L; `sigma` maps them back.
  const Similarity2 sigma = ScaledPointFrame(points, length);
  const Similarity2 to_scaled = sigma.Inverse();
  ScaledTask task;
  for (size_t j = 0; j < points.size(); ++j) {
    task.points.push_back(to_scaled.Apply(points[j]));
    task.weights.push_back(weights.empty() ? 1.0 : weights[j] / weight_mean);
    task.exact.push_back(!exact.empty() && exact[j]);
    task.turns.push_back((*input_angles)[j] - input_angles->front());
  }
  task.bounds = ScaleBounds(options.constraints, length, to_scaled);
  task.bounds_weight = std::sqrt(kBoundFirstWeight);
  // A held transmission angle: no RP output (no transmission angle defined). Free timing holds
  // it at the start's turns (the turns move little in a refinement from a projected timing; the
  // result is judged over its own sweep, and refused below the minimum when the start keeps it).
  if (options.min_transmission_deg && four_bar->output.type != DyadType::kRP) {
    task.transmission_sin_min = HeldTransmissionSine(*options.min_transmission_deg);
    for (size_t j = 0; j < points.size(); ++j) {
      const int samples = j + 1 < points.size() ? kTransmissionSamples : 1;
      for (int k = 0; k < samples; ++k) {
        const double next = j + 1 < points.size() ? task.turns[j + 1] : task.turns[j];
        task.transmission_turns.push_back(task.turns[j] +
                                          k * (next - task.turns[j]) / kTransmissionSamples);
      }
    }
  }
  State state;
  const PlanarDyad input = TransformDyad(four_bar->input, to_scaled, to_scaled);
  Eigen::Map<Eigen::Vector2d>(state.crank_pivot) = input.fixed_pivot;
  Eigen::Map<Eigen::Vector2d>(state.crank_pin) = input.moving_pivot;
  state.output = ToBlocks(TransformDyad(four_bar->output, to_scaled, to_scaled));
  Eigen::Map<Eigen::Vector2d>(state.coupler_point) = to_scaled.Apply(four_bar->coupler_point);
  if (free_timing) {
    for (size_t j = 1; j < points.size(); ++j) state.turns.push_back(task.turns[j]);
  }
  // The first point's assembly: the configuration nearer E = Sigma (AnalyzePathFourBar's).
  double sign = 1.0;
  PlanarPose first[2];
  const bool assembles[2] = {FirstConfiguration(state, 1.0, &first[0]),
                             FirstConfiguration(state, -1.0, &first[1])};
  if (assembles[0] && assembles[1] &&
      PoseError(first[1], PlanarPose(), 1.0) < PoseError(first[0], PlanarPose(), 1.0)) {
    sign = -1.0;
  } else if (!assembles[0]) {
    sign = -1.0;
  }

  ceres::Solver::Options solver_options =
      RefinerSolverOptions(options.max_iterations, options.function_tolerance,
                           options.parameter_tolerance, kGradientTolerance);

  // Least squares, then the method of multipliers for the exact points.
  std::vector<double> point_weights = task.weights;
  for (size_t j = 0; j < points.size(); ++j) {
    if (task.exact[j]) point_weights[j] *= kExactWeight;
  }
  std::vector<Eigen::Vector2d> shifts(points.size(), Eigen::Vector2d::Zero()), errors;
  std::string message;
  bool converged = true;
  Solve(task, sign, point_weights, shifts, solver_options, &state, &summary.iterations, &message,
        &converged);
  // The design bounds: the penalty raised until the design keeps them (design_bounds.h).
  int bound_rounds = 0;
  while (bound_rounds < kBoundRounds &&
         (Violation(task, state) > kBoundSlack ||
          TransmissionShortfall(task, state, sign) > kTransmissionSlack)) {
    NextBoundRound(Violation(task, state), &task.bounds, &task.bounds_weight);
    Solve(task, sign, point_weights, shifts, solver_options, &state, &summary.iterations, &message,
          &converged);
    ++bound_rounds;
  }
  const auto worst_exact = [&]() {
    if (!PointErrors(task, state, sign, &errors)) return kInfinity;
    double worst = 0.0;
    for (size_t j = 0; j < points.size(); ++j) {
      if (task.exact[j]) worst = std::max(worst, errors[j].norm());
    }
    return worst;
  };
  int round = 0;
  for (double worst = worst_exact(); round < options.max_penalty_rounds && std::isfinite(worst) &&
                                     worst > options.exact_tolerance;
       worst = worst_exact(), ++round) {
    for (size_t j = 0; j < points.size(); ++j) {
      if (task.exact[j]) shifts[j] += errors[j];
    }
    Solve(task, sign, point_weights, shifts, solver_options, &state, &summary.iterations, &message,
          &converged);
  }
  std::string note = round > 0 ? std::to_string(round) + " multiplier rounds" : "";
  if (bound_rounds > 0) {
    note += std::string(note.empty() ? "" : "; ") + std::to_string(bound_rounds) +
            " rounds onto the design bounds";
  }
  // Where the multipliers stall (typically a fit pressed against the crank's reach), the exact
  // points alone, from there: the underdetermined solve moves the design least onto them.
  const double worst = worst_exact();
  if (std::isfinite(worst) && worst > options.exact_tolerance) {
    std::vector<double> exact_only(points.size(), 0.0);
    for (size_t j = 0; j < points.size(); ++j) exact_only[j] = task.exact[j] ? 1.0 : 0.0;
    // A design run far off (toward a slider) moves below the relative tolerance: only the
    // cost (the exact points' errors) decides here.
    ceres::Solver::Options projection_options = solver_options;
    projection_options.parameter_tolerance = kProjectionTolerance;
    std::string projection_message;
    bool ignored = true;  // the projection's end is judged below, not by its convergence
    Solve(task, sign, exact_only,
          std::vector<Eigen::Vector2d>(points.size(), Eigen::Vector2d::Zero()), projection_options,
          &state, &summary.iterations, &projection_message, &ignored);
    note += std::string(note.empty() ? "" : "; ") + "projected onto the exact points";
  }

  // The refined design in the first point's convention and the task's units.
  PlanarPose first_pose;
  bool accept = false;
  PathFourBar refined;
  std::vector<double> refined_angles = *input_angles;
  if (FirstConfiguration(state, sign, &first_pose)) {
    const Eigen::Vector2d crank_pivot(state.crank_pivot[0], state.crank_pivot[1]);
    const Eigen::Vector2d crank_pin(state.crank_pin[0], state.crank_pin[1]);
    PathFourBar scaled;
    scaled.input = PlanarDyad::RR(crank_pivot, crank_pin, (crank_pin - crank_pivot).norm());
    scaled.output = FromBlocks(state.output);
    scaled.coupler_point = Eigen::Vector2d(state.coupler_point[0], state.coupler_point[1]);
    scaled = MoveToFirstConfiguration(scaled, first_pose);
    refined.input = TransformDyad(scaled.input, sigma, sigma);
    refined.output = TransformDyad(scaled.output, sigma, sigma);
    refined.coupler_point = sigma.Apply(scaled.coupler_point);
    for (size_t j = 1; free_timing && j < points.size(); ++j) {
      refined_angles[j] = input_angles->front() + Turn(task, state, j);
    }
    const Judgement result =
        Judge(refined, points, weights, exact, refined_angles, length, options.closed, options);
    accept = NotWorse(result, initial, options.exact_tolerance * length);
    if (accept) {
      summary.final_cost = result.cost;
      summary.final_rms = result.rms;
      summary.final_max = result.max;
    } else {
      note +=
          std::string(note.empty() ? "" : "; ") + "seed kept: the refined design is worse (" +
          (result.assembles ? "cost " + Format(result.cost) + ", max error " + Format(result.max)
                            : std::string("does not reach every point")) +
          ")";
    }
  } else {
    note += std::string(note.empty() ? "" : "; ") +
            "seed kept: the refined design does not "
            "assemble at the first point";
  }
  if (accept) {
    *four_bar = refined;
    if (free_timing) *input_angles = refined_angles;
    summary.converged = converged;
    const bool runaway =
        refined.input.radius > kRunawayRadius * length ||
        (refined.output.type == DyadType::kRR && refined.output.radius > kRunawayRadius * length);
    if (runaway) {
      note += std::string(note.empty() ? "" : "; ") + "a radius beyond " + Format(kRunawayRadius) +
              " L: the fit runs toward a slider";
    }
  }
  summary.message = message + (note.empty() ? "" : " [" + note + "]");
  summary.seconds = elapsed();
  return summary;
}

}  // namespace linkfit
