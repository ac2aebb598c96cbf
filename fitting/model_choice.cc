#include "fitting/model_choice.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>

namespace linkfit {
namespace {

// The total-least-squares hyperplane n . x = h through points (n the scatter's smallest
// eigenvector; the centroid lies on it).
template <int N>
struct FittedHyperplane {
  Eigen::Matrix<double, N, 1> normal;
  double offset = 0.0;
};

template <int N>
FittedHyperplane<N> FitHyperplane(const std::vector<Eigen::Matrix<double, N, 1>>& points) {
  using Vector = Eigen::Matrix<double, N, 1>;
  Vector centroid = Vector::Zero();
  for (const Vector& point : points) centroid += point;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix<double, N, N> scatter = Eigen::Matrix<double, N, N>::Zero();
  for (const Vector& point : points) scatter += (point - centroid) * (point - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eigen(scatter);
  FittedHyperplane<N> plane;
  plane.normal = eigen.eigenvectors().col(0);
  plane.offset = plane.normal.dot(centroid);
  return plane;
}

// Each parameter's first-order move when residual j may move by uncertainty[j]:
// |J^+| uncertainty; empty when J is rank-deficient (the poses do not determine the dyad).
Eigen::VectorXd ParameterMoves(const Eigen::MatrixXd& jacobian,
                               const Eigen::VectorXd& uncertainty) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  if (!(sigma[sigma.size() - 1] > 1e-12 * sigma[0])) return Eigen::VectorXd();
  const Eigen::MatrixXd pseudo_inverse =
      svd.matrixV() * sigma.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  return pseudo_inverse.cwiseAbs() * uncertainty;
}

}  // namespace

double PrecisionRatio(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                      const DataPrecision& precision, double scale) {
  double worst = 0.0;
  for (const PlanarPose& pose : poses) {
    const double distance = dyad.type == DyadType::kRP
                                ? (dyad.fixed_pivot - pose.origin_in_fixed).norm()
                                : dyad.moving_pivot.norm();
    const double ratio =
        std::abs(dyad.Residual(pose)) / PointUncertainty(precision, distance, scale, 2);
    if (!(ratio <= worst)) worst = ratio;  // NaN propagates as the worst
  }
  return worst;
}

double PrecisionRatio(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
                      const DataPrecision& precision, double scale) {
  double worst = 0.0;
  for (const DualQuaternion& pose : poses) {
    const Eigen::Matrix3d rotation = pose.Rotation();
    const Eigen::Vector3d translation = pose.Translation();
    const double distance = dyad.type == SpatialDyadType::kSP
                                ? (dyad.fixed_pivot - translation).norm()
                                : dyad.moving_pivot.norm();
    const double ratio = std::abs(dyad.Residual(rotation, translation)) /
                         PointUncertainty(precision, distance, scale, 3);
    if (!(ratio <= worst)) worst = ratio;
  }
  return worst;
}

namespace {

// The residuals of a planar dyad at the poses and their Jacobian in its parameters: RR (F, m,
// r); PR (m, the line normal's angle, offset); RP (F, angle, offset).
Eigen::VectorXd DyadParameters(const PlanarDyad& dyad) {
  if (dyad.type == DyadType::kRR) {
    Eigen::VectorXd x(5);
    x << dyad.fixed_pivot, dyad.moving_pivot, dyad.radius;
    return x;
  }
  const Eigen::Vector2d normal(-dyad.line_direction.y(), dyad.line_direction.x());
  Eigen::VectorXd x(4);
  x << (dyad.type == DyadType::kPR ? dyad.moving_pivot : dyad.fixed_pivot),
      std::atan2(normal.y(), normal.x()), normal.dot(dyad.line_point);
  return x;
}

PlanarDyad DyadOf(DyadType type, const Eigen::VectorXd& x) {
  if (type == DyadType::kRR) return PlanarDyad::RR(x.head<2>(), x.segment<2>(2), x[4]);
  // The direction whose left normal (-d_y, d_x) is the parameter's normal.
  const Eigen::Vector2d normal(std::cos(x[2]), std::sin(x[2]));
  const Eigen::Vector2d direction(normal.y(), -normal.x());
  return type == DyadType::kPR ? PlanarDyad::PR(x.head<2>(), x[3] * normal, direction)
                               : PlanarDyad::RP(x.head<2>(), x[3] * normal, direction);
}

// Residuals (and the Jacobian when non-null); returns the sum of squares.
double DyadResiduals(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                     Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian) {
  const bool rr = dyad.type == DyadType::kRR, pr = dyad.type == DyadType::kPR;
  const Eigen::Vector2d normal(-dyad.line_direction.y(), dyad.line_direction.x());
  const Eigen::Vector2d normal_rate(-normal.y(), normal.x());
  const int n = static_cast<int>(poses.size());
  residual->resize(n);
  if (jacobian != nullptr) jacobian->resize(n, rr ? 5 : 4);
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix2d rotation = Rotation2(poses[j].theta);
    const Eigen::Vector2d& origin = poses[j].origin_in_fixed;
    if (rr) {
      const Eigen::Vector2d arm = rotation * dyad.moving_pivot + origin - dyad.fixed_pivot;
      (*residual)[j] = arm.norm() - dyad.radius;
      if (jacobian != nullptr) {
        const Eigen::Vector2d u = arm.normalized();
        jacobian->block<1, 2>(j, 0) = -u.transpose();
        jacobian->block<1, 2>(j, 2) = u.transpose() * rotation;
        (*jacobian)(j, 4) = -1.0;
      }
    } else {
      // PR: the moving pivot in Sigma on n . P = h; RP: the fixed pivot in E on n . p = h.
      const Eigen::Vector2d point =
          pr ? Eigen::Vector2d(rotation * dyad.moving_pivot + origin)
             : Eigen::Vector2d(rotation.transpose() * (dyad.fixed_pivot - origin));
      (*residual)[j] = normal.dot(point - dyad.line_point);
      if (jacobian != nullptr) {
        jacobian->block<1, 2>(j, 0) = pr ? Eigen::RowVector2d(normal.transpose() * rotation)
                                         : Eigen::RowVector2d((rotation * normal).transpose());
        (*jacobian)(j, 2) = normal_rate.dot(point);
        (*jacobian)(j, 3) = -1.0;
      }
    }
  }
  return residual->squaredNorm();
}

}  // namespace

PlanarDyad FitDyadLeastSquares(const PlanarDyad& start, const std::vector<PlanarPose>& poses,
                               int iterations) {
  Eigen::VectorXd x = DyadParameters(start);
  PlanarDyad dyad = DyadOf(start.type, x);
  Eigen::VectorXd residual, trial_residual;
  Eigen::MatrixXd jacobian;
  double cost = DyadResiduals(dyad, poses, &residual, &jacobian);
  double damping = 1e-3;
  for (int iteration = 0; iteration < iterations && std::isfinite(cost) && cost > 0.0;
       ++iteration) {
    Eigen::MatrixXd damped = jacobian.transpose() * jacobian;
    damped.diagonal() *= 1.0 + damping;
    const Eigen::VectorXd step = damped.ldlt().solve(jacobian.transpose() * residual);
    if (!step.allFinite()) break;
    const PlanarDyad trial = DyadOf(start.type, x - step);
    const double trial_cost = DyadResiduals(trial, poses, &trial_residual, nullptr);
    if (trial_cost < cost) {
      x -= step;
      dyad = trial;
      cost = DyadResiduals(dyad, poses, &residual, &jacobian);
      damping = std::max(damping / 10.0, 1e-12);
    } else {
      damping *= 10.0;
      if (damping > 1e12) break;
    }
  }
  return dyad.AllFinite() ? dyad : start;
}

double DyadErrorBound(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                      const DataPrecision& precision, double scale) {
  const bool rr = dyad.type == DyadType::kRR, pr = dyad.type == DyadType::kPR;
  const int n = static_cast<int>(poses.size());
  if (n < (rr ? 5 : 4)) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd residual, uncertainty(n);
  Eigen::MatrixXd jacobian;
  DyadResiduals(dyad, poses, &residual, &jacobian);
  double extent = 0.0;  // sliders: how far along its line the constrained point runs
  for (int j = 0; j < n; ++j) {
    const PlanarPose& pose = poses[j];
    if (!rr) {
      const Eigen::Vector2d point =
          pr ? pose.ToFixed(dyad.moving_pivot) : pose.ToMoving(dyad.fixed_pivot);
      extent = std::max(extent, (point - dyad.LineFoot()).norm());
    }
    const double distance =
        pr || rr ? dyad.moving_pivot.norm() : (dyad.fixed_pivot - pose.origin_in_fixed).norm();
    uncertainty[j] = PointUncertainty(precision, distance, scale, 2);
  }
  const Eigen::VectorXd moves = ParameterMoves(jacobian, uncertainty);
  if (moves.size() == 0) return std::numeric_limits<double>::infinity();
  double bound = std::max(moves[0], moves[1]) * std::sqrt(2.0);
  if (rr) {
    bound = std::max({bound, std::sqrt(2.0) * std::max(moves[2], moves[3]), moves[4]});
  } else {
    bound = std::max(bound, moves[3] + moves[2] * extent);
  }
  return std::isfinite(bound) ? bound : std::numeric_limits<double>::infinity();
}

double DyadErrorBound(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
                      const DataPrecision& precision, double scale) {
  const bool ss = dyad.type == SpatialDyadType::kSS, sp = dyad.type == SpatialDyadType::kSP;
  const int parameters = ss ? 7 : 6;
  const int n = static_cast<int>(poses.size());
  if (n < parameters) return std::numeric_limits<double>::infinity();
  Eigen::MatrixXd jacobian(n, parameters);
  Eigen::VectorXd uncertainty(n);
  // Two directions tangent to the normal: its turns.
  const Eigen::Vector3d& normal = dyad.plane_normal;
  int k = 0;
  normal.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d tangent1 = normal.cross(Eigen::Vector3d::Unit(k)).normalized();
  const Eigen::Vector3d tangent2 = normal.cross(tangent1);
  double extent = 0.0;
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix3d rotation = poses[j].Rotation();
    const Eigen::Vector3d translation = poses[j].Translation();
    if (ss) {
      const Eigen::Vector3d u =
          (rotation * dyad.moving_pivot + translation - dyad.fixed_pivot).normalized();
      jacobian.block<1, 3>(j, 0) = -u.transpose();
      jacobian.block<1, 3>(j, 3) = u.transpose() * rotation;
      jacobian(j, 6) = -1.0;
    } else {
      // PS: the moving point in Sigma on n . X = h; SP: the fixed point in E on n . x = h.
      const Eigen::Vector3d point =
          sp ? Eigen::Vector3d(rotation.transpose() * (dyad.fixed_pivot - translation))
             : Eigen::Vector3d(rotation * dyad.moving_pivot + translation);
      jacobian.block<1, 3>(j, 0) = sp ? Eigen::RowVector3d((rotation * normal).transpose())
                                      : Eigen::RowVector3d(normal.transpose() * rotation);
      jacobian(j, 3) = tangent1.dot(point);
      jacobian(j, 4) = tangent2.dot(point);
      jacobian(j, 5) = -1.0;
      extent = std::max(extent, (point - dyad.plane_offset * normal).norm());
    }
    const double distance = sp ? (dyad.fixed_pivot - translation).norm() : dyad.moving_pivot.norm();
    uncertainty[j] = PointUncertainty(precision, distance, scale, 3);
  }
  const Eigen::VectorXd moves = ParameterMoves(jacobian, uncertainty);
  if (moves.size() == 0) return std::numeric_limits<double>::infinity();
  const double point_move = std::sqrt(3.0) * moves.head<3>().maxCoeff();
  double bound = point_move;
  if (ss) {
    bound = std::max({bound, std::sqrt(3.0) * moves.segment<3>(3).maxCoeff(), moves[6]});
  } else {
    bound = std::max(bound, moves[5] + std::hypot(moves[3], moves[4]) * extent);
  }
  return std::isfinite(bound) ? bound : std::numeric_limits<double>::infinity();
}

std::string ConditionNote(double condition, double relative_precision, double bound) {
  char text[256];
  std::snprintf(text, sizeof(text),
                "condition estimate %.3g with data precise to %.2g (relative): the dyads may be "
                "off by up to about %.2g of their size%s",
                condition, relative_precision, bound,
                bound >= 1.0
                    ? ", more than the dyads themselves: at this precision the answer means nothing"
                    : "");
  return text;
}

PlanarDyad FitSliderPR(const PlanarDyad& circle, const std::vector<PlanarPose>& poses) {
  std::vector<Eigen::Vector2d> points;
  for (const PlanarPose& pose : poses) points.push_back(pose.ToFixed(circle.moving_pivot));
  const FittedHyperplane<2> line = FitHyperplane<2>(points);
  return PlanarDyad::PR(circle.moving_pivot, line.offset * line.normal,
                        Eigen::Vector2d(-line.normal.y(), line.normal.x()));
}

PlanarDyad FitSliderRP(const PlanarDyad& circle, const std::vector<PlanarPose>& poses) {
  std::vector<Eigen::Vector2d> points;
  for (const PlanarPose& pose : poses) points.push_back(pose.ToMoving(circle.fixed_pivot));
  const FittedHyperplane<2> line = FitHyperplane<2>(points);
  return PlanarDyad::RP(circle.fixed_pivot, line.offset * line.normal,
                        Eigen::Vector2d(-line.normal.y(), line.normal.x()));
}

SpatialDyad FitPlanePS(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses) {
  std::vector<Eigen::Vector3d> points;
  for (const DualQuaternion& pose : poses) points.push_back(pose.ToFixed(sphere.moving_pivot));
  const FittedHyperplane<3> plane = FitHyperplane<3>(points);
  return SpatialDyad::PS(sphere.moving_pivot, plane.normal, plane.offset);
}

SpatialDyad FitPlaneSP(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses) {
  std::vector<Eigen::Vector3d> points;
  for (const DualQuaternion& pose : poses) {
    points.push_back(pose.Rotation().transpose() * (sphere.fixed_pivot - pose.Translation()));
  }
  const FittedHyperplane<3> plane = FitHyperplane<3>(points);
  return SpatialDyad::SP(sphere.fixed_pivot, plane.normal, plane.offset);
}

namespace {

// The candidate with the smallest PrecisionRatio when it is at most kModelUnits.
template <typename Dyad, typename Pose>
bool BestWithinPrecision(std::initializer_list<Dyad> candidates, const std::vector<Pose>& poses,
                         const DataPrecision& precision, double scale, Dyad* simpler) {
  double best = kModelUnits;
  bool found = false;
  for (const Dyad& candidate : candidates) {
    if (!candidate.AllFinite()) continue;
    const double ratio = PrecisionRatio(candidate, poses, precision, scale);
    if (ratio <= best) {
      best = ratio;
      *simpler = candidate;
      found = true;
    }
  }
  return found;
}

}  // namespace

bool SimplerModel(const PlanarDyad& circle, const std::vector<PlanarPose>& poses,
                  const DataPrecision& precision, double scale, PlanarDyad* simpler) {
  if (circle.type != DyadType::kRR || poses.size() < 3) return false;
  return BestWithinPrecision({FitSliderPR(circle, poses), FitSliderRP(circle, poses)}, poses,
                             precision, scale, simpler);
}

bool SimplerModel(const SpatialDyad& sphere, const std::vector<DualQuaternion>& poses,
                  const DataPrecision& precision, double scale, SpatialDyad* simpler) {
  if (sphere.type != SpatialDyadType::kSS || poses.size() < 4) return false;
  return BestWithinPrecision({FitPlanePS(sphere, poses), FitPlaneSP(sphere, poses)}, poses,
                             precision, scale, simpler);
}

}  // namespace linkfit
