// A link as a uniform body over its points (joints, a coupler point): a point mass at one, a
// bar between two (or the two farthest apart where they lie on a line), a plate on the polygon
// through three or more in order. For the torque that drives the links' masses
// (lib/four_bar_kinematics.h, lib/six_bar_kinematics.h, lib/dyad_four_bar_kinematics.h).
#ifndef LINKFIT_LIB_UNIFORM_BODY_H_
#define LINKFIT_LIB_UNIFORM_BODY_H_

#include <Eigen/Core>
#include <vector>

namespace linkfit {

// Its centre of mass (in the points' frame) and its polar moment of inertia about it per unit
// mass: a bar's l^2 / 12, a triangle's (a^2 + b^2 + c^2) / 36, a polygon's from the shoelace
// sums.
void UniformBody(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d* centre,
                 double* inertia_per_mass);

}  // namespace linkfit

#endif  // LINKFIT_LIB_UNIFORM_BODY_H_
