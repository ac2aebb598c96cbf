#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "tests/support/random_path.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kExact = 1e-12;  // point errors of exactly generated points, times L

// A four-bar in the first-point convention: crank B = 0, |BA| = crank at `angle0`; rocker pivot
// (ground, 0); rocker and coupler links; the coupler point above the coupler link. Label
// `upper` picks the assembly.
PathFourBar MakeFourBar(double crank, double ground, double coupler, double rocker, double angle0,
                        bool upper = true) {
  const Eigen::Vector2d pivot(0.0, 0.0), rocker_pivot(ground, 0.0);
  const Eigen::Vector2d pin = crank * Eigen::Vector2d(std::cos(angle0), std::sin(angle0));
  const double d = (rocker_pivot - pin).norm();
  const double a = (coupler * coupler - rocker * rocker + d * d) / (2.0 * d);
  const double h = std::sqrt(std::max(coupler * coupler - a * a, 0.0));
  const Eigen::Vector2d e = (rocker_pivot - pin) / d, n(-e.y(), e.x());
  const Eigen::Vector2d rocker_pin = pin + a * e + (upper ? h : -h) * n;
  PathFourBar four_bar;
  four_bar.input = PlanarDyad::RR(pivot, pin, crank);
  four_bar.output = PlanarDyad::RR(rocker_pivot, rocker_pin, rocker);
  const Eigen::Vector2d link = rocker_pin - pin;
  four_bar.coupler_point = pin + 0.5 * link + 0.4 * Eigen::Vector2d(-link.y(), link.x());
  return four_bar;
}

// The coupler point at each crank angle (absolute), on assembly `label`.
std::vector<Eigen::Vector2d> PointsAt(const PathFourBar& four_bar,
                                      const std::vector<double>& alphas, int label) {
  std::vector<Eigen::Vector2d> points;
  for (double alpha : alphas) {
    std::vector<PlanarPose> poses;
    EXPECT_EQ(AssembleFourBar(four_bar.input, four_bar.output, alpha, 1e-12, &poses), 2);
    points.push_back(poses[label].ToFixed(four_bar.coupler_point));
  }
  return points;
}

int FirstLabel(const PathFourBar& four_bar) {
  std::vector<PlanarPose> poses;
  AssembleFourBar(four_bar.input, four_bar.output, FirstCrankAngle(four_bar), 1e-12, &poses);
  return PoseError(poses[0], PlanarPose(), 1.0) < PoseError(poses[1], PlanarPose(), 1.0) ? 0 : 1;
}

TEST(PathMotion, RandomFourBarsMeetTheirPointsWithoutDefect) {
  std::mt19937_64 rng(71);
  for (DyadType output : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
    for (int t = 0; t < 30; ++t) {
      SCOPED_TRACE("seed 71, output " + std::string(DyadTypeName(output)) + ", task " +
                   std::to_string(t));
      const testing::GeneratedPathTask task = testing::RandomPathTask(rng, output, 8);
      const double length = testing::PathLength(task.points);
      const PathFourBarAnalysis analysis =
          AnalyzePathFourBar(task.four_bar, task.points, task.input_angles, length);
      ASSERT_TRUE(analysis.max_point_error) << analysis.error_note;
      EXPECT_LE(*analysis.max_point_error, kExact * length);
      EXPECT_TRUE(analysis.defects.empty());
      EXPECT_EQ(analysis.point_errors.size(), task.points.size());
    }
  }
}

TEST(PathMotion, CrankRockerTurnsFullyAndPassesAllAroundTheTurn) {
  const PathFourBar four_bar = MakeFourBar(1.0, 3.0, 2.8, 2.0, 0.3);
  const int label = FirstLabel(four_bar);
  std::vector<double> alphas;
  for (int j = 0; j < 8; ++j) alphas.push_back(0.3 + j * 0.8);  // 5.6 rad: almost a turn
  const std::vector<Eigen::Vector2d> points = PointsAt(four_bar, alphas, label);
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, alphas, 1.0);
  EXPECT_TRUE(analysis.input_rotates_fully);
  ASSERT_TRUE(analysis.max_point_error);
  EXPECT_LE(*analysis.max_point_error, kExact);
  EXPECT_TRUE(analysis.defects.empty());
  // Only the differences of the input angles matter.
  std::vector<double> shifted = alphas;
  for (double& angle : shifted) angle += 10.0;
  EXPECT_LE(*AnalyzePathFourBar(four_bar, points, shifted, 1.0).max_point_error, kExact);
}

TEST(PathMotion, PointOnTheOtherAssemblyOfACrankIsACircuitDefect) {
  const PathFourBar four_bar = MakeFourBar(1.0, 3.0, 2.8, 2.0, 0.3);
  const int label = FirstLabel(four_bar);
  const std::vector<double> alphas = {0.3, 1.1, 1.9, 2.7};
  std::vector<Eigen::Vector2d> points = PointsAt(four_bar, alphas, label);
  points[2] = PointsAt(four_bar, {alphas[2]}, 1 - label)[0];
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, alphas, 1.0);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"circuit"});
  ASSERT_TRUE(analysis.max_point_error);
  EXPECT_GT(*analysis.max_point_error, 0.1);  // measured on the assembly the crank keeps
}

TEST(PathMotion, LimitedInputThatMustPassItsLimitIsABranchDefect) {
  // Non-Grashof (triple rocker): 2.2 + 3 > 1.8 + 2.5, the input cannot turn fully.
  const PathFourBar four_bar = MakeFourBar(2.2, 3.0, 1.8, 2.5, 1.0);
  const int label = FirstLabel(four_bar);
  const PathFourBarAnalysis full =
      AnalyzePathFourBar(four_bar, {Eigen::Vector2d::Zero()}, {0.0}, 1.0);
  EXPECT_FALSE(full.input_rotates_fully);
  // Find the input's reach on the way up from 1.0 by assembling.
  double limit = 1.0;
  std::vector<PlanarPose> poses;
  while (AssembleFourBar(four_bar.input, four_bar.output, limit + 0.01, 0.0, &poses) > 0) {
    limit += 0.01;
  }
  ASSERT_LT(limit, 1.0 + 2.0 * kPi);
  // Points before the limit, then back below it: the crank has to pass the limit between
  // points 1 and 2 when driven the prescribed way (up, then up again past the limit).
  const std::vector<double> reachable = {1.0, limit - 0.02};
  const std::vector<Eigen::Vector2d> points = PointsAt(four_bar, reachable, label);
  EXPECT_TRUE(AnalyzePathFourBar(four_bar, points, reachable, 1.0).defects.empty());
  // The same points with a prescribed step that goes around past the limit (a full turn more).
  const std::vector<double> around = {1.0, limit - 0.02 + 2.0 * kPi};
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, around, 1.0);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"branch"});
}

TEST(PathMotion, ClosingInputAngleTurnsOnceInTheTimingsDirection) {
  EXPECT_NEAR(ClosingInputAngle({0.5, 1.0, 3.0}), 0.5 + 2.0 * kPi, 1e-15);
  EXPECT_NEAR(ClosingInputAngle({0.5, -1.0, -3.0}), 0.5 - 2.0 * kPi, 1e-15);
  // Angles past a turn close at the next whole turn in the same direction.
  EXPECT_NEAR(ClosingInputAngle({0.0, 3.0, 7.0}), 4.0 * kPi, 1e-15);
  // A last angle equal to the first: the second angle gives the direction.
  EXPECT_NEAR(ClosingInputAngle({1.0, 0.5, 1.0}), 1.0 - 2.0 * kPi, 1e-15);
}

TEST(PathMotion, ClosedPathOfACrankTurnsBackWithoutDefect) {
  // Grashof crank-rocker: 1 + 3 <= 2.8 + 2, the crank (shortest, on the ground) turns fully.
  const PathFourBar four_bar = MakeFourBar(1.0, 3.0, 2.8, 2.0, 0.3);
  const int label = FirstLabel(four_bar);
  for (double direction : {1.0, -1.0}) {
    SCOPED_TRACE("direction " + std::to_string(direction));
    std::vector<double> alphas;
    for (int j = 0; j < 7; ++j) alphas.push_back(0.3 + direction * j * 2.0 * kPi / 7.0);
    const std::vector<Eigen::Vector2d> points = PointsAt(four_bar, alphas, label);
    PathAnalysisOptions options;
    options.closed = true;
    options.transmission_samples = 16;
    const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, alphas, 1.0, options);
    EXPECT_TRUE(analysis.input_rotates_fully);
    EXPECT_TRUE(analysis.defects.empty());
    ASSERT_TRUE(analysis.max_point_error);
    EXPECT_LE(*analysis.max_point_error, kExact);
    EXPECT_TRUE(analysis.transmission_min_deg);
  }
}

TEST(PathMotion, ClosedPathOfALimitedInputIsABranchDefect) {
  // Grashof double-rocker: the coupler is the shortest link (1.5 + 3 <= 2.5 + 2.8); the input
  // reaches crank angles of about 25 to 102 degrees only.
  const PathFourBar four_bar = MakeFourBar(2.5, 3.0, 1.5, 2.8, 90.0 * kPi / 180.0);
  const int label = FirstLabel(four_bar);
  std::vector<double> alphas;
  for (double degrees : {90.0, 75.0, 60.0, 45.0, 35.0}) alphas.push_back(degrees * kPi / 180.0);
  const std::vector<Eigen::Vector2d> points = PointsAt(four_bar, alphas, label);
  const PathFourBarAnalysis open = AnalyzePathFourBar(four_bar, points, alphas, 1.0);
  EXPECT_FALSE(open.input_rotates_fully);
  EXPECT_TRUE(open.defects.empty());
  // Closed: the crank would have to turn on from 35 degrees down to 90 - 360 degrees.
  PathAnalysisOptions options;
  options.closed = true;
  const PathFourBarAnalysis closed = AnalyzePathFourBar(four_bar, points, alphas, 1.0, options);
  EXPECT_EQ(closed.defects, std::vector<std::string>{"branch"});
  ASSERT_TRUE(closed.max_point_error);
  EXPECT_LE(*closed.max_point_error, kExact);  // the points themselves are met
}

TEST(PathMotion, ErrorBoundIsLinearInThePrecisionAndNeedsEnoughPoints) {
  const PathFourBar four_bar = MakeFourBar(1.0, 3.0, 2.8, 2.0, 0.3);
  const int label = FirstLabel(four_bar);
  std::vector<double> alphas;
  for (int j = 0; j < 6; ++j) alphas.push_back(0.3 + j * 0.7);
  const std::vector<Eigen::Vector2d> points = PointsAt(four_bar, alphas, label);
  DataPrecision coarse, finer;
  coarse.length = 1e-4;
  coarse.angle = 1e-5;
  finer.length = 1e-6;
  finer.angle = 1e-7;
  const double bound = PathFourBarErrorBound(four_bar, points, alphas, coarse, 1.0);
  ASSERT_TRUE(std::isfinite(bound));
  EXPECT_GE(bound, coarse.length);  // no better than the points themselves
  EXPECT_NEAR(PathFourBarErrorBound(four_bar, points, alphas, finer, 1.0), 1e-2 * bound,
              1e-3 * bound);
  // Four points (8 coordinates) cannot determine the 10 parameters.
  const std::vector<Eigen::Vector2d> four(points.begin(), points.begin() + 4);
  const std::vector<double> four_angles(alphas.begin(), alphas.begin() + 4);
  EXPECT_TRUE(std::isinf(PathFourBarErrorBound(four_bar, four, four_angles, coarse, 1.0)));
  // Free timing adds the five angles: 15 parameters, 12 coordinates.
  EXPECT_TRUE(std::isinf(PathFourBarErrorBound(four_bar, points, alphas, coarse, 1.0, true)));
}

TEST(PathMotion, AngleOutOfReachLeavesTheErrorOutWithANote) {
  const PathFourBar four_bar = MakeFourBar(2.2, 3.0, 1.8, 2.5, 1.0);
  const std::vector<double> alphas = {1.0, 1.0 + kPi};  // the opposite crank angle: no assembly
  std::vector<PlanarPose> poses;
  ASSERT_EQ(AssembleFourBar(four_bar.input, four_bar.output, alphas[1], 0.0, &poses), 0);
  const std::vector<Eigen::Vector2d> points = {four_bar.coupler_point, four_bar.coupler_point};
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, alphas, 1.0);
  EXPECT_FALSE(analysis.max_point_error);
  EXPECT_NE(analysis.error_note.find("points[1]"), std::string::npos);
  EXPECT_TRUE(analysis.point_errors.empty());
}

TEST(PathMotion, MovingToTheFirstConfigurationKeepsTheMotion) {
  std::mt19937_64 rng(72);
  const testing::GeneratedPathTask task = testing::RandomPathTask(rng, DyadType::kRR, 6);
  const double length = testing::PathLength(task.points);
  // A design expressed in another coupler frame: E' = q^-1 E for some pose q; moving it back
  // with q gives the same four-bar.
  const PlanarPose q(0.3, -0.2, 0.7);
  PathFourBar other = task.four_bar;
  other.input.moving_pivot = q.ToMoving(task.four_bar.input.moving_pivot);
  other.output.moving_pivot = q.ToMoving(task.four_bar.output.moving_pivot);
  other.coupler_point = q.ToMoving(task.four_bar.coupler_point);
  const PathFourBar back = MoveToFirstConfiguration(other, q);
  EXPECT_LE(testing::PathFourBarDistance(back, task.four_bar, length), 1e-14);
}

TEST(PathMotion, CouplerCycleIsClosedForACrankAndForALimitedInput) {
  for (const PathFourBar& four_bar :
       {MakeFourBar(1.0, 3.0, 2.8, 2.0, 0.3), MakeFourBar(2.2, 3.0, 1.8, 2.5, 1.0)}) {
    const std::vector<PlanarPose> cycle = CouplerCycle(four_bar, 1.0, 360);
    ASSERT_GT(cycle.size(), 100u);
    EXPECT_LE(PoseError(cycle.front(), cycle.back(), 1.0), 1e-9);
    // Starts at the first configuration (E = Sigma) for a crank; every pose satisfies both dyads.
    for (const PlanarPose& pose : cycle) {
      EXPECT_LE(std::abs(four_bar.input.Residual(pose)), 1e-9);
      EXPECT_LE(std::abs(four_bar.output.Residual(pose)), 1e-9);
    }
  }
}

}  // namespace
}  // namespace linkfit
