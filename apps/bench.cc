// linkfit_bench: measures the five-pose solver on random exact tasks made by random
// mechanisms. Prints, per mechanism family: tasks, share with the generating dyads recovered
// (relative error <= 1e-9: pivot, radius and line differences over the dyad's own size, its
// largest pivot distance from the poses, and never less than L), the 99.9th percentile of that
// error, the share of misses that are data-limited (a one-ulp change of the input poses moves the
// exact answer by at least half the miss, so no double-precision input can pin the dyad down to
// 1e-9), the worst residual of any returned dyad over L, real roots found, and the median and
// 99th-percentile time of one solve (SolvePlanarBurmester; and of the whole SolvePlanarMotion,
// which adds the mechanism assembly checks) on one core.
//
// Then the seven-pose spatial solver (seed 000) on random tasks: the share of tasks whose 20
// roots are all found and verified (20 distinct roots, each with a polished residual below
// 1e-11 on the bilinear equations), the worst residual of a returned dyad over L, real roots and
// the median and 99th-percentile time of SolveSpatialBurmester; the share of planted SS/PS dyads
// recovered (relative error <= 1e-8); and least-squares tasks (10 and 30 noisy poses on planted
// dyads): the RMS residual of the planted dyads' seeds before and after the Ceres refinement,
// and the end-to-end time of SolveSpatialTask (seed, refinement, platform).
//
// Then approximate planar synthesis (more poses than five): for N = 10, 50, 200 poses from a
// random four-bar, noise 0, 1e-3 L and 1e-2 L on positions and L times the angles, and each
// effort level (fast, balanced, thorough), the median and worst time of SolvePlanarTask and the
// median and worst RMS pose error of its best four-bar without a circuit or branch defect (order
// defects are left aside: dense noisy poses reorder neighbouring inputs), relative to the
// generating mechanism's RMS pose error on the same noisy poses (for exact data: in units of L),
// and the share of tasks where it fits within 10 % of the generating mechanism (or better). Written
// to a CSV file (--csv, default least_squares.csv) as well.
//
// Then path generation with prescribed timing (seed 002): random five-point tasks made by random
// crank-driven four-bars (4R, slider-crank, inverted slider-crank): the share with the generating
// four-bar recovered (error <= 1e-8 in every pivot, line and the coupler point, relative to the
// four-bar's size: its largest pivot or point distance from the points, never less than L), the
// mean and largest number of four-bars returned, the worst point error over L of a returned
// four-bar without defects (assembled and driven through the points), and the median and
// 99th-percentile time of SolveTimedPath plus the simulation of every four-bar it returns
// (AnalyzePathFourBar). Then least squares (10 and 20 points, noise 0, 1e-3 L, 1e-2 L, each
// effort level; error = RMS point error of the best defect-free four-bar / the generating one's
// on the same points, noise 0: largest point error / L), and free timing (points without input
// angles, 10 and 20 points: time, final largest point error / L, and the share of tasks fitted to
// 1e-6 L (noise 0) or within 10 % of the generating four-bar). Written to path.csv (--path-csv).
//
//   linkfit_bench [--tasks N] [--spatial-tasks M] [--ls-tasks K] [--path-tasks P]
//                 [--path-ls-tasks Q] [--seed S]
//                 [--only planar|spatial|least-squares|path] [--csv FILE] [--path-csv FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fitting/planar_burmester.h"
#include "fitting/planar_motion.h"
#include "fitting/spatial_burmester.h"
#include "fitting/timed_path.h"
#include "lib/four_bar_motion.h"
#include "lib/path_motion.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spatial.h"

namespace {

using linkfit::DyadType;

constexpr double kRecoveryTolerance = 1e-9;

// The larger recovery error of the two generating dyads.
double RecoveryError(const linkfit::testing::GeneratedTask& task,
                     const std::vector<linkfit::PlanarPose>& poses) {
  std::vector<linkfit::PlanarDyad> dyads;
  linkfit::SolvePlanarBurmester(poses, linkfit::PlanarBurmesterOptions(), &dyads);
  return std::max(linkfit::testing::NearestDyadDistance(
                      dyads, task.input, linkfit::testing::DyadScale(task.input, task.poses)),
                  linkfit::testing::NearestDyadDistance(
                      dyads, task.output, linkfit::testing::DyadScale(task.output, task.poses)));
}

// The largest recovery error over a few random one-ulp perturbations of every input number.
double OneUlpSensitivity(const linkfit::testing::GeneratedTask& task, std::mt19937_64& rng) {
  const double ulp = std::numeric_limits<double>::epsilon();
  std::uniform_int_distribution<int> sign(0, 1);
  double worst = 0.0;
  for (int k = 0; k < 8; ++k) {
    std::vector<linkfit::PlanarPose> poses = task.poses;
    for (linkfit::PlanarPose& pose : poses) {
      pose.origin_in_fixed.x() *= 1.0 + (sign(rng) ? ulp : -ulp);
      pose.origin_in_fixed.y() *= 1.0 + (sign(rng) ? ulp : -ulp);
      pose.theta *= 1.0 + (sign(rng) ? ulp : -ulp);
    }
    worst = std::max(worst, RecoveryError(task, poses));
  }
  return worst;
}

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(fraction * values.size()));
  return values[index];
}

struct Family {
  const char* name;
  DyadType input;
  DyadType output;
};

void RunFamily(const Family& family, int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> solve_us, motion_us, recovery_errors;
  int recovered = 0, data_limited = 0;
  std::mt19937_64 perturbation_rng(seed ^ 0x9e3779b97f4a7c15ull);
  long real_roots = 0;
  double worst_residual = 0.0;
  std::vector<linkfit::PlanarDyad> dyads;
  const linkfit::PlanarBurmesterOptions options;
  for (int t = 0; t < tasks; ++t) {
    const linkfit::testing::GeneratedTask task =
        linkfit::testing::RandomTask(rng, family.input, family.output);
    const double length = linkfit::CharacteristicLength(task.poses);
    linkfit::PlanarBurmesterSummary summary;
    const auto start = std::chrono::steady_clock::now();
    linkfit::SolvePlanarBurmester(task.poses, options, &dyads, &summary);
    const auto stop = std::chrono::steady_clock::now();
    solve_us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
    real_roots += summary.roots_real;
    const double error =
        std::max(linkfit::testing::NearestDyadDistance(
                     dyads, task.input, linkfit::testing::DyadScale(task.input, task.poses)),
                 linkfit::testing::NearestDyadDistance(
                     dyads, task.output, linkfit::testing::DyadScale(task.output, task.poses)));
    recovery_errors.push_back(error);
    if (error <= kRecoveryTolerance) {
      ++recovered;
    } else if (OneUlpSensitivity(task, perturbation_rng) >= 0.5 * error) {
      ++data_limited;
    }
    for (const linkfit::PlanarDyad& dyad : dyads) {
      worst_residual = std::max(worst_residual, dyad.MaxResidual(task.poses) / length);
    }
    if (t % 10 == 0) {  // the end-to-end path on a tenth of the tasks
      linkfit::Task full;
      full.planar_poses = task.poses;
      const auto motion_start = std::chrono::steady_clock::now();
      const linkfit::PlanarMotionResult result = linkfit::SolvePlanarMotion(full);
      motion_us.push_back(
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - motion_start)
              .count());
      (void)result;
    }
  }
  std::printf("%-24s %8d %10.3f%% %12.2e %11.3f%% %11.3f%% %12.2e %6.2f %10.2f %8.2f %11.2f\n",
              family.name, tasks, 100.0 * recovered / tasks, Percentile(recovery_errors, 0.999),
              100.0 * data_limited / tasks, 100.0 * (tasks - recovered - data_limited) / tasks,
              worst_residual, static_cast<double>(real_roots) / tasks, Percentile(solve_us, 0.5),
              Percentile(solve_us, 0.99), Percentile(motion_us, 0.5));
}

using linkfit::DualQuaternion;
using linkfit::SpatialDyad;
using linkfit::SpatialDyadType;

double MicrosecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
      .count();
}

// Random seven-pose tasks: every root found and verified?
void RunSpatialRandom(int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> solve_us;
  int complete = 0, degenerate = 0;
  long real_roots = 0;
  double worst_residual = 0.0;
  std::vector<SpatialDyad> dyads;
  const linkfit::SpatialBurmesterOptions options;
  for (int t = 0; t < tasks; ++t) {
    std::vector<DualQuaternion> poses;
    for (int j = 0; j < 7; ++j) poses.push_back(linkfit::testing::RandomSpatialPose(rng));
    linkfit::SpatialBurmesterSummary summary;
    const auto start = std::chrono::steady_clock::now();
    linkfit::SolveSpatialBurmester(poses, {}, options, &dyads, &summary);
    solve_us.push_back(MicrosecondsSince(start));
    complete += summary.roots_total == 20 && summary.roots_verified == 20;
    degenerate += summary.degenerate;
    real_roots += summary.roots_real;
    double sum = 0.0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const DualQuaternion& pose : poses) centroid += pose.Translation() / 7.0;
    for (const DualQuaternion& pose : poses) sum += (pose.Translation() - centroid).squaredNorm();
    const double length = std::sqrt(sum / 7.0);
    for (const SpatialDyad& dyad : dyads) {
      worst_residual = std::max(worst_residual, dyad.MaxResidual(poses) / length);
    }
  }
  std::printf("%-30s %8d %11.3f%% %11.3f%% %12.2e %6.2f %10.1f %8.1f\n", "7 random poses", tasks,
              100.0 * complete / tasks, 100.0 * degenerate / tasks, worst_residual,
              static_cast<double>(real_roots) / tasks, Percentile(solve_us, 0.5),
              Percentile(solve_us, 0.99));
}

// Seven poses built on three SS and one PS dyad: are they recovered?
void RunSpatialPlanted(int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> solve_us;
  int recovered = 0;
  double worst_error = 0.0;
  std::vector<SpatialDyad> dyads;
  for (int t = 0; t < tasks; ++t) {
    const DualQuaternion start = linkfit::testing::RandomSpatialPose(rng);
    const std::vector<SpatialDyad> planted = linkfit::testing::DyadsThroughPose(
        rng, start,
        {SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kPS});
    const std::vector<DualQuaternion> poses =
        linkfit::testing::PosesOnDyads(rng, planted, start, 7);
    const auto begin = std::chrono::steady_clock::now();
    linkfit::SolveSpatialBurmester(poses, {}, {}, &dyads);
    solve_us.push_back(MicrosecondsSince(begin));
    double error = 0.0;
    for (const SpatialDyad& expected : planted) {
      error = std::max(error, linkfit::testing::NearestSpatialDyadDistance(dyads, expected));
    }
    worst_error = std::max(worst_error, error);
    recovered += error <= 1e-8;
  }
  std::printf("%-30s %8d %11.3f%% %12.2e %10.1f %8.1f\n", "7 poses on 3 SS + 1 PS", tasks,
              100.0 * recovered / tasks, worst_error, Percentile(solve_us, 0.5),
              Percentile(solve_us, 0.99));
}

// Least squares: `count` poses on planted dyads, perturbed by noise; the planted dyads' seeds
// (nearest returned seed) before and after refinement, and the whole task's time.
void RunSpatialLeastSquares(int tasks, int count, double noise, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> e2e_us, before, after, planted_rms;
  for (int t = 0; t < tasks; ++t) {
    const DualQuaternion start = linkfit::testing::RandomSpatialPose(rng);
    const std::vector<SpatialDyad> planted = linkfit::testing::DyadsThroughPose(
        rng, start, {SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kSS});
    std::vector<DualQuaternion> poses = linkfit::testing::PosesOnDyads(rng, planted, start, count);
    linkfit::testing::PerturbSpatialPoses(rng, noise, &poses);
    const linkfit::Task task = linkfit::SpatialMotionTask(poses);
    const auto begin = std::chrono::steady_clock::now();
    const linkfit::SpatialMotionResult result = linkfit::SolveSpatialTask(task);
    e2e_us.push_back(MicrosecondsSince(begin));
    // The refined dyad nearest each planted one.
    for (const SpatialDyad& expected : planted) {
      double best = std::numeric_limits<double>::infinity();
      const linkfit::SpatialDyadReport* nearest = nullptr;
      for (const linkfit::SpatialDyadReport& report : result.dyads) {
        const double distance = linkfit::testing::SpatialDyadDistance(report.dyad, expected);
        if (distance < best) {
          best = distance;
          nearest = &report;
        }
      }
      if (nearest == nullptr || !nearest->rms_residual) continue;
      before.push_back(*nearest->seed_rms_residual / result.scale);
      after.push_back(*nearest->rms_residual / result.scale);
      double sum = 0.0;
      for (const DualQuaternion& pose : poses) sum += std::pow(expected.Residual(pose), 2);
      planted_rms.push_back(std::sqrt(sum / count) / result.scale);
    }
  }
  char name[64];
  std::snprintf(name, sizeof(name), "%d poses, noise %.0e L", count, noise);
  std::printf("%-30s %8d %13.2e %13.2e %13.2e %10.1f %8.1f\n", name, tasks, Percentile(before, 0.5),
              Percentile(after, 0.5), Percentile(planted_rms, 0.5), Percentile(e2e_us, 0.5),
              Percentile(e2e_us, 0.99));
}

// RMS pose error of a four-bar at the poses (each at its nearest configuration).
double RmsPoseError(const linkfit::PlanarDyad& input, const linkfit::PlanarDyad& output,
                    const std::vector<linkfit::PlanarPose>& poses, double length) {
  const linkfit::FourBarAnalysis analysis = linkfit::AnalyzeFourBar(input, output, poses, length);
  double sum = 0.0;
  for (const linkfit::FourBarLocation& location : analysis.locations) {
    sum += location.pose_error * location.pose_error;
  }
  return std::sqrt(sum / poses.size());
}

void RunLeastSquares(int tasks, uint64_t seed, const std::string& csv_path) {
  std::printf(
      "\napproximate planar synthesis (SolvePlanarTask), random four-bars; error = RMS pose "
      "error of the best defect-free four-bar / that of the generating mechanism on the "
      "same poses (noise 0: / L)\n");
  std::printf("%-8s %-8s %-9s %6s %10s %10s %12s %12s %9s\n", "poses", "noise", "effort", "tasks",
              "median_ms", "worst_ms", "median_err", "worst_err", "success");
  FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (csv) {
    std::fprintf(csv,
                 "family,path,effort,tasks,median_ms,worst_ms,median_error,worst_error,"
                 "success_share\n");
  }
  const linkfit::Effort efforts[] = {linkfit::Effort::kFast, linkfit::Effort::kBalanced,
                                     linkfit::Effort::kThorough};
  for (int count : {10, 50, 200}) {
    for (double noise : {0.0, 1e-3, 1e-2}) {
      for (linkfit::Effort effort : efforts) {
        // The same tasks for every effort level.
        std::mt19937_64 rng(seed + count * 7 + static_cast<uint64_t>(noise * 1e4));
        const int cell_tasks =
            effort == linkfit::Effort::kThorough ? std::max(1, tasks / 4) : tasks;
        std::vector<double> times, errors;
        int success = 0;
        for (int t = 0; t < cell_tasks; ++t) {
          const linkfit::testing::GeneratedTask generated =
              linkfit::testing::RandomFourBarTask(rng, count);
          const double length = linkfit::CharacteristicLength(generated.poses);
          std::vector<linkfit::PlanarPose> poses = generated.poses;
          linkfit::testing::PerturbPlanarPoses(rng, noise, length, &poses);
          const linkfit::Task task = linkfit::PlanarMotionTask(poses, effort);
          const auto begin = std::chrono::steady_clock::now();
          const linkfit::PlanarMotionResult result = linkfit::SolvePlanarTask(task);
          times.push_back(MicrosecondsSince(begin) / 1000.0);
          double best = std::numeric_limits<double>::infinity();
          // Order defects are not counted: with dense noisy poses the noise itself reorders
          // neighbouring input values. Circuit and branch defects are.
          for (const linkfit::MechanismReport& mechanism : result.mechanisms) {
            const bool assembles_on_one_branch =
                std::find(mechanism.defects.begin(), mechanism.defects.end(), "circuit") ==
                    mechanism.defects.end() &&
                std::find(mechanism.defects.begin(), mechanism.defects.end(), "branch") ==
                    mechanism.defects.end();
            if (mechanism.rms_pose_error && assembles_on_one_branch) {
              best = std::min(best, *mechanism.rms_pose_error);
            }
          }
          const double reference =
              noise > 0.0 ? RmsPoseError(generated.input, generated.output, poses, length) : 0.0;
          const double error = noise > 0.0 ? best / reference : best / length;
          errors.push_back(error);
          success += noise > 0.0 ? error <= 1.10 : error <= 1e-9;
        }
        const char* effort_name = linkfit::EffortName(effort);
        std::printf("%-8d %-8.0e %-9s %6d %10.2f %10.2f %12.3e %12.3e %8.1f%%\n", count, noise,
                    effort_name, cell_tasks, Percentile(times, 0.5), Percentile(times, 1.0),
                    Percentile(errors, 0.5), Percentile(errors, 1.0), 100.0 * success / cell_tasks);
        if (csv) {
          std::fprintf(csv,
                       "planar motion %d poses noise %g,four-bar,%s,%d,%.4f,%.4f,%.6g,%.6g,%.4f\n",
                       count, noise, effort_name, cell_tasks, Percentile(times, 0.5),
                       Percentile(times, 1.0), Percentile(errors, 0.5), Percentile(errors, 1.0),
                       static_cast<double>(success) / cell_tasks);
        }
      }
    }
  }
  if (csv) {
    std::fclose(csv);
    std::printf("written to %s\n", csv_path.c_str());
  }
}

void RunSpatial(int tasks, uint64_t seed) {
  std::printf("\nseven-pose spatial Burmester solver (seed 000), %d random tasks\n", tasks);
  std::printf("%-30s %8s %12s %12s %12s %6s %10s %8s\n", "family", "tasks", "all_20_ok",
              "degenerate", "worst_res/L", "real", "median_us", "p99_us");
  RunSpatialRandom(tasks, seed);
  std::printf("%-30s %8s %12s %12s %10s %8s\n", "family", "tasks", "recovered", "worst_err",
              "median_us", "p99_us");
  RunSpatialPlanted(tasks / 10, seed + 1);
  std::printf(
      "least squares on planted SS dyads: median RMS residual / L of the planted dyads' "
      "seeds before and after refinement, of the planted dyads themselves, and the "
      "end-to-end time (seed + refinement + platform)\n");
  std::printf("%-30s %8s %13s %13s %13s %10s %8s\n", "family", "tasks", "seed_rms", "refined_rms",
              "planted_rms", "e2e_med_us", "p99_us");
  for (int count : {10, 30}) {
    for (double noise : {1e-3, 1e-2}) {
      RunSpatialLeastSquares(std::max(1, tasks / 20), count, noise, seed + count);
    }
  }
}

// Five timed points: the exact solver and the simulation of what it returns.
void RunPathExact(const char* name, DyadType output, int tasks, uint64_t seed, FILE* csv) {
  std::mt19937_64 rng(seed);
  std::vector<linkfit::testing::GeneratedPathTask> generated;
  for (int t = 0; t < tasks; ++t)
    generated.push_back(linkfit::testing::RandomPathTask(rng, output));
  int recovered = 0, most = 0;
  double found = 0.0, worst = 0.0;
  std::vector<double> times;
  std::vector<linkfit::PathFourBar> four_bars;
  for (const linkfit::testing::GeneratedPathTask& task : generated) {
    const double length = linkfit::testing::PathLength(task.points);
    const auto begin = std::chrono::steady_clock::now();
    std::vector<linkfit::PathFourBarAnalysis> analyses;
    linkfit::SolveTimedPath(task.points, task.input_angles, {}, &four_bars, nullptr, &analyses);
    times.push_back(MicrosecondsSince(begin));
    // Relative to the four-bar's own size: its largest pivot or point distance from the points'
    // centroid, never less than L (a pivot 1000 L away is known to a relative accuracy).
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& point : task.points) centroid += point / 5.0;
    const linkfit::PathFourBar& g = task.four_bar;
    double size = length;
    for (const Eigen::Vector2d& p :
         {g.input.fixed_pivot, g.input.moving_pivot, g.output.fixed_pivot, g.output.moving_pivot,
          g.output.line_point, g.coupler_point}) {
      size = std::max(size, (p - centroid).norm());
    }
    double best = std::numeric_limits<double>::infinity();
    for (size_t m = 0; m < four_bars.size(); ++m) {
      best = std::min(best,
                      linkfit::testing::PathFourBarDistance(four_bars[m], task.four_bar, length) *
                          length / size);
      if (analyses[m].defects.empty() && analyses[m].max_point_error) {
        worst = std::max(worst, *analyses[m].max_point_error / length);
      }
    }
    recovered += best <= 1e-8;
    found += static_cast<double>(four_bars.size());
    most = std::max(most, static_cast<int>(four_bars.size()));
  }
  std::printf("%-24s %8d %10.3f%% %9.2f %6d %12.2e %10.1f %8.1f\n", name, tasks,
              100.0 * recovered / tasks, found / tasks, most, worst, Percentile(times, 0.5),
              Percentile(times, 0.99));
  if (csv) {
    std::fprintf(csv, "timed path 5 points %s,exact,-,%d,%.6f,%.6f,0,%.6g,%.6f\n", name, tasks,
                 Percentile(times, 0.5) / 1000.0, Percentile(times, 1.0) / 1000.0, worst,
                 static_cast<double>(recovered) / tasks);
  }
}

// The RMS distance of the generating four-bar's coupler point from `points` at its own timing.
double GeneratingRms(const linkfit::testing::GeneratedPathTask& task,
                     const std::vector<Eigen::Vector2d>& points, double length) {
  const linkfit::PathFourBarAnalysis analysis =
      linkfit::AnalyzePathFourBar(task.four_bar, points, task.input_angles, length);
  return analysis.rms_point_error.value_or(std::numeric_limits<double>::infinity());
}

// More than five points (prescribed or free timing): SolvePathTask end to end.
void RunPathLeastSquares(int tasks, uint64_t seed, FILE* csv) {
  std::printf(
      "\npath generation, least squares (SolvePathTask), random four-bars; error = RMS point "
      "error of the best defect-free four-bar / the generating one's (noise 0: max point error "
      "/ L)\n");
  std::printf("%-8s %-8s %-10s %-9s %6s %10s %10s %12s %12s %9s\n", "points", "noise", "timing",
              "effort", "tasks", "median_ms", "worst_ms", "median_err", "worst_err", "success");
  const linkfit::Effort efforts[] = {linkfit::Effort::kFast, linkfit::Effort::kBalanced,
                                     linkfit::Effort::kThorough};
  for (bool free_timing : {false, true}) {
    for (int count : {10, 20}) {
      for (double noise : {0.0, 1e-3, 1e-2}) {
        for (linkfit::Effort effort : efforts) {
          if (free_timing && effort == linkfit::Effort::kThorough) continue;  // same as balanced
          std::mt19937_64 rng(seed + count * 7 + static_cast<uint64_t>(noise * 1e4));
          const int cell_tasks =
              effort == linkfit::Effort::kThorough ? std::max(1, tasks / 4) : tasks;
          std::vector<double> times, errors;
          int success = 0;
          for (int t = 0; t < cell_tasks; ++t) {
            const linkfit::testing::GeneratedPathTask generated =
                linkfit::testing::RandomPathTask(rng, DyadType::kRR, count);
            const double length = linkfit::testing::PathLength(generated.points);
            std::normal_distribution<double> normal;
            linkfit::Task task;
            task.problem = linkfit::ProblemKind::kPath;
            task.effort = effort;
            std::vector<Eigen::Vector2d> points;
            for (size_t j = 0; j < generated.points.size(); ++j) {
              linkfit::TimedPoint point;
              point.point_in_fixed =
                  generated.points[j] + noise * length * Eigen::Vector2d(normal(rng), normal(rng));
              if (!free_timing) point.input_angle = generated.input_angles[j];
              points.push_back(point.point_in_fixed);
              task.points.push_back(point);
            }
            const auto begin = std::chrono::steady_clock::now();
            const linkfit::PathResult result = linkfit::SolvePathTask(task);
            times.push_back(MicrosecondsSince(begin) / 1000.0);
            double best = std::numeric_limits<double>::infinity();
            for (const linkfit::PathMechanismReport& mechanism : result.mechanisms) {
              const std::optional<double>& error =
                  noise > 0.0 ? mechanism.rms_point_error : mechanism.max_point_error;
              if (error && mechanism.defects.empty()) best = std::min(best, *error);
            }
            const double reference = noise > 0.0 ? GeneratingRms(generated, points, length) : 0.0;
            const double error = noise > 0.0 ? best / reference : best / length;
            errors.push_back(error);
            success += noise > 0.0 ? error <= 1.10 : error <= (free_timing ? 1e-6 : 1e-9);
          }
          const char* timing = free_timing ? "free" : "prescribed";
          const char* effort_name = linkfit::EffortName(effort);
          std::printf("%-8d %-8.0e %-10s %-9s %6d %10.2f %10.2f %12.3e %12.3e %8.1f%%\n", count,
                      noise, timing, effort_name, cell_tasks, Percentile(times, 0.5),
                      Percentile(times, 1.0), Percentile(errors, 0.5), Percentile(errors, 1.0),
                      100.0 * success / cell_tasks);
          if (csv) {
            std::fprintf(csv,
                         "timed path %d points noise %g,%s timing,%s,%d,%.4f,%.4f,%.6g,%.6g,%.4f\n",
                         count, noise, timing, effort_name, cell_tasks, Percentile(times, 0.5),
                         Percentile(times, 1.0), Percentile(errors, 0.5), Percentile(errors, 1.0),
                         static_cast<double>(success) / cell_tasks);
          }
        }
      }
    }
  }
}

void RunPath(int tasks, int ls_tasks, uint64_t seed, const std::string& csv_path) {
  FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (csv) {
    std::fprintf(csv,
                 "family,path,effort,tasks,median_ms,worst_ms,median_error,worst_error,"
                 "success_share\n");
  }
  std::printf(
      "\npath generation with prescribed timing (seed 002), five random timed points; time = "
      "SolveTimedPath + simulation of every four-bar returned\n");
  std::printf("%-24s %8s %11s %9s %6s %12s %10s %8s\n", "family", "tasks", "recovered", "found",
              "most", "worst_err/L", "median_us", "p99_us");
  RunPathExact("4R (crank+RR)", DyadType::kRR, tasks, seed, csv);
  RunPathExact("slider-crank (crank+PR)", DyadType::kPR, tasks, seed + 1, csv);
  RunPathExact("inverted s-c (crank+RP)", DyadType::kRP, tasks, seed + 2, csv);
  if (ls_tasks > 0) RunPathLeastSquares(ls_tasks, seed, csv);
  if (csv) {
    std::fclose(csv);
    std::printf("written to %s\n", csv_path.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  int tasks = 100000;
  int spatial_tasks = 10000;
  int ls_tasks = 20;
  std::string csv_path = "least_squares.csv";
  uint64_t seed = 2026;
  std::string only;
  int path_tasks = 10000;
  int path_ls_tasks = 12;
  std::string path_csv = "path.csv";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tasks") && i + 1 < argc) {
      tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--spatial-tasks") && i + 1 < argc) {
      spatial_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--ls-tasks") && i + 1 < argc) {
      ls_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--path-tasks") && i + 1 < argc) {
      path_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--path-ls-tasks") && i + 1 < argc) {
      path_ls_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--path-csv") && i + 1 < argc) {
      path_csv = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: linkfit_bench [--tasks N] [--spatial-tasks M] [--ls-tasks K] "
                   "[--path-tasks P] [--path-ls-tasks Q] [--seed S] "
                   "[--only planar|spatial|least-squares|path] [--csv FILE] "
                   "[--path-csv FILE]\n");
      return 2;
    }
  }
  if (only == "spatial") {
    RunSpatial(spatial_tasks, seed);
    return 0;
  }
  if (only == "least-squares") {
    RunLeastSquares(ls_tasks, seed, csv_path);
    return 0;
  }
  if (only == "path") {
    RunPath(path_tasks, path_ls_tasks, seed, path_csv);
    return 0;
  }
  std::printf("five-pose Burmester solver, %d random exact tasks per family, seed %llu\n", tasks,
              static_cast<unsigned long long>(seed));
  std::printf("%-24s %8s %11s %12s %12s %12s %12s %6s %10s %8s %11s\n", "family", "tasks",
              "recovered", "err_p99.9", "data_limited", "unexplained", "worst_res/L", "real",
              "median_us", "p99_us", "e2e_med_us");
  const Family families[] = {
      {"4R (RR+RR)", DyadType::kRR, DyadType::kRR},
      {"slider-crank (RR+PR)", DyadType::kRR, DyadType::kPR},
      {"inverted s-c (RR+RP)", DyadType::kRR, DyadType::kRP},
      {"RPRP (PR+RP)", DyadType::kPR, DyadType::kRP},
  };
  for (const Family& family : families) RunFamily(family, tasks, seed++);
  if (only != "planar") {
    RunSpatial(spatial_tasks, seed);
    RunLeastSquares(ls_tasks, seed, csv_path);
    RunPath(path_tasks, path_ls_tasks, seed, path_csv);
  }
  return 0;
}
