// Random spatial poses, dyads and the tasks they make, for the spatial tests and the benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_SPATIAL_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_SPATIAL_H_

#include <random>
#include <vector>

#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"

namespace linkfit::testing {

// A uniformly random rotation and a translation in the box of half-width `extent`.
DualQuaternion RandomSpatialPose(std::mt19937_64& rng, double extent = 1.0);

// `count` poses of a spherical motion: uniformly random rotations about a centre drawn in the box
// of half-width 1 (returned in *center), each translation making the centre a fixed point.
std::vector<DualQuaternion> RandomSphericalMotion(std::mt19937_64& rng, int count,
                                                  Eigen::Vector3d* center);

// An SS dyad with center and moving point in the box of half-width 1 and radius in [0.5, 2].
SpatialDyad RandomSSDyad(std::mt19937_64& rng);
// A PS dyad with moving point in the box of half-width 1 and a plane within distance 1 of 0.
SpatialDyad RandomPSDyad(std::mt19937_64& rng);

// Random dyads of the given types through one pose: SS with center and moving point in the
// box of half-width 1 (radius fitted to the pose), PS with the plane through the moving point,
// SP with a fixed point in the box and the plane of E through it.
std::vector<SpatialDyad> DyadsThroughPose(std::mt19937_64& rng, const DualQuaternion& pose,
                                          const std::vector<SpatialDyadType>& types);

// `count` poses on which every dyad of `dyads` (at most five) fits exactly (|residual| below
// 1e-14), the first being `start`: random twists of `start` (up to 1.5 in each coordinate)
// projected onto the constraint set by minimum-norm Newton steps. Poses closer than 0.05 in
// the spatial pose error (L = 1) to an earlier one are drawn again. The dyads must fit `start`.
std::vector<DualQuaternion> PosesOnDyads(std::mt19937_64& rng,
                                         const std::vector<SpatialDyad>& dyads,
                                         const DualQuaternion& start, int count);

// As PosesOnDyads, but gives up after `max_attempts` random starts (an empty result): five
// dyads leave a one-degree-of-freedom motion that may be too short for `count` distinct poses.
std::vector<DualQuaternion> TryPosesOnDyads(std::mt19937_64& rng,
                                            const std::vector<SpatialDyad>& dyads,
                                            const DualQuaternion& start, int count,
                                            int max_attempts);

// A random platform: dyads of the given types through a random pose (five SS by default), and
// `count` poses on its motion, drawn again until the motion holds that many distinct poses.
struct PlantedSpatialTask {
  std::vector<SpatialDyad> planted;
  std::vector<DualQuaternion> poses;
};
PlantedSpatialTask RandomPlatformTask(std::mt19937_64& rng, int count,
                                      const std::vector<SpatialDyadType>& types =
                                          std::vector<SpatialDyadType>(5, SpatialDyadType::kSS));

// Noise on spatial poses: each turned by about `noise` (a normal axis vector of length noise
// |w|, w standard normal) and moved by noise times a standard normal vector, applied in Sigma.
void PerturbSpatialPoses(std::mt19937_64& rng, double noise, std::vector<DualQuaternion>* poses);

// A spatial dyad's size: the largest of 1 and its pivots' distances from the origins, its
// radius and plane offset (those its type uses).
double SpatialDyadSize(const SpatialDyad& dyad);

// Relative difference of two spatial dyads: the largest of the pivot, radius and plane
// differences divided by the expected dyad's SpatialDyadSize. Infinity for different types.
double SpatialDyadDistance(const SpatialDyad& found, const SpatialDyad& expected);
double NearestSpatialDyadDistance(const std::vector<SpatialDyad>& candidates,
                                  const SpatialDyad& expected);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_SPATIAL_H_
