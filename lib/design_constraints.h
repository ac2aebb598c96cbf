// Design constraints of planar motion and path tasks (README, "Design constraints"), the
// constraints a four-bar keeps or violates, and the ranking rule every result follows.
//
// The links of a four-bar are those of fixed length: the ground (the two fixed pivots, when both
// dyads have one: RR and RP), the cranks (RR radii) and the coupler (the two moving pivots, when
// both dyads have one: RR and PR). A slider-crank counts its crank and coupler, an inverted
// slider-crank its crank and ground. A path four-bar's coupler point is bounded by its distance
// from each coupler joint (the crank pin, and the output's moving pivot when it has one).
#ifndef LINKFIT_LIB_DESIGN_CONSTRAINTS_H_
#define LINKFIT_LIB_DESIGN_CONSTRAINTS_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/mechanism.h"
#include "lib/six_bar.h"

namespace linkfit {

struct PathFourBar;

// An axis-aligned box of the plane.
struct PlanarBox {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
};

// Whether `point` is in `box`, each side moved out by `slack`.
bool InBox(const PlanarBox& box, const Eigen::Vector2d& point, double slack = 0.0);

// Without "max_link_length", least-squares and search results keep every link within this
// many times L (and a result lists a four-bar beyond it, or at it to within 1e-4 of it: a fit
// that ran to the limit, as violating "max_link_length", a default it breaks).
inline constexpr double kDefaultMaxLinkLength = 100.0;

// How far (times L) a four-bar may be past a bound and still keep it: what a refinement that
// ends on the bound leaves (a link of 80.0000001 breaks a bound of 80 at L up to 100).
inline constexpr double kConstraintSlack = 1e-9;

// Two fits (RMS errors) within this ratio of each other are a near tie: the better worst
// transmission angle ranks first.
inline constexpr double kNearTieRatio = 1.1;

// Among the four-bars that meet the data within their precision, fits within this ratio are a
// tie of models (the simplest model first; the fits of one model then as near ties,
// kNearTieRatio): the first listed fits within 1.25 times the best (issue 34), and a slider the
// data cannot tell from a circle still comes first.
inline constexpr double kPrecisionTieRatio = 1.25;

// Transmission angles within this many degrees of each other are a tie too: decided by the fit.
inline constexpr double kTransmissionTie = 1.0;

struct DesignConstraints {
  std::optional<double> max_link_length;  // absent: kDefaultMaxLinkLength * L
  std::optional<double> min_link_length;
  std::optional<double> max_coupler_point_offset;  // paths
  std::optional<PlanarBox> fixed_pivots_box;       // both fixed pivots, in Sigma
  std::optional<PlanarBox> moving_pivots_box;      // motion: both moving pivots, in E
  bool input_rotates_fully = false;                // the input must be a crank
  // A required class of a 4R (GrashofType's names), or "grashof" (any Grashof class) or
  // "non-grashof"; empty: any. A four-bar that is not a 4R does not have a required class.
  std::string grashof;
  // Below it, the defect "transmission"; absent: kDefaultMinTransmissionDeg.
  std::optional<double> min_transmission_angle_deg;
  bool given = false;  // the task had "constraints"
};

inline constexpr double kDefaultMinTransmissionDeg = 30.0;

// The task's min_transmission_angle_deg, else kDefaultMinTransmissionDeg.
double MinTransmissionAngleDeg(const DesignConstraints& constraints);

// The largest link allowed: the task's max_link_length, else kDefaultMaxLinkLength * length.
double MaxLinkLength(const DesignConstraints& constraints, double length);

// A four-bar's links of fixed length (file comment); absent where the type has none.
struct FourBarLinks {
  std::optional<double> ground, input, coupler, output;
  std::vector<double> All() const;  // those present
};

FourBarLinks MotionFourBarLinks(const PlanarDyad& input, const PlanarDyad& output);
FourBarLinks PathFourBarLinks(const PathFourBar& four_bar);

// What a four-bar needs besides its dyads to be judged: its Grashof class (4R: GrashofType with
// the input driven) and whether its input turns fully.
struct FourBarClass {
  FourBarType type = FourBarType::k4R;
  std::string grashof;
  bool input_rotates_fully = false;
};

// The constraints on a four-bar's class it violates (input_rotates_fully, grashof), appended to
// *violates: the constraints of a spherical four-bar, whose links are angles.
void ClassViolations(const DesignConstraints& constraints, const FourBarClass& kind,
                     std::vector<std::string>* violates);

// The constraints a motion four-bar (input and output dyads, moving pivots in E) violates, by
// their task names, in a fixed order; empty when it keeps them all. The transmission angle is a
// defect, not listed here.
std::vector<std::string> MotionViolations(const DesignConstraints& constraints,
                                          const PlanarDyad& input, const PlanarDyad& output,
                                          const FourBarClass& kind, double length);

// Whether one dyad keeps the constraints that bound a dyad alone (its crank's length, its fixed
// pivot's box, its moving pivot's box): a seed that breaks them makes no four-bar that keeps
// them.
// The constraints a six-bar (lib/six_bar.h) breaks: its links are every two joints of one body
// (the binary links' lengths, each ternary link's three sides, the chain's links and the ground's
// pivots' distances: SixBarBodyJoints), its fixed pivots the ground's joints, its moving pivots
// the task body's (in E); `input_rotates_fully` of the input it is driven by. A Grashof class is a
// four-bar's: a task that requires one is broken by every six-bar.
std::vector<std::string> SixBarViolations(const DesignConstraints& constraints,
                                          const SixBar& six_bar, bool input_rotates_fully,
                                          double length);

bool DyadKeeps(const DesignConstraints& constraints, const PlanarDyad& dyad, double length);

// The same for a path four-bar (in the first point's configuration).
std::vector<std::string> PathViolations(const DesignConstraints& constraints,
                                        const PathFourBar& four_bar, const FourBarClass& kind,
                                        double length);

// The same for a function generator's links (its ground, cranks and coupler): the link-length
// and class constraints (its fixed pivots are the task's ground).
std::vector<std::string> FunctionViolations(const DesignConstraints& constraints,
                                            const FourBarLinks& links, const FourBarClass& kind,
                                            double length);

// Adds the defect "transmission" to `defects` (once) when the worst transmission angle is below
// the constraints' minimum (MinTransmissionAngleDeg).
void JudgeTransmission(const DesignConstraints& constraints,
                       const std::optional<double>& transmission_min_deg,
                       std::vector<std::string>* defects);

// Adds `defect` to `defects` unless it is there already.
void AddDefect(const std::string& defect, std::vector<std::string>* defects);

// The kinematic defects (all but "transmission") of `after` that `before` does not have: a
// refinement that adds one is not taken.
std::vector<std::string> AddedKinematicDefects(const std::vector<std::string>& before,
                                               const std::vector<std::string>& after);

// The defect "misses" of minimal data (five poses, timed points or orientations; three absolute
// or five relative function pairs), which every solution meets exactly (issue 35): added when
// the largest error is more than `tolerance` (the data's precision) and no kinematic defect says
// why already.
void JudgeMisses(const std::optional<double>& error, double tolerance,
                 std::vector<std::string>* defects);

// Whether `defects` holds a kinematic defect (any but "transmission": "circuit", "branch",
// "order"; function four-bars' "assembly" and "range"): the four-bar cannot be driven through the
// task as listed.
bool HasKinematicDefect(const std::vector<std::string>& defects);

// Whether `defects` lets the mechanism follow the task on one branch: no "circuit" or "branch"
// defect (an order defect only reorders the poses or points).
bool OnOneBranch(const std::vector<std::string>& defects);

// 0 without defects, 1 when the only defect is "transmission", 2 with a kinematic defect.
int DefectLevel(const std::vector<std::string>& defects);

// Whether a Grashof class (GrashofType) is the required one ("grashof" and "non-grashof" take
// any class of their kind; "change-point" counts as Grashof).
bool GrashofClassKeeps(const std::string& required, const std::string& grashof);

// The ranking rule of every result (README, "Ranking"): those meeting the task's exact items
// before those that miss one; then those keeping every constraint the task gave before those
// violating one; within each, defect-free, then those whose only defect is the transmission
// angle the task gave, then those with a kinematic defect (DefectLevel). Within each of those:
// first those that meet the task within the data's precision, by fit, fits within
// kPrecisionTieRatio of the first of their run the simplest model first (fewest parameters: a
// slider where the data cannot tell it from a circle), each model's fits within kNearTieRatio
// of each other a near tie; then the others by fit (smaller first;
// absent last), fits within kNearTieRatio of the first of their run a near tie. Within a tie,
// those keeping the defaults the task did not give (breaks_default) first, then by the worst
// transmission angle; angles within kTransmissionTie of each other are a tie, the better fit
// first (fits equal to rounding or below fit_floor: the smaller size first); an absent angle (an
// inverted slider-crank's; every one where the task gives its own limit: TransmissionTieBreak)
// is not compared (each next one listed is the best fit of those within kTransmissionTie of the
// best angle left and those without one).
struct RankKey {
  // Misses an item the task marks exact (a pose or point) by more than the promised 1e-9 L:
  // listed after every one that meets them, whatever its fit.
  bool misses_exact = false;
  bool violates = false;
  int defect_level = 0;  // DefectLevel; 2 also for a four-bar without a fit (not driven through)
  std::optional<double> fit;
  bool within_precision = false;  // its largest error is within the data's precision
  int parameters = 0;             // FourBarParameters
  // The worst transmission angle, a near tie's tie-break (TransmissionTieBreak; absent: none).
  std::optional<double> transmission_min_deg;
  // The mechanism's size (JointSpread), the last tie-break: between fits equal to rounding (the
  // timed cognates of one curve, a design found twice) or all within the data's precision, the
  // smaller first, so that the order does not depend on rounding, nor on where the data's origin
  // is. Absent: the fit's order stands.
  std::optional<double> size;
  // Fits below this (length units) are equal: an exact solution's rounding (a thousandth of the
  // data's precision tolerance).
  double fit_floor = 0.0;
  // What it breaks of the defaults the task did not give (the transmission angle of
  // kDefaultMinTransmissionDeg, links of kDefaultMaxLinkLength L): not counted in `violates`
  // nor `defect_level`; it orders near ties only (README, "Ranking"). Empty: keeps them.
  std::string breaks_default;
};

// Fills key->violates, key->defect_level and key->breaks_default from a mechanism's violations
// and defects (`driven`: it has a fit, it can be driven through the task; else level 2): a
// violation or a "transmission" defect under a default the task did not give counts in
// breaks_default only.
void JudgeWithDefaults(const DesignConstraints& constraints,
                       const std::vector<std::string>& violates,
                       const std::vector<std::string>& defects, bool driven, RankKey* key);

// Whether a refinement, ranked `after` with `after_defects`, is worse by the ranking's rule than
// the design it refines (`before`, `before_defects`): it misses an exact item the design met,
// breaks a given constraint the design kept, has a higher defect level, or adds a kinematic
// defect (AddedKinematicDefects). A default the task did not give orders near ties only: not
// counted here.
bool WorseRanked(const RankKey& before, const std::vector<std::string>& before_defects,
                 const RankKey& after, const std::vector<std::string>& after_defects);

// The worst transmission angle as a near tie's tie-break (RankKey::transmission_min_deg):
// `angle`, unless the task gives min_transmission_angle_deg. The preference for a better angle
// is the default's; a task that states the angle it needs has made it a rule (kept or violated),
// and the fit decides its near ties.
std::optional<double> TransmissionTieBreak(const DesignConstraints& constraints,
                                           const std::optional<double>& angle);

// The note a result gives when its first mechanism (ranked[0]) breaks a default the task did not
// give: which, and what the best-fitting listed mechanism that keeps the defaults (and is in the
// first one's group otherwise) costs in fit; empty when the first keeps them. `unit` names the
// fit ("RMS point error" and the like).
std::string DefaultsNote(const std::vector<RankKey>& ranked, const std::string& unit,
                         const std::string& mechanism = "four-bar");

// The note a result gives when its first mechanism breaks a constraint the task gave (its
// `violates`, or "transmission" under the task's own min_transmission_angle_deg): the ranking
// lists keepers first, so none keeps them all; which the first breaks. Empty when it keeps them.
std::string GivenConstraintsNote(const DesignConstraints& constraints,
                                 const std::vector<std::string>& violates,
                                 const std::vector<std::string>& defects,
                                 const std::string& mechanism = "four-bar");

// The sum of the distances between every two of `joints` (a mechanism's pivots, pins and
// coupler point in one configuration): its size, which no move or turn of the data changes and
// which tells apart designs that share their largest extent (timed cognates share the output).
double JointSpread(const std::vector<Eigen::Vector2d>& joints);

// The parameters of a four-bar's dyads (RR 5, PR and RP 4): its model's complexity.
int FourBarParameters(FourBarType type);

// The order in which `keys` are listed (indices into `keys`); stable for equal keys.
std::vector<int> RankOrder(const std::vector<RankKey>& keys);

// Of ranked keys (in their listed order), those a list of at most `bound` keeps (indices into
// `ranked`, in order): the first `bound`, and beyond them the best fit of each group (keeping or
// violating, DefectLevel) not yet among them, so that an exact four-bar with a poor
// transmission angle is not lost behind worse fits that have none.
std::vector<int> ListedWithinBound(const std::vector<RankKey>& ranked, int bound);

// Orders `reports` by the ranking rule (RankOrder of key_of(report)) and, with `bound` >= 0,
// keeps those ListedWithinBound; returns how many were dropped (DroppedNote says so).
template <typename Report, typename KeyOf>
int RankReports(const KeyOf& key_of, int bound, std::vector<Report>* reports) {
  std::vector<RankKey> keys;
  for (const Report& report : *reports) keys.push_back(key_of(report));
  std::vector<RankKey> ranked_keys;
  std::vector<Report> ranked;
  for (int index : RankOrder(keys)) {
    ranked_keys.push_back(keys[index]);
    ranked.push_back(std::move((*reports)[index]));
  }
  reports->clear();
  if (bound < 0) {
    *reports = std::move(ranked);
    return 0;
  }
  for (int index : ListedWithinBound(ranked_keys, bound)) {
    reports->push_back(std::move(ranked[index]));
  }
  return static_cast<int>(ranked.size() - reports->size());
}

// The note of a bounded list: how many more four-bars were found and dropped.
std::string DroppedNote(int dropped);

}  // namespace linkfit

#endif  // LINKFIT_LIB_DESIGN_CONSTRAINTS_H_
