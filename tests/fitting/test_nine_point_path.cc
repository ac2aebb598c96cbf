#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "fitting/nine_point_path.h"
#include "tests/support/random_path.h"

namespace linkfit {
namespace {

using testing::GeneratedPathTask;
using testing::PathFourBarDistance;
using testing::PathLength;
using testing::RandomPathTask;

// The distance from any of `four_bars` to the nearest of `targets` (PathFourBarDistance).
double Nearest(const std::vector<PathFourBar>& four_bars, const std::vector<PathFourBar>& targets,
               double length) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const PathFourBar& target : targets) {
    for (const PathFourBar& four_bar : four_bars) {
      nearest = std::min(nearest, PathFourBarDistance(four_bar, target, length));
    }
  }
  return nearest;
}

double Residual(const NinePointState& state, const NinePointParameters& parameters) {
  return NinePointResidual(state, parameters).cwiseAbs().maxCoeff() /
         (1.0 + state.cwiseAbs().maxCoeff());
}

// The built-in start system: 1442 orbits (Wampler, Morgan & Sommese's count), each a solution,
// each orbit's six members solutions too and no two orbits alike.
TEST(NinePointPath, StartSystemHoldsEveryOrbitOnce) {
  const NinePointStart& start = BuiltInNinePointStart();
  ASSERT_EQ(start.solutions.size(), 1442u);
  std::vector<NinePointState> members;
  for (const NinePointState& state : start.solutions) {
    EXPECT_LT(Residual(state, start.parameters), 1e-9);
    members.push_back(state);
    const std::vector<NinePointState> orbit = NinePointOrbit(state, start.parameters);
    EXPECT_EQ(orbit.size(), 5u);
    for (const NinePointState& member : orbit) {
      EXPECT_LT(Residual(member, start.parameters), 1e-8);
      members.push_back(member);
    }
  }
  // Distinct: sorted by the first unknown, neighbours compared.
  std::sort(members.begin(), members.end(), [](const NinePointState& a, const NinePointState& b) {
    return a[0].real() < b[0].real();
  });
  int same = 0;
  for (size_t i = 0; i < members.size(); ++i) {
    for (size_t k = i + 1; k < members.size() && members[k][0].real() - members[i][0].real() < 1e-6;
         ++k) {
      if ((members[k].head<8>() - members[i].head<8>()).cwiseAbs().maxCoeff() < 1e-6) ++same;
    }
  }
  EXPECT_EQ(same, 0);
}

// Monodromy from a fresh random instance finds new orbits, every one a solution.
TEST(NinePointPath, MonodromyFindsSolutions) {
  const NinePointStart start = ComputeNinePointStart(5, 30, 3);
  EXPECT_EQ(start.solutions.size(), 30u);
  for (const NinePointState& state : start.solutions) {
    EXPECT_LT(Residual(state, start.parameters), 1e-9);
  }
}

// Random four-bars, nine points of each coupler curve (any timing): the generating four-bar,
// or one of its cognates, is among the real solutions; every four-bar returned passes the
// points (its coupler curve, by the residual of the formulation, is checked through the
// generating one's recovery).
TEST(NinePointPath, RandomFourBarsComeBack) {
  std::mt19937_64 rng(21);
  for (int t = 0; t < 3; ++t) {
    const GeneratedPathTask generated = RandomPathTask(rng, DyadType::kRR, 9);
    const double length = PathLength(generated.points);
    std::vector<PathFourBar> four_bars;
    NinePointSummary summary;
    SolveNinePointPath(generated.points, NinePointOptions(), &four_bars, &summary);
    EXPECT_EQ(summary.paths, 1442);
    EXPECT_LT(summary.paths_failed, 50) << "task " << t;
    EXPECT_LT(Nearest(four_bars, CurveCognates(generated.four_bar), length), 1e-8) << "task " << t;
    // Both labelings of every real orbit.
    EXPECT_EQ(static_cast<int>(four_bars.size()), 2 * summary.real_solutions);
  }
}

// The cognates of a real solution are the Roberts-Chebyshev cognates of its four-bar.
TEST(NinePointPath, OrbitIsTheCognates) {
  std::mt19937_64 rng(22);
  const GeneratedPathTask generated = RandomPathTask(rng, DyadType::kRR, 9);
  NinePointOptions options;
  options.cognates = true;
  std::vector<PathFourBar> four_bars;
  SolveNinePointPath(generated.points, options, &four_bars);
  const double length = PathLength(generated.points);
  for (const PathFourBar& cognate : CurveCognates(generated.four_bar)) {
    EXPECT_LT(Nearest(four_bars, {cognate}, length), 1e-8);
  }
}

}  // namespace
}  // namespace linkfit
