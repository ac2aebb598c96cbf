// The Ceres solver options every refiner starts from: Levenberg-Marquardt with a dense QR
// solver on one thread, silent, with the refiner's own iteration cap and stopping tolerances.
#ifndef LINKFIT_OPTIMIZERS_SOLVER_OPTIONS_H_
#define LINKFIT_OPTIMIZERS_SOLVER_OPTIONS_H_

#include <ceres/ceres.h>

namespace linkfit {

inline ceres::Solver::Options RefinerSolverOptions(int max_iterations, double function_tolerance,
                                                   double parameter_tolerance,
                                                   double gradient_tolerance) {
  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.num_threads = 1;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = function_tolerance;
  options.parameter_tolerance = parameter_tolerance;
  options.gradient_tolerance = gradient_tolerance;
  options.minimizer_progress_to_stdout = false;
  options.logging_type = ceres::SILENT;
  return options;
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_SOLVER_OPTIONS_H_
