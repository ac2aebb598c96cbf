// Defects at the data's noise (issue 34): dense measured points of a four-bar's curve, with
// noise, do not give every listed four-bar an order defect; the one nearest the generator has
// no kinematic defect, and the first fits as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_curve.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

constexpr double kNoise = 3e-3;  // times L

TEST(NoiseDefects, FiftyNoisyPointsOfACurveGiveAFourBarWithoutOrderDefect) {
  std::mt19937_64 rng(3451);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int t = 0; t < 4; ++t) {
    SCOPED_TRACE("curve " + std::to_string(t));
    testing::CurveOptions options;
    options.count = 50;
    options.closed = t % 2 == 0;
    options.arc_turns = 0.6;
    const testing::GeneratedCurve curve =
        testing::RandomCurve(rng, t < 2 ? DyadType::kRR : DyadType::kPR, options);
    Task task;
    task.problem = ProblemKind::kPath;
    std::vector<Eigen::Vector2d> noisy;
    for (const Eigen::Vector2d& p : curve.points) {
      TimedPoint point;
      point.point_in_fixed = p + kNoise * curve.size * Eigen::Vector2d(normal(rng), normal(rng));
      noisy.push_back(point.point_in_fixed);
      task.points.push_back(point);
    }
    const PathResult result = SolvePathTask(task);
    ASSERT_FALSE(result.mechanisms.empty());
    const PathMechanismReport& first = result.mechanisms.front();
    EXPECT_FALSE(HasKinematicDefect(first.defects));
    // The listed four-bar nearest the generator's curve (within a tenth of its size, cognates
    // alike): no kinematic defect, and the first fits as well (within 1.25 times).
    for (const PathMechanismReport& listed : result.mechanisms) {
      if (!(CurveDistance(listed.design, curve.four_bar) <= 0.1 * curve.size)) continue;
      EXPECT_FALSE(HasKinematicDefect(listed.defects));
      ASSERT_TRUE(listed.rms_point_error && first.rms_point_error);
      EXPECT_LE(*first.rms_point_error, 1.25 * *listed.rms_point_error);
    }
  }
}

}  // namespace
}  // namespace linkfit
