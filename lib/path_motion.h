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
#ifndef LINKFIT_LIB_PATH_MOTION_H_
#define LINKFIT_LIB_PATH_MOTION_H_

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

struct PathFourBar {
  PlanarDyad input;   // RR crank: fixed pivot B in Sigma, moving pivot A in E
  PlanarDyad output;  // RR, PR or RP
  Eigen::Vector2d coupler_point = Eigen::Vector2d::Zero();  // R, in E
};

struct PathAnalysisOptions {
  // Slack of the assembly and stationary-configuration tests, times L.
  double assembly_tolerance = 1e-9;
  // Transmission angle: samples of the crank's sweep from the first to the last point (0 to
  // skip the transmission angle).
  int transmission_samples = 0;
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

// The coupler poses along the motion through the first point's configuration: a full crank
// turn, or the crank's reachable range (out and back on the other assembly) when it is
// limited. The coupler point's curve is their images of coupler_point.
std::vector<PlanarPose> CouplerCycle(const PathFourBar& four_bar, double length, int samples = 360);

// The frame the path solvers work in: Sigma (and E alike) centred on the points' centroid and
// scaled by `length`. Returns the similarity that maps that frame back to the task's.
Similarity2 ScaledPointFrame(const std::vector<Eigen::Vector2d>& points, double length);

// Re-expresses a design whose first configuration is `first_pose` (the coupler pose at the first
// point, not the identity) in the convention above: E is moved onto that pose.
PathFourBar MoveToFirstConfiguration(const PathFourBar& four_bar, const PlanarPose& first_pose);

}  // namespace linkfit

#endif  // LINKFIT_LIB_PATH_MOTION_H_
