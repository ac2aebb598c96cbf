// In-memory form of the task file (see README, "Task file"). Parsing and validation live in
// task_io.h; this header holds only the data.
#ifndef LINKFIT_LIB_TASK_H_
#define LINKFIT_LIB_TASK_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/dyad.h"
#include "lib/function_four_bar.h"
#include "lib/path_motion.h"
#include "lib/planar_pose.h"
#include "lib/precision.h"
#include "lib/six_bar.h"
#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"

namespace linkfit {

enum class ProblemKind { kMotion, kPath, kFunction };
enum class Space { kPlanar, kSpatial };
enum class Effort { kFast, kBalanced, kThorough };

const char* ProblemKindName(ProblemKind kind);
const char* SpaceName(Space space);
const char* EffortName(Effort effort);
// The effort a name gives ("fast", "balanced", "thorough"); none for another text.
std::optional<Effort> EffortOfName(const std::string& name);

struct TimedPoint {
  Eigen::Vector2d point_in_fixed = Eigen::Vector2d::Zero();
  std::optional<double> input_angle;  // radians; absent for free timing
  double weight = 1.0;
  bool exact = false;
};

struct Task {
  ProblemKind problem = ProblemKind::kMotion;
  Space space = Space::kPlanar;
  std::vector<PlanarPose> planar_poses;       // motion, planar
  std::vector<DualQuaternion> spatial_poses;  // motion, spatial
  std::vector<double> pose_weights;           // one per pose, default 1
  std::vector<bool> pose_exact;               // one per pose, default false
  std::vector<TimedPoint> points;             // path
  // Function problems (issue 17): the precision pairs (radians), angles counter-clockwise from the
  // ground line, measured at `ground_input` (the input pivot A) and `ground_output` (B) in Sigma.
  std::vector<FunctionPair> pairs;
  bool relative_angles = false;  // only differences matter: the cranks' offsets are unknowns
  Eigen::Vector2d ground_input = Eigen::Vector2d::Zero();
  Eigen::Vector2d ground_output = Eigen::Vector2d::UnitX();
  // A function given as samples of y = f(x): the samples mapped to angles (the result reports
  // each four-bar's largest output error over them); empty for a task of pairs.
  std::vector<FunctionPair> function_samples;
  // Planar motion with three or four poses: pivots chosen by the user, one dyad each.
  std::vector<Eigen::Vector2d> moving_pivots;  // in E (on the circle-point curve for 4 poses)
  std::vector<Eigen::Vector2d> fixed_pivots;   // in Sigma (on the center-point curve)
  // Spatial motion with four to six poses: points chosen by the user, one SS dyad each.
  std::vector<Eigen::Vector3d> spatial_moving_pivots;  // in E
  std::vector<Eigen::Vector3d> spatial_fixed_pivots;   // in Sigma
  // Spatial poses of a spherical motion with three or four orientations: axes through the
  // centre chosen by the user (directions), one spherical dyad each.
  std::vector<Eigen::Vector3d> moving_axes;  // in E
  std::vector<Eigen::Vector3d> fixed_axes;   // in Sigma
  // Spatial motion: the five dyads (indices into the result's dyads) to build the platform
  // from; empty for the default (the five of smallest radius).
  std::vector<int> platform;
  // Planar motion with "linkage": "six-bar" (issue 36): six-bars on the 3R chain `chain`
  // (lib/six_bar.h) instead of four-bars.
  bool six_bar = false;
  std::optional<SixBarChain> chain;
  std::optional<double> scale;  // characteristic length L, when given
  // Planar motion and path problems: the design's bounds (lib/design_constraints.h).
  DesignConstraints constraints;
  Effort effort = Effort::kBalanced;
  // The precision of the data, given or inferred from the digits (lib/precision.h).
  DataPrecision precision;
  // The last pose or point repeated the first within precision: a closed motion or path, given
  // once (the repeat was dropped). A closed path's crank makes a whole turn from the first
  // point back to it.
  bool closed = false;
  // What reading the task did that the result should say: input repaired within precision, a
  // closed motion or path recognised, a precision inferred in part.
  std::vector<std::string> input_notes;
};

// A planar design to refine against a task (`linkfit refine`): dyads and the four-bars made of
// two of them, as a result file lists them (or written by hand in the same form).
struct PlanarDesign {
  std::vector<PlanarDyad> dyads;
  std::vector<std::pair<int, int>> mechanisms;  // [input, output] dyad indices
};

// A path design: crank-driven four-bars in the first point's configuration (lib/path_motion.h),
// as a path result lists them ("type", "input_pivot", "input_moving", "output_pivot" and/or
// "output_moving", "output_line_point" and "output_line_angle_deg" for a slider, "coupler_point"),
// each with the input angles a free-timing result fitted (radians; empty when not given).
struct PathDesign {
  std::vector<PathFourBar> four_bars;
  std::vector<std::vector<double>> input_angles;  // one list per four-bar
};

// A spatial design: SS, PS and SP dyads, and platforms of five of them, as a spatial motion
// result lists them.
struct SpatialDesign {
  std::vector<SpatialDyad> dyads;
  std::vector<std::vector<int>> platforms;  // five dyad indices each
};

// A six-bar design (issue 36): six-bars as a six-bar result lists them ("six_bars": topology,
// joints at the first pose, the task body's pose there, the driving input, each pose's turns).
struct SixBarDesign {
  std::vector<SixBar> six_bars;
  std::vector<int> inputs;                          // the driving body of each
  std::vector<std::vector<SixBarAngles>> at_poses;  // each's turns at the poses (may be empty)
};

// Motion tasks of the given poses, each of weight 1 and not exact (what a task file without
// "weight" and "exact" gives).
Task PlanarMotionTask(const std::vector<PlanarPose>& poses, Effort effort = Effort::kBalanced);
Task SpatialMotionTask(const std::vector<DualQuaternion>& poses, Effort effort = Effort::kBalanced);

// How many of a path task's points differ from each other (untimed points may repeat in print:
// a curve traced finer than its digits, or one that crosses itself).
int DistinctPoints(const std::vector<TimedPoint>& points);

}  // namespace linkfit

#endif  // LINKFIT_LIB_TASK_H_
