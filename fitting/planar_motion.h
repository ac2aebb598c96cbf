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
  // Five poses whose constraint matrix has a condition estimate (sigma_1 / sigma_5) above this
  // are called "ill-conditioned" in the error-bound note.
  double ill_conditioned = 1e6;
  // The dyads' error bound relative to their size: condition_error_factor * condition * the
  // data's relative precision (measured: linkfit bench, rounded data), never below the
  // rounding-level bound 3e-13 * condition. Five poses whose bound exceeds error_note get a
  // note with it.
  double condition_error_factor = 10.0;
  double error_note = 1e-2;
};

// The relative error bound of five-pose dyads (PlanarMotionOptions): at least the rounding
// level, condition * factor times the data's relative precision.
double ConditionErrorBound(double condition, double relative_precision,
                           const PlanarMotionOptions& options = {});

// Solves a validated planar motion task (at least five poses). Never throws for numerical
// trouble: what could not be done is said in result.notes.
PlanarMotionResult SolvePlanarMotion(const Task& task, const PlanarMotionOptions& options = {});

// Seeds for more than five poses: the dyads of the algebraic least-squares fit (three smallest
// singular vectors) and of exact five-pose solves of up to `subsets` spread-out subsets of the
// poses, so that one bad pose does not spoil every seed. Repeated dyads are dropped. Returns
// the count.
int PlanarSeeds(const std::vector<PlanarPose>& poses, const PlanarBurmesterOptions& options,
                int subsets, std::vector<PlanarDyad>* seeds);

// The five-pose subsets PlanarSeeds solves: subset k takes the poses at positions
// round((i + k / subsets) n / 5), i = 0..4, so that consecutive subsets shift through the task.
std::vector<std::vector<int>> SpreadSubsets(int count, int subsets);

// Every four-bar made of two of result->dyads, each analysed under both inputs (the better
// kept), ranked defect-free first, then by worst transmission angle, then by pose error.
void BuildMechanisms(const std::vector<PlanarPose>& poses, double length,
                     PlanarMotionResult* result);

// The analysis of the four-bar of dyads i and j of `dyads` (both inputs tried, the better kept).
MechanismReport AnalyzeDyadPair(const std::vector<DyadReport>& dyads, int i, int j,
                                const std::vector<PlanarPose>& poses, double length);

// Ranks mechanisms: defect-free first, then by worst transmission angle, then by pose error.
void RankMechanisms(std::vector<MechanismReport>* mechanisms);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_MOTION_H_
