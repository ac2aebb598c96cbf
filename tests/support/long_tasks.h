// Long tasks of every kind (thousands to the 100,000 limit of poses, points or pairs) for the
// tests and the benchmark that hold time and memory linear in the items: one four-bar's motion
// (crank 1 about the origin, coupler 3.5, rocker 3 about (4, 0), a coupler point 1.5 off the
// crank pin) sampled over 95 % of its crank's turn as planar poses, timed and untimed coupler
// points and input/output pairs; a rotation about a fixed centre (spherical) and a screw-like
// spatial motion, over 90 % of a turn. Printed to 8 decimals (the spatial motions' rotations to
// 8, their translations too).
#ifndef LINKFIT_TESTS_SUPPORT_LONG_TASKS_H_
#define LINKFIT_TESTS_SUPPORT_LONG_TASKS_H_

#include <string>
#include <vector>

namespace linkfit::testing {

// The kinds: "motion", "timed path", "untimed path", "function", "spherical", "spatial".
const std::vector<std::string>& LongTaskKinds();

// The JSON text of a task of `kind` with `count` items at `effort` ("fast", "balanced",
// "thorough").
std::string LongTaskText(const std::string& kind, int count, const std::string& effort);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_LONG_TASKS_H_
