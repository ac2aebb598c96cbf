// Path problems (timed points) end to end: see task_solver.h.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "fitting/model_choice.h"
#include "fitting/nine_point_path.h"
#include "fitting/planar_motion.h"
#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "lib/golden_section.h"
#include "lib/mechanism.h"
#include "lib/parallel.h"
#include "lib/path_motion.h"
#include "lib/precision.h"
#include "lib/result_io.h"
#include "optimizers/coupler_atlas.h"
#include "optimizers/path_search.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Two reported four-bars closer than this (relative to L, every pivot, the coupler point and
// the crank length) are one.
constexpr double kSameFourBar = 1e-4;
// Prescribed timing with design constraints: this many times path_refined seed four-bars are
// refined. Measured on the 120 timed-path tasks of `linkfit bench`'s constrained families
// (2026-11-24): 12 instead of 6 refined seeds reach the best keeper known in 4 more tasks at
// balanced (2-10 ms more), and in 2 others add a poorly fitting defect-free keeper that the
// ranking puts before a close-fitting one with a transmission defect.
constexpr int kConstrainedSeedsFactor = 2;
// Free timing: the spans of the evenly spaced timing guesses, as fractions of a turn (the
// first is a closed curve: n points over (n - 1) / n of a turn).
constexpr double kGuessSpans[] = {-1.0, 0.75, 0.5, 0.25};
// Free timing on more points than this: the search runs on this many points spread along the
// path, and the first kScreenRefined four-bars it finds are refined on every point
// (SolveFreeTimingScreened). The search is tens of refinements, each linear in the points: 200
// points took 10 s, 2000 minutes; the trade benchmark's untimed paths have 10 and 20 points.
constexpr size_t kFreeTimingScreenPoints = 120;
constexpr int kScreenRefined = 3;
// The iterations of that refinement with the angles free, from the screened optimum.
constexpr int kScreenFreeIterations = 100;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Free timing: seed four-bars refined per timing guess.
constexpr int kFreeTimingStarts = 1;
// Free timing: five-point subsets solved per timing guess.
constexpr int kFreeTimingSubsets = 2;
// Free timing: crank samples per turn of the timing projection, and the rounds of
// refinement under a fixed timing and projection before the angles are freed.
constexpr int kProjectionSamples = 180;
constexpr int kAlternations = 3;
// Rounds of the solver's joint free-timing refinement (RefineFreeTiming) while each lowers the
// cost by a thousandth.
constexpr int kRefineRounds = 4;
// A refine's solves at most, each from where the last stopped while it gains (SolveAgain,
// refiner_summary.h): of the refiner's iterations each under a prescribed timing, of
// kFreeTimingIterations under free timing.
constexpr int kRefineSolves = 50;
// Free timing: Levenberg-Marquardt iterations of the final solve with the angles free (it
// converges slowly near the end; the other solves keep the refiner's default).
constexpr int kFreeTimingIterations = 400;
// The listed four-bars' refinement (Finish) goes on, in kPolishRounds at most, while a round
// gains (AnotherRound, refiner_summary.h): `linkfit refine` then improves no listed four-bar by
// more than 1 % (issue 35).
constexpr int kPolishRounds = 20;
// A design whose dyads miss its stored joints by more than this (times L) is re-expressed in its
// first configuration (Report).
constexpr double kJointClosureTolerance = 1e-6;
// Free timing: a near miss, a four-bar that misses the points by at most this many times their
// tolerance (PassTolerance): refined, it may pass them.
constexpr double kNearMiss = 10.0;
// Free timing, balanced: the other nine points are solved when the best refined four-bar
// misses the points by at most this many tolerances: data as precise as they say, the
// refinement stopped short. Measured (2026-11-24): ill-conditioned curves of exact data stop
// 20-90 tolerances off, four-digit data 1.5; noise of 1e-3 L on data given as exact misses by
// 1e5 tolerances and more (both sets' curves move alike; thorough solves both).
constexpr double kSecondNineMiss = 1000.0;
// Free timing, balanced: two stages' best four-bars whose coupler curves are this close (times
// L; CurveDistance) came to one curve.
constexpr double kStagesAgree = 1e-3;
// Free timing from nine points or more (balanced and thorough): the four-bars through nine of
// the points (fitting/nine_point_path.h) with the smallest error on all of them, refined; and
// near misses beyond them, up to kNinePointNearMax in all.
constexpr int kNinePointRefined = 8;
constexpr int kNinePointNearMax = 32;

// Free timing: atlas candidates (optimizers/coupler_atlas.h) refined per effort (fast lists
// them unrefined; balanced refines thorough's further ones when its own do not find the curve;
// with constraints, as many again that keep them), and a curve whose last point is within this
// many median steps of its first is matched as closed as well as open.
// Free timing, balanced: the subset seeds refined when neither the atlas nor the nine-point
// solve has found the curve, those of smallest RMS point error at their timing guess (thorough
// refines all: 8 per span and direction pair, 32 for an arc). Measured on the curves benchmark
// (2026-11-28): see README, "Path synthesis from target curves".
constexpr int kSubsetRefinedBalanced = 8;
constexpr int kAtlasFast = 3;
constexpr int kAtlasBalanced = 6;
constexpr int kAtlasThorough = 16;
constexpr double kNearlyClosedSteps = 2.5;

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The task's data as the path solvers take them.
struct PathData {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> angles;  // prescribed input angles (empty for free timing)
  std::vector<double> weights;
  std::vector<bool> exact;
  double length = 1.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // of the points
  bool closed = false;            // the crank makes a whole turn from the first point back to it
  DataPrecision precision;        // the task's
  DesignConstraints constraints;  // the task's
};

PathData Data(const Task& task) {
  PathData data;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const TimedPoint& point : task.points) {
    data.points.push_back(point.point_in_fixed);
    if (point.input_angle) data.angles.push_back(*point.input_angle);
    data.weights.push_back(point.weight);
    data.exact.push_back(point.exact);
    centroid += point.point_in_fixed / static_cast<double>(task.points.size());
  }
  data.centroid = centroid;
  double sum = 0.0;
  for (const Eigen::Vector2d& point : data.points) sum += (point - centroid).squaredNorm();
  data.length = task.scale ? *task.scale : std::sqrt(sum / static_cast<double>(task.points.size()));
  if (!(data.length > 0.0)) data.length = 1.0;
  data.closed = task.closed;
  data.precision = task.precision;
  data.constraints = task.constraints;
  return data;
}

// What a path result says of its task (precision, closed, constraints, scale, timing); returns
// whether the timing is free.
bool StartResult(const Task& task, const PathData& data, PathResult* result) {
  result->precision = task.precision;
  result->closed = task.closed;
  result->constraints = task.constraints;
  result->scale = data.length;
  const bool free_timing = data.angles.size() != data.points.size();
  result->timing = free_timing ? "free" : "prescribed";
  return free_timing;
}

// `design` with its RR radii its joints' distances, as a result file read back gives them.
PathFourBar WithJointRadii(PathFourBar design) {
  for (PlanarDyad* dyad : {&design.input, &design.output}) {
    if (dyad->type == DyadType::kRR) dyad->radius = (dyad->moving_pivot - dyad->fixed_pivot).norm();
  }
  return design;
}

PathMechanismReport Report(const PathFourBar& design, const PathData& data,
                           const std::vector<double>& angles) {
  PathMechanismReport report;
  report.type = ClassifyFourBar(design.input.type, design.output.type);
  PathAnalysisOptions options;
  options.transmission_samples = kPathTransmissionSamples;
  options.closed = data.closed;
  // The design as the result writes it and a result file reads it back, so that the joints the
  // result gives make the four-bar analysed and `linkfit refine` starts from that very design:
  // its radii its joints' distances, and, where its dyads do not close at its stored joints (a
  // search's design, whose radius is its own parameter), first re-expressed in the configuration
  // it is driven from (only beyond rounding: near a stationary configuration at the first point,
  // moving a design that closes to 1e-9 L can pick the other assembly).
  const PlanarPose joints;  // E = Sigma: the stored joints
  const bool closes = design.input.Residual(joints) <= kJointClosureTolerance * data.length &&
                      design.output.Residual(joints) <= kJointClosureTolerance * data.length;
  report.design = WithJointRadii(design);
  if (!closes) {
    // Where it does not even assemble at the first point, it is reported as it is (its radii
    // from its joints would make another four-bar).
    const PathFourBarAnalysis given =
        AnalyzePathFourBar(design, data.points, angles, data.length, options);
    report.design =
        given.configurations.empty()
            ? design
            : WithJointRadii(MoveToFirstConfiguration(design, given.configurations.front()));
  }
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(report.design, data.points, angles, data.length, options);
  report.max_point_error = analysis.max_point_error;
  report.rms_point_error = analysis.rms_point_error;
  if (std::find(data.exact.begin(), data.exact.end(), true) != data.exact.end()) {
    if (analysis.point_errors.size() == data.points.size()) {
      double worst = 0.0;
      for (size_t j = 0; j < data.points.size(); ++j) {
        if (data.exact[j]) worst = std::max(worst, analysis.point_errors[j]);
      }
      report.exact_point_error = worst;
    }
    report.misses_exact = !(report.exact_point_error &&
                            *report.exact_point_error <= kExactPoseTolerance * data.length);
  }
  report.error_note = analysis.error_note;
  report.defects = analysis.defects;
  report.input_rotates_fully = analysis.input_rotates_fully;
  report.transmission_min_deg = analysis.transmission_min_deg;
  report.transmission_max_deg = analysis.transmission_max_deg;
  if (report.type == FourBarType::k4R) {
    report.grashof = GrashofType(report.design.input, report.design.output, data.length);
  }
  FourBarClass kind;
  kind.type = report.type;
  kind.grashof = report.grashof;
  kind.input_rotates_fully = report.input_rotates_fully;
  report.violates = PathViolations(data.constraints, report.design, kind, data.length);
  return report;
}

// The defect "transmission" (JudgeTransmission), given at the end: the solver's own choices go
// by the kinematic defects. With it, those of minimal data (issue 35, as planar JudgeMechanism):
// "degenerate" when a link is no longer than the data's precision can resolve (the four-bar's
// error bound and kModelUnits of the rounding), and "misses" when an exact four-bar of five
// timed points (not refined) misses one by more than PassTolerance, with no kinematic defect to
// say why.
void JudgeTransmission(const PathData& data, PathMechanismReport* report) {
  std::vector<std::string>& defects = report->defects;
  const double bound =
      report->error_bound && std::isfinite(*report->error_bound) ? *report->error_bound : 0.0;
  const double resolve = bound + kModelUnits * data.precision.length;
  for (const double link : PathFourBarLinks(report->design).All()) {
    if (link <= resolve) AddDefect("degenerate", &defects);
  }
  if (data.points.size() == 5 && data.angles.size() == 5 && !report->seed_max_point_error) {
    JudgeMisses(report->max_point_error, PathPassTolerance(data.precision, data.length), &defects);
  }
  JudgeTransmission(data.constraints, report->transmission_min_deg, &report->defects);
}

// How far a four-bar may miss a point and still pass it within the data's precision:
// kModelUnits point uncertainties (PointUncertainty) of a point `reach` from the moving body's
// reference (an input angle's error moves the crank pin by alpha times the crank).
double PointTolerance(const PathData& data, double reach) {
  return kModelUnits * PointUncertainty(data.precision, reach, data.length, 2);
}

// The largest point error of a four-bar that passes the points: their precision's tolerance
// (PointTolerance at the crank's pivot), not below 1e-8 L.
double PassTolerance(const PathData& data) {
  return PathPassTolerance(data.precision, data.length);
}

// The ranking rule (lib/design_constraints.h RankOrder): keeping the constraints, defect-free,
// by error (RMS for least squares, the largest for exact synthesis; absent last), near ties by
// the worst transmission angle; `precision_fit`: PassTolerance.
RankKey PathRankKey(bool least_squares, double precision_fit, const DesignConstraints& constraints,
                    const PathMechanismReport& report) {
  RankKey key;
  key.within_precision = report.max_point_error && *report.max_point_error <= precision_fit;
  key.fit_floor = 1e-3 * precision_fit;
  key.parameters = FourBarParameters(report.type);
  key.misses_exact = report.misses_exact;
  key.fit = least_squares ? report.rms_point_error : report.max_point_error;
  if (!report.max_point_error) key.fit.reset();
  // Not driven through every point, it cannot pass them at all.
  JudgeWithDefaults(constraints, report.violates, report.defects,
                    report.max_point_error.has_value(), &key);
  key.transmission_min_deg = TransmissionTieBreak(constraints, report.transmission_min_deg);
  const PathFourBar& design = report.design;
  std::vector<Eigen::Vector2d> joints = {design.input.fixed_pivot, design.input.moving_pivot,
                                         design.coupler_point};
  if (design.output.type != DyadType::kPR) joints.push_back(design.output.fixed_pivot);
  if (design.output.type != DyadType::kRP) joints.push_back(design.output.moving_pivot);
  key.size = JointSpread(joints);
  return key;
}

// Ranks by PathRankKey (RankReports); with `bound` >= 0 a bounded list. Returns how many were
// dropped.
int Rank(bool least_squares, const PathData& data, int bound,
         std::vector<PathMechanismReport>* mechanisms) {
  const double precision_fit = PassTolerance(data);
  return RankReports(
      [&](const PathMechanismReport& report) {
        return PathRankKey(least_squares, precision_fit, data.constraints, report);
      },
      bound, mechanisms);
}

// The note of a ranked list whose first four-bar breaks a default the task did not give
// (DefaultsNote).
void NoteDefaults(bool least_squares, const PathData& data, PathResult* result) {
  std::vector<RankKey> keys;
  for (const PathMechanismReport& report : result->mechanisms) {
    keys.push_back(PathRankKey(least_squares, PassTolerance(data), data.constraints, report));
  }
  const std::string note =
      DefaultsNote(keys, least_squares ? "an RMS point error of" : "a largest point error of");
  if (!note.empty()) result->notes.push_back(note);
  if (!result->mechanisms.empty()) {
    const PathMechanismReport& first = result->mechanisms.front();
    const std::string given = GivenConstraintsNote(data.constraints, first.violates, first.defects);
    if (!given.empty()) result->notes.push_back(given);
  }
}

// Two four-bars are one when their crank, coupler point and output agree within kSameFourBar
// (relative to L, and to a point's distance from the origin beyond L): an RR output by its
// pivots, a PR by its moving pivot and line, an RP by its fixed pivot and line.
bool SameFourBar(const PathFourBar& a, const PathFourBar& b, double length,
                 const Eigen::Vector2d& centroid) {
  if (a.output.type != b.output.type) return false;
  const double tolerance = kSameFourBar * length;
  const auto near = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return (p - q).norm() <= tolerance * std::max(1.0, (p - centroid).norm() / length);
  };
  const DyadType type = a.output.type;
  if (!near(a.input.fixed_pivot, b.input.fixed_pivot) ||
      !near(a.input.moving_pivot, b.input.moving_pivot) ||
      !near(a.coupler_point, b.coupler_point)) {
    return false;
  }
  if (type != DyadType::kPR && !near(a.output.fixed_pivot, b.output.fixed_pivot)) return false;
  if (type != DyadType::kRP && !near(a.output.moving_pivot, b.output.moving_pivot)) return false;
  if (type == DyadType::kRR) return true;
  // A line: its foot from the points' centroid, and its direction (either sense).
  const Eigen::Vector2d u = a.output.line_direction.normalized();
  const Eigen::Vector2d v = b.output.line_direction.normalized();
  const auto foot = [&](const PlanarDyad& dyad, const Eigen::Vector2d& direction) {
    return Eigen::Vector2d(dyad.line_point +
                           (centroid - dyad.line_point).dot(direction) * direction);
  };
  return near(foot(a.output, u), foot(b.output, v)) &&
         std::abs(u.x() * v.y() - u.y() * v.x()) <= kSameFourBar;
}

// Adds `report` unless an equal four-bar is listed (then the better of the two stays: defect-free
// first, then by RMS error).
void AddDistinct(const PathMechanismReport& report, double length, const Eigen::Vector2d& centroid,
                 std::vector<PathMechanismReport>* reports) {
  for (PathMechanismReport& listed : *reports) {
    if (!SameFourBar(listed.design, report.design, length, centroid)) continue;
    const auto key = [](const PathMechanismReport& r) {
      return std::make_tuple(!r.defects.empty(),
                             r.rms_point_error.value_or(std::numeric_limits<double>::infinity()));
    };
    if (key(report) < key(listed)) listed = report;
    return;
  }
  reports->push_back(report);
}

// The four-bars of exact solves of spread five-point subsets under `angles`, each measured on
// every point; the `keep` best (RMS point error) that meet every point.
std::vector<PathMechanismReport> SubsetSeeds(const PathData& data,
                                             const std::vector<double>& angles, int subsets,
                                             int keep, const TimedPathOptions& options) {
  std::vector<PathMechanismReport> seeds;
  // The subsets' four-bars at rounding level (exact circles, as seeds for the refinement that
  // chooses the model at the data's precision) and, for coarser data, at the data's precision
  // too (four-bars meeting a subset within precision, which rounding level drops).
  std::vector<TimedPathOptions> levels = {options};
  levels.front().precision = DataPrecision();
  if (RelativePrecision(options.precision, data.length) > 1e-12) levels.push_back(options);
  const int count = static_cast<int>(data.points.size());
  // Subsets through the exact points (fitting/planar_motion.h SeedSubsets): their four-bars
  // meet them.
  for (const std::vector<int>& subset : SeedSubsets(count, subsets, data.exact)) {
    std::vector<Eigen::Vector2d> points;
    std::vector<double> subset_angles;
    for (int index : subset) {
      points.push_back(data.points[index]);
      subset_angles.push_back(angles[index]);
    }
    // One set of crank roots for both levels (they do not depend on the precision).
    std::vector<TimedCrank> cranks;
    if (SolveTimedCranks(points, subset_angles, options, &cranks) <= 0) continue;
    for (const TimedPathOptions& level : levels) {
      std::vector<PathFourBar> four_bars;
      TimedPathSummary summary;
      TimedPathFourBars(points, subset_angles, cranks, level, &four_bars, &summary);
      // At the data's precision also the four-bars of nearly real complex cranks (rounding can
      // turn the generating crank of a subset into a complex pair) and the slider readings
      // handed on for a joint fit: seeds like the others.
      four_bars.insert(four_bars.end(), summary.to_fit.begin(), summary.to_fit.end());
      for (const PathFourBar& four_bar : four_bars) {
        PathMechanismReport report = Report(four_bar, data, angles);
        if (report.rms_point_error) AddDistinct(report, data.length, data.centroid, &seeds);
      }
    }
  }
  Rank(true, data, -1, &seeds);
  if (static_cast<int>(seeds.size()) > keep) seeds.resize(keep);
  return seeds;
}

std::optional<double> BestMaxError(const std::vector<PathMechanismReport>& reports) {
  std::optional<double> best;
  for (const PathMechanismReport& report : reports) {
    if (report.max_point_error && (!best || *report.max_point_error < *best)) {
      best = report.max_point_error;
    }
  }
  return best;
}

// The smallest largest point error of a defect-free report: how near an answer came.
std::optional<double> BestDefectFreeMaxError(const std::vector<PathMechanismReport>& reports) {
  std::optional<double> best;
  for (const PathMechanismReport& report : reports) {
    if (!HasKinematicDefect(report.defects) && report.max_point_error &&
        (!best || *report.max_point_error < *best)) {
      best = report.max_point_error;
    }
  }
  return best;
}

// The defect-free report that keeps the task's constraints with the smallest RMS point error
// (null when there is none).
const PathMechanismReport* BestKeeper(const std::vector<PathMechanismReport>& reports) {
  const PathMechanismReport* best = nullptr;
  for (const PathMechanismReport& report : reports) {
    if (HasKinematicDefect(report.defects) || !report.violates.empty() || !report.rms_point_error ||
        report.input_angles.empty()) {
      continue;
    }
    if (!best || *report.rms_point_error < *best->rms_point_error) best = &report;
  }
  return best;
}

// Whether a four-bar's misses of the points look like noise in the points (true) rather than a
// coupler curve of another shape (false): a curve of another shape runs on one side of the
// points over whole stretches. The signs of the misses' components normal to the path (its
// direction at a point taken from the neighbouring points) are tested for too few runs (the
// Wald-Wolfowitz runs test, one-sided, kRunsSigmas standard deviations); points the curve passes
// within 1e-9 L are left out. Absent (undecided) with fewer than kRunsMinPoints signed misses.
constexpr double kRunsSigmas = 2.0;
constexpr int kRunsMinPoints = 40;
std::optional<bool> MissesLookLikeNoise(const PathMechanismReport& report, const PathData& data) {
  const size_t count = data.points.size();
  if (static_cast<int>(count) < kRunsMinPoints || report.input_angles.size() != count) return {};
  PathAnalysisOptions options;
  options.closed = data.closed;
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(report.design, data.points, report.input_angles, data.length, options);
  if (analysis.configurations.size() != count) return {};
  std::vector<int> signs;
  for (size_t j = 0; j < count; ++j) {
    const size_t before = j > 0 ? j - 1 : (data.closed ? count - 1 : 0);
    const size_t after = j + 1 < count ? j + 1 : (data.closed ? 0 : count - 1);
    const Eigen::Vector2d tangent = data.points[after] - data.points[before];
    if (!(tangent.norm() > 0.0)) continue;
    const Eigen::Vector2d normal(-tangent.y(), tangent.x());
    const Eigen::Vector2d miss =
        data.points[j] - analysis.configurations[j].ToFixed(report.design.coupler_point);
    if (miss.norm() <= 1e-9 * data.length) continue;
    signs.push_back(miss.dot(normal) >= 0.0 ? 1 : -1);
  }
  const double n = static_cast<double>(signs.size());
  if (static_cast<int>(signs.size()) < kRunsMinPoints) return {};
  const double plus = static_cast<double>(std::count(signs.begin(), signs.end(), 1));
  const double minus = n - plus;
  if (plus == 0.0 || minus == 0.0) return false;  // all on one side: a curve of another shape
  int runs = 1;
  for (size_t j = 1; j < signs.size(); ++j) runs += signs[j] != signs[j - 1] ? 1 : 0;
  const double mean = 1.0 + 2.0 * plus * minus / n;
  const double variance = 2.0 * plus * minus * (2.0 * plus * minus - n) / (n * n * (n - 1.0));
  return runs >= mean - kRunsSigmas * std::sqrt(std::max(0.0, variance));
}

StageReport Stage(const std::string& name, std::chrono::steady_clock::time_point start,
                  const std::vector<PathMechanismReport>& reports) {
  StageReport stage;
  stage.name = name;
  stage.seconds = Seconds(start);
  stage.best_max_point_error = BestMaxError(reports);
  return stage;
}

// `design` refined on the points under the prescribed timing, and its report; nothing when the
// refiner cannot take it. `converged`: whether the refinement ended on a tolerance.
std::optional<PathMechanismReport> RefinedReport(const PathData& data,
                                                 const PathRefinerOptions& options,
                                                 PathFourBar design, bool* converged = nullptr) {
  std::vector<double> angles = data.angles;
  try {
    const RefinerSummary summary = RefinePathFourBar(data.points, data.weights, data.exact,
                                                     data.length, false, &angles, &design, options);
    if (converged != nullptr) *converged = summary.converged;
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  return Report(design, data, data.angles);
}

// The model choice at the data's precision (fitting/model_choice.h) for a refined four-bar with
// an RR output: the slider reading of the output circle on the coupler's poses at the points,
// when it fits them within the poses' precision (TimedPathOptions::precision says how the
// coupler poses inherit the points'), refined as a four-bar of its own. It replaces the circle
// when its RMS point error is within kModelUnits point uncertainties (sqrt 2 delta) of the
// circle's: at the data's precision the points cannot tell the two apart.
bool SliderAtPrecision(const PathData& data, const PathRefinerOptions& options,
                       const PathMechanismReport& circle, PathMechanismReport* slider) {
  const PathFourBar& design = circle.design;
  if (design.output.type != DyadType::kRR || !circle.rms_point_error ||
      !(RelativePrecision(data.precision, data.length) > 1e-12)) {
    return false;
  }
  // The coupler's poses with both frames' origin at the points' centroid, as the five-point
  // solver takes them (TimedPathFourBars): a pose angle's uncertainty moves a coupler point by
  // its distance from E's origin, which E = Sigma at the first point would put wherever the
  // task's origin is (points 10^4 L from it made every output circle a slider that missed the
  // points by 25).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : data.points) {
    centroid += point / static_cast<double>(data.points.size());
  }
  Similarity2 to_centroid;
  to_centroid.translation = -centroid;
  PathFourBar centred;
  centred.input = TransformDyad(design.input, to_centroid, to_centroid);
  centred.output = TransformDyad(design.output, to_centroid, to_centroid);
  centred.coupler_point = design.coupler_point - centroid;
  std::vector<Eigen::Vector2d> centred_points;
  for (const Eigen::Vector2d& point : data.points) centred_points.push_back(point - centroid);
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(centred, centred_points, data.angles, data.length);
  if (analysis.configurations.size() != data.points.size()) return false;
  const double link = (design.coupler_point - design.input.moving_pivot).norm();
  if (!(link > 0.0)) return false;
  const DataPrecision poses = CouplerPosePrecision(data.precision, design.input.radius, link);
  PlanarDyad simpler;
  if (!SimplerModel(centred.output, analysis.configurations, poses, data.length, &simpler)) {
    return false;
  }
  PathFourBar candidate = design;
  candidate.output = TransformDyad(simpler, to_centroid.Inverse(), to_centroid.Inverse());
  const std::optional<PathMechanismReport> refined = RefinedReport(data, options, candidate);
  if (!refined) return false;
  PathMechanismReport report = *refined;
  if (!report.rms_point_error || report.defects.size() > circle.defects.size() ||
      !(*report.rms_point_error <= *circle.rms_point_error + PointTolerance(data, 0.0))) {
    return false;
  }
  report.seed_max_point_error = circle.seed_max_point_error;
  *slider = report;
  return true;
}

// Refines a report's four-bar on the points under the prescribed timing; the refined one
// replaces it when it meets the points better. Returns whether it did.
bool Polish(const PathData& data, const PathRefinerOptions& options, PathMechanismReport* report) {
  const std::optional<PathMechanismReport> polished = RefinedReport(data, options, report->design);
  if (!polished) return false;
  PathMechanismReport refined = *polished;
  if (!refined.max_point_error || refined.defects.size() > report->defects.size() ||
      !(*refined.max_point_error <
        report->max_point_error.value_or(std::numeric_limits<double>::infinity()))) {
    return false;
  }
  refined.seed_max_point_error = report->seed_max_point_error;
  *report = refined;
  return true;
}

// A four-bar the five-point solver handed on (TimedPathSummary::to_fit): crank and output fitted
// to the points together (least squares: 9 or 10 parameters on 10 coordinates). It is a
// four-bar the data describe when it then passes every point within kModelUnits point
// uncertainties: delta, and alpha times the crank's length (an input angle's error moves the
// crank pin that far), without defects.
bool FitToPoints(const PathData& data, const PathRefinerOptions& options, const PathFourBar& seed,
                 PathMechanismReport* fitted) {
  const std::optional<PathMechanismReport> refined = RefinedReport(data, options, seed);
  if (!refined) return false;
  const PathMechanismReport& report = *refined;
  if (!report.max_point_error || !report.defects.empty() ||
      !(*report.max_point_error <= PointTolerance(data, report.design.input.radius))) {
    return false;
  }
  *fitted = report;
  return true;
}

// Refines each report's four-bar under the prescribed timing, re-measured after; a circle output
// the points cannot tell from its slider at their precision becomes the slider
// (SliderAtPrecision). Returns how many did.
int RefineAll(const PathData& data, const PathRefinerOptions& options,
              std::vector<PathMechanismReport>* reports) {
  int simplified = 0;
  for (PathMechanismReport& report : *reports) {
    std::optional<PathMechanismReport> refined = RefinedReport(data, options, report.design);
    if (!refined) continue;  // a seed the refiner cannot take stays as it is
    refined->seed_max_point_error = report.max_point_error;
    report = *refined;
    PathMechanismReport slider;
    if (SliderAtPrecision(data, options, report, &slider)) {
      report = slider;
      ++simplified;
    }
  }
  return simplified;
}

bool Monotonic(const std::vector<double>& angles);  // below

// Fitted input angles as a result file gives them back (InputAngleAsWritten).
std::vector<double> AsWritten(std::vector<double> angles) {
  for (double& angle : angles) angle = InputAngleAsWritten(angle);
  return angles;
}

// The distinct candidates, judged (JudgeTransmission) and ranked; at most `reported` listed,
// with a note of how many more were dropped. Above fast, every listed four-bar is then refined
// as `linkfit refine` refines it (RefinePathDesign; issue 35: a designer who refines a listed
// four-bar finds it at its optimum already), taken where it lowers the RMS point error and is not
// worse by the ranking's rule (PathRankKey: a broken default orders near ties only) nor adds a
// kinematic defect, in rounds while each lowers it enough (kPolishRounds), and the list made
// distinct and ranked again: four-bars that refine to one optimum
// are listed once. Beyond kFreeTimingScreenPoints points, the first listed only.
void Finish(const Task& task, const PathData& data, const TaskSolverOptions& options, int reported,
            std::vector<PathMechanismReport> candidates, PathResult* result) {
  std::vector<PathMechanismReport> distinct;
  for (const PathMechanismReport& report : candidates)
    AddDistinct(report, data.length, data.centroid, &distinct);
  for (PathMechanismReport& report : distinct) JudgeTransmission(data, &report);
  // A bounded list (ListedWithinBound): the best ranked, and the best fit of each group.
  int dropped = Rank(true, data, reported, &distinct);
  // Only on the task's own points (not a screened subset's solve).
  if (task.effort != Effort::kFast && !distinct.empty() &&
      data.points.size() == task.points.size()) {
    const auto start = std::chrono::steady_clock::now();
    // Fitted angles as the result file gives them back, so that the refinement below starts
    // where `linkfit refine` starts from the file (a start near a stall can end apart from one
    // rounding away).
    for (PathMechanismReport& report : distinct) {
      if (report.input_angles.empty()) continue;
      report.input_angles = AsWritten(report.input_angles);
      const PathMechanismReport judged = Report(report.design, data, report.input_angles);
      report.max_point_error = judged.max_point_error;
      report.rms_point_error = judged.rms_point_error;
    }
    std::vector<PathMechanismReport> polished = distinct;
    // Beyond kFreeTimingScreenPoints (a long trace, each refinement costly), the first listed
    // only: the answer a designer reads first.
    const size_t polished_count =
        data.points.size() > kFreeTimingScreenPoints ? size_t{1} : distinct.size();
    ParallelFor(polished_count, ThreadCount(options.threads), [&](size_t k) {
      const PathMechanismReport& listed = distinct[k];
      // One that passes the points within their precision is at its optimum as far as they tell.
      if (!(listed.max_point_error.value_or(kInfinity) > PassTolerance(data))) return;
      // The refinement `linkfit refine` makes (RefinePathDesign: the four-bar with its timing,
      // free timing's fitted angles free too, and its fallbacks for designs far from their
      // optimum), in rounds while each gains.
      for (int round = 0; round < kPolishRounds; ++round) {
        const PathMechanismReport& from = polished[k];
        PathMechanismReport better;
        bool converged = true;
        try {
          const PathResult refined =
              RefinePathDesign(task, from.design, from.input_angles, options, &converged);
          if (refined.mechanisms.empty()) return;
          // Reported as the solver reports its own four-bars (judged below, with them).
          const PathMechanismReport& design = refined.mechanisms.front();
          if (from.input_angles.empty()) {
            better = Report(design.design, data, data.angles);
          } else {
            // Out of order only where the listed one was (an `order` defect it has already).
            if (!Monotonic(design.input_angles) && Monotonic(from.input_angles)) return;
            const std::vector<double> angles = AsWritten(design.input_angles);
            better = Report(design.design, data, angles);
            better.input_angles = angles;
          }
        } catch (const std::invalid_argument&) {
          return;  // not driven from its first angle: listed as it is
        }
        // Not worse by the ranking's rule (a default the task did not give orders near ties
        // only), and no new kinematic defect.
        const RankKey from_key = PathRankKey(true, PassTolerance(data), data.constraints, from);
        const RankKey key = PathRankKey(true, PassTolerance(data), data.constraints, better);
        const double before = from.rms_point_error.value_or(kInfinity);
        if (!better.max_point_error || WorseRanked(from_key, from.defects, key, better.defects) ||
            !(better.rms_point_error.value_or(kInfinity) < before)) {
          return;
        }
        better.seed_max_point_error =
            listed.seed_max_point_error ? listed.seed_max_point_error : listed.max_point_error;
        polished[k] = better;
        if (!AnotherRound(before, *better.rms_point_error, converged)) return;
      }
    });
    std::vector<PathMechanismReport> again;
    for (const PathMechanismReport& report : polished) {
      AddDistinct(report, data.length, data.centroid, &again);
    }
    for (PathMechanismReport& report : again) JudgeTransmission(data, &report);
    dropped += static_cast<int>(polished.size() - again.size());
    Rank(true, data, reported, &again);
    distinct = std::move(again);
    result->stages.push_back(Stage("refine the listed", start, distinct));
  }
  if (dropped > 0) result->notes.push_back(DroppedNote(dropped));
  result->mechanisms = std::move(distinct);
  NoteDefaults(true, data, result);
}

void SolvePrescribed(const Task& task, const PathData& data, const TaskSolverOptions& options,
                     PathResult* result) {
  const auto stage_start = std::chrono::steady_clock::now();
  // With constraints, more seeds go on: where every seed breaks a bound, how well a seed fits
  // says little about where its refinement onto the bound ends.
  const int refined = task.constraints.given ? kConstrainedSeedsFactor * options.path_refined
                                             : options.path_refined;
  std::vector<PathMechanismReport> candidates =
      SubsetSeeds(data, data.angles, options.path_seed_subsets, refined, options.timed_path);
  result->stages.push_back(Stage("seed", stage_start, candidates));
  if (task.effort != Effort::kFast) {
    const auto refine_start = std::chrono::steady_clock::now();
    // The refined four-bars join the seeds rather than replace them: fast's four-bars stay
    // candidates (a refinement can end worse, on a defect).
    std::vector<PathMechanismReport> refined = candidates;
    const int simplified = RefineAll(data, options.path_refiner, &refined);
    if (simplified > 0) {
      result->notes.push_back(std::to_string(simplified) +
                              " refined output circle(s) reported as sliders: at the data's "
                              "precision the points cannot tell them from their slider readings");
    }
    candidates.insert(candidates.end(), refined.begin(), refined.end());
    // With constraints, a refined four-bar that keeps them but whose transmission angle is a
    // defect is refined again holding it (PathRefinerOptions::min_transmission_deg): the fit's
    // constrained optimum often lies where the transmission angle fails. Listed beside it.
    if (task.constraints.given) {
      PathRefinerOptions held = options.path_refiner;
      held.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
      for (const PathMechanismReport& report : refined) {
        if (!report.violates.empty() || !report.max_point_error ||
            HasKinematicDefect(report.defects) || !report.transmission_min_deg ||
            *report.transmission_min_deg >= *held.min_transmission_deg) {
          continue;
        }
        std::optional<PathMechanismReport> holding = RefinedReport(data, held, report.design);
        if (holding && holding->violates.empty() && holding->transmission_min_deg &&
            *holding->transmission_min_deg >= *held.min_transmission_deg) {
          holding->seed_max_point_error = report.max_point_error;
          candidates.push_back(*holding);
        }
      }
    }
    result->stages.push_back(Stage("refine", refine_start, candidates));
  }
  // The search: thorough always; balanced too when the task has constraints (as for planar
  // motion): an optimum on a bound is often in a basin no seed reaches, and how well a refined
  // keeper fits says little about whether a better one lies elsewhere.
  const bool constrained = task.constraints.given && task.effort == Effort::kBalanced;
  if (task.effort == Effort::kThorough || constrained) {
    const auto search_start = std::chrono::steady_clock::now();
    std::vector<PathFourBar> found;
    PathSearchOptions search = options.path_search;
    search.refiner = options.path_refiner;
    // With constraints, twice the runs (sharing the budget) and twice the basins refined: the
    // constrained optimum often lies in a basin one run's archive passes over.
    if (task.constraints.given) {
      search.runs *= kConstrainedSeedsFactor;
      search.refine_count *= kConstrainedSeedsFactor;
    }
    SearchPathFourBars(data.points, data.weights, data.exact, data.angles, data.length, search,
                       &found);
    std::vector<PathMechanismReport> searched;
    for (const PathFourBar& four_bar : found)
      searched.push_back(Report(four_bar, data, data.angles));
    result->stages.push_back(Stage("search", search_start, searched));
    candidates.insert(candidates.end(), searched.begin(), searched.end());
  }
  Finish(task, data, options, options.path_reported, candidates, result);
}

// A four-bar's coupler point over one turn of its crank from the first point's angle, on the
// first point's assembly: every 1/kProjectionSamples turn, and anywhere on demand.
class CouplerTurn {
 public:
  // False when the four-bar does not assemble at the first point.
  bool Sample(const PathFourBar& four_bar, double length) {
    four_bar_ = &four_bar;
    alpha0_ = FirstCrankAngle(four_bar);
    tolerance_ = 1e-9 * length;
    std::vector<PlanarPose> first;
    const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha0_, tolerance_, &first);
    if (count == 0) return false;
    label_ = count == 2 && PoseError(first[1], PlanarPose(), length) <
                               PoseError(first[0], PlanarPose(), length)
                 ? 1
                 : 0;
    curve_.assign(kProjectionSamples, Eigen::Vector2d::Zero());
    assembled_.assign(kProjectionSamples, false);
    for (int k = 0; k < kProjectionSamples; ++k) {
      assembled_[k] = At(k * Step(), &curve_[k]);
    }
    return true;
  }
  static double Step() { return 2.0 * kPi / kProjectionSamples; }
  // The sample `k` steps from the first point's angle in `direction` (1 <= k < samples);
  // false where the four-bar does not assemble.
  bool Sampled(int k, double direction, Eigen::Vector2d* point) const {
    const int index = direction > 0.0 ? k : kProjectionSamples - k;
    *point = curve_[index];
    return assembled_[index];
  }
  // The coupler point at crank offset t from the first point's angle; false where the
  // four-bar does not assemble.
  bool At(double t, Eigen::Vector2d* point) const {
    const int here =
        AssembleFourBar(four_bar_->input, four_bar_->output, alpha0_ + t, tolerance_, &poses_);
    if (here == 0) return false;
    *point = poses_[std::min(label_, here - 1)].ToFixed(four_bar_->coupler_point);
    return true;
  }

 private:
  const PathFourBar* four_bar_ = nullptr;
  double alpha0_ = 0.0, tolerance_ = 0.0;
  int label_ = 0;
  std::vector<Eigen::Vector2d> curve_;  // at alpha0 + k * Step(), k < kProjectionSamples
  std::vector<bool> assembled_;
  mutable std::vector<PlanarPose> poses_;  // scratch
};

// The timing a four-bar gives the points: for each point the crank angle (relative to the first
// point's, on the first point's assembly) at which the coupler point passes nearest, sampled
// every 1/kProjectionSamples turn (`turn`) and refined by golden-section search over a sample
// step, turning in `direction`.
std::vector<double> ProjectTiming(const CouplerTurn& turn, const PathData& data, double direction) {
  std::vector<double> angles = {0.0};
  for (size_t j = 1; j < data.points.size(); ++j) {
    // The squared distance of point j from the coupler point at crank offset t (infinity where
    // the four-bar does not assemble).
    const auto distance = [&](double t) {
      Eigen::Vector2d point;
      return turn.At(direction * t, &point) ? (point - data.points[j]).squaredNorm()
                                            : std::numeric_limits<double>::infinity();
    };
    int nearest = -1;
    double least = 0.0;
    for (int k = 1; k < kProjectionSamples; ++k) {
      Eigen::Vector2d point;
      if (!turn.Sampled(k, direction, &point)) continue;
      const double squared = (point - data.points[j]).squaredNorm();
      if (nearest < 0 || squared < least) {
        nearest = k;
        least = squared;
      }
    }
    if (nearest < 0) return {};
    // Golden section over [nearest - 1, nearest + 1] steps.
    constexpr int kShrinks = 30;
    const double step = CouplerTurn::Step();
    const GoldenSection search =
        GoldenSectionSearch(distance, (nearest - 1) * step, (nearest + 1) * step, kShrinks);
    angles.push_back(direction * 0.5 * (search.low + search.high));
  }
  return angles;
}

// ProjectTiming of a four-bar; nothing when it does not assemble at the first point or no
// sample of its turn does.
std::optional<std::vector<double>> ProjectTiming(const PathFourBar& four_bar, const PathData& data,
                                                 double direction) {
  CouplerTurn turn;
  if (!turn.Sample(four_bar, data.length)) return std::nullopt;
  std::vector<double> angles = ProjectTiming(turn, data, direction);
  if (angles.empty()) return std::nullopt;
  return angles;
}

bool Monotonic(const std::vector<double>& angles) {
  const double direction = angles.back() >= angles.front() ? 1.0 : -1.0;
  for (size_t j = 1; j < angles.size(); ++j) {
    if (direction * (angles[j] - angles[j - 1]) < 0.0) return false;
  }
  return true;
}

// The indices of a longest run (a subsequence) of `offsets` that never decreases, `offsets[0]`
// (the smallest) first: patience sorting, O(n log n).
std::vector<size_t> LongestInOrder(const std::vector<double>& offsets) {
  std::vector<size_t> tails;  // tails[k]: the last index of the best run of k + 1
  std::vector<size_t> before(offsets.size(), 0);  // each index's predecessor in its run
  for (size_t j = 0; j < offsets.size(); ++j) {
    const auto at = std::upper_bound(tails.begin(), tails.end(), offsets[j],
                                     [&](double value, size_t k) { return value < offsets[k]; });
    if (at != tails.begin()) before[j] = *(at - 1);
    if (at == tails.end()) {
      tails.push_back(j);
    } else {
      *at = j;
    }
  }
  std::vector<size_t> run;
  if (tails.empty()) return run;
  for (size_t j = tails.back(), k = tails.size(); k > 0; --k, j = before[j]) run.push_back(j);
  std::reverse(run.begin(), run.end());
  return run;
}

// The data's noise as an order judgement sees it (MonotonicWithinNoise): a four-bar's errors at
// the points, the noise's width between two points (at least twice the fit's RMS error: one
// point's small error says little about its neighbour's) and the points' precision
// (PassTolerance).
struct OrderNoise {
  const std::vector<double>& errors;
  double width = 0.0;
  double tolerance = 0.0;
  double length = 1.0;
  // Points j and k closer to each other than twice the noise between them (their errors, at
  // least the width) and the precision, the errors within kNoiseResidualCap L: noise may swap
  // them.
  bool Swapped(const PathData& data, size_t j, size_t k) const {
    const double noise = errors[j] + errors[k];
    return noise <= kNoiseResidualCap * length &&
           (data.points[j] - data.points[k]).norm() <= 2.0 * (std::max(noise, width) + tolerance);
  }
};

// Free timing, the second look of MonotonicWithinNoise: where the coupler curve passes close to
// itself, a point's nearest crank angle can fall on the other stretch, a large step back or
// ahead that no neighbour's nearness excuses. The longest in-order run of the projected offsets
// stays; every other point is timed anew between its in-order neighbours' offsets (the window),
// and is the data's noise when
//   - it misses the coupler curve there by at most its own error plus the noise's width and the
//     precision, timed at its nearest crank angle in the window; or
//   - its own offset lies beyond the window's end, and it and the point at that end are
//     swapped by the noise (OrderNoise::Swapped, as MonotonicWithinNoise's first look has it).
//     It is timed at that end.
// Returns false, leaving `angles`, when some point is further off than that on the in-order
// stretch: an order the crank would have to go back for.
bool RetimeOutOfOrder(const PathFourBar& design, const PathData& data, const OrderNoise& noise,
                      std::vector<double>* angles) {
  if (!(noise.width <= kNoiseResidualCap * data.length)) return false;  // too poor a fit to judge
  CouplerTurn turn;
  if (!turn.Sample(design, data.length)) return false;
  const double direction = angles->back() >= angles->front() ? 1.0 : -1.0;
  const size_t count = angles->size();
  std::vector<double> offsets(count);  // crank offsets from the first point's, turning ahead
  for (size_t j = 0; j < count; ++j)
    offsets[j] = std::max(0.0, direction * ((*angles)[j] - (*angles)[0]));
  std::vector<bool> kept(count, false);
  for (const size_t j : LongestInOrder(offsets)) kept[j] = true;
  kept[0] = true;
  const double step = CouplerTurn::Step();
  double previous = 0.0;  // the offset of the point before, and its index
  size_t before = 0;
  for (size_t j = 1; j < count; ++j) {
    if (kept[j] && offsets[j] >= previous) {
      previous = offsets[j];
      before = j;
      continue;
    }
    // The window ends at the next kept point's offset (a full turn past the first when none
    // follows).
    double next = 2.0 * kPi;
    size_t after = count;
    for (size_t k = j + 1; k < count; ++k) {
      if (kept[k] && offsets[k] >= previous) {
        next = offsets[k];
        after = k;
        break;
      }
    }
    const auto distance = [&](double t) {
      Eigen::Vector2d point;
      return turn.At(direction * t, &point) ? (point - data.points[j]).norm()
                                            : std::numeric_limits<double>::infinity();
    };
    // The window's ends and its samples, then golden section about the nearest.
    double best_t = previous, best = distance(previous);
    if (const double at_next = distance(next); at_next < best) best = at_next, best_t = next;
    for (double t = (std::floor(previous / step) + 1.0) * step; t < next; t += step) {
      if (const double here = distance(t); here < best) best = here, best_t = t;
    }
    constexpr int kShrinks = 30;
    const GoldenSection search = GoldenSectionSearch(distance, std::max(previous, best_t - step),
                                                     std::min(next, best_t + step), kShrinks);
    const double middle = 0.5 * (search.low + search.high);
    if (const double here = distance(middle); here < best) best = here, best_t = middle;
    if (!(best <= noise.errors[j] + noise.width + noise.tolerance)) {
      if (offsets[j] < previous && noise.Swapped(data, j, before)) {
        best_t = previous;
      } else if (offsets[j] > next && after < count && noise.Swapped(data, j, after)) {
        best_t = next;
      } else {
        return false;
      }
    }
    offsets[j] = best_t;
    previous = best_t;
    before = j;
  }
  for (size_t j = 0; j < count; ++j) (*angles)[j] = (*angles)[0] + direction * offsets[j];
  return true;
}

// Free timing: steps of `angles` against the crank's direction between points closer to each
// other than twice the four-bar's errors at them (at least twice its RMS error) and their
// precision (PassTolerance) are the data's noise, not an order the crank must go back for
// (issue 34): such a step becomes a zero step; so does a point next to the first that the
// projection puts a turn ahead. Returns whether the angles are then monotonic (unchanged when
// some backward step is beyond the noise), after RetimeOutOfOrder's second look where the
// first finds a step beyond the noise.
bool MonotonicWithinNoise(const PathFourBar& design, const PathData& data,
                          std::vector<double>* angles) {
  if (Monotonic(*angles)) return true;
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(design, data.points, *angles, data.length);
  if (analysis.point_errors.size() != data.points.size()) return false;
  const double direction = angles->back() >= angles->front() ? 1.0 : -1.0;
  double squares = 0.0;
  for (const double error : analysis.point_errors) squares += error * error;
  const OrderNoise noise{analysis.point_errors,
                         2.0 * std::sqrt(squares / static_cast<double>(data.points.size())),
                         PassTolerance(data), data.length};
  std::vector<double> clamped = *angles;
  // The points next to the first within the noise (leading ones, swapped with it by the
  // noise): one the projection put a turn ahead (just behind the first point, read from the
  // curve's other end) gets the first's angle.
  for (size_t j = 1; j < clamped.size() && noise.Swapped(data, j, 0); ++j) {
    if (direction * (clamped[j] - clamped[0]) > kPi) clamped[j] = clamped[0];
  }
  bool within = true;
  for (size_t j = 1; j < clamped.size() && within; ++j) {
    if (direction * (clamped[j] - clamped[j - 1]) >= 0.0) continue;
    within = noise.Swapped(data, j, j - 1);
    clamped[j] = clamped[j - 1];
  }
  if (within && Monotonic(clamped)) {
    *angles = clamped;
    return true;
  }
  return RetimeOutOfOrder(design, data, noise, angles);
}

// Free timing, one seed: alternately refine the four-bar under the timing (prescribed) and
// take the timing the four-bar gives the points (ProjectTiming), `alternations` times, then
// refine with the angles free when that timing is monotonic (at most `free_iterations`).
void RefineFreeTiming(const PathData& data, const PathRefinerOptions& options,
                      PathMechanismReport* report, int alternations = kAlternations,
                      int free_iterations = kFreeTimingIterations) {
  std::vector<double> angles = report->input_angles;
  const double direction = angles.back() >= angles.front() ? 1.0 : -1.0;
  PathFourBar design = report->design;
  const std::optional<double> seed_max = report->max_point_error;
  for (int round = 0; round < alternations; ++round) {
    try {
      RefinePathFourBar(data.points, data.weights, data.exact, data.length, false, &angles, &design,
                        options);
    } catch (const std::invalid_argument&) {
      return;
    }
    const std::optional<std::vector<double>> projected = ProjectTiming(design, data, direction);
    if (!projected) break;
    angles = *projected;
  }
  if (MonotonicWithinNoise(design, data, &angles)) {
    PathRefinerOptions free_options = options;
    free_options.max_iterations = free_iterations;
    // A long, flat valley of the fit (an ill-conditioned four-bar) can take more than one
    // round of iterations: further rounds (up to kRefineRounds in all) while a round runs out of
    // iterations and lowers the cost by a thousandth (the listed four-bars are then refined as
    // `linkfit refine` refines them: Finish).
    double cost = std::numeric_limits<double>::infinity();
    try {
      for (int round = 0; round < kRefineRounds; ++round) {
        const RefinerSummary summary =
            RefinePathFourBar(data.points, data.weights, data.exact, data.length, true, &angles,
                              &design, free_options);
        if (summary.iterations < free_iterations || !(summary.final_cost < 0.999 * cost) ||
            !(summary.final_cost > 0.0)) {
          break;
        }
        cost = summary.final_cost;
      }
    } catch (const std::invalid_argument&) {
    }
  }
  PathMechanismReport refined = Report(design, data, angles);
  refined.seed_max_point_error = seed_max;
  refined.input_angles = angles;
  if (!Monotonic(angles)) refined.defects.push_back("order");
  *report = refined;
}

// The nine points of `points` a nine-point solve takes (count >= 9): spread along the path,
// both ends included; the second set (`second`) shifts the interior seven by half a spacing, so
// that the two sets leave out different points. Empty when the second set would repeat the
// first (nine points).
std::vector<Eigen::Vector2d> NinePointSubset(const std::vector<Eigen::Vector2d>& points,
                                             bool second) {
  const int count = static_cast<int>(points.size());
  std::vector<Eigen::Vector2d> nine;
  if (second && count == 9) return nine;
  const double spacing = (count - 1) / 8.0;
  for (int k = 0; k < 9; ++k) {
    const long index =
        k == 0 || k == 8 || !second ? std::lround(k * spacing) : std::lround((k - 0.5) * spacing);
    nine.push_back(points[static_cast<size_t>(index)]);
  }
  return nine;
}

// Free timing, nine points or more: every coupler curve through nine of them
// (NinePointSubset; fitting/nine_point_path.h), each curve by the one of its six designs
// (CurveCognates, which builds the orbit NinePointOrbit does, in Sigma: three cognates, either
// crank; driven by a rocker, a cognate may not pass the points in order) with the timing it
// gives all the points (ProjectTiming, either direction) of smallest error, defect-free first,
// a crank and compact among equals. Returned: the kNinePointRefined curves of smallest error,
// and near misses (kNearMiss) beyond them, up to kNinePointNearMax in all.
std::vector<PathMechanismReport> NinePointSeeds(const PathData& data, bool second, int threads) {
  const std::vector<Eigen::Vector2d> nine = NinePointSubset(data.points, second);
  if (nine.empty()) return {};
  std::vector<PathFourBar> four_bars;
  NinePointOptions nine_options;
  nine_options.swap_dyads = false;  // CurveCognates gives every design of each curve
  nine_options.threads = threads;
  SolveNinePointPath(nine, nine_options, &four_bars);
  const double tolerance = PassTolerance(data);
  // Each curve's design (on `threads`, then in the solver's order).
  std::vector<std::optional<PathMechanismReport>> bests(four_bars.size());
  ParallelFor(four_bars.size(), ThreadCount(threads), [&](size_t i) {
    const PathFourBar& four_bar = four_bars[i];
    std::vector<PathMechanismReport> designs;
    for (const PathFourBar& design : CurveCognates(four_bar)) {
      // One turn's samples for both directions.
      CouplerTurn turn;
      if (!turn.Sample(design, data.length)) continue;
      for (const double direction : {1.0, -1.0}) {
        const std::vector<double> angles = ProjectTiming(turn, data, direction);
        if (angles.empty() || !Monotonic(angles)) continue;
        PathMechanismReport report = Report(design, data, angles);
        report.input_angles = angles;
        if (report.max_point_error) designs.push_back(report);
      }
    }
    // The defect-free designs when there are any.
    const bool clean = std::any_of(designs.begin(), designs.end(),
                                   [](const PathMechanismReport& r) { return r.defects.empty(); });
    double least = std::numeric_limits<double>::infinity();
    for (const PathMechanismReport& report : designs) {
      if (report.defects.empty() || !clean) least = std::min(least, *report.max_point_error);
    }
    // Designs of one curve meet the points alike (up to the timing projection): of those, a
    // crank (it refines away from the toggles a rocker turns back at), then the most compact.
    std::optional<PathMechanismReport> best;
    double best_size = 0.0;
    for (const PathMechanismReport& report : designs) {
      if ((clean && !report.defects.empty()) || *report.max_point_error > least + tolerance) {
        continue;
      }
      const double size = PathFourBarSize(report.design, data.points, data.length);
      if (!best || std::make_pair(!report.input_rotates_fully, size) <
                       std::make_pair(!best->input_rotates_fully, best_size)) {
        best = report;
        best_size = size;
      }
    }
    bests[i] = best;
  });
  std::vector<PathMechanismReport> seeds;
  for (const std::optional<PathMechanismReport>& best : bests) {
    if (best) seeds.push_back(*best);
  }
  std::sort(seeds.begin(), seeds.end(),
            [](const PathMechanismReport& a, const PathMechanismReport& b) {
              return *a.max_point_error < *b.max_point_error;
            });
  // Beyond them, curves that nearly pass the points: refined, they may pass them within
  // precision (another four-bar the data admit; BoundErrors needs to see it).
  size_t kept = std::min(seeds.size(), static_cast<size_t>(kNinePointRefined));
  while (kept < seeds.size() && static_cast<int>(kept) < kNinePointNearMax &&
         *seeds[kept].max_point_error <= kNearMiss * tolerance) {
    ++kept;
  }
  seeds.resize(kept);
  return seeds;
}

// Free timing: the candidates of the coupler-curve atlas for the points' curve, timed by
// projection (ProjectTiming) in their direction and measured: the `count` best matches after the
// first `skip`. With constraints the task gives, as many again that keep them as aligned, from
// the next best matches (the search shaped by the bounds; the refiners then hold them, and pull
// a close match that breaks one inside).
std::vector<PathMechanismReport> AtlasSeeds(const PathData& data, int skip, int count) {
  const size_t points = data.points.size();
  std::vector<double> steps;
  for (size_t j = 1; j < points; ++j) steps.push_back((data.points[j] - data.points[j - 1]).norm());
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double median = steps[steps.size() / 2];
  const double gap = (data.points.back() - data.points.front()).norm();
  AtlasMatchOptions options;
  options.kept = data.constraints.given ? skip + 3 * count : skip + count;
  options.match_closed = data.closed || gap <= kNearlyClosedSteps * median;
  options.match_open = !data.closed;
  std::vector<PathMechanismReport> seeds;
  int rank = 0, keepers = 0;
  for (const AtlasMatch& match :
       CouplerAtlas::Shared().Match(data.points, options.match_closed, options)) {
    if (rank++ < skip) continue;
    std::optional<std::vector<double>> angles =
        ProjectTiming(match.four_bar, data, match.direction);
    if (!angles) continue;
    MonotonicWithinNoise(match.four_bar, data, &*angles);
    PathMechanismReport report = Report(match.four_bar, data, *angles);
    report.input_angles = *angles;
    if (!Monotonic(*angles)) report.defects.push_back("order");
    if (!report.rms_point_error) continue;
    if (rank <= skip + count) {
      seeds.push_back(report);
    } else if (report.violates.empty() && keepers < count) {
      seeds.push_back(report);
      ++keepers;
    }
  }
  return seeds;
}

// The free-timing refiners' options: a minimum transmission angle the task gives is held by
// every refinement (the search shaped by it, not only a filter afterwards); the default is not.
PathRefinerOptions FreeTimingRefiner(const Task& task, const TaskSolverOptions& options) {
  PathRefinerOptions refiner = options.path_refiner;
  if (task.constraints.min_transmission_angle_deg) {
    refiner.min_transmission_deg = *task.constraints.min_transmission_angle_deg;
  }
  return refiner;
}

// RefineFreeTiming of every report, each independent: on `threads` (lib/parallel.h).
void RefineEach(const PathData& data, const PathRefinerOptions& refiner, int threads,
                std::vector<PathMechanismReport>* reports) {
  ParallelFor(reports->size(), ThreadCount(threads),
              [&](size_t i) { RefineFreeTiming(data, refiner, &(*reports)[i]); });
}

// Free timing: evenly spaced timing guesses (spans kGuessSpans, both directions), the seed
// four-bars of each guess, refined with the angles free (RefineFreeTiming).
void SolveFreeTiming(const Task& task, const PathData& data, const TaskSolverOptions& options,
                     PathResult* result, std::vector<PathFourBar>* fits) {
  const PathRefinerOptions refiner = FreeTimingRefiner(task, options);
  const int count = static_cast<int>(data.points.size());
  const double tolerance = PassTolerance(data);  // a four-bar through the points
  const auto stage_start = std::chrono::steady_clock::now();
  std::vector<PathMechanismReport> candidates;
  std::vector<double> chords;
  double chord_sum = 0.0;
  for (int j = 1; j < count; ++j) {
    chords.push_back((data.points[j] - data.points[j - 1]).norm());
    chord_sum += chords.back();
  }
  if (!(chord_sum > 0.0)) chord_sum = 1.0;
  // A closed path: n points spaced over a whole turn, the last step (and chord) back to the
  // first point; the open spans make no sense for it.
  if (data.closed) {
    chords.push_back((data.points[0] - data.points[count - 1]).norm());
    chord_sum += chords.back();
  }
  const std::vector<double> spans =
      data.closed ? std::vector<double>{1.0}
                  : std::vector<double>(std::begin(kGuessSpans), std::end(kGuessSpans));
  const int steps = data.closed ? count : count - 1;  // steps the span is divided into
  for (double span_turns : spans) {
    const double span =
        2.0 * kPi * (span_turns < 0.0 ? static_cast<double>(count - 1) / count : span_turns);
    for (double direction : {1.0, -1.0}) {
      // Evenly spaced, and spaced as the chords between consecutive points (a crank turning
      // evenly moves the coupler point about evenly along its path).
      for (bool by_chord : {false, true}) {
        std::vector<double> angles = {0.0};
        for (int j = 1; j < count; ++j) {
          angles.push_back(angles.back() + (by_chord ? chords[j - 1] / chord_sum : 1.0 / steps));
        }
        for (double& angle : angles) angle *= direction * span;
        std::vector<PathMechanismReport> seeds =
            SubsetSeeds(data, angles, kFreeTimingSubsets, kFreeTimingStarts, options.timed_path);
        for (PathMechanismReport& seed : seeds) seed.input_angles = angles;
        candidates.insert(candidates.end(), seeds.begin(), seeds.end());
      }
    }
  }
  result->stages.push_back(Stage("seed", stage_start, candidates));
  // The curve as a whole: candidates from the coupler-curve atlas; above fast, refined first (a
  // few refinements from seeds near the curve).
  const auto atlas_start = std::chrono::steady_clock::now();
  const int atlas_count = task.effort == Effort::kFast       ? kAtlasFast
                          : task.effort == Effort::kBalanced ? kAtlasBalanced
                                                             : kAtlasThorough;
  std::vector<PathMechanismReport> atlas_seeds = AtlasSeeds(data, 0, atlas_count);
  const auto refine_atlas = [&](std::vector<PathMechanismReport>* seeds) {
    std::vector<PathMechanismReport> refined = *seeds;
    RefineEach(data, refiner, options.threads, &refined);
    seeds->insert(seeds->end(), refined.begin(), refined.end());
  };
  if (task.effort != Effort::kFast) refine_atlas(&atlas_seeds);
  result->stages.push_back(Stage("atlas", atlas_start, atlas_seeds));
  const std::vector<PathMechanismReport> subset_seeds = candidates;
  candidates.insert(candidates.end(), atlas_seeds.begin(), atlas_seeds.end());
  // Balanced stops where the search has found the curve: a keeper of the constraints whose
  // misses look like the points' noise (MissesLookLikeNoise), or where that cannot be told (few
  // points, or all passed within 1e-9 L), a defect-free four-bar through every point within the
  // data's precision; the other stages can only come to the same curve or to
  // a worse fit. Otherwise the nine-point solve, then the subset seeds' refinement, then the
  // other nine points (on a near miss), each only while the search has not found it. Thorough
  // runs them all.
  const auto found = [&](const std::vector<PathMechanismReport>& reports) {
    const PathMechanismReport* keeper = BestKeeper(reports);
    const std::optional<bool> noise =
        keeper != nullptr ? MissesLookLikeNoise(*keeper, data) : std::nullopt;
    if (noise) return *noise;  // within the precision or not, its shape decides
    const std::optional<double> best = BestDefectFreeMaxError(reports);
    return best && *best <= tolerance;
  };
  const bool thorough = task.effort == Effort::kThorough;
  // Balanced, not found (from kRunsMinPoints points: fewer get the nine-point solve below):
  // thorough's further atlas candidates first (a restart of the global stage: a few
  // refinements, against the nine-point solve's fixed cost).
  const bool few = count < kRunsMinPoints;
  bool atlas_found = task.effort != Effort::kFast && found(atlas_seeds);
  if (task.effort == Effort::kBalanced && !few && !atlas_found) {
    const auto more_start = std::chrono::steady_clock::now();
    std::vector<PathMechanismReport> more =
        AtlasSeeds(data, kAtlasBalanced, kAtlasThorough - kAtlasBalanced);
    refine_atlas(&more);
    result->stages.push_back(Stage("atlas, further candidates", more_start, more));
    atlas_seeds.insert(atlas_seeds.end(), more.begin(), more.end());
    candidates.insert(candidates.end(), more.begin(), more.end());
    atlas_found = found(atlas_seeds);
  }
  // Fewer points than the runs test needs: distinct coupler curves may pass them all within
  // their precision (the nine-point solve lists them; the error bounds and the note depend on
  // seeing them), so the nine-point solve runs whatever the atlas found.
  const bool search_more = task.effort != Effort::kFast && (thorough || few || !atlas_found);
  std::vector<PathMechanismReport> homotopy_seeds;
  if (search_more && count >= 9) {
    const auto homotopy_start = std::chrono::steady_clock::now();
    homotopy_seeds = NinePointSeeds(data, false, options.threads);
    result->stages.push_back(Stage("nine-point homotopy", homotopy_start, homotopy_seeds));
  }
  if (search_more) {
    const auto refine_start = std::chrono::steady_clock::now();
    RefineEach(data, refiner, options.threads, &homotopy_seeds);
    candidates.insert(candidates.end(), homotopy_seeds.begin(), homotopy_seeds.end());
    // Refined ones join the seeds rather than replace them (fast's answer stays a candidate).
    std::vector<PathMechanismReport> refined;
    if (thorough || !found(candidates)) {
      refined = subset_seeds;  // the atlas seeds were refined already
      if (!thorough && refined.size() > static_cast<size_t>(kSubsetRefinedBalanced)) {
        std::stable_sort(
            refined.begin(), refined.end(),
            [](const PathMechanismReport& a, const PathMechanismReport& b) {
              return a.rms_point_error.value_or(std::numeric_limits<double>::infinity()) <
                     b.rms_point_error.value_or(std::numeric_limits<double>::infinity());
            });
        refined.resize(kSubsetRefinedBalanced);
      }
      RefineEach(data, refiner, options.threads, &refined);
    }
    candidates.insert(candidates.end(), refined.begin(), refined.end());
    result->stages.push_back(Stage("refine", refine_start, candidates));
    // Still not found: the nine-point solve again on the other nine (a path the tracker lost, or
    // a curve coarse data moved out of reach of the refinement from one set, is found from the
    // other). Balanced does it when the miss is small (kSecondNineMiss); thorough always.
    // Not when the atlas and the first nine's homotopy, two independent global stages, came to
    // the same best curve (their best keepers' curves within kStagesAgree L): the other nine
    // are for a curve the first nine missed.
    const std::optional<double> refined_best = BestDefectFreeMaxError(candidates);
    const bool near_miss = refined_best && *refined_best <= kSecondNineMiss * tolerance;
    const auto agree = [&]() {
      const PathMechanismReport* atlas_best = BestKeeper(atlas_seeds);
      const PathMechanismReport* nine_best = BestKeeper(homotopy_seeds);
      return atlas_best != nullptr && nine_best != nullptr &&
             CurveDistance(atlas_best->design, nine_best->design) <= kStagesAgree * data.length;
    };
    if (count >= 10 && !(refined_best && *refined_best <= tolerance) &&
        (thorough || (near_miss && !found(candidates) && !agree()))) {
      const auto second_start = std::chrono::steady_clock::now();
      std::vector<PathMechanismReport> second = NinePointSeeds(data, true, options.threads);
      RefineEach(data, refiner, options.threads, &second);
      result->stages.push_back(Stage("nine-point homotopy, other nine", second_start, second));
      candidates.insert(candidates.end(), second.begin(), second.end());
    }
  }
  // Thorough: the NLopt crank search (optimizers/path_search.h) under the timing of the best
  // keeper found, its crank angles at the points: other basins of the fit near that timing,
  // their four-bars refined with the angles free.
  const PathMechanismReport* keeper = thorough ? BestKeeper(candidates) : nullptr;
  if (keeper != nullptr && Monotonic(keeper->input_angles)) {
    const auto search_start = std::chrono::steady_clock::now();
    const std::vector<double> timing = keeper->input_angles;
    PathSearchOptions search = options.path_search;
    search.refiner = refiner;
    std::vector<PathFourBar> four_bars;
    try {
      SearchPathFourBars(data.points, data.weights, data.exact, timing, data.length, search,
                         &four_bars);
    } catch (const std::invalid_argument&) {
    }
    std::vector<PathMechanismReport> searched;
    for (const PathFourBar& four_bar : four_bars) {
      PathMechanismReport report = Report(four_bar, data, timing);
      if (!report.max_point_error) continue;
      report.input_angles = timing;
      searched.push_back(report);
    }
    RefineEach(data, refiner, options.threads, &searched);
    result->stages.push_back(Stage("search, the best's timing", search_start, searched));
    candidates.insert(candidates.end(), searched.begin(), searched.end());
  }
  for (const PathMechanismReport& candidate : candidates) {
    if (candidate.defects.empty() && candidate.max_point_error &&
        *candidate.max_point_error <= tolerance) {
      fits->push_back(candidate.design);
    }
  }
  Finish(task, data, options, options.path_reported, candidates, result);
  // Nothing through the points within their precision: say so, with how far the best misses.
  const std::optional<double> best = BestDefectFreeMaxError(result->mechanisms);
  if (count >= 9 && task.effort != Effort::kFast && !result->mechanisms.empty() &&
      !(best && *best <= tolerance)) {
    std::string miss = "every four-bar found has a defect";
    if (best) {
      char text[96];
      std::snprintf(text, sizeof(text), "%.3g (%.3g times the tolerance %.3g)", *best,
                    *best / tolerance, tolerance);
      miss = std::string("the best misses one by ") + text;
    }
    result->notes.push_back(
        "no four-bar found passes every point within their precision: " + miss +
        "; the data are noisier than their digits say, or the search missed it" +
        (task.effort == Effort::kThorough ? std::string()
                                          : std::string(" (effort thorough searches more)")));
  }
}

// Free timing on more than kFreeTimingScreenPoints points (a curve traced from a picture): the
// whole search (timing guesses, subset seeds, nine-point solves, refinements: tens of
// refinements each linear in the points) runs on kFreeTimingScreenPoints points spread along
// the path (the first, the last and the exact ones among them). Each four-bar it lists is then
// timed on every point (ProjectTiming), the first kScreenRefined of them (balanced, thorough)
// refined with the angles free on every point (RefineFreeTiming), and every one re-measured and
// re-ranked on every point.
void SolveFreeTimingScreened(const Task& task, const PathData& data,
                             const TaskSolverOptions& options, PathResult* result,
                             std::vector<PathFourBar>* fits) {
  const PathRefinerOptions refiner = FreeTimingRefiner(task, options);
  const std::vector<size_t> picked =
      SpreadIndices(data.points.size(), kFreeTimingScreenPoints, data.exact);
  PathData screen = data;
  screen.points.clear();
  screen.weights.clear();
  screen.exact.clear();
  for (const size_t j : picked) {
    screen.points.push_back(data.points[j]);
    screen.weights.push_back(data.weights[j]);
    screen.exact.push_back(data.exact[j]);
  }
  PathResult screened;
  std::vector<PathFourBar> screened_fits;
  SolveFreeTiming(task, screen, options, &screened, &screened_fits);
  result->stages = screened.stages;
  const auto stage_start = std::chrono::steady_clock::now();
  // Each listed four-bar timed on every point (on options.threads), in the listed order.
  std::vector<std::optional<PathMechanismReport>> timed(screened.mechanisms.size());
  ParallelFor(timed.size(), ThreadCount(options.threads), [&](size_t i) {
    const PathMechanismReport& listed = screened.mechanisms[i];
    if (listed.input_angles.size() != screen.points.size()) return;
    const double direction = listed.input_angles.back() >= listed.input_angles.front() ? 1.0 : -1.0;
    std::optional<std::vector<double>> angles = ProjectTiming(listed.design, data, direction);
    if (!angles) return;
    MonotonicWithinNoise(listed.design, data, &*angles);
    PathMechanismReport report = Report(listed.design, data, *angles);
    report.input_angles = *angles;
    if (!Monotonic(*angles)) report.defects.push_back("order");
    timed[i] = report;
  });
  std::vector<PathMechanismReport> candidates;
  for (const std::optional<PathMechanismReport>& report : timed) {
    if (report) candidates.push_back(*report);
  }
  // From the screened optimum, timed on every point: the first kScreenRefined refined, one
  // alternation, then the angles free.
  const int refined =
      task.effort == Effort::kFast ? 0 : std::min<int>(kScreenRefined, candidates.size());
  ParallelFor(refined, ThreadCount(options.threads), [&](size_t i) {
    RefineFreeTiming(data, refiner, &candidates[i], 1, kScreenFreeIterations);
  });
  result->stages.push_back(Stage("every point", stage_start, candidates));
  const double tolerance = PassTolerance(data);
  for (const PathMechanismReport& candidate : candidates) {
    if (candidate.defects.empty() && candidate.max_point_error &&
        *candidate.max_point_error <= tolerance) {
      fits->push_back(candidate.design);
    }
  }
  Finish(task, data, options, options.path_reported, candidates, result);
  result->notes.push_back(
      std::to_string(data.points.size()) + " untimed points: the four-bars were searched for on " +
      std::to_string(screen.points.size()) +
      " points spread along the path, then timed and measured on every point" +
      (refined > 0 ? ", the best " + std::to_string(refined) + " refined on every point" : ""));
}

// Every four-bar that meets the points gets its first-order error bound at the data's
// precision, or at its own largest point error where that is larger and it has no defect
// (PathFourBarErrorBound; free timing with its fitted input angles as parameters); a note counts
// those that bound leaves loose: by more than 1 % of their size, and by more than their size
// (those mean nothing at this precision). Under free timing the bound is then widened to the
// farthest of `fits` (four-bars that also pass the points within their precision) by
// CurveDistance, with a note of its own.
void BoundErrors(const PathData& data, bool free_timing, const std::vector<PathFourBar>& fits,
                 PathResult* result) {
  int loose = 0, meaningless = 0, bounded = 0, spread = 0;
  double widest = 0.0;
  const double tolerance = PassTolerance(data);
  for (PathMechanismReport& report : result->mechanisms) {
    if (!report.max_point_error) continue;
    const std::vector<double>& angles = free_timing ? report.input_angles : data.angles;
    if (angles.size() != data.points.size()) continue;
    // A four-bar that misses the points by e is known no better than from points precise to e
    // (defect-free: a defect's error is the branch or circuit it passes to, not the fit's).
    DataPrecision precision = data.precision;
    if (!HasKinematicDefect(report.defects)) {
      precision.length = std::max(precision.length, *report.max_point_error);
    }
    report.error_bound = PathFourBarErrorBound(report.design, data.points, angles, precision,
                                               data.length, free_timing);
    ++bounded;
    const double size = PathFourBarSize(report.design, data.points, data.length);
    const double relative = *report.error_bound / size;
    if (relative > 1e-2) ++loose;
    if (!(relative <= 1.0)) ++meaningless;
    // The first-order bound sees one minimum. Another curve through the points within their
    // precision is as far as the data can move this one at least.
    if (!HasKinematicDefect(report.defects) && *report.max_point_error <= tolerance) {
      double farthest = 0.0;
      for (const PathFourBar& fit : fits) {
        const double apart = CurveDistance(report.design, fit);
        if (std::isfinite(apart)) farthest = std::max(farthest, apart);
      }
      if (farthest > *report.error_bound) {
        report.error_bound = farthest;
        ++spread;
        widest = std::max(widest, farthest / size);
      }
    }
  }
  if (spread > 0) {
    result->notes.push_back(
        "distinct coupler curves (not cognates) pass the points within their precision, up to " +
        PrecisionText(widest) +
        " of a four-bar's size apart: the points do not determine the four-bar; the error_bound "
        "of " +
        std::to_string(spread) + " four-bar(s) is that distance");
  }
  if (loose == 0) return;
  std::string note =
      "with the points precise to " + PrecisionText(data.precision.length) +
      (free_timing ? std::string()
                   : " and the input angles to " +
                         PrecisionText(data.precision.angle * 180.0 / std::acos(-1.0)) + " deg") +
      ", " + std::to_string(loose) + " of the " + std::to_string(bounded) +
      " four-bars may be off by more than 1 % of their size (error_bound, first "
      "order; at a four-bar's own point error where that is larger)";
  if (meaningless > 0) {
    // Issue 34: such a four-bar is not meaningless when it fits; its dimensions are what the
    // points leave open.
    note += "; " + std::to_string(meaningless) +
            " by more than their own size or undetermined: such a four-bar is not determined by "
            "the points at this precision (others pass them as well; its fit stands, its "
            "dimensions are one choice)";
  }
  result->notes.push_back(note);
}

// Four-bars the data's precision cannot tell apart are one: of a type, every joint and the
// coupler point of the later within the smaller of the two error bounds (and within 10 % of their
// size) of the earlier's, and their largest point errors within PathPassTolerance of each other
// (the points tell a fit twice as far from them apart, however loosely they pin the joints); the
// better ranked stays, with a note. (Least-squares refinements from several seeds end on optima
// that close; listed, they were clutter whose order rounding of the data decided.)
void MergeWithinBounds(const PathData& data, PathResult* result) {
  const double fit_tolerance = PathPassTolerance(data.precision, data.length);
  const auto joints = [](const PathFourBar& design) {
    std::vector<Eigen::Vector2d> points = {design.input.fixed_pivot, design.input.moving_pivot,
                                           design.coupler_point};
    if (design.output.type != DyadType::kPR) points.push_back(design.output.fixed_pivot);
    if (design.output.type != DyadType::kRP) points.push_back(design.output.moving_pivot);
    return points;
  };
  std::vector<PathMechanismReport> kept;
  int merged = 0;
  for (const PathMechanismReport& report : result->mechanisms) {
    bool same = false;
    for (const PathMechanismReport& other : kept) {
      if (other.type != report.type || !report.error_bound || !other.error_bound ||
          other.design.output.type != report.design.output.type || !report.max_point_error ||
          !other.max_point_error ||
          !(std::abs(*report.max_point_error - *other.max_point_error) <= fit_tolerance)) {
        continue;
      }
      const double size = std::min(PathFourBarSize(report.design, data.points, data.length),
                                   PathFourBarSize(other.design, data.points, data.length));
      const double allowed = std::min({*report.error_bound, *other.error_bound, 0.1 * size});
      const std::vector<Eigen::Vector2d> a = joints(report.design), b = joints(other.design);
      double apart = 0.0;
      for (size_t k = 0; k < a.size(); ++k) apart = std::max(apart, (a[k] - b[k]).norm());
      if (report.design.output.type != DyadType::kRR) {
        const Eigen::Vector2d u = report.design.output.line_direction.normalized();
        const Eigen::Vector2d v = other.design.output.line_direction.normalized();
        apart = std::max(apart, size * std::abs(u.x() * v.y() - u.y() * v.x()));
      }
      if (apart <= allowed) {
        same = true;
        break;
      }
    }
    if (same) {
      ++merged;
    } else {
      kept.push_back(report);
    }
  }
  if (merged == 0) return;
  result->mechanisms = std::move(kept);
  result->notes.push_back(std::to_string(merged) +
                          " four-bar(s) within the data's precision (their error_bound) of a "
                          "better-ranked one were dropped: the points cannot tell them apart");
}

}  // namespace

double PathPassTolerance(const DataPrecision& precision, double length) {
  return std::max(1e-8 * length, kModelUnits * PointUncertainty(precision, 0.0, length, 2));
}

PathResult SolvePathTask(const Task& task, const TaskSolverOptions& given_options) {
  const auto start = std::chrono::steady_clock::now();
  PathResult result;
  const PathData data = Data(task);
  // The data's precision types the five-point solver's output dyads, and a closed path is
  // judged with its closing step in the refinements too.
  TaskSolverOptions options = given_options;
  options.timed_path.precision = task.precision;
  options.path_refiner.closed = task.closed;
  options.path_refiner.constraints = task.constraints;
  const bool free_timing = StartResult(task, data, &result);
  const int count = static_cast<int>(data.points.size());
  std::vector<PathFourBar> fits;  // free timing: the four-bars through the points
  // Untimed points may repeat in print (a dense trace): the distinct ones count.
  const int distinct_count = DistinctPoints(task.points);
  if (distinct_count < 5) {
    result.notes.push_back(std::to_string(distinct_count) +
                           (distinct_count < count ? " distinct" : "") +
                           " point(s): a four-bar has 10 parameters, so " +
                           (free_timing ? "fewer than nine untimed points leave"
                                        : "fewer than five timed points leave") +
                           " a family of solutions; give at least five points");
  } else if (!free_timing && count == 5) {
    std::vector<PathFourBar> four_bars;
    TimedPathSummary summary;
    SolveTimedPath(data.points, data.angles, options.timed_path, &four_bars, &summary);
    result.crank_roots_total = summary.crank_roots_total;
    result.crank_roots_real = summary.crank_roots_real;
    result.four_bars_total = summary.four_bars_total;
    result.notes = summary.notes;
    // A circle output the points cannot tell from its slider at their precision is the slider
    // (the slider-crank fitted to the five points in least squares: the exact solver keeps the
    // circle where its slider reading alone misses them).
    int simplified = 0;
    result.analysis_seconds = summary.analysis_seconds;
    for (const PathFourBar& four_bar : four_bars) {
      const auto analysis_start = std::chrono::steady_clock::now();
      PathMechanismReport report = Report(four_bar, data, data.angles), slider;
      result.analysis_seconds += Seconds(analysis_start);
      // Kept within the data's precision (a complex pair's real part, a root computed only to
      // the crank equations' condition): polished onto the points.
      if (report.max_point_error && report.defects.empty() &&
          *report.max_point_error > options.timed_path.verify_tolerance * data.length) {
        Polish(data, options.path_refiner, &report);
      }
      if (SliderAtPrecision(data, options.path_refiner, report, &slider)) {
        ++simplified;
        AddDistinct(slider, data.length, data.centroid,
                    &result.mechanisms);  // the solver's own slider
      } else {
        result.mechanisms.push_back(report);
      }
    }
    // Four-bars the solver handed on (slider readings of far circles that miss the points,
    // and the four-bars of nearly real complex cranks), fitted to the points: kept when they
    // then pass them within their precision.
    int rescued = 0;
    for (const PathFourBar& candidate : summary.to_fit) {
      PathMechanismReport fitted;
      if (FitToPoints(data, options.path_refiner, candidate, &fitted)) {
        ++(candidate.output.type == DyadType::kRR ? rescued : simplified);
        AddDistinct(fitted, data.length, data.centroid, &result.mechanisms);
      }
    }
    if (rescued > 0) {
      result.notes.push_back(
          std::to_string(rescued) +
          " four-bar(s) from complex crank roots whose real part, fitted to the points, passes "
          "them within their precision: rounding of the data can turn two real cranks into a "
          "complex pair");
    }
    if (simplified > 0) {
      result.notes.push_back(std::to_string(simplified) +
                             " output circle(s) reported as sliders: at the data's precision the "
                             "points cannot tell them from their slider readings");
    }
    // Constraints that no exact four-bar keeps: the least-squares stages (SolvePrescribed, the
    // exact four-bars among its seeds, refined under the constraints' penalties, and the search
    // where no refinement keeps them) find those that keep them, as near the points as the
    // bounds allow. The exact four-bars stay listed, after them (the ranking rule).
    const auto keeps = [](const PathMechanismReport& report) {
      return report.violates.empty() && report.max_point_error.has_value();
    };
    if (task.constraints.given && task.effort != Effort::kFast &&
        std::none_of(result.mechanisms.begin(), result.mechanisms.end(), keeps)) {
      PathResult bounded;
      SolvePrescribed(task, data, options, &bounded);
      int added = 0;
      for (const PathMechanismReport& report : bounded.mechanisms) {
        if (!keeps(report)) continue;
        AddDistinct(report, data.length, data.centroid, &result.mechanisms);
        ++added;
      }
      result.stages = bounded.stages;
      result.notes.push_back(
          "no exact four-bar keeps the constraints: " + std::to_string(added) +
          " least-squares four-bar(s) that keep them are listed first, as near the points as "
          "the bounds allow");
    }
    for (PathMechanismReport& report : result.mechanisms) JudgeTransmission(data, &report);
    Rank(false, data, -1, &result.mechanisms);
    if (four_bars.empty() && !summary.degenerate) {
      result.notes.push_back("no real four-bar passes the five points with this timing");
    }
  } else {
    result.method = "least-squares";
    result.effort = EffortName(task.effort);
    if (free_timing && count > static_cast<int>(kFreeTimingScreenPoints)) {
      SolveFreeTimingScreened(task, data, options, &result, &fits);
    } else if (free_timing) {
      SolveFreeTiming(task, data, options, &result, &fits);
      if (count < 9) {
        result.notes.push_back(
            "fewer than nine untimed points: a family of four-bars passes "
            "them; these are some of it");
      }
    } else {
      SolvePrescribed(task, data, options, &result);
    }
    if (result.mechanisms.empty()) {
      result.notes.push_back("no four-bar found: the seeds failed (degenerate points?)");
    }
  }
  if (count >= 5) {
    BoundErrors(data, free_timing, fits, &result);
    MergeWithinBounds(data, &result);
  }
  if (task.closed && count >= 5) {
    result.notes.push_back(
        std::string("solved as a closed path: the crank makes a whole turn from points[0] back "
                    "to it") +
        (free_timing ? " (the fitted input angles span less than a turn, in one direction)"
                     : " in the direction of the timing") +
        ", and a four-bar whose crank cannot is marked with a branch defect");
  }
  result.solve_seconds = Seconds(start);
  return result;
}

namespace {

// Whether a refinement result is better than its seed: driven through every point, without a
// kinematic defect the seed did not have, and a smaller RMS point error (the refiner's objective:
// a least-squares optimum can miss one point by more than its start did).
bool Improves(const PathMechanismReport& refined, const PathMechanismReport& seed) {
  if (!refined.max_point_error) return false;
  if (!AddedKinematicDefects(seed.defects, refined.defects).empty()) return false;
  return !seed.max_point_error ||
         refined.rms_point_error.value_or(kInfinity) < seed.rms_point_error.value_or(kInfinity);
}

// A projected timing's points out of order (a coupler curve that passes near itself offers a
// point two places): each interior point whose angle is not between its neighbours', when those
// are in order, gets the angle between them in proportion to the chords; a last point out of
// order, its predecessor's step again.
void InterpolateOutOfOrder(const std::vector<Eigen::Vector2d>& points,
                           std::vector<double>* angles) {
  std::vector<double>& a = *angles;
  const size_t n = a.size();
  if (n < 3) return;
  const double direction = a.back() >= a.front() ? 1.0 : -1.0;
  const auto ordered = [&](double from, double to) { return direction * (to - from) >= 0.0; };
  for (size_t j = 1; j + 1 < n; ++j) {
    if (ordered(a[j - 1], a[j]) && ordered(a[j], a[j + 1])) continue;
    if (!ordered(a[j - 1], a[j + 1])) continue;
    const double before = (points[j] - points[j - 1]).norm();
    const double after = (points[j + 1] - points[j]).norm();
    const double share = before + after > 0.0 ? before / (before + after) : 0.5;
    a[j] = a[j - 1] + share * (a[j + 1] - a[j - 1]);
  }
  if (!ordered(a[n - 2], a[n - 1])) a[n - 1] = a[n - 2] + (a[n - 2] - a[n - 3]);
}

// The refinement of a design whose least-squares optimum lies past a defect (a step through a
// stationary configuration: on coarse data the fit can pull a crank onto its Grashof limit), or
// where the refiner keeps the seed for another reason: shorter refinements in turn, each from
// the last one accepted (the refiner accepts none that adds a defect), halving the iterations
// when one is refused; the design walks toward the optimum and stops before the defect. Returns
// whether it moved; `ended`: whether it stopped because no step was accepted (not on its rounds).
bool RefineInSteps(const PathData& data, const PathRefinerOptions& options, bool free_timing,
                   PathFourBar* design, std::vector<double>* angles, bool* ended) {
  constexpr int kFirstSteps = 64, kMaxRounds = 40;
  bool moved = false;
  double cost = std::numeric_limits<double>::infinity();
  int iterations = kFirstSteps;
  *ended = false;
  for (int round = 0; round < kMaxRounds && iterations >= 1; ++round) {
    PathFourBar next = *design;
    std::vector<double> next_angles = *angles;
    PathRefinerOptions steps = options;
    steps.max_iterations = iterations;
    RefinerSummary summary;
    try {
      summary = RefinePathFourBar(data.points, data.weights, data.exact, data.length, free_timing,
                                  &next_angles, &next, steps);
    } catch (const std::invalid_argument&) {
      *ended = true;
      return moved;
    }
    if (!std::isfinite(cost)) cost = summary.initial_cost;
    if (summary.final_cost < cost * (1.0 - 1e-9)) {
      *design = next;
      *angles = next_angles;
      cost = summary.final_cost;
      moved = true;
    } else {
      iterations /= 2;
    }
  }
  if (iterations < 1) *ended = true;
  return moved;
}

}  // namespace

PathResult RefinePathDesign(const Task& task, const PathFourBar& four_bar,
                            const std::vector<double>& input_angles,
                            const TaskSolverOptions& options, bool* converged) {
  bool ended = true;  // the refinement returned ended on a tolerance (see the header)
  const auto start = std::chrono::steady_clock::now();
  const PathData data = Data(task);
  PathRefinerOptions refiner = options.path_refiner;
  refiner.closed = task.closed;
  refiner.constraints = task.constraints;
  PathResult result;
  const bool free_timing = StartResult(task, data, &result);
  result.method = "refine";
  result.effort = EffortName(task.effort);
  const auto transmission = [](const PathMechanismReport& report) {
    return std::find(report.defects.begin(), report.defects.end(), "transmission") !=
           report.defects.end();
  };
  // With constraints given, a design whose transmission angle keeps their minimum keeps it: the
  // refiner holds it (a penalty under prescribed timing, and it refuses a result below it either
  // way). Without, the refinement is the fit's, and a note says when it costs the angle.
  bool seed_transmission_kept = false;
  const auto hold_if_kept = [&](const PathMechanismReport& seed_report) {
    PathMechanismReport judged = seed_report;
    JudgeTransmission(data, &judged);
    seed_transmission_kept = judged.max_point_error && !transmission(judged);
    if (task.constraints.given && seed_transmission_kept) {
      refiner.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
    }
  };
  PathMechanismReport seed, refined;
  if (!free_timing) {
    seed = Report(four_bar, data, data.angles);
    hold_if_kept(seed);
    if (!AnalyzePathFourBar(four_bar, data.points, data.angles, data.length).assembles) {
      throw std::invalid_argument(
          "the four-bar does not assemble at its crank's first angle: its output dyad cannot "
          "reach the coupler as given");
    }
    // A design the crank cannot drive through every point starts with its output circle moved
    // into reach (DrivableOutput, path_search.h), as the search's seeds do.
    PathFourBar start = four_bar;
    if (!seed.max_point_error) {
      std::vector<double> turns;
      for (double angle : data.angles) turns.push_back(angle - data.angles.front());
      PlanarDyad drivable;
      if (DrivableOutput(four_bar.output, four_bar.input.fixed_pivot, four_bar.input.moving_pivot,
                         turns, &drivable)) {
        start.output = drivable;
      }
    }
    // The solve again from where it stopped, while that gains: a long, curved valley can take
    // it many times its iterations, and where a step would break assembly (a point near a dead
    // point) Levenberg-Marquardt's trust region shrinks until it stops on its step tolerance
    // short of the optimum; a fresh solve from an optimum stops at once. The design `linkfit
    // refine` gives back is then at its optimum.
    std::optional<PathMechanismReport> once = RefinedReport(data, refiner, start, &ended);
    // Two solves in a row that gain too little end them (a stall is often passed only from a
    // step further along).
    for (int solve = 1, idle = 0; solve < kRefineSolves && once && idle < 2; ++solve) {
      bool again_ended = true;
      const std::optional<PathMechanismReport> again =
          RefinedReport(data, refiner, once->design, &again_ended);
      if (!again || !Improves(*again, *once)) break;  // from the same start, the same again
      const double before = once->rms_point_error.value_or(kInfinity);
      once = again;
      ended = again_ended;
      idle = SolveAgain(before, *again->rms_point_error, again_ended) ? 0 : idle + 1;
    }
    refined = once ? *once : seed;
    if (!Improves(refined, seed)) {
      PathFourBar design = start;
      std::vector<double> angles = data.angles;
      if (RefineInSteps(data, refiner, false, &design, &angles, &ended)) {
        refined = Report(design, data, data.angles);
      }
    }
    JudgeTransmission(data, &refined);
    // With constraints, a refinement that ends on a transmission defect is repeated holding the
    // angle (PathRefinerOptions::min_transmission_deg), as the solver does.
    if (task.constraints.given && !refiner.min_transmission_deg && transmission(refined)) {
      PathRefinerOptions held = refiner;
      held.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
      bool held_ended = true;
      std::optional<PathMechanismReport> holding = RefinedReport(data, held, four_bar, &held_ended);
      if (holding) {
        JudgeTransmission(data, &*holding);
        if (holding->violates.empty() && holding->max_point_error && !transmission(*holding)) {
          refined = *holding;
          ended = held_ended;
          result.notes.push_back(
              "the refinement held the transmission angle: without the hold it ended below the "
              "task's minimum");
        }
      }
    }
  } else {
    // The starting timing: the design's fitted angles, else the one its coupler curve gives
    // the points, of the two turning directions the one that meets them better.
    std::vector<double> angles = input_angles;
    if (!angles.empty()) {
      const double first = angles.front();
      for (double& angle : angles) angle -= first;
      if (!Monotonic(angles)) {
        result.notes.push_back(
            "the design's input angles do not turn one way through the points: the timing is "
            "taken from its coupler curve instead");
        angles.clear();
      }
    }
    if (angles.empty()) {
      // Both directions put the crank at the same angles modulo a turn, so meet the points
      // alike: the one that turns one way through them is the timing (as NinePointSeeds takes).
      std::pair<bool, double> best(true, std::numeric_limits<double>::infinity());
      for (double direction : {1.0, -1.0}) {
        const std::optional<std::vector<double>> projected =
            ProjectTiming(four_bar, data, direction);
        if (!projected) continue;
        const PathMechanismReport report = Report(four_bar, data, *projected);
        const std::pair<bool, double> key(
            !Monotonic(*projected),
            report.max_point_error.value_or(std::numeric_limits<double>::infinity()));
        if (key < best || angles.empty()) {
          best = key;
          angles = *projected;
        }
      }
      if (!angles.empty()) InterpolateOutOfOrder(data.points, &angles);
    }
    if (angles.empty()) {
      throw std::invalid_argument(
          "the four-bar does not assemble at its crank's first angle: its output dyad cannot "
          "reach the coupler as given");
    }
    seed = Report(four_bar, data, angles);
    seed.input_angles = angles;
    hold_if_kept(seed);
    // From a design near its optimum, the four-bar and the angles refined together find that
    // optimum; the solver's alternation (RefineFreeTiming), made for rough timing guesses, can
    // first fit the design to the projected timing's errors and leave the neighbourhood. It is
    // the fallback where the direct refinement ends on a kinematic defect or out of order.
    refined = seed;
    bool direct = false;
    try {
      std::vector<double> free_angles = angles;
      PathFourBar design = four_bar;
      PathRefinerOptions free_options = refiner;
      free_options.max_iterations = kFreeTimingIterations;
      // An ill-conditioned four-bar (a long, flat valley of the fit) can take more than one
      // round of iterations, and a solve can stall short of the optimum: further solves from
      // where the last stopped while each gains (SolveAgain).
      double cost = std::numeric_limits<double>::infinity();
      for (int round = 0; round < kRefineSolves; ++round) {
        const RefinerSummary summary =
            RefinePathFourBar(data.points, data.weights, data.exact, data.length, true,
                              &free_angles, &design, free_options);
        ended = summary.converged;
        if (!SolveAgain(cost, summary.final_cost, summary.converged) ||
            !(summary.final_cost > 0.0)) {
          break;
        }
        cost = summary.final_cost;
      }
      refined = Report(design, data, free_angles);
      refined.input_angles = free_angles;
      direct = refined.max_point_error && Monotonic(free_angles) &&
               AddedKinematicDefects(seed.defects, refined.defects).empty();
    } catch (const std::invalid_argument&) {
    }
    if (!direct) {
      ended = true;
      refined = seed;
      RefineFreeTiming(data, refiner, &refined);
    }
    if (!Improves(refined, seed)) {
      PathFourBar design = four_bar;
      std::vector<double> stepped = angles;
      if (RefineInSteps(data, refiner, true, &design, &stepped, &ended)) {
        refined = Report(design, data, stepped);
        refined.input_angles = stepped;
      }
    }
    JudgeTransmission(data, &refined);
  }
  // Never worse than the design: a refinement that is no longer driven through the points, adds
  // a kinematic defect, or fits worse by both the largest and the RMS point error (a fallback can
  // end there) gives the design back.
  const bool new_defect = !AddedKinematicDefects(seed.defects, refined.defects).empty();
  const bool worse = seed.max_point_error &&
                     (!refined.max_point_error ||
                      (*refined.max_point_error > *seed.max_point_error &&
                       refined.rms_point_error.value_or(0.0) > seed.rms_point_error.value_or(0.0)));
  if (worse || (seed.max_point_error && new_defect)) {
    ended = true;
    refined = seed;
    JudgeTransmission(data, &refined);
    result.notes.push_back("no refinement improved the design: it is given back unchanged");
  }
  refined.seed_max_point_error = seed.max_point_error;
  if (seed_transmission_kept && transmission(refined)) {
    result.notes.push_back(TransmissionNote(task.constraints));
  }
  result.mechanisms.push_back(refined);
  const auto text = [](const std::optional<double>& value) {
    if (!value) return std::string("none (not driven through the points)");
    char number[32];
    std::snprintf(number, sizeof(number), "%.6g", *value);
    return std::string(number);
  };
  result.notes.insert(result.notes.begin(),
                      "point error before: max " + text(seed.max_point_error) + ", RMS " +
                          text(seed.rms_point_error) + "; after: max " +
                          text(refined.max_point_error) + ", RMS " + text(refined.rms_point_error));
  if (data.points.size() >= 5) BoundErrors(data, free_timing, {}, &result);
  StageReport stage;
  stage.name = "four-bar refine";
  stage.seconds = Seconds(start);
  stage.best_max_point_error = refined.max_point_error;
  result.stages.push_back(stage);
  result.solve_seconds = Seconds(start);
  if (converged != nullptr) *converged = ended;
  return result;
}

}  // namespace linkfit
