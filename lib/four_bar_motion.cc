#include "lib/four_bar_motion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lib/four_bar_closure.h"
#include "lib/golden_section.h"
#include "lib/mechanism.h"

namespace linkfit {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

bool IsAngleInput(const PlanarDyad& input) { return input.type != DyadType::kPR; }

// The sampled input values: a full turn [-pi, pi) for angle inputs, or the task's slider range
// widened by the margin.
std::vector<double> InputSamples(const PlanarDyad& input, const std::vector<PlanarPose>& poses,
                                 double length, const FourBarMotionOptions& options) {
  std::vector<double> values(options.samples);
  if (IsAngleInput(input)) {
    for (int k = 0; k < options.samples; ++k) values[k] = -M_PI + kTwoPi * k / options.samples;
    return values;
  }
  double lo = 0.0, hi = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double value = InputValue(input, poses[j]);
    lo = j == 0 ? value : std::min(lo, value);
    hi = j == 0 ? value : std::max(hi, value);
  }
  const double margin = options.slider_margin * std::max(hi - lo, length);
  lo -= margin;
  hi += margin;
  for (int k = 0; k < options.samples; ++k) {
    values[k] = lo + (hi - lo) * k / (options.samples - 1);
  }
  return values;
}

// Configurations at every sample, by label (label 1 may be absent for dyad pairs whose
// assembly is linear).
struct Sampled {
  std::vector<double> inputs;
  std::vector<int> count;  // configurations per sample: 0, 1 or 2
  std::vector<PlanarPose> label[2];
};

Sampled SampleConfigurations(const PlanarDyad& input, const PlanarDyad& output,
                             const std::vector<double>& inputs) {
  Sampled sampled;
  sampled.inputs = inputs;
  sampled.count.resize(inputs.size());
  sampled.label[0].resize(inputs.size());
  sampled.label[1].resize(inputs.size());
  std::vector<PlanarPose> configurations;
  for (size_t k = 0; k < inputs.size(); ++k) {
    sampled.count[k] = AssembleFourBar(input, output, inputs[k], 0.0, &configurations);
    for (int l = 0; l < sampled.count[k]; ++l) sampled.label[l][k] = configurations[l];
  }
  return sampled;
}

// Maximal runs [first, last] of samples that assemble; for angle inputs a run may wrap around
// (first > last), and a run covering every sample is the full turn.
struct Run {
  int first = 0;
  int last = 0;
  bool full = false;
  bool open_start = false;  // slider inputs: the run reaches the sampled range's end
  bool open_end = false;
};

std::vector<Run> FindRuns(const Sampled& sampled, bool periodic) {
  const int n = static_cast<int>(sampled.count.size());
  std::vector<Run> runs;
  int start = -1;
  for (int k = 0; k < n; ++k) {
    if (sampled.count[k] > 0 && start < 0) start = k;
    if ((sampled.count[k] == 0 || k == n - 1) && start >= 0) {
      Run run;
      run.first = start;
      run.last = sampled.count[k] > 0 ? k : k - 1;
      runs.push_back(run);
      start = -1;
    }
  }
  if (periodic && !runs.empty()) {
    if (runs.size() == 1 && runs[0].first == 0 && runs[0].last == n - 1) {
      runs[0].full = true;
    } else if (runs.size() > 1 && runs.front().first == 0 && runs.back().last == n - 1) {
      // The first and last runs join across -pi.
      runs.front().first = runs.back().first;
      runs.pop_back();
    }
  } else {
    for (Run& run : runs) {
      run.open_start = run.first == 0;
      run.open_end = run.last == n - 1;
    }
  }
  return runs;
}

// Sample indices of a run in increasing input order (wrapping for angle inputs).
std::vector<int> RunIndices(const Run& run, int n) {
  std::vector<int> indices;
  int k = run.first;
  while (true) {
    indices.push_back(k);
    if (k == run.last) break;
    k = (k + 1) % n;
    if (static_cast<int>(indices.size()) > n) break;
  }
  return indices;
}

// The two configurations at `value` with their labels, and the errors against `pose`.
int Assemble(const PlanarDyad& input, const PlanarDyad& output, double value, double length,
             std::vector<PlanarPose>* configurations) {
  return AssembleFourBar(input, output, value, 1e-9 * length, configurations);
}

}  // namespace

std::optional<double> TransmissionAngleDeg(const PlanarDyad& input, const PlanarDyad& output,
                                           const PlanarPose& coupler) {
  if (input.type == DyadType::kRP || output.type == DyadType::kRP) return std::nullopt;
  const Eigen::Vector2d input_pin = coupler.ToFixed(input.moving_pivot);
  const Eigen::Vector2d output_pin = coupler.ToFixed(output.moving_pivot);
  const Eigen::Vector2d coupler_line = output_pin - input_pin;
  Eigen::Vector2d path;  // direction in which the output pin can move
  if (output.type == DyadType::kRR) {
    const Eigen::Vector2d arm = output_pin - output.fixed_pivot;
    path = Eigen::Vector2d(-arm.y(), arm.x());
  } else {
    path = output.line_direction;
  }
  const double norms = coupler_line.norm() * path.norm();
  if (!(norms > 0.0)) return std::nullopt;
  const double deviation = std::acos(std::min(1.0, std::abs(coupler_line.dot(path)) / norms));
  return 90.0 - deviation * 180.0 / M_PI;
}

bool FourBarCircuit::Spans(double value, bool angle_input) const {
  if (input_rotates_fully) return true;
  // The input's true limit lies within one step beyond the last sample that assembled.
  if (angle_input)
    return PositiveAngle(value - input_start + input_step) <= input_extent + 2.0 * input_step;
  return value >= input_start - input_step && value <= input_start + input_extent + input_step;
}

FourBarMotion TraceFourBar(const PlanarDyad& input, const PlanarDyad& output,
                           const std::vector<PlanarPose>& poses, double length,
                           const FourBarMotionOptions& options) {
  const bool periodic = IsAngleInput(input);
  const Sampled sampled =
      SampleConfigurations(input, output, InputSamples(input, poses, length, options));
  const int n = static_cast<int>(sampled.inputs.size());
  FourBarMotion motion;
  const std::vector<Run> runs = FindRuns(sampled, periodic);
  for (const Run& run : runs) {
    const std::vector<int> indices = RunIndices(run, n);
    // Two labels exist where the assembly is quadratic; check on the run's samples.
    bool two_labels = true;
    for (int k : indices) two_labels = two_labels && sampled.count[k] == 2;
    auto circuit_of_label = [&](int label, int branch, bool reverse, FourBarCircuit* circuit) {
      for (size_t i = 0; i < indices.size(); ++i) {
        const int k = indices[reverse ? indices.size() - 1 - i : i];
        circuit->samples.push_back({sampled.inputs[k], sampled.label[label][k], branch});
      }
    };
    const double step = std::abs(sampled.inputs[1] - sampled.inputs[0]);
    const double start = sampled.inputs[run.first];
    const double extent =
        periodic ? (run.full ? kTwoPi : PositiveAngle(sampled.inputs[run.last] - start))
                 : sampled.inputs[run.last] - start;
    auto describe = [&](FourBarCircuit* circuit) {
      circuit->input_start = start;
      circuit->input_extent = extent;
      circuit->input_step = step;
    };
    const bool joined_at_start = !run.full && !run.open_start;
    const bool joined_at_end = !run.full && !run.open_end;
    if (!two_labels || run.full || (!joined_at_start && !joined_at_end)) {
      // Each label is a circuit of its own (a crank, a linear assembly, or a slider range whose
      // limits were not reached).
      for (int label = 0; label < (two_labels ? 2 : 1); ++label) {
        FourBarCircuit circuit;
        describe(&circuit);
        circuit.label = label;
        circuit.input_rotates_fully = run.full && periodic;
        circuit_of_label(label, 0, false, &circuit);
        motion.circuits.push_back(std::move(circuit));
      }
    } else {
      // A limited input: forward on label 0, back on label 1; the labels meet at the input's
      // limits, the stationary configurations that separate the two branches.
      FourBarCircuit circuit;
      describe(&circuit);
      circuit.label = -1;
      circuit.branches = 2;
      circuit_of_label(0, 0, false, &circuit);
      circuit_of_label(1, 1, true, &circuit);
      motion.circuits.push_back(std::move(circuit));
    }
  }
  return motion;
}

FourBarLocation LocatePose(const FourBarMotion& motion, const PlanarDyad& input,
                           const PlanarDyad& output, const PlanarPose& pose, double length) {
  FourBarLocation location;
  std::vector<PlanarPose> configurations;
  const int count =
      AssembleFourBarAtPose(input, output, pose, 1e-9 * length, &configurations, &location.input);
  if (count == 0) return location;
  int label = 0;
  for (int l = 1; l < count; ++l) {
    if (PoseError(configurations[l], pose, length) <
        PoseError(configurations[label], pose, length)) {
      label = l;
    }
  }
  location.pose_error = PoseError(configurations[label], pose, length);
  // The circuit: the one of this label (or of both labels) that spans the input value; failing
  // that (a value beyond the sampled range), the one whose nearest sample is nearest the pose.
  const bool angle_input = IsAngleInput(input);
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < motion.circuits.size(); ++c) {
    const FourBarCircuit& circuit = motion.circuits[c];
    if (circuit.label >= 0 && circuit.label != label) continue;
    double distance = 0.0;
    if (!circuit.Spans(location.input, angle_input)) {
      distance = std::numeric_limits<double>::infinity();
      for (const FourBarSample& sample : circuit.samples) {
        distance = std::min(distance, PoseError(sample.coupler, pose, length));
      }
    }
    if (distance < nearest) {
      nearest = distance;
      location.circuit = static_cast<int>(c);
      location.branch = circuit.label >= 0 ? 0 : label;
    }
  }
  return location;
}

std::vector<bool> StepsWithinNoise(const std::vector<FourBarLocation>& locations,
                                   const std::vector<PlanarPose>& poses, double length) {
  std::vector<bool> within(locations.size(), false);
  for (size_t j = 1; j < locations.size() && j < poses.size(); ++j) {
    const double residual = locations[j - 1].pose_error + locations[j].pose_error;
    within[j] = residual <= kNoiseResidualCap * length &&
                PoseError(poses[j - 1], poses[j], length) <= 2.0 * residual;
  }
  return within;
}

namespace {

// Why the transmission angle over the poses is not given (empty when it is).
std::string TransmissionNote(const PlanarDyad& input, const PlanarDyad& output,
                             const std::vector<std::string>& defects) {
  if (input.type == DyadType::kRP || output.type == DyadType::kRP) {
    return "defined for dyads that both pin the coupler (no RP dyad)";
  }
  if (!defects.empty() && defects.front() != "order") return "the poses are not on one branch";
  return "";
}

}  // namespace

FourBarAnalysis AnalyzeFourBarSampled(const PlanarDyad& input, const PlanarDyad& output,
                                      const std::vector<PlanarPose>& poses, double length,
                                      const FourBarMotionOptions& options) {
  FourBarAnalysis analysis;
  const FourBarMotion motion = TraceFourBar(input, output, poses, length, options);
  for (const PlanarPose& pose : poses) {
    analysis.locations.push_back(LocatePose(motion, input, output, pose, length));
  }
  if (poses.empty() || analysis.locations[0].circuit < 0) return analysis;
  const int circuit_index = analysis.locations[0].circuit;
  const FourBarCircuit& circuit = motion.circuits[circuit_index];
  analysis.circuit = circuit_index;
  analysis.input_rotates_fully = circuit.input_rotates_fully;
  for (const FourBarSample& sample : circuit.samples) analysis.cycle.push_back(sample.coupler);

  // Defects; positions measured from one step before the circuit's first sample (a pose may lie
  // between that sample and the input's true limit).
  const bool periodic = IsAngleInput(input);
  const double origin = circuit.input_start - circuit.input_step;
  const auto position = [&](double value) {
    return periodic && !circuit.input_rotates_fully ? PositiveAngle(value - origin) : value;
  };
  const std::vector<bool> within_noise = StepsWithinNoise(analysis.locations, poses, length);
  const DefectVisit visit =
      JudgeDefects(analysis.locations, circuit_index, circuit.input_rotates_fully, position,
                   &analysis.defects, within_noise);
  if (std::find(within_noise.begin(), within_noise.end(), true) != within_noise.end() &&
      std::find(analysis.defects.begin(), analysis.defects.end(), "order") ==
          analysis.defects.end()) {
    std::vector<std::string> strict;
    JudgeDefects(analysis.locations, circuit_index, circuit.input_rotates_fully, position, &strict);
    analysis.order_within_noise = std::find(strict.begin(), strict.end(), "order") != strict.end();
  }
  const bool increasing = visit.increasing, decreasing = visit.decreasing;

  // Pose error on the one circuit; a pose not reachable on it at its input value: the nearest
  // configuration of the circuit, or at the same input the configuration of the circuit's label.
  std::vector<PlanarPose> configurations;
  analysis.max_pose_error = MaxPoseErrorOnCircuit(analysis.locations, circuit_index, [&](size_t j) {
    double error = std::numeric_limits<double>::infinity();
    const int count = Assemble(input, output, analysis.locations[j].input, length, &configurations);
    if (circuit.label >= 0 && circuit.label < count) {
      error = PoseError(configurations[circuit.label], poses[j], length);
    }
    for (const FourBarSample& sample : circuit.samples) {
      error = std::min(error, PoseError(sample.coupler, poses[j], length));
    }
    return error;
  });

  // Transmission angle over the motion from the first to the last pose, along the branch.
  analysis.transmission_note = TransmissionNote(input, output, analysis.defects);
  if (analysis.transmission_note.empty()) {
    const double start = analysis.locations.front().input;
    const double end = analysis.locations.back().input;
    // Direction and extent: for a full turn, the direction that visits the poses in order;
    // otherwise straight from the first to the last value.
    double extent = end - start;
    if (periodic) {
      extent =
          circuit.input_rotates_fully && !increasing && decreasing
              ? -PositiveAngle(start - end)
              : (circuit.input_rotates_fully ? PositiveAngle(end - start) : WrapAngle(end - start));
    }
    const int steps = 180;
    const int label = analysis.locations.front().branch >= 0 && circuit.label < 0
                          ? analysis.locations.front().branch
                          : std::max(circuit.label, 0);
    TransmissionRangeDeg(
        input, output, steps,
        [&](int s) -> std::optional<PlanarPose> {
          const int count =
              Assemble(input, output, start + extent * s / steps, length, &configurations);
          if (count == 0) return std::nullopt;
          return configurations[std::min(label, count - 1)];
        },
        &analysis.transmission_min_deg, &analysis.transmission_max_deg);
  }
  return analysis;
}

namespace {

// The transmission angle over the input from `start` over `extent` (RR or PR input, RR or PR
// output), in closed form: it depends on the input pin only through the closure scalar f
// (four_bar_closure.h ClosureScalar), whose range over the way is exact.
//   RR output: f = d = |M1 - F2|, and cos gamma = (l^2 + r2^2 - d^2) / (2 l r2), gamma the
//     coupler-rocker angle growing with d; folded to [0, 90] as TransmissionAngleDeg:
//     90 - |90 - gamma|;
//   PR output: f = n . (M1 - q), the coupler leans off the slider line by asin(|f| / l), and the
//     transmission angle is 90 degrees less that.
void ClosedTransmission(const PlanarDyad& input, const PlanarDyad& output, double start,
                        double extent, std::optional<double>* min_deg,
                        std::optional<double>* max_deg) {
  const ClosureScalar scalar = InputClosureScalar(input, output);
  double low = 0.0, high = 0.0;
  scalar.Range(start, extent, &low, &high);
  const double side = (output.moving_pivot - input.moving_pivot).norm();
  if (!(side > 0.0)) return;
  if (output.type == DyadType::kRR) {
    const double rocker = output.radius;
    if (!(rocker > 0.0)) return;
    const auto gamma = [&](double d) {
      const double x = (side * side + rocker * rocker - d * d) / (2.0 * side * rocker);
      return std::acos(std::clamp(x, -1.0, 1.0)) * 180.0 / M_PI;
    };
    const auto fold = [](double g) { return 90.0 - std::abs(90.0 - g); };
    const double g_low = gamma(low), g_high = gamma(high);  // gamma grows with d
    *min_deg = std::min(fold(g_low), fold(g_high));
    *max_deg = g_low <= 90.0 && g_high >= 90.0 ? 90.0 : std::max(fold(g_low), fold(g_high));
    return;
  }
  // The coupler's lean |f| / l, least 0 where f passes 0.
  const double most = std::max(std::abs(low), std::abs(high));
  const double least = low <= 0.0 && 0.0 <= high ? 0.0 : std::min(std::abs(low), std::abs(high));
  const auto transmission = [&](double lean) {
    return 90.0 - std::asin(std::min(1.0, lean / side)) * 180.0 / M_PI;
  };
  *min_deg = transmission(most);
  *max_deg = transmission(least);
}

}  // namespace

FourBarAnalysis AnalyzeFourBar(const PlanarDyad& input, const PlanarDyad& output,
                               const std::vector<PlanarPose>& poses, double length,
                               const FourBarMotionOptions& options) {
  FourBarAnalysis analysis;
  const FourBarClosure closure = SolveFourBarClosure(input, output);
  std::vector<PlanarPose> configurations;
  // Each pose's input value and its error at each assembly label there.
  std::vector<double> inputs;
  std::vector<std::array<double, 2>> label_errors;
  for (const PlanarPose& pose : poses) {
    double value = 0.0;
    const int count =
        AssembleFourBarAtPose(input, output, pose, 1e-9 * length, &configurations, &value);
    std::array<double, 2> errors = {std::numeric_limits<double>::infinity(),
                                    std::numeric_limits<double>::infinity()};
    for (int l = 0; l < count; ++l) errors[l] = PoseError(configurations[l], pose, length);
    inputs.push_back(value);
    label_errors.push_back(errors);
  }
  std::vector<double> step_distances(poses.size(), std::numeric_limits<double>::infinity());
  for (size_t j = 1; j < poses.size(); ++j) {
    step_distances[j] = PoseError(poses[j - 1], poses[j], length);
  }
  const ClosureJudgment judgment = JudgeOnClosure(
      closure, inputs, label_errors, options.slider_margin, length,
      [&](size_t j, double value, int label) {
        const int count = AssembleFourBar(input, output, value, 1e-9 * length, &configurations);
        if (count == 0) return std::numeric_limits<double>::infinity();
        return PoseError(configurations[std::min(label, count - 1)], poses[j], length);
      },
      step_distances);
  if (!TakeJudgment(judgment, &analysis)) return analysis;
  if (options.trace_cycle) {
    analysis.cycle = CircuitConfigurations<PlanarPose>(
        closure, judgment.circuits[judgment.circuit], judgment.lo, judgment.hi, options.samples,
        [&](double value, std::vector<PlanarPose>* configurations) {
          return AssembleFourBar(input, output, value, 1e-9 * length, configurations);
        });
  }
  // Transmission angle over the motion from the first to the last pose, along the branch.
  analysis.transmission_note = TransmissionNote(input, output, analysis.defects);
  if (analysis.transmission_note.empty()) {
    ClosedTransmission(input, output, judgment.sweep_start, judgment.sweep_extent,
                       &analysis.transmission_min_deg, &analysis.transmission_max_deg);
  }
  return analysis;
}

}  // namespace linkfit
