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
#include <string>
#include <vector>

#include "fitting/six_bar_synthesis.h"
#include "lib/task_io.h"
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
  PlanarBurmesterOptions burmester = options.planar.burmester;
  burmester.precision = task.precision;
  burmester.family_units = 0.0;  // as for five poses (SolveSixBarMotion)
  burmester.conic_family_units = 0.0;
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
  // Refined afresh while that gains (a fresh solve leaves a stiffened bound's penalty and a
  // collapsed trust region behind: the six-bar's valleys are flat), so that `linkfit refine`
  // finds each listed one refined.
  for (SixBarFit& fit : fits) {
    for (int pass = 0; pass < kRefinePasses; ++pass) {
      const double before = fit.rms_pose_error;
      RefineSixBar(poses, task.pose_weights, length, &fit, refiner);
      if (!Gains(before, fit.rms_pose_error, kPassGain)) break;
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
      " that fit the poses best are refined on the pose errors, every joint free (the chain's "
      "too: each six-bar's own are in its joints_at_first_pose)");
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
  SixBarFit fit;
  if (!FitSixBarToPoses(six_bar, poses, task.pose_weights, length, at_poses, &fit)) {
    throw InputError(
        "the six-bar does not assemble near the task's poses from its turns there "
        "(turns_at_poses_deg) or its upper link's range: is it this task's?");
  }
  SixBarRefinerOptions refiner = options.six_bar_refiner;
  refiner.constraints = task.constraints;
  const RefinerSummary summary = RefineSixBar(poses, task.pose_weights, length, &fit, refiner);
  const double precision_fit = PoseFitTolerance(task.precision, length);
  SixBarFit design;
  FitSixBarToPoses(six_bar, poses, task.pose_weights, length, at_poses, &design);
  const SixBarReport before = JudgeSixBar(task, six_bar, design.at_poses, length, precision_fit);
  result.six_bars.push_back(JudgeSixBar(task, fit.six_bar, fit.at_poses, length, precision_fit));
  // The refinement is the fit's: a transmission angle it gave up (below the minimum and by more
  // than a degree below the design's) is said.
  const auto least = [](const SixBarReport& report) {
    return std::min(report.transmission_min_deg[0], report.transmission_min_deg[1]);
  };
  const double minimum = MinTransmissionAngleDeg(task.constraints);
  if (least(result.six_bars.front()) < std::min(minimum, least(before) - 1.0)) {
    char angles[320];
    std::snprintf(angles, sizeof(angles),
                  "the refined six-bar's least transmission angle is %.3g deg, below %.3g (the "
                  "design's was %.3g): the six-bar refinement does not hold a transmission angle "
                  "yet, only the fit; weigh the fit against the design's angle",
                  least(result.six_bars.front()), minimum, least(before));
    result.notes.push_back(angles);
  }
  char text[200];
  std::snprintf(text, sizeof(text),
                "refined on the pose errors, every joint free: RMS pose error %.6g -> %.6g, "
                "largest %.6g -> %.6g (%d iterations)",
                summary.initial_rms, summary.final_rms, summary.initial_max, summary.final_max,
                summary.iterations);
  result.notes.push_back(text);
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace linkfit
