// Spatial motion generation, end to end: the simplest model the poses need, every dyad through
// them, and the 5-dyad platforms made of them.
//   - Poses in one plane (all relative rotations about one axis direction, translations
//     perpendicular to it): solved as a planar problem (planar_motion.h) and reported in
//     spatial coordinates, as seed 000 section 6 does; both pivots of such an RR dyad may slide
//     along the plane normal. Seven or more planar poses also get the note that every body
//     point moves in a plane parallel to the plane of motion (the PS family of section 5).
//   - Three or more poses that all fix one point within the data's precision (a spherical
//     motion): solved as spherical (fitting/spherical_motion.h), spherical RR dyads and
//     four-bars about the centre.
//   - Seven or more poses: spatial_burmester.h (exact for seven, algebraic least squares
//     beyond; the refinement is in optimizers/).
//   - Four to six poses with given pivots: one SS dyad per pivot (a sphere through the pivot's
//     positions); without pivots, the dimension of the solution family is reported.
// Design constraints (those a spatial task takes: input_rotates_fully, grashof,
// min_transmission_angle_deg) judge the spherical four-bars and the planar four-bars of planar
// data; spatial answers (dyads and platforms) are not judged by them, which a note says.
#ifndef LINKFIT_FITTING_SPATIAL_MOTION_H_
#define LINKFIT_FITTING_SPATIAL_MOTION_H_

#include <optional>
#include <vector>

#include "fitting/planar_motion.h"
#include "fitting/spatial_burmester.h"
#include "fitting/spherical_motion.h"
#include "lib/platform_motion.h"
#include "lib/result.h"
#include "lib/task.h"

namespace linkfit {

struct SpatialMotionOptions {
  SpatialBurmesterOptions burmester;  // seven or more poses
  PlanarMotionOptions planar;         // planar data
  // Poses whose out-of-plane deviation (translation along the normal, and L times the tilt of
  // the rotation axes) stays below this times L are solved as planar.
  double planarity_tolerance = 1e-8;
  // Poses whose displacements all fix one point within this times L (or within what the data's
  // precision allows) are a spherical motion.
  double sphericity_tolerance = 1e-8;
  // Poses whose fitted centre is fixed within this times L, but not within the data's precision,
  // are solved as spatial with a note that they are nearly spherical.
  double nearly_spherical = 1e-2;
  PlatformMotionOptions platform;    // the platform's forward kinematics
  SphericalMotionOptions spherical;  // spherical motions (fitting/spherical_motion.h)
};

// The characteristic length of a spatial task: its "scale", else the RMS distance of the pose
// origins from their centroid (1 if they coincide).
double SpatialTaskLength(const Task& task);

// The planarity tolerance (relative to L) of a task: the options', or what the data's precision
// allows (lib/precision.h: rounding moves origins off a plane and tilts rotations), whichever
// is larger, so that planar data printed to a few digits are solved as planar.
double PlanarityTolerance(const Task& task, double length, const SpatialMotionOptions& options);

// The plane of motion when the poses are planar within tolerance * length; nullopt otherwise.
std::optional<PlanarEmbedding> DetectPlanarMotion(const std::vector<DualQuaternion>& poses,
                                                  double length, double tolerance);

// The point of the body that the poses move least (least squares of R_j p + d_j = P), with its
// largest deviation; nullopt for fewer than three poses and when the rotations do not determine it
// (all about one axis direction).
std::optional<SphericalCenter> FitSphericalCenter(const std::vector<DualQuaternion>& poses,
                                                  double length);

// What a fitted centre may deviate and still be fixed: tolerance * L, or what the data's
// precision allows (DetectSphericalMotion).
double SphericityTolerance(const SphericalCenter& center, double length,
                           const DataPrecision& precision, double tolerance);

// The centre (lib/result.h SphericalCenter) when the poses' displacements all fix one point
// within what the data's precision allows, kModelUnits * hypot(2 sqrt(3) delta, 2 |p| alpha)
// (rounding moves a pose's origin by up to sqrt(3) delta and tilts it by alpha, which moves the
// image of p by |p| alpha; doubled for the fit of P, as PlanarityTolerance does), or within
// tolerance * length; nullopt otherwise, and when the rotations do not determine the point (all
// about one axis direction, sigma_6 below kCenterDetermined sigma_1: planar motion).
std::optional<SphericalCenter> DetectSphericalMotion(const std::vector<DualQuaternion>& poses,
                                                     double length, const DataPrecision& precision,
                                                     double tolerance);

// Solves a validated spatial motion task without refinement or platforms.
SpatialMotionResult SolveSpatialMotion(const Task& task, const SpatialMotionOptions& options = {});

// The note of a task with design constraints whose poses are solved as spatial: the
// constraints judge spherical and planar four-bars only. Added to result->notes when the task
// has constraints.
void AddSpatialConstraintsNote(const Task& task, SpatialMotionResult* result);

// Orders dyads by radius, smallest first (the platform's default dyads lead); planes last.
void SortDyadsByRadius(std::vector<SpatialDyadReport>* dyads);

// Builds the platform of the task's `platform` dyads, or by default of the five SS/PS dyads of
// smallest radius (planes last), traces its motion and appends it to result->mechanisms.
void AddPlatform(const Task& task, const PlatformMotionOptions& options,
                 SpatialMotionResult* result);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SPATIAL_MOTION_H_
