#include "tests/support/moved_design.h"

#include <cmath>

namespace linkfit::testing {
namespace {

Eigen::Vector2d Moved(std::mt19937_64& rng, const Eigen::Vector2d& point, double offset) {
  std::uniform_real_distribution<double> by(-offset, offset);
  return point + Eigen::Vector2d(by(rng), by(rng));
}

Eigen::Vector3d Moved(std::mt19937_64& rng, const Eigen::Vector3d& point, double offset) {
  std::uniform_real_distribution<double> by(-offset, offset);
  return point + Eigen::Vector3d(by(rng), by(rng), by(rng));
}

}  // namespace

PlanarDyad MovedPlanarDyad(std::mt19937_64& rng, const PlanarDyad& dyad, double offset,
                           double length) {
  std::uniform_real_distribution<double> turn(-offset / length, offset / length);
  const double angle = std::atan2(dyad.line_direction.y(), dyad.line_direction.x()) + turn(rng);
  const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
  switch (dyad.type) {
    case DyadType::kRR: {
      const Eigen::Vector2d fixed = Moved(rng, dyad.fixed_pivot, offset);
      const Eigen::Vector2d moving = Moved(rng, dyad.moving_pivot, offset);
      return PlanarDyad::RR(fixed, moving, (moving - fixed).norm());
    }
    case DyadType::kPR:
      return PlanarDyad::PR(Moved(rng, dyad.moving_pivot, offset),
                            Moved(rng, dyad.LineFoot(), offset), direction);
    case DyadType::kRP:
      break;
  }
  return PlanarDyad::RP(Moved(rng, dyad.fixed_pivot, offset), Moved(rng, dyad.LineFoot(), offset),
                        direction);
}

PathFourBar MovedPathFourBar(std::mt19937_64& rng, const PathFourBar& four_bar, double offset,
                             double length) {
  PathFourBar moved;
  moved.input = MovedPlanarDyad(rng, four_bar.input, offset, length);
  moved.output = MovedPlanarDyad(rng, four_bar.output, offset, length);
  moved.coupler_point = Moved(rng, four_bar.coupler_point, offset);
  return moved;
}

SpatialDyad MovedSpatialDyad(std::mt19937_64& rng, const SpatialDyad& dyad, double offset,
                             double length) {
  std::uniform_real_distribution<double> by(-offset, offset);
  const Eigen::Vector3d normal =
      (dyad.plane_normal + Moved(rng, Eigen::Vector3d(Eigen::Vector3d::Zero()), offset / length))
          .normalized();
  switch (dyad.type) {
    case SpatialDyadType::kSS:
      return SpatialDyad::SS(Moved(rng, dyad.fixed_pivot, offset),
                             Moved(rng, dyad.moving_pivot, offset), dyad.radius + by(rng));
    case SpatialDyadType::kPS:
      return SpatialDyad::PS(Moved(rng, dyad.moving_pivot, offset), normal,
                             dyad.plane_offset + by(rng));
    case SpatialDyadType::kSP:
      break;
  }
  return SpatialDyad::SP(Moved(rng, dyad.fixed_pivot, offset), normal, dyad.plane_offset + by(rng));
}

}  // namespace linkfit::testing
