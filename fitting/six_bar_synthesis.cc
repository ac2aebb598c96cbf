#include "fitting/six_bar_synthesis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "fitting/model_choice.h"
#include "lib/design_constraints.h"

namespace linkfit {
namespace {

double Angle(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// The displacement turning by `turn` and taking `from` to `to`: p -> to + R(turn) (p - from).
PlanarPose Displacement(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double turn) {
  PlanarPose pose;
  pose.theta = turn;
  pose.origin_in_fixed = to - Rotation2(turn) * from;
  return pose;
}

// The chain's turns at a task pose from the first (lib/six_bar.h: upper link, forearm, task
// body), with its elbow and wrist there; the RR links' turns left as they are.
void ChainTurns(const SixBar& six_bar, const Eigen::Vector2d& elbow, const Eigen::Vector2d& wrist,
                double task_turn, SixBarAngles* angles) {
  (*angles)[0] = Angle(elbow - six_bar.ground_pivot) - Angle(six_bar.elbow - six_bar.ground_pivot);
  (*angles)[1] = Angle(wrist - elbow) - Angle(six_bar.wrist - six_bar.elbow);
  (*angles)[2] = task_turn;
}

// An RR root of the relative motion of body `to` seen from body `from`: its joints (Sigma at the
// first pose) and whether it is one of the chain's own links.
struct Root {
  Eigen::Vector2d from_joint, to_joint;
  double error_bound = 0.0;  // how far the data's precision can move it (DyadErrorBound)
};

// The real RR roots of the five relative poses, less those within `tolerance` of `trivial`
// (fixed, moving) joints.
std::vector<Root> RelativeRoots(const std::vector<PlanarPose>& relative,
                                const SixBarSynthesisOptions& options, double length,
                                double tolerance, const std::vector<Root>& trivial,
                                SixBarSynthesisSummary* summary) {
  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary burmester;
  SolvePlanarBurmester(relative, options.burmester, &dyads, &burmester);
  ++summary->burmester_problems;
  summary->roots_total += burmester.roots_total;
  std::vector<Root> roots;
  for (const PlanarDyad& dyad : dyads) {
    if (dyad.type != DyadType::kRR) {
      ++summary->roots_sliders;
      continue;
    }
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
    roots.back().error_bound = DyadErrorBound(dyad, relative, options.burmester.precision, length);
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

std::vector<SixBarAngles> SixBarAnglesAtPoses(const SixBar& six_bar,
                                              const std::vector<PlanarPose>& poses,
                                              const std::vector<Eigen::Vector2d>& elbows) {
  std::vector<SixBarAngles> at_poses;
  const Eigen::Vector2d wrist_in_moving = six_bar.reference_pose.ToMoving(six_bar.wrist);
  for (size_t k = 0; k < poses.size(); ++k) {
    SixBarAngles angles = SixBarAngles::Zero();
    ChainTurns(six_bar, elbows[k], poses[k].ToFixed(wrist_in_moving),
               poses[k].theta - poses[0].theta, &angles);
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
                      SixBarSynthesisSummary* summary,
                      std::vector<std::array<double, 2>>* error_bounds) {
  SixBarSynthesisSummary local;
  if (summary == nullptr) summary = &local;
  *summary = SixBarSynthesisSummary();
  six_bars->clear();
  if (error_bounds != nullptr) error_bounds->clear();
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
  // The chain at the first pose, and each body's displacement from its place there
  // (lib/six_bar.h's frames).
  SixBar chain_only;
  chain_only.ground_pivot = pivot;
  chain_only.elbow = elbows[0];
  chain_only.wrist = wrist;
  chain_only.reference_pose = poses[0];
  std::vector<std::vector<PlanarPose>> bodies(4, std::vector<PlanarPose>(5));
  for (int k = 0; k < 5; ++k) {
    SixBarAngles angles = SixBarAngles::Zero();
    ChainTurns(chain_only, elbows[k], poses[k].ToFixed(chain.wrist_in_moving),
               poses[k].theta - poses[0].theta, &angles);
    for (const int body : {kSixBarUpperLink, kSixBarForearm, kSixBarTaskBody}) {
      bodies[body][k] = SixBarBodyDisplacement(chain_only, angles, body);
    }
  }
  const Root upper{pivot, elbows[0]}, forearm{elbows[0], wrist};
  const auto roots = [&](int from, int to, const std::vector<Root>& trivial) {
    return RelativeRoots(Relative(bodies[from], bodies[to]), options, length, tolerance, trivial,
                         summary);
  };
  const std::vector<Root> ground_forearm = roots(kSixBarGround, kSixBarForearm, {upper});
  const std::vector<Root> ground_task = roots(kSixBarGround, kSixBarTaskBody, {});
  const std::vector<Root> upper_task = roots(kSixBarUpperLink, kSixBarTaskBody, {forearm});

  const auto six_bar = [&](SixBarTopology topology, int from0, int to0, const Root& first,
                           int from1, int to1, const Root& second) {
    SixBar made = chain_only;
    made.topology = topology;
    made.links[0] = {from0, to0, first.from_joint, first.to_joint};
    made.links[1] = {from1, to1, second.from_joint, second.to_joint};
    six_bars->push_back(made);
    // A new crank's second link is solved from the crank's turns, which the first link's
    // error moves too (to first order, the two add).
    const double second_bound =
        second.error_bound + (from1 == kSixBarFirstLink ? first.error_bound : 0.0);
    if (error_bounds != nullptr) error_bounds->push_back({first.error_bound, second_bound});
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
           RelativeRoots(Relative(c, bodies[to]), options, length, tolerance, trivial, summary)) {
        six_bar(topology, kSixBarGround, kSixBarTaskBody, first, kSixBarFirstLink, to, second);
      }
    }
  }
  for (const Root& first : ground_forearm) {
    const std::vector<PlanarPose> c = crank(first, kSixBarForearm);
    // C's pin and the task body are joined by the forearm (the pin to the wrist).
    for (const Root& second : RelativeRoots(Relative(c, bodies[kSixBarTaskBody]), options, length,
                                            tolerance, {{first.to_joint, wrist}}, summary)) {
      six_bar(SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, first, kSixBarFirstLink,
              kSixBarTaskBody, second);
    }
  }
  summary->six_bars = static_cast<int>(six_bars->size());
  return summary->six_bars;
}

PlanarMotionResult SolveSixBarMotion(const Task& task, const SixBarSynthesisOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result;
  result.method = "exact";
  result.precision = task.precision;
  result.constraints = task.constraints;
  result.chain = task.chain;
  const std::vector<PlanarPose>& poses = task.planar_poses;
  result.scale = task.scale ? *task.scale : CharacteristicLength(poses);
  const double length = result.scale > 0.0 ? result.scale : 1.0;
  SixBarSynthesisOptions synthesis = options;
  // The data's precision types the roots (a circle whose slider reading fits within it is a
  // slider). It does not make a relative motion a family of dyads: its rows carry the chain's
  // inverse kinematics, and the six-bar needs its roots, however well the digits fix them
  // (measured: poses printed to four decimals lost every root of some chains to a "family").
  synthesis.burmester.precision = task.precision;
  synthesis.burmester.family_units = 0.0;
  synthesis.burmester.conic_family_units = 0.0;
  std::vector<SixBar> six_bars;
  SixBarSynthesisSummary summary;
  std::vector<std::array<double, 2>> error_bounds;
  SynthesizeSixBars(poses, *task.chain, synthesis, &six_bars, &summary, &error_bounds);
  result.burmester_problems = summary.burmester_problems;
  result.roots_total = summary.roots_total;
  result.roots_real = summary.roots_real - summary.roots_trivial;
  std::vector<Eigen::Vector2d> elbows;
  int unreachable = -1;
  ChainElbows(poses, *task.chain, &elbows, &unreachable);
  const double least_transmission = MinTransmissionAngleDeg(task.constraints);
  for (size_t i = 0; i < six_bars.size(); ++i) {
    const SixBar& six_bar = six_bars[i];
    const std::vector<SixBarAngles> at_poses = SixBarAnglesAtPoses(six_bar, poses, elbows);
    // Each grounded input judged through the poses; whether it turns fully is asked only of
    // those with the fewest defects (it ranks after them).
    std::vector<SixBarReport> reports;
    for (const int input : {kSixBarUpperLink, kSixBarFirstLink, kSixBarSecondLink}) {
      if (!SixBarGroundedLink(six_bar, input)) continue;
      const SixBarAnalysis analysis =
          AnalyzeSixBar(six_bar, at_poses, input, length, kSixBarDriveStep, false);
      SixBarReport report;
      report.six_bar = six_bar;
      report.input = input;
      report.defects = analysis.defects;
      report.input_angles = analysis.input_angles;
      report.transmission_min_deg = analysis.transmission_min_deg;
      if (std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]) <
          least_transmission) {
        report.defects.push_back("transmission");
      }
      reports.push_back(report);
    }
    size_t fewest = reports.front().defects.size();
    for (const SixBarReport& report : reports) fewest = std::min(fewest, report.defects.size());
    for (SixBarReport& report : reports) {
      const bool stopped =
          std::find(report.defects.begin(), report.defects.end(), "branch") != report.defects.end();
      if (report.defects.size() == fewest && !stopped) {
        report.input_rotates_fully =
            SixBarInputRotatesFully(six_bar, at_poses[0], report.input, length);
      }
    }
    const auto key = [](const SixBarReport& report) {
      return std::make_tuple(
          report.defects.size(), !report.input_rotates_fully,
          -std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]));
    };
    SixBarReport best = *std::min_element(
        reports.begin(), reports.end(),
        [&](const SixBarReport& a, const SixBarReport& b) { return key(a) < key(b); });
    for (size_t k = 0; k < poses.size(); ++k) {
      best.max_pose_error = std::max(
          best.max_pose_error, PoseError(SixBarTaskPose(six_bar, at_poses[k]), poses[k], length));
    }
    best.error_bound = std::max(error_bounds[i][0], error_bounds[i][1]);
    result.six_bars.push_back(best);
  }
  std::stable_sort(
      result.six_bars.begin(), result.six_bars.end(),
      [](const SixBarReport& a, const SixBarReport& b) {
        const auto kinematic = [](const SixBarReport& report) {
          return std::count_if(report.defects.begin(), report.defects.end(),
                               [](const std::string& defect) { return defect != "transmission"; });
        };
        const double ta = std::min(a.transmission_min_deg[0], a.transmission_min_deg[1]);
        const double tb = std::min(b.transmission_min_deg[0], b.transmission_min_deg[1]);
        return std::make_tuple(kinematic(a), a.defects.size(), -ta) <
               std::make_tuple(kinematic(b), b.defects.size(), -tb);
      });
  result.notes.push_back(
      "six-bars on the given 3R chain: Watt I, Stephenson I, II and III (a chain grounded at one "
      "end admits no Watt II); each RR link is the five-pose Burmester problem of the relative "
      "motion of the two bodies it joins (" +
      std::to_string(summary.burmester_problems) + " problems, " +
      std::to_string(summary.roots_total) + " roots, " + std::to_string(summary.roots_real) +
      " real, " + std::to_string(summary.roots_trivial) + " of them the chain's own links)");
  if (summary.roots_sliders > 0) {
    result.notes.push_back(
        std::to_string(summary.roots_sliders) +
        " real roots of the relative motions are sliders (PR or RP) at the data's precision; "
        "six-bars with a slider link are not synthesized yet, so those are not listed");
  }
  if (result.six_bars.empty()) {
    result.notes.push_back(
        "no six-bar on this chain: the relative motions' Burmester problems have no real root "
        "that is not the chain's own link; try another chain (its wrist or ground pivot "
        "elsewhere, other link lengths, the other elbow)");
  }
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace linkfit
