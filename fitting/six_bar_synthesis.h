// Five-pose synthesis of planar six-bars on a given 3R chain (McCarthy and Soh, Geometric Design
// of Linkages, 2nd ed., 2011, ch. 6; lib/six_bar.h). The chain's inverse kinematics places its
// links at every task pose; an RR link joining two bodies must keep one point of one on a circle
// about a point of the other, which is the Burmester problem of the two bodies' relative motion
// (fitting/planar_burmester.h): T_i,k^-1 T_j,k, k = 1..5, each body's frame Sigma at the first
// pose, so that every root's pivots are its joints there. The body pairs a chain grounded at one
// end admits, and their six-bars:
//   ground-forearm (0, 2) and upper link-task body (1, 3):  Watt I,
//   ground-forearm (0, 2) and ground-task body (0, 3):       Stephenson II,
//   ground-task body (0, 3) and upper link-task body (1, 3): Stephenson III,
// and, on a new crank C (an RR link from ground, whose turns its root gives):
//   C on the task body (0, 3) and C-upper link (4, 1):       Stephenson I,
//   C on the task body (0, 3) and C-forearm (4, 2):          Stephenson III,
//   C on the forearm (0, 2) and C-task body (4, 3):          Watt I.
// (A Watt II needs a ternary ground adjacent to a ternary link: none of these.) The relative
// motions of adjacent bodies are rotations about their joint, and the chain's own links are roots
// of two problems (the upper link of ground-forearm, the forearm of upper link-task body): these
// trivial roots are recognized and not listed.
#ifndef LINKFIT_FITTING_SIX_BAR_SYNTHESIS_H_
#define LINKFIT_FITTING_SIX_BAR_SYNTHESIS_H_

#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fitting/planar_burmester.h"
#include "lib/design_constraints.h"
#include "lib/planar_pose.h"
#include "lib/result.h"
#include "lib/six_bar.h"
#include "lib/task.h"

namespace linkfit {

// An RR root of a relative motion: its joints (Sigma at the first pose) and how far the data's
// precision can move them (DyadErrorBound; 0 where not known).
struct SixBarRoot {
  Eigen::Vector2d from_joint = Eigen::Vector2d::Zero(), to_joint = Eigen::Vector2d::Zero();
  double error_bound = 0.0;
};

// The RR roots of one relative motion (the poses of one body seen from another, each body's frame
// Sigma at the first pose, so that a root's joints are where they are at the first pose), less the
// chain's own links among them (`trivial`: IsTrivialSixBarRoot).
using SixBarRootFinder = std::function<std::vector<SixBarRoot>(
    const std::vector<PlanarPose>& relative, const std::vector<SixBarRoot>& trivial)>;

// Whether `root` is one of `trivial` (both joints within `tolerance`) or has no length.
bool IsTrivialSixBarRoot(const SixBarRoot& root, const std::vector<SixBarRoot>& trivial,
                         double tolerance);

// The length a six-bar task's roots are judged at: the poses' characteristic length, or the
// chain's longer link where that is longer.
double SixBarTaskLength(const std::vector<PlanarPose>& poses, const SixBarChain& chain);

struct SixBarSynthesisOptions {
  PlanarBurmesterOptions burmester;
  // A root whose joints are within this (times L) of a chain link's joints is that link.
  double trivial_tolerance = 1e-6;
};

// The Burmester options a six-bar task's relative motions are solved with: `base` with the data's
// `precision`, which types the roots (a circle whose slider reading fits within it is a slider),
// and no families. A relative motion's rows carry the chain's inverse kinematics, and the six-bar
// needs its roots however well the digits fix them (measured: poses printed to four decimals lost
// every root of some chains to a "family").
PlanarBurmesterOptions SixBarRootOptions(const PlanarBurmesterOptions& base,
                                         const DataPrecision& precision);

struct SixBarSynthesisSummary {
  int burmester_problems = 0;  // relative motions solved
  int roots_total = 0;         // their roots, complex ones included
  int roots_real = 0;          // real RR roots, the trivial ones included
  int roots_trivial = 0;       // the chain's own links among them
  int roots_sliders = 0;       // real PR and RP roots (at the data's precision), not used
  int six_bars = 0;            // six-bars returned
  // The first pose the chain cannot reach (its wrist beyond the two links), or -1.
  int unreachable_pose = -1;
};

// The six-bar's turns (lib/six_bar.h) at each task pose: the chain's from its elbows
// (ChainElbows), each RR link's from where its joints are on their bodies.
std::vector<SixBarAngles> SixBarAnglesAtPoses(const SixBar& six_bar,
                                              const std::vector<PlanarPose>& poses,
                                              const std::vector<Eigen::Vector2d>& elbows);

// Every six-bar of the chain's topologies whose RR links are real roots of their five-pose
// Burmester problems (RR dyads only). Requires exactly five poses. Returns the count written.
// With `error_bounds`, each six-bar's two links' first-order bounds of how far the data's
// precision (options.burmester.precision) can move them (fitting/model_choice.h DyadErrorBound
// of each root on its relative motion; a new crank's second link adds the first's), length
// units.
int SynthesizeSixBars(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                      const SixBarSynthesisOptions& options, std::vector<SixBar>* six_bars,
                      SixBarSynthesisSummary* summary = nullptr,
                      std::vector<std::array<double, 2>>* error_bounds = nullptr);

// Removes six-bars listed twice: the same topology, the same bodies joined, every joint within
// `tolerance` (a double root of a relative motion's Burmester problem gives its link twice).
// Keeps the first of each, and the entries of `error_bounds` (when given) alongside. Returns how
// many were removed.
int RemoveRepeatedSixBars(double tolerance, std::vector<SixBar>* six_bars,
                          std::vector<std::array<double, 2>>* error_bounds = nullptr);

// A six-bar's key in the shared ranking rule (lib/design_constraints.h RankKey): its violations
// and defects, its RMS pose error as its fit (within the data's precision at `precision_fit`,
// fitting/planar_motion.h PoseFitTolerance), its least transmission angle, its size (JointSpread
// of its joints).
RankKey SixBarRankKey(const SixBarReport& report, double precision_fit,
                      const DesignConstraints& constraints);

// The six-bars of the chain's topologies (the body pairs above) made of the roots `find_roots`
// gives for each relative motion of the chain through `poses` (five or more; a new crank's turns
// from its root's pin), and with `error_bounds` each one's two links' bounds (the roots'; a new
// crank's second link adds the first's). False (and *unreachable_pose) where the chain cannot
// reach a pose.
bool CombineSixBars(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                    const SixBarRootFinder& find_roots, std::vector<SixBar>* six_bars,
                    std::vector<std::array<double, 2>>* error_bounds, int* unreachable_pose);

// A six-bar judged at its configurations at the task's poses (AnalyzeSixBar under each grounded
// input; a least transmission angle below the task's minimum is the defect "transmission"; the
// task's constraints, SixBarViolations; its weighted RMS and largest pose errors) and driven by
// the input the shared rule ranks first (SixBarRankKey at `precision_fit`). No error bound.
// With `screen`, a quick judgement, to choose among chains (ScreenSixBarChain): each loop's least
// transmission angle not refined between the configurations reached; whether the input turns
// fully not asked unless the task requires it; no input driven whose turns at the poses do not run
// one way, nor any where a loop's transmission angle at a pose is below the task's minimum; the
// first input that keeps everything taken.
SixBarReport JudgeSixBar(const Task& task, const SixBar& six_bar,
                         const std::vector<SixBarAngles>& at_poses, double length,
                         double precision_fit, bool screen = false);

// A six-bar task's result before its six-bars: `method`, the task's precision, constraints and
// chain, and its scale (the task's, else the poses' characteristic length).
PlanarMotionResult SixBarResult(const Task& task, const std::string& method);

// Ranks result->six_bars by the shared rule and adds the notes on what the first breaks.
void RankSixBars(const Task& task, double precision_fit, PlanarMotionResult* result);

// A chain judged quickly (JudgeSixBar's `screen`) for choosing among chains
// (optimizers/task_solver.h SolveSixBarChosenChain): whether a six-bar on it keeps the task's
// constraints without a defect (the judging stops at the first), else the best key of its six-bars
// by the shared rule.
struct SixBarChainScreen {
  bool buildable = false;
  std::optional<RankKey> best;  // none: no six-bar on the chain
};
SixBarChainScreen ScreenSixBarChain(const Task& task);

// A validated "linkage": "six-bar" task (five planar poses and its chain): every six-bar of the
// chain, none listed twice (RemoveRepeatedSixBars), each judged under every grounded input
// (AnalyzeSixBar; a least transmission angle below the task's minimum, by default 30 degrees, is
// the defect "transmission"; the task's constraints, SixBarViolations) and driven by the one the
// shared rule ranks first (SixBarRankKey: keeping the constraints, fewer defects, then the larger
// least transmission angle), and the six-bars ranked by that rule. Notes say what the chain admits,
// when no six-bar is real, and what the first breaks.
PlanarMotionResult SolveSixBarMotion(const Task& task, const SixBarSynthesisOptions& options = {});

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SIX_BAR_SYNTHESIS_H_
