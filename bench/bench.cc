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
// Then four poses (RunFourPoses): the Burmester curves and the dyads of the generating pivots.
//
// Then the seven-pose spatial solver (seed 000) on random tasks: the share of tasks whose 20
// roots are all found and verified (20 distinct roots, each with a polished residual below
// 1e-11 on the bilinear equations), the worst residual of a returned dyad over L, real roots and
// the median and 99th-percentile time of SolveSpatialBurmester; the share of planted SS/PS dyads
// recovered (relative error <= 1e-8); and least-squares tasks (10 and 30 noisy poses on planted
// dyads): the RMS residual of the planted dyads' seeds before and after the Ceres refinement,
// and the end-to-end time of SolveSpatialTask (seed, refinement, platform).
//
// Then path generation with prescribed timing (seed 002): random five-point tasks made by random
// crank-driven four-bars (4R, slider-crank, inverted slider-crank): the share with the generating
// four-bar recovered (error <= 1e-8 in every pivot, line and the coupler point, relative to the
// four-bar's size: its largest pivot or point distance from the points, never less than L), the
// mean and largest number of four-bars returned, the worst point error over L of a returned
// four-bar without defects (assembled and driven through the points), and the median and
// 99th-percentile time of SolveTimedPath plus the simulation of every four-bar it returns
// (AnalyzePathFourBar).
//
// The least-squares paths (more poses or points than the minimum, every effort level, noise) are
// measured by `linkfit bench` (bench/trade_bench.h), which also sweeps the numerical extremes.
//
// Then `linkfit refine` (RefineTask): designs moved 1 % of L off random planar four-bars, path
// four-bars (prescribed and free timing) and spatial platforms, refined against their tasks
// printed to 17, 6 and 4 significant digits: the share that comes back to the generator (within
// 1e-6 of its size at full precision, within twice the stated error bound when rounded), the
// share whose bound says the data do not determine it, and the time of the refinement.
//
// Then end to end by stage (RunStages): parse, solve, analysis and write per task kind.
//
// Then spherical least squares by effort (RunSpherical): noisy orientations of random spherical
// four-bars about a centre, each task solved at balanced and at thorough (SolveSpatialTask): the
// median and 90th-percentile time of each and of thorough's search, the tasks where thorough's
// best dyad fits better than balanced's (beyond 1e-9 relative), where its best defect-free
// four-bar does, where the search adds a dyad balanced lacks, and the share of generating dyads
// whose least-squares optimum (the generating dyad refined to convergence) each lists.
//
// Only on request (--only curves; not part of the default run): path synthesis from target
// curves without timing (RunCurves); --curve-rows picks rows by name, --curve-detail prints a
// line per task (the fits, the best listed fit, the first's defects, the time of each stage) and
// writes each failed task to /tmp/curve_fail_<row>_<points>_<task>_<effort>.json.
//
// Only on request (--only scale; not part of the default run): long tasks of every kind
// (tests/support/long_tasks.h: 1,000, 10,000 and 100,000 items, or --scale-items) at every
// effort, each solved by the `linkfit` program beside this one in a process of its own: exit
// status, wall time and peak resident memory (RunScale).
//
//   linkfit_bench [--tasks N] [--spatial-tasks M] [--path-tasks P] [--refine-tasks R]
//                 [--four-tasks F] [--stage-tasks T] [--spherical-tasks K] [--seed S]
//                 [--curve-tasks C] [--curve-detail] [--curve-rows R] [--scale-items N,N,...]
//                 [--only planar|spatial|path|refine|stages|spherical|scale|curves]
#include <glog/logging.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bench/percentile.h"
#include "fitting/planar_burmester.h"
#include "fitting/planar_burmester_curves.h"
#include "fitting/planar_motion.h"
#include "fitting/spatial_burmester.h"
#include "fitting/spherical_motion.h"
#include "fitting/timed_path.h"
#include "lib/design_constraints.h"
#include "lib/dyad_four_bar_kinematics.h"
#include "lib/four_bar_kinematics.h"
#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "lib/result_io.h"
#include "lib/six_bar.h"
#include "lib/six_bar_kinematics.h"
#include "lib/spherical_four_bar_kinematics.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"
#include "tests/support/long_tasks.h"
#include "tests/support/moved_design.h"
#include "tests/support/random_curve.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_six_bar.h"
#include "tests/support/random_spatial.h"
#include "tests/support/random_spherical.h"
#include "tests/support/rounded_task.h"

namespace {

using linkfit::DyadType;
using linkfit::Percentile;

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

// Four poses: random tasks made by random four-bars, solved with the generating dyads' pivots
// given (the moving pivot of an RR or PR dyad, the fixed pivot of an RP dyad), as a designer
// picks them off the curves: the share whose generating dyads come back (relative error
// <= 1e-9), the share of generating dyads within the refine radius that lie within 0.02 L of a
// sample of the curves (the sampling density), the samples per task, the worst residual of a
// sample over L, and the median time of SampleBurmesterCurves and the median and 99th
// percentile of the whole SolvePlanarMotion (curves, pivot dyads, four-bar analysis).
void RunFourPoses(const Family& family, int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> curves_ms, motion_ms;
  int recovered = 0, near = 0, checked = 0;
  long samples = 0;
  double worst_residual = 0.0;
  const linkfit::BurmesterCurveOptions curve_options;
  for (int t = 0; t < tasks; ++t) {
    const linkfit::testing::GeneratedTask task =
        linkfit::testing::RandomTask(rng, family.input, family.output, 4);
    const double length = linkfit::CharacteristicLength(task.poses);
    linkfit::BurmesterCurves curves;
    auto start = std::chrono::steady_clock::now();
    samples += linkfit::SampleBurmesterCurves(task.poses, curve_options, &curves);
    curves_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    std::vector<linkfit::PlanarDyad> all;
    for (const auto& branch : curves.branches) all.insert(all.end(), branch.begin(), branch.end());
    for (const linkfit::PlanarDyad& dyad : all) {
      worst_residual = std::max(worst_residual, dyad.MaxResidual(task.poses) / length);
    }
    linkfit::Task full;
    full.planar_poses = task.poses;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const linkfit::PlanarPose& pose : task.poses) centroid += 0.25 * pose.origin_in_fixed;
    for (const linkfit::PlanarDyad& dyad : {task.input, task.output}) {
      if (dyad.type == DyadType::kRP) {
        full.fixed_pivots.push_back(dyad.fixed_pivot);
      } else {
        full.moving_pivots.push_back(dyad.moving_pivot);
      }
      if (dyad.type == DyadType::kRR &&
          std::max((dyad.fixed_pivot - centroid).norm(),
                   (task.poses[0].ToFixed(dyad.moving_pivot) - centroid).norm()) <=
              curve_options.refine_radius * length) {
        ++checked;
        near += linkfit::testing::NearestDyadDistance(all, dyad, length) <= 0.02;
      }
    }
    start = std::chrono::steady_clock::now();
    const linkfit::PlanarMotionResult result = linkfit::SolvePlanarMotion(full);
    motion_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    std::vector<linkfit::PlanarDyad> dyads;
    for (const auto& found : result.dyads) dyads.push_back(found.dyad);
    const double error =
        std::max(linkfit::testing::NearestDyadDistance(
                     dyads, task.input, linkfit::testing::DyadScale(task.input, task.poses)),
                 linkfit::testing::NearestDyadDistance(
                     dyads, task.output, linkfit::testing::DyadScale(task.output, task.poses)));
    recovered += error <= kRecoveryTolerance;
  }
  std::printf("%-24s %8d %10.2f%% %10.2f%% %8d %9.0f %12.2e %12.3f %10.3f %9.3f\n", family.name,
              tasks, 100.0 * recovered / tasks, 100.0 * near / std::max(checked, 1), checked,
              static_cast<double>(samples) / tasks, worst_residual, Percentile(curves_ms, 0.5),
              Percentile(motion_ms, 0.5), Percentile(motion_ms, 0.99));
}

using linkfit::DualQuaternion;
using linkfit::SpatialDyad;
using linkfit::SpatialDyadType;

double MicrosecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
      .count();
}

// End to end by stage (--only stages): random tasks of each kind written as a user's file
// (every number to 17 significant digits), then per task the median time of each stage on one
// core: parse (ParseTask of the JSON text), solve (SolveTask less its analysis), analysis (the
// result's analysis_seconds: the dyad pairs' assembly, defects, transmission and ranking; the
// path four-bars driven through the points; the platform traced), write (ResultToJson), and
// the sum of the four measured together.
struct StageTimes {
  std::vector<double> parse, solve, analysis, write, total;
};

void PrintStages(const char* kind, int tasks, const StageTimes& times) {
  std::printf("%-40s %6d %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f\n", kind, tasks,
              Percentile(times.parse, 0.5), Percentile(times.solve, 0.5),
              Percentile(times.analysis, 0.5), Percentile(times.write, 0.5),
              Percentile(times.total, 0.5), Percentile(times.total, 0.99));
}

// One task's stages; `adjust` may add to the parsed task what its text lacks (pivots).
template <typename Adjust>
void TimeStages(const std::string& text, const Adjust& adjust, StageTimes* times) {
  const auto start = std::chrono::steady_clock::now();
  linkfit::Task task = linkfit::ParseTask(text, "bench");
  const double parse_us = MicrosecondsSince(start);
  adjust(&task);
  const auto solve_start = std::chrono::steady_clock::now();
  const linkfit::TaskResult result = linkfit::SolveTask(task);
  const double solve_us = MicrosecondsSince(solve_start);
  const auto write_start = std::chrono::steady_clock::now();
  const std::string json = linkfit::ResultToJson(result, 2);
  const double write_us = MicrosecondsSince(write_start);
  const double total_us = MicrosecondsSince(start);
  const double analysis_us =
      1e6 * std::visit([](const auto& r) { return r.analysis_seconds; }, result);
  times->parse.push_back(parse_us);
  times->solve.push_back(solve_us - analysis_us);
  times->analysis.push_back(analysis_us);
  times->write.push_back(write_us);
  times->total.push_back(total_us);
  (void)json;
}

void RunStages(int tasks, uint64_t seed) {
  namespace t = linkfit::testing;
  std::printf(
      "\nend to end by stage, one core, median microseconds per task (tasks written to 17 "
      "digits)\n");
  std::printf("%-40s %6s %9s %9s %9s %9s %9s %9s\n", "kind", "tasks", "parse", "solve", "analysis",
              "write", "total", "total_p99");
  std::mt19937_64 rng(seed);
  const auto none = [](linkfit::Task*) {};
  {
    StageTimes times;
    for (int i = 0; i < tasks; ++i) {
      const t::GeneratedTask task = t::RandomTask(rng, DyadType::kRR, DyadType::kRR, 5);
      TimeStages(t::PlanarMotionText(task.poses, 17), none, &times);
    }
    PrintStages("five poses, 4R", tasks, times);
  }
  {
    StageTimes times;
    for (int i = 0; i < tasks; ++i) {
      const t::GeneratedTask task = t::RandomTask(rng, DyadType::kRR, DyadType::kRR, 4);
      TimeStages(
          t::PlanarMotionText(task.poses, 17),
          [&](linkfit::Task* parsed) {
            parsed->moving_pivots = {task.input.moving_pivot, task.output.moving_pivot};
          },
          &times);
    }
    PrintStages("four poses, 4R, the generator's pivots", tasks, times);
  }
  {
    StageTimes times;
    for (int i = 0; i < tasks; ++i) {
      const t::GeneratedPathTask task = t::RandomPathTask(rng, DyadType::kRR);
      TimeStages(t::PathText(task.points, task.input_angles, 17), none, &times);
    }
    PrintStages("five timed points, 4R", tasks, times);
  }
  {
    StageTimes times;
    for (int i = 0; i < tasks; ++i) {
      const t::PlantedSpatialTask task = t::RandomPlatformTask(rng, 7);
      TimeStages(t::SpatialMotionText(task.poses, 17, t::SpatialForm::kDualQuaternion), none,
                 &times);
    }
    PrintStages("seven spatial poses, 5-SS", tasks, times);
  }
  {
    StageTimes times;
    const int count = std::max(1, tasks / 5);
    for (int i = 0; i < count; ++i) {
      const t::GeneratedTask task = t::RandomTask(rng, DyadType::kRR, DyadType::kRR, 12);
      TimeStages(t::PlanarMotionText(task.poses, 17), none, &times);
    }
    PrintStages("12 poses, 4R, least squares (balanced)", count, times);
  }
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

// Seven poses on a random 5-SS platform, end to end: SolveSpatialTask (the 20 roots, the dyads,
// the platform of the five of smallest radius traced through the poses). Tasks whose platform
// motion holds seven distinct poses (RandomPlatformTask draws again otherwise).
void RunSpatialEndToEnd(int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> e2e_us;
  int one_branch = 0;
  for (int t = 0; t < tasks; ++t) {
    const linkfit::testing::PlantedSpatialTask planted =
        linkfit::testing::RandomPlatformTask(rng, 7);
    linkfit::Task task = linkfit::SpatialMotionTask(planted.poses);
    const auto begin = std::chrono::steady_clock::now();
    const linkfit::SpatialMotionResult result = linkfit::SolveSpatialTask(task);
    e2e_us.push_back(MicrosecondsSince(begin));
    one_branch += !result.mechanisms.empty() && result.mechanisms[0].one_branch;
  }
  std::printf("%-30s %8d %11.1f%% %10.1f %8.1f\n", "7 poses on a 5-SS, end to end", tasks,
              100.0 * one_branch / tasks, Percentile(e2e_us, 0.5), Percentile(e2e_us, 0.99));
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
      "end to end (SolveSpatialTask): the share whose default platform passes every pose on one "
      "branch, and the time\n");
  std::printf("%-30s %8s %12s %10s %8s\n", "family", "tasks", "one_branch", "e2e_med_us", "p99_us");
  RunSpatialEndToEnd(std::max(1, tasks / 20), seed + 2);
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
void RunPathExact(const char* name, DyadType output, int tasks, uint64_t seed) {
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
}

void RunPath(int tasks, uint64_t seed) {
  std::printf(
      "\npath generation with prescribed timing (seed 002), five random timed points; time = "
      "SolveTimedPath + simulation of every four-bar returned\n");
  std::printf("%-24s %8s %11s %9s %6s %12s %10s %8s\n", "family", "tasks", "recovered", "found",
              "most", "worst_err/L", "median_us", "p99_us");
  RunPathExact("4R (crank+RR)", DyadType::kRR, tasks, seed);
  RunPathExact("slider-crank (crank+PR)", DyadType::kPR, tasks, seed + 1);
  RunPathExact("inverted s-c (crank+RP)", DyadType::kRP, tasks, seed + 2);
}

// The generator's recovery from a refined result: at full precision (17 digits) its largest
// relative difference from the refined design is at most 1e-6; from rounded data within twice
// the error bound the result states (tests/support/rounded_task.h), or the bound says the data
// do not determine it (rough).
// A design the move left unable to reach every pose or point (it does not assemble there, or
// the crank cannot be driven through them) is counted apart when it is not recovered: its
// refinement starts outside the generator's basin.
enum class Recovered { kYes, kRough, kSeedOff, kNo };

Recovered FromRounded(double recovery, bool rough) {
  if (recovery <= 1.0) return Recovered::kYes;
  return rough ? Recovered::kRough : Recovered::kNo;
}

Recovered SeedOff(Recovered recovered, bool seed_reaches) {
  return recovered == Recovered::kNo && !seed_reaches ? Recovered::kSeedOff : recovered;
}

// One row of the refine table: `tasks` designs moved 1 % of L off their generators, refined
// against tasks printed to `digits` significant digits; `refine` makes a task, refines its moved
// design and judges the generator's recovery.
template <typename RefineOne>
void RunRefineRow(const std::string& name, int digits, int tasks, uint64_t seed,
                  RefineOne refine_one) {
  std::mt19937_64 rng(seed);
  int counts[4] = {0, 0, 0, 0};
  std::vector<double> times;
  for (int t = 0; t < tasks; ++t) {
    double seconds = 0.0;
    ++counts[static_cast<int>(refine_one(rng, digits, &seconds))];
    times.push_back(1e3 * seconds);
  }
  std::printf("%-34s %6d %6d %9.1f%% %7.1f%% %8.1f%% %7.1f%% %10.2f %8.2f\n", name.c_str(), digits,
              tasks, 100.0 * counts[0] / tasks, 100.0 * counts[1] / tasks,
              100.0 * counts[2] / tasks, 100.0 * counts[3] / tasks, Percentile(times, 0.5),
              Percentile(times, 0.99));
}

constexpr double kRefineOffset = 0.01;  // designs start this much (times L) off

template <typename Call>
linkfit::TaskResult Timed(Call call, double* seconds) {
  const auto begin = std::chrono::steady_clock::now();
  linkfit::TaskResult result = call();
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

void RunRefine(int tasks, uint64_t seed) {
  namespace t = linkfit::testing;
  std::printf(
      "\nlinkfit refine (optimizers/task_solver.h RefineTask): designs moved up to 1 %% of L off "
      "their generators in every coordinate, refined against the generator's task printed to "
      "`digits` significant digits (17: full); recovered = within 1e-6 of the generator's size "
      "(full) or within twice the stated error bound (rounded); rough = the bound says the data "
      "do not determine it; seed_off = missed from a design the move left unable to reach every "
      "pose or point; time of RefineTask alone, one core\n");
  std::printf("%-34s %6s %6s %10s %8s %9s %8s %10s %8s\n", "family", "digits", "tasks", "recovered",
              "rough", "seed_off", "missed", "median_ms", "p99_ms");
  const int all_digits[] = {17, 6, 4};
  for (const DyadType output : {DyadType::kRR, DyadType::kPR}) {
    const std::string name = std::string("planar motion, 12 poses, ") +
                             (output == DyadType::kRR ? "4R" : "slider-crank");
    for (const int digits : all_digits) {
      RunRefineRow(name, digits, tasks, seed++, [&](std::mt19937_64& rng, int d, double* seconds) {
        const t::GeneratedTask generated = t::RandomTask(rng, DyadType::kRR, output, 12);
        const linkfit::Task task = t::ReadRounded(t::PlanarMotionText(generated.poses, d));
        const double length = linkfit::CharacteristicLength(generated.poses);
        linkfit::PlanarDesign design;
        design.dyads = {t::MovedPlanarDyad(rng, generated.input, kRefineOffset * length, length),
                        t::MovedPlanarDyad(rng, generated.output, kRefineOffset * length, length)};
        const auto result = std::get<linkfit::PlanarMotionResult>(
            Timed([&] { return linkfit::RefineTask(task, design, {}); }, seconds));
        const std::optional<double>& seed_error = result.mechanisms[0].seed_max_pose_error;
        const bool seed_reaches = seed_error && std::isfinite(*seed_error);
        if (d == 17) {
          const double error =
              std::max(t::NearestDyadDistance({result.dyads[0].dyad, result.dyads[1].dyad},
                                              generated.input, length),
                       t::NearestDyadDistance({result.dyads[0].dyad, result.dyads[1].dyad},
                                              generated.output, length));
          return SeedOff(error <= 1e-6 ? Recovered::kYes : Recovered::kNo, seed_reaches);
        }
        bool rough = false;
        const double recovery =
            std::max(t::RoundedRecovery(generated.input, result.dyads, task.precision,
                                        task.planar_poses, &rough),
                     t::RoundedRecovery(generated.output, result.dyads, task.precision,
                                        task.planar_poses, &rough));
        return SeedOff(FromRounded(recovery, rough), seed_reaches);
      });
    }
  }
  for (const bool free_timing : {false, true}) {
    for (const DyadType output : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
      const std::string name =
          std::string(free_timing ? "path, 12 points, free, " : "path, 12 timed points, ") +
          (output == DyadType::kRR   ? "4R"
           : output == DyadType::kPR ? "s-c"
                                     : "inv. s-c");
      for (const int digits : all_digits) {
        RunRefineRow(
            name, digits, tasks, seed++, [&](std::mt19937_64& rng, int d, double* seconds) {
              const t::GeneratedPathTask generated = t::RandomPathTask(rng, output, 12);
              const std::vector<double> angles =
                  free_timing ? std::vector<double>() : generated.input_angles;
              const linkfit::Task task = t::ReadRounded(t::PathText(generated.points, angles, d));
              const double length = t::PathLength(generated.points);
              linkfit::PathDesign design;
              design.four_bars = {
                  t::MovedPathFourBar(rng, generated.four_bar, kRefineOffset * length, length)};
              design.input_angles = {{}};
              linkfit::TaskResult any;
              try {
                any = Timed([&] { return linkfit::RefineTask(task, design, {}); }, seconds);
              } catch (const linkfit::InputError&) {
                return Recovered::kSeedOff;  // the moved four-bar no longer assembles
              }
              const linkfit::PathResult& result = std::get<linkfit::PathResult>(any);
              const linkfit::PathMechanismReport& refined = result.mechanisms[0];
              const bool seed_reaches = refined.seed_max_point_error.has_value();
              if (d == 17) {
                const bool near =
                    refined.max_point_error &&
                    t::PathFourBarDistance(refined.design, generated.four_bar, length) <= 1e-6;
                return SeedOff(near ? Recovered::kYes : Recovered::kNo, seed_reaches);
              }
              bool rough = false;
              const double recovery = t::RoundedPathRecovery(generated.four_bar, result,
                                                             generated.points, angles, &rough);
              return SeedOff(FromRounded(recovery, rough), seed_reaches);
            });
      }
    }
  }
  const std::vector<linkfit::SpatialDyadType> types = {
      linkfit::SpatialDyadType::kSS, linkfit::SpatialDyadType::kSS, linkfit::SpatialDyadType::kSS,
      linkfit::SpatialDyadType::kPS, linkfit::SpatialDyadType::kSP};
  for (const int digits : all_digits) {
    RunRefineRow(
        "spatial, 10 poses, SS+SS+SS+PS+SP", digits, tasks, seed++,
        [&](std::mt19937_64& rng, int d, double* seconds) {
          const t::PlantedSpatialTask planted = t::RandomPlatformTask(rng, 10, types);
          const linkfit::Task task = t::ReadRounded(
              t::SpatialMotionText(planted.poses, d, t::SpatialForm::kDualQuaternion));
          const double length = linkfit::SpatialTaskLength(task);
          linkfit::SpatialDesign design;
          for (const linkfit::SpatialDyad& dyad : planted.planted) {
            design.dyads.push_back(t::MovedSpatialDyad(rng, dyad, kRefineOffset * length, length));
          }
          const auto result = std::get<linkfit::SpatialMotionResult>(
              Timed([&] { return linkfit::RefineTask(task, design, {}); }, seconds));
          Recovered worst = Recovered::kYes;
          for (size_t k = 0; k < planted.planted.size(); ++k) {
            Recovered one;
            if (d == 17) {
              one = t::SpatialDyadDistance(result.dyads[k].dyad, planted.planted[k]) <= 1e-6
                        ? Recovered::kYes
                        : Recovered::kNo;
            } else {
              bool rough = false;
              const double recovery =
                  t::RoundedRecovery(planted.planted[k], {result.dyads[k]}, task.precision,
                                     task.spatial_poses, length, &rough);
              one = FromRounded(recovery, rough);
            }
            worst = std::max(worst, one);
          }
          return worst;
        });
  }
}
}  // namespace

// Spherical least squares, balanced against thorough (file comment): `tasks` random spherical
// four-bars, `count` orientations each turned by noise `noise` (radians), about a centre away
// from both frames' origins (tests/support/random_spherical.h RandomSphericalPoses, as linkfit
// bench's spherical motion rows).
void RunSphericalRow(int tasks, int count, double noise, uint64_t seed) {
  using linkfit::SpatialMotionResult;
  using linkfit::SphericalDyad;
  using linkfit::SphericalDyadReport;
  std::mt19937_64 rng(seed);
  std::vector<double> balanced_ms, thorough_ms, search_ms;
  int better_dyad = 0, better_four_bar = 0, added = 0, generators = 0;
  int balanced_found = 0, thorough_found = 0;
  const auto best_dyad = [](const SpatialMotionResult& result) {
    double best = std::numeric_limits<double>::infinity();
    for (const SphericalDyadReport& report : result.spherical_dyads) {
      best = std::min(best, report.rms_residual.value_or(best));
    }
    return best;
  };
  const auto best_four_bar = [](const SpatialMotionResult& result) {
    double best = std::numeric_limits<double>::infinity();
    for (const linkfit::MechanismReport& mechanism : result.spherical_mechanisms) {
      if (mechanism.defects.empty()) best = std::min(best, mechanism.rms_pose_error.value_or(best));
    }
    return best;
  };
  const auto lists = [](const SpatialMotionResult& result, const SphericalDyad& dyad) {
    return std::any_of(result.spherical_dyads.begin(), result.spherical_dyads.end(),
                       [&](const SphericalDyadReport& report) {
                         return linkfit::SameSphericalDyad(report.dyad, dyad, 1e-6);
                       });
  };
  linkfit::SphericalDyadRefinerOptions converged;
  converged.max_iterations = 1000;
  for (int t = 0; t < tasks; ++t) {
    const linkfit::testing::SphericalPosesTask drawn =
        linkfit::testing::RandomSphericalPoses(rng, count, noise);
    linkfit::Task task = linkfit::SpatialMotionTask(drawn.poses);
    task.effort = linkfit::Effort::kBalanced;
    auto begin = std::chrono::steady_clock::now();
    const SpatialMotionResult balanced = linkfit::SolveSpatialTask(task);
    balanced_ms.push_back(1e-3 * MicrosecondsSince(begin));
    task.effort = linkfit::Effort::kThorough;
    begin = std::chrono::steady_clock::now();
    const SpatialMotionResult thorough = linkfit::SolveSpatialTask(task);
    thorough_ms.push_back(1e-3 * MicrosecondsSince(begin));
    search_ms.push_back(1e3 * thorough.search_seconds);
    if (thorough.model != "spherical" || balanced.model != "spherical") continue;
    better_dyad += best_dyad(thorough) < best_dyad(balanced) * (1.0 - 1e-9);
    better_four_bar += best_four_bar(thorough) < best_four_bar(balanced) * (1.0 - 1e-9);
    added += thorough.spherical_dyads.size() > balanced.spherical_dyads.size();
    const linkfit::SphericalMotion motion =
        linkfit::TaskSphericalMotion(task, *thorough.spherical, thorough.scale);
    for (const SphericalDyad* generating : {&drawn.four_bar.input, &drawn.four_bar.output}) {
      SphericalDyad optimum = *generating;
      linkfit::RefineSphericalDyad(motion.rotations, {}, {}, &optimum, converged);
      ++generators;
      balanced_found += lists(balanced, optimum);
      thorough_found += lists(thorough, optimum);
    }
  }
  char name[64];
  std::snprintf(name, sizeof(name), "%d orientations, noise %.0e", count, noise);
  std::printf("%-28s %6d %8.2f %8.2f %8.2f %8.2f %8.2f %7d %7d %7d %8.1f%% %8.1f%%\n", name, tasks,
              Percentile(balanced_ms, 0.5), Percentile(balanced_ms, 0.9),
              Percentile(thorough_ms, 0.5), Percentile(thorough_ms, 0.9),
              Percentile(search_ms, 0.5), better_dyad, better_four_bar, added,
              100.0 * balanced_found / std::max(1, generators),
              100.0 * thorough_found / std::max(1, generators));
}

void RunSpherical(int tasks, uint64_t seed) {
  std::printf(
      "\nspherical least squares, balanced and thorough (SolveSpatialTask, one core): times in ms "
      "(median, 90th percentile; thorough's search median), tasks where thorough's best dyad / "
      "best defect-free four-bar fits better and where the search adds a dyad, share of "
      "generating dyads' optima listed\n");
  std::printf("%-28s %6s %8s %8s %8s %8s %8s %7s %7s %7s %9s %9s\n", "family", "tasks", "bal_med",
              "bal_p90", "thr_med", "thr_p90", "search", "dyad+", "4bar+", "added", "bal_opt",
              "thr_opt");
  for (const auto& [count, noise] :
       std::vector<std::pair<int, double>>{{10, 1e-3}, {10, 1e-2}, {20, 1e-3}}) {
    RunSphericalRow(tasks, count, noise, seed + count);
  }
}

// The name of a random six-bar layout in the six-bar rows.
std::string SixBarLayoutName(const linkfit::testing::SixBarLayout& layout) {
  return std::string(linkfit::SixBarTopologyName(layout.topology)) + ", link 2 from " +
         std::to_string(layout.from1);
}

// Whether no four-bar through the poses (SolvePlanarMotion) is without defect.
bool NoDefectFreeFourBar(const std::vector<linkfit::PlanarPose>& poses) {
  const linkfit::PlanarMotionResult four_bars =
      linkfit::SolvePlanarMotion(linkfit::PlanarMotionTask(poses));
  return std::none_of(four_bars.mechanisms.begin(), four_bars.mechanisms.end(),
                      [](const linkfit::MechanismReport& m) { return m.defects.empty(); });
}

// Six-bars on a chain linkfit chooses (issue 36): the tasks of RunSixBar (the same seed) without
// their chain, solved end to end (SolvePlanarTask: SolveSixBarChosenChain at balanced effort);
// the time, the chains solved, the share whose first listed six-bar is defect-free and keeps the
// defaults, the share with any defect-free six-bar, and of the tasks with no defect-free four-bar
// the share with a defect-free six-bar.
void RunSixBarChosen(int tasks, uint64_t seed) {
  std::printf(
      "\nsix-bars on a chosen chain, the same five exact poses without their chain "
      "(SolvePlanarTask, one core): time in ms (median, 99th percentile, max), mean chains judged, "
      "share whose first six-bar is defect-free, share with a defect-free six-bar, share with no "
      "defect-free four-bar, and of those the share with a defect-free six-bar\n");
  std::printf("%-26s %6s %8s %8s %8s %7s %10s %10s %10s %12s\n", "layout", "tasks", "med_ms",
              "p99_ms", "max_ms", "chains", "first_ok", "free_6bar", "no_4bar", "6bar_of_no4");
  std::mt19937_64 rng(seed);
  for (const linkfit::testing::SixBarLayout& layout : linkfit::testing::SixBarLayouts()) {
    std::vector<double> ms;
    int chains = 0, first_ok = 0, free_six_bar = 0, no_four_bar = 0, six_bar_instead = 0;
    for (int t = 0; t < tasks; ++t) {
      const linkfit::testing::GeneratedSixBarTask generated =
          linkfit::testing::RandomSixBarTask(rng, layout);
      linkfit::Task task = linkfit::PlanarMotionTask(generated.poses);
      task.six_bar = true;
      const auto begin = std::chrono::steady_clock::now();
      const linkfit::PlanarMotionResult result = linkfit::SolvePlanarTask(task);
      ms.push_back(1e-3 * MicrosecondsSince(begin));
      for (const std::string& note : result.notes) {
        // "... Judged: N; ..."
        const size_t at = note.find("Judged: ");
        if (note.rfind("linkfit chose the 3R chain", 0) == 0 && at != std::string::npos) {
          chains += std::atoi(note.substr(at + 8).c_str());
        }
      }
      const bool free =
          std::any_of(result.six_bars.begin(), result.six_bars.end(),
                      [](const linkfit::SixBarReport& report) { return report.defects.empty(); });
      first_ok += !result.six_bars.empty() && result.six_bars.front().defects.empty() &&
                  result.six_bars.front().violates.empty();
      free_six_bar += free;
      if (NoDefectFreeFourBar(generated.poses)) {
        ++no_four_bar;
        six_bar_instead += free;
      }
    }
    const std::string name = SixBarLayoutName(layout);
    std::printf("%-26s %6d %8.2f %8.2f %8.2f %7.2f %9.1f%% %9.1f%% %9.1f%% %11.1f%%\n",
                name.c_str(), tasks, linkfit::Percentile(ms, 0.5), linkfit::Percentile(ms, 0.99),
                *std::max_element(ms.begin(), ms.end()), 1.0 * chains / tasks,
                100.0 * first_ok / tasks, 100.0 * free_six_bar / tasks, 100.0 * no_four_bar / tasks,
                no_four_bar > 0 ? 100.0 * six_bar_instead / no_four_bar : 0.0);
    std::fflush(stdout);
  }
}

// Six-bars on a given 3R chain (issue 36): per layout of tests/support/random_six_bar.h, random
// six-bars driven by their upper link through five poses; each task solved end to end
// (SolvePlanarTask: synthesis, every six-bar's analysis, ranking), the generator recovered (a
// listed six-bar of its layout within 1e-7 L, no kinematic defect), the six-bars listed, and the
// tasks where a six-bar without defect is listed although no four-bar through the same five poses
// (SolvePlanarMotion) is without defect.
void RunSixBar(int tasks, uint64_t seed) {
  std::printf(
      "\nsix-bars on a given chain, five exact poses (SolvePlanarTask, one core): time in ms "
      "(median, 99th percentile; the synthesis alone, median us), generators recovered, mean "
      "six-bars listed, share of tasks "
      "with a defect-free six-bar, share with no defect-free four-bar, and of those the share "
      "with a defect-free six-bar\n");
  std::printf("%-26s %6s %8s %8s %8s %10s %8s %10s %10s %12s\n", "layout", "tasks", "med_ms",
              "p99_ms", "synth_us", "recovered", "listed", "free_6bar", "no_4bar", "6bar_of_no4");
  std::mt19937_64 rng(seed);
  for (const linkfit::testing::SixBarLayout& layout : linkfit::testing::SixBarLayouts()) {
    std::vector<double> ms, synthesis_us;
    int recovered = 0, listed = 0, free_six_bar = 0, no_four_bar = 0, six_bar_instead = 0;
    for (int t = 0; t < tasks; ++t) {
      const linkfit::testing::GeneratedSixBarTask generated =
          linkfit::testing::RandomSixBarTask(rng, layout);
      linkfit::Task task = linkfit::PlanarMotionTask(generated.poses);
      task.six_bar = true;
      task.chain = generated.chain;
      const auto begin = std::chrono::steady_clock::now();
      const linkfit::PlanarMotionResult result = linkfit::SolvePlanarTask(task);
      ms.push_back(1e-3 * MicrosecondsSince(begin));
      // The synthesis alone (every root of the relative motions, combined; no analysis).
      {
        linkfit::SixBarSynthesisOptions synthesis;
        synthesis.burmester = linkfit::SixBarRootOptions(synthesis.burmester, task.precision);
        std::vector<linkfit::SixBar> six_bars;
        const auto synthesis_begin = std::chrono::steady_clock::now();
        linkfit::SynthesizeSixBars(generated.poses, generated.chain, synthesis, &six_bars);
        synthesis_us.push_back(MicrosecondsSince(synthesis_begin));
      }
      listed += static_cast<int>(result.six_bars.size());
      bool found = false, free = false;
      for (const linkfit::SixBarReport& report : result.six_bars) {
        free |= report.defects.empty();
        bool same = report.six_bar.topology == generated.six_bar.topology &&
                    !linkfit::HasKinematicDefect(report.defects);
        for (int l = 0; l < 2 && same; ++l) {
          same =
              report.six_bar.links[l].from_body == generated.six_bar.links[l].from_body &&
              (report.six_bar.links[l].from_joint - generated.six_bar.links[l].from_joint).norm() <
                  1e-7 &&
              (report.six_bar.links[l].to_joint - generated.six_bar.links[l].to_joint).norm() <
                  1e-7;
        }
        found |= same;
      }
      recovered += found;
      free_six_bar += free;
      if (NoDefectFreeFourBar(generated.poses)) {
        ++no_four_bar;
        six_bar_instead += free;
      }
    }
    const std::string name = SixBarLayoutName(layout);
    std::printf("%-26s %6d %8.2f %8.2f %8.0f %9.1f%% %8.1f %9.1f%% %9.1f%% %11.1f%%\n",
                name.c_str(), tasks, linkfit::Percentile(ms, 0.5), linkfit::Percentile(ms, 0.99),
                linkfit::Percentile(synthesis_us, 0.5), 100.0 * recovered / tasks,
                1.0 * listed / tasks, 100.0 * free_six_bar / tasks, 100.0 * no_four_bar / tasks,
                no_four_bar > 0 ? 100.0 * six_bar_instead / no_four_bar : 0.0);
    std::fflush(stdout);
  }
}

// Six-bars through nine noisy poses by least squares (SolveSixBarLeastSquares, issue 36): per
// layout, the time, the best listed fit and the first listed fit against the generating six-bar's
// own RMS pose error on the noisy poses, and the share whose first listed keeps the defaults.
void RunSixBarLeastSquares(int tasks, uint64_t seed, bool chosen) {
  std::printf(
      "\nsix-bars on a %s, nine poses with noise 0.002 L and 0.002 rad, least squares at "
      "balanced effort (SolvePlanarTask, one core): time in s (median, max), best listed and "
      "first listed RMS pose error over the generator's (median, max), share whose first keeps "
      "the defaults, share whose first is also defect-free\n",
      chosen ? "chosen chain (the same tasks without theirs)" : "given chain");
  std::printf("%-26s %6s %8s %8s %10s %10s %10s %10s %10s %10s\n", "layout", "tasks", "med_s",
              "max_s", "best_med", "best_max", "first_med", "first_max", "first_ok", "first_free");
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.002);
  for (const linkfit::testing::SixBarLayout& layout : linkfit::testing::SixBarLayouts()) {
    std::vector<double> seconds, best, first;
    int keeps = 0, free = 0;
    for (int t = 0; t < tasks; ++t) {
      linkfit::testing::GeneratedSixBarTask generated =
          linkfit::testing::RandomSixBarTask(rng, layout, 9);
      for (linkfit::PlanarPose& pose : generated.poses) {
        pose.origin_in_fixed += Eigen::Vector2d(noise(rng), noise(rng));
        pose.theta += noise(rng);
      }
      linkfit::Task task = linkfit::PlanarMotionTask(generated.poses);
      task.six_bar = true;
      if (!chosen) task.chain = generated.chain;
      const auto begin = std::chrono::steady_clock::now();
      const linkfit::PlanarMotionResult result = linkfit::SolvePlanarTask(task);
      seconds.push_back(1e-6 * MicrosecondsSince(begin));
      linkfit::SixBarFit generator;
      if (result.six_bars.empty() ||
          !linkfit::FitSixBarToPoses(generated.six_bar, generated.poses, {}, result.scale,
                                     generated.configurations, &generator)) {
        continue;
      }
      double least = std::numeric_limits<double>::infinity();
      for (const linkfit::SixBarReport& report : result.six_bars) {
        least = std::min(least, report.rms_pose_error);
      }
      best.push_back(least / generator.rms_pose_error);
      first.push_back(result.six_bars.front().rms_pose_error / generator.rms_pose_error);
      keeps += result.six_bars.front().violates.empty();
      free += result.six_bars.front().violates.empty() && result.six_bars.front().defects.empty();
    }
    const std::string name = SixBarLayoutName(layout);
    std::printf("%-26s %6d %8.2f %8.2f %10.3f %10.3f %10.3f %10.3f %9.1f%% %9.1f%%\n", name.c_str(),
                tasks, linkfit::Percentile(seconds, 0.5), linkfit::Percentile(seconds, 1.0),
                linkfit::Percentile(best, 0.5), linkfit::Percentile(best, 1.0),
                linkfit::Percentile(first, 0.5), linkfit::Percentile(first, 1.0),
                100.0 * keeps / std::max(1, tasks), 100.0 * free / std::max(1, tasks));
    std::fflush(stdout);
  }
}

// One run of the `linkfit` program beside this one on `task_path` (result to `result_path`):
// its exit status, wall time and peak resident memory (wait4's ru_maxrss, kB).
struct ProgramRun {
  int status = -1;
  double seconds = 0.0;
  long max_rss_kb = 0;
};

ProgramRun RunLinkfit(const std::string& task_path, const std::string& result_path) {
  const std::string program =
      (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "linkfit").string();
  ProgramRun run;
  std::fflush(stdout);  // the child's freopen would print what is buffered again
  std::fflush(stderr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t child = fork();
  if (child == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execl(program.c_str(), "linkfit", "solve", task_path.c_str(), "-o", result_path.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (child < 0 || wait4(child, &status, 0, &usage) != child) return run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.max_rss_kb = usage.ru_maxrss;
  return run;
}

// Long tasks (tests/support/long_tasks.h) of every kind at every effort level, each solved by
// the `linkfit` program in a process of its own: exit status, wall time and peak memory.
void RunScale(const std::vector<int>& counts) {
  std::printf(
      "\nlong tasks: every kind and effort solved by `linkfit solve` (one process each, one "
      "thread): exit status, wall time, peak resident memory\n");
  std::printf("%-14s %8s %-9s %5s %9s %9s\n", "kind", "items", "effort", "exit", "seconds",
              "peak_MB");
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("linkfit-bench-scale." + std::to_string(getpid()));
  std::filesystem::create_directories(directory);
  const std::string task_path = (directory / "task.json").string();
  const std::string result_path = (directory / "result.json").string();
  for (const int count : counts) {
    for (const std::string& kind : linkfit::testing::LongTaskKinds()) {
      for (const char* effort : {"fast", "balanced", "thorough"}) {
        std::ofstream(task_path, std::ios::trunc)
            << linkfit::testing::LongTaskText(kind, count, effort);
        const ProgramRun run = RunLinkfit(task_path, result_path);
        std::printf("%-14s %8d %-9s %5d %9.2f %9.1f\n", kind.c_str(), count, effort, run.status,
                    run.seconds, run.max_rss_kb / 1024.0);
        std::fflush(stdout);
      }
    }
  }
  std::filesystem::remove_all(directory);
}

// Path synthesis from target curves (--only curves; issue 34): closed full cycles, open arcs of
// a quarter to three quarters of the cycle and partial arcs (0.8 to 0.95 of a closed curve) of
// random 4Rs, slider-cranks and inverted slider-cranks (tests/support/random_curve.h), 12, 40
// and 400 points unevenly spaced, the curve 1 to 100 units across, noise 0, 1e-3 or 1e-2 of its
// size, printed to 2 to 4 decimals of its size's order, half of them with bounds the generator
// keeps (links at most 1.25 times its longest, both fixed pivots in its pivots' box grown by 30 %
// of the curve's size). Each task solved at balanced and at thorough (SolvePathTask): the share
// whose first listed four-bar fits the printed points as well as the generator (its untimed fit,
// the RMS distance to the nearest point of its coupler curve, and its timed RMS point error, each
// within 1.1 times the generator's own plus 1e-6 of the size), the share whose first keeps the
// bounds, the median and 95th-percentile time, and the share where thorough's first fits
// better than balanced's (by more than 1 %).
struct CurveRow {
  const char* name;
  bool closed;
  double arc_low, arc_high;
  int count;
};

void RunCurves(int tasks, uint64_t seed, bool detail, const std::string& only_rows) {
  using linkfit::DyadType;
  using linkfit::Effort;
  const CurveRow rows[] = {{"closed, 12 points", true, 1.0, 1.0, 12},
                           {"closed, 40 points", true, 1.0, 1.0, 40},
                           {"closed, 400 points", true, 1.0, 1.0, 400},
                           {"open arc, 12 points", false, 0.25, 0.75, 12},
                           {"open arc, 40 points", false, 0.25, 0.75, 40},
                           {"open arc, 400 points", false, 0.25, 0.75, 400},
                           {"partial arc, 40 points", false, 0.8, 0.95, 40}};
  std::printf(
      "\npath synthesis from target curves, free timing (--only curves), %d tasks per row, "
      "seed %llu\n",
      tasks, static_cast<unsigned long long>(seed));
  std::printf("%-24s %-9s %9s %9s %9s %10s %10s %12s\n", "row", "effort", "curve_fit", "timed_fit",
              "bounds", "median_s", "p95_s", "thorough_better");
  for (const CurveRow& row : rows) {
    std::mt19937_64 rng(seed++);
    // --curve-rows: a row runs when its name contains the text (e.g. "closed, 40").
    if (!only_rows.empty() && std::string(row.name).find(only_rows) == std::string::npos) continue;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    struct Tally {
      int curve_fit = 0, timed_fit = 0, bounded = 0, kept = 0;
      std::vector<double> seconds;
    } tally[2];
    int better = 0, refused = 0;
    for (int t = 0; t < tasks; ++t) {
      const DyadType output = t % 3 == 0   ? DyadType::kRR
                              : t % 3 == 1 ? DyadType::kPR
                                           : DyadType::kRP;
      linkfit::testing::CurveOptions options;
      options.count = row.count;
      options.closed = row.closed;
      options.arc_turns = row.arc_low + (row.arc_high - row.arc_low) * unit(rng);
      const linkfit::testing::GeneratedCurve curve =
          linkfit::testing::RandomCurve(rng, output, options);
      // The curve 1 to 100 across, noise, and the digits printed.
      const double across = std::exp(std::log(100.0) * unit(rng));
      const double factor = across / (4.0 * curve.size);
      const double noise_levels[] = {0.0, 1e-3, 1e-2};
      const double noise = noise_levels[t % 3 == 0 ? (t / 3) % 3 : (t + t / 3) % 3];
      std::normal_distribution<double> gauss(0.0, noise * curve.size * factor);
      const int magnitude = static_cast<int>(std::floor(std::log10(across)));
      const int decimals = std::max(0, 2 + static_cast<int>(unit(rng) * 3) - magnitude);
      linkfit::Similarity2 scaling;
      scaling.scale = factor;
      const linkfit::PathFourBar generator = linkfit::TransformPathFourBar(curve.four_bar, scaling);
      std::string text = R"({"problem": "path", "points": [)";
      char buffer[512];
      for (size_t j = 0; j < curve.points.size(); ++j) {
        const Eigen::Vector2d p =
            curve.points[j] * factor + Eigen::Vector2d(gauss(rng), gauss(rng));
        std::snprintf(buffer, sizeof(buffer), "%s{\"x\": %.*f, \"y\": %.*f}", j ? ", " : "",
                      decimals, p.x(), decimals, p.y());
        text += buffer;
      }
      text += "]";
      const bool bounds = t % 2 == 1;
      if (bounds) {
        // Its links as the constraints count them (lib/design_constraints.h).
        const std::vector<double> links = linkfit::PathFourBarLinks(generator).All();
        const double longest = *std::max_element(links.begin(), links.end());
        Eigen::Vector2d low = generator.input.fixed_pivot, high = low;
        if (generator.output.type != DyadType::kPR) {
          low = low.cwiseMin(generator.output.fixed_pivot);
          high = high.cwiseMax(generator.output.fixed_pivot);
        }
        const double grow = 0.3 * 4.0 * curve.size * factor;
        std::snprintf(buffer, sizeof(buffer),
                      R"(, "constraints": {"max_link_length": %.6g, "fixed_pivots_box": )"
                      R"([[%.6g, %.6g], [%.6g, %.6g]]})",
                      1.25 * longest, low.x() - grow, low.y() - grow, high.x() + grow,
                      high.y() + grow);
        text += buffer;
      }
      text += "}";
      double fits[2] = {0.0, 0.0};
      std::string lines;  // --curve-detail: one line per task and effort
      linkfit::Task parsed;
      try {
        parsed = linkfit::ParseTask(text, "curve");
      } catch (const linkfit::InputError&) {
        ++refused;  // points equal as printed (a coarse table of a small curve)
        continue;
      }
      for (int e = 0; e < 2; ++e) {
        linkfit::Task task = parsed;
        task.effort = e == 0 ? Effort::kBalanced : Effort::kThorough;
        std::vector<Eigen::Vector2d> printed;
        for (const linkfit::TimedPoint& point : task.points)
          printed.push_back(point.point_in_fixed);
        const auto start = std::chrono::steady_clock::now();
        const linkfit::PathResult result = linkfit::SolvePathTask(task);
        tally[e].seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        const double size = across / 4.0;
        const double own = linkfit::testing::CurveRmsDistance(generator, printed, size);
        // The generator's timed fit: driven through its own crank angles.
        linkfit::PathAnalysisOptions analysis;
        analysis.closed = task.closed;
        const linkfit::PathFourBarAnalysis generated =
            linkfit::AnalyzePathFourBar(generator, printed, curve.input_angles, size, analysis);
        fits[e] = std::numeric_limits<double>::infinity();
        if (result.mechanisms.empty()) continue;
        const linkfit::PathMechanismReport& first = result.mechanisms.front();
        fits[e] = linkfit::testing::CurveRmsDistance(first.design, printed, size);
        if (fits[e] <= 1.1 * own + 1e-6 * size) ++tally[e].curve_fit;
        if (first.rms_point_error && generated.rms_point_error &&
            *first.rms_point_error <= 1.1 * *generated.rms_point_error + 1e-6 * size) {
          ++tally[e].timed_fit;
        }
        if (bounds) {
          ++tally[e].bounded;
          if (first.violates.empty()) ++tally[e].kept;
        }
        if (detail && !(fits[e] <= 1.1 * own + 1e-6 * size)) {
          // A failed task's text, for a look with the CLI.
          char name[128];
          std::snprintf(name, sizeof(name), "/tmp/curve_fail_%s_%d_%d_%s.json",
                        row.closed          ? "closed"
                        : row.arc_low > 0.5 ? "partial"
                                            : "open",
                        row.count, t, e == 0 ? "balanced" : "thorough");
          if (FILE* file = std::fopen(name, "w")) {
            std::fputs(text.c_str(), file);
            std::fclose(file);
          }
        }
        if (detail) {
          // The best curve fit listed (a search miss, or a ranking that put it further down),
          // the first's defects and the time of each stage.
          double best = std::numeric_limits<double>::infinity();
          size_t best_index = 0;
          for (size_t m = 0; m < result.mechanisms.size(); ++m) {
            const double fit =
                linkfit::testing::CurveRmsDistance(result.mechanisms[m].design, printed, size);
            if (fit < best) best = fit, best_index = m;
          }
          std::string defects;
          for (const std::string& d : first.defects) defects += d + " ";
          for (const std::string& v : first.violates) defects += "!" + v + " ";
          if (!result.mechanisms.empty() && best_index > 0) {
            defects += "| best:";
            for (const std::string& d : result.mechanisms[best_index].defects) defects += " " + d;
            for (const std::string& v : result.mechanisms[best_index].violates) defects += " !" + v;
          }
          std::string stages;
          for (const linkfit::StageReport& stage : result.stages) {
            std::snprintf(buffer, sizeof(buffer), " %s=%.2f", stage.name.c_str(), stage.seconds);
            stages += buffer;
          }
          std::snprintf(buffer, sizeof(buffer),
                        "  task %d %s type=%d noise=%g dec=%d bounds=%d %.2fs own=%.3g first=%.3g "
                        "(%s) best=%.3g #%zu of %zu [%s]%s\n",
                        t, e == 0 ? "bal" : "tho", static_cast<int>(output), noise, decimals,
                        bounds ? 1 : 0, tally[e].seconds.back(), own / size, fits[e] / size,
                        fits[e] <= 1.1 * own + 1e-6 * size ? "pass" : "FAIL", best / size,
                        best_index, result.mechanisms.size(), defects.c_str(), stages.c_str());
          lines += buffer;
        }
      }
      if (fits[1] < 0.99 * fits[0]) ++better;
      if (detail) std::printf("%s", lines.c_str());
    }
    const int solved = std::max(1, tasks - refused);
    for (int e = 0; e < 2; ++e) {
      char kept[32];
      std::snprintf(kept, sizeof(kept), "%d/%d", tally[e].kept, tally[e].bounded);
      std::printf("%-24s %-9s %8.1f%% %8.1f%% %9s %10.3f %10.3f %11s\n", e == 0 ? row.name : "",
                  e == 0 ? "balanced" : "thorough", 100.0 * tally[e].curve_fit / solved,
                  100.0 * tally[e].timed_fit / solved, kept,
                  linkfit::Percentile(tally[e].seconds, 0.5),
                  linkfit::Percentile(tally[e].seconds, 0.95),
                  e == 1 ? (std::to_string(better) + "/" + std::to_string(solved)).c_str() : "");
    }
    if (refused > 0)
      std::printf("%-24s %d task(s) refused: points equal as printed\n", "", refused);
    std::fflush(stdout);
  }
}

namespace linkfit {
namespace {

// Kinematic analysis (--only analysis; issue 37): random mechanisms of each kind analyzed over
// 360 steps of their input (a crank's whole turn, a rocker's range between its dead points):
// the time per analysis (one thread), and the worst relative difference of a rate from
// Richardson-extrapolated central differences of the positions, at three states of each analysis
// away from its dead points (the coupler's or the output's angular velocity; a six-bar's task
// body's).
struct AnalysisRow {
  std::vector<double> micros;
  double worst = 0.0;
  int analyses = 0, checked = 0;
  void Print(const char* kind) const {
    std::printf("%-34s %9d %10.1f %10.1f %9d %14.2e\n", kind, analyses, Percentile(micros, 0.5),
                Percentile(micros, 0.99), checked, worst);
  }
};

// f'(t) from f at t +- h, t +- h/2 (Richardson); false where f is not defined there.
template <typename F>
bool RichardsonRate(const F& f, double t, double h, double* rate) {
  double v[4];
  const double at[4] = {t + h, t - h, t + 0.5 * h, t - 0.5 * h};
  for (int i = 0; i < 4; ++i) {
    if (!f(at[i], &v[i])) return false;
  }
  *rate = (4.0 * (v[2] - v[3]) / h - (v[0] - v[1]) / (2.0 * h)) / 3.0;
  return true;
}

template <typename F>
double Timed(const F& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
      .count();
}

void RunAnalysis(int tasks, uint64_t seed) {
  std::printf(
      "\nkinematic analysis (linkfit analyze), %d random mechanisms per kind, 360 steps each, one "
      "thread; rates against Richardson differences of the positions at 3 states each\n",
      tasks);
  std::printf("%-34s %9s %10s %10s %9s %14s\n", "kind", "analyses", "median_us", "p99_us",
              "checked", "worst_rel_err");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.3, 1.5);
  const auto check = [](AnalysisRow* row, double got, double want) {
    row->worst = std::max(row->worst, std::abs(got - want) / std::max(1.0, std::abs(want)));
    ++row->checked;
  };
  // Planar 4Rs and slider-cranks, closed form.
  for (const bool slider : {false, true}) {
    AnalysisRow row;
    while (row.analyses < tasks) {
      FourBarJoints joints;
      joints.input_pivot = Eigen::Vector2d(unit(rng), unit(rng));
      const double angle = M_PI * unit(rng);
      joints.input_pin =
          joints.input_pivot + size(rng) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      const double turn = M_PI * unit(rng);
      joints.output_pin =
          joints.input_pin + (size(rng) + 0.5) * Eigen::Vector2d(std::cos(turn), std::sin(turn));
      joints.coupler_point = joints.input_pin + Eigen::Vector2d(unit(rng), unit(rng));
      if (slider) {
        joints.slider = true;
        const double line = M_PI * unit(rng);
        joints.slider_direction = Eigen::Vector2d(std::cos(line), std::sin(line));
        joints.slider_point = joints.output_pin - 0.5 * joints.slider_direction;
      } else {
        const double at = M_PI * unit(rng);
        joints.output_pivot =
            joints.output_pin - size(rng) * Eigen::Vector2d(std::cos(at), std::sin(at));
      }
      FourBarKinematics kinematics;
      row.micros.push_back(Timed([&] { kinematics = AnalyzeFourBarKinematics(joints, {}, 1.0); }));
      ++row.analyses;
      for (size_t k = 0; k < kinematics.states.size(); k += kinematics.states.size() / 3 + 1) {
        const FourBarState& state = kinematics.states[k];
        if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 10.0)
          continue;
        double rate = 0.0;
        const auto coupler = [&](double t, double* value) {
          FourBarState placed;
          if (!PlaceFourBar(joints, t, 1.0, &placed)) return false;
          *value =
              placed.coupler_angle +
              2.0 * M_PI * std::round((state.coupler_angle - placed.coupler_angle) / (2.0 * M_PI));
          return true;
        };
        if (RichardsonRate(coupler, state.input_angle, 2.5e-4, &rate)) {
          check(&row, state.coupler_velocity, rate);
        }
      }
    }
    row.Print(slider ? "slider-crank (closed form)" : "4R (closed form)");
  }
  // The other planar types and slider inputs (general closure rows).
  {
    AnalysisRow row;
    const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
    while (row.analyses < tasks) {
      PlanarDyad dyads[2];
      for (PlanarDyad& dyad : dyads) {
        const DyadType type = types[rng() % 3];
        const Eigen::Vector2d fixed(unit(rng), unit(rng)), moving(unit(rng) + 0.3, unit(rng) + 0.8);
        const double line = M_PI * unit(rng);
        const Eigen::Vector2d direction(std::cos(line), std::sin(line));
        dyad = type == DyadType::kRR   ? PlanarDyad::RR(fixed, moving, (moving - fixed).norm())
               : type == DyadType::kPR ? PlanarDyad::PR(moving, moving - 0.3 * direction, direction)
                                       : PlanarDyad::RP(fixed, fixed - 0.3 * direction, direction);
      }
      if (dyads[0].type == DyadType::kRR && dyads[1].type != DyadType::kRP) continue;  // above
      DyadFourBarKinematics kinematics;
      row.micros.push_back(Timed([&] {
        kinematics = AnalyzeDyadFourBarKinematics(dyads[0], dyads[1], Eigen::Vector2d(0.3, -0.5),
                                                  PlanarPose(), {}, 1.0);
      }));
      ++row.analyses;
      for (size_t k = 0; k < kinematics.states.size(); k += kinematics.states.size() / 3 + 1) {
        const DyadFourBarState& state = kinematics.states[k];
        if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 10.0)
          continue;
        if (state.velocity.cwiseAbs().maxCoeff() > 20.0) continue;
        const auto theta = [&](double t, double* value) {
          std::vector<PlanarPose> poses;
          if (AssembleFourBar(dyads[0], dyads[1], t, 0.0, &poses) == 0) return false;
          double best = std::numeric_limits<double>::infinity();
          for (const PlanarPose& pose : poses) {
            const double continued =
                pose.theta +
                2.0 * M_PI * std::round((state.coupler.theta - pose.theta) / (2.0 * M_PI));
            const double distance = (pose.origin_in_fixed - state.coupler.origin_in_fixed).norm() +
                                    std::abs(continued - state.coupler.theta);
            if (distance < best) {
              best = distance;
              *value = continued;
            }
          }
          return true;
        };
        double rate = 0.0;
        if (RichardsonRate(theta, state.input, 2.5e-4, &rate)) check(&row, state.velocity[2], rate);
      }
    }
    row.Print("other types, slider inputs (general)");
  }
  // Spherical four-bars.
  {
    AnalysisRow row;
    while (row.analyses < tasks) {
      const SphericalFourBar made = testing::RandomSphericalFourBar(rng);
      const std::vector<Eigen::Matrix3d> rotations =
          testing::SphericalFourBarRotations(rng, made, 1);
      if (rotations.empty()) continue;
      SphericalFourBarJoints joints;
      joints.input_pivot = made.input.fixed_axis.normalized();
      joints.output_pivot = made.output.fixed_axis.normalized();
      joints.input_pin = (rotations[0] * made.input.moving_axis).normalized();
      joints.output_pin = (rotations[0] * made.output.moving_axis).normalized();
      SphericalFourBarKinematics kinematics;
      row.micros.push_back(
          Timed([&] { kinematics = AnalyzeSphericalFourBarKinematics(joints, {}); }));
      ++row.analyses;
      for (size_t k = 0; k < kinematics.states.size(); k += kinematics.states.size() / 3 + 1) {
        const SphericalFourBarState& state = kinematics.states[k];
        if (std::min(state.transmission_angle_deg, 180.0 - state.transmission_angle_deg) < 10.0)
          continue;
        const auto psi = [&](double t, double* value) {
          SphericalFourBarState placed;
          if (!PlaceSphericalFourBar(joints, t, &placed)) return false;
          *value =
              placed.output_angle +
              2.0 * M_PI * std::round((state.output_angle - placed.output_angle) / (2.0 * M_PI));
          return true;
        };
        double rate = 0.0;
        if (RichardsonRate(psi, state.input_angle, 2.5e-4, &rate))
          check(&row, state.output_velocity, rate);
      }
    }
    row.Print("spherical four-bar");
  }
  // Six-bars of every layout, driven by their upper link.
  {
    AnalysisRow row;
    int layout = 0;
    while (row.analyses < tasks) {
      const testing::GeneratedSixBarTask task = testing::RandomSixBarTask(
          rng, testing::SixBarLayouts()[layout++ % testing::SixBarLayouts().size()]);
      const SixBar& six_bar = task.six_bar;
      SixBarKinematics kinematics;
      row.micros.push_back(
          Timed([&] { kinematics = AnalyzeSixBarKinematics(six_bar, kSixBarUpperLink, {}, 1.0); }));
      ++row.analyses;
      const SixBarDriver driver(six_bar, kSixBarUpperLink, 1.0);
      for (size_t k = 0; k < kinematics.states.size(); k += kinematics.states.size() / 3 + 1) {
        const SixBarState& state = kinematics.states[k];
        if (std::min(state.transmission_deg[0], state.transmission_deg[1]) < 10.0) continue;
        if (state.angular_velocity.cwiseAbs().maxCoeff() > 20.0) continue;
        SixBarAssembly assembly;
        if (!driver.AssemblyOf(state.turns, &assembly)) continue;
        const auto task_body = [&](double t, double* value) {
          SixBarAngles turns = state.turns;
          if (!driver.Place(assembly, t, &turns, 1e-13)) return false;
          *value = turns[kSixBarTaskBody - 1];
          return true;
        };
        double rate = 0.0;
        if (RichardsonRate(task_body, state.turns[kSixBarUpperLink - 1], 2.5e-4, &rate)) {
          check(&row, state.angular_velocity[kSixBarTaskBody - 1], rate);
        }
      }
    }
    row.Print("six-bar (upper link input)");
  }
}

}  // namespace
}  // namespace linkfit

int main(int argc, char** argv) {
  // Ceres reports steps the refiners handle through glog at ERROR level (the CLI silences it the
  // same way, apps/cli.cc RunCli): the tables stay clean.
  FLAGS_minloglevel = google::GLOG_FATAL;
  int tasks = 100000;
  int spatial_tasks = 10000;
  uint64_t seed = 2026;
  std::string only;
  int path_tasks = 10000;
  int refine_tasks = 100;
  int four_tasks = 1000;
  int stage_tasks = 1000;
  int spherical_tasks = 200;
  int curve_tasks = 24;
  int six_bar_tasks = 200;
  int analysis_tasks = 1000;
  bool curve_detail = false;
  std::string curve_rows;  // the curve rows run (their first words: closed, open, partial)
  std::vector<int> scale_counts = {1000, 10000, 100000};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tasks") && i + 1 < argc) {
      tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--spatial-tasks") && i + 1 < argc) {
      spatial_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--path-tasks") && i + 1 < argc) {
      path_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--refine-tasks") && i + 1 < argc) {
      refine_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--four-tasks") && i + 1 < argc) {
      four_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--stage-tasks") && i + 1 < argc) {
      stage_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--curve-tasks") && i + 1 < argc) {
      curve_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--six-bar-tasks") && i + 1 < argc) {
      six_bar_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--analysis-tasks") && i + 1 < argc) {
      analysis_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--curve-detail")) {
      curve_detail = true;
    } else if (!std::strcmp(argv[i], "--curve-rows") && i + 1 < argc) {
      curve_rows = argv[++i];
    } else if (!std::strcmp(argv[i], "--spherical-tasks") && i + 1 < argc) {
      spherical_tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--scale-items") && i + 1 < argc) {
      scale_counts.clear();
      std::istringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) {
        scale_counts.push_back(std::max(1, std::atoi(item.c_str())));
      }
    } else {
      std::fprintf(stderr,
                   "usage: linkfit_bench [--tasks N] [--spatial-tasks M] [--path-tasks P] "
                   "[--refine-tasks R] [--four-tasks F] [--stage-tasks T] "
                   "[--spherical-tasks K] [--curve-tasks C] [--curve-detail] [--curve-rows R] "
                   "[--scale-items N,N,...] [--six-bar-tasks X] [--analysis-tasks A] [--seed S] "
                   "[--only planar|spatial|path|refine|stages|spherical|scale|curves|six-bar|"
                   "analysis]\n"
                   "(the least-squares paths and the extremes: linkfit bench)\n");
      return 2;
    }
  }
  if (only == "spatial") {
    RunSpatial(spatial_tasks, seed);
    return 0;
  }
  if (only == "path") {
    RunPath(path_tasks, seed);
    return 0;
  }
  if (only == "refine") {
    RunRefine(refine_tasks, seed);
    return 0;
  }
  if (only == "stages") {
    RunStages(stage_tasks, seed);
    return 0;
  }
  if (only == "spherical") {
    RunSpherical(spherical_tasks, seed);
    return 0;
  }
  if (only == "scale") {
    RunScale(scale_counts);
    return 0;
  }
  if (only == "curves") {
    RunCurves(curve_tasks, seed, curve_detail, curve_rows);
    return 0;
  }
  if (only == "analysis") {
    linkfit::RunAnalysis(analysis_tasks, seed);
    return 0;
  }
  if (only == "six-bar") {
    RunSixBar(six_bar_tasks, seed);
    RunSixBarChosen(six_bar_tasks, seed);
    RunSixBarLeastSquares(std::max(1, six_bar_tasks / 10), seed + 1, false);
    RunSixBarLeastSquares(std::max(1, six_bar_tasks / 10), seed + 1, true);
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
  std::printf(
      "\nfour poses: Burmester curves and the dyads of the generating pivots (SolvePlanarMotion), "
      "%d random exact tasks per family\n",
      four_tasks);
  std::printf("%-24s %8s %11s %11s %8s %9s %12s %12s %10s %9s\n", "family", "tasks", "recovered",
              "on_curve", "checked", "samples", "worst_res/L", "curves_med_ms", "e2e_med_ms",
              "e2e_p99_ms");
  for (int i = 0; i < 3; ++i) RunFourPoses(families[i], four_tasks, seed++);
  if (only != "planar") {
    RunSpatial(spatial_tasks, seed);
    RunPath(path_tasks, seed);
    RunRefine(refine_tasks, seed);
    RunStages(stage_tasks, seed);
    RunSpherical(spherical_tasks, seed);
    RunSixBar(six_bar_tasks, seed);
    RunSixBarChosen(six_bar_tasks, seed);
    RunSixBarLeastSquares(std::max(1, six_bar_tasks / 10), seed + 1, false);
    RunSixBarLeastSquares(std::max(1, six_bar_tasks / 10), seed + 1, true);
    linkfit::RunAnalysis(analysis_tasks, seed);
  }
  return 0;
}
