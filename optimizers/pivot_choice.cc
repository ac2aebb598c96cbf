#include "optimizers/pivot_choice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "fitting/model_choice.h"
#include "fitting/planar_burmester_curves.h"
#include "fitting/planar_motion.h"
#include "lib/design_constraints.h"
#include "lib/text_format.h"
#include "optimizers/task_solver.h"

namespace linkfit {

namespace {

// Where no pivot lies within PivotChoiceOptions::reach L, the dyads are taken out to this many
// L (the Burmester curves' densely sampled radius, BurmesterCurveOptions::refine_radius), and
// where none lies there either (poses close together, moved by a large mechanism), from
// anywhere on the sampled curves.
constexpr double kFarReach = 25.0;

// Five poses' least-squares fits are refined as `linkfit refine` refines a design, in up to this
// many rounds while a round still lowers the largest pose error by kRefineGain.
constexpr int kRefineRounds = 3;
constexpr double kRefineGain = 0.005;

// A candidate dyad and the poses it was made for (its group: four-bars pair dyads of one group,
// which meet those poses exactly).
struct Candidate {
  DyadReport report;
  int group = 0;
};

// Whether the dyad's pivots without a box lie within `reach` of `centroid` (the moving pivot at
// the first pose).
bool WithinReach(const PlanarDyad& dyad, const DesignConstraints& constraints,
                 const PlanarPose& first, const Eigen::Vector2d& centroid, double reach) {
  if (dyad.HasFixedPivot() && !constraints.fixed_pivots_box &&
      !((dyad.fixed_pivot - centroid).norm() <= reach)) {
    return false;
  }
  return !(dyad.HasMovingPivot() && !constraints.moving_pivots_box &&
           !((first.ToFixed(dyad.moving_pivot) - centroid).norm() <= reach));
}

// How far apart two dyads of one type are (their pivots, a slider's line turned by its angle
// times L); infinity between types.
double DyadDistance(const PlanarDyad& a, const PlanarDyad& b, double length) {
  if (a.type != b.type) return std::numeric_limits<double>::infinity();
  double distance = 0.0;
  if (a.HasFixedPivot()) distance = std::max(distance, (a.fixed_pivot - b.fixed_pivot).norm());
  if (a.HasMovingPivot()) distance = std::max(distance, (a.moving_pivot - b.moving_pivot).norm());
  if (a.type != DyadType::kRR) {
    const double turn = std::abs(std::atan2(
        a.line_direction.x() * b.line_direction.y() - a.line_direction.y() * b.line_direction.x(),
        a.line_direction.dot(b.line_direction)));
    distance = std::max(distance, length * std::min(turn, M_PI - turn));
  }
  return distance;
}

// Up to `wanted` of `dyads`, spread evenly over their order (the curves' samples lie evenly
// along them where the dyads are within reach).
std::vector<PlanarDyad> SpreadOver(const std::vector<PlanarDyad>& dyads, int wanted) {
  if (static_cast<int>(dyads.size()) <= wanted) return dyads;
  std::vector<PlanarDyad> spread;
  for (int k = 0; k < wanted; ++k) {
    const double at = static_cast<double>(k) * static_cast<double>(dyads.size() - 1) /
                      static_cast<double>(wanted - 1);
    spread.push_back(dyads[static_cast<size_t>(std::lround(at))]);
  }
  return spread;
}

// The dyads of four poses' Burmester curves within the constraints that bound a dyad alone and
// within reach, spread along the curves.
std::vector<PlanarDyad> CurveDyads(const std::vector<PlanarPose>& four, const Task& task,
                                   double length, const Eigen::Vector2d& centroid, int wanted,
                                   double reach) {
  BurmesterCurves curves;
  if (SampleBurmesterCurves(four, BurmesterCurveOptions(), &curves) == 0) return {};
  for (const double within :
       {reach * length, kFarReach * length, std::numeric_limits<double>::infinity()}) {
    std::vector<PlanarDyad> eligible;
    for (const std::vector<PlanarDyad>& branch : curves.branches) {
      for (const PlanarDyad& dyad : branch) {
        if (DyadKeeps(task.constraints, dyad, length) &&
            WithinReach(dyad, task.constraints, four.front(), centroid, within)) {
          eligible.push_back(dyad);
        }
      }
    }
    if (!eligible.empty()) return SpreadOver(eligible, wanted);
  }
  return {};
}

// `side` x `side` points spread over a box (cell centres).
std::vector<Eigen::Vector2d> Grid(const PlanarBox& box, int side) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const Eigen::Vector2d t((i + 0.5) / side, (j + 0.5) / side);
      points.push_back(box.min + t.cwiseProduct(box.max - box.min));
    }
  }
  return points;
}

// Three poses: the dyads of moving pivots spread over E and of fixed pivots spread over Sigma
// (the task's boxes, else squares of half-width 1.5 L about the poses), within the constraints.
std::vector<PlanarDyad> ThreePoseDyads(const Task& task, double length,
                                       const Eigen::Vector2d& centroid, int side) {
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const Eigen::Vector2d half(1.5 * length, 1.5 * length);
  PlanarBox moving_box;
  if (task.constraints.moving_pivots_box) {
    moving_box = *task.constraints.moving_pivots_box;
  } else {
    const Eigen::Vector2d middle = poses.front().ToMoving(centroid);
    moving_box = {middle - half, middle + half};
  }
  const PlanarBox fixed_box =
      task.constraints.fixed_pivots_box.value_or(PlanarBox{centroid - half, centroid + half});
  std::vector<PlanarDyad> dyads;
  std::string note;
  PlanarDyad dyad;
  for (const Eigen::Vector2d& pivot : Grid(moving_box, side)) {
    if (DyadFromMovingPivot(poses, pivot, &dyad, &note) &&
        DyadKeeps(task.constraints, dyad, length)) {
      dyads.push_back(dyad);
    }
  }
  for (const Eigen::Vector2d& pivot : Grid(fixed_box, side)) {
    if (DyadFromFixedPivot(poses, pivot, &dyad, &note) &&
        DyadKeeps(task.constraints, dyad, length)) {
      dyads.push_back(dyad);
    }
  }
  return dyads;
}

// The 1-based numbers of the poses in `indices`, "1, 2, 4 and 5".
std::string PoseNumbers(const std::vector<int>& indices) {
  std::string text;
  for (size_t k = 0; k < indices.size(); ++k) {
    if (k > 0) text += k + 1 == indices.size() ? " and " : ", ";
    text += std::to_string(indices[k] + 1);
  }
  return text;
}

// A four-bar and its two dyads, not yet in the result.
struct Choice {
  MechanismReport mechanism;  // its input_dyad / output_dyad index `dyads`
  DyadReport dyads[2];
};

// The four-bar of dyads a (input tried both ways) and b judged on every task pose.
Choice Judge(const Task& task, double length, const DyadReport& a, const DyadReport& b,
             const std::string& chosen) {
  Choice choice;
  choice.dyads[0] = a;
  choice.dyads[1] = b;
  const std::vector<DyadReport> pair = {a, b};
  choice.mechanism = AnalyzeDyadPair(pair, 0, 1, task.planar_poses, length, task.pose_exact);
  choice.mechanism.chosen = chosen;
  JudgeMechanism(task, pair, length, &choice.mechanism);
  return choice;
}

// Whether two four-bars are one choice: each dyad of one within `distance` of one of the other's.
bool Near(const Choice& a, const Choice& b, double distance, double length) {
  const PlanarDyad& a0 = a.dyads[0].dyad;
  const PlanarDyad& a1 = a.dyads[1].dyad;
  const PlanarDyad& b0 = b.dyads[0].dyad;
  const PlanarDyad& b1 = b.dyads[1].dyad;
  const auto within = [&](const PlanarDyad& x, const PlanarDyad& y) {
    return DyadDistance(x, y, length) <= distance;
  };
  return (within(a0, b0) && within(a1, b1)) || (within(a0, b1) && within(a1, b0));
}

// Whether a four-bar's shortest link is at least `ratio` times its longest.
bool Proportioned(const Choice& choice, double ratio) {
  const std::vector<double> links =
      MotionFourBarLinks(choice.dyads[0].dyad, choice.dyads[1].dyad).All();
  if (links.empty()) return true;
  const auto [shortest, longest] = std::minmax_element(links.begin(), links.end());
  return *shortest >= ratio * *longest;
}

// Of `choices`, up to `count` in ranked order, each bringing a dyad farther than `spread` L from
// those of the ones taken before it; those with a link shorter than `ratio` times their longest
// only when no other is; with a ratio, crank-driven ones first (below).
std::vector<Choice> BestSpread(const std::vector<Choice>& choices, const Task& task, double length,
                               double precision_fit, double spread, double ratio, int count) {
  std::vector<RankKey> keys;
  for (const Choice& choice : choices) {
    keys.push_back(MechanismRankKey(choice.mechanism, precision_fit, task.constraints));
  }
  const std::vector<int> order = RankOrder(keys);
  std::vector<Choice> taken;
  // Exact choices (a `ratio` given: three and four poses, which all meet the poses): half of them
  // (at most) from those whose input turns fully (a motor's crank) first, then any; the
  // proportion waived only when nothing else is found. Fits (no ratio) go by their rank alone.
  struct Pass {
    double ratio;
    bool crank;
    int count;
  };
  for (const Pass& pass :
       {Pass{ratio, true, (count + 1) / 2}, Pass{ratio, false, count}, Pass{0.0, false, count}}) {
    if (pass.crank && ratio == 0.0) continue;
    if (pass.ratio == 0.0 && ratio > 0.0 && !taken.empty()) break;
    for (const int index : order) {
      if (static_cast<int>(taken.size()) >= pass.count) break;
      const Choice& choice = choices[index];
      if (!choice.mechanism.max_pose_error || !Proportioned(choice, pass.ratio)) continue;
      if (pass.crank &&
          (!choice.mechanism.input_rotates_fully || HasKinematicDefect(choice.mechanism.defects) ||
           !choice.mechanism.violates.empty())) {
        continue;
      }
      // A choice that only recombines taken dyads, or moves them by less than `spread`, is not
      // another choice.
      const auto known = [&](const PlanarDyad& dyad) {
        return std::any_of(taken.begin(), taken.end(), [&](const Choice& other) {
          return DyadDistance(dyad, other.dyads[0].dyad, length) <= spread * length ||
                 DyadDistance(dyad, other.dyads[1].dyad, length) <= spread * length;
        });
      };
      if (known(choice.dyads[0].dyad) && known(choice.dyads[1].dyad)) continue;
      taken.push_back(choice);
    }
  }
  return taken;
}

// Every four-bar of two candidates of one group, judged on every task pose.
std::vector<Choice> PairUp(const Task& task, double length,
                           const std::vector<Candidate>& candidates,
                           const std::vector<std::string>& chosen) {
  std::vector<Choice> choices;
  for (size_t i = 0; i < candidates.size(); ++i) {
    for (size_t j = i + 1; j < candidates.size(); ++j) {
      if (candidates[i].group != candidates[j].group) continue;
      choices.push_back(Judge(task, length, candidates[i].report, candidates[j].report,
                              chosen[candidates[i].group]));
    }
  }
  return choices;
}

DyadReport Report(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses, const Task& task,
                  double length) {
  DyadReport report(dyad, dyad.MaxResidual(poses));
  report.error_bound = PivotDyadErrorBound(dyad, poses, task.precision, length, true);
  return report;
}

}  // namespace

bool NeedsPivotChoices(const Task& task, const PlanarMotionResult& result) {
  const size_t count = task.planar_poses.size();
  if (count < 3 || count > 5) return false;
  if (count == 4 && task.moving_pivots.empty() && task.fixed_pivots.empty()) return true;
  // No four-bar at all (five poses whose Burmester roots are all complex, or whose dyads do not
  // pair): the nearest ones, with or without constraints given.
  if (result.mechanisms.empty()) return true;
  if (!task.constraints.given) return false;
  const double precision_fit = PoseFitTolerance(task.precision, result.scale);
  const RankKey first =
      MechanismRankKey(result.mechanisms.front(), precision_fit, task.constraints);
  return first.violates || first.defect_level > 0 || first.misses_exact;
}

void AddPivotChoices(const Task& task, const TaskSolverOptions& solver,
                     PlanarMotionResult* result) {
  const PivotChoiceOptions& options = solver.pivot_choice;
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const bool no_exact_four_bar = result->mechanisms.empty();
  const double length = result->scale;
  const double precision_fit = PoseFitTolerance(task.precision, length);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) {
    centroid += pose.origin_in_fixed / static_cast<double>(poses.size());
  }
  const std::string within = task.constraints.given ? " within the constraints"
                             : poses.size() == 5    ? ""
                                                    : " (no pivots given)";
  std::vector<Candidate> candidates;
  std::vector<std::string> chosen;
  if (poses.size() == 3) {
    chosen.push_back("pivots spread over the body and the ground" + within);
    for (const PlanarDyad& dyad : ThreePoseDyads(task, length, centroid, options.grid)) {
      candidates.push_back({Report(dyad, poses, task, length), 0});
    }
  } else if (poses.size() == 4) {
    chosen.push_back("pivots on the Burmester curves" + within);
    for (const PlanarDyad& dyad :
         CurveDyads(poses, task, length, centroid, options.curve_candidates, options.reach)) {
      candidates.push_back({Report(dyad, poses, task, length), 0});
    }
  } else {
    for (int left_out = 0; left_out < 5; ++left_out) {
      std::vector<PlanarPose> four;
      std::vector<int> indices;
      for (int k = 0; k < 5; ++k) {
        if (k == left_out) continue;
        four.push_back(poses[k]);
        indices.push_back(k);
      }
      chosen.push_back("pivots on the Burmester curves of poses " + PoseNumbers(indices) + within);
      for (const PlanarDyad& dyad :
           CurveDyads(four, task, length, centroid, options.subset_candidates, options.reach)) {
        candidates.push_back({Report(dyad, four, task, length), left_out});
      }
    }
  }
  std::vector<Choice> listed =
      BestSpread(PairUp(task, length, candidates, chosen), task, length, precision_fit,
                 options.spread, poses.size() == 5 ? 0.0 : options.link_ratio,
                 poses.size() == 5 ? options.refined : options.listed);

  // Five poses: the bounded least-squares fit of all five, from the best subset choices and from
  // the exact four-bars that break a constraint (onto the bounds).
  if (poses.size() == 5 && task.effort != Effort::kFast) {
    std::vector<Choice> seeds = listed;
    int exact_seeds = 0;
    for (const MechanismReport& mechanism : result->mechanisms) {
      if (exact_seeds >= 1) break;
      if (mechanism.violates.empty() || !mechanism.max_pose_error) continue;
      Choice seed;
      seed.mechanism = mechanism;
      seed.dyads[0] = result->dyads[mechanism.input_dyad];
      seed.dyads[1] = result->dyads[mechanism.output_dyad];
      seeds.push_back(seed);
      ++exact_seeds;
    }
    const std::string fit = "least squares of all five poses" + within;
    std::vector<Choice> fits;
    for (const Choice& seed : seeds) {
      const int input = seed.mechanism.input_dyad == 0 ? 0 : 1;
      PlanarDyad in = seed.dyads[input].dyad;
      PlanarDyad out = seed.dyads[1 - input].dyad;
      // As `linkfit refine` refines it (RefinePlanarDesign: the bounds as penalties, the
      // transmission angle held where the seed keeps it), again while that still gains
      // kRefineGain: what is listed, refine no longer improves.
      std::optional<Choice> refined;
      for (int round = 0; round < kRefineRounds; ++round) {
        const PlanarMotionResult design = RefinePlanarDesign(task, in, out, solver);
        if (design.mechanisms.empty()) break;
        const MechanismReport& ended = design.mechanisms.front();
        const DyadReport& a = design.dyads[ended.input_dyad];
        const DyadReport& b = design.dyads[ended.output_dyad];
        Choice next = Judge(task, length, a, b, fit);
        if (!next.mechanism.max_pose_error) break;
        const bool gains = !refined || *next.mechanism.max_pose_error <
                                           (1.0 - kRefineGain) * *refined->mechanism.max_pose_error;
        if (refined && !gains) break;
        refined = next;
        in = a.dyad;
        out = b.dyad;
      }
      if (refined) fits.push_back(*refined);
    }
    // The fits that keep the constraints and the subset choices, the best spread of them: a fit
    // near its seed and better replaces it.
    std::vector<Choice> pool = listed;
    for (const Choice& choice : fits) {
      if (choice.mechanism.violates.empty() && !HasKinematicDefect(choice.mechanism.defects)) {
        pool.push_back(choice);
      }
    }
    // Their fit decides: a short link a fit needs is the data's (the ratio sorts exact choices).
    listed = BestSpread(pool, task, length, precision_fit, options.spread, 0.0, options.listed);
  }
  // The four-bars of the task's own exact dyads are not chosen again.
  listed.erase(std::remove_if(listed.begin(), listed.end(),
                              [&](const Choice& choice) {
                                return std::any_of(
                                    result->mechanisms.begin(), result->mechanisms.end(),
                                    [&](const MechanismReport& own) {
                                      Choice other;
                                      other.dyads[0] = result->dyads[own.input_dyad];
                                      other.dyads[1] = result->dyads[own.output_dyad];
                                      return Near(choice, other, 1e-6 * length, length);
                                    });
                              }),
               listed.end());
  const long least_squares = std::count_if(listed.begin(), listed.end(), [](const Choice& c) {
    return c.mechanism.chosen.rfind("least squares", 0) == 0;
  });

  // Listed with the task's own four-bars, their dyads appended, and everything ranked again.
  // A dyad two choices share is listed once.
  const size_t own_dyads = result->dyads.size();
  const auto index_of = [&](const DyadReport& report) {
    for (size_t k = own_dyads; k < result->dyads.size(); ++k) {
      const PlanarDyad& other = result->dyads[k].dyad;
      if (other.type == report.dyad.type && other.fixed_pivot == report.dyad.fixed_pivot &&
          other.moving_pivot == report.dyad.moving_pivot && other.radius == report.dyad.radius &&
          other.line_point == report.dyad.line_point &&
          other.line_direction == report.dyad.line_direction) {
        return static_cast<int>(k);
      }
    }
    result->dyads.push_back(report);
    return static_cast<int>(result->dyads.size() - 1);
  };
  for (Choice& choice : listed) {
    const int input = choice.mechanism.input_dyad;
    choice.mechanism.input_dyad = index_of(choice.dyads[input]);
    choice.mechanism.output_dyad = index_of(choice.dyads[1 - input]);
    result->mechanisms.push_back(choice.mechanism);
  }
  RankMechanisms(precision_fit, task.constraints, -1, &result->mechanisms);

  std::string note;
  if (poses.size() == 4 && !task.constraints.given) {
    note = "linkfit chose " + std::to_string(listed.size()) +
           " four-bars with pivots spread along the Burmester curves (\"chosen\"), the best "
           "transmission angle first (\"constraints\": {\"input_rotates_fully\": true} asks for "
           "a crank-driven one)";
  } else {
    const std::string why =
        poses.size() == 4 && task.moving_pivots.empty() && task.fixed_pivots.empty()
            ? "no pivots were given"
        : no_exact_four_bar ? "no exact four-bar passes the poses"
                            : "no exact four-bar keeps the constraints without a defect";
    note = why + ": linkfit chose " + std::to_string(listed.size()) + " four-bars" + within +
           " (\"chosen\"";
    if (poses.size() == 5) {
      note += ": " + std::to_string(listed.size() - least_squares) +
              " with pivots on the Burmester curves of four of the poses, " +
              std::to_string(least_squares) + " least-squares fit(s) of all five";
    }
    note += ")";
  }
  if (!result->mechanisms.empty() && !result->mechanisms.front().chosen.empty()) {
    const MechanismReport& first = result->mechanisms.front();
    if (poses.size() == 5 && first.max_pose_error) {
      const auto worst = std::max_element(first.pose_errors.begin(), first.pose_errors.end());
      note += "; the first misses pose " +
              std::to_string(static_cast<int>(worst - first.pose_errors.begin()) + 1) + " by " +
              Format("%.3g", *first.max_pose_error) + " (pose_errors)";
    }
    if (!first.violates.empty() || HasKinematicDefect(first.defects)) {
      note += "; none of them keeps every constraint without a kinematic defect either";
    }
  } else if (listed.empty()) {
    note += "; none could be chosen (no dyad of the curves keeps the bounds on a single dyad)";
  }
  result->notes.push_back(note);
  if (!result->mechanisms.empty()) {
    const MechanismReport& first = result->mechanisms.front();
    const std::string given = GivenConstraintsNote(task.constraints, first.violates, first.defects);
    if (!given.empty()) result->notes.push_back(given);
  }
}

}  // namespace linkfit
