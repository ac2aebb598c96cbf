// Writing result files (JSON). Values that cannot be computed are left out with a reason;
// NaN or Infinity are never written.
#ifndef LINKFIT_LIB_RESULT_IO_H_
#define LINKFIT_LIB_RESULT_IO_H_

#include <string>

#include "lib/result.h"

namespace linkfit {

// The result as JSON text; `indent` < 0 gives one line (batch mode), otherwise pretty-printed.
std::string ResultToJson(const PlanarMotionResult& result, int indent);
std::string ResultToJson(const SpatialMotionResult& result, int indent);
std::string ResultToJson(const PathResult& result, int indent);
std::string ResultToJson(const FunctionResult& result, int indent);
std::string ResultToJson(const TaskResult& result, int indent);

// A path four-bar's input angle (radians) as a result file gives it back: written in degrees as
// `input_deg` and read back in radians (task_io). A refinement from it starts where `linkfit
// refine` starts from the file.
double InputAngleAsWritten(double radians);

}  // namespace linkfit

#endif  // LINKFIT_LIB_RESULT_IO_H_
