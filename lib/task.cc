#include "lib/task.h"

namespace linkfit {

const char* ProblemKindName(ProblemKind kind) {
  return kind == ProblemKind::kMotion ? "motion" : "path";
}

const char* SpaceName(Space space) { return space == Space::kPlanar ? "planar" : "spatial"; }

const char* EffortName(Effort effort) {
  switch (effort) {
    case Effort::kFast:
      return "fast";
    case Effort::kBalanced:
      return "balanced";
    case Effort::kThorough:
      return "thorough";
  }
  return "balanced";
}

}  // namespace linkfit
