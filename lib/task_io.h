// Reading task files (JSON, or JSON lines for batch mode) with the error contract of the
// design: any problem is reported as one line naming the file, the item and what is wrong.
#ifndef LINKFIT_LIB_TASK_IO_H_
#define LINKFIT_LIB_TASK_IO_H_

#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "lib/task.h"

namespace linkfit {

// Bad input. what() is the complete one-line message, e.g.
// "task.json: poses[3].theta_deg: expected a number, got a string".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TaskReadOptions {
  // Input off its unit conditions (|q| = 1, seed 000 eq. 2; q . g = 0, eq. 3; R^T R = I) by up
  // to this many times what the precision of its digits explains (first-order bound) is
  // repaired to the nearest rigid motion; beyond, it is refused.
  double repair_units = 2.0;
  // Two poses closer than this (pose error relative to L), or closer than the data's precision
  // tells apart, are coincident.
  double coincident_tolerance = 1e-10;
  // Upper bound on poses or points in one task (bounded memory, clear message).
  size_t max_items = 100000;
};

// Parses and validates one task given as JSON text. `source` names the input in messages
// ("task.json" or "tasks.jsonl:4").
Task ParseTask(const std::string& json_text, const std::string& source,
               const TaskReadOptions& options = {});

// The whole text of the file at `path` (a `what`, e.g. "result", named in messages). A regular
// file larger than the limit (256 MiB) is refused unread; a stream (a FIFO, a device such as
// /dev/zero) is read in chunks and refused as soon as it passes the limit; a directory, an
// unreadable or an empty file is refused too (InputError).
std::string ReadText(const std::string& path, const char* what);

// Reads a file: a .jsonl file gives one task per non-empty line, anything else one task.
// Every task is validated before any is returned, so a bad line leaves nothing done.
std::vector<Task> ReadTaskFile(const std::string& path, const TaskReadOptions& options = {});

// Parses a planar design: a JSON object with "dyads" (each {"type": "RR", "fixed": [x, y],
// "moving": [x, y], "radius": r}, {"type": "PR", "moving", "line_point", "line_angle_deg"} or
// {"type": "RP", "fixed", "line_point", "line_angle_deg"}, as in result files) and optionally
// "mechanisms" ([{"dyads": [input, output]}, ...]). Other fields (a result file's residuals,
// notes, ...) are ignored. Errors as for tasks.
PlanarDesign ParseDesign(const std::string& json_text, const std::string& source);
PlanarDesign ReadDesignFile(const std::string& path);

// Parses a path design (lib/task.h PathDesign): {"mechanisms": [...]} with each four-bar as a
// path result writes it; other fields are ignored. Errors as for tasks.
PathDesign ParsePathDesign(const std::string& json_text, const std::string& source);

// Parses a spatial design (lib/task.h SpatialDesign): "dyads" ({"type": "SS", "fixed", "moving",
// "radius"}, {"type": "PS", "moving", "plane_normal", "plane_offset"} or {"type": "SP", "fixed",
// "plane_normal_in_moving", "plane_offset_in_moving"}) and optionally "mechanisms" ([{"dyads":
// [five indices]}, ...]). Other fields are ignored. Errors as for tasks.
SpatialDesign ParseSpatialDesign(const std::string& json_text, const std::string& source);

// Parses a six-bar design (lib/task.h SixBarDesign): {"six_bars": [...]} as a six-bar result
// writes them ("topology", "input", "joints_at_first_pose" with "ground_pivot", "elbow", "wrist"
// and two "links" of "from", "to", "from_joint", "to_joint"; optionally "task_body_at_first_pose"
// [x, y, theta_deg], else the task's first pose, and "turns_at_poses_deg", used where there are
// as many as `poses`, the task's); other fields are ignored. Errors as for tasks.
SixBarDesign ParseSixBarDesign(const std::string& json_text, const std::string& source,
                               const std::vector<PlanarPose>& poses);

// A design for `task` (`linkfit refine`): planar, path, spatial or six-bar by the task's kind.
using TaskDesign = std::variant<PlanarDesign, PathDesign, SpatialDesign, SixBarDesign>;
TaskDesign ParseTaskDesign(const std::string& json_text, const std::string& source,
                           const Task& task);
TaskDesign ReadTaskDesignFile(const std::string& path, const Task& task);

}  // namespace linkfit

#endif  // LINKFIT_LIB_TASK_IO_H_
