// The stability sweep (see extremes_bench.h).
#include "bench/extremes_bench.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "apps/output_file.h"
#include "fitting/model_choice.h"
#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "lib/precision.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spatial.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// What one task gave.
struct Verdict {
  bool finite = true;        // no NaN or infinity anywhere in the result
  bool noted = false;        // an "ill-conditioned" note with a condition estimate
  double error = kInfinity;  // relative error of the mechanism (the case defines it)
  double tolerance = 0.0;    // when positive, replaces the row's tolerance for this task
  std::string kind;          // e.g. the type returned or the model chosen (for `detail`)
  std::string task_text;     // the task file, when the case has one (BenchOptions::wrong_dir)
  std::string expected;      // the generating mechanism, in words (written beside task_text)
  // Not counted, another task drawn: the case measures something the task cannot show (the
  // rounded-data paths: the solver misses the task at full precision already).
  bool redraw = false;
};

// The solvers' "ill-conditioned" notes (the motion solvers' carry the condition estimate; the
// timed-path solver's names the far pivots of the four-bars it dropped).
bool HasIllConditionedNote(const std::vector<std::string>& notes) {
  return std::any_of(notes.begin(), notes.end(), [](const std::string& note) {
    return note.find("ill-conditioned") != std::string::npos;
  });
}

bool Finite(const std::optional<double>& value) { return !value || std::isfinite(*value); }

bool AllFinite(const PlanarMotionResult& result) {
  for (const DyadReport& report : result.dyads) {
    if (!report.dyad.AllFinite() || !std::isfinite(report.max_residual) ||
        !Finite(report.rms_residual) || !Finite(report.seed_rms_residual)) {
      return false;
    }
  }
  for (const MechanismReport& mechanism : result.mechanisms) {
    if (!Finite(mechanism.max_pose_error) || !Finite(mechanism.rms_pose_error) ||
        !Finite(mechanism.seed_max_pose_error) || !Finite(mechanism.transmission_min_deg) ||
        !Finite(mechanism.transmission_max_deg)) {
      return false;
    }
  }
  return std::isfinite(result.scale);
}

bool AllFinite(const SpatialMotionResult& result) {
  for (const SpatialDyadReport& report : result.dyads) {
    if (!report.dyad.AllFinite() || !std::isfinite(report.max_residual) ||
        !Finite(report.rms_residual)) {
      return false;
    }
  }
  for (const PlatformReport& platform : result.mechanisms) {
    if (!Finite(platform.max_pose_error)) return false;
  }
  if (result.planar && !AllFinite(*result.planar)) return false;
  if (result.spherical &&
      !(result.spherical->in_fixed.allFinite() && result.spherical->in_moving.allFinite() &&
        std::isfinite(result.spherical->sphericity))) {
    return false;
  }
  return std::isfinite(result.scale);
}

bool AllFinite(const PathResult& result) {
  for (const PathMechanismReport& mechanism : result.mechanisms) {
    if (!mechanism.design.input.AllFinite() || !mechanism.design.output.AllFinite() ||
        !mechanism.design.coupler_point.allFinite() || !Finite(mechanism.max_point_error) ||
        !Finite(mechanism.rms_point_error)) {
      return false;
    }
  }
  return std::isfinite(result.scale);
}

void Tally(const Verdict& verdict, ExtremeRow* row) {
  ++row->tasks;
  if (!verdict.finite) {
    ++row->non_finite;
  } else if (verdict.error <= (verdict.tolerance > 0.0 ? verdict.tolerance : row->tolerance)) {
    ++row->right;
  } else if (verdict.noted) {
    ++row->noted;
  } else {
    ++row->wrong;
  }
  if (verdict.finite && std::isfinite(verdict.error)) {
    row->worst_error = std::max(row->worst_error, verdict.error);
  }
}

// Counts of the verdicts' kinds, e.g. "RR 12, PR 8".
std::string KindCounts(const std::vector<std::string>& kinds) {
  std::vector<std::pair<std::string, int>> counts;
  for (const std::string& kind : kinds) {
    if (kind.empty()) continue;
    auto found = std::find_if(counts.begin(), counts.end(),
                              [&](const auto& entry) { return entry.first == kind; });
    if (found == counts.end()) {
      counts.emplace_back(kind, 1);
    } else {
      ++found->second;
    }
  }
  std::string text;
  for (const auto& [kind, count] : counts) {
    text += (text.empty() ? "" : "; ") + kind + " " + std::to_string(count);
  }
  return text;
}

// ---- planar motion, five poses ----

// The generating dyads' recovery error (random_mechanism.h's DyadDistance relative to each dyad's
// own size) after mapping the answer back through sigma (fixed) and epsilon (moving frame).
double PlanarRecovery(const testing::GeneratedTask& generated, const PlanarMotionResult& result,
                      const Similarity2& sigma_back, const Similarity2& epsilon_back) {
  std::vector<PlanarDyad> dyads;
  for (const DyadReport& report : result.dyads) {
    dyads.push_back(TransformDyad(report.dyad, sigma_back, epsilon_back));
  }
  return std::max(
      testing::NearestDyadDistance(dyads, generated.input,
                                   testing::DyadScale(generated.input, generated.poses)),
      testing::NearestDyadDistance(dyads, generated.output,
                                   testing::DyadScale(generated.output, generated.poses)));
}

// Solves the generated task seen through sigma (fixed frame) and epsilon (moving frame).
Verdict SolveTransformedPlanar(const testing::GeneratedTask& generated, const Similarity2& sigma,
                               const Similarity2& epsilon) {
  std::vector<PlanarPose> poses;
  for (const PlanarPose& pose : generated.poses)
    poses.push_back(TransformPose(pose, sigma, epsilon));
  const PlanarMotionResult result = SolvePlanarTask(PlanarMotionTask(poses));
  Verdict verdict;
  verdict.finite = AllFinite(result);
  verdict.noted = HasIllConditionedNote(result.notes);
  verdict.error = PlanarRecovery(generated, result, sigma.Inverse(), epsilon.Inverse());
  return verdict;
}

// ---- spatial motion, seven poses ----

using testing::PlantedSpatialTask;
using testing::RandomPlatformTask;

Verdict SolveTransformedSpatial(const PlantedSpatialTask& generated, const Similarity3& sigma,
                                const Similarity3& epsilon) {
  // TransformSpatialPose takes the maps from the new frames to the old ones.
  const Similarity3 sigma_back = sigma.Inverse(), epsilon_back = epsilon.Inverse();
  std::vector<DualQuaternion> poses;
  for (const DualQuaternion& pose : generated.poses) {
    poses.push_back(TransformSpatialPose(pose, sigma_back, epsilon_back));
  }
  const SpatialMotionResult result = SolveSpatialTask(SpatialMotionTask(poses));
  Verdict verdict;
  verdict.finite = AllFinite(result);
  verdict.noted = HasIllConditionedNote(result.notes);
  std::vector<SpatialDyad> dyads;
  for (const SpatialDyadReport& report : result.dyads) {
    dyads.push_back(TransformSpatialDyad(report.dyad, sigma_back, epsilon_back));
  }
  verdict.error = 0.0;
  for (const SpatialDyad& expected : generated.planted) {
    verdict.error = std::max(verdict.error, testing::NearestSpatialDyadDistance(dyads, expected));
  }
  return verdict;
}

// ---- path, five timed points ----

// The generating four-bar's recovery error relative to its size (its largest pivot or point
// distance from the points' centroid, never less than L), as linkfit_bench measures it.
double PathRecovery(const testing::GeneratedPathTask& generated, const PathResult& result,
                    const Similarity2& sigma_back) {
  const double length = testing::PathLength(generated.points);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : generated.points) {
    centroid += point / static_cast<double>(generated.points.size());
  }
  const PathFourBar& g = generated.four_bar;
  double size = length;
  for (const Eigen::Vector2d& p : {g.input.fixed_pivot, g.input.moving_pivot, g.output.fixed_pivot,
                                   g.output.moving_pivot, g.output.line_point, g.coupler_point}) {
    size = std::max(size, (p - centroid).norm());
  }
  double best = kInfinity;
  for (const PathMechanismReport& mechanism : result.mechanisms) {
    // Path designs live in Sigma (E coincides with it at the first point): one map for all.
    PathFourBar found = mechanism.design;
    found.input = TransformDyad(found.input, sigma_back, sigma_back);
    found.output = TransformDyad(found.output, sigma_back, sigma_back);
    found.coupler_point = sigma_back.Apply(found.coupler_point);
    best = std::min(best, testing::PathFourBarDistance(found, g, length) * length / size);
  }
  return best;
}

Verdict SolveTransformedPath(const testing::GeneratedPathTask& generated,
                             const Similarity2& sigma) {
  Task task;
  task.problem = ProblemKind::kPath;
  for (size_t j = 0; j < generated.points.size(); ++j) {
    TimedPoint point;
    point.point_in_fixed = sigma.Apply(generated.points[j]);
    point.input_angle = generated.input_angles[j] + sigma.angle;
    task.points.push_back(point);
  }
  const PathResult result = SolvePathTask(task);
  Verdict verdict;
  verdict.finite = AllFinite(result);
  verdict.noted = HasIllConditionedNote(result.notes);
  verdict.error = PathRecovery(generated, result, sigma.Inverse());
  return verdict;
}

// Makes the poses of a 4R with a huge output radius exact to rounding. The generated poses
// (AssembleFourBar with the centre stored R away) satisfy the circle only to ulp(R); here the
// circle is taken through the first pose's output pivot x0 with the unit normal n towards the
// centre, n . (p - x0) = |p - x0|^2 / (2 R), which keeps its digits, and every later pose is
// turned about the input's moving pivot (so that the input stays satisfied) by Newton steps
// on it.
void ExactOnCircle(const PlanarDyad& input, double radius, testing::GeneratedTask* task) {
  const PlanarDyad& output = task->output;
  const Eigen::Vector2d x0 = task->poses.front().ToFixed(output.moving_pivot);
  const Eigen::Vector2d normal = (output.fixed_pivot - x0) / radius;  // unit (as constructed)
  for (size_t j = 1; j < task->poses.size(); ++j) {
    PlanarPose& pose = task->poses[j];
    for (int iteration = 0; iteration < 4; ++iteration) {
      const Eigen::Vector2d pin = pose.ToFixed(input.moving_pivot);
      const Eigen::Vector2d offset = pose.ToFixed(output.moving_pivot) - x0;
      const double f = normal.dot(offset) - offset.squaredNorm() / (2.0 * radius);
      // d(offset)/d(phi) for a turn by phi about the pin.
      const Eigen::Vector2d arm = offset + x0 - pin;
      const Eigen::Vector2d velocity(-arm.y(), arm.x());
      const double slope = (normal - offset / radius).dot(velocity);
      if (slope == 0.0) break;
      const double phi = -f / slope;
      const Eigen::Vector2d origin = pose.origin_in_fixed - pin;
      pose.origin_in_fixed =
          pin + Eigen::Vector2d(std::cos(phi) * origin.x() - std::sin(phi) * origin.y(),
                                std::sin(phi) * origin.x() + std::cos(phi) * origin.y());
      pose.theta += phi;
    }
  }
}

// ---- rounded data: tasks printed to a few significant digits and read back ----

std::string Coordinates(const Eigen::VectorXd& point) {
  std::string text = "[";
  for (Eigen::Index i = 0; i < point.size(); ++i) {
    char number[32];
    std::snprintf(number, sizeof(number), "%s%.17g", i > 0 ? ", " : "", point[i]);
    text += number;
  }
  return text + "]";
}

// A generating dyad in words, for the files BenchOptions::wrong_dir gets.
std::string DyadText(const PlanarDyad& dyad) {
  std::string text = DyadTypeName(dyad.type);
  if (dyad.type == DyadType::kRR) {
    text += " fixed_pivot " + Coordinates(dyad.fixed_pivot) + " moving_pivot " +
            Coordinates(dyad.moving_pivot) + " radius " + std::to_string(dyad.radius);
  } else {
    text += (dyad.type == DyadType::kPR ? " moving_pivot " + Coordinates(dyad.moving_pivot)
                                        : " fixed_pivot " + Coordinates(dyad.fixed_pivot)) +
            " line_point " + Coordinates(dyad.line_point) + " line_direction " +
            Coordinates(dyad.line_direction);
  }
  return text + "\n";
}

std::string DyadText(const SpatialDyad& dyad) {
  return "SS fixed_pivot " + Coordinates(dyad.fixed_pivot) + " moving_pivot " +
         Coordinates(dyad.moving_pivot) + " radius " + std::to_string(dyad.radius) + "\n";
}

using testing::RoundedRecovery;
using testing::SaysTooCoarse;

// Planar motion from rounded data: both generating dyads within their bounds.
Verdict SolveRoundedPlanar(const testing::GeneratedTask& generated, int digits) {
  const std::string text = testing::PlanarMotionText(generated.poses, digits);
  const Task task = testing::ReadRounded(text);
  const PlanarMotionResult result = SolvePlanarTask(task);
  Verdict verdict;
  verdict.task_text = text;
  verdict.expected = DyadText(generated.input) + DyadText(generated.output);
  verdict.finite = AllFinite(result);
  bool undetermined = false;
  verdict.error = std::max(RoundedRecovery(generated.input, result.dyads, task.precision,
                                           task.planar_poses, &undetermined),
                           RoundedRecovery(generated.output, result.dyads, task.precision,
                                           task.planar_poses, &undetermined));
  verdict.noted = undetermined || SaysTooCoarse(result.notes);
  verdict.tolerance = 1.0;
  // The type the generating output came back as.
  const double scale = testing::DyadScale(generated.output, generated.poses);
  double nearest = kInfinity;
  for (const DyadReport& report : result.dyads) {
    const PlanarDyad& dyad = report.dyad;
    const double distance =
        generated.output.type == DyadType::kRP
            ? (dyad.type == DyadType::kPR
                   ? kInfinity
                   : (dyad.fixed_pivot - generated.output.fixed_pivot).norm())
            : (dyad.type == DyadType::kRP
                   ? kInfinity
                   : (dyad.moving_pivot - generated.output.moving_pivot).norm());
    if (distance < nearest && distance < 0.1 * scale) {
      nearest = distance;
      verdict.kind = DyadTypeName(dyad.type);
    }
  }
  return verdict;
}

// A rounded spatial task text read and solved: the verdict's task file, finiteness and model.
Verdict SolveRoundedText(const std::string& text, Task* task, SpatialMotionResult* result) {
  *task = testing::ReadRounded(text);
  *result = SolveSpatialTask(*task);
  Verdict verdict;
  verdict.task_text = text;
  verdict.finite = AllFinite(*result);
  verdict.kind = result->model;
  return verdict;
}

// Seven poses of a spherical motion (random rotations about a random centre) from rounded data:
// solved as spherical (SolveSpatialMotion's model "spherical"), the centre within 100 relative
// precisions of L.
Verdict SolveRoundedSpherical(std::mt19937_64& rng, int digits, testing::SpatialForm form) {
  Eigen::Vector3d center;
  const std::vector<DualQuaternion> poses = testing::RandomSphericalMotion(rng, 7, &center);
  Task task;
  SpatialMotionResult result;
  Verdict verdict =
      SolveRoundedText(testing::SpatialMotionText(poses, digits, form), &task, &result);
  verdict.expected = "a spherical motion about [" + std::to_string(center.x()) + ", " +
                     std::to_string(center.y()) + ", " + std::to_string(center.z()) + "]\n";
  if (!result.spherical || result.model != "spherical" || !result.dyads.empty()) return verdict;
  verdict.kind = "spherical";
  const double length = SpatialTaskLength(task);
  verdict.error = (result.spherical->in_fixed - center).norm() / length;
  verdict.tolerance = 100.0 * std::max(RelativePrecision(task.precision, length), 1e-12);
  return verdict;
}

// Seven spatial poses from rounded data: the five generating SS dyads within their bounds.
Verdict SolveRoundedSpatial(const PlantedSpatialTask& generated, int digits,
                            testing::SpatialForm form) {
  Task task;
  SpatialMotionResult result;
  Verdict verdict =
      SolveRoundedText(testing::SpatialMotionText(generated.poses, digits, form), &task, &result);
  const double length = SpatialTaskLength(task);
  bool undetermined = false;
  verdict.error = 0.0;
  for (const SpatialDyad& expected : generated.planted) {
    verdict.expected += DyadText(expected);
    verdict.error =
        std::max(verdict.error, RoundedRecovery(expected, result.dyads, task.precision,
                                                task.spatial_poses, length, &undetermined));
  }
  verdict.noted = undetermined || SaysTooCoarse(result.notes);
  verdict.tolerance = 1.0;
  return verdict;
}

// Seven poses of a planar four-bar given as spatial poses (in the plane z = 0) and rounded:
// solved as planar, with the generating dyads back within their bounds.
Verdict SolveRoundedPlanarAsSpatial(const testing::GeneratedTask& generated, int digits,
                                    testing::SpatialForm form) {
  std::vector<DualQuaternion> poses;
  for (const PlanarPose& pose : generated.poses) {
    poses.push_back(DualQuaternion::FromAxisAngle(
        Eigen::Vector3d::UnitZ(), pose.theta,
        Eigen::Vector3d(pose.origin_in_fixed.x(), pose.origin_in_fixed.y(), 0.0)));
  }
  Task task;
  SpatialMotionResult result;
  Verdict verdict =
      SolveRoundedText(testing::SpatialMotionText(poses, digits, form), &task, &result);
  verdict.tolerance = 1.0;
  if (result.model != "planar" || !result.planar || !result.plane) return verdict;
  // The planar dyads mapped to z = 0 coordinates (the plane's normal may point down).
  const PlanarEmbedding& plane = *result.plane;
  const Eigen::Matrix<double, 3, 2> to_fixed = plane.axes_in_fixed.leftCols<2>();
  const Eigen::Matrix<double, 3, 2> to_moving = plane.axes_in_moving.leftCols<2>();
  std::vector<DyadReport> lifted;
  for (DyadReport report : result.planar->dyads) {
    PlanarDyad& dyad = report.dyad;
    const Eigen::Vector3d fixed = plane.origin_in_fixed + to_fixed * dyad.fixed_pivot;
    const Eigen::Vector3d moving = to_moving * dyad.moving_pivot;
    const Eigen::Vector3d line_point =
        dyad.type == DyadType::kPR
            ? Eigen::Vector3d(plane.origin_in_fixed + to_fixed * dyad.line_point)
            : Eigen::Vector3d(to_moving * dyad.line_point);
    const Eigen::Vector3d direction =
        (dyad.type == DyadType::kPR ? to_fixed : to_moving) * dyad.line_direction;
    dyad.fixed_pivot = fixed.head<2>();
    dyad.moving_pivot = moving.head<2>();
    dyad.line_point = line_point.head<2>();
    dyad.line_direction = direction.head<2>().normalized();
    lifted.push_back(report);
  }
  bool undetermined = false;
  verdict.error = std::max(
      RoundedRecovery(generated.input, lifted, task.precision, generated.poses, &undetermined),
      RoundedRecovery(generated.output, lifted, task.precision, generated.poses, &undetermined));
  verdict.noted = undetermined || SaysTooCoarse(result.notes);
  return verdict;
}

std::string DyadText(const PathFourBar& four_bar) {
  return "input " + DyadText(four_bar.input) + "output " + DyadText(four_bar.output) +
         "coupler_point " + Coordinates(four_bar.coupler_point) + "\n";
}

// Points of a path from rounded data (timed, or free timing when `free_timing`): the generating
// four-bar (free timing: or a cognate tracing the same curve) within twice the error bound the
// result states. The case measures what rounding costs: a task whose generating four-bar the
// solver misses at full precision already (the free-timing search's misses) is drawn again, and
// the detail column counts those.
Verdict SolveRoundedPath(const testing::GeneratedPathTask& generated, int digits, bool free_timing,
                         Effort effort) {
  const std::vector<double> angles = free_timing ? std::vector<double>() : generated.input_angles;
  Verdict verdict;
  const Task unrounded =
      testing::ReadRounded(testing::PathText(generated.points, angles, 17), effort);
  if (!(testing::RoundedPathRecovery(generated.four_bar, SolvePathTask(unrounded), generated.points,
                                     angles) <= 1.0)) {
    verdict.redraw = true;
    return verdict;
  }
  const std::string text = testing::PathText(generated.points, angles, digits);
  const Task task = testing::ReadRounded(text, effort);
  const PathResult result = SolvePathTask(task);
  verdict.task_text = text;
  verdict.expected = DyadText(generated.four_bar);
  verdict.finite = AllFinite(result);
  bool rough = false;
  verdict.error =
      testing::RoundedPathRecovery(generated.four_bar, result, generated.points, angles, &rough);
  // Noted: the nearest four-bar meeting the points has a rough bound (the path notes count
  // loose four-bars among many, so they do not speak for the generating one).
  verdict.noted = rough;
  verdict.tolerance = 1.0;
  // A miss where no listed four-bar meets the points within their precision is the search's
  // (free timing), not the model choice's: counted in the detail column.
  if (!(verdict.error <= 1.0) && !rough &&
      std::none_of(result.mechanisms.begin(), result.mechanisms.end(),
                   [&](const PathMechanismReport& report) {
                     return testing::MeetsPointsWithinPrecision(report, generated.points,
                                                                task.precision);
                   })) {
    verdict.kind = "search miss";
  }
  return verdict;
}

std::string Power(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

class Sweep {
 public:
  Sweep(const BenchOptions& options, std::FILE* table)
      : tasks_(options.quick ? 10 : 100),
        seed_(options.seed),
        table_(table),
        wrong_dir_(options.wrong_dir),
        family_(options.family) {}

  // Runs `tasks` tasks of a case: `run(rng)` makes and solves one.
  template <typename Run>
  void Case(const std::string& family, const std::string& variant, double tolerance, Run run,
            int tasks = 0) {
    if (!family_.empty()) {
      // "family" or "family:part of the variant"
      const size_t colon = family_.find(':');
      if (family != family_.substr(0, colon)) return;
      if (colon != std::string::npos &&
          variant.find(family_.substr(colon + 1)) == std::string::npos) {
        return;
      }
    }
    ExtremeRow row;
    row.family = family;
    row.variant = variant;
    row.tolerance = tolerance;
    std::mt19937_64 rng(seed_ + std::hash<std::string>()(family + variant));
    std::vector<std::string> kinds;
    const int wanted = tasks > 0 ? tasks : tasks_;
    int redrawn = 0;
    for (int t = 0; t < wanted && redrawn < 10 * wanted;) {
      Verdict verdict;
      try {
        verdict = run(rng);
      } catch (const std::exception& error) {
        verdict.finite = false;
        verdict.kind = std::string("exception: ") + error.what();
      }
      if (verdict.redraw) {
        ++redrawn;
        continue;
      }
      const int wrong = row.wrong, noted = row.noted;
      Tally(verdict, &row);
      kinds.push_back(verdict.kind);
      if (row.wrong + row.noted > wrong + noted && !wrong_dir_.empty() &&
          !verdict.task_text.empty()) {
        WriteWrong(row, t, row.wrong > wrong ? "" : "-noted", verdict);
      }
      ++t;
    }
    row.detail = KindCounts(kinds);
    if (redrawn > 0) {
      row.detail += (row.detail.empty() ? "" : "; ") + std::string("drawn again: ") +
                    std::to_string(redrawn) + " missed at full precision";
    }
    if (table_ != nullptr) {
      std::fprintf(table_, "%-16s %-56s %8.0e %6d %6d %6d %6d %6d %11.2e  %s\n", family.c_str(),
                   variant.c_str(), tolerance, row.tasks, row.right, row.noted, row.wrong,
                   row.non_finite, row.worst_error, row.detail.c_str());
      std::fflush(table_);
    }
    rows_.push_back(row);
  }

  int tasks() const { return tasks_; }
  std::vector<ExtremeRow> rows() const { return rows_; }

 private:
  int tasks_;
  uint64_t seed_;
  // The task file of a wrong answer: <wrong_dir>/<family> <variant>-<task>.json, the name's
  // spaces and punctuation as '_', and the generating mechanism beside it (.expected.txt); a
  // noted one likewise, as <...>-<task>-noted.json.
  void WriteWrong(const ExtremeRow& row, int task, const std::string& suffix,
                  const Verdict& verdict) const {
    std::string name = row.family + "_" + row.variant;
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    const std::string path = wrong_dir_ + "/" + name + "-" + std::to_string(task) + suffix;
    for (const auto& [suffix, text] :
         {std::pair{".json", verdict.task_text}, std::pair{".expected.txt", verdict.expected}}) {
      WriteOutputFile(path + suffix, "--wrong-dir", text);
    }
  }

  std::FILE* table_;
  std::string wrong_dir_;
  std::string family_;
  std::vector<ExtremeRow> rows_;
};

}  // namespace

std::vector<ExtremeRow> RunExtremesBench(const BenchOptions& options, std::FILE* table) {
  if (table != nullptr) {
    std::fprintf(table,
                 "\nstability at the extremes (%s): right = within the tolerance (relative "
                 "error of the mechanism); noted = an \"ill-conditioned\" note with the "
                 "condition estimate\n",
                 options.quick ? "quick" : "full");
    std::fprintf(table, "%-16s %-56s %8s %6s %6s %6s %6s %6s %11s  %s\n", "family", "variant",
                 "tol", "tasks", "right", "noted", "wrong", "nan", "worst_err", "detail");
  }
  Sweep sweep(options, table);

  // Scale and translation: the same answers, transformed back.
  // Exact tolerances: the planar five-pose solver recovers 99.99 % of random tasks to 1e-9
  // (linkfit_bench); a translation by 1e4 L costs four digits of every input coordinate.
  struct Frame {
    const char* name;
    double scale;
    double offset;  // translation of the fixed frame, in L (after scaling)
  };
  const Frame frames[] = {{"L = 1e-3", 1e-3, 0.0},
                          {"L = 1", 1.0, 0.0},
                          {"L = 1e3", 1e3, 0.0},
                          {"L = 1e5", 1e5, 0.0},
                          {"translated 1e4 L", 1.0, 1e4}};
  for (const Frame& frame : frames) {
    const double tolerance = frame.offset > 0.0 ? 1e-5 : 1e-8;
    Similarity2 sigma, epsilon;
    sigma.scale = epsilon.scale = frame.scale;
    sigma.translation = frame.scale * frame.offset * Eigen::Vector2d(0.6, 0.8);
    sweep.Case("scale", std::string("planar 5 poses, ") + frame.name, tolerance,
               [&](std::mt19937_64& rng) {
                 const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 5);
                 return SolveTransformedPlanar(generated, sigma, epsilon);
               });
    sweep.Case(
        "scale", std::string("planar 10 poses (balanced), ") + frame.name, tolerance,
        [&](std::mt19937_64& rng) {
          const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 10);
          return SolveTransformedPlanar(generated, sigma, epsilon);
        },
        std::max(3, sweep.tasks() / 5));
    Similarity3 sigma3, epsilon3;
    sigma3.scale = epsilon3.scale = frame.scale;
    sigma3.translation = frame.scale * frame.offset * Eigen::Vector3d(0.48, 0.64, 0.6);
    sweep.Case(
        "scale", std::string("spatial 7 poses, ") + frame.name, tolerance * 10,
        [&](std::mt19937_64& rng) {
          return SolveTransformedSpatial(RandomPlatformTask(rng, 7), sigma3, epsilon3);
        },
        std::max(3, sweep.tasks() / 5));
    sweep.Case("scale", std::string("path 5 points, ") + frame.name, tolerance * 10,
               [&](std::mt19937_64& rng) {
                 return SolveTransformedPath(testing::RandomPathTask(rng, DyadType::kRR), sigma);
               });
  }

  // Rotations near +-180 degrees: the moving frame turned so that the third pose's angle is
  // 180 degrees minus delta (or -180 plus delta); the answer turned back.
  for (const double delta : {1e-3, 1e-6, 1e-9, 1e-12, 0.0}) {
    for (const double side : {1.0, -1.0}) {
      const std::string variant =
          "planar 5 poses, theta_2 = " + std::string(side > 0 ? "180 - " : "-180 + ") +
          Power(delta) + " rad";
      sweep.Case("rotation", variant, 1e-8, [&](std::mt19937_64& rng) {
        const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 5);
        Similarity2 sigma, epsilon;
        // TransformPose: the new pose maps epsilon(p) to pose(p), so its angle is theta - angle.
        epsilon.angle = generated.poses[2].theta - side * (M_PI - delta);
        return SolveTransformedPlanar(generated, sigma, epsilon);
      });
    }
    sweep.Case(
        "rotation", "spatial 7 poses, pose 2 turned by 180 deg - " + Power(delta) + " rad", 1e-7,
        [&](std::mt19937_64& rng) {
          const PlantedSpatialTask generated = RandomPlatformTask(rng, 7);
          // Epsilon maps E to E': the new pose is pose * epsilon^-1, a turn by pi - delta about
          // a random axis for pose 2.
          std::normal_distribution<double> normal;
          const Eigen::Vector3d axis =
              Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
          const Eigen::Matrix3d target = Eigen::AngleAxisd(M_PI - delta, axis).toRotationMatrix();
          Similarity3 sigma, epsilon;
          epsilon.rotation = target.transpose() * generated.poses[2].Rotation();
          return SolveTransformedSpatial(generated, sigma, epsilon);
        },
        std::max(3, sweep.tasks() / 5));
  }

  // Quaternions of both signs: (q, g) and (-q, -g) are the same pose.
  sweep.Case(
      "quaternion sign", "spatial 7 poses, random signs", 1e-7,
      [&](std::mt19937_64& rng) {
        PlantedSpatialTask generated = RandomPlatformTask(rng, 7);
        std::bernoulli_distribution flip(0.5);
        for (DualQuaternion& pose : generated.poses) {
          if (flip(rng)) {
            pose.q = -pose.q;
            pose.g = -pose.g;
          }
        }
        return SolveTransformedSpatial(generated, Similarity3(), Similarity3());
      },
      std::max(3, sweep.tasks() / 5));

  // Sliders: slider-cranks, and 4Rs whose output circle has radius R (the slider's line bent
  // into a circle tangent to it at the first pose). A centre R away is stored to ulp(R), so no
  // dyad of that radius can be known better than about 16 eps R at the poses: right is an RR
  // or PR dyad whose moving pivot matches the generating one to 1e-6 (relative) and which fits
  // every pose to 1e-9 L + 16 eps R (error = its largest residual / L). The types found are
  // counted in the detail column.
  for (const double radius : {0.0, 1e2, 1e4, 1e6, 1e8}) {
    const std::string variant =
        radius == 0.0 ? "slider-crank, 5 poses" : "4R, output radius " + Power(radius) + " L";
    sweep.Case("slider", variant, 1e-9, [&](std::mt19937_64& rng) {
      testing::GeneratedTask generated;
      do {
        generated = testing::RandomTask(rng, DyadType::kRR, DyadType::kPR, 5);
        if (radius > 0.0) {
          const PlanarDyad line = generated.output;
          const PlanarPose start = generated.poses.front();
          const Eigen::Vector2d pivot = start.ToFixed(line.moving_pivot);
          const Eigen::Vector2d normal(-line.line_direction.y(), line.line_direction.x());
          generated.output = PlanarDyad::RR(pivot + radius * normal, line.moving_pivot, radius);
        }
      } while (radius > 0.0 &&
               !testing::DriveFourBar(rng, PlanarPose(generated.poses.front()), 5, &generated));
      if (radius > 0.0) ExactOnCircle(generated.input, radius, &generated);
      const PlanarMotionResult result = SolvePlanarTask(PlanarMotionTask(generated.poses));
      const double length = CharacteristicLength(generated.poses);
      Verdict verdict;
      verdict.finite = AllFinite(result);
      verdict.noted = HasIllConditionedNote(result.notes);
      verdict.tolerance = 1e-9 + 16.0 * std::numeric_limits<double>::epsilon() * radius / length;
      const PlanarDyad& expected = generated.output;
      for (const DyadReport& report : result.dyads) {
        const PlanarDyad& found = report.dyad;
        // The output dyad, not one of the other roots (which lie O(L) away). Near its slider
        // limit the moving pivot itself is ill-determined, so the test is the fit.
        if (found.type == DyadType::kRP ||
            (found.moving_pivot - expected.moving_pivot).norm() >
                1e-3 * std::max(length, expected.moving_pivot.norm())) {
          continue;
        }
        const double fit = found.MaxResidual(generated.poses) / length;
        if (fit < verdict.error) {
          verdict.error = fit;
          verdict.kind = found.type == DyadType::kRR ? "RR" : "PR";
        }
      }
      return verdict;
    });
  }

  // Nearly coincident poses: the fifth pose a small input step from the fourth.
  for (const double step : {1e-2, 1e-4, 1e-6, 1e-8}) {
    sweep.Case(
        "coincident", "planar, poses 3 and 4 an input step " + Power(step) + " rad apart", 1e-6,
        [&](std::mt19937_64& rng) {
          testing::GeneratedTask generated;
          do {
            generated = testing::RandomFourBarTask(rng, 5);
          } while (!testing::AssembleNear(generated.input, generated.output,
                                          InputValue(generated.input, generated.poses[3]) + step,
                                          generated.poses[3], &generated.poses[4]));
          return SolveTransformedPlanar(generated, Similarity2(), Similarity2());
        });
  }

  // Nearly collinear pose origins: a slider-crank's coupler frame E moved so that its origin is
  // within delta of the slider pin (delta = 0: on it, the five origins on the slider's line).
  for (const double delta : {1e-3, 1e-6, 1e-9, 0.0}) {
    sweep.Case("collinear", "planar 5 poses, origins within " + Power(delta) + " L of a line", 1e-8,
               [&](std::mt19937_64& rng) {
                 const testing::GeneratedTask generated =
                     testing::RandomTask(rng, DyadType::kRR, DyadType::kPR, 5);
                 // epsilon maps E to E': the new origin sits at the pin, offset along E's y.
                 Similarity2 epsilon;
                 epsilon.translation = -generated.output.moving_pivot + Eigen::Vector2d(0.0, delta);
                 return SolveTransformedPlanar(generated, Similarity2(), epsilon);
               });
  }

  // Nearly collinear points: a slider-crank's coupler point within delta of its slider line
  // (delta = 0: on it, the five points on one line).
  for (const double delta : {1e-3, 1e-6, 1e-9, 0.0}) {
    sweep.Case("collinear", "path 5 points within " + Power(delta) + " L of a line", 1e-6,
               [&](std::mt19937_64& rng) {
                 const testing::GeneratedTask motion =
                     testing::RandomTask(rng, DyadType::kRR, DyadType::kPR, 5);
                 const PlanarPose& start = motion.poses.front();
                 const Eigen::Vector2d direction_in_moving =
                     start.ToMoving(start.origin_in_fixed + motion.output.line_direction) -
                     start.ToMoving(start.origin_in_fixed);
                 const testing::GeneratedPathTask generated = testing::PathTaskOf(
                     motion,
                     motion.output.moving_pivot + delta * Eigen::Vector2d(-direction_in_moving.y(),
                                                                          direction_in_moving.x()));
                 return SolveTransformedPath(generated, Similarity2());
               });
  }

  // Spatial poses of a planar four-bar, tilted off their plane: every pose turned about a
  // random horizontal axis by up to `tilt` and lifted by up to tilt L (the largest exactly).
  // Below the planarity tolerance (1e-8 L) they are solved as planar and the generating dyads
  // must come back to within 1e-6 (the tilt moves them by about tilt times the task's
  // condition); above it, as spatial, and every dyad returned must fit to 1e-9 L.
  for (const double tilt : {0.0, 1e-9, 3e-9, 3e-8, 1e-7, 1e-5, 1e-3}) {
    sweep.Case(
        "planarity", "7 planar poses tilted " + Power(tilt) + " off the plane", 1e-6,
        [&](std::mt19937_64& rng) {
          const testing::GeneratedTask generated = testing::RandomFourBarTask(rng, 7);
          const double length = CharacteristicLength(generated.poses);
          std::uniform_real_distribution<double> unit(-1.0, 1.0);
          std::vector<DualQuaternion> poses;
          for (size_t j = 0; j < generated.poses.size(); ++j) {
            const PlanarPose& pose = generated.poses[j];
            const double amount = j == 3 ? 1.0 : unit(rng);
            const double axis_angle = M_PI * unit(rng);
            const Eigen::Matrix3d tilt_rotation =
                Eigen::AngleAxisd(tilt * amount,
                                  Eigen::Vector3d(std::cos(axis_angle), std::sin(axis_angle), 0.0))
                    .toRotationMatrix();
            const Eigen::Matrix3d rotation =
                tilt_rotation *
                Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
            const Eigen::Vector3d translation(pose.origin_in_fixed.x(), pose.origin_in_fixed.y(),
                                              tilt * length * unit(rng));
            poses.push_back(DualQuaternion::FromRotationTranslation(rotation, translation));
          }
          const SpatialMotionResult result = SolveSpatialTask(SpatialMotionTask(poses));
          Verdict verdict;
          verdict.finite = AllFinite(result);
          verdict.noted = HasIllConditionedNote(result.notes);
          verdict.kind = result.model;
          if (result.model == "planar" && result.planar && result.plane) {
            // The generating dyads, lifted: each must be matched by a returned SS dyad
            // with the same moving point and radius whose centre lies on the vertical
            // through the planar one (such pivots may slide along the normal).
            verdict.error = 0.0;
            for (const PlanarDyad& expected : {generated.input, generated.output}) {
              const double scale = testing::DyadScale(expected, generated.poses);
              double best = kInfinity;
              // The planar dyads live in the plane frames (result.plane).
              for (const DyadReport& report : result.planar->dyads) {
                const PlanarDyad& found = report.dyad;
                if (found.type != DyadType::kRR) continue;
                const Eigen::Vector3d fixed_pivot =
                    result.plane->origin_in_fixed +
                    result.plane->axes_in_fixed.leftCols<2>() * found.fixed_pivot;
                const Eigen::Vector3d moving_pivot =
                    result.plane->axes_in_moving.leftCols<2>() * found.moving_pivot;
                const double error =
                    std::max({(fixed_pivot.head<2>() - expected.fixed_pivot).norm(),
                              (moving_pivot.head<2>() - expected.moving_pivot).norm(),
                              std::abs(found.radius - expected.radius)});
                best = std::min(best, error / scale);
              }
              verdict.error = std::max(verdict.error, best);
            }
          } else {
            // Spatial: every returned dyad must fit the poses.
            double worst = 0.0;
            for (const SpatialDyadReport& report : result.dyads) {
              worst = std::max(worst, report.dyad.MaxResidual(poses) / length);
            }
            verdict.error = result.dyads.empty() ? kInfinity : worst;
            verdict.tolerance = 1e-9;
          }
          return verdict;
        });
  }

  // Rounded data: generated tasks printed to 8, 6 and 4 significant digits as tables print
  // them, read back (precision inferred from the digits) and solved. Right: both generating
  // dyads (planar) or all five (spatial) back within twice the error bound the result states,
  // typed as the data allow (a circle the rounded poses cannot tell from a line may come back
  // as the slider); noted: the result says the data are too coarse. The detail column counts
  // the types (planar: the generating output's) or models found.
  for (const int digits : {8, 6, 4}) {
    const std::string printed = " to " + std::to_string(digits) + " digits";
    for (const auto& [name, output] :
         {std::pair{"4R", DyadType::kRR}, std::pair{"slider-crank", DyadType::kPR},
          std::pair{"inverted slider-crank", DyadType::kRP}}) {
      sweep.Case("rounded", std::string("planar 5 poses, ") + name + printed, 1.0,
                 [&, output = output](std::mt19937_64& rng) {
                   return SolveRoundedPlanar(testing::RandomTask(rng, DyadType::kRR, output, 5),
                                             digits);
                 });
    }
    sweep.Case("rounded", "spatial 7 poses (q, g)" + printed, 1.0, [&](std::mt19937_64& rng) {
      return SolveRoundedSpatial(RandomPlatformTask(rng, 7), digits,
                                 testing::SpatialForm::kDualQuaternion);
    });
    sweep.Case("rounded", "spatial 7 poses (rotation matrix)" + printed, 1.0,
               [&](std::mt19937_64& rng) {
                 return SolveRoundedSpatial(RandomPlatformTask(rng, 7), digits,
                                            testing::SpatialForm::kRotationMatrix);
               });
    // Paths: five timed points (exact), ten timed points and ten untimed points (least
    // squares at the default effort).
    for (const auto& [name, output] :
         {std::pair{"4R", DyadType::kRR}, std::pair{"slider-crank", DyadType::kPR}}) {
      sweep.Case("rounded", std::string("timed path 5 points, ") + name + printed, 1.0,
                 [&, output = output](std::mt19937_64& rng) {
                   return SolveRoundedPath(testing::RandomPathTask(rng, output), digits, false,
                                           Effort::kBalanced);
                 });
    }
    sweep.Case("rounded", "timed path 10 points, 4R" + printed, 1.0, [&](std::mt19937_64& rng) {
      return SolveRoundedPath(testing::RandomPathTask(rng, DyadType::kRR, 10), digits, false,
                              Effort::kBalanced);
    });
    sweep.Case("rounded", "free timing 10 points, 4R" + printed, 1.0, [&](std::mt19937_64& rng) {
      return SolveRoundedPath(testing::RandomPathTask(rng, DyadType::kRR, 10), digits, true,
                              Effort::kBalanced);
    });
    for (const auto& [name, form] : {std::pair{"(q, g)", testing::SpatialForm::kDualQuaternion},
                                     std::pair{"(Euler ZYX)", testing::SpatialForm::kEulerZYX}}) {
      sweep.Case("rounded", std::string("planar 4R as 7 spatial poses ") + name + printed, 1.0,
                 [&, form = form](std::mt19937_64& rng) {
                   return SolveRoundedPlanarAsSpatial(testing::RandomFourBarTask(rng, 7), digits,
                                                      form);
                 });
    }
    sweep.Case("rounded", "spherical 7 poses (q, g), solved as spherical" + printed, 1.0,
               [&](std::mt19937_64& rng) {
                 return SolveRoundedSpherical(rng, digits, testing::SpatialForm::kDualQuaternion);
               });
  }
  return sweep.rows();
}

std::string ExtremesCsv(const std::vector<ExtremeRow>& rows) {
  std::ostringstream csv;
  csv << "family,variant,tolerance,tasks,right,noted,wrong,non_finite,worst_error,detail\n";
  for (const ExtremeRow& row : rows) {
    // The variant and the detail may hold commas: quoted (RFC 4180).
    csv << row.family << ",\"" << row.variant << "\"," << row.tolerance << "," << row.tasks << ","
        << row.right << "," << row.noted << "," << row.wrong << "," << row.non_finite << ","
        << row.worst_error << ",\"" << row.detail << "\"\n";
  }
  return csv.str();
}

}  // namespace linkfit
