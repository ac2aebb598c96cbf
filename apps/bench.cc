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
//   linkfit_bench [--tasks N] [--seed S]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fitting/planar_burmester.h"
#include "fitting/planar_motion.h"
#include "tests/support/random_mechanism.h"

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

}  // namespace

int main(int argc, char** argv) {
  int tasks = 100000;
  uint64_t seed = 2026;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tasks") && i + 1 < argc) {
      tasks = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else {
      std::fprintf(stderr, "usage: linkfit_bench [--tasks N] [--seed S]\n");
      return 2;
    }
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
  return 0;
}
