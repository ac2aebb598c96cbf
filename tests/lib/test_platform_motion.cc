#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lib/platform_motion.h"
#include "tests/support/random_spatial.h"

namespace linkfit {
namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix56d = Eigen::Matrix<double, 5, 6>;

constexpr double kExact = 1e-9;            // pose errors of exact tasks, relative to L
constexpr double kHugeRadiusExact = 1e-8;  // the same with a sphere of radius 1e6 L (its rounding)
constexpr double kOnCurve = 1e-9;          // dyad residuals of the reported path, relative to L
constexpr double kPoseSpacing = 0.1;       // between generated task poses, in the fixed coordinate
constexpr int kSubsteps = 25;              // Newton solves between two generated poses
constexpr int kTaskPoses = 7;
constexpr double kHugeRadius = 1e6;

// ---- An independent generator of poses on a platform's motion ----------------------------------
// A pose near the start pose (R0, d0) is y = (phi, d): R = exp([phi]) R0, translation d. One
// coordinate of y is held at successive values and the five dyad residuals are solved for the
// other five by damped Newton (central-difference Jacobian) from the previous solutions.

struct Platform {
  std::vector<SpatialDyad> dyads;
  Eigen::Matrix3d start_rotation = Eigen::Matrix3d::Identity();
};

Eigen::Matrix3d RotationOf(const Platform& platform, const Vector6d& y) {
  const Eigen::Vector3d phi = y.head<3>();
  const double angle = phi.norm();
  const Eigen::Matrix3d turn = angle > 0.0
                                   ? Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix()
                                   : Eigen::Matrix3d::Identity();
  return turn * platform.start_rotation;
}

DualQuaternion PoseOf(const Platform& platform, const Vector6d& y) {
  return DualQuaternion::FromRotationTranslation(RotationOf(platform, y), y.tail<3>());
}

Vector5d Residuals(const Platform& platform, const Vector6d& y) {
  const Eigen::Matrix3d rotation = RotationOf(platform, y);
  Vector5d residuals;
  for (int i = 0; i < 5; ++i) residuals(i) = platform.dyads[i].Residual(rotation, y.tail<3>());
  return residuals;
}

Matrix56d NumericJacobian(const Platform& platform, const Vector6d& y) {
  constexpr double kDifference = 1e-5;
  Matrix56d jacobian;
  for (int k = 0; k < 6; ++k) {
    Vector6d plus = y, minus = y;
    plus(k) += kDifference;
    minus(k) -= kDifference;
    jacobian.col(k) = (Residuals(platform, plus) - Residuals(platform, minus)) / (2 * kDifference);
  }
  return jacobian;
}

// The unit null vector of the residuals' Jacobian (the motion's direction in y).
Vector6d MotionDirection(const Platform& platform, const Vector6d& y) {
  Eigen::Matrix<double, 6, 6> square = Eigen::Matrix<double, 6, 6>::Zero();
  square.topRows<5>() = NumericJacobian(platform, y);
  Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> svd(square, Eigen::ComputeFullV);
  return svd.matrixV().col(5);
}

// Rounding floor of a dyad's residual (large spheres carry large coordinates).
double ResidualFloor(const SpatialDyad& dyad) {
  return 1e-14 + 4e-16 * (dyad.fixed_pivot.norm() + std::abs(dyad.radius) +
                          std::abs(dyad.plane_offset) + dyad.moving_pivot.norm());
}

// Damped Newton for the five coordinates other than `fixed` (y(fixed) is kept).
bool SolveWithFixed(const Platform& platform, int fixed, Vector6d* y) {
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Vector5d residuals = Residuals(platform, *y);
    bool converged = true;
    for (int i = 0; i < 5; ++i) {
      converged = converged && std::abs(residuals(i)) <= ResidualFloor(platform.dyads[i]);
    }
    if (converged) return true;
    const Matrix56d full = NumericJacobian(platform, *y);
    Eigen::Matrix<double, 5, 5> jacobian;
    for (int k = 0, column = 0; k < 6; ++k) {
      if (k != fixed) jacobian.col(column++) = full.col(k);
    }
    const Vector5d step = jacobian.fullPivLu().solve(-residuals);
    if (!step.allFinite()) return false;
    Vector6d full_step = Vector6d::Zero();
    for (int k = 0, row = 0; k < 6; ++k) {
      if (k != fixed) full_step(k) = step(row++);
    }
    double damping = 1.0;
    while (damping > 1e-6) {
      const Vector6d trial = *y + damping * full_step;
      if (Residuals(platform, trial).norm() < residuals.norm() || damping < 2e-6) {
        *y = trial;
        break;
      }
      damping *= 0.5;
    }
    if (damping <= 1e-6) return false;
  }
  return false;
}

// kTaskPoses poses in order along the motion from y = (0, d0): the coordinate the motion changes
// most at the start is stepped by kPoseSpacing / kSubsteps at a time. Fails (returns false) near a
// turning point of that coordinate, where the five others stop being a function of it.
bool GenerateMotion(const Platform& platform, const Eigen::Vector3d& start_translation,
                    std::vector<DualQuaternion>* poses, int* fixed_out = nullptr,
                    std::vector<Vector6d>* coordinates = nullptr) {
  Vector6d y = Vector6d::Zero();
  y.tail<3>() = start_translation;
  const Vector6d direction = MotionDirection(platform, y);
  int fixed = 0;
  direction.cwiseAbs().maxCoeff(&fixed);
  const double sign = direction(fixed) > 0.0 ? 1.0 : -1.0;
  const double increment = sign * kPoseSpacing / kSubsteps;
  poses->assign(1, PoseOf(platform, y));
  if (coordinates != nullptr) coordinates->assign(1, y);
  Vector6d previous = y - increment / direction(fixed) * direction;
  for (int pose = 1; pose < kTaskPoses; ++pose) {
    for (int substep = 0; substep < kSubsteps; ++substep) {
      Vector6d guess = 2.0 * y - previous;  // secant predictor
      guess(fixed) = y(fixed) + increment;
      if (!SolveWithFixed(platform, fixed, &guess)) return false;
      if ((guess - y).norm() > 10.0 * std::abs(increment)) return false;           // jumped
      if (std::abs(MotionDirection(platform, guess)(fixed)) < 0.15) return false;  // turning
      previous = y;
      y = guess;
    }
    poses->push_back(PoseOf(platform, y));
    if (coordinates != nullptr) coordinates->push_back(y);
  }
  if (fixed_out != nullptr) *fixed_out = fixed;
  return true;
}

Eigen::Matrix3d RandomRotation(std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  return q.normalized().toRotationMatrix();
}

Eigen::Vector3d RandomPoint(std::mt19937* rng, double half_width) {
  std::uniform_real_distribution<double> uniform(-half_width, half_width);
  return Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng));
}

enum class Kind {
  kAllSS,   // five SS dyads
  kMixed,   // dyad 1 PS, dyad 3 SS of radius kHugeRadius, the others SS
  kWithSP,  // kMixed with dyad 4 SP
};

// A random platform through the start pose (R0, d0): body points in a box of half-width 1, sphere
// centers in a box of half-width 2, plane normals random.
Platform RandomPlatform(std::mt19937* rng, Kind kind, Eigen::Vector3d* start_translation) {
  Platform platform;
  platform.start_rotation = RandomRotation(rng);
  *start_translation = RandomPoint(rng, 1.0);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d moving = RandomPoint(rng, 1.0);
    const Eigen::Vector3d point = platform.start_rotation * moving + *start_translation;
    if (kind != Kind::kAllSS && i == 1) {
      const Eigen::Vector3d normal = RandomPoint(rng, 1.0).normalized();
      platform.dyads.push_back(SpatialDyad::PS(moving, normal, normal.dot(point)));
    } else if (kind != Kind::kAllSS && i == 3) {
      const Eigen::Vector3d center = point + kHugeRadius * RandomPoint(rng, 1.0).normalized();
      platform.dyads.push_back(SpatialDyad::SS(center, moving, (point - center).norm()));
    } else if (kind == Kind::kWithSP && i == 4) {
      // The fixed point `center` on a plane of E through where it is at the start pose.
      const Eigen::Vector3d center = RandomPoint(rng, 2.0);
      const Eigen::Vector3d normal = RandomPoint(rng, 1.0).normalized();
      const Eigen::Vector3d in_moving =
          platform.start_rotation.transpose() * (center - *start_translation);
      platform.dyads.push_back(SpatialDyad::SP(center, normal, normal.dot(in_moving)));
    } else {
      const Eigen::Vector3d center = RandomPoint(rng, 2.0);
      platform.dyads.push_back(SpatialDyad::SS(center, moving, (point - center).norm()));
    }
  }
  return platform;
}

// The first seed from `first_seed` whose platform gives a 7-pose task.
struct Instance {
  unsigned seed = 0;
  Platform platform;
  std::vector<DualQuaternion> poses;
  std::vector<Vector6d> coordinates;
  int fixed = 0;
};

Instance MakeInstance(unsigned first_seed, Kind kind) {
  Instance instance;
  for (unsigned seed = first_seed; seed < first_seed + 50; ++seed) {
    std::mt19937 rng(seed);
    Eigen::Vector3d start_translation;
    instance.platform = RandomPlatform(&rng, kind, &start_translation);
    instance.seed = seed;
    if (GenerateMotion(instance.platform, start_translation, &instance.poses, &instance.fixed,
                       &instance.coordinates)) {
      return instance;
    }
  }
  ADD_FAILURE() << "no seed from " << first_seed << " gave a task";
  return instance;
}

// X -> scale * (Q X + b) applied to the fixed frame, and the body frame scaled by `scale`.
void Transform(double scale, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& shift,
               std::vector<SpatialDyad>* dyads, std::vector<DualQuaternion>* poses) {
  for (SpatialDyad& dyad : *dyads) {
    dyad.moving_pivot *= scale;
    if (dyad.type == SpatialDyadType::kSP) {
      dyad.fixed_pivot = scale * (rotation * dyad.fixed_pivot + shift);
      dyad.plane_offset *= scale;  // the plane is in E
    } else if (dyad.type == SpatialDyadType::kSS) {
      dyad.fixed_pivot = scale * (rotation * dyad.fixed_pivot + shift);
      dyad.radius *= scale;
    } else {
      dyad.plane_normal = rotation * dyad.plane_normal;
      dyad.plane_offset = scale * (dyad.plane_offset + dyad.plane_normal.dot(shift));
    }
  }
  for (DualQuaternion& pose : *poses) {
    pose = DualQuaternion::FromRotationTranslation(rotation * pose.Rotation(),
                                                   scale * (rotation * pose.Translation() + shift));
  }
}

std::vector<int> Iota(int count) {
  std::vector<int> order(count);
  for (int j = 0; j < count; ++j) order[j] = j;
  return order;
}

// Every reported path pose satisfies the dyads, and the path is continuous.
void ExpectPathOnMotion(const std::vector<SpatialDyad>& dyads, const PlatformMotionReport& report,
                        double length) {
  ASSERT_FALSE(report.path.empty());
  EXPECT_LE(report.path.size(), 721u);
  double worst = 0.0, largest_gap = 0.0;
  for (size_t k = 0; k < report.path.size(); ++k) {
    for (const SpatialDyad& dyad : dyads) {
      worst = std::max(worst, std::abs(dyad.Residual(report.path[k])));
    }
    if (k > 0) {
      largest_gap = std::max(largest_gap, PoseError(report.path[k - 1], report.path[k], length));
    }
  }
  EXPECT_LE(worst, kOnCurve * length);
  EXPECT_LE(largest_gap, 0.5 * length);
}

// Traces an exact task given in order along the motion and checks the report.
PlatformMotionReport ExpectExactTask(const std::vector<SpatialDyad>& dyads,
                                     const std::vector<DualQuaternion>& poses, double length,
                                     double tolerance) {
  PlatformMotionReport report = TracePlatform(dyads, poses, length);
  SCOPED_TRACE("length " + std::to_string(length) + ", note: " + report.note);
  EXPECT_TRUE(report.assembles);
  EXPECT_TRUE(report.one_branch);
  EXPECT_LT(report.max_pose_error, tolerance * length);
  EXPECT_EQ(report.order, Iota(static_cast<int>(poses.size())));
  EXPECT_EQ(report.pose_errors.size(), poses.size());
  ExpectPathOnMotion(dyads, report, length);
  return report;
}

TEST(PlatformMotion, FollowsTheMotionOfARandom5SS) {
  for (unsigned first_seed : {1u, 101u, 201u}) {
    const Instance instance = MakeInstance(first_seed, Kind::kAllSS);
    SCOPED_TRACE("seed " + std::to_string(instance.seed));
    ASSERT_EQ(instance.poses.size(), static_cast<size_t>(kTaskPoses));
    const std::vector<SpatialDyad>& dyads = instance.platform.dyads;

    const PlatformMotionReport report = ExpectExactTask(dyads, instance.poses, 1.0, kExact);
    // A loop starts and ends at the first pose.
    if (report.closed) {
      EXPECT_LT(PoseError(report.path.front(), report.path.back(), 1.0), kExact);
      EXPECT_TRUE(report.note.empty()) << report.note;
    } else {
      EXPECT_FALSE(report.note.empty());
    }

    // Units and the placement of the fixed frame do not matter.
    for (double scale : {1e-3, 1e3}) {
      std::vector<SpatialDyad> scaled_dyads = dyads;
      std::vector<DualQuaternion> scaled_poses = instance.poses;
      Transform(scale, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), &scaled_dyads,
                &scaled_poses);
      const PlatformMotionReport scaled =
          ExpectExactTask(scaled_dyads, scaled_poses, scale, kExact);
      EXPECT_EQ(scaled.closed, report.closed);
      EXPECT_NEAR(scaled.steps, report.steps, 2 + report.steps / 100);  // same curve, same steps
    }
    std::mt19937 rng(instance.seed + 1000);
    const Eigen::Matrix3d rotation = RandomRotation(&rng);
    const Eigen::Vector3d shift = RandomPoint(&rng, 10.0);
    std::vector<SpatialDyad> moved_dyads = dyads;
    std::vector<DualQuaternion> moved_poses = instance.poses;
    Transform(1.0, rotation, shift, &moved_dyads, &moved_poses);
    EXPECT_EQ(ExpectExactTask(moved_dyads, moved_poses, 1.0, kExact).closed, report.closed);

    // Reversed task: the order is reported from pose 0 toward pose 1 again.
    std::vector<DualQuaternion> reversed(instance.poses.rbegin(), instance.poses.rend());
    const PlatformMotionReport backward = TracePlatform(dyads, reversed, 1.0);
    EXPECT_TRUE(backward.one_branch) << backward.note;
    EXPECT_EQ(backward.order, Iota(kTaskPoses));
  }
}

TEST(PlatformMotion, PrismaticAndHugeSphereDyads) {
  for (const auto& [first_seed, kind] :
       {std::make_pair(11u, Kind::kMixed), std::make_pair(111u, Kind::kMixed),
        std::make_pair(211u, Kind::kWithSP)}) {
    const Instance instance = MakeInstance(first_seed, kind);
    SCOPED_TRACE("seed " + std::to_string(instance.seed));
    ASSERT_EQ(instance.poses.size(), static_cast<size_t>(kTaskPoses));
    ASSERT_EQ(instance.platform.dyads[1].type, SpatialDyadType::kPS);
    ASSERT_GT(instance.platform.dyads[3].radius, 0.5 * kHugeRadius);
    ExpectExactTask(instance.platform.dyads, instance.poses, 1.0, kHugeRadiusExact);
    for (double scale : {1e-3, 1e3}) {
      std::vector<SpatialDyad> dyads = instance.platform.dyads;
      std::vector<DualQuaternion> poses = instance.poses;
      Transform(scale, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), &dyads, &poses);
      ExpectExactTask(dyads, poses, scale, kHugeRadiusExact);
    }
    std::mt19937 rng(instance.seed + 1000);
    std::vector<SpatialDyad> dyads = instance.platform.dyads;
    std::vector<DualQuaternion> poses = instance.poses;
    Transform(1.0, RandomRotation(&rng), RandomPoint(&rng, 10.0), &dyads, &poses);
    ExpectExactTask(dyads, poses, 1.0, kHugeRadiusExact);
  }
}

// An open curve (the step limit stands in for singular ends): the poses are still met, and with
// the first pose in the middle of the task the order runs toward pose 1 first, then (the motion
// reversing) to the poses on the other side.
TEST(PlatformMotion, OpenCurveOrder) {
  const Instance instance = MakeInstance(51, Kind::kAllSS);
  SCOPED_TRACE("seed " + std::to_string(instance.seed));
  ASSERT_EQ(instance.poses.size(), static_cast<size_t>(kTaskPoses));
  const std::vector<DualQuaternion>& p = instance.poses;
  const std::vector<DualQuaternion> middle_first = {p[3], p[4], p[5], p[6], p[2], p[1], p[0]};
  const PlatformMotionReport full = TracePlatform(instance.platform.dyads, middle_first, 1.0);
  ASSERT_TRUE(full.closed) << full.note;
  // Enough steps to reach both ends of the task, too few to close the loop.
  double reach = 0.0;
  for (int j = 0; j + 1 < kTaskPoses; ++j) reach += PoseError(p[j], p[j + 1], 1.0);
  PlatformMotionOptions options;
  options.max_steps = static_cast<int>(std::ceil(2.0 * reach / options.step));
  ASSERT_LT(2 * options.max_steps, full.steps) << "the loop is too short for this test";
  const PlatformMotionReport report =
      TracePlatform(instance.platform.dyads, middle_first, 1.0, options);
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(report.one_branch) << report.note;
  EXPECT_NE(report.note.find("step limit"), std::string::npos) << report.note;
  EXPECT_LT(report.max_pose_error, kExact);
  EXPECT_EQ(report.order, Iota(kTaskPoses));
  // The path runs from the far end behind the first pose to the far end ahead of it.
  ExpectPathOnMotion(instance.platform.dyads, report, 1.0);
  EXPECT_GT(PoseError(report.path.front(), middle_first[0], 1.0), 0.1);
  EXPECT_GT(PoseError(report.path.back(), middle_first[0], 1.0), 0.1);
  // On the full loop the same task goes 0, 1, 2, 3 and then around to 6, 5, 4.
  EXPECT_EQ(full.order, (std::vector<int>{0, 1, 2, 3, 6, 5, 4}));
}

// Minimum-norm Newton of all six coordinates onto the dyads (central-difference Jacobian).
bool ProjectOntoDyads(const Platform& platform, Vector6d* y) {
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Vector5d residuals = Residuals(platform, *y);
    if (residuals.cwiseAbs().maxCoeff() < 1e-13) return true;
    const Matrix56d jacobian = NumericJacobian(platform, *y);
    *y -= jacobian.completeOrthogonalDecomposition().solve(residuals);
    if (!y->allFinite()) return false;
  }
  return false;
}

// A platform with a bifurcation point: at the start pose the lines of dyads 0 and 1 (center to
// moving point) coincide, so the Jacobian loses rank there; two arcs of the motion cross there.
// From a pose on one arc the trace stops at that configuration at both ends, meets a task pose
// placed at it, and does not reach a pose on the other arc.
TEST(PlatformMotion, BifurcationEndsTheBranch) {
  constexpr double kAway = 0.05;  // distance of the arc poses from the bifurcation, L
  constexpr double kOtherArc =
      0.03;  // a pose this far from every traced sample is on the other arc
  constexpr double kAtSingular = 1e-5;  // how near the trace ends to the bifurcation, L
  bool tested = false;
  for (unsigned seed = 1; seed < 20 && !tested; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    Eigen::Vector3d start_translation;
    Platform platform = RandomPlatform(&rng, Kind::kAllSS, &start_translation);
    const Eigen::Matrix3d& rotation = platform.start_rotation;
    const Eigen::Vector3d point = rotation * platform.dyads[0].moving_pivot + start_translation;
    const Eigen::Vector3d line = RandomPoint(&rng, 1.0).normalized();
    platform.dyads[0] = SpatialDyad::SS(point + 1.5 * line, platform.dyads[0].moving_pivot, 1.5);
    platform.dyads[1] = SpatialDyad::SS(
        point - 1.2 * line, rotation.transpose() * (point + 0.7 * line - start_translation), 1.9);
    Vector6d singular = Vector6d::Zero();
    singular.tail<3>() = start_translation;
    const DualQuaternion singular_pose = PoseOf(platform, singular);

    // Poses near the bifurcation along its two-dimensional kernel, projected onto the motion.
    Eigen::Matrix<double, 6, 6> square = Eigen::Matrix<double, 6, 6>::Zero();
    square.topRows<5>() = NumericJacobian(platform, singular);
    const Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> svd(square, Eigen::ComputeFullV);
    std::vector<DualQuaternion> near;
    for (int k = 0; k < 8; ++k) {
      const double angle = k * M_PI / 8.0;
      Vector6d y = singular + kAway * (std::cos(angle) * svd.matrixV().col(4) +
                                       std::sin(angle) * svd.matrixV().col(5));
      if (!ProjectOntoDyads(platform, &y)) continue;
      const DualQuaternion pose = PoseOf(platform, y);
      if (PoseError(pose, singular_pose, 1.0) > 0.2 * kAway) near.push_back(pose);
    }
    if (near.size() < 2) continue;
    const PlatformMotionReport arc = TracePlatform(platform.dyads, {near[0], singular_pose}, 1.0);
    if (arc.closed) continue;  // this circuit misses the singular point
    ASSERT_TRUE(arc.assembles) << arc.note;
    EXPECT_NE(arc.note.find("singular"), std::string::npos) << arc.note;
    EXPECT_TRUE(arc.one_branch) << arc.note;
    EXPECT_LT(arc.pose_errors[1], kAtSingular);
    EXPECT_LT(std::min(PoseError(arc.path.front(), singular_pose, 1.0),
                       PoseError(arc.path.back(), singular_pose, 1.0)),
              kAtSingular);
    ExpectPathOnMotion(platform.dyads, arc, 1.0);
    for (const DualQuaternion& other : near) {
      double nearest = 1e300;
      for (const DualQuaternion& sample : arc.path) {
        nearest = std::min(nearest, PoseError(sample, other, 1.0));
      }
      if (nearest < kOtherArc) continue;
      tested = true;
      const PlatformMotionReport report = TracePlatform(platform.dyads, {near[0], other}, 1.0);
      EXPECT_TRUE(report.assembles) << report.note;
      EXPECT_FALSE(report.one_branch);
      EXPECT_GT(report.pose_errors[1], 0.5 * kOtherArc);
      EXPECT_NE(report.note.find("singular"), std::string::npos) << report.note;
      break;
    }
  }
  EXPECT_TRUE(tested) << "no seed gave poses on both arcs through the bifurcation";
}

TEST(PlatformMotion, PoseOffTheMotionIsNotMet) {
  constexpr double kOffset = 0.1;  // relative to L
  const Instance instance = MakeInstance(21, Kind::kAllSS);
  SCOPED_TRACE("seed " + std::to_string(instance.seed));
  ASSERT_EQ(instance.poses.size(), static_cast<size_t>(kTaskPoses));
  // Move pose 3 by kOffset across the motion: normal to the chord of poses 2 and 4 in translation.
  const Eigen::Vector3d chord =
      (instance.poses[4].Translation() - instance.poses[2].Translation()).normalized();
  const Eigen::Vector3d across = (Eigen::Vector3d::UnitZ() - chord.z() * chord).norm() > 0.5
                                     ? (Eigen::Vector3d::UnitZ() - chord.z() * chord).normalized()
                                     : (Eigen::Vector3d::UnitX() - chord.x() * chord).normalized();
  std::vector<DualQuaternion> poses = instance.poses;
  poses[3] = DualQuaternion::FromRotationTranslation(poses[3].Rotation(),
                                                     poses[3].Translation() + kOffset * across);
  const PlatformMotionReport report = TracePlatform(instance.platform.dyads, poses, 1.0);
  EXPECT_TRUE(report.assembles);
  EXPECT_FALSE(report.one_branch);
  EXPECT_FALSE(report.note.empty());
  EXPECT_NE(report.note.find("task pose 3"), std::string::npos) << report.note;
  ASSERT_EQ(report.pose_errors.size(), poses.size());
  EXPECT_GT(report.pose_errors[3], 0.5 * kOffset);
  EXPECT_LT(report.pose_errors[3], 1.01 * kOffset);
  EXPECT_NEAR(report.max_pose_error, report.pose_errors[3], 1e-15);
  for (int j : {0, 1, 2, 4, 5, 6}) EXPECT_LT(report.pose_errors[j], kExact) << "pose " << j;
  EXPECT_EQ(report.order, (std::vector<int>{0, 1, 2, 4, 5, 6}));
}

TEST(PlatformMotion, FirstPoseOffTheDyadsDoesNotAssemble) {
  const Instance instance = MakeInstance(31, Kind::kAllSS);
  SCOPED_TRACE("seed " + std::to_string(instance.seed));
  ASSERT_EQ(instance.poses.size(), static_cast<size_t>(kTaskPoses));
  std::vector<DualQuaternion> poses = instance.poses;
  const DualQuaternion first = poses[0];
  poses[0] = DualQuaternion::FromRotationTranslation(
      first.Rotation(), first.Translation() + Eigen::Vector3d(0.01, 0.0, 0.0));
  const PlatformMotionReport report = TracePlatform(instance.platform.dyads, poses, 1.0);
  EXPECT_FALSE(report.assembles);
  EXPECT_FALSE(report.one_branch);
  EXPECT_NE(report.note.find("first task pose"), std::string::npos) << report.note;
  EXPECT_TRUE(report.path.empty());
  EXPECT_TRUE(report.order.empty());

  // Within the assembly tolerance it is projected and the task passes.
  poses[0] = DualQuaternion::FromRotationTranslation(
      first.Rotation(), first.Translation() + Eigen::Vector3d(1e-8, 0.0, 0.0));
  const PlatformMotionReport near = TracePlatform(instance.platform.dyads, poses, 1.0);
  EXPECT_TRUE(near.assembles) << near.note;
  EXPECT_TRUE(near.one_branch) << near.note;
  EXPECT_LT(near.pose_errors[0], 2e-8);

  // Bad input is reported, not crashed on.
  std::vector<SpatialDyad> four(instance.platform.dyads.begin(),
                                instance.platform.dyads.begin() + 4);
  EXPECT_FALSE(TracePlatform(four, instance.poses, 1.0).note.empty());
  EXPECT_FALSE(TracePlatform(instance.platform.dyads, {}, 1.0).note.empty());
  EXPECT_FALSE(TracePlatform(instance.platform.dyads, instance.poses, 0.0).assembles);
  std::vector<DualQuaternion> nan_poses = instance.poses;
  nan_poses[2].g[1] = std::nan("");
  EXPECT_FALSE(TracePlatform(instance.platform.dyads, nan_poses, 1.0).assembles);
}

// The other assembly branch: configurations of the same platform with the same value of the
// generator's fixed coordinate, found by Newton from random far starts, that lie far from the
// whole traced loop through the first pose. The loop is a complete circuit (it closed, with no
// singular configuration on it, and its samples are checked on the motion here), so such a
// configuration is on another circuit. Platforms whose traced curve does not close, or whose
// other solutions all lie on the same circuit, are skipped over to the next seed.
TEST(PlatformMotion, PoseOnAnotherCircuitIsNotOnTheBranch) {
  constexpr double kFar = 0.3;  // distance from every traced sample, relative to L
  bool found = false;
  for (unsigned first_seed = 41; first_seed < 200 && !found; first_seed += 10) {
    const Instance instance = MakeInstance(first_seed, Kind::kAllSS);
    const std::vector<SpatialDyad>& dyads = instance.platform.dyads;
    const PlatformMotionReport loop = TracePlatform(dyads, instance.poses, 1.0);
    if (!loop.closed || !loop.one_branch) continue;
    std::mt19937 rng(instance.seed + 2000);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    for (int attempt = 0; attempt < 200 && !found; ++attempt) {
      Vector6d y;
      y.head<3>() = RandomPoint(&rng, 1.0).normalized() * angle(rng);
      y.tail<3>() = RandomPoint(&rng, 2.0);
      y(instance.fixed) = instance.coordinates[3](instance.fixed);
      if (!SolveWithFixed(instance.platform, instance.fixed, &y)) continue;
      const DualQuaternion other = PoseOf(instance.platform, y);
      double nearest = 1e300;
      for (const DualQuaternion& sample : loop.path) {
        nearest = std::min(nearest, PoseError(sample, other, 1.0));
      }
      if (nearest < kFar) continue;
      found = true;
      SCOPED_TRACE("seed " + std::to_string(instance.seed) + ", attempt " +
                   std::to_string(attempt));
      ExpectPathOnMotion(dyads, loop, 1.0);
      std::vector<DualQuaternion> task = instance.poses;
      task[3] = other;
      const PlatformMotionReport report = TracePlatform(dyads, task, 1.0);
      EXPECT_TRUE(report.assembles);
      EXPECT_FALSE(report.one_branch);
      EXPECT_GT(report.pose_errors[3], 0.5 * kFar);
      EXPECT_NE(report.note.find("task pose 3"), std::string::npos) << report.note;
      // Started on the other circuit, the first task's poses are the ones missed.
      const PlatformMotionReport there = TracePlatform(dyads, {other, instance.poses[0]}, 1.0);
      EXPECT_TRUE(there.assembles) << there.note;
      EXPECT_FALSE(there.one_branch);
      EXPECT_GT(there.pose_errors[1], 0.5 * kFar);
    }
  }
  EXPECT_TRUE(found) << "no platform with a second circuit among the seeds tried";
}

// The default continuation step (0.1 L, halved where the corrector or the tangent says the curve
// turns) traces the same motion as steps of 0.005 L on random platforms of SS, PS and SP dyads:
// the same branch, loop, order of the task poses, and pose errors; it does not jump to another
// branch of the curve.
TEST(PlatformMotion, DefaultStepsTraceTheFineStepsMotion) {
  std::mt19937_64 rng(1660);
  const std::vector<std::vector<SpatialDyadType>> kinds = {
      std::vector<SpatialDyadType>(5, SpatialDyadType::kSS),
      {SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kSS, SpatialDyadType::kPS,
       SpatialDyadType::kSP}};
  PlatformMotionOptions fine;
  fine.step = 0.005;
  int traced = 0, loops = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const testing::PlantedSpatialTask task =
        testing::RandomPlatformTask(rng, 8, kinds[trial % kinds.size()]);
    SCOPED_TRACE("trial " + std::to_string(trial));
    const PlatformMotionReport coarse = TracePlatform(task.planted, task.poses, 1.0);
    const PlatformMotionReport reference = TracePlatform(task.planted, task.poses, 1.0, fine);
    ASSERT_EQ(coarse.assembles, reference.assembles);
    EXPECT_EQ(coarse.one_branch, reference.one_branch) << coarse.note << " / " << reference.note;
    EXPECT_EQ(coarse.closed, reference.closed);
    EXPECT_EQ(coarse.order, reference.order);
    EXPECT_NEAR(coarse.max_pose_error, reference.max_pose_error, 1e-6);
    EXPECT_LT(coarse.steps, reference.steps);
    loops += coarse.closed;
    ++traced;
  }
  EXPECT_EQ(traced, 60);
  EXPECT_GT(loops, 10);
}

}  // namespace
}  // namespace linkfit
