#include "lib/spatial_pose.h"

#include <Eigen/Geometry>
#include <cmath>

namespace linkfit {

namespace {

// Vector (first three) part of a quaternion stored as (x, y, z, w).
Eigen::Vector3d VectorPart(const Eigen::Vector4d& a) { return a.head<3>(); }

// The pure quaternion (v, 0).
Eigen::Vector4d PureQuaternion(const Eigen::Vector3d& v) {
  return Eigen::Vector4d(v.x(), v.y(), v.z(), 0.0);
}

// Dual part of seed 000 eq. 5: g = 1/2 D(d) q, which is the Hamilton product 1/2 (d, 0) q.
Eigen::Vector4d DualPart(const Eigen::Vector3d& translation, const Eigen::Vector4d& q) {
  return 0.5 * QuaternionProduct(PureQuaternion(translation), q);
}

}  // namespace

Eigen::Vector4d QuaternionProduct(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  // (va, wa)(vb, wb) = (wa vb + wb va + va x vb, wa wb - va . vb).
  const Eigen::Vector3d va = VectorPart(a), vb = VectorPart(b);
  const double wa = a[3], wb = b[3];
  const Eigen::Vector3d v = wa * vb + wb * va + va.cross(vb);
  return Eigen::Vector4d(v.x(), v.y(), v.z(), wa * wb - va.dot(vb));
}

Eigen::Vector4d QuaternionConjugate(const Eigen::Vector4d& a) {
  return Eigen::Vector4d(-a[0], -a[1], -a[2], a[3]);
}

DualQuaternion DualQuaternion::FromRotationTranslation(const Eigen::Matrix3d& rotation,
                                                       const Eigen::Vector3d& translation) {
  // Eigen's matrix-to-quaternion conversion picks the largest of the diagonal-based candidates
  // (Shepperd's method), so it stays accurate for rotations near 180 degrees where q4 -> 0.
  Eigen::Quaterniond quaternion(rotation);
  quaternion.normalize();
  DualQuaternion out;
  // Seed 000 eq. 4 with q4 = cos(theta/2) >= 0 (theta in [0, pi]); q and -q are the same pose.
  out.q = Eigen::Vector4d(quaternion.x(), quaternion.y(), quaternion.z(), quaternion.w());
  if (out.q[3] < 0.0) out.q = -out.q;
  out.g = DualPart(translation, out.q);  // seed 000 eq. 5
  return out;
}

DualQuaternion DualQuaternion::FromAxisAngle(const Eigen::Vector3d& axis, double angle,
                                             const Eigen::Vector3d& translation) {
  // Seed 000 eq. 4, taken literally: q = (s sin(theta/2), cos(theta/2)). No sign is
  // normalized here, so an angle beyond pi gives q4 < 0 (the same pose as -q).
  const Eigen::Vector3d unit_axis = axis.normalized();
  const double half = 0.5 * angle;
  const Eigen::Vector3d v = std::sin(half) * unit_axis;
  DualQuaternion out;
  out.q = Eigen::Vector4d(v.x(), v.y(), v.z(), std::cos(half));
  out.g = DualPart(translation, out.q);  // seed 000 eq. 5
  return out;
}

Eigen::Matrix3d DualQuaternion::Rotation() const {
  // Seed 000 eq. 6.
  const double q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3];
  Eigen::Matrix3d r;
  r << q4 * q4 + q1 * q1 - q2 * q2 - q3 * q3, 2.0 * (q1 * q2 - q4 * q3), 2.0 * (q1 * q3 + q4 * q2),
      2.0 * (q1 * q2 + q4 * q3), q4 * q4 - q1 * q1 + q2 * q2 - q3 * q3, 2.0 * (q2 * q3 - q4 * q1),
      2.0 * (q1 * q3 - q4 * q2), 2.0 * (q2 * q3 + q4 * q1), q4 * q4 - q1 * q1 - q2 * q2 + q3 * q3;
  return r;
}

Eigen::Vector3d DualQuaternion::Translation() const {
  // Seed 000 eq. 7 (the vector part of 2 g q*).
  const double q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3];
  const double g1 = g[0], g2 = g[1], g3 = g[2], g4 = g[3];
  return -2.0 * Eigen::Vector3d(g4 * q1 - g1 * q4 + g2 * q3 - g3 * q2,
                                g4 * q2 - g2 * q4 + g3 * q1 - g1 * q3,
                                g4 * q3 - g3 * q4 + g1 * q2 - g2 * q1);
}

void DualQuaternion::ToAxisAngle(Eigen::Vector3d* axis, double* angle) const {
  // Inverse of seed 000 eq. 4. q and -q are the same rotation; take the one with q4 >= 0 so that
  // theta = 2 atan2(|v|, q4) lies in [0, pi]. atan2 stays accurate near 0 and near pi.
  Eigen::Vector4d unit = q;
  if (unit[3] < 0.0) unit = -unit;
  const Eigen::Vector3d v = VectorPart(unit);
  const double sine_norm = v.norm();
  *angle = 2.0 * std::atan2(sine_norm, unit[3]);
  if (sine_norm > 0.0) {
    *axis = v / sine_norm;
  } else {
    *axis = Eigen::Vector3d::UnitZ();
  }
}

Eigen::Vector3d DualQuaternion::ToFixed(const Eigen::Vector3d& point_in_moving) const {
  // Seed 000 eq. 1: C = R c + d.
  return Rotation() * point_in_moving + Translation();
}

double DualQuaternion::NormDefect() const { return q.squaredNorm() - 1.0; }  // seed 000 eq. 2

double DualQuaternion::OrthogonalityDefect() const { return q.dot(g); }  // seed 000 eq. 3

DualQuaternion DualQuaternion::Normalized() const {
  // Restores seed 000 eqs 2-3: q / |q| and g / |q|, then g minus its component along q.
  const double norm = q.norm();
  DualQuaternion out;
  out.q = q / norm;
  out.g = g / norm;
  out.g -= out.q.dot(out.g) * out.q;
  return out;
}

DualQuaternion DualQuaternion::Inverse() const {
  // (q, g)^-1 = (q*, g*) for a unit dual quaternion: R^T and -R^T d.
  DualQuaternion out;
  out.q = QuaternionConjugate(q);
  out.g = QuaternionConjugate(g);
  return out;
}

DualQuaternion operator*(const DualQuaternion& a, const DualQuaternion& b) {
  // (qa + e ga)(qb + e gb) = qa qb + e (ga qb + qa gb): R = Ra Rb, d = da + Ra db.
  DualQuaternion ab;
  ab.q = QuaternionProduct(a.q, b.q);
  ab.g = QuaternionProduct(a.g, b.q) + QuaternionProduct(a.q, b.g);
  return ab;
}

double PoseError(const DualQuaternion& a, const DualQuaternion& b, double length) {
  // The relative rotation R_a R_b^T has quaternion qa qb*; its angle 2 atan2(|v|, |w|) lies in
  // [0, pi], does not depend on the signs of qa, qb and is accurate for small angles.
  const Eigen::Vector4d relative = QuaternionProduct(a.q, QuaternionConjugate(b.q));
  const double angle = 2.0 * std::atan2(VectorPart(relative).norm(), std::abs(relative[3]));
  const double distance = (a.Translation() - b.Translation()).norm();
  return std::hypot(distance, length * angle);
}

}  // namespace linkfit
