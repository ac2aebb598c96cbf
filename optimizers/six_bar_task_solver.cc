// Six-bars through six or more poses, by least squares (issue 36; optimizers/task_solver.h
// SolveSixBarLeastSquares): each relative motion's RR links are least-squares dyads (seeded by
// exact five-pose solves, refined on the dyad residual), combined into the chain's six-bars as the
// exact synthesis combines its roots (fitting/six_bar_synthesis.h CombineSixBars), each placed at
// the poses and the best refined on the pose errors (optimizers/six_bar_refiner.h), then judged and
// ranked as five-pose six-bars are.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "fitting/planar_motion.h"
#include "fitting/six_bar_chains.h"
#include "fitting/six_bar_synthesis.h"
#include "lib/task_io.h"
#include "lib/text_format.h"
#include "optimizers/six_bar_refiner.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

// A root whose joints are within this (times L) of a better one's is that one.
constexpr double kSameRoot = 1e-4;

// Refined six-bars whose joints are within this (times L: a drawing's tolerance) of a better
// one's are listed once: the pose errors fix a six-bar's joints weakly
// (optimizers/six_bar_refiner.h: singular values down to 1e-7 of the largest), and two seeds
// refined to one optimum stop a little apart along its valley.
constexpr double kSameSixBar = 2e-2;

// Fresh refinements of a six-bar at most, each while the last gained more than kPassGain.
constexpr int kRefinePasses = 4;
constexpr double kPassGain = 0.005;

// The RMS of a dyad's residuals over `poses`.
double RmsResidual(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses) {
  double squares = 0.0;
  for (const PlanarPose& pose : poses) {
    const double residual = dyad.Residual(pose);
    squares += residual * residual;
  }
  return poses.empty() ? 0.0 : std::sqrt(squares / static_cast<double>(poses.size()));
}

// Roots kept per relative motion and six-bars refined, by effort.
int RootsKept(const TaskSolverOptions& options, Effort effort) {
  return effort == Effort::kFast       ? std::max(2, options.six_bar_roots / 2)
         : effort == Effort::kThorough ? 2 * options.six_bar_roots
                                       : options.six_bar_roots;
}
// The least transmission angle of a fit's loops at its configurations at the poses, degrees.
double LeastTransmissionAtPoses(const SixBarFit& fit) {
  double least = 90.0;
  for (const SixBarAngles& angles : fit.at_poses) {
    const std::array<double, 2> degrees = SixBarTransmissionDeg(fit.six_bar, angles);
    least = std::min({least, degrees[0], degrees[1]});
  }
  return least;
}

int SixBarsRefined(const TaskSolverOptions& options, Effort effort) {
  return effort == Effort::kFast       ? std::max(1, options.six_bars_refined / 3)
         : effort == Effort::kThorough ? 3 * options.six_bars_refined
                                       : options.six_bars_refined;
}

}  // namespace

PlanarMotionResult SolveSixBarLeastSquares(const Task& task, const TaskSolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result = SixBarResult(task, "least-squares");
  result.effort = EffortName(task.effort);
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = result.scale > 0.0 ? result.scale : 1.0;
  const SixBarChain& chain = *task.chain;
  const double root_length = SixBarTaskLength(poses, chain);
  const double trivial_tolerance = SixBarSynthesisOptions().trivial_tolerance * root_length;
  const PlanarBurmesterOptions burmester =
      SixBarRootOptions(options.planar.burmester, task.precision);
  const int kept_roots = RootsKept(options, task.effort);
  int problems = 0, sliders = 0, trivial = 0;
  // Each relative motion's RR links: the seeds' dyads refined on every relative pose, the chain's
  // own links and repeats left out, the best fits kept.
  const SixBarRootFinder find_roots = [&](const std::vector<PlanarPose>& relative,
                                          const std::vector<SixBarRoot>& own) {
    ++problems;
    std::vector<PlanarDyad> seeds;
    PlanarSeeds(relative, burmester, options.seed_subsets, &seeds);
    std::vector<std::pair<double, SixBarRoot>> scored;
    for (PlanarDyad dyad : seeds) {
      if (dyad.type != DyadType::kRR) continue;
      RefinePlanarDyad(relative, {}, {}, root_length, &dyad, options.planar_refiner);
      if (dyad.type != DyadType::kRR) {
        ++sliders;
        continue;
      }
      const SixBarRoot root{dyad.fixed_pivot, dyad.moving_pivot, 0.0};
      if (IsTrivialSixBarRoot(root, own, trivial_tolerance)) {
        ++trivial;
        continue;
      }
      scored.emplace_back(RmsResidual(dyad, relative), root);
    }
    std::stable_sort(scored.begin(), scored.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<SixBarRoot> roots;
    for (const auto& [rms, root] : scored) {
      if (static_cast<int>(roots.size()) == kept_roots) break;
      const bool repeated = std::any_of(roots.begin(), roots.end(), [&](const SixBarRoot& kept) {
        return (kept.from_joint - root.from_joint).norm() <= kSameRoot * root_length &&
               (kept.to_joint - root.to_joint).norm() <= kSameRoot * root_length;
      });
      if (!repeated) roots.push_back(root);
    }
    return roots;
  };
  std::vector<SixBar> six_bars;
  int unreachable = -1;
  CombineSixBars(poses, chain, find_roots, &six_bars, nullptr, &unreachable);
  // Each placed at the poses from the chain's inverse kinematics, the best refined.
  std::vector<Eigen::Vector2d> elbows;
  ChainElbows(poses, chain, &elbows, &unreachable);
  std::vector<SixBarFit> fits;
  for (const SixBar& six_bar : six_bars) {
    SixBarFit fit;
    if (FitSixBarToPoses(six_bar, poses, task.pose_weights, length,
                         SixBarAnglesAtPoses(six_bar, poses, elbows), &fit)) {
      fits.push_back(std::move(fit));
    }
  }
  std::stable_sort(fits.begin(), fits.end(), [](const SixBarFit& a, const SixBarFit& b) {
    return a.rms_pose_error < b.rms_pose_error;
  });
  fits.resize(std::min<size_t>(fits.size(), SixBarsRefined(options, task.effort)));
  SixBarRefinerOptions refiner = options.six_bar_refiner;
  refiner.constraints = task.constraints;
  if (task.chain && task.chain->hold) refiner.held_chain = task.chain;
  // Refined afresh while that gains (a fresh solve leaves a stiffened bound's penalty and a
  // collapsed trust region behind: the six-bar's valleys are flat), so that `linkfit refine`
  // finds each listed one refined.
  // A fit whose loops keep the task's least transmission angle at the poses is then refined as
  // `linkfit refine` refines it (RefineSixBarDesign): holding that angle.
  const double minimum = MinTransmissionAngleDeg(task.constraints);
  SixBarRefinerOptions holding = refiner;
  holding.min_transmission_deg = minimum;
  for (SixBarFit& fit : fits) {
    for (const SixBarRefinerOptions* with : {&refiner, &holding}) {
      if (with == &holding && LeastTransmissionAtPoses(fit) < minimum) break;
      for (int pass = 0; pass < kRefinePasses; ++pass) {
        const double before = fit.rms_pose_error;
        RefineSixBar(poses, task.pose_weights, length, &fit, *with);
        if (!Gains(before, fit.rms_pose_error, kPassGain)) break;
      }
    }
  }
  std::stable_sort(fits.begin(), fits.end(), [](const SixBarFit& a, const SixBarFit& b) {
    return a.rms_pose_error < b.rms_pose_error;
  });
  // Listed once each: a refined six-bar within kSameSixBar of a better one is that one.
  const double precision_fit = PoseFitTolerance(task.precision, length);
  std::vector<SixBar> kept;
  int repeated = 0;
  for (const SixBarFit& fit : fits) {
    std::vector<SixBar> with = kept;
    with.push_back(fit.six_bar);
    if (RemoveRepeatedSixBars(kSameSixBar * length, &with) > 0) {
      ++repeated;
      continue;
    }
    kept.push_back(fit.six_bar);
    result.six_bars.push_back(JudgeSixBar(task, fit.six_bar, fit.at_poses, length, precision_fit));
  }
  RankSixBars(task, precision_fit, &result);
  result.notes.push_back(
      std::to_string(poses.size()) +
      " poses, least squares: each RR link is a least-squares dyad of the relative motion of "
      "the two bodies it joins (" +
      std::to_string(problems) + " relative motions, the " + std::to_string(kept_roots) +
      " best-fitting dyads of each kept); of the " + std::to_string(six_bars.size()) +
      " six-bars they make on the chain, the " + std::to_string(fits.size()) +
      " that fit the poses best are refined on the pose errors, " +
      (task.chain->hold ? std::string("the chain held (\"hold\": true; its ground pivot, link "
                                      "lengths and wrist in E) and the RR links' joints free")
                        : std::string("every joint free (the chain's too: each six-bar's own are "
                                      "in its joints_at_first_pose; \"hold\": true in the chain "
                                      "holds it)")));
  if (std::find(task.pose_exact.begin(), task.pose_exact.end(), true) != task.pose_exact.end()) {
    result.notes.push_back(
        "poses marked exact are fitted as the others: six-bars do not hold exact poses yet");
  }
  if (sliders > 0) {
    result.notes.push_back(std::to_string(sliders) +
                           " refined dyads of the relative motions are sliders; six-bars with a "
                           "slider link are not synthesized yet, so those are not used");
  }
  if (repeated > 0) {
    result.notes.push_back(std::to_string(repeated) +
                           " refined six-bar(s) came to one another (joints within 0.02 L) and "
                           "are listed once");
  }
  if (result.six_bars.empty()) {
    result.notes.push_back(
        "no six-bar on this chain: the relative motions have no RR dyad that is not the chain's "
        "own link; try another chain (its wrist or ground pivot elsewhere, other link lengths, "
        "the other elbow)");
  }
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

PlanarMotionResult RefineSixBarDesign(const Task& task, const SixBar& six_bar,
                                      const std::vector<SixBarAngles>& at_poses,
                                      const TaskSolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result = SixBarResult(task, "refined");
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = result.scale > 0.0 ? result.scale : 1.0;
  SixBarFit design;
  if (!FitSixBarToPoses(six_bar, poses, task.pose_weights, length, at_poses, &design)) {
    throw InputError(
        "the six-bar does not assemble near the task's poses from its turns there "
        "(turns_at_poses_deg) or its upper link's range: is it this task's?");
  }
  SixBarFit fit = design;
  const double precision_fit = PoseFitTolerance(task.precision, length);
  const SixBarReport before = JudgeSixBar(task, six_bar, design.at_poses, length, precision_fit);
  const auto least = [](const SixBarReport& report) {
    return std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]);
  };
  // A design whose transmission angle keeps the task's minimum keeps it: the refiner holds it
  // (SixBarRefinerOptions::min_transmission_deg). Below it, the refinement is the fit's, and a
  // note says when it costs the angle more.
  const double minimum = MinTransmissionAngleDeg(task.constraints);
  SixBarRefinerOptions refiner = options.six_bar_refiner;
  refiner.constraints = task.constraints;
  if (task.chain && task.chain->hold) refiner.held_chain = task.chain;
  if (least(before) >= minimum && LeastTransmissionAtPoses(design) >= minimum) {
    refiner.min_transmission_deg = minimum;
  }
  const RefinerSummary summary = RefineSixBar(poses, task.pose_weights, length, &fit, refiner);
  SixBarReport refined = JudgeSixBar(task, fit.six_bar, fit.at_poses, length, precision_fit);
  // Never worse than the design: a refinement that fits worse without breaking fewer constraints
  // gives the design back.
  if (refined.rms_pose_error > before.rms_pose_error &&
      refined.violates.size() >= before.violates.size()) {
    refined = before;
    result.notes.push_back(
        "the refinement found no better fit that keeps what the design keeps: the design is "
        "given back unchanged");
  }
  result.six_bars.push_back(refined);
  if (refiner.min_transmission_deg) {
    result.notes.push_back(
        "the refinement held the transmission angle at the task's minimum (" +
        Format("%g", minimum) +
        " degrees), which the design keeps: at every pose, by penalty (the analysis judges it "
        "between them too)");
  } else if (least(result.six_bars.front()) < least(before) - 1.0) {
    char angles[320];
    std::snprintf(angles, sizeof(angles),
                  "the refined six-bar's least transmission angle is %.3g deg, the design's %.3g, "
                  "both below %.3g: a design below the minimum is refined on the fit alone; "
                  "weigh the fit against the angle",
                  least(result.six_bars.front()), least(before), minimum);
    result.notes.push_back(angles);
  }
  char text[240];
  std::snprintf(text, sizeof(text),
                "refined on the pose errors, %s: RMS pose error %.6g -> %.6g, "
                "largest %.6g -> %.6g (%d iterations)",
                refiner.held_chain ? "the task's chain held" : "every joint free",
                summary.initial_rms, result.six_bars.front().rms_pose_error, summary.initial_max,
                result.six_bars.front().max_pose_error, summary.iterations);
  result.notes.push_back(text);
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

PlanarMotionResult SolveSixBarChosenChain(const Task& task, const TaskSolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  const bool exact = poses.size() == 5;
  SixBarChainSearchOptions search;
  const int chains = options.six_bar_chains;
  search.max_candidates = task.effort == Effort::kFast       ? std::max(1, chains / 3)
                          : task.effort == Effort::kThorough ? 3 * chains
                                                             : chains;
  const std::vector<SixBarChainCandidate> candidates =
      SixBarChainCandidates(poses, task.constraints, length, search);
  if (candidates.empty()) {
    PlanarMotionResult result = SixBarResult(task, exact ? "exact" : "least-squares");
    result.notes.push_back(
        "no 3R chain found for a six-bar: none of the chains tried reaches every pose on one elbow "
        "with elbow angles within " +
        Format("%g", search.min_elbow_angle_deg) + " to " +
        Format("%g", 180.0 - search.min_elbow_angle_deg) + " degrees and joint travel within " +
        Format("%g", search.max_joint_travel_deg) +
        " degrees inside the task's bounds; give \"chain\" in the task");
    result.solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
  const double precision_fit = PoseFitTolerance(task.precision, length);
  // Each chain judged quickly (ScreenSixBarChain) on five poses: the task's, or beyond five five
  // spread over the task (the first and the last among them). Five poses: the chosen chain is
  // solved in full. Beyond: the chains that screen best are solved by least squares, the best
  // result kept.
  Task screened = task;
  if (!exact) {
    screened.planar_poses.clear();
    screened.pose_weights.clear();
    screened.pose_exact.clear();
    for (size_t k : SpreadIndices(poses.size(), 5, {})) screened.planar_poses.push_back(poses[k]);
  }
  struct Screened {
    SixBarChain chain;
    std::optional<RankKey> key;
  };
  std::vector<Screened> judged;
  bool buildable = false;
  for (const SixBarChainCandidate& candidate : candidates) {
    Task on_chain = screened;
    on_chain.chain = candidate.chain;
    const SixBarChainScreen screen = ScreenSixBarChain(on_chain);
    judged.push_back({candidate.chain, screen.best});
    if (screen.buildable) {
      buildable = true;
      break;
    }
  }
  // The judged chains by their best six-bar (the shared rule), a chain without one last.
  std::vector<RankKey> keys;
  std::vector<int> with_key, order;
  for (size_t c = 0; c < judged.size(); ++c) {
    if (judged[c].key) {
      keys.push_back(*judged[c].key);
      with_key.push_back(static_cast<int>(c));
    }
  }
  for (int k : RankOrder(keys)) order.push_back(with_key[k]);
  for (size_t c = 0; c < judged.size(); ++c) {
    if (!judged[c].key) order.push_back(static_cast<int>(c));
  }
  if (buildable)
    std::swap(order.front(), *std::find(order.begin(), order.end(), judged.size() - 1));
  const int solved = static_cast<int>(judged.size());
  int chosen = order.front();  // into judged (candidates, in order; not empty)
  std::optional<PlanarMotionResult> best;
  int fitted_count = 0;
  if (!exact) {
    // Least squares on the best-screened chains, the result whose first six-bar ranks first kept.
    std::optional<RankKey> best_key;
    const int fits = task.effort == Effort::kFast       ? 1
                     : task.effort == Effort::kThorough ? 3 * options.six_bar_least_squares_chains
                                                        : options.six_bar_least_squares_chains;
    fitted_count = std::min<int>(fits, static_cast<int>(order.size()));
    for (int c = 0; c < fitted_count; ++c) {
      Task on_chain = task;
      on_chain.chain = judged[order[c]].chain;
      PlanarMotionResult fitted = SolveSixBarLeastSquares(on_chain, options);
      std::optional<RankKey> key;
      if (!fitted.six_bars.empty()) {
        key = SixBarRankKey(fitted.six_bars.front(), precision_fit, task.constraints);
      }
      if (!best || (key && (!best_key || RankOrder({*key, *best_key}).front() == 0))) {
        best = std::move(fitted);
        chosen = order[c];
        if (key) best_key = key;
      }
    }
  }
  Task on_chain = task;
  on_chain.chain = judged[chosen].chain;
  PlanarMotionResult result = exact ? SolveSixBarMotion(on_chain) : std::move(*best);
  const bool any = std::any_of(judged.begin(), judged.end(),
                               [](const Screened& screened) { return screened.key.has_value(); });
  result.chain_chosen = true;
  const SixBarChain& chain = *result.chain;
  const std::string where =
      "linkfit chose the 3R chain (the task gives none): ground pivot (" +
      Format("%.4g", chain.ground_pivot.x()) + ", " + Format("%.4g", chain.ground_pivot.y()) +
      "), wrist (" + Format("%.4g", chain.wrist_in_moving.x()) + ", " +
      Format("%.4g", chain.wrist_in_moving.y()) + ") in E, links " +
      Format("%.4g", chain.upper_length) + " and " + Format("%.4g", chain.forearm_length) +
      ", elbow " + (chain.elbow_left ? "left" : "right") +
      " of the line from the ground pivot to "
      "the wrist. ";
  const std::string searched =
      "It is candidate " + std::to_string(chosen + 1) + " of " + std::to_string(candidates.size()) +
      " tried in order (each reaches every pose on one elbow, with elbow angles from " +
      Format("%g", search.min_elbow_angle_deg) + " to " +
      Format("%g", 180.0 - search.min_elbow_angle_deg) + " degrees and joint travel up to " +
      Format("%g", search.max_joint_travel_deg) + " degrees). Judged: " + std::to_string(solved) +
      (exact ? "" : " (on five of the poses spread over the task)") + "; ";
  std::string why;
  if (exact) {
    why = buildable ? "this is the first with a six-bar that keeps every constraint without a "
                      "defect"
          : any     ? "none has a six-bar that keeps every constraint without a defect; this "
                      "one's best six-bar ranks first"
                    : "none gives a six-bar";
  } else {
    why = std::string(buildable ? "the last has a six-bar through those five poses that keeps "
                                  "every constraint without a defect"
                      : any     ? "none has a six-bar through those five poses that keeps every "
                                  "constraint without a defect"
                                : "none gives a six-bar") +
          "; the best " + std::to_string(fitted_count) +
          " were fitted to all the poses, and this one's first six-bar ranks first";
  }
  result.notes.insert(result.notes.begin(),
                      where + searched + why + ". Give \"chain\" in the task to use your own.");
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace linkfit
