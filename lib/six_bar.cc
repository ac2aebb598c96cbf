#include "lib/six_bar.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

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

// The closure's Jacobian in the four turns other than the input's (`free`, their indices),
// factored; false at a dead point of the input (the closure does not fix them to first order).
bool FreeTurns(const Eigen::Matrix<double, 4, 5>& jacobian, int input, int free[4],
               Eigen::FullPivLU<Eigen::Matrix4d>* lu) {
  Eigen::Matrix4d square;
  for (int k = 0, c = 0; k < 5; ++k) {
    if (k != input - 1) free[c++] = k;
  }
  for (int c = 0; c < 4; ++c) square.col(c) = jacobian.col(free[c]);
  lu->compute(square);
  lu->setThreshold(1e-10);
  return lu->rank() == 4;
}

// The turns' rates for a unit rate of the input (J_free rates = -J_input), or false at a dead
// point of the input.
bool Rates(const SixBar& six_bar, const SixBarAngles& angles, int input, SixBarAngles* velocity) {
  Eigen::Matrix<double, 4, 5> jacobian;
  Closure(six_bar, angles, &jacobian);
  int free[4];
  Eigen::FullPivLU<Eigen::Matrix4d> lu;
  if (!FreeTurns(jacobian, input, free, &lu)) return false;
  const Eigen::Vector4d rates = lu.solve(-Eigen::Vector4d(jacobian.col(input - 1)));
  velocity->setZero();
  (*velocity)[input - 1] = 1.0;
  for (int c = 0; c < 4; ++c) (*velocity)[free[c]] = rates[c];
  return true;
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

bool ChainElbows(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                 std::vector<Eigen::Vector2d>* elbows, int* unreachable_pose) {
  elbows->clear();
  *unreachable_pose = -1;
  const double a = chain.upper_length, b = chain.forearm_length;
  double side = chain.elbow_left ? 1.0 : -1.0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector2d wrist = poses[k].ToFixed(chain.wrist_in_moving);
    const Eigen::Vector2d to_wrist = wrist - chain.ground_pivot;
    const double d = to_wrist.norm();
    // The elbow: on the circle of radius a about G and of radius b about the wrist.
    const double along = d > 0.0 ? (a * a - b * b + d * d) / (2.0 * d) : 0.0;
    const double reach = a * a - along * along;
    const double slack = 1e-12 * (a + b) * (a + b);
    if (!(d > 0.0) || reach < -slack) {
      *unreachable_pose = static_cast<int>(k);
      return false;
    }
    const Eigen::Vector2d u = to_wrist / d;
    const double h = std::sqrt(std::max(reach, 0.0));
    const Eigen::Vector2d base = chain.ground_pivot + along * u;
    if (k == 0 && chain.elbow_at_first_pose) {
      const Eigen::Vector2d left = base + h * Perp(u), right = base - h * Perp(u);
      side =
          (left - *chain.elbow_at_first_pose).norm() <= (right - *chain.elbow_at_first_pose).norm()
              ? 1.0
              : -1.0;
    }
    elbows->push_back(base + side * h * Perp(u));
  }
  return true;
}

bool DriveSixBar(const SixBar& six_bar, int input, double to_angle, SixBarAngles* angles,
                 double length, double max_step) {
  const double tolerance = 1e-13 * length;
  double step = max_step;
  while (std::abs(to_angle - (*angles)[input - 1]) > 0.0) {
    const double remaining = to_angle - (*angles)[input - 1];
    const double delta = std::copysign(std::min(step, std::abs(remaining)), remaining);
    SixBarAngles velocity;
    if (!Rates(six_bar, *angles, input, &velocity)) return false;
    const SixBarAngles predicted = *angles + delta * velocity;
    SixBarAngles next = predicted;
    const double target =
        std::abs(delta) < std::abs(remaining) ? (*angles)[input - 1] + delta : to_angle;
    if (AssembleSixBar(six_bar, input, target, &next, tolerance) &&
        (next - predicted).cwiseAbs().maxCoeff() <= std::max(std::abs(delta), 1e-6)) {
      *angles = next;
      step = std::min(max_step, 2.0 * step);
      continue;
    }
    step /= 2.0;
    if (step < 1e-9) return false;
  }
  return true;
}

std::array<double, 2> SixBarTransmissionDeg(const SixBar& six_bar, const SixBarAngles& angles) {
  std::array<double, 2> degrees = {90.0, 90.0};
  for (int l = 0; l < 2; ++l) {
    const SixBarRRLink& link = six_bar.links[l];
    // The loop's coupler-rocker angle at the joint J the link closes on: between the link and
    // the body's lever from J to the joint K by which that body hangs from its parent.
    int parent = 0;
    Eigen::Vector2d hinge;
    Parent(six_bar, link.to_body, &parent, &hinge);
    const Eigen::Vector2d j = Place(six_bar, angles, link.to_body, link.to_joint, nullptr);
    const Eigen::Vector2d k = Place(six_bar, angles, link.to_body, hinge, nullptr);
    const Eigen::Vector2d from = Place(six_bar, angles, link.from_body, link.from_joint, nullptr);
    const Eigen::Vector2d a = from - j, b = k - j;
    if (!(a.norm() > 0.0) || !(b.norm() > 0.0)) continue;
    const double sine = std::abs(a.x() * b.y() - a.y() * b.x()) / (a.norm() * b.norm());
    degrees[l] = std::asin(std::min(1.0, sine)) * 180.0 / M_PI;
  }
  return degrees;
}

SixBarAnalysis AnalyzeSixBar(const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses,
                             int input, double length, double step) {
  SixBarAnalysis analysis;
  if (at_poses.empty()) return analysis;
  const int index = input - 1;
  for (const SixBarAngles& angles : at_poses) {
    analysis.input_angles.push_back(angles[index] - at_poses[0][index]);
  }
  const auto add = [&](const char* defect) {
    if (std::find(analysis.defects.begin(), analysis.defects.end(), defect) ==
        analysis.defects.end()) {
      analysis.defects.push_back(defect);
    }
  };
  for (size_t k = 2; k < at_poses.size(); ++k) {
    const double before = analysis.input_angles[k - 1] - analysis.input_angles[k - 2];
    const double after = analysis.input_angles[k] - analysis.input_angles[k - 1];
    if (before * after <= 0.0) add("order");
  }
  const auto transmission = [&](const SixBarAngles& angles) {
    const std::array<double, 2> degrees = SixBarTransmissionDeg(six_bar, angles);
    for (int l = 0; l < 2; ++l) {
      analysis.transmission_min_deg[l] = std::min(analysis.transmission_min_deg[l], degrees[l]);
    }
  };
  // From each pose to the next along the input (its turns as the poses give them).
  SixBarAngles angles = at_poses[0];
  transmission(angles);
  for (size_t k = 1; k < at_poses.size(); ++k) {
    const double from = at_poses[k - 1][index], to = at_poses[k][index];
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(to - from) / step)));
    bool driven = true;
    for (int s = 1; s <= steps && driven; ++s) {
      driven = DriveSixBar(six_bar, input, from + (to - from) * s / steps, &angles, length, step);
      if (driven) transmission(angles);
    }
    if (!driven) {
      add("branch");
      break;
    }
    // Arrived in the pose's own assembly: the same turns (up to whole turns).
    double apart = 0.0;
    for (int j = 0; j < 5; ++j) {
      apart = std::max(apart, std::abs(std::remainder(angles[j] - at_poses[k][j], 2.0 * M_PI)));
    }
    if (apart > 1e-6) {
      add("circuit");
      angles = at_poses[k];  // on from the pose itself
    }
  }
  // A whole turn of the input from the first pose.
  angles = at_poses[0];
  analysis.input_rotates_fully =
      DriveSixBar(six_bar, input, at_poses[0][index] + 2.0 * M_PI, &angles, length, step);
  return analysis;
}

bool AssembleSixBar(const SixBar& six_bar, int input, double input_angle, SixBarAngles* angles,
                    double tolerance, int max_iterations) {
  SixBarAngles x = *angles;
  x[input - 1] = input_angle;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    Eigen::Matrix<double, 4, 5> jacobian;
    const Eigen::Vector4d residual = Closure(six_bar, x, &jacobian);
    int free[4];
    Eigen::FullPivLU<Eigen::Matrix4d> lu;
    if (!FreeTurns(jacobian, input, free, &lu)) return false;  // a dead point
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
