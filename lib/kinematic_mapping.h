// Planar kinematic mapping of Blaschke and Gruenwald (seed 001, section 2): a planar
// displacement (a, b, phi) maps to the homogeneous image point (X1 : X2 : X3 : X4).
#ifndef LINKFIT_LIB_KINEMATIC_MAPPING_H_
#define LINKFIT_LIB_KINEMATIC_MAPPING_H_

#include <Eigen/Core>

#include "lib/planar_pose.h"

namespace linkfit {

// Image coordinates of seed 001 eq. 2, with the homogenizing scale of the paper
// (X3^2 + X4^2 = 4).
Eigen::Vector4d ImageCoordinates(const PlanarPose& pose);

// Inverse mapping, seed 001 eq. 3; accepts any non-zero multiple of an image point with
// (X3, X4) != (0, 0).
PlanarPose PoseFromImage(const Eigen::Vector4d& image);

}  // namespace linkfit

#endif  // LINKFIT_LIB_KINEMATIC_MAPPING_H_
