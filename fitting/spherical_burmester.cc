#include "fitting/spherical_burmester.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "fitting/model_choice.h"
#include "fitting/polynomial.h"

namespace linkfit {
namespace {

// Levenberg-Marquardt steps for the real part of a complex root (as the spatial solver's), and
// how near (SphericalDyadDistance, radians) two fitted real parts, or a real part and a real
// root, are one dyad.
constexpr int kComplexFitIterations = 50;
constexpr double kSameRealPart = 1e-6;

using Complex = std::complex<double>;
using Vector3c = Eigen::Vector3cd;

// Monomials of v of degree 2 and 3 (exponents sorted), indexed 0..5 and 0..9.
int Monomial2(int a, int b) {
  if (a > b) std::swap(a, b);
  static constexpr int kIndex[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  return kIndex[a][b];
}

int Monomial3(int a, int b, int c) {
  int e[3] = {a, b, c};
  std::sort(e, e + 3);
  // (000 001 002 011 012 022 111 112 122 222)
  static constexpr int kFirst[3] = {0, 6, 9};  // first index of each leading exponent
  if (e[0] == 0) return e[1] == 0 ? e[2] : (e[1] == 1 ? 2 + e[2] : 5);
  if (e[0] == 1) return kFirst[1] + (e[1] == 1 ? e[2] - 1 : 2);
  return kFirst[2];
}

// The weights, or 1 for each orientation.
std::vector<double> WeightsOf(const std::vector<double>& weights, size_t count) {
  return weights.size() == count ? weights : std::vector<double>(count, 1.0);
}

// Newton's method on u^T B_k v = 0 with |u| = |v| = 1 (six equations in six unknowns). Returns
// the largest |u^T B_k v| reached.
double PolishRoot(const std::vector<Eigen::Matrix3d>& bilinear, int iterations, Eigen::Vector3d* u,
                  Eigen::Vector3d* v) {
  const int equations = static_cast<int>(bilinear.size());
  const auto residual = [&]() {
    double worst = 0.0;
    for (const Eigen::Matrix3d& b : bilinear) worst = std::max(worst, std::abs(u->dot(b * *v)));
    return worst;
  };
  for (int iteration = 0; iteration < iterations; ++iteration) {
    Eigen::MatrixXd jacobian(equations + 2, 6);
    Eigen::VectorXd value(equations + 2);
    for (int k = 0; k < equations; ++k) {
      value(k) = u->dot(bilinear[k] * *v);
      jacobian.block<1, 3>(k, 0) = (bilinear[k] * *v).transpose();
      jacobian.block<1, 3>(k, 3) = (bilinear[k].transpose() * *u).transpose();
    }
    value(equations) = 0.5 * (u->squaredNorm() - 1.0);
    value(equations + 1) = 0.5 * (v->squaredNorm() - 1.0);
    jacobian.row(equations) << u->transpose(), 0.0, 0.0, 0.0;
    jacobian.row(equations + 1) << 0.0, 0.0, 0.0, v->transpose();
    const Eigen::VectorXd step = jacobian.colPivHouseholderQr().solve(value);
    if (!step.allFinite()) break;
    *u -= step.head<3>();
    *v -= step.tail<3>();
    if (step.norm() < 1e-15) break;
  }
  u->normalize();
  v->normalize();
  return residual();
}

// A complex vector scaled so that its largest entry is real and positive, of unit norm.
Vector3c PhaseNormalized(const Vector3c& x) {
  Eigen::Index largest = 0;
  x.cwiseAbs().maxCoeff(&largest);
  const Complex phase = x(largest) / std::abs(x(largest));
  return (x / phase).normalized();
}

// The dyad of axes u and v: alpha the weighted mean of the angles between u and R_j v.
SphericalDyad DyadOf(const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                     const std::vector<Eigen::Matrix3d>& rotations,
                     const std::vector<double>& weights) {
  double sum = 0.0, total = 0.0;
  for (size_t j = 0; j < rotations.size(); ++j) {
    sum += weights[j] * DirectionAngle(u, rotations[j] * v);
    total += weights[j];
  }
  return SphericalDyad::Make(u, v, sum / total);
}

// The adjugate's rows of M = [a0 a1 a2] are a1 x a2, a2 x a0, a0 x a1: tr(adj(A) B).
double AdjugateTrace(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return a.col(1).cross(a.col(2)).dot(b.col(0)) + a.col(2).cross(a.col(0)).dot(b.col(1)) +
         a.col(0).cross(a.col(1)).dot(b.col(2));
}

// M(x) = [B_1 x, B_2 x, B_3 x]: its determinant is the cubic cone of the moving axes.
Eigen::Matrix3d ConeMatrix(const std::vector<Eigen::Matrix3d>& bilinear, const Eigen::Vector3d& x) {
  Eigen::Matrix3d m;
  for (int k = 0; k < 3; ++k) m.col(k) = bilinear[k] * x;
  return m;
}

// Moves the unit x onto the cone det M(x) = 0 by Newton steps along the cone's gradient on the
// sphere. Returns false when it does not converge.
bool ProjectOntoCone(const std::vector<Eigen::Matrix3d>& bilinear, Eigen::Vector3d* x) {
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Matrix3d m = ConeMatrix(bilinear, *x);
    const double value = m.determinant();
    Eigen::Vector3d gradient;
    for (int c = 0; c < 3; ++c) {
      gradient(c) = AdjugateTrace(m, ConeMatrix(bilinear, Eigen::Vector3d::Unit(c)));
    }
    gradient -= gradient.dot(*x) * *x;  // along the sphere
    if (!(gradient.squaredNorm() > 0.0)) return std::abs(value) < 1e-14;
    const Eigen::Vector3d step = value / gradient.squaredNorm() * gradient;
    *x = (*x - step).normalized();
    if (step.norm() < 1e-15) break;
  }
  return std::abs(ConeMatrix(bilinear, *x).determinant()) < 1e-12;
}

// Samples the cone det M(x) = 0 (M of three bilinear matrices): a base line b of the cone, then
// the pencil of planes through it, each meeting the cone in two more lines (header comment).
std::vector<std::vector<Eigen::Vector3d>> SampleCone(const std::vector<Eigen::Matrix3d>& bilinear,
                                                     int samples) {
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  // A base line: the binary cubic of the cone on the plane of p and q has a real root.
  const Eigen::Vector3d p = Eigen::Vector3d(0.8, 0.36, 0.48).normalized();
  const Eigen::Vector3d q = p.unitOrthogonal();
  const Eigen::Matrix3d mp = ConeMatrix(bilinear, p), mq = ConeMatrix(bilinear, q);
  Eigen::Vector3d base = q;
  const double c3 = mp.determinant(), c0 = mq.determinant();
  if (c3 != 0.0) {
    double roots[3];
    SolveCubicReal(c3, AdjugateTrace(mp, mq), AdjugateTrace(mq, mp), c0, roots);
    base = (roots[0] * p + q).normalized();
  } else {
    base = p;
  }
  if (!ProjectOntoCone(bilinear, &base)) return polylines;
  const Eigen::Vector3d p1 = base.unitOrthogonal(), q1 = base.cross(p1);
  const Eigen::Matrix3d mb = ConeMatrix(bilinear, base);
  constexpr double kBreak = 0.3;  // radians between consecutive samples that start a new line
  std::vector<Eigen::Vector3d> current[2];
  const auto flush = [&](int slot) {
    if (current[slot].size() > 1) polylines.push_back(current[slot]);
    current[slot].clear();
  };
  for (int k = 0; k <= samples; ++k) {
    const double s = M_PI * k / samples;
    const Eigen::Vector3d w = std::cos(s) * p1 + std::sin(s) * q1;
    const Eigen::Matrix3d mw = ConeMatrix(bilinear, w);
    // det(l M(b) + m M(w)) = m (a2 l^2 + a1 l m + a0 m^2), det M(b) = 0.
    const double a2 = AdjugateTrace(mb, mw), a1 = AdjugateTrace(mw, mb), a0 = mw.determinant();
    if (0.25 * a1 * a1 - a2 * a0 < 0.0) {
      flush(0);
      flush(1);
      continue;
    }
    Complex alpha[2], beta[2];
    SolveBinaryQuadratic(a2, 0.5 * a1, a0, alpha, beta);
    Eigen::Vector3d points[2];
    for (int r = 0; r < 2; ++r) {
      points[r] = (alpha[r].real() * base + beta[r].real() * w).normalized();
    }
    // Keep each slot's line continuous: match the new lines to the slots' last samples.
    const auto near = [](const std::vector<Eigen::Vector3d>& line, const Eigen::Vector3d& x) {
      return line.empty() ? 0.0 : DirectionAngle(line.back(), x);
    };
    if (!current[0].empty() && !current[1].empty()) {
      const auto flip = [](const std::vector<Eigen::Vector3d>& line, const Eigen::Vector3d& x) {
        return std::min(DirectionAngle(line.back(), x), DirectionAngle(line.back(), -x));
      };
      if (flip(current[0], points[1]) + flip(current[1], points[0]) <
          flip(current[0], points[0]) + flip(current[1], points[1])) {
        std::swap(points[0], points[1]);
      }
    }
    for (int slot = 0; slot < 2; ++slot) {
      Eigen::Vector3d x = points[slot];
      if (!x.allFinite()) {
        flush(slot);
        continue;
      }
      if (!current[slot].empty() && current[slot].back().dot(x) < 0.0) x = -x;
      if (near(current[slot], x) > kBreak) flush(slot);
      current[slot].push_back(x);
    }
  }
  flush(0);
  flush(1);
  return polylines;
}

std::vector<Eigen::Matrix3d> Inverted(const std::vector<Eigen::Matrix3d>& rotations) {
  std::vector<Eigen::Matrix3d> inverted;
  for (const Eigen::Matrix3d& rotation : rotations) inverted.push_back(rotation.transpose());
  return inverted;
}

}  // namespace

void SphericalEquations(const std::vector<Eigen::Matrix3d>& rotations,
                        const std::vector<double>& weights_in, int equations,
                        std::vector<Eigen::Matrix3d>* bilinear, Eigen::VectorXd* singular_values) {
  const int n = static_cast<int>(rotations.size());
  const std::vector<double> weights = WeightsOf(weights_in, n);
  Eigen::Matrix<double, 9, 1> mean = Eigen::Matrix<double, 9, 1>::Zero();
  double total = 0.0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) mean(3 * i + k) += weights[j] * rotations[j](i, k);
    }
    total += weights[j];
  }
  mean /= total;
  Eigen::MatrixXd rows(n, 9);
  for (int j = 0; j < n; ++j) {
    const double scale = std::sqrt(weights[j]);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k)
        rows(j, 3 * i + k) = scale * (rotations[j](i, k) - mean(3 * i + k));
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeFullV);
  *singular_values = svd.singularValues();
  bilinear->clear();
  for (int e = 0; e < equations; ++e) {
    Eigen::Matrix3d b;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) b(i, k) = svd.matrixV()(3 * i + k, e);
    }
    bilinear->push_back(b);
  }
}

int SolveSphericalBurmester(const std::vector<Eigen::Matrix3d>& rotations,
                            const std::vector<double>& weights_in,
                            const SphericalBurmesterOptions& options,
                            std::vector<SphericalDyad>* dyads, SphericalBurmesterSummary* summary) {
  dyads->clear();
  SphericalBurmesterSummary local;
  SphericalBurmesterSummary& info = summary ? *summary : local;
  info = SphericalBurmesterSummary();
  const int n = static_cast<int>(rotations.size());
  if (n < 5) return 0;
  const std::vector<double> weights = WeightsOf(weights_in, n);
  std::vector<Eigen::Matrix3d> bilinear;
  Eigen::VectorXd singular;
  SphericalEquations(rotations, weights, 4, &bilinear, &singular);
  info.condition =
      singular(3) > 0.0 ? singular(0) / singular(3) : std::numeric_limits<double>::infinity();
  if (n > 5) {
    double tail = 0.0;
    for (int k = 4; k < singular.size(); ++k) tail += singular(k) * singular(k);
    info.fit_residual = std::sqrt(tail / n);
  }
  if (!(singular(3) > options.rank_tolerance * singular(0))) {
    info.degenerate = true;
    return 0;
  }

  // Macaulay matrix of degree (1, 3): rows f_k v_a v_b, columns u_i v^3 (i * 10 + Monomial3).
  Eigen::Matrix<double, 24, 30> macaulay = Eigen::Matrix<double, 24, 30>::Zero();
  for (int k = 0; k < 4; ++k) {
    for (int a = 0; a < 3; ++a) {
      for (int b = a; b < 3; ++b) {
        const int row = 6 * k + Monomial2(a, b);
        for (int i = 0; i < 3; ++i) {
          for (int c = 0; c < 3; ++c)
            macaulay(row, 10 * i + Monomial3(a, b, c)) += bilinear[k](i, c);
        }
      }
    }
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, 24, 30>> svd(macaulay, Eigen::ComputeFullV);
  if (!(svd.singularValues()(23) > 1e-10 * svd.singularValues()(0))) {
    info.degenerate = true;
    return 0;
  }
  const Eigen::Matrix<double, 30, 6> null = svd.matrixV().rightCols<6>();
  // Shift the degree-(1, 2) monomials by h . v and g . v (fixed generic forms).
  const Eigen::Vector3d h(0.5773, 0.6143, 0.5379), g(-0.3217, 0.7713, 0.2269);
  Eigen::Matrix<double, 18, 6> shift_h, shift_g;
  for (int i = 0; i < 3; ++i) {
    for (int a = 0; a < 3; ++a) {
      for (int b = a; b < 3; ++b) {
        const int row = 6 * i + Monomial2(a, b);
        shift_h.row(row).setZero();
        shift_g.row(row).setZero();
        for (int c = 0; c < 3; ++c) {
          shift_h.row(row) += h(c) * null.row(10 * i + Monomial3(a, b, c));
          shift_g.row(row) += g(c) * null.row(10 * i + Monomial3(a, b, c));
        }
      }
    }
  }
  const Eigen::Matrix<double, 6, 6> operator_gh = shift_h.colPivHouseholderQr().solve(shift_g);
  const Eigen::EigenSolver<Eigen::Matrix<double, 6, 6>> eigen(operator_gh);
  if (eigen.info() != Eigen::Success) {
    info.degenerate = true;
    return 0;
  }
  info.roots_total = 6;
  const Eigen::Matrix<Complex, 30, 6> roots = null.cast<Complex>() * eigen.eigenvectors();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> real_roots;
  // The real parts of complex roots that fit the orientations within the data's precision.
  std::vector<SphericalDyad> within_precision;
  const double fits_within =
      kModelUnits * PointUncertainty(DataPrecision{0.0, options.precision.angle}, 1.0, 1.0);
  // Rounding by a relative p splits a double root by about sqrt(p): only roots within 100 sqrt(p)
  // of real are tried (10 sqrt(p) lost 4 of 400 dyads of five Euler-angle orientations printed
  // to four digits, whose precision is that of the largest angle; the bound spares the fit of
  // far complex roots on exact data).
  const double near_real_share =
      100.0 * std::sqrt(std::max(options.precision.angle, std::numeric_limits<double>::epsilon()));
  const auto keep_real_part = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                                  double share) {
    if (!(share <= near_real_share) || !(u.norm() > 0.0) || !(v.norm() > 0.0)) return;
    const SphericalDyad raw =
        FitDyadLeastSquares(DyadOf(u.normalized(), v.normalized(), rotations, weights), rotations,
                            kComplexFitIterations);
    const SphericalDyad fitted = SphericalDyad::Make(raw.fixed_axis, raw.moving_axis, raw.angle);
    if (!fitted.AllFinite() || !(fitted.MaxResidual(rotations) <= fits_within)) return;
    // A conjugate pair has one real part: kept once.
    for (const SphericalDyad& kept : within_precision) {
      if (SphericalDyadDistance(kept, fitted) < kSameRealPart) return;
    }
    within_precision.push_back(fitted);
  };
  for (int r = 0; r < 6; ++r) {
    // The monomial vector u_i v^3: u from its largest column, v from v_a^2 v (a the largest).
    Eigen::Matrix<Complex, 3, 10> m;
    for (int i = 0; i < 3; ++i) m.row(i) = roots.col(r).segment<10>(10 * i).transpose();
    Eigen::Index column = 0;
    m.colwise().norm().maxCoeff(&column);
    const Vector3c u = PhaseNormalized(m.col(column));
    const Eigen::Matrix<Complex, 1, 10> cubic = u.adjoint() * m;
    int a = 0;
    for (int e = 1; e < 3; ++e) {
      if (std::abs(cubic(Monomial3(e, e, e))) > std::abs(cubic(Monomial3(a, a, a)))) a = e;
    }
    const Vector3c v = PhaseNormalized(
        Vector3c(cubic(Monomial3(a, a, 0)), cubic(Monomial3(a, a, 1)), cubic(Monomial3(a, a, 2))));
    const double share = std::max(u.imag().cwiseAbs().maxCoeff(), v.imag().cwiseAbs().maxCoeff());
    if (!(share < options.real_tolerance)) {
      keep_real_part(u.real(), v.real(), share);
      continue;
    }
    Eigen::Vector3d ur = u.real(), vr = v.real();
    const double residual = PolishRoot(bilinear, options.newton_iterations, &ur, &vr);
    if (!(residual < 1e-9) || !ur.allFinite() || !vr.allFinite()) {
      if (share > 0.0) ++info.nearly_real;
      keep_real_part(u.real(), v.real(), share);
      continue;
    }
    // A double root polishes twice to one dyad.
    bool repeated = false;
    for (const auto& [uk, vk] : real_roots) {
      repeated =
          repeated || (std::abs(uk.dot(ur)) > 1.0 - 1e-9 && std::abs(vk.dot(vr)) > 1.0 - 1e-9);
    }
    if (repeated) continue;
    real_roots.push_back({ur, vr});
  }
  info.roots_real = static_cast<int>(real_roots.size());
  for (const auto& [u, v] : real_roots) dyads->push_back(DyadOf(u, v, rotations, weights));
  for (const SphericalDyad& dyad : within_precision) {
    // Not when it is one of the real roots (a double root that also polished).
    const bool repeat = std::any_of(dyads->begin(), dyads->end(), [&](const SphericalDyad& real) {
      return SphericalDyadDistance(real, dyad) < kSameRealPart;
    });
    if (repeat) continue;
    dyads->push_back(dyad);
    ++info.real_within_precision;
  }
  return static_cast<int>(dyads->size());
}

bool SphericalDyadFromMovingAxis(const std::vector<Eigen::Matrix3d>& rotations,
                                 const std::vector<double>& weights_in, const Eigen::Vector3d& axis,
                                 SphericalDyad* dyad, double* moved_deg) {
  const size_t n = rotations.size();
  if (n < 3 || !axis.allFinite() || !(axis.norm() > 0.0)) return false;
  const std::vector<double> weights = WeightsOf(weights_in, n);
  Eigen::Vector3d v = axis.normalized();
  if (moved_deg) *moved_deg = 0.0;
  if (n == 4) {
    std::vector<Eigen::Matrix3d> bilinear;
    Eigen::VectorXd singular;
    SphericalEquations(rotations, weights, 3, &bilinear, &singular);
    const Eigen::Vector3d given = v;
    if (!ProjectOntoCone(bilinear, &v)) return false;
    if (moved_deg) *moved_deg = DirectionAngle(given, v) * 180.0 / M_PI;
  }
  // The plane best fitting the positions R_j v: its normal is the fixed axis.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (size_t j = 0; j < n; ++j) {
    centroid += weights[j] * (rotations[j] * v);
    total += weights[j];
  }
  centroid /= total;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (size_t j = 0; j < n; ++j) {
    const Eigen::Vector3d x = rotations[j] * v - centroid;
    scatter += weights[j] * x * x.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // Positions that barely move (v along the common axis) do not determine the plane.
  if (!(eigen.eigenvalues()(1) > 1e-20 * total)) return false;
  *dyad = DyadOf(eigen.eigenvectors().col(0), v, rotations, weights);
  return dyad->AllFinite();
}

bool SphericalDyadFromFixedAxis(const std::vector<Eigen::Matrix3d>& rotations,
                                const std::vector<double>& weights,
                                const Eigen::Vector3d& fixed_axis, SphericalDyad* dyad,
                                double* moved_deg) {
  // In the inverted motion (E seen from Sigma) the fixed axis moves and the moving one stays.
  SphericalDyad inverted;
  if (!SphericalDyadFromMovingAxis(Inverted(rotations), weights, fixed_axis, &inverted,
                                   moved_deg)) {
    return false;
  }
  *dyad = SphericalDyad::Make(inverted.moving_axis, inverted.fixed_axis, inverted.angle);
  return true;
}

bool SampleSphericalBurmesterCones(const std::vector<Eigen::Matrix3d>& rotations, int samples,
                                   SphericalBurmesterCones* cones) {
  cones->center_axes.clear();
  cones->circle_axes.clear();
  if (rotations.size() != 4) return false;
  std::vector<Eigen::Matrix3d> bilinear;
  Eigen::VectorXd singular;
  SphericalEquations(rotations, {}, 3, &bilinear, &singular);
  if (!(singular(2) > 1e-10 * singular(0))) return false;
  cones->circle_axes = SampleCone(bilinear, samples);
  std::vector<Eigen::Matrix3d> transposed;
  for (const Eigen::Matrix3d& b : bilinear) transposed.push_back(b.transpose());
  cones->center_axes = SampleCone(transposed, samples);
  return !(cones->circle_axes.empty() && cones->center_axes.empty());
}

}  // namespace linkfit
