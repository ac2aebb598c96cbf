// A planar dyad's parameters as Ceres parameter blocks, shared by the mechanism-level refiners
// (four_bar_refiner.cc, path_refiner.cc): the blocks, the conversions to and from PlanarDyad,
// and the unit-circle manifold of a line normal.
#ifndef LINKFIT_OPTIMIZERS_PLANAR_DYAD_BLOCKS_H_
#define LINKFIT_OPTIMIZERS_PLANAR_DYAD_BLOCKS_H_

#include <ceres/ceres.h>

#include <Eigen/Core>

#include "lib/dyad.h"

namespace linkfit {

// A dyad's parameters as three Ceres blocks of sizes 2, 2, 1:
//   RR: fixed pivot F (Sigma), moving pivot m (E), radius r;
//   PR: moving pivot m (E), unit line normal n (Sigma), offset h: the slider line n . X = h;
//   RP: fixed pivot F (Sigma), unit line normal n (E), offset h: the line n . x = h in E.
// The normals live on the unit circle (ceres::SphereManifold of size 2): a line never turns into a
// circle, nor the reverse, inside the solver.
struct DyadBlocks {
  DyadType type = DyadType::kRR;
  double point[2] = {0.0, 0.0};                          // RR, RP: F; PR: m
  double second[2] = {0.0, 0.0};                         // RR: m; PR, RP: n
  double scalar[1] = {0.0};                              // RR: r; PR, RP: h
  Eigen::Vector2d line_point = Eigen::Vector2d::Zero();  // PR, RP: the seed's line point
};

// v turned by +90 degrees.
inline Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

inline DyadBlocks ToBlocks(const PlanarDyad& dyad) {
  DyadBlocks blocks;
  blocks.type = dyad.type;
  const Eigen::Vector2d normal = Perp(dyad.line_direction.normalized());
  Eigen::Map<Eigen::Vector2d> point(blocks.point), second(blocks.second);
  switch (dyad.type) {
    case DyadType::kRR:
      point = dyad.fixed_pivot;
      second = dyad.moving_pivot;
      blocks.scalar[0] = dyad.radius;
      break;
    case DyadType::kPR:
      point = dyad.moving_pivot;
      second = normal;
      blocks.scalar[0] = normal.dot(dyad.line_point);
      break;
    case DyadType::kRP:
      point = dyad.fixed_pivot;
      second = normal;
      blocks.scalar[0] = normal.dot(dyad.line_point);
      break;
  }
  blocks.line_point = dyad.line_point;
  return blocks;
}

// The dyad of the blocks; a line keeps the seed's direction sense and the seed's line point
// moved perpendicularly onto the refined line.
inline PlanarDyad FromBlocks(const DyadBlocks& blocks) {
  const Eigen::Vector2d point(blocks.point[0], blocks.point[1]);
  const Eigen::Vector2d second(blocks.second[0], blocks.second[1]);
  if (blocks.type == DyadType::kRR) return PlanarDyad::RR(point, second, blocks.scalar[0]);
  const Eigen::Vector2d normal = second.normalized();
  const Eigen::Vector2d direction(normal.y(), -normal.x());  // Perp(direction) = normal
  const Eigen::Vector2d line_point =
      blocks.line_point - (normal.dot(blocks.line_point) - blocks.scalar[0]) * normal;
  return blocks.type == DyadType::kPR ? PlanarDyad::PR(point, line_point, direction)
                                      : PlanarDyad::RP(point, line_point, direction);
}

// Unit normal of a PR or RP block (the manifold keeps it unit up to rounding).
template <typename T>
bool UnitNormal(const T* normal, T* nx, T* ny) {
  using std::sqrt;
  const T norm_squared = normal[0] * normal[0] + normal[1] * normal[1];
  if (!(norm_squared > T(0.0))) return false;
  const T norm = sqrt(norm_squared);
  *nx = normal[0] / norm;
  *ny = normal[1] / norm;
  return true;
}

// A held transmission angle's shortfall (lib/four_bar_motion.h TransmissionAngleDeg) at one
// configuration: input pin A and output pin B in Sigma, the output dyad's blocks (RR: fixed pivot
// F in `output_point`; PR: line normal in `output_second`). The output pin moves along
// u = perp(B - F) (RR) or along the line (PR); sin(mu) = |(B - A) . u| / (|B - A| |u|), and the
// shortfall is max(0, sin_min - sin(mu)) (0 where the angle is undefined).
template <typename T>
T TransmissionShortfallAt(DyadType output_type, const T& ax, const T& ay, const T& bx, const T& by,
                          const T* output_point, const T* output_second, double sin_min) {
  using std::abs;
  using std::sqrt;
  T ux, uy;
  if (output_type == DyadType::kRR) {
    ux = -(by - output_point[1]);
    uy = bx - output_point[0];
  } else {
    T nx, ny;
    if (!UnitNormal(output_second, &nx, &ny)) return T(0.0);
    ux = -ny;
    uy = nx;
  }
  const T cx = bx - ax, cy = by - ay;
  const T norms_squared = (cx * cx + cy * cy) * (ux * ux + uy * uy);
  if (!(norms_squared > T(0.0))) return T(0.0);
  const T sin_mu = abs(cx * ux + cy * uy) / sqrt(norms_squared);
  return sin_mu < T(sin_min) ? T(sin_min) - sin_mu : T(0.0);
}

// The manifold of a line normal block (the problem takes ownership).
inline ceres::Manifold* UnitCircle() {
  // SphereManifold<2> does not compile in Ceres 2.1 (its 2x1 row-major Jacobian type); the
  // dynamic-size manifold of size 2 is the same manifold.
  return new ceres::SphereManifold<ceres::DYNAMIC>(2);
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_PLANAR_DYAD_BLOCKS_H_
