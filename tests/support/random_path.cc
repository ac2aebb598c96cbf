#include "tests/support/random_path.h"

#include <array>
#include <cmath>
#include <complex>

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

std::vector<PathFourBar> CurveCognates(const PathFourBar& four_bar) {
  std::vector<PathFourBar> cognates;
  if (four_bar.input.type != DyadType::kRR || four_bar.output.type != DyadType::kRR) {
    return cognates;
  }
  using Complex = std::complex<double>;
  const auto complex = [](const Eigen::Vector2d& point) { return Complex(point.x(), point.y()); };
  const auto point = [](const Complex& z) { return Eigen::Vector2d(z.real(), z.imag()); };
  const Complex a0 = complex(four_bar.input.fixed_pivot), a = complex(four_bar.input.moving_pivot);
  const Complex b0 = complex(four_bar.output.fixed_pivot);
  const Complex b = complex(four_bar.output.moving_pivot), p = complex(four_bar.coupler_point);
  // The coupler triangle A B P as p = a + z (b - a); the third fixed pivot makes A0 B0 C0
  // similar to it. Each cognate's crank is parallel to a side of the coupler (a parallelogram
  // with the original links) and its coupler is a triangle similar to A B P.
  const Complex z = (p - a) / (b - a), z2 = 1.0 - z;  // z2 = (p - b) / (a - b)
  const Complex c0 = a0 + z * (b0 - a0);
  const Complex e1 = a0 + (p - a), f1 = e1 + z * (a - a0);
  const Complex g1 = b0 + (p - b), h1 = g1 + z2 * (b - b0);
  const auto make = [&](const Complex& fixed_in, const Complex& moving_in, const Complex& fixed_out,
                        const Complex& moving_out) {
    PathFourBar cognate;
    cognate.input =
        PlanarDyad::RR(point(fixed_in), point(moving_in), std::abs(moving_in - fixed_in));
    cognate.output =
        PlanarDyad::RR(point(fixed_out), point(moving_out), std::abs(moving_out - fixed_out));
    cognate.coupler_point = four_bar.coupler_point;
    return cognate;
  };
  for (const auto& [fixed_1, moving_1, fixed_2, moving_2] :
       {std::array<Complex, 4>{a0, a, b0, b}, std::array<Complex, 4>{a0, e1, c0, f1},
        std::array<Complex, 4>{b0, g1, c0, h1}}) {
    cognates.push_back(make(fixed_1, moving_1, fixed_2, moving_2));
    cognates.push_back(make(fixed_2, moving_2, fixed_1, moving_1));
  }
  return cognates;
}

double PathLength(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : points) centroid += point;
  centroid /= static_cast<double>(points.size());
  double sum = 0.0;
  for (const Eigen::Vector2d& point : points) sum += (point - centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace linkfit::testing
