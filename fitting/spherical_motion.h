// Spherical motion generation, end to end: spatial poses whose displacements all fix one point
// (fitting/spatial_motion.h DetectSphericalMotion) are solved as spherical, the way planar data
// are solved as planar: spherical RR dyads about the centre (fitting/spherical_burmester.h) and
// the spherical four-bars of every pair (lib/spherical_four_bar.h), analysed and ranked as the
// planar four-bars are.
//   - Five orientations: every dyad (up to six).
//   - Six or more: the algebraic least-squares seed and the exact dyads of spread five-pose
//     subsets (refined in optimizers/).
//   - Four: the center-axis and circle-axis cones; three or four with chosen axes
//     (moving_axes / fixed_axes): one dyad each.
#ifndef LINKFIT_FITTING_SPHERICAL_MOTION_H_
#define LINKFIT_FITTING_SPHERICAL_MOTION_H_

#include <vector>

#include "fitting/spherical_burmester.h"
#include "lib/result.h"
#include "lib/spherical_four_bar.h"
#include "lib/task.h"

namespace linkfit {

struct SphericalMotionOptions {
  SphericalBurmesterOptions burmester;
  int cone_samples = 720;  // four orientations: planes of the cones' pencils
  // Six or more orientations: five-orientation subsets solved for seeds besides the algebraic
  // least-squares fit.
  int seed_subsets = 4;
  // Six or more orientations: build the four-bars of the seeds. False when the caller refines the
  // seeds first and builds the four-bars of the refined dyads (SolveSpatialTask).
  bool seed_mechanisms = true;
};

// The task's motion about the centre.
SphericalMotion TaskSphericalMotion(const Task& task, const SphericalCenter& center, double length);

// Solves a spherical task (the centre found) into result: model "spherical", its dyads and
// four-bars (not refined).
void SolveSphericalMotion(const Task& task, const SphericalCenter& center,
                          const SphericalMotionOptions& options, SpatialMotionResult* result);

// The dyads of five orientations, or for more the seeds: the algebraic least-squares dyads and
// those of up to `subsets` spread five-orientation subsets; repeats dropped. `summary`: of the
// solve of all orientations.
int SphericalSeeds(const std::vector<Eigen::Matrix3d>& rotations,
                   const std::vector<double>& weights, const SphericalBurmesterOptions& options,
                   int subsets, std::vector<SphericalDyad>* seeds,
                   SphericalBurmesterSummary* summary = nullptr);

// Whether two dyads are one: SphericalDyadDistance (lib/spherical_dyad.h) within `tolerance`.
bool SameSphericalDyad(const SphericalDyad& a, const SphericalDyad& b, double tolerance);

// The report of a dyad over the motion: max_residual (and for more than five orientations the
// weighted RMS) in length units (L times the angle), and its error bound at the data's precision.
SphericalDyadReport ReportSphericalDyad(const SphericalDyad& dyad, const SphericalMotion& motion,
                                        const std::vector<double>& weights,
                                        const DataPrecision& precision);

// The four-bar of dyads i and j (both inputs tried, the better kept), judged against the task's
// constraints (input_rotates_fully, grashof, min_transmission_angle_deg). With `screened` (its
// analysis on spread orientations: BuildSphericalMechanisms), the input it chose drives and its
// output's full rotation is taken from it.
MechanismReport AnalyzeSphericalPair(const std::vector<SphericalDyadReport>& dyads, int i, int j,
                                     const SphericalMotion& motion,
                                     const DesignConstraints& constraints,
                                     const MechanismReport* screened = nullptr);

// Every four-bar of two of result->spherical_dyads, analysed and ranked; with `bound` >= 0 at
// most that many listed (RankMechanisms: and the best of each group), the rest said in a note.
void BuildSphericalMechanisms(const Task& task, const SphericalMotion& motion,
                              SpatialMotionResult* result, int bound = -1);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SPHERICAL_MOTION_H_
