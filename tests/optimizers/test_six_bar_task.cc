// "linkage": "six-bar" tasks end to end (issue 36): a task file of five poses of a random
// six-bar and its chain, read (lib/task_io), solved (SolveTask: fitting/six_bar_synthesis.h
// SolveSixBarMotion) and written (lib/result_io); the generating six-bar is listed without
// defect, and the command line takes the file (exit 0) and names a pose out of the chain's reach
// (exit 2).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "lib/result_io.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_six_bar.h"

namespace linkfit {
namespace {

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

std::string Point(const Eigen::Vector2d& p) {
  return "[" + Number(p.x()) + ", " + Number(p.y()) + "]";
}

// The task file of a generated six-bar's poses and chain.
std::string TaskText(const testing::GeneratedSixBarTask& task) {
  std::string text = "{\"problem\": \"motion\", \"linkage\": \"six-bar\", \"poses\": [";
  for (size_t k = 0; k < task.poses.size(); ++k) {
    const PlanarPose& pose = task.poses[k];
    text += std::string(k > 0 ? ", " : "") + "{\"x\": " + Number(pose.origin_in_fixed.x()) +
            ", \"y\": " + Number(pose.origin_in_fixed.y()) +
            ", \"theta_deg\": " + Number(pose.theta * 180.0 / M_PI) + "}";
  }
  text += "], \"chain\": {\"ground_pivot\": " + Point(task.chain.ground_pivot) +
          ", \"wrist\": " + Point(task.chain.wrist_in_moving) + ", \"link_lengths\": [" +
          Number(task.chain.upper_length) + ", " + Number(task.chain.forearm_length) +
          "], \"elbow_at_first_pose\": " + Point(*task.chain.elbow_at_first_pose) + "}}";
  return text;
}

TEST(SixBarTask, TheGeneratorIsListedWithoutDefect) {
  std::mt19937_64 rng(3604);
  for (const testing::SixBarLayout& layout : testing::SixBarLayouts()) {
    const testing::GeneratedSixBarTask generated = testing::RandomSixBarTask(rng, layout);
    SCOPED_TRACE(SixBarTopologyName(layout.topology));
    const Task task = ParseTask(TaskText(generated), "six_bar.json");
    ASSERT_TRUE(task.six_bar);
    const TaskResult solved = SolveTask(task);
    const PlanarMotionResult& result = std::get<PlanarMotionResult>(solved);
    EXPECT_TRUE(result.mechanisms.empty());
    int found = 0;
    for (const SixBarReport& report : result.six_bars) {
      EXPECT_LT(report.max_pose_error, 1e-8 * result.scale);
      bool same = report.six_bar.topology == generated.six_bar.topology;
      for (int l = 0; l < 2 && same; ++l) {
        same =
            report.six_bar.links[l].from_body == generated.six_bar.links[l].from_body &&
            (report.six_bar.links[l].from_joint - generated.six_bar.links[l].from_joint).norm() <
                1e-6 &&
            (report.six_bar.links[l].to_joint - generated.six_bar.links[l].to_joint).norm() < 1e-6;
      }
      if (!same) continue;
      ++found;
      // Made by driving its upper link: no kinematic defect (its transmission is the task's).
      for (const std::string& defect : report.defects) EXPECT_EQ(defect, "transmission");
    }
    EXPECT_EQ(found, 1);
    // Ranked: no six-bar with a kinematic defect ahead of one without.
    bool kinematic_seen = false;
    for (const SixBarReport& report : result.six_bars) {
      bool kinematic = false;
      for (const std::string& defect : report.defects) kinematic |= defect != "transmission";
      EXPECT_FALSE(kinematic_seen && !kinematic);
      kinematic_seen |= kinematic;
    }
    const nlohmann::json written = nlohmann::json::parse(ResultToJson(solved, 2));
    ASSERT_TRUE(written.contains("six_bars"));
    EXPECT_EQ(written["six_bars"].size(), result.six_bars.size());
    if (!result.six_bars.empty()) {
      const nlohmann::json& first = written["six_bars"][0];
      EXPECT_EQ(first["topology"], SixBarTopologyName(result.six_bars[0].six_bar.topology));
      EXPECT_EQ(first["joints_at_first_pose"]["links"].size(), 2u);
    }
  }
}

TEST(SixBarTask, TheCommandLineSolvesItAndNamesAPoseOutOfReach) {
  std::mt19937_64 rng(3605);
  testing::GeneratedSixBarTask generated =
      testing::RandomSixBarTask(rng, testing::SixBarLayouts()[1]);
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("linkfit_six_bar_" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(dir);
  const auto run = [&](const std::string& text, std::string* err) {
    std::ofstream(dir + "/task.json") << text;
    const std::string command = std::string("'") + LINKFIT_BINARY + "' solve '" + dir +
                                "/task.json' -o '" + dir + "/result.json' 2>'" + dir + "/err'";
    const int raw = std::system(command.c_str());
    std::ifstream in(dir + "/err");
    std::stringstream buffer;
    buffer << in.rdbuf();
    *err = buffer.str();
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  };
  std::string err;
  EXPECT_EQ(run(TaskText(generated), &err), 0) << err;
  generated.poses[3].origin_in_fixed += Eigen::Vector2d(40.0, 0.0);
  EXPECT_EQ(run(TaskText(generated), &err), 2);
  EXPECT_NE(err.find("poses[3]: out of the chain's reach"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace linkfit
