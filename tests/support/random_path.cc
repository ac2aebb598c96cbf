#include "tests/support/random_path.h"

#include <cmath>
#include <random>

#include "lib/mechanism.h"
#include "tests/support/random_mechanism.h"

namespace linkfit::testing {

GeneratedPathTask PathTaskOf(const GeneratedTask& motion, const Eigen::Vector2d& coupler_point) {
  PathFourBar four_bar;
  four_bar.input = motion.input;
  four_bar.output = motion.output;
  four_bar.coupler_point = coupler_point;
  GeneratedPathTask task;
  task.four_bar = MoveToFirstConfiguration(four_bar, motion.poses.front());
  double previous = InputValue(motion.input, motion.poses.front());
  double unwrapped = previous;
  for (const PlanarPose& pose : motion.poses) {
    const double value = InputValue(motion.input, pose);
    unwrapped += WrapAngle(value - previous);
    previous = value;
    task.input_angles.push_back(unwrapped);
    task.points.push_back(pose.ToFixed(coupler_point));
  }
  return task;
}

GeneratedPathTask RandomPathTask(std::mt19937_64& rng, DyadType output, int count) {
  // The motion generator follows the nearest configuration in 1-degree sub-steps, which can hop
  // across a stationary configuration to the other branch. Driven by its crank from the first
  // point, such a four-bar does not pass its own points: drawn again.
  for (;;) {
    const GeneratedTask motion = RandomTask(rng, DyadType::kRR, output, count);
    std::uniform_real_distribution<double> box(-1.0, 1.0);
    const Eigen::Vector2d coupler_point(box(rng), box(rng));
    GeneratedPathTask task = PathTaskOf(motion, coupler_point);
    const double length = PathLength(task.points);
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(task.four_bar, task.points, task.input_angles, length);
    if (analysis.defects.empty() && analysis.max_point_error &&
        *analysis.max_point_error <= 1e-9 * length) {
      return task;
    }
  }
}

double PathFourBarDistance(const PathFourBar& found, const PathFourBar& expected, double length) {
  const double input = DyadDistance(found.input, expected.input, length);
  const double output = DyadDistance(found.output, expected.output, length);
  const double point = (found.coupler_point - expected.coupler_point).norm() / length;
  return std::max({input, output, point});
}

double PathLength(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : points) centroid += point;
  centroid /= static_cast<double>(points.size());
  double sum = 0.0;
  for (const Eigen::Vector2d& point : points) sum += (point - centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

Task NoisyPathTask(const GeneratedPathTask& generated, double noise, bool free_timing,
                   Effort effort, std::mt19937_64& rng) {
  const double length = PathLength(generated.points);
  std::normal_distribution<double> normal;
  Task task;
  task.problem = ProblemKind::kPath;
  task.effort = effort;
  for (size_t j = 0; j < generated.points.size(); ++j) {
    TimedPoint point;
    point.point_in_fixed =
        generated.points[j] + noise * length * Eigen::Vector2d(normal(rng), normal(rng));
    if (!free_timing) point.input_angle = generated.input_angles[j];
    task.points.push_back(point);
  }
  return task;
}

}  // namespace linkfit::testing
