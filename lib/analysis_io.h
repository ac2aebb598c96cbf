// `linkfit analyze`: the kinematic and static analysis (lib/four_bar_kinematics.h) of one
// mechanism of a result file, written as JSON or CSV.
#ifndef LINKFIT_LIB_ANALYSIS_IO_H_
#define LINKFIT_LIB_ANALYSIS_IO_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lib/dyad.h"
#include "lib/four_bar_kinematics.h"
#include "lib/six_bar.h"
#include "lib/task.h"

namespace linkfit {

struct AnalysisRequest {
  int mechanism = 0;         // its index in the result's "mechanisms" (0: the first listed)
  double input_speed = 1.0;  // rad/s, not 0
  int steps = 360;           // samples over the input's range (1 to 1000000)
  FourBarLoad load;          // the load the input holds
  // The links' masses (kg; masses.length_unit_m is set from length_unit) for the inertial torque
  // at the constant input speed and, with masses.gravity, their weight's.
  FourBarMasses masses;
  // The links' masses as given (kg): a four-bar's three (INPUT, COUPLER, OUTPUT; they fill
  // `masses`), a six-bar's five (upper link, forearm, task body, first link, second link).
  std::vector<double> mass_list;
  // The result's length unit: "m", "cm", "mm", "in" or "ft" (needed with masses).
  std::string length_unit;
  bool csv = false;  // CSV (one row per step) instead of JSON
  // The part of the input's range sampled: by default a crank's whole turn, a rocking input's
  // task range where the result gives it (a six-bar's turns at the poses), else its whole range
  // between its dead points; `whole_range`: that whole range; `task_range`: the input's angles
  // from the first task pose to the last (refused where the result does not give them);
  // `range_deg`: the input's angles in degrees (from below to).
  std::optional<std::pair<double, double>> range_deg;
  bool whole_range = false;
  bool task_range = false;
  // The result's task (its poses, points or function), for a four-bar's task range where the
  // result alone does not give it (motion, and timed path results); checked against the result.
  const Task* task = nullptr;
};

// A four-bar of a result file: its joints at the first pose, its type ("4R", "slider-crank") and
// a length for tolerances (its crank's, its coupler's or the result's scale, the largest).
struct ResultFourBar {
  FourBarJoints joints;
  std::string type;
  double length = 1.0;
};

// Mechanism `mechanism_index` (0: the first listed) of the result `result_text`; InputError
// (naming `source` and the item) as AnalyzeResultText.
ResultFourBar ReadResultFourBar(const std::string& result_text, const std::string& source,
                                int mechanism_index);

// A planar four-bar of a result file that the closed form (lib/four_bar_kinematics.h) does not
// take: an inverted slider-crank, a double slider, an RPRP, an inverted double slider, or any
// four-bar driven by a slider; its dyads with E equal to Sigma at the first configuration
// (lib/dyad_four_bar_kinematics.h), its coupler point there, a length for tolerances.
struct ResultDyadFourBar {
  std::string type;
  PlanarDyad input, output;
  std::optional<Eigen::Vector2d> coupler_point;
  double length = 1.0;
};

// Mechanism `index` of the result as such a four-bar; none where it is not one (a 4R or a
// slider-crank driven by its crank, another kind of mechanism, no such mechanism).
std::optional<ResultDyadFourBar> ReadResultDyadFourBar(const std::string& result_text,
                                                       const std::string& source, int index);

// A six-bar of a result file: the six-bar, its input body, its turns at the task's poses (where
// the result gives them) and a length for tolerances.
struct ResultSixBar {
  SixBar six_bar;
  int input = 1;
  std::vector<SixBarAngles> at_poses;
  double length = 1.0;
};

// Six-bar `index` (0: the first listed) of the result `result_text` (its "six_bars"); InputError
// naming `source` where there is none such.
ResultSixBar ReadResultSixBar(const std::string& result_text, const std::string& source, int index);

// A four-bar's task range (its crank's angles in radians from the first task pose, point or
// pair to the last, least to greatest): from the result where it gives them, else from `task`;
// none where neither does. Throws InputError where `task` is not this result's (its first pose
// or point does not fit the mechanism), and as ReadResultFourBar.
std::optional<std::pair<double, double>> ResultFourBarTaskRange(const std::string& result_text,
                                                                const std::string& source,
                                                                int mechanism_index,
                                                                const Task* task);

// The analysis of mechanism `request.mechanism` of the result `result_text` (a result file's
// JSON: planar four-bars of motion, path and function results whose input is a crank: 4Rs and
// slider-cranks with the slider's line on ground; six-bars, `request.mechanism` indexing its
// "six_bars", driven by their input, lib/six_bar_kinematics.h). JSON: the input's range and whether
// it turns fully, per step "input_deg", per link ("input", "coupler", "output"; a slider's
// "slider") its angle (deg; a slider: its position along its line), angular velocity (rad/s) and
// angular acceleration (rad/s^2; a slider: velocity and acceleration), "coupler_point",
// "coupler_point_velocity", "coupler_point_acceleration" ([x, y] each; none without a coupler
// point), "transmission_angle_deg", "mechanical_advantage" (null where the output stands still),
// "input_torque" and "peak_input_torque" (with a load or masses; with masses also
// "inertial_torque" and, with gravity, "weight_torque", its parts), and the "dead_points". A
// six-bar's links are "upper_link", "forearm", "task_body", "first_link" and "second_link" (the
// input among them), its coupler point the tool frame's origin, its "transmission_angle_deg" the
// worse of its two loops' (0-90; each in "transmission_angles_deg"), its output the task body
// (the mechanical advantage, --output-torque), and "task_range_deg" the input's angles at the
// first and last poses. Throws
// InputError (naming `source` and the item) for a result that is not JSON, has no such mechanism,
// or one of a kind not analyzed (yet), and for a bad request.
std::string AnalyzeResultText(const std::string& result_text, const std::string& source,
                              const AnalysisRequest& request);

// The part of the input's range `range` names into `request`: "FROM,TO" (the input's angles in
// degrees), "task" or "whole" (`linkfit analyze --range`, the server's ?range=); InputError
// naming `item` otherwise.
void SetAnalysisRange(const std::string& range, const std::string& item, AnalysisRequest* request);

}  // namespace linkfit

#endif  // LINKFIT_LIB_ANALYSIS_IO_H_
