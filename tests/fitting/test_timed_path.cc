#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "fitting/timed_path.h"
#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

using testing::GeneratedPathTask;
using testing::PathFourBarDistance;
using testing::PathLength;
using testing::RandomPathTask;

constexpr double kRecovered = 1e-8;     // relative error of the generating four-bar
constexpr double kPassesPoints = 1e-8;  // point error in simulation, times L

// The smallest distance from R_j of the coupler point over both assemblies at psi_j.
double NearestAssembly(const PathFourBar& four_bar, const GeneratedPathTask& task, size_t j) {
  const double alpha = FirstCrankAngle(four_bar) + task.input_angles[j] - task.input_angles[0];
  std::vector<PlanarPose> poses;
  AssembleFourBar(four_bar.input, four_bar.output, alpha, 1e-9, &poses);
  double nearest = std::numeric_limits<double>::infinity();
  for (const PlanarPose& pose : poses) {
    nearest = std::min(nearest, (pose.ToFixed(four_bar.coupler_point) - task.points[j]).norm());
  }
  return nearest;
}

void ExpectGeneratingFourBar(DyadType output, int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  int recovered = 0;
  for (int t = 0; t < tasks; ++t) {
    SCOPED_TRACE("seed " + std::to_string(seed) + ", task " + std::to_string(t));
    const GeneratedPathTask task = RandomPathTask(rng, output);
    const double length = PathLength(task.points);
    std::vector<PathFourBar> four_bars;
    TimedPathSummary summary;
    SolveTimedPath(task.points, task.input_angles, {}, &four_bars, &summary);
    // Four cranks (12 four-bars); data made by a slider-crank put one crank at infinity.
    EXPECT_EQ(summary.crank_roots_total, output == DyadType::kPR ? 3 : 4);
    EXPECT_EQ(summary.four_bars_total, 3 * summary.crank_roots_total);
    EXPECT_LE(four_bars.size(), 12u);
    EXPECT_EQ((summary.crank_roots_total - summary.crank_roots_real) % 2, 0);  // conjugate pairs
    double best = std::numeric_limits<double>::infinity();
    for (const PathFourBar& four_bar : four_bars) {
      best = std::min(best, PathFourBarDistance(four_bar, task.four_bar, length));
      // Every four-bar meets every point at its input angle (on some assembly); without a
      // defect, on the assembly of the first point.
      for (size_t j = 0; j < task.points.size(); ++j) {
        EXPECT_LE(NearestAssembly(four_bar, task, j), kPassesPoints * length) << "point " << j;
      }
      const PathFourBarAnalysis analysis =
          AnalyzePathFourBar(four_bar, task.points, task.input_angles, length);
      ASSERT_TRUE(analysis.assembles);
      if (analysis.defects.empty() && analysis.max_point_error) {
        EXPECT_LE(*analysis.max_point_error, kPassesPoints * length);
      }
    }
    if (best <= kRecovered) ++recovered;
    EXPECT_LE(best, kRecovered);
  }
  EXPECT_EQ(recovered, tasks);
}

TEST(TimedPath, RecoversRandomFourBars) { ExpectGeneratingFourBar(DyadType::kRR, 200, 61); }

TEST(TimedPath, RecoversRandomSliderCranks) { ExpectGeneratingFourBar(DyadType::kPR, 100, 62); }

TEST(TimedPath, RecoversInvertedSliderCranks) { ExpectGeneratingFourBar(DyadType::kRP, 100, 63); }

// Rounded data: the points and input angles printed to `digits` significant digits and read
// back (precision inferred from the digits), solved at that precision. Counts the tasks whose
// nearest returned four-bar has the generating output's type (a slider-crank's output is not a
// huge circle) and lies within twice its first-order error bound (PathFourBarErrorBound;
// twice: first order). Where the slider reading alone makes the four-bar miss the points (an
// ill-conditioned crank), the exact solver keeps the circle.
int RoundedFourBarsBack(DyadType output, int digits, int tasks, uint64_t seed) {
  std::mt19937_64 rng(seed);
  int back = 0;
  for (int t = 0; t < tasks; ++t) {
    const GeneratedPathTask generated = RandomPathTask(rng, output);
    const Task task =
        testing::ReadRounded(testing::PathText(generated.points, generated.input_angles, digits));
    std::vector<Eigen::Vector2d> points;
    std::vector<double> angles;
    testing::TimedPoints(task, &points, &angles);
    const double length = PathLength(points);
    TimedPathOptions options;
    options.precision = task.precision;
    std::vector<PathFourBar> four_bars;
    SolveTimedPath(points, angles, options, &four_bars);
    double best = std::numeric_limits<double>::infinity(), bound = 0.0;
    for (const PathFourBar& four_bar : four_bars) {
      const double distance = PathFourBarDistance(four_bar, generated.four_bar, length);
      if (distance < best) {
        best = distance;
        bound = PathFourBarErrorBound(four_bar, points, angles, task.precision, length);
      }
    }
    if (best * length <= 2.0 * bound) ++back;
  }
  return back;
}

// Measured (seeds 64 and 65, 30 tasks at 8 and at 6 digits): 56 of 60 slider-cranks come back
// as slider-cranks, 60 of 60 4R as 4R.
constexpr int kRoundedTasks = 30;
constexpr int kRoundedSlidersBack = 26;  // of kRoundedTasks, per digit level

TEST(TimedPath, RoundedSliderCrankComesBackAsASliderCrank) {
  for (int digits : {8, 6}) {
    SCOPED_TRACE("seed 64, digits " + std::to_string(digits));
    EXPECT_GE(RoundedFourBarsBack(DyadType::kPR, digits, kRoundedTasks, 64), kRoundedSlidersBack);
  }
}

TEST(TimedPath, RoundedFourBarComesBackAsAFourBar) {
  for (int digits : {8, 6}) {
    SCOPED_TRACE("seed 65, digits " + std::to_string(digits));
    EXPECT_EQ(RoundedFourBarsBack(DyadType::kRR, digits, kRoundedTasks, 65), kRoundedTasks);
  }
}

TEST(TimedPath, GeneratingFourBarHasNoDefect) {
  std::mt19937_64 rng(64);
  for (int t = 0; t < 50; ++t) {
    const GeneratedPathTask task = RandomPathTask(rng, DyadType::kRR);
    const double length = PathLength(task.points);
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(task.four_bar, task.points, task.input_angles, length);
    ASSERT_TRUE(analysis.max_point_error) << analysis.error_note;
    EXPECT_LE(*analysis.max_point_error, 1e-12 * length);
    EXPECT_TRUE(analysis.defects.empty());
  }
}

TEST(TimedPath, Timing) {
  constexpr int kRepeats = 10;
  std::mt19937_64 rng(65);
  std::vector<GeneratedPathTask> tasks;
  for (int t = 0; t < 500; ++t) tasks.push_back(RandomPathTask(rng, DyadType::kRR));
  std::vector<double> times;
  std::vector<PathFourBar> four_bars;
  for (const GeneratedPathTask& task : tasks) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kRepeats; ++k)
      SolveTimedPath(task.points, task.input_angles, {}, &four_bars);
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRepeats);
  }
  std::sort(times.begin(), times.end());
  std::cout << "median SolveTimedPath " << times[times.size() / 2] * 1e6 << " us\n";
}

}  // namespace
}  // namespace linkfit
