// Least-squares refinement of a four-bar function generator (issue 17, item 7): the output
// angle's error over the pairs.
//
// Minimizes 1/2 sum_j w_j wrap(psi(phi_j) - psi_j)^2, psi(phi) the output angle of the four-bar
// driven to input angle phi on its assembly sigma (lib/function_four_bar.h, eq. (F) solved in
// closed form for t4). Unknowns: the link lengths a, b, c (the ground d is the task's), and with
// relative angles the cranks' offsets. Where a pair's input is beyond the crank's reach, the
// output is taken at the nearest stationary configuration and the miss |C| / hypot(A, B) - 1 is
// a second residual, so a step past the reach is pulled back rather than undefined.
//
// Pairs marked exact: penalty continuation (optimizers/exact_poses.h) until their error is within
// exact_tolerance. Lengths are scaled by d internally and bounded to [1e-6, max_link_length] d.
// The seed is returned unchanged unless the result fits better (exact pairs met, then cost).
#ifndef LINKFIT_OPTIMIZERS_FUNCTION_REFINER_H_
#define LINKFIT_OPTIMIZERS_FUNCTION_REFINER_H_

#include <limits>
#include <optional>
#include <vector>

#include "lib/function_four_bar.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct FunctionRefinerOptions {
  int max_iterations = 100;       // Levenberg-Marquardt iterations per solve
  bool free_offsets = false;      // relative angles: the cranks' offsets are unknowns too
  double exact_tolerance = 1e-9;  // exact pairs' output error, radians
  int max_penalty_rounds = 4;     // penalty continuation rounds for exact pairs
  // The longest link allowed (times d); the lengths are bounded to it.
  double max_link_length = std::numeric_limits<double>::infinity();
  // When set (a task's min_transmission_angle_deg given), the transmission angle at every
  // pair's input is held at or above it (degrees, plus a 1 degree margin) by a penalty
  // kMissWeight (|cos mu| - cos mu_min) where it is below.
  std::optional<double> min_transmission_deg;
};

// The cost 1/2 sum w e^2 of a four-bar on the pairs (radians squared), with every input beyond
// the crank's reach adding 1/2 w (kMissWeight miss)^2: the refiner's and the search's objective.
// With `min_transmission_deg`, also the transmission penalty (FunctionRefinerOptions).
double FunctionCost(const FunctionFourBar& four_bar, const std::vector<FunctionPair>& pairs,
                    std::optional<double> min_transmission_deg = std::nullopt);

// Refines `four_bar` in place (its assembly kept). Costs in the summary are 1/2 sum w e^2 in
// radians squared, rms and max the output angle errors in radians. Throws std::invalid_argument
// for fewer than two pairs or an invalid four-bar.
RefinerSummary RefineFunctionFourBar(const std::vector<FunctionPair>& pairs,
                                     FunctionFourBar* four_bar,
                                     const FunctionRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_FUNCTION_REFINER_H_
