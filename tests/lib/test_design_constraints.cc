#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/path_motion.h"
#include "lib/task_io.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

RankKey Key(double fit, double transmission, bool within = false, int level = 0,
            bool violates = false, int parameters = 10) {
  RankKey key;
  key.fit = fit;
  key.transmission_min_deg = transmission;
  key.within_precision = within;
  key.defect_level = level;
  key.violates = violates;
  key.parameters = parameters;
  return key;
}

TEST(RankOrder, KeepersThenDefectLevelsThenFit) {
  const std::vector<RankKey> keys = {
      Key(1e-3, 80, false, 0, true),  // violates: last group of all
      Key(5e-1, 10, false, 2),        // kinematic defect
      Key(2e-3, 20, false, 1),        // transmission only
      Key(4e-2, 60),                  // defect-free, worse fit
      Key(1e-2, 40),                  // defect-free, best fit
  };
  EXPECT_EQ(RankOrder(keys), (std::vector<int>{4, 3, 2, 1, 0}));
}

TEST(RankOrder, NearTiesGoByTransmissionAngle) {
  // Within 10 % of the run's first: the larger worst transmission angle first; angles within
  // kTransmissionTie of each other are a tie, the better fit first.
  const std::vector<RankKey> keys = {Key(1.00, 40), Key(1.05, 70), Key(1.08, 69.5), Key(1.20, 89)};
  EXPECT_EQ(RankOrder(keys), (std::vector<int>{1, 2, 0, 3}));
  // An absent angle (an inverted slider-crank's) is not compared: each next one listed is the
  // best fit of those without an angle or within kTransmissionTie of the best angle left. An
  // absent fit goes last in its group.
  RankKey no_angle = Key(1.0, 0);
  no_angle.transmission_min_deg.reset();
  RankKey no_fit = Key(0, 90);
  no_fit.fit.reset();
  EXPECT_EQ(RankOrder({no_angle, Key(1.01, 35), no_fit}), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(RankOrder({Key(0.99, 35), no_angle, Key(1.02, 60)}), (std::vector<int>{1, 2, 0}));
}

// A task that gives min_transmission_angle_deg has made the angle a rule (kept or violated):
// near ties then go by fit, as the optimizers of the classic path problems rank them; without
// it the better angle (the default's preference) decides them.
TEST(RankOrder, TheTasksOwnTransmissionLimitLeavesNearTiesToTheFit) {
  DesignConstraints given;
  given.min_transmission_angle_deg = 0.0;
  DesignConstraints none;
  for (const DesignConstraints* constraints : {&given, &none}) {
    std::vector<RankKey> keys = {Key(1.05, 43), Key(1.00, 38), Key(1.30, 80)};
    for (RankKey& key : keys) {
      key.transmission_min_deg = TransmissionTieBreak(*constraints, key.transmission_min_deg);
    }
    EXPECT_EQ(RankOrder(keys),
              constraints == &given ? (std::vector<int>{1, 0, 2}) : (std::vector<int>{0, 1, 2}));
  }
}

// Issue 34: defaults the task did not give (the 30 degree transmission angle, links of 100 L)
// order near ties only; the note says what keeping them costs.
TEST(RankOrder, DefaultsTheTaskDidNotGiveOrderNearTiesOnly) {
  DesignConstraints none;
  RankKey best = Key(1.0, 12);
  JudgeWithDefaults(none, {}, {"transmission"}, true, &best);
  EXPECT_EQ(best.defect_level, 0);
  EXPECT_NE(best.breaks_default.find("transmission angle (30 degrees)"), std::string::npos);
  RankKey long_link = Key(1.02, 60);
  JudgeWithDefaults(none, {"max_link_length"}, {}, true, &long_link);
  EXPECT_FALSE(long_link.violates);
  EXPECT_NE(long_link.breaks_default.find("link limit (100 L)"), std::string::npos);
  RankKey near = Key(1.05, 50), far = Key(9.0, 80);
  JudgeWithDefaults(none, {}, {}, true, &near);
  JudgeWithDefaults(none, {}, {}, true, &far);
  // A keeper within the near-tie ratio goes first (then the others of the tie by transmission
  // angle); one 9 times worse does not.
  EXPECT_EQ(RankOrder({best, long_link, near}), (std::vector<int>{2, 1, 0}));
  const std::vector<RankKey> ranked = {best, far};
  EXPECT_EQ(RankOrder(ranked), (std::vector<int>{0, 1}));
  const std::string note = DefaultsNote(ranked, "an RMS point error of");
  EXPECT_NE(note.find("breaks the default minimum transmission angle"), std::string::npos) << note;
  EXPECT_NE(note.find("(--mechanism 2) has an RMS point error of 9, 9 times the first's"),
            std::string::npos)
      << note;
  EXPECT_NE(note.find("it is first as it fits best of those with no more defects"),
            std::string::npos)
      << note;
  // Exact solutions fit equally: the first is the smallest of those within the precision.
  RankKey exact = best;
  exact.within_precision = true;
  EXPECT_NE(DefaultsNote({exact, far}, "an RMS point error of")
                .find("it meets the data within their precision, the smallest that does"),
            std::string::npos);
  EXPECT_EQ(DefaultsNote({far, best}, "an RMS point error of"), "");
  // Given by the task, the same limits are constraints and defects as before.
  DesignConstraints given;
  given.min_transmission_angle_deg = 30.0;
  given.max_link_length = 100.0;
  RankKey judged = Key(1.0, 12);
  JudgeWithDefaults(given, {"max_link_length"}, {"transmission"}, true, &judged);
  EXPECT_TRUE(judged.violates);
  EXPECT_EQ(judged.defect_level, 1);
  EXPECT_TRUE(judged.breaks_default.empty());
  // A kinematic defect counts whatever the defaults; not driven through: level 2.
  RankKey kinematic = Key(1.0, 40);
  JudgeWithDefaults(none, {}, {"order", "transmission"}, true, &kinematic);
  EXPECT_EQ(kinematic.defect_level, 2);
  JudgeWithDefaults(none, {}, {}, false, &kinematic);
  EXPECT_EQ(kinematic.defect_level, 2);
}

TEST(RankOrder, WithinPrecisionTheSimplestModelFirst) {
  // Both meet the data within their precision: the slider-crank (9 parameters) before the 4R
  // however their transmission angles and RMS fits compare; then the rest by fit.
  const std::vector<RankKey> keys = {Key(5e-4, 71, true, 0, false, 10),
                                     Key(2e-4, 64, true, 0, false, 9),
                                     Key(1e-4, 89, false, 0, false, 10)};
  EXPECT_EQ(RankOrder(keys), (std::vector<int>{1, 0, 2}));
}

TEST(ListedWithinBound, KeepsTheBestOfEachGroup) {
  std::vector<RankKey> ranked;
  for (int i = 0; i < 5; ++i) ranked.push_back(Key(1e-2 * (i + 1), 60));
  ranked.push_back(Key(1e-12, 5, false, 1));  // exact, transmission only
  ranked.push_back(Key(1e-11, 4, false, 1));
  ranked.push_back(Key(1.0, 0, false, 2));
  EXPECT_EQ(ListedWithinBound(ranked, 3), (std::vector<int>{0, 1, 2, 5, 7}));
  EXPECT_EQ(ListedWithinBound(ranked, 20).size(), ranked.size());
}

TEST(DesignConstraints, MotionViolationsNameEachConstraint) {
  // A 4R: ground 4, crank 1, coupler |(0,1) - (3,1)| = 3, rocker 2.5.
  const PlanarDyad input = PlanarDyad::RR({0, 0}, {0, 1}, 1.0);
  const PlanarDyad output = PlanarDyad::RR({4, 0}, {3, 1}, 2.5);
  FourBarClass kind;
  kind.type = FourBarType::k4R;
  kind.grashof = GrashofType(input, output, 1.0);
  kind.input_rotates_fully = true;
  const FourBarLinks links = MotionFourBarLinks(input, output);
  EXPECT_DOUBLE_EQ(*links.ground, 4.0);
  EXPECT_DOUBLE_EQ(*links.coupler, 3.0);
  DesignConstraints constraints;
  EXPECT_TRUE(MotionViolations(constraints, input, output, kind, 1.0).empty());
  constraints.max_link_length = 3.5;
  constraints.min_link_length = 1.5;
  constraints.fixed_pivots_box = PlanarBox{{-1, -1}, {3, 1}};
  constraints.moving_pivots_box = PlanarBox{{-1, 0}, {3, 2}};  // (0,1) and (3,1) inside
  constraints.grashof = "double-crank";
  EXPECT_EQ(MotionViolations(constraints, input, output, kind, 1.0),
            (std::vector<std::string>{"max_link_length", "min_link_length", "fixed_pivots_box",
                                      "grashof"}));
  // On a bound is inside (kConstraintSlack).
  DesignConstraints on_bound;
  on_bound.max_link_length = 4.0;
  on_bound.fixed_pivots_box = PlanarBox{{0, 0}, {4, 0}};
  EXPECT_TRUE(MotionViolations(on_bound, input, output, kind, 1.0).empty());
  // Past it by 1e-9 relative breaks it (issue 34: a link of 80.0000001 breaks 80), at a task
  // length of the links' order.
  DesignConstraints just_under;
  just_under.max_link_length = 4.0 / (1.0 + 1.25e-9);
  EXPECT_EQ(MotionViolations(just_under, input, output, kind, 2.0),
            (std::vector<std::string>{"max_link_length"}));
  // Without max_link_length the default bounds the links: 100 L.
  EXPECT_EQ(MotionViolations(DesignConstraints(), input, output, kind, 0.039),
            (std::vector<std::string>{"max_link_length"}));
  // A slider-crank counts its crank and coupler; its slider has no fixed pivot.
  const PlanarDyad slider = PlanarDyad::PR({3, 1}, {0, 1}, {1, 0});
  kind.type = FourBarType::kSliderCrank;
  const FourBarLinks slider_links = MotionFourBarLinks(input, slider);
  EXPECT_FALSE(slider_links.ground);
  EXPECT_DOUBLE_EQ(*slider_links.coupler, 3.0);
  DesignConstraints crank_rocker;
  crank_rocker.grashof = "crank-rocker";
  crank_rocker.input_rotates_fully = true;
  kind.input_rotates_fully = false;
  EXPECT_EQ(MotionViolations(crank_rocker, input, slider, kind, 1.0),
            (std::vector<std::string>{"input_rotates_fully", "grashof"}));
}

TEST(DesignConstraints, PathCouplerPointOffset) {
  PathFourBar four_bar;
  four_bar.input = PlanarDyad::RR({0, 0}, {1, 0}, 1.0);
  four_bar.output = PlanarDyad::RR({3, 0}, {3, 2}, 2.0);
  four_bar.coupler_point = {2, 3};  // 3.16 from the crank pin, 1.41 from the rocker pin
  FourBarClass kind;
  DesignConstraints constraints;
  constraints.max_coupler_point_offset = 3.0;
  EXPECT_EQ(PathViolations(constraints, four_bar, kind, 1.0),
            (std::vector<std::string>{"max_coupler_point_offset"}));
  constraints.max_coupler_point_offset = 3.2;
  EXPECT_TRUE(PathViolations(constraints, four_bar, kind, 1.0).empty());
}

std::string ErrorOf(const std::string& text) { return testing::ParseErrorOf(text); }

const char* kPoses =
    R"("poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 1, "y": 0.2, "theta_deg": 10},
                 {"x": 1.5, "y": 1, "theta_deg": 25}, {"x": 1, "y": 2, "theta_deg": 40},
                 {"x": 0, "y": 2.2, "theta_deg": 60}])";

TEST(DesignConstraints, ParsedFromTheTask) {
  const Task task = ParseTask(std::string("{") + kPoses + R"(, "constraints": {
      "max_link_length": 50, "min_link_length": 0.5, "fixed_pivots_box": [[-1, -2], [3, 4]],
      "moving_pivots_box": [[-5, -5], [5, 5]], "input_rotates_fully": true,
      "grashof": "crank-rocker", "min_transmission_angle_deg": 40}})",
                              "task.json");
  const DesignConstraints& c = task.constraints;
  EXPECT_TRUE(c.given);
  EXPECT_EQ(*c.max_link_length, 50.0);
  EXPECT_EQ(*c.min_link_length, 0.5);
  EXPECT_EQ(c.fixed_pivots_box->min, Eigen::Vector2d(-1, -2));
  EXPECT_EQ(c.fixed_pivots_box->max, Eigen::Vector2d(3, 4));
  EXPECT_TRUE(c.input_rotates_fully);
  EXPECT_EQ(c.grashof, "crank-rocker");
  EXPECT_EQ(MinTransmissionAngleDeg(c), 40.0);
  EXPECT_EQ(MinTransmissionAngleDeg(ParseTask(std::string("{") + kPoses + "}", "t").constraints),
            kDefaultMinTransmissionDeg);
}

TEST(DesignConstraints, BadConstraintsSayWhatIsWrong) {
  const auto motion = [](const std::string& constraints) {
    return ErrorOf(std::string("{") + kPoses + ", \"constraints\": " + constraints + "}");
  };
  EXPECT_EQ(motion(R"({"max_link": 5})"),
            "task.json: constraints.max_link: unknown field (known fields: max_link_length, "
            "min_link_length, max_coupler_point_offset, fixed_pivots_box, moving_pivots_box, "
            "input_rotates_fully, grashof, min_transmission_angle_deg)");
  EXPECT_EQ(motion(R"({"max_link_length": -1})"),
            "task.json: constraints.max_link_length: must be positive, got -1");
  EXPECT_EQ(motion(R"({"max_link_length": 1, "min_link_length": 2})"),
            "task.json: constraints.min_link_length: above max_link_length (1)");
  EXPECT_EQ(motion(R"({"fixed_pivots_box": [[0, 0], [-1, 1]]})"),
            "task.json: constraints.fixed_pivots_box: the lower corner's x (0) is above the upper "
            "corner's (-1)");
  EXPECT_EQ(motion(R"({"fixed_pivots_box": [0, 0, 1, 1]})"),
            "task.json: constraints.fixed_pivots_box: expected [[xmin, ymin], [xmax, ymax]], got "
            "an array");
  EXPECT_EQ(motion(R"({"grashof": "crank"})")
                .rfind("task.json: constraints.grashof: expected \"grashof\", \"non-grashof\"", 0),
            0u);
  EXPECT_EQ(motion(R"({"min_transmission_angle_deg": 95})"),
            "task.json: constraints.min_transmission_angle_deg: at most 90, got 95");
  EXPECT_EQ(motion(R"({"max_coupler_point_offset": 1})"),
            "task.json: constraints.max_coupler_point_offset: used by path problems only");
  EXPECT_EQ(motion("[]"), "task.json: constraints: expected an object, got an array");
  EXPECT_EQ(
      ErrorOf(R"({"problem": "path", "points": [{"x": 0, "y": 0}, {"x": 1, "y": 0}], "constraints":
                  {"moving_pivots_box": [[0, 0], [1, 1]]}})"),
      "task.json: constraints.moving_pivots_box: used by motion problems only (a path four-bar's "
      "coupler has no frame of the task)");
  EXPECT_EQ(ErrorOf(R"({"space": "spatial", "scale": 1,
                        "poses": [{"q": [1, 0, 0, 0], "g": [0, 0, 0, 0]}],
                        "constraints": {"max_link_length": 5}})"),
            "task.json: constraints.max_link_length: not used by spatial tasks: spherical "
            "four-bars' links are angles and their pivots axes (spatial tasks take "
            "input_rotates_fully, grashof and min_transmission_angle_deg)");
}

}  // namespace
}  // namespace linkfit

namespace linkfit {
namespace {

// A design whose longest link sits at the default link limit the task did not give (a fit that
// ran to the limit, wanting a longer link: issue 35's function four-bars with a coupler of
// exactly 100) is listed as breaking that default, not as if the limit were its choice; at a
// limit the task gave, it keeps it.
TEST(DesignConstraints, ALinkAtTheDefaultLimitBreaksIt) {
  const double length = 2.0;
  FourBarLinks links;
  links.ground = 1.0;
  links.input = 0.5;
  links.coupler = kDefaultMaxLinkLength * length * (1.0 - 1e-6);
  links.output = 3.0;
  FourBarClass kind;
  DesignConstraints constraints;
  const std::vector<std::string> at_default = FunctionViolations(constraints, links, kind, length);
  ASSERT_EQ(at_default.size(), 1u);
  EXPECT_EQ(at_default.front(), "max_link_length");
  RankKey key;
  JudgeWithDefaults(constraints, at_default, {}, true, &key);
  EXPECT_FALSE(key.violates);
  EXPECT_NE(key.breaks_default.find("default link limit"), std::string::npos);
  // Well inside the default limit: kept.
  links.coupler = 0.9 * kDefaultMaxLinkLength * length;
  EXPECT_TRUE(FunctionViolations(constraints, links, kind, length).empty());
  // At a limit the task gave: kept (a bound the designer chose).
  constraints.given = true;
  constraints.max_link_length = 0.9 * kDefaultMaxLinkLength * length;
  EXPECT_TRUE(FunctionViolations(constraints, links, kind, length).empty());
}

}  // namespace
}  // namespace linkfit
