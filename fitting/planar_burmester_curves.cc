// Burmester curves of four poses and the dyad of a chosen pivot (planar_burmester_curves.h).
//
// What each part implements:
// - SampleBurmesterCurves: the dyads of four poses as the curve Q1 = Q2 = 0 in the projective
//   3-space of the null space of the four constraint rows (planar_burmester.h, after seed 001
//   eqs 6 and 9 and seed 000's constraint space). A pencil of planes through a line of the
//   slider plane z0 = K0 = 0 (so that one plane of the pencil holds exactly the PR and RP
//   dyads) is swept, each plane cut by IntersectConstraintConics; its real points seed a
//   predictor-corrector continuation along the curve (tangent orthogonal to w, A1 w, A2 w;
//   Newton's method on the two quadrics), which orders the samples into branches and keeps
//   consecutive dyads within a set distance however fast they move with the plane. Each
//   component is traced once: sweep points that a trace passes are not traced again.
// - DyadFromMovingPivot: the centre of the circle through (three poses) or best fitting
//   (more: algebraic fit, then Gauss-Newton on the geometric distance) the pivot's positions
//   R_j m + d_j; for four poses the pivot is first projected onto the circle-point curve, the
//   cubic det[|P_j|^2, P_j, 1] = 0 (the four positions concyclic), by Newton's method along
//   the gradient and then the foot-point iteration. Collinear positions make a PR dyad.
// - DyadFromFixedPivot: the same on the inverted motion (center-point curve), inverted back.
// - DefaultMovingPivots: a grid search for two well-conditioned moving pivots.
// The constraint-space pieces (pose frames, normalization, the restricted conics, the readings
// of z as RR/PR/RP dyads, the typing rule and the geometric polish of a dyad) are shared with
// planar_burmester.cc through planar_constraint_space.h.
#include "fitting/planar_burmester_curves.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>

#include "fitting/planar_burmester.h"
#include "fitting/planar_constraint_space.h"

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
using PlaneBasis = Eigen::Matrix<double, 8, 3>;
using NullBasis4 = Eigen::Matrix<double, 8, 4>;

// A root whose imaginary part is below this (relative to its largest component) is tried as
// a real root (it is accepted only if Newton's method then converges).
constexpr double kRealTolerance = 1e-5;
// Relative residual of the two restricted conics below which a polished root is real.
constexpr double kConicTolerance = 1e-10;
// A slider reading fitting the poses within this (normalized units) is taken (ChooseReading).
constexpr double kSliderTolerance = 1e-9;
// Largest residual (normalized units) of a sampled dyad; worse samples are dropped.
constexpr double kSampleResidual = 1e-10;
// Residual (normalized units) above which a sample is polished on its geometric equations.
constexpr double kPolishResidual = 1e-11;
// Pivots farther than this (normalized units) from the centroid: the sample is dropped.
constexpr double kFarPivot = 1e3;
// Two real points of one plane closer than this (projective distance) are one.
constexpr double kDuplicateDistance = 1e-7;
constexpr int kPolishIterations = 4;
// Curve tracing in the projective 3-space (unit null-space coordinates): the largest and the
// smallest step, the steps per component at most, the least cosine between consecutive
// tangents, and the distance within which a sweep point counts as reached by a trace.
constexpr double kMaxStep = 0.005;
constexpr double kMinStep = 1e-13;
constexpr int kMaxTraceSteps = 200000;
constexpr int kMaxTotalSteps = 400000;  // over all traces of one call (a guard, not a limit)
constexpr double kMinTangentCosine = 0.99;
constexpr double kCoverDistance = 0.01;
// Steps are at most this fraction of the Jacobian's smallest singular value (Separation), but
// need not be shorter than kMinSafeStep.
constexpr double kSeparationStep = 0.1;
constexpr double kMinSafeStep = 1e-7;
// Candidate lines tried for the pencil's axis (seeded, deterministic).
constexpr int kAxisCandidates = 64;
constexpr uint64_t kAxisSeed = 20240613;
// Positions of a pivot closer than this (relative to their spread or L) coincide; positions
// whose triangle is flatter than this (|cross| / longest side^2) are collinear.
constexpr double kCoincident = 1e-12;
constexpr double kCollinear = 1e-10;
// A fitted circle larger than this (relative to the spread of the points) is a line.
constexpr double kLineRadius = 1e9;
// A pivot this close (relative to L, first order) to the circle-point curve is on it.
constexpr double kOnCurve = 1e-11;
// A pivot moved by less than this (relative to L) onto the curve is reported as not moved.
constexpr double kMoveNoteThreshold = 1e-9;

// ---------------------------------------------------------------------------------------------
// Curve sampling.

// One real point of the curve, in the normalized frames. `point` is its projective point (unit
// null-space coordinates w, z = N w; the sign is carried continuously along a trace); `key`
// places its dyad for drawing and density: RR (F, m), PR (foot of the slider line in Sigma, m),
// RP (F, foot of the line in E).
struct Sample {
  PlanarDyad dyad;
  Eigen::Vector4d point = Eigen::Vector4d::Zero();
  Eigen::Vector4d key = Eigen::Vector4d::Zero();
  double radius = 0.0;     // RR: the dyad's radius (with `key`, what KeyDistance compares)
  bool kept = false;       // a dyad of the poses to the sample tolerance, pivots not far
  bool refinable = false;  // kept and RR
  bool inside = false;     // refinable with both pivots within refine_radius of the centroid
};

// How far apart two samples' dyads are, as DyadDistance measures it: the larger pivot
// displacement (RR: and the radius change).
double KeyDistance(const Sample& a, const Sample& b) {
  const Eigen::Vector4d d = a.key - b.key;
  return std::max({d.head<2>().norm(), d.tail<2>().norm(), std::abs(a.radius - b.radius)});
}

// Distance of two projective points (unit vectors up to sign): |a -+ b| for the nearer sign.
double ProjectiveDistance(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return std::sqrt(std::max(0.0, 2.0 - 2.0 * std::abs(a.dot(b))));
}

class CurveSampler {
 public:
  CurveSampler(const std::vector<PlanarPose>& poses, const BurmesterCurveOptions& options)
      : frames_(MakeFrames(poses)), options_(options) {}

  // Sets up the null space N of the four rows, the two quadrics restricted to it
  // (w^T A_i w = Q_i(N w)) and the pencil. False for a degenerate task.
  bool Init(const std::vector<PlanarPose>& poses) {
    Eigen::Matrix<double, 4, 8> rows;
    for (int j = 0; j < 4; ++j) rows.row(j) = ConstraintRow(poses[j]).transpose();
    const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 8, 4>> qr(rows.transpose());
    const double r_first = std::abs(qr.matrixR()(0, 0));
    const double r_last = std::abs(qr.matrixR()(3, 3));
    if (!(r_last > 1e-10 * r_first)) return false;
    const Eigen::Matrix<double, 8, 8> q = qr.householderQ();
    null_ = q.rightCols<4>();
    RestrictedConics(null_, ConicFill::kMirrorUpper, &a1_, &a2_);
    if (!(a1_.norm() > 0.0) || !(a2_.norm() > 0.0)) return false;
    a1_ /= a1_.norm();
    a2_ /= a2_.norm();
    // The slider hyperplane z0 = 0 of the 3-space: w orthogonal to c = row 0 of the basis.
    Eigen::Vector4d c = null_.row(0).transpose();
    if (!(c.norm() > 1e-12)) c = Eigen::Vector4d::UnitX();  // every dyad a slider: any pencil
    c.normalize();
    const Eigen::HouseholderQR<Eigen::Vector4d> house(c);
    const Eigen::Matrix4d h = house.householderQ();
    const Eigen::Matrix<double, 4, 3> w = h.rightCols<3>();  // orthonormal basis of c^perp
    // The curve meets the slider plane in 4 points (complex included); the axis of the pencil
    // is a line of that plane as far from them as possible, so that it misses the curve (any
    // point of the curve on a line of the slider plane is one of these four).
    std::vector<ComplexConstraintVector> roots;
    const PlaneBasis slider_plane = null_ * w;
    std::vector<Vector3c> points;
    if (IntersectConstraintConics(slider_plane, &roots) > 0) {
      for (const ComplexConstraintVector& z : roots) {
        Vector3c s = slider_plane.transpose().cast<Complex>() * z;
        const double norm = s.norm();
        if (norm > 0.0) points.push_back(s / norm);
      }
    }
    std::mt19937_64 rng(kAxisSeed);
    std::normal_distribution<double> gauss;
    Eigen::Vector3d best = Eigen::Vector3d::UnitZ();
    double best_score = -1.0;
    for (int candidate = 0; candidate < kAxisCandidates; ++candidate) {
      Eigen::Vector3d v(gauss(rng), gauss(rng), gauss(rng));
      v.normalize();
      double score = 1.0;  // min over the points of |v . s|: sine of their distance to the axis
      for (const Vector3c& s : points) {
        score = std::min(score, std::abs(v.cast<Complex>().dot(s)));
      }
      if (score > best_score) {
        best_score = score;
        best = v;
      }
    }
    // Axis spanned by u1, u2 (orthogonal to `best` within c^perp); planes through it contain
    // v(phi) = cos(phi) v1 + sin(phi) c with v1 = w * best: phi = 0 is the slider plane.
    const Eigen::HouseholderQR<Eigen::Vector3d> house3(best);
    const Eigen::Matrix3d h3 = house3.householderQ();
    axis4_.col(0) = w * h3.col(1);
    axis4_.col(1) = w * h3.col(2);
    v1_4_ = w * best;
    v2_4_ = c;
    axis_ = null_ * axis4_;
    v1_ = null_ * v1_4_;
    v2_ = null_ * v2_4_;
    return true;
  }

  // The real curve points in the plane of angle phi of the pencil (IntersectConstraintConics,
  // each root polished on the two conics and read as a dyad).
  std::vector<Sample> SamplePlane(double phi) const {
    std::vector<Sample> out;
    PlaneBasis basis;
    basis.leftCols<2>() = axis_;
    basis.col(2) = std::cos(phi) * v1_ + std::sin(phi) * v2_;
    std::vector<ComplexConstraintVector> roots;
    if (IntersectConstraintConics(basis, &roots) <= 0) return out;
    Eigen::Matrix3d m1, m2;
    RestrictedConics(basis, ConicFill::kMirrorUpper, &m1, &m2);
    for (const ComplexConstraintVector& z : roots) {
      Vector3c a = basis.transpose().cast<Complex>() * z;
      int k = 0;
      a.cwiseAbs().maxCoeff(&k);
      if (!(std::abs(a[k]) > 0.0)) continue;
      a /= a[k];
      if (!(a.imag().norm() <= kRealTolerance * a.real().norm())) continue;
      Eigen::Vector3d a_real = a.real();
      if (!(PolishRealRoot(m1, m2, kPolishIterations, &a_real) <= kConicTolerance)) continue;
      const Sample sample = ReadPoint((null_.transpose() * (basis * a_real)).normalized());
      bool duplicate = false;
      for (const Sample& previous : out) {
        duplicate =
            duplicate || ProjectiveDistance(previous.point, sample.point) < kDuplicateDistance;
      }
      if (!duplicate) out.push_back(sample);
    }
    return out;
  }

  // The pencil angle in [0, pi) of the plane through the axis and w.
  double PlaneAngle(const Eigen::Vector4d& w) const {
    double phi = std::atan2(v2_4_.dot(w), v1_4_.dot(w));
    if (phi < 0.0) phi += M_PI;
    if (phi >= M_PI) phi -= M_PI;
    return phi;
  }

  // Traces the component of the curve through `seed` by predictor-corrector continuation in
  // the projective 3-space: a step along the tangent (orthogonal to w, A1 w and A2 w), then
  // Newton's method on Q1 = Q2 = 0 orthogonally to the tangent. Steps are at most kMaxStep and,
  // where the dyads lie inside the refine radius, as long as keeps consecutive dyads within
  // the refine step. Returns true when the trace came back to the seed (a closed component);
  // `path` holds the samples from the seed on.
  bool Trace(const Sample& seed, int* budget, std::vector<Sample>* path) const {
    path->assign(1, seed);
    const Eigen::Vector4d start = seed.point;
    const Eigen::Vector4d start_tangent = Tangent(start);
    Eigen::Vector4d tangent = start_tangent;
    double step =
        std::min(0.25 * kMaxStep, std::max(kSeparationStep * Separation(start), kMinSafeStep));
    const double key_step = options_.refine_step;
    auto controlled = [](const Sample& a, const Sample& b) {
      return a.refinable && b.refinable && (a.inside || b.inside);
    };
    for (int n = 0; n < kMaxTraceSteps; ++n) {
      const Sample& current = path->back();
      Sample next;
      Eigen::Vector4d next_tangent;
      double taken = 0.0;
      while (true) {
        if (!(step >= kMinStep) || --*budget < 0) return false;
        const Eigen::Vector4d predicted = (current.point + step * tangent).normalized();
        Eigen::Vector4d w = predicted;
        bool ok = Correct(tangent, &w) && ProjectiveDistance(w, predicted) <= 0.1 * step;
        if (ok) {
          next_tangent = Tangent(w);
          if (next_tangent.dot(tangent) < 0.0) next_tangent = -next_tangent;
          ok = next_tangent.dot(tangent) >= kMinTangentCosine;
        }
        if (ok) {
          next = ReadPoint(w);
          ok = !controlled(current, next) || KeyDistance(current, next) <= key_step;
        }
        if (ok) {
          taken = step;
          break;
        }
        step *= 0.5;
      }
      // Back at the seed: it lies on the arc just taken, and the trace passes it in the
      // direction it left (another strand of the curve may pass close by).
      if (n >= 2 &&
          ProjectiveDistance(current.point, start) + ProjectiveDistance(start, next.point) <=
              1.1 * taken &&
          (current.point.dot(start) < 0.0 ? -1.0 : 1.0) * tangent.dot(start_tangent) >
              kMinTangentCosine) {
        return true;
      }
      if (controlled(current, next)) {
        const double jump = std::max(KeyDistance(current, next), 1e-300);
        step *= std::clamp(0.7 * key_step / jump, 0.5, 2.0);
      } else {
        step *= 2.0;
      }
      step = std::min(step, std::max(kSeparationStep * Separation(next.point), kMinSafeStep));
      step = std::min(step, kMaxStep);
      tangent = next_tangent;
      path->push_back(next);
    }
    return false;
  }

 private:
  // The smallest singular value of the Jacobian of (Q1, Q2) on the unit sphere at w: small
  // where two strands of the curve come close (near a node), which the step must not jump.
  double Separation(const Eigen::Vector4d& w) const {
    Eigen::Matrix<double, 2, 4> jacobian;
    jacobian.row(0) = 2.0 * (a1_ * w).transpose();
    jacobian.row(1) = 2.0 * (a2_ * w).transpose();
    const Eigen::Matrix2d gram = jacobian * jacobian.transpose();
    const double half_trace = 0.5 * gram.trace();
    const double root = std::sqrt(std::max(0.0, half_trace * half_trace - gram.determinant()));
    return std::sqrt(std::max(0.0, half_trace - root));
  }

  // The unit vector orthogonal to w, A1 w and A2 w (the curve's tangent at w): the
  // generalized cross product of the three, by cofactors.
  Eigen::Vector4d Tangent(const Eigen::Vector4d& w) const {
    Eigen::Matrix<double, 3, 4> rows;
    rows.row(0) = w.transpose();
    rows.row(1) = (a1_ * w).transpose();
    rows.row(2) = (a2_ * w).transpose();
    Eigen::Vector4d tangent;
    for (int i = 0; i < 4; ++i) {
      Eigen::Matrix3d minor;
      for (int c = 0, cc = 0; c < 4; ++c) {
        if (c != i) minor.col(cc++) = rows.col(c);
      }
      tangent[i] = (i % 2 ? -1.0 : 1.0) * minor.determinant();
    }
    return tangent.normalized();
  }

  // Newton's method on w^T A1 w = w^T A2 w = 0 with the step orthogonal to `tangent` and to
  // w (then renormalized). True when it converged.
  bool Correct(const Eigen::Vector4d& tangent, Eigen::Vector4d* w) const {
    for (int iteration = 0; iteration < 8; ++iteration) {
      const Eigen::Vector4d g1 = a1_ * *w, g2 = a2_ * *w;
      const double f1 = w->dot(g1), f2 = w->dot(g2);
      if (std::hypot(f1, f2) <= 1e-15) return true;
      Eigen::Matrix4d jacobian;
      jacobian.row(0) = 2.0 * g1.transpose();
      jacobian.row(1) = 2.0 * g2.transpose();
      jacobian.row(2) = tangent.transpose();
      jacobian.row(3) = w->transpose();
      const Eigen::Vector4d delta = jacobian.partialPivLu().solve(Eigen::Vector4d(-f1, -f2, 0, 0));
      if (!delta.allFinite()) return false;
      *w = (*w + delta).normalized();
      if (delta.norm() <= 1e-15) break;
    }
    const double f1 = w->dot(a1_ * *w), f2 = w->dot(a2_ * *w);
    return std::hypot(f1, f2) <= 1e-12;
  }

  // The sample of the projective point w (ReadingsOf, ChooseReading), its dyad polished on its
  // geometric equations when needed; `kept` when it fits the poses and its pivots are not far.
  Sample ReadPoint(const Eigen::Vector4d& w) const {
    Sample sample;
    sample.point = w;
    const ConstraintVector z = null_ * w;
    // A slider reading fits only where K0 vanishes: with |K0| > 1e-3 |z| its residual is of
    // the order of K0 |P|^2 / |K| >> kSliderTolerance, and the RR reading is not far.
    const bool sliders = std::abs(z[0]) <= 1e-3 * z.norm();
    DyadReading readings[3];
    const int count = ReadingsOf(z, frames_, sliders, readings);
    if (count == 0) return sample;
    PlanarDyad dyad = readings[ChooseReading(readings, count, kSliderTolerance)].dyad;
    if (dyad.type == DyadType::kRR && Far(dyad)) return sample;
    if (MaxResidual(dyad, frames_) > kPolishResidual) {
      dyad = PolishDyad<4>(dyad, frames_, kPolishIterations);
    }
    if (!(MaxResidual(dyad, frames_) <= kSampleResidual)) return sample;
    if (dyad.type == DyadType::kRR && Far(dyad)) return sample;
    sample.dyad = dyad;
    sample.kept = true;
    switch (dyad.type) {
      case DyadType::kRR:
        sample.key << dyad.fixed_pivot, dyad.moving_pivot;
        sample.radius = dyad.radius;
        sample.refinable = true;
        sample.inside = PivotDistance(dyad) <= options_.refine_radius;
        break;
      case DyadType::kPR:
        sample.key << dyad.LineFoot(), dyad.moving_pivot;
        break;
      case DyadType::kRP:
        sample.key << dyad.fixed_pivot, dyad.LineFoot();
        break;
    }
    return sample;
  }

  // Distance of the farther pivot of an RR dyad from the centroid (the moving pivot at the
  // first pose).
  double PivotDistance(const PlanarDyad& dyad) const {
    const Eigen::Vector2d moving = frames_[0].rotation * dyad.moving_pivot + frames_[0].origin;
    return std::max(dyad.fixed_pivot.norm(), moving.norm());
  }
  bool Far(const PlanarDyad& dyad) const { return !(PivotDistance(dyad) <= kFarPivot); }

  std::vector<PoseFrame> frames_;
  BurmesterCurveOptions options_;
  NullBasis4 null_;
  Eigen::Matrix4d a1_, a2_;
  // The pencil: planes spanned by the axis and cos(phi) v1 + sin(phi) v2, in the null-space
  // coordinates (4) and in constraint space (8).
  Eigen::Matrix<double, 4, 2> axis4_;
  Eigen::Vector4d v1_4_, v2_4_;
  Eigen::Matrix<double, 8, 2> axis_;
  ConstraintVector v1_, v2_;
};

// ---------------------------------------------------------------------------------------------
// Pivot dyads.

enum class FitKind { kCircle, kLine, kPoint, kUndetermined };

struct CircleFit {
  FitKind kind = FitKind::kUndetermined;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // circle centre, or the single point
  double radius = 0.0;
  Eigen::Vector2d line_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d line_direction = Eigen::Vector2d::UnitX();
};

// Circle through three points, or best fitting more (algebraic fit |p|^2 A + B . p + D = 0 by
// the smallest singular vector, then Gauss-Newton on the geometric distances); a line when the
// points are collinear. `length` is the scale below which points coincide.
CircleFit FitCircle(const std::vector<Eigen::Vector2d>& points, double length) {
  CircleFit fit;
  const int n = static_cast<int>(points.size());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p;
  centroid /= n;
  double spread = 0.0;
  for (const Eigen::Vector2d& p : points) spread += (p - centroid).squaredNorm();
  spread = std::sqrt(spread / n);
  if (!(spread > kCoincident * std::max(length, centroid.norm()))) {
    fit.kind = FitKind::kPoint;
    fit.center = centroid;
    return fit;
  }
  std::vector<Eigen::Vector2d> p(n);
  for (int j = 0; j < n; ++j) p[j] = (points[j] - centroid) / spread;
  // Principal direction, for the line case.
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& q : p) scatter += q * q.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
  fit.line_point = centroid;
  fit.line_direction = eigen.eigenvectors().col(1);
  auto line = [&]() {
    fit.kind = FitKind::kLine;
    return fit;
  };
  Eigen::Vector2d center;
  double radius = 0.0;
  if (n == 3) {
    const Eigen::Vector2d a = p[1] - p[0], b = p[2] - p[0], c = p[2] - p[1];
    const double longest = std::max({a.norm(), b.norm(), c.norm()});
    const double shortest = std::min({a.norm(), b.norm(), c.norm()});
    if (!(shortest > kCoincident * longest)) return fit;  // two positions coincide
    const double cross = a.x() * b.y() - a.y() * b.x();
    if (!(std::abs(cross) > kCollinear * longest * longest)) return line();
    center = p[0] + Eigen::Vector2d(a.squaredNorm() * b.y() - b.squaredNorm() * a.y(),
                                    b.squaredNorm() * a.x() - a.squaredNorm() * b.x()) /
                        (2.0 * cross);
    for (const Eigen::Vector2d& q : p) radius += (q - center).norm();
    radius /= 3.0;
  } else {
    const Eigen::Vector2d lambda = eigen.eigenvalues();
    if (!(lambda[0] > kCollinear * kCollinear * lambda[1])) return line();
    Eigen::MatrixXd rows(n, 4);
    for (int j = 0; j < n; ++j) rows.row(j) << p[j].squaredNorm(), p[j].x(), p[j].y(), 1.0;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeFullV);
    const Eigen::Vector4d w = svd.matrixV().col(3);
    const Eigen::Vector2d b(w[1], w[2]);
    if (!(std::abs(w[0]) * kLineRadius > b.norm())) return line();
    center = -b / (2.0 * w[0]);
    radius = std::sqrt(std::max(0.0, center.squaredNorm() - w[3] / w[0]));
    // Gauss-Newton on the geometric distances |p_j - c| - r.
    for (int iteration = 0; iteration < 10; ++iteration) {
      Eigen::MatrixXd jacobian(n, 3);
      Eigen::VectorXd residual(n);
      for (int j = 0; j < n; ++j) {
        const Eigen::Vector2d arm = p[j] - center;
        const double distance = arm.norm();
        if (!(distance > 0.0)) break;
        residual[j] = distance - radius;
        jacobian.block<1, 2>(j, 0) = -(arm / distance).transpose();
        jacobian(j, 2) = -1.0;
      }
      const Eigen::Vector3d step = jacobian.colPivHouseholderQr().solve(residual);
      if (!step.allFinite()) break;
      center -= step.head<2>();
      radius -= step[2];
      if (step.norm() <= 1e-15 * (1.0 + center.norm())) break;
    }
  }
  if (!(radius < kLineRadius) || !center.allFinite()) return line();
  fit.kind = FitKind::kCircle;
  fit.center = centroid + spread * center;
  fit.radius = spread * radius;
  return fit;
}

// g(m) = det [|P_j|^2, P_jx, P_jy, 1] over four poses, P_j = R_j m + d_j (zero on the
// circle-point curve), and its gradient by the cofactor expansion of d det.
double ConcyclicCondition(const std::vector<PoseFrame>& frames, const Eigen::Vector2d& m,
                          Eigen::Vector2d* gradient) {
  // The determinant is unchanged by a translation of the four positions (column operations),
  // so they are taken about their centroid (held fixed for the derivative), against rounding.
  Eigen::Vector2d positions[4];
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int j = 0; j < 4; ++j) {
    positions[j] = frames[j].rotation * m + frames[j].origin;
    centroid += 0.25 * positions[j];
  }
  Eigen::Matrix4d rows;
  for (int j = 0; j < 4; ++j) {
    positions[j] -= centroid;
    rows.row(j) << positions[j].squaredNorm(), positions[j].x(), positions[j].y(), 1.0;
  }
  Eigen::Matrix4d cofactor;
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) {
      Eigen::Matrix3d minor;
      for (int r = 0, rr = 0; r < 4; ++r) {
        if (r == j) continue;
        for (int c = 0, cc = 0; c < 4; ++c) {
          if (c == k) continue;
          minor(rr, cc++) = rows(r, c);
        }
        ++rr;
      }
      cofactor(j, k) = ((j + k) % 2 ? -1.0 : 1.0) * minor.determinant();
    }
  }
  gradient->setZero();
  for (int j = 0; j < 4; ++j) {
    *gradient += frames[j].rotation.transpose() *
                 (2.0 * cofactor(j, 0) * positions[j] + cofactor.block<1, 2>(j, 1).transpose());
  }
  return rows.row(0).dot(cofactor.row(0));
}

// Moves m0 onto the circle-point curve of four (normalized) poses: Newton along the gradient
// onto the curve, then the foot-point iteration m = m0 - t grad g(m) towards the nearest
// point. Returns false when it does not converge.
bool ProjectOntoCirclePointCurve(const std::vector<PoseFrame>& frames, const Eigen::Vector2d& m0,
                                 Eigen::Vector2d* m) {
  // The first-order distance |g| / |grad g| from the curve (normalized units).
  auto distance = [&](const Eigen::Vector2d& x) {
    Eigen::Vector2d gradient;
    const double g = ConcyclicCondition(frames, x, &gradient);
    return std::abs(g) / gradient.norm();
  };
  auto on_curve = [&](const Eigen::Vector2d& x) { return distance(x) <= kOnCurve; };
  // Newton along the gradient until the distance stops decreasing (rounding level).
  Eigen::Vector2d x = m0;
  double current = distance(x);
  for (int iteration = 0; iteration < 100 && current > 0.0; ++iteration) {
    Eigen::Vector2d gradient;
    const double g = ConcyclicCondition(frames, x, &gradient);
    const Eigen::Vector2d next = x - (g / gradient.squaredNorm()) * gradient;
    const double next_distance = distance(next);
    if (!next.allFinite() || !(next_distance < current)) break;
    x = next;
    current = next_distance;
  }
  if (!on_curve(x)) return false;
  *m = x;
  // Foot-point iteration from the curve point reached.
  Eigen::Vector2d y = x;
  bool converged = false;
  for (int iteration = 0; iteration < 50; ++iteration) {
    Eigen::Vector2d gradient;
    const double g = ConcyclicCondition(frames, y, &gradient);
    const double gg = gradient.squaredNorm();
    if (!(gg > 0.0)) break;
    const Eigen::Vector2d next = m0 - ((g + gradient.dot(m0 - y)) / gg) * gradient;
    if (!next.allFinite()) break;
    const double change = (next - y).norm();
    y = next;
    if (change <= 1e-12 * (1.0 + y.norm())) {
      converged = true;
      break;
    }
  }
  if (converged && on_curve(y) && (y - m0).norm() <= (x - m0).norm()) *m = y;
  return true;
}

std::string Format(const char* format, double a, double b) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), format, a, b);
  return buffer;
}

void AddNote(std::string* note, const std::string& text) {
  if (!note) return;
  if (!note->empty()) *note += "; ";
  *note += text;
}

// The dyad of a moving pivot (in E) of `poses`; with `inverted` the poses are an inverted
// motion and the wording speaks of the fixed pivot (center-point curve, line fixed in E).
// `report_length` is the L of the user's task, for the note.
bool PivotDyad(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& pivot, bool inverted,
               double report_length, PlanarDyad* dyad, std::string* note) {
  if (note) note->clear();
  const char* which = inverted ? "fixed pivot" : "moving pivot";
  if (poses.size() < 3) {
    AddNote(note, std::string("a ") + which + " fixes a dyad only for three or more poses");
    return false;
  }
  if (!pivot.allFinite()) {
    AddNote(note, std::string("the ") + which + " is not finite");
    return false;
  }
  const NormalizedMotion motion = Normalize(poses);
  const std::vector<PoseFrame> frames = MakeFrames(motion.poses);
  const Eigen::Vector2d m0 = motion.to_original_moving.Inverse().Apply(pivot);
  Eigen::Vector2d m = m0;
  if (poses.size() == 4) {
    if (!ProjectOntoCirclePointCurve(frames, m0, &m)) {
      AddNote(note, std::string("the ") + which + " could not be moved onto the " +
                        (inverted ? "center-point" : "circle-point") + " curve of the four poses");
      return false;
    }
    const double moved = (m - m0).norm() * motion.length;
    if (moved > kMoveNoteThreshold * report_length) {
      AddNote(note, Format(inverted ? "fixed pivot moved by %.6g (%.3g L) onto the center-point "
                                      "curve of the four poses"
                                    : "moving pivot moved by %.6g (%.3g L) onto the "
                                      "circle-point curve of the four poses",
                           moved, moved / report_length));
    }
  }
  std::vector<Eigen::Vector2d> positions;
  for (const PoseFrame& frame : frames) positions.push_back(frame.rotation * m + frame.origin);
  const CircleFit fit = FitCircle(positions, 1.0);
  PlanarDyad local;
  switch (fit.kind) {
    case FitKind::kUndetermined:
      AddNote(note, std::string("two positions of the ") + which +
                        " coincide: the circle through them is not determined");
      return false;
    case FitKind::kPoint:
      local = PlanarDyad::RR(fit.center, m, 0.0);
      AddNote(note, std::string("the ") + which +
                        " does not move: it is the pole of the motion (zero-length crank)");
      break;
    case FitKind::kLine:
      local = PlanarDyad::PR(m, fit.line_point, fit.line_direction);
      AddNote(note, inverted ? "the fixed pivot's positions in E are collinear: an RP dyad "
                               "(its line is fixed in E)"
                             : "the moving pivot's positions are collinear: a PR dyad (slider "
                               "along their line)");
      break;
    case FitKind::kCircle:
      local = PlanarDyad::RR(fit.center, m, fit.radius);
      break;
  }
  *dyad = TransformDyad(local, motion.to_original_fixed, motion.to_original_moving);
  return true;
}

}  // namespace

int SampleBurmesterCurves(const std::vector<PlanarPose>& poses,
                          const BurmesterCurveOptions& options, BurmesterCurves* curves) {
  curves->branches.clear();
  if (poses.size() != 4) return 0;
  for (const PlanarPose& pose : poses) {
    if (!pose.origin_in_fixed.allFinite() || !std::isfinite(pose.theta)) return 0;
  }
  const NormalizedMotion motion = Normalize(poses);
  CurveSampler sampler(motion.poses, options);
  if (!sampler.Init(motion.poses)) return 0;
  const int planes = std::max(options.planes, 1);
  const double h = M_PI / planes;

  // The sweep: the real points of every plane of the pencil, seeds of the traces.
  std::vector<std::vector<Sample>> seeds(planes);
  for (int k = 0; k < planes; ++k) seeds[k] = sampler.SamplePlane(k * h);
  std::vector<std::vector<char>> covered(planes);
  for (int k = 0; k < planes; ++k) covered[k].assign(seeds[k].size(), 0);

  // Marks the seeds that the step from a to b passes: those of the planes it crosses that lie
  // within kCoverDistance of the chord. (A step that turns the plane by much passes close to
  // the axis; then every plane is checked.)
  auto cover = [&](const Eigen::Vector4d& a, Eigen::Vector4d b) {
    if (a.dot(b) < 0.0) b = -b;
    const Eigen::Vector4d chord = b - a;
    auto mark = [&](int plane) {
      for (size_t i = 0; i < seeds[plane].size(); ++i) {
        if (covered[plane][i]) continue;
        Eigen::Vector4d seed = seeds[plane][i].point;
        if (seed.dot(a) < 0.0) seed = -seed;
        const double t = std::clamp((seed - a).dot(chord) / chord.squaredNorm(), 0.0, 1.0);
        if ((seed - a - t * chord).norm() < kCoverDistance) covered[plane][i] = 1;
      }
    };
    const double phi_a = sampler.PlaneAngle(a);
    double delta = sampler.PlaneAngle(b) - phi_a;
    if (delta > 0.5 * M_PI) delta -= M_PI;
    if (delta <= -0.5 * M_PI) delta += M_PI;
    if (!(chord.squaredNorm() > 0.0)) return;
    if (std::abs(delta) > 0.1) {
      for (int plane = 0; plane < planes; ++plane) mark(plane);
      return;
    }
    const double lo = std::min(phi_a, phi_a + delta), hi = std::max(phi_a, phi_a + delta);
    for (long k = static_cast<long>(std::ceil(lo / h)); k * h <= hi; ++k) {
      mark(static_cast<int>(((k % planes) + planes) % planes));
    }
  };

  // Trace one component per uncovered seed (the slider plane k = 0 last: its points are the
  // sliders, listed on their own below).
  struct Trace {
    std::vector<Sample> path;
    bool closed = false;
  };
  std::vector<Trace> traces;
  int budget = kMaxTotalSteps;
  for (int pass = 0; pass < planes && budget > 0; ++pass) {
    const int k = (pass + 1) % planes;
    for (size_t i = 0; i < seeds[k].size(); ++i) {
      if (covered[k][i]) continue;
      covered[k][i] = 1;
      Trace trace;
      trace.closed = sampler.Trace(seeds[k][i], &budget, &trace.path);
      for (size_t j = 0; j + 1 < trace.path.size(); ++j) {
        cover(trace.path[j].point, trace.path[j + 1].point);
      }
      if (trace.closed) cover(trace.path.back().point, trace.path.front().point);
      traces.push_back(std::move(trace));
    }
  }

  // Polylines: kept RR dyads, cut where a dyad is dropped or consecutive dyads jump farther
  // than the break distance. A closed trace is started at such a cut, or closed by repeating
  // its first dyad when it has none.
  int count = 0;
  auto joined = [&](const Sample& a, const Sample& b) {
    return a.refinable && b.refinable && KeyDistance(a, b) <= options.break_distance;
  };
  for (Trace& trace : traces) {
    std::vector<Sample>& path = trace.path;
    const size_t n = path.size();
    size_t first = 0;
    bool cut = !trace.closed;
    if (trace.closed) {
      for (size_t j = 0; j < n && !cut; ++j) {
        if (!joined(path[j], path[(j + 1) % n])) {
          first = (j + 1) % n;
          cut = true;
        }
      }
    }
    std::vector<PlanarDyad> branch;
    auto flush = [&]() {
      if (!branch.empty()) curves->branches.push_back(std::move(branch));
      branch.clear();
    };
    for (size_t j = 0; j < n; ++j) {
      const Sample& sample = path[(first + j) % n];
      if (j > 0 && !joined(path[(first + j - 1) % n], sample)) flush();
      if (!sample.refinable) continue;
      branch.push_back(
          TransformDyad(sample.dyad, motion.to_original_fixed, motion.to_original_moving));
      ++count;
    }
    if (!cut && !branch.empty()) branch.push_back(branch.front());
    flush();
  }
  // The sliders: the kept PR and RP points of the slider plane, each on its own (their
  // neighbours on the curve are RR dyads with a pivot far away).
  for (const Sample& sample : seeds[0]) {
    if (!sample.kept || sample.dyad.type == DyadType::kRR) continue;
    curves->branches.push_back(
        {TransformDyad(sample.dyad, motion.to_original_fixed, motion.to_original_moving)});
    ++count;
  }
  return count;
}

bool DyadFromMovingPivot(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& moving_pivot,
                         PlanarDyad* dyad, std::string* note) {
  return PivotDyad(poses, moving_pivot, false, CharacteristicLength(poses), dyad, note);
}

bool DyadFromFixedPivot(const std::vector<PlanarPose>& poses, const Eigen::Vector2d& fixed_pivot,
                        PlanarDyad* dyad, std::string* note) {
  std::vector<PlanarPose> inverse;
  inverse.reserve(poses.size());
  for (const PlanarPose& pose : poses) inverse.push_back(pose.Inverse());
  PlanarDyad inverted;
  if (!PivotDyad(inverse, fixed_pivot, true, CharacteristicLength(poses), &inverted, note)) {
    return false;
  }
  *dyad = inverted.Inverted();
  return true;
}

void DefaultMovingPivots(const std::vector<PlanarPose>& poses, Eigen::Vector2d pivots[2],
                         std::string* explanation) {
  if (explanation) explanation->clear();
  double length = CharacteristicLength(poses);
  if (!(length > 0.0)) length = 1.0;
  auto fallback = [&](const char* why) {
    pivots[0] = Eigen::Vector2d(-0.5 * length, 0.0);
    pivots[1] = Eigen::Vector2d(0.5 * length, 0.0);
    if (explanation) {
      *explanation = std::string(
                         "moving pivots chosen at E's origin -+ L/2 along E's x-axis (no "
                         "pivots given; ") +
                     why + ")";
    }
  };
  if (poses.size() < 3) return fallback("fewer than three poses");
  // Score every point of a grid of E about its origin (normalized units) by the three
  // positions it takes at the first, middle and last pose: the altitude of their triangle on
  // its longest side (how well the positions fix the circle: a pivot error e moves the centre
  // by about e / altitude), discounted for long cranks, far fixed pivots and far moving pivots.
  const NormalizedMotion motion = Normalize(poses);
  const std::vector<PoseFrame> frames = MakeFrames(motion.poses);
  const PoseFrame* three[3] = {&frames.front(), &frames[frames.size() / 2], &frames.back()};
  constexpr int kGrid = 17;
  constexpr double kHalfWidth = 2.0;
  struct Candidate {
    Eigen::Vector2d point;
    double score;
    double radius;
    Eigen::Vector2d fixed_pivot;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Eigen::Vector2d p(-kHalfWidth + 2.0 * kHalfWidth * i / (kGrid - 1),
                              -kHalfWidth + 2.0 * kHalfWidth * j / (kGrid - 1));
      std::vector<Eigen::Vector2d> q;
      for (const PoseFrame* frame : three) q.push_back(frame->rotation * p + frame->origin);
      const Eigen::Vector2d a = q[1] - q[0], b = q[2] - q[0], c = q[2] - q[1];
      const double longest = std::max({a.norm(), b.norm(), c.norm()});
      const double altitude = std::abs(a.x() * b.y() - a.y() * b.x()) / longest;
      if (!(altitude > 1e-3)) continue;
      const CircleFit fit = FitCircle(q, 1.0);
      if (fit.kind != FitKind::kCircle) continue;
      const double r = fit.radius, f = fit.center.norm(), m = p.norm();
      const double score =
          altitude / ((1.0 + 0.25 * r * r) * (1.0 + f * f / 9.0) * (1.0 + m * m / 9.0));
      candidates.push_back({p, score, r, fit.center});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.score > y.score; });
  // The second pivot at least L from the first, and so its fixed pivot (a ground link of
  // some length), if the grid has one.
  const Candidate* second = nullptr;
  int pass = 0;
  for (; pass < 2 && second == nullptr; ++pass) {
    for (const Candidate& candidate : candidates) {
      if ((candidate.point - candidates[0].point).norm() >= 1.0 &&
          (pass == 1 || (candidate.fixed_pivot - candidates[0].fixed_pivot).norm() >= 1.0)) {
        second = &candidate;
        break;
      }
    }
  }
  const bool ground_link_apart = pass == 1;
  if (candidates.empty() || second == nullptr) {
    return fallback("no grid point moves on a well-conditioned circle");
  }
  pivots[0] = motion.to_original_moving.Apply(candidates[0].point);
  pivots[1] = motion.to_original_moving.Apply(second->point);
  if (explanation) {
    char buffer[512];
    std::snprintf(buffer, sizeof(buffer),
                  "moving pivots chosen at (%.4g, %.4g) and (%.4g, %.4g) in E (no pivots given): "
                  "the best pair of a %d x %d grid within 2 L of E's origin, scored by how well "
                  "their three positions fix a circle against crank length, with %s L apart "
                  "(radii %.4g and %.4g, ground link %.4g)",
                  pivots[0].x(), pivots[0].y(), pivots[1].x(), pivots[1].y(), kGrid, kGrid,
                  ground_link_apart ? "moving and fixed pivots" : "the moving pivots",
                  candidates[0].radius * length, second->radius * length,
                  (candidates[0].fixed_pivot - second->fixed_pivot).norm() * length);
    *explanation = buffer;
  }
}

}  // namespace linkfit
