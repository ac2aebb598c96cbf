// Tests of result writing: the design's field names and order, a round trip through a JSON
// parser, and no NaN or Infinity ever written.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lib/result_io.h"

namespace linkfit {
namespace {

using Json = nlohmann::ordered_json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

PlanarMotionResult HandBuiltResult() {
  PlanarMotionResult result;
  result.method = "exact";
  result.scale = 3.25;
  result.dyads.push_back({PlanarDyad::RR({1.0, 2.0}, {-0.5, 0.25}, 1.75), 1e-12});
  // Direction at -30 degrees: the line's angle is 150 degrees.
  result.dyads.push_back(
      {PlanarDyad::PR({0.1, 0.2}, {3.0, 4.0}, {std::cos(-M_PI / 6), std::sin(-M_PI / 6)}), 2e-11});
  result.dyads.push_back({PlanarDyad::RP({-1.0, 0.5}, {0.0, 2.0}, {0.0, -1.0}), 3e-10});
  MechanismReport four_bar;
  four_bar.type = FourBarType::kSliderCrank;
  four_bar.input_dyad = 0;
  four_bar.output_dyad = 1;
  four_bar.max_pose_error = 4e-9;
  result.mechanisms.push_back(four_bar);
  MechanismReport broken;
  broken.type = FourBarType::kInvertedSliderCrank;
  broken.input_dyad = 0;
  broken.output_dyad = 2;
  broken.pose_error_note = "does not assemble at pose 3";
  result.mechanisms.push_back(broken);
  MechanismReport grashof;
  grashof.type = FourBarType::k4R;
  grashof.input_dyad = 0;
  grashof.output_dyad = 0;
  grashof.max_pose_error = 0.0;
  grashof.grashof = "crank-rocker";
  result.mechanisms.push_back(grashof);
  result.roots_total = 4;
  result.roots_real = 2;
  result.notes = {"two roots are complex"};
  result.solve_seconds = 0.0125;
  return result;
}

std::vector<std::string> Keys(const Json& object) {
  std::vector<std::string> keys;
  for (const auto& entry : object.items()) keys.push_back(entry.key());
  return keys;
}

bool HasNonFiniteText(const std::string& text) {
  for (const char* word : {"NaN", "nan", "Infinity", "inf", "null"}) {
    if (text.find(word) != std::string::npos) return true;
  }
  return false;
}

TEST(ResultIo, RoundTrip) {
  const PlanarMotionResult result = HandBuiltResult();
  const std::string text = ResultToJson(result, 2);
  EXPECT_FALSE(HasNonFiniteText(text)) << text;
  const Json json = Json::parse(text);
  EXPECT_EQ(Keys(json), (std::vector<std::string>{"problem", "space", "method", "scale",
                                                  "precision", "constraints", "dyads", "mechanisms",
                                                  "roots", "notes", "solve_time_ms"}));
  // The constraints judged by: here the defaults, named.
  EXPECT_EQ(json["constraints"]["max_link_length"].get<double>(), 325.0);
  EXPECT_EQ(json["constraints"]["min_transmission_angle_deg"].get<double>(), 30.0);
  EXPECT_EQ(json["constraints"]["defaults"],
            Json({"max_link_length", "min_transmission_angle_deg"}));
  EXPECT_EQ(json["problem"], "motion");
  EXPECT_EQ(json["space"], "planar");
  EXPECT_EQ(json["method"], "exact");
  EXPECT_EQ(json["scale"].get<double>(), 3.25);
  EXPECT_EQ(json["roots"], Json({{"total", 4}, {"real", 2}}));
  EXPECT_EQ(json["notes"], Json({"two roots are complex"}));
  EXPECT_DOUBLE_EQ(json["solve_time_ms"].get<double>(), 12.5);

  const Json& dyads = json["dyads"];
  ASSERT_EQ(dyads.size(), 3u);
  EXPECT_EQ(Keys(dyads[0]),
            (std::vector<std::string>{"type", "fixed", "moving", "radius", "max_residual"}));
  EXPECT_EQ(dyads[0]["type"], "RR");
  EXPECT_EQ(dyads[0]["fixed"], Json({1.0, 2.0}));
  EXPECT_EQ(dyads[0]["moving"], Json({-0.5, 0.25}));
  EXPECT_EQ(dyads[0]["radius"].get<double>(), 1.75);
  EXPECT_EQ(dyads[0]["max_residual"].get<double>(), 1e-12);

  EXPECT_EQ(Keys(dyads[1]), (std::vector<std::string>{"type", "moving", "line_point",
                                                      "line_angle_deg", "max_residual"}));
  EXPECT_EQ(dyads[1]["type"], "PR");
  const double angle = dyads[1]["line_angle_deg"].get<double>();
  EXPECT_GE(angle, 0.0);
  EXPECT_LT(angle, 180.0);
  EXPECT_NEAR(angle, 150.0, 1e-12);
  // line_point is the foot of the perpendicular from the origin and lies on the line.
  const Eigen::Vector2d foot(dyads[1]["line_point"][0].get<double>(),
                             dyads[1]["line_point"][1].get<double>());
  const Eigen::Vector2d direction = result.dyads[1].dyad.line_direction;
  EXPECT_NEAR(foot.dot(direction), 0.0, 1e-12);
  const Eigen::Vector2d offset = foot - Eigen::Vector2d(3.0, 4.0);
  EXPECT_NEAR(offset.x() * direction.y() - offset.y() * direction.x(), 0.0, 1e-12);

  EXPECT_EQ(Keys(dyads[2]), (std::vector<std::string>{"type", "fixed", "line_point",
                                                      "line_angle_deg", "max_residual"}));
  EXPECT_EQ(dyads[2]["type"], "RP");
  EXPECT_EQ(dyads[2]["fixed"], Json({-1.0, 0.5}));
  EXPECT_NEAR(dyads[2]["line_angle_deg"].get<double>(), 90.0, 1e-12);
  EXPECT_NEAR(dyads[2]["line_point"][0].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(dyads[2]["line_point"][1].get<double>(), 0.0, 1e-12);

  const Json& mechanisms = json["mechanisms"];
  ASSERT_EQ(mechanisms.size(), 3u);
  EXPECT_EQ(Keys(mechanisms[0]),
            (std::vector<std::string>{"type", "dyads", "max_pose_error", "defects", "violates",
                                      "full_rotation", "transmission_angle_note"}));
  EXPECT_EQ(mechanisms[0]["defects"], Json::array());
  EXPECT_EQ(mechanisms[0]["violates"], Json::array());
  EXPECT_EQ(mechanisms[0]["full_rotation"], Json({{"input", false}, {"output", false}}));
  EXPECT_EQ(mechanisms[0]["type"], FourBarTypeName(FourBarType::kSliderCrank));
  EXPECT_EQ(mechanisms[0]["dyads"], Json({0, 1}));
  EXPECT_EQ(mechanisms[0]["max_pose_error"].get<double>(), 4e-9);
  EXPECT_FALSE(mechanisms[1].contains("max_pose_error"));
  EXPECT_EQ(mechanisms[1]["max_pose_error_note"], "does not assemble at pose 3");
  EXPECT_EQ(mechanisms[1]["dyads"], Json({0, 2}));
  EXPECT_EQ(mechanisms[2]["type"], "4R");
  EXPECT_EQ(mechanisms[2]["grashof"], "crank-rocker");
}

TEST(ResultIo, NonFiniteValuesAreLeftOutWithANote) {
  PlanarMotionResult result = HandBuiltResult();
  result.scale = kNaN;
  result.dyads[0].dyad.radius = kInf;
  result.dyads[0].dyad.fixed_pivot.x() = kNaN;
  result.dyads[1].max_residual = -kInf;
  result.mechanisms[0].max_pose_error = kNaN;
  result.mechanisms[1].pose_error_note.clear();
  result.solve_seconds = kInf;
  const std::string text = ResultToJson(result, -1);
  EXPECT_FALSE(HasNonFiniteText(text)) << text;
  const Json json = Json::parse(text);
  EXPECT_FALSE(json.contains("scale"));
  EXPECT_TRUE(json.contains("scale_note"));
  EXPECT_FALSE(json.contains("solve_time_ms"));
  EXPECT_TRUE(json.contains("solve_time_ms_note"));
  EXPECT_FALSE(json["dyads"][0].contains("radius"));
  EXPECT_TRUE(json["dyads"][0].contains("radius_note"));
  EXPECT_FALSE(json["dyads"][0].contains("fixed"));
  EXPECT_TRUE(json["dyads"][0].contains("fixed_note"));
  EXPECT_EQ(json["dyads"][0]["moving"], Json({-0.5, 0.25}));
  EXPECT_FALSE(json["dyads"][1].contains("max_residual"));
  EXPECT_TRUE(json["dyads"][1].contains("max_residual_note"));
  EXPECT_FALSE(json["mechanisms"][0].contains("max_pose_error"));
  EXPECT_TRUE(json["mechanisms"][0].contains("max_pose_error_note"));
  EXPECT_EQ(json["mechanisms"][1]["max_pose_error_note"], "not computed");
}

TEST(ResultIo, EmptyResult) {
  PlanarMotionResult result;
  const std::string text = ResultToJson(result, 2);
  const Json json = Json::parse(text);
  EXPECT_EQ(json["dyads"], Json::array());
  EXPECT_EQ(json["mechanisms"], Json::array());
  EXPECT_FALSE(json.contains("notes"));
  // No root system was solved (three or four poses, a degenerate task): no "roots".
  EXPECT_FALSE(json.contains("roots"));

  result.notes = {"no real dyad"};
  EXPECT_EQ(Json::parse(ResultToJson(result, 2))["notes"], Json({"no real dyad"}));
}

TEST(ResultIo, IndentAndOneLine) {
  const PlanarMotionResult result = HandBuiltResult();
  const std::string line = ResultToJson(result, -1);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  const std::string pretty = ResultToJson(result, 2);
  EXPECT_NE(pretty.find("\n  \"space\""), std::string::npos) << pretty;
  EXPECT_EQ(Json::parse(line), Json::parse(pretty));
  // Points stay on one line in the pretty form.
  const size_t fixed = pretty.find("\"fixed\": [");
  ASSERT_NE(fixed, std::string::npos) << pretty;
  EXPECT_LT(pretty.find(']', fixed), pretty.find('\n', fixed)) << pretty;
}

TEST(ResultIo, CompactArraysLeaveStringsAlone) {
  PlanarMotionResult result = HandBuiltResult();
  result.notes.push_back("bracket in text [\n 1,\n 2 ] stays");
  const std::string pretty = ResultToJson(result, 2);
  EXPECT_EQ(Json::parse(pretty), Json::parse(ResultToJson(result, -1)));
  EXPECT_EQ(Json::parse(pretty)["notes"].back(), "bracket in text [\n 1,\n 2 ] stays");
}

TEST(ResultIo, LineAngleStaysInRange) {
  for (int k = -720; k <= 720; k += 15) {
    const double angle = k * M_PI / 180.0;
    PlanarMotionResult result;
    result.dyads.push_back(
        {PlanarDyad::PR({0, 0}, {1, 1}, {std::cos(angle), std::sin(angle)}), 0.0});
    const Json json = Json::parse(ResultToJson(result, -1));
    const double written = json["dyads"][0]["line_angle_deg"].get<double>();
    EXPECT_GE(written, 0.0) << k;
    EXPECT_LT(written, 180.0) << k;
  }
}

TEST(ResultIo, InvalidUtf8InNotesDoesNotThrow) {
  PlanarMotionResult result;
  result.notes = {std::string("bad byte \xff here")};
  std::string text;
  EXPECT_NO_THROW(text = ResultToJson(result, 2));
  EXPECT_NO_THROW(Json::parse(text));
}

}  // namespace
}  // namespace linkfit
