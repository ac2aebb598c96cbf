#include "fitting/model_choice.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
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

using JacobianSvd = Eigen::JacobiSVD<Eigen::MatrixXd>;

JacobianSvd SvdOf(const Eigen::MatrixXd& jacobian) {
  return JacobianSvd(jacobian, Eigen::ComputeThinU | Eigen::ComputeThinV);
}

// Each parameter's first-order move when residual j may move by uncertainty[j]:
// |J^+| uncertainty (J given by its SVD); empty when J is rank-deficient (the poses do not
// determine the dyad).

Eigen::VectorXd ParameterMoves(const JacobianSvd& svd, const Eigen::VectorXd& uncertainty) {
  const Eigen::VectorXd& sigma = svd.singularValues();
  if (!(sigma[sigma.size() - 1] > 1e-12 * sigma[0])) return Eigen::VectorXd();
  const Eigen::MatrixXd pseudo_inverse =
      svd.matrixV() * sigma.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  return pseudo_inverse.cwiseAbs() * uncertainty;
}

// ParameterMoves of a Jacobian of full column rank from its QR factorization with column
// pivoting, J P = Q R: J^+ = P R^-1 Q1^T, the same matrix as the SVD's, at a fraction of the cost
// (the analysis of every dyad of a five-pose task needs it). The rank test compares R's last
// diagonal entry with its first, as the SVD's test compares the singular values (they agree
// within a factor sqrt(n)); empty when it fails.
Eigen::VectorXd ParameterMovesQr(const Eigen::MatrixXd& jacobian,
                                 const Eigen::VectorXd& uncertainty) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(jacobian);
  const Eigen::Index p = jacobian.cols();
  const Eigen::MatrixXd& packed = qr.matrixQR();
  if (!(std::abs(packed(p - 1, p - 1)) > 1e-12 * std::abs(packed(0, 0)))) {
    return Eigen::VectorXd();
  }
  // R^-1 Q1^T, with Q1 = Q [I_p; 0] the thin factor (n x p: memory and time linear in the
  // number of poses; the full Q is n x n), then the triangular solve.
  const Eigen::MatrixXd q1 = qr.householderQ() * Eigen::MatrixXd::Identity(jacobian.rows(), p);
  const Eigen::MatrixXd pseudo_inverse_permuted =
      packed.topLeftCorner(p, p).triangularView<Eigen::Upper>().solve(q1.transpose());
  const Eigen::MatrixXd pseudo_inverse = qr.colsPermutation() * pseudo_inverse_permuted;
  return pseudo_inverse.cwiseAbs() * uncertainty;
}

// The step of the central differences below, in units of the task's scale L.
constexpr double kCurvatureStep = 1e-4;

// ParameterMoves near a double root (a fold: J nearly singular, as for the real part of a
// complex pair that rounding made of two nearby dyads), where first order overstates the move
// along J's weakest direction v without bound and the residuals' curvature limits it. With
// sigma, w the smallest singular value and its left vector, kappa = |w . d^2r/dt^2| along v
// (`residuals_at(t v)`, by central differences) and U = sum_j |w_j| uncertainty[j] + |w . r|,
// the component t along v keeps sigma t + kappa t^2 / 2 within U of its value: |t| <= (sigma -
// sqrt(sigma^2 - 2 kappa U)) / kappa on the dyad's side of the fold, (sigma + sqrt(sigma^2 + 2
// kappa U)) / kappa across it. Each parameter gets the smaller of its first-order move and its
// moves along the other directions plus |v_p| |t|.
template <typename ResidualsAt>
Eigen::VectorXd ParameterMovesNearFold(const Eigen::MatrixXd& jacobian,
                                       const Eigen::VectorXd& residual,
                                       const Eigen::VectorXd& uncertainty, double step,
                                       const ResidualsAt& residuals_at) {
  const JacobianSvd svd = SvdOf(jacobian);
  const Eigen::VectorXd first_order = ParameterMoves(svd, uncertainty);
  if (first_order.size() == 0) return first_order;
  const Eigen::VectorXd& sigma = svd.singularValues();
  const Eigen::Index weakest = sigma.size() - 1;
  Eigen::VectorXd inverse = sigma.cwiseInverse();
  inverse[weakest] = 0.0;
  const Eigen::VectorXd others =
      (svd.matrixV() * inverse.asDiagonal() * svd.matrixU().transpose()).cwiseAbs() * uncertainty;
  const Eigen::VectorXd direction = svd.matrixV().col(weakest);
  const Eigen::VectorXd left = svd.matrixU().col(weakest);
  const Eigen::VectorXd curvature =
      (residuals_at(step * direction) + residuals_at(-step * direction) - 2.0 * residual) /
      (step * step);
  const double kappa = std::abs(left.dot(curvature));
  const double allowed = left.cwiseAbs().dot(uncertainty) + std::abs(left.dot(residual));
  const double s = sigma[weakest];
  if (!(kappa > 0.0)) return first_order;
  const double discriminant = s * s - 2.0 * kappa * allowed;
  const double along = discriminant > 0.0 ? 2.0 * allowed / (s + std::sqrt(discriminant))
                                          : (s + std::sqrt(s * s + 2.0 * kappa * allowed)) / kappa;
  const Eigen::VectorXd second_order = others + direction.cwiseAbs() * along;
  return second_order.allFinite() ? first_order.cwiseMin(second_order) : first_order;
}

}  // namespace

double SameDesignTolerance(const DataPrecision& precision, double size, double length,
                           int dimension, double bound, double relative) {
  return std::max({relative * size,
                   kModelUnits * PointUncertainty(precision, size, length, dimension),
                   std::min(bound, 0.1 * size)});
}

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

// Levenberg-Marquardt for both dyad fits: `residuals(state, &r, &J or nullptr)` returns the sum
// of squares, `step(state, delta)` the state moved by -delta. `converged` > 0: a relative cost
// change below it (accepted or rejected step) ends the fit; 0 runs to the iteration limit.
template <typename State, typename Residuals, typename Step>
State LevenbergMarquardt(State state, int iterations, double converged, const Residuals& residuals,
                         const Step& step) {
  Eigen::VectorXd residual, trial_residual;
  Eigen::MatrixXd jacobian;
  double cost = residuals(state, &residual, &jacobian);
  double damping = 1e-3;
  for (int iteration = 0; iteration < iterations && std::isfinite(cost) && cost > 0.0;
       ++iteration) {
    Eigen::MatrixXd damped = jacobian.transpose() * jacobian;
    damped.diagonal() *= 1.0 + damping;
    const Eigen::VectorXd delta = damped.ldlt().solve(jacobian.transpose() * residual);
    if (!delta.allFinite()) break;
    const State trial = step(state, delta);
    const double trial_cost = residuals(trial, &trial_residual, nullptr);
    if (trial_cost < cost) {
      state = trial;
      const double previous = cost;
      cost = residuals(state, &residual, &jacobian);
      if (converged > 0.0 && previous - cost <= converged * previous) break;
      damping = std::max(damping / 10.0, 1e-12);
    } else {
      // At the minimum, to rounding.
      if (converged > 0.0 && trial_cost - cost <= converged * cost) break;
      damping *= 10.0;
      if (damping > 1e12) break;
    }
  }
  return state;
}

}  // namespace

PlanarDyad FitDyadLeastSquares(const PlanarDyad& start, const std::vector<PlanarPose>& poses,
                               int iterations) {
  // In the dyad's parameters (DyadParameters), run to the iteration limit.
  const auto residuals = [&](const Eigen::VectorXd& x, Eigen::VectorXd* residual,
                             Eigen::MatrixXd* jacobian) {
    return DyadResiduals(DyadOf(start.type, x), poses, residual, jacobian);
  };
  const auto step = [](const Eigen::VectorXd& x, const Eigen::VectorXd& delta) {
    return Eigen::VectorXd(x - delta);
  };
  const PlanarDyad dyad = DyadOf(
      start.type, LevenbergMarquardt(DyadParameters(start), iterations, 0.0, residuals, step));
  return dyad.AllFinite() ? dyad : start;
}

namespace {

// The uncertainty u_j of the dyad's constrained point at each pose (DyadErrorBound: RR, PR the
// moving pivot, |m| from E's origin; RP the fixed pivot, |F - d_j| from the pose's origin), in
// *uncertainty (sized to the poses); returns, for a slider, how far along its line the
// constrained point runs (0 for RR).
double ConstrainedPointUncertainties(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                                     const DataPrecision& precision, double scale,
                                     Eigen::VectorXd* uncertainty) {
  const bool rr = dyad.type == DyadType::kRR, pr = dyad.type == DyadType::kPR;
  uncertainty->resize(static_cast<Eigen::Index>(poses.size()));
  double extent = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    const PlanarPose& pose = poses[j];
    if (!rr) {
      const Eigen::Vector2d point =
          pr ? pose.ToFixed(dyad.moving_pivot) : pose.ToMoving(dyad.fixed_pivot);
      extent = std::max(extent, (point - dyad.LineFoot()).norm());
    }
    const double distance =
        pr || rr ? dyad.moving_pivot.norm() : (dyad.fixed_pivot - pose.origin_in_fixed).norm();
    (*uncertainty)[static_cast<Eigen::Index>(j)] = PointUncertainty(precision, distance, scale, 2);
  }
  return extent;
}

}  // namespace

PlanarDyadBounds DyadErrorBounds(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                                 const DataPrecision& precision, double scale) {
  const bool rr = dyad.type == DyadType::kRR, pr = dyad.type == DyadType::kPR;
  const int n = static_cast<int>(poses.size());
  PlanarDyadBounds bounds;
  if (n < (rr ? 5 : 4)) return bounds;
  Eigen::VectorXd residual, uncertainty(n);
  Eigen::MatrixXd jacobian;
  DyadResiduals(dyad, poses, &residual, &jacobian);
  // Sliders: how far along its line the constrained point runs.
  const double extent = ConstrainedPointUncertainties(dyad, poses, precision, scale, &uncertainty);
  const Eigen::VectorXd moves = ParameterMovesQr(jacobian, uncertainty);
  if (moves.size() == 0) return bounds;
  const auto finite = [](double value) {
    return std::isfinite(value) ? value : std::numeric_limits<double>::infinity();
  };
  // The first pivot's (RR and RP: the fixed one; PR: the moving one) two coordinates.
  const double first = finite(std::max(moves[0], moves[1]) * std::sqrt(2.0));
  if (rr) {
    bounds.fixed_pivot = first;
    bounds.moving_pivot = finite(std::sqrt(2.0) * std::max(moves[2], moves[3]));
    bounds.radius = finite(moves[4]);
  } else {
    (pr ? bounds.moving_pivot : bounds.fixed_pivot) = first;
    bounds.line = finite(moves[3] + moves[2] * extent);
  }
  return bounds;
}

double PivotDyadErrorBound(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                           const DataPrecision& precision, double scale, bool moving_given) {
  const bool rr = dyad.type == DyadType::kRR;
  // The free parameters' columns of DyadResiduals' Jacobian: RR the other pivot and the radius;
  // a slider (PR from a moving pivot, RP from a fixed one) its line's angle and offset.
  const std::vector<int> columns =
      rr ? (moving_given ? std::vector<int>{0, 1, 4} : std::vector<int>{2, 3, 4})
         : std::vector<int>{2, 3};
  const int n = static_cast<int>(poses.size());
  if (n < static_cast<int>(columns.size())) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd residual, uncertainty(n);
  Eigen::MatrixXd jacobian;
  DyadResiduals(dyad, poses, &residual, &jacobian);
  Eigen::MatrixXd free(n, static_cast<Eigen::Index>(columns.size()));
  for (size_t k = 0; k < columns.size(); ++k) free.col(k) = jacobian.col(columns[k]);
  // Sliders: how far along its line the constrained point runs.
  const double extent = ConstrainedPointUncertainties(dyad, poses, precision, scale, &uncertainty);
  const Eigen::VectorXd moves = ParameterMovesQr(free, uncertainty);
  if (moves.size() == 0) return std::numeric_limits<double>::infinity();
  const double bound = rr ? std::max(std::sqrt(2.0) * std::max(moves[0], moves[1]), moves[2])
                          : moves[1] + moves[0] * extent;
  return std::isfinite(bound) ? bound : std::numeric_limits<double>::infinity();
}

double DyadErrorBound(const PlanarDyad& dyad, const std::vector<PlanarPose>& poses,
                      const DataPrecision& precision, double scale) {
  const PlanarDyadBounds bounds = DyadErrorBounds(dyad, poses, precision, scale);
  switch (dyad.type) {
    case DyadType::kRR:
      return std::max({bounds.fixed_pivot, bounds.moving_pivot, bounds.radius});
    case DyadType::kPR:
      return std::max(bounds.moving_pivot, bounds.line);
    case DyadType::kRP:
      return std::max(bounds.fixed_pivot, bounds.line);
  }
  return std::numeric_limits<double>::infinity();
}

void NormalTurns(const Eigen::Vector3d& normal, Eigen::Vector3d* turn1, Eigen::Vector3d* turn2) {
  int k = 0;
  normal.cwiseAbs().minCoeff(&k);
  *turn1 = normal.cross(Eigen::Vector3d::Unit(k)).normalized();
  *turn2 = normal.cross(*turn1);
}

std::vector<SpatialFrame> SpatialFrames(const std::vector<DualQuaternion>& poses) {
  std::vector<SpatialFrame> frames;
  frames.reserve(poses.size());
  for (const DualQuaternion& pose : poses) frames.push_back({pose.Rotation(), pose.Translation()});
  return frames;
}

double SpatialDyadResiduals(const SpatialDyad& dyad, const std::vector<SpatialFrame>& frames,
                            Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian, double* extent) {
  const bool ss = dyad.type == SpatialDyadType::kSS, sp = dyad.type == SpatialDyadType::kSP;
  const int n = static_cast<int>(frames.size());
  residual->resize(n);
  if (jacobian != nullptr) jacobian->resize(n, ss ? 7 : 6);
  Eigen::Vector3d turn1, turn2;
  NormalTurns(dyad.plane_normal, &turn1, &turn2);
  const Eigen::Vector3d& normal = dyad.plane_normal;
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix3d& rotation = frames[j].rotation;
    const Eigen::Vector3d& translation = frames[j].translation;
    (*residual)[j] = dyad.Residual(rotation, translation);
    if (ss) {
      if (jacobian == nullptr) continue;
      const Eigen::Vector3d u =
          (rotation * dyad.moving_pivot + translation - dyad.fixed_pivot).normalized();
      jacobian->block<1, 3>(j, 0) = -u.transpose();
      jacobian->block<1, 3>(j, 3) = u.transpose() * rotation;
      (*jacobian)(j, 6) = -1.0;
    } else {
      // PS: the moving point in Sigma on n . X = h; SP: the fixed point in E on n . x = h.
      const Eigen::Vector3d point =
          sp ? Eigen::Vector3d(rotation.transpose() * (dyad.fixed_pivot - translation))
             : Eigen::Vector3d(rotation * dyad.moving_pivot + translation);
      if (extent != nullptr) {
        *extent = std::max(*extent, (point - dyad.plane_offset * normal).norm());
      }
      if (jacobian == nullptr) continue;
      jacobian->block<1, 3>(j, 0) = sp ? Eigen::RowVector3d((rotation * normal).transpose())
                                       : Eigen::RowVector3d(normal.transpose() * rotation);
      (*jacobian)(j, 3) = turn1.dot(point);
      (*jacobian)(j, 4) = turn2.dot(point);
      (*jacobian)(j, 5) = -1.0;
    }
  }
  return residual->squaredNorm();
}

SpatialDyad SpatialDyadStep(const SpatialDyad& dyad, const Eigen::VectorXd& step) {
  SpatialDyad next = dyad;
  if (dyad.type == SpatialDyadType::kSS) {
    next.fixed_pivot -= step.head<3>();
    next.moving_pivot -= step.segment<3>(3);
    next.radius -= step[6];
    return next;
  }
  Eigen::Vector3d turn1, turn2;
  NormalTurns(dyad.plane_normal, &turn1, &turn2);
  (dyad.type == SpatialDyadType::kPS ? next.moving_pivot : next.fixed_pivot) -= step.head<3>();
  next.plane_normal = (dyad.plane_normal - step[3] * turn1 - step[4] * turn2).normalized();
  next.plane_offset -= step[5];
  return next;
}

SpatialDyad FitDyadLeastSquares(const SpatialDyad& start, const std::vector<DualQuaternion>& poses,
                                int iterations) {
  return FitDyadLeastSquares(start, SpatialFrames(poses), iterations);
}

SpatialDyad FitDyadLeastSquares(const SpatialDyad& start, const std::vector<SpatialFrame>& frames,
                                int iterations) {
  // A step that changes the cost by less than this fraction ends the fit: converged.
  constexpr double kConverged = 1e-12;
  const auto residuals = [&](const SpatialDyad& dyad, Eigen::VectorXd* residual,
                             Eigen::MatrixXd* jacobian) {
    return SpatialDyadResiduals(dyad, frames, residual, jacobian);
  };
  const SpatialDyad dyad =
      LevenbergMarquardt(start, iterations, kConverged, residuals, SpatialDyadStep);
  return dyad.AllFinite() ? dyad : start;
}

double DyadErrorBound(const SpatialDyad& dyad, const std::vector<DualQuaternion>& poses,
                      const DataPrecision& precision, double scale) {
  const bool ss = dyad.type == SpatialDyadType::kSS, sp = dyad.type == SpatialDyadType::kSP;
  const int n = static_cast<int>(poses.size());
  if (n < (ss ? 7 : 6)) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd residual, uncertainty(n);
  Eigen::MatrixXd jacobian;
  double extent = 0.0;
  const std::vector<SpatialFrame> frames = SpatialFrames(poses);
  SpatialDyadResiduals(dyad, frames, &residual, &jacobian, &extent);
  for (int j = 0; j < n; ++j) {
    const double distance =
        sp ? (dyad.fixed_pivot - frames[j].translation).norm() : dyad.moving_pivot.norm();
    uncertainty[j] = PointUncertainty(precision, distance, scale, 3);
  }
  const Eigen::VectorXd moves = ParameterMovesNearFold(
      jacobian, residual, uncertainty, kCurvatureStep * scale, [&](const Eigen::VectorXd& step) {
        Eigen::VectorXd moved;
        SpatialDyadResiduals(SpatialDyadStep(dyad, -step), frames, &moved, nullptr);
        return moved;
      });
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

namespace {

// The residuals of a spherical dyad at the rotations and (when `jacobian` is given) their
// Jacobian in its parameters: the fixed axis u turned by its tangents t1, t2 (NormalTurns), the
// moving axis v by s1, s2, the cone angle. With w = R v and theta = angle(u, w), moving u by du
// changes theta by -n . du (n: the unit tangent at u toward w) and moving w by dw by -m . dw (m:
// the unit tangent at w toward u).
void SphericalDyadResiduals(const SphericalDyad& dyad,
                            const std::vector<Eigen::Matrix3d>& rotations,
                            Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian) {
  const int n = static_cast<int>(rotations.size());
  residual->resize(n);
  Eigen::Vector3d t1, t2, s1, s2;
  NormalTurns(dyad.fixed_axis, &t1, &t2);
  NormalTurns(dyad.moving_axis, &s1, &s2);
  if (jacobian != nullptr) jacobian->resize(n, 5);
  for (int j = 0; j < n; ++j) {
    (*residual)[j] = dyad.Residual(rotations[j]);
    if (jacobian == nullptr) continue;
    const Eigen::Vector3d& u = dyad.fixed_axis;
    const Eigen::Vector3d w = rotations[j] * dyad.moving_axis;
    const double c = u.dot(w);
    const Eigen::Vector3d toward_w = (w - c * u).normalized();
    const Eigen::Vector3d toward_u = (u - c * w).normalized();
    (*jacobian)(j, 0) = -toward_w.dot(t1);
    (*jacobian)(j, 1) = -toward_w.dot(t2);
    (*jacobian)(j, 2) = -toward_u.dot(rotations[j] * s1);
    (*jacobian)(j, 3) = -toward_u.dot(rotations[j] * s2);
    (*jacobian)(j, 4) = -1.0;
  }
}

// The dyad moved by -step in the parameters of SphericalDyadResiduals (the axes turned about
// their current tangents and normalized; not made canonical, so the parameters stay continuous).
SphericalDyad SphericalDyadStep(const SphericalDyad& dyad, const Eigen::VectorXd& step) {
  Eigen::Vector3d t1, t2, s1, s2;
  NormalTurns(dyad.fixed_axis, &t1, &t2);
  NormalTurns(dyad.moving_axis, &s1, &s2);
  SphericalDyad next;
  next.fixed_axis = (dyad.fixed_axis - step[0] * t1 - step[1] * t2).normalized();
  next.moving_axis = (dyad.moving_axis - step[2] * s1 - step[3] * s2).normalized();
  next.angle = dyad.angle - step[4];
  return next;
}

}  // namespace

SphericalDyad FitDyadLeastSquares(const SphericalDyad& start,
                                  const std::vector<Eigen::Matrix3d>& rotations, int iterations) {
  // A step that changes the cost by less than this fraction ends the fit: converged.
  constexpr double kConverged = 1e-12;
  const auto residuals = [&](const SphericalDyad& dyad, Eigen::VectorXd* residual,
                             Eigen::MatrixXd* jacobian) {
    SphericalDyadResiduals(dyad, rotations, residual, jacobian);
    return residual->squaredNorm();
  };
  const SphericalDyad dyad =
      LevenbergMarquardt(start, iterations, kConverged, residuals, SphericalDyadStep);
  return dyad.AllFinite() ? dyad : start;
}

double DyadErrorBound(const SphericalDyad& dyad, const std::vector<Eigen::Matrix3d>& rotations,
                      const DataPrecision& precision) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int n = static_cast<int>(rotations.size());
  if (n < 5) return kInf;
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  SphericalDyadResiduals(dyad, rotations, &residual, &jacobian);
  // An orientation given to alpha turns R_j v by up to alpha; rounding of unit vectors at least.
  const Eigen::VectorXd uncertainty =
      Eigen::VectorXd::Constant(n, PointUncertainty(DataPrecision{0.0, precision.angle}, 1.0, 1.0));
  const Eigen::VectorXd moves = ParameterMovesNearFold(
      jacobian, residual, uncertainty, kCurvatureStep, [&](const Eigen::VectorXd& step) {
        Eigen::VectorXd moved;
        SphericalDyadResiduals(SphericalDyadStep(dyad, -step), rotations, &moved, nullptr);
        return moved;
      });
  if (moves.size() == 0) return kInf;
  const double bound =
      std::max({std::hypot(moves[0], moves[1]), std::hypot(moves[2], moves[3]), moves[4]});
  return std::isfinite(bound) ? bound : kInf;
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

namespace {

// The total-least-squares line through `points`: its foot from the origin and its direction.
std::pair<Eigen::Vector2d, Eigen::Vector2d> LineThrough(
    const std::vector<Eigen::Vector2d>& points) {
  const FittedHyperplane<2> line = FitHyperplane<2>(points);
  return {line.offset * line.normal, Eigen::Vector2d(-line.normal.y(), line.normal.x())};
}

}  // namespace

PlanarDyad FitSliderPR(const PlanarDyad& circle, const std::vector<PlanarPose>& poses) {
  std::vector<Eigen::Vector2d> points;
  for (const PlanarPose& pose : poses) points.push_back(pose.ToFixed(circle.moving_pivot));
  const auto [foot, direction] = LineThrough(points);
  return PlanarDyad::PR(circle.moving_pivot, foot, direction);
}

PlanarDyad FitSliderRP(const PlanarDyad& circle, const std::vector<PlanarPose>& poses) {
  std::vector<Eigen::Vector2d> points;
  for (const PlanarPose& pose : poses) points.push_back(pose.ToMoving(circle.fixed_pivot));
  const auto [foot, direction] = LineThrough(points);
  return PlanarDyad::RP(circle.fixed_pivot, foot, direction);
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
