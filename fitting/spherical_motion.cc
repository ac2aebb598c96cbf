#include "fitting/spherical_motion.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "fitting/model_choice.h"
#include "fitting/planar_motion.h"
#include "lib/design_constraints.h"
#include "lib/text_format.h"

namespace linkfit {
namespace {

std::string VectorText(const Eigen::Vector3d& x) {
  return "[" + Format("%.6g", x.x()) + ", " + Format("%.6g", x.y()) + ", " + Format("%.6g", x.z()) +
         "]";
}

std::vector<double> TaskWeights(const Task& task) {
  return task.pose_weights.size() == task.spatial_poses.size()
             ? task.pose_weights
             : std::vector<double>(task.spatial_poses.size(), 1.0);
}

// Dyads chosen by their axes (three or four orientations), one per axis.
void AxisDyads(const Task& task, const SphericalMotion& motion, const std::vector<double>& weights,
               SpatialMotionResult* result) {
  for (int side = 0; side < 2; ++side) {
    const bool moving = side == 0;
    const std::vector<Eigen::Vector3d>& axes = moving ? task.moving_axes : task.fixed_axes;
    for (const Eigen::Vector3d& axis : axes) {
      SphericalDyad dyad;
      double moved_deg = 0.0;
      const bool found =
          moving ? SphericalDyadFromMovingAxis(motion.rotations, weights, axis, &dyad, &moved_deg)
                 : SphericalDyadFromFixedAxis(motion.rotations, weights, axis, &dyad, &moved_deg);
      const char* which = moving ? "moving axis " : "fixed axis ";
      if (!found) {
        result->notes.push_back(std::string(which) + VectorText(axis) +
                                ": its positions do not determine a circle of the sphere (it "
                                "barely moves, or could not be moved onto its cone)");
        continue;
      }
      if (moved_deg > 1e-6) {
        result->notes.push_back(std::string(which) + VectorText(axis) + " moved by " +
                                Format("%.3g", moved_deg) + " deg onto the " +
                                (moving ? "circle-axis" : "center-axis") +
                                " cone of the four orientations");
      }
      result->spherical_dyads.push_back(ReportSphericalDyad(dyad, motion, weights, task.precision));
    }
  }
}

}  // namespace

SphericalMotion TaskSphericalMotion(const Task& task, const SphericalCenter& center,
                                    double length) {
  return MakeSphericalMotion(task.spatial_poses, center.in_moving, center.in_fixed, length);
}

bool SameSphericalDyad(const SphericalDyad& a, const SphericalDyad& b, double tolerance) {
  return SphericalDyadDistance(a, b) <= tolerance;
}

SphericalDyadReport ReportSphericalDyad(const SphericalDyad& dyad, const SphericalMotion& motion,
                                        const std::vector<double>& weights,
                                        const DataPrecision& precision) {
  SphericalDyadReport report;
  report.dyad = dyad;
  double worst = 0.0, sum = 0.0, total = 0.0;
  for (size_t j = 0; j < motion.rotations.size(); ++j) {
    const double residual = dyad.Residual(motion.rotations[j]);
    const double weight = j < weights.size() ? weights[j] : 1.0;
    worst = std::max(worst, std::abs(residual));
    sum += weight * residual * residual;
    total += weight;
  }
  report.max_residual = motion.length * worst;
  if (motion.rotations.size() > 5 && total > 0.0) {
    report.rms_residual = motion.length * std::sqrt(sum / total);
  }
  report.error_bound = DyadErrorBound(dyad, motion.rotations, precision);
  return report;
}

int SphericalSeeds(const std::vector<Eigen::Matrix3d>& rotations,
                   const std::vector<double>& weights, const SphericalBurmesterOptions& options,
                   int subsets, std::vector<SphericalDyad>* seeds,
                   SphericalBurmesterSummary* summary) {
  seeds->clear();
  const auto add = [&](const std::vector<SphericalDyad>& found) {
    for (const SphericalDyad& dyad : found) {
      bool repeat = false;
      for (const SphericalDyad& seed : *seeds) repeat |= SameSphericalDyad(seed, dyad, 1e-9);
      if (!repeat) seeds->push_back(dyad);
    }
  };
  std::vector<SphericalDyad> found;
  SolveSphericalBurmester(rotations, weights, options, &found, summary);
  add(found);
  const int n = static_cast<int>(rotations.size());
  if (n > 5) {
    for (const std::vector<int>& subset : SpreadSubsets(n, subsets)) {
      std::vector<Eigen::Matrix3d> chosen;
      std::vector<double> chosen_weights;
      for (int index : subset) {
        chosen.push_back(rotations[index]);
        chosen_weights.push_back(index < static_cast<int>(weights.size()) ? weights[index] : 1.0);
      }
      SolveSphericalBurmester(chosen, chosen_weights, options, &found);
      add(found);
    }
  }
  return static_cast<int>(seeds->size());
}

// Above this many orientations, BuildSphericalMechanisms ranks the dyad pairs on this many
// spread orientations first and analyses on every one only the best kScreenKept (and the best
// of each group): as planar four-bars (fitting/planar_motion.cc BuildMechanisms).
constexpr size_t kScreenOrientations = 2000;
constexpr int kScreenKept = 12;

MechanismReport AnalyzeSphericalPair(const std::vector<SphericalDyadReport>& dyads, int i, int j,
                                     const SphericalMotion& motion,
                                     const DesignConstraints& constraints,
                                     const MechanismReport* screened) {
  const SphericalFourBar a_drives = MakeSphericalFourBar(dyads[i].dyad, dyads[j].dyad);
  const SphericalFourBar b_drives = MakeSphericalFourBar(dyads[j].dyad, dyads[i].dyad);
  // Screened: the screening's input drives (as planar AnalyzeDyadPair).
  SphericalFourBarAnalysis a_analysis, b_analysis;
  bool swap = false;
  if (screened != nullptr) {
    swap = screened->input_dyad == j;
    (swap ? b_analysis : a_analysis) = AnalyzeSphericalFourBar(swap ? b_drives : a_drives, motion);
  } else {
    a_analysis = AnalyzeSphericalFourBar(a_drives, motion);
    b_analysis = AnalyzeSphericalFourBar(b_drives, motion);
    swap = BetterAnalysis(b_analysis, a_analysis);
  }
  const SphericalFourBarAnalysis& chosen = swap ? b_analysis : a_analysis;
  const SphericalFourBar& four_bar = swap ? b_drives : a_drives;
  MechanismReport mechanism;
  mechanism.type = FourBarType::k4R;
  mechanism.input_dyad = swap ? j : i;
  mechanism.output_dyad = swap ? i : j;
  TakeAnalysis(chosen, swap ? a_analysis : b_analysis, motion.rotations.size() > 5, &mechanism);
  if (screened != nullptr) mechanism.output_rotates_fully = screened->output_rotates_fully;
  if (!mechanism.max_pose_error) {
    mechanism.pose_error_note = four_bar.valid
                                    ? "the mechanism does not assemble at the first task pose"
                                    : four_bar.invalid_note;
  }
  if (four_bar.valid && !motion.rotations.empty()) {
    // The configuration nearest the first orientation: where the result's "linkage" shows it.
    Eigen::Matrix3d rotations[2];
    double input_angle = 0.0;
    const int count =
        AssembleSphericalFourBarAt(four_bar, motion.rotations[0], 1e-9, rotations, &input_angle);
    mechanism.first_rotation = motion.rotations[0];
    for (int l = 0; l < count; ++l) {
      if (l == 0 || (rotations[l] - motion.rotations[0]).norm() <
                        (*mechanism.first_rotation - motion.rotations[0]).norm()) {
        mechanism.first_rotation = rotations[l];
      }
    }
  }
  if (four_bar.valid) {
    mechanism.grashof = SphericalGrashofType(four_bar);
    // Its size for the ranking's last tie-break (lib/design_constraints.h): its four links'
    // arcs on the sphere of radius L.
    mechanism.size = motion.length * (four_bar.ground + four_bar.input.angle + four_bar.coupler +
                                      four_bar.output.angle);
  }
  FourBarClass kind;
  kind.type = mechanism.type;
  kind.grashof = mechanism.grashof;
  kind.input_rotates_fully = mechanism.input_rotates_fully;
  ClassViolations(constraints, kind, &mechanism.violates);
  JudgeTransmission(constraints, mechanism.transmission_min_deg, &mechanism.defects);
  return mechanism;
}

// The defects of minimal data (issue 35, as planar JudgeMechanism): "degenerate" when a link (an
// angle between axes) is no larger than the data's precision can resolve (the dyads' error
// bounds and kModelUnits of the angle precision), "misses" when five orientations or fewer are
// missed by more than `precision_fit` with no kinematic defect to say why.
void JudgeMinimal(const std::vector<SphericalDyadReport>& dyads, size_t orientations,
                  double precision_fit, const DataPrecision& precision,
                  MechanismReport* mechanism) {
  const SphericalDyadReport& input = dyads[mechanism->input_dyad];
  const SphericalDyadReport& output = dyads[mechanism->output_dyad];
  const auto bound = [](const SphericalDyadReport& report) {
    return report.error_bound && std::isfinite(*report.error_bound) ? *report.error_bound : 0.0;
  };
  const auto between = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double angle = DirectionAngle(a, b);
    return std::min(angle, M_PI - angle);  // an axis is a line: its two directions are one
  };
  const double rounding = kModelUnits * precision.angle;
  const double both = bound(input) + bound(output) + rounding;
  std::vector<std::string>& defects = mechanism->defects;
  if (between(input.dyad.fixed_axis, output.dyad.fixed_axis) <= both ||
      between(input.dyad.moving_axis, output.dyad.moving_axis) <= both ||
      std::min(input.dyad.angle, M_PI - input.dyad.angle) <= bound(input) + rounding ||
      std::min(output.dyad.angle, M_PI - output.dyad.angle) <= bound(output) + rounding) {
    AddDefect("degenerate", &defects);
  }
  if (orientations <= 5) JudgeMisses(mechanism->max_pose_error, precision_fit, &defects);
}

void BuildSphericalMechanisms(const Task& task, const SphericalMotion& motion,
                              SpatialMotionResult* result, int bound) {
  const auto start = std::chrono::steady_clock::now();
  result->spherical_mechanisms.clear();
  const int count = static_cast<int>(result->spherical_dyads.size());
  const double precision_fit = PoseFitTolerance(task.precision, motion.length);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) pairs.emplace_back(i, j);
  }
  const size_t orientations = motion.rotations.size();
  if (orientations <= kScreenOrientations || pairs.size() <= static_cast<size_t>(kScreenKept)) {
    for (const auto& [i, j] : pairs) {
      result->spherical_mechanisms.push_back(
          AnalyzeSphericalPair(result->spherical_dyads, i, j, motion, task.constraints));
    }
  } else {
    // As planar four-bars (BuildMechanisms): every pair ranked on spread orientations first, the
    // best analysed on every orientation.
    SphericalMotion screen = motion;
    screen.rotations.clear();
    screen.translations.clear();
    for (const size_t k : SpreadIndices(orientations, kScreenOrientations, task.pose_exact)) {
      screen.rotations.push_back(motion.rotations[k]);
      if (k < motion.translations.size()) screen.translations.push_back(motion.translations[k]);
    }
    std::vector<MechanismReport> screened;
    std::vector<RankKey> keys;
    for (const auto& [i, j] : pairs) {
      screened.push_back(
          AnalyzeSphericalPair(result->spherical_dyads, i, j, screen, task.constraints));
      keys.push_back(MechanismRankKey(screened.back(), precision_fit, task.constraints));
    }
    const std::vector<int> order = RankOrder(keys);
    std::vector<RankKey> ranked;
    for (const int index : order) ranked.push_back(keys[index]);
    std::vector<bool> keep(pairs.size(), false);
    for (const int position : ListedWithinBound(ranked, std::max(bound, kScreenKept))) {
      keep[order[position]] = true;
    }
    int kept = 0;
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (!keep[k]) continue;
      ++kept;
      result->spherical_mechanisms.push_back(
          AnalyzeSphericalPair(result->spherical_dyads, pairs[k].first, pairs[k].second, motion,
                               task.constraints, &screened[k]));
    }
    result->notes.push_back(std::to_string(orientations) + " orientations: the four-bars of " +
                            std::to_string(pairs.size()) + " dyad pairs were ranked on " +
                            std::to_string(screen.rotations.size()) +
                            " spread orientations first, and the best " + std::to_string(kept) +
                            " analysed on every orientation");
  }
  for (MechanismReport& mechanism : result->spherical_mechanisms) {
    JudgeMinimal(result->spherical_dyads, orientations, precision_fit, task.precision, &mechanism);
  }
  const int dropped =
      RankMechanisms(precision_fit, task.constraints, bound, &result->spherical_mechanisms);
  if (dropped > 0) result->notes.push_back(DroppedNote(dropped));
  result->analysis_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SolveSphericalMotion(const Task& task, const SphericalCenter& center,
                          const SphericalMotionOptions& options, SpatialMotionResult* result) {
  result->model = "spherical";
  result->spherical = center;
  result->constraints = task.constraints;
  const SphericalMotion motion = TaskSphericalMotion(task, center, result->scale);
  const std::vector<double> weights = TaskWeights(task);
  const int n = static_cast<int>(motion.rotations.size());
  result->notes.push_back(
      "the poses are a spherical motion: every displacement fixes the point " +
      VectorText(center.in_fixed) + " of the fixed frame (largest deviation " +
      Format("%.3g", center.sphericity) +
      ", within the data's precision); solved as spherical, every joint axis through it");
  if (!task.moving_axes.empty() || !task.fixed_axes.empty()) {
    result->method = "exact";
    AxisDyads(task, motion, weights, result);
  } else if (n < 5) {
    result->method = "exact";
    if (n == 4) {
      SphericalBurmesterCones cones;
      if (SampleSphericalBurmesterCones(motion.rotations, options.cone_samples, &cones)) {
        result->center_axis_curves = cones.center_axes;
        result->circle_axis_curves = cones.circle_axes;
      }
      result->notes.push_back(
          "four orientations leave a one-parameter family of spherical dyads: their fixed axes "
          "form the center-axis cone and their moving axes the circle-axis cone "
          "(burmester_cones); give \"moving_axes\" or \"fixed_axes\" to pick dyads from it");
    } else {
      result->notes.push_back(
          std::to_string(n) + " orientations leave a " + std::to_string(5 - n) +
          "-parameter family of spherical dyads (five determine them); give \"moving_axes\" or "
          "\"fixed_axes\" (three or four orientations) to pick dyads from it");
    }
  } else {
    std::vector<SphericalDyad> dyads;
    SphericalBurmesterSummary summary;
    SphericalBurmesterOptions burmester = options.burmester;
    burmester.precision = task.precision;
    SphericalSeeds(motion.rotations, weights, burmester, n == 5 ? 0 : options.seed_subsets, &dyads,
                   &summary);
    result->method = n == 5 ? "exact" : "least-squares";
    result->roots_total = summary.roots_total;
    result->roots_real = summary.roots_real;
    result->condition = summary.condition;
    if (summary.degenerate) {
      result->notes.push_back(
          "the spherical constraint equations are rank-deficient (condition " +
          Format("%.3g", summary.condition) +
          "): the orientations admit a family of dyads, not finitely many (rotations about one "
          "axis, or repeated orientations, do this)");
    }
    if (summary.nearly_real > 0) {
      result->notes.push_back(std::to_string(summary.nearly_real) +
                              " complex roots are nearly real: ill-conditioned near a double "
                              "root, where rounding can turn two real dyads into a complex pair");
    }
    if (summary.real_within_precision > 0) {
      result->notes.push_back(std::to_string(summary.real_within_precision) +
                              " complex roots are real within the data's precision (rounding "
                              "turns two nearby dyads into a complex pair): their real parts, "
                              "fitted to the orientations, fit them within it and are listed");
    }
    for (const SphericalDyad& dyad : dyads) {
      result->spherical_dyads.push_back(ReportSphericalDyad(dyad, motion, weights, task.precision));
    }
    std::stable_sort(result->spherical_dyads.begin(), result->spherical_dyads.end(),
                     [](const SphericalDyadReport& a, const SphericalDyadReport& b) {
                       return a.dyad.angle < b.dyad.angle;
                     });
    if (result->spherical_dyads.empty() && !summary.degenerate) {
      result->notes.push_back("no real spherical dyad: all roots are complex");
    }
  }
  if (result->method != "least-squares" || options.seed_mechanisms) {
    BuildSphericalMechanisms(task, motion, result);
  }
}

}  // namespace linkfit
