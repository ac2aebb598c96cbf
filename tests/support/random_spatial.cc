#include "tests/support/random_spatial.h"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace linkfit::testing {
namespace {

Eigen::Vector3d RandomVector(std::mt19937_64& rng, double extent) {
  std::uniform_real_distribution<double> uniform(-extent, extent);
  return Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
}

Eigen::Vector3d RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

Eigen::Matrix3d Exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

}  // namespace

DualQuaternion RandomSpatialPose(std::mt19937_64& rng, double extent) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return DualQuaternion::FromRotationTranslation(q.toRotationMatrix(), RandomVector(rng, extent));
}

std::vector<DualQuaternion> RandomSphericalMotion(std::mt19937_64& rng, int count,
                                                  Eigen::Vector3d* center) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d fixed(uniform(rng), uniform(rng), uniform(rng));
  std::vector<DualQuaternion> poses;
  for (int j = 0; j < count; ++j) {
    const Eigen::Matrix3d rotation = RandomSpatialPose(rng).Rotation();
    poses.push_back(DualQuaternion::FromRotationTranslation(rotation, fixed - rotation * fixed));
  }
  *center = fixed;
  return poses;
}

SpatialDyad RandomSSDyad(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(0.5, 2.0);
  return SpatialDyad::SS(RandomVector(rng, 1.0), RandomVector(rng, 1.0), radius(rng));
}

SpatialDyad RandomPSDyad(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  return SpatialDyad::PS(RandomVector(rng, 1.0), RandomUnit(rng), offset(rng));
}

std::vector<SpatialDyad> DyadsThroughPose(std::mt19937_64& rng, const DualQuaternion& pose,
                                          const std::vector<SpatialDyadType>& types) {
  std::vector<SpatialDyad> dyads;
  for (SpatialDyadType type : types) {
    const Eigen::Vector3d moving = RandomVector(rng, 1.0);
    const Eigen::Vector3d point = pose.ToFixed(moving);
    if (type == SpatialDyadType::kSS) {
      Eigen::Vector3d center = RandomVector(rng, 1.0);
      while ((center - point).norm() < 0.3) center = RandomVector(rng, 1.0);
      dyads.push_back(SpatialDyad::SS(center, moving, (point - center).norm()));
    } else if (type == SpatialDyadType::kPS) {
      const Eigen::Vector3d normal = RandomUnit(rng);
      dyads.push_back(SpatialDyad::PS(moving, normal, normal.dot(point)));
    } else {
      // SP: a random point of Sigma on a plane of E through where E sees it.
      const Eigen::Vector3d fixed = RandomVector(rng, 1.0);
      const Eigen::Vector3d seen = pose.Rotation().transpose() * (fixed - pose.Translation());
      const Eigen::Vector3d normal = RandomUnit(rng);
      dyads.push_back(SpatialDyad::SP(fixed, normal, normal.dot(seen)));
    }
  }
  return dyads;
}

std::vector<DualQuaternion> PosesOnDyads(std::mt19937_64& rng,
                                         const std::vector<SpatialDyad>& dyads,
                                         const DualQuaternion& start, int count) {
  std::vector<DualQuaternion> poses = TryPosesOnDyads(rng, dyads, start, count, 100000);
  if (poses.empty()) std::abort();  // the dyads do not fit `start`
  return poses;
}

std::vector<DualQuaternion> TryPosesOnDyads(std::mt19937_64& rng,
                                            const std::vector<SpatialDyad>& dyads,
                                            const DualQuaternion& start, int count,
                                            int max_attempts) {
  std::vector<DualQuaternion> poses = {start};
  const int k = static_cast<int>(dyads.size());
  for (int attempt = 0; static_cast<int>(poses.size()) < count; ++attempt) {
    if (attempt > max_attempts) return {};
    Eigen::Matrix3d rotation = Exp(RandomVector(rng, 1.5)) * start.Rotation();
    Eigen::Vector3d translation = start.Translation() + RandomVector(rng, 1.5);
    bool converged = k == 0;
    for (int iteration = 0; iteration < 60 && !converged; ++iteration) {
      Eigen::VectorXd residual(k);
      Eigen::MatrixXd jacobian(k, 6);
      for (int i = 0; i < k; ++i) {
        residual[i] = dyads[i].Residual(rotation, translation);
        // Numerical derivative in the twist (w, v): R -> exp(w) R, d -> d + v.
        for (int p = 0; p < 6; ++p) {
          const double h = 1e-7;
          Eigen::Vector3d w = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
          (p < 3 ? w[p] : v[p - 3]) = h;
          const double plus = dyads[i].Residual(Exp(w) * rotation, translation + v);
          const double minus = dyads[i].Residual(Exp(-w) * rotation, translation - v);
          jacobian(i, p) = (plus - minus) / (2 * h);
        }
      }
      if (residual.cwiseAbs().maxCoeff() < 1e-15) {
        converged = true;
        break;
      }
      // Minimum-norm step.
      const Eigen::VectorXd step = jacobian.completeOrthogonalDecomposition().solve(residual);
      if (!step.allFinite()) break;
      rotation = Exp(-step.head<3>()) * rotation;
      translation -= step.tail<3>();
    }
    if (!converged) {
      double worst = 0.0;
      for (const SpatialDyad& dyad : dyads) {
        worst = std::max(worst, std::abs(dyad.Residual(rotation, translation)));
      }
      converged = worst < 1e-14;
    }
    if (!converged || (translation - start.Translation()).norm() > 4.0) continue;
    const DualQuaternion pose = DualQuaternion::FromRotationTranslation(rotation, translation);
    bool close = false;
    for (const DualQuaternion& previous : poses) close |= PoseError(previous, pose, 1.0) < 0.05;
    if (!close) poses.push_back(pose);
  }
  return poses;
}

PlantedSpatialTask RandomPlatformTask(std::mt19937_64& rng, int count,
                                      const std::vector<SpatialDyadType>& types) {
  PlantedSpatialTask task;
  while (task.poses.empty()) {
    const DualQuaternion start = RandomSpatialPose(rng);
    task.planted = DyadsThroughPose(rng, start, types);
    task.poses = TryPosesOnDyads(rng, task.planted, start, count, 2000);
  }
  return task;
}

void PerturbSpatialPoses(std::mt19937_64& rng, double noise, std::vector<DualQuaternion>* poses) {
  std::normal_distribution<double> normal;
  for (DualQuaternion& pose : *poses) {
    const Eigen::Vector3d w(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d v(normal(rng), normal(rng), normal(rng));
    pose = DualQuaternion::FromAxisAngle(w, noise * w.norm(), noise * v) * pose;
  }
}

double SpatialDyadSize(const SpatialDyad& dyad) {
  double size = std::max({1.0, dyad.moving_pivot.norm(), std::abs(dyad.plane_offset)});
  if (dyad.type != SpatialDyadType::kPS) size = std::max(size, dyad.fixed_pivot.norm());
  if (dyad.type == SpatialDyadType::kSS) size = std::max(size, dyad.radius);
  return size;
}

double SpatialDyadDistance(const SpatialDyad& found, const SpatialDyad& expected) {
  if (found.type != expected.type) return std::numeric_limits<double>::infinity();
  double difference = 0.0;
  if (expected.type != SpatialDyadType::kSP) {
    difference = (found.moving_pivot - expected.moving_pivot).norm();
  }
  if (expected.type != SpatialDyadType::kPS) {
    difference = std::max(difference, (found.fixed_pivot - expected.fixed_pivot).norm());
  }
  if (expected.type == SpatialDyadType::kSS) {
    difference = std::max(difference, std::abs(found.radius - expected.radius));
  } else {
    // Planes compared as planes: (n, h) and (-n, -h) are the same.
    const double sign = found.plane_normal.dot(expected.plane_normal) < 0.0 ? -1.0 : 1.0;
    difference = std::max({difference, (sign * found.plane_normal - expected.plane_normal).norm(),
                           std::abs(sign * found.plane_offset - expected.plane_offset)});
  }
  return difference / SpatialDyadSize(expected);
}

double NearestSpatialDyadDistance(const std::vector<SpatialDyad>& candidates,
                                  const SpatialDyad& expected) {
  double best = std::numeric_limits<double>::infinity();
  for (const SpatialDyad& candidate : candidates) {
    best = std::min(best, SpatialDyadDistance(candidate, expected));
  }
  return best;
}

}  // namespace linkfit::testing
