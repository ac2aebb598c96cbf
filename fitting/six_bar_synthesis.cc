#include "fitting/six_bar_synthesis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "fitting/model_choice.h"
#include "fitting/planar_motion.h"
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

using Root = SixBarRoot;

// The real RR roots of the five relative poses, less the chain's own links (`trivial`, within
// `tolerance`).
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
    if (IsTrivialSixBarRoot(root, trivial, tolerance)) {
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

bool IsTrivialSixBarRoot(const SixBarRoot& root, const std::vector<SixBarRoot>& trivial,
                         double tolerance) {
  bool own = (root.to_joint - root.from_joint).norm() <= tolerance;
  for (const SixBarRoot& link : trivial) {
    own = own || ((root.from_joint - link.from_joint).norm() <= tolerance &&
                  (root.to_joint - link.to_joint).norm() <= tolerance);
  }
  return own;
}

double SixBarTaskLength(const std::vector<PlanarPose>& poses, const SixBarChain& chain) {
  return std::max(CharacteristicLength(poses), std::max(chain.upper_length, chain.forearm_length));
}

int SynthesizeSixBars(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                      const SixBarSynthesisOptions& options, std::vector<SixBar>* six_bars,
                      SixBarSynthesisSummary* summary,
                      std::vector<std::array<double, 2>>* error_bounds) {
  SixBarSynthesisSummary local;
  if (summary == nullptr) summary = &local;
  *summary = SixBarSynthesisSummary();
  if (poses.size() != 5) {
    throw std::invalid_argument("six-bar synthesis needs exactly five poses");
  }
  const double length = SixBarTaskLength(poses, chain);
  const double tolerance = options.trivial_tolerance * length;
  CombineSixBars(
      poses, chain,
      [&](const std::vector<PlanarPose>& relative, const std::vector<SixBarRoot>& trivial) {
        return RelativeRoots(relative, options, length, tolerance, trivial, summary);
      },
      six_bars, error_bounds, &summary->unreachable_pose);
  summary->six_bars = static_cast<int>(six_bars->size());
  return summary->six_bars;
}

bool CombineSixBars(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                    const SixBarRootFinder& find_roots, std::vector<SixBar>* six_bars,
                    std::vector<std::array<double, 2>>* error_bounds, int* unreachable_pose) {
  six_bars->clear();
  if (error_bounds != nullptr) error_bounds->clear();
  std::vector<Eigen::Vector2d> elbows;
  if (!ChainElbows(poses, chain, &elbows, unreachable_pose)) return false;
  const size_t count = poses.size();
  const Eigen::Vector2d& pivot = chain.ground_pivot;
  const Eigen::Vector2d wrist = poses[0].ToFixed(chain.wrist_in_moving);
  // The chain at the first pose, and each body's displacement from its place there
  // (lib/six_bar.h's frames).
  SixBar chain_only;
  chain_only.ground_pivot = pivot;
  chain_only.elbow = elbows[0];
  chain_only.wrist = wrist;
  chain_only.reference_pose = poses[0];
  std::vector<std::vector<PlanarPose>> bodies(4, std::vector<PlanarPose>(count));
  for (size_t k = 0; k < count; ++k) {
    SixBarAngles angles = SixBarAngles::Zero();
    ChainTurns(chain_only, elbows[k], poses[k].ToFixed(chain.wrist_in_moving),
               poses[k].theta - poses[0].theta, &angles);
    for (const int body : {kSixBarUpperLink, kSixBarForearm, kSixBarTaskBody}) {
      bodies[body][k] = SixBarBodyDisplacement(chain_only, angles, body);
    }
  }
  const Root upper{pivot, elbows[0]}, forearm{elbows[0], wrist};
  const auto roots = [&](int from, int to, const std::vector<Root>& trivial) {
    return find_roots(Relative(bodies[from], bodies[to]), trivial);
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
    std::vector<PlanarPose> turns(count);
    const double start = Angle(root.to_joint - root.from_joint);
    for (size_t k = 0; k < count; ++k) {
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
      for (const Root& second : find_roots(Relative(c, bodies[to]), trivial)) {
        six_bar(topology, kSixBarGround, kSixBarTaskBody, first, kSixBarFirstLink, to, second);
      }
    }
  }
  for (const Root& first : ground_forearm) {
    const std::vector<PlanarPose> c = crank(first, kSixBarForearm);
    // C's pin and the task body are joined by the forearm (the pin to the wrist).
    for (const Root& second :
         find_roots(Relative(c, bodies[kSixBarTaskBody]), {{first.to_joint, wrist}})) {
      six_bar(SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, first, kSixBarFirstLink,
              kSixBarTaskBody, second);
    }
  }
  return true;
}

int RemoveRepeatedSixBars(double tolerance, std::vector<SixBar>* six_bars,
                          std::vector<std::array<double, 2>>* error_bounds) {
  const auto same = [tolerance](const SixBar& a, const SixBar& b) {
    if (a.topology != b.topology) return false;
    for (int l = 0; l < 2; ++l) {
      if (a.links[l].from_body != b.links[l].from_body ||
          a.links[l].to_body != b.links[l].to_body) {
        return false;
      }
    }
    const std::array<double, kSixBarJointCount> ja = SixBarJointNumbers(a);
    const std::array<double, kSixBarJointCount> jb = SixBarJointNumbers(b);
    for (int k = 0; k < kSixBarJointCount; k += 2) {
      if (std::hypot(ja[k] - jb[k], ja[k + 1] - jb[k + 1]) > tolerance) return false;
    }
    return true;
  };
  std::vector<SixBar> kept;
  std::vector<std::array<double, 2>> kept_bounds;
  for (size_t i = 0; i < six_bars->size(); ++i) {
    const SixBar& six_bar = (*six_bars)[i];
    if (std::any_of(kept.begin(), kept.end(),
                    [&](const SixBar& other) { return same(other, six_bar); })) {
      continue;
    }
    kept.push_back(six_bar);
    if (error_bounds != nullptr) kept_bounds.push_back((*error_bounds)[i]);
  }
  const int removed = static_cast<int>(six_bars->size() - kept.size());
  *six_bars = std::move(kept);
  if (error_bounds != nullptr) *error_bounds = std::move(kept_bounds);
  return removed;
}

RankKey SixBarRankKey(const SixBarReport& report, double precision_fit,
                      const DesignConstraints& constraints) {
  RankKey key;
  key.within_precision = report.max_pose_error <= precision_fit;
  key.fit_floor = 1e-3 * precision_fit;
  key.parameters = FourBarParameters(FourBarType::k4R);  // two RR links, as a 4R's
  key.fit = report.rms_pose_error;
  std::vector<Eigen::Vector2d> joints;
  for (const std::vector<Eigen::Vector2d>& body : SixBarBodyJoints(report.six_bar)) {
    joints.insert(joints.end(), body.begin(), body.end());
  }
  key.size = JointSpread(joints);
  JudgeWithDefaults(constraints, report.violates, report.defects, true, &key);
  key.transmission_min_deg = TransmissionTieBreak(
      constraints, std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]));
  return key;
}

SixBarReport JudgeSixBar(const Task& task, const SixBar& six_bar,
                         const std::vector<SixBarAngles>& at_poses, double length,
                         double precision_fit, bool screen) {
  const std::vector<PlanarPose>& poses = task.planar_poses;
  // A whole turn of the input from the first pose (none after a dead point between poses).
  const auto rotates = [&](SixBarReport* report) {
    report->input_rotates_fully =
        std::find(report->defects.begin(), report->defects.end(), "branch") ==
            report->defects.end() &&
        SixBarInputRotatesFully(six_bar, at_poses[0], report->input, length);
  };
  // The pose errors: the mechanism's, whichever link drives it.
  double largest = 0.0, squares = 0.0, total = 0.0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const double error = PoseError(SixBarTaskPose(six_bar, at_poses[k]), poses[k], length);
    const double weight = k < task.pose_weights.size() ? task.pose_weights[k] : 1.0;
    largest = std::max(largest, error);
    squares += weight * error * error;
    total += weight;
  }
  // Each grounded input judged through the poses, and the best by the shared rule drives it.
  // Whether an input turns fully is asked of every input where the task requires it, else of
  // the chosen one only (it does not rank).
  std::vector<SixBarReport> reports;
  std::vector<RankKey> keys;
  // A quick judgement: a loop's transmission angle at a pose below the task's minimum is the
  // defect under every input (the angle is the loop's, whichever link drives), so none is driven.
  const double least_allowed = MinTransmissionAngleDeg(task.constraints);
  std::array<double, 2> at_poses_deg = {90.0, 90.0};
  for (size_t k = 0; screen && k < at_poses.size(); ++k) {
    const std::array<double, 2> degrees = SixBarTransmissionDeg(six_bar, at_poses[k]);
    for (int l = 0; l < 2; ++l) at_poses_deg[l] = std::min(at_poses_deg[l], degrees[l]);
  }
  const bool poor = std::min(at_poses_deg[0], at_poses_deg[1]) < least_allowed;
  // The inputs whose turns at the poses run one way first: when one of them drives the six-bar
  // without a kinematic defect, an input with an order defect cannot rank above it (the shared
  // rule's groups; the violations are the same under every input unless the task asks for a
  // fully turning one), and is not driven. A quick judgement drives none with an order defect.
  const auto ordered = [&](int input) {
    for (size_t k = 2; k < at_poses.size(); ++k) {
      if ((at_poses[k - 1][input - 1] - at_poses[k - 2][input - 1]) *
              (at_poses[k][input - 1] - at_poses[k - 1][input - 1]) <=
          0.0) {
        return false;
      }
    }
    return true;
  };
  std::vector<std::pair<int, bool>> inputs;  // each grounded link, and whether it has "order"
  for (const int input : {kSixBarUpperLink, kSixBarFirstLink, kSixBarSecondLink}) {
    if (SixBarGroundedLink(six_bar, input)) inputs.emplace_back(input, !ordered(input));
  }
  std::stable_partition(inputs.begin(), inputs.end(),
                        [](const std::pair<int, bool>& input) { return !input.second; });
  bool kinematically_free = false;
  for (const auto& [input, order] : inputs) {
    if (order && kinematically_free && !task.constraints.input_rotates_fully) break;
    SixBarAnalysis analysis;
    if ((order && screen) || poor) {
      if (order) analysis.defects = {"order"};
      analysis.transmission_min_deg = at_poses_deg;
      for (const SixBarAngles& angles : at_poses) {
        analysis.input_angles.push_back(angles[input - 1] - at_poses[0][input - 1]);
      }
    } else {
      analysis = AnalyzeSixBar(six_bar, at_poses, input, length, kSixBarDriveStep, false, !screen);
    }
    SixBarReport report;
    report.six_bar = six_bar;
    report.input = input;
    report.defects = analysis.defects;
    report.input_angles = analysis.input_angles;
    report.at_poses = at_poses;
    report.transmission_min_deg = analysis.transmission_min_deg;
    report.max_pose_error = largest;
    report.rms_pose_error = total > 0.0 ? std::sqrt(squares / total) : 0.0;
    if (std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]) <
        MinTransmissionAngleDeg(task.constraints)) {
      report.defects.push_back("transmission");
    }
    if (task.constraints.input_rotates_fully) rotates(&report);
    report.violates =
        SixBarViolations(task.constraints, six_bar, report.input_rotates_fully, length);
    // A quick judgement asks only whether some input keeps everything.
    if (screen && report.defects.empty() && report.violates.empty()) return report;
    kinematically_free |= !HasKinematicDefect(report.defects);
    keys.push_back(SixBarRankKey(report, precision_fit, task.constraints));
    reports.push_back(report);
  }
  SixBarReport best = reports[RankOrder(keys).front()];
  if (!task.constraints.input_rotates_fully && !screen) rotates(&best);
  return best;
}

PlanarMotionResult SixBarResult(const Task& task, const std::string& method) {
  PlanarMotionResult result;
  result.method = method;
  result.precision = task.precision;
  result.constraints = task.constraints;
  result.six_bar = true;
  result.chain = task.chain;
  result.scale = task.scale ? *task.scale : CharacteristicLength(task.planar_poses);
  return result;
}

void RankSixBars(const Task& task, double precision_fit, PlanarMotionResult* result) {
  RankReports(
      [&](const SixBarReport& report) {
        return SixBarRankKey(report, precision_fit, task.constraints);
      },
      -1, &result->six_bars);
  if (result->six_bars.empty()) return;
  std::vector<RankKey> keys;
  for (const SixBarReport& report : result->six_bars) {
    keys.push_back(SixBarRankKey(report, precision_fit, task.constraints));
  }
  const std::string defaults = DefaultsNote(keys, "an RMS pose error of", "six-bar");
  if (!defaults.empty()) result->notes.push_back(defaults);
  const SixBarReport& first = result->six_bars.front();
  const std::string given =
      GivenConstraintsNote(task.constraints, first.violates, first.defects, "six-bar");
  if (!given.empty()) result->notes.push_back(given);
}

PlanarBurmesterOptions SixBarRootOptions(const PlanarBurmesterOptions& base,
                                         const DataPrecision& precision) {
  PlanarBurmesterOptions options = base;
  options.precision = precision;
  options.family_units = 0.0;
  options.conic_family_units = 0.0;
  return options;
}

SixBarChainScreen ScreenSixBarChain(const Task& task) {
  SixBarChainScreen screen;
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  SixBarSynthesisOptions options;
  options.burmester = SixBarRootOptions(options.burmester, task.precision);
  std::vector<SixBar> six_bars;
  SynthesizeSixBars(poses, *task.chain, options, &six_bars);
  RemoveRepeatedSixBars(options.trivial_tolerance * length, &six_bars);
  std::vector<Eigen::Vector2d> elbows;
  int unreachable = -1;
  if (!ChainElbows(poses, *task.chain, &elbows, &unreachable)) return screen;
  const double precision_fit = PoseFitTolerance(task.precision, length);
  std::vector<RankKey> keys;
  for (const SixBar& six_bar : six_bars) {
    const SixBarReport report = JudgeSixBar(
        task, six_bar, SixBarAnglesAtPoses(six_bar, poses, elbows), length, precision_fit, true);
    keys.push_back(SixBarRankKey(report, precision_fit, task.constraints));
    if (report.defects.empty() && report.violates.empty()) {
      screen.buildable = true;
      screen.best = keys.back();
      return screen;
    }
  }
  if (!keys.empty()) screen.best = keys[RankOrder(keys).front()];
  return screen;
}

PlanarMotionResult SolveSixBarMotion(const Task& task, const SixBarSynthesisOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result = SixBarResult(task, "exact");
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = result.scale > 0.0 ? result.scale : 1.0;
  SixBarSynthesisOptions synthesis = options;
  synthesis.burmester = SixBarRootOptions(options.burmester, task.precision);
  std::vector<SixBar> six_bars;
  SixBarSynthesisSummary summary;
  std::vector<std::array<double, 2>> error_bounds;
  SynthesizeSixBars(poses, *task.chain, synthesis, &six_bars, &summary, &error_bounds);
  const int repeated =
      RemoveRepeatedSixBars(options.trivial_tolerance * length, &six_bars, &error_bounds);
  result.burmester_problems = summary.burmester_problems;
  result.roots_total = summary.roots_total;
  result.roots_real = summary.roots_real - summary.roots_trivial;
  std::vector<Eigen::Vector2d> elbows;
  int unreachable = -1;
  ChainElbows(poses, *task.chain, &elbows, &unreachable);
  const double precision_fit = PoseFitTolerance(task.precision, length);
  for (size_t i = 0; i < six_bars.size(); ++i) {
    SixBarReport report = JudgeSixBar(
        task, six_bars[i], SixBarAnglesAtPoses(six_bars[i], poses, elbows), length, precision_fit);
    report.error_bound = std::max(error_bounds[i][0], error_bounds[i][1]);
    result.six_bars.push_back(report);
  }
  RankSixBars(task, precision_fit, &result);
  result.notes.push_back(
      "six-bars on the 3R chain: Watt I, Stephenson I, II and III (a chain grounded at one "
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
  if (repeated > 0) {
    result.notes.push_back(std::to_string(repeated) +
                           " six-bar(s) came twice (a double root of a relative motion) and are "
                           "listed once");
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
