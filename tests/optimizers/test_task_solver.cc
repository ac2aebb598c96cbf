#include <gtest/gtest.h>

#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

TEST(TaskSolver, PathProblemsReturnANote) {
  Task task;
  task.problem = ProblemKind::kPath;
  const TaskResult result = SolveTask(task);
  ASSERT_TRUE(std::holds_alternative<PlanarMotionResult>(result));
  const PlanarMotionResult& planar = std::get<PlanarMotionResult>(result);
  EXPECT_TRUE(planar.dyads.empty());
  ASSERT_EQ(planar.notes.size(), 1u);
}

}  // namespace
}  // namespace linkfit
