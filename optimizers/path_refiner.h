// Least-squares refinement of a crank-driven four-bar as a path generator (seed 002's problem
// with more than five points): the coupler point's distance from the task points.
//
// Minimizes 1/2 sum_j w_j |C_j - R_j|^2, where C_j is the coupler point of the four-bar
// assembled at crank angle alpha_0 + (psi_j - psi_0) on the assembly of the first point
// (lib/path_motion.h; AnalyzePathFourBar measures the same errors). The coupler pose at each
// point is eliminated in closed form (the crank places its pin, the coupler turns about it until
// the output dyad closes: a cos(theta) + b sin(theta) = c), so the solver never steps where a
// point goes past the crank's reach. Unknowns: the crank (B, A), the output dyad (RR: F, M, r;
// PR: M, unit line normal, offset; RP: F, unit normal in E, offset; normals on a sphere
// manifold), the coupler point, and with free timing the input angles.
//
// Prescribed timing: the psi_j are data. Free timing: psi_1..psi_{n-1} become unknowns,
// psi_j = psi_0 + sum_{k<=j} delta_k with every delta_k of the direction's sign (the crank turns
// one way through the points) and their sum at most one turn; the starting angles give the
// direction and must be monotonic.
//
// Points marked exact get a large weight, then the method of multipliers until their error is
// within exact_tolerance * L. Data are centred (point centroid) and scaled by L internally. The
// result is normalised to the first point's configuration (MoveToFirstConfiguration) and
// re-analysed with AnalyzePathFourBar; the seed is returned unchanged unless the result is not
// worse (assembles at every point on one assembly, no new defect, exact points met or nearer,
// no higher cost).
#ifndef LINKFIT_OPTIMIZERS_PATH_REFINER_H_
#define LINKFIT_OPTIMIZERS_PATH_REFINER_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/path_motion.h"
#include "optimizers/refiner_summary.h"

namespace linkfit {

struct PathRefinerOptions {
  int max_iterations = 100;            // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-15;   // Ceres relative cost change to stop
  double parameter_tolerance = 1e-14;  // Ceres relative step to stop
  double exact_tolerance = 1e-9;       // exact points' error, times L
  int max_penalty_rounds = 8;          // method-of-multipliers rounds for exact points
  // A closed path (lib/path_motion.h): the seed and the result are judged with the closing step
  // back to the first point, so a refinement that costs the crank its whole turn is not taken.
  bool closed = false;
  // The design bounds (lib/design_constraints.h) as penalties (design_bounds.h): link lengths
  // (by default at most 100 L), the fixed pivots' box, the coupler point's offset, a crank input.
  // A result that keeps them replaces a seed that does not, whatever its cost.
  DesignConstraints constraints;
  // When set (no RP output), the transmission angle over the crank's sweep is held at or above
  // it (degrees, plus a 1 degree margin) as the bounds are: a penalty raised with theirs at the
  // points' crank angles and between them (free timing: the start's), and a result that keeps it
  // counts as keeping the bounds.
  std::optional<double> min_transmission_deg;
};

// Refines `four_bar` in place. `weights`/`exact` may be empty (all 1 / none). `input_angles`
// (radians, one per point) are read, and with free_timing also written (the fitted angles).
// Costs in the summary are 1/2 sum w_j e_j^2 (length units squared); initial_max / final_max the
// largest point error (AnalyzePathFourBar), rms likewise. Throws std::invalid_argument for
// counts that do not match, fewer than two points, non-positive length or weights, non-finite
// data, an input that is not RR, or (free timing) angles that are not monotonic.
RefinerSummary RefinePathFourBar(const std::vector<Eigen::Vector2d>& points,
                                 const std::vector<double>& weights, const std::vector<bool>& exact,
                                 double length, bool free_timing, std::vector<double>* input_angles,
                                 PathFourBar* four_bar, const PathRefinerOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PATH_REFINER_H_
