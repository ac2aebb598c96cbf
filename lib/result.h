// In-memory form of the result file (see README, "Result file").
#ifndef LINKFIT_LIB_RESULT_H_
#define LINKFIT_LIB_RESULT_H_

#include <array>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "lib/dyad.h"
#include "lib/function_four_bar.h"
#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "lib/spatial_dyad.h"
#include "lib/spherical_dyad.h"
#include "lib/task.h"

namespace linkfit {

struct DyadReport {
  DyadReport() = default;
  DyadReport(const PlanarDyad& dyad_in, double max_residual_in)
      : dyad(dyad_in), max_residual(max_residual_in) {}

  PlanarDyad dyad;
  double max_residual = 0.0;  // over the task poses, length units
  // Least squares (more than five poses): the weighted RMS residual, and the seed's before the
  // refinement (absent when not refined).
  std::optional<double> rms_residual;
  std::optional<double> seed_rms_residual;
  // How far the data's precision can move the dyad (fitting/model_choice.h DyadErrorBound),
  // length units; infinity when the poses do not determine it at that precision.
  std::optional<double> error_bound;
};

// One stage of an approximate synthesis (seed, refine, search, mechanism refinement): its time
// and the best result after it.
struct StageReport {
  std::string name;  // "seed", "refine", "search", "four-bar refine"
  double seconds = 0.0;
  std::optional<double> best_dyad_rms;         // smallest weighted RMS dyad residual
  std::optional<double> best_max_pose_error;   // smallest max pose error of a listed four-bar
  std::optional<double> best_max_point_error;  // path problems: the same for the points
  std::optional<double> best_max_angle_error;  // function problems: the output's, radians
};

// The points of each kind of Burmester curve a result file carries by default (about 40 KB).
inline constexpr int kDefaultCurvePoints = 400;

struct MechanismReport {
  FourBarType type = FourBarType::k4R;
  int input_dyad = 0;   // index into the result's dyads; the driven dyad
  int output_dyad = 1;  // index into the result's dyads
  // The coupler's pose in Sigma in the four-bar's configuration nearest the first task pose (the
  // task pose itself where it does not assemble there): where the result's "linkage" shows it.
  std::optional<PlanarPose> first_configuration;
  // A spherical four-bar's: the body's rotation in that configuration (its joints are axes).
  std::optional<Eigen::Matrix3d> first_rotation;
  // Largest pose error when assembled at every task pose on one circuit (four_bar_motion.h);
  // absent when the mechanism does not assemble at the first pose.
  std::optional<double> max_pose_error;
  std::string pose_error_note;  // why max_pose_error is absent
  std::string grashof;          // 4R only
  // "circuit", "branch", "order", "transmission" (the worst transmission angle below the
  // task's min_transmission_angle_deg)
  std::vector<std::string> defects;
  // The task's design constraints this four-bar breaks (lib/design_constraints.h); empty when it
  // keeps them all.
  std::vector<std::string> violates;
  bool input_rotates_fully = false;  // the input dyad can be a crank on this circuit
  bool output_rotates_fully = false;
  std::optional<double> transmission_min_deg;  // folded to [0, 90], first to last pose
  std::optional<double> transmission_max_deg;
  std::string transmission_note;  // why the transmission angle is absent
  std::vector<PlanarPose> cycle;  // coupler poses along the circuit (pictures; not written)
  // Neighbouring poses closer than the fit's residual were reached in swapped order: not an
  // "order" defect at the data's noise (lib/four_bar_motion.h; a note of the result says so).
  bool order_within_noise = false;
  // Least squares: the RMS pose error on the circuit, and the largest before the mechanism-level
  // refinement (absent when not refined).
  std::optional<double> rms_pose_error;
  std::optional<double> seed_max_pose_error;
  // Least squares with poses marked exact: the largest pose error at them, and whether it is
  // more than the promised kExactPoseTolerance L (such a four-bar is ranked after every one
  // that meets them).
  std::optional<double> exact_pose_error;
  bool misses_exact = false;
  // Its joints' spread at the first pose (lib/design_constraints.h JointSpread): the ranking's
  // last tie-break.
  std::optional<double> size;
  // Three to five poses whose exact four-bars keep no constraint (issue 35): how linkfit chose
  // this one instead (pivots on the Burmester curves of four of the poses within the
  // constraints, a bounded least-squares fit of all of them; optimizers/pivot_choice.h). Empty
  // for the task's own exact four-bars. A chosen four-bar may miss a pose by design: its pose
  // errors (one per task pose, on its circuit) say by how much, and "misses" is no defect of it.
  std::string chosen;
  std::vector<double> pose_errors;
};

// A six-bar of a "linkage": "six-bar" task (issue 36; lib/six_bar.h), driven by `input` (a body
// turning about ground: 1 the chain's upper link, 4 or 5 an RR link) as lib/six_bar.h
// AnalyzeSixBar drives it through the poses.
struct SixBarReport {
  SixBar six_bar;
  int input = kSixBarUpperLink;
  std::vector<std::string> defects;  // "order", "branch", "circuit"; "transmission"
  std::vector<std::string> violates;
  std::vector<double> input_angles;  // the input's turn at each pose, radians
  // Its configuration at each pose: the turns of bodies 1 to 5 from the reference configuration
  // (the first pose's), radians (lib/six_bar.h SixBarAngles).
  std::vector<SixBarAngles> at_poses;
  std::array<double, 2> transmission_min_deg = {90.0, 90.0};  // each RR link's least
  bool input_rotates_fully = false;
  double max_pose_error = 0.0;  // length units, with L for the angle (PoseError)
  double rms_pose_error = 0.0;  // over the poses, the same units
  // How far the data's precision can move its RR links' joints (the larger link's bound, first
  // order; fitting/six_bar_synthesis.h), length units: five poses only.
  std::optional<double> error_bound;
};

struct PlanarMotionResult {
  ProblemKind problem = ProblemKind::kMotion;
  Space space = Space::kPlanar;
  std::string method = "exact";  // "exact" | "least-squares"
  double scale = 1.0;            // the characteristic length L used
  std::vector<DyadReport> dyads;
  std::vector<MechanismReport> mechanisms;
  // Four poses: the sampled Burmester curves, as polylines; center points in Sigma, circle
  // points in E.
  std::vector<std::vector<Eigen::Vector2d>> center_point_curves;
  std::vector<std::vector<Eigen::Vector2d>> circle_point_curves;
  // How many points of each kind of curve the result file carries (ResultToJson simplifies the
  // polylines to at most this many, Ramer-Douglas-Peucker: a drawing's resolution; the solver
  // samples them far more densely). `linkfit solve --curve-points N` sets it.
  int curve_points = kDefaultCurvePoints;
  int roots_total = 0;  // roots of the constraint-space system, complex ones included
  int roots_real = 0;   // of which real
  std::vector<std::string> notes;
  double solve_seconds = 0.0;
  // Of solve_seconds, the analysis of the dyad pairs (assembly, circuits, defects,
  // transmission, ranking: BuildMechanisms).
  double analysis_seconds = 0.0;
  std::string effort;               // least squares: the effort level used
  std::vector<StageReport> stages;  // least squares: what each stage took and gave
  DataPrecision precision;          // the data precision assumed (the task's)
  bool closed = false;              // the task's last pose repeated the first (dropped)
  DesignConstraints constraints;    // the task's, echoed
  // "linkage": "six-bar": the chain used and the six-bars on it (the four-bar lists are empty).
  bool six_bar = false;  // a six-bar task's result: six_bars listed (none, maybe), no four-bars
  std::optional<SixBarChain> chain;  // the chain the six-bars are built on (none in a refinement
                                     // of a task without one)
  bool chain_chosen = false;         // linkfit chose the chain (the task gave none)
  std::vector<SixBarReport> six_bars;
  int burmester_problems = 0;  // the relative motions solved for them
};

struct SpatialDyadReport {
  SpatialDyad dyad;
  double max_residual = 0.0;  // over the task poses, length units
  // More than seven poses, after refinement: the seed's largest and RMS residual, and the RMS
  // after refinement (the refined design's largest is max_residual).
  std::optional<double> seed_max_residual;
  std::optional<double> seed_rms_residual;
  std::optional<double> rms_residual;
  // How far the data's precision can move the dyad (fitting/model_choice.h DyadErrorBound),
  // length units; infinity when the poses do not determine it at that precision.
  std::optional<double> error_bound;
};

// A 5-SS (or mixed SS/PS) platform: five dyads acting on one body, one degree of freedom.
struct PlatformReport {
  std::vector<int> dyads;   // five indices into the result's dyads
  bool assembles = false;   // the first task pose satisfies every dyad
  bool one_branch = false;  // every task pose is met on the motion through the first pose
  bool closed = false;      // that motion is a closed loop
  std::optional<double> max_pose_error;  // over the task poses, along the traced motion
  std::vector<int> order;                // task poses in the order the motion meets them
  std::string note;                      // why something is false
  std::vector<DualQuaternion> path;      // sampled motion (pictures; not written)
};

// Planar data in a spatial task: the plane of motion, and the planar synthesis in it.
struct PlanarEmbedding {
  // The plane frame in Sigma: origin, in-plane axes and the normal (the common rotation axis).
  Eigen::Vector3d origin_in_fixed = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes_in_fixed = Eigen::Matrix3d::Identity();  // columns u1, u2, n
  // The matching frame in E: origin at E's origin, axes R_1^T (u1, u2, n).
  Eigen::Matrix3d axes_in_moving = Eigen::Matrix3d::Identity();
  double planarity = 0.0;         // largest out-of-plane deviation found, length units
  std::vector<PlanarPose> poses;  // the task poses in the plane frames
};

// A point of the moving body that every pose puts at one place of the fixed frame: the motion
// is spherical about it.
struct SphericalCenter {
  Eigen::Vector3d in_moving = Eigen::Vector3d::Zero();  // p, in E
  Eigen::Vector3d in_fixed = Eigen::Vector3d::Zero();   // P, in Sigma
  double sphericity = 0.0;  // the largest |R_j p + d_j - P|, length units
};

// A spherical RR dyad of a spherical motion (lib/spherical_dyad.h), axes through the centre.
struct SphericalDyadReport {
  SphericalDyad dyad;
  // L times the largest angle by which the moving axis misses its cone over the task poses: how
  // far a point of the moving axis L from the centre misses its circle (length units).
  double max_residual = 0.0;
  // Least squares: the weighted RMS of the same, and the seed's before the refinement.
  std::optional<double> rms_residual;
  std::optional<double> seed_rms_residual;
  // How far the data's angle precision can move the dyad, radians (fitting/model_choice.h
  // DyadErrorBound: either axis' turn or the cone angle's change); infinity when the orientations
  // do not determine it (fewer than five).
  std::optional<double> error_bound;
};

struct SpatialMotionResult {
  std::string method = "exact";  // "exact" | "least-squares"
  double scale = 1.0;            // the characteristic length L used
  // "spatial" | "planar" (the data lie in a plane) | "spherical" (the poses fix one point)
  std::string model = "spatial";
  std::vector<SpatialDyadReport> dyads;
  std::vector<PlatformReport> mechanisms;
  int roots_total = 0;     // complex roots of the bilinear system (20 when generic)
  int roots_real = 0;      // of which real
  double condition = 0.0;  // sigma_1 / sigma_6 of the centered constraint rows
  // Planar data: the plane and the planar result (dyads in plane coordinates).
  std::optional<PlanarEmbedding> plane;
  std::optional<PlanarMotionResult> planar;
  // A spherical motion within the data's precision: its centre, and (model "spherical") its
  // spherical RR dyads and the spherical four-bars of every pair (dyad indices into
  // spherical_dyads; pose errors spatial, lib/spherical_dyad.h SphericalMotion::PoseError).
  std::optional<SphericalCenter> spherical;
  std::vector<SphericalDyadReport> spherical_dyads;
  std::vector<MechanismReport> spherical_mechanisms;
  // Four orientations: the spherical Burmester cones (fitting/spherical_burmester.h), polylines
  // of unit vectors: fixed axes in Sigma, moving axes in E.
  std::vector<std::vector<Eigen::Vector3d>> center_axis_curves;
  std::vector<std::vector<Eigen::Vector3d>> circle_axis_curves;
  std::vector<std::string> notes;
  double solve_seconds = 0.0;
  double refine_seconds = 0.0;    // Ceres refinement (more than seven poses)
  double search_seconds = 0.0;    // of refine_seconds, the spherical search (effort thorough)
  double analysis_seconds = 0.0;  // of solve_seconds, the platform's tracing
  DataPrecision precision;        // the data precision assumed (the task's)
  bool closed = false;            // the task's last pose repeated the first (dropped)
  // Model "spherical": the task's design constraints its four-bars were judged by, echoed.
  DesignConstraints constraints;
};

// A four-bar for a path task (timed points), in the first point's configuration
// (lib/path_motion.h), and how it meets the points when driven by its crank.
struct PathMechanismReport {
  FourBarType type = FourBarType::k4R;
  PathFourBar design;
  std::optional<double> max_point_error;  // absent when it cannot be driven through the points
  std::optional<double> rms_point_error;
  std::string error_note;  // why max_point_error is absent
  // Least squares: the largest point error before the refinement (absent when not refined).
  std::optional<double> seed_max_point_error;
  std::vector<std::string> defects;   // "branch", "circuit", "order", "transmission"
  std::vector<std::string> violates;  // the task's design constraints it breaks
  std::string grashof;                // 4R only
  bool input_rotates_fully = false;
  std::optional<double> transmission_min_deg;  // over the crank's sweep, first to last point
  std::optional<double> transmission_max_deg;
  std::vector<double> input_angles;  // free timing: the fitted input angles, radians
  // Least squares with points marked exact: the largest point error at them, and whether it is
  // more than 1e-9 L (such a four-bar is ranked after every one that meets them).
  std::optional<double> exact_point_error;
  bool misses_exact = false;
  // How far the data's precision can move the four-bar (lib/path_motion.h
  // PathFourBarErrorBound; infinity: the points do not determine it); absent when it does not
  // meet every point.
  std::optional<double> error_bound;
};

struct PathResult {
  std::string method = "exact";                 // "exact" (five points) | "least-squares"
  std::string timing = "prescribed";            // "prescribed" | "free"
  double scale = 1.0;                           // the characteristic length L used
  std::vector<PathMechanismReport> mechanisms;  // defect-free first, then by point error
  // Five points: roots of the crank equations (fitting/timed_path.h), complex included, and
  // the four-bars they make (3 per crank).
  int crank_roots_total = 0;
  int crank_roots_real = 0;
  int four_bars_total = 0;
  std::vector<std::string> notes;
  double solve_seconds = 0.0;
  // Of solve_seconds, five timed points: the four-bars driven through the points (the
  // solver's assembly check and the reports' simulation and transmission angle).
  double analysis_seconds = 0.0;
  std::string effort;               // least squares: the effort level used
  std::vector<StageReport> stages;  // least squares: what each stage took and gave
  DataPrecision precision;          // the data precision assumed (the task's)
  // A closed path: the last point repeated the first, and the crank makes a whole turn from
  // the first point back to it.
  bool closed = false;
  DesignConstraints constraints;  // the task's, echoed
};

// A four-bar function generator (lib/function_four_bar.h) and how it meets the pairs, driven by
// its input from the first pair's configuration (AnalyzeFunctionFourBar).
struct FunctionMechanismReport {
  FunctionFourBar design;
  // The pivots and pins in Sigma at the first pair's input; absent when it does not assemble
  // there.
  std::optional<FunctionConfiguration> first;
  std::optional<double> max_angle_error;  // over the pairs, radians
  std::optional<double> rms_angle_error;  // weighted RMS, radians
  std::string error_note;                 // why max_angle_error is absent
  // Least squares: the largest error before the refinement (absent when not refined).
  std::optional<double> seed_max_angle_error;
  // Least squares with pairs marked exact: the largest output error at them (radians), and
  // whether it is more than the exact tolerance (such a four-bar is ranked after every one
  // that meets them).
  std::optional<double> exact_angle_error;
  bool misses_exact = false;
  // A function given as samples: the largest output error over every sample (the structural
  // error between the precision points), radians; absent when the four-bar does not run over the
  // function's whole input range on the first pair's circuit and branch (the defect "range"),
  // and function_error_note says where.
  std::optional<double> function_max_error;
  std::string function_error_note;
  // How far the data's precision can move the four-bar (lib/function_four_bar.h
  // FunctionErrorBound; infinity: the pairs do not determine it); absent when it does not meet
  // the pairs.
  std::optional<double> error_bound;
  // "assembly" (not at the first pair), "circuit", "branch", "range", "transmission"
  std::vector<std::string> defects;
  std::vector<std::string> violates;  // the task's design constraints it breaks
  std::string grashof;
  bool input_rotates_fully = false;
  bool output_rotates_fully = false;
  // Over the pairs' input range, or a function's whole input range (its samples).
  std::optional<double> transmission_min_deg;
  std::optional<double> transmission_max_deg;
};

struct FunctionResult {
  std::string method = "exact";  // "exact" | "least-squares"
  bool relative_angles = false;  // the task's "angles": "relative"
  Eigen::Vector2d ground_input = Eigen::Vector2d::Zero();
  Eigen::Vector2d ground_output = Eigen::Vector2d::UnitX();
  double scale = 1.0;  // the ground length d, the characteristic length L
  // A function given as samples: the precision pairs made of it (Chebyshev or uniform points),
  // echoed; empty for a task of pairs.
  std::vector<FunctionPair> precision_points;
  std::vector<FunctionMechanismReport> mechanisms;  // ranked (lib/design_constraints.h)
  std::vector<std::string> notes;
  double solve_seconds = 0.0;
  double analysis_seconds = 0.0;    // of solve_seconds, the four-bars' analysis and ranking
  std::string effort;               // least squares: the effort level used
  std::vector<StageReport> stages;  // least squares: what each stage took and gave
  DataPrecision precision;          // the data precision assumed (the task's)
  DesignConstraints constraints;    // the task's, echoed
};

// What `linkfit solve` returns for one task.
using TaskResult =
    std::variant<PlanarMotionResult, SpatialMotionResult, PathResult, FunctionResult>;

}  // namespace linkfit

#endif  // LINKFIT_LIB_RESULT_H_
