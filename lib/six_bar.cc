#include "lib/six_bar.h"

#include <Eigen/LU>
#include <cmath>

namespace linkfit {
namespace {

// The body body `body` hangs from and the joint by which it does (its reference place).
void Parent(const SixBar& six_bar, int body, int* parent, Eigen::Vector2d* joint) {
  switch (body) {
    case kSixBarUpperLink:
      *parent = kSixBarGround;
      *joint = six_bar.ground_pivot;
      return;
    case kSixBarForearm:
      *parent = kSixBarUpperLink;
      *joint = six_bar.elbow;
      return;
    case kSixBarTaskBody:
      *parent = kSixBarForearm;
      *joint = six_bar.wrist;
      return;
    default:
      *parent = six_bar.links[body - kSixBarFirstLink].from_body;
      *joint = six_bar.links[body - kSixBarFirstLink].from_joint;
  }
}

// Where the point of body `body` whose reference place is `point` is at `angles`, and its
// derivative with respect to the five turns (2 x 5):
//   T_k(p) = T_parent(x_k) + R(alpha_k) (p - x_k),  d/d alpha_k = perp(R(alpha_k) (p - x_k)).
Eigen::Vector2d Place(const SixBar& six_bar, const SixBarAngles& angles, int body,
                      const Eigen::Vector2d& point, Eigen::Matrix<double, 2, 5>* gradient) {
  if (gradient != nullptr) gradient->setZero();
  if (body == kSixBarGround) return point;
  int parent = 0;
  Eigen::Vector2d joint;
  Parent(six_bar, body, &parent, &joint);
  const Eigen::Vector2d arm = Rotation2(angles[body - 1]) * (point - joint);
  const Eigen::Vector2d at = Place(six_bar, angles, parent, joint, gradient);
  if (gradient != nullptr) gradient->col(body - 1) += Eigen::Vector2d(-arm.y(), arm.x());
  return at + arm;
}

// The closures and their Jacobian (4 x 5).
Eigen::Vector4d Closure(const SixBar& six_bar, const SixBarAngles& angles,
                        Eigen::Matrix<double, 4, 5>* jacobian) {
  Eigen::Vector4d residual;
  for (int l = 0; l < 2; ++l) {
    const SixBarRRLink& link = six_bar.links[l];
    Eigen::Matrix<double, 2, 5> on_link, on_body;
    const Eigen::Vector2d a =
        Place(six_bar, angles, kSixBarFirstLink + l, link.to_joint, jacobian ? &on_link : nullptr);
    const Eigen::Vector2d b =
        Place(six_bar, angles, link.to_body, link.to_joint, jacobian ? &on_body : nullptr);
    residual.segment<2>(2 * l) = a - b;
    if (jacobian != nullptr) jacobian->block<2, 5>(2 * l, 0) = on_link - on_body;
  }
  return residual;
}

}  // namespace

const char* SixBarTopologyName(SixBarTopology topology) {
  switch (topology) {
    case SixBarTopology::kWattI:
      return "Watt I";
    case SixBarTopology::kStephensonI:
      return "Stephenson I";
    case SixBarTopology::kStephensonII:
      return "Stephenson II";
    case SixBarTopology::kStephensonIII:
      return "Stephenson III";
  }
  return "six-bar";
}

PlanarPose SixBarBodyDisplacement(const SixBar& six_bar, const SixBarAngles& angles, int body) {
  PlanarPose pose;
  if (body == kSixBarGround) return pose;
  pose.theta = angles[body - 1];
  // The origin: where the reference place (0, 0) of the body's frame goes.
  pose.origin_in_fixed = Place(six_bar, angles, body, Eigen::Vector2d::Zero(), nullptr);
  return pose;
}

PlanarPose SixBarTaskPose(const SixBar& six_bar, const SixBarAngles& angles) {
  return SixBarBodyDisplacement(six_bar, angles, kSixBarTaskBody) * six_bar.reference_pose;
}

Eigen::Vector4d SixBarClosure(const SixBar& six_bar, const SixBarAngles& angles) {
  return Closure(six_bar, angles, nullptr);
}

bool SixBarGroundedLink(const SixBar& six_bar, int body) {
  if (body == kSixBarUpperLink) return true;
  if (body == kSixBarFirstLink || body == kSixBarSecondLink) {
    return six_bar.links[body - kSixBarFirstLink].from_body == kSixBarGround;
  }
  return false;
}

bool AssembleSixBar(const SixBar& six_bar, int input, double input_angle, SixBarAngles* angles,
                    double tolerance, int max_iterations) {
  SixBarAngles x = *angles;
  x[input - 1] = input_angle;
  int free[4], count = 0;
  for (int k = 0; k < 5; ++k) {
    if (k != input - 1) free[count++] = k;
  }
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    Eigen::Matrix<double, 4, 5> jacobian;
    const Eigen::Vector4d residual = Closure(six_bar, x, &jacobian);
    Eigen::Matrix4d square;
    for (int c = 0; c < 4; ++c) square.col(c) = jacobian.col(free[c]);
    Eigen::FullPivLU<Eigen::Matrix4d> lu(square);
    // A dead point: the closure does not fix the other turns to first order.
    lu.setThreshold(1e-10);
    if (lu.rank() < 4) return false;
    if (residual.norm() <= tolerance) {
      *angles = x;
      return true;
    }
    const Eigen::Vector4d step = lu.solve(-residual);
    for (int c = 0; c < 4; ++c) x[free[c]] += step[c];
    if (!x.allFinite()) return false;
  }
  return false;
}

}  // namespace linkfit
