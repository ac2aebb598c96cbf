// One task of every kind the solvers take, for the tests that must hold for all of them (the
// exact items, invariance under a move of the data, the fuzz corpus): planar motion of 3, 4, 5
// and 12 poses, spatial motion of 5, 7 and 10 poses, spherical motion of 5 and 10 orientations,
// timed paths of 5 and 12 points, an untimed path of 12, function generation from 3 absolute,
// 5 relative and 12 absolute pairs. The bundled examples (data/) where there is one, generated
// mechanisms' tasks (printed to 8 significant digits) where there is not.
#ifndef LINKFIT_TESTS_SUPPORT_EVERY_KIND_H_
#define LINKFIT_TESTS_SUPPORT_EVERY_KIND_H_

#include <cstdint>
#include <string>
#include <vector>

namespace linkfit::testing {

struct KindTask {
  std::string name;            // e.g. "planar motion, 12 poses"
  std::string text;            // the task's JSON text
  std::string items;           // its list of items: "poses", "points" or "pairs"
  bool least_squares = false;  // more items than the exact solvers take
};

// `data_dir`: the project's data/ folder.
std::vector<KindTask> EveryKindOfTask(const std::string& data_dir, uint64_t seed = 20261127);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_EVERY_KIND_H_
