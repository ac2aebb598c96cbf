// `linkfit export --dxf/--svg`: a listed four-bar (or six-bar: a layer per body) as a DXF drawing
// for CAD, written by dxflib (Debian's libdxflib-dev), or the same drawing as SVG (for a laser
// cutter, a web page, a report). Each link on its own layer (GROUND, INPUT, COUPLER, OUTPUT) with
// its pivots as circles, the coupler body as a closed polyline through its pins and coupler point,
// the coupler curve over the input's range (CURVE), the task's poses or points when the task is
// given (TASK) and aligned dimensions of the link lengths (DIMENSIONS). Coordinates are the
// result's, in Sigma.
#ifndef LINKFIT_APPS_CAD_EXPORT_H_
#define LINKFIT_APPS_CAD_EXPORT_H_

#include <optional>
#include <string>

#include "lib/task.h"

namespace linkfit {

struct CadExportRequest {
  int mechanism = 0;                // its index in the result's "mechanisms" (0: the first)
  std::optional<double> input_deg;  // the crank angle drawn (default: the first pose's)
  const Task* task = nullptr;       // its poses or points drawn, when given
  int curve_steps = 360;            // samples of the coupler curve
};

// The DXF text of mechanism `request.mechanism` of the result `result_text` (4Rs and
// slider-cranks driven by a crank, as `linkfit analyze`). Throws InputError naming `source` for
// a result without such a mechanism or an input angle where it does not assemble.
std::string ResultDxf(const std::string& result_text, const std::string& source,
                      const CadExportRequest& request);

// The same drawing as an SVG document: a group per layer (its id the layer's name, its stroke
// the layer's colour), in the result's coordinates (y up, through a flipping group) and units;
// the dimensions as extension lines, a dimension line and the length as text.
std::string ResultSvg(const std::string& result_text, const std::string& source,
                      const CadExportRequest& request);

}  // namespace linkfit

#endif  // LINKFIT_APPS_CAD_EXPORT_H_
