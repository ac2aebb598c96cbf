// libFuzzer target for the task parser: any text given to ParseTask (and ParseDesign) either
// parses into a task that holds what validation promises, or ends in an InputError with one
// printable line naming the source. Anything else (another exception, a crash, a sanitizer
// report, a message that breaks the contract, an accepted task with a non-finite number) is
// a finding. Built with -fsanitize=fuzzer by scripts/fuzz.sh; replay_main.cc runs it on the
// seed corpus in every build.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "lib/task_io.h"
#include "tests/fuzz/fuzz_contract.h"

namespace {

constexpr char kSource[] = "fuzz.json";

[[noreturn]] void Finding(const std::string& what) {
  linkfit::fuzz::Finding("fuzz_task_parser", what);
}

void CheckMessage(const char* what) {
  linkfit::fuzz::CheckMessage("fuzz_task_parser", kSource, what);
}

template <typename Matrix>
void CheckFinite(const Matrix& value, const char* what) {
  if (!value.allFinite()) Finding(std::string("accepted a non-finite ") + what);
}

void CheckTask(const linkfit::Task& task, const linkfit::TaskReadOptions& options) {
  const size_t poses = task.planar_poses.size() + task.spatial_poses.size();
  if (poses > options.max_items || task.points.size() > options.max_items) {
    Finding("accepted more poses or points than the limit");
  }
  if (task.problem == linkfit::ProblemKind::kMotion) {
    if (poses == 0 || !task.points.empty()) Finding("motion task without poses or with points");
    if (task.space == linkfit::Space::kPlanar && task.planar_poses.size() < 3) {
      Finding("planar motion task with fewer than three poses");
    }
  } else if (task.problem == linkfit::ProblemKind::kFunction) {
    const size_t minimum = task.relative_angles ? 5 : 3;
    if (task.pairs.size() < minimum || poses != 0 || !task.points.empty()) {
      Finding("function task with too few pairs, or with poses or points");
    }
    for (const linkfit::FunctionPair& pair : task.pairs) {
      if (!std::isfinite(pair.input) || !std::isfinite(pair.output) ||
          !std::isfinite(pair.weight) || !(pair.weight > 0.0)) {
        Finding("accepted a non-finite pair or a non-positive weight");
      }
    }
    CheckFinite(task.ground_input, "ground pivot");
    CheckFinite(task.ground_output, "ground pivot");
  } else if (task.points.empty() || poses != 0) {
    Finding("path task without points or with poses");
  }
  if (task.pose_weights.size() != poses || task.pose_exact.size() != poses) {
    Finding("one weight and one exact flag per pose");
  }
  for (const double weight : task.pose_weights) {
    if (!(weight > 0.0) || !std::isfinite(weight)) Finding("accepted a bad weight");
  }
  for (const auto& pose : task.planar_poses) {
    CheckFinite(pose.origin_in_fixed, "planar pose");
    if (!std::isfinite(pose.theta)) Finding("accepted a non-finite angle");
  }
  for (const auto& pose : task.spatial_poses) {
    CheckFinite(pose.q, "quaternion");
    CheckFinite(pose.g, "dual part");
    if (!(std::abs(pose.q.norm() - 1.0) <= 1e-9)) Finding("accepted a non-unit quaternion");
  }
  for (const auto& point : task.points) {
    CheckFinite(point.point_in_fixed, "path point");
    if (point.input_angle && !std::isfinite(*point.input_angle)) {
      Finding("accepted a non-finite input angle");
    }
    if (!(point.weight > 0.0) || !std::isfinite(point.weight)) Finding("accepted a bad weight");
  }
  for (const auto& pivot : task.moving_pivots) CheckFinite(pivot, "pivot");
  for (const auto& pivot : task.fixed_pivots) CheckFinite(pivot, "pivot");
  for (const auto& pivot : task.spatial_moving_pivots) CheckFinite(pivot, "pivot");
  for (const auto& pivot : task.spatial_fixed_pivots) CheckFinite(pivot, "pivot");
  if (task.scale && !(*task.scale > 0.0 && std::isfinite(*task.scale))) {
    Finding("accepted a bad scale");
  }
}

void CheckDesign(const linkfit::PlanarDesign& design) {
  if (design.dyads.empty()) Finding("design without dyads");
  for (const auto& dyad : design.dyads) {
    CheckFinite(dyad.fixed_pivot, "fixed pivot");
    CheckFinite(dyad.moving_pivot, "moving pivot");
    CheckFinite(dyad.line_point, "line point");
    CheckFinite(dyad.line_direction, "line direction");
    if (!std::isfinite(dyad.radius)) Finding("accepted a non-finite radius");
  }
  const int count = static_cast<int>(design.dyads.size());
  for (const auto& [input, output] : design.mechanisms) {
    if (input < 0 || input >= count || output < 0 || output >= count || input == output) {
      Finding("accepted a mechanism with bad dyad indices");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // The default options, and a limit small enough for inputs of a few kB to reach the limit
  // on poses or points and the budget of JSON values (32 * (8 + 128)).
  linkfit::TaskReadOptions small;
  small.max_items = 8;
  for (const linkfit::TaskReadOptions& options : {linkfit::TaskReadOptions(), small}) {
    try {
      CheckTask(linkfit::ParseTask(text, kSource, options), options);
    } catch (const linkfit::InputError& error) {
      CheckMessage(error.what());
    }
  }
  try {
    CheckDesign(linkfit::ParseDesign(text, kSource));
  } catch (const linkfit::InputError& error) {
    CheckMessage(error.what());
  }
  return 0;
}
