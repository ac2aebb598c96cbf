#include "fitting/six_bar_synthesis.h"

#include <cmath>
#include <stdexcept>

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

double Angle(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// The displacement turning by `turn` and taking `from` to `to`: p -> to + R(turn) (p - from).
PlanarPose Displacement(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double turn) {
  PlanarPose pose;
  pose.theta = turn;
  pose.origin_in_fixed = to - Rotation2(turn) * from;
  return pose;
}

// An RR root of the relative motion of body `to` seen from body `from`: its joints (Sigma at the
// first pose) and whether it is one of the chain's own links.
struct Root {
  Eigen::Vector2d from_joint, to_joint;
};

// The real RR roots of the five relative poses, less those within `tolerance` of `trivial`
// (fixed, moving) joints.
std::vector<Root> RelativeRoots(const std::vector<PlanarPose>& relative,
                                const SixBarSynthesisOptions& options, double tolerance,
                                const std::vector<Root>& trivial, SixBarSynthesisSummary* summary) {
  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary burmester;
  SolvePlanarBurmester(relative, options.burmester, &dyads, &burmester);
  ++summary->burmester_problems;
  summary->roots_total += burmester.roots_total;
  std::vector<Root> roots;
  for (const PlanarDyad& dyad : dyads) {
    if (dyad.type != DyadType::kRR) continue;
    ++summary->roots_real;
    const Root root{dyad.fixed_pivot, dyad.moving_pivot};
    bool own = (root.to_joint - root.from_joint).norm() <= tolerance;
    for (const Root& link : trivial) {
      own = own || ((root.from_joint - link.from_joint).norm() <= tolerance &&
                    (root.to_joint - link.to_joint).norm() <= tolerance);
    }
    if (own) {
      ++summary->roots_trivial;
      continue;
    }
    roots.push_back(root);
  }
  return roots;
}

std::vector<PlanarPose> Relative(const std::vector<PlanarPose>& from,
                                 const std::vector<PlanarPose>& to) {
  std::vector<PlanarPose> relative;
  for (size_t k = 0; k < from.size(); ++k) relative.push_back(from[k].Inverse() * to[k]);
  return relative;
}

}  // namespace

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

std::vector<SixBarAngles> SixBarAnglesAtPoses(const SixBar& six_bar,
                                              const std::vector<PlanarPose>& poses,
                                              const std::vector<Eigen::Vector2d>& elbows) {
  std::vector<SixBarAngles> at_poses;
  const Eigen::Vector2d wrist_in_moving = six_bar.reference_pose.ToMoving(six_bar.wrist);
  for (size_t k = 0; k < poses.size(); ++k) {
    SixBarAngles angles = SixBarAngles::Zero();
    const Eigen::Vector2d wrist = poses[k].ToFixed(wrist_in_moving);
    angles[0] =
        Angle(elbows[k] - six_bar.ground_pivot) - Angle(six_bar.elbow - six_bar.ground_pivot);
    angles[1] = Angle(wrist - elbows[k]) - Angle(six_bar.wrist - six_bar.elbow);
    angles[2] = poses[k].theta - poses[0].theta;
    // Each turn continued from the previous pose's (not wrapped: the input's turns run on).
    for (int l = 0; l < 2; ++l) {
      const SixBarRRLink& link = six_bar.links[l];
      const Eigen::Vector2d from =
          SixBarBodyDisplacement(six_bar, angles, link.from_body).ToFixed(link.from_joint);
      const Eigen::Vector2d to =
          SixBarBodyDisplacement(six_bar, angles, link.to_body).ToFixed(link.to_joint);
      angles[3 + l] = Angle(to - from) - Angle(link.to_joint - link.from_joint);
    }
    if (k > 0) {
      for (int j = 0; j < 5; ++j) {
        angles[j] = at_poses.back()[j] + std::remainder(angles[j] - at_poses.back()[j], 2.0 * M_PI);
      }
    }
    at_poses.push_back(angles);
  }
  return at_poses;
}

int SynthesizeSixBars(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                      const SixBarSynthesisOptions& options, std::vector<SixBar>* six_bars,
                      SixBarSynthesisSummary* summary) {
  SixBarSynthesisSummary local;
  if (summary == nullptr) summary = &local;
  *summary = SixBarSynthesisSummary();
  six_bars->clear();
  if (poses.size() != 5) {
    throw std::invalid_argument("six-bar synthesis needs exactly five poses");
  }
  std::vector<Eigen::Vector2d> elbows;
  if (!ChainElbows(poses, chain, &elbows, &summary->unreachable_pose)) return 0;
  const double length =
      std::max(CharacteristicLength(poses), std::max(chain.upper_length, chain.forearm_length));
  const double tolerance = options.trivial_tolerance * length;
  const Eigen::Vector2d& pivot = chain.ground_pivot;
  const Eigen::Vector2d wrist = poses[0].ToFixed(chain.wrist_in_moving);
  // Each body's displacement from its place at the first pose (lib/six_bar.h's frames).
  std::vector<std::vector<PlanarPose>> bodies(4, std::vector<PlanarPose>(5));
  for (int k = 0; k < 5; ++k) {
    const Eigen::Vector2d wrist_k = poses[k].ToFixed(chain.wrist_in_moving);
    bodies[kSixBarUpperLink][k] =
        Displacement(pivot, pivot, Angle(elbows[k] - pivot) - Angle(elbows[0] - pivot));
    bodies[kSixBarForearm][k] =
        Displacement(elbows[0], elbows[k], Angle(wrist_k - elbows[k]) - Angle(wrist - elbows[0]));
    bodies[kSixBarTaskBody][k] = poses[k] * poses[0].Inverse();
  }
  const Root upper{pivot, elbows[0]}, forearm{elbows[0], wrist};
  const auto roots = [&](int from, int to, const std::vector<Root>& trivial) {
    return RelativeRoots(Relative(bodies[from], bodies[to]), options, tolerance, trivial, summary);
  };
  const std::vector<Root> ground_forearm = roots(kSixBarGround, kSixBarForearm, {upper});
  const std::vector<Root> ground_task = roots(kSixBarGround, kSixBarTaskBody, {});
  const std::vector<Root> upper_task = roots(kSixBarUpperLink, kSixBarTaskBody, {forearm});

  const auto six_bar = [&](SixBarTopology topology, int from0, int to0, const Root& first,
                           int from1, int to1, const Root& second) {
    SixBar made;
    made.topology = topology;
    made.ground_pivot = pivot;
    made.elbow = elbows[0];
    made.wrist = wrist;
    made.reference_pose = poses[0];
    made.links[0] = {from0, to0, first.from_joint, first.to_joint};
    made.links[1] = {from1, to1, second.from_joint, second.to_joint};
    six_bars->push_back(made);
  };
  for (const Root& first : ground_forearm) {
    for (const Root& second : upper_task) {
      six_bar(SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, first, kSixBarUpperLink,
              kSixBarTaskBody, second);
    }
    for (const Root& second : ground_task) {
      six_bar(SixBarTopology::kStephensonII, kSixBarGround, kSixBarForearm, first, kSixBarGround,
              kSixBarTaskBody, second);
    }
  }
  for (const Root& first : ground_task) {
    for (const Root& second : upper_task) {
      six_bar(SixBarTopology::kStephensonIII, kSixBarGround, kSixBarTaskBody, first,
              kSixBarUpperLink, kSixBarTaskBody, second);
    }
  }
  // New cranks: an RR link C from ground, turning about its pivot as its pin on body `on` moves,
  // and a second RR link from C to another chain body.
  const auto crank = [&](const Root& root, int on) {
    std::vector<PlanarPose> turns(5);
    const double start = Angle(root.to_joint - root.from_joint);
    for (int k = 0; k < 5; ++k) {
      const Eigen::Vector2d pin = bodies[on][k].ToFixed(root.to_joint);
      turns[k] =
          Displacement(root.from_joint, root.from_joint, Angle(pin - root.from_joint) - start);
    }
    return turns;
  };
  for (const Root& first : ground_task) {
    const std::vector<PlanarPose> c = crank(first, kSixBarTaskBody);
    for (const auto& [to, topology] :
         {std::pair<int, SixBarTopology>{kSixBarUpperLink, SixBarTopology::kStephensonI},
          std::pair<int, SixBarTopology>{kSixBarForearm, SixBarTopology::kStephensonIII}}) {
      // C and the upper link both turn about ground: ground joins them (C's pivot to G); C's
      // pin and the forearm are joined by the task body (the pin to the wrist).
      const std::vector<Root> trivial = {to == kSixBarUpperLink ? Root{first.from_joint, pivot}
                                                                : Root{first.to_joint, wrist}};
      for (const Root& second :
           RelativeRoots(Relative(c, bodies[to]), options, tolerance, trivial, summary)) {
        six_bar(topology, kSixBarGround, kSixBarTaskBody, first, kSixBarFirstLink, to, second);
      }
    }
  }
  for (const Root& first : ground_forearm) {
    const std::vector<PlanarPose> c = crank(first, kSixBarForearm);
    // C's pin and the task body are joined by the forearm (the pin to the wrist).
    for (const Root& second : RelativeRoots(Relative(c, bodies[kSixBarTaskBody]), options,
                                            tolerance, {{first.to_joint, wrist}}, summary)) {
      six_bar(SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, first, kSixBarFirstLink,
              kSixBarTaskBody, second);
    }
  }
  summary->six_bars = static_cast<int>(six_bars->size());
  return summary->six_bars;
}

}  // namespace linkfit
