// Solves any validated task end to end: the exact or algebraic solvers of fitting/, then the
// Ceres refinement where the task has more data than the minimum, then the mechanisms.
//   - planar motion: fitting/planar_motion.h for five poses or fewer; more poses are approximate
//     synthesis, by effort level: fast = the algebraic seeds (least-squares fit and exact solves
//     of five-pose subsets); balanced (default) = every seed refined on its geometric residual
//     (planar_dyad_refiner.h) and the best four-bars refined on their pose error
//     (four_bar_refiner.h); thorough = as balanced plus an NLopt global search for dyads
//     (global_search.h) before the four-bars are built;
//   - spatial motion: fitting/spatial_motion.h; more than seven poses (effort balanced or
//     thorough) refine every dyad on its geometric residual (spatial_dyad_refiner.h), then the
//     platform is built and traced; a spherical motion of six or more orientations refines its
//     seeds (spherical_dyad_refiner.h), and thorough adds an NLopt search over the moving axis
//     (spherical_search.h);
//   - path problems (timed points): five points with input angles are solved exactly
//     (fitting/timed_path.h); more are least squares: fast = the four-bars of exact solves of
//     five-point subsets, balanced = those refined on the point errors (path_refiner.h),
//     thorough = as balanced plus an NLopt search over the crank (path_search.h). Points without
//     input angles (free timing) are fitted with the angles as unknowns, from timing guesses
//     (evenly spaced angles over several spans, both directions) solved as above.
// A higher effort keeps what a lower one finds (planar motion: the lower level's best-fitting
// four-bar where it fits better; paths: the seeds beside their refinements; spherical motion:
// balanced's dyads beside the search's), so it never fits worse (spatial motion aside: there
// fast's dyads are replaced by their refinements).
#ifndef LINKFIT_OPTIMIZERS_TASK_SOLVER_H_
#define LINKFIT_OPTIMIZERS_TASK_SOLVER_H_

#include <string>
#include <vector>

#include "fitting/planar_motion.h"
#include "fitting/spatial_motion.h"
#include "fitting/timed_path.h"
#include "lib/result.h"
#include "lib/task.h"
#include "lib/task_io.h"
#include "optimizers/four_bar_refiner.h"
#include "optimizers/function_refiner.h"
#include "optimizers/function_search.h"
#include "optimizers/global_search.h"
#include "optimizers/path_refiner.h"
#include "optimizers/path_search.h"
#include "optimizers/pivot_choice.h"
#include "optimizers/planar_dyad_refiner.h"
#include "optimizers/six_bar_refiner.h"
#include "optimizers/spatial_dyad_refiner.h"
#include "optimizers/spherical_dyad_refiner.h"
#include "optimizers/spherical_search.h"

namespace linkfit {

struct TaskSolverOptions {
  PlanarMotionOptions planar;                     // planar motion
  SpatialMotionOptions spatial;                   // spatial motion (and its platform tracing)
  SpatialDyadRefinerOptions refiner;              // spatial least squares
  SphericalDyadRefinerOptions spherical_refiner;  // spherical least squares
  PlanarDyadRefinerOptions planar_refiner;        // planar least squares, dyad level
  FourBarRefinerOptions four_bar_refiner;         // planar least squares, mechanism level
  GlobalSearchOptions search;                     // planar least squares, effort thorough
  SphericalSearchOptions spherical_search;        // spherical least squares, effort thorough
  int seed_subsets = 6;                           // five-pose subsets solved exactly for seeds
  int max_dyads = 10;  // dyads kept per effort level (best RMS first) for four-bars
  // Best-ranked four-bars refined per level (mechanism level), each in rounds while they gain.
  int refined_mechanisms = 3;
  int reported_mechanisms = 12;     // four-bars listed at most (least squares)
  PivotChoiceOptions pivot_choice;  // three to five poses: pivots chosen within the constraints
  TimedPathOptions timed_path;      // path problems: the five-point solver
  PathRefinerOptions path_refiner;  // path problems, least squares
  PathSearchOptions path_search;    // path problems, effort thorough
  int path_seed_subsets = 6;        // five-point subsets solved exactly for seeds
  int path_refined = 6;             // best seed four-bars refined (balanced and thorough)
  int path_reported = 12;           // four-bars listed at most (least squares)
  FunctionRefinerOptions function_refiner;  // function problems, least squares
  FunctionSearchOptions function_search;    // function problems, effort thorough
  int function_seed_subsets = 8;  // exact solves of spread subsets (3 or 5 pairs) for seeds
  int function_reported = 12;     // four-bars listed at most (least squares)
  // Threads one solve may use (lib/parallel.h; 0: the machine's): the nine-point homotopy's
  // paths and a free-timing stage's refinements, each independent (the result does not depend
  // on them). The batch modes run a task a thread, each with one.
  int threads = 0;
  // Six-bars through six or more poses (SolveSixBarLeastSquares), at balanced effort (fast: a
  // half of the roots and a third of the refinements; thorough: twice and three times): the
  // best-fitting least-squares dyads kept per relative motion, and the six-bars refined.
  int six_bar_roots = 6;
  int six_bars_refined = 8;
  SixBarRefinerOptions six_bar_refiner;
  // Chains judged when a six-bar task leaves its chain to linkfit (SolveSixBarChosenChain), and
  // beyond five poses those solved by least squares, at balanced effort (fast: a third, and one;
  // thorough: three times).
  int six_bar_chains = 24;
  int six_bar_least_squares_chains = 2;
};

// Never throws for numerical trouble: what could not be done is said in the result's notes.
TaskResult SolveTask(const Task& task, const TaskSolverOptions& options = {});

// Planar motion only: exact for five poses or fewer, approximate beyond (see above).
PlanarMotionResult SolvePlanarTask(const Task& task, const TaskSolverOptions& options = {});

// A validated "linkage": "six-bar" task of six or more poses (issue 36;
// optimizers/six_bar_task_solver.cc): every relative motion's best least-squares RR dyads combined
// into the chain's six-bars (fitting/six_bar_synthesis.h CombineSixBars), the best fits refined on
// the pose errors with every joint free (RefineSixBar), listed once each, judged and ranked as
// five-pose six-bars are (JudgeSixBar, RankSixBars).
PlanarMotionResult SolveSixBarLeastSquares(const Task& task, const TaskSolverOptions& options = {});

// A "linkage": "six-bar" task without "chain" (issue 36): linkfit chooses the chain. The
// candidate chains (fitting/six_bar_chains.h SixBarChainCandidates: every pose reached on one
// elbow, elbow angles away from the singular places, acceptable joint travel, the task's pivot
// boxes and link bounds kept; fast, balanced and thorough effort try 8, 24 and 72 of them) are
// judged quickly in their order (ScreenSixBarChain; beyond five poses on five spread over the
// task) until one has a six-bar that keeps every constraint without a defect. Five poses: that
// chain, else the one whose best six-bar the shared rule ranks first, is solved
// (SolveSixBarMotion). Beyond: the best-judged chains (fast 1, balanced 2, thorough 6) are solved
// by least squares (SolveSixBarLeastSquares) and the result whose first six-bar ranks first kept.
// The chain is stated in the result (chain_chosen) and in a note.
PlanarMotionResult SolveSixBarChosenChain(const Task& task, const TaskSolverOptions& options = {});

// `linkfit refine` of a six-bar (a "linkage": "six-bar" task, any number of poses): placed at the
// poses from `at_poses` (the design's turns; empty: from its upper link's range,
// FitSixBarToPoses), refined on the pose errors with every joint free (RefineSixBar) and judged as
// the solver judges it; never worse than the design.
PlanarMotionResult RefineSixBarDesign(const Task& task, const SixBar& six_bar,
                                      const std::vector<SixBarAngles>& at_poses,
                                      const TaskSolverOptions& options = {});

// Path problems only: exact for five timed points, least squares beyond, free timing when the
// points have no input angles.
PathResult SolvePathTask(const Task& task, const TaskSolverOptions& options = {});

// The largest point error of a path four-bar that passes the points (ranked "within precision"):
// kModelUnits point uncertainties of `precision` at the crank's pivot, not below 1e-8 `length`.
double PathPassTolerance(const DataPrecision& precision, double length);

// Function problems only (issue 17): absolute angles, three pairs, and relative angles, five
// pairs, exactly (fitting/function_generation.h); more pairs by least squares: fast = the linear
// least-squares and subset seeds on both assemblies, balanced = each refined on the output-angle
// error (function_refiner.h), thorough = as balanced plus an NLopt search (function_search.h).
// The four-bars are analysed from the first pair's configuration and ranked (lib/design_
// constraints.h).
FunctionResult SolveFunctionTask(const Task& task, const TaskSolverOptions& options = {});

// Spatial motion only: solve, refine (more than seven poses, unless effort is fast), and add
// the platform. A spherical motion of six or more orientations: every seed dyad refined
// (RefineSphericalResult), unless effort is fast.
SpatialMotionResult SolveSpatialTask(const Task& task, const TaskSolverOptions& options = {});

// Effort fast on a spherical least-squares result: its seed dyads, the max_dyads best-fitting
// kept (a note counts the rest), and their four-bars, at most reported_mechanisms listed.
void SolveSphericalSeedsFast(const Task& task, const TaskSolverOptions& options,
                             SpatialMotionResult* result);

// Refines every seed dyad of a spherical least-squares result on its cone residual
// (spherical_dyad_refiner.h), drops repeats, keeps the max_dyads best-fitting and rebuilds the
// four-bars. Effort thorough adds the distinct optima of the search (SearchSphericalDyads, up to
// spherical_search.polish_count) to those max_dyads, dropping none of them, and says what the
// search did in a note; its time is search_seconds. Of the fast level's (SolveSphericalSeedsFast)
// refined_mechanisms first-ranked four-bars and its best-fitting defect-free one, those that are
// defect-free and fit better than every defect-free four-bar of the refined dyads keep their seed
// dyads too, unrefined (when they meet every exact orientation), so that balanced never answers
// worse than fast, nor thorough than balanced.
void RefineSphericalResult(const Task& task, const TaskSolverOptions& options,
                           SpatialMotionResult* result);

// `linkfit refine` and linkfit.refine: a design (a result file's, or written by hand) refined
// against a task, the result in the form `linkfit solve` gives, with "method": "refine", the
// errors before and after in a note and each design's "before_refinement". The task's weights,
// exact poses or points and design constraints hold as in the solver's refinements; with
// constraints given, a design whose transmission angle keeps their minimum keeps it (planar and
// path four-bars); without, the refinement is the fit's, and a note says when that costs the
// transmission angle.
//   - planar motion: the four-bar of two dyads refined on its pose error (four_bar_refiner.h);
//   - path problems: the crank-driven four-bar refined on its point errors (path_refiner.h),
//     under the task's timing; free timing starts from the design's fitted input angles, or from
//     the timing its coupler curve gives the points (the nearer of both turning directions);
//   - spatial motion: each dyad refined on its residuals (spatial_dyad_refiner.h), then the
//     platform of the design's five traced.
struct RefineChoice {
  int mechanism = 0;                 // which of the design's mechanisms (0 = the first listed)
  std::string task_source = "task";  // names the task, the design and the choice in messages
  std::string design_source = "design";
  std::string mechanism_item = "design: mechanism 0";
};

// Throws InputError (lib/task_io.h) when the design does not fit the task: a mechanism it does
// not list, a planar design of more than two dyads and no mechanisms, free-timing angles of
// another count than the points, a spatial task of fewer than seven poses. `design` must be of
// the task's kind (ParseTaskDesign).
TaskResult RefineTask(const Task& task, const TaskDesign& design, const RefineChoice& choice,
                      const TaskSolverOptions& options = {});

// The note of a refinement whose result's transmission angle falls below the task's minimum
// where the design's did not (a task without constraints: the refinement is the fit's).
std::string TransmissionNote(const DesignConstraints& constraints);

// The refinements RefineTask dispatches to, one per kind of task. `converged` (planar motion
// and paths), when given, says whether the refinement of the design returned ended on a
// tolerance; false where it stopped at its iteration limit (RefinerSummary::converged), so that
// refining the result again may still gain.
PlanarMotionResult RefinePlanarDesign(const Task& task, const PlanarDyad& input,
                                      const PlanarDyad& output,
                                      const TaskSolverOptions& options = {},
                                      bool* converged = nullptr);
// `input_angles`: free timing's starting angles (radians, one per point), or empty. Throws
// std::invalid_argument when the four-bar does not assemble at its crank's first angle.
PathResult RefinePathDesign(const Task& task, const PathFourBar& four_bar,
                            const std::vector<double>& input_angles,
                            const TaskSolverOptions& options = {}, bool* converged = nullptr);
// `platform`: five indices into `dyads`, or empty for the default five (AddPlatform).
SpatialMotionResult RefineSpatialDesign(const Task& task, const std::vector<SpatialDyad>& dyads,
                                        const std::vector<int>& platform,
                                        const TaskSolverOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_TASK_SOLVER_H_
