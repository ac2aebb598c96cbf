#include "fitting/planar_motion.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

namespace linkfit {
namespace {

std::string Format(const char* format, double value) {
  char buffer[128];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

// Order of the dyad list: RR by crank length, then PR, then RP.
bool DyadBefore(const DyadReport& a, const DyadReport& b) {
  if (a.dyad.type != b.dyad.type) return a.dyad.type < b.dyad.type;
  if (a.dyad.type == DyadType::kRR) return a.dyad.radius < b.dyad.radius;
  return a.max_residual < b.max_residual;
}

}  // namespace

PlanarMotionResult SolvePlanarMotion(const Task& task, const PlanarMotionOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result;
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  result.scale = length;
  result.method = poses.size() == 5 ? "exact" : "least-squares";

  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary summary;
  SolvePlanarBurmester(poses, options.burmester, &dyads, &summary);
  result.roots_total = summary.roots_total;
  result.roots_real = summary.roots_real;
  if (summary.degenerate) {
    result.notes.push_back(
        "the pose constraints are dependent (condition estimate " +
        Format("%.3g", summary.condition) +
        "): the poses admit a family of dyads, not isolated ones (e.g. all poses of one "
        "orientation)");
  }
  for (const PlanarDyad& dyad : dyads) result.dyads.push_back({dyad, dyad.MaxResidual(poses)});
  std::sort(result.dyads.begin(), result.dyads.end(), DyadBefore);
  if (poses.size() > 5 && !summary.degenerate) {
    result.notes.push_back(
        "more than five poses: the dyads are the algebraic least-squares seed (RMS algebraic "
        "residual " +
        Format("%.3g", summary.fit_residual) +
        " in normalized units); geometric refinement is not applied");
  }
  if (!summary.degenerate && summary.roots_total > 0) {
    const int complex_roots = summary.roots_total - summary.roots_real;
    if (complex_roots > 0) {
      result.notes.push_back(std::to_string(complex_roots) + " of the " +
                             std::to_string(summary.roots_total) +
                             " Burmester roots are complex and were dropped");
    }
  }

  for (size_t i = 0; i < result.dyads.size(); ++i) {
    for (size_t j = i + 1; j < result.dyads.size(); ++j) {
      MechanismReport mechanism;
      mechanism.input_dyad = static_cast<int>(i);
      mechanism.output_dyad = static_cast<int>(j);
      const PlanarDyad& input = result.dyads[i].dyad;
      const PlanarDyad& output = result.dyads[j].dyad;
      mechanism.type = ClassifyFourBar(input.type, output.type);
      mechanism.max_pose_error = MaxAssembledPoseError(input, output, poses, length);
      if (!mechanism.max_pose_error) {
        mechanism.pose_error_note = "the mechanism does not assemble at every task pose";
      }
      mechanism.grashof = GrashofType(input, output, length);
      result.mechanisms.push_back(mechanism);
    }
  }
  if (result.dyads.empty() && result.notes.empty()) {
    result.notes.push_back("no real dyad guides the body through these poses");
  } else if (result.dyads.size() == 1) {
    result.notes.push_back("only one real dyad: no four-bar");
  }
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

PlanarMotionResult SolveTask(const Task& task, const PlanarMotionOptions& options) {
  if (task.problem == ProblemKind::kMotion && task.space == Space::kPlanar) {
    return SolvePlanarMotion(task, options);
  }
  PlanarMotionResult result;
  result.problem = task.problem;
  result.space = task.space;
  result.method = "exact";
  if (task.scale) result.scale = *task.scale;
  result.notes.push_back(task.problem == ProblemKind::kPath
                             ? "path synthesis with timed points is not available in this version"
                             : "spatial motion synthesis is not available in this version");
  return result;
}

}  // namespace linkfit
