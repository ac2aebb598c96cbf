// The bodies of a six-bar (lib/six_bar.h) placed at a configuration, for any scalar (double in
// lib/six_bar.cc, Ceres Jets in the six-bar refiner): its joints at the reference configuration
// as 14 numbers, SixBarJoints order, and its five turns.
//
// A body k hangs from its parent by the joint whose reference place is x_k; at the turns alpha,
// that joint is at H_k = T_parent(x_k), and a point p of body k at T_k(p) = H_k + R(alpha_k)
// (p - x_k) (every body hangs from one of a lower number, so H_k is known when body k is placed).
#ifndef LINKFIT_LIB_SIX_BAR_FRAMES_H_
#define LINKFIT_LIB_SIX_BAR_FRAMES_H_

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace linkfit {

// The six-bar's joints at the reference configuration as numbers (Sigma): the ground pivot, the
// elbow, the wrist, then each RR link's first and second joint.
enum SixBarJoint : int {
  kJointGroundPivot = 0,
  kJointElbow = 2,
  kJointWrist = 4,
  kJointFirstFrom = 6,
  kJointFirstTo = 8,
  kJointSecondFrom = 10,
  kJointSecondTo = 12,
  kSixBarJointCount = 14,
};

template <typename T>
class SixBarFrames {
 public:
  using Vector = Eigen::Matrix<T, 2, 1>;

  // `from_body`, `to_body`: the bodies each RR link joins (lib/six_bar.h SixBarRRLink);
  // `joints`: kSixBarJointCount numbers (read, not copied: they must outlive the frames);
  // `angles`: the turns of bodies 1 to 5.
  SixBarFrames(const std::array<int, 2>& from_body, const std::array<int, 2>& to_body,
               const T* joints, const T* angles)
      : from_body_(from_body), to_body_(to_body), joints_(joints) {
    rotation_[0].setIdentity();
    hinge_[0].setZero();
    hinge_at_[0].setZero();
    for (int body = 1; body < 6; ++body) {
      switch (body) {
        case 1:  // the upper link, from ground at the ground pivot
          parent_[body] = 0;
          hinge_[body] = Joint(kJointGroundPivot);
          break;
        case 2:  // the forearm, from the upper link at the elbow
          parent_[body] = 1;
          hinge_[body] = Joint(kJointElbow);
          break;
        case 3:  // the task body, from the forearm at the wrist
          parent_[body] = 2;
          hinge_[body] = Joint(kJointWrist);
          break;
        default:  // an RR link, from its first body at its first joint
          parent_[body] = from_body_[body - 4];
          hinge_[body] = Joint(body == 4 ? kJointFirstFrom : kJointSecondFrom);
      }
      using std::cos;
      using std::sin;
      const T c = cos(angles[body - 1]), s = sin(angles[body - 1]);
      rotation_[body] << c, -s, s, c;
      hinge_at_[body] = At(parent_[body], hinge_[body]);
    }
  }

  Vector Joint(int index) const { return Vector(joints_[index], joints_[index + 1]); }
  const Vector& HingeAt(int body) const { return hinge_at_[body]; }  // H_body

  // T_body(point): where the point of `body` whose reference place is `point` is now.
  Vector At(int body, const Vector& point) const {
    if (body == 0) return point;
    return hinge_at_[body] + rotation_[body] * (point - hinge_[body]);
  }

  // Where RR link l's second joint is on the link and on the body it closes on.
  Vector OnLink(int l) const { return At(4 + l, Joint(l == 0 ? kJointFirstTo : kJointSecondTo)); }
  Vector OnBody(int l) const {
    return At(to_body_[l], Joint(l == 0 ? kJointFirstTo : kJointSecondTo));
  }

  // The sine of loop l's transmission angle (lib/six_bar.h SixBarTransmissionDeg): at the joint
  // J = OnBody(l) the link closes on, between the link (to its first joint, HingeAt(4 + l)) and
  // the body's lever to the joint by which it hangs (HingeAt(body)); 0 where either has no
  // length.
  T TransmissionSine(int l) const {
    const Vector j = OnBody(l);
    const Vector a = HingeAt(4 + l) - j, b = HingeAt(to_body_[l]) - j;
    const T norms = a.norm() * b.norm();
    if (!(norms > T(0.0))) return T(0.0);
    using std::abs;
    return abs(a.x() * b.y() - a.y() * b.x()) / norms;
  }

  // The two loop closures (lib/six_bar.h SixBarClosure): OnLink(l) - OnBody(l).
  Eigen::Matrix<T, 4, 1> Closure() const {
    Eigen::Matrix<T, 4, 1> residual;
    for (int l = 0; l < 2; ++l) residual.template segment<2>(2 * l) = OnLink(l) - OnBody(l);
    return residual;
  }

  // The derivative of the place `now` of a point of `body` with respect to the five turns
  // (2 x 5): its own turn swings it about H_body, d/d alpha_body = perp(now - H_body); an
  // ancestor j's swings the joint of j's child c on the path, d/d alpha_j = perp(H_c - H_j).
  Eigen::Matrix<T, 2, 5> Gradient(int body, const Vector& now) const {
    Eigen::Matrix<T, 2, 5> gradient = Eigen::Matrix<T, 2, 5>::Zero();
    if (body == 0) return gradient;
    gradient.col(body - 1) = Perp(now - hinge_at_[body]);
    for (int child = body, j = parent_[body]; j != 0; child = j, j = parent_[j]) {
      gradient.col(j - 1) += Perp(hinge_at_[child] - hinge_at_[j]);
    }
    return gradient;
  }

  // The closures' Jacobian with respect to the five turns (4 x 5).
  Eigen::Matrix<T, 4, 5> ClosureJacobian() const {
    Eigen::Matrix<T, 4, 5> jacobian;
    for (int l = 0; l < 2; ++l) {
      jacobian.template block<2, 5>(2 * l, 0) =
          Gradient(4 + l, OnLink(l)) - Gradient(to_body_[l], OnBody(l));
    }
    return jacobian;
  }

 private:
  static Vector Perp(const Vector& v) { return Vector(-v.y(), v.x()); }

  std::array<int, 2> from_body_, to_body_;
  const T* joints_;
  std::array<int, 6> parent_ = {};
  std::array<Eigen::Matrix<T, 2, 2>, 6> rotation_;
  std::array<Vector, 6> hinge_;     // x_k
  std::array<Vector, 6> hinge_at_;  // H_k
};

}  // namespace linkfit

#endif  // LINKFIT_LIB_SIX_BAR_FRAMES_H_
