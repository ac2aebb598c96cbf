#include "lib/platform_motion.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace linkfit {

namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix56d = Eigen::Matrix<double, 5, 6>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

constexpr int kDyadCount = 5;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Newton (all in units of L): a correction this small ends the iteration (the next one would be
// below rounding); a stalled correction below kNewtonFloor is accepted as rounding noise.
constexpr double kNewtonConverged = 1e-11;
constexpr double kNewtonFloor = 1e-9;
constexpr int kNewtonIterations = 12;
// A predictor step is rejected when the corrector moves it by more than this share of the step,
// or when the tangent turns by more than acos(kMinTangentCosine) over it.
constexpr double kMaxCorrectionShare = 0.5;
constexpr double kMinTangentCosine = 0.85;
// The step collapses (a singular configuration) below this share of options.step.
constexpr double kMinStepShare = 1e-6;
// Closure: the curve is back at the first pose when the curve point in the first pose's hyperplane
// is within this distance of it (units of L).
constexpr double kClosureDistance = 1e-8;
// Root finding along a segment stops when the parameter moves by less than this (units of L).
constexpr double kRefineTolerance = 1e-15;
constexpr int kRefineIterations = 80;
// Sampled minima refined per task pose: those within this many steps of the nearest sample.
constexpr double kRefineWindowSteps = 4.0;
constexpr int kMaxPathSamples = 721;

// A pose in the centered, scaled coordinates: R = q, translation d.
struct State {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
};

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

Eigen::Quaterniond ExpRotation(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  const double half = 0.5 * angle;
  // sin(angle/2)/angle, with its series near 0.
  const double factor = angle < 1e-6 ? 0.5 - angle * angle / 48.0 : std::sin(half) / angle;
  return Eigen::Quaterniond(std::cos(half), factor * w.x(), factor * w.y(), factor * w.z());
}

// Rotation vector of q, angle in [0, pi].
Eigen::Vector3d LogRotation(const Eigen::Quaterniond& q) {
  double w = q.w();
  Eigen::Vector3d v = q.vec();
  if (w < 0.0) {
    w = -w;
    v = -v;
  }
  const double sine = v.norm();
  if (!(sine > 0.0)) return Eigen::Vector3d::Zero();
  return (2.0 * std::atan2(sine, w) / sine) * v;
}

// Left Jacobian of SO(3): exp(phi + e) = exp(J_l(phi) e) exp(phi) to first order in e.
Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d k = Hat(phi);
  if (angle < 1e-4) {
    return Eigen::Matrix3d::Identity() + 0.5 * k + (1.0 / 6.0) * k * k;
  }
  const double a2 = angle * angle;
  return Eigen::Matrix3d::Identity() + ((1.0 - std::cos(angle)) / a2) * k +
         ((angle - std::sin(angle)) / (a2 * angle)) * k * k;
}

// The pose reached from `base` by the twist delta = (w, v): R = exp([w]) R_base, d = d_base + v.
State Retract(const State& base, const Vector6d& delta) {
  State out;
  out.q = (ExpRotation(delta.head<3>()) * base.q).normalized();
  out.d = base.d + delta.tail<3>();
  return out;
}

// The twist that takes `base` to `x` (the inverse of Retract).
Vector6d Relative(const State& x, const State& base) {
  Vector6d delta;
  delta.head<3>() = LogRotation(x.q * base.q.conjugate());
  delta.tail<3>() = x.d - base.d;
  return delta;
}

// Pose error sqrt(|dd|^2 + angle^2) in units of L.
double Distance(const State& a, const State& b) {
  const Eigen::Quaterniond relative = a.q * b.q.conjugate();
  const double angle = 2.0 * std::atan2(relative.vec().norm(), std::abs(relative.w()));
  return std::hypot((a.d - b.d).norm(), angle);
}

// The unit null vector of the 5x6 Jacobian and (an estimate of) its smallest singular value:
// from the QR factorization of J^T with column pivoting, J^T P = Q R, the null vector is Q's last
// column (orthogonal to J's rows) and |R_55| is within a factor sqrt(5) of the smallest singular
// value (R's diagonal decreases), enough for the singularity test; a fraction of an SVD's cost,
// at every continuation step.
void NullSpace(const Matrix56d& jacobian, Vector6d* tangent, double* smallest_singular_value) {
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 6, 5>> qr(jacobian.transpose());
  const Matrix6d q = qr.householderQ();
  *tangent = q.col(5);
  *smallest_singular_value = std::abs(qr.matrixQR()(4, 4));
}

// det [J; t^T]: its sign orients the curve.
double Orientation(const Matrix56d& jacobian, const Vector6d& tangent) {
  Matrix6d augmented;
  augmented.topRows<5>() = jacobian;
  augmented.row(5) = tangent.transpose();
  return augmented.determinant();
}

// One dyad in the centered, scaled coordinates, evaluated relative to the first task pose.
struct Constraint {
  SpatialDyadType type = SpatialDyadType::kSS;
  Eigen::Vector3d moving_pivot = Eigen::Vector3d::Zero();  // SS, PS: c in E
  Eigen::Vector3d fixed_pivot = Eigen::Vector3d::Zero();   // SP: A in Sigma
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();       // PS: in Sigma; SP: in E
  double offset = 0.0;                                     // SP: plane offset h
  double radius = 0.0;                                     // SS
  // SS, PS: the constrained point at the first task pose (X_ref, in Sigma).
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  // SS: a = X_ref - A and c0 = |a|^2 - r^2; PS: c0 = n . X_ref - h.
  Eigen::Vector3d to_reference = Eigen::Vector3d::Zero();
  double constant = 0.0;
};

// Residuals (signed distances, units of L) and their Jacobian in the twist (w, v) at x.
//   SS: with u = X - X_ref, |X - A|^2 - r^2 = |u|^2 + 2 a . u + c0, divided by |X - A| + r. Each
//       term is small or computed once, so a sphere of radius 1e6 keeps full precision.
//   PS: n . u + c0.
//   SP: (R n) . (A - d) - h.
// Rows: dX = w x (R c) + v, so an SS/PS row is [((R c) x g)^T, g^T] with g the unit gradient in X;
// an SP row is [((R n) x (A - d))^T, -(R n)^T].
void Evaluate(const std::vector<Constraint>& constraints, const State& x, Vector5d* residuals,
              Matrix56d* jacobian) {
  const Eigen::Matrix3d rotation = x.q.toRotationMatrix();
  for (int i = 0; i < kDyadCount; ++i) {
    const Constraint& c = constraints[i];
    if (c.type == SpatialDyadType::kSP) {
      const Eigen::Vector3d normal = rotation * c.normal;
      const Eigen::Vector3d arm = c.fixed_pivot - x.d;
      (*residuals)(i) = normal.dot(arm) - c.offset;
      jacobian->block<1, 3>(i, 0) = normal.cross(arm).transpose();
      jacobian->block<1, 3>(i, 3) = -normal.transpose();
      continue;
    }
    const Eigen::Vector3d arm = rotation * c.moving_pivot;
    const Eigen::Vector3d u = arm + x.d - c.reference;
    Eigen::Vector3d gradient;
    if (c.type == SpatialDyadType::kSS) {
      const Eigen::Vector3d from_center = u + c.to_reference;
      const double distance = from_center.norm();
      const double denominator = distance + c.radius;
      const double numerator = u.squaredNorm() + 2.0 * c.to_reference.dot(u) + c.constant;
      (*residuals)(i) = denominator > 0.0 ? numerator / denominator : 0.0;
      gradient = distance > 0.0 ? Eigen::Vector3d(from_center / distance) : Eigen::Vector3d::Zero();
    } else {
      (*residuals)(i) = c.normal.dot(u) + c.constant;
      gradient = c.normal;
    }
    jacobian->block<1, 3>(i, 0) = arm.cross(gradient).transpose();
    jacobian->block<1, 3>(i, 3) = gradient.transpose();
  }
}

// Newton's method for the curve point x = Retract(base, delta) with tangent . delta = offset
// (the pseudo-arclength hyperplane), from the initial twist `delta`.
bool Project(const std::vector<Constraint>& constraints, const State& base, const Vector6d& tangent,
             double offset, Vector6d delta, State* out, Vector6d* delta_out, int* iterations) {
  double previous = kInfinity;
  Vector5d residuals;
  Matrix56d jacobian;
  for (int iteration = 1; iteration <= kNewtonIterations; ++iteration) {
    const State x = Retract(base, delta);
    Evaluate(constraints, x, &residuals, &jacobian);
    Matrix6d system;
    system.topRows<5>() = jacobian;
    system.block<5, 3>(0, 0) = jacobian.leftCols<3>() * LeftJacobian(delta.head<3>());
    system.row(5) = tangent.transpose();
    Vector6d rhs;
    rhs.head<5>() = -residuals;
    rhs(5) = offset - tangent.dot(delta);
    const Vector6d correction = system.partialPivLu().solve(rhs);
    if (!correction.allFinite()) return false;
    delta += correction;
    const double size = correction.norm();
    bool done = size <= kNewtonConverged;
    if (!done && iteration >= 2 && size > 0.5 * previous) {
      if (size > kNewtonFloor) return false;  // not converging
      done = true;                            // stalled at rounding noise
    }
    if (done) {
      *out = Retract(base, delta);
      *delta_out = delta;
      *iterations = iteration;
      return true;
    }
    previous = size;
  }
  return false;
}

// Minimum-norm Newton projection of a pose onto the five constraints.
bool ProjectOntoConstraints(const std::vector<Constraint>& constraints, State* x) {
  double previous = kInfinity;
  Vector5d residuals;
  Matrix56d jacobian;
  for (int iteration = 1; iteration <= 2 * kNewtonIterations; ++iteration) {
    Evaluate(constraints, *x, &residuals, &jacobian);
    const Vector6d correction = -jacobian.completeOrthogonalDecomposition().solve(residuals).eval();
    if (!correction.allFinite()) return false;
    *x = Retract(*x, correction);
    const double size = correction.norm();
    if (size <= kNewtonConverged) return true;
    if (iteration >= 3 && size > 0.5 * previous) return size <= kNewtonFloor;
    previous = size;
  }
  return false;
}

// A sample of the traced curve: the pose, the unit tangent (in the curve's forward direction)
// and the curve parameter (accumulated pseudo-arclength, 0 at the first pose).
struct Sample {
  State x;
  Vector6d tangent = Vector6d::Zero();
  double parameter = 0.0;
};

enum class CurveEnd { kClosed, kSingular, kBifurcation, kCollapsed, kStepLimit };

const char* CurveEndText(CurveEnd end) {
  switch (end) {
    case CurveEnd::kClosed:
      return "closes";
    case CurveEnd::kSingular:
      return "stops at a singular configuration";
    case CurveEnd::kBifurcation:
      return "stops at a singular (bifurcation) configuration it would cross";
    case CurveEnd::kCollapsed:
      return "stops where the step collapses (a singular configuration)";
    case CurveEnd::kStepLimit:
      return "stops at the step limit";
  }
  return "";
}

struct Trace {
  std::vector<Sample> samples;  // samples[0] is the start
  CurveEnd end = CurveEnd::kStepLimit;
  double closing_offset = 0.0;  // closed: the parameter step from the last sample to the start
  int steps = 0;
};

// Pseudo-arclength continuation from `start` along `tangent`. With `detect_closure`, stops when
// the curve comes back to the start heading the same way.
Trace TraceDirection(const std::vector<Constraint>& constraints, const State& start,
                     const Vector6d& tangent, bool detect_closure,
                     const PlatformMotionOptions& options) {
  Trace trace;
  trace.samples.push_back({start, tangent, 0.0});
  Vector5d residuals;
  Matrix56d jacobian;
  Evaluate(constraints, start, &residuals, &jacobian);
  double orientation = Orientation(jacobian, tangent);
  const double max_step = options.step;
  const double min_step = kMinStepShare * max_step;
  double step = max_step;
  // Each accepted step follows at most ~log2(1 / kMinStepShare) rejected ones.
  const long max_attempts = 64L * std::max(options.max_steps, 1);
  long attempts = 0;
  while (trace.steps < options.max_steps) {
    if (++attempts > max_attempts) {
      trace.end = CurveEnd::kStepLimit;
      return trace;
    }
    const Sample current = trace.samples.back();
    State next;
    Vector6d delta;
    int iterations = 0;
    bool accepted = Project(constraints, current.x, current.tangent, step, step * current.tangent,
                            &next, &delta, &iterations) &&
                    (delta - step * current.tangent).norm() <= kMaxCorrectionShare * step;
    Vector6d next_tangent;
    double smallest = 0.0, next_orientation = 0.0;
    bool crossed = false;
    if (accepted) {
      Evaluate(constraints, next, &residuals, &jacobian);
      NullSpace(jacobian, &next_tangent, &smallest);
      if (next_tangent.dot(delta) < 0.0) next_tangent = -next_tangent;
      accepted = next_tangent.allFinite() && next_tangent.dot(current.tangent) >= kMinTangentCosine;
      // det [J; t^T] keeps its sign along a regular curve and changes it where the curve passes
      // through a simple bifurcation point (where J loses rank). Such a step is rejected, so the
      // halving steps close in on the bifurcation point and the curve ends just before it.
      next_orientation = Orientation(jacobian, next_tangent);
      crossed = accepted && (next_orientation > 0.0) != (orientation > 0.0);
      accepted = accepted && !crossed;
    }
    if (!accepted) {
      step *= 0.5;
      if (step < min_step) {
        trace.end = crossed ? CurveEnd::kBifurcation : CurveEnd::kCollapsed;
        return trace;
      }
      continue;
    }
    ++trace.steps;
    if (detect_closure && trace.samples.size() >= 3 && current.tangent.dot(tangent) > 0.0) {
      // Is the start on the arc just traversed? It lies in a hyperplane between the two samples,
      // and the curve point in that hyperplane (reached from the predictor) is the start.
      const Vector6d to_start = Relative(start, current.x);
      const double offset = current.tangent.dot(to_start);
      if (offset >= 0.0 && offset <= step &&
          (to_start - offset * current.tangent).norm() <= kMaxCorrectionShare * step) {
        State on_curve;
        Vector6d unused_delta;
        int unused_iterations = 0;
        if (Project(constraints, current.x, current.tangent, offset, offset * current.tangent,
                    &on_curve, &unused_delta, &unused_iterations) &&
            Distance(on_curve, start) <= kClosureDistance) {
          trace.end = CurveEnd::kClosed;
          trace.closing_offset = offset;
          return trace;
        }
      }
    }
    orientation = next_orientation;
    trace.samples.push_back({next, next_tangent, current.parameter + step});
    if (smallest < options.singular_tolerance) {
      trace.end = CurveEnd::kSingular;
      return trace;
    }
    if (iterations <= 4) step = std::min(max_step, 2.0 * step);
  }
  trace.end = CurveEnd::kStepLimit;
  return trace;
}

// The traced curve: samples in the forward direction (parameter 0 at the first pose).
struct Curve {
  std::vector<Sample> samples;
  bool closed = false;
  double closing_offset = 0.0;  // closed: parameter step from the last sample back to samples[0]
  double total = 0.0;           // closed: the loop's parameter length
};

// The gradient test of a task pose along the curve: g = tangent . (twist from x to the pose).
// The squared distance decreases along the tangent where g > 0.
double Slope(const Vector6d& tangent, const State& x, const State& pose) {
  return tangent.dot(Relative(pose, x));
}

// The nearest point to `pose` on the segment from samples a to b (slope > 0 at a, <= 0 at b):
// root finding (Illinois false position) of the slope along the curve parameterized by the offset
// in a's hyperplane. Returns the smallest distance found and its offset.
bool RefineOnSegment(const std::vector<Constraint>& constraints, const Sample& a, const Sample& b,
                     const State& pose, double* distance, double* offset_at) {
  const double length = a.tangent.dot(Relative(b.x, a.x));
  if (!(length > 0.0)) return false;
  double low = 0.0, high = length;
  double slope_low = Slope(a.tangent, a.x, pose);
  double slope_high = Slope(b.tangent, b.x, pose);
  *distance = std::min(Distance(a.x, pose), Distance(b.x, pose));
  *offset_at = Distance(a.x, pose) <= Distance(b.x, pose) ? 0.0 : length;
  if (!(slope_low > 0.0) || slope_high > 0.0) return false;
  int side = 0;  // the side kept last time (Illinois)
  double previous = kInfinity;
  Vector5d residuals;
  Matrix56d jacobian;
  for (int iteration = 0; iteration < kRefineIterations; ++iteration) {
    double s = (low * slope_high - high * slope_low) / (slope_high - slope_low);
    if (!(s > low && s < high)) s = 0.5 * (low + high);
    State x;
    Vector6d delta;
    int iterations = 0;
    if (!Project(constraints, a.x, a.tangent, s, s * a.tangent, &x, &delta, &iterations)) {
      return false;
    }
    Evaluate(constraints, x, &residuals, &jacobian);
    Vector6d tangent;
    double unused_smallest = 0.0;
    NullSpace(jacobian, &tangent, &unused_smallest);
    if (tangent.dot(a.tangent) < 0.0) tangent = -tangent;
    const double slope = Slope(tangent, x, pose);
    const double here = Distance(x, pose);
    if (here < *distance) {
      *distance = here;
      *offset_at = s;
    }
    if (slope > 0.0) {
      low = s;
      slope_low = slope;
      if (side == 1) slope_high *= 0.5;
      side = 1;
    } else {
      high = s;
      slope_high = slope;
      if (side == -1) slope_low *= 0.5;
      side = -1;
    }
    if (std::abs(s - previous) <= kRefineTolerance || high - low <= kRefineTolerance ||
        slope == 0.0) {
      break;
    }
    previous = s;
  }
  return true;
}

// Where a task pose is nearest to the curve: its distance and curve parameter.
struct Location {
  double distance = kInfinity;
  double parameter = 0.0;
};

Location Locate(const std::vector<Constraint>& constraints, const Curve& curve, const State& pose,
                double max_step) {
  const int count = static_cast<int>(curve.samples.size());
  std::vector<double> distances(count), slopes(count);
  Location best;
  for (int i = 0; i < count; ++i) {
    const Sample& sample = curve.samples[i];
    distances[i] = Distance(sample.x, pose);
    slopes[i] = Slope(sample.tangent, sample.x, pose);
    if (distances[i] < best.distance) best = {distances[i], sample.parameter};
  }
  const double window = best.distance + kRefineWindowSteps * max_step;
  const int segments = curve.closed ? count : count - 1;
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % count;
    if (!(slopes[i] > 0.0 && slopes[j] <= 0.0)) continue;
    if (std::min(distances[i], distances[j]) > window) continue;
    double distance = kInfinity, offset = 0.0;
    // On a failure RefineOnSegment still returns the better end sample, already counted.
    if (!RefineOnSegment(constraints, curve.samples[i], curve.samples[j], pose, &distance,
                         &offset)) {
      continue;
    }
    if (distance < best.distance) best = {distance, curve.samples[i].parameter + offset};
  }
  return best;
}

DualQuaternion ToPose(const State& x, const Eigen::Vector3d& centroid, double length) {
  DualQuaternion pose;
  pose.q = Eigen::Vector4d(x.q.x(), x.q.y(), x.q.z(), x.q.w());
  if (pose.q[3] < 0.0) pose.q = -pose.q;
  const Eigen::Vector3d translation = length * x.d + centroid;
  pose.g =
      0.5 * QuaternionProduct(
                Eigen::Vector4d(translation.x(), translation.y(), translation.z(), 0.0), pose.q);
  return pose;
}

bool IsFinite(const DualQuaternion& pose) { return pose.q.allFinite() && pose.g.allFinite(); }

std::string Format(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

// The order in which a direction meets the located poses: (key, index) pairs sorted.
std::vector<std::pair<double, int>> OrderKeys(const std::vector<double>& parameters,
                                              const std::vector<bool>& met, const Curve& curve,
                                              int direction) {
  std::vector<std::pair<double, int>> keys;
  // Open curves: the far side comes after the near side, past the largest parameter distance.
  double span = 0.0;
  for (const Sample& sample : curve.samples) span = std::max(span, std::abs(sample.parameter));
  for (size_t j = 0; j < parameters.size(); ++j) {
    if (!met[j]) continue;
    const double signed_parameter = direction * parameters[j];
    double key = 0.0;
    if (j == 0) {
      key = -1.0;  // the first pose starts the order
    } else if (curve.closed) {
      key = std::fmod(signed_parameter, curve.total);
      if (key < 0.0) key += curve.total;
    } else {
      key = signed_parameter >= 0.0 ? signed_parameter : 2.0 * span + 1.0 - signed_parameter;
    }
    keys.emplace_back(key, static_cast<int>(j));
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

}  // namespace

PlatformMotionReport TracePlatform(const std::vector<SpatialDyad>& dyads,
                                   const std::vector<DualQuaternion>& task_poses, double length,
                                   const PlatformMotionOptions& options) {
  PlatformMotionReport report;
  if (static_cast<int>(dyads.size()) != kDyadCount) {
    report.note = "a platform needs exactly five dyads, got " + std::to_string(dyads.size()) + ".";
    return report;
  }
  if (task_poses.empty()) {
    report.note = "there are no task poses.";
    return report;
  }
  if (!(std::isfinite(length) && length > 0.0)) {
    report.note = "the characteristic length must be positive and finite.";
    return report;
  }
  if (!(options.step > 0.0 && std::isfinite(options.step)) || options.max_steps < 1) {
    report.note = "the continuation step must be positive and max_steps at least 1.";
    return report;
  }
  for (const SpatialDyad& dyad : dyads) {
    if (!dyad.AllFinite()) {
      report.note = "a dyad has a non-finite number.";
      return report;
    }
    if (dyad.type != SpatialDyadType::kSS && !(dyad.plane_normal.norm() > 0.0)) {
      report.note = "a plane dyad has a zero normal.";
      return report;
    }
  }
  for (const DualQuaternion& pose : task_poses) {
    if (!IsFinite(pose) || !(pose.q.norm() > 0.0)) {
      report.note = "a task pose has a non-finite number or a zero rotation quaternion.";
      return report;
    }
  }

  // Centered, scaled coordinates.
  std::vector<State> poses(task_poses.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<Eigen::Matrix3d> rotations(task_poses.size());
  std::vector<Eigen::Vector3d> translations(task_poses.size());
  for (size_t j = 0; j < task_poses.size(); ++j) {
    const DualQuaternion unit = task_poses[j].Normalized();
    rotations[j] = unit.Rotation();
    translations[j] = unit.Translation();
    poses[j].q = Eigen::Quaterniond(unit.q[3], unit.q[0], unit.q[1], unit.q[2]);
    centroid += translations[j];
  }
  centroid /= static_cast<double>(task_poses.size());
  for (size_t j = 0; j < task_poses.size(); ++j) {
    poses[j].d = (translations[j] - centroid) / length;
  }

  // The first pose must satisfy every dyad.
  int worst_dyad = 0;
  double worst_residual = 0.0;
  for (int i = 0; i < kDyadCount; ++i) {
    const double residual = std::abs(dyads[i].Residual(rotations[0], translations[0]));
    if (!(residual <= worst_residual)) {
      worst_residual = residual;
      worst_dyad = i;
    }
  }
  if (!(worst_residual <= options.assembly_tolerance * length)) {
    report.note = "the first task pose does not satisfy dyad " + std::to_string(worst_dyad) +
                  " (residual " + Format(worst_residual / length) + " L, tolerance " +
                  Format(options.assembly_tolerance) + " L).";
    return report;
  }

  std::vector<Constraint> constraints(kDyadCount);
  for (int i = 0; i < kDyadCount; ++i) {
    const SpatialDyad& dyad = dyads[i];
    Constraint& c = constraints[i];
    c.type = dyad.type;
    if (dyad.type == SpatialDyadType::kSP) {
      c.fixed_pivot = (dyad.fixed_pivot - centroid) / length;
      c.normal = dyad.plane_normal.normalized();
      c.offset = dyad.plane_offset / dyad.plane_normal.norm() / length;
      continue;
    }
    c.moving_pivot = dyad.moving_pivot / length;
    const Eigen::Vector3d reference = rotations[0] * dyad.moving_pivot + translations[0];
    c.reference = (reference - centroid) / length;
    if (dyad.type == SpatialDyadType::kSS) {
      // a and c0 from the original numbers, once.
      c.radius = std::abs(dyad.radius) / length;
      const Eigen::Vector3d to_reference = reference - dyad.fixed_pivot;
      const double distance = to_reference.norm();
      c.to_reference = to_reference / length;
      c.constant = ((distance - std::abs(dyad.radius)) / length) *
                   ((distance + std::abs(dyad.radius)) / length);
    } else {
      c.normal = dyad.plane_normal.normalized();
      c.constant =
          (c.normal.dot(reference) - dyad.plane_offset / dyad.plane_normal.norm()) / length;
    }
  }

  State start = poses[0];
  if (!ProjectOntoConstraints(constraints, &start)) {
    report.note = "Newton's method could not project the first task pose onto the dyads.";
    return report;
  }
  report.assembles = true;

  Vector5d residuals;
  Matrix56d jacobian;
  Evaluate(constraints, start, &residuals, &jacobian);
  Vector6d tangent;
  double smallest = 0.0;
  NullSpace(jacobian, &tangent, &smallest);
  if (!(smallest >= options.singular_tolerance) || !tangent.allFinite()) {
    report.note =
        "the first task pose is a singular configuration of the platform (smallest "
        "singular value " +
        Format(smallest) + ").";
    report.path.push_back(ToPose(start, centroid, length));
    report.order.push_back(0);
    for (const State& pose : poses) {
      report.pose_errors.push_back(length * Distance(start, pose));
      report.max_pose_error = std::max(report.max_pose_error, report.pose_errors.back());
    }
    return report;
  }

  // Trace forward; if the curve does not close, trace backward too and join.
  Curve curve;
  const Trace forward = TraceDirection(constraints, start, tangent, true, options);
  report.steps = forward.steps;
  CurveEnd backward_end = CurveEnd::kClosed;
  if (forward.end == CurveEnd::kClosed) {
    curve.samples = forward.samples;
    curve.closed = true;
    curve.closing_offset = forward.closing_offset;
    curve.total = forward.samples.back().parameter + forward.closing_offset;
  } else {
    const Trace backward = TraceDirection(constraints, start, -tangent, false, options);
    report.steps += backward.steps;
    backward_end = backward.end;
    for (size_t k = backward.samples.size(); k-- > 1;) {
      Sample sample = backward.samples[k];
      sample.tangent = -sample.tangent;
      sample.parameter = -sample.parameter;
      curve.samples.push_back(sample);
    }
    curve.samples.insert(curve.samples.end(), forward.samples.begin(), forward.samples.end());
  }
  report.closed = curve.closed;

  // Locate the task poses.
  const size_t count = poses.size();
  std::vector<double> parameters(count, 0.0);
  std::vector<bool> met(count, false);
  report.pose_errors.assign(count, 0.0);
  std::vector<int> missed;
  double worst_missed = 0.0;
  for (size_t j = 0; j < count; ++j) {
    const Location location = Locate(constraints, curve, poses[j], options.step);
    report.pose_errors[j] = length * location.distance;
    report.max_pose_error = std::max(report.max_pose_error, report.pose_errors[j]);
    parameters[j] = j == 0 ? 0.0 : location.parameter;
    // The curve starts at the first pose's projection.
    met[j] = j == 0 || location.distance <= options.pose_tolerance;
    if (!met[j]) {
      missed.push_back(static_cast<int>(j));
      worst_missed = std::max(worst_missed, location.distance);
    }
  }
  report.one_branch = missed.empty();

  // The reported direction: task pose 1 (or the lowest-index other pose met) earlier.
  int direction = 1;
  int probe = -1;
  for (size_t j = 1; j < count && probe < 0; ++j) {
    if (met[j]) probe = static_cast<int>(j);
  }
  const std::vector<std::pair<double, int>> plus = OrderKeys(parameters, met, curve, 1);
  const std::vector<std::pair<double, int>> minus = OrderKeys(parameters, met, curve, -1);
  if (probe >= 0) {
    auto rank = [probe](const std::vector<std::pair<double, int>>& keys) {
      for (size_t k = 0; k < keys.size(); ++k) {
        if (keys[k].second == probe) return std::make_pair(static_cast<double>(k), keys[k].first);
      }
      return std::make_pair(kInfinity, kInfinity);
    };
    if (rank(minus) < rank(plus)) direction = -1;
  }
  for (const auto& key : direction > 0 ? plus : minus) report.order.push_back(key.second);

  // The path, in the reported direction.
  std::vector<const State*> path;
  if (curve.closed) {
    const int n = static_cast<int>(curve.samples.size());
    path.push_back(&curve.samples[0].x);
    for (int k = 1; k < n; ++k) path.push_back(&curve.samples[direction > 0 ? k : n - k].x);
    path.push_back(&curve.samples[0].x);
  } else {
    for (const Sample& sample : curve.samples) path.push_back(&sample.x);
    if (direction < 0) std::reverse(path.begin(), path.end());
  }
  if (static_cast<int>(path.size()) <= kMaxPathSamples) {
    for (const State* x : path) report.path.push_back(ToPose(*x, centroid, length));
  } else {
    const double stride = static_cast<double>(path.size() - 1) / (kMaxPathSamples - 1);
    for (int k = 0; k < kMaxPathSamples; ++k) {
      const size_t index = std::min(path.size() - 1, static_cast<size_t>(std::lround(k * stride)));
      report.path.push_back(ToPose(*path[index], centroid, length));
    }
  }

  // The note: the first thing that is false.
  if (!report.one_branch) {
    std::string list;
    for (size_t k = 0; k < missed.size(); ++k) {
      list += (k == 0 ? "" : (k + 1 == missed.size() ? " and " : ", ")) + std::to_string(missed[k]);
    }
    report.note = std::string(missed.size() == 1 ? "task pose " : "task poses ") + list +
                  (missed.size() == 1 ? " is" : " are") +
                  " not met by the curve through the first pose (nearest approach " +
                  Format(worst_missed) + " L)";
    if (!curve.closed) {
      report.note += std::string(", which forward ") + CurveEndText(forward.end) +
                     " and backward " + CurveEndText(backward_end);
    }
    report.note += ".";
  } else if (!curve.closed) {
    report.note = std::string("the traced curve does not close: forward it ") +
                  CurveEndText(forward.end) + ", backward it " + CurveEndText(backward_end) + ".";
  }
  return report;
}

}  // namespace linkfit
