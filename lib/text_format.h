// printf-style text of one number for notes and messages ("%.3g" of a condition estimate, a
// distance), shared by the solvers' and refiners' notes.
#ifndef LINKFIT_LIB_TEXT_FORMAT_H_
#define LINKFIT_LIB_TEXT_FORMAT_H_

#include <cstdio>
#include <string>

namespace linkfit {

// `value` written by std::snprintf with `format` (one double conversion, up to 127 characters).
inline std::string Format(const char* format, double value) {
  char buffer[128];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_TEXT_FORMAT_H_
