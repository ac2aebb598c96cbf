#include "tests/support/every_kind.h"

#include <fstream>
#include <random>
#include <sstream>

#include "tests/support/random_function.h"
#include "tests/support/random_spatial.h"
#include "tests/support/random_spherical.h"
#include "tests/support/rounded_task.h"

namespace linkfit::testing {
namespace {

std::string FileText(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace

std::vector<KindTask> EveryKindOfTask(const std::string& data_dir, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto file = [&](const std::string& name) { return FileText(data_dir + "/" + name); };
  std::vector<KindTask> tasks = {
      {"planar motion, 3 poses", file("four_bar_3_poses.json"), "poses"},
      {"planar motion, 4 poses", file("four_bar_4_poses.json"), "poses"},
      {"planar motion, 5 poses", file("four_bar_5_poses.json"), "poses"},
      {"planar motion, 12 poses", file("four_bar_12_poses.json"), "poses", true},
      {"spatial motion, 7 poses", file("platform_7_poses.json"), "poses"},
      {"spherical motion, 5 orientations", file("spherical_four_bar_5_poses.json"), "poses"},
      {"timed path, 5 points", file("path_5_points.json"), "points"},
      {"timed path, 12 points", file("path_12_points.json"), "points", true},
      {"untimed path, 12 points", file("path_12_points_untimed.json"), "points", true},
      {"function, 3 absolute pairs", file("function_3_pairs.json"), "pairs"},
  };
  const PlantedSpatialTask five = RandomPlatformTask(rng, 5);
  tasks.push_back({"spatial motion, 5 poses",
                   SpatialMotionText(five.poses, 8, SpatialForm::kRotationMatrix), "poses"});
  PlantedSpatialTask ten = RandomPlatformTask(rng, 10);
  PerturbSpatialPoses(rng, 1e-4, &ten.poses);
  tasks.push_back({"spatial motion, 10 poses",
                   SpatialMotionText(ten.poses, 8, SpatialForm::kRotationMatrix), "poses", true});
  const SphericalPosesTask spherical = RandomSphericalPoses(rng, 10, 1e-3);
  tasks.push_back({"spherical motion, 10 orientations",
                   SpatialMotionText(spherical.poses, 8, SpatialForm::kAxisAngle), "poses", true});
  tasks.push_back({"function, 5 relative pairs",
                   FunctionTaskJson(RandomFunctionTask(rng, 5, true).pairs, true, 8), "pairs"});
  tasks.push_back({"function, 12 absolute pairs",
                   FunctionTaskJson(RandomFunctionTask(rng, 12, false).pairs, false, 8), "pairs",
                   true});
  return tasks;
}

}  // namespace linkfit::testing
