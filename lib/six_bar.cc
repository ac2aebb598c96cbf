#include "lib/six_bar.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "lib/golden_section.h"

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// The bodies placed at `angles` (lib/six_bar_frames.h), with the joints they read.
struct Placement {
  std::array<double, kSixBarJointCount> joints;
  SixBarFrames<double> frames;

  Placement(const SixBar& six_bar, const SixBarAngles& angles)
      : joints(SixBarJointNumbers(six_bar)),
        frames({six_bar.links[0].from_body, six_bar.links[1].from_body},
               {six_bar.links[0].to_body, six_bar.links[1].to_body}, joints.data(), angles.data()) {
  }
  Placement(const Placement&) = delete;  // frames reads joints
  Placement& operator=(const Placement&) = delete;
};

// Where the point of body `body` whose reference place is `point` is at `angles`.
Eigen::Vector2d Place(const SixBar& six_bar, const SixBarAngles& angles, int body,
                      const Eigen::Vector2d& point) {
  return Placement(six_bar, angles).frames.At(body, point);
}

// The closures and their Jacobian (4 x 5).
Eigen::Vector4d Closure(const SixBar& six_bar, const SixBarAngles& angles,
                        Eigen::Matrix<double, 4, 5>* jacobian) {
  const Placement placement(six_bar, angles);
  if (jacobian != nullptr) *jacobian = placement.frames.ClosureJacobian();
  return placement.frames.Closure();
}

// The closure's Jacobian in the four turns other than the input's (`free`, their indices),
// factored; false at a dead point of the input (the closure does not fix them to first order:
// a pivot below 1e-10 of the largest).
bool FreeTurns(const Eigen::Matrix<double, 4, 5>& jacobian, int input, int free[4],
               Eigen::PartialPivLU<Eigen::Matrix4d>* lu) {
  Eigen::Matrix4d square;
  for (int k = 0, c = 0; k < 5; ++k) {
    if (k != input - 1) free[c++] = k;
  }
  for (int c = 0; c < 4; ++c) square.col(c) = jacobian.col(free[c]);
  lu->compute(square);
  const Eigen::Vector4d pivots = lu->matrixLU().diagonal().cwiseAbs();
  return pivots.minCoeff() > 1e-10 * pivots.maxCoeff();
}

// Newton's method for the four free turns with the input's set (AssembleSixBar); with
// `velocity`, the turns' rates there for a unit rate of the input (J_free rates = -J_input), and
// with `determinant` the free turns' Jacobian's, from the Jacobian the last iteration factored.
bool Assemble(const SixBar& six_bar, int input, double input_angle, SixBarAngles* angles,
              double tolerance, int max_iterations, SixBarAngles* velocity,
              double* determinant = nullptr) {
  SixBarAngles x = *angles;
  x[input - 1] = input_angle;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    Eigen::Matrix<double, 4, 5> jacobian;
    const Eigen::Vector4d residual = Closure(six_bar, x, &jacobian);
    int free[4];
    Eigen::PartialPivLU<Eigen::Matrix4d> lu;
    if (!FreeTurns(jacobian, input, free, &lu)) return false;  // a dead point
    if (residual.norm() <= tolerance) {
      *angles = x;
      if (determinant != nullptr) *determinant = lu.determinant();
      if (velocity != nullptr) {
        const Eigen::Vector4d rates = lu.solve(-Eigen::Vector4d(jacobian.col(input - 1)));
        velocity->setZero();
        (*velocity)[input - 1] = 1.0;
        for (int c = 0; c < 4; ++c) (*velocity)[free[c]] = rates[c];
      }
      return true;
    }
    const Eigen::Vector4d step = lu.solve(-residual);
    for (int c = 0; c < 4; ++c) x[free[c]] += step[c];
    if (!x.allFinite()) return false;
  }
  return false;
}

// The closure a continuation step on the way is assembled to (times L); the last step, to the
// drive's target, to 1e-13 L (measured: the same defects and transmission angles).
constexpr double kStepTolerance = 1e-10;

// Newton steps a continuation step may take (more: the step is halved).
constexpr int kDriveIterations = 8;

// An input step below this (radians) that still fails is taken for a dead point (measured on the
// 1048 analyses: 1e-7 and 1e-6 stop at some crossings that 1e-9 passes).
constexpr double kDeadPointStep = 1e-8;

// Continuation steps one drive may take: more is a crawl toward a dead point, taken for one.
constexpr int kMaxDriveSteps = 20000;

// A continuation step's Newton correction may be at most this share of the predicted move of the
// fastest turn (measured on 1048 analyses of random six-bars: 0.1 judges as steps of 0.025
// degrees with the correction at most half the input step; 0.25 and 0.5, scaled so, let steps
// jump between assemblies where other turns run far faster than the input).
constexpr double kDriveCorrection = 0.1;

// A sample of a transmission angle more than this above the least so far is not refined (its
// neighbours four degrees of input apart: the least between them is not that far below).
constexpr double kRefineWindowDeg = 10.0;

// Golden-section shrinks of a least transmission angle's bracket (two continuation steps):
// to 2 * 4 * 0.618^10 = 0.065 degrees of the input (measured: the least angles within 0.03
// degrees of 18 shrinks after steps of 0.025 degrees).
constexpr int kTransmissionShrinks = 10;

// Dyads placed in closed form (SixBarDriver::Drive) whose least sine squared of the angle between
// a dyad's bodies is below this (15 degrees) at a step or the next are searched for a dead point
// between them, by this many golden-section shrinks (to 0.00013 of the step: a dip below 0
// narrower than that is passed).
constexpr double kDipMargin = 0.067;
constexpr int kDipShrinks = 20;

// DriveSixBar by continuation.
bool Continue(const SixBar& six_bar, int input, double to_angle, SixBarAngles* angles,
              double length, double max_step,
              const std::function<void(const SixBarAngles&)>& visit) {
  const double tolerance = 1e-13 * length;
  SixBarAngles velocity;
  double determinant = 0.0;
  if (!Assemble(six_bar, input, (*angles)[input - 1], angles, tolerance, kDriveIterations,
                &velocity, &determinant)) {
    return false;
  }
  double step = max_step;
  SixBarAngles acceleration = SixBarAngles::Zero();
  for (int steps = 0; std::abs(to_angle - (*angles)[input - 1]) > 0.0; ++steps) {
    if (steps == kMaxDriveSteps) return false;
    const double remaining = to_angle - (*angles)[input - 1];
    const double delta = std::copysign(std::min(step, std::abs(remaining)), remaining);
    const SixBarAngles predicted = *angles + delta * velocity;
    // Newton starts from the second-order prediction (the turns' acceleration from the last
    // step's change of velocity); the step is judged against the first-order one.
    SixBarAngles next = predicted + 0.5 * delta * delta * acceleration, next_velocity;
    double next_determinant = 0.0;
    const double target =
        std::abs(delta) < std::abs(remaining) ? (*angles)[input - 1] + delta : to_angle;
    // Corrected within a few Newton steps by a small share of the predicted move, the free turns'
    // Jacobian's determinant of the same sign: the same assembly, no dead point (a fold, or a
    // crossing of two assemblies) stepped over.
    const double allowed =
        kDriveCorrection * std::max(std::abs(delta) * velocity.cwiseAbs().maxCoeff(), 1e-6);
    // Steps on the way are assembled to kStepTolerance, the last to full precision.
    const bool last = target == to_angle;
    if (Assemble(six_bar, input, target, &next, last ? tolerance : kStepTolerance * length,
                 kDriveIterations, &next_velocity, &next_determinant) &&
        (next - predicted).cwiseAbs().maxCoeff() <= allowed &&
        next_determinant * determinant > 0.0) {
      acceleration = (next_velocity - velocity) / delta;
      *angles = next;
      velocity = next_velocity;
      determinant = next_determinant;
      if (visit) visit(*angles);
      // The next step grows while the correction stays well within its bound (it grows as the
      // step's square): doubled below a quarter of it, by a quarter below half of it.
      const double share = (next - predicted).cwiseAbs().maxCoeff() / allowed;
      step = std::min(max_step, share < 0.25 ? 2.0 * step : share < 0.5 ? 1.25 * step : step);
      continue;
    }
    step /= 2.0;
    if (step < kDeadPointStep) return false;
  }
  return true;
}

}  // namespace

std::array<double, kSixBarJointCount> SixBarJointNumbers(const SixBar& six_bar) {
  std::array<double, kSixBarJointCount> joints;
  const Eigen::Vector2d points[7] = {six_bar.ground_pivot,
                                     six_bar.elbow,
                                     six_bar.wrist,
                                     six_bar.links[0].from_joint,
                                     six_bar.links[0].to_joint,
                                     six_bar.links[1].from_joint,
                                     six_bar.links[1].to_joint};
  for (int k = 0; k < 7; ++k) {
    joints[2 * k] = points[k].x();
    joints[2 * k + 1] = points[k].y();
  }
  return joints;
}

std::array<std::vector<int>, 6> SixBarBodyJointIndices(const SixBar& six_bar) {
  std::array<std::vector<int>, 6> bodies;
  bodies[kSixBarGround] = {0};
  bodies[kSixBarUpperLink] = {0, 1};
  bodies[kSixBarForearm] = {1, 2};
  bodies[kSixBarTaskBody] = {2};
  for (int l = 0; l < 2; ++l) {
    const int from = 3 + 2 * l, to = 4 + 2 * l;
    bodies[kSixBarFirstLink + l].push_back(from);
    bodies[kSixBarFirstLink + l].push_back(to);
    bodies[six_bar.links[l].from_body].push_back(from);
    bodies[six_bar.links[l].to_body].push_back(to);
  }
  return bodies;
}

std::array<std::vector<Eigen::Vector2d>, 6> SixBarBodyJoints(const SixBar& six_bar) {
  const std::array<double, kSixBarJointCount> numbers = SixBarJointNumbers(six_bar);
  std::array<std::vector<Eigen::Vector2d>, 6> joints;
  const std::array<std::vector<int>, 6> indices = SixBarBodyJointIndices(six_bar);
  for (int body = 0; body < 6; ++body) {
    for (const int j : indices[body]) joints[body].emplace_back(numbers[2 * j], numbers[2 * j + 1]);
  }
  return joints;
}

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
  pose.origin_in_fixed = Place(six_bar, angles, body, Eigen::Vector2d::Zero());
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

SixBarDriver::SixBarDriver(const SixBar& six_bar, int input, double length,
                           SixBarPositions positions)
    : six_bar_(six_bar), input_(input), length_(length) {
  const std::array<double, kSixBarJointCount> numbers = SixBarJointNumbers(six_bar);
  for (int j = 0; j < 7; ++j) reference_[j] = Eigen::Vector2d(numbers[2 * j], numbers[2 * j + 1]);
  const std::array<std::vector<int>, 6> body_joints = SixBarBodyJointIndices(six_bar);
  input_hinge_ = input == kSixBarUpperLink   ? 0
                 : input == kSixBarFirstLink ? kJointFirstFrom / 2
                                             : kJointSecondFrom / 2;
  ground_joints_ = body_joints[kSixBarGround];
  input_joints_ = body_joints[input];
  if (positions != SixBarPositions::kClosedFormWhereItCan || !SixBarGroundedLink(six_bar, input)) {
    return;
  }
  // Each joint's two bodies.
  std::array<std::vector<int>, 7> joint_bodies;
  for (int body = 0; body < 6; ++body) {
    for (const int j : body_joints[body]) joint_bodies[j].push_back(body);
  }
  // Dyads found one after the other from ground and the input: two bodies not yet placed, joined
  // at a joint, each with one other joint on a placed body (two would fix it alone: not a dyad).
  std::array<bool, 6> placed = {};
  placed[kSixBarGround] = placed[input] = true;
  const auto other = [&](int j, int body) {
    return joint_bodies[j][0] == body ? joint_bodies[j][1] : joint_bodies[j][0];
  };
  // The one joint of `body` but `j` on a placed body; -1 where none or more than one.
  const auto hung = [&](int body, int j) {
    int found = -1;
    for (const int k : body_joints[body]) {
      if (k == j || !placed[other(k, body)]) continue;
      if (found >= 0) return -1;
      found = k;
    }
    return found;
  };
  const double shortest = 1e-9 * length;
  for (int count = 0; count < 2; ++count) {
    bool found = false;
    for (int j = 0; j < 7 && !found; ++j) {
      if (joint_bodies[j].size() != 2) return;
      const int a = joint_bodies[j][0], b = joint_bodies[j][1];
      if (placed[a] || placed[b]) continue;
      const int ja = hung(a, j), jb = hung(b, j);
      if (ja < 0 || jb < 0) continue;
      Dyad& dyad = dyads_[count];
      dyad.a = a;
      dyad.b = b;
      dyad.j = j;
      dyad.ja = ja;
      dyad.jb = jb;
      const Eigen::Vector2d along_a = reference_[j] - reference_[ja];
      const Eigen::Vector2d along_b = reference_[j] - reference_[jb];
      dyad.ra = along_a.norm();
      dyad.rb = along_b.norm();
      if (!(dyad.ra > shortest) || !(dyad.rb > shortest)) return;  // by continuation
      dyad.lever_a = along_a;
      dyad.lever_b = along_b;
      for (const int k : body_joints[a]) {
        if (k != j && k != ja) dyad.joints_a.push_back(k);
      }
      for (const int k : body_joints[b]) {
        if (k != j && k != jb) dyad.joints_b.push_back(k);
      }
      placed[a] = placed[b] = true;
      found = true;
    }
    if (!found) return;  // a triad: by continuation
  }
  dyad_count_ = 2;
}

std::array<int, 2> SixBarDriver::Sides(const SixBarAngles& angles) const {
  const Placement placement(six_bar_, angles);
  std::array<int, 2> sides = {1, 1};
  for (int k = 0; k < 2; ++k) {
    const Dyad& dyad = dyads_[k];
    // Each joint on body a of its dyad (or the known body of ja, jb: placed the same).
    const Eigen::Vector2d j = placement.frames.At(dyad.a, reference_[dyad.j]);
    const Eigen::Vector2d ja = placement.frames.At(dyad.a, reference_[dyad.ja]);
    const Eigen::Vector2d jb = placement.frames.At(dyad.b, reference_[dyad.jb]);
    const Eigen::Vector2d d = jb - ja, e = j - ja;
    sides[k] = d.x() * e.y() - d.y() * e.x() >= 0.0 ? 1 : -1;
  }
  return sides;
}

bool SixBarDriver::Close(double input_angle, const std::array<int, 2>& sides, SixBarAngles* angles,
                         double* margin) const {
  std::array<Eigen::Vector2d, 7> at;
  std::array<double, 6> turns = {};
  for (const int j : ground_joints_) at[j] = reference_[j];
  const Eigen::Rotation2Dd input_turn(input_angle);
  turns[input_] = input_angle;
  for (const int j : input_joints_) {
    at[j] = reference_[input_hinge_] + input_turn * (reference_[j] - reference_[input_hinge_]);
  }
  *margin = 1.0;
  for (int k = 0; k < 2; ++k) {
    const Dyad& dyad = dyads_[k];
    // The middle joint j at distances ra from ja and rb from jb: with d = jb - ja,
    // j = ja + u d + v perp(d), u = (ra^2 - rb^2 + |d|^2) / (2 |d|^2), v = +-sqrt(D) / (2 |d|^2),
    // D = (|d|^2 - (ra - rb)^2) ((ra + rb)^2 - |d|^2), and D / (4 ra^2 rb^2) the sine squared of
    // the angle between the dyad's two bodies at j: 0 at a dead point, negative past one.
    const Eigen::Vector2d d = at[dyad.jb] - at[dyad.ja];
    const double d2 = d.squaredNorm();
    const double ra = dyad.ra, rb = dyad.rb;
    const double discriminant = (d2 - (ra - rb) * (ra - rb)) * ((ra + rb) * (ra + rb) - d2);
    *margin = std::min(*margin, discriminant / (4.0 * ra * ra * rb * rb));
    if (!(discriminant >= 0.0) || !(d2 > 0.0)) return false;
    const double u = (ra * ra - rb * rb + d2) / (2.0 * d2);
    const double v = sides[k] * std::sqrt(discriminant) / (2.0 * d2);
    at[dyad.j] = at[dyad.ja] + u * d + v * Perp(d);
    // Each body's turn from the reference as a rotation: the one taking its reference lever
    // (from its known joint to j) to the lever now, both of its length.
    for (const bool first : {true, false}) {
      const int known = first ? dyad.ja : dyad.jb;
      const Eigen::Vector2d& lever = first ? dyad.lever_a : dyad.lever_b;
      const Eigen::Vector2d now = at[dyad.j] - at[known];
      const double squared = lever.squaredNorm();
      Eigen::Matrix2d rotation;
      const double c = lever.dot(now) / squared,
                   s = (lever.x() * now.y() - lever.y() * now.x()) / squared;
      rotation << c, -s, s, c;
      for (const int j : first ? dyad.joints_a : dyad.joints_b) {
        at[j] = at[known] + rotation * (reference_[j] - reference_[known]);
      }
      if (angles != nullptr) turns[first ? dyad.a : dyad.b] = std::atan2(s, c);
    }
  }
  if (angles == nullptr) return true;
  for (int body = 1; body < 6; ++body) {
    // Each turn continued from the one it replaces (whole turns off the change).
    const double change = turns[body] - (*angles)[body - 1];
    (*angles)[body - 1] += change - 2.0 * M_PI * std::nearbyint(change / (2.0 * M_PI));
  }
  (*angles)[input_ - 1] = input_angle;
  return true;
}

bool SixBarDriver::AssemblyOf(const SixBarAngles& angles, SixBarAssembly* assembly) const {
  if (closed_form()) {
    assembly->sides = Sides(angles);
    return true;
  }
  SixBarAngles assembled = angles;
  return Assemble(six_bar_, input_, angles[input_ - 1], &assembled, kStepTolerance * length_,
                  kDriveIterations, nullptr, &assembly->determinant);
}

bool SixBarDriver::Place(const SixBarAssembly& assembly, double input_angle, SixBarAngles* angles,
                         double tolerance) const {
  if (closed_form()) {
    double margin = 0.0;
    return Close(input_angle, assembly.sides, angles, &margin);
  }
  SixBarAngles assembled = *angles;
  double determinant = 0.0;
  if (!Assemble(six_bar_, input_, input_angle, &assembled, tolerance * length_, kDriveIterations,
                nullptr, &determinant) ||
      !(determinant * assembly.determinant > 0.0)) {
    return false;
  }
  *angles = assembled;
  return true;
}

bool SixBarDriver::Drive(double to_angle, SixBarAngles* angles, double max_step,
                         const std::function<void(const SixBarAngles&)>& visit) const {
  if (!closed_form()) {
    return Continue(six_bar_, input_, to_angle, angles, length_, max_step, visit);
  }
  const std::array<int, 2> sides = Sides(*angles);
  const double from = (*angles)[input_ - 1];
  SixBarAngles next = *angles;
  double margin = 0.0;
  if (!Close(from, sides, &next, &margin)) return false;
  const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(to_angle - from) / max_step)));
  const auto least = [&](double input_angle) {
    double at = 0.0;
    Close(input_angle, sides, nullptr, &at);
    return at;
  };
  // Stopped at a dead point between the input turns `good` (assembled) and `past` (not): the
  // last assembly before it, found by bisection to kDeadPointStep, is the last one reached.
  const auto stop = [&](double good, double past) {
    SixBarAngles placed = *angles;
    double at = 0.0;
    while (std::abs(past - good) > kDeadPointStep) {
      const double middle = 0.5 * (good + past);
      if (Close(middle, sides, &placed, &at)) {
        good = middle;
        next = placed;
      } else {
        past = middle;
      }
    }
    if (good != (*angles)[input_ - 1]) {
      *angles = next;
      if (visit) visit(*angles);
    }
    return false;
  };
  for (int step = 1; step <= steps; ++step) {
    const double before = (*angles)[input_ - 1], before_margin = margin;
    const double input_angle = step == steps ? to_angle : from + (to_angle - from) * step / steps;
    if (!Close(input_angle, sides, &next, &margin)) return stop(before, input_angle);
    // A dyad may fold and open again between two steps: where the dyads' least angle is small at
    // either, its least between them is sought (a dead point where it falls below 0).
    if (std::min(before_margin, margin) < kDipMargin) {
      const GoldenSection dip = GoldenSectionSearch(least, before, input_angle, kDipShrinks);
      if (dip.least < 0.0) {
        const double middle = 0.5 * (dip.low + dip.high);
        return stop(before, least(middle) < 0.0    ? middle
                            : least(dip.low) < 0.0 ? dip.low
                                                   : dip.high);
      }
    }
    *angles = next;
    if (visit) visit(*angles);
  }
  return true;
}

bool DriveSixBar(const SixBar& six_bar, int input, double to_angle, SixBarAngles* angles,
                 double length, double max_step,
                 const std::function<void(const SixBarAngles&)>& visit, SixBarPositions positions) {
  return SixBarDriver(six_bar, input, length, positions).Drive(to_angle, angles, max_step, visit);
}

std::array<double, 2> SixBarTransmissionDeg(const SixBar& six_bar, const SixBarAngles& angles) {
  const Placement placement(six_bar, angles);
  const SixBarFrames<double>& frames = placement.frames;
  std::array<double, 2> degrees = {90.0, 90.0};
  for (int l = 0; l < 2; ++l) {
    // The loop's coupler-rocker angle at the joint J the link closes on: between the link and
    // the body's lever from J to the joint K by which that body hangs from its parent
    // (SixBarFrames::TransmissionSine); a link or lever of no length leaves 90.
    const Eigen::Vector2d j = frames.OnBody(l);
    if (!((frames.HingeAt(4 + l) - j).norm() > 0.0) ||
        !((frames.HingeAt(six_bar.links[l].to_body) - j).norm() > 0.0)) {
      continue;
    }
    degrees[l] = std::asin(std::min(1.0, frames.TransmissionSine(l))) * 180.0 / M_PI;
  }
  return degrees;
}

bool SixBarInputRotatesFully(const SixBar& six_bar, const SixBarAngles& angles, int input,
                             double length, double step, SixBarPositions positions) {
  SixBarAngles driven = angles;
  return DriveSixBar(six_bar, input, angles[input - 1] + 2.0 * M_PI, &driven, length, step, nullptr,
                     positions);
}

SixBarAnalysis AnalyzeSixBar(const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses,
                             int input, double length, double step, bool full_turn,
                             bool refine_transmission, SixBarPositions positions) {
  SixBarAnalysis analysis;
  if (at_poses.empty()) return analysis;
  const SixBarDriver driver(six_bar, input, length, positions);
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
  // Each loop's transmission angle at every configuration the continuation reaches. Where its
  // least may lie between samples, it is refined by golden-section search over the input there,
  // each configuration on the sample's assembly (the free turns'
  // Jacobian's determinant of the same sign: near a dead point, Newton's method can reach the
  // other assembly close by): about a sample below its two neighbours (the input running one way
  // through them), and between the first two samples of a run or its last two (a run: from the
  // first pose, or a pose the continuation restarts from, to a stop) where the end is the lower.
  // Each from the last configuration the search reached, assembled to kStepTolerance.
  SixBarAngles last[3];
  std::array<double, 2> degrees[3];
  int samples = 0;
  const auto refine = [&](int l, const SixBarAngles& from, double value, double low, double high) {
    SixBarAssembly assembly;
    if (!refine_transmission || !(low != high) || !driver.AssemblyOf(from, &assembly)) return;
    SixBarAngles warm = from;
    const auto at = [&](double input_angle) {
      SixBarAngles assembled = warm;
      if (!driver.Place(assembly, input_angle, &assembled, kStepTolerance)) return value;
      warm = assembled;
      return SixBarTransmissionDeg(six_bar, assembled)[l];
    };
    double& least = analysis.transmission_min_deg[l];
    least = std::min(least, GoldenSectionSearch(at, low, high, kTransmissionShrinks).least);
  };
  const auto transmission = [&](const SixBarAngles& angles) {
    last[0] = last[1];
    last[1] = last[2];
    last[2] = angles;
    degrees[0] = degrees[1];
    degrees[1] = degrees[2];
    degrees[2] = SixBarTransmissionDeg(six_bar, angles);
    ++samples;
    const double low = last[0][index], middle = last[1][index], high = last[2][index];
    for (int l = 0; l < 2; ++l) {
      analysis.transmission_min_deg[l] = std::min(analysis.transmission_min_deg[l], degrees[2][l]);
      if (degrees[1][l] > analysis.transmission_min_deg[l] + kRefineWindowDeg) continue;
      if (samples == 2 && degrees[1][l] <= degrees[2][l]) {
        refine(l, last[1], degrees[1][l], middle, high);
      } else if (samples >= 3 && degrees[1][l] <= degrees[0][l] && degrees[1][l] <= degrees[2][l] &&
                 (degrees[1][l] < degrees[0][l] || degrees[1][l] < degrees[2][l]) &&
                 (middle - low) * (high - middle) > 0.0) {
        refine(l, last[1], degrees[1][l], low, high);
      }
    }
  };
  const auto finish = [&]() {
    for (int l = 0; l < 2 && samples >= 2; ++l) {
      if (degrees[2][l] <= degrees[1][l] &&
          degrees[2][l] <= analysis.transmission_min_deg[l] + kRefineWindowDeg) {
        refine(l, last[2], degrees[2][l], last[1][index], last[2][index]);
      }
    }
    samples = 0;
  };
  // From each pose to the next along the input (its turns as the poses give them).
  SixBarAngles angles = at_poses[0];
  transmission(angles);
  for (size_t k = 1; k < at_poses.size(); ++k) {
    if (!driver.Drive(at_poses[k][index], &angles, step, transmission)) {
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
      finish();
      angles = at_poses[k];  // on from the pose itself
      transmission(angles);
    }
  }
  finish();
  // A whole turn of the input from the first pose (none past a dead point between poses).
  if (full_turn && std::find(analysis.defects.begin(), analysis.defects.end(), "branch") ==
                       analysis.defects.end()) {
    SixBarAngles driven = at_poses[0];
    analysis.input_rotates_fully = driver.Drive(at_poses[0][index] + 2.0 * M_PI, &driven, step);
  }
  return analysis;
}

std::vector<SixBarAngles> SixBarSweep(const SixBar& six_bar, const SixBarAngles& at_first,
                                      int input, double length, double step) {
  std::vector<SixBarAngles> ahead = {at_first}, behind;
  SixBarAngles angles = at_first;
  const double start = at_first[input - 1];
  if (DriveSixBar(six_bar, input, start + 2.0 * M_PI, &angles, length, step,
                  [&](const SixBarAngles& reached) { ahead.push_back(reached); })) {
    ahead.pop_back();  // the whole turn's end is its start
    return ahead;
  }
  angles = at_first;
  DriveSixBar(six_bar, input, start - 2.0 * M_PI, &angles, length, step,
              [&](const SixBarAngles& reached) { behind.push_back(reached); });
  std::vector<SixBarAngles> sweep(behind.rbegin(), behind.rend());
  sweep.insert(sweep.end(), ahead.begin(), ahead.end());
  return sweep;
}

bool AssembleSixBar(const SixBar& six_bar, int input, double input_angle, SixBarAngles* angles,
                    double tolerance, int max_iterations) {
  return Assemble(six_bar, input, input_angle, angles, tolerance, max_iterations, nullptr);
}

}  // namespace linkfit
