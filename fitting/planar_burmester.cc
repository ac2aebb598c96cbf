#include "fitting/planar_burmester.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "fitting/polynomial.h"
#include "lib/kinematic_mapping.h"

namespace linkfit {
namespace {

using Complex = std::complex<double>;
using Vector3c = Eigen::Matrix<Complex, 3, 1>;
using Matrix3c = Eigen::Matrix<Complex, 3, 3>;
using NullBasis = Eigen::Matrix<double, 8, 3>;

// A pose with its rotation matrix evaluated once (residuals are evaluated many times).
struct PoseFrame {
  Eigen::Matrix2d rotation;
  Eigen::Vector2d origin;
};

std::vector<PoseFrame> MakeFrames(const std::vector<PlanarPose>& poses) {
  std::vector<PoseFrame> frames(poses.size());
  for (size_t j = 0; j < poses.size(); ++j) {
    frames[j].rotation = Rotation2(poses[j].theta);
    frames[j].origin = poses[j].origin_in_fixed;
  }
  return frames;
}

double MaxResidual(const PlanarDyad& dyad, const std::vector<PoseFrame>& frames) {
  double worst = 0.0;
  for (const PoseFrame& frame : frames) {
    worst = std::max(worst, std::abs(dyad.Residual(frame.rotation, frame.origin)));
  }
  return worst;
}

// Symmetric bilinear forms of the two quadric relations (file comment):
//   Q1(z) = z0 z5 - z1 z3 - z2 z4,   Q2(z) = z0 z6 - z1 z4 + z2 z3.
template <typename U, typename V>
auto BilinearQ1(const U& u, const V& v) {
  return 0.5 * (u[0] * v[5] + u[5] * v[0] - u[1] * v[3] - u[3] * v[1] - u[2] * v[4] - u[4] * v[2]);
}
template <typename U, typename V>
auto BilinearQ2(const U& u, const V& v) {
  return 0.5 * (u[0] * v[6] + u[6] * v[0] - u[1] * v[4] - u[4] * v[1] + u[2] * v[3] + u[3] * v[2]);
}

Eigen::Matrix3d Adjugate(const Eigen::Matrix3d& m) {
  Eigen::Matrix3d adj;
  adj(0, 0) = m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1);
  adj(0, 1) = m(0, 2) * m(2, 1) - m(0, 1) * m(2, 2);
  adj(0, 2) = m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1);
  adj(1, 0) = m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2);
  adj(1, 1) = m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0);
  adj(1, 2) = m(0, 2) * m(1, 0) - m(0, 0) * m(1, 2);
  adj(2, 0) = m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0);
  adj(2, 1) = m(0, 1) * m(2, 0) - m(0, 0) * m(2, 1);
  adj(2, 2) = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  return adj;
}

// The two quadric relations restricted to the span of `basis`: a^T M1 a = Q1(basis a).
void RestrictedConics(const NullBasis& basis, Eigen::Matrix3d* m1, Eigen::Matrix3d* m2) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      (*m1)(i, j) = BilinearQ1(basis.col(i), basis.col(j));
      (*m2)(i, j) = BilinearQ2(basis.col(i), basis.col(j));
    }
  }
}

// Splits a degenerate real symmetric conic D = g h^T + h g^T into its two (possibly complex
// conjugate) lines g, h (Richter-Gebert, Perspectives on Projective Geometry, 11.3):
// adj(D) = -p p^T with p = g x h the lines' intersection, and D + [p]_x has rank one.
void SplitDegenerateConic(const Eigen::Matrix3d& d, Vector3c* g, Vector3c* h) {
  const Eigen::Matrix3d adj = Adjugate(d);
  int i = 0;
  adj.diagonal().cwiseAbs().maxCoeff(&i);
  if (adj(i, i) == 0.0) {
    // A double line D = g g^T.
    int k = 0;
    d.diagonal().cwiseAbs().maxCoeff(&k);
    const Complex scale = std::sqrt(Complex(d(k, k)));
    *g = d.col(k).cast<Complex>() / scale;
    *h = *g;
    return;
  }
  const Complex beta = std::sqrt(Complex(-adj(i, i)));
  const Vector3c p = adj.col(i).cast<Complex>() / beta;
  Matrix3c c = d.cast<Complex>();
  c(0, 1) -= p[2];
  c(0, 2) += p[1];
  c(1, 0) += p[2];
  c(1, 2) -= p[0];
  c(2, 0) -= p[1];
  c(2, 1) += p[0];
  int row = 0, col = 0;
  c.cwiseAbs().maxCoeff(&row, &col);
  *g = c.row(row).transpose();
  *h = c.col(col);
}

// The two points where the line l meets the conic m (complex in general).
void IntersectLineConic(const Vector3c& l, const Eigen::Matrix3d& m, Vector3c points[2]) {
  int k = 0;
  l.cwiseAbs().maxCoeff(&k);
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  // Two independent points of the line: l x e_a and l x e_b (bilinear, no conjugation).
  const Vector3c u = l.cross(Vector3c::Unit(a));
  const Vector3c v = l.cross(Vector3c::Unit(b));
  const Matrix3c mc = m.cast<Complex>();
  const Complex uu = u.transpose() * mc * u;
  const Complex uv = u.transpose() * mc * v;
  const Complex vv = v.transpose() * mc * v;
  Complex alpha[2], beta[2];
  SolveBinaryQuadratic(uu, uv, vv, alpha, beta);
  for (int j = 0; j < 2; ++j) points[j] = alpha[j] * u + beta[j] * v;
}

// IntersectConstraintConics on the already restricted conics.
int IntersectConics(const NullBasis& basis, Eigen::Matrix3d m1, Eigen::Matrix3d m2,
                    std::vector<ComplexConstraintVector>* roots) {
  roots->clear();
  const double n1 = m1.norm(), n2 = m2.norm();
  if (!(n1 > 0.0) || !(n2 > 0.0)) return 0;
  m1 /= n1;
  m2 /= n2;
  // Degenerate members of the pencil M1 + t M2: det = c0 + c1 t + c2 t^2 + c3 t^3 with
  // c1 = tr(adj(M1) M2), c2 = tr(M1 adj(M2)). A real root always exists (odd degree); solve
  // in t or in 1/t, whichever keeps the leading coefficient the larger.
  const double c0 = m1.determinant(), c3 = m2.determinant();
  const double c1 = (Adjugate(m1) * m2).trace(), c2 = (m1 * Adjugate(m2)).trace();
  if (std::max({std::abs(c0), std::abs(c1), std::abs(c2), std::abs(c3)}) <= 1e-11) return -1;
  double parameters[3];
  Eigen::Matrix3d members[3];
  int count = 0;
  if (std::abs(c3) >= std::abs(c0) && c3 != 0.0) {
    count = SolveCubicReal(c3, c2, c1, c0, parameters);
    for (int i = 0; i < count; ++i) members[i] = m1 + parameters[i] * m2;
  } else if (c0 != 0.0) {
    count = SolveCubicReal(c0, c1, c2, c3, parameters);  // in u = 1/t
    for (int i = 0; i < count; ++i) members[i] = parameters[i] * m1 + m2;
  } else {
    members[0] = m1;  // both ends singular: M1 itself is degenerate
    count = 1;
  }
  // The best-conditioned split: lines well apart, |adj(D)| large against |D|^2.
  int best = 0;
  double best_quality = -1.0;
  for (int i = 0; i < count; ++i) {
    members[i] /= members[i].norm();
    const double quality = Adjugate(members[i]).diagonal().cwiseAbs().maxCoeff();
    if (quality > best_quality) {
      best_quality = quality;
      best = i;
    }
  }
  const Eigen::Matrix3d& degenerate = members[best];
  // Intersect the two lines with the pencil member farthest from the degenerate one.
  const Eigen::Matrix3d other =
      std::abs(degenerate.cwiseProduct(m1).sum()) < std::abs(degenerate.cwiseProduct(m2).sum())
          ? m1
          : m2;
  Vector3c lines[2];
  SplitDegenerateConic(degenerate, &lines[0], &lines[1]);
  for (const Vector3c& line : lines) {
    Vector3c points[2];
    IntersectLineConic(line, other, points);
    for (const Vector3c& point : points) roots->push_back(basis.cast<Complex>() * point);
  }
  return static_cast<int>(roots->size());
}

// Newton's method in real arithmetic on a^T M1 a = a^T M2 a = 0 in the chart a0 . a = a0 . a0.
// Returns the final relative equation residual.
double PolishRealRoot(const Eigen::Matrix3d& m1, const Eigen::Matrix3d& m2, int iterations,
                      Eigen::Vector3d* a) {
  const Eigen::Vector3d a0 = a->normalized();
  *a = a0;
  const double scale1 = m1.norm(), scale2 = m2.norm();
  auto residual = [&](const Eigen::Vector3d& x) {
    return std::hypot(x.dot(m1 * x) / scale1, x.dot(m2 * x) / scale2) / x.squaredNorm();
  };
  double current = residual(*a);
  for (int iteration = 0; iteration < iterations && current > 1e-16; ++iteration) {
    Eigen::Matrix3d jacobian;
    jacobian.row(0) = 2.0 * (m1 * *a).transpose() / scale1;
    jacobian.row(1) = 2.0 * (m2 * *a).transpose() / scale2;
    jacobian.row(2) = a0.transpose();
    const Eigen::Vector3d f(a->dot(m1 * *a) / scale1, a->dot(m2 * *a) / scale2, 0.0);
    const Eigen::Vector3d step = jacobian.partialPivLu().solve(f);
    if (!step.allFinite()) break;
    const Eigen::Vector3d next = *a - step;
    const double next_residual = residual(next);
    if (!(next_residual < current)) break;
    *a = next;
    current = next_residual;
  }
  *a = a->normalized();
  return current;
}

// Gauss-Newton on a five-pose dyad (Newton for RR: 5 equations, 5 unknowns) on the
// dyad's own geometric equations, residual_j = signed distance of the constrained point from
// its circle or line (the design's residual). The projective root fixes the dyad; its reading
// in pivot coordinates, e.g. F = -K/K0, loses digits when the pivots are far from the pose
// origins (K0 small against |z|), which this polish in the dyad's own parameters restores to
// rounding level. Parameters: RR (F, m, r); PR (m, line normal angle, offset); RP (F, line
// normal angle in E, offset). Returns the polished dyad when it fits at least as well.
template <int kParameters>
PlanarDyad PolishDyadFixed(const PlanarDyad& dyad, const std::vector<PoseFrame>& poses,
                           int iterations) {
  using Parameters = Eigen::Matrix<double, kParameters, 1>;
  Parameters x;
  if constexpr (kParameters == 5) {
    x << dyad.fixed_pivot, dyad.moving_pivot, dyad.radius;
  } else {
    const Eigen::Vector2d normal(-dyad.line_direction.y(), dyad.line_direction.x());
    const Eigen::Vector2d point = dyad.type == DyadType::kPR ? dyad.moving_pivot : dyad.fixed_pivot;
    x << point, std::atan2(normal.y(), normal.x()), normal.dot(dyad.line_point);
  }
  auto make = [&](const Parameters& p) {
    if constexpr (kParameters == 5) {
      return PlanarDyad::RR(p.template segment<2>(0), p.template segment<2>(2), p[4]);
    } else {
      const Eigen::Vector2d normal(std::cos(p[2]), std::sin(p[2]));
      const Eigen::Vector2d direction(-normal.y(), normal.x());
      return dyad.type == DyadType::kPR
                 ? PlanarDyad::PR(p.template head<2>(), p[3] * normal, direction)
                 : PlanarDyad::RP(p.template head<2>(), p[3] * normal, direction);
    }
  };
  PlanarDyad best = dyad;
  double best_residual = MaxResidual(dyad, poses);
  Eigen::Matrix<double, 5, kParameters> jacobian;
  Eigen::Matrix<double, 5, 1> residual;
  for (int iteration = 0; iteration < iterations && best_residual > 0.0; ++iteration) {
    for (int j = 0; j < 5; ++j) {
      const Eigen::Matrix2d& rotation = poses[j].rotation;
      const Eigen::Vector2d& origin = poses[j].origin;
      if constexpr (kParameters == 5) {
        // |R m + d - F| - r; u the unit vector from F to the moving pivot.
        const Eigen::Vector2d arm =
            rotation * x.template segment<2>(2) + origin - x.template head<2>();
        const double distance = arm.norm();
        const Eigen::Vector2d u = arm / distance;
        residual[j] = distance - x[4];
        jacobian.template block<1, 2>(j, 0) = -u.transpose();
        jacobian.template block<1, 2>(j, 2) = u.transpose() * rotation;
        jacobian(j, 4) = -1.0;
      } else {
        const Eigen::Vector2d normal(std::cos(x[2]), std::sin(x[2]));
        const Eigen::Vector2d normal_rate(-normal.y(), normal.x());
        // PR: the moving pivot in Sigma on n . P = h; RP: the fixed pivot in E on n . p = h.
        const bool slider = dyad.type == DyadType::kPR;
        const Eigen::Vector2d point =
            slider ? Eigen::Vector2d(rotation * x.template head<2>() + origin)
                   : Eigen::Vector2d(rotation.transpose() * (x.template head<2>() - origin));
        residual[j] = normal.dot(point) - x[3];
        jacobian.template block<1, 2>(j, 0) =
            slider ? Eigen::RowVector2d(normal.transpose() * rotation)
                   : Eigen::RowVector2d((rotation * normal).transpose());
        jacobian(j, 2) = normal_rate.dot(point);
        jacobian(j, 3) = -1.0;
      }
    }
    Parameters step;
    if constexpr (kParameters == 5) {
      step = jacobian.partialPivLu().solve(residual);
    } else {
      step = jacobian.householderQr().solve(residual);
    }
    if (!step.allFinite()) break;
    x -= step;
    const PlanarDyad candidate = make(x);
    const double candidate_residual = MaxResidual(candidate, poses);
    if (!(candidate_residual <= best_residual)) break;
    best = candidate;
    best_residual = candidate_residual;
  }
  return best;
}

PlanarDyad PolishDyad(const PlanarDyad& dyad, const std::vector<PoseFrame>& poses, int iterations) {
  return dyad.type == DyadType::kRR ? PolishDyadFixed<5>(dyad, poses, iterations)
                                    : PolishDyadFixed<4>(dyad, poses, iterations);
}

// A real root read as a dyad in the normalized frames.
struct ReadRoot {
  PlanarDyad dyad;
  double max_residual = std::numeric_limits<double>::infinity();
};

// The readings of a real root z as a dyad, sliders first. Three readings exist (file
// comment): PR (K0 := 0, seed 001 eq. 13), RP (K0 := 0 and K := 0: the limit of an RR dyad
// whose moving pivot runs to infinity along n, z -> (0, n, 0, 0, -F . n, Fx ny - Fy nx, 2h),
// i.e. the fixed pivot F stays on the line n . p_E = h of E) and RR (K0 != 0). Returns the
// count.
int ReadingsOf(const ConstraintVector& z, const std::vector<PoseFrame>& poses,
               ReadRoot readings[3]) {
  const double k0 = z[0];
  const Eigen::Vector2d k(z[3], z[4]);
  const Eigen::Vector2d n(z[1], z[2]);
  int count = 0;
  auto add = [&](const PlanarDyad& dyad) {
    readings[count].dyad = dyad;
    readings[count].max_residual = MaxResidual(dyad, poses);
    ++count;
  };
  if (k.norm() > 0.0) {
    // PR: the line 2 K . P + K3 = 0, K3 = z7; moving pivot from [[K1, K2], [K2, -K1]] m =
    // (z5, z6).
    Eigen::Matrix2d kmat;
    kmat << k.x(), k.y(), k.y(), -k.x();
    const Eigen::Vector2d moving_pivot = kmat * Eigen::Vector2d(z[5], z[6]) / k.squaredNorm();
    const Eigen::Vector2d normal = k.normalized();
    add(PlanarDyad::PR(moving_pivot, (-z[7] / (2.0 * k.norm())) * normal,
                       Eigen::Vector2d(-normal.y(), normal.x())));
  }
  if (n.norm() > 0.0) {
    // RP: (z5, z6) = (-F . n, Fx ny - Fy nx) = [[-nx, -ny], [ny, -nx]] F, whose inverse is
    // its transpose over |n|^2; the line of E is n . p = z7 / 2.
    Eigen::Matrix2d nmat;
    nmat << -n.x(), n.y(), -n.y(), -n.x();
    const Eigen::Vector2d fixed_pivot = nmat * Eigen::Vector2d(z[5], z[6]) / n.squaredNorm();
    const Eigen::Vector2d normal = n.normalized();
    add(PlanarDyad::RP(fixed_pivot, (0.5 * z[7] / n.norm()) * normal,
                       Eigen::Vector2d(-normal.y(), normal.x())));
  }
  if (k0 != 0.0) {
    // RR: fixed pivot -K/K0 (seed 001 eq. 10); moving pivot from the least-squares
    // combination of z0 m = (z1, z2) and [[K1, K2], [K2, -K1]] m = (z5, z6), exact at a root
    // and well conditioned whether the fixed pivot is near (|K0| large) or far (|K| large).
    // The radius is the mean pivot distance over the poses (equal at every pose for an exact
    // root), free of the cancellation in |F|^2 - K3/K0.
    Eigen::Matrix2d kmat;
    kmat << k.x(), k.y(), k.y(), -k.x();
    const Eigen::Vector2d moving_pivot =
        (k0 * n + kmat * Eigen::Vector2d(z[5], z[6])) / (k0 * k0 + k.squaredNorm());
    const Eigen::Vector2d fixed_pivot = -k / k0;
    double radius = 0.0;
    for (const PoseFrame& pose : poses) {
      radius += (pose.rotation * moving_pivot + pose.origin - fixed_pivot).norm();
    }
    radius /= static_cast<double>(poses.size());
    add(PlanarDyad::RR(fixed_pivot, moving_pivot, radius));
  }
  return count;
}

// The typing rule: a slider reading (listed first) is taken when it fits the poses within
// `slider_tolerance` or at least as well as the circle reading, so that a radius beyond what
// rounding can tell from infinity is reported as a slider, consistently in both directions.
int ChooseReading(const ReadRoot readings[3], int count, double slider_tolerance) {
  int best = -1;
  for (int i = 0; i < count; ++i) {
    if (best < 0 || (readings[i].max_residual < readings[best].max_residual &&
                     readings[best].max_residual > slider_tolerance)) {
      best = i;
    }
  }
  return best;
}

// Centres and scales a motion: the fixed frame by its pose-origin centroid and L, the moving
// frame by L. `to_original_*` map the normalized frames back.
struct NormalizedMotion {
  std::vector<PlanarPose> poses;
  Similarity2 to_original_fixed;
  Similarity2 to_original_moving;
};

NormalizedMotion Normalize(const std::vector<PlanarPose>& poses) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  centroid /= static_cast<double>(poses.size());
  double length = CharacteristicLength(poses);
  if (!(length > 0.0)) length = 1.0;
  NormalizedMotion out;
  out.to_original_fixed.scale = length;
  out.to_original_fixed.translation = centroid;
  out.to_original_moving.scale = length;
  const Similarity2 to_fixed = out.to_original_fixed.Inverse();
  const Similarity2 to_moving = out.to_original_moving.Inverse();
  out.poses.reserve(poses.size());
  for (const PlanarPose& pose : poses)
    out.poses.push_back(TransformPose(pose, to_fixed, to_moving));
  return out;
}

struct CoreResult {
  std::vector<ReadRoot> roots;  // real roots, read, without duplicates
  int roots_total = 0;
  int roots_real = 0;
  double condition = 0.0;
  double fit_residual = 0.0;
  bool degenerate = false;
};

// The constraint-space solve on normalized poses.
void SolveNormalized(const std::vector<PlanarPose>& poses, const PlanarBurmesterOptions& options,
                     CoreResult* result) {
  const int n = static_cast<int>(poses.size());
  NullBasis basis;
  if (n == 5) {
    // Null space of the 5 x 8 matrix from a column-pivoted QR of its transpose.
    Eigen::Matrix<double, 5, 8> rows5;
    for (int j = 0; j < 5; ++j) rows5.row(j) = ConstraintRow(poses[j]).transpose();
    const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 8, 5>> qr(rows5.transpose());
    const Eigen::Matrix<double, 8, 8> q = qr.householderQ();
    basis = q.rightCols<3>();
    const double r_first = std::abs(qr.matrixR()(0, 0));
    const double r_last = std::abs(qr.matrixR()(4, 4));
    result->condition = r_last > 0.0 ? r_first / r_last : std::numeric_limits<double>::infinity();
    result->degenerate = !(r_last > options.rank_tolerance * r_first);
  } else {
    // More poses: the three smallest right singular vectors, the algebraic least-squares
    // seed (the planar counterpart of seed 000 section 4.1).
    Eigen::MatrixXd rows(n, 8);
    for (int j = 0; j < n; ++j) rows.row(j) = ConstraintRow(poses[j]).transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeFullV);
    basis = svd.matrixV().rightCols<3>();
    const Eigen::VectorXd sigma = svd.singularValues();
    result->condition =
        sigma[4] > 0.0 ? sigma[0] / sigma[4] : std::numeric_limits<double>::infinity();
    result->degenerate = !(sigma[4] > options.rank_tolerance * sigma[0]);
    double sum = 0.0;
    for (int i = 5; i < sigma.size(); ++i) sum += sigma[i] * sigma[i];
    result->fit_residual = std::sqrt(sum / n);
  }
  if (result->degenerate) return;

  std::vector<ComplexConstraintVector> complex_roots;
  Eigen::Matrix3d m1, m2;
  RestrictedConics(basis, &m1, &m2);
  result->roots_total = IntersectConics(basis, m1, m2, &complex_roots);
  if (result->roots_total < 0) {
    // The two conics share a component: a curve of dyads (e.g. the Cardan motion of an
    // elliptic trammel, where every point of a circle of E moves on a line).
    result->roots_total = 0;
    result->degenerate = true;
    return;
  }

  const std::vector<PoseFrame> frames = MakeFrames(poses);
  for (const ComplexConstraintVector& z : complex_roots) {
    // Back to P^2 coordinates (the basis is orthonormal), phase removed.
    Vector3c a = basis.transpose().cast<Complex>() * z;
    int k = 0;
    a.cwiseAbs().maxCoeff(&k);
    a /= a[k];
    const double imaginary = a.imag().norm() / a.real().norm();
    if (!(imaginary <= options.real_tolerance)) continue;
    Eigen::Vector3d a_real = a.real();
    const double residual = PolishRealRoot(m1, m2, options.newton_iterations, &a_real);
    if (!(residual <= 1e-9)) continue;
    ++result->roots_real;
    const ConstraintVector z_real = basis * a_real;
    ReadRoot readings[3];
    const int count = ReadingsOf(z_real, frames, readings);
    if (count == 0) continue;
    int chosen = ChooseReading(readings, count, options.slider_tolerance);
    if (n == 5) {
      // Polish the chosen reading on its geometric equations. Near a double root (a slider
      // next to a huge-radius circle) the unpolished residuals can mislead the typing: then
      // polish every reading and type again on the polished ones.
      ReadRoot& first = readings[chosen];
      first.dyad = PolishDyad(first.dyad, frames, options.newton_iterations);
      first.max_residual = MaxResidual(first.dyad, frames);
      if (first.max_residual > options.slider_tolerance) {
        for (int i = 0; i < count; ++i) {
          if (i == chosen) continue;
          readings[i].dyad = PolishDyad(readings[i].dyad, frames, options.newton_iterations);
          readings[i].max_residual = MaxResidual(readings[i].dyad, frames);
        }
        chosen = ChooseReading(readings, count, options.slider_tolerance);
      }
    }
    // Two complex-conjugate roots near a real double root polish to the same point: keep one.
    const ReadRoot& read = readings[chosen];
    bool duplicate = false;
    for (const ReadRoot& previous : result->roots) {
      if (previous.dyad.type == read.dyad.type &&
          (previous.dyad.moving_pivot - read.dyad.moving_pivot).norm() < 1e-7 &&
          (previous.dyad.fixed_pivot - read.dyad.fixed_pivot).norm() < 1e-7 &&
          (previous.dyad.line_point - read.dyad.line_point).norm() < 1e-7) {
        duplicate = true;
      }
    }
    if (!duplicate) result->roots.push_back(read);
  }
}

}  // namespace

ConstraintVector ConstraintRow(const PlanarPose& pose) {
  // The constraint K0 |P|^2 + 2 K . P + K3 = 0 with P = R m + d, multiplied by
  // (X3^2 + X4^2)/4, written in the image coordinates of seed 001 eq. 2 (so that
  // cos(phi) = (X4^2 - X3^2)/4, sin(phi) = X3 X4 / 2, d from eq. 3, R^T d from eq. 5):
  //   |d|^2 z0 + 2 (R^T d) . (z1, z2) + 2 d . (z3, z4) + 2 cos(phi) z5 + 2 sin(phi) z6 + z7.
  const Eigen::Vector4d x = ImageCoordinates(pose);
  ConstraintVector row;
  row << x[0] * x[0] + x[1] * x[1],       //
      x[1] * x[3] - x[0] * x[2],          //
      -(x[1] * x[2] + x[0] * x[3]),       //
      x[0] * x[2] + x[1] * x[3],          //
      x[1] * x[2] - x[0] * x[3],          //
      0.5 * (x[3] * x[3] - x[2] * x[2]),  //
      x[2] * x[3],                        //
      0.25 * (x[2] * x[2] + x[3] * x[3]);
  return row;
}

int IntersectConstraintConics(const Eigen::Matrix<double, 8, 3>& basis,
                              std::vector<ComplexConstraintVector>* roots) {
  Eigen::Matrix3d m1, m2;
  RestrictedConics(basis, &m1, &m2);
  return IntersectConics(basis, m1, m2, roots);
}

int SolvePlanarBurmester(const std::vector<PlanarPose>& poses,
                         const PlanarBurmesterOptions& options, std::vector<PlanarDyad>* dyads,
                         PlanarBurmesterSummary* summary) {
  dyads->clear();
  PlanarBurmesterSummary local_summary;
  if (poses.size() < 5) {
    if (summary) *summary = local_summary;
    return 0;
  }
  const NormalizedMotion direct = Normalize(poses);
  CoreResult core;
  SolveNormalized(direct.poses, options, &core);
  local_summary.roots_total = core.roots_total;
  local_summary.roots_real = core.roots_real;
  local_summary.condition = core.condition;
  local_summary.fit_residual = core.fit_residual;
  local_summary.degenerate = core.degenerate;
  for (const ReadRoot& root : core.roots) {
    dyads->push_back(TransformDyad(root.dyad, direct.to_original_fixed, direct.to_original_moving));
  }
  if (summary) *summary = local_summary;
  return static_cast<int>(dyads->size());
}

}  // namespace linkfit
