// `linkfit analyze --svg`: an analysis (lib/analysis_io.h's JSON) as an SVG chart: four panels
// against the input angle (every link's angle, angular velocity, angular acceleration; the
// input torque holding the load, or without one the transmission angle), the input's dead points
// dashed on each; as linkfit.plot_analysis draws it.
#ifndef LINKFIT_APPS_ANALYSIS_SVG_H_
#define LINKFIT_APPS_ANALYSIS_SVG_H_

#include <string>

namespace linkfit {

// The SVG text of the analysis `analysis_json` (AnalyzeResultText's JSON).
std::string AnalysisSvg(const std::string& analysis_json);

}  // namespace linkfit

#endif  // LINKFIT_APPS_ANALYSIS_SVG_H_
