// Burmester curves of four poses and the dyad of a chosen pivot (planar_burmester_curves.h).
//
// What each part implements:
// - SampleBurmesterCurves: the center-point curve of four poses as the plane cubic D(F) = 0,
//   D(F) = det[|q_j|^2, q_jx, q_jy, 1] with q_j = R_j^T (F - d_j) the positions in E of the
//   fixed pivot F at the four poses (the inverted motion; F is a center point exactly when its
//   four positions are concyclic, and the circle's centre is the dyad's circle point m). Its
//   coefficients come from the multilinear expansion of the determinant about a base point B of
//   the curve; every line through B at angle theta meets the curve in two more points, the roots
//   of the quadratic f3(u) s^2 + f2(u) s + f1(u) = 0 (f_k the cubic's homogeneous parts about B,
//   u = (cos theta, sin theta)). The two roots, as functions of theta in [0, pi), cover the
//   whole curve, each continuous where the quadratic's discriminant is positive; the
//   discriminant is a quartic form in u whose roots (a companion matrix) bound the intervals,
//   and at their ends the two roots meet. So each component of the curve is one root walked
//   over an interval of theta and the other walked back, sampled in order, densely where the
//   dyads move fast, and no component is missed however small. The PR and RP dyads are the curve's
//   point at infinity and the point whose circle point is at infinity: the four points of the
//   slider plane z0 = K0 = 0 of the constraint space (planar_burmester.h, after seed 001 eqs 6, 9
//   and 13), cut by IntersectConstraintConics.
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
#include <unsupported/Eigen/Polynomials>
#include <utility>

#include "fitting/planar_burmester.h"
#include "fitting/planar_constraint_space.h"
#include "fitting/polynomial.h"

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
// Pivots farther than this (normalized units) from the centroid: the sample is not kept (the
// curve's sketch ends there; a slider dyad is listed on its own, exactly).
constexpr double kFarPivot = 100.0;
constexpr int kPolishIterations = 4;
// Outside the refine radius consecutive samples are at most this fraction of their distance
// from the centroid apart (and at most half the break distance, so that the sketch stays one
// polyline).
constexpr double kSketchStep = 0.04;
// Steps of theta (radians): the largest (also across samples that are not kept), the first
// from an interval's end (where the curve's speed in theta is infinite), the smallest.
constexpr double kMaxAngleStep = 0.02;
constexpr double kFirstAngleStep = 1e-6;
constexpr double kMinAngleStep = 1e-13;
// Directions of the lines through the centroid on which a base point is sought.
constexpr int kBaseDirections = 16;
// A discriminant root whose imaginary part is below this (relative to 1 + |t|) is tried as a
// real root; it is taken when, after Newton's method, the discriminant there is below
// kRootValue times its largest coefficient.
constexpr double kRootImaginary = 1e-3;
constexpr double kRootValue = 1e-10;
// Positions of a pivot closer than this (relative to their spread or L) coincide; positions
// whose triangle is flatter than this (|cross| / longest side^2) are collinear.
constexpr double kCoincident = 1e-12;
constexpr double kCollinear = 1e-10;
// A fitted circle larger than this (relative to the spread of the points) is a line.
constexpr double kLineRadius = 1e9;
// A pivot this close (relative to L, first order) to the circle-point curve, times 1 plus its
// distance from E's origin (over L), is on it: the determinant's rounding floor grows with the
// distance (a pivot 140 L away gets within 2e-11 L at best).
constexpr double kOnCurve = 1e-11;
// A pivot moved by less than this (relative to L) onto the curve is reported as not moved.
constexpr double kMoveNoteThreshold = 1e-9;

// ---------------------------------------------------------------------------------------------
// Curve sampling.

// One point of the curve, in the normalized frames: an RR dyad (fixed pivot F in Sigma, moving
// pivot m in E, radius r), `kept` when it fits the poses to kSampleResidual with both pivots
// within kFarPivot of the centroid, `inside` when both are within the refine radius.
struct Sample {
  Eigen::Vector2d fixed_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d moving_pivot = Eigen::Vector2d::Zero();
  double radius = 0.0;
  double reach = 0.0;  // the farther pivot's distance from the centroid (moving: at pose 0)
  bool kept = false;
  bool inside = false;
};

// How far apart two samples' dyads are, as DyadDistance measures it: the larger pivot
// displacement and the radius change.
double KeyDistance(const Sample& a, const Sample& b) {
  const double dr = a.radius - b.radius;
  return std::sqrt(std::max({(a.fixed_pivot - b.fixed_pivot).squaredNorm(),
                             (a.moving_pivot - b.moving_pivot).squaredNorm(), dr * dr}));
}

// The center-point cubic D(F) of four frames, expanded about a base point B:
// D(B + x) = sum_{a + b <= 3} c(a, b) x^a y^b. Subtracting |F|^2 times the column of ones from
// the first column makes every row of the determinant affine in F, M(F) = M(B) + x Mx + y My,
// so the coefficients are sums of the determinants with each of the first three columns taken
// from M(B), Mx or My (multilinearity).
class CenterPointCubic {
 public:
  explicit CenterPointCubic(const std::vector<PoseFrame>& frames) {
    for (int j = 0; j < 4; ++j) {
      const Eigen::Matrix2d rt = frames[j].rotation.transpose();
      const Eigen::Vector2d d = frames[j].origin;
      m0_.row(j) << d.squaredNorm(), -(rt * d).transpose(), 1.0;
      mx_.row(j) << -2.0 * d.x(), rt.col(0).transpose(), 0.0;
      my_.row(j) << -2.0 * d.y(), rt.col(1).transpose(), 0.0;
    }
  }

  void Expand(const Eigen::Vector2d& base) {
    base_ = base;
    const Eigen::Matrix4d at_base = m0_ + base.x() * mx_ + base.y() * my_;
    const Eigen::Matrix4d* parts[3] = {&at_base, &mx_, &my_};
    c_.setZero();
    for (int k = 0; k < 27; ++k) {
      const int pick[3] = {k % 3, (k / 3) % 3, k / 9};
      Eigen::Matrix4d m;
      for (int i = 0; i < 3; ++i) m.col(i) = parts[pick[i]]->col(i);
      m.col(3).setOnes();
      const int a = (pick[0] == 1) + (pick[1] == 1) + (pick[2] == 1);
      const int b = (pick[0] == 2) + (pick[1] == 2) + (pick[2] == 2);
      c_(a, b) += m.determinant();
    }
  }

  const Eigen::Vector2d& base() const { return base_; }
  double Coefficient(int a, int b) const { return c_(a, b); }

  // The homogeneous parts f1, f2, f3 about the base along u.
  void Parts(const Eigen::Vector2d& u, double* f1, double* f2, double* f3) const {
    const double x = u.x(), y = u.y();
    *f1 = c_(1, 0) * x + c_(0, 1) * y;
    *f2 = (c_(2, 0) * x + c_(1, 1) * y) * x + c_(0, 2) * y * y;
    *f3 = ((c_(3, 0) * x + c_(2, 1) * y) * x + c_(1, 2) * y * y) * x + c_(0, 3) * y * y * y;
  }

  // The gradient of D at base + x.
  Eigen::Vector2d Gradient(const Eigen::Vector2d& x) const {
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (int a = 0; a <= 3; ++a) {
      for (int b = 0; a + b <= 3; ++b) {
        if (a > 0) g.x() += a * c_(a, b) * std::pow(x.x(), a - 1) * std::pow(x.y(), b);
        if (b > 0) g.y() += b * c_(a, b) * std::pow(x.x(), a) * std::pow(x.y(), b - 1);
      }
    }
    return g;
  }

  double Scale() const { return c_.cwiseAbs().maxCoeff(); }

 private:
  Eigen::Matrix4d m0_, mx_, my_;
  Eigen::Vector2d base_ = Eigen::Vector2d::Zero();
  Eigen::Matrix4d c_ = Eigen::Matrix4d::Zero();  // c_(a, b), a + b <= 3
};

// The center-point curve of four normalized frames as a function of the angle of the line
// through the base point (file comment), and its sampling.
class CurveTracer {
 public:
  CurveTracer(const std::vector<PoseFrame>& frames, const BurmesterCurveOptions& options)
      : frames_(frames), options_(options), cubic_(frames) {}

  // Finds a base point of the curve near the centroid, where the curve is regular: a real
  // intersection with one of kBaseDirections lines through the centroid, the one of largest
  // gradient over (1 + distance)^4 (the gradient grows as the distance squared). Seen from a
  // far base point the rest of the curve lies within a narrow angle, where the discriminant's
  // roots cluster. False when the cubic vanishes (a degenerate task).
  bool Init() {
    cubic_.Expand(Eigen::Vector2d::Zero());
    const double scale = cubic_.Scale();
    if (!(scale > 0.0) || !std::isfinite(scale)) return false;
    double best = -1.0;
    Eigen::Vector2d base = Eigen::Vector2d::Zero();
    for (int k = 0; k < kBaseDirections; ++k) {
      const double angle = M_PI * (k + 0.5) / kBaseDirections;
      const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
      double f1, f2, f3;
      cubic_.Parts(u, &f1, &f2, &f3);
      if (!(std::abs(f3) > 1e-12 * scale)) continue;
      double roots[3];
      const int count = SolveCubicReal(f3, f2, f1, cubic_.Coefficient(0, 0), roots);
      for (int i = 0; i < count; ++i) {
        const Eigen::Vector2d point = roots[i] * u;
        const double score = cubic_.Gradient(point).norm() / std::pow(1.0 + point.norm(), 4);
        if (std::isfinite(score) && score > best) {
          best = score;
          base = point;
        }
      }
    }
    if (!(best > 0.0)) return false;
    cubic_.Expand(base);
    return true;
  }

  // The sample on the line of direction u (theta): the root s+ (`plus`) or s- of the line's
  // quadratic (stable forms, no cancellation), F = B + s u, m the centre of the circle through
  // F's four positions q_j in E. (F does not depend on the length of u: the quadratic's
  // coefficients are forms of degree 1, 2 and 3 in u.)
  Sample At(const Eigen::Vector2d& u, bool plus) const {
    Sample sample;
    double f1, f2, f3;
    cubic_.Parts(u, &f1, &f2, &f3);
    const double root = std::sqrt(std::max(0.0, f2 * f2 - 4.0 * f1 * f3));
    const double s = f2 >= 0.0 ? (plus ? -2.0 * f1 / (f2 + root) : -(f2 + root) / (2.0 * f3))
                               : (plus ? (root - f2) / (2.0 * f3) : 2.0 * f1 / (root - f2));
    if (!std::isfinite(s)) return sample;
    const Eigen::Vector2d fixed = cubic_.base() + s * u;
    if (!(fixed.squaredNorm() <= kFarPivot * kFarPivot)) return sample;
    // The circle point: least squares on 2 (q_j - q_0) . m = |q_j|^2 - |q_0|^2 about the
    // positions' centroid (normal equations of the 3 x 2 system).
    Eigen::Vector2d q[4];
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (int j = 0; j < 4; ++j) {
      q[j] = frames_[j].rotation.transpose() * (fixed - frames_[j].origin);
      centroid += 0.25 * q[j];
    }
    for (Eigen::Vector2d& p : q) p -= centroid;
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    for (int j = 1; j < 4; ++j) {
      const Eigen::Vector2d row = 2.0 * (q[j] - q[0]);
      normal += row * row.transpose();
      rhs += row * (q[j].squaredNorm() - q[0].squaredNorm());
    }
    const double det = normal.determinant();
    if (!(std::abs(det) > 0.0)) return sample;
    const Eigen::Vector2d center =
        Eigen::Vector2d(normal(1, 1) * rhs.x() - normal(0, 1) * rhs.y(),
                        normal(0, 0) * rhs.y() - normal(1, 0) * rhs.x()) /
        det;
    // The radius from the mean squared distance; |d_j - r| = |d_j^2 - r^2| / (d_j + r) is at
    // most `spread` / r, which bounds the dyad's residual without a square root per pose.
    double squared[4], mean = 0.0;
    for (int j = 0; j < 4; ++j) {
      squared[j] = (q[j] - center).squaredNorm();
      mean += 0.25 * squared[j];
    }
    double spread = 0.0;
    for (int j = 0; j < 4; ++j) spread = std::max(spread, std::abs(squared[j] - mean));
    PlanarDyad dyad = PlanarDyad::RR(fixed, center + centroid, std::sqrt(mean));
    // Far samples are dropped before any polish (the curve's arms beyond the sketch).
    if (!(Reach(dyad) <= kFarPivot)) return sample;
    if (!(spread <= kPolishResidual * dyad.radius)) {
      dyad = PolishDyad<4>(dyad, frames_, kPolishIterations);
      if (!(MaxResidual(dyad, frames_) <= kSampleResidual)) return sample;
    }
    sample.fixed_pivot = dyad.fixed_pivot;
    sample.moving_pivot = dyad.moving_pivot;
    sample.radius = dyad.radius;
    sample.reach = Reach(dyad);
    sample.kept = sample.reach <= kFarPivot;
    sample.inside = sample.reach <= options_.refine_radius;
    return sample;
  }

  // The intervals (a, b) of theta, 0 <= a < pi, a < b < a + pi, where the discriminant is
  // positive, between consecutive roots (theta and theta + pi are one line). Returns false when
  // there is none. `whole` is set when the discriminant has no real root and is positive: then
  // each root of the quadratic is a loop over theta in [0, pi).
  bool Intervals(std::vector<std::pair<double, double>>* intervals, bool* whole) const {
    intervals->clear();
    *whole = false;
    // Quartic form disc(u) = f2^2 - 4 f1 f3 = sum_k e_k ux^(4-k) uy^k.
    const double p1[2] = {cubic_.Coefficient(1, 0), cubic_.Coefficient(0, 1)};
    const double p2[3] = {cubic_.Coefficient(2, 0), cubic_.Coefficient(1, 1),
                          cubic_.Coefficient(0, 2)};
    const double p3[4] = {cubic_.Coefficient(3, 0), cubic_.Coefficient(2, 1),
                          cubic_.Coefficient(1, 2), cubic_.Coefficient(0, 3)};
    std::array<double, 5> e{};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) e[i + j] += p2[i] * p2[j];
    }
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 4; ++j) e[i + j] -= 4.0 * p1[i] * p3[j];
    }
    const double size =
        std::max({std::abs(e[0]), std::abs(e[1]), std::abs(e[2]), std::abs(e[3]), std::abs(e[4])});
    if (!(size > 0.0)) return false;
    auto disc = [&](double theta, double* derivative) {
      const double x = std::cos(theta), y = std::sin(theta);
      double value = 0.0, dx = 0.0, dy = 0.0;
      for (int k = 0; k <= 4; ++k) {
        value += e[k] * std::pow(x, 4 - k) * std::pow(y, k);
        if (k < 4) dx += (4 - k) * e[k] * std::pow(x, 3 - k) * std::pow(y, k);
        if (k > 0) dy += k * e[k] * std::pow(x, 4 - k) * std::pow(y, k - 1);
      }
      if (derivative) *derivative = -y * dx + x * dy;
      return value;
    };
    // Roots in t = uy / ux (a companion matrix), and theta = pi / 2 when the degree drops.
    std::vector<double> roots;
    int degree = 4;
    while (degree > 0 && !(std::abs(e[degree]) > 1e-13 * size)) --degree;
    if (degree < 4) roots.push_back(0.5 * M_PI);
    if (degree > 0) {
      Eigen::VectorXd coefficients(degree + 1);
      for (int k = 0; k <= degree; ++k) coefficients[k] = e[k];
      Eigen::PolynomialSolver<double, Eigen::Dynamic> solver(coefficients);
      for (int i = 0; i < solver.roots().size(); ++i) {
        const Complex t = solver.roots()[i];
        if (std::abs(t.imag()) <= kRootImaginary * (1.0 + std::abs(t))) {
          roots.push_back(std::atan(t.real()));
        }
      }
    }
    // Newton's method on the trigonometric form, then into [0, pi), ascending, distinct.
    for (double& theta : roots) {
      for (int iteration = 0; iteration < 8; ++iteration) {
        double derivative;
        const double value = disc(theta, &derivative);
        if (!(std::abs(derivative) > 0.0)) break;
        const double step = value / derivative;
        if (!(std::abs(step) < 1e-2)) break;
        theta -= step;
        if (std::abs(step) < 1e-15) break;
      }
      if (!(std::abs(disc(theta, nullptr)) <= kRootValue * size)) theta = NAN;
      theta = std::fmod(theta, M_PI);
      if (theta < 0.0) theta += M_PI;
    }
    roots.erase(std::remove_if(roots.begin(), roots.end(), [](double t) { return std::isnan(t); }),
                roots.end());
    std::sort(roots.begin(), roots.end());
    roots.erase(
        std::unique(roots.begin(), roots.end(), [](double a, double b) { return b - a < 1e-12; }),
        roots.end());
    if (roots.size() > 1 && roots.back() - roots.front() > M_PI - 1e-12) roots.pop_back();
    if (roots.empty()) {
      *whole = disc(0.0, nullptr) > 0.0;
      return *whole;
    }
    for (size_t i = 0; i < roots.size(); ++i) {
      const double a = roots[i];
      const double b = i + 1 < roots.size() ? roots[i + 1] : roots[0] + M_PI;
      if (disc(0.5 * (a + b), nullptr) > 0.0) intervals->push_back({a, b});
    }
    return !intervals->empty();
  }

  // Samples theta from `from` to `to` (either way) in order and hands each sample to `emit`,
  // the ends included unless `skip_first` / `skip_last`: consecutive dyads within the refine
  // step where either is inside the refine radius, within the sketch step where both are kept,
  // and theta steps of at most kMaxAngleStep.
  template <typename Emit>
  void Sweep(double from, double to, bool plus, bool skip_first, bool skip_last,
             Emit&& emit) const {
    const double direction = to >= from ? 1.0 : -1.0;
    Eigen::Vector2d u(std::cos(from), std::sin(from));
    Sample current = At(u, plus);
    if (!skip_first) emit(current);
    double left = std::abs(to - from);  // of the sweep, in radians
    double step = kFirstAngleStep;
    while (left > 0.0) {
      step = std::min({step, left, kMaxAngleStep});
      const bool last = step >= left;
      // u turned by the step (Taylor series: step <= kMaxAngleStep, error below 1e-18).
      const double h2 = step * step;
      const double c = 1.0 - h2 / 2.0 * (1.0 - h2 / 12.0 * (1.0 - h2 / 30.0));
      const double s = direction * step * (1.0 - h2 / 6.0 * (1.0 - h2 / 20.0 * (1.0 - h2 / 42.0)));
      const Eigen::Vector2d next_u =
          last ? Eigen::Vector2d(std::cos(to), std::sin(to))
               : Eigen::Vector2d(c * u.x() - s * u.y(), s * u.x() + c * u.y());
      Sample next = At(next_u, plus);
      double limit = std::numeric_limits<double>::infinity();
      if (current.kept && next.kept) {
        limit = current.inside || next.inside
                    ? options_.refine_step
                    : std::min(0.5 * options_.break_distance,
                               std::max(options_.refine_step,
                                        kSketchStep * std::min(current.reach, next.reach)));
      }
      const double jump = current.kept && next.kept ? KeyDistance(current, next) : 0.0;
      if (jump > limit && step > kMinAngleStep) {
        step *= std::clamp(0.7 * limit / jump, 0.1, 0.5);
        continue;
      }
      left = last ? 0.0 : left - step;
      u = next_u;
      current = next;
      if (!(last && skip_last)) emit(current);
      step *= jump > 0.0 ? std::clamp(0.7 * limit / jump, 0.5, 2.0) : 2.0;
    }
  }

 private:
  double Reach(const PlanarDyad& dyad) const {
    const Eigen::Vector2d moving = frames_[0].rotation * dyad.moving_pivot + frames_[0].origin;
    return std::max(dyad.fixed_pivot.norm(), moving.norm());
  }

  const std::vector<PoseFrame>& frames_;
  BurmesterCurveOptions options_;
  CenterPointCubic cubic_;
};

// The slider dyads of four normalized poses (file comment): the real points of the plane
// z0 = 0 of the null space N of the four constraint rows, read as PR or RP dyads and polished on
// their geometric equations. False for a degenerate task (rank-deficient rows).
bool SliderDyads(const std::vector<PlanarPose>& poses, const std::vector<PoseFrame>& frames,
                 std::vector<PlanarDyad>* sliders) {
  sliders->clear();
  Eigen::Matrix<double, 4, 8> rows;
  for (int j = 0; j < 4; ++j) rows.row(j) = ConstraintRow(poses[j]).transpose();
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 8, 4>> qr(rows.transpose());
  const double r_first = std::abs(qr.matrixR()(0, 0));
  const double r_last = std::abs(qr.matrixR()(3, 3));
  if (!(r_last > 1e-10 * r_first)) return false;
  const Eigen::Matrix<double, 8, 8> q = qr.householderQ();
  const Eigen::Matrix<double, 8, 4> null = q.rightCols<4>();
  // w orthogonal to c = row 0 of the basis: z0 = 0 (every dyad a slider when c vanishes; then
  // any plane).
  Eigen::Vector4d c = null.row(0).transpose();
  if (!(c.norm() > 1e-12)) c = Eigen::Vector4d::UnitX();
  c.normalize();
  const Eigen::HouseholderQR<Eigen::Vector4d> house(c);
  const Eigen::Matrix4d h = house.householderQ();
  const PlaneBasis plane = null * h.rightCols<3>();
  std::vector<ComplexConstraintVector> roots;
  if (IntersectConstraintConics(plane, &roots) <= 0) return true;
  Eigen::Matrix3d m1, m2;
  RestrictedConics(plane, ConicFill::kMirrorUpper, &m1, &m2);
  for (const ComplexConstraintVector& z : roots) {
    Vector3c a = plane.transpose().cast<Complex>() * z;
    int k = 0;
    a.cwiseAbs().maxCoeff(&k);
    if (!(std::abs(a[k]) > 0.0)) continue;
    a /= a[k];
    if (!(a.imag().norm() <= kRealTolerance * a.real().norm())) continue;
    Eigen::Vector3d a_real = a.real();
    if (!(PolishRealRoot(m1, m2, kPolishIterations, &a_real) <= kConicTolerance)) continue;
    const ConstraintVector point = (plane * a_real).normalized();
    DyadReading readings[3];
    const int count = ReadingsOf(point, frames, true, readings);
    if (count == 0) continue;
    PlanarDyad dyad = readings[ChooseReading(readings, count, kSliderTolerance)].dyad;
    if (dyad.type == DyadType::kRR) continue;
    if (MaxResidual(dyad, frames) > kPolishResidual) {
      dyad = PolishDyad<4>(dyad, frames, kPolishIterations);
    }
    if (!(MaxResidual(dyad, frames) <= kSampleResidual)) continue;
    bool repeat = false;
    for (const PlanarDyad& other : *sliders) {
      repeat = repeat ||
               (other.type == dyad.type && (other.moving_pivot - dyad.moving_pivot).norm() +
                                                   (other.fixed_pivot - dyad.fixed_pivot).norm() +
                                                   (other.line_point - dyad.line_point).norm() <
                                               1e-9);
    }
    if (!repeat) sliders->push_back(dyad);
  }
  return true;
}

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
  auto on_curve = [&](const Eigen::Vector2d& x) {
    return distance(x) <= kOnCurve * (1.0 + x.norm());
  };
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
  const std::vector<PoseFrame> frames = MakeFrames(motion.poses);
  std::vector<PlanarDyad> sliders;
  if (!SliderDyads(motion.poses, frames, &sliders)) return 0;

  // Polylines of kept dyads, cut where a dyad is dropped or consecutive dyads jump farther
  // than the break distance, built as the samples come. A loop's last polyline is joined to its
  // first when the loop closes there; a loop without a cut is closed by repeating its first dyad.
  int count = 0;
  // The similarities back to the user's frames, as matrices (TransformDyad evaluates the
  // rotation per point).
  const Similarity2& sigma = motion.to_original_fixed;
  const Similarity2& epsilon = motion.to_original_moving;
  const Eigen::Matrix2d to_fixed = sigma.scale * Rotation2(sigma.angle);
  const Eigen::Matrix2d to_moving = epsilon.scale * Rotation2(epsilon.angle);
  const Eigen::Vector2d fixed_shift = sigma.translation, moving_shift = epsilon.translation;
  auto joined = [&](const Sample& a, const Sample& b) {
    return a.kept && b.kept && KeyDistance(a, b) <= options.break_distance;
  };
  Sample first, previous;
  bool started = false, cut = false;
  std::vector<PlanarDyad> first_run, run;
  auto flush = [&](std::vector<PlanarDyad>* polyline) {
    if (!polyline->empty()) curves->branches.push_back(std::move(*polyline));
    polyline->clear();
  };
  auto emit = [&](const Sample& sample) {
    if (!started) {
      first = sample;
      started = true;
    } else if (!joined(previous, sample)) {
      if (cut) {
        flush(&run);
      } else {
        first_run = std::move(run);
        run.clear();
      }
      cut = true;
    }
    if (sample.kept) {
      run.push_back(PlanarDyad::RR(to_fixed * sample.fixed_pivot + fixed_shift,
                                   to_moving * sample.moving_pivot + moving_shift,
                                   sigma.scale * sample.radius));
      ++count;
    }
    previous = sample;
  };
  auto close_loop = [&]() {
    if (!started) return;
    if (joined(previous, first)) {
      if (cut) {
        run.insert(run.end(), first_run.begin(), first_run.end());
      } else if (!run.empty()) {
        run.push_back(run.front());
      }
      first_run.clear();
    }
    flush(&run);
    flush(&first_run);
    started = cut = false;
  };

  // The loops of the curve, in order (file comment): over an interval (a, b) of theta, the root
  // s+ from a to b and then s- back from b to a (the two roots meet at a and b); or, when the
  // discriminant has no root, each root over [0, pi) (theta + pi is the same line: s+ at pi is
  // s+ at 0 with the direction reversed).
  CurveTracer tracer(frames, options);
  std::vector<std::pair<double, double>> intervals;
  bool whole = false;
  if (tracer.Init() && tracer.Intervals(&intervals, &whole)) {
    if (whole) {
      for (const bool plus : {true, false}) {
        tracer.Sweep(0.0, M_PI, plus, false, true, emit);
        close_loop();
      }
    }
    for (const auto& [a, b] : intervals) {
      tracer.Sweep(a, b, true, false, false, emit);
      tracer.Sweep(b, a, false, true, true, emit);
      close_loop();
    }
  }
  // The sliders, each on its own (their neighbours on the curve are RR dyads with a pivot at
  // infinity).
  for (const PlanarDyad& slider : sliders) {
    curves->branches.push_back(
        {TransformDyad(slider, motion.to_original_fixed, motion.to_original_moving)});
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
  // Scores within kScoreTie of the best are a tie, decided by nearness to E's origin (then the
  // grid's order): the rounding of the data moves every score a little, and a pick among near
  // equals must not follow it.
  constexpr double kScoreTie = 0.01;
  if (!candidates.empty()) {
    const double best = candidates.front().score;
    const auto tied = std::partition_point(
        candidates.begin(), candidates.end(),
        [&](const Candidate& c) { return c.score >= (1.0 - kScoreTie) * best; });
    std::stable_sort(candidates.begin(), tied, [](const Candidate& x, const Candidate& y) {
      return x.point.norm() < y.point.norm() - 1e-12;
    });
  }
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
