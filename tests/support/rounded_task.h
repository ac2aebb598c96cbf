// Generated tasks printed as tables print them (a number of significant digits), and read back
// through the task parser, so that the precision is inferred from the digits as for a user's
// file. Shared by the tests and `linkfit bench` (the rounded-data family).
#ifndef LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_
#define LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "lib/path_motion.h"
#include "lib/planar_pose.h"
#include "lib/result.h"
#include "lib/spatial_pose.h"
#include "lib/task.h"

namespace linkfit::testing {

// `value` to `digits` significant digits, as %g prints it ("0.000123457", "1.5e+06"), always
// with a decimal point or exponent so that the parser reads it as a measured number.
std::string Printed(double value, int digits);

// The forms a table gives spatial poses in.
enum class SpatialForm { kDualQuaternion, kRotationMatrix, kAxisAngle, kEulerZYX };

// Task texts with every number printed to `digits` significant digits.
std::string PlanarMotionText(const std::vector<PlanarPose>& poses, int digits);
std::string SpatialMotionText(const std::vector<DualQuaternion>& poses, int digits,
                              SpatialForm form);
// `input_angles` (radians) empty: free timing.
std::string PathText(const std::vector<Eigen::Vector2d>& points,
                     const std::vector<double>& input_angles, int digits);

// The text parsed as a user's file (source "rounded"); `effort` replaces the default.
Task ReadRounded(const std::string& text, Effort effort = Effort::kBalanced);

// The one-line InputError message of parsing `text` as "task.json", or "<no error>".
std::string ParseErrorOf(const std::string& text);

// A path task's points and their input angles (radians; only those given).
void TimedPoints(const Task& task, std::vector<Eigen::Vector2d>* points,
                 std::vector<double>* input_angles);

// What counts as recovered from rounded data (the tests and `linkfit bench`'s rounded-data
// family judge alike).

// A stated error bound above this fraction of a dyad's size says that the data barely
// determine it (the bound is first order, and so itself rough there).
inline constexpr double kRoughBound = 0.25;

// The result says that its data are too coarse: a family within precision, an error bound
// beyond the dyads' own size, or nearly real complex roots that rounding may have cost.
bool SaysTooCoarse(const std::vector<std::string>& notes);

// Recovery of a generating dyad from rounded data: the distance to the nearest listed dyad of
// its type in units of twice that dyad's stated error_bound (twice: the bound is first order),
// so right is at most 1. A generating circle (sphere) that the rounded poses cannot tell from
// its slider (plane) reading may come back as that reading (fitting/model_choice.h).
// *rough is set (never cleared) when the generating dyad is not right and the nearest listed
// dyad's bound is rough (kRoughBound, or the poses do not determine it).
double RoundedRecovery(const PlanarDyad& expected, const std::vector<DyadReport>& found,
                       const DataPrecision& precision, const std::vector<PlanarPose>& poses,
                       bool* rough = nullptr);
double RoundedRecovery(const SpatialDyad& expected, const std::vector<SpatialDyadReport>& found,
                       const DataPrecision& precision, const std::vector<DualQuaternion>& poses,
                       double length, bool* rough = nullptr);

// Whether a listed four-bar meets the points within their precision: every point within
// kModelUnits point uncertainties (delta, and alpha times the point's reach from the crank
// pivot), never less than the exact solver's check (1e-8 L).
bool MeetsPointsWithinPrecision(const PathMechanismReport& report,
                                const std::vector<Eigen::Vector2d>& points,
                                const DataPrecision& precision);

// The same for a generating four-bar from rounded points: the distance to the nearest listed
// four-bar of its type that meets the points within their precision (PathFourBarDistance with the
// four-bar's size, lib/path_motion.h PathFourBarSize, as the length) in units of twice that
// four-bar's stated error_bound. Timed
// (`input_angles` given): a generating output circle whose slider reading fits its coupler
// poses within their precision may come back as that reading (fitting/model_choice.h). Free
// timing (`input_angles` empty): a Roberts cognate of a 4R, or the four-bar driven by its
// other crank, traces the same curve through the same points and counts as the generating one
// (CurveCognates, random_path.h). *rough is set as for RoundedRecovery, and also when a listed
// four-bar with another output type has the generating crank and coupler point within its
// bound and that bound is rough: the points determine neither the output nor its type.
double RoundedPathRecovery(const PathFourBar& expected, const PathResult& result,
                           const std::vector<Eigen::Vector2d>& points,
                           const std::vector<double>& input_angles, bool* rough = nullptr);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_
