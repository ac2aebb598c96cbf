// Model choice at the data's precision (README, "Data from tables and measurements"). Where the
// data cannot tell two models apart at their precision (lib/precision.h), the simpler one is
// reported, and the result says what was tested:
//   - slider or circle: a circle whose slider reading fits the poses within the data's
//     uncertainty is a slider. The reading is a least-squares fit of the line to the pivot's
//     positions (PR: the moving pivot in Sigma; RP: the fixed pivot seen from E), not the
//     circle's tangent, so a circle bent by rounding still straightens;
//   - plane or sphere (spatial): the same with a plane fitted to the moving point's positions
//     (PS) or to the fixed point seen from E (SP).
// "Within the uncertainty" is PrecisionRatio <= kModelUnits: at every pose the constrained
// point misses its line or plane by at most kModelUnits times PointUncertainty (the data move a
// point r from the frame origin by up to sqrt(dim) delta + r alpha). The factor covers the
// least-squares model fitting a little worse at its worst pose than the generating one.
#ifndef LINKFIT_FITTING_MODEL_CHOICE_H_
#define LINKFIT_FITTING_MODEL_CHOICE_H_

#include <limits>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "lib/precision.h"
#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"
#include "lib/spherical_dyad.h"

namespace linkfit {

// A simpler model fits the data when its PrecisionRatio is at most this.
inline constexpr double kModelUnits = 2.0;

// Largest over the poses of |residual_j| / u_j, u_j = PointUncertainty of the dyad's
// constrained point at pose j (RR, PR: the moving pivot, |m| from E's origin; RP: the fixed
// pivot, |F - d_j| from it). `scale` (the task's L) sets the rounding floor.
double PrecisionRatio(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                      const DataPrecision& precision, double scale);
// The same in space (SS, PS: the moving point c; SP: the fixed point seen from E).
double PrecisionRatio(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
                      const DataPrecision& precision, double scale);

// First-order bound of how far the data's precision can move a dyad fitted to the poses: with
// J the Jacobian of the residuals (one per pose) in the dyad's parameters (RR: F, m, r; PR: m,
// line normal angle, offset; RP: F, angle, offset) and u_j the uncertainty of the constrained
// point at pose j (PrecisionRatio), each parameter moves by at most sum_j |(J^+)_ij| u_j. The
// bound is the largest pivot, radius or line displacement (an angle error times the extent of
// the line the pivot sweeps), in length units. Infinity when the poses do not determine the
// dyad (J rank-deficient: e.g. the radius of a circle whose pivot barely turns).
double DyadErrorBound(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                      const DataPrecision& precision, double scale);

// The parts of the planar DyadErrorBound (its largest): how far the data's precision can move
// each pivot, the radius and the line (the normal's angle error times the extent of the line
// the pivot sweeps, plus the offset's), in length units; infinity for a part the dyad does not
// have or the poses do not determine.
struct PlanarDyadBounds {
  double fixed_pivot = std::numeric_limits<double>::infinity();   // RR, RP
  double moving_pivot = std::numeric_limits<double>::infinity();  // RR, PR
  double radius = std::numeric_limits<double>::infinity();        // RR
  double line = std::numeric_limits<double>::infinity();          // PR, RP
};
PlanarDyadBounds DyadErrorBounds(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                                 const DataPrecision& precision, double scale);

// The same for the dyad of a pivot the task gives (three or four poses: the circle through the
// pivot's positions): the pivot held (`moving_given`: the moving pivot, else the fixed one), the
// other pivot and the radius (a slider: its line) moved by the poses' precision. Infinity when
// the poses do not determine them.
double PivotDyadErrorBound(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                           const DataPrecision& precision, double scale, bool moving_given);

// The same in space: SS (A, c, r), PS (c, the normal's two tangent turns, offset), SP (A, normal,
// offset). Near a double root of the seven-pose problem (J nearly singular: the real part of a
// complex pair that rounding made of two nearby dyads) the move along J's weakest direction is
// bounded to second order, by the residuals' curvature along it, where first order grows
// without bound.
double DyadErrorBound(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
                      const DataPrecision& precision, double scale);

// The same for a spherical RR dyad (lib/spherical_dyad.h) over the orientations of a spherical
// motion: the residuals angle(u, R_j v) - alpha in the fixed axis' two tangent turns, the moving
// axis' two and the cone angle, each orientation uncertain by the data's angle precision (the
// rotations are the poses' own, whatever the centre); second order along J's weakest direction
// near a double root, as in space. The bound is the largest turn of either axis or change of the
// cone angle, in radians. Infinity for fewer than five orientations or when they do not
// determine the dyad.
double DyadErrorBound(const SphericalDyad& dyad, const std::vector<Eigen::Matrix3d>& rotations,
                      const DataPrecision& precision);

// How far apart two designs of size `size` may be and still be one (planar SameDyad, the
// spatial dyads' merge): within the data's precision (kModelUnits point uncertainties at their
// size, in `dimension` coordinates), within `bound` (how far the precision can move them: the
// smaller of their error bounds, at most 10 % of their size), or within `relative` of their size.
double SameDesignTolerance(const DataPrecision& precision, double size, double length,
                           int dimension, double bound, double relative);

// The dyad of the same type that fits the poses best in least squares (the sum of squared
// residuals), by Levenberg-Marquardt from `start` in the parameters of DyadErrorBound, at most
// `iterations` steps. Used where no exact real dyad exists nearby: a circle bent from a line
// by rounding (its slider reading), the real part of a complex root pair.
PlanarDyad FitDyadLeastSquares(const PlanarDyad& start, const std::vector<PlanarPose>& poses,
                               int iterations);
// Two unit vectors tangent to a unit plane normal (normal x the least axis, then normal x that):
// the directions it turns in, and with the normal a right-handed frame.
void NormalTurns(const Eigen::Vector3d& normal, Eigen::Vector3d* turn1, Eigen::Vector3d* turn2);

// The same for a spherical dyad over the orientations of a spherical motion, in the parameters of
// its DyadErrorBound (the axes' tangent turns, the cone angle): the real part of a complex root
// pair of the five-orientation problem.
SphericalDyad FitDyadLeastSquares(const SphericalDyad& start,
                                  const std::vector<Eigen::Matrix3d>& rotations, int iterations);

// A pose's rotation and translation, evaluated once (the fits evaluate residuals many times).
struct SpatialFrame {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};
std::vector<SpatialFrame> SpatialFrames(const std::vector<DualQuaternion>& poses);

// The residuals of a spatial dyad at the poses and their Jacobian (when `jacobian` is given) in
// its parameters: SS (A, c, r); PS (c, the normal's two turns, offset); SP (A, the turns,
// offset). *extent (PS, SP) gets how far the constrained point runs from the plane's foot.
// Returns the sum of squares (weights ignored).
double SpatialDyadResiduals(const SpatialDyad& dyad, const std::vector<SpatialFrame>& frames,
                            Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian,
                            double* extent = nullptr);
// The dyad moved by -step in the parameters of SpatialDyadResiduals (the normal turned about
// its current turns and normalized).
SpatialDyad SpatialDyadStep(const SpatialDyad& dyad, const Eigen::VectorXd& step);

// The same in space, in the parameters of SpatialDyadResiduals (those of the spatial
// DyadErrorBound): the real part of a complex root pair of the seven-pose problem.
SpatialDyad FitDyadLeastSquares(const SpatialDyad& start, const std::vector<DualQuaternion>& poses,
                                int iterations);
SpatialDyad FitDyadLeastSquares(const SpatialDyad& start, const std::vector<SpatialFrame>& frames,
                                int iterations);

// The note of a condition-based error bound: "condition estimate K with data precise to p
// (relative): the dyads may be off by up to about B of their size", and, when B >= 1, that the
// answer means nothing at this precision.
std::string ConditionNote(double condition, double relative_precision, double bound);

// The slider readings of a circle by total least squares: PR keeps the moving pivot and fits
// the line to its positions in Sigma; RP keeps the fixed pivot and fits the line to where E
// sees it.
PlanarDyad FitSliderPR(const PlanarDyad& circle, const std::vector<PlanarPose>& poses);
PlanarDyad FitSliderRP(const PlanarDyad& circle, const std::vector<PlanarPose>& poses);

// The plane readings of a sphere by total least squares: PS keeps the moving point and fits
// the plane to its positions in Sigma; SP keeps the fixed point and fits the plane in E.
SpatialDyad FitPlanePS(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses);
SpatialDyad FitPlaneSP(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses);

// The simpler model of a circle or sphere at the data's precision: the slider or plane reading
// with the smaller PrecisionRatio when it is at most kModelUnits (written to *simpler,
// returns true); otherwise false.
bool SimplerModel(const PlanarDyad& circle, const std::vector<PlanarPose>& poses,
                  const DataPrecision& precision, double scale, PlanarDyad* simpler);
bool SimplerModel(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses,
                  const DataPrecision& precision, double scale, SpatialDyad* simpler);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_MODEL_CHOICE_H_
