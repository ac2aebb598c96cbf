// The motion of a planar four-bar under its input joint, and the defects of a four-bar as a
// solution of a motion task.
//
// The configuration curve is traced by sampling the input joint (see mechanism.h for what the
// input value is). AssembleFourBar's two solutions carry consistent labels (the +/- of its
// closed form), so the curve splits into
//   circuits: parts that can be traversed without taking the mechanism apart. Where the
//     input turns fully (a crank) each label is a closed circuit of its own; where the input
//     is limited, the two labels meet at the input's limits and form one circuit;
//   branches: parts of a circuit between stationary configurations under the input (the
//     input's limits, where the two labels meet; the input must reverse there).
// Defects (Chase and Mirth's terms): circuit (task poses on different circuits), branch
// (consecutive poses on different branches of one circuit) and order (a monotonic input
// reaches the poses out of task order).
#ifndef LINKFIT_LIB_FOUR_BAR_MOTION_H_
#define LINKFIT_LIB_FOUR_BAR_MOTION_H_

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

struct FourBarMotionOptions {
  int samples = 720;  // input samples over a full turn (angle inputs) or the slider range
  // Slider inputs: the sampled range is the task's input range widened by this many times
  // max(range, L) on each side.
  double slider_margin = 3.0;
  // AnalyzeFourBar: trace the circuit's coupler poses (FourBarAnalysis::cycle, for pictures)
  // with `samples` of them; the analysis itself does not need them.
  bool trace_cycle = false;
};

struct FourBarSample {
  double input = 0.0;  // input joint value
  PlanarPose coupler;  // pose of E
  int branch = 0;      // 0 or 1 within the circuit
};

struct FourBarCircuit {
  std::vector<FourBarSample> samples;  // in order along the circuit
  bool input_rotates_fully = false;    // the input turns a full revolution on it
  int branches = 1;                    // 1, or 2 when the input reverses on it
  // The assembly label(s) it uses: 0 or 1, or -1 for both (the two branches of a limited
  // input), and the input values it spans: from input_start over input_extent (increasing,
  // around the turn for angle inputs), sampled every input_step.
  int label = -1;
  double input_start = 0.0;
  double input_extent = 0.0;
  double input_step = 0.0;

  // Whether the circuit reaches input value `value` (within half a sampling step).
  bool Spans(double value, bool angle_input) const;
};

struct FourBarMotion {
  std::vector<FourBarCircuit> circuits;
};

// Traces the motion of the four-bar driven by `input`. `poses` (may be empty) and `length` set
// the sampled range of a slider input.
FourBarMotion TraceFourBar(const PlanarDyad& input, const PlanarDyad& output,
                           const std::vector<PlanarPose>& poses, double length,
                           const FourBarMotionOptions& options = {});

// Where a task pose lies on the motion: the circuit and branch of the configuration nearest to
// it at its input value, and that configuration's pose error. circuit = -1 when the mechanism
// does not assemble at the pose's input value.
struct FourBarLocation {
  int circuit = -1;
  int branch = -1;
  double input = 0.0;
  double pose_error = 0.0;
};

FourBarLocation LocatePose(const FourBarMotion& motion, const PlanarDyad& input,
                           const PlanarDyad& output, const PlanarPose& pose, double length);

// A four-bar judged as a solution of a motion task, driven by `input`.
struct FourBarAnalysis {
  std::vector<FourBarLocation> locations;  // one per task pose
  std::vector<std::string> defects;        // "circuit", "branch", "order"
  int circuit = -1;                        // the circuit of the first pose
  // Largest pose error when the mechanism is assembled at each pose on that one circuit
  // (for a pose the circuit cannot reach at its input value: the distance to the nearest
  // configuration of the circuit). Absent when the first pose cannot be assembled.
  std::optional<double> max_pose_error;
  bool input_rotates_fully = false;  // on that circuit
  // Transmission angle (TransmissionAngleDeg), min and max over the motion from the first to
  // the last pose on the circuit. Absent for dyad pairs without two coupler pins (RP dyads)
  // and when the poses are not on one branch.
  std::optional<double> transmission_min_deg;
  std::optional<double> transmission_max_deg;
  std::string transmission_note;  // why the transmission angle is absent
  std::vector<PlanarPose> cycle;  // coupler poses along the circuit (for pictures)
};

// In closed form (four_bar_closure.h): the circuits and branches from the closure's intervals
// and the assembly labels, the defects from the poses' input values on them, the 4R's
// transmission-angle extremes from the crank's critical angles (other types: 180 samples of the
// motion between the first and the last pose). The circuit is sampled only for a pose off it
// (its nearest configuration) and for the cycle (options.trace_cycle).
FourBarAnalysis AnalyzeFourBar(const PlanarDyad& input, const PlanarDyad& output,
                               const std::vector<PlanarPose>& poses, double length,
                               const FourBarMotionOptions& options = {});

// The same analysis from the sampled trace (TraceFourBar, LocatePose; the cycle always): the
// oracle of AnalyzeFourBar's tests.
FourBarAnalysis AnalyzeFourBarSampled(const PlanarDyad& input, const PlanarDyad& output,
                                      const std::vector<PlanarPose>& poses, double length,
                                      const FourBarMotionOptions& options = {});

// Transmission angle at a configuration, folded into [0, 90] degrees: 90 minus the angle
// between the coupler line (input pin to output pin, in Sigma) and the direction in which the
// output pin can move (normal to an RR output crank; along a PR output's line). For a 4R this
// is the classical coupler-rocker angle folded to [0, 90]. Returns nothing when a dyad is RP.
std::optional<double> TransmissionAngleDeg(const PlanarDyad& input, const PlanarDyad& output,
                                           const PlanarPose& coupler);

// The four-bar's transmission angle over a motion: the smallest and largest TransmissionAngleDeg
// of the coupler poses `sample(k)`, k = 0..steps, where `sample` gives the pose at step k or
// nothing (no assembly there). Written to *min_deg and *max_deg when some angle is defined.
template <typename Sample>
void TransmissionRangeDeg(const PlanarDyad& input, const PlanarDyad& output, int steps,
                          const Sample& sample, std::optional<double>* min_deg,
                          std::optional<double>* max_deg) {
  double low = 90.0, high = 0.0;
  for (int k = 0; k <= steps; ++k) {
    const std::optional<PlanarPose> coupler = sample(k);
    if (!coupler) continue;
    const std::optional<double> angle = TransmissionAngleDeg(input, output, *coupler);
    if (!angle) continue;
    low = std::min(low, *angle);
    high = std::max(high, *angle);
  }
  if (low <= high) {
    *min_deg = low;
    *max_deg = high;
  }
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_FOUR_BAR_MOTION_H_
