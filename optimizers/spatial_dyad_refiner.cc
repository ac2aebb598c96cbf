#include "optimizers/spatial_dyad_refiner.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "optimizers/limit_hyperplane.h"
#include "optimizers/refiner_input.h"
#include "optimizers/solver_options.h"

namespace linkfit {
namespace {

// Ceres's projected-gradient stop, in the scaled problem (L = 1, mean weight 1): low enough
// that only function_tolerance and parameter_tolerance decide, except at an exact optimum.
constexpr double kGradientTolerance = 1e-16;

// The poses in the centred and scaled frames: Sigma' = (Sigma - centroid) / L, E' = E / L.
struct ScaledTask {
  std::vector<Eigen::Matrix3d> rotations;
  std::vector<Eigen::Vector3d> translations;
  std::vector<double> weights;  // divided by their mean
};

// Weighted fit of a dyad in the scaled frames.
struct Fit {
  double cost = 0.0;  // 1/2 sum w' e'^2; infinity if not finite
  double max = 0.0;   // max |e'|
};

// One model refined from one start, in the scaled frames.
struct Attempt {
  SpatialDyad dyad;
  Fit fit;
  int iterations = 0;
  std::string message;
};

// Residual of an SS dyad at one pose (R, d) with weight w, parameters A, c, r:
//   e = sqrt(w) (|R c + d - A| - r).
// At R c + d = A the distance is not differentiable; its subgradient 0 is used there.
class SphereResidual {
 public:
  SphereResidual(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                 double sqrt_weight)
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
    residual[0] = sqrt_weight_ * (distance - radius[0]);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& rotation,
                                     const Eigen::Vector3d& translation, double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<SphereResidual, 1, 3, 3, 1>(
        new SphereResidual(rotation, translation, sqrt_weight));
  }

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  double sqrt_weight_;
};

// Residual of a PS dyad at one pose (R, d) with weight w, parameters c, n (unit), h:
//   e = sqrt(w) (n . (R c + d) - h).
class PlaneResidual {
 public:
  PlaneResidual(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                double sqrt_weight)
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
    residual[0] = sqrt_weight_ * height;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& rotation,
                                     const Eigen::Vector3d& translation, double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<PlaneResidual, 1, 3, 3, 1>(
        new PlaneResidual(rotation, translation, sqrt_weight));
  }

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  double sqrt_weight_;
};

bool IsFinite(const SpatialDyad& dyad) {
  if (!dyad.moving_pivot.allFinite()) return false;
  if (dyad.type == SpatialDyadType::kSS) {
    return dyad.fixed_pivot.allFinite() && std::isfinite(dyad.radius);
  }
  return dyad.plane_normal.allFinite() && std::isfinite(dyad.plane_offset) &&
         dyad.plane_normal.norm() > 0.0;
}

Fit Evaluate(const ScaledTask& task, const SpatialDyad& dyad) {
  Fit fit;
  for (size_t j = 0; j < task.rotations.size(); ++j) {
    const double residual = dyad.Residual(task.rotations[j], task.translations[j]);
    fit.cost += 0.5 * task.weights[j] * residual * residual;
    fit.max = std::max(fit.max, std::abs(residual));
  }
  if (!std::isfinite(fit.cost) || !std::isfinite(fit.max)) {
    fit.cost = fit.max = std::numeric_limits<double>::infinity();
  }
  return fit;
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

Attempt RefineSphere(const ScaledTask& task, const SpatialDyad& seed,
                     const ceres::Solver::Options& solver_options) {
  Attempt attempt;
  attempt.dyad = seed;
  ceres::Problem problem;
  double* fixed_pivot = attempt.dyad.fixed_pivot.data();
  double* moving_pivot = attempt.dyad.moving_pivot.data();
  double* radius = &attempt.dyad.radius;
  for (size_t j = 0; j < task.rotations.size(); ++j) {
    problem.AddResidualBlock(
        SphereResidual::Create(task.rotations[j], task.translations[j], std::sqrt(task.weights[j])),
        nullptr, fixed_pivot, moving_pivot, radius);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  attempt.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  attempt.message = summary.message;
  attempt.fit = IsFinite(attempt.dyad) ? Evaluate(task, attempt.dyad)
                                       : Fit{std::numeric_limits<double>::infinity(),
                                             std::numeric_limits<double>::infinity()};
  return attempt;
}

Attempt RefinePlane(const ScaledTask& task, const SpatialDyad& seed,
                    const ceres::Solver::Options& solver_options) {
  Attempt attempt;
  attempt.dyad = seed;
  attempt.dyad.plane_normal.normalize();
  ceres::Problem problem;
  double* moving_pivot = attempt.dyad.moving_pivot.data();
  double* plane_normal = attempt.dyad.plane_normal.data();
  double* plane_offset = &attempt.dyad.plane_offset;
  for (size_t j = 0; j < task.rotations.size(); ++j) {
    problem.AddResidualBlock(
        PlaneResidual::Create(task.rotations[j], task.translations[j], std::sqrt(task.weights[j])),
        nullptr, moving_pivot, plane_normal, plane_offset);
  }
  problem.SetManifold(plane_normal, new ceres::SphereManifold<3>());
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  attempt.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  attempt.message = summary.message;
  if (IsFinite(attempt.dyad)) {
    attempt.dyad.plane_normal.normalize();  // the manifold keeps it unit up to rounding
    attempt.fit = Evaluate(task, attempt.dyad);
  } else {
    attempt.fit.cost = attempt.fit.max = std::numeric_limits<double>::infinity();
  }
  return attempt;
}

}  // namespace

RefinerSummary RefineSpatialDyad(const std::vector<DualQuaternion>& poses,
                                 const std::vector<double>& weights, double length,
                                 SpatialDyad* dyad, const SpatialDyadRefinerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double weight_mean = CheckRefinerInput("RefineSpatialDyad", poses.size(), length, weights);

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
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
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
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < poses.size(); ++j) {
    task.rotations[j] = poses[j].Rotation();
    task.translations[j] = poses[j].Translation();
    centroid += task.translations[j];
    if (!weights.empty()) task.weights[j] = weights[j] / weight_mean;
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
  const Fit initial = Evaluate(task, seed);

  ceres::Solver::Options solver_options =
      RefinerSolverOptions(options.max_iterations, options.function_tolerance,
                           options.parameter_tolerance, kGradientTolerance);

  // The model rule of the header comment.
  Attempt best;
  std::string note;
  if (seed.type == SpatialDyadType::kPS) {
    best = RefinePlane(task, seed, solver_options);
  } else if (std::abs(seed.radius) > options.max_radius_ratio) {
    best = RefinePlane(task, LimitPlane(task, seed), solver_options);
    note = "SS seed radius above max_radius_ratio L: refined as PS";
  } else {
    best = RefineSphere(task, seed, solver_options);
    const bool sphere_ok = std::isfinite(best.fit.cost);
    const bool sphere_flat = !sphere_ok || std::abs(best.dyad.radius) > options.max_radius_ratio;
    if (sphere_flat || std::abs(seed.radius) > kBothModelsRadiusRatio ||
        std::abs(best.dyad.radius) > kBothModelsRadiusRatio) {
      const Attempt plane =
          RefinePlane(task, LimitPlane(task, sphere_ok ? best.dyad : seed), solver_options);
      const int iterations = best.iterations + plane.iterations;
      if (sphere_flat || plane.fit.cost <= best.fit.cost) {
        best = plane;
        note = sphere_flat ? "refined as SS and PS: SS radius ran above max_radius_ratio L, PS kept"
                           : "refined as SS and PS: PS kept (fits at least as well)";
      } else {
        note = "refined as SS and PS: SS kept (fits better)";
      }
      best.iterations = iterations;
    }
  }

  summary.iterations = best.iterations;
  summary.message = best.message;
  Fit final = best.fit;
  if (!(best.fit.cost <= initial.cost)) {
    final = initial;
    note = note.empty() ? "" : note + "; ";
    note += "seed kept: refinement did not lower the cost";
  } else {
    *dyad = TransformSpatialDyad(best.dyad, sigma, epsilon);
    summary.model_changed = best.dyad.type != seed.type;
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
