#include "fitting/planar_burmester.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "fitting/model_choice.h"
#include "fitting/planar_constraint_space.h"
#include "fitting/polynomial.h"
#include "lib/kinematic_mapping.h"

namespace linkfit {
namespace {

using internal::ChooseReading;
using internal::ConicFill;
using internal::DyadReading;
using internal::MakeFrames;
using internal::MaxResidual;
using internal::Normalize;
using internal::NormalizedMotion;
using internal::PolishDyad;
using internal::PolishRealRoot;
using internal::PoseFrame;
using internal::ReadingsOf;
using internal::RestrictedConics;

using Complex = std::complex<double>;
using Vector3c = Eigen::Matrix<Complex, 3, 1>;
using Matrix3c = Eigen::Matrix<Complex, 3, 3>;
using NullBasis = Eigen::Matrix<double, 8, 3>;

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
// `family_tolerance`: pencil determinant coefficients all below it mean the conics share a
// component (a curve of dyads).
int IntersectConics(const NullBasis& basis, Eigen::Matrix3d m1, Eigen::Matrix3d m2,
                    std::vector<ComplexConstraintVector>* roots, double family_tolerance = 1e-11) {
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
  if (std::max({std::abs(c0), std::abs(c1), std::abs(c2), std::abs(c3)}) <= family_tolerance) {
    return -1;
  }
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

struct CoreResult {
  std::vector<DyadReading> roots;  // real roots, read, without duplicates
  int roots_total = 0;
  int roots_real = 0;
  int real_within_precision = 0;  // complex roots whose real part fits within precision
  double condition = 0.0;
  double fit_residual = 0.0;
  bool degenerate = false;
};

// Normalized poses (L = 1): circles beyond this radius are always tested for their slider.
constexpr double kFarRadius = 100.0;
// A circle's slider reading may be polished by at most this fraction of the circle's size (PR:
// its radius; RP: its moving pivot's distance): the slider of a circle that rounding bent from
// a line differs from it by a small part of that size, while a polish that moves farther is
// running to another dyad. Measured on five poses printed to 4 digits: the polish moves 95 % of
// the circles that rounding bent from a generating slider by less than 1.2 % of that size (99 %
// by less than 4.4 %), and the circles of generating four-bars whose polished slider fits by a
// median 13 % (5 % by less than 1.3 %).
constexpr double kPolishReach = 0.025;

// The simpler reading of a circle at the data's precision (fitting/model_choice.h): the PR or
// RP slider fitted by least squares to the pivot's positions, when it fits the poses within
// kModelUnits of the data's uncertainty. For data coarser than rounding, a circle that rounding
// may have bent from a line (its curvature within the data's precision: the radius's error
// bound, DyadErrorBounds, at least the radius) has its slider polished on the five poses to the
// slider that fits them best, which its error bound describes; the polish may move the kept
// pivot (PR: moving, RP: fixed) by at most kPolishReach of the circle's size, written to
// *moved (0 for an unpolished reading: two roots whose sliders coincide keep the slider for the
// one it moved least, SolveNormalized).
bool SliderAtPrecision(const PlanarDyad& circle, const std::vector<PlanarPose>& poses,
                       const std::vector<PoseFrame>& frames, const DataPrecision& precision,
                       int iterations, DyadReading* slider, double* moved) {
  // A cheap test first: the pivot's positions lie on the circle (PR: the moving pivot's in
  // Sigma; RP: the fixed pivot's in E, on a circle of the same radius about the moving pivot),
  // and an arc of chord c bows off its best line by about c^2 / (16 r). A slider that fits
  // within kModelUnits of the data's uncertainty needs that bow within a few times as much.
  const auto bowed = [&](bool pr) {
    double chord = 0.0, distance = pr ? circle.moving_pivot.norm() : 0.0;
    Eigen::Vector2d first = Eigen::Vector2d::Zero();
    for (size_t j = 0; j < frames.size(); ++j) {
      const Eigen::Vector2d point =
          pr ? Eigen::Vector2d(frames[j].rotation * circle.moving_pivot + frames[j].origin)
             : Eigen::Vector2d(frames[j].rotation.transpose() *
                               (circle.fixed_pivot - frames[j].origin));
      if (j == 0) first = point;
      chord = std::max(chord, (point - first).norm());
      if (!pr) distance = std::max(distance, (circle.fixed_pivot - frames[j].origin).norm());
    }
    // (A root that rounding bent from a line can be bowed more, by its own conditioning,
    // but then its radius is huge: those are always tried.)
    const double bow = chord * chord / (16.0 * circle.radius);
    return circle.radius < kFarRadius &&
           bow > 64.0 * kModelUnits * PointUncertainty(precision, distance, 1.0, 2);
  };
  double best = kModelUnits;
  bool found = false;
  // Polished only for data coarser than rounding: at full precision a slider root is read as
  // a slider already (ChooseReading), and a circle is a circle.
  const bool polish = poses.size() == 5 && RelativePrecision(precision, 1.0) > 1e-12;
  double radius_bound = -1.0;  // the circle's, computed when first needed
  for (const bool pr : {true, false}) {
    if (bowed(pr)) continue;
    PlanarDyad candidate = pr ? FitSliderPR(circle, poses) : FitSliderRP(circle, poses);
    if (!candidate.AllFinite()) continue;
    double ratio = PrecisionRatio(candidate, poses, precision, 1.0);
    double candidate_moved = 0.0;
    if (polish && radius_bound < 0.0) {
      radius_bound = DyadErrorBounds(circle, poses, precision, 1.0).radius;
    }
    if (polish && !(circle.radius > radius_bound)) {
      const PlanarDyad polished = FitDyadLeastSquares(candidate, poses, iterations);
      const double move = pr ? (polished.moving_pivot - candidate.moving_pivot).norm()
                             : (polished.fixed_pivot - candidate.fixed_pivot).norm();
      const double reach = kPolishReach * (pr ? circle.radius : circle.moving_pivot.norm());
      const double polished_ratio = PrecisionRatio(polished, poses, precision, 1.0);
      if (move <= reach && (polished_ratio <= best || polished_ratio < ratio)) {
        candidate = polished;
        ratio = polished_ratio;
        candidate_moved = move;
      }
    }
    if (ratio <= best) {
      best = ratio;
      slider->dyad = candidate;
      slider->max_residual = MaxResidual(candidate, frames);
      *moved = candidate_moved;
      found = true;
    }
  }
  return found;
}

// The constraint-space solve on normalized poses; `precision` is the data's, normalized.
void SolveNormalized(const std::vector<PlanarPose>& poses, const PlanarBurmesterOptions& options,
                     const DataPrecision& precision, CoreResult* result) {
  const int n = static_cast<int>(poses.size());
  // Rows dependent within the data's precision are a family (one orientation, ...).
  const double rank_tolerance = std::max(
      options.rank_tolerance, precision.length > 0.0 || precision.angle > 0.0
                                  ? options.family_units * RelativePrecision(precision, 1.0)
                                  : 0.0);
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
    result->degenerate = !(r_last > rank_tolerance * r_first);
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
    result->degenerate = !(sigma[4] > rank_tolerance * sigma[0]);
    double sum = 0.0;
    for (int i = 5; i < sigma.size(); ++i) sum += sigma[i] * sigma[i];
    result->fit_residual = std::sqrt(sum / n);
  }
  if (result->degenerate) return;

  std::vector<ComplexConstraintVector> complex_roots;
  Eigen::Matrix3d m1, m2;
  RestrictedConics(basis, ConicFill::kEvaluateAll, &m1, &m2);
  // The conics' entries move by about condition * relative precision under the data's
  // rounding: a shared component within that is a family at this precision (the Cardan motion
  // printed to a few digits).
  // Only where the condition bound already lets the dyads move by a tenth of their size:
  // a nearly shared component of a well-conditioned task is its own business.
  const double perturbation = result->condition * RelativePrecision(precision, 1.0);
  const double family_tolerance =
      std::max(1e-11, (precision.length > 0.0 || precision.angle > 0.0) && perturbation >= 1e-2
                          ? options.conic_family_units * perturbation
                          : 0.0);
  result->roots_total = IntersectConics(basis, m1, m2, &complex_roots, family_tolerance);
  if (result->roots_total < 0) {
    // The two conics share a component: a curve of dyads (e.g. the Cardan motion of an
    // elliptic trammel, where every point of a circle of E moves on a line).
    result->roots_total = 0;
    result->degenerate = true;
    return;
  }

  const std::vector<PoseFrame> frames = MakeFrames(poses);
  // Data coarser than rounding: complex roots may be real within their precision.
  const bool coarse = RelativePrecision(precision, 1.0) > 1e-12;
  // Each root's reading at the data's precision, before duplicates are resolved (the conics
  // meet in at most four points).
  struct RootReading {
    Eigen::Vector3d real_part;  // the root's, normalized (a complex-conjugate pair shares it)
    bool real = true;
    DyadReading reading;
    DyadReading circle;  // a slider read from a circle: the circle
    double moved = 0.0;  // how far the slider's polish moved the circle's pivot (0: unpolished)
  };
  constexpr int kMaxRoots = 4;
  std::array<RootReading, kMaxRoots> found;
  int found_count = 0;
  // The real parts of complex roots whose readings did not fit within precision: a conjugate
  // pair's second member reads the same.
  std::vector<Eigen::Vector3d> rejected;
  const auto same_part = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - b).norm() < 1e-9;
  };
  for (const ComplexConstraintVector& z : complex_roots) {
    if (found_count == kMaxRoots) break;
    // Back to P^2 coordinates (the basis is orthonormal), phase removed.
    Vector3c a = basis.transpose().cast<Complex>() * z;
    int k = 0;
    a.cwiseAbs().maxCoeff(&k);
    a /= a[k];
    const double imaginary = a.imag().norm() / a.real().norm();
    Eigen::Vector3d a_real = a.real();
    const double residual = imaginary <= options.real_tolerance
                                ? PolishRealRoot(m1, m2, options.newton_iterations, &a_real)
                                : std::numeric_limits<double>::infinity();
    const bool real = residual <= 1e-9;
    // A complex root is kept only when its real part, read and polished as a dyad, fits the
    // poses within the data's precision (rounding can turn two nearby real dyads into a
    // complex pair): at that precision it is real.
    if (!real && !coarse) continue;
    if (real) ++result->roots_real;
    // A root whose real part an earlier root shares (a complex-conjugate pair near a real
    // double root) is that root, read once; a pair kept counts twice as real within precision.
    const Eigen::Vector3d real_part = a.real().normalized();
    const auto earlier =
        std::find_if(found.begin(), found.begin() + found_count,
                     [&](const RootReading& root) { return same_part(root.real_part, real_part); });
    if (earlier != found.begin() + found_count) {
      if (!real && !earlier->real) ++result->real_within_precision;
      continue;
    }
    if (!real && std::any_of(rejected.begin(), rejected.end(), [&](const Eigen::Vector3d& part) {
          return same_part(part, real_part);
        })) {
      continue;
    }
    const ConstraintVector z_real = basis * a_real.normalized();
    DyadReading readings[3];
    const int count = ReadingsOf(z_real, frames, /*sliders=*/true, readings);
    if (count == 0) continue;
    int chosen = ChooseReading(readings, count, options.slider_tolerance);
    if (n == 5) {
      // Polish the chosen reading on its geometric equations. Near a double root (a slider
      // next to a huge-radius circle) the unpolished residuals can mislead the typing: then
      // polish every reading and type again on the polished ones.
      DyadReading& first = readings[chosen];
      first.dyad = PolishDyad<5>(first.dyad, frames, options.newton_iterations);
      first.max_residual = MaxResidual(first.dyad, frames);
      if (first.max_residual > options.slider_tolerance) {
        for (int i = 0; i < count; ++i) {
          if (i == chosen) continue;
          readings[i].dyad = PolishDyad<5>(readings[i].dyad, frames, options.newton_iterations);
          readings[i].max_residual = MaxResidual(readings[i].dyad, frames);
        }
        chosen = ChooseReading(readings, count, options.slider_tolerance);
      }
    }
    if (!real) {
      // The nearest real circle first (the pair came from two circles, or from a circle and a
      // slider), else the chosen reading; kept when it fits within the data's precision.
      for (int i = 0; i < count; ++i) {
        if (readings[i].dyad.type != DyadType::kRR) continue;
        const PlanarDyad circle = FitDyadLeastSquares(readings[i].dyad, poses, 50);
        if (PrecisionRatio(circle, poses, precision, 1.0) <= kModelUnits) {
          readings[i].dyad = circle;
          readings[i].max_residual = MaxResidual(circle, frames);
          chosen = i;
        }
      }
      if (!(PrecisionRatio(readings[chosen].dyad, poses, precision, 1.0) <= kModelUnits)) {
        rejected.push_back(real_part);
        continue;
      }
      ++result->real_within_precision;
    }
    RootReading& root = found[found_count];
    root.real_part = real_part;
    root.real = real;
    root.reading = readings[chosen];
    // A circle that the data cannot tell from a slider is the slider.
    if (readings[chosen].dyad.type == DyadType::kRR) {
      DyadReading slider;
      if (SliderAtPrecision(readings[chosen].dyad, poses, frames, precision, 50, &slider,
                            &root.moved)) {
        root.circle = readings[chosen];
        root.reading = slider;
      }
    }
    ++found_count;
  }
  // Roots whose readings coincide. A slider polished from a circle onto another root's reading
  // ran to that root: the root whose pivot the polish moved least (an unpolished reading: not at
  // all) keeps the slider, the others stay circles.
  const auto same = [](const DyadReading& a, const DyadReading& b) {
    return a.dyad.type == b.dyad.type &&
           (a.dyad.moving_pivot - b.dyad.moving_pivot).norm() < 1e-7 &&
           (a.dyad.fixed_pivot - b.dyad.fixed_pivot).norm() < 1e-7 &&
           (a.dyad.line_point - b.dyad.line_point).norm() < 1e-7;
  };
  std::array<int, kMaxRoots> order;  // by the polish's move, stable
  std::iota(order.begin(), order.begin() + found_count, 0);
  std::stable_sort(order.begin(), order.begin() + found_count,
                   [&](int i, int j) { return found[i].moved < found[j].moved; });
  std::array<const DyadReading*, kMaxRoots> kept = {};
  const auto taken = [&](const DyadReading& reading) {
    return std::any_of(kept.begin(), kept.begin() + found_count, [&](const DyadReading* other) {
      return other != nullptr && same(*other, reading);
    });
  };
  for (int rank = 0; rank < found_count; ++rank) {
    const RootReading& root = found[order[rank]];
    if (!taken(root.reading)) {
      kept[order[rank]] = &root.reading;
    } else if (root.moved > 0.0 && !taken(root.circle)) {
      kept[order[rank]] = &root.circle;
    }
  }
  for (int i = 0; i < found_count; ++i) {
    if (kept[i] != nullptr) result->roots.push_back(*kept[i]);
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
  RestrictedConics(basis, ConicFill::kEvaluateAll, &m1, &m2);
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
  DataPrecision normalized_precision = options.precision;
  normalized_precision.length /= direct.length;
  CoreResult core;
  SolveNormalized(direct.poses, options, normalized_precision, &core);
  local_summary.roots_total = core.roots_total;
  local_summary.roots_real = core.roots_real;
  local_summary.real_within_precision = core.real_within_precision;
  local_summary.condition = core.condition;
  local_summary.fit_residual = core.fit_residual;
  local_summary.degenerate = core.degenerate;
  for (const DyadReading& root : core.roots) {
    dyads->push_back(TransformDyad(root.dyad, direct.to_original_fixed, direct.to_original_moving));
  }
  if (summary) *summary = local_summary;
  return static_cast<int>(dyads->size());
}

}  // namespace linkfit
