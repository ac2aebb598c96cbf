// A result as a designer reads it at a glance (issue 35): one table per result, a row per listed
// mechanism in rank order, for `linkfit solve --summary`, `linkfit show` and Python.
#ifndef LINKFIT_LIB_RESULT_SUMMARY_H_
#define LINKFIT_LIB_RESULT_SUMMARY_H_

#include <string>

namespace linkfit {

// The table of one result (its JSON text, as `linkfit solve` writes it): a heading (the problem,
// the method, how many are listed and how many have no kinematic defect, the notes) and per
// mechanism its rank (1 = first, as --mechanism counts), type, Grashof class, link lengths
// (ground, input, coupler, output; a slider's offset; the coupler point's distance and angle from
// the input pin), fit (RMS where least squares, else largest), worst transmission angle, defects
// and the constraints it violates. Throws std::invalid_argument when the text is not a result.
std::string ResultSummary(const std::string& result_json, const std::string& title = "");

}  // namespace linkfit

#endif  // LINKFIT_LIB_RESULT_SUMMARY_H_
