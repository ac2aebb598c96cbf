// The bad-input matrix of the design ("Errors"), run through the `linkfit` program as a user
// runs it: for every kind of bad task file, `linkfit solve case.json -o out.json` exits 2 with
// one printable line on stderr that starts with the file name and names the item, and writes
// nothing. Also: a task of 10^6 poses is refused in bounded memory.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/apps/program_run.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LINKFIT_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define LINKFIT_UNDER_ASAN 1
#endif

namespace {

// The five distinct planar poses of a minimal motion task (as in test_cli.cc).
const char* const kPoses[5] = {
    R"({"x": 0.0, "y": 0.0, "theta_deg": 0.0})", R"({"x": 1.0, "y": 0.0, "theta_deg": 10.0})",
    R"({"x": 2.0, "y": 1.0, "theta_deg": 20.0})", R"({"x": 1.0, "y": 2.0, "theta_deg": 30.0})",
    R"({"x": 0.0, "y": 1.0, "theta_deg": 40.0})"};

std::vector<std::string> FivePoses() { return {kPoses, kPoses + 5}; }

// A planar motion task with the given pose texts, pretty-printed one pose a line.
std::string MotionTask(const std::vector<std::string>& poses) {
  std::string text = "{\n  \"problem\": \"motion\",\n  \"poses\": [\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    text += "    " + poses[i] + (i + 1 < poses.size() ? ",\n" : "\n");
  }
  return text + "  ]\n}\n";
}

// The same five poses on one line (a JSON-lines task).
std::string MotionTaskLine(const std::vector<std::string>& poses) {
  std::string text = R"({"problem": "motion", "poses": [)";
  for (size_t i = 0; i < poses.size(); ++i) text += (i ? ", " : "") + poses[i];
  return text + "]}";
}

// A spatial motion task whose third pose is `third` (dual-quaternion form, eqs. 2 and 3).
std::string SpatialTask(const std::string& third) {
  return R"({"space": "spatial", "poses": [
    {"q": [0, 0, 0, 1], "g": [0.5, 0, 0, 0]},
    {"axis": [0, 0, 1], "angle_deg": 30, "translation": [1, 1, 1]},
    )" + third +
         "]}\n";
}

// A timed path task with the given point texts.
std::string PathTask(const std::vector<std::string>& points) {
  std::string text = "{\"problem\": \"path\", \"points\": [\n";
  for (size_t i = 0; i < points.size(); ++i) {
    text += "  " + points[i] + (i + 1 < points.size() ? ",\n" : "\n");
  }
  return text + "]}\n";
}

const std::vector<std::string> kPoints = {R"({"x": 56.421, "y": 87.644, "input_deg": 30.0})",
                                          R"({"x": 26.434, "y": 99.438, "input_deg": 105.0})",
                                          R"({"x": -11.682, "y": 65.177, "input_deg": 180.0})",
                                          R"({"x": -12.640, "y": 32.390, "input_deg": 255.0})",
                                          R"({"x": 24.105, "y": 50.278, "input_deg": 330.0})"};

std::vector<std::string> With(std::vector<std::string> items, size_t index,
                              const std::string& item) {
  items[index] = item;
  return items;
}

// `text` cut just after the first occurrence of `mark` at or after the occurrence of `after`.
std::string CutAfter(const std::string& text, const std::string& after, const std::string& mark) {
  const size_t start = text.find(after);
  const size_t at = text.find(mark, start == std::string::npos ? 0 : start);
  EXPECT_NE(start, std::string::npos) << after;
  EXPECT_NE(at, std::string::npos) << mark;
  return text.substr(0, at + mark.size());
}

struct RunResult {
  int status = -1;       // exit status, -1 when the program did not exit normally
  long max_rss_kb = -1;  // the program's peak resident set size
  std::string out;
  std::string err;
};

class BadInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/linkfit_bad_input_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
  }

  // Runs `linkfit ARGS` in the temporary directory (tests/apps/program_run.h).
  RunResult Run(const std::vector<std::string>& args) const {
    linkfit::testing::ProgramOptions options;
    options.directory = dir_;
    const linkfit::testing::ProgramResult run =
        linkfit::testing::RunProgram(LINKFIT_BINARY, args, options);
    RunResult result;
    result.status = run.status;
    result.max_rss_kb = run.max_rss_kb;
    result.out = run.out;
    result.err = run.err;
    return result;
  }

  // `linkfit solve FILE -o out.json` on `text` written to FILE: exit 2, nothing on stdout, no
  // out.json, and one printable line "linkfit: error: FILE[:LINE]: ..." that contains
  // `expected` (the item and what is wrong). Returns the run.
  RunResult ExpectRejected(const std::string& name, const std::string& file,
                           const std::string& text, const std::string& expected) {
    SCOPED_TRACE(name);
    Write(file, text);
    const RunResult run = Run({"solve", file, "-o", "out.json"});
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(std::filesystem::exists(Path("out.json")));
    EXPECT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "not one line: " << run.err;
    for (const char c : run.err.substr(0, run.err.size() - 1)) {
      EXPECT_TRUE(c >= 0x20 && c < 0x7f)
          << "unprintable byte " << static_cast<int>(c) << " in " << run.err;
    }
    const std::string prefix = "linkfit: error: " + file + ":";
    EXPECT_EQ(run.err.rfind(prefix, 0), 0u) << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos)
        << "expected \"" << expected << "\" in " << run.err;
    // Nothing else is left behind (no temporary result file either).
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string(), file);
    }
    std::filesystem::remove(Path(file));
    return run;
  }

  std::string dir_;
};

struct Case {
  std::string name;
  std::string text;
  std::string expected;            // a part of the message: the item and what is wrong
  std::string file = "case.json";  // the task file's name
};

TEST_F(BadInputTest, EveryKindOfBadInputIsOneLineAndExitTwo) {
  const std::string task = MotionTask(FivePoses());
  std::mt19937 random(20240607);
  std::string garbage(4096, '\0');
  for (char& c : garbage) c = static_cast<char>(random() & 0xff);
  const std::vector<Case> cases = {
      // Syntax.
      {"malformed", "{\"poses\": [{\"x\": 1,, }]}",
       "case.json: malformed JSON at line 1, column 20 (near poses[0].x): syntax error"},
      {"unclosed string", "{\"problem\": \"motion}", "(near problem): syntax error"},
      {"trailing text", task + "{}",
       "case.json: malformed JSON at line 11, column 1: syntax error"},
      {"truncated after a key", CutAfter(task, kPoses[3], "\"theta_deg\": "),
       "(near poses[3].theta_deg): syntax error"},
      {"truncated after a value", CutAfter(task, kPoses[1], "\"x\": 1.0, "),
       "(near poses[1].x): syntax error"},
      {"truncated in a number", CutAfter(task, kPoses[4], "\"y\": 1."),
       "(near poses[4].y): syntax error"},
      {"truncated after an element", CutAfter(task, kPoses[2], "},"),
       "(near poses[3]): syntax error"},
      {"truncated after the array", CutAfter(task, "]", "]"), "(near poses): syntax error"},
      {"truncated at the start", "{", "case.json: malformed JSON at line 1, column 2: syntax"},
      // Wrong types.
      {"string for a number",
       MotionTask(With(FivePoses(), 3, R"({"x": 1, "y": 2, "theta_deg": "30"})")),
       "case.json: poses[3].theta_deg: expected a number, got a string"},
      {"object for an array", R"({"poses": {"x": 1, "y": 2, "theta_deg": 3}})",
       "case.json: poses: expected an array, got an object"},
      {"number for a string", R"({"problem": 7, "poses": []})",
       "case.json: problem: expected \"motion\" or \"path\" or \"function\", got a number"},
      {"number for an object", MotionTask(With(FivePoses(), 2, "7")),
       "case.json: poses[2]: expected an object, got a number"},
      {"boolean for a number",
       MotionTask(With(FivePoses(), 1, R"({"x": true, "y": 0, "theta_deg": 10})")),
       "case.json: poses[1].x: expected a number, got a boolean"},
      {"string for a vector",
       SpatialTask(R"({"axis": [0, 1, 0], "angle_deg": 20, "translation": "here"})"),
       "case.json: poses[2].translation: expected an array of 3 numbers, got a string"},
      {"top level array", "[" + std::string(kPoses[0]) + "]",
       "case.json: top level: expected an object, got an array"},
      // Missing and unknown fields.
      {"missing field", MotionTask(With(FivePoses(), 2, R"({"x": 2.0, "theta_deg": 20.0})")),
       "case.json: poses[2].y: missing field"},
      {"missing poses", R"({"problem": "motion"})", "case.json: poses: missing field"},
      {"missing g", SpatialTask(R"({"q": [0, 0, 0, 1]})"), "case.json: poses[2].g: missing field"},
      {"missing point x", PathTask(With(kPoints, 1, R"({"y": 1, "input_deg": 90})")),
       "case.json: points[1].x: missing field"},
      {"unknown field", R"({"pose": [], "poses": []})", "case.json: pose: unknown field"},
      {"field given twice", R"({"problem": "motion", "problem": "path"})",
       "case.json: problem: field given twice"},
      // Numbers that are not.
      {"NaN", MotionTask(With(FivePoses(), 2, R"({"x": NaN, "y": 1.0, "theta_deg": 20.0})")),
       "case.json: poses[2].x: NaN and Infinity are not numbers"},
      {"Infinity", MotionTask(With(FivePoses(), 3, R"({"x": 1, "y": Infinity, "theta_deg": 30})")),
       "case.json: poses[3].y: NaN and Infinity are not numbers"},
      {"-Infinity", PathTask(With(kPoints, 4, R"({"x": 1, "y": 2, "input_deg": -Infinity})")),
       "case.json: points[4].input_deg: NaN and Infinity are not numbers"},
      {"1e999", MotionTask(With(FivePoses(), 1, R"({"x": 1e999, "y": 0.0, "theta_deg": 10.0})")),
       "case.json: poses[1].x: not a finite number"},
      {"-1e999 scale", R"({"scale": -1e999, "poses": []})",
       "case.json: scale: not a finite number"},
      // Spatial poses that are not rigid motions.
      {"non-unit quaternion", SpatialTask(R"({"q": [0, 0, 0, 1.02], "g": [0, 0, 0, 0]})"),
       "case.json: poses[2].q: not a unit quaternion: |q| = 1.02, off by 0.02; the precision of "
       "its digits (0.005 per component) accepts at most 0.01"},
      {"q . g not 0", SpatialTask(R"({"q": [0, 0, 0, 1], "g": [0, 0, 0, 0.3]})"),
       "case.json: poses[2].g: q . g = 0.3, must be 0; the precision of the digits accepts at "
       "most"},
      {"reflection",
       SpatialTask(R"({"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, -1]], "translation": [0, 0, 0]})"),
       "case.json: poses[2].rotation: determinant is -1"},
      // Duplicates.
      {"duplicate planar poses", MotionTask(With(FivePoses(), 4, kPoses[1])),
       "case.json: poses[4]: coincides with poses[1]"},
      {"duplicate spatial poses",
       SpatialTask(R"({"axis": [0, 0, 2], "angle_deg": 390, "translation": [1, 1, 1]})"),
       "case.json: poses[2]: coincides with poses[1]"},
      {"duplicate path points", PathTask(With(kPoints, 3, kPoints[0])),
       "case.json: points[3]: coincides with points[0]"},
      // Too few for the problem.
      {"two planar poses", MotionTask({kPoses[0], kPoses[1]}),
       "case.json: poses: 2 poses given, planar motion synthesis needs at least 3"},
      {"no spatial poses", R"({"space": "spatial", "poses": []})",
       "case.json: poses: 0 poses given, spatial motion synthesis needs at least 1"},
      {"spatial pivots with three poses",
       R"({"space": "spatial", "moving_pivots": [[0, 0, 1]], "poses": [
           {"q": [0, 0, 0, 1], "g": [0.5, 0, 0, 0]},
           {"axis": [0, 0, 1], "angle_deg": 30, "translation": [1, 1, 1]},
           {"axis": [0, 1, 0], "angle_deg": 30, "translation": [2, 1, 1]}]})",
       "case.json: moving_pivots: need at least four poses"},
      {"no path points", R"({"problem": "path", "points": []})",
       "case.json: points: 0 points given, path synthesis needs at least 1"},
      // Unknown kinds.
      {"unknown problem", R"({"problem": "linkage", "poses": []})",
       "case.json: problem: expected \"motion\" or \"path\" or \"function\", got \"linkage\""},
      {"unknown space", R"({"space": "hyperbolic", "poses": []})",
       "case.json: space: expected \"planar\" or \"spatial\", got \"hyperbolic\""},
      {"spatial path", R"({"problem": "path", "space": "spatial", "points": []})",
       "case.json: space: path problems are planar only"},
      // Junk.
      {"deeply nested", "{\"poses\": [{\"x\": " + std::string(100000, '[') + "}",
       "case.json: malformed JSON at line 1, column 79: nested deeper than 64 levels"},
      {"nested objects",
       [] {
         std::string text;
         for (int i = 0; i < 10000; ++i) text += "{\"a\": ";
         return text;
       }(),
       "case.json: malformed JSON at line 1, column 385: nested deeper than 64 levels"},
      {"binary garbage", "\x89PNG\r\n\x1a\n" + garbage,
       "case.json: malformed JSON at line 1, column 1: syntax error"},
      {"NUL bytes", std::string("{\"poses\": \0\0\0]}", 15),
       "case.json: malformed JSON at line 1, column 11 (near poses): syntax error"},
      {"invalid UTF-8", "{\"problem\": \"mo\xff\xfetion\", \"poses\": []}",
       "case.json: malformed JSON at line 1, column 16 (near problem): "},
      {"empty file", "", "case.json: empty file, expected a task"},
      {"blank file", " \n\t\r\n", "case.json: empty file, expected a task"},
      // A batch of tasks, one line bad: nothing is solved.
      {"bad line of a batch",
       MotionTaskLine(FivePoses()) + "\n" +
           MotionTaskLine(With(FivePoses(), 1, R"({"x": 1, "y": 0, "theta_deg": "10"})")) + "\n" +
           MotionTaskLine(FivePoses()) + "\n",
       "tasks.jsonl:2: poses[1].theta_deg: expected a number, got a string", "tasks.jsonl"},
      {"malformed line of a batch", MotionTaskLine(FivePoses()) + "\n\n" + task,
       "tasks.jsonl:3: malformed JSON at line 1, column 2: syntax error", "tasks.jsonl"},
  };
  for (const Case& c : cases) ExpectRejected(c.name, c.file, c.text, c.expected);
}

// 10^6 poses (about 50 MB of text) are refused with the count and the limit, and the program's
// memory stays bounded: the text is held once, and the poses beyond the limit (100000) are
// counted while parsing but not built.
TEST_F(BadInputTest, AMillionPosesInBoundedMemory) {
  constexpr int kPoseCount = 1000000;
  std::string text = "{\"problem\": \"motion\", \"poses\": [\n";
  text.reserve(size_t{kPoseCount} * 56);
  char pose[96];
  for (int i = 0; i < kPoseCount; ++i) {
    std::snprintf(pose, sizeof pose, "%s{\"x\": %d.5, \"y\": %d.25, \"theta_deg\": %d.125}",
                  i ? ",\n" : "", i, i % 977, i % 360);
    text += pose;
  }
  text += "\n]}\n";
  const size_t text_mb = text.size() >> 20;
  const auto start = std::chrono::steady_clock::now();
  const RunResult run = ExpectRejected("10^6 poses", "case.json", text,
                                       "case.json: poses: 1000000 poses given, more than the "
                                       "limit of 100000");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const long rss_mb = run.max_rss_kb >> 10;
  // The text, read into memory once (text_mb), the DOM of at most 100000 planar poses (about
  // 300 bytes each: 30 MB) and the program itself (about 15 MB) need well under text_mb + 96
  // MB. Building all 10^6 poses took about 440 MB for this text.
  const long bound_mb = static_cast<long>(text_mb) + 96;
  std::printf("10^6 poses: %zu MB of text, peak RSS %ld MB (bound %ld MB), %.2f s\n", text_mb,
              rss_mb, bound_mb, seconds);
#ifndef LINKFIT_UNDER_ASAN
  EXPECT_GT(rss_mb, static_cast<long>(text_mb));  // the measure is the program's
  EXPECT_LT(rss_mb, bound_mb);
#else
  std::printf("(AddressSanitizer build: its shadow memory and quarantine make RSS no measure)\n");
#endif
}

}  // namespace
