#include "optimizers/six_bar_refiner.h"

#include <ceres/ceres.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "lib/six_bar_frames.h"
#include "optimizers/design_bounds.h"

namespace linkfit {
namespace {

// The turn of the upper link (body 1) parameterizes each configuration; the other four are the
// closures' solution.
constexpr int kTurn = kSixBarUpperLink - 1;

// Newton iterations of an assembly, and its tolerance (times L).
constexpr int kAssemblyIterations = 30;
constexpr double kAssemblyTolerance = 1e-13;

// Rounds of refinement at most (each while the last gained: AnotherRound).
constexpr int kMaxRounds = 10;

// Gauss-Newton iterations on a pose's turn (FitSixBarToPoses), and the step of its derivative.
constexpr int kTurnIterations = 20;
constexpr double kTurnDelta = 1e-7;

double Value(double x) { return x; }
template <typename T, int N>
double Value(const ceres::Jet<T, N>& x) {
  return x.a;
}

std::array<int, 2> FromBodies(const SixBar& six_bar) {
  return {six_bar.links[0].from_body, six_bar.links[1].from_body};
}
std::array<int, 2> ToBodies(const SixBar& six_bar) {
  return {six_bar.links[0].to_body, six_bar.links[1].to_body};
}

// Newton's method for the four free turns of `angles` (the upper link's held), on the joints
// `joints`; false where it does not converge or meets a dead point.
bool AssembleFree(const std::array<int, 2>& from, const std::array<int, 2>& to,
                  const double* joints, double tolerance, SixBarAngles* angles) {
  for (int iteration = 0; iteration <= kAssemblyIterations; ++iteration) {
    const SixBarFrames<double> frames(from, to, joints, angles->data());
    const Eigen::Vector4d residual = frames.Closure();
    if (residual.norm() <= tolerance) return true;
    const Eigen::Matrix4d free = frames.ClosureJacobian().rightCols<4>();
    const Eigen::PartialPivLU<Eigen::Matrix4d> lu(free);
    const Eigen::Vector4d pivots = lu.matrixLU().diagonal().cwiseAbs();
    if (!(pivots.minCoeff() > 1e-12 * pivots.maxCoeff())) return false;
    angles->tail<4>() -= lu.solve(residual);
    if (!angles->allFinite()) return false;
  }
  return false;
}

// The task body's pose error components at `angles`: (dx, dy, L dtheta), the angle wrapped.
Eigen::Vector3d PoseResidual(const SixBar& six_bar, const SixBarAngles& angles,
                             const PlanarPose& target, double length) {
  const PlanarPose pose = SixBarTaskPose(six_bar, angles);
  const Eigen::Vector2d d = pose.origin_in_fixed - target.origin_in_fixed;
  return Eigen::Vector3d(d.x(), d.y(),
                         length * std::remainder(pose.theta - target.theta, 2.0 * M_PI));
}

// A configuration's solutions during a solve: the last evaluation's (a trial step's too) and the
// last accepted step's, which each evaluation starts from (a rejected trial's, far off, could
// lead Newton's method to another assembly; WarmKeeper moves `last` to `accepted` after each
// successful step).
struct Warm {
  SixBarAngles accepted, last;
};

class WarmKeeper : public ceres::IterationCallback {
 public:
  explicit WarmKeeper(std::vector<Warm*> warms) : warms_(std::move(warms)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (summary.step_is_successful) {
      for (Warm* warm : warms_) warm->accepted = warm->last;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::vector<Warm*> warms_;
};

// The configuration at the upper link's turn `turn` in T: assembled in doubles from
// warm->accepted (the result in warm->last), then one Newton step in T, which carries the free
// turns' derivatives (implicit function theorem). False where it does not assemble.
template <typename T>
bool Configuration(const std::array<int, 2>& from, const std::array<int, 2>& to, const T* joints,
                   const T& turn, double length, Warm* warm, std::array<T, 5>* angles) {
  std::array<double, kSixBarJointCount> values;
  for (int k = 0; k < kSixBarJointCount; ++k) values[k] = Value(joints[k]);
  SixBarAngles x = warm->accepted;
  x[kTurn] = Value(turn);
  if (!AssembleFree(from, to, values.data(), kAssemblyTolerance * length, &x)) return false;
  warm->last = x;
  (*angles)[kTurn] = turn;
  for (int k = 1; k < 5; ++k) (*angles)[k] = T(x[k]);
  const SixBarFrames<T> frames(from, to, joints, angles->data());
  const Eigen::Matrix<T, 4, 1> closure = frames.Closure();
  const Eigen::Matrix<T, 4, 4> free = frames.ClosureJacobian().template rightCols<4>();
  const Eigen::Matrix<T, 4, 1> step = free.partialPivLu().solve(closure);
  for (int k = 1; k < 5; ++k) (*angles)[k] -= step[k - 1];
  return true;
}

// A held transmission angle's penalties at a configuration (optimizers/design_bounds.h): per loop,
// sqrt(weight) L max(0, held_sine - sin mu); 0 where no angle is held (held_sine 0).
template <typename T>
void TransmissionPenalty(const SixBarFrames<T>& frames, double length, double held_sine,
                         double weight, T* residual) {
  for (int l = 0; l < 2; ++l) {
    const T shortfall = T(held_sine) - frames.TransmissionSine(l);
    residual[l] = shortfall > T(0.0) ? T(std::sqrt(weight) * length) * shortfall : T(0.0);
  }
}

// The transmission hold of a refinement: the sine held (0: none) and the penalty's weight (raised
// in rounds with the bounds').
struct TransmissionHold {
  double held_sine = 0.0;
  // The sine of the minimum itself: a fit is taken over a better one only where it keeps that
  // (the penalty's degree of margin aside), so that a design keeping it is never given up for a
  // worse fit.
  double kept_sine = 0.0;
  const double* weight = nullptr;
};

// One pose's residual for Ceres: parameters the joints (14), E's pose at the reference
// configuration (x, y, theta) and the upper link's turn; the other turns solved inside, from the
// last solution (`warm`, updated). Residuals: the pose error (3) and, holding a transmission angle
// (kHeld), each loop's penalty there (2).
template <bool kHeld>
class SixBarPoseCost {
 public:
  SixBarPoseCost(const std::array<int, 2>& from, const std::array<int, 2>& to,
                 const PlanarPose& target, double length, double weight, Warm* warm,
                 const TransmissionHold& hold)
      : from_(from),
        to_(to),
        target_(target),
        length_(length),
        scale_(std::sqrt(weight)),
        warm_(warm),
        hold_(hold) {}

  template <typename T>
  bool operator()(const T* joints, const T* reference, const T* turn, T* residual) const {
    std::array<T, 5> angles;
    if (!Configuration(from_, to_, joints, turn[0], length_, warm_, &angles)) return false;
    const SixBarFrames<T> moved(from_, to_, joints, angles.data());
    if constexpr (kHeld) {
      TransmissionPenalty(moved, length_, hold_.held_sine, *hold_.weight, residual + 3);
    }
    const Eigen::Matrix<T, 2, 1> origin =
        moved.At(kSixBarTaskBody, Eigen::Matrix<T, 2, 1>(reference[0], reference[1]));
    const T theta = reference[2] + angles[kSixBarTaskBody - 1];
    const double wrap = 2.0 * M_PI * std::round((Value(theta) - target_.theta) / (2.0 * M_PI));
    residual[0] = scale_ * (origin.x() - target_.origin_in_fixed.x());
    residual[1] = scale_ * (origin.y() - target_.origin_in_fixed.y());
    residual[2] = scale_ * length_ * (theta - target_.theta - wrap);
    return true;
  }

 private:
  std::array<int, 2> from_, to_;
  PlanarPose target_;
  double length_, scale_;
  Warm* warm_;
  TransmissionHold hold_;
};

// A bound on two joints of one body (a link: `lower` <= distance <= `upper`) or on one joint (a
// box, in Sigma or, with `in_task_body`, in E), each side a penalty sqrt(weight) max(0, excess)
// (the bounds held `inset` further in: design_bounds.h's shift).
struct SixBarBound {
  int first = 0, second = -1;  // joint indices (SixBarJoint / 2); second -1: a box
  double lower = 0.0, upper = std::numeric_limits<double>::infinity();
  bool in_task_body = false;
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero(), box_max = Eigen::Vector2d::Zero();
};

class SixBarBoundCost {
 public:
  SixBarBoundCost(const SixBarBound& bound, const double* weight, const double* inset)
      : bound_(bound), weight_(weight), inset_(inset) {}

  template <typename T>
  bool operator()(const T* joints, const T* reference, T* residual) const {
    const T scale = T(std::sqrt(*weight_));
    const T inset = T(*inset_);
    const Eigen::Matrix<T, 2, 1> a(joints[2 * bound_.first], joints[2 * bound_.first + 1]);
    const auto excess = [](const T& value) { return value > T(0.0) ? value : T(0.0); };
    if (bound_.second >= 0) {
      const Eigen::Matrix<T, 2, 1> b(joints[2 * bound_.second], joints[2 * bound_.second + 1]);
      using std::sqrt;
      const T distance = sqrt((a - b).squaredNorm() + T(1e-300));
      residual[0] = scale * excess(distance - (T(bound_.upper) - inset));
      residual[1] = scale * excess((T(bound_.lower) + inset) - distance);
      residual[2] = T(0.0);
      residual[3] = T(0.0);
      return true;
    }
    Eigen::Matrix<T, 2, 1> p = a;
    if (bound_.in_task_body) {  // E's coordinates of the joint: R(-theta) (a - origin)
      using std::cos;
      using std::sin;
      const T c = cos(reference[2]), s = sin(reference[2]);
      const T dx = a.x() - reference[0], dy = a.y() - reference[1];
      p = Eigen::Matrix<T, 2, 1>(c * dx + s * dy, -s * dx + c * dy);
    }
    for (int k = 0; k < 2; ++k) {
      residual[2 * k] = scale * excess((T(bound_.box_min[k]) + inset) - p[k]);
      residual[2 * k + 1] = scale * excess(p[k] - (T(bound_.box_max[k]) - inset));
    }
    return true;
  }

 private:
  SixBarBound bound_;
  const double* weight_;
  const double* inset_;
};

// A held chain (SixBarRefinerOptions::held_chain): sqrt(kChainHoldWeight) times the ground pivot's
// offset (2), each chain link's length error (2) and the wrist's offset in E (2).
class SixBarChainHoldCost {
 public:
  explicit SixBarChainHoldCost(const SixBarChain& chain) : chain_(chain) {}

  template <typename T>
  bool operator()(const T* joints, const T* reference, T* residual) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T scale = T(std::sqrt(kChainHoldWeight));
    const Eigen::Matrix<T, 2, 1> ground(joints[kJointGroundPivot], joints[kJointGroundPivot + 1]);
    const Eigen::Matrix<T, 2, 1> elbow(joints[kJointElbow], joints[kJointElbow + 1]);
    const Eigen::Matrix<T, 2, 1> wrist(joints[kJointWrist], joints[kJointWrist + 1]);
    residual[0] = scale * (ground.x() - T(chain_.ground_pivot.x()));
    residual[1] = scale * (ground.y() - T(chain_.ground_pivot.y()));
    residual[2] =
        scale * (sqrt((elbow - ground).squaredNorm() + T(1e-300)) - T(chain_.upper_length));
    residual[3] =
        scale * (sqrt((wrist - elbow).squaredNorm() + T(1e-300)) - T(chain_.forearm_length));
    // The wrist in E: R(-theta) (wrist - origin) at the reference configuration.
    const T c = cos(reference[2]), s = sin(reference[2]);
    const T dx = wrist.x() - reference[0], dy = wrist.y() - reference[1];
    residual[4] = scale * (c * dx + s * dy - T(chain_.wrist_in_moving.x()));
    residual[5] = scale * (-s * dx + c * dy - T(chain_.wrist_in_moving.y()));
    return true;
  }

 private:
  SixBarChain chain_;
};

// The task's bounds on the six-bar's joints (SixBarViolations' links and boxes).
std::vector<SixBarBound> Bounds(const SixBar& six_bar, const DesignConstraints& constraints,
                                double length) {
  const std::array<std::vector<int>, 6> bodies = SixBarBodyJointIndices(six_bar);
  std::vector<SixBarBound> bounds;
  for (const std::vector<int>& body : bodies) {
    for (size_t i = 0; i < body.size(); ++i) {
      for (size_t j = i + 1; j < body.size(); ++j) {
        SixBarBound bound;
        bound.first = body[i];
        bound.second = body[j];
        bound.upper = MaxLinkLength(constraints, length);
        bound.lower = constraints.min_link_length.value_or(0.0);
        bounds.push_back(bound);
      }
    }
  }
  const auto boxes = [&](const std::optional<PlanarBox>& box, int body, bool in_task_body) {
    if (!box) return;
    for (const int joint : bodies[body]) {
      SixBarBound bound;
      bound.first = joint;
      bound.in_task_body = in_task_body;
      bound.box_min = box->min;
      bound.box_max = box->max;
      bounds.push_back(bound);
    }
  };
  boxes(constraints.fixed_pivots_box, kSixBarGround, false);
  boxes(constraints.moving_pivots_box, kSixBarTaskBody, true);
  return bounds;
}

// The largest amount by which the six-bar breaks `bounds` (length units).
double BoundViolation(const SixBar& six_bar, const std::vector<SixBarBound>& bounds) {
  const std::array<double, kSixBarJointCount> joints = SixBarJointNumbers(six_bar);
  const double reference[3] = {six_bar.reference_pose.origin_in_fixed.x(),
                               six_bar.reference_pose.origin_in_fixed.y(),
                               six_bar.reference_pose.theta};
  double worst = 0.0;
  const double weight = 1.0, inset = 0.0;
  for (const SixBarBound& bound : bounds) {
    double residual[4];
    SixBarBoundCost(bound, &weight, &inset)(joints.data(), reference, residual);
    for (const double r : residual) worst = std::max(worst, r);
  }
  return worst;
}

double Weight(const std::vector<double>& weights, size_t k) {
  return k < weights.size() ? weights[k] : 1.0;
}

// The fit's errors from its configurations.
void Score(const std::vector<PlanarPose>& poses, const std::vector<double>& weights, double length,
           SixBarFit* fit) {
  fit->pose_errors.clear();
  double squares = 0.0, total = 0.0;
  fit->max_pose_error = 0.0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const double error = PoseResidual(fit->six_bar, fit->at_poses[k], poses[k], length).norm();
    fit->pose_errors.push_back(error);
    fit->max_pose_error = std::max(fit->max_pose_error, error);
    squares += Weight(weights, k) * error * error;
    total += Weight(weights, k);
  }
  fit->rms_pose_error = total > 0.0 ? std::sqrt(squares / total) : 0.0;
}

// How far a held transmission angle's sine falls short at the configurations of the poses (0
// where none is held).
double TransmissionShortfall(const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses,
                             double held_sine) {
  if (!(held_sine > 0.0)) return 0.0;
  const std::array<double, kSixBarJointCount> joints = SixBarJointNumbers(six_bar);
  const std::array<int, 2> from = FromBodies(six_bar), to = ToBodies(six_bar);
  double worst = 0.0;
  const auto at = [&](const SixBarAngles& angles) {
    const SixBarFrames<double> frames(from, to, joints.data(), angles.data());
    for (int l = 0; l < 2; ++l) worst = std::max(worst, held_sine - frames.TransmissionSine(l));
  };
  for (const SixBarAngles& angles : at_poses) at(angles);
  return worst;
}

// One Levenberg-Marquardt solve from *fit, kept where it fits better (keeping the bounds and a
// held transmission angle first).
void RefineOnce(const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
                double length, const SixBarRefinerOptions& options,
                const std::vector<SixBarBound>& bounds, const double* bound_weight,
                const double* inset, const TransmissionHold& hold, SixBarFit* fit, int* iterations,
                bool* converged, std::string* message, double* violation, double* shortfall) {
  *violation = 0.0;
  *shortfall = 0.0;
  const SixBar seed = fit->six_bar;
  std::array<double, kSixBarJointCount> joints = SixBarJointNumbers(seed);
  std::array<double, 3> reference = {seed.reference_pose.origin_in_fixed.x(),
                                     seed.reference_pose.origin_in_fixed.y(),
                                     seed.reference_pose.theta};
  std::vector<Warm> warm;
  for (const SixBarAngles& angles : fit->at_poses) warm.push_back({angles, angles});
  std::vector<double> turns;
  for (const SixBarAngles& angles : fit->at_poses) turns.push_back(angles[kTurn]);
  ceres::Problem problem;
  for (size_t k = 0; k < poses.size(); ++k) {
    if (hold.held_sine > 0.0) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<SixBarPoseCost<true>, 5, kSixBarJointCount, 3, 1>(
              new SixBarPoseCost<true>(FromBodies(seed), ToBodies(seed), poses[k], length,
                                       Weight(weights, k), &warm[k], hold)),
          nullptr, joints.data(), reference.data(), &turns[k]);
    } else {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<SixBarPoseCost<false>, 3, kSixBarJointCount, 3, 1>(
              new SixBarPoseCost<false>(FromBodies(seed), ToBodies(seed), poses[k], length,
                                        Weight(weights, k), &warm[k], hold)),
          nullptr, joints.data(), reference.data(), &turns[k]);
    }
  }
  for (const SixBarBound& bound : bounds) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<SixBarBoundCost, 4, kSixBarJointCount, 3>(
            new SixBarBoundCost(bound, bound_weight, inset)),
        nullptr, joints.data(), reference.data());
  }
  if (options.held_chain) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<SixBarChainHoldCost, 6, kSixBarJointCount, 3>(
            new SixBarChainHoldCost(*options.held_chain)),
        nullptr, joints.data(), reference.data());
  }
  problem.SetParameterBlockConstant(&turns[0]);
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  // A start the closures cannot be solved at (a configuration at a dead point) is not refined.
  double start_cost = 0.0;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &start_cost, nullptr, nullptr,
                        nullptr)) {
    *converged = true;
    *message = "not refined: the six-bar's closures cannot be solved at its configurations";
    return;
  }
  std::vector<Warm*> warms;
  for (Warm& w : warm) warms.push_back(&w);
  WarmKeeper keeper(warms);
  solver_options.callbacks.push_back(&keeper);
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);
  *iterations += static_cast<int>(ceres_summary.iterations.size());
  *converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  *message = ceres_summary.BriefReport();
  // The refined six-bar, placed again from its last configurations (the cost's last evaluation
  // may have been a rejected step's) and referenced at the first pose.
  SixBar refined = seed;
  refined.ground_pivot = {joints[kJointGroundPivot], joints[kJointGroundPivot + 1]};
  refined.elbow = {joints[kJointElbow], joints[kJointElbow + 1]};
  refined.wrist = {joints[kJointWrist], joints[kJointWrist + 1]};
  for (int l = 0; l < 2; ++l) {
    const int from = l == 0 ? kJointFirstFrom : kJointSecondFrom;
    const int to = l == 0 ? kJointFirstTo : kJointSecondTo;
    refined.links[l].from_joint = {joints[from], joints[from + 1]};
    refined.links[l].to_joint = {joints[to], joints[to + 1]};
  }
  refined.reference_pose = PlanarPose(reference[0], reference[1], reference[2]);
  // Placed from the last accepted step's configurations (the solution's).
  std::vector<SixBarAngles> start;
  for (size_t k = 0; k < poses.size(); ++k) {
    start.push_back(warm[k].accepted);
    start.back()[kTurn] = turns[k];
  }
  SixBarFit candidate;
  bool placed = FitSixBarToPoses(refined, poses, weights, length, start, &candidate) ||
                FitSixBarToPoses(refined, poses, weights, length, fit->at_poses, &candidate);
  if (placed) {
    const SixBarAngles first = candidate.at_poses[0];
    candidate.six_bar = ReReferenceSixBar(candidate.six_bar, first);
    for (SixBarAngles& angles : candidate.at_poses) angles -= first;
    Score(poses, weights, length, &candidate);
  }
  // Better: keeping the bounds (to within the slack) and a held transmission angle's minimum,
  // then the fit.
  const double slack = kConstraintSlack * length;
  if (placed) {
    *violation = BoundViolation(candidate.six_bar, bounds);
    *shortfall = TransmissionShortfall(candidate.six_bar, candidate.at_poses, hold.held_sine);
  }
  const bool keeps =
      placed && *violation <= slack &&
      TransmissionShortfall(candidate.six_bar, candidate.at_poses, hold.kept_sine) <= 0.0;
  const bool kept = BoundViolation(fit->six_bar, bounds) <= slack &&
                    TransmissionShortfall(fit->six_bar, fit->at_poses, hold.kept_sine) <= 0.0;
  if (placed &&
      ((keeps && !kept) || (keeps == kept && candidate.rms_pose_error <= fit->rms_pose_error))) {
    *fit = candidate;
  }
}

}  // namespace

bool FitSixBarToPoses(const SixBar& six_bar, const std::vector<PlanarPose>& poses,
                      const std::vector<double>& weights, double length,
                      const std::vector<SixBarAngles>& start, SixBarFit* fit) {
  fit->six_bar = six_bar;
  fit->at_poses.clear();
  const std::array<double, kSixBarJointCount> joints = SixBarJointNumbers(six_bar);
  const std::array<int, 2> from = FromBodies(six_bar), to = ToBodies(six_bar);
  const double tolerance = kAssemblyTolerance * length;
  // Without starts: the configurations over the upper link's range from the reference one, the
  // nearest to each pose.
  std::vector<SixBarAngles> sweep;
  if (start.size() < poses.size()) {
    sweep = SixBarSweep(six_bar, SixBarAngles::Zero(), kSixBarUpperLink, length);
  }
  for (size_t k = 0; k < poses.size(); ++k) {
    SixBarAngles angles = SixBarAngles::Zero();
    if (k < start.size()) {
      angles = start[k];
    } else {
      double nearest = std::numeric_limits<double>::infinity();
      for (const SixBarAngles& sample : sweep) {
        const double error = PoseResidual(six_bar, sample, poses[k], length).norm();
        if (error < nearest) {
          nearest = error;
          angles = sample;
        }
      }
    }
    if (!AssembleFree(from, to, joints.data(), tolerance, &angles)) return false;
    // Gauss-Newton on the upper link's turn: the pose error's derivative by a difference.
    for (int iteration = 0; iteration < kTurnIterations; ++iteration) {
      const Eigen::Vector3d residual = PoseResidual(six_bar, angles, poses[k], length);
      SixBarAngles ahead = angles;
      ahead[kTurn] += kTurnDelta;
      if (!AssembleFree(from, to, joints.data(), tolerance, &ahead)) break;
      const Eigen::Vector3d slope =
          (PoseResidual(six_bar, ahead, poses[k], length) - residual) / kTurnDelta;
      if (!(slope.squaredNorm() > 0.0)) break;
      const double step = -slope.dot(residual) / slope.squaredNorm();
      SixBarAngles next = angles;
      next[kTurn] += step;
      if (!AssembleFree(from, to, joints.data(), tolerance, &next) ||
          !(PoseResidual(six_bar, next, poses[k], length).norm() <= residual.norm())) {
        break;
      }
      angles = next;
      if (std::abs(step) < 1e-12) break;
    }
    fit->at_poses.push_back(angles);
  }
  Score(poses, weights, length, fit);
  return true;
}

SixBar ReReferenceSixBar(const SixBar& six_bar, const SixBarAngles& angles) {
  SixBar moved = six_bar;
  const auto place = [&](int body, const Eigen::Vector2d& point) {
    return SixBarBodyDisplacement(six_bar, angles, body).ToFixed(point);
  };
  moved.ground_pivot = six_bar.ground_pivot;
  moved.elbow = place(kSixBarForearm, six_bar.elbow);
  moved.wrist = place(kSixBarTaskBody, six_bar.wrist);
  for (int l = 0; l < 2; ++l) {
    moved.links[l].from_joint = place(kSixBarFirstLink + l, six_bar.links[l].from_joint);
    moved.links[l].to_joint = place(kSixBarFirstLink + l, six_bar.links[l].to_joint);
  }
  moved.reference_pose = SixBarTaskPose(six_bar, angles);
  return moved;
}

RefinerSummary RefineSixBar(const std::vector<PlanarPose>& poses,
                            const std::vector<double>& weights, double length, SixBarFit* fit,
                            const SixBarRefinerOptions& options) {
  const auto begin = std::chrono::steady_clock::now();
  RefinerSummary summary;
  Score(poses, weights, length, fit);
  summary.initial_rms = fit->rms_pose_error;
  summary.initial_max = fit->max_pose_error;
  // In rounds while they gain (optimizers/refiner_summary.h AnotherRound): Levenberg-Marquardt
  // descends the six-bar's flat valleys slowly.
  // The bounds' penalty raised, or held further in, while the six-bar breaks them
  // (optimizers/design_bounds.h's rounds).
  const std::vector<SixBarBound> bounds = Bounds(fit->six_bar, options.constraints, length);
  double bound_weight = kBoundFirstWeight, inset = 0.0;
  TransmissionHold hold;
  if (options.min_transmission_deg) {
    hold.held_sine = HeldTransmissionSine(*options.min_transmission_deg);
    hold.kept_sine = std::sin(std::min(90.0, *options.min_transmission_deg) * M_PI / 180.0);
    hold.weight = &bound_weight;
  }
  for (int round = 0; round < kMaxRounds + kBoundRounds; ++round) {
    const double before = fit->rms_pose_error;
    const double violation_before = BoundViolation(fit->six_bar, bounds);
    const double shortfall_before =
        TransmissionShortfall(fit->six_bar, fit->at_poses, hold.held_sine);
    bool converged = true;
    double violation = 0.0, shortfall = 0.0;  // the round's solution's (kept or not)
    RefineOnce(poses, weights, length, options, bounds, &bound_weight, &inset, hold, fit,
               &summary.iterations, &converged, &summary.message, &violation, &shortfall);
    summary.converged = converged;
    if (shortfall > kTransmissionSlack && violation <= kBoundSlack * length) {
      bound_weight *= kBoundGrowth;
      continue;
    }
    if (violation > kBoundSlack * length) {
      if (violation > kBoundShiftFrom * length) {
        bound_weight *= kBoundGrowth;
      } else {
        inset += violation;
      }
      continue;
    }
    if (violation_before <= kBoundSlack * length && shortfall_before <= kTransmissionSlack &&
        !AnotherRound(before, fit->rms_pose_error, converged)) {
      break;
    }
  }
  summary.final_rms = fit->rms_pose_error;
  summary.final_max = fit->max_pose_error;
  double total = 0.0;
  for (size_t k = 0; k < poses.size(); ++k) total += Weight(weights, k);
  summary.initial_cost = 0.5 * total * summary.initial_rms * summary.initial_rms;
  summary.final_cost = 0.5 * total * summary.final_rms * summary.final_rms;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return summary;
}

}  // namespace linkfit
