// The constrained part of `linkfit bench` (see constrained_bench.h).
#include "bench/constrained_bench.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <sstream>

#include "apps/output_file.h"
#include "bench/percentile.h"
#include "fitting/model_choice.h"
#include "fitting/planar_motion.h"
#include "lib/design_constraints.h"
#include "lib/path_motion.h"
#include "lib/precision.h"
#include "lib/task_io.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The targets' ratio: a first design within 10 % of the reference (and the ranking's near tie,
// lib/design_constraints.h kNearTieRatio).
constexpr double kWithinRatio = 1.1;
// Fits within this many L of each other count as equal (exact fits differ by rounding): the
// path solver's floor for passing the points (PassTolerance).
constexpr double kExactFit = 1e-8;
// The reference design is on a bound when some bound's slack is at most this many L.
constexpr double kActiveSlack = 1e-3;
// A generated bound: links at this fraction of the exact designs' longest link.
constexpr double kLinkFraction = 0.8;
// A generated box: its cut side this many L inside the pivot it cuts off, its other sides this
// many L beyond the pivots and the data.
constexpr double kCutMargin = 0.25;
constexpr double kBoxReach = 4.0;
// Generated tasks: points or poses each.
constexpr int kItems = 10;
// Tasks per random family: full and quick runs.
constexpr int kFullTasks = 40;
constexpr int kQuickTasks = 3;
// Digits of the generated task files (round trip of every double).
constexpr int kDigits = 17;

// The classic problems, compiled in from data/classic_path_*.json (bench/CMakeLists.txt):
// {file name without .json, file text}. Their points, timings and bounds are the five cases of
// the public code of S. Nguyen-Van, Q. X. Lieu, N. Xuan-Mung, T. T. N. Nguyen, "A New Study on
// Optimization of Four-Bar Mechanisms Based on a Hybrid-Combined Differential Evolution and Jaya
// Algorithm", Symmetry 14(2):381, 2022 (github.com/sy-nguyen-van/
// Dimensional_Synthesis_Four_Bar_Mechanisms, src/cases/case1-5.py, src/config.py), cases the
// literature attributes to Kunjur & Krishnamurty (1997), Cabrera et al. (2002) and Acharyya &
// Mandal (2009): 1 vertical_line_6, 2 5_points_timed, 3 closed_18_points, 4 arc_6_points_timed,
// 5 ellipse_10_points. How their constraints map to linkfit's: user guide, "the constrained
// families".
struct ClassicTask {
  const char* name;
  const char* text;
};
constexpr ClassicTask kClassicTasks[] = {
#include "bench/classic_tasks.inc"
};

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// FNV-1a: a seed per family name, the same on every platform.
uint64_t NameHash(const std::string& text) {
  uint64_t hash = 1469598103934665603ull;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

// ---- what a result lists, as the targets see it ----

struct Listed {
  bool keeps = false;        // no violated constraint
  int defect_level = 2;      // DefectLevel (0: none; 1: only "transmission"; 2: kinematic)
  double rms = kInfinity;    // RMS point or pose error (infinity: not driven through the task);
                             // the largest for five exact points, as the ranking has it
  double slack = kInfinity;  // the smallest slack to a bound of the task, times L
  // Meets every point or pose within the data's precision (the ranking's first run of a group).
  bool within_precision = false;
};

struct Solved {
  double ms = 0.0;
  double length = 1.0;         // the task's L (the result's scale)
  std::vector<Listed> listed;  // in the listed order
};

// A keeper's rank group (the ranking rule: keepers, then defect-free, then those whose only
// defect is the transmission angle); -1 for a four-bar that violates a constraint or has a
// kinematic defect or no fit.
int KeeperLevel(const Listed& listed) {
  return listed.keeps && listed.defect_level < 2 && std::isfinite(listed.rms) ? listed.defect_level
                                                                              : -1;
}

// The best group present among `solved`'s keepers (0 or 1; 2 when none) and its best RMS.
std::pair<int, double> BestKeeper(const Solved& solved) {
  std::pair<int, double> best(2, kInfinity);
  for (const Listed& listed : solved.listed) {
    const int level = KeeperLevel(listed);
    if (level >= 0) best = std::min(best, std::make_pair(level, listed.rms));
  }
  return best;
}

// How far `point` is inside `box` (negative outside).
double BoxSlack(const PlanarBox& box, const Eigen::Vector2d& point) {
  return std::min({point.x() - box.min.x(), box.max.x() - point.x(), point.y() - box.min.y(),
                   box.max.y() - point.y()});
}

// The smallest slack to a bound that the task gives (link lengths, the pivots' boxes), in L.
double BoundSlack(const DesignConstraints& constraints, const FourBarLinks& links,
                  const std::vector<Eigen::Vector2d>& fixed_pivots,
                  const std::vector<Eigen::Vector2d>& moving_pivots, double length) {
  double slack = kInfinity;
  const std::vector<double> all = links.All();
  if (constraints.max_link_length && !all.empty()) {
    slack =
        std::min(slack, *constraints.max_link_length - *std::max_element(all.begin(), all.end()));
  }
  if (constraints.min_link_length && !all.empty()) {
    slack =
        std::min(slack, *std::min_element(all.begin(), all.end()) - *constraints.min_link_length);
  }
  if (constraints.fixed_pivots_box) {
    for (const Eigen::Vector2d& pivot : fixed_pivots) {
      slack = std::min(slack, BoxSlack(*constraints.fixed_pivots_box, pivot));
    }
  }
  if (constraints.moving_pivots_box) {
    for (const Eigen::Vector2d& pivot : moving_pivots) {
      slack = std::min(slack, BoxSlack(*constraints.moving_pivots_box, pivot));
    }
  }
  return slack / length;
}

// One listed four-bar as the ranking groups it: its violations, defects, largest and RMS error
// (the ranked fit: the RMS, or the largest where `fit_is_max`, for five exact points).
Listed ListedOf(const std::vector<std::string>& violates, const std::vector<std::string>& defects,
                const std::optional<double>& max, const std::optional<double>& rms, bool fit_is_max,
                double precision_fit) {
  Listed listed;
  listed.keeps = violates.empty();
  listed.defect_level = DefectLevel(defects);
  if (max && rms) {
    listed.rms = fit_is_max ? *max : *rms;
    listed.within_precision = *max <= precision_fit;
  }
  return listed;
}

Solved Summarize(const PathResult& result, const Task& task, double ms) {
  const DesignConstraints& constraints = task.constraints;
  const double precision_fit = PathPassTolerance(task.precision, result.scale);
  Solved solved;
  solved.ms = ms;
  solved.length = result.scale;
  for (const PathMechanismReport& report : result.mechanisms) {
    Listed listed = ListedOf(report.violates, report.defects, report.max_point_error,
                             report.rms_point_error, result.method == "exact", precision_fit);
    const PathFourBar& design = report.design;
    std::vector<Eigen::Vector2d> fixed = {design.input.fixed_pivot};
    if (design.output.type != DyadType::kPR) fixed.push_back(design.output.fixed_pivot);
    listed.slack = BoundSlack(constraints, PathFourBarLinks(design), fixed, {}, result.scale);
    solved.listed.push_back(listed);
  }
  return solved;
}

Solved Summarize(const PlanarMotionResult& result, const Task& task, double ms) {
  const DesignConstraints& constraints = task.constraints;
  const double precision_fit = PoseFitTolerance(task.precision, result.scale);
  Solved solved;
  solved.ms = ms;
  solved.length = result.scale;
  for (const MechanismReport& report : result.mechanisms) {
    // Five poses or fewer: the largest pose error is the fit (no RMS), as the ranking has it.
    const bool exact = result.method == "exact";
    Listed listed =
        ListedOf(report.violates, report.defects, report.max_pose_error,
                 exact ? report.max_pose_error : report.rms_pose_error, exact, precision_fit);
    const PlanarDyad& input = result.dyads[report.input_dyad].dyad;
    const PlanarDyad& output = result.dyads[report.output_dyad].dyad;
    std::vector<Eigen::Vector2d> fixed, moving;
    for (const PlanarDyad* dyad : {&input, &output}) {
      if (dyad->type != DyadType::kPR) fixed.push_back(dyad->fixed_pivot);
      if (dyad->type != DyadType::kRP) moving.push_back(dyad->moving_pivot);
    }
    listed.slack =
        BoundSlack(constraints, MotionFourBarLinks(input, output), fixed, moving, result.scale);
    solved.listed.push_back(listed);
  }
  return solved;
}

// Solves `task` (path or planar motion) at `effort` with `options`.
Solved Solve(Task task, Effort effort, const TaskSolverOptions& options) {
  task.effort = effort;
  const auto begin = std::chrono::steady_clock::now();
  if (task.problem == ProblemKind::kPath) {
    const PathResult result = SolvePathTask(task, options);
    return Summarize(result, task, MillisecondsSince(begin));
  }
  const PlanarMotionResult result = SolvePlanarTask(task, options);
  return Summarize(result, task, MillisecondsSince(begin));
}

// ---- the families ----

// A family's next task: its file text (read back through the parser for the solve).
using Generator = std::function<std::string(std::mt19937_64& rng)>;

std::string Number(double value) { return testing::Printed(value, kDigits); }

std::string BoxText(const PlanarBox& box) {
  return "[[" + Number(box.min.x()) + ", " + Number(box.min.y()) + "], [" + Number(box.max.x()) +
         ", " + Number(box.max.y()) + "]]";
}

// `text` (a task object) with the constraints object `constraints` added.
std::string WithConstraints(const std::string& text, const std::string& constraints) {
  const size_t end = text.rfind('}');
  return text.substr(0, end) + ", \"constraints\": {" + constraints + "}}";
}

// A box about `centre` of half-width kBoxReach * length that holds every pivot of `designs`
// with kBoxReach * length to spare, with one side (`side`: 0 x max, 1 x min, 2 y max, 3 y min)
// cut so that every design has a pivot kCutMargin * length beyond it. Nothing when the cut
// leaves less than one L of box.
std::optional<PlanarBox> CuttingBox(const std::vector<std::vector<Eigen::Vector2d>>& designs,
                                    const Eigen::Vector2d& centre, double length, int side) {
  PlanarBox box;
  box.min = centre - Eigen::Vector2d::Constant(kBoxReach * length);
  box.max = centre + Eigen::Vector2d::Constant(kBoxReach * length);
  for (const std::vector<Eigen::Vector2d>& pivots : designs) {
    for (const Eigen::Vector2d& pivot : pivots) {
      box.min = box.min.cwiseMin(pivot - Eigen::Vector2d::Constant(kBoxReach * length));
      box.max = box.max.cwiseMax(pivot + Eigen::Vector2d::Constant(kBoxReach * length));
    }
  }
  const int axis = side / 2;
  const bool upper = side % 2 == 0;
  // The cut: the design that reaches least far beyond it still has its farthest pivot
  // kCutMargin * length beyond.
  double cut = upper ? kInfinity : -kInfinity;
  for (const std::vector<Eigen::Vector2d>& pivots : designs) {
    double reach = upper ? -kInfinity : kInfinity;
    for (const Eigen::Vector2d& pivot : pivots) {
      reach = upper ? std::max(reach, pivot[axis]) : std::min(reach, pivot[axis]);
    }
    cut = upper ? std::min(cut, reach - kCutMargin * length)
                : std::max(cut, reach + kCutMargin * length);
  }
  if (upper) {
    box.max[axis] = cut;
  } else {
    box.min[axis] = cut;
  }
  if (!(box.max[axis] - box.min[axis] >= length)) return std::nullopt;
  return box;
}

// A box cutting every design (CuttingBox), the side drawn from `rng` (the next sides tried in
// turn when a cut leaves too little).
std::optional<PlanarBox> DrawBox(std::mt19937_64& rng,
                                 const std::vector<std::vector<Eigen::Vector2d>>& designs,
                                 const Eigen::Vector2d& centre, double length) {
  const int first = static_cast<int>(rng() % 4);
  for (int k = 0; k < 4; ++k) {
    const std::optional<PlanarBox> box = CuttingBox(designs, centre, length, (first + k) % 4);
    if (box) return box;
  }
  return std::nullopt;
}

double LongestLink(const FourBarLinks& links) {
  const std::vector<double> all = links.All();
  return *std::max_element(all.begin(), all.end());
}

// Timed path, kItems points of a random crank-driven 4R: the bounds of `kind` ("link", "box",
// "link and box") against every exact four-bar (the generating one and its cognate driven with
// the same timing).
std::string TimedPathTask(std::mt19937_64& rng, const std::string& kind) {
  for (;;) {
    const testing::GeneratedPathTask generated =
        testing::RandomPathTask(rng, DyadType::kRR, kItems);
    const double length = testing::PathLength(generated.points);
    std::vector<PathFourBar> exact = {generated.four_bar};
    for (const PathFourBar& cognate : CurveCognates(generated.four_bar)) {
      const PathFourBarAnalysis analysis =
          AnalyzePathFourBar(cognate, generated.points, generated.input_angles, length);
      if (analysis.rms_point_error && *analysis.rms_point_error <= 1e-9 * length) {
        exact.push_back(cognate);
      }
    }
    std::string constraints;
    if (kind.find("link") != std::string::npos) {
      double shortest = kInfinity;
      for (const PathFourBar& design : exact) {
        shortest = std::min(shortest, LongestLink(PathFourBarLinks(design)));
      }
      constraints = "\"max_link_length\": " + Number(kLinkFraction * shortest);
    }
    if (kind.find("box") != std::string::npos) {
      std::vector<std::vector<Eigen::Vector2d>> pivots;
      for (const PathFourBar& design : exact) {
        pivots.push_back({design.input.fixed_pivot, design.output.fixed_pivot});
      }
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for (const Eigen::Vector2d& point : generated.points) centroid += point / kItems;
      const std::optional<PlanarBox> box = DrawBox(rng, pivots, centroid, length);
      if (!box) continue;  // drawn again
      constraints +=
          std::string(constraints.empty() ? "" : ", ") + "\"fixed_pivots_box\": " + BoxText(*box);
    }
    return WithConstraints(testing::PathText(generated.points, generated.input_angles, kDigits),
                           constraints);
  }
}

// Planar motion, `count` poses of a random 4R (kItems; five: minimal data, where the four-bars
// linkfit chooses within the bounds answer, issue 35): the bound of `kind` ("link", "fixed box",
// "moving box") against the generating four-bar (the only exact one of more than five poses).
std::string PlanarMotionBoundTask(std::mt19937_64& rng, const std::string& kind,
                                  int count = kItems) {
  for (;;) {
    const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, count);
    const double length = CharacteristicLength(generated.poses);
    std::string constraints;
    if (kind == "link") {
      constraints = "\"max_link_length\": " +
                    Number(kLinkFraction *
                           LongestLink(MotionFourBarLinks(generated.input, generated.output)));
    } else {
      const bool fixed = kind == "fixed box";
      const std::vector<Eigen::Vector2d> pivots =
          fixed ? std::vector<Eigen::Vector2d>{generated.input.fixed_pivot,
                                               generated.output.fixed_pivot}
                : std::vector<Eigen::Vector2d>{generated.input.moving_pivot,
                                               generated.output.moving_pivot};
      // Fixed pivots about the pose origins' centroid (Sigma); moving pivots about E's origin.
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      if (fixed) {
        for (const PlanarPose& pose : generated.poses) centre += pose.origin_in_fixed / count;
      }
      const std::optional<PlanarBox> box = DrawBox(rng, {pivots}, centre, length);
      if (!box) continue;
      constraints =
          std::string(fixed ? "\"fixed_pivots_box\": " : "\"moving_pivots_box\": ") + BoxText(*box);
    }
    return WithConstraints(testing::PlanarMotionText(generated.poses, kDigits), constraints);
  }
}

struct Family {
  std::string name;
  int tasks = 0;
  Generator generate;  // random families
  const ClassicTask* classic = nullptr;
};

std::vector<Family> Families(const BenchOptions& options) {
  const int tasks = options.constrained_tasks > 0 ? options.constrained_tasks
                    : options.quick               ? kQuickTasks
                                                  : kFullTasks;
  std::vector<Family> families;
  for (const std::string kind : {"link", "box", "link and box"}) {
    Family family;
    family.name = "timed path " + std::to_string(kItems) + " points, " +
                  (kind == "box"    ? "fixed box"
                   : kind == "link" ? "link bound"
                                    : "link bound + box");
    family.tasks = tasks;
    family.generate = [kind](std::mt19937_64& rng) { return TimedPathTask(rng, kind); };
    families.push_back(family);
  }
  for (const std::string kind : {"link", "fixed box", "moving box"}) {
    Family family;
    family.name = "planar motion " + std::to_string(kItems) + " poses, " +
                  (kind == "link" ? std::string("link bound") : kind);
    family.tasks = tasks;
    family.generate = [kind](std::mt19937_64& rng) { return PlanarMotionBoundTask(rng, kind); };
    families.push_back(family);
  }
  for (const std::string kind : {"link", "fixed box"}) {
    Family family;
    family.name = "planar motion 5 poses, " + (kind == "link" ? std::string("link bound") : kind);
    family.tasks = tasks;
    family.generate = [kind](std::mt19937_64& rng) { return PlanarMotionBoundTask(rng, kind, 5); };
    families.push_back(family);
  }
  for (const ClassicTask& classic : kClassicTasks) {
    Family family;
    // "classic_path_closed_18_points" is "classic: closed 18 points".
    std::string name = classic.name;
    const std::string prefix = "classic_path_";
    if (name.rfind(prefix, 0) == 0) name = name.substr(prefix.size());
    std::replace(name.begin(), name.end(), '_', ' ');
    family.name = "classic: " + name;
    family.tasks = 1;
    family.classic = &classic;
    families.push_back(family);
  }
  // BenchOptions::family: "constrained" or "constrained:<part of a name>".
  if (!options.family.empty()) {
    const size_t colon = options.family.find(':');
    if (options.family.substr(0, colon) != "constrained") return {};
    if (colon != std::string::npos) {
      const std::string part = options.family.substr(colon + 1);
      families.erase(std::remove_if(families.begin(), families.end(),
                                    [&](const Family& family) {
                                      return family.name.find(part) == std::string::npos;
                                    }),
                     families.end());
    }
  }
  return families;
}

// ---- the rows ----

// What one effort did on one task (the file comment's measures).
struct Judged {
  double ms = 0.0;
  bool within = false;
  bool first_is_best = false;
  double ratio = kInfinity;
  std::vector<std::string> causes;  // why a measure failed, and what else is worth counting
};

// Whether a keeper of group `level` in `solved` meets the task within the data's precision.
bool AnyWithinPrecision(const Solved& solved, int level) {
  return std::any_of(solved.listed.begin(), solved.listed.end(), [&](const Listed& listed) {
    return KeeperLevel(listed) == level && listed.within_precision;
  });
}

// `reference`: the best group and RMS of a keeper over every solve of the task (BestKeeper);
// `reference_within_precision`: that keeper meets the task within the data's precision.
Judged Judge(const Solved& solved, const std::pair<int, double>& reference,
             bool reference_within_precision) {
  Judged judged;
  judged.ms = solved.ms;
  if (solved.listed.empty()) {
    judged.causes.push_back("nothing listed");
    return judged;
  }
  const Listed& first = solved.listed.front();
  const double slack = kExactFit * solved.length;
  const std::pair<int, double> own = BestKeeper(solved);
  const int level = KeeperLevel(first);
  if (own.first == 2) {
    judged.causes.push_back("no keeper listed");
    return judged;
  }
  if (level < 0) {
    judged.causes.push_back("first ranked before a keeper");  // a ranking fault
    return judged;
  }
  // Within 10 %: a keeper without a kinematic defect, fitting within 10 % of the reference (or
  // both within the data's precision).
  judged.ratio = reference.second > 0.0 ? first.rms / reference.second
                                        : (first.rms <= slack ? 1.0 : kInfinity);
  judged.within = first.rms <= kWithinRatio * reference.second + slack ||
                  (first.within_precision && reference_within_precision);
  if (!judged.within) judged.causes.push_back("beyond 10 % of the reference");
  // The best of its list by the ranking rule: of the best group there (defect-free before a
  // transmission defect), those within the data's precision first (any of them is as good at
  // that precision), then by fit with near ties.
  if (level > own.first) {
    judged.causes.push_back("first ranked before a defect-free keeper");  // a ranking fault
  } else {
    judged.first_is_best =
        first.within_precision ||
        (!AnyWithinPrecision(solved, level) && first.rms <= kWithinRatio * own.second + slack);
    if (!judged.first_is_best) judged.causes.push_back("not the best of its group");
  }
  // What the rule costs: a defect-free first that fits far worse than a keeper listed below it
  // whose only defect is the transmission angle.
  for (const Listed& listed : solved.listed) {
    if (level == 0 && KeeperLevel(listed) == 1 && 10.0 * listed.rms < first.rms) {
      judged.causes.push_back(
          "(first defect-free, 10x worse than a listed keeper with a transmission defect)");
      break;
    }
  }
  return judged;
}

// `no_keeper`: tasks where no solve found a keeper at all (none to rank first): left out of the
// shares and ratios, and listed in the detail.
ConstrainedRow MakeRow(const std::string& family, const std::string& effort,
                       const std::vector<Judged>& judged, const std::vector<bool>& active,
                       const std::vector<bool>& transmission_only,
                       const std::vector<bool>& no_keeper, const std::vector<double>& long_ms) {
  ConstrainedRow row;
  row.family = family;
  row.effort = effort;
  row.tasks = static_cast<int>(judged.size());
  std::vector<double> times, ratios;
  int within = 0, best = 0, on_bound = 0, counted = 0;
  // Misses by cause: their task numbers (with the ratio where the first keeps).
  std::vector<std::pair<std::string, std::vector<std::string>>> causes;
  std::vector<std::string> without_keeper;
  for (size_t t = 0; t < judged.size(); ++t) {
    times.push_back(judged[t].ms);
    if (no_keeper[t]) {
      without_keeper.push_back(std::to_string(t));
      continue;
    }
    ++counted;
    ratios.push_back(judged[t].ratio);
    within += judged[t].within;
    best += judged[t].first_is_best;
    on_bound += active[t];
    for (const std::string& cause : judged[t].causes) {
      auto found = std::find_if(causes.begin(), causes.end(),
                                [&](const auto& entry) { return entry.first == cause; });
      if (found == causes.end()) {
        causes.emplace_back(cause, std::vector<std::string>());
        found = causes.end() - 1;
      }
      char text[48];
      if (std::isfinite(judged[t].ratio) && cause.find("10 %") != std::string::npos) {
        std::snprintf(text, sizeof(text), "%zu (%.3g)", t, judged[t].ratio);
      } else {
        std::snprintf(text, sizeof(text), "%zu", t);
      }
      found->second.push_back(text);
    }
  }
  // Tasks whose best keeper has a transmission defect (none found without): judged in that
  // group, as the ranking does.
  std::vector<std::string> transmission;
  for (size_t t = 0; t < transmission_only.size(); ++t) {
    if (transmission_only[t]) transmission.push_back(std::to_string(t));
  }
  if (!transmission.empty()) {
    causes.emplace_back("(no defect-free keeper found: reference with a transmission defect)",
                        transmission);
  }
  if (!without_keeper.empty()) {
    causes.emplace_back("(no keeper found by any solve: not counted)", without_keeper);
  }
  for (const auto& [cause, tasks] : causes) {
    std::string list;
    for (const std::string& task : tasks) list += (list.empty() ? "" : " ") + task;
    row.detail += std::string(row.detail.empty() ? "" : "; ") + cause + " " +
                  std::to_string(tasks.size()) + ": task " + list;
  }
  const double count = std::max<double>(1.0, static_cast<double>(counted));
  row.median_ms = Percentile(times, 0.5);
  row.worst_ms = Percentile(times, 1.0);
  row.share_within_10pct = within / count;
  row.share_first_is_best = best / count;
  row.median_ratio = Percentile(ratios, 0.5);
  row.worst_ratio = Percentile(ratios, 1.0);
  row.share_bound_active = on_bound / count;
  row.long_median_ms = Percentile(long_ms, 0.5);
  return row;
}

void PrintRow(std::FILE* table, const ConstrainedRow& row) {
  if (table == nullptr) return;
  std::fprintf(
      table, "%-44s %-9s %5d %10.1f %10.1f %7.1f%% %7.1f%% %9.4g %9.4g %7.1f%% %10.1f  %s\n",
      row.family.c_str(), row.effort.c_str(), row.tasks, row.median_ms, row.worst_ms,
      100.0 * row.share_within_10pct, 100.0 * row.share_first_is_best, row.median_ratio,
      row.worst_ratio, 100.0 * row.share_bound_active, row.long_median_ms, row.detail.c_str());
  std::fflush(table);
}

std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// A task file name part: letters and digits, the rest '_'.
std::string FileName(const std::string& text) {
  std::string name;
  for (const char c : text) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

}  // namespace

TaskSolverOptions LongSearchOptions(double multiplier) {
  TaskSolverOptions options;
  const auto scaled = [&](int count) { return static_cast<int>(std::lround(count * multiplier)); };
  // Path problems: the crank search's budget, its basins refined, and the seeds.
  options.path_search.max_evaluations = scaled(options.path_search.max_evaluations);
  // The evaluations, not the clock, end the run (reproducible); the limit only guards.
  options.path_search.time_limit *= 10.0 * multiplier;
  options.path_search.refine_count *= 4;
  options.path_search.runs *= 4;
  options.path_search.seed = 101;  // other draws than the default's
  options.path_seed_subsets *= 4;
  options.path_refined *= 4;
  // Planar motion: the dyad search's budget and polished optima, the seeds, the dyads kept and
  // the four-bars refined.
  options.search.max_evaluations = scaled(options.search.max_evaluations);
  options.search.time_limit *= 10.0 * multiplier;
  options.search.polish_count *= 4;
  options.search.seed = 101;
  options.seed_subsets *= 4;
  options.max_dyads *= 2;
  options.refined_mechanisms *= 3;
  return options;
}

std::vector<ConstrainedRow> RunConstrainedBench(const BenchOptions& options, std::FILE* table) {
  const std::vector<Family> families = Families(options);
  std::vector<ConstrainedRow> rows;
  if (families.empty()) return rows;
  if (table != nullptr) {
    std::fprintf(table,
                 "\nconstrained families (%s, seed %llu): the first listed design against the "
                 "best keeper found (the long search: thorough, NLopt budgets x25, and both "
                 "efforts); within = a keeper without kinematic defect whose RMS is within 10 %% "
                 "of that reference (defect-free where one was found); best = the best of its own "
                 "list by the ranking rule (keepers, defect-free, within precision, fit with 10 %% "
                 "near ties); active = the reference on a bound\n",
                 options.quick ? "quick" : "full", static_cast<unsigned long long>(options.seed));
    std::fprintf(table, "%-44s %-9s %5s %10s %10s %8s %8s %9s %9s %8s %10s  %s\n", "family",
                 "effort", "tasks", "median_ms", "worst_ms", "within", "best", "med_ratio",
                 "worst_ratio", "active", "long_ms", "detail");
  }
  const TaskSolverOptions defaults;
  const TaskSolverOptions long_search = LongSearchOptions();
  for (const Family& family : families) {
    std::mt19937_64 rng(options.seed ^ NameHash(family.name));
    std::vector<Judged> judged[2];
    std::vector<bool> active, transmission_only, no_keeper;
    std::vector<double> long_ms;
    for (int t = 0; t < family.tasks; ++t) {
      const std::string text =
          family.classic != nullptr ? std::string(family.classic->text) : family.generate(rng);
      const Task task = ParseTask(text, family.name);
      const Solved balanced = Solve(task, Effort::kBalanced, defaults);
      const Solved thorough = Solve(task, Effort::kThorough, defaults);
      const Solved longer = Solve(task, Effort::kThorough, long_search);
      // The reference: the best keeper (group, then RMS) found by any of the three; its bound
      // slack.
      std::pair<int, double> reference(2, kInfinity);
      double slack = kInfinity;
      bool reference_within_precision = false;
      for (const Solved* solved : {&longer, &balanced, &thorough}) {
        for (const Listed& listed : solved->listed) {
          const int level = KeeperLevel(listed);
          if (level >= 0 && std::make_pair(level, listed.rms) < reference) {
            reference = std::make_pair(level, listed.rms);
            slack = listed.slack;
            reference_within_precision = listed.within_precision;
          }
        }
      }
      judged[0].push_back(Judge(balanced, reference, reference_within_precision));
      judged[1].push_back(Judge(thorough, reference, reference_within_precision));
      transmission_only.push_back(reference.first == 1);
      no_keeper.push_back(reference.first == 2);
      active.push_back(std::abs(slack) <= kActiveSlack);
      long_ms.push_back(longer.ms);
      const auto missed = [](const Judged& judged) {
        return !judged.within || !judged.first_is_best;
      };
      if (!options.wrong_dir.empty() && (missed(judged[0].back()) || missed(judged[1].back()))) {
        std::error_code error;
        std::filesystem::create_directories(options.wrong_dir, error);
        const std::string path = options.wrong_dir + "/constrained_" + FileName(family.name) + "-" +
                                 std::to_string(t) + ".json";
        WriteOutputFile(path, "--wrong-dir", text + "\n");
      }
    }
    const char* efforts[] = {"balanced", "thorough"};
    for (int e = 0; e < 2; ++e) {
      rows.push_back(MakeRow(family.name, efforts[e], judged[e], active, transmission_only,
                             no_keeper, long_ms));
      PrintRow(table, rows.back());
    }
  }
  return rows;
}

std::string ConstrainedCsv(const std::vector<ConstrainedRow>& rows) {
  std::ostringstream csv;
  csv << "family,effort,tasks,median_ms,worst_ms,share_within_10pct,share_first_is_best,"
         "median_ratio,worst_ratio,share_bound_active,long_median_ms,detail\n";
  for (const ConstrainedRow& row : rows) {
    csv << Quoted(row.family) << "," << row.effort << "," << row.tasks << ","
        << FormatNumber(row.median_ms) << "," << FormatNumber(row.worst_ms) << ","
        << FormatNumber(row.share_within_10pct) << "," << FormatNumber(row.share_first_is_best)
        << "," << FormatNumber(row.median_ratio) << "," << FormatNumber(row.worst_ratio) << ","
        << FormatNumber(row.share_bound_active) << "," << FormatNumber(row.long_median_ms) << ","
        << Quoted(row.detail) << "\n";
  }
  return csv.str();
}

}  // namespace linkfit
