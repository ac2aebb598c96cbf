#include "fitting/planar_motion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "fitting/model_choice.h"
#include "fitting/planar_burmester_curves.h"
#include "lib/design_constraints.h"
#include "lib/four_bar_motion.h"
#include "lib/precision.h"
#include "lib/text_format.h"

namespace linkfit {
namespace {

// Order of the dyad list: RR by crank length, then PR, then RP.
bool DyadBefore(const DyadReport& a, const DyadReport& b) {
  if (a.dyad.type != b.dyad.type) return a.dyad.type < b.dyad.type;
  if (a.dyad.type == DyadType::kRR) return a.dyad.radius < b.dyad.radius;
  return a.max_residual < b.max_residual;
}

}  // namespace

double ConditionErrorBound(double condition, double relative_precision,
                           const PlanarMotionOptions& options) {
  // Measured on random four-bars with two nearly coincident poses at full precision (linkfit
  // bench): the dyads' relative error is about condition * 1e-15, at worst condition * 3e-13.
  return std::max(3e-13, options.condition_error_factor * relative_precision) * condition;
}

MechanismReport AnalyzeDyadPair(const std::vector<DyadReport>& dyads, int i, int j,
                                const std::vector<PlanarPose>& poses, double length,
                                const std::vector<bool>& exact, const MechanismReport* screened) {
  const PlanarDyad& a = dyads[i].dyad;
  const PlanarDyad& b = dyads[j].dyad;
  // Screened: the input the screening chose drives, and the other dyad's full rotation is the
  // screening's (one analysis on every pose instead of two).
  FourBarAnalysis a_drives, b_drives;
  bool swap = false;
  if (screened != nullptr) {
    swap = screened->input_dyad == j;
    (swap ? b_drives : a_drives) =
        swap ? AnalyzeFourBar(b, a, poses, length) : AnalyzeFourBar(a, b, poses, length);
  } else {
    a_drives = AnalyzeFourBar(a, b, poses, length);
    b_drives = AnalyzeFourBar(b, a, poses, length);
    swap = BetterAnalysis(b_drives, a_drives);
  }
  const FourBarAnalysis& chosen = swap ? b_drives : a_drives;
  MechanismReport mechanism;
  mechanism.input_dyad = swap ? j : i;
  mechanism.output_dyad = swap ? i : j;
  const PlanarDyad& input = swap ? b : a;
  const PlanarDyad& output = swap ? a : b;
  mechanism.type = ClassifyFourBar(input.type, output.type);
  TakeAnalysis(chosen, swap ? a_drives : b_drives, poses.size() > 5, &mechanism);
  // Minimal data: each pose's error (a four-bar chosen within constraints reports them).
  if (poses.size() <= 5) {
    for (const FourBarLocation& location : chosen.locations) {
      mechanism.pose_errors.push_back(location.pose_error);
    }
  }
  if (screened != nullptr) mechanism.output_rotates_fully = screened->output_rotates_fully;
  if (!mechanism.max_pose_error) {
    mechanism.pose_error_note = "the mechanism does not assemble at the first task pose";
  }
  mechanism.grashof = GrashofType(input, output, length);
  mechanism.cycle = chosen.cycle;
  if (!poses.empty()) {
    std::vector<PlanarPose> configurations;
    double value = 0.0;
    const int count =
        AssembleFourBarAtPose(input, output, poses[0], 1e-9 * length, &configurations, &value);
    mechanism.first_configuration = poses[0];
    for (int l = 0; l < count; ++l) {
      if (l == 0 || PoseError(configurations[l], poses[0], length) <
                        PoseError(*mechanism.first_configuration, poses[0], length)) {
        mechanism.first_configuration = configurations[l];
      }
    }
  }
  if (!poses.empty()) {
    std::vector<Eigen::Vector2d> joints;
    for (const PlanarDyad* dyad : {&input, &output}) {
      if (dyad->type != DyadType::kPR) joints.push_back(dyad->fixed_pivot);
      if (dyad->type != DyadType::kRP) joints.push_back(poses[0].ToFixed(dyad->moving_pivot));
    }
    mechanism.size = JointSpread(joints);
  }
  if (std::find(exact.begin(), exact.end(), true) != exact.end()) {
    if (mechanism.max_pose_error && chosen.locations.size() == poses.size()) {
      double worst = 0.0;
      // A pose off the first pose's circuit is reached only at the largest error's bound.
      for (size_t k = 0; k < poses.size() && k < exact.size(); ++k) {
        if (!exact[k]) continue;
        const FourBarLocation& location = chosen.locations[k];
        worst = std::max(worst, location.circuit == chosen.circuit ? location.pose_error
                                                                   : *mechanism.max_pose_error);
      }
      mechanism.exact_pose_error = worst;
    }
    mechanism.misses_exact = !(mechanism.exact_pose_error &&
                               *mechanism.exact_pose_error <= kExactPoseTolerance * length);
  }
  return mechanism;
}

bool SameDyad(const PlanarDyad& a, const PlanarDyad& b, const DataPrecision& precision,
              double length, const Eigen::Vector2d& center, double bound) {
  if (a.type != b.type) return false;
  // Only what the type has: an RR its pivots and radius, a PR its moving pivot and line in
  // Sigma, an RP its fixed pivot and line in E.
  const bool fixed = a.type != DyadType::kPR, moving = a.type != DyadType::kRP;
  double size = length;
  if (fixed) size = std::max(size, (a.fixed_pivot - center).norm());
  if (moving) size = std::max(size, a.moving_pivot.norm());
  double difference = 0.0;
  if (fixed) difference = std::max(difference, (a.fixed_pivot - b.fixed_pivot).norm());
  if (moving) difference = std::max(difference, (a.moving_pivot - b.moving_pivot).norm());
  if (a.type == DyadType::kRR) {
    difference = std::max(difference, std::abs(a.radius - b.radius));
  } else {
    // The line's nearest point to the centre (a PR's line in Sigma; an RP's in E, about E's
    // origin).
    const Eigen::Vector2d from = a.type == DyadType::kPR ? center : Eigen::Vector2d::Zero();
    const Eigen::Vector2d direction = a.line_direction.normalized();
    const Eigen::Vector2d nearest = a.line_point + (from - a.line_point).dot(direction) * direction;
    size = std::max(size, (nearest - from).norm());
    const Eigen::Vector2d na(-a.line_direction.y(), a.line_direction.x());
    const double sign =
        na.dot(Eigen::Vector2d(-b.line_direction.y(), b.line_direction.x())) < 0 ? -1.0 : 1.0;
    difference = std::max({difference, size * (a.line_direction - sign * b.line_direction).norm(),
                           std::abs(na.dot(b.line_point - a.line_point))});
  }
  return difference <= SameDesignTolerance(precision, size, length, 2, bound, 1e-7);
}

double PoseFitTolerance(const DataPrecision& precision, double length) {
  return std::max(1e-8 * length, kModelUnits * PointUncertainty(precision, length, length, 2));
}

void JudgeMechanism(const Task& task, const std::vector<DyadReport>& dyads, double length,
                    MechanismReport* mechanism) {
  const DyadReport& input_report = dyads[mechanism->input_dyad];
  const DyadReport& output_report = dyads[mechanism->output_dyad];
  const PlanarDyad& input = input_report.dyad;
  const PlanarDyad& output = output_report.dyad;
  FourBarClass kind;
  kind.type = mechanism->type;
  kind.grashof = mechanism->grashof;
  kind.input_rotates_fully = mechanism->input_rotates_fully;
  mechanism->violates = MotionViolations(task.constraints, input, output, kind, length);
  std::vector<std::string>& defects = mechanism->defects;
  // A link the data cannot resolve (issue 35): no longer than how far their precision can move
  // its pivots (the dyads' finite error bounds) plus kModelUnits of the data's rounding. And two
  // dyads fitted toward one (a least-squares fit's coupler and ground both no longer than its
  // RMS pose error: the poses scatter about the fit by more than either, and the coupler keeps a
  // second freedom that fits anything); a single short link of a fit of many poses can be well
  // determined, so the scatter alone does not judge it.
  const auto bound = [](const DyadReport& report) {
    return report.error_bound && std::isfinite(*report.error_bound) ? *report.error_bound : 0.0;
  };
  const double rounding = kModelUnits * task.precision.length;
  const FourBarLinks links = MotionFourBarLinks(input, output);
  const auto unresolved = [&](const std::optional<double>& link, double moves) {
    return link && *link <= moves + rounding;
  };
  const auto within = [](const std::optional<double>& link, const std::optional<double>& scatter) {
    return link && scatter && *link <= *scatter;
  };
  const bool coinciding = within(links.coupler, mechanism->rms_pose_error) &&
                          within(links.ground, mechanism->rms_pose_error);
  if (coinciding || unresolved(links.coupler, bound(input_report) + bound(output_report)) ||
      unresolved(links.ground, bound(input_report) + bound(output_report)) ||
      unresolved(links.input, bound(input_report)) ||
      unresolved(links.output, bound(output_report))) {
    AddDefect("degenerate", &defects);
  }
  // Minimal data (five poses or fewer) are met exactly by every dyad: a four-bar that misses
  // them by more than their precision on its one circuit and branch does not do the task (one
  // linkfit chose misses a pose by design: that is its fit).
  if (task.planar_poses.size() <= 5 && mechanism->chosen.empty()) {
    JudgeMisses(mechanism->max_pose_error, PoseFitTolerance(task.precision, length), &defects);
  }
  JudgeTransmission(task.constraints, mechanism->transmission_min_deg, &defects);
}

namespace {

// Two distinct PR dyads (or two distinct RP dyads) among five poses' roots, a circle counting
// as its slider reading when that fits the poses within their precision (SimplerModel): two
// points of E run on lines of Sigma (RP: two points of Sigma on lines of E), which only an
// elliptic trammel's motion allows, and that motion has a whole circle of such points.
// Distinct: at least 0.1 L apart (their error bounds are no guide: near such a family the poses
// barely determine the isolated roots rounding leaves).
bool CardanWithinPrecision(const std::vector<DyadReport>& dyads,
                           const std::vector<PlanarPose>& poses, const DataPrecision& precision,
                           double length) {
  std::vector<PlanarDyad> sliders;
  for (const DyadReport& report : dyads) {
    PlanarDyad slider = report.dyad;
    if (slider.type == DyadType::kRR &&
        !SimplerModel(report.dyad, poses, precision, length, &slider)) {
      continue;
    }
    sliders.push_back(slider);
  }
  for (size_t a = 0; a < sliders.size(); ++a) {
    for (size_t b = a + 1; b < sliders.size(); ++b) {
      const PlanarDyad& first = sliders[a];
      const PlanarDyad& second = sliders[b];
      if (first.type != second.type) continue;
      const double apart = first.type == DyadType::kPR
                               ? (first.moving_pivot - second.moving_pivot).norm()
                               : (first.fixed_pivot - second.fixed_pivot).norm();
      if (apart >= 0.1 * length) return true;
    }
  }
  return false;
}

}  // namespace

// Five poses (exact) or more (the algebraic least-squares seed).
void SolveFivePosesOrMore(const Task& task, const PlanarMotionOptions& options,
                          PlanarMotionResult* result) {
  const std::vector<PlanarPose>& poses = task.planar_poses;
  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary summary;
  SolvePlanarBurmester(poses, options.burmester, &dyads, &summary);
  result->roots_total = summary.roots_total;
  result->roots_real = summary.roots_real;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  const double relative = RelativePrecision(task.precision, length);
  if (summary.degenerate) {
    result->notes.push_back(
        "the pose constraints are dependent within the data's precision (relative " +
        Format("%.2g", relative) + "; ill-conditioned: condition estimate " +
        Format("%.3g", summary.condition) +
        "): the poses admit a family of dyads, not isolated ones (e.g. all poses of one "
        "orientation, or two poses nearly coincident)");
  } else if (poses.size() == 5) {
    const double bound = ConditionErrorBound(summary.condition, relative, options);
    if (summary.condition > options.ill_conditioned || bound > options.error_note) {
      const std::string prefix =
          summary.condition > options.ill_conditioned
              ? "ill-conditioned: the five poses nearly admit a family of dyads; "
              : "";
      const std::string note = prefix + ConditionNote(summary.condition, relative, bound);
      result->notes.push_back(note);
    }
  }
  for (const PlanarDyad& dyad : dyads) {
    DyadReport report(dyad, dyad.MaxResidual(poses));
    report.error_bound = DyadErrorBound(dyad, poses, task.precision, length);
    result->dyads.push_back(report);
  }
  if (poses.size() == 5 && !summary.degenerate && relative > 1e-12 &&
      CardanWithinPrecision(result->dyads, poses, task.precision, length)) {
    // Two points of E run on lines within the data's precision: the poses are an elliptic
    // trammel's (the Cardan motion, or its inversion for RP), whose slider dyads form a
    // family. The rounded data only break that family into a few isolated roots.
    result->dyads.clear();
    result->notes.push_back(
        "the pose constraints are dependent within the data's precision (relative " +
        Format("%.2g", relative) +
        "): two points run on straight lines within it, so the poses are the Cardan motion of "
        "an elliptic trammel, where every point of a circle runs on a line: a family of slider "
        "dyads, not isolated ones");
    return;
  }
  std::sort(result->dyads.begin(), result->dyads.end(), DyadBefore);
  if (poses.size() > 5 && !summary.degenerate) {
    result->notes.push_back(
        "more than five poses: the dyads are the algebraic least-squares seed (RMS algebraic "
        "residual " +
        Format("%.3g", summary.fit_residual) +
        " in normalized units); geometric refinement is not applied");
  }
  if (!summary.degenerate && summary.roots_total > 0) {
    const int complex_roots = summary.roots_total - summary.roots_real;
    if (summary.real_within_precision > 0) {
      result->notes.push_back(
          std::to_string(summary.real_within_precision) + " of the " +
          std::to_string(summary.roots_total) +
          " Burmester roots are complex but real within the data's precision (rounding turns two "
          "nearby dyads into a complex pair): their real parts fit the poses within it and are "
          "listed");
    }
    if (complex_roots > summary.real_within_precision) {
      result->notes.push_back(std::to_string(complex_roots - summary.real_within_precision) +
                              " of the " + std::to_string(summary.roots_total) +
                              " Burmester roots are complex and were dropped");
    }
  }
}

// Three or four poses: the dyads of the chosen pivots (or, for three poses without pivots, of
// default ones) and, for four poses, the Burmester curves.
void SolveFewPoses(const Task& task, PlanarMotionResult* result) {
  const std::vector<PlanarPose>& poses = task.planar_poses;
  std::string note;
  PlanarDyad dyad;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  // Each with its error bound, the pivot held (model_choice.h PivotDyadErrorBound).
  bool moving_given = true;
  auto add = [&](bool ok, const std::string& what) {
    if (ok) {
      DyadReport report{dyad, dyad.MaxResidual(poses)};
      report.error_bound = PivotDyadErrorBound(dyad, poses, task.precision, length, moving_given);
      result->dyads.push_back(report);
    }
    if (!ok) result->notes.push_back(what + ": no dyad");
    if (!note.empty()) result->notes.push_back(what + ": " + note);
    note.clear();
  };
  for (size_t i = 0; i < task.moving_pivots.size(); ++i) {
    add(DyadFromMovingPivot(poses, task.moving_pivots[i], &dyad, &note),
        "moving_pivots[" + std::to_string(i) + "]");
  }
  moving_given = false;
  for (size_t i = 0; i < task.fixed_pivots.size(); ++i) {
    add(DyadFromFixedPivot(poses, task.fixed_pivots[i], &dyad, &note),
        "fixed_pivots[" + std::to_string(i) + "]");
  }
  const bool pivots_given = !task.moving_pivots.empty() || !task.fixed_pivots.empty();
  if (poses.size() == 3 && !pivots_given) {
    Eigen::Vector2d pivots[2];
    std::string explanation;
    DefaultMovingPivots(poses, pivots, &explanation);
    result->notes.push_back(explanation);
    moving_given = true;
    for (int i = 0; i < 2; ++i)
      add(DyadFromMovingPivot(poses, pivots[i], &dyad, &note), "default pivot");
  }
  if (poses.size() == 4) {
    BurmesterCurves curves;
    SampleBurmesterCurves(poses, BurmesterCurveOptions(), &curves);
    // A PR dyad's center point and an RP dyad's circle point are at infinity: the polylines
    // break there.
    for (const std::vector<PlanarDyad>& branch : curves.branches) {
      std::vector<Eigen::Vector2d> centers, circles;
      auto flush = [](std::vector<Eigen::Vector2d>* polyline,
                      std::vector<std::vector<Eigen::Vector2d>>* out) {
        if (polyline->size() > 1) out->push_back(*polyline);
        polyline->clear();
      };
      for (const PlanarDyad& sample : branch) {
        if (sample.type == DyadType::kRR) {
          centers.push_back(sample.fixed_pivot);
        } else {
          flush(&centers, &result->center_point_curves);
        }
        if (sample.type != DyadType::kRP) {
          circles.push_back(sample.moving_pivot);
        } else {
          flush(&circles, &result->circle_point_curves);
        }
      }
      flush(&centers, &result->center_point_curves);
      flush(&circles, &result->circle_point_curves);
    }
    if (!pivots_given) {
      result->notes.push_back(
          "four poses admit a one-parameter family of dyads (burmester_curves): give "
          "\"moving_pivots\" on the circle-point curve (in the body frame) or \"fixed_pivots\" on "
          "the center-point curve to choose the pivots yourself");
    }
  }
}

RankKey MechanismRankKey(const MechanismReport& mechanism, double precision_fit,
                         const DesignConstraints& constraints) {
  RankKey key;
  key.within_precision = mechanism.max_pose_error && *mechanism.max_pose_error <= precision_fit;
  key.fit_floor = 1e-3 * precision_fit;
  key.parameters = FourBarParameters(mechanism.type);
  key.misses_exact = mechanism.misses_exact;
  key.size = mechanism.size;
  key.fit = mechanism.rms_pose_error ? mechanism.rms_pose_error : mechanism.max_pose_error;
  // Not assembling at the first pose, it cannot be driven through the poses at all.
  JudgeWithDefaults(constraints, mechanism.violates, mechanism.defects,
                    mechanism.max_pose_error.has_value(), &key);
  key.transmission_min_deg = TransmissionTieBreak(constraints, mechanism.transmission_min_deg);
  return key;
}

int RankMechanisms(double precision_fit, const DesignConstraints& constraints, int bound,
                   std::vector<MechanismReport>* mechanisms) {
  return RankReports(
      [precision_fit, &constraints](const MechanismReport& mechanism) {
        return MechanismRankKey(mechanism, precision_fit, constraints);
      },
      bound, mechanisms);
}

namespace {

// Above this many poses, BuildMechanisms ranks the dyad pairs on this many spread poses first
// and analyses on every pose only the best of them: the analysis costs a pose assembly per pose,
// pair and input (about 2 us), and 90 of them at 100,000 poses took 18 s.
constexpr size_t kScreenPoses = 2000;
// Of the screened pairs, those analysed on every pose: the first this many of the ranking,
// the first kScreenKeptPerLevel of each effort level, and the best fit of each level and of each
// group of the ranking rule.
constexpr int kScreenKept = 12;
constexpr int kScreenKeptPerLevel = 4;

}  // namespace

void BuildMechanisms(const Task& task, double length, PlanarMotionResult* result,
                     const std::function<int(int, int)>& levels) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double precision_fit = PoseFitTolerance(task.precision, length);
  std::vector<std::pair<int, int>> pairs;
  for (size_t i = 0; i < result->dyads.size(); ++i) {
    for (size_t j = i + 1; j < result->dyads.size(); ++j) {
      if (levels && levels(static_cast<int>(i), static_cast<int>(j)) == 0) continue;
      pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  }
  const auto analyse = [&](int i, int j, const std::vector<PlanarPose>& on,
                           const std::vector<bool>& exact,
                           const MechanismReport* screened = nullptr) {
    MechanismReport mechanism = AnalyzeDyadPair(result->dyads, i, j, on, length, exact, screened);
    JudgeMechanism(task, result->dyads, length, &mechanism);
    return mechanism;
  };
  result->mechanisms.clear();
  if (poses.size() <= kScreenPoses || pairs.size() <= static_cast<size_t>(kScreenKept)) {
    for (const auto& [i, j] : pairs) {
      result->mechanisms.push_back(analyse(i, j, poses, task.pose_exact));
    }
  } else {
    // Screening: every pair on the spread poses, ranked; the kept ones on every pose.
    std::vector<PlanarPose> screen_poses;
    std::vector<bool> screen_exact;
    for (const size_t j : SpreadIndices(poses.size(), kScreenPoses, task.pose_exact)) {
      screen_poses.push_back(poses[j]);
      screen_exact.push_back(j < task.pose_exact.size() && task.pose_exact[j]);
    }
    std::vector<MechanismReport> screened;
    for (const auto& [i, j] : pairs) screened.push_back(analyse(i, j, screen_poses, screen_exact));
    std::vector<RankKey> keys;
    for (const MechanismReport& mechanism : screened) {
      keys.push_back(MechanismRankKey(mechanism, precision_fit, task.constraints));
    }
    const std::vector<int> order = RankOrder(keys);
    std::vector<bool> keep(screened.size(), false);
    std::vector<RankKey> ranked_keys;
    for (const int index : order) ranked_keys.push_back(keys[index]);
    for (const int position : ListedWithinBound(ranked_keys, kScreenKept)) {
      keep[order[position]] = true;
    }
    const int level_count = levels ? 3 : 1;
    for (int level = 0; level < level_count; ++level) {
      int taken = 0;
      int best_fit = -1;
      for (const int index : order) {
        const auto& [i, j] = pairs[index];
        if (levels && !(levels(i, j) >> level & 1)) continue;
        if (taken < kScreenKeptPerLevel) {
          keep[index] = true;
          ++taken;
        }
        const auto fit = [&](int k) {
          return screened[k].rms_pose_error.value_or(
              screened[k].max_pose_error.value_or(std::numeric_limits<double>::infinity()));
        };
        if (best_fit < 0 || fit(index) < fit(best_fit)) best_fit = index;
      }
      if (best_fit >= 0) keep[best_fit] = true;
    }
    int kept = 0;
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (!keep[k]) continue;
      ++kept;
      result->mechanisms.push_back(
          analyse(pairs[k].first, pairs[k].second, poses, task.pose_exact, &screened[k]));
    }
    result->notes.push_back(
        std::to_string(poses.size()) + " poses: the four-bars of " + std::to_string(pairs.size()) +
        " dyad pairs were ranked on " + std::to_string(screen_poses.size()) +
        " spread poses first, and the best " + std::to_string(kept) + " analysed on every pose");
  }
  RankMechanisms(precision_fit, task.constraints, -1, &result->mechanisms);
  result->analysis_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<size_t> SpreadIndices(size_t count, size_t wanted, const std::vector<bool>& exact) {
  std::vector<size_t> chosen;
  if (count == 0) return chosen;
  if (wanted < 2 || wanted >= count) {
    for (size_t j = 0; j < count; ++j) chosen.push_back(j);
    return chosen;
  }
  for (size_t k = 0; k < wanted; ++k) {
    chosen.push_back(
        static_cast<size_t>(std::llround(static_cast<double>(k) * static_cast<double>(count - 1) /
                                         static_cast<double>(wanted - 1))));
  }
  for (size_t j = 0; j < count && j < exact.size(); ++j) {
    if (exact[j]) chosen.push_back(j);
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

std::vector<std::vector<int>> SpreadSubsets(int count, int subsets, int size) {
  std::vector<std::vector<int>> out;
  for (int k = 0; k < subsets; ++k) {
    std::vector<int> subset;
    for (int i = 0; i < size; ++i) {
      const int index = static_cast<int>(std::lround((i + static_cast<double>(k) / subsets) *
                                                     count / static_cast<double>(size))) %
                        count;
      if (std::find(subset.begin(), subset.end(), index) == subset.end()) subset.push_back(index);
    }
    std::sort(subset.begin(), subset.end());
    if (static_cast<int>(subset.size()) == size &&
        std::find(out.begin(), out.end(), subset) == out.end()) {
      out.push_back(subset);
    }
  }
  return out;
}

std::vector<std::vector<int>> SeedSubsets(int count, int subsets, const std::vector<bool>& exact,
                                          int size) {
  std::vector<int> exact_indices, others;
  for (int j = 0; j < count; ++j) {
    (j < static_cast<int>(exact.size()) && exact[j] ? exact_indices : others).push_back(j);
  }
  if (exact_indices.empty()) return SpreadSubsets(count, subsets, size);
  const int free = size - static_cast<int>(exact_indices.size());
  const std::vector<int>& drawn = free > 0 ? others : exact_indices;
  std::vector<std::vector<int>> out;
  if (free == 0) return {exact_indices};
  for (const std::vector<int>& subset :
       SpreadSubsets(static_cast<int>(drawn.size()), subsets, free > 0 ? free : size)) {
    std::vector<int> chosen = free > 0 ? exact_indices : std::vector<int>();
    for (const int k : subset) chosen.push_back(drawn[k]);
    std::sort(chosen.begin(), chosen.end());
    out.push_back(chosen);
  }
  return out;
}

int PlanarSeeds(const std::vector<PlanarPose>& poses, const PlanarBurmesterOptions& options,
                int subsets, std::vector<PlanarDyad>* seeds, const std::vector<bool>& exact) {
  seeds->clear();
  const double length = CharacteristicLength(poses);
  const auto add = [&](const std::vector<PlanarDyad>& found) {
    for (const PlanarDyad& dyad : found) {
      bool repeat = false;
      for (const PlanarDyad& seed : *seeds) {
        repeat |= seed.type == dyad.type &&
                  (seed.fixed_pivot - dyad.fixed_pivot).norm() <= 1e-9 * length &&
                  (seed.moving_pivot - dyad.moving_pivot).norm() <= 1e-9 * length &&
                  (seed.line_point - dyad.line_point).norm() <= 1e-9 * length;
      }
      if (!repeat) seeds->push_back(dyad);
    }
  };
  std::vector<PlanarDyad> found;
  SolvePlanarBurmester(poses, options, &found);
  add(found);
  if (poses.size() > 5) {
    for (const std::vector<int>& subset :
         SeedSubsets(static_cast<int>(poses.size()), subsets, exact)) {
      std::vector<PlanarPose> chosen;
      for (int index : subset) chosen.push_back(poses[index]);
      SolvePlanarBurmester(chosen, options, &found);
      add(found);
    }
  }
  return static_cast<int>(seeds->size());
}

PlanarMotionResult SolvePlanarMotion(const Task& task, const PlanarMotionOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PlanarMotionResult result;
  const std::vector<PlanarPose>& poses = task.planar_poses;
  const double length = task.scale ? *task.scale : CharacteristicLength(poses);
  result.scale = length;
  result.constraints = task.constraints;
  result.method = poses.size() <= 5 ? "exact" : "least-squares";
  PlanarMotionOptions at_precision = options;
  at_precision.burmester.precision = task.precision;
  if (poses.size() < 5) {
    SolveFewPoses(task, &result);
  } else {
    SolveFivePosesOrMore(task, at_precision, &result);
  }

  BuildMechanisms(task, length, &result);
  if (result.dyads.empty() && result.notes.empty()) {
    result.notes.push_back("no real dyad guides the body through these poses");
  } else if (result.dyads.size() == 1) {
    result.notes.push_back("only one real dyad: no four-bar");
  }
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace linkfit
