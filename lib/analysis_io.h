// `linkfit analyze`: the kinematic and static analysis (lib/four_bar_kinematics.h) of one
// mechanism of a result file, written as JSON or CSV.
#ifndef LINKFIT_LIB_ANALYSIS_IO_H_
#define LINKFIT_LIB_ANALYSIS_IO_H_

#include <optional>
#include <string>
#include <utility>

#include "lib/four_bar_kinematics.h"

namespace linkfit {

struct AnalysisRequest {
  int mechanism = 0;         // its index in the result's "mechanisms" (0: the first listed)
  double input_speed = 1.0;  // rad/s, not 0
  int steps = 360;           // samples over the input's range (1 to 1000000)
  FourBarLoad load;          // the load the input holds
  // The links' masses (kg; masses.length_unit_m is set from length_unit) for the inertial torque
  // at the constant input speed and, with masses.gravity, their weight's.
  FourBarMasses masses;
  // The result's length unit: "m", "cm", "mm", "in" or "ft" (needed with masses).
  std::string length_unit;
  bool csv = false;  // CSV (one row per step) instead of JSON
  // Crank angles in degrees (from below to): sample this part of the input's range instead.
  std::optional<std::pair<double, double>> range_deg;
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

// The analysis of mechanism `request.mechanism` of the result `result_text` (a result file's
// JSON: planar four-bars of motion, path and function results whose input is a crank: 4Rs and
// slider-cranks with the slider's line on ground). JSON: the input's range and whether it turns
// fully, per step "input_deg", per link ("input", "coupler", "output"; a slider's "slider") its
// angle (deg; a slider: its position along its line), angular velocity (rad/s) and angular
// acceleration (rad/s^2; a slider: velocity and acceleration), "coupler_point",
// "coupler_point_velocity", "coupler_point_acceleration" ([x, y] each; none without a coupler
// point), "transmission_angle_deg", "mechanical_advantage" (null where the output stands still),
// "input_torque" and "peak_input_torque" (with a load or masses; with masses also
// "inertial_torque" and, with gravity, "weight_torque", its parts), and the "dead_points". Throws
// InputError (naming `source` and the item) for a result that is not JSON, has no such mechanism,
// or one of a kind not analyzed (yet), and for a bad request.
std::string AnalyzeResultText(const std::string& result_text, const std::string& source,
                              const AnalysisRequest& request);

}  // namespace linkfit

#endif  // LINKFIT_LIB_ANALYSIS_IO_H_
