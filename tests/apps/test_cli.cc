// Tests of the `linkfit` program as a user runs it: exit status, one line on stderr, and no
// result file for bad input; help for the program and for `solve`.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "lib/spherical_dyad.h"

namespace {

// The five distinct planar poses of a minimal motion task, as JSON objects.
const char* const kPoses[5] = {
    R"({"x": 0.0, "y": 0.0, "theta_deg": 0.0})", R"({"x": 1.0, "y": 0.0, "theta_deg": 10.0})",
    R"({"x": 2.0, "y": 1.0, "theta_deg": 20.0})", R"({"x": 1.0, "y": 2.0, "theta_deg": 30.0})",
    R"({"x": 0.0, "y": 1.0, "theta_deg": 40.0})"};

// A motion task with the given pose texts.
std::string MotionTask(const std::vector<std::string>& poses) {
  std::string text = "{\n  \"problem\": \"motion\",\n  \"poses\": [\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    text += "    " + poses[i] + (i + 1 < poses.size() ? ",\n" : "\n");
  }
  return text + "  ]\n}\n";
}

std::vector<std::string> FivePoses() { return {kPoses, kPoses + 5}; }

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

struct RunResult {
  int status = -1;
  std::string out;
  std::string err;
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/linkfit_cli_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  std::string WriteTask(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }

  // Runs `linkfit ARGS` with stdout and stderr captured in files of the temporary directory.
  RunResult Run(const std::string& args) const {
    const std::string command = std::string("'") + LINKFIT_BINARY + "' " + args + " >'" +
                                Path("stdout") + "' 2>'" + Path("stderr") + "'";
    const int raw = std::system(command.c_str());
    RunResult result;
    result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    result.out = ReadFile(Path("stdout"));
    result.err = ReadFile(Path("stderr"));
    return result;
  }

  // Runs `solve` on a task that must be rejected: exit 2, one stderr line that starts with
  // `expected_start`, no result file, nothing on stdout.
  void ExpectRejected(const std::string& task_text, const std::string& expected_start) {
    const std::string task = WriteTask("task.json", task_text);
    const std::string output = Path("result.json");
    const RunResult run = Run("solve '" + task + "' -o '" + output + "'");
    EXPECT_EQ(run.status, 2) << run.err;
    ASSERT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "not one line: " << run.err;
    EXPECT_EQ(run.err.rfind("linkfit: error: " + task + ": " + expected_start, 0), 0u) << run.err;
    EXPECT_FALSE(std::filesystem::exists(output));
    EXPECT_EQ(run.out, "");
    // No temporary file is left behind either.
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "task.json" || name == "stdout" || name == "stderr") << name;
    }
  }

  // The result of `linkfit solve` on the bundled example `name`, written in the temporary
  // directory; its path.
  std::string Solved(const std::string& name) const {
    const std::string path = Path("solved_" + name);
    const RunResult run =
        Run("solve '" + std::string(LINKFIT_SOURCE_DIR) + "/data/" + name + "' -o '" + path + "'");
    EXPECT_EQ(run.status, 0) << name << ": " << run.err;
    return path;
  }

  // Each `linkfit COMMAND ARGS -o/--dxf OUTPUT` of `refused` (arguments, start of the message)
  // exits 2 with one line holding the message and writes no `output`.
  void ExpectRefused(const std::string& command, const std::string& output_option,
                     const std::vector<std::pair<std::string, std::string>>& refused) const {
    for (const auto& [args, message] : refused) {
      const RunResult run =
          Run(command + " " + args + " " + output_option + " '" + Path("refused.out") + "'");
      EXPECT_EQ(run.status, 2) << args;
      EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
      EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
      EXPECT_FALSE(std::filesystem::exists(Path("refused.out")));
    }
  }

  std::string dir_;
};

TEST_F(CliTest, MalformedJson) {
  ExpectRejected("{\n  \"poses\": [\n    {\"x\": 1,, }\n",
                 "malformed JSON at line 3, column 13 (near poses[0].x): ");
}

TEST_F(CliTest, NaNAsSomeWritersEmitIt) {
  std::vector<std::string> poses = FivePoses();
  poses[2] = R"({"x": NaN, "y": 1.0, "theta_deg": 20.0})";
  ExpectRejected(MotionTask(poses), "poses[2].x: NaN and Infinity are not numbers");
}

TEST_F(CliTest, MissingField) {
  std::vector<std::string> poses = FivePoses();
  poses[2] = R"({"x": 2.0, "theta_deg": 20.0})";
  ExpectRejected(MotionTask(poses), "poses[2].y: missing field");
}

TEST_F(CliTest, StringForANumber) {
  std::vector<std::string> poses = FivePoses();
  poses[3] = R"({"x": 1.0, "y": 2.0, "theta_deg": "30"})";
  ExpectRejected(MotionTask(poses), "poses[3].theta_deg: expected a number, got a string");
}

TEST_F(CliTest, NumberThatOverflows) {
  std::vector<std::string> poses = FivePoses();
  poses[1] = R"({"x": 1e999, "y": 0.0, "theta_deg": 10.0})";
  ExpectRejected(MotionTask(poses), "poses[1].x: not a finite number");
}

TEST_F(CliTest, TwoIdenticalPoses) {
  std::vector<std::string> poses = FivePoses();
  poses[4] = poses[1];
  ExpectRejected(MotionTask(poses), "poses[4]: coincides with poses[1]");
}

TEST_F(CliTest, TwoPoses) {
  std::vector<std::string> poses = FivePoses();
  poses.resize(2);
  ExpectRejected(MotionTask(poses),
                 "poses: 2 poses given, planar motion synthesis needs at least 3");
}

TEST_F(CliTest, UnknownField) {
  std::string text = MotionTask(FivePoses());
  text.replace(text.find("\"poses\""), 7, "\"pose\"");
  ExpectRejected(text, "pose: unknown field");
}

TEST_F(CliTest, DeepNesting) {
  ExpectRejected(std::string(100000, '['), "malformed JSON at line 1, column 65: nested deeper");
}

TEST_F(CliTest, BadLineOfAJsonLinesFile) {
  const std::string good = R"({"poses": [)" + std::string(kPoses[0]) + "," + kPoses[1] + "," +
                           kPoses[2] + "," + kPoses[3] + "," + kPoses[4] + "]}";
  const std::string bad = R"({"poses": [)" + std::string(kPoses[0]) + "]}";
  const std::string task = WriteTask("tasks.jsonl", good + "\n" + good + "\n" + bad + "\n");
  const std::string output = Path("results.jsonl");
  const RunResult run = Run("solve '" + task + "' -o '" + output + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err, "linkfit: error: " + task +
                         ":3: poses: 1 pose given, planar motion synthesis needs at least 3\n");
  EXPECT_FALSE(std::filesystem::exists(output));
}

TEST_F(CliTest, MissingTaskFile) {
  const RunResult run = Run("solve '" + Path("nope.json") + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err, "linkfit: error: " + Path("nope.json") + ": cannot open file\n");
}

TEST_F(CliTest, UsageErrors) {
  for (const std::string& args : {std::string(""), std::string("solve"), std::string("--bogus"),
                                  std::string("solve a.json --bogus"), std::string("frobnicate"),
                                  std::string("solve a.json -o")}) {
    const RunResult run = Run(args);
    EXPECT_EQ(run.status, 2) << args;
    EXPECT_EQ(run.err.rfind("linkfit: error: ", 0), 0u) << args << ": " << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << args << ": " << run.err;
  }
}

TEST_F(CliTest, Help) {
  RunResult run = Run("--help");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("solve"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Exit status"), std::string::npos) << run.out;
  EXPECT_EQ(run.err, "");
  run = Run("solve --help");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("theta_deg"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("rotation"), std::string::npos) << run.out;
  // Every problem kind and how --mechanism counts (issue 35).
  for (const char* text :
       {"\"function\"", "\"path\"", "input_range_deg", "--summary", "counted from 1", "from 0"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text;
  }
}

// `linkfit solve --summary` and `linkfit show` (issue 35): the table a designer reads first, the
// bundled five poses' generating four-bar (ground 100, crank 37.5, coupler 87.5, rocker 75) first.
TEST_F(CliTest, SummaryAndShowPrintTheTable) {
  const std::string task = std::string(LINKFIT_SOURCE_DIR) + "/data/four_bar_5_poses.json";
  const RunResult alone = Run("solve --summary '" + task + "'");
  ASSERT_EQ(alone.status, 0) << alone.err;
  EXPECT_EQ(alone.out.rfind("four_bar_5_poses.json: motion (planar), exact: ", 0), 0u) << alone.out;
  for (const char* column :
       {"type", "grashof", "ground", "input", "coupler", "output", "largest pose error",
        "worst transmission, deg", "defects", "violates"}) {
    EXPECT_NE(alone.out.find(column), std::string::npos) << column;
  }
  const size_t first_row = alone.out.find("\n1  ");
  ASSERT_NE(first_row, std::string::npos) << alone.out;
  const std::string row =
      alone.out.substr(first_row + 1, alone.out.find('\n', first_row + 1) - first_row - 1);
  std::istringstream cells(row);
  std::string rank, type, grashof, ground, input, coupler, output;
  cells >> rank >> type >> grashof >> ground >> input >> coupler >> output;
  EXPECT_EQ(type, "4R");
  EXPECT_EQ(grashof, "crank-rocker");
  EXPECT_EQ(ground + " " + input + " " + coupler + " " + output, "100 37.5 87.5 75") << row;
  // With -o the JSON goes to the file and the table to stdout; `show` prints the same table.
  const std::string output_path = Path("result.json");
  const RunResult with_file = Run("solve --summary '" + task + "' -o '" + output_path + "'");
  ASSERT_EQ(with_file.status, 0) << with_file.err;
  EXPECT_EQ(with_file.out, alone.out);
  const nlohmann::json written = nlohmann::json::parse(ReadFile(output_path));
  EXPECT_EQ(written["mechanisms"].size(), 6u);
  const RunResult shown = Run("show '" + output_path + "'");
  ASSERT_EQ(shown.status, 0) << shown.err;
  EXPECT_EQ(shown.out.substr(shown.out.find(':')), alone.out.substr(alone.out.find(':')));
  // A file that is not a result: one line, exit 2.
  const RunResult bad = Run("show '" + task + "'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("not a linkfit result"), std::string::npos) << bad.err;
  EXPECT_EQ(Run("solve --summary -o - '" + task + "'").status, 2);
}

// `linkfit analyze` (issue 37) on the bundled four-bar's result: the named arrays, one entry per
// step from the first pose's crank angle (the coupler point there where the result puts it),
// the load's torque, CSV with a row per step; path and function results (the latter without a
// coupler point); bad requests exit 2 with one line and write nothing.
TEST_F(CliTest, AnalyzeGivesTheKinematicsOfAListedFourBar) {
  const std::string result_path = Solved("four_bar_5_poses.json");
  const nlohmann::json result = nlohmann::json::parse(ReadFile(result_path));
  const RunResult run =
      Run("analyze '" + result_path + "' --steps 36 --input-speed 2 --force 0,-10 -o '" +
          Path("kinematics.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json kinematics = nlohmann::json::parse(ReadFile(Path("kinematics.json")));
  for (const char* key :
       {"input_deg", "coupler_point", "coupler_point_velocity", "coupler_point_acceleration",
        "transmission_angle_deg", "mechanical_advantage", "input_torque"}) {
    ASSERT_TRUE(kinematics.contains(key)) << key;
    EXPECT_EQ(kinematics[key].size(), 36u) << key;
  }
  for (const char* link : {"input", "coupler", "output"}) {
    for (const char* key : {"angle_deg", "angular_velocity", "angular_acceleration"}) {
      EXPECT_EQ(kinematics["links"][link][key].size(), 36u) << link << " " << key;
    }
  }
  EXPECT_TRUE(kinematics["input_rotates_fully"].get<bool>());  // the first is a crank-rocker
  const nlohmann::json& joints = result["mechanisms"][0]["linkage"]["joints"];
  const double crank_deg =
      std::atan2(joints["input_pin"][1].get<double>() - joints["input_pivot"][1].get<double>(),
                 joints["input_pin"][0].get<double>() - joints["input_pivot"][0].get<double>()) *
      180.0 / M_PI;
  EXPECT_NEAR(kinematics["input_deg"][0].get<double>(), crank_deg, 1e-9);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(kinematics["coupler_point"][0][c].get<double>(),
                joints["coupler_point"][c].get<double>(), 1e-9);
  }
  EXPECT_EQ(kinematics["links"]["input"]["angular_velocity"][5].get<double>(), 2.0);
  EXPECT_GT(kinematics["peak_input_torque"].get<double>(), 0.0);
  // CSV: a header and a row per step.
  const RunResult csv = Run("analyze '" + result_path + "' --steps 36 --csv");
  ASSERT_EQ(csv.status, 0) << csv.err;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 37);
  EXPECT_EQ(csv.out.rfind("input_deg,coupler_angle_deg,", 0), 0u);
  // A path result and a function result.
  for (const char* task : {"path_5_points.json", "function_log10.json"}) {
    const std::string solved = Solved(task);
    const RunResult analyzed = Run("analyze '" + solved + "' --steps 10");
    ASSERT_EQ(analyzed.status, 0) << task << ": " << analyzed.err;
    const nlohmann::json parsed = nlohmann::json::parse(analyzed.out);
    EXPECT_EQ(parsed.contains("coupler_point"), std::string(task) == "path_5_points.json");
    EXPECT_FALSE(parsed["input_deg"].empty()) << task;
  }
  // Bad requests: one line, exit 2, no output file.
  ExpectRefused(
      "analyze", "-o",
      {{"'" + result_path + "' --mechanism 99", "no mechanism ranked 99"},
       {"'" + result_path + "' --input-speed 0",
        "--input-speed: expected a finite number other than 0"},
       {"'" + std::string(LINKFIT_SOURCE_DIR) + "/data/four_bar_5_poses.json'",
        "no \"mechanisms\""},
       {"'" + Solved("function_log10.json") + "' --force 0,-1",
        "--force: the four-bar has no "
        "coupler point"},
       {"'" + Solved("function_log10.json") + "' --range 30,100",
        "--range 30,100: the range asked for leaves the input's range on its circuit"},
       {"'" + result_path + "' --mass 1,2,3", "--length-unit: expected m, cm, mm, in or ft"},
       {"'" + result_path + "' --mass 1,-2,3 --length-unit mm",
        "--mass: expected the links' masses in kg"},
       {"'" + result_path + "' --gravity", "--gravity: give the links' masses"},
       {"'" + Solved("platform_7_poses.json") + "'",
        "spatial mechanisms are not analyzed or drawn yet"},
       {"'" + result_path + "' --mass 1,2,3 --length-unit yd", "got 'yd'"}});
  // With masses: the inertial torque (and the weight's) as columns and arrays, in N mm.
  const RunResult massive =
      Run("analyze '" + result_path + "' --steps 4 --mass 0.2,0.5,0.3 --length-unit mm --gravity");
  ASSERT_EQ(massive.status, 0) << massive.err;
  const nlohmann::json heavy = nlohmann::json::parse(massive.out);
  EXPECT_EQ(heavy["units"]["torque"], "N mm");
  ASSERT_EQ(heavy["inertial_torque"].size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(heavy["input_torque"][k].get<double>(),
                heavy["inertial_torque"][k].get<double>() + heavy["weight_torque"][k].get<double>(),
                1e-9 * (1.0 + std::abs(heavy["input_torque"][k].get<double>())));
  }
  const RunResult massive_csv =
      Run("analyze '" + result_path + "' --steps 4 --mass 0.2,0.5,0.3 --length-unit mm --csv");
  ASSERT_EQ(massive_csv.status, 0) << massive_csv.err;
  EXPECT_NE(massive_csv.out.find(",input_torque,inertial_torque\n"), std::string::npos);
  // A part of the range: sampled from end to end; the worst transmission angle folded.
  const RunResult part = Run("analyze '" + result_path + "' --range 70,130 --steps 7");
  ASSERT_EQ(part.status, 0) << part.err;
  const nlohmann::json sampled = nlohmann::json::parse(part.out);
  ASSERT_EQ(sampled["input_deg"].size(), 7u);
  EXPECT_NEAR(sampled["input_deg"][0].get<double>(), 70.0, 1e-9);
  EXPECT_NEAR(sampled["input_deg"][6].get<double>(), 130.0, 1e-9);
  double worst = 90.0;
  for (const auto& mu : sampled["transmission_angle_deg"]) {
    worst = std::min({worst, mu.get<double>(), 180.0 - mu.get<double>()});
  }
  EXPECT_EQ(sampled["transmission_angle_worst_deg"].get<double>(), worst);
}

// `linkfit analyze` of a six-bar result (issue 37): its five moving links, the tool frame's
// origin as the coupler point, both loops' transmission angles; a rocking input is sampled over
// the task's range by default (the input's angles at the first and last poses, the first pose's
// configuration at one end), over its whole range with --range whole; bad requests refused.
TEST_F(CliTest, AnalyzeGivesTheKinematicsOfASixBar) {
  const std::string result_path = Solved("six_bar_5_poses.json");
  const nlohmann::json result = nlohmann::json::parse(ReadFile(result_path));
  const nlohmann::json& six_bar = result["six_bars"][0];
  ASSERT_FALSE(six_bar["input_rotates_fully"].get<bool>());  // the bundled first one rocks
  const RunResult run = Run("analyze '" + result_path + "' --steps 41 --force 0,-10");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json kinematics = nlohmann::json::parse(run.out);
  EXPECT_EQ(kinematics["type"], "six-bar");
  EXPECT_EQ(kinematics["topology"], six_bar["topology"]);
  for (const char* link : {"upper_link", "forearm", "task_body", "first_link", "second_link"}) {
    for (const char* key : {"angle_deg", "angular_velocity", "angular_acceleration"}) {
      EXPECT_EQ(kinematics["links"][link][key].size(), 41u) << link << " " << key;
    }
  }
  for (const char* key :
       {"input_deg", "coupler_point", "coupler_point_velocity", "coupler_point_acceleration",
        "transmission_angle_deg", "mechanical_advantage", "input_torque"}) {
    EXPECT_EQ(kinematics[key].size(), 41u) << key;
  }
  // The task's range, from the result's input angles at the poses; the first pose at one end.
  const nlohmann::json& range = kinematics["task_range_deg"];
  EXPECT_NEAR(kinematics["input_deg"][0].get<double>(), range[0].get<double>(), 1e-9);
  EXPECT_NEAR(kinematics["input_deg"][40].get<double>(), range[1].get<double>(), 1e-9);
  double turned = 0.0;
  for (const auto& at : six_bar["input_deg"]) turned = std::min(turned, at.get<double>());
  EXPECT_NEAR(range[1].get<double>() - range[0].get<double>(), -turned, 1e-9);
  const nlohmann::json& first_pose = six_bar["task_body_at_first_pose"];
  bool at_first_pose = false;
  for (const int end : {0, 40}) {
    const nlohmann::json& p = kinematics["coupler_point"][end];
    at_first_pose |= std::hypot(p[0].get<double>() - first_pose[0].get<double>(),
                                p[1].get<double>() - first_pose[1].get<double>()) < 1e-9 &&
                     std::abs(kinematics["links"]["task_body"]["angle_deg"][end].get<double>() -
                              first_pose[2].get<double>()) < 1e-9;
  }
  EXPECT_TRUE(at_first_pose);
  // Its least transmission angle per loop over the task's range is the result's (which refines
  // between samples: the samples may stay a little above it).
  for (int l = 0; l < 2; ++l) {
    double least = 90.0;
    for (const auto& mu :
         kinematics["transmission_angles_deg"][l == 0 ? "first_link" : "second_link"]) {
      least = std::min(least, mu.get<double>());
    }
    EXPECT_GE(least, six_bar["transmission_angle_min_deg"][l].get<double>() - 1e-9);
    EXPECT_LT(least, six_bar["transmission_angle_min_deg"][l].get<double>() + 0.5);
  }
  // With its bodies' masses: the inertial and the weight's torques, the parts of the input's.
  const RunResult heavy = Run("analyze '" + result_path +
                              "' --steps 6 --mass 0.2,0.3,0.4,0.2,0.1 --length-unit mm --gravity");
  ASSERT_EQ(heavy.status, 0) << heavy.err;
  const nlohmann::json massive = nlohmann::json::parse(heavy.out);
  EXPECT_EQ(massive["units"]["torque"], "N mm");
  EXPECT_EQ(massive["masses"]["task_body"].get<double>(), 0.4);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(
        massive["input_torque"][k].get<double>(),
        massive["inertial_torque"][k].get<double>() + massive["weight_torque"][k].get<double>(),
        1e-12 * (1.0 + std::abs(massive["input_torque"][k].get<double>())));
  }
  // The whole range: between the two dead points, sampled inside them.
  const RunResult whole = Run("analyze '" + result_path + "' --steps 10 --range whole --csv");
  ASSERT_EQ(whole.status, 0) << whole.err;
  EXPECT_EQ(std::count(whole.out.begin(), whole.out.end(), '\n'), 11);
  EXPECT_EQ(whole.out.rfind("input_deg,upper_link_angle_deg,", 0), 0u);
  ExpectRefused("analyze", "-o",
                {{"'" + result_path + "' --mechanism 99", "no six-bar ranked 99"},
                 {"'" + result_path + "' --mass 1,1,1 --length-unit m",
                  "--mass: a six-bar takes five masses"},
                 {"'" + result_path + "' --slider-force 2", "a six-bar has no slider"},
                 {"'" + result_path + "' --range 0,1", "--range 0,1: the range asked for leaves"},
                 {"'" + result_path + "' --range 3", "--range: expected FROM,TO"},
                 {"'" + Solved("four_bar_5_poses.json") + "' --range task",
                  "--range task: the result does not give the crank's angles"}});
}

// A fitted four-bar (least squares, or moved into its bounds) passes its first pose only within
// its max_pose_error: its task is still its task (issue 38: the page animates each over its task
// range), while another task is refused.
TEST_F(CliTest, AnalyzeTakesAFittedFourBarsTask) {
  for (const char* name : {"four_bar_12_poses.json", "bounded_four_bar_5_poses.json",
                           "bounded_four_bar_12_poses.json"}) {
    const std::string task = std::string(LINKFIT_SOURCE_DIR) + "/data/" + name;
    const std::string result_path = Solved(name);
    const nlohmann::json result = nlohmann::json::parse(ReadFile(result_path));
    int fitted = 0;
    for (size_t k = 0; k < result["mechanisms"].size(); ++k) {
      const nlohmann::json& mechanism = result["mechanisms"][k];
      if (mechanism.value("type", "") != "4R") continue;
      fitted += mechanism.value("max_pose_error", 0.0) > 1e-9 * result["scale"].get<double>();
      const RunResult run = Run("analyze '" + result_path + "' --mechanism " +
                                std::to_string(k + 1) + " --task '" + task + "' --steps 3");
      ASSERT_EQ(run.status, 0) << name << " mechanism " << k + 1 << ": " << run.err;
      EXPECT_TRUE(nlohmann::json::parse(run.out).contains("task_range_deg"));
    }
    EXPECT_GT(fitted, 0) << name;
  }
}

// A four-bar's task range (issue 37): with its motion task, the crank's angles from the first
// pose to the last (each pose carries the input dyad's moving pivot to the crank pin), sampled
// with --range task; a rocking function generator is sampled over its precision pairs' inputs by
// default; a task that is not the result's is refused.
TEST_F(CliTest, AnalyzeSamplesAFourBarsTaskRange) {
  const std::string task = std::string(LINKFIT_SOURCE_DIR) + "/data/four_bar_5_poses.json";
  const std::string result_path = Solved("four_bar_5_poses.json");
  const nlohmann::json result = nlohmann::json::parse(ReadFile(result_path));
  const RunResult run =
      Run("analyze '" + result_path + "' --task '" + task + "' --range task --steps 9");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json kinematics = nlohmann::json::parse(run.out);
  const nlohmann::json& joints = result["mechanisms"][0]["linkage"]["joints"];
  const double crank_deg =
      std::atan2(joints["input_pin"][1].get<double>() - joints["input_pivot"][1].get<double>(),
                 joints["input_pin"][0].get<double>() - joints["input_pivot"][0].get<double>()) *
      180.0 / M_PI;
  // The bundled poses turn the first four-bar's crank from 60 to 140 degrees.
  const nlohmann::json& range = kinematics["task_range_deg"];
  EXPECT_NEAR(range[0].get<double>(), crank_deg, 1e-9);
  EXPECT_NEAR(range[1].get<double>() - range[0].get<double>(), 80.0, 1e-6);
  ASSERT_EQ(kinematics["input_deg"].size(), 9u);
  EXPECT_NEAR(kinematics["input_deg"][0].get<double>(), range[0].get<double>(), 1e-9);
  EXPECT_NEAR(kinematics["input_deg"][8].get<double>(), range[1].get<double>(), 1e-9);
  EXPECT_NEAR(kinematics["coupler_point"][0][0].get<double>(),
              joints["coupler_point"][0].get<double>(), 1e-9);
  // A rocking function generator: its precision pairs' inputs by default.
  const std::string function_path = Solved("function_log10.json");
  const nlohmann::json function = nlohmann::json::parse(ReadFile(function_path));
  const RunResult rocker = Run("analyze '" + function_path + "' --steps 5");
  ASSERT_EQ(rocker.status, 0) << rocker.err;
  const nlohmann::json rocking = nlohmann::json::parse(rocker.out);
  ASSERT_FALSE(rocking["input_rotates_fully"].get<bool>());
  const double offset = function["mechanisms"][0]["input_offset_deg"].get<double>();
  const nlohmann::json& pairs = function["precision_points"];
  EXPECT_NEAR(rocking["input_deg"][0].get<double>(), offset + pairs[0]["input_deg"].get<double>(),
              1e-9);
  EXPECT_NEAR(rocking["input_deg"][4].get<double>(),
              offset + pairs[pairs.size() - 1]["input_deg"].get<double>(), 1e-9);
  // With its task, the task's whole input range (0 to 90 degrees from the offset).
  const RunResult whole_task = Run("analyze '" + function_path + "' --steps 5 --task '" +
                                   std::string(LINKFIT_SOURCE_DIR) + "/data/function_log10.json'");
  ASSERT_EQ(whole_task.status, 0) << whole_task.err;
  const nlohmann::json on_task = nlohmann::json::parse(whole_task.out);
  EXPECT_NEAR(on_task["task_range_deg"][0].get<double>(), offset, 1e-9);
  EXPECT_NEAR(on_task["task_range_deg"][1].get<double>(), offset + 90.0, 1e-9);
  ExpectRefused("analyze", "-o",
                {{"'" + result_path + "' --task '" + std::string(LINKFIT_SOURCE_DIR) +
                      "/data/slider_crank_5_poses.json'",
                  "--task: its first pose does not put the crank pin where"},
                 {"'" + result_path + "' --task '" + std::string(LINKFIT_SOURCE_DIR) +
                      "/data/path_5_points.json'",
                  "--task: not a planar motion task"}});
}

// `linkfit analyze` of the four-bars the closed form does not take (issue 37), made from the
// bundled slider-crank result: the same slider-crank driven by its slider (input_position,
// input_force), and an inverted slider-crank (its rod through the crank pin sliding in a block
// on a ground pivot); the power balance holds at every step; masses are refused.
TEST_F(CliTest, AnalyzeGivesTheKinematicsOfOtherFourBarTypes) {
  nlohmann::json result = nlohmann::json::parse(ReadFile(Solved("slider_crank_5_poses.json")));
  const nlohmann::json joints = result["mechanisms"][0]["linkage"]["joints"];
  nlohmann::json driven = result;
  driven["mechanisms"][0]["linkage"]["joints"] = {
      {"input_pin", joints["output_pin"]},
      {"input_slider_line", joints["output_slider_line"]},
      {"output_pivot", joints["input_pivot"]},
      {"output_pin", joints["input_pin"]},
      {"coupler_point", joints["coupler_point"]}};
  const std::string driven_path = WriteTask("driven.json", driven.dump());
  const RunResult run = Run("analyze '" + driven_path + "' --steps 9 --force 3,-10");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json by_slider = nlohmann::json::parse(run.out);
  EXPECT_EQ(by_slider["input"], "slider");
  ASSERT_EQ(by_slider["input_position"].size(), 9u);
  EXPECT_TRUE(by_slider["links"]["input"].contains("position"));
  for (int k = 0; k < 9; ++k) {
    const nlohmann::json& v = by_slider["coupler_point_velocity"][k];
    const double power = by_slider["input_force"][k].get<double>() + 3.0 * v[0].get<double>() -
                         10.0 * v[1].get<double>();
    EXPECT_NEAR(power, 0.0, 1e-9 * (1.0 + std::abs(by_slider["input_force"][k].get<double>())));
  }
  // With its task, the task's range: the slider's positions from the first pose to the last; at
  // either end of it the coupler point (the tool frame's origin) is at a pose's origin.
  const std::string task_path = std::string(LINKFIT_SOURCE_DIR) + "/data/slider_crank_5_poses.json";
  const RunResult on_task =
      Run("analyze '" + driven_path + "' --task '" + task_path + "' --range task --steps 3");
  ASSERT_EQ(on_task.status, 0) << on_task.err;
  const nlohmann::json over_task = nlohmann::json::parse(on_task.out);
  const nlohmann::json task = nlohmann::json::parse(ReadFile(task_path));
  for (const int end : {0, 2}) {
    const nlohmann::json& p = over_task["coupler_point"][end];
    double nearest = 1e300;
    for (const auto& pose : task["poses"]) {
      nearest = std::min(nearest, std::hypot(p[0].get<double>() - pose["x"].get<double>(),
                                             p[1].get<double>() - pose["y"].get<double>()));
    }
    EXPECT_LT(nearest, 1e-6 * result["scale"].get<double>()) << end;
  }
  // The slider stops where the coupler and the crank align (its dead points, listed).
  ASSERT_EQ(by_slider["dead_points"].size(), 2u);
  for (const auto& dead : by_slider["dead_points"]) {
    const double mu = dead["transmission_angle_deg"].get<double>();
    EXPECT_LT(std::min(mu, 180.0 - mu), 1e-3);
  }

  nlohmann::json inverted = result;
  const std::vector<double> a = joints["input_pin"], b = joints["output_pin"];
  inverted["mechanisms"][0]["type"] = "inverted slider-crank";
  inverted["mechanisms"][0]["linkage"]["joints"] = {
      {"input_pivot", joints["input_pivot"]},
      {"input_pin", joints["input_pin"]},
      {"output_pivot", {a[0] + 1.3 * (b[0] - a[0]), a[1] + 1.3 * (b[1] - a[1])}},
      {"output_slider_line",
       {{"point", joints["input_pin"]},
        {"angle_deg", std::atan2(b[1] - a[1], b[0] - a[0]) * 180.0 / M_PI},
        {"on", "coupler"}}},
      {"coupler_point", joints["coupler_point"]}};
  const std::string inverted_path = WriteTask("inverted.json", inverted.dump());
  const RunResult rod = Run("analyze '" + inverted_path + "' --steps 12 --slider-force 10");
  ASSERT_EQ(rod.status, 0) << rod.err;
  const nlohmann::json by_crank = nlohmann::json::parse(rod.out);
  EXPECT_EQ(by_crank["type"], "inverted slider-crank");
  EXPECT_TRUE(by_crank["input_rotates_fully"].get<bool>());
  for (int k = 0; k < 12; ++k) {
    // T w + F_s s' = 0 (the cylinder's force along the rod).
    const double power = by_crank["input_torque"][k].get<double>() +
                         10.0 * by_crank["links"]["block"]["velocity"][k].get<double>();
    EXPECT_NEAR(power, 0.0, 1e-9 * (1.0 + std::abs(by_crank["input_torque"][k].get<double>())));
  }
  // With masses: the inertial and the weight's parts of the input torque.
  const RunResult heavy = Run("analyze '" + inverted_path +
                              "' --steps 5 --input-speed 20 --mass 0.1,0.5,0.2 --length-unit mm "
                              "--gravity");
  ASSERT_EQ(heavy.status, 0) << heavy.err;
  const nlohmann::json massive = nlohmann::json::parse(heavy.out);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(
        massive["input_torque"][k].get<double>(),
        massive["inertial_torque"][k].get<double>() + massive["weight_torque"][k].get<double>(),
        1e-12 * (1.0 + std::abs(massive["input_torque"][k].get<double>())));
  }
  ExpectRefused("analyze", "-o",
                {{"'" + inverted_path + "' --mass 1,1,1,1,1 --length-unit mm",
                  "--mass: a four-bar takes three masses"},
                 {"'" + driven_path + "' --range 0,10", "--range 0,10: the range asked for"}});
}

// `linkfit analyze` of a spherical four-bar (issue 37): the input and output angles and rates,
// the coupler's rotation and angular velocity and acceleration vectors, the transmission angle
// (at the first pose the result's), the torque holding an output torque; loads it cannot take
// refused.
TEST_F(CliTest, AnalyzeGivesTheKinematicsOfASphericalFourBar) {
  const std::string result_path = Solved("spherical_four_bar_5_poses.json");
  const nlohmann::json result = nlohmann::json::parse(ReadFile(result_path));
  const RunResult run = Run("analyze '" + result_path + "' --steps 12 --output-torque 2");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json kinematics = nlohmann::json::parse(run.out);
  EXPECT_EQ(kinematics["type"], "spherical 4R");
  ASSERT_EQ(kinematics["input_deg"].size(), 12u);
  EXPECT_EQ(kinematics["links"]["coupler"]["angle_deg"][0].get<double>(), 0.0);
  EXPECT_EQ(kinematics["links"]["coupler"]["angular_velocity"][3].size(), 3u);
  EXPECT_EQ(kinematics["links"]["output"]["angular_acceleration"].size(), 12u);
  const nlohmann::json& first = result["mechanisms"][0];
  ASSERT_TRUE(kinematics["input_rotates_fully"].get<bool>());  // a crank: from the first pose
  EXPECT_NEAR(kinematics["transmission_angle_deg"][0].get<double>(),
              first["transmission_angle_deg"][0].get<double>(), 1e-6);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(kinematics["input_pin"][0][c].get<double>(),
                first["linkage"]["joints"]["input_pin"][c].get<double>(), 1e-12);
    EXPECT_NEAR(kinematics["output_pin"][0][c].get<double>(),
                first["linkage"]["joints"]["output_pin"][c].get<double>(), 1e-12);
  }
  EXPECT_EQ(kinematics["input_torque"].size(), 12u);
  const RunResult csv = Run("analyze '" + result_path + "' --steps 5 --csv");
  ASSERT_EQ(csv.status, 0) << csv.err;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 6);
  // With the links' masses (arcs of the sphere): the inertial and the weight's torques.
  const RunResult heavy = Run("analyze '" + result_path +
                              "' --steps 4 --input-speed 10 --mass 0.2,0.4,0.3 --length-unit m "
                              "--gravity");
  ASSERT_EQ(heavy.status, 0) << heavy.err;
  const nlohmann::json massive = nlohmann::json::parse(heavy.out);
  EXPECT_GT(massive["masses"]["radius"].get<double>(), 0.0);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(
        massive["input_torque"][k].get<double>(),
        massive["inertial_torque"][k].get<double>() + massive["weight_torque"][k].get<double>(),
        1e-12 * (1.0 + std::abs(massive["input_torque"][k].get<double>())));
  }
  ExpectRefused("analyze", "-o",
                {{"'" + result_path + "' --force 1,0", "give --output-torque"},
                 {"'" + result_path + "' --mass 1,1,1,1,1 --length-unit m",
                  "--mass: a four-bar takes three masses"},
                 {"'" + result_path + "' --mechanism 999", "no mechanism ranked 999"}});
}

// `linkfit analyze --svg` (issue 37): a chart of four panels with a series per link (and the
// torque), a rocker's two dead points dashed on each panel; the JSON still goes to -o. Sampled
// over its task's range, the dead points far beyond it are left out of the chart.
TEST_F(CliTest, AnalyzeChartsTheAnalysis) {
  const std::string result_path = Solved("function_log10.json");
  // (Its whole range: by default a rocker is sampled over its task's, away from them.)
  const RunResult run =
      Run("analyze '" + result_path + "' --range whole --output-torque 1 --svg '" +
          Path("chart.svg") + "' -o '" + Path("kinematics.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json kinematics = nlohmann::json::parse(ReadFile(Path("kinematics.json")));
  ASSERT_EQ(kinematics["dead_points"].size(), 2u);  // its crank is a rocker
  const std::string svg = ReadFile(Path("chart.svg"));
  const auto count = [&](const std::string& what) {
    size_t n = 0;
    for (size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("class=\"series\""), 3u * 3u + 1u);  // three links in three panels, the torque
  EXPECT_EQ(count("class=\"dead-point\""), 2u * 4u);
  EXPECT_NE(svg.find("peak "), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  // --svg alone writes no JSON on stdout.
  const RunResult alone = Run("analyze '" + result_path + "' --svg '" + Path("chart2.svg") + "'");
  ASSERT_EQ(alone.status, 0) << alone.err;
  EXPECT_EQ(alone.out, "");
  const std::string task_chart = ReadFile(Path("chart2.svg"));
  EXPECT_NE(task_chart.find("transmission angle"), std::string::npos);
  // Over the task's range (its precision pairs', 52 to 138 degrees): the dead point at 48
  // degrees is drawn on each panel, the one at 165 is not.
  size_t marks = 0;
  for (size_t at = task_chart.find("class=\"dead-point\""); at != std::string::npos;
       at = task_chart.find("class=\"dead-point\"", at + 1)) {
    ++marks;
  }
  EXPECT_EQ(marks, 4u);
}

// `linkfit export --dxf` and `--svg` (issue 37): a DXF file (its content is read back by ezdxf in
// tests/python/test_linkfit.py), at a chosen crank angle too; bad requests exit 2 with one line
// and write nothing, an angle where a rocker does not assemble among them.
TEST_F(CliTest, ExportWritesADxfDrawing) {
  const std::string result_path = Solved("four_bar_5_poses.json");
  const RunResult run = Run("export '" + result_path + "' --dxf '" + Path("a.dxf") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, "");
  const std::string dxf = ReadFile(Path("a.dxf"));
  EXPECT_NE(dxf.find("SECTION\n  2\nENTITIES"), std::string::npos);
  EXPECT_EQ(dxf.substr(dxf.size() - 4), "EOF\n");
  for (const char* layer : {"GROUND", "INPUT", "COUPLER", "OUTPUT", "CURVE", "DIMENSIONS"}) {
    EXPECT_NE(dxf.find(std::string("\n") + layer + "\n"), std::string::npos) << layer;
  }
  // Another crank angle draws another configuration.
  ASSERT_EQ(
      Run("export '" + result_path + "' --input-deg 200 --dxf '" + Path("b.dxf") + "'").status, 0);
  EXPECT_NE(ReadFile(Path("b.dxf")), dxf);
  // A function generator whose crank is a rocker: an angle outside its range is refused.
  ExpectRefused("export", "--dxf",
                {{"'" + result_path + "' --mechanism 99", "no mechanism ranked 99"},
                 {"'" + Solved("function_log10.json") + "' --input-deg 270",
                  "--input-deg 270: the four-bar does not reach it on its circuit"},
                 {"'" + result_path + "' --task '" + Path("missing.json") + "'", "missing.json"},
                 {"'" + result_path + "' --task '" + std::string(LINKFIT_SOURCE_DIR) +
                      "/data/slider_crank_5_poses.json'",
                  "--task: its first pose does not put the crank pin where"},
                 {"'" + Solved("six_bar_5_poses.json") + "' --input-deg 10",
                  "--input-deg 10: the six-bar does not reach it on its assembly"},
                 {"'" + Solved("spherical_four_bar_5_poses.json") + "' --task '" +
                      std::string(LINKFIT_SOURCE_DIR) + "/data/platform_7_poses.json'",
                  "--task: its first pose does not carry the result's centre"}});
  const RunResult neither = Run("export '" + result_path + "'");
  EXPECT_EQ(neither.status, 2);
  EXPECT_NE(neither.err.find("give --dxf FILE, --svg FILE or both"), std::string::npos);
  // --svg (its content is read back in tests/python/test_linkfit.py): alone, or with --dxf, the
  // DXF then the same bytes; refused alike.
  ASSERT_EQ(Run("export '" + result_path + "' --svg '" + Path("a.svg") + "' --dxf '" +
                Path("c.dxf") + "'")
                .status,
            0);
  EXPECT_EQ(ReadFile(Path("c.dxf")), dxf);
  const std::string svg = ReadFile(Path("a.svg"));
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<g id=\"COUPLER\""), std::string::npos);
  ExpectRefused("export", "--svg",
                {{"'" + result_path + "' --mechanism 99", "no mechanism ranked 99"},
                 {"'" + Solved("function_log10.json") + "' --input-deg 270",
                  "--input-deg 270: the four-bar does not reach it on its circuit"}});
}

// A six-bar result's table (issue 36): one row per six-bar listed, in the result's order, with its
// topology, its input, its links' lengths (each RR link with the bodies it joins) as the JSON
// gives them; the bundled example's first is its defect-free Stephenson I.
TEST_F(CliTest, SummaryPrintsTheSixBars) {
  const std::string task = std::string(LINKFIT_SOURCE_DIR) + "/data/six_bar_5_poses.json";
  const std::string output_path = Path("six_bar.json");
  const RunResult run = Run("solve --summary '" + task + "' -o '" + output_path + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json written = nlohmann::json::parse(ReadFile(output_path));
  const nlohmann::json& six_bars = written["six_bars"];
  ASSERT_GT(six_bars.size(), 1u);
  EXPECT_EQ(run.out.rfind("six_bar_5_poses.json: motion (planar), six-bars, exact: " +
                              std::to_string(six_bars.size()) + " listed",
                          0),
            0u)
      << run.out;
  for (const char* column : {"topology", "input", "upper link", "forearm", "first link",
                             "second link", "RMS pose error", "full turn", "defects"}) {
    EXPECT_NE(run.out.find(column), std::string::npos) << column;
  }
  for (size_t i = 0; i < six_bars.size(); ++i) {
    const size_t at = run.out.find("\n" + std::to_string(i + 1) + "  ");
    ASSERT_NE(at, std::string::npos) << "row " << i + 1;
    const std::string row = run.out.substr(at + 1, run.out.find('\n', at + 1) - at - 1);
    const std::string topology = six_bars[i]["topology"];
    EXPECT_NE(row.find(topology), std::string::npos) << row;
    char first[32];
    std::snprintf(first, sizeof(first), "%.4g",
                  six_bars[i]["link_lengths"]["first_link"].get<double>());
    EXPECT_NE(row.find(std::string(first) + " " +
                       six_bars[i]["joints_at_first_pose"]["links"][0]["from"].get<std::string>()),
              std::string::npos)
        << row;
  }
  EXPECT_EQ(six_bars[0]["topology"], "Stephenson I");
  EXPECT_TRUE(six_bars[0]["defects"].empty());
  const RunResult shown = Run("show '" + output_path + "'");
  ASSERT_EQ(shown.status, 0) << shown.err;
  EXPECT_EQ(shown.out.substr(shown.out.find(':')), run.out.substr(run.out.find(':')));
}

// Four poses' Burmester curves are written at a drawing's resolution (issue 35: a four-pose
// result was 569 KB): the file under 50 KB, each polyline a subset of the dense one with its
// ends; --curve-points asks for more.
TEST_F(CliTest, FourPoseCurvesAreWrittenAtADrawingsResolution) {
  const std::string task = std::string(LINKFIT_SOURCE_DIR) + "/data/four_bar_4_poses.json";
  const std::string small_path = Path("small.json"), dense_path = Path("dense.json");
  ASSERT_EQ(Run("solve '" + task + "' -o '" + small_path + "'").status, 0);
  ASSERT_EQ(Run("solve '" + task + "' --curve-points 10000000 -o '" + dense_path + "'").status, 0);
  EXPECT_LT(std::filesystem::file_size(small_path), 50000u);
  const nlohmann::json small = nlohmann::json::parse(ReadFile(small_path));
  const nlohmann::json dense = nlohmann::json::parse(ReadFile(dense_path));
  for (const char* kind : {"center_points", "circle_points"}) {
    const nlohmann::json& few = small["burmester_curves"][kind];
    const nlohmann::json& many = dense["burmester_curves"][kind];
    ASSERT_EQ(few.size(), many.size()) << kind;
    size_t written = 0, solved = 0;
    for (size_t k = 0; k < few.size(); ++k) {
      written += few[k].size();
      solved += many[k].size();
      EXPECT_EQ(few[k].front(), many[k].front());
      EXPECT_EQ(few[k].back(), many[k].back());
      size_t at = 0;  // each written point is one of the dense polyline's, in order
      for (const nlohmann::json& point : few[k]) {
        while (at < many[k].size() && many[k][at] != point) ++at;
        EXPECT_LT(at, many[k].size());
      }
    }
    EXPECT_LE(written, 400u) << kind;
    EXPECT_GT(solved, 4 * written) << kind;
  }
}

// Every listed mechanism of every planar problem kind gives "linkage" (issue 35): its joints in
// one assembled configuration, whose distances are the named links.
TEST_F(CliTest, EveryMechanismGivesItsJointsAndNamedLinks) {
  for (const char* name :
       {"four_bar_5_poses.json", "slider_crank_5_poses.json", "four_bar_12_poses.json",
        "four_bar_4_poses.json", "path_12_points_untimed.json", "path_5_points.json",
        "function_log10.json", "function_3_pairs.json", "spherical_four_bar_5_poses.json"}) {
    SCOPED_TRACE(name);
    const std::string output_path = Path("result.json");
    const RunResult run = Run("solve '" + std::string(LINKFIT_SOURCE_DIR) + "/data/" + name +
                              "' -o '" + output_path + "'");
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json result = nlohmann::json::parse(ReadFile(output_path));
    const double scale = result["scale"].get<double>();
    ASSERT_FALSE(result["mechanisms"].empty());
    // A spherical four-bar's joints are unit axes and its links the angles between them (deg).
    const bool spherical = result.value("model", "") == "spherical";
    for (const nlohmann::json& mechanism : result["mechanisms"]) {
      ASSERT_TRUE(mechanism.contains("linkage")) << mechanism.dump();
      EXPECT_EQ(mechanism["linkage"].contains("units"), spherical);
      const nlohmann::json& joints = mechanism["linkage"]["joints"];
      const nlohmann::json& links = mechanism["linkage"]["links"];
      const auto point = [&](const char* key) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        for (size_t k = 0; k < joints[key].size(); ++k) p[k] = joints[key][k].get<double>();
        return p;
      };
      const auto check = [&](const char* link, const char* a, const char* b) {
        if (!joints.contains(a) || !joints.contains(b)) {
          EXPECT_FALSE(links.contains(link)) << link;
          return;
        }
        ASSERT_TRUE(links.contains(link)) << link;
        const double expected =
            spherical
                ? std::atan2(point(a).cross(point(b)).norm(), point(a).dot(point(b))) * 180.0 / M_PI
                : (point(a) - point(b)).norm();
        EXPECT_NEAR(links[link].get<double>(), expected, spherical ? 1e-6 : 1e-7 * scale)
            << link << " " << mechanism.dump();
      };
      check("ground", "input_pivot", "output_pivot");
      check("input", "input_pivot", "input_pin");
      check("coupler", "input_pin", "output_pin");
      check("output", "output_pivot", "output_pin");
    }
  }
}

}  // namespace

namespace {

constexpr double kSolveTolerance = 1e-9;  // relative to the task's L

// A result without its timing fields (they differ from run to run).
nlohmann::json Untimed(const nlohmann::json& value) {
  if (value.is_object()) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& item : value.items()) {
      const std::string& key = item.key();
      const bool timing = (key.size() > 3 && key.compare(key.size() - 3, 3, "_ms") == 0) ||
                          (key.size() > 8 && key.compare(key.size() - 8, 8, "_seconds") == 0);
      if (!timing) object[key] = Untimed(item.value());
    }
    return object;
  }
  if (value.is_array()) {
    nlohmann::json array = nlohmann::json::array();
    for (const nlohmann::json& item : value) array.push_back(Untimed(item));
    return array;
  }
  return value;
}

std::string DataPath(const std::string& name) {
  return std::string(LINKFIT_SOURCE_DIR) + "/data/" + name;
}

// True when the result lists an RR dyad with these pivots and radius, to kSolveTolerance * L.
bool HasRR(const nlohmann::json& result, double fx, double fy, double mx, double my, double r) {
  const double tolerance = kSolveTolerance * result["scale"].get<double>();
  for (const nlohmann::json& dyad : result["dyads"]) {
    if (dyad["type"] != "RR") continue;
    if (std::abs(dyad["fixed"][0].get<double>() - fx) <= tolerance &&
        std::abs(dyad["fixed"][1].get<double>() - fy) <= tolerance &&
        std::abs(dyad["moving"][0].get<double>() - mx) <= tolerance &&
        std::abs(dyad["moving"][1].get<double>() - my) <= tolerance &&
        std::abs(dyad["radius"].get<double>() - r) <= tolerance) {
      return true;
    }
  }
  return false;
}

}  // namespace

// The bundled 4R (ground pivots (0,0) and (100,0) mm, crank 37.5, coupler 87.5, rocker 75; E at
// the crank pin, x-axis toward the rocker pin) must come back with both dyads and as a 4R
// that reaches every pose.
TEST_F(CliTest, SolvesTheBundledFourBar) {
  const std::string output = Path("result.json");
  const RunResult run =
      Run("solve '" + DataPath("four_bar_5_poses.json") + "' -o '" + output + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(ReadFile(output));
  EXPECT_EQ(result["method"], "exact");
  EXPECT_EQ(result["roots"]["total"], 4);
  EXPECT_TRUE(HasRR(result, 0.0, 0.0, 0.0, 0.0, 37.5));
  EXPECT_TRUE(HasRR(result, 100.0, 0.0, 87.5, 0.0, 75.0));
  const double tolerance = kSolveTolerance * result["scale"].get<double>();
  for (const nlohmann::json& dyad : result["dyads"]) {
    EXPECT_LE(dyad["max_residual"].get<double>(), tolerance);
  }
  int four_bars = 0;
  for (const nlohmann::json& mechanism : result["mechanisms"]) {
    EXPECT_LE(mechanism["max_pose_error"].get<double>(), tolerance);
    four_bars += mechanism["type"] == "4R";
  }
  EXPECT_GE(four_bars, 1);
  // Without -o the same result goes to stdout.
  const RunResult to_stdout = Run("solve '" + DataPath("four_bar_5_poses.json") + "'");
  ASSERT_EQ(to_stdout.status, 0);
  EXPECT_EQ(nlohmann::json::parse(to_stdout.out)["dyads"], result["dyads"]);
}

// The bundled slider-crank (crank pivot (0,0), radius 30; slider pin 80 mm along E's x-axis on
// the line y = -10) must come back typed: an RR crank and a PR slider, not a huge radius.
TEST_F(CliTest, SolvesTheBundledSliderCrankAsASlider) {
  const RunResult run = Run("solve '" + DataPath("slider_crank_5_poses.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(run.out);
  const double tolerance = kSolveTolerance * result["scale"].get<double>();
  EXPECT_TRUE(HasRR(result, 0.0, 0.0, 0.0, 0.0, 30.0));
  bool slider = false;
  for (const nlohmann::json& dyad : result["dyads"]) {
    if (dyad["type"] != "PR") continue;
    const double angle = dyad["line_angle_deg"].get<double>();
    slider = slider || (std::abs(dyad["moving"][0].get<double>() - 80.0) <= tolerance &&
                        std::abs(dyad["moving"][1].get<double>()) <= tolerance &&
                        std::abs(dyad["line_point"][1].get<double>() + 10.0) <= tolerance &&
                        std::min(angle, 180.0 - angle) <= 1e-9);
  }
  EXPECT_TRUE(slider) << result.dump(2);
  bool slider_crank = false;
  for (const nlohmann::json& mechanism : result["mechanisms"]) {
    slider_crank = slider_crank || mechanism["type"] == "slider-crank";
  }
  EXPECT_TRUE(slider_crank);
}

// The same slider-crank printed to four decimals, as a table gives it: the precision is read
// from the digits and stated, the slider is still a slider, and the generating dyads come back
// within the error bounds the result states (twice: the bounds are first order).
TEST_F(CliTest, SolvesTheSliderCrankPrintedToFourDecimals) {
  const RunResult run = Run("solve '" + DataPath("slider_crank_5_poses_4_decimals.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["precision"]["source"], "digits");
  EXPECT_DOUBLE_EQ(result["precision"]["length"].get<double>(), 5e-5);
  EXPECT_DOUBLE_EQ(result["precision"]["angle_deg"].get<double>(), 5e-5);
  bool crank = false, slider = false;
  for (const nlohmann::json& dyad : result["dyads"]) {
    ASSERT_TRUE(dyad.contains("error_bound")) << dyad.dump();
    const double allowed = 2.0 * dyad["error_bound"].get<double>();
    if (dyad["type"] == "RR") {
      crank = crank || (std::hypot(dyad["fixed"][0].get<double>(),
                                   dyad["fixed"][1].get<double>()) <= allowed &&
                        std::abs(dyad["radius"].get<double>() - 30.0) <= allowed);
    } else if (dyad["type"] == "PR") {
      const double angle = dyad["line_angle_deg"].get<double>();
      slider = slider || (std::abs(dyad["moving"][0].get<double>() - 80.0) <= allowed &&
                          std::abs(dyad["moving"][1].get<double>()) <= allowed &&
                          std::abs(dyad["line_point"][1].get<double>() + 10.0) <= allowed &&
                          std::min(angle, 180.0 - angle) * M_PI / 180.0 * 80.0 <= allowed);
    }
  }
  EXPECT_TRUE(crank) << result.dump(2);
  EXPECT_TRUE(slider) << result.dump(2);
}

// Batch mode: one result line per task line, in order.
TEST_F(CliTest, SolvesAJsonLinesBatch) {
  const RunResult run = Run("solve '" + DataPath("batch.jsonl") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  std::istringstream lines(run.out);
  std::string line;
  std::vector<nlohmann::json> results;
  while (std::getline(lines, line)) results.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_TRUE(HasRR(results[0], 100.0, 0.0, 87.5, 0.0, 75.0));
  EXPECT_TRUE(HasRR(results[1], 0.0, 0.0, 0.0, 0.0, 30.0));
}

// A batch streams through chunks solved on --jobs threads: every job count gives the results of
// solving the lines one by one, in input order, over more lines than a chunk holds (4096) and with
// blank lines between; a bad line past the first chunk leaves no result file and nothing on
// stdout.
TEST_F(CliTest, BatchKeepsTheInputOrderOnEveryJobCount) {
  std::vector<std::string> kinds;
  for (const char* name : {"four_bar_5_poses.json", "slider_crank_5_poses.json",
                           "path_5_points.json", "four_bar_3_poses.json"}) {
    kinds.push_back(nlohmann::json::parse(ReadFile(DataPath(name))).dump());
  }
  std::string text;
  constexpr int kLines = 4500;
  for (int i = 0; i < kLines; ++i)
    text += kinds[i % kinds.size()] + (i % 1000 == 7 ? "\n\n" : "\n");
  const std::string batch = WriteTask("big.jsonl", text);
  std::vector<std::string> expected;
  for (const std::string& kind : kinds) {
    const RunResult one = Run("solve '" + WriteTask("one.jsonl", kind + "\n") + "'");
    ASSERT_EQ(one.status, 0) << one.err;
    expected.push_back(Untimed(nlohmann::json::parse(one.out)).dump());
  }
  for (const char* jobs : {"1", "2", "3"}) {
    SCOPED_TRACE(std::string("--jobs ") + jobs);
    const std::string output = Path(std::string("big_") + jobs + ".jsonl");
    const RunResult run = Run("solve '" + batch + "' --jobs " + jobs + " -o '" + output + "'");
    ASSERT_EQ(run.status, 0) << run.err;
    std::istringstream lines(ReadFile(output));
    std::string line;
    int count = 0;
    while (std::getline(lines, line)) {
      ASSERT_EQ(Untimed(nlohmann::json::parse(line)).dump(), expected[count % kinds.size()])
          << "line " << count + 1;
      ++count;
    }
    EXPECT_EQ(count, kLines);
  }
  // Line 4400 (in the second chunk) bad: exit 2, one line naming it, no result anywhere.
  std::string bad_text;
  for (int i = 0; i < 4400; ++i) bad_text += kinds[0] + "\n";
  bad_text += "{\"poses\": 3}\n" + kinds[0] + "\n";
  const std::string bad = WriteTask("bad.jsonl", bad_text);
  const std::string output = Path("bad_results.jsonl");
  for (const std::string& target : {std::string(" -o '") + output + "'", std::string()}) {
    const RunResult run = Run("solve '" + bad + "'" + target);
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.err,
              "linkfit: error: " + bad + ":4401: poses: expected an array, got a number\n");
    EXPECT_TRUE(run.out.empty());
    EXPECT_FALSE(std::filesystem::exists(output));
  }
}

// --svg and --animate draw the bundled four-bar: well-formed files that render, written along
// with the result.
TEST_F(CliTest, DrawsAndAnimatesTheBundledFourBar) {
  const std::string svg = Path("four_bar.svg"), svg_png = Path("four_bar.png");
  const std::string animation = Path("four_bar_animation.svg"), page = Path("four_bar.html");
  const RunResult run =
      Run("solve '" + DataPath("four_bar_5_poses.json") + "' -o '" + Path("result.json") +
          "' --svg '" + svg + "' --animate '" + animation + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(std::filesystem::exists(Path("result.json")));
  for (const std::string& file : {svg, animation}) {
    ASSERT_TRUE(std::filesystem::exists(file)) << file;
    EXPECT_EQ(std::system(("xmllint --noout '" + file + "'").c_str()), 0) << file;
  }
  EXPECT_NE(ReadFile(animation).find("<animate"), std::string::npos);
  // The drawing names the best mechanism and renders to a picture of some substance.
  EXPECT_NE(ReadFile(svg).find("crank-rocker"), std::string::npos);
  ASSERT_EQ(std::system(("rsvg-convert -o '" + svg_png + "' '" + svg + "'").c_str()), 0);
  EXPECT_GT(std::filesystem::file_size(svg_png), 10000u);
  // An .html animation of the second mechanism.
  const RunResult html = Run("solve '" + DataPath("four_bar_5_poses.json") + "' -o '" +
                             Path("result.json") + "' --animate '" + page + "' --mechanism 2");
  ASSERT_EQ(html.status, 0) << html.err;
  EXPECT_NE(ReadFile(page).find("<script"), std::string::npos);
}

// The bundled five timed points (a crank-rocker in mm, points rounded to 0.001 mm, angles to
// 0.1 degree): every four-bar through them, the designed one among them, drawn.
TEST_F(CliTest, SolvesAndDrawsTheBundledTimedPath) {
  const std::string output = Path("path.json"), svg = Path("path.svg"), png = Path("path.png");
  const RunResult run = Run("solve '" + DataPath("path_5_points.json") + "' -o '" + output +
                            "' --svg '" + svg + "' --animate '" + Path("path_animation.svg") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(ReadFile(output));
  EXPECT_EQ(result["problem"], "path");
  EXPECT_EQ(result["method"], "exact");
  EXPECT_EQ(result["roots"]["cranks"], 4);
  EXPECT_EQ(result["roots"]["four_bars"], 12);
  ASSERT_FALSE(result["mechanisms"].empty());
  EXPECT_LE(result["mechanisms"].size(), 12u);
  // The designed crank-rocker: crank pivot (0, 0), pin (34.641, 20), rocker pivot (120, 0). The
  // rounding of the angles moves the pivots by some hundredths of a millimetre.
  constexpr double kRounding = 0.05;
  bool designed = false;
  for (const nlohmann::json& mechanism : result["mechanisms"]) {
    EXPECT_TRUE(mechanism.contains("coupler_point"));
    if (mechanism["type"] == "4R" && mechanism["defects"].empty() &&
        std::hypot(mechanism["input_pivot"][0].get<double>(),
                   mechanism["input_pivot"][1].get<double>()) < kRounding &&
        std::hypot(mechanism["output_pivot"][0].get<double>() - 120.0,
                   mechanism["output_pivot"][1].get<double>()) < kRounding) {
      designed = true;
      EXPECT_LT(mechanism["max_point_error"].get<double>(), 1e-9);  // exact through the data
      EXPECT_EQ(mechanism["grashof"], "crank-rocker");
    }
  }
  EXPECT_TRUE(designed) << result.dump(2);
  EXPECT_EQ(std::system(("xmllint --noout '" + svg + "'").c_str()), 0);
  EXPECT_NE(ReadFile(svg).find("coupler curve (coupler point)"), std::string::npos);
  ASSERT_EQ(std::system(("rsvg-convert -o '" + png + "' '" + svg + "'").c_str()), 0);
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
  EXPECT_NE(ReadFile(Path("path_animation.svg")).find("<animate"), std::string::npos);
}

// Twelve timed points of the same crank-rocker: least squares; without the angles: free timing.
TEST_F(CliTest, FitsTwelvePointsWithAndWithoutTiming) {
  const RunResult timed = Run("solve '" + DataPath("path_12_points.json") + "'");
  ASSERT_EQ(timed.status, 0) << timed.err;
  const nlohmann::json result = nlohmann::json::parse(timed.out);
  EXPECT_EQ(result["method"], "least-squares");
  EXPECT_EQ(result["timing"], "prescribed");
  ASSERT_FALSE(result["mechanisms"].empty());
  // Angles rounded to 0.1 degree on a 40 mm crank: about 0.03 mm.
  EXPECT_LT(result["mechanisms"][0]["max_point_error"].get<double>(), 0.05);
  EXPECT_TRUE(result["mechanisms"][0].contains("before_refinement"));

  const RunResult untimed = Run("solve '" + DataPath("path_12_points_untimed.json") + "'");
  ASSERT_EQ(untimed.status, 0) << untimed.err;
  const nlohmann::json free = nlohmann::json::parse(untimed.out);
  EXPECT_EQ(free["timing"], "free");
  ASSERT_FALSE(free["mechanisms"].empty());
  const nlohmann::json& best = free["mechanisms"][0];
  EXPECT_LT(best["max_point_error"].get<double>(), 0.01);
  ASSERT_EQ(best["input_deg"].size(), 12u);
  // The designed crank turns 300/11 degrees between points.
  for (size_t j = 1; j < 12; ++j) {
    EXPECT_NEAR(
        std::abs(best["input_deg"][j].get<double>() - best["input_deg"][j - 1].get<double>()),
        300.0 / 11.0, 0.5);
  }
}

TEST_F(CliTest, AnimatingAMechanismThatIsNotListedWritesNothing) {
  const std::string animation = Path("animation.svg");
  const RunResult run = Run("solve '" + DataPath("four_bar_5_poses.json") + "' -o '" +
                            Path("result.json") + "' --animate '" + animation + "' --mechanism 99");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("--mechanism 99"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(animation));
  EXPECT_FALSE(std::filesystem::exists(Path("result.json")));
}

// The bundled spatial task: seven poses of a 5-SS platform (body points 60, 55, ... mm from E's
// origin; centers 120..180 mm below). All 20 roots are found, the five generating SS dyads are
// among the real ones, and the platform built of them (--platform) passes every pose on one
// branch, in order.
TEST_F(CliTest, SolvesTheBundledPlatform) {
  const RunResult run = Run("solve '" + DataPath("platform_7_poses.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["space"], "spatial");
  EXPECT_EQ(result["model"], "spatial");
  EXPECT_EQ(result["roots"]["total"], 20);
  const double tolerance = kSolveTolerance * result["scale"].get<double>();
  const double planted[5][6] = {{120, -30, -90, 60, 0, 0},
                                {50, 130, -100, 20, 55, 0},
                                {-130, 60, -80, -50, 35, 10},
                                {-100, -120, -90, -45, -40, 0},
                                {70, -130, -110, 15, -60, -10}};
  std::vector<int> indices;
  for (const auto& expected : planted) {
    int found = -1;
    for (size_t i = 0; i < result["dyads"].size(); ++i) {
      const nlohmann::json& dyad = result["dyads"][i];
      EXPECT_LE(dyad["max_residual"].get<double>(), tolerance);
      if (dyad["type"] != "SS") continue;
      bool same = true;
      for (int k = 0; k < 3; ++k) {
        same &= std::abs(dyad["fixed"][k].get<double>() - expected[k]) <= tolerance &&
                std::abs(dyad["moving"][k].get<double>() - expected[3 + k]) <= tolerance;
      }
      if (same) found = static_cast<int>(i);
    }
    ASSERT_GE(found, 0) << "dyad centered at " << expected[0] << ", " << expected[1];
    indices.push_back(found);
  }
  // By default the five smallest radii make the platform.
  ASSERT_EQ(result["mechanisms"].size(), 1u);
  EXPECT_EQ(result["mechanisms"][0]["dyads"], nlohmann::json({0, 1, 2, 3, 4}));
  std::string list;
  for (int index : indices) list += (list.empty() ? "" : ",") + std::to_string(index);
  const RunResult chosen =
      Run("solve '" + DataPath("platform_7_poses.json") + "' --platform " + list);
  ASSERT_EQ(chosen.status, 0) << chosen.err;
  const nlohmann::json platform = nlohmann::json::parse(chosen.out)["mechanisms"][0];
  EXPECT_TRUE(platform["assembles"].get<bool>());
  EXPECT_TRUE(platform["one_branch"].get<bool>());
  EXPECT_LE(platform["max_pose_error"].get<double>(), tolerance);
  EXPECT_EQ(platform["order"], nlohmann::json({0, 1, 2, 3, 4, 5, 6}));
}

// The bundled spherical four-bar (data/spherical_four_bar_5_poses.json: five orientations of a
// spherical 4R about the centre [1.2, -0.5, 0.8], printed to six digits, made by
// tests/support/random_spherical.h): solved as spherical, both generating dyads back within what
// six digits allow, their four-bar listed; drawn as an orthographic view; not animated.
TEST_F(CliTest, SolvesTheBundledFunctionGenerators) {
  // Three absolute pairs printed to two decimals, of the crank-rocker with cranks 40 and 80,
  // coupler 110 and ground 100: Freudenstein's equation gives it back within its error bound.
  RunResult run = Run("solve '" + DataPath("function_3_pairs.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  nlohmann::json result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["problem"], "function");
  EXPECT_EQ(result["method"], "exact");
  ASSERT_EQ(result["mechanisms"].size(), 1u) << run.out;
  const nlohmann::json& first = result["mechanisms"][0];
  const double bound = first["error_bound"].get<double>();
  EXPECT_LT(bound, 0.5);
  EXPECT_NEAR(first["input_length"].get<double>(), 40.0, bound);
  EXPECT_NEAR(first["coupler_length"].get<double>(), 110.0, bound);
  EXPECT_NEAR(first["output_length"].get<double>(), 80.0, bound);
  EXPECT_EQ(first["grashof"], "crank-rocker");
  EXPECT_EQ(first["defects"], nlohmann::json::array());
  // The first pair's configuration: the input crank at 40 degrees from the ground line.
  EXPECT_NEAR(first["input_moving"][0].get<double>(),
              first["input_length"].get<double>() * std::cos(40.0 * M_PI / 180.0), 1e-9);
  // y = log10 x through five Chebyshev precision points (relative angles).
  run = Run("solve '" + DataPath("function_log10.json") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["angles"], "relative");
  EXPECT_EQ(result["precision_points"].size(), 5u);
  ASSERT_FALSE(result["mechanisms"].empty());
  EXPECT_LT(result["mechanisms"][0]["max_angle_error_deg"].get<double>(), 1e-9);
  EXPECT_LT(result["mechanisms"][0]["function_max_error_deg"].get<double>(), 1.0);
  // Pictures draw motion and path tasks: --svg says so (exit 2).
  run = Run("solve '" + DataPath("function_3_pairs.json") + "' --svg '" + Path("f.svg") + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("function generators are not drawn"), std::string::npos) << run.err;
}

TEST_F(CliTest, SolvesAndDrawsTheBundledSphericalFourBar) {
  const std::string svg = Path("sphere.svg");
  const RunResult run =
      Run("solve '" + DataPath("spherical_four_bar_5_poses.json") + "' --svg '" + svg + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["model"], "spherical");
  EXPECT_EQ(result["method"], "exact");
  EXPECT_EQ(result["roots"]["total"], 6);
  // The constraints the four-bars were judged by: the default transmission angle, no lengths
  // (a spherical four-bar's links are angles).
  EXPECT_EQ(result["constraints"], nlohmann::json::parse(R"({"min_transmission_angle_deg": 30.0,
                                      "defaults": ["min_transmission_angle_deg"]})"));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(result["center"][k].get<double>(), (std::vector<double>{1.2, -0.5, 0.8})[k], 1e-5);
  }
  // The generating dyads (fixed axis, moving axis, angle in degrees), each within the error bound
  // its listed dyad states (six digits: a few thousandths of a degree).
  const double planted[2][7] = {
      {-0.386329, 0.686501, -0.616008, -0.891556, 0.382512, -0.242514, 40.8505},
      {0.272805, 0.454243, 0.84808, -0.539467, 0.520343, 0.661981, 49.4127}};
  const auto axis = [](const nlohmann::json& json) {
    return Eigen::Vector3d(json[0].get<double>(), json[1].get<double>(), json[2].get<double>());
  };
  std::vector<int> found;
  for (const auto& expected : planted) {
    for (size_t i = 0; i < result["dyads"].size(); ++i) {
      const nlohmann::json& dyad = result["dyads"][i];
      EXPECT_EQ(dyad["type"], "RR");
      ASSERT_TRUE(dyad.contains("error_bound_deg")) << dyad;
      const double bound = dyad["error_bound_deg"].get<double>();
      EXPECT_LT(bound, 0.01);
      const double fixed_deg =
          linkfit::DirectionAngle(axis(dyad["fixed_axis"]),
                                  Eigen::Vector3d(expected[0], expected[1], expected[2])) *
          180.0 / M_PI;
      const double moving_deg =
          linkfit::DirectionAngle(axis(dyad["moving_axis"]),
                                  Eigen::Vector3d(expected[3], expected[4], expected[5])) *
          180.0 / M_PI;
      const bool same = std::abs(dyad["angle_deg"].get<double>() - expected[6]) <= bound &&
                        fixed_deg <= bound && moving_deg <= bound;
      if (same) found.push_back(static_cast<int>(i));
    }
  }
  ASSERT_EQ(found.size(), 2u) << run.out;
  bool listed = false;
  for (const nlohmann::json& mechanism : result["mechanisms"]) {
    const nlohmann::json pair = mechanism["dyads"];
    if ((pair[0] == found[0] && pair[1] == found[1]) ||
        (pair[0] == found[1] && pair[1] == found[0])) {
      listed = true;
      EXPECT_LE(mechanism["max_pose_error"].get<double>(), 1e-5);
      EXPECT_EQ(mechanism["type"], "4R");
    }
  }
  EXPECT_TRUE(listed);
  const std::string picture = ReadFile(svg);
  EXPECT_NE(picture.find("orthographic view of the unit sphere"), std::string::npos);
  EXPECT_NE(picture.find("spherical 4R"), std::string::npos);
  EXPECT_EQ(picture.find("nan"), std::string::npos);
  const RunResult animate = Run("solve '" + DataPath("spherical_four_bar_5_poses.json") +
                                "' --animate '" + Path("sphere_anim.svg") + "'");
  EXPECT_EQ(animate.status, 2);
  EXPECT_NE(animate.err.find("a spherical result is drawn by --svg"), std::string::npos)
      << animate.err;
}

// Spatial tasks that are not seven general poses: fewer poses give the family's dimension in a
// note; planar data are solved as planar and say so; pictures of a spatial platform and
// --platform on a planar task are usage errors.
TEST_F(CliTest, SpatialTasksThatNeedLessThanSpace) {
  const std::string five = WriteTask("five.json", R"({"space": "spatial", "poses": [
      {"axis": [0, 0, 1], "angle_deg": 0, "translation": [0, 0, 0]},
      {"axis": [1, 0, 0], "angle_deg": 20, "translation": [1, 0, 0]},
      {"axis": [0, 1, 0], "angle_deg": 40, "translation": [1, 1, 0]},
      {"axis": [1, 1, 0], "angle_deg": 30, "translation": [0, 1, 1]},
      {"axis": [0, 1, 1], "angle_deg": 50, "translation": [0, 0, 1]}]})");
  const RunResult family = Run("solve '" + five + "'");
  ASSERT_EQ(family.status, 0) << family.err;
  const nlohmann::json family_result = nlohmann::json::parse(family.out);
  EXPECT_TRUE(family_result["dyads"].empty());
  EXPECT_NE(family_result["notes"][0].get<std::string>().find("2-parameter family"),
            std::string::npos);

  // The bundled planar four-bar poses, turned about the x-axis into the plane y = z.
  std::string planar = R"({"space": "spatial", "poses": [)";
  const nlohmann::json four_bar =
      nlohmann::json::parse(ReadFile(DataPath("four_bar_5_poses.json")));
  const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
  for (size_t j = 0; j < four_bar["poses"].size(); ++j) {
    const nlohmann::json& pose = four_bar["poses"][j];
    const double x = pose["x"], y = pose["y"], theta = pose["theta_deg"];
    planar += (j ? "," : "") + nlohmann::json({{"axis", {0.0, -s, c}},
                                               {"angle_deg", theta},
                                               {"translation", {x, c * y, s * y}}})
                                   .dump();
  }
  const std::string planar_path = WriteTask("planar.json", planar + "]}");
  const RunResult solved = Run("solve '" + planar_path + "'");
  ASSERT_EQ(solved.status, 0) << solved.err;
  const nlohmann::json planar_result = nlohmann::json::parse(solved.out);
  EXPECT_EQ(planar_result["model"], "planar");
  const double tolerance = kSolveTolerance * planar_result["scale"].get<double>();
  bool rocker = false;  // the rocker: fixed (100, 0) in the plane, moving (87.5, 0), radius 75
  for (const nlohmann::json& dyad : planar_result["dyads"]) {
    if (dyad["type"] != "RR") continue;
    rocker |= std::abs(dyad["fixed"][0].get<double>() - 100.0) <= tolerance &&
              std::abs(dyad["fixed"][1].get<double>()) <= tolerance &&
              std::abs(dyad["radius"].get<double>() - 75.0) <= tolerance;
  }
  EXPECT_TRUE(rocker) << planar_result.dump(2);
  EXPECT_FALSE(planar_result["mechanisms"].empty());
  EXPECT_EQ(Run("solve '" + planar_path + "' --svg '" + Path("planar.svg") + "'").status, 0);

  const RunResult picture =
      Run("solve '" + DataPath("platform_7_poses.json") + "' --svg '" + Path("platform.svg") + "'");
  EXPECT_EQ(picture.status, 2);
  EXPECT_FALSE(std::filesystem::exists(Path("platform.svg")));
  EXPECT_EQ(Run("solve '" + DataPath("four_bar_5_poses.json") + "' --platform 0,1,2,3,4").status,
            2);
}

// Approximate synthesis: twelve poses of the bundled 4R, rounded to 0.001 mm and 0.001 deg.
// Every effort level gives a least-squares result; balanced (the default) finds the 4R to the
// rounding, and `refine` takes the result file as a design.
TEST_F(CliTest, FitsTwelveRoundedPosesAndRefinesTheResult) {
  const std::string output = Path("result.json");
  const RunResult run =
      Run("solve '" + DataPath("four_bar_12_poses.json") + "' -o '" + output + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json result = nlohmann::json::parse(ReadFile(output));
  EXPECT_EQ(result["method"], "least-squares");
  EXPECT_EQ(result["effort"], "balanced");
  ASSERT_FALSE(result["stages"].empty());
  // Rounding of 0.0005 mm leaves the pivots within about 0.05 mm.
  constexpr double kRounding = 0.05;
  const auto near_rr = [&](double fx, double fy, double r) {
    for (const nlohmann::json& dyad : result["dyads"]) {
      if (dyad["type"] == "RR" && std::abs(dyad["fixed"][0].get<double>() - fx) < kRounding &&
          std::abs(dyad["fixed"][1].get<double>() - fy) < kRounding &&
          std::abs(dyad["radius"].get<double>() - r) < kRounding) {
        return true;
      }
    }
    return false;
  };
  EXPECT_TRUE(near_rr(0.0, 0.0, 37.5)) << result.dump(2);
  EXPECT_TRUE(near_rr(100.0, 0.0, 75.0));
  ASSERT_FALSE(result["mechanisms"].empty());
  EXPECT_LT(result["mechanisms"][0]["max_pose_error"].get<double>(), 2e-3);

  for (const char* effort : {"fast", "thorough"}) {
    const RunResult other =
        Run("solve '" + DataPath("four_bar_12_poses.json") + "' --effort " + effort);
    ASSERT_EQ(other.status, 0) << other.err;
    EXPECT_EQ(nlohmann::json::parse(other.out)["effort"], effort);
  }
  EXPECT_EQ(Run("solve '" + DataPath("four_bar_12_poses.json") + "' --effort best").status, 2);

  const RunResult refined =
      Run("refine '" + DataPath("four_bar_12_poses.json") + "' '" + output + "'");
  ASSERT_EQ(refined.status, 0) << refined.err;
  const nlohmann::json after = nlohmann::json::parse(refined.out);
  EXPECT_EQ(after["method"], "refine");
  ASSERT_EQ(after["mechanisms"].size(), 1u);
  EXPECT_LE(after["mechanisms"][0]["max_pose_error"].get<double>(),
            result["mechanisms"][0]["max_pose_error"].get<double>() * (1 + 1e-9));
  EXPECT_NE(after["notes"][0].get<std::string>().find("before"), std::string::npos);

  // A hand-written design with a bad dyad type is bad input.
  const std::string design = WriteTask("design.json", R"({"dyads": [{"type": "RS"}]})");
  const RunResult bad = Run("refine '" + DataPath("four_bar_12_poses.json") + "' '" + design + "'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("dyads[0].type"), std::string::npos) << bad.err;
}

// `refine` takes every kind of task: a path result (prescribed and free timing) and a spatial
// result as designs, and path and spatial designs written by hand; a bad design exits 2 with
// one line naming the design and the item.
TEST_F(CliTest, RefinesPathAndSpatialDesigns) {
  for (const char* task : {"path_12_points.json", "path_12_points_untimed.json"}) {
    SCOPED_TRACE(task);
    const std::string solved = Path(std::string("solved_") + task);
    ASSERT_EQ(Run("solve '" + DataPath(task) + "' -o '" + solved + "'").status, 0);
    const nlohmann::json before = nlohmann::json::parse(ReadFile(solved));
    // The second listed four-bar: a seed left less refined than the first.
    const RunResult run = Run("refine '" + DataPath(task) + "' '" + solved + "' --mechanism 2");
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json after = nlohmann::json::parse(run.out);
    EXPECT_EQ(after["problem"], "path");
    EXPECT_EQ(after["method"], "refine");
    EXPECT_EQ(after["timing"], before["timing"]);
    ASSERT_EQ(after["mechanisms"].size(), 1u);
    const nlohmann::json& refined = after["mechanisms"][0];
    EXPECT_LE(refined["max_point_error"].get<double>(),
              before["mechanisms"][1]["max_point_error"].get<double>() * (1 + 1e-9));
    // The design as written (the output's radius follows from its pivots) is the listed one to
    // the last few digits.
    EXPECT_NEAR(refined["before_refinement"]["max_point_error"].get<double>(),
                before["mechanisms"][1]["max_point_error"].get<double>(),
                1e-9 * before["mechanisms"][1]["max_point_error"].get<double>());
    EXPECT_NE(after["notes"][0].get<std::string>().find("point error before"), std::string::npos);
  }

  // A path four-bar by hand: a four-bar `solve` lists first for data/path_12_points.json (with
  // its timed cognate, of the same fit, the more compact of the two listed first), rounded to
  // whole millimetres: it comes back to that four-bar.
  const std::string hand = WriteTask("path_design.json", R"({"mechanisms": [{"type": "4R",
      "input_pivot": [0, 0], "input_moving": [35, 20], "output_pivot": [120, 0],
      "output_moving": [127, 80], "coupler_point": [56, 88]}]})");
  const RunResult by_hand = Run("refine '" + DataPath("path_12_points.json") + "' '" + hand + "'");
  ASSERT_EQ(by_hand.status, 0) << by_hand.err;
  const nlohmann::json hand_result = nlohmann::json::parse(by_hand.out)["mechanisms"][0];
  EXPECT_EQ(hand_result["type"], "4R");
  EXPECT_GT(hand_result["before_refinement"]["max_point_error"].get<double>(), 0.3);
  const nlohmann::json listed =
      nlohmann::json::parse(ReadFile(Path("solved_path_12_points.json")))["mechanisms"];
  ASSERT_GE(listed.size(), 2u);
  EXPECT_NEAR(listed[0]["max_point_error"].get<double>(),
              listed[1]["max_point_error"].get<double>(), 1e-6);
  const nlohmann::json& first = std::abs(listed[0]["input_pivot"][0].get<double>() -
                                         hand_result["input_pivot"][0].get<double>()) <
                                        std::abs(listed[1]["input_pivot"][0].get<double>() -
                                                 hand_result["input_pivot"][0].get<double>())
                                    ? listed[0]
                                    : listed[1];
  EXPECT_NEAR(hand_result["max_point_error"].get<double>(), first["max_point_error"].get<double>(),
              1e-6);
  for (const char* pivot : {"input_pivot", "output_pivot", "coupler_point"}) {
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(hand_result[pivot][k].get<double>(), first[pivot][k].get<double>(), 1e-4);
    }
  }

  const std::string spatial = Path("spatial.json");
  ASSERT_EQ(Run("solve '" + DataPath("platform_7_poses.json") + "' -o '" + spatial + "'").status,
            0);
  const RunResult platform =
      Run("refine '" + DataPath("platform_7_poses.json") + "' '" + spatial + "'");
  ASSERT_EQ(platform.status, 0) << platform.err;
  const nlohmann::json platform_result = nlohmann::json::parse(platform.out);
  EXPECT_EQ(platform_result["method"], "refine");
  EXPECT_EQ(platform_result["dyads"].size(), 5u);
  ASSERT_EQ(platform_result["mechanisms"].size(), 1u);
  EXPECT_EQ(platform_result["mechanisms"][0]["dyads"], nlohmann::json({0, 1, 2, 3, 4}));

  const auto bad = [&](const std::string& task, const std::string& design_text,
                       const std::string& args = "") {
    const std::string design = WriteTask("bad_design.json", design_text);
    const RunResult run = Run("refine '" + DataPath(task) + "' '" + design + "'" + args);
    EXPECT_EQ(run.status, 2) << run.out;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    return run.err;
  };
  EXPECT_NE(bad("path_12_points.json", R"({"mechanisms": [{"type": "4R", "input_pivot": [0, 0]}]})")
                .find("bad_design.json: mechanisms[0].input_moving: missing field"),
            std::string::npos);
  EXPECT_NE(bad("path_12_points.json", R"({"mechanisms": [{"type": "RRRR"}]})")
                .find("mechanisms[0].type: expected \"4R\""),
            std::string::npos);
  EXPECT_NE(bad("platform_7_poses.json", R"({"dyads": [{"type": "SS", "fixed": [0, 0, 0],
                    "moving": [1, 0, 0], "radius": -1}]})")
                .find("bad_design.json: dyads[0].radius: must be positive"),
            std::string::npos);
  EXPECT_NE(bad("platform_7_poses.json", R"({"dyads": [{"type": "PS", "moving": [0, 0, 0],
                    "plane_normal": [0, 0, 0], "plane_offset": 1}]})")
                .find("dyads[0].plane_normal: a plane normal must not be zero"),
            std::string::npos);
  EXPECT_NE(bad("path_12_points.json", ReadFile(DataPath("path_12_points.json")), " --mechanism 1")
                .find("mechanisms: missing field"),
            std::string::npos);
  EXPECT_NE(
      bad("path_12_points.json", ReadFile(Path("solved_path_12_points.json")), " --mechanism 40")
          .find("--mechanism 40: the design lists"),
      std::string::npos);
}
