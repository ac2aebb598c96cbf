// Three to five planar poses whose exact four-bars do not give a designer one to build (issue
// 35, item 1): linkfit chooses the pivots itself, within the task's constraints.
//
// Minimal data leave a family of dyads (three poses: every point of E; four: the Burmester
// curves) or a few isolated ones (five). When no listed four-bar keeps the constraints without a
// defect, or four poses come without pivots, the result goes on:
//   - four poses: dyads spread along the Burmester curves (center-point curve in Sigma,
//     circle-point curve in E) within the constraints that bound a dyad alone (pivot boxes,
//     crank lengths), paired into four-bars that meet all four poses exactly;
//   - three poses: dyads of moving pivots spread over E (the moving-pivot box, else the body's
//     neighbourhood) and of fixed pivots spread over Sigma (the fixed-pivot box, else the poses'
//     neighbourhood), the circle through each pivot's three positions (its centre the fixed
//     pivot), paired likewise;
//   - five poses: the four-bars of each four-pose subset chosen as above, judged on all five
//     (their largest pose error is the fifth pose's miss), and the best of them and the exact
//     four-bars that break a constraint refined as the bounded least-squares fit of all five
//     (FourBarRefinerOptions::constraints, the transmission angle held where it fails).
// The best-ranked of them (lib/design_constraints.h: keeping every constraint without a defect
// first; among exact ones the better transmission angle), each bringing a dyad farther than
// PivotChoiceOptions::spread from those of the better-ranked ones, are listed with the task's own,
// each with MechanismReport::chosen saying how it was chosen and its pose errors.
#ifndef LINKFIT_OPTIMIZERS_PIVOT_CHOICE_H_
#define LINKFIT_OPTIMIZERS_PIVOT_CHOICE_H_

#include "lib/result.h"
#include "lib/task.h"

namespace linkfit {

struct PivotChoiceOptions {
  int curve_candidates = 60;   // four poses: dyads taken along the curves within the bounds
  int subset_candidates = 20;  // five poses: the same per four-pose subset
  int grid = 7;                // three poses: pivots per side of each grid (moving, fixed)
  // Without a box for them, pivots are chosen within this many L of the pose origins' centroid
  // (the moving pivot at the first pose); where none is, farther (pivot_choice.cc kFarReach).
  double reach = 5.0;
  // A chosen four-bar brings a dyad whose pivots are more than this many L from those of every
  // better-ranked choice: one that only recombines them, or moves them less, is not listed.
  double spread = 0.5;
  // Three and four poses: a chosen four-bar whose shortest link is below this times its longest
  // is listed only when no other is (they all meet the poses: a designer does not build a
  // coupler of a tenth of its cranks). Five poses' choices are judged by their fit.
  double link_ratio = 0.1;
  int listed = 6;   // chosen four-bars listed at most
  int refined = 2;  // five poses: chosen four-bars refined by least squares of all five
};

// Whether a solved planar motion task of three to five poses gets chosen pivots: four poses
// without pivots given, no four-bar listed, or constraints given and the first listed four-bar
// breaks one, has a defect (the transmission angle included) or misses a pose marked exact.
bool NeedsPivotChoices(const Task& task, const PlanarMotionResult& result);

struct TaskSolverOptions;

// Adds the chosen four-bars (file comment) to `result`, their dyads appended to its dyads, ranks
// every listed four-bar again and says in a note what was chosen and how the first fits. Five
// poses' least squares (not at effort "fast") refines as `linkfit refine` does
// (RefinePlanarDesign with `solver`); `solver.pivot_choice` sets the choice.
void AddPivotChoices(const Task& task, const TaskSolverOptions& solver, PlanarMotionResult* result);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PIVOT_CHOICE_H_
