// Planar motion generation, end to end: every dyad through the task poses and every
// four-bar made of two of them, checked by assembly. For exactly five poses the dyads are
// exact (planar_burmester.h); for more, the algebraic least-squares seed.
#ifndef LINKFIT_FITTING_PLANAR_MOTION_H_
#define LINKFIT_FITTING_PLANAR_MOTION_H_

#include "fitting/planar_burmester.h"
#include "lib/result.h"
#include "lib/task.h"

namespace linkfit {

struct PlanarMotionOptions {
  PlanarBurmesterOptions burmester;  // root finding and typing
};

// Solves a validated planar motion task (at least five poses). Never throws for numerical
// trouble: what could not be done is said in result.notes.
PlanarMotionResult SolvePlanarMotion(const Task& task, const PlanarMotionOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_MOTION_H_
