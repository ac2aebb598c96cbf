#include "lib/mechanism.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace linkfit {
namespace {

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// Solutions theta of a cos(theta) + b sin(theta) = c, theta = base +- spread with
// (cos base, sin base) = (a, b) / rho and cos spread = c / rho, rho = |(a, b)|; a near-tangent
// case within `slack` (relative to rho) is taken as the double root. Each root's cosine and
// sine come from the angle-sum formulas (no trigonometric call), its angle from one atan2.
int SolveTrigLinear(double a, double b, double c, double slack, double thetas[2],
                    Eigen::Vector2d unit[2]) {
  const double rho = std::sqrt(a * a + b * b);  // hypot is slow, and no length overflows
  if (!(rho > 0.0)) return 0;
  double ratio = c / rho;
  if (std::abs(ratio) > 1.0) {
    if (std::abs(ratio) - 1.0 > slack) return 0;
    ratio = std::copysign(1.0, ratio);
  }
  const double ca = a / rho, sa = b / rho;                                      // base
  const double cs = ratio, ss = std::sqrt(std::max(0.0, 1.0 - ratio * ratio));  // spread
  unit[0] = Eigen::Vector2d(ca * cs - sa * ss, sa * cs + ca * ss);
  unit[1] = Eigen::Vector2d(ca * cs + sa * ss, sa * cs - ca * ss);
  for (int i = 0; i < 2; ++i) thetas[i] = std::atan2(unit[i].y(), unit[i].x());
  return 2;
}

// The moving pivot of an RR or PR input dyad, in Sigma, at joint value `value`.
Eigen::Vector2d InputPivotInFixed(const PlanarDyad& input, double value) {
  if (input.type == DyadType::kRR) {
    return input.fixed_pivot + input.radius * Eigen::Vector2d(std::cos(value), std::sin(value));
  }
  return input.line_point + value * input.line_direction;
}

}  // namespace

const char* FourBarTypeName(FourBarType type) {
  switch (type) {
    case FourBarType::k4R:
      return "4R";
    case FourBarType::kSliderCrank:
      return "slider-crank";
    case FourBarType::kInvertedSliderCrank:
      return "inverted slider-crank";
    case FourBarType::kDoubleSlider:
      return "double slider";
    case FourBarType::kRPRP:
      return "RPRP";
    case FourBarType::kInvertedDoubleSlider:
      return "inverted double slider";
  }
  return "?";
}

FourBarType ClassifyFourBar(DyadType a, DyadType b) {
  const int rr = (a == DyadType::kRR) + (b == DyadType::kRR);
  const int pr = (a == DyadType::kPR) + (b == DyadType::kPR);
  const int rp = (a == DyadType::kRP) + (b == DyadType::kRP);
  if (rr == 2) return FourBarType::k4R;
  if (rr == 1) return pr == 1 ? FourBarType::kSliderCrank : FourBarType::kInvertedSliderCrank;
  if (pr == 2) return FourBarType::kDoubleSlider;
  if (rp == 2) return FourBarType::kInvertedDoubleSlider;
  return FourBarType::kRPRP;
}

std::string GrashofType(const PlanarDyad& input, const PlanarDyad& output, double length) {
  if (input.type != DyadType::kRR || output.type != DyadType::kRR) return "";
  const double ground = (input.fixed_pivot - output.fixed_pivot).norm();
  const double coupler = (input.moving_pivot - output.moving_pivot).norm();
  const double links[4] = {ground, input.radius, coupler, output.radius};
  const double shortest = *std::min_element(links, links + 4);
  const double longest = *std::max_element(links, links + 4);
  const double sum = links[0] + links[1] + links[2] + links[3];
  const double margin = (sum - shortest - longest) - (shortest + longest);
  if (std::abs(margin) <= 1e-9 * length) return "change-point";
  if (margin < 0.0) return "triple-rocker";
  if (shortest == ground) return "double-crank";
  if (shortest == input.radius) return "crank-rocker";
  if (shortest == output.radius) return "rocker-crank";
  return "double-rocker";
}

double InputValue(const PlanarDyad& dyad, const PlanarPose& pose) {
  switch (dyad.type) {
    case DyadType::kRR: {
      const Eigen::Vector2d arm = pose.ToFixed(dyad.moving_pivot) - dyad.fixed_pivot;
      return std::atan2(arm.y(), arm.x());
    }
    case DyadType::kPR:
      return (pose.ToFixed(dyad.moving_pivot) - dyad.line_point).dot(dyad.line_direction);
    case DyadType::kRP:
      return pose.theta;
  }
  return 0.0;
}

void OutputTurnEquation(const PlanarDyad& output, const Eigen::Vector2d& m1,
                        const Eigen::Vector2d& pivot, double* a, double* b, double* c,
                        double* scale) {
  if (output.type == DyadType::kRR) {
    // |R v + w| = r2 with v = m2 - m1 (E), w = M1 - F2 (Sigma):
    // 2 w . R v = r2^2 - |v|^2 - |w|^2.
    const Eigen::Vector2d v = output.moving_pivot - m1, w = pivot - output.fixed_pivot;
    *a = 2.0 * w.dot(v);
    *b = 2.0 * (w.y() * v.x() - w.x() * v.y());
    *c = output.radius * output.radius - v.squaredNorm() - w.squaredNorm();
    // A length slack t on the radius moves c by 2 r2 t against rho = 2 |v||w|.
    *scale = std::max(v.norm() * w.norm(), 1e-300) / std::max(output.radius, 1e-300);
  } else if (output.type == DyadType::kPR) {
    // n . (R v + M1) = n . line_point, n the line normal.
    const Eigen::Vector2d v = output.moving_pivot - m1, n = Perp(output.line_direction);
    *a = n.dot(v);
    *b = n.y() * v.x() - n.x() * v.y();
    *c = n.dot(output.line_point - pivot);
    *scale = std::max(v.norm(), 1e-300);
  } else {
    // The fixed pivot F2 lies on the line of E: (R n_E) . (F2 - M1) = n_E . (q_E - m1).
    const Eigen::Vector2d n = Perp(output.line_direction), u = output.fixed_pivot - pivot;
    *a = n.dot(u);
    *b = n.x() * u.y() - n.y() * u.x();
    *c = n.dot(output.line_point - m1);
    *scale = std::max(u.norm(), 1e-300);
  }
}

namespace {

// The configurations of an RR or PR input whose moving pivot is at `pivot` in Sigma: the coupler
// turns about it by theta, P(p_E) = R(theta) (p_E - m1) + M1, and the output constraint becomes
// a cos(theta) + b sin(theta) = c.
int AssembleAtInputPin(const PlanarDyad& input, const PlanarDyad& output,
                       const Eigen::Vector2d& pivot, double tolerance,
                       std::vector<PlanarPose>* coupler_poses) {
  const Eigen::Vector2d& m1 = input.moving_pivot;
  double a = 0.0, b = 0.0, c = 0.0, scale = 1.0;
  OutputTurnEquation(output, m1, pivot, &a, &b, &c, &scale);
  double thetas[2];
  Eigen::Vector2d unit[2];
  const int count = SolveTrigLinear(a, b, c, tolerance / scale, thetas, unit);
  for (int i = 0; i < count; ++i) {
    PlanarPose pose;
    pose.theta = thetas[i];
    pose.origin_in_fixed = pivot - Eigen::Vector2d(unit[i].x() * m1.x() - unit[i].y() * m1.y(),
                                                   unit[i].y() * m1.x() + unit[i].x() * m1.y());
    coupler_poses->push_back(pose);
  }
  return count;
}

}  // namespace

int AssembleFourBar(const PlanarDyad& input, const PlanarDyad& output, double input_value,
                    double tolerance, std::vector<PlanarPose>* coupler_poses) {
  coupler_poses->clear();
  if (input.type != DyadType::kRP) {
    return AssembleAtInputPin(input, output, InputPivotInFixed(input, input_value), tolerance,
                              coupler_poses);
  }
  // RP input: the coupler angle is the input; the RP constraint puts the origin d on a line,
  // (R n_E) . d = (R n_E) . F1 - n_E . q_E, i.e. d = d0 + t e.
  const double theta = input_value;
  const Eigen::Matrix2d rotation = Rotation2(theta);
  const Eigen::Vector2d normal = rotation * Perp(input.line_direction);
  const double offset =
      normal.dot(input.fixed_pivot) - Perp(input.line_direction).dot(input.line_point);
  const Eigen::Vector2d d0 = offset * normal, e = Perp(normal);
  std::vector<double> ts;
  if (output.type == DyadType::kRR) {
    // |R m2 + d0 + t e - F2| = r2: t^2 + 2 t (e . g) + |g|^2 - r2^2 = 0, g = R m2 + d0 - F2.
    const Eigen::Vector2d g = rotation * output.moving_pivot + d0 - output.fixed_pivot;
    const double half_b = e.dot(g);
    double discriminant = half_b * half_b - (g.squaredNorm() - output.radius * output.radius);
    if (discriminant < 0.0 &&
        discriminant > -2.0 * tolerance * std::max(output.radius, tolerance)) {
      discriminant = 0.0;
    }
    if (discriminant >= 0.0) {
      ts.push_back(-half_b + std::sqrt(discriminant));
      ts.push_back(-half_b - std::sqrt(discriminant));
    }
  } else {
    // One linear equation n2 . d = h2 in t.
    Eigen::Vector2d n2;
    double h2 = 0.0;
    if (output.type == DyadType::kPR) {
      n2 = Perp(output.line_direction);
      h2 = n2.dot(output.line_point) - n2.dot(rotation * output.moving_pivot);
    } else {
      n2 = rotation * Perp(output.line_direction);
      h2 = n2.dot(output.fixed_pivot) - Perp(output.line_direction).dot(output.line_point);
    }
    const double denominator = n2.dot(e);
    if (std::abs(denominator) > 1e-12) ts.push_back((h2 - n2.dot(d0)) / denominator);
  }
  for (double t : ts) {
    PlanarPose pose;
    pose.theta = WrapAngle(theta);
    pose.origin_in_fixed = d0 + t * e;
    coupler_poses->push_back(pose);
  }
  return static_cast<int>(coupler_poses->size());
}

int AssembleFourBarAtPose(const PlanarDyad& input, const PlanarDyad& output, const PlanarPose& pose,
                          double tolerance, std::vector<PlanarPose>* coupler_poses,
                          double* input_value) {
  if (input.type == DyadType::kRR) {
    const Eigen::Vector2d arm = pose.ToFixed(input.moving_pivot) - input.fixed_pivot;
    *input_value = std::atan2(arm.y(), arm.x());
    const double norm = arm.norm();
    if (norm > 0.0) {
      coupler_poses->clear();
      return AssembleAtInputPin(input, output, input.fixed_pivot + (input.radius / norm) * arm,
                                tolerance, coupler_poses);
    }
  } else {
    *input_value = InputValue(input, pose);
  }
  return AssembleFourBar(input, output, *input_value, tolerance, coupler_poses);
}

std::optional<double> MaxAssembledPoseError(const PlanarDyad& input, const PlanarDyad& output,
                                            const std::vector<PlanarPose>& poses, double length) {
  double worst = 0.0;
  std::vector<PlanarPose> assembled;
  const double tolerance = 1e-9 * length;
  for (const PlanarPose& pose : poses) {
    double value = 0.0;
    if (AssembleFourBarAtPose(input, output, pose, tolerance, &assembled, &value) == 0) {
      return std::nullopt;
    }
    double best = std::numeric_limits<double>::infinity();
    for (const PlanarPose& candidate : assembled) {
      best = std::min(best, PoseError(candidate, pose, length));
    }
    worst = std::max(worst, best);
  }
  return worst;
}

}  // namespace linkfit
