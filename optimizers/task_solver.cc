#include "optimizers/task_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace linkfit {

SpatialMotionResult SolveSpatialTask(const Task& task, const TaskSolverOptions& options) {
  SpatialMotionResult result = SolveSpatialMotion(task, options.spatial);
  if (result.model == "spatial" && result.method == "least-squares" &&
      task.spatial_poses.size() > 7 && task.effort != Effort::kFast) {
    const auto start = std::chrono::steady_clock::now();
    for (SpatialDyadReport& report : result.dyads) {
      if (report.dyad.type == SpatialDyadType::kSP) continue;  // no refiner for SP yet
      SpatialDyad dyad = report.dyad;
      const RefinerSummary summary = RefineSpatialDyad(task.spatial_poses, task.pose_weights,
                                                       result.scale, &dyad, options.refiner);
      report.seed_max_residual = summary.initial_max;
      report.seed_rms_residual = summary.initial_rms;
      report.rms_residual = summary.final_rms;
      report.dyad = dyad;
      report.max_residual = dyad.MaxResidual(task.spatial_poses);
    }
    // Refinement can reorder the radii (and turn spheres into planes).
    std::stable_sort(result.dyads.begin(), result.dyads.end(),
                     [](const SpatialDyadReport& a, const SpatialDyadReport& b) {
                       const auto key = [](const SpatialDyad& d) {
                         return d.type == SpatialDyadType::kSS
                                    ? d.radius
                                    : std::numeric_limits<double>::infinity();
                       };
                       return key(a.dyad) < key(b.dyad);
                     });
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
