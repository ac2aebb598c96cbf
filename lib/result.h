// In-memory form of the result file (see README, "Result file").
#ifndef LINKFIT_LIB_RESULT_H_
#define LINKFIT_LIB_RESULT_H_

#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/mechanism.h"
#include "lib/task.h"

namespace linkfit {

struct DyadReport {
  PlanarDyad dyad;
  double max_residual = 0.0;  // over the task poses, length units
};

struct MechanismReport {
  FourBarType type = FourBarType::k4R;
  int input_dyad = 0;   // index into the result's dyads; the driven dyad
  int output_dyad = 1;  // index into the result's dyads
  // Largest pose error when assembled at every task pose on one circuit (four_bar_motion.h);
  // absent when the mechanism does not assemble at the first pose.
  std::optional<double> max_pose_error;
  std::string pose_error_note;       // why max_pose_error is absent
  std::string grashof;               // 4R only
  std::vector<std::string> defects;  // "circuit", "branch", "order"
  bool input_rotates_fully = false;  // the input dyad can be a crank on this circuit
  bool output_rotates_fully = false;
  std::optional<double> transmission_min_deg;  // folded to [0, 90], first to last pose
  std::optional<double> transmission_max_deg;
  std::string transmission_note;  // why the transmission angle is absent
  std::vector<PlanarPose> cycle;  // coupler poses along the circuit (pictures; not written)
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
  int roots_total = 0;  // roots of the constraint-space system, complex ones included
  int roots_real = 0;   // of which real
  std::vector<std::string> notes;
  double solve_seconds = 0.0;
};

}  // namespace linkfit

#endif  // LINKFIT_LIB_RESULT_H_
