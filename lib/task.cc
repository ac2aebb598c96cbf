#include "lib/task.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace linkfit {

const char* ProblemKindName(ProblemKind kind) {
  return kind == ProblemKind::kMotion ? "motion" : kind == ProblemKind::kPath ? "path" : "function";
}

const char* SpaceName(Space space) { return space == Space::kPlanar ? "planar" : "spatial"; }

const char* EffortName(Effort effort) {
  switch (effort) {
    case Effort::kFast:
      return "fast";
    case Effort::kBalanced:
      return "balanced";
    case Effort::kThorough:
      return "thorough";
  }
  return "balanced";
}

std::optional<Effort> EffortOfName(const std::string& name) {
  for (const Effort effort : {Effort::kFast, Effort::kBalanced, Effort::kThorough}) {
    if (name == EffortName(effort)) return effort;
  }
  return std::nullopt;
}

int DistinctPoints(const std::vector<TimedPoint>& points) {
  std::vector<std::pair<double, double>> locations;
  for (const TimedPoint& point : points) {
    locations.emplace_back(point.point_in_fixed.x(), point.point_in_fixed.y());
  }
  std::sort(locations.begin(), locations.end());
  return static_cast<int>(std::unique(locations.begin(), locations.end()) - locations.begin());
}

Task PlanarMotionTask(const std::vector<PlanarPose>& poses, Effort effort) {
  Task task;
  task.planar_poses = poses;
  task.pose_weights.assign(poses.size(), 1.0);
  task.pose_exact.assign(poses.size(), false);
  task.effort = effort;
  return task;
}

Task SpatialMotionTask(const std::vector<DualQuaternion>& poses, Effort effort) {
  Task task;
  task.space = Space::kSpatial;
  task.spatial_poses = poses;
  task.pose_weights.assign(poses.size(), 1.0);
  task.pose_exact.assign(poses.size(), false);
  task.effort = effort;
  return task;
}

}  // namespace linkfit
