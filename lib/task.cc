#include "lib/task.h"

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
