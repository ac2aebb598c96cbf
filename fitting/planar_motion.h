// Planar motion generation, end to end: every dyad through the task poses and every
// four-bar made of two of them, checked by assembly. For exactly five poses the dyads are
// exact (planar_burmester.h); for more, the algebraic least-squares seed.
#ifndef LINKFIT_FITTING_PLANAR_MOTION_H_
#define LINKFIT_FITTING_PLANAR_MOTION_H_

#include <cmath>
#include <functional>

#include "fitting/planar_burmester.h"
#include "lib/four_bar_motion.h"
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
// poses, so that one bad pose does not spoil every seed. With poses marked `exact` (one flag per
// pose, or empty), every subset holds them (up to five; more: subsets of them alone), so that
// the subsets' dyads pass through them. Repeated dyads are dropped. Returns the count.
int PlanarSeeds(const std::vector<PlanarPose>& poses, const PlanarBurmesterOptions& options,
                int subsets, std::vector<PlanarDyad>* seeds, const std::vector<bool>& exact = {});

// The subsets of `size` items the seeds of a least-squares task are solved from (planar poses,
// path points, spherical orientations, function pairs): SpreadSubsets of the items, or with
// items marked exact, each the exact ones and a spread subset of the others (more exact items
// than `size`: SpreadSubsets of the exact ones), so that every seed meets them. Indices into the
// items, each subset sorted.
std::vector<std::vector<int>> SeedSubsets(int count, int subsets, const std::vector<bool>& exact,
                                          int size = 5);

// The five-pose subsets PlanarSeeds solves (other solvers: subsets of `size`): subset k takes the
// poses at positions round((i + k / subsets) n / size) modulo n, i < size, so that consecutive
// subsets shift through the task; repeated subsets and those with a repeated position are left out.
std::vector<std::vector<int>> SpreadSubsets(int count, int subsets, int size = 5);

// `wanted` indices spread evenly over [0, count), the first and the last among them, and every
// index `exact` marks, in order and once each (all indices when `wanted` >= count): the items a
// solver screens a long task on (BuildMechanisms; free-timing paths).
std::vector<size_t> SpreadIndices(size_t count, size_t wanted, const std::vector<bool>& exact);

// Whether two dyads are one: of a type, and their pivots, radii and lines within the data's
// precision (kModelUnits point uncertainties at their size), within `bound` (how far the data's
// precision can move them: the smaller of their DyadErrorBounds, at most 10 % of their size) or
// within 1e-7 of their size. The size is the larger of L and the dyad's reach: its moving pivot
// from E's origin, its fixed pivot and line from `center` (the pose origins' centroid in Sigma),
// so that moving the data's origin away merges nothing.
bool SameDyad(const PlanarDyad& a, const PlanarDyad& b, const DataPrecision& precision,
              double length, const Eigen::Vector2d& center, double bound = 0.0);

// The pose error below which a four-bar meets the poses within their precision (kModelUnits
// point uncertainties of a point L from E's origin), not below 1e-8 L: two fits below it are a
// near tie in the ranking.
double PoseFitTolerance(const DataPrecision& precision, double length);

// A four-bar judged against the task: the constraints it violates; the defect "degenerate" when
// a link is no longer than the data's precision can resolve (the dyads' error bounds and
// kModelUnits of the rounding), "misses" when of five poses or fewer it misses one by more than
// PoseFitTolerance on its circuit and branch (no other kinematic defect to say why), and
// "transmission" when its worst transmission angle is below min_transmission_angle_deg.
void JudgeMechanism(const Task& task, const std::vector<DyadReport>& dyads, double length,
                    MechanismReport* mechanism);

// Every four-bar made of two of result->dyads (of those pairs i < j whose `levels` mask is not
// 0, when given: bit k set when both dyads are among effort level k's), each analysed under both
// inputs (the better kept), judged (JudgeMechanism; misses of the task's exact poses too), those
// of the same two dyads listed once, and ranked (RankMechanisms). The poses are the task's
// planar poses. Above 2000 poses the pairs are ranked on 2000 spread poses (and the exact ones)
// first, and only the best-ranked (the first 12, the first 4 and the best fit of each level, the
// best of each group of the ranking rule) are analysed on every pose and listed, with a note.
void BuildMechanisms(const Task& task, double length, PlanarMotionResult* result,
                     const std::function<int(int, int)>& levels = {});

// The parts of a four-bar's report that its analysis gives (planar FourBarAnalysis, spherical
// SphericalFourBarAnalysis): from `chosen`, the analysis of its input, the largest pose error,
// the defects, the input's full rotation and the transmission angle; from `other`, that of the
// other dyad driving, the output's full rotation; with `least_squares` (more than five poses),
// the RMS of the pose errors (each at its nearest configuration).
template <typename Analysis>
void TakeAnalysis(const Analysis& chosen, const Analysis& other, bool least_squares,
                  MechanismReport* mechanism) {
  mechanism->max_pose_error = chosen.max_pose_error;
  mechanism->defects = chosen.defects;
  mechanism->input_rotates_fully = chosen.input_rotates_fully;
  mechanism->output_rotates_fully = other.input_rotates_fully;
  mechanism->transmission_min_deg = chosen.transmission_min_deg;
  mechanism->transmission_max_deg = chosen.transmission_max_deg;
  mechanism->transmission_note = chosen.transmission_note;
  mechanism->order_within_noise = chosen.order_within_noise;
  if (least_squares && mechanism->max_pose_error) {
    double sum = 0.0;
    for (const FourBarLocation& location : chosen.locations) {
      sum += location.pose_error * location.pose_error;
    }
    mechanism->rms_pose_error = std::sqrt(sum / static_cast<double>(chosen.locations.size()));
  }
}

// How near a least-squares four-bar or dyad must come to a pose marked exact, times L (README,
// "Task file": such poses are met to 1e-9 L).
constexpr double kExactPoseTolerance = 1e-9;

// The analysis of the four-bar of dyads i and j of `dyads` (both inputs tried, the better kept).
// With `exact` (one flag per pose), its largest error at the exact poses and whether it misses
// them (MechanismReport::exact_pose_error, misses_exact).
// With `screened` (its analysis on spread poses: BuildMechanisms), the input it chose drives and
// its output's full rotation is taken from it.
MechanismReport AnalyzeDyadPair(const std::vector<DyadReport>& dyads, int i, int j,
                                const std::vector<PlanarPose>& poses, double length,
                                const std::vector<bool>& exact = {},
                                const MechanismReport* screened = nullptr);

// A mechanism's key in the ranking rule (lib/design_constraints.h): the fit is the RMS pose
// error for least squares, else the largest; within the data's precision when its largest pose
// error is at most `precision_fit` (PoseFitTolerance); the task's `constraints` tell its
// defaults (JudgeWithDefaults).
RankKey MechanismRankKey(const MechanismReport& mechanism, double precision_fit,
                         const DesignConstraints& constraints);

// Ranks mechanisms by the rule of lib/design_constraints.h (RankReports): keeping the
// constraints, defect-free, by fit (RMS pose error for least squares, else the largest), near
// ties by worst transmission angle. `precision_fit`: PoseFitTolerance. With `bound` >= 0 at
// most that many are kept, and the best fit of each group (ListedWithinBound); returns how many
// were dropped.
int RankMechanisms(double precision_fit, const DesignConstraints& constraints, int bound,
                   std::vector<MechanismReport>* mechanisms);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_MOTION_H_
