// Minimal data (five timed points, five orientations) printed as tables print them (issue 35,
// item 2): every listed four-bar that meets the data within their precision on one circuit may
// be defect-free; one that misses them says why in `defects` ("misses", or a kinematic defect),
// and one whose link the precision cannot resolve is "degenerate". None ranks among the
// defect-free otherwise.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "fitting/planar_motion.h"
#include "lib/design_constraints.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spherical.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

TEST(MinimalDefects, ExactPathFourBarsMeetTheirPointsOrSayWhy) {
  std::mt19937_64 rng(3521);
  int listed = 0, misses = 0;
  for (int t = 0; t < 16; ++t) {
    const testing::GeneratedPathTask generated =
        testing::RandomPathTask(rng, t % 2 == 0 ? DyadType::kRR : DyadType::kPR, 5);
    for (const int digits : {4, 6}) {
      SCOPED_TRACE("seed 3521, task " + std::to_string(t) + ", " + std::to_string(digits) +
                   " digits");
      const Task task = testing::ReadRounded(
          testing::PathText(generated.points, generated.input_angles, digits), Effort::kFast);
      const PathResult result = SolvePathTask(task);
      const double pass = PathPassTolerance(task.precision, result.scale);
      for (const PathMechanismReport& report : result.mechanisms) {
        ++listed;
        const bool says = HasKinematicDefect(report.defects);
        if (std::find(report.defects.begin(), report.defects.end(), "misses") !=
            report.defects.end()) {
          ++misses;
        }
        if (says || !report.max_point_error) continue;
        EXPECT_LE(*report.max_point_error, pass);
      }
    }
  }
  EXPECT_GT(listed, 32);
  RecordProperty("misses", misses);
}

TEST(MinimalDefects, ExactSphericalFourBarsMeetTheirOrientationsOrSayWhy) {
  std::mt19937_64 rng(3522);
  int listed = 0;
  for (int t = 0; t < 12; ++t) {
    const testing::SphericalPosesTask generated = testing::RandomSphericalPoses(rng, 5, 0.0);
    for (const int digits : {4, 6}) {
      SCOPED_TRACE("seed 3522, task " + std::to_string(t) + ", " + std::to_string(digits) +
                   " digits");
      const Task task =
          testing::ReadRounded(testing::SpatialMotionText(generated.poses, digits,
                                                          testing::SpatialForm::kRotationMatrix),
                               Effort::kFast);
      const SpatialMotionResult result = SolveSpatialTask(task);
      if (result.model != "spherical") continue;
      ASSERT_TRUE(result.spherical.has_value());
      const double fit = PoseFitTolerance(task.precision, result.scale);
      for (const MechanismReport& mechanism : result.spherical_mechanisms) {
        ++listed;
        if (HasKinematicDefect(mechanism.defects) || !mechanism.max_pose_error) continue;
        EXPECT_LE(*mechanism.max_pose_error, fit);
      }
    }
  }
  EXPECT_GT(listed, 12);
}

}  // namespace
}  // namespace linkfit
