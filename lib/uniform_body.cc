#include "lib/uniform_body.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace linkfit {

void UniformBody(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d* centre,
                 double* inertia_per_mass) {
  *centre = points.empty() ? Eigen::Vector2d::Zero() : points[0];
  *inertia_per_mass = 0.0;
  if (points.size() < 2) return;
  if (points.size() >= 3) {
    // A plate: the polygon through the points (shoelace sums about the first point).
    double area = 0.0, polar = 0.0;
    Eigen::Vector2d moment = Eigen::Vector2d::Zero();
    const Eigen::Vector2d origin = points[0];
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d p = points[i] - origin, q = points[(i + 1) % points.size()] - origin;
      const double cross = p.x() * q.y() - p.y() * q.x();
      area += 0.5 * cross;
      moment += cross * (p + q) / 6.0;
      polar += cross * (p.squaredNorm() + p.dot(q) + q.squaredNorm()) / 12.0;
    }
    double extent = 0.0;
    for (const Eigen::Vector2d& p : points) extent = std::max(extent, (p - origin).norm());
    if (std::abs(area) > 1e-9 * extent * extent) {
      const Eigen::Vector2d centroid = moment / area;
      *centre = origin + centroid;
      *inertia_per_mass = polar / area - centroid.squaredNorm();
      return;
    }
  }
  // A bar between the two points farthest apart.
  size_t a = 0, b = 1;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      if ((points[i] - points[j]).norm() > (points[a] - points[b]).norm()) {
        a = i;
        b = j;
      }
    }
  }
  *centre = 0.5 * (points[a] + points[b]);
  *inertia_per_mass = (points[a] - points[b]).squaredNorm() / 12.0;
}

}  // namespace linkfit
