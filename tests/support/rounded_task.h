// Generated tasks printed as tables print them (a number of significant digits), and read back
// through the task parser, so that the precision is inferred from the digits as for a user's
// file. Shared by the tests and `linkfit bench` (the rounded-data family).
#ifndef LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_
#define LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "lib/planar_pose.h"
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

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_ROUNDED_TASK_H_
