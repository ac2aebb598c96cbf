// Random six-bars on a 3R chain (lib/six_bar.h) and the five-pose tasks they make, for the tests
// and the benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_SIX_BAR_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_SIX_BAR_H_

#include <random>
#include <vector>

#include "fitting/six_bar_synthesis.h"
#include "lib/planar_pose.h"
#include "lib/six_bar.h"

namespace linkfit::testing {

// The six ways of building a six-bar on a 3R chain (fitting/six_bar_synthesis.h): the bodies each
// RR link joins.
struct SixBarLayout {
  SixBarTopology topology;
  int from0, to0, from1, to1;
};
const std::vector<SixBarLayout>& SixBarLayouts();

struct GeneratedSixBarTask {
  SixBar six_bar;
  SixBarChain chain;              // its 3R chain, the elbow at the first pose given
  std::vector<PlanarPose> poses;  // the task body's poses
  std::vector<SixBarAngles> configurations;
};

// A random six-bar of `layout` (chain links 0.6 to 1.4, joints in a box of half-width 1.5),
// driven by its upper link through `count` poses spread over a turn of 40 to 100 degrees by
// continuation (DriveSixBar); drawn again where the continuation meets a
// dead point or the chain's elbow changes side on the way, or where the two bodies an RR link
// joins turn apart by less than 20 degrees over the poses, or by less than 2 degrees between two
// of them (a nearly rigid relative motion, or two nearly equal relative poses, whose
// five-pose Burmester problem is ill-conditioned: its roots come to a few digits only).
GeneratedSixBarTask RandomSixBarTask(std::mt19937_64& rng, const SixBarLayout& layout,
                                     int count = 5);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_SIX_BAR_H_
