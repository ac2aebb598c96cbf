#include "optimizers/task_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "fitting/exact_items.h"
#include "fitting/model_choice.h"
#include "fitting/six_bar_synthesis.h"
#include "lib/parallel.h"
#include "lib/task_io.h"
#include "lib/text_format.h"
#include "optimizers/limit_hyperplane.h"
#include "optimizers/nested_model_test.h"

namespace linkfit {

namespace {

// A refined SS dyad whose radius (or moving point's distance from E's origin) exceeds this
// times L is also refined as its plane limit, PS (or SP): see PreferPlaneLimits.
constexpr double kFarMovingPoint = 10.0;

// Two refined spatial dyads this close (relative to their size) are one optimum reached twice:
// the dyad refiner stops where the cost no longer changes (function tolerance 1e-15), which
// leaves the parameters of a noisy optimum uncertain to about its square root times the
// conditioning; two refinements of one optimum were seen 4e-7 apart.
constexpr double kSameRefinedOptimum = 1e-5;
// Two refined spherical dyads whose axes and angles agree to this (radians) are one optimum.
constexpr double kSameSphericalOptimum = 1e-7;

// With constraints, planar motion keeps this many times the dyads per level and refines this many
// times the four-bars: the constrained optimum is often a pair refined onto a bound whose dyads
// fit the poses a little worse than the best few, and where every four-bar breaks a bound, how
// well it fits says little about where its refinement onto the bound ends (measured by the
// constrained part of `linkfit bench`).
constexpr int kConstrainedDyadsFactor = 2;
constexpr int kConstrainedRefinedFactor = 3;
// A listed four-bar is refined again while a round gains (AnotherRound, refiner_summary.h), in
// kPolishRounds at most at the mechanism level and kListedRounds as `linkfit refine` refines it:
// `linkfit refine` then improves it by less than 1 %.
constexpr int kPolishRounds = 3;
constexpr int kListedRounds = 20;

// Whether two planar dyads are of one type and agree to `tolerance` (length units) in every
// parameter (line directions to tolerance / length).
bool NearDyads(const PlanarDyad& a, const PlanarDyad& b, double tolerance, double length) {
  return a.type == b.type &&
         (a.fixed_pivot - b.fixed_pivot).lpNorm<Eigen::Infinity>() <= tolerance &&
         (a.moving_pivot - b.moving_pivot).lpNorm<Eigen::Infinity>() <= tolerance &&
         std::abs(a.radius - b.radius) <= tolerance &&
         (a.line_point - b.line_point).lpNorm<Eigen::Infinity>() <= tolerance &&
         (a.line_direction - b.line_direction).lpNorm<Eigen::Infinity>() <= tolerance / length;
}

// A refinement that moved a dyad by less than this times L left it where it was
// (RefinePlanarDesign).
constexpr double kUnmovedDyad = 1e-10;
// Two refined planar dyads this close (times L) are one optimum reached twice (as
// kSameRefinedOptimum for spatial dyads: a refinement stops where the cost no longer changes,
// which leaves a noisy optimum's parameters uncertain to about the square root of the
// tolerance).
constexpr double kSamePlanarOptimum = 1e-6;

// The SP limit of an SS dyad whose moving point runs off to infinity: the center A stays on
// the plane of E normal to the moving point's direction (as seen from the points e_j where E
// sees A), through their weighted mean; returned as the PS dyad of the inverted motion.
SpatialDyad LimitPlaneInMoving(const SpatialDyad& dyad, const Task& task) {
  std::vector<Eigen::Vector3d> seen;
  for (const DualQuaternion& pose : task.spatial_poses) {
    seen.push_back(pose.Rotation().transpose() * (dyad.fixed_pivot - pose.Translation()));
  }
  const Hyperplane<3> plane = LimitHyperplane<3>(seen, task.pose_weights, dyad.moving_pivot, false,
                                                 Eigen::Vector3d::UnitZ());
  return SpatialDyad::PS(dyad.fixed_pivot, plane.normal, plane.offset);
}

// The PS limit of an SS dyad whose center runs off to infinity: the plane normal to the
// center's direction, through the weighted mean of the moving point's positions.
SpatialDyad LimitPlaneInFixed(const SpatialDyad& dyad, const Task& task) {
  std::vector<Eigen::Vector3d> points;
  for (const DualQuaternion& pose : task.spatial_poses) {
    points.push_back(pose.ToFixed(dyad.moving_pivot));
  }
  const Hyperplane<3> plane = LimitHyperplane<3>(points, task.pose_weights, dyad.fixed_pivot, true,
                                                 Eigen::Vector3d::UnitZ());
  return SpatialDyad::PS(dyad.moving_pivot, plane.normal, plane.offset);
}

// The nested-model test between a plane (6 parameters) and a sphere (7) fitted to n poses:
// keep the simpler plane unless the sphere's cost is significantly lower (F test at 5 %).
bool PlaneSuffices(double plane_cost, double sphere_cost, int n) {
  return SimplerModelSuffices(plane_cost, sphere_cost, n - 7);
}

// The largest |residual| of a dyad over the task's exact poses, in length units: 0 without
// exact poses, infinity when one is not finite.
double ExactPoseMiss(const SpatialDyad& dyad, const Task& task) {
  double miss = 0.0;
  for (size_t j = 0; j < task.spatial_poses.size() && j < task.pose_exact.size(); ++j) {
    if (!task.pose_exact[j]) continue;
    const double residual = std::abs(dyad.Residual(task.spatial_poses[j]));
    miss = std::isfinite(residual) ? std::max(miss, residual)
                                   : std::numeric_limits<double>::infinity();
  }
  return miss;
}

// The same for a planar dyad over the task's exact planar poses.
double ExactPoseMiss(const PlanarDyad& dyad, const Task& task) {
  double miss = 0.0;
  for (size_t j = 0; j < task.planar_poses.size() && j < task.pose_exact.size(); ++j) {
    if (!task.pose_exact[j]) continue;
    const double residual = std::abs(dyad.Residual(task.planar_poses[j]));
    miss = std::isfinite(residual) ? std::max(miss, residual)
                                   : std::numeric_limits<double>::infinity();
  }
  return miss;
}

// A refined sphere far out in Sigma (radius) or in E (moving point) is nearly a plane: refine
// those limits too (PS; SP as a PS dyad of the inverted motion, same exact poses) and keep the
// best plane that beats the sphere. As in the refiner, meeting the exact poses (to
// exact_tolerance L) decides first: a plane that meets them when the sphere does not beats it,
// one that does not when the sphere does never; otherwise a plane beats the sphere when it
// suffices (PlaneSuffices), and of two planes the lower cost wins. A slider is reported as a
// slider.
void PreferPlaneLimits(const Task& task, const std::vector<DualQuaternion>& inverted, double length,
                       const SpatialDyadRefinerOptions& options, SpatialDyad* dyad,
                       RefinerSummary* summary) {
  const int n = static_cast<int>(task.spatial_poses.size());
  const SpatialDyad sphere = *dyad;
  const double sphere_cost = summary->final_cost;
  const double exact_limit = options.exact_tolerance * length;
  const bool sphere_meets = ExactPoseMiss(sphere, task) <= exact_limit;
  bool best_meets = false;
  double best_cost = std::numeric_limits<double>::infinity();
  const auto consider = [&](const SpatialDyad& plane, const RefinerSummary& plane_summary) {
    const double cost = plane_summary.final_cost;
    const bool meets = std::isfinite(cost) && ExactPoseMiss(plane, task) <= exact_limit;
    const bool beats_sphere = meets != sphere_meets ? meets : PlaneSuffices(cost, sphere_cost, n);
    const bool beats_best = meets != best_meets ? meets : cost < best_cost;
    if (!beats_sphere || !beats_best) return;
    best_meets = meets;
    best_cost = cost;
    *dyad = plane;
    summary->final_cost = plane_summary.final_cost;
    summary->final_rms = plane_summary.final_rms;
    summary->final_max = plane_summary.final_max;
    summary->model_changed = true;
  };
  if (sphere.radius > kFarMovingPoint * length) {
    SpatialDyad plane = LimitPlaneInFixed(sphere, task);
    const RefinerSummary plane_summary = RefineSpatialDyad(
        task.spatial_poses, task.pose_weights, task.pose_exact, length, &plane, options);
    if (plane.type == SpatialDyadType::kPS) consider(plane, plane_summary);
  }
  if (sphere.moving_pivot.norm() > kFarMovingPoint * length) {
    SpatialDyad flipped = LimitPlaneInMoving(sphere, task);
    const RefinerSummary plane_summary =
        RefineSpatialDyad(inverted, task.pose_weights, task.pose_exact, length, &flipped, options);
    if (flipped.type == SpatialDyadType::kPS) {
      consider(SpatialDyad::SP(flipped.moving_pivot, flipped.plane_normal, flipped.plane_offset),
               plane_summary);
    }
  }
}

// Refines one dyad of a spatial task on its residuals (spatial_dyad_refiner.h; an SP dyad as the
// PS dyad of the inverted motion, `inverted`), an SS whose centre or moving point runs far also
// as its plane limits (PreferPlaneLimits), and a sphere the data cannot tell from a plane at
// their precision as that plane, refined. The report gets the refined dyad, its residuals and
// the seed's. Returns whether the sphere became its plane.
bool RefineSpatialReport(const Task& task, const std::vector<DualQuaternion>& inverted,
                         double length, const SpatialDyadRefinerOptions& options,
                         SpatialDyadReport* report) {
  SpatialDyad dyad = report->dyad;
  RefinerSummary summary;
  bool simplified = false;
  if (dyad.type == SpatialDyadType::kSP) {
    SpatialDyad flipped = SpatialDyad::PS(dyad.fixed_pivot, dyad.plane_normal, dyad.plane_offset);
    summary =
        RefineSpatialDyad(inverted, task.pose_weights, task.pose_exact, length, &flipped, options);
    dyad = flipped.type == SpatialDyadType::kPS
               ? SpatialDyad::SP(flipped.moving_pivot, flipped.plane_normal, flipped.plane_offset)
               : SpatialDyad::SS(flipped.moving_pivot, flipped.fixed_pivot, flipped.radius);
  } else {
    summary = RefineSpatialDyad(task.spatial_poses, task.pose_weights, task.pose_exact, length,
                                &dyad, options);
    if (dyad.type == SpatialDyadType::kSS) {
      PreferPlaneLimits(task, inverted, length, options, &dyad, &summary);
    }
  }
  // A sphere the data cannot tell from a plane at their precision is the plane, refined.
  SpatialDyad plane;
  if (dyad.type == SpatialDyadType::kSS &&
      SimplerModel(dyad, task.spatial_poses, task.precision, length, &plane)) {
    const bool in_moving = plane.type == SpatialDyadType::kSP;
    SpatialDyad start =
        in_moving ? SpatialDyad::PS(plane.fixed_pivot, plane.plane_normal, plane.plane_offset)
                  : plane;
    RefineSpatialDyad(in_moving ? inverted : task.spatial_poses, task.pose_weights, task.pose_exact,
                      length, &start, options);
    if (start.type == SpatialDyadType::kPS) {
      plane = in_moving
                  ? SpatialDyad::SP(start.moving_pivot, start.plane_normal, start.plane_offset)
                  : start;
      if (PrecisionRatio(plane, task.spatial_poses, task.precision, length) <= kModelUnits) {
        dyad = plane;
        simplified = true;
      }
    }
  }
  report->seed_max_residual = summary.initial_max;
  report->seed_rms_residual = summary.initial_rms;
  report->rms_residual = summary.final_rms;
  report->dyad = dyad;
  report->max_residual = dyad.MaxResidual(task.spatial_poses);
  return simplified;
}

// Whether two spatial dyads are one, as planar SameDyad decides it (fitting/planar_motion.h; sizes
// from `center`, the pose origins' centroid, in Sigma): of a type, and what the type has within
// SameDesignTolerance (fitting/model_choice.h: `bound` the smaller of their DyadErrorBounds; the
// relative floor kSameRefinedOptimum). An SS: both centres and the radius; a PS: its moving centre
// and its plane in Sigma; an SP: its fixed centre and its plane in E. A plane is one whichever
// sense its normal has ((n, h) and (-n, -h)).
bool SameSpatialDyad(const SpatialDyad& a, const SpatialDyad& b, const DataPrecision& precision,
                     double length, const Eigen::Vector3d& center, double bound) {
  if (a.type != b.type) return false;
  const bool fixed = a.type != SpatialDyadType::kPS, moving = a.type != SpatialDyadType::kSP;
  double size = length, difference = 0.0;
  if (fixed) {
    size = std::max(size, (a.fixed_pivot - center).norm());
    difference = std::max(difference, (a.fixed_pivot - b.fixed_pivot).norm());
  }
  if (moving) {
    size = std::max(size, a.moving_pivot.norm());
    difference = std::max(difference, (a.moving_pivot - b.moving_pivot).norm());
  }
  if (a.type == SpatialDyadType::kSS) {
    difference = std::max(difference, std::abs(a.radius - b.radius));
  } else {
    // A PS plane (in Sigma) measured from the centre, an SP plane (in E) from E's origin.
    const double offset = a.type == SpatialDyadType::kPS ? a.plane_normal.dot(center) : 0.0;
    size = std::max(size, std::abs(a.plane_offset - offset));
    const double sense = a.plane_normal.dot(b.plane_normal) < 0.0 ? -1.0 : 1.0;
    difference = std::max({difference, size * (a.plane_normal - sense * b.plane_normal).norm(),
                           std::abs(a.plane_offset - sense * b.plane_offset)});
  }
  return difference <= SameDesignTolerance(precision, size, length, 3, bound, kSameRefinedOptimum);
}

// Drops reports whose dyad repeats another (two seeds refined to one optimum: SameSpatialDyad),
// the better fitting (RMS residual) of them kept, in the place of the first. Every report gets
// its error bound (DyadErrorBound).
void DropRepeats(const Task& task, double length, std::vector<SpatialDyadReport>* dyads) {
  for (SpatialDyadReport& report : *dyads) {
    report.error_bound = DyadErrorBound(report.dyad, task.spatial_poses, task.precision, length);
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : task.spatial_poses) {
    center += pose.Translation() / static_cast<double>(task.spatial_poses.size());
  }
  std::vector<SpatialDyadReport> kept;
  for (const SpatialDyadReport& report : *dyads) {
    bool repeat = false;
    for (SpatialDyadReport& other : kept) {
      const double bound =
          std::min(report.error_bound.value_or(0.0), other.error_bound.value_or(0.0));
      if (!SameSpatialDyad(report.dyad, other.dyad, task.precision, length, center, bound)) {
        continue;
      }
      repeat = true;
      if (report.rms_residual.value_or(kInf) < other.rms_residual.value_or(kInf)) other = report;
      break;
    }
    if (!repeat) kept.push_back(report);
  }
  *dyads = std::move(kept);
}

// One note per refined dyad that misses an exact pose by more than exact_tolerance L: which
// dyad (its index in the result) and by how much, as the dyad refiners say it.
void AddExactPoseNotes(const Task& task, double exact_tolerance, SpatialMotionResult* result) {
  const int exact_count =
      static_cast<int>(std::count(task.pose_exact.begin(), task.pose_exact.end(), true));
  if (exact_count == 0) return;
  for (size_t i = 0; i < result->dyads.size(); ++i) {
    const SpatialDyad& dyad = result->dyads[i].dyad;
    const double miss = ExactPoseMiss(dyad, task) / result->scale;
    if (miss <= exact_tolerance) continue;
    char amount[32];
    std::snprintf(amount, sizeof(amount), "%.3g", miss);
    result->notes.push_back("dyad " + std::to_string(i) + " (" + SpatialDyadTypeName(dyad.type) +
                            "): exact poses not met: max residual " + amount + " L over " +
                            std::to_string(exact_count) + " exact poses");
  }
}

// Spherical dyads ordered by fit (weighted RMS residual), best first.
void SortByFit(std::vector<SphericalDyadReport>* dyads) {
  std::stable_sort(dyads->begin(), dyads->end(),
                   [](const SphericalDyadReport& a, const SphericalDyadReport& b) {
                     return a.rms_residual.value_or(0.0) < b.rms_residual.value_or(0.0);
                   });
}

}  // namespace

void SolveSphericalSeedsFast(const Task& task, const TaskSolverOptions& options,
                             SpatialMotionResult* result) {
  const SphericalMotion motion = TaskSphericalMotion(task, *result->spherical, result->scale);
  // Orientations marked exact: each seed projected onto them (fitting/exact_items.h).
  if (std::find(task.pose_exact.begin(), task.pose_exact.end(), true) != task.pose_exact.end()) {
    std::vector<double> weights = task.pose_weights;
    if (weights.size() != motion.rotations.size()) weights.assign(motion.rotations.size(), 1.0);
    int missed = 0;
    for (SphericalDyadReport& report : result->spherical_dyads) {
      SphericalDyad dyad = report.dyad;
      if (ProjectOntoExactOrientations(motion.rotations, task.pose_exact, &dyad)) {
        report = ReportSphericalDyad(dyad, motion, weights, task.precision);
      } else {
        ++missed;
      }
    }
    if (missed > 0) {
      result->notes.push_back(std::to_string(missed) +
                              " seed dyads could not be moved onto the exact orientations");
    }
  }
  SortByFit(&result->spherical_dyads);
  const int seeds = static_cast<int>(result->spherical_dyads.size());
  if (seeds > options.max_dyads) {
    result->spherical_dyads.resize(options.max_dyads);
    result->notes.push_back(std::to_string(seeds - options.max_dyads) +
                            " more seed dyads with larger residuals were found and dropped");
  }
  BuildSphericalMechanisms(task, motion, result, options.reported_mechanisms);
}

void RefineSphericalResult(const Task& task, const TaskSolverOptions& options,
                           SpatialMotionResult* result) {
  const auto start = std::chrono::steady_clock::now();
  const SphericalMotion motion = TaskSphericalMotion(task, *result->spherical, result->scale);
  std::vector<double> weights = task.pose_weights;
  if (weights.size() != motion.rotations.size()) weights.assign(motion.rotations.size(), 1.0);
  // The fast level's answer: where its four-bars fit better than the refined dyads' (refining
  // each dyad on its own cone residual can lose a four-bar that fits better), their seed dyads
  // join the refined ones below, so that balanced and thorough never answer worse.
  SpatialMotionResult fast = *result;
  SolveSphericalSeedsFast(task, options, &fast);
  std::vector<SphericalDyadReport> refined;
  for (const SphericalDyadReport& seed : result->spherical_dyads) {
    SphericalDyad dyad = seed.dyad;
    RefineSphericalDyad(motion.rotations, weights, task.pose_exact, &dyad,
                        options.spherical_refiner);
    SphericalDyadReport report = ReportSphericalDyad(dyad, motion, weights, task.precision);
    report.seed_rms_residual = seed.rms_residual;
    bool repeat = false;
    for (SphericalDyadReport& kept : refined) {
      if (!SameSphericalDyad(kept.dyad, dyad, kSameSphericalOptimum)) continue;
      repeat = true;
      if (report.rms_residual < kept.rms_residual) kept = report;
    }
    if (!repeat) refined.push_back(report);
  }
  // The best-fitting dyads make the four-bars.
  SortByFit(&refined);
  if (static_cast<int>(refined.size()) > options.max_dyads) refined.resize(options.max_dyads);
  // The refined dyads' four-bars, bounded as the answer is (the best fit of each defect group
  // stays listed): when no seed is kept and no search runs, they are the answer.
  SpatialMotionResult refined_only = *result;
  refined_only.spherical_dyads = refined;
  BuildSphericalMechanisms(task, motion, &refined_only, options.reported_mechanisms);
  const auto defect_free_fit = [](const MechanismReport& mechanism) {
    return mechanism.rms_pose_error && !HasKinematicDefect(mechanism.defects)
               ? *mechanism.rms_pose_error
               : std::numeric_limits<double>::infinity();
  };
  double refined_best = std::numeric_limits<double>::infinity();
  for (const MechanismReport& mechanism : refined_only.spherical_mechanisms) {
    refined_best = std::min(refined_best, defect_free_fit(mechanism));
  }
  // Fast's refined_mechanisms best-ranked four-bars and its best-fitting defect-free one (near
  // ties in fit rank by transmission angle, so it may rank below them): those that are
  // defect-free and fit the poses better than every defect-free four-bar of the refined dyads
  // keep their seed dyads (a seed near its refined optimum is not listed beside it otherwise).
  const int fast_count = static_cast<int>(fast.spherical_mechanisms.size());
  std::vector<int> chosen;
  for (int k = 0; k < std::min(options.refined_mechanisms, fast_count); ++k) chosen.push_back(k);
  int best_fit = -1;
  for (int k = 0; k < fast_count; ++k) {
    const double fit = defect_free_fit(fast.spherical_mechanisms[k]);
    if (fit < std::numeric_limits<double>::infinity() &&
        (best_fit < 0 || fit < defect_free_fit(fast.spherical_mechanisms[best_fit]))) {
      best_fit = k;
    }
  }
  if (best_fit >= options.refined_mechanisms) chosen.push_back(best_fit);
  int kept_seeds = 0;
  for (const int k : chosen) {
    const MechanismReport& mechanism = fast.spherical_mechanisms[k];
    if (!(defect_free_fit(mechanism) < refined_best)) continue;
    for (const int index : {mechanism.input_dyad, mechanism.output_dyad}) {
      const SphericalDyadReport& seed = fast.spherical_dyads[index];
      // Not a seed that misses an exact orientation: the refined dyads meet them.
      bool misses_exact = false;
      for (size_t j = 0; j < task.pose_exact.size() && j < motion.rotations.size(); ++j) {
        misses_exact |= task.pose_exact[j] && !(std::abs(seed.dyad.Residual(motion.rotations[j])) <=
                                                options.spherical_refiner.exact_tolerance);
      }
      const bool listed =
          std::any_of(refined.begin(), refined.end(), [&](const SphericalDyadReport& kept) {
            return SameSphericalDyad(kept.dyad, seed.dyad, kSameSphericalOptimum);
          });
      if (misses_exact || listed) continue;
      // A refined dyad the data's precision cannot tell from the seed (within the smaller of
      // their error bounds) is the seed's twin: the seed, whose four-bar fits better, takes its
      // place rather than being listed beside it.
      const auto twin =
          std::find_if(refined.begin(), refined.end(), [&](const SphericalDyadReport& kept) {
            const double bound =
                std::min(kept.error_bound.value_or(0.0), seed.error_bound.value_or(0.0));
            return std::isfinite(bound) && bound > 0.0 &&
                   SameSphericalDyad(kept.dyad, seed.dyad, bound);
          });
      if (twin != refined.end()) {
        *twin = seed;
      } else {
        refined.push_back(seed);
      }
      ++kept_seeds;
    }
  }
  if (kept_seeds > 0) {
    result->notes.push_back(
        std::to_string(kept_seeds) +
        " seed dyads (unrefined: no before_refinement) are kept for four-bars of the fast level "
        "that fit the poses better than those of the refined dyads");
  }
  if (task.effort == Effort::kThorough) {
    // The search's optima join balanced's dyads, none of which is dropped or changed for them:
    // thorough lists every dyad and four-bar balanced lists, so it never fits worse.
    SphericalSearchOptions search = options.spherical_search;
    search.refiner = options.spherical_refiner;
    std::vector<SphericalDyad> found;
    SphericalSearchSummary summary;
    SearchSphericalDyads(motion.rotations, weights, task.pose_exact, search, &found, &summary);
    int added = 0;
    const size_t balanced_count = refined.size();
    for (const SphericalDyad& dyad : found) {
      const bool repeat = std::any_of(
          refined.begin(), refined.begin() + balanced_count, [&](const SphericalDyadReport& kept) {
            return SameSphericalDyad(kept.dyad, dyad, kSameSphericalOptimum);
          });
      if (repeat) continue;
      refined.push_back(ReportSphericalDyad(dyad, motion, weights, task.precision));
      ++added;
    }
    SortByFit(&refined);
    result->notes.push_back("search (thorough): NLopt " + summary.algorithm +
                            " over the moving axis, " + std::to_string(summary.evaluations) +
                            " evaluations, " + std::to_string(summary.optima) + " local optima, " +
                            std::to_string(found.size()) + " distinct after the polish, " +
                            std::to_string(added) + " new");
    result->search_seconds = summary.seconds;
  }
  if (kept_seeds == 0 && task.effort != Effort::kThorough) {
    *result = std::move(refined_only);
  } else {
    result->spherical_dyads = refined;
    BuildSphericalMechanisms(task, motion, result, options.reported_mechanisms);
  }
  result->refine_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SpatialMotionResult SolveSpatialTask(const Task& task, const TaskSolverOptions& options) {
  // Spherical seeds that will be refined make their four-bars after the refinement only.
  SpatialMotionOptions spatial = options.spatial;
  spatial.spherical.seed_mechanisms = false;
  SpatialMotionResult result = SolveSpatialMotion(task, spatial);
  if (result.model == "planar" && result.planar && result.plane && result.plane->poses.size() > 5) {
    // Planar data beyond five poses: the approximate planar synthesis, in the plane.
    Task planar_task = task;
    planar_task.space = Space::kPlanar;
    planar_task.planar_poses = result.plane->poses;
    result.planar = SolvePlanarTask(planar_task, options);
  }
  if (result.model == "spatial" && result.method == "least-squares" &&
      task.spatial_poses.size() > 7 && task.effort != Effort::kFast) {
    const auto start = std::chrono::steady_clock::now();
    // An SP dyad of the motion is a PS dyad of the inverted motion (E and Sigma exchanged).
    std::vector<DualQuaternion> inverted;
    for (const DualQuaternion& pose : task.spatial_poses) inverted.push_back(pose.Inverse());
    int simplified = 0;
    for (SpatialDyadReport& report : result.dyads) {
      if (RefineSpatialReport(task, inverted, result.scale, options.refiner, &report)) {
        ++simplified;
      }
    }
    if (simplified > 0) {
      result.notes.push_back(std::to_string(simplified) +
                             " refined spheres are reported as planes: at the data's precision "
                             "the poses cannot tell them from their plane readings");
    }
    DropRepeats(task, result.scale, &result.dyads);
    SortDyadsByRadius(&result.dyads);  // refinement can reorder radii, or make planes
    AddExactPoseNotes(task, options.refiner.exact_tolerance, &result);
    result.refine_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // Fast: the algebraic seeds, each projected onto the poses marked exact
  // (fitting/exact_items.h); balanced refines them with those poses held.
  if (result.model == "spatial" && result.method == "least-squares" &&
      task.effort == Effort::kFast &&
      std::find(task.pose_exact.begin(), task.pose_exact.end(), true) != task.pose_exact.end()) {
    int missed = 0;
    for (SpatialDyadReport& report : result.dyads) {
      if (!ProjectOntoExactPoses(task.spatial_poses, task.pose_exact, result.scale, &report.dyad)) {
        ++missed;
      }
      report.max_residual = report.dyad.MaxResidual(task.spatial_poses);
      report.error_bound =
          DyadErrorBound(report.dyad, task.spatial_poses, task.precision, result.scale);
    }
    if (missed > 0) {
      result.notes.push_back(std::to_string(missed) +
                             " seed dyads could not be moved onto the exact poses");
    }
    SortDyadsByRadius(&result.dyads);
  }
  if (result.model == "spherical" && result.method == "least-squares") {
    if (task.effort == Effort::kFast) {
      SolveSphericalSeedsFast(task, options, &result);
    } else {
      RefineSphericalResult(task, options, &result);
    }
  }
  PlatformMotionOptions platform = options.spatial.platform;
  if (result.method == "least-squares") {
    // A least-squares design meets the poses only nearly: judge it by its own residuals.
    double worst = 0.0;
    for (const SpatialDyadReport& report : result.dyads) {
      worst = std::max(worst, report.max_residual);
    }
    platform.assembly_tolerance =
        std::max(platform.assembly_tolerance, 10.0 * worst / result.scale);
    platform.pose_tolerance = std::max(platform.pose_tolerance, 10.0 * worst / result.scale);
  }
  AddPlatform(task, platform, &result);
  return result;
}

namespace {

double WeightedRms(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                   const std::vector<double>& weights) {
  double sum = 0.0, weight_sum = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const double weight = weights.empty() ? 1.0 : weights[j];
    const double residual = dyad.Residual(poses[j]);
    sum += weight * residual * residual;
    weight_sum += weight;
  }
  return std::sqrt(sum / weight_sum);
}

// The best stage figures of the current dyads and mechanisms.
StageReport Stage(const std::string& name, std::chrono::steady_clock::time_point start,
                  const PlanarMotionResult& result) {
  StageReport stage;
  stage.name = name;
  stage.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const DyadReport& dyad : result.dyads) {
    if (dyad.rms_residual) {
      stage.best_dyad_rms = std::min(stage.best_dyad_rms.value_or(1e300), *dyad.rms_residual);
    }
  }
  for (const MechanismReport& mechanism : result.mechanisms) {
    if (mechanism.max_pose_error) {
      stage.best_max_pose_error =
          std::min(stage.best_max_pose_error.value_or(1e300), *mechanism.max_pose_error);
    }
  }
  return stage;
}

// The best `count` distinct dyads of `found` in the order `before` (of two that are `same`, the
// first in that order); `dropped` gets how many more distinct ones there are.
template <typename Before, typename Same>
std::vector<DyadReport> BestDistinct(std::vector<DyadReport> found, int count, Before before,
                                     Same same, int* dropped) {
  std::stable_sort(found.begin(), found.end(), before);
  std::vector<DyadReport> kept;
  for (const DyadReport& report : found) {
    bool repeat = false;
    for (const DyadReport& other : kept) repeat |= same(report, other);
    if (!repeat) kept.push_back(report);
  }
  *dropped = std::max(0, static_cast<int>(kept.size()) - count);
  kept.resize(kept.size() - *dropped);
  return kept;
}

// Drops the dyads no listed four-bar uses, but for those `kept` marks (a shorter `kept`: the
// rest unmarked), and renumbers the four-bars' dyads.
void DropUnusedDyads(std::vector<bool> kept, PlanarMotionResult* result) {
  kept.resize(result->dyads.size(), false);
  for (const MechanismReport& mechanism : result->mechanisms) {
    kept[mechanism.input_dyad] = kept[mechanism.output_dyad] = true;
  }
  std::vector<int> index(result->dyads.size(), -1);
  std::vector<DyadReport> dyads;
  for (size_t i = 0; i < result->dyads.size(); ++i) {
    if (!kept[i]) continue;
    index[i] = static_cast<int>(dyads.size());
    dyads.push_back(result->dyads[i]);
  }
  for (MechanismReport& mechanism : result->mechanisms) {
    mechanism.input_dyad = index[mechanism.input_dyad];
    mechanism.output_dyad = index[mechanism.output_dyad];
  }
  result->dyads = std::move(dyads);
}

// Keeps the four-bars of effort level `top` (both dyads among its own: `mechanism_levels` has
// its bit) and of each lower level its best fit, the four-bar of least RMS pose error on one
// branch, where that fits better than the kept ones: so a higher effort never fits worse. Drops
// the dyads no kept four-bar uses, but for the level's own.
void KeepLevel(int top, const std::vector<int>& dyad_levels,
               const std::vector<int>& mechanism_levels, PlanarMotionResult* result) {
  const std::vector<MechanismReport>& mechanisms = result->mechanisms;
  const auto fit = [&mechanisms](size_t m) {
    return OnOneBranch(mechanisms[m].defects) ? mechanisms[m].rms_pose_error.value_or(1e300)
                                              : 1e300;
  };
  std::vector<bool> keep(mechanisms.size());
  double best_fit = 1e300;
  for (size_t m = 0; m < mechanisms.size(); ++m) {
    keep[m] = mechanism_levels[m] >> top & 1;
    if (keep[m]) best_fit = std::min(best_fit, fit(m));
  }
  for (int level = top - 1; level >= 0; --level) {
    size_t best = mechanisms.size();
    for (size_t m = 0; m < mechanisms.size(); ++m) {
      if ((mechanism_levels[m] >> level & 1) && fit(m) < best_fit) {
        best = m;
        best_fit = fit(m);
      }
    }
    if (best < mechanisms.size()) keep[best] = true;
  }
  std::vector<bool> kept_dyads(result->dyads.size(), false);
  for (size_t i = 0; i < dyad_levels.size(); ++i) kept_dyads[i] = dyad_levels[i] >> top & 1;
  std::vector<MechanismReport> kept;
  for (size_t m = 0; m < mechanisms.size(); ++m) {
    if (keep[m]) kept.push_back(mechanisms[m]);
  }
  result->mechanisms = std::move(kept);
  DropUnusedDyads(kept_dyads, result);
}

// Two refinements can end on one four-bar (the same two dyads): listed once, the first (best
// ranked) kept, with the effort levels (`levels`, one per four-bar) of both.
void ListOnce(std::vector<MechanismReport>* mechanisms, std::vector<int>* levels) {
  std::vector<MechanismReport> distinct;
  std::vector<int> distinct_levels;
  for (size_t m = 0; m < mechanisms->size(); ++m) {
    const MechanismReport& mechanism = (*mechanisms)[m];
    size_t k = 0;
    while (k < distinct.size() &&
           std::minmax(mechanism.input_dyad, mechanism.output_dyad) !=
               std::minmax(distinct[k].input_dyad, distinct[k].output_dyad)) {
      ++k;
    }
    if (k == distinct.size()) {
      distinct.push_back(mechanism);
      distinct_levels.push_back(0);
    }
    distinct_levels[k] |= (*levels)[m];
  }
  *mechanisms = std::move(distinct);
  *levels = std::move(distinct_levels);
}

// Trailing zeros a table may have lost (json.dump writes 1.200 as 1.2): two decimals.
constexpr double kTypedDecimals = 100.0;

// Minimal planar data whose precision was read from their digits (issue 35, item 3). A table
// reads the same with its trailing zeros or without them (lib/precision.h: the finest decimal
// of a kind sets it), but a table whose every number ends in zeros, or that was printed coarser
// than measured, claims a coarser precision than the same numbers written with kTypedDecimals
// finer digits. When that finer reading would list another type first, the precision as written
// cannot tell the two apart, and the note says so and which way the data lean: the first
// listed's slider misses the poses by its PrecisionRatio of what the precision allows
// (kModelUnits); below half of it the data lean to the slider, above to the circle. Empty
// otherwise.
std::string TypingNote(const Task& task, const TaskSolverOptions& options,
                       const PlanarMotionResult& result) {
  if (task.precision.source != "digits" || result.mechanisms.empty()) return "";
  if (!(RelativePrecision(task.precision, result.scale) > 1e-9)) return "";
  // A finer precision types fewer sliders, nothing else: where none is typed, both readings list
  // 4Rs, and the five poses are not solved again.
  if (std::none_of(result.dyads.begin(), result.dyads.end(),
                   [](const DyadReport& report) { return report.dyad.type != DyadType::kRR; })) {
    return "";
  }
  Task finer = task;
  finer.precision.length /= kTypedDecimals;
  finer.precision.angle /= kTypedDecimals;
  const PlanarMotionResult fine = SolvePlanarMotion(finer, options.planar);
  if (fine.mechanisms.empty()) return "";
  const MechanismReport& first = result.mechanisms.front();
  const MechanismReport& fine_first = fine.mechanisms.front();
  if (first.type == fine_first.type) return "";
  const std::string as_written = FourBarTypeName(first.type);
  const std::string finer_type = FourBarTypeName(fine_first.type);
  std::string note = "at the precision the digits give (" + PrecisionText(task.precision.length) +
                     " in length, " + PrecisionText(task.precision.angle * 180.0 / M_PI) +
                     " deg) the poses cannot tell a " + as_written + " from a " + finer_type +
                     ": the " + as_written +
                     " is listed first (the simpler model), and written "
                     "with two more decimals (1.200 for 1.2) the same poses would list the " +
                     finer_type + " first";
  double ratio = 0.0;
  for (const int index : {first.input_dyad, first.output_dyad}) {
    const PlanarDyad& dyad = result.dyads[index].dyad;
    if (dyad.type == DyadType::kRR) continue;
    ratio = std::max(ratio, PrecisionRatio(dyad, task.planar_poses, task.precision, result.scale));
  }
  if (ratio > 0.0) {
    note += "; its slider misses the poses by " + Format("%.2g", ratio / kModelUnits) +
            " of what the precision allows, so the data lean to the " +
            (ratio <= 0.5 * kModelUnits ? as_written : finer_type);
  }
  return note + " (give \"precision\" in the task when the table was measured finer)";
}

}  // namespace

PlanarMotionResult SolvePlanarTask(const Task& task, const TaskSolverOptions& options) {
  if (task.six_bar) {  // issue 36
    if (!task.chain) return SolveSixBarChosenChain(task, options);
    return task.planar_poses.size() == 5 ? SolveSixBarMotion(task)
                                         : SolveSixBarLeastSquares(task, options);
  }
  const std::vector<PlanarPose>& poses = task.planar_poses;
  if (poses.size() <= 5) {
    PlanarMotionResult result = SolvePlanarMotion(task, options.planar);
    const std::string lean = TypingNote(task, options, result);
    if (!lean.empty()) result.notes.push_back(lean);
    if (NeedsPivotChoices(task, result)) {
      const auto start = std::chrono::steady_clock::now();
      AddPivotChoices(task, options, &result);
      result.solve_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return result;
  }
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  result.scale = length;
  result.constraints = task.constraints;
  result.method = "least-squares";
  result.effort = EffortName(task.effort);
  const std::vector<double>& weights = task.pose_weights;
  const std::vector<bool>& exact = task.pose_exact;
  // The refiners and the search carry the task's design constraints (optimizers/design_bounds.h).
  PlanarDyadRefinerOptions dyad_refiner = options.planar_refiner;
  dyad_refiner.constraints = task.constraints;
  FourBarRefinerOptions four_bar_refiner = options.four_bar_refiner;
  four_bar_refiner.constraints = task.constraints;
  // Refined onto the bounds, a four-bar also holds its transmission angle: the constrained
  // optimum of the fit alone often lies where the transmission angle is a defect.
  FourBarRefinerOptions onto_bounds_refiner = four_bar_refiner;
  onto_bounds_refiner.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);

  // Seeds: the algebraic least-squares fit and exact solves of spread five-pose subsets.
  auto stage_start = std::chrono::steady_clock::now();
  std::vector<PlanarDyad> seeds;
  PlanarSeeds(poses, options.planar.burmester, options.seed_subsets, &seeds, exact);
  for (const PlanarDyad& seed : seeds) {
    DyadReport report;
    report.dyad = seed;
    report.rms_residual = WeightedRms(seed, poses, weights);
    result.dyads.push_back(report);
  }
  result.stages.push_back(Stage("seed", stage_start, result));

  // The dyads found by each effort level: fast the seeds, balanced also their refinements,
  // thorough also the search's.
  std::vector<size_t> found_count = {result.dyads.size()};
  if (task.effort != Effort::kFast) {
    stage_start = std::chrono::steady_clock::now();
    // The refined dyads join the seeds rather than replace them: seeds often refine to the same
    // few optima, and a seed that fits a little worse can still make the only four-bar without
    // a circuit or branch defect.
    const size_t seed_count = result.dyads.size();
    int simplified = 0;
    for (size_t i = 0; i < seed_count; ++i) {
      DyadReport report = result.dyads[i];
      report.seed_rms_residual = report.rms_residual;
      RefinePlanarDyad(poses, weights, exact, length, &report.dyad, dyad_refiner);
      // A circle the data cannot tell from a slider at their precision is the slider, refined.
      PlanarDyad slider;
      if (SimplerModel(report.dyad, poses, task.precision, length, &slider)) {
        RefinePlanarDyad(poses, weights, exact, length, &slider, dyad_refiner);
        if (slider.type != DyadType::kRR &&
            PrecisionRatio(slider, poses, task.precision, length) <= kModelUnits) {
          report.dyad = slider;
          ++simplified;
        }
      }
      report.rms_residual = WeightedRms(report.dyad, poses, weights);
      result.dyads.push_back(report);
    }
    if (simplified > 0) {
      result.notes.push_back(std::to_string(simplified) +
                             " refined circles are reported as sliders: at the data's precision "
                             "the poses cannot tell them from their slider readings");
    }
    result.stages.push_back(Stage("refine", stage_start, result));
    found_count.push_back(result.dyads.size());
  }
  // The search: thorough always; balanced too when the task has constraints (an optimum on a
  // bound is rarely near a seed: the seeds fit the poses, not the bounds).
  if (task.effort == Effort::kThorough ||
      (task.effort == Effort::kBalanced && task.constraints.given)) {
    stage_start = std::chrono::steady_clock::now();
    std::vector<PlanarDyad> found;
    GlobalSearchOptions search = options.search;
    search.refiner = dyad_refiner;
    SearchPlanarDyads(poses, weights, exact, length, search, &found);
    for (const PlanarDyad& dyad : found) {
      DyadReport report;
      report.dyad = dyad;
      report.rms_residual = WeightedRms(dyad, poses, weights);
      result.dyads.push_back(report);
    }
    result.stages.push_back(Stage("search", stage_start, result));
    found_count.push_back(result.dyads.size());
  }

  // Each effort level's dyads: the best few distinct ones it found, those within the constraints
  // that bound a single dyad first (seeds filtered), then best fit first. Dyads the data's
  // precision cannot tell apart (SameDyad within their error bounds) are one, the best listed.
  // A level's four-bars are the pairs of its dyads, and each level above fast refines its
  // best-ranked ones (below); the result lists the effort's own and, where better, the best fit
  // of a lower level (KeepLevel), so that a higher effort is never worse. `levels` marks, per
  // dyad, the levels it is one of (bit 0 fast, 1 balanced, 2 thorough).
  for (DyadReport& report : result.dyads) {
    report.error_bound = DyadErrorBound(report.dyad, poses, task.precision, length);
  }
  const auto keeps = [&](const DyadReport& report) {
    return DyadKeeps(task.constraints, report.dyad, length);
  };
  // Dyads through the exact poses first (a four-bar of two of them meets those poses).
  const auto meets_exact = [&](const DyadReport& report) {
    return ExactPoseMiss(report.dyad, task) <= kExactPoseTolerance * length;
  };
  const auto before = [&](const DyadReport& a, const DyadReport& b) {
    if (meets_exact(a) != meets_exact(b)) return meets_exact(a);
    if (keeps(a) != keeps(b)) return keeps(a);
    return a.rms_residual.value_or(1e300) < b.rms_residual.value_or(1e300);
  };
  Eigen::Vector2d pose_centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) {
    pose_centroid += pose.origin_in_fixed / static_cast<double>(poses.size());
  }
  const auto same = [&](const DyadReport& a, const DyadReport& b) {
    const double bound = std::min(a.error_bound.value_or(0.0), b.error_bound.value_or(0.0));
    return SameDyad(a.dyad, b.dyad, task.precision, length, pose_centroid, bound);
  };
  const int max_dyads =
      task.constraints.given ? kConstrainedDyadsFactor * options.max_dyads : options.max_dyads;
  const int refined_mechanisms = task.constraints.given
                                     ? kConstrainedRefinedFactor * options.refined_mechanisms
                                     : options.refined_mechanisms;
  std::vector<DyadReport> kept;
  std::vector<int> levels;
  int dropped_dyads = 0;
  for (size_t level = 0; level < found_count.size(); ++level) {
    const std::vector<DyadReport> best =
        BestDistinct({result.dyads.begin(), result.dyads.begin() + found_count[level]}, max_dyads,
                     before, same, &dropped_dyads);
    for (const DyadReport& report : best) {
      size_t k = 0;
      while (k < kept.size() && !same(report, kept[k])) ++k;
      if (k == kept.size()) {
        kept.push_back(report);
        levels.push_back(0);
      }
      levels[k] |= 1 << level;
    }
  }
  if (dropped_dyads > 0) {
    result.notes.push_back(std::to_string(dropped_dyads) +
                           " more dyads with larger residuals were found and dropped");
  }
  std::vector<size_t> order(kept.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return before(kept[a], kept[b]); });
  result.dyads.clear();
  std::vector<int> dyad_levels;
  for (size_t k : order) {
    result.dyads.push_back(kept[k]);
    dyad_levels.push_back(levels[k]);
  }
  for (DyadReport& report : result.dyads) report.max_residual = report.dyad.MaxResidual(poses);
  stage_start = std::chrono::steady_clock::now();
  const double precision_fit = PoseFitTolerance(task.precision, length);
  BuildMechanisms(task, length, &result,
                  [&](int i, int j) { return dyad_levels[i] & dyad_levels[j]; });
  std::vector<int> mechanism_levels;
  for (const MechanismReport& mechanism : result.mechanisms) {
    mechanism_levels.push_back(dyad_levels[mechanism.input_dyad] &
                               dyad_levels[mechanism.output_dyad]);
  }
  result.stages.push_back(Stage("four-bars", stage_start, result));

  int dropped = 0;  // four-bars beyond the list's bound
  if (task.effort != Effort::kFast) {
    // Mechanism level: the best-ranked four-bars refined on their pose error, the first
    // refined_mechanisms of each level above fast, each in rounds while a round lowers its RMS
    // pose error by more than kRoundGain (issue 35: `linkfit refine` then improves the first
    // listed by less than 1 %). A refined four-bar gets its own two dyads, appended to the list
    // (or the listed ones it repeats): four-bars refined onto one optimum are listed once
    // (below). When the first already meets the poses within their precision, without defect and
    // within the constraints, it is the answer: the others are not refined into near copies of
    // its dyads.
    stage_start = std::chrono::steady_clock::now();
    bool answered = false;
    if (!result.mechanisms.empty()) {
      const RankKey first =
          MechanismRankKey(result.mechanisms.front(), precision_fit, task.constraints);
      answered = !first.misses_exact && !first.violates && first.defect_level == 0 &&
                 first.within_precision;
    }
    // A four-bar that breaks a constraint is refined onto the bounds too (the penalties of
    // FourBarRefinerOptions::constraints), the first refined_mechanisms of them per level: the
    // constrained optimum is often the unconstrained one pulled onto a bound. What it gives is
    // listed beside it (an exact four-bar that breaks a constraint is never hidden).
    std::vector<int> chosen(found_count.size(), 0), chosen_onto(found_count.size(), 0);
    // Violating four-bars that share both dyads with ones already refined onto the bounds mostly
    // end on the same design: those refined bring a dyad not yet refined onto the bounds.
    std::vector<bool> onto_dyads(result.dyads.size(), false);
    // A refined dyad's index: the listed one it repeats (SameDyad, or one optimum reached twice:
    // within `optimum` in every parameter), else a new one appended.
    const auto listed_or_added = [&](const DyadReport& report, double optimum) {
      for (size_t i = 0; i < result.dyads.size(); ++i) {
        if (same(report, result.dyads[i]) ||
            (optimum > 0.0 && NearDyads(report.dyad, result.dyads[i].dyad, optimum, length))) {
          return static_cast<int>(i);
        }
      }
      result.dyads.push_back(report);
      return static_cast<int>(result.dyads.size()) - 1;
    };
    // One refinement of `current` (the seed `seed`, or the last round's refinement of it) with
    // `refiner`: the refined four-bar, or nothing where it is dropped (below). Its dyads, each
    // the listed one it repeats or a new one appended.
    const auto refine_once =
        [&](const MechanismReport& seed, const MechanismReport& current, bool onto_bounds,
            const FourBarRefinerOptions& refiner) -> std::optional<MechanismReport> {
      PlanarDyad input = result.dyads[current.input_dyad].dyad;
      PlanarDyad output = result.dyads[current.output_dyad].dyad;
      const RefinerSummary summary =
          RefineFourBar(poses, weights, exact, length, &input, &output, refiner);
      // A seed that misses an exact pose is refined for them, whatever the fit costs; else the
      // fit decides (the RMS pose error, the ranking's).
      if (!onto_bounds && !current.misses_exact && !(summary.final_rms < summary.initial_rms)) {
        return std::nullopt;
      }
      const size_t listed = result.dyads.size();
      int index[2];
      int k = 0;
      for (const PlanarDyad& dyad : {input, output}) {
        DyadReport report;
        report.dyad = dyad;
        report.max_residual = dyad.MaxResidual(poses);
        report.rms_residual = WeightedRms(dyad, poses, weights);
        report.error_bound = DyadErrorBound(dyad, poses, task.precision, length);
        index[k++] = listed_or_added(report, 0.0);
      }
      // Re-analysed, the refined pair may be driven by its other dyad (AnalyzeDyadPair), and
      // its errors are those of that drive: a refinement that adds a defect, breaks a
      // constraint, or is not better on them, is dropped; one onto the bounds is kept when it
      // keeps them all and adds no kinematic defect.
      MechanismReport refined;
      if (index[0] != index[1]) {
        refined = AnalyzeDyadPair(result.dyads, index[0], index[1], poses, length, exact);
        JudgeMechanism(task, result.dyads, length, &refined);
      }
      const bool adds_defect = std::any_of(
          refined.defects.begin(), refined.defects.end(), [&](const std::string& defect) {
            return (!onto_bounds || defect != "transmission") &&
                   std::find(seed.defects.begin(), seed.defects.end(), defect) ==
                       seed.defects.end();
          });
      // Meeting the exact poses decides first: a refinement that meets them where the seed
      // does not is better whatever its fit, one that misses them where the seed met them is
      // worse.
      const bool meets_exact = current.misses_exact && !refined.misses_exact;
      const bool worse = onto_bounds
                             ? !refined.violates.empty() || refined.misses_exact
                             : (refined.misses_exact && !current.misses_exact) ||
                                   refined.violates.size() > current.violates.size() ||
                                   (!meets_exact && !(refined.rms_pose_error.value_or(1e300) <
                                                      current.rms_pose_error.value_or(1e300)));
      if (index[0] == index[1] || !refined.max_pose_error || adds_defect || worse) {
        result.dyads.resize(listed);
        return std::nullopt;
      }
      refined.seed_max_pose_error = seed.max_pose_error;
      return refined;
    };
    // A four-bar that keeps the constraints, refined in rounds while a round gains more than
    // kRoundGain (a refinement can stop at its iteration limit): `mechanism` becomes the last
    // round's four-bar, or is marked tried (its "before_refinement" is itself) where no round
    // improves it.
    const auto polish = [&](MechanismReport* mechanism) {
      const MechanismReport seed = *mechanism;
      std::optional<MechanismReport> refined = refine_once(seed, seed, false, four_bar_refiner);
      for (int round = 1; refined && round < kPolishRounds; ++round) {
        const double before = refined->rms_pose_error.value_or(0.0);
        const std::optional<MechanismReport> again =
            refine_once(seed, *refined, false, four_bar_refiner);
        if (!again) break;
        refined = again;
        if (!AnotherRound(before, *again->rms_pose_error, true)) break;
      }
      if (refined) {
        *mechanism = *refined;
      } else {
        mechanism->seed_max_pose_error = seed.max_pose_error;
      }
    };
    const size_t ranked = result.mechanisms.size();
    for (size_t m = 0; m < ranked && !answered; ++m) {
      const MechanismReport seed = result.mechanisms[m];
      const bool onto_bounds = !seed.violates.empty();
      if (onto_bounds && onto_dyads[seed.input_dyad] && onto_dyads[seed.output_dyad]) continue;
      bool refine = false;
      for (size_t level = 1; level < found_count.size(); ++level) {
        if (!(mechanism_levels[m] >> level & 1)) continue;
        int& count = onto_bounds ? chosen_onto[level] : chosen[level];
        if (count < refined_mechanisms) {
          ++count;
          refine = true;
        }
      }
      if (!refine || !seed.max_pose_error) continue;
      if (!onto_bounds) {
        polish(&result.mechanisms[m]);
        continue;
      }
      onto_dyads[seed.input_dyad] = onto_dyads[seed.output_dyad] = true;
      const std::optional<MechanismReport> refined =
          refine_once(seed, seed, true, four_bar_refiner);
      if (refined) {
        result.mechanisms.push_back(*refined);
        mechanism_levels.push_back(mechanism_levels[m]);
      }
      // Onto the bounds, the fit's constrained optimum often has a transmission defect: the seed
      // is refined again holding the transmission angle (FourBarRefinerOptions::
      // min_transmission_deg), and that design listed too.
      const bool transmission_defect =
          !refined || std::find(refined->defects.begin(), refined->defects.end(), "transmission") !=
                          refined->defects.end();
      if (!transmission_defect) continue;
      if (const std::optional<MechanismReport> held =
              refine_once(seed, seed, true, onto_bounds_refiner)) {
        result.mechanisms.push_back(*held);
        mechanism_levels.push_back(mechanism_levels[m]);
      }
    }
    ListOnce(&result.mechanisms, &mechanism_levels);
    KeepLevel(static_cast<int>(found_count.size()) - 1, dyad_levels, mechanism_levels, &result);
    result.stages.push_back(Stage("four-bar refine", stage_start, result));

    // Every listed four-bar refined as `linkfit refine` refines it (RefinePlanarDesign; issue 35:
    // a designer who refines a listed four-bar finds it at its optimum already). The list as
    // ranked and bounded (below); in rounds, each of its four-bars that misses the poses by more
    // than their precision (and gained enough in the last round: kListedRounds) refined, and
    // taken where it fits better and is not worse by the ranking's rule (misses no exact pose it
    // met, breaks no given constraint it kept, no higher defect level, no new kinematic defect);
    // after each round, four-bars refined onto one are listed once, so that a round refines each
    // optimum once. (A four-bar that breaks a constraint is refined with the constraints'
    // penalties, as `linkfit refine` does; the mechanism level lists its refinement onto the
    // bounds beside it.)
    stage_start = std::chrono::steady_clock::now();
    dropped += RankMechanisms(precision_fit, task.constraints, options.reported_mechanisms,
                              &result.mechanisms);
    const size_t stage_dyads = result.dyads.size();
    std::vector<int> active;  // 1: refined in the next round
    for (const MechanismReport& mechanism : result.mechanisms) {
      const RankKey key = MechanismRankKey(mechanism, precision_fit, task.constraints);
      active.push_back(mechanism.rms_pose_error && !key.within_precision ? 1 : 0);
    }
    for (int round = 0; round < kListedRounds; ++round) {
      std::vector<size_t> refined_now;
      for (size_t k = 0; k < active.size(); ++k) {
        if (active[k]) refined_now.push_back(k);
      }
      if (refined_now.empty()) break;
      std::vector<std::optional<PlanarMotionResult>> polished(refined_now.size());
      std::vector<char> descending(refined_now.size(), 0);  // stopped at its iteration limit
      ParallelFor(refined_now.size(), ThreadCount(options.threads), [&](size_t i) {
        const MechanismReport& listed = result.mechanisms[refined_now[i]];
        bool converged = true;
        PlanarMotionResult refined =
            RefinePlanarDesign(task, result.dyads[listed.input_dyad].dyad,
                               result.dyads[listed.output_dyad].dyad, options, &converged);
        descending[i] = !converged;
        const MechanismReport& mechanism = refined.mechanisms[0];
        const RankKey key = MechanismRankKey(mechanism, precision_fit, task.constraints);
        const RankKey listed_key = MechanismRankKey(listed, precision_fit, task.constraints);
        if (!mechanism.rms_pose_error || !(*mechanism.rms_pose_error < *listed.rms_pose_error) ||
            WorseRanked(listed_key, listed.defects, key, mechanism.defects)) {
          return;
        }
        polished[i] = std::move(refined);
      });
      for (size_t i = 0; i < refined_now.size(); ++i) {
        const size_t k = refined_now[i];
        active[k] = 0;
        if (!polished[i]) continue;
        MechanismReport& listed = result.mechanisms[k];
        // The refined dyads, each the listed one it repeats (or one optimum reached twice:
        // kSamePlanarOptimum) or a new one appended, and the four-bar they make taken where it
        // fits better than the listed one (not where both repeat one dyad: no four-bar).
        const size_t listed_dyads = result.dyads.size();
        int index[2];
        for (int d = 0; d < 2; ++d) {
          index[d] = listed_or_added(polished[i]->dyads[d], kSamePlanarOptimum * length);
        }
        MechanismReport refined;
        if (index[0] != index[1]) {
          refined = AnalyzeDyadPair(result.dyads, index[0], index[1], poses, length, exact);
          JudgeMechanism(task, result.dyads, length, &refined);
        }
        if (!refined.rms_pose_error || !(*refined.rms_pose_error < *listed.rms_pose_error)) {
          result.dyads.resize(listed_dyads);
          continue;
        }
        active[k] = AnotherRound(*listed.rms_pose_error, *refined.rms_pose_error, !descending[i]);
        refined.seed_max_pose_error =
            listed.seed_max_pose_error ? listed.seed_max_pose_error : listed.max_pose_error;
        listed = refined;
      }
      ListOnce(&result.mechanisms, &active);
    }
    // The dyads this stage added that no listed four-bar kept (refinements onto one optimum).
    DropUnusedDyads(std::vector<bool>(stage_dyads, true), &result);
    result.stages.push_back(Stage("refine the listed", stage_start, result));
  }
  // Ranked, and a bounded list (ListedWithinBound): the best ranked, and the best fit of each
  // group. (Every dyad has its error bound: the seeds' were set before the dyads were merged,
  // the refined ones' when they were added.)
  dropped += RankMechanisms(precision_fit, task.constraints, options.reported_mechanisms,
                            &result.mechanisms);
  if (dropped > 0) result.notes.push_back(DroppedNote(dropped));
  {
    std::vector<RankKey> keys;
    for (const MechanismReport& mechanism : result.mechanisms) {
      keys.push_back(MechanismRankKey(mechanism, precision_fit, task.constraints));
    }
    const std::string note = DefaultsNote(keys, "an RMS pose error of");
    if (!note.empty()) result.notes.push_back(note);
    if (!result.mechanisms.empty()) {
      const MechanismReport& first = result.mechanisms.front();
      const std::string given =
          GivenConstraintsNote(task.constraints, first.violates, first.defects);
      if (!given.empty()) result.notes.push_back(given);
    }
    const long swapped =
        std::count_if(result.mechanisms.begin(), result.mechanisms.end(),
                      [](const MechanismReport& m) { return m.order_within_noise; });
    if (swapped > 0) {
      result.notes.push_back(
          std::to_string(swapped) +
          " four-bar(s) reach some neighbouring poses, closer to each other than the fit's "
          "residual at them, in swapped order: within the data's noise, not an order defect");
    }
  }
  if (result.dyads.empty()) result.notes.push_back("no dyad: the seeds failed (degenerate poses?)");
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

TaskResult SolveTask(const Task& task, const TaskSolverOptions& options) {
  // Function results carry the task's notes and precision themselves.
  if (task.problem == ProblemKind::kFunction) return SolveFunctionTask(task, options);
  TaskResult result;
  if (task.problem == ProblemKind::kMotion && task.space == Space::kPlanar) {
    result = SolvePlanarTask(task, options);
  } else if (task.problem == ProblemKind::kMotion && task.space == Space::kSpatial) {
    result = SolveSpatialTask(task, options);
  } else {
    result = SolvePathTask(task, options);
  }
  std::visit(
      [&task](auto& solved) {
        solved.precision = task.precision;
        if constexpr (!std::is_same_v<std::decay_t<decltype(solved)>, FunctionResult>) {
          solved.closed = task.closed;
        }
        // What reading the task did comes first.
        solved.notes.insert(solved.notes.begin(), task.input_notes.begin(), task.input_notes.end());
      },
      result);
  return result;
}

namespace {

// "before: max a, RMS b; after: max c, RMS d (n iterations)" of a refinement, `what` the error;
// a design not driven through the poses has no error ("none").
std::string BeforeAfterNote(const std::string& what, double initial_max, double initial_rms,
                            double final_max, double final_rms, int iterations) {
  const auto pair = [](double max, double rms) {
    if (!std::isfinite(max)) return std::string("none (not driven through the poses)");
    char text[80];
    std::snprintf(text, sizeof(text), "max %.6g, RMS %.6g", max, rms);
    return std::string(text);
  };
  return what + " before: " + pair(initial_max, initial_rms) +
         "; after: " + pair(final_max, final_rms) + " (" + std::to_string(iterations) +
         " iterations)";
}

}  // namespace

constexpr double kInfinityValue = std::numeric_limits<double>::infinity();

std::string TransmissionNote(const DesignConstraints& constraints) {
  char line[240];
  std::snprintf(line, sizeof(line),
                "the refined design's transmission angle falls below %.3g deg, the design's did "
                "not: give \"constraints\": {\"min_transmission_angle_deg\": %.3g} in the task "
                "to hold it",
                MinTransmissionAngleDeg(constraints), MinTransmissionAngleDeg(constraints));
  return line;
}

PlanarMotionResult RefinePlanarDesign(const Task& task, const PlanarDyad& input,
                                      const PlanarDyad& output, const TaskSolverOptions& options,
                                      bool* converged) {
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  FourBarRefinerOptions refiner = options.four_bar_refiner;
  refiner.constraints = task.constraints;
  // Refines a design from `from_input` and `from_output` with `with` and judges it: the dyads'
  // reports and the four-bar's.
  const auto refine_from = [&](const PlanarDyad& from_input, const PlanarDyad& from_output,
                               const FourBarRefinerOptions& with, RefinerSummary* summary) {
    PlanarMotionResult result;
    PlanarDyad refined_input = from_input, refined_output = from_output;
    *summary = RefineFourBar(poses, task.pose_weights, task.pose_exact, length, &refined_input,
                             &refined_output, with);
    for (const PlanarDyad& dyad : {refined_input, refined_output}) {
      DyadReport report;
      report.dyad = dyad;
      report.max_residual = dyad.MaxResidual(poses);
      report.rms_residual = WeightedRms(dyad, poses, task.pose_weights);
      report.error_bound = DyadErrorBound(dyad, poses, task.precision, length);
      result.dyads.push_back(report);
    }
    MechanismReport mechanism = AnalyzeDyadPair(result.dyads, 0, 1, poses, length, task.pose_exact);
    JudgeMechanism(task, result.dyads, length, &mechanism);
    result.mechanisms.push_back(mechanism);
    return result;
  };
  // The design's own refinement, and the one that first refines each dyad on its residuals (the
  // solver's dyad stage, planar_dyad_refiner.h): a design outside the four-bar refiner's reach
  // (it does not assemble at the first pose, or its circuit leads elsewhere) comes in from its
  // dyads' own optima. The better of the two is kept: the one driven through the poses, then
  // with fewer kinematic defects, fewer broken constraints, the smaller RMS pose error (the
  // largest for minimal data). A second start RefineFourBar gives back unchanged is not taken.
  const auto refine = [&](const FourBarRefinerOptions& with, RefinerSummary* summary) {
    PlanarMotionResult result = refine_from(input, output, with, summary);
    PlanarDyadRefinerOptions dyad_options = options.planar_refiner;
    dyad_options.constraints = task.constraints;
    PlanarDyad dyad_input = input, dyad_output = output;
    for (PlanarDyad* dyad : {&dyad_input, &dyad_output}) {
      RefinePlanarDyad(poses, task.pose_weights, task.pose_exact, length, dyad, dyad_options);
    }
    // Dyads at their own optima already (the solver's four-bars of refined dyads): the second
    // start is the first, refined alike.
    if (NearDyads(input, dyad_input, kUnmovedDyad * length, length) &&
        NearDyads(output, dyad_output, kUnmovedDyad * length, length)) {
      return result;
    }
    RefinerSummary via_summary;
    PlanarMotionResult via = refine_from(dyad_input, dyad_output, with, &via_summary);
    const auto key = [](const MechanismReport& mechanism) {
      const int kinematic = static_cast<int>(
          std::count_if(mechanism.defects.begin(), mechanism.defects.end(),
                        [](const std::string& defect) { return defect != "transmission"; }));
      // The fit's own measure: the RMS pose error where least squares reports it (a design
      // with a smaller largest error but a larger RMS is no better fit), else the largest.
      const std::optional<double>& error =
          mechanism.rms_pose_error ? mechanism.rms_pose_error : mechanism.max_pose_error;
      return std::make_tuple(!mechanism.max_pose_error.has_value(), kinematic,
                             mechanism.violates.size(), error.value_or(kInfinityValue));
    };
    // A start RefineFourBar returns unchanged (its dyads coincide: both reached one dyad
    // optimum, or it does not assemble) is no refinement: two dyads at one optimum make no
    // four-bar, however well their near-copy fits.
    if (std::isfinite(via_summary.final_rms) &&
        key(via.mechanisms[0]) < key(result.mechanisms[0])) {
      via_summary.initial_cost = summary->initial_cost;
      via_summary.initial_rms = summary->initial_rms;
      via_summary.initial_max = summary->initial_max;
      via_summary.iterations += summary->iterations;
      via_summary.seconds += summary->seconds;
      via.notes.push_back(
          "refined dyad by dyad on their residuals first: the four-bar refinement of the design "
          "itself ended worse");
      result = via;
      *summary = via_summary;
    } else {
      summary->seconds += via_summary.seconds;
    }
    result.mechanisms[0].seed_max_pose_error = summary->initial_max;
    return result;
  };
  const auto has = [](const MechanismReport& mechanism, const char* defect) {
    return std::find(mechanism.defects.begin(), mechanism.defects.end(), defect) !=
           mechanism.defects.end();
  };
  // With constraints given, a design whose transmission angle keeps their minimum keeps it: the
  // refiner holds it (FourBarRefinerOptions::min_transmission_deg). Without, the refinement is
  // the fit's, and a note says when it costs the angle.
  std::vector<DyadReport> seed_dyads(2);
  seed_dyads[0].dyad = input;
  seed_dyads[1].dyad = output;
  MechanismReport seed = AnalyzeDyadPair(seed_dyads, 0, 1, poses, length, task.pose_exact);
  JudgeMechanism(task, seed_dyads, length, &seed);
  const bool seed_transmission_kept = seed.max_pose_error && !has(seed, "transmission");
  if (task.constraints.given && seed_transmission_kept) {
    refiner.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
  }
  RefinerSummary summary;
  PlanarMotionResult result = refine(refiner, &summary);
  // With constraints, a refinement that ends on a transmission defect is repeated holding the
  // angle, as the solver does onto the bounds; the held design is taken when it keeps the
  // constraints without that defect.
  if (task.constraints.given && !refiner.min_transmission_deg &&
      has(result.mechanisms[0], "transmission")) {
    FourBarRefinerOptions held = refiner;
    held.min_transmission_deg = MinTransmissionAngleDeg(task.constraints);
    RefinerSummary held_summary;
    PlanarMotionResult held_result = refine(held, &held_summary);
    const MechanismReport& mechanism = held_result.mechanisms[0];
    if (mechanism.violates.empty() && !has(mechanism, "transmission") && mechanism.max_pose_error) {
      held_summary.seconds += summary.seconds;
      held_result.notes.push_back(
          "the refinement held the transmission angle: without the hold it ended below the "
          "task's minimum");
      result = held_result;
      summary = held_summary;
    }
  }
  // Never a design with a kinematic defect the given one did not have (as for path designs, and
  // as the solver refines its listed four-bars): the design is given back unchanged.
  const std::vector<std::string> added_defects =
      seed.max_pose_error ? AddedKinematicDefects(seed.defects, result.mechanisms[0].defects)
                          : std::vector<std::string>();
  if (!added_defects.empty()) {
    PlanarMotionResult given;
    for (DyadReport report : seed_dyads) {
      report.max_residual = report.dyad.MaxResidual(poses);
      report.rms_residual = WeightedRms(report.dyad, poses, task.pose_weights);
      report.error_bound = DyadErrorBound(report.dyad, poses, task.precision, length);
      given.dyads.push_back(report);
    }
    MechanismReport unchanged = AnalyzeDyadPair(given.dyads, 0, 1, poses, length, task.pose_exact);
    JudgeMechanism(task, given.dyads, length, &unchanged);
    given.mechanisms.push_back(unchanged);
    std::string added;
    for (const std::string& defect : added_defects) added += (added.empty() ? "" : ", ") + defect;
    given.notes.push_back("no refinement improved the design without a new defect (it ended with " +
                          added + "): it is given back unchanged");
    summary.final_max = summary.initial_max;
    summary.final_rms = summary.initial_rms;
    summary.converged = true;
    result = given;
  } else if (seed_transmission_kept && has(result.mechanisms[0], "transmission")) {
    result.notes.push_back(TransmissionNote(task.constraints));
  }
  result.method = "refine";
  result.scale = length;
  result.effort = EffortName(task.effort);
  result.precision = task.precision;
  result.closed = task.closed;
  result.constraints = task.constraints;
  StageReport stage;
  stage.name = "four-bar refine";
  stage.seconds = summary.seconds;
  stage.best_max_pose_error = summary.final_max;
  result.stages.push_back(stage);
  result.notes.insert(result.notes.begin(),
                      BeforeAfterNote("pose error", summary.initial_max, summary.initial_rms,
                                      summary.final_max, summary.final_rms, summary.iterations));
  if (!summary.message.empty()) result.notes.push_back(summary.message);
  result.solve_seconds = summary.seconds;
  if (converged != nullptr) *converged = summary.converged;
  return result;
}

SpatialMotionResult RefineSpatialDesign(const Task& task, const std::vector<SpatialDyad>& dyads,
                                        const std::vector<int>& platform,
                                        const TaskSolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SpatialMotionResult result;
  result.method = "refine";
  result.scale = SpatialTaskLength(task);
  result.precision = task.precision;
  result.closed = task.closed;
  std::vector<DualQuaternion> inverted;
  for (const DualQuaternion& pose : task.spatial_poses) inverted.push_back(pose.Inverse());
  int simplified = 0;
  double initial_max = 0.0, final_max = 0.0;
  for (const SpatialDyad& dyad : dyads) {
    SpatialDyadReport report;
    report.dyad = dyad;
    if (RefineSpatialReport(task, inverted, result.scale, options.refiner, &report)) {
      ++simplified;
    }
    report.error_bound =
        DyadErrorBound(report.dyad, task.spatial_poses, task.precision, result.scale);
    initial_max = std::max(initial_max, report.seed_max_residual.value_or(0.0));
    final_max = std::max(final_max, report.max_residual);
    result.dyads.push_back(report);
  }
  char line[200];
  std::snprintf(line, sizeof(line),
                "%zu dyad(s) refined on their residuals: largest residual before %.6g, after %.6g "
                "(each dyad's before_refinement and max_residual)",
                dyads.size(), initial_max, final_max);
  result.notes.push_back(line);
  if (simplified > 0) {
    result.notes.push_back(std::to_string(simplified) +
                           " refined spheres are reported as planes: at the data's precision "
                           "the poses cannot tell them from their plane readings");
  }
  AddExactPoseNotes(task, options.refiner.exact_tolerance, &result);
  AddSpatialConstraintsNote(task, &result);
  result.refine_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The platform of the design's five (or, without one, the default five), judged by the
  // refined dyads' own residuals as a least-squares design is.
  PlatformMotionOptions platform_options = options.spatial.platform;
  platform_options.assembly_tolerance =
      std::max(platform_options.assembly_tolerance, 10.0 * final_max / result.scale);
  platform_options.pose_tolerance =
      std::max(platform_options.pose_tolerance, 10.0 * final_max / result.scale);
  Task platform_task = task;
  platform_task.platform = platform;
  AddPlatform(platform_task, platform_options, &result);
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

TaskResult RefineTask(const Task& task, const TaskDesign& design, const RefineChoice& choice,
                      const TaskSolverOptions& options) {
  const auto listed = [&](size_t count, const char* what) {
    if (choice.mechanism < 0 || static_cast<size_t>(choice.mechanism) >= count) {
      throw InputError(choice.mechanism_item + ": the design lists " + std::to_string(count) + " " +
                       what);
    }
    return static_cast<size_t>(choice.mechanism);
  };
  if (const SixBarDesign* six_bars = std::get_if<SixBarDesign>(&design)) {
    const size_t m = listed(six_bars->six_bars.size(), "six-bars");
    return RefineSixBarDesign(task, six_bars->six_bars[m], six_bars->at_poses[m], options);
  }
  if (task.problem == ProblemKind::kPath) {
    const PathDesign& path = std::get<PathDesign>(design);
    const size_t m = listed(path.four_bars.size(), "mechanisms");
    const std::vector<double>& angles = path.input_angles[m];
    if (!angles.empty() && angles.size() != task.points.size()) {
      throw InputError(choice.design_source + ": mechanisms[" + std::to_string(m) +
                       "].input_deg: expected " + std::to_string(task.points.size()) +
                       " angles (one per point of the task), got " + std::to_string(angles.size()));
    }
    try {
      return RefinePathDesign(task, path.four_bars[m], angles, options);
    } catch (const std::invalid_argument& error) {
      throw InputError(choice.design_source + ": mechanisms[" + std::to_string(m) +
                       "]: " + error.what());
    }
  }
  if (task.space == Space::kSpatial) {
    const SpatialDesign& spatial = std::get<SpatialDesign>(design);
    if (task.spatial_poses.size() < 7) {
      throw InputError(choice.task_source +
                       ": refine of spatial dyads takes at least seven poses "
                       "(an SS dyad has seven parameters), the task has " +
                       std::to_string(task.spatial_poses.size()));
    }
    if (spatial.platforms.empty()) {
      return RefineSpatialDesign(task, spatial.dyads, task.platform, options);
    }
    const size_t m = listed(spatial.platforms.size(), "platforms");
    std::vector<SpatialDyad> five;
    for (int index : spatial.platforms[m]) five.push_back(spatial.dyads[index]);
    return RefineSpatialDesign(task, five, {0, 1, 2, 3, 4}, options);
  }
  const PlanarDesign& planar = std::get<PlanarDesign>(design);
  std::pair<int, int> pair;
  if (!planar.mechanisms.empty()) {
    pair = planar.mechanisms[listed(planar.mechanisms.size(), "mechanisms")];
  } else if (planar.dyads.size() == 2) {
    pair = {0, 1};
  } else {
    throw InputError(choice.design_source +
                     ": mechanisms: missing field (needed to pick two of the " +
                     std::to_string(planar.dyads.size()) + " dyads)");
  }
  return RefinePlanarDesign(task, planar.dyads[pair.first], planar.dyads[pair.second], options);
}

}  // namespace linkfit
