// A planar four-bar as a path generator with prescribed timing: its input crank turns by the
// task's input angles and a point of its coupler must pass the task's points (seed 002).
//
// Conventions: the coupler frame E coincides with Sigma in the configuration of the first
// point, so every pivot and the coupler point are also their positions in Sigma at the first
// point (the design's path-mechanism format). The input dyad is an RR crank; at point j its
// crank angle is InputValue(input, identity) + (psi_j - psi_0).
//
// Defects under a prescribed input (the crank is driven from psi_0 through psi_1, ... in
// turn, each step the direct way psi_j - psi_{j-1}):
//   branch  a step passes a stationary configuration (the output loses assembly between two
//           points: the crank would have to reverse, or the mechanism be taken apart);
//   circuit a point is met only in the other assembly (the coupler point is nearer the point
//           on the assembly the crank does not reach from the first point).
// The order of the points is the timing itself, so an order defect cannot occur.
//
// Closed paths (PathAnalysisOptions::closed; the task's last point repeated the first): the
// crank makes a whole turn from the first point back to it, in the direction of the timing, so
// the drive has one more step, from the last point's input angle to the first's plus a turn
// (plus k turns, the first such angle past the last point's). That step is judged as the others:
// a crank that cannot turn fully meets a stationary configuration on it, which is a `branch`
// defect (no separate "closure" defect: it is the same event, the crank would have to reverse);
// a crank that turns fully without one comes back to the first configuration, so the closing
// point is met on the first point's assembly and the step adds no circuit defect.
#ifndef LINKFIT_LIB_PATH_MOTION_H_
#define LINKFIT_LIB_PATH_MOTION_H_

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "lib/precision.h"

namespace linkfit {

struct PathFourBar {
  PlanarDyad input;   // RR crank: fixed pivot B in Sigma, moving pivot A in E
  PlanarDyad output;  // RR, PR or RP
  Eigen::Vector2d coupler_point = Eigen::Vector2d::Zero();  // R, in E
};

// The transmission angle's samples of the crank's sweep in reported path four-bars (and in a
// refinement that holds it).
inline constexpr int kPathTransmissionSamples = 64;

struct PathAnalysisOptions {
  // Slack of the assembly and stationary-configuration tests, times L.
  double assembly_tolerance = 1e-9;
  // Transmission angle: samples of the crank's sweep from the first to the last point (0 to
  // skip the transmission angle).
  int transmission_samples = 0;
  // A closed path: the closing step back to the first point is driven and judged too (file
  // comment), and the transmission angle is sampled over the whole closed sweep.
  bool closed = false;
};

struct PathFourBarAnalysis {
  bool assembles = false;  // the output closes at the first point's crank angle
  int label = -1;          // assembly label (AssembleFourBar) of the first point's configuration
  // Largest and RMS (weights 1) distance of the coupler point from the task points, the
  // mechanism driven from the first point's configuration. Absent when the crank cannot reach
  // some point's input angle on that assembly (error_note says which).
  std::optional<double> max_point_error;
  std::optional<double> rms_point_error;
  std::string error_note;
  std::vector<double> point_errors;  // per point (empty when max_point_error is absent)
  // The largest over the points of the nearer of the two assemblies' errors (infinity when some
  // input angle does not assemble): whether the four-bar passes the points at all.
  double nearest_max_error = std::numeric_limits<double>::infinity();
  std::vector<PlanarPose> configurations;      // coupler pose at each point (same condition)
  std::vector<std::string> defects;            // "branch", "circuit"
  bool input_rotates_fully = false;            // the crank can turn a full revolution
  std::optional<double> transmission_min_deg;  // over the sweep (when sampled)
  std::optional<double> transmission_max_deg;
};

// The crank angle of `four_bar`'s input in the configuration of the first point (E = Sigma).
double FirstCrankAngle(const PathFourBar& four_bar);

// Drives the four-bar through the input angles (radians, psi_j as given) and measures the
// coupler point against `points` (same count). `length` is the task's L.
PathFourBarAnalysis AnalyzePathFourBar(const PathFourBar& four_bar,
                                       const std::vector<Eigen::Vector2d>& points,
                                       const std::vector<double>& input_angles, double length,
                                       const PathAnalysisOptions& options = {});

// The direction a closed path's crank turns in (+1 or -1): the sign of the last input angle
// minus the first (of the second minus the first when they agree), and the closing angle the
// crank reaches the first point again at: the first psi_0 + direction * k * 2 pi (k >= 1) past
// the last input angle.
double ClosingInputAngle(const std::vector<double>& input_angles);

// First-order bound of how far the data's precision can move a four-bar that passes timed
// points (the path counterpart of fitting/model_choice.h DyadErrorBound). Parameters, in the
// first point's configuration: the crank B, A, the output (RR: F, M; PR: M and the line's angle;
// RP: F and the line's angle in E), the coupler point R: 10 or 9 of them. J is the Jacobian of
// the coupler point's coordinates at the input angles (2 per point) in these parameters (central
// differences; the output's radius and the line's offset follow from the first configuration),
// u_jk = delta + |dC_jk / dpsi_j| alpha the uncertainty of coordinate k of point j (the point's
// own delta, and the input angle's alpha moving the coupler point along its path). Each
// parameter moves by at most sum |(J^+)_i,jk| u_jk; the bound is the largest pivot or coupler
// point displacement (sqrt 2 times the larger coordinate move) or line angle move times the
// four-bar's size (its largest pivot distance from the points' centroid, at least `length`), in
// length units. With free timing the input angles psi_1..psi_{n-1} are parameters too (the
// columns dC_j / dpsi_j; no alpha term). Infinity when the points do not determine the four-bar
// (J rank-deficient, or fewer coordinates than parameters) or it cannot be driven through them.
double PathFourBarErrorBound(const PathFourBar& four_bar,
                             const std::vector<Eigen::Vector2d>& points,
                             const std::vector<double>& input_angles,
                             const DataPrecision& precision, double length,
                             bool free_timing = false);

// The three four-bars that trace the coupler curve of a 4R (Roberts-Chebyshev cognates): the
// four-bar itself and its two cognates, each in the same first configuration (E = Sigma there),
// and each also with its two cranks' roles swapped: six designs. Empty unless both dyads are RR.
// With free timing every one passes the same points.
std::vector<PathFourBar> CurveCognates(const PathFourBar& four_bar);

// How far apart the coupler curves of two four-bars of one type are: for 4Rs the least, over
// the six designs of CurveCognates(b), of the largest distance between a's and that design's
// fixed pivots, moving pivots and coupler points; otherwise that largest distance (a slider's
// line by its foot) between a and b themselves. Length units; infinity for different types.
double CurveDistance(const PathFourBar& a, const PathFourBar& b);

// A four-bar's size as PathFourBarErrorBound measures it: its largest pivot or coupler point
// distance from the points' centroid, at least `length`.
double PathFourBarSize(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                       double length);

// The coupler poses along the motion through the first point's configuration: a full crank
// turn, or the crank's reachable range (out and back on the other assembly) when it is
// limited. The coupler point's curve is their images of coupler_point.
std::vector<PlanarPose> CouplerCycle(const PathFourBar& four_bar, double length, int samples = 360);

// The frame the path solvers work in: Sigma (and E alike) centred on the points' centroid and
// scaled by `length`. Returns the similarity that maps that frame back to the task's.
Similarity2 ScaledPointFrame(const std::vector<Eigen::Vector2d>& points, double length);

// `four_bar` with every point (pivots, line points, the coupler point: Sigma and E alike, as they
// coincide in the first configuration) mapped by `similarity`, after a reflection y -> -y when
// `mirror`; radii scaled, line directions turned (and reflected). A reflected four-bar is a
// four-bar whose crank turns the other way.
PathFourBar TransformPathFourBar(const PathFourBar& four_bar, const Similarity2& similarity,
                                 bool mirror = false);

// Re-expresses a design whose first configuration is `first_pose` (the coupler pose at the first
// point, not the identity) in the convention above: E is moved onto that pose.
PathFourBar MoveToFirstConfiguration(const PathFourBar& four_bar, const PlanarPose& first_pose);

}  // namespace linkfit

#endif  // LINKFIT_LIB_PATH_MOTION_H_
