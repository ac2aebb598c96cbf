// Tests of task reading: valid planar, spatial and path tasks, and for every kind of bad
// input the exact one-line message "<source>: <item>: <what is wrong>".
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "lib/task_io.h"

namespace linkfit {
namespace {

using Json = nlohmann::json;

constexpr double kTight = 1e-12;
constexpr double kDegree = M_PI / 180.0;

// Five distinct planar poses (x, y, theta_deg).
Json PlanarTaskJson() {
  Json task;
  task["poses"] = Json::array();
  const double poses[5][3] = {{0, 0, 0}, {1, 0, 10}, {2, 1, 20}, {1, 2, 30}, {0, 1, 40}};
  for (const auto& pose : poses) {
    task["poses"].push_back({{"x", pose[0]}, {"y", pose[1]}, {"theta_deg", pose[2]}});
  }
  return task;
}

Json PathTaskJson() {
  Json task;
  task["problem"] = "path";
  task["points"] = Json::array();
  for (int i = 0; i < 5; ++i) {
    task["points"].push_back(
        {{"x", std::cos(0.5 * i)}, {"y", std::sin(0.7 * i)}, {"input_deg", 20.0 * i}});
  }
  return task;
}

// The InputError message of parsing `text`, or "<no error>".
std::string ErrorOf(const std::string& text, const TaskReadOptions& options = {}) {
  try {
    ParseTask(text, "task.json", options);
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line";
    return message;
  }
  return "<no error>";
}

std::string ErrorOf(const char* text) { return ErrorOf(std::string(text)); }

std::string ErrorOf(const Json& task, const TaskReadOptions& options = {}) {
  return ErrorOf(task.dump(), options);
}

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

// A temporary file that is removed when the test ends.
class TempFile {
 public:
  TempFile(const std::string& suffix, const std::string& contents) {
    char pattern[] = "/tmp/linkfit_task_io_XXXXXX";
    const int fd = mkstemp(pattern);
    EXPECT_GE(fd, 0);
    close(fd);
    std::remove(pattern);
    path_ = std::string(pattern) + suffix;
    std::ofstream(path_, std::ios::binary) << contents;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(TaskIoParse, ValidPlanarTask) {
  Json json = PlanarTaskJson();
  json["problem"] = "motion";
  json["space"] = "planar";
  json["scale"] = 2.5;
  json["options"] = {{"effort", "thorough"}};
  json["poses"][2]["weight"] = 3.0;
  json["poses"][4]["exact"] = true;
  json["poses"][3]["theta_deg"] = 390.0;  // wraps to 30 degrees
  const Task task = ParseTask(json.dump(2), "task.json");
  EXPECT_EQ(task.problem, ProblemKind::kMotion);
  EXPECT_EQ(task.space, Space::kPlanar);
  EXPECT_EQ(task.effort, Effort::kThorough);
  ASSERT_TRUE(task.scale.has_value());
  EXPECT_EQ(*task.scale, 2.5);
  ASSERT_EQ(task.planar_poses.size(), 5u);
  EXPECT_EQ(task.planar_poses[2].origin_in_fixed, Eigen::Vector2d(2, 1));
  EXPECT_NEAR(task.planar_poses[2].theta, 20 * kDegree, kTight);
  EXPECT_NEAR(task.planar_poses[3].theta, 30 * kDegree, kTight);
  EXPECT_EQ(task.pose_weights, (std::vector<double>{1, 1, 3, 1, 1}));
  EXPECT_EQ(task.pose_exact, (std::vector<bool>{false, false, false, false, true}));
  EXPECT_TRUE(task.spatial_poses.empty());
  EXPECT_TRUE(task.points.empty());
}

TEST(TaskIoParse, Defaults) {
  const Task task = ParseTask(PlanarTaskJson().dump(), "task.json");
  EXPECT_EQ(task.problem, ProblemKind::kMotion);
  EXPECT_EQ(task.space, Space::kPlanar);
  EXPECT_EQ(task.effort, Effort::kBalanced);
  EXPECT_FALSE(task.scale.has_value());
  EXPECT_EQ(task.pose_weights, std::vector<double>(5, 1.0));
  EXPECT_EQ(task.pose_exact, std::vector<bool>(5, false));
}

TEST(TaskIoParse, SpatialFormsAgree) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  const double angle = 50 * kDegree;
  const Eigen::Vector3d d(0.3, -1.0, 2.0);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  const Eigen::Vector4d q(axis.x() * std::sin(angle / 2), axis.y() * std::sin(angle / 2),
                          axis.z() * std::sin(angle / 2), std::cos(angle / 2));
  const Eigen::Vector4d g = 0.5 * QuaternionProduct(Eigen::Vector4d(d.x(), d.y(), d.z(), 0), q);

  Json from_q = {{"q", {q[0], q[1], q[2], q[3]}}, {"g", {g[0], g[1], g[2], g[3]}}};
  Json from_matrix = {{"rotation", Json::array()}, {"translation", {d.x(), d.y(), d.z()}}};
  for (int row = 0; row < 3; ++row) {
    from_matrix["rotation"].push_back({rotation(row, 0), rotation(row, 1), rotation(row, 2)});
  }
  Json from_axis = {
      {"axis", {2.0, 4.0, 6.0}}, {"angle_deg", 50.0}, {"translation", {0.3, -1.0, 2.0}}};
  from_axis["weight"] = 2.0;

  Json json = {{"space", "spatial"}, {"poses", {from_q, from_matrix, from_axis}}, {"scale", 1.0}};
  // The three forms give the same pose, so they must be spread out to not coincide; check
  // each alone instead.
  for (const Json& pose : {from_q, from_matrix, from_axis}) {
    json["poses"] = Json::array({pose});
    const Task task = ParseTask(json.dump(), "task.json");
    ASSERT_EQ(task.spatial_poses.size(), 1u);
    const DualQuaternion& parsed = task.spatial_poses[0];
    EXPECT_TRUE(parsed.Rotation().isApprox(rotation, 1e-12)) << pose.dump();
    EXPECT_TRUE(parsed.Translation().isApprox(d, 1e-12)) << pose.dump();
    EXPECT_NEAR(std::abs(parsed.NormDefect()), 0.0, kTight);
    EXPECT_NEAR(std::abs(parsed.OrthogonalityDefect()), 0.0, kTight);
    EXPECT_EQ(task.pose_weights[0], pose.contains("weight") ? 2.0 : 1.0);
  }
  // Together, they are one pose given three times.
  json["poses"] = {from_q, from_matrix, from_axis};
  EXPECT_EQ(ErrorOf(json), "task.json: poses[1]: coincides with poses[0]");
}

TEST(TaskIoParse, SpatialQuaternionSignIsTheSamePose) {
  Json json = {{"space", "spatial"}, {"scale", 1.0}};
  json["poses"] = {{{"q", {0.0, 0.6, 0.0, 0.8}}, {"g", {0.0, 0.0, 0.0, 0.0}}},
                   {{"q", {0.0, -0.6, 0.0, -0.8}}, {"g", {0.0, 0.0, 0.0, 0.0}}}};
  EXPECT_EQ(ErrorOf(json), "task.json: poses[1]: coincides with poses[0]");
}

TEST(TaskIoParse, SpatialQuaternionIsNormalized) {
  // Within the tolerance: accepted and made exactly unit.
  Json json = {{"space", "spatial"}, {"scale", 1.0}};
  json["poses"] = {{{"q", {0.0, 0.0, 0.0, 1.0 + 1e-7}}, {"g", {0.1, 0.0, 0.0, 0.0}}}};
  const Task task = ParseTask(json.dump(), "task.json");
  EXPECT_NEAR(task.spatial_poses[0].q.norm(), 1.0, kTight);
}

TEST(TaskIoParse, ValidPathTask) {
  Json json = PathTaskJson();
  json["points"][1]["weight"] = 0.5;
  const Task task = ParseTask(json.dump(), "task.json");
  EXPECT_EQ(task.problem, ProblemKind::kPath);
  ASSERT_EQ(task.points.size(), 5u);
  EXPECT_EQ(task.points[2].point_in_fixed, Eigen::Vector2d(std::cos(1.0), std::sin(1.4)));
  ASSERT_TRUE(task.points[2].input_angle.has_value());
  EXPECT_NEAR(*task.points[2].input_angle, 40 * kDegree, kTight);
  EXPECT_EQ(task.points[1].weight, 0.5);
  EXPECT_TRUE(task.planar_poses.empty());
}

TEST(TaskIoErrors, FieldTypesAndValues) {
  struct Case {
    std::function<void(Json*)> corrupt;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[](Json* j) { (*j)["poses"][3]["theta_deg"] = "30"; },
       "task.json: poses[3].theta_deg: expected a number, got a string"},
      {[](Json* j) { (*j)["poses"][0].erase("x"); }, "task.json: poses[0].x: missing field"},
      {[](Json* j) { (*j)["poses"][2]["y"] = nullptr; },
       "task.json: poses[2].y: expected a number, got null"},
      {[](Json* j) { (*j)["poses"][1]["x"] = true; },
       "task.json: poses[1].x: expected a number, got a boolean"},
      {[](Json* j) { (*j)["poses"][1]["x"] = Json::array({1}); },
       "task.json: poses[1].x: expected a number, got an array"},
      {[](Json* j) { (*j)["poses"][1]["weight"] = 0; },
       "task.json: poses[1].weight: must be positive, got 0"},
      {[](Json* j) { (*j)["poses"][1]["weight"] = -2.5; },
       "task.json: poses[1].weight: must be positive, got -2.5"},
      {[](Json* j) { (*j)["poses"][4]["exact"] = "yes"; },
       "task.json: poses[4].exact: expected true or false, got a string"},
      {[](Json* j) { (*j)["poses"][2] = 7; },
       "task.json: poses[2]: expected an object, got a number"},
      {[](Json* j) { (*j)["poses"] = Json::object(); },
       "task.json: poses: expected an array, got an object"},
      {[](Json* j) { j->erase("poses"); }, "task.json: poses: missing field"},
      {[](Json* j) { (*j)["problem"] = "moton"; },
       "task.json: problem: expected \"motion\" or \"path\" or \"function\", got \"moton\""},
      {[](Json* j) { (*j)["space"] = 3; },
       "task.json: space: expected \"planar\" or \"spatial\", got a number"},
      {[](Json* j) {
         (*j)["options"] = {{"effort", "hard"}};
       },
       "task.json: options.effort: expected \"fast\" or \"balanced\" or \"thorough\", got "
       "\"hard\""},
      {[](Json* j) { (*j)["options"] = "fast"; },
       "task.json: options: expected an object, got a string"},
      {[](Json* j) { (*j)["scale"] = -1; }, "task.json: scale: must be positive, got -1"},
      {[](Json* j) { (*j)["scale"] = "1"; }, "task.json: scale: expected a number, got a string"},
      {[](Json* j) { (*j)["points"] = Json::array(); },
       "task.json: points: not used by motion problems (give \"poses\")"},
  };
  for (const Case& c : cases) {
    Json json = PlanarTaskJson();
    c.corrupt(&json);
    EXPECT_EQ(ErrorOf(json), c.message);
  }
}

TEST(TaskIoErrors, UnknownFieldsAreNamed) {
  Json json = PlanarTaskJson();
  json["pose"] = json["poses"];
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: pose: unknown field")) << ErrorOf(json);
  json = PlanarTaskJson();
  json["poses"][1]["theta"] = 3;
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: poses[1].theta: unknown field"));
  json = PlanarTaskJson();
  json["options"] = {{"efort", "fast"}};
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: options.efort: unknown field"));
  // A key with a line break is quoted and escaped: the message stays one line.
  json = PlanarTaskJson();
  json["bad\nkey"] = 1;
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: \"bad\\nkey\": unknown field"))
      << ErrorOf(json);
}

TEST(TaskIoErrors, Pivots) {
  Json json = PlanarTaskJson();
  json["poses"].erase(4);
  json["moving_pivots"] = {{0.0, 1.0}, {2.0, "x"}};
  EXPECT_EQ(ErrorOf(json), "task.json: moving_pivots[1][1]: expected a number, got a string");
  json["moving_pivots"] = {{0.0, 1.0, 2.0}};
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: moving_pivots[0]: expected an array of 2"))
      << ErrorOf(json);
  // Five poses determine the dyads: pivots are a mistake there.
  json = PlanarTaskJson();
  json["fixed_pivots"] = {{0.0, 1.0}};
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: fixed_pivots: used with three or four poses"))
      << ErrorOf(json);
}

// A pivot beyond 1e8 L of the poses (moving: of E's origin) is refused, naming it: at 1e200 its
// squares overflowed and the solver returned a radius-0 dyad with a false note. Nearer, it is
// accepted.
TEST(TaskIoErrors, PivotsTooFarAreRefused) {
  Json json = PlanarTaskJson();
  json["poses"].erase(4);
  json["poses"].erase(3);
  for (const char* key : {"moving_pivots", "fixed_pivots"}) {
    SCOPED_TRACE(key);
    for (const double far : {1e200, 1e12, -1e300}) {
      json.erase("moving_pivots");
      json.erase("fixed_pivots");
      json[key] = {{0.5, 0.25}, {far, 1.0}};
      const std::string error = ErrorOf(json);
      EXPECT_TRUE(StartsWith(error, std::string("task.json: ") + key + "[1]: ")) << error;
      EXPECT_NE(error.find("farther than 1e+08 L"), std::string::npos) << error;
    }
    json.erase("moving_pivots");
    json.erase("fixed_pivots");
    json[key] = {{0.5, 0.25}, {1e3, 1.0}};
    EXPECT_NO_THROW(ParseTask(json.dump(), "task.json")) << ErrorOf(json);
  }
}

TEST(TaskIoErrors, Counts) {
  Json json = PlanarTaskJson();
  json["poses"].erase(4);
  json["poses"].erase(3);
  json["poses"].erase(2);
  EXPECT_EQ(ErrorOf(json),
            "task.json: poses: 2 poses given, planar motion synthesis needs at least 3");
  json["poses"] = Json::array();
  EXPECT_EQ(ErrorOf(json),
            "task.json: poses: 0 poses given, planar motion synthesis needs at least 3");

  json = {{"space", "spatial"}, {"poses", Json::array()}};
  EXPECT_EQ(ErrorOf(json),
            "task.json: poses: 0 poses given, spatial motion synthesis needs at least 1");
  json = {{"problem", "path"}, {"points", Json::array()}};
  EXPECT_EQ(ErrorOf(json), "task.json: points: 0 points given, path synthesis needs at least 1");

  TaskReadOptions options;
  options.max_items = 6;
  json = PlanarTaskJson();
  json["poses"].push_back({{"x", 5}, {"y", 5}, {"theta_deg", 5}});
  EXPECT_EQ(ErrorOf(json, options), "<no error>");
  json["poses"].push_back({{"x", 6}, {"y", 6}, {"theta_deg", 6}});
  EXPECT_EQ(ErrorOf(json, options), "task.json: poses: 7 poses given, more than the limit of 6");
}

// The item limit bites while parsing: poses or points beyond it are counted, not built, and
// the message is the one of the count check (before the unknown field, which a complete parse
// would name first).
TEST(TaskIoErrors, ItemLimitWhileParsing) {
  TaskReadOptions options;
  options.max_items = 6;
  std::string poses;
  for (int i = 0; i < 10; ++i) {
    poses += std::string(i ? ", " : "") + "{\"x\": " + std::to_string(i) +
             ", \"y\": " + std::to_string(i * i) + ", \"theta_deg\": " + std::to_string(3 * i) +
             "}";
  }
  EXPECT_EQ(ErrorOf("{\"poses\": [" + poses + "], \"bogus\": 1}", options),
            "task.json: poses: 10 poses given, more than the limit of 6");
  EXPECT_EQ(ErrorOf("{\"bogus\": 1, \"poses\": [" + poses + "]}", options),
            "task.json: poses: 10 poses given, more than the limit of 6");
  // Poses beyond the limit are still read as JSON.
  const std::string malformed = "{\"poses\": [" + poses + ", {\"x\": 1,, }]}";
  EXPECT_TRUE(StartsWith(ErrorOf(malformed, options),
                         "task.json: malformed JSON at line 1, column " +
                             std::to_string(malformed.find(",,") + 2) + " (near poses[10].x): "))
      << ErrorOf(malformed, options);
  // Nested arrays inside the poses beyond the limit do not end the count.
  Json spatial = {{"space", "spatial"}, {"poses", Json::array()}};
  for (int i = 0; i < 8; ++i) {
    spatial["poses"].push_back(
        {{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"translation", {i, 0, 0}}});
  }
  options.max_items = 3;
  EXPECT_EQ(ErrorOf(spatial, options), "task.json: poses: 8 poses given, more than the limit of 3");
  // The limit is on poses and points, not on other arrays (q has four numbers).
  options.max_items = 2;
  const Json two = {{"space", "spatial"},
                    {"poses",
                     {{{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.0, 0.0, 0.0, 0.0}}},
                      {{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.5, 0.0, 0.0, 0.0}}}}}};
  EXPECT_EQ(ErrorOf(two, options), "<no error>");
  Json path = PathTaskJson();
  options.max_items = 4;
  EXPECT_EQ(ErrorOf(path, options), "task.json: points: 5 points given, more than the limit of 4");
  options.max_items = 0;
  EXPECT_EQ(ErrorOf(path, options), "task.json: points: 5 points given, more than the limit of 0");
}

// Junk elsewhere cannot build a DOM larger than a task within the limit: the JSON values are
// budgeted at 32 per pose or point (the largest pose form has 20) plus 32 * 128.
TEST(TaskIoErrors, ValueBudget) {
  TaskReadOptions options;
  options.max_items = 10;  // budget 32 * (10 + 128) = 4416 values
  std::string junk = "{\"junk\": [0";
  for (int i = 1; i < 5000; ++i) junk += ",0";
  junk += "]}";
  // The root object and the array are values 1 and 2, junk[4414] is value 4417.
  EXPECT_EQ(ErrorOf(junk, options),
            "task.json: junk[4414]: too many JSON values (more than 4416; a task has at most 10 "
            "poses or points)");
  EXPECT_TRUE(StartsWith(ErrorOf(junk), "task.json: junk: unknown field"));
  // A task as large as the limit allows: ten spatial poses in the largest form.
  Json json = {{"space", "spatial"}, {"poses", Json::array()}, {"options", {{"effort", "fast"}}}};
  for (int i = 0; i < 10; ++i) {
    json["poses"].push_back({{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
                             {"translation", {i, 0, 0}},
                             {"weight", 2.0},
                             {"exact", false}});
  }
  EXPECT_EQ(ErrorOf(json, options), "<no error>");
}

TEST(TaskIoErrors, NonFiniteNumbers) {
  const std::string five = PlanarTaskJson().dump();
  std::string text = five;
  text.replace(text.find("\"theta_deg\":30.0"), 16, "\"theta_deg\":1e999");
  EXPECT_TRUE(StartsWith(ErrorOf(text), "task.json: poses[3].theta_deg: not a finite number"))
      << ErrorOf(text);
  text = five;
  text.replace(text.find("\"x\":2.0"), 7, "\"x\":-1e400");
  EXPECT_TRUE(StartsWith(ErrorOf(text), "task.json: poses[2].x: not a finite number"))
      << ErrorOf(text);
  EXPECT_TRUE(StartsWith(ErrorOf("{\"scale\": 1e999}"), "task.json: scale: not a finite number"));
  EXPECT_TRUE(StartsWith(ErrorOf("1e999"), "task.json: top level: not a finite number"));
  // Finite but so large that the spread overflows.
  Json json = PlanarTaskJson();
  json["poses"][0]["x"] = 1e300;
  EXPECT_EQ(ErrorOf(json),
            "task.json: poses: coordinates too large (their spread overflows a double)");
}

TEST(TaskIoErrors, MalformedJson) {
  EXPECT_EQ(ErrorOf("{\n  \"poses\": [\n    {\"x\": 1,, }"),
            "task.json: malformed JSON at line 3, column 13 (near poses[0].x): syntax error while "
            "parsing object key - unexpected ','; expected string literal");
  // NaN and Infinity, as some writers emit them, are named at their item.
  EXPECT_EQ(ErrorOf("{\"poses\": [{\"x\": 0, \"y\": NaN}]}"),
            "task.json: poses[0].y: NaN and Infinity are not numbers (line 1, column 26)");
  EXPECT_TRUE(StartsWith(ErrorOf("{\"scale\": -Infinity}"),
                         "task.json: scale: NaN and Infinity are not numbers"));
  EXPECT_TRUE(
      StartsWith(ErrorOf("{\"poses\": [tru]}"), "task.json: malformed JSON at line 1, column"));
  EXPECT_TRUE(StartsWith(ErrorOf("{\"poses\": ["),
                         "task.json: malformed JSON at line 1, column 12 (near poses[0]): "));
  // An object cut before its first key is itself the item.
  EXPECT_TRUE(StartsWith(ErrorOf("{\"poses\": [{"),
                         "task.json: malformed JSON at line 1, column 13 (near poses[0]): "))
      << ErrorOf("{\"poses\": [{");
  EXPECT_TRUE(StartsWith(ErrorOf("{"), "task.json: malformed JSON at line 1, column 2: syntax"))
      << ErrorOf("{");
  EXPECT_TRUE(StartsWith(ErrorOf("{\"\": 1"),
                         "task.json: malformed JSON at line 1, column 7 (near \"\"): "))
      << ErrorOf("{\"\": 1");
  EXPECT_TRUE(StartsWith(ErrorOf("{} {}"), "task.json: malformed JSON at line 1, column 4: "));
  EXPECT_EQ(ErrorOf(""), "task.json: no JSON text (empty input)");
  EXPECT_EQ(ErrorOf(" \n\t"), "task.json: no JSON text (empty input)");
  EXPECT_EQ(ErrorOf("[1, 2]"), "task.json: top level: expected an object, got an array");
  EXPECT_EQ(ErrorOf("null"), "task.json: top level: expected an object, got null");
  // A long unterminated string is quoted only in part.
  const std::string long_string = "{\"problem\": \"" + std::string(100000, 'a');
  EXPECT_LT(ErrorOf(long_string).size(), 400u);
  // Raw control characters and invalid UTF-8 do not leak into the message.
  const std::string message = ErrorOf(std::string("{\"a\": \"x\x01\xff\"}"));
  EXPECT_TRUE(StartsWith(message, "task.json: malformed JSON at line 1")) << message;
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << message;
}

TEST(TaskIoErrors, DuplicateField) {
  const std::string text =
      "{\"poses\": [{\"x\": 0, \"y\": 0, \"theta_deg\": 0}, {\"x\": 0, \"y\": 1, \"y\": 2}]}";
  EXPECT_EQ(ErrorOf(text), "task.json: poses[1].y: field given twice");
  EXPECT_EQ(ErrorOf("{\"scale\": 1, \"scale\": 2}"), "task.json: scale: field given twice");
}

TEST(TaskIoErrors, DeepNestingIsRejectedWithoutCrash) {
  EXPECT_EQ(ErrorOf(std::string(100000, '[')),
            "task.json: malformed JSON at line 1, column 65: nested deeper than 64 levels");
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
  EXPECT_TRUE(StartsWith(ErrorOf(objects),
                         "task.json: malformed JSON at line 1, column 321: "
                         "nested deeper than 64 levels"));
  // Brackets inside strings do not count, nor do escaped quotes end a string.
  const std::string in_string = "{\"problem\": \"\\\"" + std::string(1000, '[') + "\"}";
  EXPECT_TRUE(StartsWith(ErrorOf(in_string), "task.json: problem: expected")) << ErrorOf(in_string);
  // 64 levels pass the depth check (and fail later for another reason).
  const std::string deep_ok = "{\"poses\": " + std::string(63, '[') + std::string(63, ']') + "}";
  EXPECT_EQ(ErrorOf(deep_ok),
            "task.json: poses: 1 pose given, planar motion synthesis needs at least 3");
}

TEST(TaskIoErrors, AllOriginsCoincide) {
  Json json = PlanarTaskJson();
  for (auto& pose : json["poses"]) pose["x"] = pose["y"] = 1.5;
  EXPECT_EQ(ErrorOf(json), "task.json: poses: all pose origins coincide; give \"scale\"");
  json["scale"] = 1.0;
  EXPECT_EQ(ErrorOf(json), "<no error>");

  json = {{"space", "spatial"},
          {"poses", {{{"axis", {0, 0, 1}}, {"angle_deg", 10}, {"translation", {1, 2, 3}}}}}};
  EXPECT_EQ(ErrorOf(json), "task.json: poses: all pose origins coincide; give \"scale\"");
  json["scale"] = 0.5;
  EXPECT_EQ(ErrorOf(json), "<no error>");

  json = {{"problem", "path"}, {"points", {{{"x", 1}, {"y", 1}}}}};
  EXPECT_EQ(ErrorOf(json), "task.json: points: all points coincide; give \"scale\"");
}

TEST(TaskIoErrors, CoincidentPlanarPoses) {
  Json json = PlanarTaskJson();
  json["poses"][4] = json["poses"][1];
  EXPECT_EQ(ErrorOf(json), "task.json: poses[4]: coincides with poses[1]");
  // A full turn is the same pose.
  json = PlanarTaskJson();
  json["poses"][4] = json["poses"][1];
  json["poses"][4]["theta_deg"] = 10.0 - 360.0;
  EXPECT_EQ(ErrorOf(json), "task.json: poses[4]: coincides with poses[1]");
  // Within the tolerance (1e-10 L) it coincides, beyond it does not.
  json["poses"][4]["theta_deg"] = 10.0;
  json["poses"][4]["x"] = 1.0 + 1e-13;
  EXPECT_EQ(ErrorOf(json), "task.json: poses[4]: coincides with poses[1]");
  json["poses"][4]["x"] = 1.0 + 1e-6;
  EXPECT_EQ(ErrorOf(json), "<no error>");
  // Same origin, different angle: distinct poses.
  json["poses"][4]["x"] = 1.0;
  json["poses"][4]["theta_deg"] = 11.0;
  EXPECT_EQ(ErrorOf(json), "<no error>");
  // The first offending pair is named, the later index first.
  json = PlanarTaskJson();
  json["poses"][3] = json["poses"][2];
  json["poses"][4] = json["poses"][0];
  EXPECT_EQ(ErrorOf(json), "task.json: poses[3]: coincides with poses[2]");
}

TEST(TaskIoErrors, CoincidentAmongManyPosesIsFast) {
  // 100000 poses on one vertical line, in scrambled order: the worst case for a sweep along
  // x alone.
  Json json;
  json["poses"] = Json::array();
  for (int i = 0; i < 100000; ++i) {
    json["poses"].push_back({{"x", 0.0}, {"y", 1e-3 * ((i * 7919) % 100000)}, {"theta_deg", 0.0}});
  }
  const std::string text = json.dump();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(ErrorOf(text), "<no error>");
  json["poses"][99999] = json["poses"][12345];
  EXPECT_EQ(ErrorOf(json), "task.json: poses[99999]: coincides with poses[12345]");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 10.0);
  json["poses"].push_back(json["poses"][0]);
  EXPECT_EQ(ErrorOf(json), "task.json: poses: 100001 poses given, more than the limit of 100000");
}

TEST(TaskIoErrors, SpatialPoses) {
  const Json good = {{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.5, 0.0, 0.0, 0.0}}};
  const Json other = {{"axis", {0, 0, 1}}, {"angle_deg", 30}, {"translation", {1, 1, 1}}};
  struct Case {
    Json pose;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{{"q", {0.0, 0.0, 0.0, 1.02}}, {"g", {0.0, 0.0, 0.0, 0.0}}},
       "task.json: poses[2].q: not a unit quaternion: |q| = 1.02, off by 0.02; the precision "
       "of its digits (0.005 per component) accepts at most 0.01"},
      {{{"q", {0.0, 0.0, 0.0, 0.0}}, {"g", {0.0, 0.0, 0.0, 0.0}}},
       "task.json: poses[2].q: not a unit quaternion: |q| = 0, off by 1; the precision of its "
       "digits (0.05 per component) accepts at most 3.6e-15"},
      {{{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.0, 0.0, 0.0, 0.3}}},
       "task.json: poses[2].g: q . g = 0.3, must be 0; the precision of the digits accepts at "
       "most 0.13"},
      {{{"q", {0.0, 0.0, 1.0}}, {"g", {0.0, 0.0, 0.0, 0.0}}},
       "task.json: poses[2].q: expected an array of 4 numbers, got 3 elements"},
      {{{"q", {0.0, 0.0, 0.0, 1.0}}}, "task.json: poses[2].g: missing field"},
      {{{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.0, "0", 0.0, 0.0}}},
       "task.json: poses[2].g[1]: expected a number, got a string"},
      {{{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
        {"translation", {0, 0, 0}},
        {"q", {0.0, 0.0, 0.0, 1.0}}},
       "task.json: poses[2]: give exactly one of {\"q\", \"g\"}, {\"rotation\", "
       "\"translation\"}, {\"axis\", \"angle_deg\", \"translation\"}, {\"euler_deg\", "
       "\"euler_axes\", \"translation\"} or {\"translation\", \"x_axis\", \"y_axis\"}"},
      {{{"translation", {0, 0, 0}}},
       "task.json: poses[2]: give exactly one of {\"q\", \"g\"}, {\"rotation\", "
       "\"translation\"}, {\"axis\", \"angle_deg\", \"translation\"}, {\"euler_deg\", "
       "\"euler_axes\", \"translation\"} or {\"translation\", \"x_axis\", \"y_axis\"}"},
      {{{"q", {0.0, 0.0, 0.0, 1.0}}, {"g", {0.0, 0.0, 0.0, 0.0}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].translation: unknown field (known fields: q, g, weight, exact)"},
      {{{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].rotation: determinant is -1, must be +1 (a reflection is not a "
       "rotation)"},
      {{{"rotation", {{1, 0, 0}, {0, 1.3, 0}, {0, 0, 1}}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].rotation: not orthonormal: an entry of R^T R - I is 0.69; the "
       "precision of its digits (0.05 per entry) accepts at most 0.26"},
      {{{"rotation", {{1, 0, 0}, {0, 1, 0}}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].rotation: expected 3 rows of 3 numbers, got 2 rows"},
      {{{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, "1"}}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].rotation[2][2]: expected a number, got a string"},
      {{{"rotation", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}},
       "task.json: poses[2].translation: missing field"},
      {{{"axis", {0, 0, 0}}, {"angle_deg", 30}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].axis: zero vector, the axis needs a direction"},
      {{{"axis", {0, 0, 1}}, {"translation", {0, 0, 0}}},
       "task.json: poses[2].angle_deg: missing field"},
      {{{"axis", {0, 0, 1}}, {"angle_deg", 30}, {"translation", "here"}},
       "task.json: poses[2].translation: expected an array of 3 numbers, got a string"},
  };
  for (const Case& c : cases) {
    const Json json = {{"space", "spatial"}, {"poses", {good, other, c.pose}}};
    EXPECT_EQ(ErrorOf(json), c.message) << c.pose.dump();
  }
}

TEST(TaskIoErrors, PathPoints) {
  Json json = PathTaskJson();
  json["points"][2].erase("input_deg");
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: points[2].input_deg: missing field"));
  json = PathTaskJson();
  for (auto& point : json["points"]) point.erase("input_deg");
  EXPECT_EQ(ErrorOf(json), "<no error>");
  json["points"][3]["input_deg"] = 10;
  EXPECT_TRUE(StartsWith(ErrorOf(json), "task.json: points[3].input_deg: given, but points[0]"));

  json = PathTaskJson();
  json["points"][3] = json["points"][0];
  EXPECT_EQ(ErrorOf(json), "task.json: points[3]: coincides with points[0]");
  // The same point at another input angle is a crossing of the curve, not a duplicate.
  json["points"][3]["input_deg"] = 90.0;
  EXPECT_EQ(ErrorOf(json), "<no error>");
  // Untimed, points equal in print are a dense trace, or a curve crossing itself (issue 34):
  // kept, and noted.
  json = PathTaskJson();
  for (auto& point : json["points"]) point.erase("input_deg");
  json["points"][3] = json["points"][2];
  json["points"][4] = json["points"][1];
  EXPECT_EQ(ErrorOf(json), "<no error>");
  const Task repeated = ParseTask(json.dump(), "task.json");
  EXPECT_EQ(repeated.points.size(), json["points"].size());
  ASSERT_FALSE(repeated.input_notes.empty());
  EXPECT_NE(repeated.input_notes.back().find("2 point(s) equal in print to another"),
            std::string::npos);

  json = PathTaskJson();
  json["space"] = "spatial";
  EXPECT_EQ(ErrorOf(json), "task.json: space: path problems are planar only");
  json = PathTaskJson();
  json["poses"] = PlanarTaskJson()["poses"];
  EXPECT_EQ(ErrorOf(json), "task.json: poses: not used by path problems (give \"points\")");
  json = PathTaskJson();
  json["points"][1]["input_deg"] = "ten";
  EXPECT_EQ(ErrorOf(json), "task.json: points[1].input_deg: expected a number, got a string");
  json = PathTaskJson();
  json.erase("points");
  EXPECT_EQ(ErrorOf(json), "task.json: points: missing field");
}

TEST(TaskIoFile, SingleJsonFile) {
  const TempFile file(".json", PlanarTaskJson().dump(2));
  const std::vector<Task> tasks = ReadTaskFile(file.path());
  ASSERT_EQ(tasks.size(), 1u);
  EXPECT_EQ(tasks[0].planar_poses.size(), 5u);
}

TEST(TaskIoFile, JsonLines) {
  const std::string good = PlanarTaskJson().dump();
  Json path = PathTaskJson();
  const TempFile file(".jsonl", good + "\n\n" + path.dump() + "\r\n  \n" + good + "\n");
  const std::vector<Task> tasks = ReadTaskFile(file.path());
  ASSERT_EQ(tasks.size(), 3u);
  EXPECT_EQ(tasks[1].problem, ProblemKind::kPath);

  Json bad = PlanarTaskJson();
  bad["poses"][0].erase("x");
  const TempFile bad_file(".jsonl", good + "\n" + good + "\n" + bad.dump() + "\n" + good);
  try {
    ReadTaskFile(bad_file.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), bad_file.path() + ":3: poses[0].x: missing field");
  }
  // A pretty-printed task in a .jsonl file fails on its first line.
  const TempFile pretty(".jsonl", PlanarTaskJson().dump(2));
  try {
    ReadTaskFile(pretty.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_TRUE(StartsWith(error.what(), pretty.path() + ":1: malformed JSON at line 1"))
        << error.what();
  }
}

TEST(TaskIoFile, FileErrors) {
  const std::string missing = "/tmp/linkfit_no_such_dir/task.json";
  try {
    ReadTaskFile(missing);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": cannot open file");
  }
  for (const std::string& suffix : {std::string(".json"), std::string(".jsonl")}) {
    const TempFile empty(suffix, "\n  \n");
    try {
      ReadTaskFile(empty.path());
      ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()), empty.path() + ": empty file, expected a task");
    }
  }
  try {
    ReadTaskFile("/tmp");
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "/tmp: is a directory, not a task file");
  }
}

}  // namespace
}  // namespace linkfit

namespace linkfit {
namespace {

// n spatial poses in axis-angle form.
nlohmann::json SpatialTaskJson(int count) {
  nlohmann::json task = {{"problem", "motion"}, {"space", "spatial"}};
  task["poses"] = nlohmann::json::array();
  for (int i = 0; i < count; ++i) {
    task["poses"].push_back({{"axis", {1.0, 0.5 * i, 0.2}},
                             {"angle_deg", 10.0 * i},
                             {"translation", {std::cos(i), std::sin(0.7 * i), 0.3 * i}}});
  }
  return task;
}

TEST(TaskIoSpatial, PivotsAndPlatform) {
  nlohmann::json json = SpatialTaskJson(5);
  json["moving_pivots"] = {{0.0, 1.0, 2.0}};
  json["fixed_pivots"] = {{1.0, 1.0, 1.0}, {2.0, 0.0, 0.0}};
  const Task task = ParseTask(json.dump(), "task.json");
  ASSERT_EQ(task.spatial_moving_pivots.size(), 1u);
  EXPECT_EQ(task.spatial_moving_pivots[0], Eigen::Vector3d(0.0, 1.0, 2.0));
  EXPECT_EQ(task.spatial_fixed_pivots.size(), 2u);
  EXPECT_TRUE(task.moving_pivots.empty());

  json["moving_pivots"] = {{0.0, 1.0}};
  EXPECT_TRUE(
      StartsWith(ErrorOf(json.dump()), "task.json: moving_pivots[0]: expected an array of 3"))
      << ErrorOf(json.dump());
  json = SpatialTaskJson(7);
  json["moving_pivots"] = {{0.0, 1.0, 2.0}};
  EXPECT_TRUE(StartsWith(ErrorOf(json.dump()), "task.json: moving_pivots: used with four to six"))
      << ErrorOf(json.dump());

  json = SpatialTaskJson(7);
  json["platform"] = {4, 3, 2, 1, 0};
  EXPECT_EQ(ParseTask(json.dump(), "task.json").platform, (std::vector<int>{4, 3, 2, 1, 0}));
  json["platform"] = {0, 1, 2};
  EXPECT_TRUE(StartsWith(ErrorOf(json.dump()), "task.json: platform: expected an array of five"));
  json["platform"] = {0, 1, 2, 3, 3};
  EXPECT_EQ(ErrorOf(json.dump()), "task.json: platform[4]: dyad 3 named twice");
  json["platform"] = {0, 1, 2, 3, -1};
  EXPECT_TRUE(StartsWith(ErrorOf(json.dump()), "task.json: platform[4]: expected a dyad index"));
  nlohmann::json planar = PlanarTaskJson();
  planar["platform"] = {0, 1, 2, 3, 4};
  EXPECT_EQ(ErrorOf(planar.dump()), "task.json: platform: used by spatial motion problems only");
}

// Spatial tasks take the constraints of a spherical four-bar's class and transmission angle;
// lengths and boxes (a spherical four-bar's links are angles) are refused, each by its name.
TEST(TaskIoSpatial, ConstraintsOfSphericalFourBars) {
  nlohmann::json json = SpatialTaskJson(7);
  json["constraints"] = {{"input_rotates_fully", true},
                         {"grashof", "crank-rocker"},
                         {"min_transmission_angle_deg", 35}};
  const Task task = ParseTask(json.dump(), "task.json");
  EXPECT_TRUE(task.constraints.given);
  EXPECT_TRUE(task.constraints.input_rotates_fully);
  EXPECT_EQ(task.constraints.grashof, "crank-rocker");
  EXPECT_EQ(task.constraints.min_transmission_angle_deg, 35.0);
  json["constraints"] = nlohmann::json::object();
  EXPECT_TRUE(ParseTask(json.dump(), "task.json").constraints.given);

  const std::string refused =
      ": not used by spatial tasks: spherical four-bars' links are angles and their pivots axes "
      "(spatial tasks take input_rotates_fully, grashof and min_transmission_angle_deg)";
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, nlohmann::json>>{{"max_link_length", 5.0},
                                                           {"min_link_length", 0.5},
                                                           {"fixed_pivots_box", {{0, 0}, {1, 1}}},
                                                           {"moving_pivots_box", {{0, 0}, {1, 1}}},
                                                           {"max_coupler_point_offset", 1.0}}) {
    json["constraints"] = {{"input_rotates_fully", true}, {key, value}};
    EXPECT_EQ(ErrorOf(json.dump()), "task.json: constraints." + key + refused);
  }
  // The object's own checks come first, as for planar tasks.
  json["constraints"] = {{"max_link", 5}};
  EXPECT_TRUE(StartsWith(ErrorOf(json.dump()), "task.json: constraints.max_link: unknown field"));
  json["constraints"] = {{"grashof", "crank"}};
  EXPECT_TRUE(StartsWith(ErrorOf(json.dump()), "task.json: constraints.grashof: expected"));
  json["constraints"] = {{"min_transmission_angle_deg", 95}};
  EXPECT_EQ(ErrorOf(json.dump()),
            "task.json: constraints.min_transmission_angle_deg: at most 90, got 95");
  json["constraints"] = nlohmann::json::array();
  EXPECT_EQ(ErrorOf(json.dump()), "task.json: constraints: expected an object, got an array");
}

}  // namespace
}  // namespace linkfit

namespace linkfit {
namespace {

// Function problems (issue 17, item 6).
TEST(TaskIoFunction, PairsAnglesGroundAndPrecision) {
  const Task task = ParseTask(R"({"problem": "function", "ground": [[1, 2], [1, 5]],
      "pairs": [{"input_deg": 10.25, "output_deg": 42.5}, {"input_deg": 30.5, "output_deg": 50},
                {"input_deg": 50, "output_deg": 61.75, "weight": 2, "exact": true}]})",
                              "t");
  EXPECT_EQ(task.problem, ProblemKind::kFunction);
  EXPECT_FALSE(task.relative_angles);  // pairs: absolute by default
  ASSERT_EQ(task.pairs.size(), 3u);
  EXPECT_NEAR(task.pairs[0].input, 10.25 * M_PI / 180.0, 1e-15);
  EXPECT_NEAR(task.pairs[2].output, 61.75 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(task.pairs[2].weight, 2.0);
  EXPECT_TRUE(task.pairs[2].exact);
  EXPECT_EQ(task.ground_output, Eigen::Vector2d(1, 5));
  // Two decimals in degrees: half a unit of the last digit.
  EXPECT_NEAR(task.precision.angle, 0.005 * M_PI / 180.0, 1e-12);
}

TEST(TaskIoFunction, FunctionSamplesMapOntoTheRanges) {
  const Task task = ParseTask(R"({"problem": "function", "function": {"x": [0, 1, 2, 3, 4],
      "y": [0, 1, 4, 9, 16], "input_range_deg": [10, 90], "output_range_deg": [0, 120],
      "precision_points": 5, "spacing": "uniform"}})",
                              "t");
  EXPECT_TRUE(task.relative_angles);  // a function: relative by default
  ASSERT_EQ(task.function_samples.size(), 5u);
  ASSERT_EQ(task.pairs.size(), 5u);
  // x = 1 is a quarter of the input range; f(1) = 1 a sixteenth of the output's.
  EXPECT_NEAR(task.function_samples[1].input, 30.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(task.function_samples[1].output, 7.5 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(task.pairs[2].input, 50.0 * M_PI / 180.0, 1e-12);
}

// Three or four precision points of a function are absolute angles unless the task says
// otherwise (issue 35: the textbooks' three points were refused as "needs at least 5"), with a
// note; five or more keep the relative default; "angles" given decides.
TEST(TaskIoFunction, FewPrecisionPointsAreAbsoluteAngles) {
  const auto task_with = [](const std::string& count, const std::string& extra) {
    return ParseTask(R"({"problem": "function", )" + extra +
                         R"("function": {"x": [0, 1, 2, 3, 4, 5], "y": [0, 1, 4, 9, 16, 25],
        "input_range_deg": [30, 90], "output_range_deg": [60, 150], "precision_points": )" +
                         count + "}}",
                     "t");
  };
  for (const char* count : {"3", "4"}) {
    const Task task = task_with(count, "");
    EXPECT_FALSE(task.relative_angles) << count;
    EXPECT_EQ(task.pairs.size(), static_cast<size_t>(std::stoi(count)));
    ASSERT_EQ(task.input_notes.size(), 1u);
    EXPECT_NE(task.input_notes[0].find("angles read as absolute"), std::string::npos);
  }
  const Task five = task_with("5", "");
  EXPECT_TRUE(five.relative_angles);
  EXPECT_TRUE(five.input_notes.empty());
  const Task said = task_with("3", R"("angles": "absolute", )");
  EXPECT_FALSE(said.relative_angles);
  EXPECT_TRUE(said.input_notes.empty());
  EXPECT_NE(ErrorOf(R"({"problem": "function", "angles": "relative", "function": {"x": [0, 1, 2],
      "y": [0, 1, 4], "input_range_deg": [0, 90], "output_range_deg": [0, 90],
      "precision_points": 3}})")
                .find("needs at least 5"),
            std::string::npos);
  // Two points: what a function needs, not what relative angles need.
  EXPECT_NE(ErrorOf(R"({"problem": "function", "function": {"x": [0, 1, 2],
      "y": [0, 1, 4], "input_range_deg": [0, 90], "output_range_deg": [0, 90],
      "precision_points": 2}})")
                .find("at least three precision points"),
            std::string::npos);
}

TEST(TaskIoFunction, BadFunctionTasksSayWhatIsWrong) {
  const std::string pairs3 =
      R"("pairs": [{"input_deg": 10, "output_deg": 40}, {"input_deg": 30, "output_deg": 50},
                   {"input_deg": 50, "output_deg": 61}])";
  EXPECT_NE(ErrorOf(R"({"problem": "function"})").find("pairs: missing field"), std::string::npos);
  EXPECT_NE(ErrorOf("{\"problem\": \"function\", \"angles\": \"relative\", " + pairs3 + "}")
                .find("needs at least 5"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{\"problem\": \"function\", \"angles\": \"sideways\", " + pairs3 + "}")
                .find("angles: expected \"absolute\" or \"relative\""),
            std::string::npos);
  EXPECT_NE(ErrorOf("{\"problem\": \"function\", \"ground\": [[0, 0], [0, 0]], " + pairs3 + "}")
                .find("ground: the two pivots coincide"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"problem": "function", "pairs": [{"input_deg": 10, "output_deg": 40},
      {"input_deg": 370, "output_deg": 50}, {"input_deg": 50, "output_deg": 61}]})")
                .find("pairs[1]: the same input angle as pairs[0]"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"problem": "function", "function": {"x": [0, 2, 1], "y": [0, 1, 2],
      "input_range_deg": [0, 90], "output_range_deg": [0, 90], "precision_points": 3}})")
                .find("function.x[2]: x must increase"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"problem": "function", "function": {"x": [0, 1, 2], "y": [0, 1, 0],
      "input_range_deg": [0, 90], "output_range_deg": [0, 90], "precision_points": 3}})")
                .find("the same at both ends"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{\"problem\": \"function\", \"poses\": [], " + pairs3 + "}")
                .find("poses: not used by function problems"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(R"({"poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 1, "y": 0, "theta_deg": 10},
                {"x": 2, "y": 1, "theta_deg": 30}], "pairs": []})")
          .find("pairs: used by function"),
      std::string::npos);
  EXPECT_NE(ErrorOf("{\"problem\": \"function\", \"constraints\": {\"fixed_pivots_box\": [[0, 0], "
                    "[1, 1]]}, " +
                    pairs3 + "}")
                .find("fixed_pivots_box: not used by function problems"),
            std::string::npos);
}

}  // namespace
}  // namespace linkfit
