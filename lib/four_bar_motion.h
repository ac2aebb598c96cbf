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
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lib/dyad.h"
#include "lib/four_bar_closure.h"
#include "lib/golden_section.h"
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
  // Neighbouring poses closer to each other than the fit's residual at them are visited in
  // swapped order: an "order" judgement the data's noise decides, not a defect (issue 34).
  bool order_within_noise = false;
};

// The residual (times L) up to which a fit's residuals are the data's noise: a four-bar that
// misses poses by more is judged strictly (its order is its own, not the noise's).
inline constexpr double kNoiseResidualCap = 0.05;

// The steps j - 1 -> j between poses closer to each other (pose error) than twice the sum of
// the fit's residuals at them (their located pose errors, together at most kNoiseResidualCap L):
// their order is within the noise.
std::vector<bool> StepsWithinNoise(const std::vector<FourBarLocation>& locations,
                                   const std::vector<PlanarPose>& poses, double length);

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

// Which way a monotonic input visits the poses in order.
struct DefectVisit {
  bool increasing = true;
  bool decreasing = true;
};

// The defects of poses located on a motion (Chase and Mirth's, the file comment): "circuit" when
// a pose is off the first pose's circuit, "branch" when consecutive poses are on different
// branches of it, "order" when on one branch the input cannot run monotonically through their
// values: around a full turn the forward (or backward) steps must add up to less than a turn;
// on a limited input `position` measures each value along the circuit. A step j - 1 -> j marked
// in `within_noise` (poses closer to each other than the fit's residual at them, issue 34) may
// go either way: its order is not judged.
template <typename Position>
DefectVisit JudgeDefects(const std::vector<FourBarLocation>& locations, int circuit_index,
                         bool rotates_fully, const Position& position,
                         std::vector<std::string>* defects,
                         const std::vector<bool>& within_noise = {}) {
  bool one_circuit = true, one_branch = true;
  for (size_t j = 0; j < locations.size(); ++j) {
    one_circuit = one_circuit && locations[j].circuit == circuit_index;
    if (j > 0 && locations[j].branch != locations[j - 1].branch) one_branch = false;
  }
  if (!one_circuit) defects->push_back("circuit");
  if (one_circuit && !one_branch) defects->push_back("branch");
  if (!one_circuit || !one_branch || locations.size() < 2) return DefectVisit();
  // The visit with the steps marked `free` taken either way (none: the strict visit).
  const auto visit_with = [&](const std::vector<bool>& free) {
    const auto free_step = [&](size_t j) { return j < free.size() && free[j]; };
    DefectVisit visit;
    if (rotates_fully) {
      double forward = 0.0, backward = 0.0;
      for (size_t j = 1; j < locations.size(); ++j) {
        if (free_step(j)) {
          // Either way by the short step: forward adds it only when it goes forward.
          const double wrapped = WrapAngle(locations[j].input - locations[j - 1].input);
          forward += std::max(wrapped, 0.0);
          backward += std::max(-wrapped, 0.0);
          continue;
        }
        const double step = PositiveAngle(locations[j].input - locations[j - 1].input);
        forward += step;
        backward += step == 0.0 ? 0.0 : kClosureTwoPi - step;
      }
      visit.increasing = forward < kClosureTwoPi;
      visit.decreasing = backward < kClosureTwoPi;
    } else {
      for (size_t j = 1; j < locations.size(); ++j) {
        if (free_step(j)) continue;
        const double a = position(locations[j - 1].input), b = position(locations[j].input);
        visit.increasing = visit.increasing && b > a;
        visit.decreasing = visit.decreasing && b < a;
      }
    }
    return visit;
  };
  const DefectVisit strict = visit_with({});
  if (strict.increasing || strict.decreasing) return strict;
  // Out of order strictly: within the noise when the steps marked free explain it.
  if (std::find(within_noise.begin(), within_noise.end(), true) != within_noise.end()) {
    const DefectVisit tolerant = visit_with(within_noise);
    if (tolerant.increasing || tolerant.decreasing) return tolerant;
  }
  defects->push_back("order");
  return strict;
}

// The largest pose error on the first pose's circuit: a pose on it at its own location, one off
// it `off_circuit(j)`, which `upper(j)` bounds from above and costs far less: the poses off the
// circuit are taken largest bound first, and once no bound can raise the maximum the searches
// stop (the same maximum; on a task the four-bar fits badly most poses are off its circuit, and
// 100,000 searches along it took seconds).
template <typename OffCircuit, typename Upper>
double MaxPoseErrorOnCircuit(const std::vector<FourBarLocation>& locations, int circuit_index,
                             const OffCircuit& off_circuit, const Upper& upper) {
  double worst = 0.0;
  std::vector<std::pair<double, size_t>> off;
  for (size_t j = 0; j < locations.size(); ++j) {
    if (locations[j].circuit == circuit_index) {
      worst = std::max(worst, locations[j].pose_error);
    } else {
      const double bound = upper(j);
      off.emplace_back(std::isnan(bound) ? std::numeric_limits<double>::infinity() : bound, j);
    }
  }
  std::sort(off.begin(), off.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [bound, j] : off) {
    if (bound <= worst) break;
    worst = std::max(worst, off_circuit(j));
  }
  return worst;
}
template <typename OffCircuit>
double MaxPoseErrorOnCircuit(const std::vector<FourBarLocation>& locations, int circuit_index,
                             const OffCircuit& off_circuit) {
  return MaxPoseErrorOnCircuit(locations, circuit_index, off_circuit,
                               [](size_t) { return std::numeric_limits<double>::infinity(); });
}

// The configurations along a circuit of `closure`, `samples` of them over its interval (label 0
// forward and label 1 back for a joined circuit); an open slider side is sampled from `lo` or
// to `hi`. `assemble(value, &configurations)` writes the configurations at an input value and
// returns their count (AssembleFourBar's order of labels).
template <typename Configuration, typename Assemble>
std::vector<Configuration> CircuitConfigurations(const FourBarClosure& closure,
                                                 const ClosedCircuit& circuit, double lo, double hi,
                                                 int samples, const Assemble& assemble) {
  const ClosureInterval& interval = closure.intervals[circuit.interval];
  const double start = interval.open_start ? lo : interval.start;
  const double end = interval.open_end ? hi : interval.end;
  std::vector<Configuration> along, back, configurations;
  const int steps = std::max(samples - 1, 1);
  for (int k = 0; k <= steps; ++k) {
    const int count = assemble(start + (end - start) * k / steps, &configurations);
    if (count == 0) continue;
    if (circuit.label >= 0) {
      along.push_back(configurations[std::min(circuit.label, count - 1)]);
    } else {
      along.push_back(configurations[0]);
      back.push_back(configurations[count - 1]);
    }
  }
  along.insert(along.end(), back.rbegin(), back.rend());
  return along;
}

// The error of a pose from the circuit's nearest configuration: kNearestSamples over the
// interval on each of the circuit's labels, then golden-section search about the best one.
// `error(value, label)` is the pose's error from the configuration of that label at an input
// value (infinity where it does not assemble); an open slider side is searched from `lo` or to
// `hi`.
template <typename Error>
double NearestOnCircuit(const FourBarClosure& closure, const ClosedCircuit& circuit, double lo,
                        double hi, const Error& error) {
  constexpr int kNearestSamples = 16, kIterations = 20;
  const ClosureInterval& interval = closure.intervals[circuit.interval];
  const double start = interval.open_start ? lo : interval.start;
  const double end = interval.open_end ? hi : interval.end;
  double best = std::numeric_limits<double>::infinity();
  for (int label = 0; label < closure.labels; ++label) {
    if (circuit.label >= 0 && circuit.label != label) continue;
    const auto at = [&](double t) { return error(start + (end - start) * t, label); };
    int nearest = 0;
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < kNearestSamples; ++k) {
      const double e = at(static_cast<double>(k) / (kNearestSamples - 1));
      if (e < least) {
        least = e;
        nearest = k;
      }
    }
    const double step = 1.0 / (kNearestSamples - 1);
    // kIterations evaluations after the first two: one shrink more (the last only narrows).
    const GoldenSection search =
        GoldenSectionSearch(at, std::max(0.0, (nearest - 1) * step),
                            std::min(1.0, (nearest + 1) * step), kIterations + 1);
    best = std::min({best, least, search.least});
  }
  return best;
}

// The better of two analyses of one dyad pair (input i or input j; planar FourBarAnalysis or
// spherical): fewer defects, then a crank input, then a better worst transmission angle.
template <typename Analysis>
bool BetterAnalysis(const Analysis& a, const Analysis& b) {
  if (a.defects.size() != b.defects.size()) return a.defects.size() < b.defects.size();
  if (a.input_rotates_fully != b.input_rotates_fully) return a.input_rotates_fully;
  return a.transmission_min_deg.value_or(-1.0) > b.transmission_min_deg.value_or(-1.0);
}

// Where task poses lie on a closed-form motion and what that makes of the four-bar, shared by
// the planar four-bars (AnalyzeFourBar) and the spherical ones (spherical_four_bar.h).
struct ClosureJudgment {
  std::vector<ClosedCircuit> circuits;     // ClosedCircuits of the closure
  std::vector<FourBarLocation> locations;  // one per pose
  std::vector<std::string> defects;        // JudgeDefects
  int circuit = -1;                        // the first pose's; -1 when it does not assemble
  bool input_rotates_fully = false;        // on that circuit
  std::optional<double> max_pose_error;    // on that circuit (MaxPoseErrorOnCircuit)
  double lo = 0.0, hi = 0.0;               // a slider's range: the poses' values and the margin
  // The input's way from the first pose to the last along the circuit: from sweep_start over
  // sweep_extent (signed; a crank runs the way its monotonic visit goes, a limited input within
  // its interval).
  double sweep_start = 0.0, sweep_extent = 0.0;
  bool order_within_noise = false;  // FourBarAnalysis::order_within_noise
};

// inputs[j] is pose j's input value and label_errors[j] its pose error from the configuration
// of each assembly label there (infinity where there is none). A pose is located on the circuit
// of its interval and of its nearer label; a pose off the first pose's circuit is measured to
// that circuit: at its own input value on the circuit's label, or to the circuit's nearest
// configuration (NearestOnCircuit with error_at(j, value, label)). A slider's open side reaches
// slider_margin times the larger of the poses' range and `length` beyond their values.
// `step_distances[j]` (optional) is the pose error between poses j - 1 and j: a step between
// poses closer than twice their residuals is within the noise (JudgeDefects).
template <typename ErrorAt>
ClosureJudgment JudgeOnClosure(const FourBarClosure& closure, const std::vector<double>& inputs,
                               const std::vector<std::array<double, 2>>& label_errors,
                               double slider_margin, double length, const ErrorAt& error_at,
                               const std::vector<double>& step_distances = {}) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  ClosureJudgment judgment;
  judgment.circuits = ClosedCircuits(closure);
  const std::vector<ClosedCircuit>& circuits = judgment.circuits;
  for (size_t j = 0; j < inputs.size(); ++j) {
    FourBarLocation location;
    location.input = inputs[j];
    const std::array<double, 2>& errors = label_errors[j];
    if (errors[0] < kInfinity || errors[1] < kInfinity) {
      const int label = errors[1] < errors[0] ? 1 : 0;
      location.pose_error = errors[label];
      const int interval = NearestInterval(closure, location.input);
      for (size_t c = 0; c < circuits.size() && interval >= 0; ++c) {
        if (circuits[c].interval == interval &&
            (circuits[c].label < 0 || circuits[c].label == label)) {
          location.circuit = static_cast<int>(c);
          location.branch = circuits[c].label >= 0 ? 0 : label;
          break;
        }
      }
    }
    judgment.locations.push_back(location);
  }
  if (inputs.empty() || judgment.locations[0].circuit < 0) return judgment;
  const int circuit_index = judgment.locations[0].circuit;
  const ClosedCircuit& circuit = circuits[circuit_index];
  const ClosureInterval& interval = closure.intervals[circuit.interval];
  judgment.circuit = circuit_index;
  judgment.input_rotates_fully = circuit.rotates_fully;
  double lo = inputs[0], hi = inputs[0];
  for (const double value : inputs) {
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  const double widen = slider_margin * std::max(hi - lo, length);
  judgment.lo = lo - widen;
  judgment.hi = hi + widen;

  // Defects; positions along the interval measured from just before its start (a pose admitted
  // by the assembly's tolerance may lie a hair before it).
  const double origin = interval.start - 1e-9;
  const auto position = [&](double value) {
    return closure.angle_input ? PositiveAngle(value - origin) : value;
  };
  std::vector<bool> within_noise(judgment.locations.size(), false);
  bool any_within_noise = false;
  for (size_t j = 1; j < judgment.locations.size() && j < step_distances.size(); ++j) {
    const double residual = judgment.locations[j - 1].pose_error + judgment.locations[j].pose_error;
    within_noise[j] = residual <= kNoiseResidualCap * length && step_distances[j] <= 2.0 * residual;
    any_within_noise = any_within_noise || within_noise[j];
  }
  const DefectVisit visit = JudgeDefects(judgment.locations, circuit_index, circuit.rotates_fully,
                                         position, &judgment.defects, within_noise);
  if (any_within_noise && std::find(judgment.defects.begin(), judgment.defects.end(), "order") ==
                              judgment.defects.end()) {
    std::vector<std::string> strict;
    JudgeDefects(judgment.locations, circuit_index, circuit.rotates_fully, position, &strict);
    judgment.order_within_noise = std::find(strict.begin(), strict.end(), "order") != strict.end();
  }
  // A bound on a pose's error from the circuit: at its own input value on the circuit's label,
  // or where that does not assemble, at the nearer end of the circuit's interval (a
  // configuration of the circuit, so no nearer than the nearest).
  const ClosureInterval& bound_interval = closure.intervals[circuit.interval];
  const double bound_start = bound_interval.open_start ? judgment.lo : bound_interval.start;
  const double bound_end = bound_interval.open_end ? judgment.hi : bound_interval.end;
  const auto at_label = [&](size_t j) {
    const double own = circuit.label >= 0 ? label_errors[j][circuit.label] : kInfinity;
    if (own < kInfinity) return own;
    const double value = judgment.locations[j].input;
    const double end =
        std::abs(value - bound_start) <= std::abs(value - bound_end) ? bound_start : bound_end;
    double bound = kInfinity;
    for (int label = 0; label < closure.labels; ++label) {
      if (circuit.label < 0 || circuit.label == label) {
        bound = std::min(bound, error_at(j, end, label));
      }
    }
    return bound;
  };
  judgment.max_pose_error = MaxPoseErrorOnCircuit(
      judgment.locations, circuit_index,
      [&](size_t j) {
        return std::min(at_label(j), NearestOnCircuit(closure, circuit, judgment.lo, judgment.hi,
                                                      [&](double value, int label) {
                                                        return error_at(j, value, label);
                                                      }));
      },
      at_label);

  const double start = inputs.front(), end = inputs.back();
  judgment.sweep_start = start;
  judgment.sweep_extent = end - start;
  if (closure.angle_input && circuit.rotates_fully) {
    judgment.sweep_extent = !visit.increasing && visit.decreasing ? -PositiveAngle(start - end)
                                                                  : PositiveAngle(end - start);
  } else if (closure.angle_input) {
    // Within the interval (the short way round may cross where it does not assemble).
    judgment.sweep_extent = position(end) - position(start);
  }
  return judgment;
}

// Copies what a judgment says of the four-bar into an analysis (FourBarAnalysis or the
// spherical one): its locations and defects, and, when the first pose assembles, its circuit,
// whether the input turns fully there and the largest pose error. Returns whether it assembles.
template <typename Analysis>
bool TakeJudgment(const ClosureJudgment& judgment, Analysis* analysis) {
  analysis->locations = judgment.locations;
  analysis->defects = judgment.defects;
  if (judgment.circuit < 0) return false;
  analysis->circuit = judgment.circuit;
  analysis->input_rotates_fully = judgment.input_rotates_fully;
  analysis->max_pose_error = judgment.max_pose_error;
  analysis->order_within_noise = judgment.order_within_noise;
  return true;
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_FOUR_BAR_MOTION_H_
