#include "optimizers/task_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace linkfit {

namespace {

// A refined SS dyad whose radius (or moving point's distance from E's origin) exceeds this
// times L is also refined as its plane limit, PS (or SP): see PreferPlaneLimits.
constexpr double kFarMovingPoint = 10.0;

// The SP limit of an SS dyad whose moving point runs off to infinity: the center A stays on
// the plane of E normal to the moving point's direction (as seen from the points e_j where E
// sees A), through their weighted mean; returned as the PS dyad of the inverted motion.
SpatialDyad LimitPlaneInMoving(const SpatialDyad& dyad, const Task& task) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double weight_sum = 0.0;
  std::vector<Eigen::Vector3d> seen;
  for (size_t j = 0; j < task.spatial_poses.size(); ++j) {
    const DualQuaternion& pose = task.spatial_poses[j];
    seen.push_back(pose.Rotation().transpose() * (dyad.fixed_pivot - pose.Translation()));
    const double weight = task.pose_weights.empty() ? 1.0 : task.pose_weights[j];
    mean += weight * seen.back();
    weight_sum += weight;
  }
  mean /= weight_sum;
  const Eigen::Vector3d normal = (dyad.moving_pivot - mean).normalized();
  return SpatialDyad::PS(dyad.fixed_pivot, normal, normal.dot(mean));
}

// The PS limit of an SS dyad whose center runs off to infinity: the plane normal to the
// center's direction, through the weighted mean of the moving point's positions.
SpatialDyad LimitPlaneInFixed(const SpatialDyad& dyad, const Task& task) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double weight_sum = 0.0;
  for (size_t j = 0; j < task.spatial_poses.size(); ++j) {
    const double weight = task.pose_weights.empty() ? 1.0 : task.pose_weights[j];
    mean += weight * task.spatial_poses[j].ToFixed(dyad.moving_pivot);
    weight_sum += weight;
  }
  mean /= weight_sum;
  const Eigen::Vector3d normal = (mean - dyad.fixed_pivot).normalized();
  return SpatialDyad::PS(dyad.moving_pivot, normal, normal.dot(mean));
}

// The 95th percentile of the F(1, m) distribution: the square of Student's t quantile, from
// its Cornish-Fisher expansion about the normal quantile (within 4 % for m >= 3).
double FQuantile95(double m) {
  const double z = 1.959963984540054;
  const double z3 = z * z * z, z5 = z3 * z * z;
  const double t = z + (z3 + z) / (4.0 * m) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * m * m);
  return t * t;
}

// The nested-model test between a plane (6 parameters) and a sphere (7) fitted to n poses:
// keep the simpler plane unless the sphere's cost is significantly lower (F test at 5 %).
bool PlaneSuffices(double plane_cost, double sphere_cost, int n) {
  const double m = n - 7.0;
  if (m < 1.0 || !(sphere_cost > 0.0)) return plane_cost <= sphere_cost;
  return (plane_cost - sphere_cost) / (sphere_cost / m) <= FQuantile95(m);
}

// A refined sphere far out in Sigma (radius) or in E (moving point) is nearly a plane: refine
// those limits too (PS; SP as a PS dyad of the inverted motion) and keep the plane that
// suffices (PlaneSuffices) with the lower cost. A slider is reported as a slider.
void PreferPlaneLimits(const Task& task, const std::vector<DualQuaternion>& inverted, double length,
                       const SpatialDyadRefinerOptions& options, SpatialDyad* dyad,
                       RefinerSummary* summary) {
  const int n = static_cast<int>(task.spatial_poses.size());
  const SpatialDyad sphere = *dyad;
  const double sphere_cost = summary->final_cost;
  double best_cost = std::numeric_limits<double>::infinity();
  const auto consider = [&](const SpatialDyad& plane, const RefinerSummary& plane_summary) {
    if (!PlaneSuffices(plane_summary.final_cost, sphere_cost, n) ||
        !(plane_summary.final_cost < best_cost)) {
      return;
    }
    best_cost = plane_summary.final_cost;
    *dyad = plane;
    summary->final_cost = plane_summary.final_cost;
    summary->final_rms = plane_summary.final_rms;
    summary->final_max = plane_summary.final_max;
    summary->model_changed = true;
  };
  if (sphere.radius > kFarMovingPoint * length) {
    SpatialDyad plane = LimitPlaneInFixed(sphere, task);
    const RefinerSummary plane_summary =
        RefineSpatialDyad(task.spatial_poses, task.pose_weights, length, &plane, options);
    if (plane.type == SpatialDyadType::kPS) consider(plane, plane_summary);
  }
  if (sphere.moving_pivot.norm() > kFarMovingPoint * length) {
    SpatialDyad flipped = LimitPlaneInMoving(sphere, task);
    const RefinerSummary plane_summary =
        RefineSpatialDyad(inverted, task.pose_weights, length, &flipped, options);
    if (flipped.type == SpatialDyadType::kPS) {
      consider(SpatialDyad::SP(flipped.moving_pivot, flipped.plane_normal, flipped.plane_offset),
               plane_summary);
    }
  }
}

// Drops reports whose dyad repeats an earlier one (two seeds refined to one optimum).
void DropRepeats(double length, std::vector<SpatialDyadReport>* dyads) {
  std::vector<SpatialDyadReport> kept;
  for (const SpatialDyadReport& report : *dyads) {
    const SpatialDyad& d = report.dyad;
    bool repeat = false;
    for (const SpatialDyadReport& other : kept) {
      const SpatialDyad& e = other.dyad;
      if (e.type != d.type) continue;
      const double size = std::max({length, d.moving_pivot.norm(), d.fixed_pivot.norm()});
      double difference = std::max((e.moving_pivot - d.moving_pivot).norm(),
                                   (e.fixed_pivot - d.fixed_pivot).norm());
      if (d.type == SpatialDyadType::kSS) {
        difference = std::max(difference, std::abs(e.radius - d.radius));
      } else {
        difference = std::max({difference, length * (e.plane_normal - d.plane_normal).norm(),
                               std::abs(e.plane_offset - d.plane_offset)});
      }
      repeat |= difference <= 1e-7 * size;
    }
    if (!repeat) kept.push_back(report);
  }
  *dyads = std::move(kept);
}

}  // namespace

SpatialMotionResult SolveSpatialTask(const Task& task, const TaskSolverOptions& options) {
  SpatialMotionResult result = SolveSpatialMotion(task, options.spatial);
  if (result.model == "spatial" && result.method == "least-squares" &&
      task.spatial_poses.size() > 7 && task.effort != Effort::kFast) {
    const auto start = std::chrono::steady_clock::now();
    // An SP dyad of the motion is a PS dyad of the inverted motion (E and Sigma exchanged).
    std::vector<DualQuaternion> inverted;
    for (const DualQuaternion& pose : task.spatial_poses) inverted.push_back(pose.Inverse());
    for (SpatialDyadReport& report : result.dyads) {
      SpatialDyad dyad = report.dyad;
      RefinerSummary summary;
      if (dyad.type == SpatialDyadType::kSP) {
        SpatialDyad flipped =
            SpatialDyad::PS(dyad.fixed_pivot, dyad.plane_normal, dyad.plane_offset);
        summary =
            RefineSpatialDyad(inverted, task.pose_weights, result.scale, &flipped, options.refiner);
        dyad =
            flipped.type == SpatialDyadType::kPS
                ? SpatialDyad::SP(flipped.moving_pivot, flipped.plane_normal, flipped.plane_offset)
                : SpatialDyad::SS(flipped.moving_pivot, flipped.fixed_pivot, flipped.radius);
      } else {
        summary = RefineSpatialDyad(task.spatial_poses, task.pose_weights, result.scale, &dyad,
                                    options.refiner);
        if (dyad.type == SpatialDyadType::kSS) {
          PreferPlaneLimits(task, inverted, result.scale, options.refiner, &dyad, &summary);
        }
      }
      report.seed_max_residual = summary.initial_max;
      report.seed_rms_residual = summary.initial_rms;
      report.rms_residual = summary.final_rms;
      report.dyad = dyad;
      report.max_residual = dyad.MaxResidual(task.spatial_poses);
    }
    DropRepeats(result.scale, &result.dyads);
    SortDyadsByRadius(&result.dyads);  // refinement can reorder radii, or make planes
    result.refine_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  PlatformMotionOptions platform = options.spatial.platform;
  if (result.method == "least-squares") {
    // A least-squares design meets the poses only nearly: judge it by its own residuals.
    double worst = 0.0;
    for (const SpatialDyadReport& report : result.dyads) {
      worst = std::max(worst, report.max_residual);
    }
    platform.assembly_tolerance =
        std::max(platform.assembly_tolerance, 10.0 * worst / result.scale);
    platform.pose_tolerance = std::max(platform.pose_tolerance, 10.0 * worst / result.scale);
  }
  AddPlatform(task, platform, &result);
  return result;
}

TaskResult SolveTask(const Task& task, const TaskSolverOptions& options) {
  if (task.problem == ProblemKind::kMotion && task.space == Space::kPlanar) {
    return SolvePlanarMotion(task, options.planar);
  }
  if (task.problem == ProblemKind::kMotion && task.space == Space::kSpatial) {
    return SolveSpatialTask(task, options);
  }
  PlanarMotionResult result;
  result.problem = task.problem;
  result.space = task.space;
  if (task.scale) result.scale = *task.scale;
  result.notes.push_back("path synthesis with timed points is not available in this version");
  return result;
}

}  // namespace linkfit
