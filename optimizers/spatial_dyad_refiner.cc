#include "optimizers/spatial_dyad_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "lib/text_format.h"
#include "optimizers/exact_poses.h"
#include "optimizers/limit_hyperplane.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Ceres's projected-gradient stop, in the scaled problem (L = 1, mean weight 1): low enough
// that only function_tolerance and parameter_tolerance decide, except at an exact optimum.
constexpr double kGradientTolerance = 1e-16;

// A penalty round starts where the last one stopped, possibly at a point already stationary to
// rounding, where Levenberg-Marquardt's predicted decrease is rounding, often <= 0: an "invalid
// step". Ceres logs an error when max_num_consecutive_invalid_steps (default 5) run out; with
// this many the trust region shrinks to min_trust_region_radius first and the solve ends
// quietly, as converged. Used only when some pose is exact, so that a refinement without exact
// poses solves as it always did.
constexpr int kMaxInvalidSteps = 50;

// The poses in the centred and scaled frames: Sigma' = (Sigma - centroid) / L, E' = E / L.
struct ScaledTask {
  std::vector<Eigen::Matrix3d> rotations;
  std::vector<Eigen::Vector3d> translations;
  std::vector<double> weights;  // divided by their mean
  std::vector<bool> exact;      // one per pose
  int exact_count = 0;
};

using internal::Better;
using internal::kPenaltyGrowth;
using Fit = internal::DyadFit;

// One model refined from one start, in the scaled frames.
struct Attempt {
  SpatialDyad dyad;
  Fit fit;
  int iterations = 0;
  std::string message;  // the last Ceres message
};

// Residual of an SS dyad at one pose (R, d) with the current weight w, parameters A, c, r:
//   e = sqrt(w) (|R c + d - A| - r).
// At R c + d = A the distance is not differentiable; its subgradient 0 is used there.
class SphereResidual {
 public:
  SphereResidual(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                 const double* sqrt_weight)
      : rotation_(rotation), translation_(translation), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* fixed_pivot, const T* moving_pivot, const T* radius, T* residual) const {
    T squared_distance(0.0);
    for (int i = 0; i < 3; ++i) {
      const T offset = rotation_(i, 0) * moving_pivot[0] + rotation_(i, 1) * moving_pivot[1] +
                       rotation_(i, 2) * moving_pivot[2] + translation_[i] - fixed_pivot[i];
      squared_distance += offset * offset;
    }
    using std::sqrt;
    const T distance = squared_distance > T(0.0) ? T(sqrt(squared_distance)) : T(0.0);
    residual[0] = *sqrt_weight_ * (distance - radius[0]);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& rotation,
                                     const Eigen::Vector3d& translation,
                                     const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<SphereResidual, 1, 3, 3, 1>(
        new SphereResidual(rotation, translation, sqrt_weight));
  }

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  const double* sqrt_weight_;  // changed between penalty rounds
};

// Residual of a PS dyad at one pose (R, d) with the current weight w, parameters c, n (unit), h:
//   e = sqrt(w) (n . (R c + d) - h).
class PlaneResidual {
 public:
  PlaneResidual(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                const double* sqrt_weight)
      : rotation_(rotation), translation_(translation), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* moving_pivot, const T* plane_normal, const T* plane_offset,
                  T* residual) const {
    T height = -plane_offset[0];
    for (int i = 0; i < 3; ++i) {
      const T point = rotation_(i, 0) * moving_pivot[0] + rotation_(i, 1) * moving_pivot[1] +
                      rotation_(i, 2) * moving_pivot[2] + translation_[i];
      height += plane_normal[i] * point;
    }
    residual[0] = *sqrt_weight_ * height;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& rotation,
                                     const Eigen::Vector3d& translation,
                                     const double* sqrt_weight) {
    return new ceres::AutoDiffCostFunction<PlaneResidual, 1, 3, 3, 1>(
        new PlaneResidual(rotation, translation, sqrt_weight));
  }

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  const double* sqrt_weight_;  // changed between penalty rounds
};

bool IsFinite(const SpatialDyad& dyad) {
  if (!dyad.moving_pivot.allFinite()) return false;
  if (dyad.type == SpatialDyadType::kSS) {
    return dyad.fixed_pivot.allFinite() && std::isfinite(dyad.radius);
  }
  return dyad.plane_normal.allFinite() && std::isfinite(dyad.plane_offset) &&
         dyad.plane_normal.norm() > 0.0;
}

Fit Evaluate(const ScaledTask& task, const SpatialDyad& dyad, double exact_tolerance) {
  if (!IsFinite(dyad)) return Fit();
  return internal::EvaluateFit(task.weights, task.exact, exact_tolerance, [&](size_t j) {
    return dyad.Residual(task.rotations[j], task.translations[j]);
  });
}

// The plane an SS dyad flattens into as its radius grows: normal from A towards the weighted
// centroid of the C_j = R_j c + d_j, offset the weighted mean of n . C_j (the best offset for
// that normal and c), same moving pivot.
SpatialDyad LimitPlane(const ScaledTask& task, const SpatialDyad& sphere) {
  std::vector<Eigen::Vector3d> points(task.rotations.size());
  for (size_t j = 0; j < points.size(); ++j) {
    points[j] = task.rotations[j] * sphere.moving_pivot + task.translations[j];
  }
  const Hyperplane<3> plane =
      LimitHyperplane<3>(points, task.weights, sphere.fixed_pivot, true, Eigen::Vector3d::UnitZ());
  return SpatialDyad::PS(sphere.moving_pivot, plane.normal, plane.offset);
}

// Refines one model (SS, or PS with n on the sphere manifold) from `start`, with the penalty
// continuation on the exact poses: solve, and while an exact pose misses exact_tolerance,
// multiply the exact poses' weights by kPenaltyGrowth and solve again from where the last solve
// ended (at most max_penalty_rounds times). Returns the first round's design, or a later round
// that is Better: the first round that meets the exact poses, or the lowest cost if none does.
// Without exact poses, one solve.
Attempt RefineModel(const ScaledTask& task, const SpatialDyad& start,
                    const ceres::Solver::Options& solver_options,
                    const SpatialDyadRefinerOptions& options) {
  const bool sphere = start.type == SpatialDyadType::kSS;
  SpatialDyad dyad = start;  // the parameter blocks
  if (!sphere) dyad.plane_normal.normalize();
  std::vector<double> sqrt_weights(task.weights.size());
  double penalty = 1.0;
  const auto set_weights = [&]() {
    for (size_t j = 0; j < sqrt_weights.size(); ++j) {
      sqrt_weights[j] = std::sqrt(task.exact[j] ? penalty * task.weights[j] : task.weights[j]);
    }
  };
  set_weights();

  ceres::Problem problem;
  for (size_t j = 0; j < task.rotations.size(); ++j) {
    if (sphere) {
      problem.AddResidualBlock(
          SphereResidual::Create(task.rotations[j], task.translations[j], &sqrt_weights[j]),
          nullptr, dyad.fixed_pivot.data(), dyad.moving_pivot.data(), &dyad.radius);
    } else {
      problem.AddResidualBlock(
          PlaneResidual::Create(task.rotations[j], task.translations[j], &sqrt_weights[j]), nullptr,
          dyad.moving_pivot.data(), dyad.plane_normal.data(), &dyad.plane_offset);
    }
  }
  if (!sphere) problem.SetManifold(dyad.plane_normal.data(), new ceres::SphereManifold<3>());

  Attempt best;
  const int rounds = task.exact_count > 0 ? 1 + std::max(0, options.max_penalty_rounds) : 1;
  for (int round = 0; round < rounds; ++round) {
    if (round > 0) {
      penalty *= kPenaltyGrowth;
      set_weights();
    }
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    best.iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
    best.message = summary.message;
    SpatialDyad solved = dyad;
    if (!sphere && IsFinite(solved)) {
      solved.plane_normal.normalize();  // the manifold keeps it unit up to rounding
    }
    const Fit fit = Evaluate(task, solved, options.exact_tolerance);
    if (round == 0 || Better(fit, best.fit)) {
      best.dyad = solved;
      best.fit = fit;
    }
    if (!std::isfinite(fit.cost)) break;  // cannot continue from non-finite parameters
    if (fit.meets_exact) break;
  }
  return best;
}

}  // namespace

RefinerSummary RefineSpatialDyad(const std::vector<DualQuaternion>& poses,
                                 const std::vector<double>& weights, const std::vector<bool>& exact,
                                 double length, SpatialDyad* dyad,
                                 const SpatialDyadRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double weight_mean =
      CheckRefinerInput("RefineSpatialDyad", poses.size(), length, weights, &exact);

  RefinerSummary summary;
  const auto elapsed = [&start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (poses.empty()) {
    summary.message = "no poses: seed returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }
  if (!IsFinite(*dyad)) {
    summary.initial_cost = summary.final_cost = kInfinity;
    summary.initial_rms = summary.final_rms = kInfinity;
    summary.initial_max = summary.final_max = kInfinity;
    summary.message = "seed not finite: returned unchanged";
    summary.seconds = elapsed();
    return summary;
  }

  // Sigma' = (Sigma - centroid) / L and E' = E / L; `sigma` and `epsilon` map them back.
  ScaledTask task;
  task.rotations.resize(poses.size());
  task.translations.resize(poses.size());
  task.weights.assign(poses.size(), 1.0);
  task.exact.assign(poses.size(), false);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < poses.size(); ++j) {
    task.rotations[j] = poses[j].Rotation();
    task.translations[j] = poses[j].Translation();
    centroid += task.translations[j];
    if (!weights.empty()) task.weights[j] = weights[j] / weight_mean;
    if (!exact.empty() && exact[j]) {
      task.exact[j] = true;
      ++task.exact_count;
    }
  }
  centroid /= static_cast<double>(poses.size());
  for (Eigen::Vector3d& translation : task.translations) {
    translation = (translation - centroid) / length;
  }
  Similarity3 sigma;
  sigma.scale = length;
  sigma.translation = centroid;
  Similarity3 epsilon;
  epsilon.scale = length;
  SpatialDyad seed = TransformSpatialDyad(*dyad, sigma.Inverse(), epsilon.Inverse());
  if (seed.type == SpatialDyadType::kPS) seed.plane_normal.normalize();
  const Fit initial = Evaluate(task, seed, options.exact_tolerance);

  ceres::Solver::Options solver_options =
      RefinerSolverOptions(options.max_iterations, options.function_tolerance,
                           options.parameter_tolerance, kGradientTolerance);
  if (task.exact_count > 0) solver_options.max_num_consecutive_invalid_steps = kMaxInvalidSteps;

  // The model rule of the header comment.
  Attempt best;
  std::string note;
  if (seed.type == SpatialDyadType::kPS) {
    best = RefineModel(task, seed, solver_options, options);
  } else if (std::abs(seed.radius) > options.max_radius_ratio) {
    best = RefineModel(task, LimitPlane(task, seed), solver_options, options);
    note = "SS seed radius above max_radius_ratio L: refined as PS";
  } else {
    best = RefineModel(task, seed, solver_options, options);
    const bool sphere_ok = std::isfinite(best.fit.cost);
    const bool sphere_flat = !sphere_ok || std::abs(best.dyad.radius) > options.max_radius_ratio;
    if (sphere_flat || std::abs(seed.radius) > kBothModelsRadiusRatio ||
        std::abs(best.dyad.radius) > kBothModelsRadiusRatio) {
      const Attempt plane = RefineModel(task, LimitPlane(task, sphere_ok ? best.dyad : seed),
                                        solver_options, options);
      const int iterations = best.iterations + plane.iterations;
      // Meeting the exact poses decides first; then a sphere that ran off, or the cost.
      const bool exact_decides =
          task.exact_count > 0 && sphere_ok && plane.fit.meets_exact != best.fit.meets_exact;
      if (exact_decides) {
        note = std::string("refined as SS and PS: ") + (plane.fit.meets_exact ? "PS" : "SS") +
               " kept (meets the exact poses)";
        if (plane.fit.meets_exact) best = plane;
      } else if (sphere_flat || plane.fit.cost <= best.fit.cost) {
        note = sphere_flat ? "refined as SS and PS: SS radius ran above max_radius_ratio L, PS kept"
                           : "refined as SS and PS: PS kept (fits at least as well)";
        best = plane;
      } else {
        note = "refined as SS and PS: SS kept (fits better)";
      }
      best.iterations = iterations;
    }
  }

  summary.iterations = best.iterations;
  summary.message = best.message;
  Fit final = best.fit;
  SpatialDyadType final_type = best.dyad.type;
  if (Better(initial, best.fit)) {
    final = initial;
    final_type = seed.type;
    note = note.empty() ? "" : note + "; ";
    note += "seed kept: refinement did not improve it";
  } else {
    *dyad = TransformSpatialDyad(best.dyad, sigma, epsilon);
    summary.model_changed = best.dyad.type != seed.type;
  }
  if (task.exact_count > 0 && !final.meets_exact) {
    note += std::string(note.empty() ? "" : "; ") + "exact poses not met: max residual " +
            Format("%.3g", final.exact_max) + " L over " + std::to_string(task.exact_count) +
            " exact poses";
    const int parameters = final_type == SpatialDyadType::kSS ? 7 : 6;
    if (task.exact_count > parameters) {
      note += " (more than the dyad's " + std::to_string(parameters) +
              " parameters: generally inconsistent)";
    }
  }
  if (!note.empty()) summary.message += " [" + note + "]";

  // Back to task units: e = L e', w = mean(w) w', sum w' = n.
  const double cost_scale = weight_mean * length * length;
  const double count = static_cast<double>(poses.size());
  summary.initial_cost = cost_scale * initial.cost;
  summary.final_cost = cost_scale * final.cost;
  summary.initial_rms = length * std::sqrt(2.0 * initial.cost / count);
  summary.final_rms = length * std::sqrt(2.0 * final.cost / count);
  summary.initial_max = length * initial.max;
  summary.final_max = length * final.max;
  summary.seconds = elapsed();
  return summary;
}

}  // namespace linkfit
