// Design constraints acting in the solvers' stages (optimizers/design_bounds.h): an optimum that
// lies on a bound is found, not just a feasible point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/design_constraints.h"
#include "optimizers/path_search.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_path.h"

namespace linkfit {
namespace {

Task TimedTask(const testing::GeneratedPathTask& generated) {
  Task task;
  task.problem = ProblemKind::kPath;
  for (size_t j = 0; j < generated.points.size(); ++j) {
    TimedPoint point;
    point.point_in_fixed = generated.points[j];
    point.input_angle = generated.input_angles[j];
    task.points.push_back(point);
  }
  return task;
}

double LongestLink(const PathFourBar& four_bar) {
  const std::vector<double> links = PathFourBarLinks(four_bar).All();
  return *std::max_element(links.begin(), links.end());
}

// The RMS point error of `four_bar` on the task's points (infinity when it cannot be driven).
double Rms(const PathFourBar& four_bar, const testing::GeneratedPathTask& generated,
           double length) {
  const PathFourBarAnalysis analysis =
      AnalyzePathFourBar(four_bar, generated.points, generated.input_angles, length);
  return analysis.rms_point_error.value_or(std::numeric_limits<double>::infinity());
}

// Ten timed points of a random 4R with every link held to 80 % of the longest of any exact
// four-bar (it and its cognate of the same timing): each breaks the bound, so the constrained
// optimum lies on it. The first listed four-bar
// keeps the bound, and fits within 10 % of the best a long search (the NLopt crank search with
// 25 times the budget, its four-bars refined under the bound) finds; the default effort does it.
TEST(DesignBounds, PathOptimumOnALinkBoundIsFound) {
  std::mt19937_64 rng(1405);
  int on_bound = 0;
  constexpr int kTasks = 4;
  for (int t = 0; t < kTasks; ++t) {
    SCOPED_TRACE("seed 1405, task " + std::to_string(t));
    const testing::GeneratedPathTask generated = testing::RandomPathTask(rng, DyadType::kRR, 10);
    const double length = testing::PathLength(generated.points);
    Task task = TimedTask(generated);
    // Every exact four-bar breaks the bound: the generating one and its cognate driven with the
    // same timing (CurveCognates lists it).
    double shortest_exact = LongestLink(generated.four_bar);
    for (const PathFourBar& cognate : CurveCognates(generated.four_bar)) {
      if (Rms(cognate, generated, length) <= 1e-9 * length) {
        shortest_exact = std::min(shortest_exact, LongestLink(cognate));
      }
    }
    task.constraints.given = true;
    task.constraints.max_link_length = 0.8 * shortest_exact;
    const PathResult result = SolvePathTask(task);
    ASSERT_FALSE(result.mechanisms.empty());
    const PathMechanismReport& first = result.mechanisms.front();
    EXPECT_TRUE(first.violates.empty());
    ASSERT_TRUE(first.rms_point_error.has_value());
    const double longest = LongestLink(first.design);
    EXPECT_LE(longest, *task.constraints.max_link_length * (1.0 + 1e-6));
    if (longest >= *task.constraints.max_link_length * (1.0 - 1e-4)) ++on_bound;

    PathSearchOptions search;
    search.max_evaluations = 500000;
    search.time_limit = 2.5;
    search.refine_count = 8;
    search.seed = 7;
    search.refiner.constraints = task.constraints;
    std::vector<PathFourBar> found;
    std::vector<double> angles = generated.input_angles;
    SearchPathFourBars(generated.points, {}, {}, angles, length, search, &found);
    double best = std::numeric_limits<double>::infinity();
    for (const PathFourBar& four_bar : found) {
      if (LongestLink(four_bar) <= *task.constraints.max_link_length * (1.0 + 1e-6)) {
        best = std::min(best, Rms(four_bar, generated, length));
      }
    }
    EXPECT_LE(*first.rms_point_error, 1.1 * best + 1e-12 * length)
        << "first " << *first.rms_point_error << ", long search " << best;
  }
  // The bound binds at the optimum of most such tasks.
  EXPECT_GE(on_bound, kTasks - 1);
}

}  // namespace
}  // namespace linkfit
