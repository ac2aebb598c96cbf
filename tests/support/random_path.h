// Random crank-driven four-bars and the timed-point (path) tasks they make, for the tests and
// the benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_PATH_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_PATH_H_

#include <Eigen/Core>
#include <random>
#include <vector>

#include "lib/dyad.h"
#include "lib/path_motion.h"
#include "lib/task.h"
#include "tests/support/random_mechanism.h"

namespace linkfit::testing {

struct GeneratedPathTask {
  PathFourBar four_bar;  // in the first point's configuration (lib/path_motion.h)
  std::vector<Eigen::Vector2d> points;
  std::vector<double> input_angles;  // radians, unwrapped (psi_0 is the first crank angle)
};

// A random four-bar with an RR crank and an `output` dyad (RandomTask, random_mechanism.h,
// driven by the crank in one direction on one branch), a random coupler point in a box of
// half-width 1 about E's origin, and the `count` points it passes with their crank angles.
// Four-bars that, driven by the crank from the first point (AnalyzePathFourBar), show a defect
// or miss a point by more than 1e-9 L are drawn again.
GeneratedPathTask RandomPathTask(std::mt19937_64& rng, DyadType output, int count = 5);

// The timed-point task of a generated motion (random_mechanism.h) whose coupler carries
// `coupler_point` (in E): the four-bar moved to the first pose's configuration, the points and
// the unwrapped input angles.
GeneratedPathTask PathTaskOf(const GeneratedTask& motion, const Eigen::Vector2d& coupler_point);

// The largest of DyadDistance over both dyads and |coupler point difference|, relative to
// `length` (infinity for different types).
double PathFourBarDistance(const PathFourBar& found, const PathFourBar& expected, double length);

// The task's L: the RMS distance of the points from their centroid.
double PathLength(const std::vector<Eigen::Vector2d>& points);

// The path task of `generated`'s points, each moved by Gaussian noise of sigma `noise` times
// their PathLength (drawn from `rng`, two draws per point whatever the noise), with their crank
// angles unless `free_timing`, to be solved at `effort` (the trade of `linkfit bench`).
Task NoisyPathTask(const GeneratedPathTask& generated, double noise, bool free_timing,
                   Effort effort, std::mt19937_64& rng);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_PATH_H_
