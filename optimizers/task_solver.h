// Solves any validated task end to end: the exact or algebraic solvers of fitting/, then the
// Ceres refinement where the task has more data than the minimum, then the mechanisms.
//   - planar motion: fitting/planar_motion.h;
//   - spatial motion: fitting/spatial_motion.h; more than seven poses (effort balanced or
//     thorough) refine every dyad on its geometric residual (spatial_dyad_refiner.h), then the
//     platform is built and traced;
//   - path problems: not available yet (a note).
#ifndef LINKFIT_OPTIMIZERS_TASK_SOLVER_H_
#define LINKFIT_OPTIMIZERS_TASK_SOLVER_H_

#include "fitting/planar_motion.h"
#include "fitting/spatial_motion.h"
#include "lib/result.h"
#include "lib/task.h"
#include "optimizers/spatial_dyad_refiner.h"

namespace linkfit {

struct TaskSolverOptions {
  PlanarMotionOptions planar;         // planar motion
  SpatialMotionOptions spatial;       // spatial motion (and its platform tracing)
  SpatialDyadRefinerOptions refiner;  // spatial least squares
};

// Never throws for numerical trouble: what could not be done is said in the result's notes.
TaskResult SolveTask(const Task& task, const TaskSolverOptions& options = {});

// Spatial motion only: solve, refine (more than seven poses, unless effort is fast), and add
// the platform.
SpatialMotionResult SolveSpatialTask(const Task& task, const TaskSolverOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_TASK_SOLVER_H_
