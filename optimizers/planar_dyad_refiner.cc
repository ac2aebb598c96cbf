#include "optimizers/planar_dyad_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "lib/text_format.h"
#include "optimizers/design_bounds.h"
#include "optimizers/exact_poses.h"
#include "optimizers/limit_hyperplane.h"
#include "optimizers/nested_model_test.h"
#include "optimizers/planar_dyad_blocks.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Ceres's projected-gradient stop, in the scaled problem (L = 1, mean weight 1): low enough
// that only function_tolerance and parameter_tolerance decide, except at an exact optimum.
constexpr double kGradientTolerance = 1e-16;

// At a stationary point Levenberg-Marquardt's predicted decrease is rounding, often <= 0: an
// "invalid step". Ceres logs an error when max_num_consecutive_invalid_steps (default 5) run
// out; with this many the trust region shrinks to min_trust_region_radius first (after about 15
// steps) and the solve ends quietly, as converged.
constexpr int kMaxInvalidSteps = 50;

// The poses in the centred and scaled frames: Sigma' = (Sigma - centroid) / L, E' = E / L.
struct ScaledTask {
  std::vector<Eigen::Matrix2d> rotations;
  std::vector<Eigen::Vector2d> origins;
  std::vector<double> weights;  // divided by their mean
  std::vector<bool> exact;      // one per pose
  int exact_count = 0;
  ScaledBounds bounds;  // the design bounds of one dyad (design_bounds.h)
};

using internal::Better;
using internal::kPenaltyGrowth;
using Fit = internal::DyadFit;

// One model refined from one start (the start included: an attempt never ends worse than it
// began), in the scaled frames.
struct Attempt {
  PlanarDyad dyad;
  Fit fit;
  int iterations = 0;
  bool improved = false;  // some solve beat the start
  std::string message;    // the last Ceres message
};

// Residuals of an RR dyad at every pose j (R_j, d_j) with the current weights w_j; parameters
// F (Sigma), M (E), r:
//   e_j = sqrt(w_j) (|R_j M + d_j - F| - r).
// Where R_j M + d_j = F the distance is not differentiable; its subgradient 0 is used there.
class CircleResiduals {
 public:
  CircleResiduals(const ScaledTask* task, const std::vector<double>* sqrt_weights)
      : task_(task), sqrt_weights_(sqrt_weights) {}

  template <typename T>
  bool operator()(const T* fixed_pivot, const T* moving_pivot, const T* radius,
                  T* residuals) const {
    using std::sqrt;
    for (size_t j = 0; j < task_->rotations.size(); ++j) {
      const Eigen::Matrix2d& rotation = task_->rotations[j];
      const Eigen::Vector2d& origin = task_->origins[j];
      const T x = rotation(0, 0) * moving_pivot[0] + rotation(0, 1) * moving_pivot[1] + origin[0] -
                  fixed_pivot[0];
      const T y = rotation(1, 0) * moving_pivot[0] + rotation(1, 1) * moving_pivot[1] + origin[1] -
                  fixed_pivot[1];
      const T squared_distance = x * x + y * y;
      const T distance = squared_distance > T(0.0) ? T(sqrt(squared_distance)) : T(0.0);
      residuals[j] = (*sqrt_weights_)[j] * (distance - radius[0]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const ScaledTask* task,
                                     const std::vector<double>* sqrt_weights) {
    return new ceres::AutoDiffCostFunction<CircleResiduals, ceres::DYNAMIC, 2, 2, 1>(
        new CircleResiduals(task, sqrt_weights), static_cast<int>(task->rotations.size()));
  }

 private:
  const ScaledTask* task_;
  const std::vector<double>* sqrt_weights_;
};

// Residuals of a PR dyad at every pose j (R_j, d_j) with the current weights w_j; parameters
// M (E), the unit normal n of the line in Sigma, its offset h (the line n . X = h):
//   e_j = sqrt(w_j) (n . (R_j M + d_j) - h).
class FixedLineResiduals {
 public:
  FixedLineResiduals(const ScaledTask* task, const std::vector<double>* sqrt_weights)
      : task_(task), sqrt_weights_(sqrt_weights) {}

  template <typename T>
  bool operator()(const T* moving_pivot, const T* line_normal, const T* line_offset,
                  T* residuals) const {
    for (size_t j = 0; j < task_->rotations.size(); ++j) {
      const Eigen::Matrix2d& rotation = task_->rotations[j];
      const Eigen::Vector2d& origin = task_->origins[j];
      const T x = rotation(0, 0) * moving_pivot[0] + rotation(0, 1) * moving_pivot[1] + origin[0];
      const T y = rotation(1, 0) * moving_pivot[0] + rotation(1, 1) * moving_pivot[1] + origin[1];
      residuals[j] =
          (*sqrt_weights_)[j] * (line_normal[0] * x + line_normal[1] * y - line_offset[0]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const ScaledTask* task,
                                     const std::vector<double>* sqrt_weights) {
    return new ceres::AutoDiffCostFunction<FixedLineResiduals, ceres::DYNAMIC, 2, 2, 1>(
        new FixedLineResiduals(task, sqrt_weights), static_cast<int>(task->rotations.size()));
  }

 private:
  const ScaledTask* task_;
  const std::vector<double>* sqrt_weights_;
};

// Residuals of an RP dyad at every pose j (R_j, d_j) with the current weights w_j; parameters
// F (Sigma), the unit normal n of the line in E, its offset h (the line n . x = h in E):
//   e_j = sqrt(w_j) (n . (R_j^T (F - d_j)) - h).
class MovingLineResiduals {
 public:
  MovingLineResiduals(const ScaledTask* task, const std::vector<double>* sqrt_weights)
      : task_(task), sqrt_weights_(sqrt_weights) {}

  template <typename T>
  bool operator()(const T* fixed_pivot, const T* line_normal, const T* line_offset,
                  T* residuals) const {
    for (size_t j = 0; j < task_->rotations.size(); ++j) {
      const Eigen::Matrix2d& rotation = task_->rotations[j];
      const Eigen::Vector2d& origin = task_->origins[j];
      const T dx = fixed_pivot[0] - origin[0];
      const T dy = fixed_pivot[1] - origin[1];
      const T x = rotation(0, 0) * dx + rotation(1, 0) * dy;  // R^T (F - d)
      const T y = rotation(0, 1) * dx + rotation(1, 1) * dy;
      residuals[j] =
          (*sqrt_weights_)[j] * (line_normal[0] * x + line_normal[1] * y - line_offset[0]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const ScaledTask* task,
                                     const std::vector<double>* sqrt_weights) {
    return new ceres::AutoDiffCostFunction<MovingLineResiduals, ceres::DYNAMIC, 2, 2, 1>(
        new MovingLineResiduals(task, sqrt_weights), static_cast<int>(task->rotations.size()));
  }

 private:
  const ScaledTask* task_;
  const std::vector<double>* sqrt_weights_;
};

// The design bounds of one dyad (design_bounds.h, DyadBoundGeometry):
// sqrt(mu) max(0, g), mu read through `sqrt_weight`; blocks as Parameters below.
class DyadBoundsResidual {
 public:
  DyadBoundsResidual(DyadType type, const ScaledBounds* bounds, const double* sqrt_weight)
      : type_(type), bounds_(bounds), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* first, const T* second, const T* third, T* residual) const {
    const BoundGeometry<T> geometry = DyadBoundGeometry(type_, first, second, third);
    BoundPenalties(*bounds_, geometry, *sqrt_weight_, residual);
    return true;
  }

  static ceres::CostFunction* Create(DyadType type, const ScaledBounds* bounds,
                                     const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<DyadBoundsResidual, kBoundResiduals, 2, 2, 1>(
        new DyadBoundsResidual(type, bounds, sqrt_weight));
  }

 private:
  DyadType type_;
  const ScaledBounds* bounds_;
  const double* sqrt_weight_;
};

// The solver's parameter blocks of a dyad: RR (F, M, r); PR (M, n, h); RP (F, n, h), with n the
// unit normal of the line and h its offset, n . X = h. The line of a PlanarDyad (point p,
// direction u) has n = (-u_y, u_x), the normal its signed residual is measured along, and
// h = n . p; back, p = h n and u = (n_y, -n_x): the same line with the same residual sign.
struct Parameters {
  DyadType type = DyadType::kRR;
  Eigen::Vector2d first = Eigen::Vector2d::Zero();   // F (RR, RP) or M (PR)
  Eigen::Vector2d second = Eigen::Vector2d::Zero();  // M (RR) or n (PR, RP)
  double third = 0.0;                                // r (RR) or h (PR, RP)
};

Parameters ToParameters(const PlanarDyad& dyad) {
  Parameters p;
  p.type = dyad.type;
  if (dyad.type == DyadType::kRR) {
    p.first = dyad.fixed_pivot;
    p.second = dyad.moving_pivot;
    p.third = dyad.radius;
    return p;
  }
  p.first = dyad.type == DyadType::kPR ? dyad.moving_pivot : dyad.fixed_pivot;
  const Eigen::Vector2d direction = dyad.line_direction.normalized();
  p.second = Eigen::Vector2d(-direction.y(), direction.x());
  p.third = p.second.dot(dyad.line_point);
  return p;
}

PlanarDyad FromParameters(const Parameters& p) {
  if (p.type == DyadType::kRR) return PlanarDyad::RR(p.first, p.second, p.third);
  const Eigen::Vector2d normal = p.second.normalized();  // unit up to rounding on the manifold
  const Eigen::Vector2d direction(normal.y(), -normal.x());
  return p.type == DyadType::kPR ? PlanarDyad::PR(p.first, p.third * normal, direction)
                                 : PlanarDyad::RP(p.first, p.third * normal, direction);
}

// The largest violation of the design bounds by `p` (scaled units).
double Violation(const ScaledTask& task, const Parameters& p) {
  return BoundViolation(task.bounds,
                        DyadBoundGeometry(p.type, p.first.data(), p.second.data(), &p.third));
}

Fit Evaluate(const ScaledTask& task, const PlanarDyad& dyad, double exact_tolerance) {
  if (!dyad.AllFinite()) return Fit();
  Fit fit = internal::EvaluateFit(task.weights, task.exact, exact_tolerance, [&](size_t j) {
    return dyad.Residual(task.rotations[j], task.origins[j]);
  });
  fit.keeps_bounds = Violation(task, ToParameters(dyad)) <= kBoundSlack;
  return fit;
}

// Refines one model from `start`, with the penalty continuation on the exact poses: solve,
// and while an exact pose misses exact_tolerance, multiply the exact poses' weights by
// kPenaltyGrowth and solve again from where the last solve ended (at most max_penalty_rounds
// times). Returns the best design by Better over the start and every round: the first round
// that meets the exact poses, or the lowest cost if none does.
Attempt RefineModel(const ScaledTask& task, const PlanarDyad& start,
                    const ceres::Solver::Options& solver_options,
                    const PlanarDyadRefinerOptions& options) {
  Attempt best;
  best.dyad = start;
  best.fit = Evaluate(task, start, options.exact_tolerance);
  if (!start.AllFinite()) {
    best.message = "start not finite";
    return best;
  }

  Parameters p = ToParameters(start);
  std::vector<double> sqrt_weights(task.weights.size());
  double penalty = 1.0;
  const auto set_weights = [&]() {
    for (size_t j = 0; j < sqrt_weights.size(); ++j) {
      sqrt_weights[j] = std::sqrt(task.exact[j] ? penalty * task.weights[j] : task.weights[j]);
    }
  };
  set_weights();

  ceres::Problem problem;
  double* first = p.first.data();
  double* second = p.second.data();
  double* third = &p.third;
  switch (p.type) {
    case DyadType::kRR:
      problem.AddResidualBlock(CircleResiduals::Create(&task, &sqrt_weights), nullptr, first,
                               second, third);
      break;
    case DyadType::kPR:
      problem.AddResidualBlock(FixedLineResiduals::Create(&task, &sqrt_weights), nullptr, first,
                               second, third);
      problem.SetManifold(second, UnitCircle());
      break;
    case DyadType::kRP:
      problem.AddResidualBlock(MovingLineResiduals::Create(&task, &sqrt_weights), nullptr, first,
                               second, third);
      problem.SetManifold(second, UnitCircle());
      break;
  }
  double bounds_weight = std::sqrt(kBoundFirstWeight);
  ScaledBounds held = task.bounds;  // the bounds as the penalty holds them (NextBoundRound)
  problem.AddResidualBlock(DyadBoundsResidual::Create(p.type, &held, &bounds_weight), nullptr,
                           first, second, third);

  // The exact poses' penalty rounds, then the design bounds' (design_bounds.h).
  const int rounds = task.exact_count > 0 ? 1 + std::max(0, options.max_penalty_rounds) : 1;
  for (int round = 0; round < rounds + kBoundRounds; ++round) {
    if (round >= rounds) {
      const double violation = Violation(task, p);
      if (violation <= kBoundSlack) break;
      NextBoundRound(violation, &held, &bounds_weight);
    } else if (round > 0) {
      penalty *= kPenaltyGrowth;
      set_weights();
    }
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    best.iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
    best.message = summary.message;
    const PlanarDyad dyad = FromParameters(p);
    const Fit fit = Evaluate(task, dyad, options.exact_tolerance);
    if (!std::isfinite(fit.cost)) break;  // cannot continue from non-finite parameters
    if (Better(fit, best.fit) || (!best.improved && !Better(best.fit, fit))) {
      best.dyad = dyad;
      best.fit = fit;
      best.improved = true;
    }
    if (round < rounds && fit.meets_exact) round = rounds - 1;  // on to the bounds' rounds
  }
  return best;
}

// The PR limit of an RR dyad whose fixed pivot runs off to infinity: the line in Sigma normal
// to the direction from F to the weighted mean of the moving pivot's positions
// P_j = R_j M + d_j, at the weighted mean of n . P_j (the best offset for that normal); same M.
PlanarDyad LimitLineInFixed(const ScaledTask& task, const PlanarDyad& circle) {
  std::vector<Eigen::Vector2d> points(task.rotations.size());
  for (size_t j = 0; j < points.size(); ++j) {
    points[j] = task.rotations[j] * circle.moving_pivot + task.origins[j];
  }
  const Hyperplane<2> line =
      LimitHyperplane<2>(points, task.weights, circle.fixed_pivot, true, Eigen::Vector2d::UnitY());
  return PlanarDyad::PR(circle.moving_pivot, line.offset * line.normal,
                        Eigen::Vector2d(line.normal.y(), -line.normal.x()));
}

// The RP limit of an RR dyad whose moving pivot runs off to infinity in E: the fixed pivot seen
// from E, e_j = R_j^T (F - d_j), stays on the line of E normal to the direction from the
// weighted mean of the e_j to M, at the weighted mean of n . e_j; same F.
PlanarDyad LimitLineInMoving(const ScaledTask& task, const PlanarDyad& circle) {
  std::vector<Eigen::Vector2d> seen(task.rotations.size());
  for (size_t j = 0; j < seen.size(); ++j) {
    seen[j] = task.rotations[j].transpose() * (circle.fixed_pivot - task.origins[j]);
  }
  const Hyperplane<2> line =
      LimitHyperplane<2>(seen, task.weights, circle.moving_pivot, false, Eigen::Vector2d::UnitY());
  return PlanarDyad::RP(circle.fixed_pivot, line.offset * line.normal,
                        Eigen::Vector2d(line.normal.y(), -line.normal.x()));
}

// Whether a slider (4 parameters) suffices against the circle (RR, 5) on n poses: a slider that
// meets the exact poses when the circle does not, or the reverse, decides; otherwise the slider
// is kept unless the circle's cost is significantly lower by the nested F test at 5 %,
// (cost_slider - cost_RR) / (cost_RR / m) <= F_0.95(1, m), m = n - 5; with m < 1 or
// cost_RR = 0, unless it is lower at all.
bool SliderSuffices(const Fit& slider, const Fit& circle, int n) {
  if (!std::isfinite(slider.cost)) return false;
  if (!std::isfinite(circle.cost)) return true;
  if (slider.meets_exact != circle.meets_exact) return slider.meets_exact;
  return SimplerModelSuffices(slider.cost, circle.cost, n - 5);
}

}  // namespace

RefinerSummary RefinePlanarDyad(const std::vector<PlanarPose>& poses,
                                const std::vector<double>& weights, const std::vector<bool>& exact,
                                double length, PlanarDyad* dyad,
                                const PlanarDyadRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double weight_mean =
      CheckRefinerInput("RefinePlanarDyad", poses.size(), length, weights, &exact);

  RefinerSummary summary;
  const auto elapsed = [&start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (poses.empty()) {
    summary.message = "no poses: seed returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }
  if (!dyad->AllFinite()) {
    summary.initial_cost = summary.final_cost = kInfinity;
    summary.initial_rms = summary.final_rms = kInfinity;
    summary.initial_max = summary.final_max = kInfinity;
    summary.message = "seed not finite (or a line without direction): returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }

  // Sigma' = (Sigma - centroid) / L and E' = E / L; `sigma` and `epsilon` map them back.
  const int n = static_cast<int>(poses.size());
  ScaledTask task;
  task.rotations.resize(n);
  task.origins.resize(n);
  task.weights.assign(n, 1.0);
  task.exact.assign(n, false);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int j = 0; j < n; ++j) {
    task.rotations[j] = Rotation2(poses[j].theta);
    task.origins[j] = poses[j].origin_in_fixed;
    centroid += poses[j].origin_in_fixed;
    if (!weights.empty()) task.weights[j] = weights[j] / weight_mean;
    if (!exact.empty() && exact[j]) {
      task.exact[j] = true;
      ++task.exact_count;
    }
  }
  centroid /= static_cast<double>(n);
  for (Eigen::Vector2d& origin : task.origins) origin = (origin - centroid) / length;
  Similarity2 sigma;
  sigma.scale = length;
  sigma.translation = centroid;
  Similarity2 epsilon;
  epsilon.scale = length;
  task.bounds = ScaleBounds(options.constraints, length, sigma.Inverse(), epsilon.Inverse());
  PlanarDyad seed = TransformDyad(*dyad, sigma.Inverse(), epsilon.Inverse());
  if (seed.type != DyadType::kRR) seed.line_direction.normalize();
  const Fit initial = Evaluate(task, seed, options.exact_tolerance);

  ceres::Solver::Options solver_options =
      RefinerSolverOptions(options.max_iterations, options.function_tolerance,
                           options.parameter_tolerance, kGradientTolerance);
  solver_options.max_num_consecutive_invalid_steps = kMaxInvalidSteps;

  // A slider seed stays a slider. An RR seed is refined as RR; an RR (the seed or the refined
  // one) with a radius beyond slider_radius_ratio L is also refined as its PR limit, and as its
  // RP limit when its moving pivot is beyond slider_radius_ratio L from E's origin; the best
  // slider is kept if it suffices against the RR (SliderSuffices).
  Attempt best = RefineModel(task, seed, solver_options, options);
  int iterations = best.iterations;
  std::string note;
  if (seed.type == DyadType::kRR) {
    const double ratio = options.slider_radius_ratio;
    // The limits of the refined RR (no worse than the seed, a better start) when its radius is
    // large, else of the seed when the seed's is.
    const bool refined_large = std::abs(best.dyad.radius) > ratio;
    const PlanarDyad& circle = refined_large ? best.dyad : seed;
    Attempt slider;
    bool have_slider = false;
    std::string tried;
    if (refined_large || std::abs(seed.radius) > ratio) {
      std::vector<PlanarDyad> limits = {LimitLineInFixed(task, circle)};
      if (circle.moving_pivot.norm() > ratio) limits.push_back(LimitLineInMoving(task, circle));
      for (const PlanarDyad& limit : limits) {
        const Attempt attempt = RefineModel(task, limit, solver_options, options);
        iterations += attempt.iterations;
        tried += std::string(" and ") + DyadTypeName(limit.type);
        if (!have_slider || Better(attempt.fit, slider.fit)) {
          slider = attempt;
          have_slider = true;
        }
      }
    }
    if (have_slider) {
      const bool suffices = SliderSuffices(slider.fit, best.fit, n);
      note = "large radius: refined as RR" + tried + ", " +
             (suffices ? std::string(DyadTypeName(slider.dyad.type)) +
                             " kept (the circle does not fit significantly better)"
                       : std::string("RR kept (fits significantly better, F test at 5 %)"));
      if (suffices) best = slider;
    }
  }
  summary.iterations = iterations;
  summary.message = best.message;

  // Never worse than the seed: within a type by Better; a slider that replaced an RR seed was
  // compared with the refined RR, itself no worse than the seed, by SliderSuffices.
  Fit final = best.fit;
  const bool changed = best.dyad.type != seed.type;
  if (!changed && !best.improved) {
    final = initial;
    note += std::string(note.empty() ? "" : "; ") + "seed kept: refinement did not improve it";
  } else {
    *dyad = TransformDyad(best.dyad, sigma, epsilon);
    summary.model_changed = changed;
  }
  if (task.exact_count > 0 && !final.meets_exact) {
    note += std::string(note.empty() ? "" : "; ") + "exact poses not met: max residual " +
            Format("%.3g", final.exact_max) + " L over " + std::to_string(task.exact_count) +
            " exact poses";
    const int parameters = best.dyad.type == DyadType::kRR ? 5 : 4;
    if (task.exact_count > parameters) {
      note += " (more than the dyad's " + std::to_string(parameters) +
              " parameters: generally inconsistent)";
    }
  }
  if (!note.empty()) summary.message += " [" + note + "]";

  // Back to task units: e = L e', w = mean(w) w', sum w' = n.
  const double cost_scale = weight_mean * length * length;
  summary.initial_cost = cost_scale * initial.cost;
  summary.final_cost = cost_scale * final.cost;
  summary.initial_rms = length * std::sqrt(2.0 * initial.cost / n);
  summary.final_rms = length * std::sqrt(2.0 * final.cost / n);
  summary.initial_max = length * initial.max;
  summary.final_max = length * final.max;
  summary.seconds = elapsed();
  return summary;
}

}  // namespace linkfit
