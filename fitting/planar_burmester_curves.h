// Fewer than five planar poses: the one-parameter dyad families of four poses (Burmester's
// center-point and circle-point curves) and the dyad of a chosen pivot for three or four poses.
//
// The dyads of four poses form a curve: their fixed pivots trace the center-point curve (in
// Sigma), a circular cubic, and their moving pivots the circle-point curve (in E). The curve is
// traced parametrically: lines through a point of the cubic meet it in two more points, the
// roots of a quadratic in the distance along the line, so the line's angle parametrizes the
// whole curve in closed form (each root over the angles where the quadratic's discriminant, a
// quartic form, is positive; the two roots meet at its zeros). Every component is found, in
// order, with the samples dense where the dyads move fast. The PR and RP dyads (the cubic's
// point at infinity and the point whose circle point is at infinity) come from the slider plane
// of the constraint space (planar_burmester.h).
#ifndef LINKFIT_FITTING_PLANAR_BURMESTER_CURVES_H_
#define LINKFIT_FITTING_PLANAR_BURMESTER_CURVES_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

struct BurmesterCurveOptions {
  // Consecutive samples farther apart than this (relative to L) start a new polyline, so that
  // branches through infinity are not joined across the picture.
  double break_distance = 2.0;
  // Where the dyads lie within refine_radius, consecutive samples differ by at most this
  // (relative to L) in either pivot and in the radius, so that every dyad of the curve there
  // is within about half of it of a sample. Elsewhere the curve is only sketched.
  double refine_step = 0.03;
  // The radius (relative to L) about the pose-origin centroid within which the sampling is
  // this dense: a dyad is inside when both pivots (the moving one at the first pose) are.
  // Farther out the curve runs off to infinity; it is sketched (consecutive samples at most 4 %
  // of their distance from the centroid apart, and at most half the break distance) out to
  // 100 L, where it is left.
  double refine_radius = 25.0;
};

// The sampled Burmester curve of exactly four poses: polylines of dyads, each continuous.
// Center points are the dyads' fixed pivots (RR) and circle points their moving pivots. A closed
// branch repeats its first dyad at its end; the PR and RP dyads of the curve (at most one each
// for a general task) are branches of one dyad. RR dyads with a pivot beyond 100 L are left out.
struct BurmesterCurves {
  std::vector<std::vector<PlanarDyad>> branches;
};

// Samples the curve; returns the number of dyads sampled, each counted once (0 for fewer or
// more than four poses or a degenerate task). Every dyad fits the four poses to 1e-10 L.
int SampleBurmesterCurves(const std::vector<PlanarPose>& poses,
                          const BurmesterCurveOptions& options, BurmesterCurves* curves);

// The dyad whose moving pivot (in E) is `moving_pivot`, for three or more poses: the fixed
// pivot is the centre of the circle through (three poses) or best fitting (more) the pivot's
// positions in Sigma. For four poses, a pivot off the circle-point curve is first moved to the
// nearest point of the curve. Sets *note when it moved the pivot or the positions are collinear
// (then the dyad is PR). Returns false when no dyad exists.
bool DyadFromMovingPivot(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& moving_pivot,
                         PlanarDyad* dyad, std::string* note);

// The same from a fixed pivot (in Sigma), by inversion (center-point curve; RP if collinear).
bool DyadFromFixedPivot(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& fixed_pivot,
                        PlanarDyad* dyad, std::string* note);

// For three poses without user pivots: two moving pivots a designer would start from, and a
// one-line explanation of the choice for the result's notes.
void DefaultMovingPivots(const std::vector<PlanarPose>& poses, Eigen::Vector2d pivots[2],
                         std::string* explanation);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_BURMESTER_CURVES_H_
