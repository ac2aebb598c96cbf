#include "lib/dyad.h"

#include <algorithm>
#include <cmath>

namespace linkfit {

const char* DyadTypeName(DyadType type) {
  switch (type) {
    case DyadType::kRR:
      return "RR";
    case DyadType::kPR:
      return "PR";
    case DyadType::kRP:
      return "RP";
  }
  return "?";
}

PlanarDyad PlanarDyad::RR(const Eigen::Vector2d& fixed_pivot, const Eigen::Vector2d& moving_pivot,
                          double radius) {
  PlanarDyad dyad;
  dyad.type = DyadType::kRR;
  dyad.fixed_pivot = fixed_pivot;
  dyad.moving_pivot = moving_pivot;
  dyad.radius = radius;
  return dyad;
}

PlanarDyad PlanarDyad::PR(const Eigen::Vector2d& moving_pivot, const Eigen::Vector2d& line_point,
                          const Eigen::Vector2d& line_direction) {
  PlanarDyad dyad;
  dyad.type = DyadType::kPR;
  dyad.moving_pivot = moving_pivot;
  dyad.line_point = line_point;
  dyad.line_direction = line_direction.normalized();
  return dyad;
}

PlanarDyad PlanarDyad::RP(const Eigen::Vector2d& fixed_pivot, const Eigen::Vector2d& line_point,
                          const Eigen::Vector2d& line_direction) {
  PlanarDyad dyad;
  dyad.type = DyadType::kRP;
  dyad.fixed_pivot = fixed_pivot;
  dyad.line_point = line_point;
  dyad.line_direction = line_direction.normalized();
  return dyad;
}

double PlanarDyad::Residual(const PlanarPose& pose) const {
  return Residual(Rotation2(pose.theta), pose.origin_in_fixed);
}

bool PlanarDyad::AllFinite() const {
  switch (type) {
    case DyadType::kRR:
      return fixed_pivot.allFinite() && moving_pivot.allFinite() && std::isfinite(radius);
    case DyadType::kPR:
      return moving_pivot.allFinite() && line_point.allFinite() && line_direction.allFinite() &&
             line_direction.norm() > 0.0;
    case DyadType::kRP:
      return fixed_pivot.allFinite() && line_point.allFinite() && line_direction.allFinite() &&
             line_direction.norm() > 0.0;
  }
  return false;
}

double PlanarDyad::MaxResidual(const std::vector<PlanarPose>& poses) const {
  double worst = 0.0;
  for (const PlanarPose& pose : poses) worst = std::max(worst, std::abs(Residual(pose)));
  return worst;
}

PlanarDyad PlanarDyad::Inverted() const {
  PlanarDyad inverted = *this;
  switch (type) {
    case DyadType::kRR:
      inverted.fixed_pivot = moving_pivot;
      inverted.moving_pivot = fixed_pivot;
      break;
    case DyadType::kPR:
      inverted.type = DyadType::kRP;
      inverted.fixed_pivot = moving_pivot;
      break;
    case DyadType::kRP:
      inverted.type = DyadType::kPR;
      inverted.moving_pivot = fixed_pivot;
      break;
  }
  return inverted;
}

double PlanarDyad::LineAngleDeg() const {
  double angle = std::atan2(line_direction.y(), line_direction.x()) * 180.0 / M_PI;
  if (angle < 0.0) angle += 180.0;
  if (angle >= 180.0) angle -= 180.0;
  return angle;
}

Eigen::Vector2d PlanarDyad::LineFoot() const {
  return line_point - line_point.dot(line_direction) * line_direction;
}

PlanarDyad TransformDyad(const PlanarDyad& dyad, const Similarity2& sigma,
                         const Similarity2& epsilon) {
  PlanarDyad out = dyad;
  out.fixed_pivot = sigma.Apply(dyad.fixed_pivot);
  out.moving_pivot = epsilon.Apply(dyad.moving_pivot);
  out.radius = sigma.scale * dyad.radius;
  if (dyad.type == DyadType::kPR) {
    out.line_point = sigma.Apply(dyad.line_point);
    out.line_direction = sigma.ApplyToDirection(dyad.line_direction);
  } else if (dyad.type == DyadType::kRP) {
    out.line_point = epsilon.Apply(dyad.line_point);
    out.line_direction = epsilon.ApplyToDirection(dyad.line_direction);
  }
  return out;
}

}  // namespace linkfit
