// Function problems (issue 17, items 6-8): the exact solvers of fitting/function_generation.h,
// least squares beyond them (seeds refined by optimizers/function_refiner.h, searched by
// optimizers/function_search.h), and the four-bars' analysis and ranking.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "fitting/function_generation.h"
#include "fitting/model_choice.h"
#include "fitting/planar_motion.h"
#include "lib/text_format.h"
#include "optimizers/function_refiner.h"
#include "optimizers/function_search.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Two four-bars are one when of one assembly, their lengths agree within `tolerance` times the
// larger of the ground and the length, and their offsets within `tolerance` radians.
bool SameFourBar(const FunctionFourBar& a, const FunctionFourBar& b, double tolerance) {
  if (a.assembly != b.assembly) return false;
  const auto same = [&](double x, double y) {
    return std::abs(x - y) <= tolerance * std::max({a.ground, std::abs(x), std::abs(y)});
  };
  return same(a.input_length, b.input_length) && same(a.coupler_length, b.coupler_length) &&
         same(a.output_length, b.output_length) &&
         std::abs(WrapToPi(a.input_offset - b.input_offset)) <= tolerance &&
         std::abs(WrapToPi(a.output_offset - b.output_offset)) <= tolerance;
}

// The largest output error of a four-bar that meets the pairs within the data's precision:
// kModelUnits angle uncertainties of a pair (its input's and output's rounding, sqrt 2 h), not
// below 1e-8 radians (pairs computed from a function at full precision: an exact four-bar meets
// them only to its own rounding, 1e-13 degrees and more, which is no miss).
double AnglePassTolerance(const DataPrecision& precision) {
  return std::max(1e-8, kModelUnits * std::sqrt(2.0) * precision.angle);
}

// How near a four-bar comes to a pair marked exact (radians): 1e-9, or a thousandth of the
// data's angle precision (the refiner's exact tolerance: the pairs' own rounding).
double ExactPairTolerance(const DataPrecision& precision) {
  return std::max(FunctionRefinerOptions().exact_tolerance, 1e-3 * precision.angle);
}

FunctionMechanismReport Report(const Task& task, const FunctionFourBar& four_bar,
                               std::optional<double> seed_max) {
  FunctionMechanismReport report;
  report.design = four_bar;
  const FunctionAnalysis analysis = AnalyzeFunctionFourBar(four_bar, task.pairs);
  report.max_angle_error = analysis.max_error;
  report.rms_angle_error = analysis.rms_error;
  report.error_note = analysis.error_note;
  report.defects = analysis.defects;
  report.grashof = analysis.grashof;
  report.input_rotates_fully = analysis.input_rotates_fully;
  report.output_rotates_fully = analysis.output_rotates_fully;
  report.transmission_min_deg = analysis.transmission_min_deg;
  report.transmission_max_deg = analysis.transmission_max_deg;
  if (seed_max && report.max_angle_error && *seed_max != *report.max_angle_error) {
    report.seed_max_angle_error = seed_max;
  }
  if (std::any_of(task.pairs.begin(), task.pairs.end(),
                  [](const FunctionPair& pair) { return pair.exact; })) {
    if (analysis.errors.size() == task.pairs.size()) {
      double worst = 0.0;
      for (size_t j = 0; j < task.pairs.size(); ++j) {
        if (task.pairs[j].exact) worst = std::max(worst, std::abs(analysis.errors[j]));
      }
      report.exact_angle_error = worst;
    }
    report.misses_exact = !(report.exact_angle_error &&
                            *report.exact_angle_error <= ExactPairTolerance(task.precision));
  }
  if (!task.pairs.empty()) {
    report.first =
        ConfigurationAt(four_bar, task.pairs[0].input, task.ground_input, task.ground_output);
  }
  if (report.max_angle_error && !HasKinematicDefect(report.defects)) {
    report.error_bound =
        FunctionErrorBound(four_bar, task.pairs, task.relative_angles, task.precision.angle);
  }
  // A function given as samples: the four-bar runs over its whole input range (between and
  // beyond the precision points), or has the defect "range"; the transmission angle is then the
  // range's (else the pairs').
  if (!task.function_samples.empty() && analysis.assembles_first) {
    const FunctionRangeAnalysis range =
        AnalyzeFunctionRange(four_bar, task.pairs[0], task.function_samples);
    report.function_max_error = range.max_error;
    report.function_error_note = range.note;
    if (!range.max_error) {
      report.defects.push_back("range");
    } else {
      report.transmission_min_deg = range.transmission_min_deg;
      report.transmission_max_deg = range.transmission_max_deg;
    }
  } else if (!task.function_samples.empty()) {
    report.function_error_note = analysis.error_note;
  }
  FourBarLinks links;
  links.ground = four_bar.ground;
  links.input = four_bar.input_length;
  links.coupler = four_bar.coupler_length;
  links.output = four_bar.output_length;
  FourBarClass kind;
  kind.grashof = analysis.grashof;
  kind.input_rotates_fully = analysis.input_rotates_fully;
  report.violates = FunctionViolations(task.constraints, links, kind, four_bar.ground);
  // Minimal pairs are met exactly: a four-bar that misses one by more than their precision on
  // its circuit and assembly does not do the task (issue 35).
  const size_t minimum = task.relative_angles ? 5 : 3;
  if (task.pairs.size() == minimum) {
    JudgeMisses(report.max_angle_error, AnglePassTolerance(task.precision), &report.defects);
  }
  JudgeTransmission(task.constraints, report.transmission_min_deg, &report.defects);
  return report;
}

}  // namespace

// Three absolute pairs fix one four-bar by where the input's and the output's ranges start
// (issue 35, item 5): when none listed is one to build (no defect, every constraint kept), the
// starts are tried on a grid of kStartStepDeg (both cranks turned by the same function) and the
// note names the one whose four-bar builds with the smallest structural error (over the sampled
// function, else at the pairs), to give in the task. Empty otherwise.
constexpr int kStartStepDeg = 10;

std::string StartAngleNote(const Task& task, const FunctionResult& result, double d) {
  if (task.relative_angles || task.pairs.size() != 3) return "";
  const auto builds = [&](const FunctionMechanismReport& report) {
    return report.defects.empty() && report.violates.empty() && report.max_angle_error;
  };
  if (!result.mechanisms.empty() && builds(result.mechanisms.front())) return "";
  std::optional<double> best_error;
  int best_input = 0, best_output = 0;
  double best_transmission = 0.0;
  for (int input = 0; input < 360; input += kStartStepDeg) {
    for (int output = 0; output < 360; output += kStartStepDeg) {
      if (input == 0 && output == 0) continue;
      Task shifted = task;
      const double da = input * M_PI / 180.0, db = output * M_PI / 180.0;
      for (std::vector<FunctionPair>* pairs : {&shifted.pairs, &shifted.function_samples}) {
        for (FunctionPair& pair : *pairs) {
          pair.input += da;
          pair.output += db;
        }
      }
      std::vector<FunctionFourBar> four_bars;
      SolveFreudenstein(shifted.pairs, d, &four_bars, nullptr);
      for (const FunctionFourBar& four_bar : four_bars) {
        if (!four_bar.Valid()) continue;
        const FunctionMechanismReport report = Report(shifted, four_bar, std::nullopt);
        if (!builds(report)) continue;
        const double error =
            report.function_max_error ? *report.function_max_error : *report.max_angle_error;
        if (!best_error || error < *best_error) {
          best_error = error;
          best_input = input;
          best_output = output;
          best_transmission = report.transmission_min_deg.value_or(0.0);
        }
      }
    }
  }
  const std::string why = result.mechanisms.empty()
                              ? "no four-bar meets the three pairs where the ranges start"
                              : "the one four-bar of the three pairs is not one to build (its "
                                "\"defects\" and \"violates\" say why)";
  if (!best_error) {
    return why + "; no start of the input and output ranges on a " + std::to_string(kStartStepDeg) +
           "-degree grid gives one that is: try five or more precision points (\"angles\": "
           "\"relative\")";
  }
  return why + ": three absolute pairs fix it by where the ranges start, and starting the input " +
         std::to_string(best_input) + " deg and the output " + std::to_string(best_output) +
         " deg later (add them to input_range_deg and output_range_deg, or to the pairs' angles) "
         "gives one without defect that keeps the constraints: structural error " +
         Format("%.3g", *best_error * 180.0 / M_PI) + " deg, worst transmission angle " +
         Format("%.3g", best_transmission) + " deg";
}

FunctionResult SolveFunctionTask(const Task& task, const TaskSolverOptions& options) {
  const auto start = Clock::now();
  FunctionResult result;
  result.relative_angles = task.relative_angles;
  result.ground_input = task.ground_input;
  result.ground_output = task.ground_output;
  result.precision = task.precision;
  result.constraints = task.constraints;
  result.notes = task.input_notes;
  if (!task.function_samples.empty() && task.pairs.size() != task.function_samples.size()) {
    result.precision_points = task.pairs;
  }
  const double d = (task.ground_output - task.ground_input).norm();
  result.scale = d;
  const size_t minimum = task.relative_angles ? 5 : 3;
  const bool exact = task.pairs.size() == minimum;
  if (!exact) {
    result.method = "least-squares";
    result.effort = EffortName(task.effort);
  }
  FunctionGenerationOptions generation;
  generation.precision = task.precision;

  // Seeds: the exact or linear least-squares solve of every pair, and beyond the minimum the
  // exact solves of spread subsets.
  auto stage_start = Clock::now();
  std::vector<FunctionFourBar> seeds;
  std::string why;
  const auto solve = [&](const std::vector<FunctionPair>& pairs, std::string* reason) {
    return task.relative_angles ? SolveRelativeFunction(pairs, d, generation, &seeds, reason)
                                : SolveFreudenstein(pairs, d, &seeds, reason);
  };
  solve(task.pairs, &why);
  if (!exact) {
    // Subsets through the pairs marked exact (SeedSubsets): their four-bars meet them.
    std::vector<bool> exact_pairs;
    for (const FunctionPair& pair : task.pairs) exact_pairs.push_back(pair.exact);
    for (const std::vector<int>& indices :
         SeedSubsets(static_cast<int>(task.pairs.size()), options.function_seed_subsets,
                     exact_pairs, static_cast<int>(minimum))) {
      std::vector<FunctionPair> subset;
      for (int index : indices) subset.push_back(task.pairs[index]);
      solve(subset, nullptr);
    }
  }
  // Each seed on both assemblies: a subset's assembly need not be the whole task's.
  std::vector<FunctionFourBar> candidates;
  std::vector<std::optional<double>> seed_errors;
  for (FunctionFourBar seed : seeds) {
    for (int sigma : {seed.assembly, -seed.assembly}) {
      if (exact && sigma != seed.assembly) continue;
      seed.assembly = sigma;
      // Subsets often give one four-bar twice: refined once.
      if (std::none_of(candidates.begin(), candidates.end(), [&](const FunctionFourBar& other) {
            return SameFourBar(other, seed, 1e-9);
          })) {
        candidates.push_back(seed);
      }
    }
  }
  const auto best_max = [&](const std::vector<FunctionFourBar>& four_bars) {
    std::optional<double> best;
    for (const FunctionFourBar& f : four_bars) {
      const FunctionAnalysis analysis = AnalyzeFunctionFourBar(f, task.pairs);
      if (analysis.max_error && (!best || *analysis.max_error < *best)) best = analysis.max_error;
    }
    return best;
  };
  if (!exact) {
    StageReport stage;
    stage.name = "seed";
    stage.seconds = Since(stage_start);
    stage.best_max_angle_error = best_max(candidates);
    result.stages.push_back(stage);
  }
  // Balanced and thorough: every seed refined on the output-angle error; thorough also searches.
  std::vector<std::optional<double>> before(candidates.size());
  if (!exact && task.effort != Effort::kFast) {
    stage_start = Clock::now();
    FunctionRefinerOptions refiner = options.function_refiner;
    refiner.free_offsets = task.relative_angles;
    refiner.exact_tolerance = ExactPairTolerance(task.precision);
    refiner.max_link_length = MaxLinkLength(task.constraints, d) / d;
    // With constraints given, the transmission angle is held (as for path four-bars).
    if (task.constraints.given) {
      refiner.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
    }
    std::vector<FunctionFourBar> refined;
    for (size_t i = 0; i < candidates.size(); ++i) {
      FunctionFourBar four_bar = candidates[i];
      const RefinerSummary summary = RefineFunctionFourBar(task.pairs, &four_bar, refiner);
      before[i] = summary.initial_max;
      candidates[i] = four_bar;
    }
    StageReport stage;
    stage.name = "refine";
    stage.seconds = Since(stage_start);
    stage.best_max_angle_error = best_max(candidates);
    result.stages.push_back(stage);
    if (task.effort == Effort::kThorough) {
      stage_start = Clock::now();
      FunctionSearchOptions search = options.function_search;
      search.relative = task.relative_angles;
      search.max_link_length = refiner.max_link_length;
      search.refiner = refiner;
      std::vector<FunctionFourBar> found;
      SearchFunctionFourBars(task.pairs, d, search, &found);
      for (const FunctionFourBar& f : found) {
        candidates.push_back(f);
        before.push_back(std::nullopt);
      }
      StageReport search_stage;
      search_stage.name = "search";
      search_stage.seconds = Since(stage_start);
      search_stage.best_max_angle_error = best_max(candidates);
      result.stages.push_back(search_stage);
    }
  }

  // The four-bars, without repeats (the better-fitting of two kept), analysed and ranked.
  const auto analysis_start = Clock::now();
  std::vector<FunctionMechanismReport> reports;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!candidates[i].Valid()) continue;
    FunctionMechanismReport report = Report(task, candidates[i], before[i]);
    bool repeated = false;
    for (FunctionMechanismReport& other : reports) {
      if (!SameFourBar(other.design, report.design, exact ? 1e-9 : 1e-4)) continue;
      repeated = true;
      const double mine = report.rms_angle_error.value_or(std::numeric_limits<double>::infinity());
      const double theirs = other.rms_angle_error.value_or(std::numeric_limits<double>::infinity());
      if (mine < theirs) other = report;
      break;
    }
    if (!repeated) reports.push_back(report);
  }
  const double pass = AnglePassTolerance(task.precision);
  const auto key_of = [&](const FunctionMechanismReport& report) {
    RankKey key;
    key.misses_exact = report.misses_exact;
    JudgeWithDefaults(task.constraints, report.violates, report.defects,
                      report.max_angle_error.has_value(), &key);
    key.fit = report.rms_angle_error;
    key.within_precision = report.max_angle_error && *report.max_angle_error <= pass;
    key.fit_floor = 1e-3 * pass;
    key.parameters = FourBarParameters(FourBarType::k4R);
    key.transmission_min_deg = TransmissionTieBreak(task.constraints, report.transmission_min_deg);
    if (report.first) {
      key.size = JointSpread({report.first->input_pivot, report.first->input_moving,
                              report.first->output_pivot, report.first->output_moving});
    }
    return key;
  };
  const int dropped = RankReports<FunctionMechanismReport>(
      key_of, exact ? -1 : options.function_reported, &reports);
  if (dropped > 0) result.notes.push_back(DroppedNote(dropped));
  result.mechanisms = std::move(reports);
  {
    std::vector<RankKey> keys;
    for (const FunctionMechanismReport& report : result.mechanisms) keys.push_back(key_of(report));
    const std::string note = DefaultsNote(keys, "an RMS angle error (radians) of");
    if (!note.empty()) result.notes.push_back(note);
    if (!result.mechanisms.empty()) {
      const FunctionMechanismReport& first = result.mechanisms.front();
      const std::string given =
          GivenConstraintsNote(task.constraints, first.violates, first.defects);
      if (!given.empty()) result.notes.push_back(given);
    }
  }
  if (result.mechanisms.empty()) {
    result.notes.push_back("no four-bar meets the pairs" + (why.empty() ? "" : ": " + why));
  }
  if (exact) {
    const std::string start_note = StartAngleNote(task, result, d);
    if (!start_note.empty()) result.notes.push_back(start_note);
  }
  result.analysis_seconds = Since(analysis_start);
  result.solve_seconds = Since(start);
  return result;
}

}  // namespace linkfit
