// Defects at the data's noise (issue 34): dense measured points of a four-bar's curve, with
// noise, do not give every listed four-bar an order defect; the one nearest the generator has
// no kinematic defect, and the first fits as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "lib/planar_pose.h"
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

// Fifty measured poses of a four-bar (the first fifty of a dense run, noise 3e-3 L on every
// origin and angle): the listed four-bar nearest the generator has no kinematic defect, and the
// first has none and fits as well (issue 34: neighbouring poses a noise-width apart swap order).
// Two 4Rs; a slider-crank drawn next from this seed is left open (issue 34): the first listed is
// a 4R whose poses near its toggle are judged on two branches, and no slider-crank is found.
TEST(NoiseDefects, FiftyNoisyPosesGiveTheFourBarNearestTheGeneratorWithoutOrderDefect) {
  std::mt19937_64 rng(3457);
  for (int t = 0; t < 2; ++t) {
    SCOPED_TRACE("four-bar " + std::to_string(t));
    testing::GeneratedTask generated = testing::RandomTask(rng, DyadType::kRR, DyadType::kRR, 400);
    generated.poses.resize(50);
    const double length = CharacteristicLength(generated.poses);
    std::vector<PlanarPose> noisy = generated.poses;
    testing::PerturbPlanarPoses(rng, kNoise, length, &noisy);
    Task task;
    task.problem = ProblemKind::kMotion;
    task.planar_poses = noisy;
    const PlanarMotionResult result = SolvePlanarTask(task);
    ASSERT_FALSE(result.mechanisms.empty());
    const MechanismReport& first = result.mechanisms.front();
    EXPECT_FALSE(HasKinematicDefect(first.defects));
    // The listed four-bar nearest the generator (the poses span a short arc: the data do not
    // pin the four-bar down, so nearest rather than within a bound).
    const MechanismReport* nearest = nullptr;
    double nearest_apart = std::numeric_limits<double>::infinity();
    for (const MechanismReport& listed : result.mechanisms) {
      const PlanarDyad& input = result.dyads[listed.input_dyad].dyad;
      const PlanarDyad& output = result.dyads[listed.output_dyad].dyad;
      const double apart =
          std::min(std::max(testing::DyadDistance(input, generated.input, length),
                            testing::DyadDistance(output, generated.output, length)),
                   std::max(testing::DyadDistance(output, generated.input, length),
                            testing::DyadDistance(input, generated.output, length)));
      if (apart < nearest_apart) nearest_apart = apart, nearest = &listed;
    }
    ASSERT_NE(nearest, nullptr);
    EXPECT_FALSE(HasKinematicDefect(nearest->defects));
    ASSERT_TRUE(nearest->rms_pose_error && first.rms_pose_error);
    EXPECT_LE(*first.rms_pose_error, 1.25 * *nearest->rms_pose_error);
  }
}

}  // namespace
}  // namespace linkfit
