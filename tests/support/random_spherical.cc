#include "tests/support/random_spherical.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

namespace linkfit::testing {

Eigen::Vector3d RandomUnitVector(std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d x;
  do {
    x = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  } while (x.norm() < 1e-3);
  return x.normalized();
}

Eigen::Matrix3d RandomSmallRotation(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> normal(0.0, sigma);
  return Eigen::AngleAxisd(normal(rng), RandomUnitVector(rng)).toRotationMatrix();
}

void JitterRotations(std::mt19937_64& rng, double sigma, std::vector<Eigen::Matrix3d>* rotations) {
  for (Eigen::Matrix3d& rotation : *rotations)
    rotation = RandomSmallRotation(rng, sigma) * rotation;
}

SphericalFourBar RandomSphericalFourBar(std::mt19937_64& rng) {
  const double low = 15.0 * M_PI / 180.0, high = M_PI - low;
  for (;;) {
    const Eigen::Vector3d u1 = RandomUnitVector(rng), u2 = RandomUnitVector(rng);
    const Eigen::Vector3d v1 = RandomUnitVector(rng), v2 = RandomUnitVector(rng);
    const SphericalDyad input = SphericalDyad::Make(u1, v1, DirectionAngle(u1, v1));
    const SphericalDyad output = SphericalDyad::Make(u2, v2, DirectionAngle(u2, v2));
    const SphericalFourBar four_bar = MakeSphericalFourBar(input, output);
    bool good = four_bar.valid;
    for (const double angle :
         {DirectionAngle(u1, v1), DirectionAngle(u2, v2), four_bar.ground, four_bar.coupler}) {
      good = good && angle > low && angle < high;
    }
    // Away from a stationary configuration at the identity: the coupler's pin off the plane of
    // the output axis and the crank pin.
    good = good && std::abs(u2.cross(v1).normalized().dot(v2)) > 0.1;
    if (good) return four_bar;
  }
}

std::vector<Eigen::Matrix3d> SphericalFourBarRotations(std::mt19937_64& rng,
                                                       const SphericalFourBar& four_bar, int count,
                                                       double spread) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const double start = SphericalInputAngle(four_bar, identity);
  Eigen::Matrix3d configurations[2];
  double value = 0.0;
  if (AssembleSphericalFourBarAt(four_bar, identity, 1e-9, configurations, &value) != 2) return {};
  const int label =
      (configurations[0] - identity).norm() <= (configurations[1] - identity).norm() ? 0 : 1;
  // How far the input can run forward from the identity on its branch: to the end of its arc.
  const FourBarClosure closure = SphericalClosure(four_bar);
  const int interval = ClosureIntervalOf(closure, start, 1e-9);
  if (interval < 0) return {};
  // On a limited input each label is a branch from one end of the arc to the other: forward on
  // the identity's label to the arc's end stays on its branch.
  const ClosureInterval& arc = closure.intervals[interval];
  const double room =
      std::min(0.95 * (closure.full_turn ? 2.0 * M_PI : PositiveAngle(arc.end - start)), spread);
  // Inputs at least 0.15 rad apart, or half the even spacing for many orientations.
  const double kGap = std::min(0.15, 0.5 * room / count);
  if (room < 0.15 * std::min(count, 5)) return {};
  std::uniform_real_distribution<double> uniform(0.0, room);
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::vector<double> steps = {0.0};
    for (int k = 1; k < count; ++k) steps.push_back(uniform(rng));
    std::sort(steps.begin(), steps.end());
    bool apart = true;
    for (int k = 1; k < count; ++k) apart = apart && steps[k] - steps[k - 1] >= kGap;
    if (!apart) continue;
    std::vector<Eigen::Matrix3d> rotations;
    for (const double step : steps) {
      if (AssembleSphericalFourBar(four_bar, start + step, 1e-9, configurations) != 2) {
        return {};
      }
      rotations.push_back(configurations[label]);
    }
    rotations[0] = identity;
    return rotations;
  }
  return {};
}

SphericalTask RandomSphericalTask(std::mt19937_64& rng, int count, double spread) {
  SphericalTask task;
  while (task.rotations.empty()) {
    task.four_bar = RandomSphericalFourBar(rng);
    task.rotations = SphericalFourBarRotations(rng, task.four_bar, count, spread);
  }
  return task;
}

std::vector<DualQuaternion> PosesAboutCenter(const std::vector<Eigen::Matrix3d>& rotations,
                                             const Eigen::Vector3d& center_in_moving,
                                             const Eigen::Vector3d& center_in_fixed) {
  std::vector<DualQuaternion> poses;
  for (const Eigen::Matrix3d& rotation : rotations) {
    poses.push_back(DualQuaternion::FromRotationTranslation(
        rotation, center_in_fixed - rotation * center_in_moving));
  }
  return poses;
}

SphericalPosesTask RandomSphericalPoses(std::mt19937_64& rng, int count, double sigma) {
  SphericalTask drawn = RandomSphericalTask(rng, count);
  if (sigma > 0.0) JitterRotations(rng, sigma, &drawn.rotations);
  SphericalPosesTask task;
  task.four_bar = drawn.four_bar;
  task.rotations = std::move(drawn.rotations);
  task.poses = PosesAboutCenter(task.rotations, Eigen::Vector3d(0.3, -0.2, 0.5),
                                Eigen::Vector3d(1.0, 2.0, -1.0));
  return task;
}

}  // namespace linkfit::testing
