#include "fitting/spatial_burmester.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "fitting/model_choice.h"

namespace linkfit {
namespace {

using Complex = std::complex<double>;
using Vector8c = Eigen::Matrix<Complex, 8, 1>;
using Matrix8c = Eigen::Matrix<Complex, 8, 8>;
using Vector8d = Eigen::Matrix<double, 8, 1>;
using Matrix8d = Eigen::Matrix<double, 8, 8>;

// Monomials in c = (c1, c2, c3, c4) of degree 3 (20) and 4 (35), and the product table.
struct MonomialTables {
  static constexpr int kCubic = 20;
  static constexpr int kQuartic = 35;
  std::array<std::array<int, 4>, kCubic> cubic;
  std::array<std::array<int, 4>, kQuartic> quartic;
  std::array<std::array<int, 4>, kCubic> times;  // index of cubic[m] * c_j among the quartics
  std::array<int, 4> pure;                       // index of c_l^4
  std::array<std::array<int, 4>, 4> mixed;       // index of c_j c_l^3 (mixed[j][l])

  MonomialTables() {
    int count3 = 0, count4 = 0;
    for (int e0 = 4; e0 >= 0; --e0) {
      for (int e1 = 4 - e0; e1 >= 0; --e1) {
        for (int e2 = 4 - e0 - e1; e2 >= 0; --e2) {
          quartic[count4++] = {e0, e1, e2, 4 - e0 - e1 - e2};
        }
      }
    }
    for (int e0 = 3; e0 >= 0; --e0) {
      for (int e1 = 3 - e0; e1 >= 0; --e1) {
        for (int e2 = 3 - e0 - e1; e2 >= 0; --e2) cubic[count3++] = {e0, e1, e2, 3 - e0 - e1 - e2};
      }
    }
    for (int m = 0; m < kCubic; ++m) {
      for (int j = 0; j < 4; ++j) {
        std::array<int, 4> e = cubic[m];
        ++e[j];
        times[m][j] = Find(e);
      }
    }
    for (int l = 0; l < 4; ++l) {
      std::array<int, 4> e = {0, 0, 0, 0};
      e[l] = 4;
      pure[l] = Find(e);
      for (int j = 0; j < 4; ++j) {
        std::array<int, 4> f = {0, 0, 0, 0};
        f[l] = 3;
        ++f[j];
        mixed[j][l] = Find(f);
      }
    }
  }
  int Find(const std::array<int, 4>& e) const {
    for (int i = 0; i < kQuartic; ++i) {
      if (quartic[i] == e) return i;
    }
    return -1;
  }
};

const MonomialTables& Tables() {
  static const MonomialTables tables;
  return tables;
}

// Fixed generic coefficients for the shift polynomial h(c) and the combination of the shift
// operators: any numbers away from special values do; fixed ones keep results reproducible.
constexpr double kShift[4] = {0.4318, -0.7351, 0.2579, 0.8892};
constexpr double kCombination[4] = {0.6181, 0.2903, -0.5557, 0.3719};

double Residual(const BilinearMatrices& matrices, const Eigen::Vector4cd& a,
                const Eigen::Vector4cd& c) {
  const Eigen::Vector4cd unit_a = a / a.norm(), unit_c = c / c.norm();
  double worst = 0.0;
  for (int k = 0; k < 6; ++k) {
    const Complex value = (unit_a.transpose() * matrices[k].cast<Complex>() * unit_c)(0, 0);
    worst = std::max(worst, std::abs(value) / matrices[k].norm());
  }
  return worst;
}

// Newton's method on a^T B_k c = 0 with the patches conj(a0) . a = 1, conj(c0) . c = 1 (a0, c0
// the unit start values), in the scalar type of the start (real or complex).
template <typename Scalar>
void PolishBilinear(const BilinearMatrices& matrices, int iterations,
                    Eigen::Matrix<Scalar, 4, 1>* a, Eigen::Matrix<Scalar, 4, 1>* c) {
  using Vector4 = Eigen::Matrix<Scalar, 4, 1>;
  using Vector8 = Eigen::Matrix<Scalar, 8, 1>;
  using Matrix8 = Eigen::Matrix<Scalar, 8, 8>;
  *a /= a->norm();
  *c /= c->norm();
  const Vector4 patch_a = a->conjugate(), patch_c = c->conjugate();
  for (int iteration = 0; iteration < iterations; ++iteration) {
    Vector8 f;
    Matrix8 jacobian = Matrix8::Zero();
    for (int k = 0; k < 6; ++k) {
      const Eigen::Matrix<Scalar, 4, 4> b = matrices[k].cast<Scalar>();
      const Vector4 bc = b * *c;
      f[k] = a->cwiseProduct(bc).sum();
      jacobian.template block<1, 4>(k, 0) = bc.transpose();
      jacobian.template block<1, 4>(k, 4) = (b.transpose() * *a).transpose();
    }
    f[6] = patch_a.cwiseProduct(*a).sum() - Scalar(1);
    f[7] = patch_c.cwiseProduct(*c).sum() - Scalar(1);
    jacobian.template block<1, 4>(6, 0) = patch_a.transpose();
    jacobian.template block<1, 4>(7, 4) = patch_c.transpose();
    const Vector8 step = jacobian.partialPivLu().solve(f);
    if (!step.allFinite()) break;
    *a -= step.template head<4>();
    *c -= step.template tail<4>();
    if (step.norm() < 1e-15) break;
  }
}

// Unit norm, largest entry real and positive.
Eigen::Vector4cd Canonical(Eigen::Vector4cd v) {
  int k = 0;
  v.cwiseAbs().maxCoeff(&k);
  v *= std::conj(v[k]) / std::abs(v[k]);
  return v / v.norm();
}

double ImaginaryShare(const Eigen::Vector4cd& v) { return v.imag().norm() / v.norm(); }

double ProjectiveDistance(const Eigen::Vector4cd& u, const Eigen::Vector4cd& v) {
  const double overlap = std::abs(u.dot(v)) / (u.norm() * v.norm());
  return std::sqrt(std::max(0.0, 1.0 - overlap * overlap));
}

}  // namespace

Eigen::Matrix<double, 17, 1> SpatialConstraintRow(const Eigen::Matrix3d& rotation,
                                                  const Eigen::Vector3d& translation) {
  // Eq. 8 times C4 with C = R c + d c4: the terms 2 A . C C4 + A0 C4^2 - A4 |C|^2, divided by
  // c4, regrouped on P0 = A0 c4 - A4 |c|^2 / c4 and P = a (x) c (eqs 10-12).
  Eigen::Matrix<double, 17, 1> row;
  row[0] = 1.0;
  const Eigen::Vector3d rotated_translation = rotation.transpose() * translation;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      double value;
      if (i < 3 && j < 3) {
        value = 2.0 * rotation(i, j);
      } else if (i < 3) {
        value = 2.0 * translation[i];
      } else if (j < 3) {
        value = -2.0 * rotated_translation[j];
      } else {
        value = -translation.squaredNorm();
      }
      row[1 + 4 * j + i] = value;
    }
  }
  return row;
}

int SolveBilinearSystem(const BilinearMatrices& matrices, const BilinearSolverOptions& options,
                        std::vector<BilinearRoot>* roots, BilinearSolverSummary* summary) {
  const MonomialTables& tables = Tables();
  constexpr int kRows = 6 * MonomialTables::kCubic;       // 120
  constexpr int kColumns = 4 * MonomialTables::kQuartic;  // 140
  constexpr int kRoots = kColumns - kRows;                // 20
  roots->clear();
  BilinearSolverSummary local;

  // The transposed Macaulay matrix: column (k, m) holds the coefficients of (a^T B_k c) * m(c),
  // m a cubic monomial, on the monomials a_i * q(c), q quartic (row i * 35 + q).
  Eigen::MatrixXd macaulay_t = Eigen::MatrixXd::Zero(kColumns, kRows);
  for (int k = 0; k < 6; ++k) {
    for (int m = 0; m < MonomialTables::kCubic; ++m) {
      const int column = k * MonomialTables::kCubic + m;
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          macaulay_t(i * MonomialTables::kQuartic + tables.times[m][j], column) +=
              matrices[k](i, j);
        }
      }
    }
  }
  // Its null space: the orthogonal complement of the column space of the transpose.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(macaulay_t);
  const auto r = qr.matrixQR().topLeftCorner(kRows, kRows);
  double r_max = 0.0, r_min = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kRows; ++i) {
    r_max = std::max(r_max, std::abs(r(i, i)));
    r_min = std::min(r_min, std::abs(r(i, i)));
  }
  local.rank = kRows;
  if (!(r_min > options.rank_tolerance * r_max)) {
    int rank = 0;
    for (int i = 0; i < kRows; ++i) rank += std::abs(r(i, i)) > options.rank_tolerance * r_max;
    local.rank = rank;
    if (summary) *summary = local;
    return -1;
  }
  Eigen::MatrixXd null_space = Eigen::MatrixXd::Identity(kColumns, kColumns).rightCols(kRoots);
  null_space.applyOnTheLeft(qr.householderQ());

  // Rows of the null space at the monomials a_i m c_j (m cubic) give the shifts: with
  // Z = W T (W the monomial vectors of the roots), Z_j = W_3 D_j T, so Z_h^+ Z_j has the
  // eigenvalues c_j / h(c) and the common eigenvectors T^-1 e_p.
  constexpr int kBasis = 4 * MonomialTables::kCubic;  // 80
  Eigen::Matrix<double, kBasis, kRoots> z_h = Eigen::Matrix<double, kBasis, kRoots>::Zero();
  Eigen::Matrix<double, kBasis, kRoots> z_g = Eigen::Matrix<double, kBasis, kRoots>::Zero();
  for (int i = 0; i < 4; ++i) {
    for (int m = 0; m < MonomialTables::kCubic; ++m) {
      const int row = i * MonomialTables::kCubic + m;
      for (int j = 0; j < 4; ++j) {
        const auto source = null_space.row(i * MonomialTables::kQuartic + tables.times[m][j]);
        z_h.row(row) += kShift[j] * source;
        z_g.row(row) += kCombination[j] * source;
      }
    }
  }
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, kBasis, kRoots>> shift_qr(z_h);
  const Eigen::Matrix<double, kRoots, kRoots> operator_g = shift_qr.solve(z_g);
  const Eigen::EigenSolver<Eigen::Matrix<double, kRoots, kRoots>> eigen(operator_g, true);
  if (eigen.info() != Eigen::Success) {
    if (summary) *summary = local;
    return -1;
  }
  const Eigen::MatrixXcd evaluations = null_space.cast<Complex>() * eigen.eigenvectors();

  for (int p = 0; p < kRoots; ++p) {
    const auto w = evaluations.col(p);
    // Read c from the entries a_i c_j c_l^3 and a from a_i c_l^4, at the largest c_l^4.
    int best_i = 0, best_l = 0;
    double best = -1.0;
    for (int i = 0; i < 4; ++i) {
      for (int l = 0; l < 4; ++l) {
        const double size = std::abs(w[i * MonomialTables::kQuartic + tables.pure[l]]);
        if (size > best) {
          best = size;
          best_i = i;
          best_l = l;
        }
      }
    }
    Eigen::Vector4cd a, c;
    const Complex pivot = w[best_i * MonomialTables::kQuartic + tables.pure[best_l]];
    for (int j = 0; j < 4; ++j) {
      c[j] = w[best_i * MonomialTables::kQuartic + tables.mixed[j][best_l]] / pivot;
      a[j] = w[j * MonomialTables::kQuartic + tables.pure[best_l]] / pivot;
    }
    PolishBilinear<Complex>(matrices, options.newton_iterations, &a, &c);
    BilinearRoot root;
    root.a = Canonical(a);
    root.c = Canonical(c);
    const double imaginary = std::max(ImaginaryShare(root.a), ImaginaryShare(root.c));
    if (imaginary <= options.real_tolerance) {
      Eigen::Vector4d a_real = root.a.real(), c_real = root.c.real();
      PolishBilinear<double>(matrices, options.newton_iterations, &a_real, &c_real);
      const Eigen::Vector4cd a_candidate = a_real.cast<Complex>(),
                             c_candidate = c_real.cast<Complex>();
      if (Residual(matrices, a_candidate, c_candidate) <= options.residual_tolerance) {
        root.a = Canonical(a_candidate);
        root.c = Canonical(c_candidate);
        root.real = true;
      }
    }
    root.residual = Residual(matrices, root.a, root.c);
    if (!(root.residual <= options.residual_tolerance)) ++local.unconverged;
    // Two eigenvectors that polish to one root (nearly equal eigenvalues): keep one.
    bool duplicate = false;
    for (const BilinearRoot& previous : *roots) {
      if (ProjectiveDistance(previous.a, root.a) < 1e-8 &&
          ProjectiveDistance(previous.c, root.c) < 1e-8) {
        duplicate = true;
      }
    }
    if (duplicate) continue;
    local.real_roots += root.real;
    local.nearly_real += !root.real && imaginary <= options.nearly_real_share;
    roots->push_back(root);
  }
  local.roots = static_cast<int>(roots->size());
  if (summary) *summary = local;
  return local.roots;
}

BilinearMatrices SpatialBilinearMatrices(const std::vector<DualQuaternion>& poses,
                                         const std::vector<double>& weights,
                                         Eigen::Matrix<double, 16, 1>* sigma) {
  const int n = static_cast<int>(poses.size());
  Eigen::Matrix<double, Eigen::Dynamic, 16> rows(n, 16);
  Eigen::Matrix<double, 1, 16> mean = Eigen::Matrix<double, 1, 16>::Zero();
  double weight_sum = 0.0;
  for (int j = 0; j < n; ++j) {
    const double weight = weights.empty() ? 1.0 : weights[j];
    rows.row(j) =
        SpatialConstraintRow(poses[j].Rotation(), poses[j].Translation()).tail<16>().transpose();
    mean += weight * rows.row(j);
    weight_sum += weight;
  }
  mean /= weight_sum;
  // Eliminating P0 (eq. 10 with K0 = 1): the least-squares P0 is minus the weighted mean of
  // the other terms, which leaves the weighted, centered rows.
  for (int j = 0; j < n; ++j) {
    const double weight = weights.empty() ? 1.0 : weights[j];
    rows.row(j) = std::sqrt(weight) * (rows.row(j) - mean);
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, 16>> svd(rows, Eigen::ComputeFullV);
  if (sigma) {
    sigma->setZero();
    sigma->head(svd.singularValues().size()) = svd.singularValues();
  }
  BilinearMatrices matrices;
  for (int k = 0; k < 6; ++k) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) matrices[k](i, j) = svd.matrixV()(4 * j + i, k);
    }
  }
  return matrices;
}

namespace {

using Frame = SpatialFrame;

double MaxResidual(const SpatialDyad& dyad, const std::vector<Frame>& frames) {
  double worst = 0.0;
  for (const Frame& frame : frames) {
    worst = std::max(worst, std::abs(dyad.Residual(frame.rotation, frame.translation)));
  }
  return worst;
}

// Gauss-Newton on the dyad's own geometric residuals (SpatialDyadResiduals: SS 7 parameters A,
// c, r; PS and SP the point, the normal's two turns, the offset), each step kept while it
// lowers the largest residual.
SpatialDyad PolishGeometric(SpatialDyad dyad, const std::vector<Frame>& frames, int iterations) {
  double worst = MaxResidual(dyad, frames);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    Eigen::VectorXd residual;
    Eigen::MatrixXd jacobian;
    SpatialDyadResiduals(dyad, frames, &residual, &jacobian);
    if (!residual.allFinite() || !jacobian.allFinite()) break;
    const Eigen::VectorXd step = jacobian.colPivHouseholderQr().solve(residual);
    if (!step.allFinite()) break;
    const SpatialDyad next = SpatialDyadStep(dyad, step);
    const double next_worst = MaxResidual(next, frames);
    if (!(next_worst <= worst)) break;
    dyad = next;
    worst = next_worst;
    if (step.norm() < 1e-15) break;
  }
  return dyad;
}

// Levenberg-Marquardt steps for the real part of a complex root.
constexpr int kComplexFitIterations = 50;

struct Reading {
  SpatialDyad dyad;
  double max_residual = 0.0;
};

}  // namespace

int SolveSpatialBurmester(const std::vector<DualQuaternion>& poses,
                          const std::vector<double>& weights,
                          const SpatialBurmesterOptions& options, std::vector<SpatialDyad>* dyads,
                          SpatialBurmesterSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  dyads->clear();
  SpatialBurmesterSummary local;
  const int n = static_cast<int>(poses.size());
  const auto finish = [&]() {
    local.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (summary) *summary = local;
    return static_cast<int>(dyads->size());
  };
  if (n < 7) return finish();

  // Center Sigma at the pose-origin centroid, scale both frames by L.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : poses) centroid += pose.Translation();
  centroid /= n;
  double sum = 0.0;
  for (const DualQuaternion& pose : poses) sum += (pose.Translation() - centroid).squaredNorm();
  double length = std::sqrt(sum / n);
  if (!(length > 0.0)) length = 1.0;
  Similarity3 to_original_fixed, to_original_moving;
  to_original_fixed.scale = length;
  to_original_fixed.translation = centroid;
  to_original_moving.scale = length;
  std::vector<DualQuaternion> normalized;
  std::vector<Frame> frames;
  normalized.reserve(n);
  frames.reserve(n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix3d rotation = poses[j].Rotation();
    Frame frame;
    frame.rotation = rotation;
    frame.translation = (poses[j].Translation() - centroid) / length;
    normalized.push_back(DualQuaternion::FromRotationTranslation(rotation, frame.translation));
    frames.push_back(frame);
  }

  Eigen::Matrix<double, 16, 1> sigma;
  const BilinearMatrices matrices = SpatialBilinearMatrices(normalized, weights, &sigma);
  local.condition = sigma[5] > 0.0 ? sigma[0] / sigma[5] : std::numeric_limits<double>::infinity();
  if (n > 7) {
    double tail = 0.0;
    for (int i = 6; i < 16; ++i) tail += sigma[i] * sigma[i];
    local.fit_residual = std::sqrt(tail / n);
  }
  if (!(sigma[5] > options.rank_tolerance * sigma[0])) {
    local.degenerate = true;
    return finish();
  }
  std::vector<BilinearRoot> roots;
  BilinearSolverSummary bilinear;
  const int count = SolveBilinearSystem(matrices, options.bilinear, &roots, &bilinear);
  if (count < 0) {
    local.degenerate = true;
    return finish();
  }
  local.roots_total = count;
  local.roots_real = bilinear.real_roots;
  local.roots_verified = count - bilinear.unconverged;
  local.nearly_real = bilinear.nearly_real;

  // P0 of eq. 10 for a real root: minus the weighted mean of the other terms.
  const auto weight = [&](int j) { return weights.empty() ? 1.0 : weights[j]; };
  double weight_sum = 0.0;
  Eigen::Matrix<double, 16, 1> mean_row = Eigen::Matrix<double, 16, 1>::Zero();
  for (int j = 0; j < n; ++j) {
    mean_row +=
        weight(j) * SpatialConstraintRow(frames[j].rotation, frames[j].translation).tail<16>();
    weight_sum += weight(j);
  }
  mean_row /= weight_sum;
  const auto weighted_mean = [&](auto value) {
    double total = 0.0;
    for (int j = 0; j < n; ++j) total += weight(j) * value(frames[j]);
    return total / weight_sum;
  };

  // The data's precision in the normalized frames; coarser than rounding, complex roots may
  // be real within it.
  DataPrecision precision = options.precision;
  precision.length /= length;
  const bool coarse = RelativePrecision(precision, 1.0) > 1e-12;
  std::vector<Reading> found;
  std::vector<std::pair<Eigen::Vector4d, Eigen::Vector4d>> real_parts;  // of complex roots
  for (const BilinearRoot& root : roots) {
    if (!root.real && !coarse) continue;
    const Eigen::Vector4d a = root.a.real(), c = root.c.real();
    if (!root.real) {
      // A complex-conjugate pair has one real part: fitted once.
      const bool pair = std::any_of(real_parts.begin(), real_parts.end(), [&](const auto& seen) {
        return (seen.first - a).norm() < 1e-9 && (seen.second - c).norm() < 1e-9;
      });
      if (pair) continue;
      real_parts.emplace_back(a, c);
    }
    Reading readings[3];
    int readings_count = 0;
    // Sphere: center A = a/a4, point c/c4; r^2 = P0 + |c|^2 + |A|^2 (from P0 = A0 c4 -
    // A4 |c|^2/c4 and eq. 9 with a4 = c4 = 1).
    if (a[3] != 0.0 && c[3] != 0.0) {
      const Eigen::Vector3d center = a.head<3>() / a[3], point = c.head<3>() / c[3];
      Eigen::Matrix<double, 16, 1> outer;
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
          outer[4 * j + i] = (i < 3 ? center[i] : 1.0) * (j < 3 ? point[j] : 1.0);
        }
      }
      const double p0 = -mean_row.dot(outer);
      const double radius_squared = p0 + point.squaredNorm() + center.squaredNorm();
      if (radius_squared > 0.0 && std::isfinite(radius_squared)) {
        Reading& reading = readings[readings_count++];
        reading.dyad = SpatialDyad::SS(center, point, std::sqrt(radius_squared));
        reading.max_residual = MaxResidual(reading.dyad, frames);
      } else if (!(radius_squared > 0.0)) {
        ++local.imaginary_spheres;
      }
    }
    // Plane of Sigma (A4 -> 0): normal a_vec, the moving point c/c4.
    if (a.head<3>().norm() > 0.0 && c[3] != 0.0) {
      const Eigen::Vector3d normal = a.head<3>().normalized(), point = c.head<3>() / c[3];
      const double offset = weighted_mean(
          [&](const Frame& f) { return normal.dot(f.rotation * point + f.translation); });
      Reading& reading = readings[readings_count++];
      reading.dyad = SpatialDyad::PS(point, normal, offset);
      reading.max_residual = MaxResidual(reading.dyad, frames);
    }
    // Plane of E (c4 -> 0): the point A of Sigma stays on the plane c_vec . x = h of E.
    if (c.head<3>().norm() > 0.0 && a[3] != 0.0) {
      const Eigen::Vector3d normal = c.head<3>().normalized(), point = a.head<3>() / a[3];
      const double offset = weighted_mean([&](const Frame& f) {
        return normal.dot(f.rotation.transpose() * (point - f.translation));
      });
      Reading& reading = readings[readings_count++];
      reading.dyad = SpatialDyad::SP(point, normal, offset);
      reading.max_residual = MaxResidual(reading.dyad, frames);
    }
    if (readings_count == 0) continue;
    const auto choose = [&]() {
      // The sphere unless a plane reading fits within tolerance or at least as well.
      int chosen = 0;
      for (int i = 0; i < readings_count; ++i) {
        if (!std::isfinite(readings[i].max_residual)) continue;
        if (!std::isfinite(readings[chosen].max_residual)) chosen = i;
        if (readings[i].dyad.type != SpatialDyadType::kSS &&
            (readings[i].max_residual <= options.plane_tolerance ||
             readings[i].max_residual <= readings[chosen].max_residual)) {
          chosen = i;
        }
      }
      return chosen;
    };
    int chosen = choose();
    // The chosen reading refitted by `polish`; when it then misses (`fits` false), the other
    // readings too, typed again.
    const auto refit = [&](const auto& polish, const auto& fits) {
      const auto apply = [&](Reading* reading) {
        reading->dyad = polish(reading->dyad);
        reading->max_residual = MaxResidual(reading->dyad, frames);
      };
      apply(&readings[chosen]);
      if (fits(readings[chosen])) return;
      for (int i = 0; i < readings_count; ++i) {
        if (i != chosen) apply(&readings[i]);
      }
      chosen = choose();
    };
    if (!root.real) {
      // The real part of a complex root: fitted to the poses by least squares
      // (Levenberg-Marquardt: near the double root that rounding split there is no exact real
      // dyad, and Gauss-Newton's square steps overshoot the fold), within precision or not.
      refit(
          [&](const SpatialDyad& dyad) {
            return FitDyadLeastSquares(dyad, frames, kComplexFitIterations);
          },
          [&](const Reading& reading) {
            return PrecisionRatio(reading.dyad, normalized, precision, 1.0) <= kModelUnits;
          });
    } else if (n == 7) {
      refit(
          [&](const SpatialDyad& dyad) {
            return PolishGeometric(dyad, frames, options.newton_iterations);
          },
          [&](const Reading& reading) {
            return !(reading.max_residual > options.plane_tolerance);
          });
    }
    if (!std::isfinite(readings[chosen].max_residual)) continue;
    if (!root.real) {
      // The real part of a complex root: kept when its fitted dyad fits the poses within
      // precision, and once when two roots' fits come to the same dyad.
      const Reading& reading = readings[chosen];
      if (!(PrecisionRatio(reading.dyad, normalized, precision, 1.0) <= kModelUnits)) continue;
      const bool repeat = std::any_of(found.begin(), found.end(), [&](const Reading& other) {
        return other.dyad.type == reading.dyad.type &&
               (other.dyad.moving_pivot - reading.dyad.moving_pivot).norm() < 1e-6 &&
               (other.dyad.fixed_pivot - reading.dyad.fixed_pivot).norm() < 1e-6;
      });
      if (repeat) continue;
      ++local.real_within_precision;
    }
    found.push_back(readings[chosen]);
  }
  for (const Reading& reading : found) {
    dyads->push_back(TransformSpatialDyad(reading.dyad, to_original_fixed, to_original_moving));
  }
  return finish();
}

}  // namespace linkfit
