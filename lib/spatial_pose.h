// Spatial poses as unit dual quaternions in the convention of seed 000 (eqs 2-7):
// q = (q1, q2, q3, q4) with q4 = cos(theta/2) the scalar part, g = 1/2 D(d) q (eq. 5), which
// is the Hamilton product g = 1/2 d q with d the pure quaternion (d, 0). A body point c is at
// C = R c + d in the fixed frame, R from eq. 6 and d from eq. 7.
#ifndef LINKFIT_LIB_SPATIAL_POSE_H_
#define LINKFIT_LIB_SPATIAL_POSE_H_

#include <Eigen/Core>

namespace linkfit {

// Hamilton product of quaternions stored as (x, y, z, w), w the scalar part.
Eigen::Vector4d QuaternionProduct(const Eigen::Vector4d& a, const Eigen::Vector4d& b);
// Conjugate (-x, -y, -z, w).
Eigen::Vector4d QuaternionConjugate(const Eigen::Vector4d& a);

struct DualQuaternion {
  Eigen::Vector4d q = Eigen::Vector4d(0, 0, 0, 1);  // real part, eq. 4: (s sin(t/2), cos(t/2))
  Eigen::Vector4d g = Eigen::Vector4d::Zero();      // dual part, eq. 5

  // From rotation matrix R (orthonormal, det +1) and translation d: eqs 4-5.
  static DualQuaternion FromRotationTranslation(const Eigen::Matrix3d& rotation,
                                                const Eigen::Vector3d& translation);
  // From a rotation axis (need not be unit, must be non-zero), angle in radians and translation.
  static DualQuaternion FromAxisAngle(const Eigen::Vector3d& axis, double angle,
                                      const Eigen::Vector3d& translation);

  Eigen::Matrix3d Rotation() const;     // eq. 6
  Eigen::Vector3d Translation() const;  // eq. 7
  // Axis (unit) and angle in [0, pi]; the axis is (0, 0, 1) for the identity rotation.
  void ToAxisAngle(Eigen::Vector3d* axis, double* angle) const;

  // C = R c + d for a point c given in the moving frame.
  Eigen::Vector3d ToFixed(const Eigen::Vector3d& point_in_moving) const;

  // Deviation from the unit conditions: |q|^2 - 1 (eq. 2) and q . g (eq. 3).
  double NormDefect() const;
  double OrthogonalityDefect() const;
  // Returns the nearest unit dual quaternion (q normalized, g made orthogonal to q).
  DualQuaternion Normalized() const;

  DualQuaternion Inverse() const;  // the pose of the fixed frame seen from the moving one
};

// Composition: (a * b).ToFixed(c) == a.ToFixed(b.ToFixed(c)).
DualQuaternion operator*(const DualQuaternion& a, const DualQuaternion& b);

// Spatial pose error sqrt(|delta d|^2 + (L * angle(R_a R_b^T))^2).
double PoseError(const DualQuaternion& a, const DualQuaternion& b, double length);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SPATIAL_POSE_H_
