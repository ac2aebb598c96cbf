// The speed/accuracy trade (see trade_bench.h).
#include "bench/trade_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <variant>

#include "apps/output_file.h"
#include "bench/constrained_bench.h"
#include "bench/extremes_bench.h"
#include "bench/percentile.h"
#include "fitting/spherical_motion.h"
#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "lib/path_motion.h"
#include "lib/result_io.h"
#include "lib/spherical_four_bar.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_function.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spatial.h"
#include "tests/support/random_spherical.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Success thresholds (trade_bench.h).
constexpr double kExactTolerance = 1e-9;       // exact data, in L
constexpr double kFreeTimingTolerance = 1e-6;  // exact data under free timing, in L
constexpr double kNoisyRatio = 1.10;           // noisy data, against the generating mechanism

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// A generator makes task `t` of a cell (the same tasks for every effort level) and solves it.
using CellRunner = std::function<TradeOutcome(std::mt19937_64& rng, Effort effort)>;

TradeRow RunCell(const std::string& family, int items, double noise, const std::string& path,
                 const char* effort_name, Effort effort, int tasks, uint64_t seed,
                 double success_tolerance, const CellRunner& run) {
  TradeRow row;
  row.family = family;
  row.items = items;
  row.noise = noise;
  row.path = path;
  row.effort = effort_name;
  row.tasks = tasks;
  std::vector<double> times, errors;
  int listed = 0, at_optimum = 0;
  int success = 0;
  std::mt19937_64 rng(seed);
  for (int t = 0; t < tasks; ++t) {
    const TradeOutcome outcome = run(rng, effort);
    times.push_back(outcome.ms);
    errors.push_back(outcome.error);
    success += outcome.error <= success_tolerance;
    listed += outcome.listed;
    at_optimum += outcome.at_optimum;
  }
  if (listed > 0) row.optimum_share = static_cast<double>(at_optimum) / listed;
  row.median_ms = Percentile(times, 0.5);
  row.worst_ms = Percentile(times, 1.0);
  row.median_error = Percentile(errors, 0.5);
  row.worst_error = Percentile(errors, 1.0);
  row.success_share = tasks > 0 ? static_cast<double>(success) / tasks : 0.0;
  return row;
}

// ---- at its optimum ----

// The RMS error of listed mechanism `k` of a planar motion or path result.
double RmsError(const TaskResult& result, size_t k) {
  if (const auto* path = std::get_if<PathResult>(&result)) {
    return path->mechanisms[k].rms_point_error.value_or(kInfinity);
  }
  return std::get<PlanarMotionResult>(result).mechanisms[k].rms_pose_error.value_or(kInfinity);
}

// The result's length scale L.
double Scale(const TaskResult& result) {
  if (const auto* path = std::get_if<PathResult>(&result)) return path->scale;
  return std::get<PlanarMotionResult>(result).scale;
}

size_t ListedCount(const TaskResult& result) {
  if (const auto* path = std::get_if<PathResult>(&result)) return path->mechanisms.size();
  return std::get<PlanarMotionResult>(result).mechanisms.size();
}

// Counts a least-squares result's listed four-bars, and those `linkfit refine` improves by less
// than 1 % of their RMS error: the result written as the CLI writes it, read back as a design
// and each four-bar refined as `linkfit refine --mechanism` refines it.
void CountAtOptimum(const Task& task, const TaskResult& result, TradeOutcome* outcome) {
  const TaskDesign design = ParseTaskDesign(ResultToJson(result, -1), "result", task);
  for (size_t k = 0; k < ListedCount(result); ++k) {
    const double error = RmsError(result, k);
    if (!std::isfinite(error)) continue;  // not driven through the task: no fit to improve
    RefineChoice choice;
    choice.mechanism = static_cast<int>(k);
    ++outcome->listed;
    try {
      const TaskResult refined = RefineTask(task, design, choice);
      outcome->at_optimum += ListedCount(refined) == 0 || RmsError(refined, 0) >= 0.99 * error ||
                             error - RmsError(refined, 0) <= kExactTolerance * Scale(result);
    } catch (const InputError&) {
      ++outcome->at_optimum;  // refine does not take it (as the CLI says): nothing to improve
    }
  }
}

// ---- planar motion ----

TradeOutcome RunPlanar(std::mt19937_64& rng, Effort effort, int count, double noise) {
  const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, count);
  const double length = CharacteristicLength(generated.poses);
  std::vector<PlanarPose> poses = generated.poses;
  testing::PerturbPlanarPoses(rng, noise, length, &poses);
  const Task task = PlanarMotionTask(poses, effort);
  TradeOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const PlanarMotionResult result = SolvePlanarTask(task);
  outcome.ms = MillisecondsSince(begin);
  if (count > 5) CountAtOptimum(task, result, &outcome);
  // Minimal data: the largest pose error (no RMS is reported); more: the RMS pose error.
  double best = kInfinity;
  for (const MechanismReport& mechanism : result.mechanisms) {
    const std::optional<double>& error =
        mechanism.rms_pose_error ? mechanism.rms_pose_error : mechanism.max_pose_error;
    if (error && OnOneBranch(mechanism.defects)) best = std::min(best, *error);
  }
  if (noise == 0.0) {
    outcome.error = best / length;
    return outcome;
  }
  // The generating four-bar on the same noisy poses, measured the same way.
  const FourBarAnalysis analysis = AnalyzeFourBar(generated.input, generated.output, poses, length);
  double sum = 0.0, worst = 0.0;
  for (const FourBarLocation& location : analysis.locations) {
    sum += location.pose_error * location.pose_error;
    worst = std::max(worst, location.pose_error);
  }
  const double reference = count > 5 ? std::sqrt(sum / poses.size()) : worst;
  outcome.error = best / reference;
  return outcome;
}

// ---- spatial motion ----

double RmsResidual(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses) {
  double sum = 0.0;
  for (const DualQuaternion& pose : poses) sum += std::pow(dyad.Residual(pose), 2);
  return std::sqrt(sum / poses.size());
}

TradeOutcome RunSpatial(std::mt19937_64& rng, Effort effort, int count, double noise) {
  // A random 5-SS platform and `count` poses on its motion (redrawn when its motion is too short
  // for that many distinct poses).
  testing::PlantedSpatialTask platform = testing::RandomPlatformTask(rng, count);
  const std::vector<SpatialDyad>& planted = platform.planted;
  std::vector<DualQuaternion>& poses = platform.poses;
  testing::PerturbSpatialPoses(rng, noise, &poses);
  const Task task = SpatialMotionTask(poses, effort);
  TradeOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const SpatialMotionResult result = SolveSpatialTask(task);
  outcome.ms = MillisecondsSince(begin);
  // Each generating dyad: the returned dyad nearest it, by its RMS residual on the task.
  double error = 0.0;
  for (const SpatialDyad& expected : planted) {
    double nearest = kInfinity, residual = kInfinity;
    for (const SpatialDyadReport& report : result.dyads) {
      const double distance = testing::SpatialDyadDistance(report.dyad, expected);
      if (distance < nearest) {
        nearest = distance;
        residual = RmsResidual(report.dyad, poses);
      }
    }
    const double reference = noise == 0.0 ? result.scale : RmsResidual(expected, poses);
    error = std::max(error, residual / reference);
  }
  outcome.error = error;
  return outcome;
}

// ---- path generation ----

TradeOutcome RunPath(std::mt19937_64& rng, Effort effort, int count, double noise,
                     bool free_timing) {
  const testing::GeneratedPathTask generated = testing::RandomPathTask(rng, DyadType::kRR, count);
  const double length = testing::PathLength(generated.points);
  const Task task = testing::NoisyPathTask(generated, noise, free_timing, effort, rng);
  std::vector<Eigen::Vector2d> points;
  for (const TimedPoint& point : task.points) points.push_back(point.point_in_fixed);
  TradeOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const PathResult result = SolvePathTask(task);
  outcome.ms = MillisecondsSince(begin);
  if (count > 5) CountAtOptimum(task, result, &outcome);
  // Exact data: the largest point error; noisy: the RMS point error against the generating
  // four-bar's (minimal data: the largest against its largest).
  const bool use_rms = noise > 0.0 && count > 5;
  double best = kInfinity;
  for (const PathMechanismReport& mechanism : result.mechanisms) {
    const std::optional<double>& error =
        use_rms ? mechanism.rms_point_error : mechanism.max_point_error;
    if (error && !HasKinematicDefect(mechanism.defects)) best = std::min(best, *error);
  }
  if (noise == 0.0) {
    outcome.error = best / length;
    return outcome;
  }
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(generated.four_bar, points, generated.input_angles, length);
  const std::optional<double>& reference =
      use_rms ? analysis.rms_point_error : analysis.max_point_error;
  outcome.error = reference ? best / *reference : kInfinity;
  return outcome;
}

// ---- function generation ----

// Absolute or relative pairs of a random four-bar (tests/support/random_function.h), the outputs
// with noise sigma radians. Error: noise 0, the best four-bar's largest output error (radians);
// noisy, its RMS error against the generator's on the same pairs.
TradeOutcome RunFunction(std::mt19937_64& rng, Effort effort, int count, double noise,
                         bool relative) {
  const testing::FunctionTask generated = testing::RandomFunctionTask(rng, count, relative);
  std::normal_distribution<double> normal;
  Task task;
  task.problem = ProblemKind::kFunction;
  task.relative_angles = relative;
  task.effort = effort;
  task.pairs = generated.pairs;
  for (FunctionPair& pair : task.pairs) pair.output += noise * normal(rng);
  TradeOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const FunctionResult result = SolveFunctionTask(task);
  outcome.ms = MillisecondsSince(begin);
  const bool use_rms = noise > 0.0 && count > (relative ? 5 : 3);
  double best = kInfinity;
  for (const FunctionMechanismReport& mechanism : result.mechanisms) {
    const std::optional<double>& error =
        use_rms ? mechanism.rms_angle_error : mechanism.max_angle_error;
    if (error && !HasKinematicDefect(mechanism.defects)) best = std::min(best, *error);
  }
  if (noise == 0.0) {
    outcome.error = best;
    return outcome;
  }
  const FunctionAnalysis reference = AnalyzeFunctionFourBar(generated.four_bar, task.pairs);
  const std::optional<double>& own = use_rms ? reference.rms_error : reference.max_error;
  outcome.error = own && *own > 0.0 ? best / *own : kInfinity;
  return outcome;
}

// ---- spherical motion ----

// Orientations of a random spherical four-bar about a centre off both frames' origins
// (tests/support/random_spherical.h RandomSphericalPoses), each turned by noise sigma radians,
// given as spatial poses and solved as `linkfit solve` would: the result must say "spherical"
// (else the task is a miss, error inf). Error: noise 0, the best spherical four-bar's pose error
// in L (no circuit or branch defect; minimal data: the largest, else the RMS), as for planar
// motion; noisy, that against the generating four-bar's own on the same poses. The noise is on
// the rotations only: the poses still fix the centre, so the motion stays spherical.
TradeOutcome RunSpherical(std::mt19937_64& rng, Effort effort, int count, double noise) {
  const testing::SphericalPosesTask generated = testing::RandomSphericalPoses(rng, count, noise);
  const Task task = SpatialMotionTask(generated.poses, effort);
  TradeOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const SpatialMotionResult result = SolveSpatialTask(task);
  outcome.ms = MillisecondsSince(begin);
  if (result.model != "spherical" || !result.spherical) return outcome;
  // Minimal data: the largest pose error (no RMS is reported); more: the RMS pose error.
  double best = kInfinity;
  for (const MechanismReport& mechanism : result.spherical_mechanisms) {
    const std::optional<double>& error =
        mechanism.rms_pose_error ? mechanism.rms_pose_error : mechanism.max_pose_error;
    if (error && OnOneBranch(mechanism.defects)) best = std::min(best, *error);
  }
  if (noise == 0.0) {
    outcome.error = best / result.scale;
    return outcome;
  }
  // The generating four-bar on the same noisy poses, about the centre the solver found, measured
  // the same way (fitting/spherical_motion.cc AnalyzeSphericalPair).
  const SphericalMotion motion = TaskSphericalMotion(task, *result.spherical, result.scale);
  const SphericalFourBarAnalysis analysis = AnalyzeSphericalFourBar(generated.four_bar, motion);
  if (!analysis.max_pose_error) return outcome;  // no reference (not seen: the noise is small)
  double sum = 0.0;
  for (const FourBarLocation& location : analysis.locations) {
    sum += location.pose_error * location.pose_error;
  }
  const double reference =
      count > 5 ? std::sqrt(sum / analysis.locations.size()) : *analysis.max_pose_error;
  outcome.error = reference > 0.0 ? best / reference : kInfinity;
  return outcome;
}

// ---- the table ----

struct Sizes {
  int exact;   // tasks per cell of minimal data
  int fitted;  // tasks per cell, at every effort level
};

void PrintRow(std::FILE* table, const TradeRow& row) {
  if (table == nullptr) return;
  char optimum[16] = "       -";
  if (row.optimum_share >= 0.0) {
    std::snprintf(optimum, sizeof(optimum), "%7.1f%%", 100.0 * row.optimum_share);
  }
  std::fprintf(table, "%-15s %5d %-7g %-26s %-9s %5d %10.3f %10.3f %11.3e %11.3e %7.1f%% %s\n",
               row.family.c_str(), row.items, row.noise, row.path.c_str(), row.effort.c_str(),
               row.tasks, row.median_ms, row.worst_ms, row.median_error, row.worst_error,
               100.0 * row.success_share, optimum);
  std::fflush(table);
}

}  // namespace

std::string FormatNumber(double value) {
  if (std::isinf(value)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

TradeOutcome RunTradeTask(const std::string& family, int items, double noise, Effort effort,
                          std::mt19937_64& rng) {
  if (family == "planar motion") return RunPlanar(rng, effort, items, noise);
  if (family == "spatial motion") return RunSpatial(rng, effort, items, noise);
  if (family == "spherical motion") return RunSpherical(rng, effort, items, noise);
  if (family == "function abs") return RunFunction(rng, effort, items, noise, false);
  if (family == "function rel") return RunFunction(rng, effort, items, noise, true);
  return RunPath(rng, effort, items, noise, family == "untimed path");
}

std::vector<TradeRow> RunTradeBench(const BenchOptions& options, std::FILE* table) {
  const Sizes sizes = options.quick ? Sizes{20, 4} : Sizes{200, 24};
  if (table != nullptr) {
    std::fprintf(table,
                 "speed/accuracy trade (%s, seed %llu): error = noise 0: in L; noisy: against "
                 "the generating mechanism (success: <= %.0e L, free timing %.0e L; <= %.2f)\n",
                 options.quick ? "quick" : "full", static_cast<unsigned long long>(options.seed),
                 kExactTolerance, kFreeTimingTolerance, kNoisyRatio);
    std::fprintf(table, "%-15s %5s %-7s %-26s %-9s %5s %10s %10s %11s %11s %8s %8s\n", "family",
                 "items", "noise", "path", "effort", "tasks", "median_ms", "worst_ms", "median_err",
                 "worst_err", "success", "optimum");
  }
  std::vector<TradeRow> rows;
  const std::pair<const char*, Effort> efforts[] = {
      {"fast", Effort::kFast}, {"balanced", Effort::kBalanced}, {"thorough", Effort::kThorough}};
  auto run_family = [&](const std::string& family, int items, bool minimal,
                        const std::string& exact_path, const std::string& fitted_path,
                        double exact_tolerance) {
    // "family" (the trade family, e.g. "untimed path") or "family:number of items"
    if (!options.family.empty()) {
      const size_t colon = options.family.find(':');
      if (family != options.family.substr(0, colon)) return;
      if (colon != std::string::npos && options.family.substr(colon + 1) != std::to_string(items)) {
        return;
      }
    }
    for (const double noise : {0.0, 1e-3, 1e-2}) {
      // The same tasks for every effort level of a cell.
      const uint64_t seed = options.seed + 1000003ull * items + static_cast<uint64_t>(noise * 1e5) +
                            std::hash<std::string>()(family);
      const double tolerance = noise > 0.0 ? kNoisyRatio : exact_tolerance;
      auto runner = [&](std::mt19937_64& rng, Effort effort) {
        return RunTradeTask(family, items, noise, effort, rng);
      };
      if (minimal) {
        rows.push_back(RunCell(family, items, noise, exact_path, "exact", Effort::kBalanced,
                               sizes.exact, seed, tolerance, runner));
        PrintRow(table, rows.back());
        continue;
      }
      for (const auto& [name, effort] : efforts) {
        rows.push_back(RunCell(family, items, noise, fitted_path, name, effort, sizes.fitted, seed,
                               tolerance, runner));
        PrintRow(table, rows.back());
      }
    }
  };
  for (const int count : {5, 10, 50, 200}) {
    run_family("planar motion", count, count == 5, "planar exact", "planar least squares",
               kExactTolerance);
  }
  for (const int count : {7, 10, 30}) {
    run_family("spatial motion", count, count == 7, "spatial exact", "spatial least squares",
               kExactTolerance);
  }
  // Spherical motion: noise in radians of each orientation, errors in L.
  for (const int count : {5, 10, 20}) {
    run_family("spherical motion", count, count == 5, "spherical exact", "spherical least squares",
               kExactTolerance);
  }
  for (const int count : {5, 10, 20}) {
    run_family("timed path", count, count == 5, "path exact", "path least squares",
               kExactTolerance);
  }
  for (const int count : {10, 20}) {
    run_family("untimed path", count, false, "", "path free timing", kFreeTimingTolerance);
  }
  // Function generation: noise in radians of the output angle, errors in radians.
  for (const int count : {3, 12}) {
    run_family("function abs", count, count == 3, "function exact", "function least squares",
               kExactTolerance);
  }
  for (const int count : {5, 12}) {
    run_family("function rel", count, count == 5, "function exact", "function least squares",
               kExactTolerance);
  }
  return rows;
}

std::string TradeCsv(const std::vector<TradeRow>& rows) {
  std::ostringstream csv;
  csv << "family,path,effort,tasks,median_ms,worst_ms,median_error,worst_error,success_share,"
         "items,noise,error_unit,optimum_share\n";
  for (const TradeRow& row : rows) {
    const bool points = row.family.find("path") != std::string::npos;
    csv << row.family << " " << row.items << (points ? " points" : " poses") << " noise "
        << FormatNumber(row.noise) << "," << row.path << "," << row.effort << "," << row.tasks
        << "," << FormatNumber(row.median_ms) << "," << FormatNumber(row.worst_ms) << ","
        << FormatNumber(row.median_error) << "," << FormatNumber(row.worst_error) << ","
        << FormatNumber(row.success_share) << "," << row.items << "," << FormatNumber(row.noise)
        << "," << (row.noise > 0.0 ? "ratio" : "L") << ","
        << (row.optimum_share >= 0.0 ? FormatNumber(row.optimum_share) : "") << "\n";
  }
  return csv.str();
}

namespace {

// Plot geometry, in SVG units.
constexpr double kPanelLeft = 80.0, kPanelTop = 50.0, kPanelWidth = 330.0, kPanelHeight = 300.0;
constexpr double kPanelGap = 70.0;

const char* PathColor(const std::string& path) {
  static const std::map<std::string, const char*> colors = {{"planar exact", "#1f77b4"},
                                                            {"planar least squares", "#1f77b4"},
                                                            {"spatial exact", "#d62728"},
                                                            {"spatial least squares", "#d62728"},
                                                            {"spherical exact", "#ff7f0e"},
                                                            {"spherical least squares", "#ff7f0e"},
                                                            {"path exact", "#2ca02c"},
                                                            {"path least squares", "#2ca02c"},
                                                            {"path free timing", "#9467bd"},
                                                            {"function exact", "#8c564b"},
                                                            {"function least squares", "#8c564b"}};
  const auto found = colors.find(path);
  return found == colors.end() ? "#555555" : found->second;
}

// A marker per effort level: diamond (exact), circle (fast), square (balanced), triangle
// (thorough).
std::string Marker(const std::string& effort, double x, double y, const char* color) {
  char text[400];
  if (effort == "fast") {
    std::snprintf(text, sizeof(text), "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>", x, y,
                  color);
  } else if (effort == "balanced") {
    std::snprintf(text, sizeof(text),
                  "<rect x=\"%.1f\" y=\"%.1f\" width=\"8\" height=\"8\" fill=\"%s\"/>", x - 4,
                  y - 4, color);
  } else if (effort == "thorough") {
    std::snprintf(text, sizeof(text),
                  "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"%s\"/>", x, y - 5,
                  x - 5, y + 4, x + 5, y + 4, color);
  } else {
    std::snprintf(text, sizeof(text),
                  "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"white\" "
                  "stroke=\"%s\" stroke-width=\"2\"/>",
                  x, y - 6, x + 5, y, x, y + 6, x - 5, y, color);
  }
  return text;
}

std::string TimeLabel(int decade) {
  static const char* labels[] = {"1 µs",  "10 µs", "0.1 ms", "1 ms", "10 ms",
                                 "0.1 s", "1 s",   "10 s",   "100 s"};
  const int index = decade + 3;  // decade of milliseconds: -3 is 1 µs
  return index >= 0 && index < 9 ? labels[index] : "1e" + std::to_string(decade) + " ms";
}

std::string PowerLabel(int decade) {
  if (decade == 0) return "1";
  if (decade == 1) return "10";
  return "1e" + std::to_string(decade);
}

}  // namespace

std::string TradeSvg(const std::vector<TradeRow>& rows) {
  const double noises[] = {0.0, 1e-3, 1e-2};
  // The time axis is shared: whole decades around every median time.
  double low_time = kInfinity, high_time = 0.0;
  for (const TradeRow& row : rows) {
    if (row.median_ms > 0.0) {
      low_time = std::min(low_time, row.median_ms);
      high_time = std::max(high_time, row.median_ms);
    }
  }
  if (!(low_time < kInfinity)) low_time = high_time = 1.0;
  const int x_low = static_cast<int>(std::floor(std::log10(low_time)));
  const int x_high = std::max(x_low + 1, static_cast<int>(std::ceil(std::log10(high_time))));
  const double width = 2 * kPanelLeft + 3 * kPanelWidth + 2 * kPanelGap;
  const double height = kPanelTop + kPanelHeight + 150.0;
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << " " << height
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (int panel = 0; panel < 3; ++panel) {
    const double noise = noises[panel];
    const double left = kPanelLeft + panel * (kPanelWidth + kPanelGap);
    const double top = kPanelTop;
    // Error axis: exact data in L from 1e-17; noisy data as a ratio from 0.1. Values beyond
    // the axis are drawn on its edge.
    double high_error = noise == 0.0 ? 1e-3 : 10.0;
    for (const TradeRow& row : rows) {
      if (row.noise == noise && std::isfinite(row.median_error)) {
        high_error = std::max(high_error, row.median_error);
      }
    }
    const int y_low = noise == 0.0 ? -17 : -1;
    const int y_high = static_cast<int>(std::ceil(std::log10(high_error)));
    auto to_x = [&](double ms) {
      const double t = (std::log10(std::max(ms, 1e-9)) - x_low) / (x_high - x_low);
      return left + kPanelWidth * std::clamp(t, 0.0, 1.0);
    };
    auto to_y = [&](double error) {
      const double e = std::isnan(error) ? y_high : std::log10(std::max(error, 1e-300));
      const double t = (e - y_low) / (y_high - y_low);
      return top + kPanelHeight * (1.0 - std::clamp(t, 0.0, 1.0));
    };
    svg << "<text x=\"" << left + kPanelWidth / 2 << "\" y=\"" << top - 18
        << "\" text-anchor=\"middle\" font-weight=\"bold\">"
        << (noise == 0.0    ? "exact data"
            : noise == 1e-3 ? "noise 1e-3 L"
                            : "noise 1e-2 L")
        << "</text>\n";
    svg << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << kPanelWidth
        << "\" height=\"" << kPanelHeight << "\" fill=\"none\" stroke=\"#333\"/>\n";
    for (int decade = x_low; decade <= x_high; ++decade) {
      const double x = to_x(std::pow(10.0, decade));
      svg << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\""
          << top + kPanelHeight << "\" stroke=\"#ddd\"/>\n"
          << "<text x=\"" << x << "\" y=\"" << top + kPanelHeight + 16
          << "\" text-anchor=\"middle\" font-size=\"10\">" << TimeLabel(decade) << "</text>\n";
    }
    const int y_step = noise == 0.0 ? 2 : 1;
    for (int decade = y_low; decade <= y_high; decade += y_step) {
      const double y = to_y(std::pow(10.0, decade));
      svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + kPanelWidth
          << "\" y2=\"" << y << "\" stroke=\"#ddd\"/>\n"
          << "<text x=\"" << left - 6 << "\" y=\"" << y + 4
          << "\" text-anchor=\"end\" font-size=\"10\">" << PowerLabel(decade) << "</text>\n";
    }
    // The success threshold.
    const double threshold = noise == 0.0 ? kExactTolerance : kNoisyRatio;
    svg << "<line x1=\"" << left << "\" y1=\"" << to_y(threshold) << "\" x2=\""
        << left + kPanelWidth << "\" y2=\"" << to_y(threshold)
        << "\" stroke=\"#888\" stroke-dasharray=\"4,3\"/>\n";
    svg << "<text x=\"" << left + kPanelWidth / 2 << "\" y=\"" << top + kPanelHeight + 34
        << "\" text-anchor=\"middle\">median time per task (log)</text>\n";
    svg << "<text transform=\"translate(" << left - 48 << "," << top + kPanelHeight / 2
        << ") rotate(-90)\" text-anchor=\"middle\">"
        << (noise == 0.0 ? "median final error / L (log)"
                         : "median final error / generating mechanism's (log)")
        << "</text>\n";
    // One curve per solver path and task size, through its effort levels.
    std::map<std::pair<std::string, int>, std::vector<const TradeRow*>> curves;
    for (const TradeRow& row : rows) {
      if (row.noise == noise) curves[{row.path, row.items}].push_back(&row);
    }
    for (const auto& [key, points] : curves) {
      const char* color = PathColor(key.first);
      std::ostringstream polyline;
      for (const TradeRow* row : points) {
        polyline << to_x(row->median_ms) << "," << to_y(row->median_error) << " ";
      }
      svg << "<polyline points=\"" << polyline.str() << "\" fill=\"none\" stroke=\"" << color
          << "\" stroke-width=\"1.5\" opacity=\"0.8\"/>\n";
      for (const TradeRow* row : points) {
        svg << Marker(row->effort, to_x(row->median_ms), to_y(row->median_error), color) << "\n";
      }
      const TradeRow* last = points.back();
      svg << "<text x=\"" << to_x(last->median_ms) + 7 << "\" y=\"" << to_y(last->median_error) - 5
          << "\" font-size=\"9\" fill=\"" << color << "\">" << key.second << "</text>\n";
    }
  }
  // Legend: colour = solver path, marker = effort level, number = poses or points per task.
  double y = kPanelTop + kPanelHeight + 62;
  const std::pair<const char*, const char*> paths[] = {
      {"planar motion", "planar exact"},         {"spatial motion", "spatial exact"},
      {"spherical motion", "spherical exact"},   {"timed path", "path exact"},
      {"path, free timing", "path free timing"}, {"function", "function exact"}};
  // An entry for each family the table has.
  const auto in_table = [&](const std::string& color) {
    return std::any_of(rows.begin(), rows.end(),
                       [&](const TradeRow& row) { return PathColor(row.path) == color; });
  };
  double x = kPanelLeft;
  for (const auto& [label, path] : paths) {
    const char* color = PathColor(path);
    if (!in_table(color)) continue;
    svg << "<line x1=\"" << x << "\" y1=\"" << y - 4 << "\" x2=\"" << x + 20 << "\" y2=\"" << y - 4
        << "\" stroke=\"" << color << "\" stroke-width=\"3\"/>\n"
        << "<text x=\"" << x + 26 << "\" y=\"" << y << "\">" << label << "</text>\n";
    x += 180;
  }
  y += 24;
  x = kPanelLeft;
  for (const char* effort : {"exact", "fast", "balanced", "thorough"}) {
    svg << Marker(effort, x + 6, y - 4, "#333") << "\n"
        << "<text x=\"" << x + 16 << "\" y=\"" << y << "\">" << effort << "</text>\n";
    x += 100;
  }
  svg << "<text x=\"" << x + 20 << "\" y=\"" << y
      << "\">numbers: poses or points per task; dashed: success threshold</text>\n";
  y += 24;
  svg << "<text x=\"" << kPanelLeft << "\" y=\"" << y << "\" font-size=\"10\" fill=\"#555\">"
      << "Error: exact data in L (best four-bar's pose or point error; spatial: generating dyads' "
         "nearest match); noisy data divided by the generating mechanism's own error. Values "
         "beyond an axis are drawn on its edge.</text>\n";
  y += 14;
  svg << "<text x=\"" << kPanelLeft << "\" y=\"" << y << "\" font-size=\"10\" fill=\"#555\">"
      << "Noise: sigma / L (positions, and L times the angles); spherical motion and function "
         "generation: sigma in radians (orientations, output angles).</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

int RunBench(const BenchOptions& options) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(options.output_dir, error);
  if (!fs::is_directory(options.output_dir)) {
    throw OutputError("-o " + options.output_dir + ": cannot create the output directory" +
                      (error ? " (" + error.message() + ")" : std::string()));
  }
  // Every table of the run is prepared first and written at the end (apps/output_file.h).
  OutputSet outputs;
  const auto add = [&](const std::string& name) -> OutputFile& {
    return outputs.Add((fs::path(options.output_dir) / name).string(), "-o");
  };
  OutputFile* trade_csv = options.trade ? &add("trade.csv") : nullptr;
  OutputFile* trade_svg = options.trade ? &add("trade.svg") : nullptr;
  OutputFile* extremes_csv = options.extremes ? &add("extremes.csv") : nullptr;
  OutputFile* constrained_csv = options.constrained ? &add("constrained.csv") : nullptr;
  if (options.trade) {
    const std::vector<TradeRow> rows = RunTradeBench(options, stdout);
    trade_csv->Write(TradeCsv(rows));
    trade_svg->Write(TradeSvg(rows));
  }
  if (options.extremes) extremes_csv->Write(ExtremesCsv(RunExtremesBench(options, stdout)));
  if (options.constrained) {
    constrained_csv->Write(ConstrainedCsv(RunConstrainedBench(options, stdout)));
  }
  outputs.CommitAll();
  for (const OutputFile* file : {trade_csv, trade_svg, extremes_csv, constrained_csv}) {
    if (file != nullptr) std::printf("written to %s\n", file->path().c_str());
  }
  return 0;
}

}  // namespace linkfit
