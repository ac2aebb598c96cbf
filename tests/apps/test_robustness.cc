// The program as a careless or hostile user runs it (issue 33): items marked exact in every kind
// of task at every effort, in a batch and one file at a time; output paths that are FIFOs,
// devices, links, the task itself or unwritable; signals mid-batch; a closed standard output; a
// file over the size limit; option values out of range; long tasks of every kind. Each time:
// never a crash or an internal fault, never a file destroyed that the run did not create, never
// a temporary file left behind, and one line that names the item for every refusal.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "lib/path_motion.h"
#include "lib/spatial_pose.h"
#include "lib/spherical_dyad.h"
#include "lib/task_io.h"
#include "tests/apps/program_run.h"
#include "tests/support/every_kind.h"
#include "tests/support/long_tasks.h"

// Under AddressSanitizer (GCC defines __SANITIZE_ADDRESS__, Clang answers __has_feature) the
// time and resident-memory bounds do not hold: its shadow memory and checks inflate both.
#if defined(__SANITIZE_ADDRESS__)
#define LINKFIT_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LINKFIT_UNDER_ASAN 1
#endif
#endif

namespace linkfit {
namespace {

using nlohmann::json;
using testing::OnePrintableLine;
using testing::ProgramOptions;
using testing::ProgramResult;
using testing::ReadWholeFile;

// Items marked exact are met to 1e-9 L (user guide, "Task file"); spherical orientations and
// function angles to 1e-9 rad.
constexpr double kExactTolerance = 1e-9;

class RobustnessTest : public testing::ScratchDirectoryTest {
 protected:
  ProgramResult Run(const std::vector<std::string>& args, ProgramOptions options = {}) const {
    if (options.directory == ".") options.directory = dir_;
    return testing::RunProgram(LINKFIT_BINARY, args, options);
  }
};

std::string DataPath(const std::string& name) {
  return std::string(LINKFIT_SOURCE_DIR) + "/data/" + name;
}

// Every kind of task with one item marked exact (first, interior or last) at each effort.
struct ExactCase {
  std::string name;
  json task;
  std::string items;
  size_t exact = 0;
  bool least_squares = false;
};

std::vector<ExactCase> ExactCases(bool interior_only) {
  std::vector<ExactCase> cases;
  for (const testing::KindTask& kind :
       testing::EveryKindOfTask(std::string(LINKFIT_SOURCE_DIR) + "/data")) {
    const json base = json::parse(kind.text);
    const size_t count = base[kind.items].size();
    std::vector<size_t> positions = {count / 2};
    if (!interior_only) positions = {0, count / 2, count - 1};
    for (const size_t position : positions) {
      for (const char* effort : {"fast", "balanced", "thorough"}) {
        ExactCase item;
        item.task = base;
        item.task[kind.items][position]["exact"] = true;
        item.task["options"] = {{"effort", effort}};
        item.items = kind.items;
        item.exact = position;
        item.least_squares = kind.least_squares;
        item.name =
            kind.name + ", " + kind.items + "[" + std::to_string(position) + "] exact, " + effort;
        cases.push_back(item);
      }
    }
  }
  return cases;
}

// How far the first answer misses the exact item, in the units of kExactTolerance (L or
// radians); negative when the result lists nothing to measure.
double ExactMiss(const ExactCase& item, const json& result) {
  const Task task = ParseTask(item.task.dump(), "task.json");
  const std::string text = result.dump();
  const double length = result.value("scale", 1.0);
  const size_t j = item.exact;
  if (task.problem == ProblemKind::kPath) {
    const PathDesign design = ParsePathDesign(text, "result");
    if (design.four_bars.empty()) return -1.0;
    std::vector<Eigen::Vector2d> points;
    std::vector<double> angles;
    for (const TimedPoint& point : task.points) {
      points.push_back(point.point_in_fixed);
      if (point.input_angle) angles.push_back(*point.input_angle);
    }
    if (angles.size() != points.size()) angles = design.input_angles[0];
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(design.four_bars[0], points, angles, length);
    if (analysis.point_errors.size() != points.size()) return 1e300;
    return analysis.point_errors[j] / length;
  }
  if (task.problem == ProblemKind::kMotion && task.space == Space::kPlanar) {
    if (result["mechanisms"].empty()) return -1.0;
    const json& first = result["mechanisms"][0];
    if (!first.contains("exact_pose_error")) return 1e300;
    return first["exact_pose_error"].get<double>() / length;
  }
  if (task.problem == ProblemKind::kMotion && result.value("model", "") == "spherical") {
    if (result["dyads"].empty()) return -1.0;
    const json& dyad = result["dyads"][0];
    const auto vector = [](const json& v) {
      return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    };
    const SphericalDyad spherical =
        SphericalDyad::Make(vector(dyad["fixed_axis"]), vector(dyad["moving_axis"]),
                            dyad["angle_deg"].get<double>() * M_PI / 180.0);
    return std::abs(spherical.Residual(task.spatial_poses[j].Rotation()));
  }
  if (task.problem == ProblemKind::kMotion) {
    const SpatialDesign design = ParseSpatialDesign(text, "result");
    if (design.dyads.empty()) return -1.0;
    return std::abs(design.dyads[0].Residual(task.spatial_poses[j])) / length;
  }
  // Function generation: pairs are met to 1e-9 rad or a thousandth of their angle precision
  // (the refiner's tolerance), in units of kExactTolerance.
  if (result["mechanisms"].empty()) return -1.0;
  const json& first = result["mechanisms"][0];
  if (!first.contains("exact_angle_error_deg")) return 1e300;
  const double tolerance = std::max(kExactTolerance, 1e-3 * task.precision.angle);
  return first["exact_angle_error_deg"].get<double>() * M_PI / 180.0 / tolerance * kExactTolerance;
}

// A batch of every kind of task with an item marked exact, first, interior or last, at every
// effort: each solved (an untimed path with an exact interior point aborted the process in a
// Ceres CHECK at balanced and thorough), and the first answer of a least-squares task meets the
// exact item.
TEST_F(RobustnessTest, ExactItemsInEveryKindOfTaskAtEveryEffort) {
  const std::vector<ExactCase> cases = ExactCases(false);
  std::string batch;
  for (const ExactCase& item : cases) batch += item.task.dump() + "\n";
  Write("exact.jsonl", batch);
  const ProgramResult run = Run({"solve", "exact.jsonl", "-o", "results.jsonl", "--jobs", "2"});
  ASSERT_EQ(run.status, 0) << run.err;
  ASSERT_EQ(run.signal, 0);
  std::ifstream results(Path("results.jsonl"));
  std::string line;
  size_t k = 0;
  for (; std::getline(results, line) && k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].name);
    const json result = json::parse(line);
    if (!cases[k].least_squares) continue;
    const double miss = ExactMiss(cases[k], result);
    if (miss >= 0.0) {
      EXPECT_LE(miss, kExactTolerance)
          << result["notes"].dump() << "\nTASK " << cases[k].task.dump();
    }
  }
  EXPECT_EQ(k, cases.size());
  EXPECT_EQ(Names(), (std::vector<std::string>{"exact.jsonl", "results.jsonl"}));
}

// The same, one task file at a time as the CLI reads it (the exact item in the interior).
TEST_F(RobustnessTest, ExactItemsOneFileAtATime) {
  for (const ExactCase& item : ExactCases(true)) {
    SCOPED_TRACE(item.name);
    Write("task.json", item.task.dump(2));
    const ProgramResult run = Run({"solve", "task.json", "-o", "result.json"});
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_EQ(run.signal, 0);
    EXPECT_EQ(run.err, "");
  }
}

TEST_F(RobustnessTest, AFifoTargetGetsTheResultAndStaysAFifo) {
  ASSERT_EQ(mkfifo(Path("out.fifo").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&]() { received = ReadWholeFile(Path("out.fifo")); });
  const ProgramResult run = Run({"solve", DataPath("four_bar_5_poses.json"), "-o", "out.fifo"});
  reader.join();
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(json::parse(received)["problem"], "motion");
  struct stat status;
  ASSERT_EQ(lstat(Path("out.fifo").c_str(), &status), 0);
  EXPECT_TRUE(S_ISFIFO(status.st_mode));
}

// A run that fails with a FIFO for -o opens and closes it, as a shell's redirection would have:
// its reader gets end of file instead of waiting for ever. (Linux reports POLLHUP on a FIFO's
// read end only once a writer has come and gone.)
TEST_F(RobustnessTest, AFailedRunLetsTheFifoReaderGo) {
  ASSERT_EQ(mkfifo(Path("out.fifo").c_str(), 0600), 0);
  Write("bad.json", R"({"poses": [{"x": 0, "y": 0, "theta_deg": "a"}]})");
  const int reader = open(Path("out.fifo").c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_NE(reader, -1);
  const ProgramResult run = Run({"solve", "bad.json", "-o", "out.fifo"});
  EXPECT_EQ(run.status, 2) << run.err;
  pollfd end{reader, POLLIN, 0};
  EXPECT_EQ(poll(&end, 1, 0), 1);
  EXPECT_TRUE(end.revents & POLLHUP);
  char byte;
  EXPECT_EQ(read(reader, &byte, 1), 0);  // end of file, nothing written
  close(reader);
}

// As root, `-o /dev/null` used to rename a regular file over /dev/null.
TEST_F(RobustnessTest, DevicesAndStandardOutputAreWrittenInPlace) {
  const std::string task = DataPath("four_bar_5_poses.json");
  ProgramResult run = Run({"solve", task, "-o", "/dev/null", "--svg", "/dev/null"});
  EXPECT_EQ(run.status, 0) << run.err;
  struct stat status;
  ASSERT_EQ(stat("/dev/null", &status), 0);
  EXPECT_TRUE(S_ISCHR(status.st_mode));
  // /dev/stdout, with standard output a file: the file gets the result, and stays that file.
  ProgramOptions to_file;
  to_file.stdout_path = Path("captured.json");
  Write("captured.json", "");
  struct stat before;
  ASSERT_EQ(stat(Path("captured.json").c_str(), &before), 0);
  run = Run({"solve", task, "-o", "/dev/stdout"}, to_file);
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_EQ(stat(Path("captured.json").c_str(), &status), 0);
  EXPECT_EQ(status.st_ino, before.st_ino);
  EXPECT_EQ(json::parse(ReadWholeFile(Path("captured.json")))["problem"], "motion");
}

TEST_F(RobustnessTest, AReplacedFileKeepsItsPermissionsAndALinkStays) {
  const std::string task = DataPath("four_bar_5_poses.json");
  Write("out.json", "old");
  ASSERT_EQ(chmod(Path("out.json").c_str(), 0640), 0);
  ASSERT_EQ(symlink("out.json", Path("link.json").c_str()), 0);
  const ProgramResult run = Run({"solve", task, "-o", "link.json"});
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(std::filesystem::is_symlink(Path("link.json")));
  struct stat status;
  ASSERT_EQ(stat(Path("out.json").c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 07777, 0640u);
  EXPECT_EQ(json::parse(ReadWholeFile(Path("out.json")))["problem"], "motion");
  EXPECT_EQ(Names(), (std::vector<std::string>{"link.json", "out.json"}));
}

// Every output of a run is written only when all of them can be: a picture that cannot be
// written used to leave the -o result written. Refusals are one line naming the option.
TEST_F(RobustnessTest, NothingIsWrittenUnlessEverythingIs) {
  Write("task.json", ReadWholeFile(DataPath("four_bar_5_poses.json")));
  const struct {
    std::vector<std::string> args;
    std::string expected;  // the start of the message after "linkfit: error: "
  } cases[] = {
      {{"solve", "task.json", "-o", "out.json", "--svg", "missing/out.svg"},
       "--svg missing/out.svg: cannot create a file in missing"},
      {{"solve", "task.json", "-o", "out.json", "--animate", "out.json"},
       "--animate out.json: the same file as -o out.json"},
      {{"solve", "task.json", "-o", "task.json"},
       "-o task.json: is task.json, which this run reads"},
      {{"solve", "task.json", "-o", "."}, "-o .: is a directory"},
      {{"refine", "task.json", "task.json", "-o", "task.json"},
       "-o task.json: is task.json, which this run reads"},
  };
  for (const auto& [args, expected] : cases) {
    SCOPED_TRACE(args.back());
    const ProgramResult run = Run(args);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_TRUE(OnePrintableLine(run.err)) << run.err;
    EXPECT_EQ(run.err.rfind("linkfit: error: " + expected, 0), 0u) << run.err;
    EXPECT_EQ(Names(), std::vector<std::string>{"task.json"});
    EXPECT_EQ(ReadWholeFile(Path("task.json")), ReadWholeFile(DataPath("four_bar_5_poses.json")));
  }
}

// A batch of 600 tasks stopped by a signal after half a second: it exits 128 + the signal with
// one line, and neither the result nor a temporary file is left (one of 10.7 MB was). To
// standard output, the temporary directory is left empty too.
TEST_F(RobustnessTest, ASignalStopsABatchAndCleansUp) {
  const std::string task = json::parse(ReadWholeFile(DataPath("four_bar_12_poses.json"))).dump();
  std::string batch;
  for (int k = 0; k < 600; ++k) batch += task + "\n";
  Write("batch.jsonl", batch);
  std::filesystem::create_directory(Path("tmp"));
  const struct {
    int signal;
    const char* name;
  } signals[] = {{SIGINT, "SIGINT"}, {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"}};
  for (const auto& [signal, name] : signals) {
    for (const bool to_stdout : {false, true}) {
      SCOPED_TRACE(std::string(name) + (to_stdout ? ", to standard output" : ", to a file"));
      ProgramOptions options;
      options.signal = signal;
      options.signal_after_seconds = 0.5;
      options.environment = {"TMPDIR=" + Path("tmp")};
      std::vector<std::string> args = {"solve", "batch.jsonl", "--jobs", "2"};
      if (!to_stdout) args.insert(args.end(), {"-o", "out.jsonl"});
      const ProgramResult run = Run(args, options);
      EXPECT_EQ(run.signal, 0);
      EXPECT_EQ(run.status, 128 + signal) << run.err;
      EXPECT_EQ(run.err, std::string("linkfit: stopped by ") + name + ": nothing written\n");
      EXPECT_EQ(run.out, "");
      EXPECT_EQ(Names(), (std::vector<std::string>{"batch.jsonl", "tmp"}));
      EXPECT_TRUE(std::filesystem::is_empty(Path("tmp")));
    }
  }
}

// A closed standard output is an output that cannot be written (exit 2, one line), not an
// internal fault.
TEST_F(RobustnessTest, AClosedStandardOutputIsNamed) {
  ProgramOptions closed;
  closed.close_stdout = true;
  const ProgramResult run = Run({"solve", DataPath("four_bar_5_poses.json")}, closed);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_EQ(run.err, "linkfit: error: standard output: cannot write (Bad file descriptor)\n");
  // Named by the option when it was given.
  const ProgramResult dash = Run({"solve", DataPath("four_bar_5_poses.json"), "-o", "-"}, closed);
  EXPECT_EQ(dash.status, 2) << dash.err;
  EXPECT_EQ(dash.err, "linkfit: error: -o: standard output: cannot write (Bad file descriptor)\n");
}

// A file over the 256 MiB limit is refused before it is read (a sparse file of 300 MiB: it
// used to be read, 533 MB at the peak).
TEST_F(RobustnessTest, AFileOverTheLimitIsRefusedUnread) {
  const std::string big = Path("big.json");
  std::ofstream(big).close();
  std::filesystem::resize_file(big, std::uintmax_t{300} << 20);
  const ProgramResult run = Run({"solve", "big.json"});
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err, "linkfit: error: big.json: file too large (more than 256 MiB)\n");
#if !defined(LINKFIT_UNDER_ASAN)
  EXPECT_LT(run.max_rss_kb, 64L << 10);
#endif
}

// Option values: one line naming the option and the value, whatever the value (--jobs 0 printed
// a range of 309 digits).
TEST_F(RobustnessTest, OptionValuesAreRefusedInOneLine) {
  const std::string task = DataPath("four_bar_5_poses.json");
  const struct {
    std::vector<std::string> args;
    std::string expected;
  } cases[] = {
      {{"solve", task, "--jobs", "-1"}, "--jobs: expected a whole number from 0 to 1024, got -1"},
      {{"solve", task, "--jobs", "two"},
       "--jobs: expected a whole number from 0 to 1024, got 'two'"},
      {{"solve", task, "--jobs", "99999999999999999999999"},
       "--jobs: expected a whole number from 0 to 1024, got 99999999999999999999999"},
      {{"solve", task, "--jobs", "1.5"},
       "--jobs: expected a whole number from 0 to 1024, got '1.5'"},
      {{"solve", task, "--mechanism", "0"},
       "--mechanism: expected a whole number from 1 to 1000000000, got 0"},
      {{"solve", task, "--platform", "0,1,2,3,x"},
       "--platform: expected a whole number from 0 to 1000000000, got 'x'"},
      {{"solve", task, "--effort", "slow"}, "--effort: slow not in {fast,balanced,thorough}"},
      {{"refine", task, task, "--mechanism", "-3"},
       "--mechanism: expected a whole number from 1 to 1000000000, got -3"},
      {{"bench", "--seed", "-1"},
       "--seed: expected a whole number from 0 to 9223372036854775807, got -1"},
      {{"analyze", task, "--steps", "0"},
       "--steps: expected a whole number from 1 to 1000000, got 0"},
      {{"analyze", task, "--input-speed", "fast"}, "--input-speed"},
      {{"analyze", task, "--force", "1"}, "--force"},
      {{"frobnicate", task},
       "unknown command 'frobnicate': solve, refine, analyze, export, show, serve or bench"},
      {{"solve", task, "--jobs"}, "--jobs: 1 required INT missing"},
  };
  for (const auto& [args, expected] : cases) {
    SCOPED_TRACE(args[args.size() - 2] + " " + args.back());
    const ProgramResult run = Run(args);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_TRUE(OnePrintableLine(run.err)) << run.err;
    EXPECT_LT(run.err.size(), 200u) << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos) << run.err;
    EXPECT_EQ(run.out, "");
  }
  // --jobs 0 is every core, as threads=0 is in Python.
  const ProgramResult every_core = Run({"solve", DataPath("batch.jsonl"), "--jobs", "0"});
  EXPECT_EQ(every_core.status, 0) << every_core.err;
}

// Long tasks of every kind in time and memory linear in their items: 20,000 poses, points or
// pairs at fast (each took minutes to hours, or an n x n matrix of memory, somewhere). The bounds
// are generous (the measured figures are a fifth of them or less); the benchmark
// (linkfit_bench --only scale) measures 100,000.
TEST_F(RobustnessTest, LongTasksOfEveryKindInLinearTimeAndMemory) {
  constexpr int kCount = 20000;
  Write("motion.json", testing::LongTaskText("motion", kCount, "fast"));
  Write("timed.json", testing::LongTaskText("timed path", kCount, "fast"));
  Write("function.json", testing::LongTaskText("function", kCount, "fast"));
  Write("spherical.json", testing::LongTaskText("spherical", kCount, "fast"));
  for (const char* name : {"motion.json", "timed.json", "function.json", "spherical.json"}) {
    SCOPED_TRACE(name);
    const ProgramResult run = Run({"solve", name, "-o", "out.json"});
    EXPECT_EQ(run.status, 0) << run.err;
    std::printf("%s: %d items at fast in %.2f s, peak %ld MB\n", name, kCount, run.seconds,
                run.max_rss_kb >> 10);
#if !defined(LINKFIT_UNDER_ASAN)
    EXPECT_LT(run.seconds, 20.0);
    EXPECT_LT(run.max_rss_kb, 400L << 10);
#endif
  }
}

}  // namespace
}  // namespace linkfit
