#include "lib/design_constraints.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <tuple>

#include "lib/path_motion.h"

namespace linkfit {

bool InBox(const PlanarBox& box, const Eigen::Vector2d& point, double slack) {
  return point.x() >= box.min.x() - slack && point.x() <= box.max.x() + slack &&
         point.y() >= box.min.y() - slack && point.y() <= box.max.y() + slack;
}

void ClassViolations(const DesignConstraints& constraints, const FourBarClass& kind,
                     std::vector<std::string>* violates) {
  if (constraints.input_rotates_fully && !kind.input_rotates_fully) {
    violates->push_back("input_rotates_fully");
  }
  if (!constraints.grashof.empty() &&
      !(kind.type == FourBarType::k4R && GrashofClassKeeps(constraints.grashof, kind.grashof))) {
    violates->push_back("grashof");
  }
}

namespace {

// A link within this fraction of the default link limit is at it (CommonViolations).
constexpr double kAtDefaultLimit = 1e-4;

// The violations of link lengths (`all`) and the fixed pivots' box, appended in that order.
void LinkViolations(const DesignConstraints& constraints, const std::vector<double>& all,
                    const std::vector<Eigen::Vector2d>& fixed_pivots, double length,
                    std::vector<std::string>* violates) {
  const double slack = kConstraintSlack * length;
  const double longest = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
  const double shortest = all.empty() ? std::numeric_limits<double>::infinity()
                                      : *std::min_element(all.begin(), all.end());
  // A link at the default limit the task did not give counts as breaking it (issue 35): the fit
  // ran to the limit, wanting a longer link, and the design is the limit's, not one chosen.
  const double limit = MaxLinkLength(constraints, length);
  const bool at_default =
      !constraints.max_link_length && longest >= (1.0 - kAtDefaultLimit) * limit;
  if (!(longest <= limit + slack) || at_default) {
    violates->push_back("max_link_length");
  }
  if (constraints.min_link_length && !(shortest >= *constraints.min_link_length - slack)) {
    violates->push_back("min_link_length");
  }
  if (constraints.fixed_pivots_box) {
    for (const Eigen::Vector2d& pivot : fixed_pivots) {
      if (!InBox(*constraints.fixed_pivots_box, pivot, slack)) {
        violates->push_back("fixed_pivots_box");
        break;
      }
    }
  }
}

// The violations every four-bar problem shares: link lengths, the fixed pivots' box, the input's
// turn and the Grashof class, appended in that order.
void CommonViolations(const DesignConstraints& constraints, const FourBarLinks& links,
                      const std::vector<Eigen::Vector2d>& fixed_pivots, const FourBarClass& kind,
                      double length, std::vector<std::string>* violates) {
  LinkViolations(constraints, links.All(), fixed_pivots, length, violates);
  ClassViolations(constraints, kind, violates);
}

// A key's fit for ordering: infinity when absent or not finite.
double FitOf(const RankKey& key) {
  return key.fit && std::isfinite(*key.fit) ? *key.fit : std::numeric_limits<double>::infinity();
}

// A key's group in the rule: meeting the exact items or not, keeping the constraints or
// violating them, then DefectLevel.
std::tuple<bool, bool, int> GroupOf(const RankKey& key) {
  return std::make_tuple(key.misses_exact, key.violates, key.defect_level);
}

}  // namespace

std::vector<std::string> FunctionViolations(const DesignConstraints& constraints,
                                            const FourBarLinks& links, const FourBarClass& kind,
                                            double length) {
  std::vector<std::string> violates;
  CommonViolations(constraints, links, {}, kind, length, &violates);
  return violates;
}

std::vector<std::string> SixBarViolations(const DesignConstraints& constraints,
                                          const SixBar& six_bar, bool input_rotates_fully,
                                          double length) {
  std::vector<std::string> violates;
  const std::array<std::vector<Eigen::Vector2d>, 6> joints = SixBarBodyJoints(six_bar);
  std::vector<double> lengths;
  for (const std::vector<Eigen::Vector2d>& body : joints) {
    for (size_t i = 0; i < body.size(); ++i) {
      for (size_t j = i + 1; j < body.size(); ++j) lengths.push_back((body[i] - body[j]).norm());
    }
  }
  LinkViolations(constraints, lengths, joints[kSixBarGround], length, &violates);
  if (constraints.moving_pivots_box) {
    const double slack = kConstraintSlack * length;
    for (const Eigen::Vector2d& joint : joints[kSixBarTaskBody]) {
      if (!InBox(*constraints.moving_pivots_box, six_bar.reference_pose.ToMoving(joint), slack)) {
        violates.push_back("moving_pivots_box");
        break;
      }
    }
  }
  if (constraints.input_rotates_fully && !input_rotates_fully) {
    violates.push_back("input_rotates_fully");
  }
  // A Grashof class is a four-bar's (a 4R's); a six-bar has none.
  if (!constraints.grashof.empty()) violates.push_back("grashof");
  return violates;
}

double MaxLinkLength(const DesignConstraints& constraints, double length) {
  return constraints.max_link_length ? *constraints.max_link_length
                                     : kDefaultMaxLinkLength * length;
}

double MinTransmissionAngleDeg(const DesignConstraints& constraints) {
  return constraints.min_transmission_angle_deg.value_or(kDefaultMinTransmissionDeg);
}

std::vector<double> FourBarLinks::All() const {
  std::vector<double> all;
  for (const std::optional<double>& link : {ground, input, coupler, output}) {
    if (link) all.push_back(*link);
  }
  return all;
}

FourBarLinks MotionFourBarLinks(const PlanarDyad& input, const PlanarDyad& output) {
  FourBarLinks links;
  if (input.HasFixedPivot() && output.HasFixedPivot()) {
    links.ground = (input.fixed_pivot - output.fixed_pivot).norm();
  }
  if (input.HasMovingPivot() && output.HasMovingPivot()) {
    links.coupler = (input.moving_pivot - output.moving_pivot).norm();
  }
  if (input.type == DyadType::kRR) links.input = std::abs(input.radius);
  if (output.type == DyadType::kRR) links.output = std::abs(output.radius);
  return links;
}

FourBarLinks PathFourBarLinks(const PathFourBar& four_bar) {
  return MotionFourBarLinks(four_bar.input, four_bar.output);
}

void AddDefect(const std::string& defect, std::vector<std::string>* defects) {
  if (std::find(defects->begin(), defects->end(), defect) == defects->end()) {
    defects->push_back(defect);
  }
}

std::vector<std::string> AddedKinematicDefects(const std::vector<std::string>& before,
                                               const std::vector<std::string>& after) {
  std::vector<std::string> added;
  for (const std::string& defect : after) {
    if (defect != "transmission" &&
        std::find(before.begin(), before.end(), defect) == before.end()) {
      added.push_back(defect);
    }
  }
  return added;
}

bool WorseRanked(const RankKey& before, const std::vector<std::string>& before_defects,
                 const RankKey& after, const std::vector<std::string>& after_defects) {
  return (after.misses_exact && !before.misses_exact) || (after.violates && !before.violates) ||
         after.defect_level > before.defect_level ||
         !AddedKinematicDefects(before_defects, after_defects).empty();
}

void JudgeMisses(const std::optional<double>& error, double tolerance,
                 std::vector<std::string>* defects) {
  if (error && *error > tolerance && !HasKinematicDefect(*defects)) AddDefect("misses", defects);
}

bool HasKinematicDefect(const std::vector<std::string>& defects) {
  return std::any_of(defects.begin(), defects.end(),
                     [](const std::string& defect) { return defect != "transmission"; });
}

bool OnOneBranch(const std::vector<std::string>& defects) {
  return std::find(defects.begin(), defects.end(), "circuit") == defects.end() &&
         std::find(defects.begin(), defects.end(), "branch") == defects.end();
}

void JudgeTransmission(const DesignConstraints& constraints,
                       const std::optional<double>& transmission_min_deg,
                       std::vector<std::string>* defects) {
  if (transmission_min_deg && *transmission_min_deg < MinTransmissionAngleDeg(constraints)) {
    AddDefect("transmission", defects);
  }
}

int DefectLevel(const std::vector<std::string>& defects) {
  if (defects.empty()) return 0;
  return HasKinematicDefect(defects) ? 2 : 1;
}

bool GrashofClassKeeps(const std::string& required, const std::string& grashof) {
  if (grashof.empty()) return false;
  const bool is_grashof = grashof != "triple-rocker";
  if (required == "grashof") return is_grashof;
  if (required == "non-grashof") return !is_grashof;
  return required == grashof;
}

std::vector<std::string> MotionViolations(const DesignConstraints& constraints,
                                          const PlanarDyad& input, const PlanarDyad& output,
                                          const FourBarClass& kind, double length) {
  std::vector<std::string> violates;
  std::vector<Eigen::Vector2d> fixed_pivots;
  for (const PlanarDyad* dyad : {&input, &output}) {
    if (dyad->HasFixedPivot()) fixed_pivots.push_back(dyad->fixed_pivot);
  }
  CommonViolations(constraints, MotionFourBarLinks(input, output), fixed_pivots, kind, length,
                   &violates);
  if (constraints.moving_pivots_box) {
    const double slack = kConstraintSlack * length;
    for (const PlanarDyad* dyad : {&input, &output}) {
      if (dyad->HasMovingPivot() &&
          !InBox(*constraints.moving_pivots_box, dyad->moving_pivot, slack)) {
        violates.push_back("moving_pivots_box");
        break;
      }
    }
  }
  return violates;
}

bool DyadKeeps(const DesignConstraints& constraints, const PlanarDyad& dyad, double length) {
  const double slack = kConstraintSlack * length;
  if (dyad.type == DyadType::kRR) {
    const double radius = std::abs(dyad.radius);
    if (!(radius <= MaxLinkLength(constraints, length) + slack)) return false;
    if (constraints.min_link_length && !(radius >= *constraints.min_link_length - slack)) {
      return false;
    }
  }
  if (constraints.fixed_pivots_box && dyad.HasFixedPivot() &&
      !InBox(*constraints.fixed_pivots_box, dyad.fixed_pivot, slack)) {
    return false;
  }
  return !(constraints.moving_pivots_box && dyad.HasMovingPivot() &&
           !InBox(*constraints.moving_pivots_box, dyad.moving_pivot, slack));
}

std::vector<std::string> PathViolations(const DesignConstraints& constraints,
                                        const PathFourBar& four_bar, const FourBarClass& kind,
                                        double length) {
  std::vector<std::string> violates;
  std::vector<Eigen::Vector2d> fixed_pivots = {four_bar.input.fixed_pivot};
  if (four_bar.output.HasFixedPivot()) fixed_pivots.push_back(four_bar.output.fixed_pivot);
  CommonViolations(constraints, PathFourBarLinks(four_bar), fixed_pivots, kind, length, &violates);
  if (constraints.max_coupler_point_offset) {
    double offset = (four_bar.coupler_point - four_bar.input.moving_pivot).norm();
    if (four_bar.output.HasMovingPivot()) {
      offset = std::max(offset, (four_bar.coupler_point - four_bar.output.moving_pivot).norm());
    }
    if (!(offset <= *constraints.max_coupler_point_offset + kConstraintSlack * length)) {
      violates.push_back("max_coupler_point_offset");
    }
  }
  return violates;
}

int FourBarParameters(FourBarType type) {
  switch (type) {
    case FourBarType::k4R:
      return 10;
    case FourBarType::kSliderCrank:
    case FourBarType::kInvertedSliderCrank:
      return 9;
    default:
      return 8;
  }
}

double JointSpread(const std::vector<Eigen::Vector2d>& joints) {
  double spread = 0.0;
  for (size_t i = 0; i < joints.size(); ++i) {
    for (size_t j = i + 1; j < joints.size(); ++j) spread += (joints[i] - joints[j]).norm();
  }
  return spread;
}

std::vector<int> RankOrder(const std::vector<RankKey>& keys) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // Fits within this share of each other are equal to rounding (two refinements of one curve
  // end within the refiner's tolerance of each other; timed cognates, whose errors are equal,
  // measured at coordinates 10^6 L from the origin came out 5e-6 apart).
  constexpr double kFitRounding = 1e-4;
  std::vector<int> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  // A fit below its key's floor (an exact solution's rounding) counts as the floor.
  const auto fit = [&](int i) { return std::max(FitOf(keys[i]), keys[i].fit_floor); };
  const auto group = [&](int i) { return GroupOf(keys[i]); };
  const auto size = [&](int i) { return keys[i].size.value_or(kInfinity); };
  const bool sized = std::all_of(keys.begin(), keys.end(),
                                 [](const RankKey& key) { return key.size.has_value(); });
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (group(a) != group(b)) return group(a) < group(b);
    if (keys[a].within_precision != keys[b].within_precision) return keys[a].within_precision;
    if (fit(a) != fit(b)) return fit(a) < fit(b);
    return sized && size(a) < size(b);
  });
  // Runs of fits equal to rounding (each within kFitRounding of the one before): the smaller
  // first, so that the order depends neither on rounding nor on where the data's origin is.
  for (size_t begin = 0; sized && begin < order.size();) {
    size_t end = begin + 1;
    while (end < order.size() && group(order[end]) == group(order[begin]) &&
           keys[order[end]].within_precision == keys[order[begin]].within_precision &&
           std::isfinite(fit(order[end])) &&
           fit(order[end]) - fit(order[end - 1]) <= kFitRounding * fit(order[end])) {
      ++end;
    }
    std::stable_sort(order.begin() + begin, order.begin() + end,
                     [&](int a, int b) { return size(a) < size(b); });
    begin = end;
  }
  // Runs of near ties: from the first of a run every later one of the group (and of its
  // within-precision standing) whose fit is within kNearTieRatio of it (kPrecisionTieRatio among
  // those within the data's precision).
  const auto angle = [&](int i) { return keys[i].transmission_min_deg; };
  size_t begin = 0;
  while (begin < order.size()) {
    const int first = order[begin];
    const bool within = keys[first].within_precision;
    const double ratio = within ? kPrecisionTieRatio : kNearTieRatio;
    size_t end = begin + 1;
    while (end < order.size()) {
      const int next = order[end];
      if (group(next) != group(first) || keys[next].within_precision != within) break;
      if (!(std::isfinite(fit(next)) && fit(next) <= ratio * fit(first))) break;
      ++end;
    }
    // Within the run: within the data's precision the simplest model first (fewest
    // parameters), each model's fits in near ties; then those keeping the defaults the task did
    // not give; then the best fit of
    // those within kTransmissionTie of the best remaining transmission angle, repeatedly
    // (angles that close are a tie too, decided by the fit).
    std::vector<int> run(order.begin() + begin, order.begin() + end);
    if (within) {
      std::stable_sort(run.begin(), run.end(),
                       [&](int a, int b) { return keys[a].parameters < keys[b].parameters; });
    }
    size_t slot = begin;
    for (size_t class_begin = 0; class_begin < run.size();) {
      // A class: one model (within the data's precision), then near ties of its fits
      // (kNearTieRatio of the first: a model's better fit is not traded for more than that).
      size_t class_end = class_begin + 1;
      while (class_end < run.size() &&
             (!within || (keys[run[class_end]].parameters == keys[run[class_begin]].parameters &&
                          fit(run[class_end]) <= kNearTieRatio * fit(run[class_begin])))) {
        ++class_end;
      }
      std::vector<int> keeping(run.begin() + class_begin, run.begin() + class_end);
      const auto keeps_defaults = std::stable_partition(
          keeping.begin(), keeping.end(), [&](int i) { return keys[i].breaks_default.empty(); });
      std::vector<int> breaking(keeps_defaults, keeping.end());
      keeping.erase(keeps_defaults, keeping.end());
      for (size_t placed = class_begin; placed < class_end; ++placed) {
        if (keeping.empty()) keeping.swap(breaking);
        // Next: the best fit of those within kTransmissionTie of the best angle left and of those
        // without one (an inverted slider-crank's is not defined; none where the task gives its
        // own limit), which are not compared by angle.
        double best = -kInfinity;
        for (int i : keeping) {
          if (angle(i)) best = std::max(best, *angle(i));
        }
        const auto pick = std::find_if(keeping.begin(), keeping.end(), [&](int i) {
          return !angle(i) || *angle(i) >= best - kTransmissionTie;
        });
        order[slot++] = *pick;
        keeping.erase(pick);
      }
      class_begin = class_end;
    }
    begin = end;
  }
  return order;
}

std::vector<int> ListedWithinBound(const std::vector<RankKey>& ranked, int bound) {
  const auto fit = [&](int i) { return FitOf(ranked[i]); };
  const auto group = [&](int i) { return GroupOf(ranked[i]); };
  std::vector<int> listed;
  const int count = static_cast<int>(ranked.size());
  for (int i = 0; i < count; ++i) {
    bool keep = i < bound;
    if (!keep && std::isfinite(fit(i))) {
      keep = true;  // the best fit of its group, unless another listed one fits as well
      for (int j = 0; j < count && keep; ++j) {
        if (j != i && group(j) == group(i) && (fit(j) < fit(i) || (fit(j) == fit(i) && j < i))) {
          keep = false;
        }
      }
    }
    if (keep) listed.push_back(i);
  }
  return listed;
}

void JudgeWithDefaults(const DesignConstraints& constraints,
                       const std::vector<std::string>& violates,
                       const std::vector<std::string>& defects, bool driven, RankKey* key) {
  std::vector<std::string> given_violations, given_defects;
  key->breaks_default.clear();
  const auto breaks = [&](const std::string& what) {
    key->breaks_default += (key->breaks_default.empty() ? "" : " and ") + what;
  };
  for (const std::string& violation : violates) {
    if (violation == "max_link_length" && !constraints.max_link_length) {
      char text[96];
      std::snprintf(text, sizeof(text), "the default link limit (%g L)", kDefaultMaxLinkLength);
      breaks(text);
    } else {
      given_violations.push_back(violation);
    }
  }
  for (const std::string& defect : defects) {
    if (defect == "transmission" && !constraints.min_transmission_angle_deg) {
      char text[96];
      std::snprintf(text, sizeof(text), "the default minimum transmission angle (%g degrees)",
                    kDefaultMinTransmissionDeg);
      breaks(text);
    } else {
      given_defects.push_back(defect);
    }
  }
  key->violates = !given_violations.empty();
  key->defect_level = driven ? DefectLevel(given_defects) : 2;
}

std::optional<double> TransmissionTieBreak(const DesignConstraints& constraints,
                                           const std::optional<double>& angle) {
  if (constraints.min_transmission_angle_deg) return std::nullopt;
  return angle;
}

std::string DefaultsNote(const std::vector<RankKey>& ranked, const std::string& unit,
                         const std::string& mechanism) {
  if (ranked.empty() || ranked.front().breaks_default.empty()) return "";
  const RankKey& first = ranked.front();
  // Why it is first: among those of its group (no more defects, no more violations), within the
  // data's precision and then the smallest (exact solutions fit equally), or the best fit.
  std::string note =
      "the first " + mechanism + " breaks " + first.breaks_default +
      ", which the task did not give; it is first as " +
      (first.within_precision ? "it meets the data within their precision, the smallest that does"
                              : "it fits best of those with no more defects");
  for (size_t i = 1; i < ranked.size(); ++i) {
    const RankKey& key = ranked[i];
    if (!key.breaks_default.empty() || GroupOf(key) != GroupOf(first) || !key.fit) continue;
    char text[200];
    const double ratio = first.fit && *first.fit > 0.0 ? *key.fit / *first.fit : 0.0;
    if (ratio > 0.0) {
      std::snprintf(text, sizeof(text),
                    "; the best that keeps the defaults (--mechanism %zu) has %s %.3g, %.3g times "
                    "the first's",
                    i + 1, unit.c_str(), *key.fit, ratio);
    } else {
      std::snprintf(text, sizeof(text),
                    "; the best that keeps the defaults (--mechanism %zu) has %s %.3g", i + 1,
                    unit.c_str(), *key.fit);
    }
    return note + text + "; give \"constraints\" to require them";
  }
  return note + "; no listed " + mechanism +
         " of its group keeps the defaults; give \"constraints\" to require them";
}

std::string GivenConstraintsNote(const DesignConstraints& constraints,
                                 const std::vector<std::string>& violates,
                                 const std::vector<std::string>& defects,
                                 const std::string& mechanism) {
  std::string broken;
  const auto add = [&](const std::string& name) { broken += (broken.empty() ? "" : ", ") + name; };
  for (const std::string& violation : violates) {
    if (violation != "max_link_length" || constraints.max_link_length) add(violation);
  }
  if (constraints.min_transmission_angle_deg &&
      std::find(defects.begin(), defects.end(), "transmission") != defects.end()) {
    add("min_transmission_angle_deg");
  }
  if (broken.empty()) return "";
  return "no listed " + mechanism + " keeps every constraint the task gave: the first breaks " +
         broken +
         " (a bound in its \"violates\"; the transmission angle as the defect \"transmission\" in "
         "its \"defects\")";
}

std::string DroppedNote(int dropped) {
  return std::to_string(dropped) + " more four-bars, ranked below these, were found and dropped";
}

}  // namespace linkfit
