// Random spherical four-bars and the orientations they reach, for the spherical tests and the
// benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_SPHERICAL_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_SPHERICAL_H_

#include <Eigen/Core>
#include <random>
#include <vector>

#include "lib/spatial_pose.h"
#include "lib/spherical_four_bar.h"

namespace linkfit::testing {

// A uniformly random unit vector.
Eigen::Vector3d RandomUnitVector(std::mt19937_64& rng);

// A rotation about a uniformly random axis by a normal angle of deviation `sigma` (radians):
// noise on an orientation.
Eigen::Matrix3d RandomSmallRotation(std::mt19937_64& rng, double sigma);

// `rotations` each turned by its own RandomSmallRotation(rng, sigma), on the left.
void JitterRotations(std::mt19937_64& rng, double sigma, std::vector<Eigen::Matrix3d>* rotations);

// A random spherical four-bar assembled at the identity rotation: random fixed axes u1, u2 and
// moving axes v1, v2 (the cranks' angles those between u_i and v_i), every link (cranks,
// coupler, ground) between 15 and 165 degrees and its axes not nearly coplanar at the identity.
SphericalFourBar RandomSphericalFourBar(std::mt19937_64& rng);

// `count` rotations of the four-bar on the branch of the identity (including it, first), at
// input angles spread over up to `spread` radians of that branch's input, increasing and at least
// 0.15 rad apart (many orientations: half their even spacing). Empty when the branch is too
// short for that.
std::vector<Eigen::Matrix3d> SphericalFourBarRotations(std::mt19937_64& rng,
                                                       const SphericalFourBar& four_bar, int count,
                                                       double spread = 3.0);

// A spherical four-bar and `count` of its rotations on one branch (SphericalFourBarRotations),
// the four-bar drawn again until its branch is long enough.
struct SphericalTask {
  SphericalFourBar four_bar;
  std::vector<Eigen::Matrix3d> rotations;
};
SphericalTask RandomSphericalTask(std::mt19937_64& rng, int count, double spread = 3.0);

// The spatial poses (R_j, P - R_j p) of rotations about the centre p (E) = P (Sigma).
std::vector<DualQuaternion> PosesAboutCenter(const std::vector<Eigen::Matrix3d>& rotations,
                                             const Eigen::Vector3d& center_in_moving,
                                             const Eigen::Vector3d& center_in_fixed);

// The benchmarks' spherical tasks (linkfit_bench --only spherical; linkfit bench's spherical
// motion rows): a RandomSphericalTask of `count` orientations, each turned by noise `sigma`
// radians (JitterRotations; none for sigma 0), as spatial poses about a centre off both frames'
// origins, p = (0.3, -0.2, 0.5) in E and P = (1, 2, -1) in Sigma (PosesAboutCenter). The noise is
// on the rotations only: the poses still fix the centre, to rounding.
struct SphericalPosesTask {
  SphericalFourBar four_bar;               // the generating four-bar
  std::vector<Eigen::Matrix3d> rotations;  // its rotations, with the noise
  std::vector<DualQuaternion> poses;       // their poses about the centre
};
SphericalPosesTask RandomSphericalPoses(std::mt19937_64& rng, int count, double sigma);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_SPHERICAL_H_
