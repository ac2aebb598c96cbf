// Random planar four-bars and the exact tasks they make, for the tests and the benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_MECHANISM_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_MECHANISM_H_

#include <random>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit::testing {

// A four-bar given by two dyads, and the poses its coupler E reaches.
struct GeneratedTask {
  PlanarDyad input;   // the driven dyad
  PlanarDyad output;  // the other dyad
  std::vector<PlanarPose> poses;
};

// Draws a four-bar of the given dyad types in an assembled start configuration (pivots in a
// box of half-width 1 about the origin, random coupler frame E), then drives the input joint
// in one direction by random steps (15 to 45 degrees, or 0.15 to 0.45 for a slider; scaled by
// 8 / count beyond eight poses, so that long tasks stay within about one turn), following
// the coupler continuously in small sub-steps, for `count` poses: the mechanism reaches them on
// one branch, in order. Mechanisms that lock up on the way, or tasks with two poses closer than
// 0.05 L (scaled likewise), are drawn again.
GeneratedTask RandomTask(std::mt19937_64& rng, DyadType input, DyadType output, int count = 5);

// The coupler pose of the four-bar input + output at input joint value `input_value` nearest
// `near` (PoseError with L = 1): where a driven input takes the coupler from `near` in a small
// step. False when the four-bar does not assemble there.
bool AssembleNear(const PlanarDyad& input, const PlanarDyad& output, double input_value,
                  const PlanarPose& near, PlanarPose* pose);

// Drives the four-bar task->input + task->output (both satisfied at `start`) as RandomTask
// does, writing `count` poses from `start` to task->poses. False when it locks up or two poses
// come closer than RandomTask allows.
bool DriveFourBar(std::mt19937_64& rng, const PlanarPose& start, int count, GeneratedTask* task);

inline GeneratedTask RandomFourBarTask(std::mt19937_64& rng, int count = 5) {
  return RandomTask(rng, DyadType::kRR, DyadType::kRR, count);
}
inline GeneratedTask RandomSliderCrankTask(std::mt19937_64& rng, int count = 5) {
  return RandomTask(rng, DyadType::kRR, DyadType::kPR, count);
}
inline GeneratedTask RandomInvertedSliderCrankTask(std::mt19937_64& rng, int count = 5) {
  return RandomTask(rng, DyadType::kRR, DyadType::kRP, count);
}

// Noise on planar poses: every origin moved by noise * length times a standard normal vector,
// every angle turned by noise times a standard normal number (radians).
void PerturbPlanarPoses(std::mt19937_64& rng, double noise, double length,
                        std::vector<PlanarPose>* poses);

// Relative difference of two dyads, in units of `length`: the largest of the pivot, radius
// and line differences (lines compared as lines: direction up to sign, and the distance of
// each line point from the other line). Infinity for different types.
double DyadDistance(const PlanarDyad& found, const PlanarDyad& expected, double length);

// The length to measure a dyad's error against: the larger of L and the distance of its
// pivots and line points from the pose-origin centroid (Sigma) or from E's origin (E). A pivot
// 1000 L away is known to a relative, not an absolute, accuracy.
double DyadScale(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses);

// The smallest DyadDistance from `expected` to any of `candidates` (infinity if none).
double NearestDyadDistance(const std::vector<PlanarDyad>& candidates, const PlanarDyad& expected,
                           double length);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_MECHANISM_H_
