#include "fitting/timed_path.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "fitting/model_choice.h"
#include "lib/mechanism.h"

namespace linkfit {
namespace {

using Complex = std::complex<double>;
using Matrix3 = Eigen::Matrix3d;
using Vector3c = Eigen::Vector3cd;
using Vector4c = Eigen::Matrix<Complex, 4, 1>;
using Vector4d = Eigen::Vector4d;

// Two crank roots closer than this (relative, scaled frame) after Newton's method are one
// double root.
constexpr double kDoubleRoot = 1e-4;
// A complex-conjugate pair whose imaginary part is below this (relative, scaled frame) is tried
// as one real double root: the eigenvalues of a double root are accurate only to about
// sqrt(epsilon * condition), and a last-digit change of the data splits an inverted
// slider-crank's double crank into a real pair or a complex one 4e-4 apart (seen in a test
// task). The deflated polish then accepts it only if it is a real double root.
constexpr double kConjugateDoubleRoot = 1e-3;
// Newton iterations before the roots are compared (the full polish comes after).
constexpr int kClusterIterations = 2;
// Newton iterations on a complex (non-real) crank after the comparison.
constexpr int kComplexIterations = 2;
// Two output dyads of one crank closer than this (relative, scaled frame) are one.
constexpr double kSameDyad = 1e-6;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Index of the monomial u_l u_k among u1^2, u1 u2, u1 u0, u2^2, u2 u0, u0^2.
int Monomial(int l, int k) {
  static constexpr int kIndex[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  return kIndex[l][k];
}

// The task in the scaled frame: points P_j = (R_j - centroid) / L and the crank rotations.
struct ScaledPoints {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> betas;  // psi_j - psi_0
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double length = 1.0;
};

ScaledPoints Scale(const std::vector<Eigen::Vector2d>& points,
                   const std::vector<double>& input_angles) {
  ScaledPoints scaled;
  for (const Eigen::Vector2d& point : points) scaled.centroid += point;
  scaled.centroid /= static_cast<double>(points.size());
  double sum = 0.0;
  for (const Eigen::Vector2d& point : points) sum += (point - scaled.centroid).squaredNorm();
  scaled.length = std::sqrt(sum / static_cast<double>(points.size()));
  for (size_t j = 0; j < points.size(); ++j) {
    scaled.points.push_back((points[j] - scaled.centroid) / scaled.length);
    scaled.betas.push_back(input_angles[j] - input_angles[0]);
  }
  return scaled;
}

// The crank equation of point j >= 1 as a bilinear form b^T G u in homogeneous (b1, b2, b0),
// (u1, u2, u0) (see the header; seed 002 eq. 9 in B and u = a_0 - b):
//   G = [ R_j - 1              -(P_j - P_0)            ]
//       [ -(R_j^T P_j - P_0)^T  (|P_j|^2 - |P_0|^2) / 2 ]
Matrix3 CrankForm(const ScaledPoints& scaled, int j) {
  const Eigen::Matrix2d rotation = Rotation2(scaled.betas[j]);
  const Eigen::Vector2d& p0 = scaled.points[0];
  const Eigen::Vector2d& pj = scaled.points[j];
  Matrix3 form;
  form.topLeftCorner<2, 2>() = rotation - Eigen::Matrix2d::Identity();
  form.topRightCorner<2, 1>() = -(pj - p0);
  form.bottomLeftCorner<1, 2>() = -(rotation.transpose() * pj - p0).transpose();
  form(2, 2) = 0.5 * (pj.squaredNorm() - p0.squaredNorm());
  return form;
}

// The four affine crank equations at x = (B, u) and their Jacobian (T complex or real).
template <typename T>
void CrankEquations(const std::vector<Matrix3>& forms, const Eigen::Matrix<T, 4, 1>& x,
                    Eigen::Matrix<T, 4, 1>* value, Eigen::Matrix<T, 4, 4>* jacobian) {
  const T b[3] = {x(0), x(1), T(1.0)};
  const T u[3] = {x(2), x(3), T(1.0)};
  for (int j = 0; j < 4; ++j) {
    const Matrix3& form = forms[j];
    T form_u[3], form_t_b[3];  // G u and G^T b
    for (int i = 0; i < 3; ++i) {
      form_u[i] = form(i, 0) * u[0] + form(i, 1) * u[1] + form(i, 2) * u[2];
      form_t_b[i] = form(0, i) * b[0] + form(1, i) * b[1] + form(2, i) * b[2];
    }
    (*value)(j) = b[0] * form_u[0] + b[1] * form_u[1] + form_u[2];
    if (jacobian != nullptr) {
      (*jacobian)(j, 0) = form_u[0];
      (*jacobian)(j, 1) = form_u[1];
      (*jacobian)(j, 2) = form_t_b[0];
      (*jacobian)(j, 3) = form_t_b[1];
    }
  }
}

// Newton's method on the crank equations, stopping early once the step is below rounding;
// returns the largest |equation| after.
template <typename T>
double PolishCrank(const std::vector<Matrix3>& forms, int iterations, Eigen::Matrix<T, 4, 1>* x) {
  Eigen::Matrix<T, 4, 1> value;
  Eigen::Matrix<T, 4, 4> jacobian;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    CrankEquations(forms, *x, &value, &jacobian);
    const Eigen::Matrix<T, 4, 1> step = jacobian.partialPivLu().solve(value);
    if (!step.allFinite()) break;
    *x -= step;
    if (step.norm() <= 1e-15 * std::max(1.0, x->norm())) break;
  }
  CrankEquations<T>(forms, *x, &value, nullptr);
  return value.cwiseAbs().maxCoeff();
}

// A double root x is a regular root of the deflated system (Leykin, Verschelde and Zhao)
//   F(x) = 0,  J(x) v = 0,  c . v = 1
// (9 equations in x, v), solved by Gauss-Newton. F is bilinear, so d(J v)/dx is constant in x:
// row j is (G_j' v_u, G_j'^T v_B) with G_j' the 2 x 2 block of form j.
template <typename T>
double PolishDoubleCrank(const std::vector<Matrix3>& forms, int iterations,
                         Eigen::Matrix<T, 4, 1>* x) {
  Eigen::Matrix<T, 4, 1> value;
  Eigen::Matrix<T, 4, 4> jacobian;
  CrankEquations(forms, *x, &value, &jacobian);
  // v: the Jacobian's null vector, scaled so that c . v = 1.
  const Eigen::Matrix<T, 4, 1> c(T(0.4127), T(-0.2291), T(0.6833), T(0.5519));
  Eigen::JacobiSVD<Eigen::Matrix<T, 4, 4>> svd(jacobian, Eigen::ComputeFullV);
  Eigen::Matrix<T, 4, 1> v = svd.matrixV().col(3);
  const T scale = c.dot(v.conjugate());
  if (std::abs(scale) < 1e-3) return PolishCrank(forms, iterations, x);
  v /= scale;
  for (int iteration = 0; iteration < 2 * iterations; ++iteration) {
    CrankEquations(forms, *x, &value, &jacobian);
    Eigen::Matrix<T, 9, 1> residual;
    Eigen::Matrix<T, 9, 8> derivative = Eigen::Matrix<T, 9, 8>::Zero();
    residual.template head<4>() = value;
    residual.template segment<4>(4) = jacobian * v;
    residual(8) = c.dot(v.conjugate()) - T(1.0);
    derivative.template topLeftCorner<4, 4>() = jacobian;
    for (int j = 0; j < 4; ++j) {
      const Eigen::Matrix<T, 2, 2> block = forms[j].topLeftCorner<2, 2>().cast<T>();
      derivative.template block<1, 2>(4 + j, 0) = (block * v.template tail<2>()).transpose();
      derivative.template block<1, 2>(4 + j, 2) =
          (block.transpose() * v.template head<2>()).transpose();
    }
    derivative.template block<4, 4>(4, 4) = jacobian;
    derivative.template block<1, 4>(8, 4) = c.transpose();
    const Eigen::Matrix<T, 8, 1> step = derivative.colPivHouseholderQr().solve(residual);
    if (!step.allFinite()) break;
    *x -= step.template head<4>();
    v -= step.template tail<4>();
    if (step.norm() <= 1e-15 * std::max(1.0, x->norm())) break;
  }
  CrankEquations<T>(forms, *x, &value, nullptr);
  return value.cwiseAbs().maxCoeff();
}

// Whether two dyads are the same within `tolerance` (scaled frame): type, pivots, radius, line.
bool SameDyad(const PlanarDyad& a, const PlanarDyad& b, double tolerance) {
  if (a.type != b.type) return false;
  const double size = std::max({1.0, a.fixed_pivot.norm(), a.moving_pivot.norm(), a.radius});
  const auto near = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return (p - q).norm() <= tolerance * size;
  };
  switch (a.type) {
    case DyadType::kRR:
      return near(a.fixed_pivot, b.fixed_pivot) && near(a.moving_pivot, b.moving_pivot);
    case DyadType::kPR:
      return near(a.moving_pivot, b.moving_pivot) && near(a.LineFoot(), b.LineFoot()) &&
             std::abs(a.line_direction.x() * b.line_direction.y() -
                      a.line_direction.y() * b.line_direction.x()) <= tolerance;
    case DyadType::kRP:
      return near(a.fixed_pivot, b.fixed_pivot) && near(a.LineFoot(), b.LineFoot()) &&
             std::abs(a.line_direction.x() * b.line_direction.y() -
                      a.line_direction.y() * b.line_direction.x()) <= tolerance;
  }
  return false;
}

}  // namespace

int SolveTimedCranks(const std::vector<Eigen::Vector2d>& points,
                     const std::vector<double>& input_angles, const TimedPathOptions& options,
                     std::vector<TimedCrank>* cranks, TimedPathSummary* summary) {
  cranks->clear();
  TimedPathSummary local;
  TimedPathSummary& report = summary != nullptr ? *summary : local;
  report = TimedPathSummary();
  if (points.size() != 5 || input_angles.size() != 5) return 0;
  const ScaledPoints scaled = Scale(points, input_angles);
  if (!(scaled.length > 0.0) || !std::isfinite(scaled.length)) return 0;

  std::vector<Matrix3> forms;
  for (int j = 1; j < 5; ++j) forms.push_back(CrankForm(scaled, j));

  // Macaulay matrix of bidegree (1, 2): form j times u_k, columns b_i u_l u_k.
  Eigen::Matrix<double, 12, 18> macaulay = Eigen::Matrix<double, 12, 18>::Zero();
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) {
        for (int l = 0; l < 3; ++l) macaulay(3 * j + k, 6 * i + Monomial(l, k)) += forms[j](i, l);
      }
    }
  }
  // The null space by QR of the transpose: the last 6 columns of Q. |R_ii| stands in for the
  // singular values in the rank test.
  const Eigen::HouseholderQR<Eigen::Matrix<double, 18, 12>> qr(macaulay.transpose());
  const Eigen::Matrix<double, 12, 1> diagonal = qr.matrixQR().diagonal().cwiseAbs();
  report.condition = diagonal.minCoeff() > 0.0 ? diagonal.maxCoeff() / diagonal.minCoeff() : 0.0;
  if (!(diagonal.minCoeff() > options.rank_tolerance * diagonal.maxCoeff())) {
    report.degenerate = true;
    report.notes.push_back(
        "the crank equations are dependent (points or input angles in a special position): "
        "a family of cranks, not four");
    return -1;
  }
  // The null space: every root b (x) sym2(u) lies in it (6 roots, two at the circular points).
  Eigen::Matrix<double, 18, 6> null_space = Eigen::Matrix<double, 18, 6>::Zero();
  null_space.bottomRows<6>().setIdentity();
  null_space.applyOnTheLeft(qr.householderQ());
  // Eigenvalues lambda = l(b) / h(b) of two fixed generic linear forms in b: with
  // N_i the rows of b_i, N_l = N_h T^-1 diag(lambda) T.
  const Eigen::Vector3d h(0.5371, -0.3124, 0.7829), ell(0.2467, 0.8813, -0.4032);
  Eigen::Matrix<double, 6, 6> n_h = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> n_ell = Eigen::Matrix<double, 6, 6>::Zero();
  for (int i = 0; i < 3; ++i) {
    n_h += h(i) * null_space.middleRows<6>(6 * i);
    n_ell += ell(i) * null_space.middleRows<6>(6 * i);
  }
  const Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> lu(n_h);
  const Eigen::EigenSolver<Eigen::Matrix<double, 6, 6>> eigen(lu.solve(n_ell));
  if (eigen.info() != Eigen::Success) return 0;

  std::vector<Vector4c> roots;  // (B, u) in the scaled frame
  for (int r = 0; r < 6; ++r) {
    const Eigen::Matrix<Complex, 6, 1> x = eigen.eigenvectors().col(r);
    const Eigen::Matrix<Complex, 6, 1> w = n_h.cast<Complex>() * x;  // h(b) sym2(u)
    Vector3c b;
    for (int i = 0; i < 3; ++i) {
      b(i) = w.dot(null_space.middleRows<6>(6 * i).cast<Complex>() * x);  // conj(w) . (b_i w)
    }
    Eigen::Matrix3cd sym;
    for (int l = 0; l < 3; ++l) {
      for (int k = 0; k < 3; ++k) sym(l, k) = w(Monomial(l, k));
    }
    int column = 0;
    for (int k = 1; k < 3; ++k) {
      if (std::abs(sym(k, k)) > std::abs(sym(column, column))) column = k;
    }
    const Vector3c u = sym.col(column);
    // The circular points (and any root with B or A at infinity) are no crank.
    if (std::abs(b(2)) <= options.infinity_tolerance * b.norm() ||
        std::abs(u(2)) <= options.infinity_tolerance * u.norm()) {
      continue;
    }
    Vector4c root;
    root << b.head<2>() / b(2), u.head<2>() / u(2);
    PolishCrank<Complex>(forms, kClusterIterations, &root);
    if (root.allFinite()) roots.push_back(root);
  }
  // A double root (data made by a crank with an RP output dyad have one) converges only to
  // about sqrt(epsilon) under Newton's method: pairs closer than kDoubleRoot, and conjugate
  // pairs within kConjugateDoubleRoot of the real axis, are merged and polished on the deflated
  // system.
  std::vector<int> multiplicity(roots.size(), 1);
  for (size_t r = 0; r < roots.size(); ++r) {
    for (size_t s = r + 1; s < roots.size() && multiplicity[r] > 0; ++s) {
      const double size = std::max(1.0, roots[r].norm());
      if (multiplicity[s] == 0) continue;
      const bool conjugate = (roots[r] - roots[s].conjugate()).norm() <= kDoubleRoot * size &&
                             roots[r].imag().norm() <= kConjugateDoubleRoot * size;
      if (!conjugate && (roots[r] - roots[s]).norm() > kDoubleRoot * size) continue;
      roots[r] = 0.5 * (roots[r] + roots[s]);
      multiplicity[r] += multiplicity[s];
      multiplicity[s] = 0;
    }
  }
  int total = 0;
  for (size_t r = 0; r < roots.size(); ++r) {
    if (multiplicity[r] == 0) continue;
    total += multiplicity[r];
    Vector4c root = roots[r];
    const bool is_double = multiplicity[r] > 1;
    TimedCrank crank;
    crank.multiplicity = multiplicity[r];
    const double size = std::max(1.0, root.norm());
    // A near-real root is polished in real arithmetic and accepted if that converges; the
    // others (and near-real ones that do not converge) are polished as complex roots.
    double residual = 0.0;
    if (root.imag().norm() <= options.real_tolerance * size) {
      Vector4d real_root = root.real();
      residual = is_double ? PolishDoubleCrank<double>(forms, options.newton_iterations, &real_root)
                           : PolishCrank<double>(forms, options.newton_iterations, &real_root);
      if (real_root.allFinite() && residual <= 1e-9 * size) {
        root = real_root.cast<Complex>();
        crank.real = true;
      }
    }
    if (!crank.real) {
      // A complex crank makes no four-bar: a little polish to report it is enough.
      residual = is_double ? PolishDoubleCrank<Complex>(forms, kComplexIterations, &root)
                           : PolishCrank<Complex>(forms, kComplexIterations, &root);
    }
    if (!root.allFinite()) continue;
    // Back to the task's frame.
    crank.fixed_pivot = root.head<2>() * scaled.length + scaled.centroid.cast<Complex>();
    crank.crank = root.tail<2>() * scaled.length;
    crank.residual = residual;
    cranks->push_back(crank);
  }
  report.crank_roots_total = total;
  report.crank_roots_real = 0;
  for (const TimedCrank& crank : *cranks) {
    if (crank.real) report.crank_roots_real += crank.multiplicity;
  }
  report.four_bars_total = 3 * report.crank_roots_total;
  return report.crank_roots_total;
}

DataPrecision CouplerPosePrecision(const DataPrecision& points, double crank, double link) {
  DataPrecision poses = points;
  poses.length = points.length + 2.0 * points.angle * crank;
  poses.angle = (points.length + poses.length) / link;
  return poses;
}

int SolveTimedPath(const std::vector<Eigen::Vector2d>& points,
                   const std::vector<double>& input_angles, const TimedPathOptions& options,
                   std::vector<PathFourBar>* four_bars, TimedPathSummary* summary,
                   std::vector<PathFourBarAnalysis>* analyses) {
  four_bars->clear();
  if (analyses != nullptr) analyses->clear();
  std::vector<TimedCrank> cranks;
  if (SolveTimedCranks(points, input_angles, options, &cranks, summary) <= 0) return 0;
  return TimedPathFourBars(points, input_angles, cranks, options, four_bars, summary, analyses);
}

int TimedPathFourBars(const std::vector<Eigen::Vector2d>& points,
                      const std::vector<double>& input_angles,
                      const std::vector<TimedCrank>& cranks, const TimedPathOptions& options,
                      std::vector<PathFourBar>* four_bars, TimedPathSummary* summary,
                      std::vector<PathFourBarAnalysis>* analyses) {
  four_bars->clear();
  if (analyses != nullptr) analyses->clear();
  TimedPathSummary local;
  TimedPathSummary& report = summary != nullptr ? *summary : local;
  const ScaledPoints scaled = Scale(points, input_angles);
  Similarity2 unscale;  // scaled frame -> task frame (Sigma and E alike)
  unscale.scale = scaled.length;
  unscale.translation = scaled.centroid;

  // Data coarser than rounding: the output dyads are typed at their precision.
  const bool coarse = RelativePrecision(options.precision, scaled.length) > 1e-12;
  std::vector<Eigen::Matrix2d> rotations;  // the crank's rotations R(beta_j)
  for (double beta : scaled.betas) rotations.push_back(Rotation2(beta));
  std::vector<Eigen::Vector4d> near_real_seen;  // real parts of the complex roots taken
  for (const TimedCrank& root : cranks) {
    // Data coarser than rounding: a complex root whose imaginary part is small (rounding can
    // turn two real cranks into a complex pair) is tried by its real part, and its four-bars
    // are handed on for a joint fit to the points (TimedPathSummary::to_fit).
    bool near_real = false;
    if (!root.real) {
      const double size =
          std::max((root.fixed_pivot.real() - scaled.centroid).norm(), root.crank.real().norm());
      const double imaginary =
          std::max(root.fixed_pivot.imag().norm(), root.crank.imag().norm()) / scaled.length;
      if (!coarse || !(imaginary <= kNearRealShare * std::max(1.0, size / scaled.length))) {
        continue;
      }
      Eigen::Vector4d key;
      key << root.fixed_pivot.real(), root.crank.real();
      if (std::any_of(near_real_seen.begin(), near_real_seen.end(),
                      [&](const Eigen::Vector4d& seen) {
                        return (seen - key).norm() <= 1e-9 * scaled.length;
                      })) {
        continue;  // the conjugate of a root taken
      }
      near_real_seen.push_back(key);
      near_real = true;
    }
    const Eigen::Vector2d pivot = (root.fixed_pivot.real() - scaled.centroid) / scaled.length;
    const Eigen::Vector2d crank = root.crank.real() / scaled.length;
    const Eigen::Vector2d pin = pivot + crank;  // A_0, in Sigma and in E
    const Eigen::Vector2d link = scaled.points[0] - pin;
    if (!(crank.norm() > 1e-9) || !(link.norm() > 1e-9)) {
      report.notes.push_back(crank.norm() > 1e-9
                                 ? "a crank whose pin is the coupler point: the coupler's "
                                   "rotation is free (skipped)"
                                 : "a crank of zero length (skipped)");
      continue;
    }
    // The coupler poses (seed 002 eqs 4-8): the pin goes to A_j = B + R(beta_j) u, and the
    // coupler turns by the angle of the line A_j R_j; E = Sigma at the first point.
    std::vector<PlanarPose> poses;
    for (size_t j = 0; j < 5; ++j) {
      const Eigen::Vector2d pin_j = pivot + rotations[j] * crank;
      const Eigen::Vector2d link_j = scaled.points[j] - pin_j;
      PlanarPose pose;
      pose.theta = std::atan2(link_j.y(), link_j.x()) - std::atan2(link.y(), link.x());
      pose.origin_in_fixed = pin_j - Rotation2(pose.theta) * pin;
      poses.push_back(pose);
    }
    // The coupler poses' precision (TimedPathOptions::precision), in the scaled frame. The
    // family tests at precision (dependent rows, conics sharing a component) are left to the
    // crank equations: these five poses are exact for this crank, so a family of output dyads
    // is one at rounding level only.
    PlanarBurmesterOptions burmester_options = options.burmester;
    // A four-bar that passes the points within what their precision allows passes them: the
    // exact solution of rounded data is itself only computed to the condition of the crank
    // equations, and a miss far below the data's precision says nothing.
    double passes = options.verify_tolerance;
    if (coarse) {
      DataPrecision scaled_points = options.precision;
      scaled_points.length /= scaled.length;
      passes = std::max(passes, PointUncertainty(scaled_points, crank.norm(), 1.0, 2));
      burmester_options.precision = CouplerPosePrecision(scaled_points, crank.norm(), link.norm());
      burmester_options.family_units = 0.0;
      burmester_options.conic_family_units = 0.0;
    }
    std::vector<PlanarDyad> dyads;
    std::vector<PlanarDyad> circles;  // the dyads at rounding level, when needed
    PlanarBurmesterSummary burmester;
    SolvePlanarBurmester(poses, burmester_options, &dyads, &burmester);
    if (burmester.degenerate) {
      report.notes.push_back(
          "a crank whose coupler poses admit a family of output dyads (skipped)");
      continue;
    }
    // One root of the coupler's Burmester problem is the crank itself.
    const PlanarDyad input = PlanarDyad::RR(pivot, pin, crank.norm());
    int self = -1;
    double nearest = 1e-6;
    for (size_t d = 0; d < dyads.size(); ++d) {
      if (dyads[d].type != DyadType::kRR) continue;
      const double distance =
          std::max({(dyads[d].fixed_pivot - pivot).norm(), (dyads[d].moving_pivot - pin).norm()});
      if (distance < nearest) {
        nearest = distance;
        self = static_cast<int>(d);
      }
    }
    if (self < 0) report.notes.push_back("the crank is not among its coupler's Burmester dyads");
    for (size_t d = 0; d < dyads.size(); ++d) {
      if (static_cast<int>(d) == self) continue;
      // A double root of the coupler's Burmester problem can come back twice.
      bool repeated = false;
      for (size_t e = 0; e < d; ++e) {
        repeated =
            repeated || (static_cast<int>(e) != self && SameDyad(dyads[d], dyads[e], kSameDyad));
      }
      if (repeated) continue;
      PathFourBar four_bar;
      four_bar.input = TransformDyad(input, unscale, unscale);
      four_bar.output = TransformDyad(dyads[d], unscale, unscale);
      four_bar.coupler_point = points[0];
      if (near_real) {
        report.to_fit.push_back(four_bar);
        continue;
      }
      // Assembled and driven through the points (lib/path_motion.h).
      auto analysis_start = std::chrono::steady_clock::now();
      PathFourBarAnalysis analysis =
          AnalyzePathFourBar(four_bar, points, input_angles, scaled.length);
      report.analysis_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - analysis_start).count();
      // A circle typed as its slider at the data's precision misses by what that allows.
      double allowed = passes;
      if (coarse && dyads[d].type != DyadType::kRR) {
        const Eigen::Vector2d output_pin =
            dyads[d].type == DyadType::kPR ? dyads[d].moving_pivot : dyads[d].fixed_pivot;
        const double uncertainty =
            PointUncertainty(burmester_options.precision, output_pin.norm(), 1.0, 2);
        const double lever = std::max(1.0, link.norm() / (output_pin - pin).norm());
        allowed = std::max(allowed, kModelUnits * uncertainty * lever);
      }
      if (coarse && dyads[d].type != DyadType::kRR &&
          !(analysis.nearest_max_error <= allowed * scaled.length)) {
        // The simplified four-bar misses: the slider reading moved the output more than the
        // points allow for this four-bar (the coupler point is sensitive to it). The exact
        // circle stays (the task solver may still fit a slider-crank in least squares).
        const PathFourBar reading = four_bar;
        if (circles.empty()) {
          PlanarBurmesterOptions exact_options = options.burmester;
          exact_options.family_units = 0.0;
          SolvePlanarBurmester(poses, exact_options, &circles);
        }
        const Eigen::Vector2d here =
            dyads[d].type == DyadType::kPR ? dyads[d].moving_pivot : dyads[d].fixed_pivot;
        double nearest_circle = kInfinity;
        for (const PlanarDyad& circle : circles) {
          if (circle.type != DyadType::kRR) continue;
          const double distance = dyads[d].type == DyadType::kPR
                                      ? (circle.moving_pivot - here).norm()
                                      : (circle.fixed_pivot - here).norm();
          if (distance < nearest_circle && !SameDyad(circle, input, kSameDyad)) {
            nearest_circle = distance;
            four_bar.output = TransformDyad(circle, unscale, unscale);
          }
        }
        if (std::isfinite(nearest_circle)) {
          analysis_start = std::chrono::steady_clock::now();
          analysis = AnalyzePathFourBar(four_bar, points, input_angles, scaled.length);
          report.analysis_seconds +=
              std::chrono::duration<double>(std::chrono::steady_clock::now() - analysis_start)
                  .count();
          allowed = passes;
        }
        if (!(analysis.nearest_max_error <= allowed * scaled.length)) {
          // The circle misses too (far, and sensitive to rounding): the slider reading is
          // handed on for a joint fit of crank and slider to the points.
          report.to_fit.push_back(reading);
        }
      }
      if (!(analysis.nearest_max_error <= allowed * scaled.length)) {
        ++report.four_bars_dropped;
        continue;
      }
      four_bars->push_back(four_bar);
      if (analyses != nullptr) analyses->push_back(std::move(analysis));
    }
  }
  if (report.four_bars_dropped > 0) {
    report.notes.push_back(std::to_string(report.four_bars_dropped) +
                           " four-bar(s) dropped: assembled at the input angles they miss a "
                           "point (ill-conditioned, pivots far outside the task)");
  }
  report.four_bars_real = static_cast<int>(four_bars->size());
  return report.four_bars_real;
}

}  // namespace linkfit
