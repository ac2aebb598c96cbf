#include "tests/support/random_mechanism.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lib/mechanism.h"

namespace linkfit::testing {
namespace {

Eigen::Vector2d RandomPoint(std::mt19937_64& rng, double half_width) {
  std::uniform_real_distribution<double> u(-half_width, half_width);
  return Eigen::Vector2d(u(rng), u(rng));
}

Eigen::Vector2d RandomDirection(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const double a = angle(rng);
  return Eigen::Vector2d(std::cos(a), std::sin(a));
}

// A dyad of `type` satisfied by the coupler at `pose`.
PlanarDyad RandomDyadAt(std::mt19937_64& rng, DyadType type, const PlanarPose& pose) {
  switch (type) {
    case DyadType::kRR: {
      const Eigen::Vector2d fixed_pivot = RandomPoint(rng, 1.0);
      const Eigen::Vector2d pivot_in_fixed = RandomPoint(rng, 1.0);
      return PlanarDyad::RR(fixed_pivot, pose.ToMoving(pivot_in_fixed),
                            (pivot_in_fixed - fixed_pivot).norm());
    }
    case DyadType::kPR: {
      const Eigen::Vector2d pivot_in_fixed = RandomPoint(rng, 1.0);
      return PlanarDyad::PR(pose.ToMoving(pivot_in_fixed), pivot_in_fixed, RandomDirection(rng));
    }
    case DyadType::kRP: {
      const Eigen::Vector2d fixed_pivot = RandomPoint(rng, 1.0);
      return PlanarDyad::RP(fixed_pivot, pose.ToMoving(fixed_pivot), RandomDirection(rng));
    }
  }
  return PlanarDyad();
}

bool TryTask(std::mt19937_64& rng, DyadType input_type, DyadType output_type, int count,
             GeneratedTask* task) {
  PlanarPose start(0.0, 0.0, 0.0);
  start.origin_in_fixed = RandomPoint(rng, 1.0);
  start.theta = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
  task->input = RandomDyadAt(rng, input_type, start);
  task->output = RandomDyadAt(rng, output_type, start);
  return DriveFourBar(rng, start, count, task);
}

}  // namespace

bool AssembleNear(const PlanarDyad& input, const PlanarDyad& output, double input_value,
                  const PlanarPose& near, PlanarPose* pose) {
  std::vector<PlanarPose> candidates;
  if (AssembleFourBar(input, output, input_value, 0.0, &candidates) == 0) return false;
  const PlanarPose* nearest = &candidates[0];
  for (const PlanarPose& candidate : candidates) {
    if (PoseError(candidate, near, 1.0) < PoseError(*nearest, near, 1.0)) nearest = &candidate;
  }
  *pose = *nearest;
  return true;
}

bool DriveFourBar(std::mt19937_64& rng, const PlanarPose& start, int count, GeneratedTask* task) {
  const DyadType input_type = task->input.type;
  task->poses.assign(1, start);

  // The input advances by random steps between poses, in sub-steps of 1 degree (0.01 for a
  // slider) along which the coupler is followed continuously (nearest configuration), so that
  // the mechanism really moves from pose to pose on one branch, as a driven input would.
  // More than eight poses share the travel of eight (steps and separation scaled by 8 / count),
  // so that long tasks stay within about one turn instead of overlapping themselves.
  const double spread = std::min(1.0, 8.0 / count);
  const bool slider_input = input_type == DyadType::kPR;
  std::uniform_real_distribution<double> step_size(
      spread * (slider_input ? 0.15 : 15.0 * M_PI / 180.0),
      spread * (slider_input ? 0.45 : 45.0 * M_PI / 180.0));
  const double sub_step = std::min(slider_input ? 0.01 : M_PI / 180.0, step_size.a() / 4.0);
  const double direction = std::bernoulli_distribution(0.5)(rng) ? 1.0 : -1.0;
  double value = InputValue(task->input, start);
  PlanarPose current = start;
  while (static_cast<int>(task->poses.size()) < count) {
    const double step = step_size(rng);
    const int sub_steps = static_cast<int>(std::ceil(step / sub_step));
    for (int s = 1; s <= sub_steps; ++s) {
      if (!AssembleNear(task->input, task->output, value + direction * step * s / sub_steps,
                        current, &current)) {
        return false;
      }
    }
    value += direction * step;
    task->poses.push_back(current);
  }
  const double length = CharacteristicLength(task->poses);
  if (!(length > 1e-3)) return false;
  for (size_t i = 0; i < task->poses.size(); ++i) {
    for (size_t j = i + 1; j < task->poses.size(); ++j) {
      if (PoseError(task->poses[i], task->poses[j], length) < 0.05 * spread * length) {
        return false;
      }
    }
  }
  return true;
}

GeneratedTask RandomTask(std::mt19937_64& rng, DyadType input, DyadType output, int count) {
  GeneratedTask task;
  while (!TryTask(rng, input, output, count, &task)) {
  }
  return task;
}

void PerturbPlanarPoses(std::mt19937_64& rng, double noise, double length,
                        std::vector<PlanarPose>* poses) {
  std::normal_distribution<double> normal;
  for (PlanarPose& pose : *poses) {
    pose.origin_in_fixed += noise * length * Eigen::Vector2d(normal(rng), normal(rng));
    pose.theta += noise * normal(rng);
  }
}

double DyadDistance(const PlanarDyad& found, const PlanarDyad& expected, double length) {
  if (found.type != expected.type) return std::numeric_limits<double>::infinity();
  auto line_distance = [](const Eigen::Vector2d& dir_a, const Eigen::Vector2d& point_a,
                          const Eigen::Vector2d& dir_b, const Eigen::Vector2d& point_b) {
    const double angle = std::abs(dir_a.x() * dir_b.y() - dir_a.y() * dir_b.x());
    const Eigen::Vector2d normal_a(-dir_a.y(), dir_a.x()), normal_b(-dir_b.y(), dir_b.x());
    return std::max({angle, std::abs(normal_a.dot(point_b - point_a)),
                     std::abs(normal_b.dot(point_a - point_b))});
  };
  switch (expected.type) {
    case DyadType::kRR:
      return std::max({(found.fixed_pivot - expected.fixed_pivot).norm(),
                       (found.moving_pivot - expected.moving_pivot).norm(),
                       std::abs(found.radius - expected.radius)}) /
             length;
    case DyadType::kPR:
      return std::max((found.moving_pivot - expected.moving_pivot).norm() / length,
                      line_distance(found.line_direction, found.line_point / length,
                                    expected.line_direction, expected.line_point / length));
    case DyadType::kRP:
      return std::max((found.fixed_pivot - expected.fixed_pivot).norm() / length,
                      line_distance(found.line_direction, found.line_point / length,
                                    expected.line_direction, expected.line_point / length));
  }
  return std::numeric_limits<double>::infinity();
}

double DyadScale(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  centroid /= static_cast<double>(poses.size());
  double scale = CharacteristicLength(poses);
  switch (dyad.type) {
    case DyadType::kRR:
      return std::max({scale, (dyad.fixed_pivot - centroid).norm(), dyad.moving_pivot.norm()});
    case DyadType::kPR:
      return std::max({scale, dyad.moving_pivot.norm(), (dyad.LineFoot() - centroid).norm()});
    case DyadType::kRP:
      return std::max({scale, (dyad.fixed_pivot - centroid).norm(), dyad.LineFoot().norm()});
  }
  return scale;
}

double NearestDyadDistance(const std::vector<PlanarDyad>& candidates, const PlanarDyad& expected,
                           double length) {
  double best = std::numeric_limits<double>::infinity();
  for (const PlanarDyad& candidate : candidates) {
    best = std::min(best, DyadDistance(candidate, expected, length));
  }
  return best;
}

}  // namespace linkfit::testing
