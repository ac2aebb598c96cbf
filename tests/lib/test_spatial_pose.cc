// Tests of lib/spatial_pose.h: unit dual quaternions in the convention of seed 000 eqs 2-7.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "lib/spatial_pose.h"

namespace {

using linkfit::DualQuaternion;

constexpr double kTight = 1e-12;      // exact algebra on O(1) numbers
constexpr double kRoundTrip = 1e-10;  // round trips through matrices and trigonometry
constexpr unsigned kSeed = 20240517;  // fixed seed of every random test here
constexpr int kTrials = 200;

struct RandomPoseSource {
  explicit RandomPoseSource(unsigned seed) : engine(seed) {}

  Eigen::Matrix3d Rotation() {
    // A uniformly random rotation from a normalized Gaussian quaternion.
    Eigen::Quaterniond quaternion(normal(engine), normal(engine), normal(engine), normal(engine));
    quaternion.normalize();
    return quaternion.toRotationMatrix();
  }
  Eigen::Vector3d Vector(double scale = 5.0) {
    return scale * Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine));
  }
  DualQuaternion Pose() { return DualQuaternion::FromRotationTranslation(Rotation(), Vector()); }

  std::mt19937 engine;
  std::normal_distribution<double> normal{0.0, 1.0};
  std::uniform_real_distribution<double> uniform{-1.0, 1.0};
};

Eigen::Matrix4d Homogeneous(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  // Seed 000 eq. 1.
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation;
  m.topRightCorner<3, 1>() = translation;
  return m;
}

Eigen::Matrix3d AxisAngleMatrix(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

void ExpectUnit(const DualQuaternion& pose) {
  EXPECT_NEAR(pose.q.norm(), 1.0, kTight);
  EXPECT_NEAR(pose.NormDefect(), 0.0, kTight);
  EXPECT_NEAR(pose.OrthogonalityDefect(), 0.0, kTight);
}

TEST(SpatialPoseQuaternion, ProductMatchesEigen) {
  RandomPoseSource source(kSeed);
  SCOPED_TRACE("seed " + std::to_string(kSeed));
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector4d a(source.normal(source.engine), source.normal(source.engine),
                            source.normal(source.engine), source.normal(source.engine));
    const Eigen::Vector4d b(source.normal(source.engine), source.normal(source.engine),
                            source.normal(source.engine), source.normal(source.engine));
    const Eigen::Quaterniond ea(a[3], a[0], a[1], a[2]), eb(b[3], b[0], b[1], b[2]);
    const Eigen::Quaterniond expected = ea * eb;
    const Eigen::Vector4d product = linkfit::QuaternionProduct(a, b);
    EXPECT_TRUE(product.isApprox(
        Eigen::Vector4d(expected.x(), expected.y(), expected.z(), expected.w()), kTight))
        << "trial " << trial;
    EXPECT_EQ(linkfit::QuaternionConjugate(a), Eigen::Vector4d(-a[0], -a[1], -a[2], a[3]));
  }
}

TEST(SpatialPoseQuaternion, DualPartIsEq5) {
  // g = 1/2 D(d) q with the 4x4 matrix of seed 000 eq. 5, written out here.
  RandomPoseSource source(kSeed + 1);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 1));
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d rotation = source.Rotation();
    const Eigen::Vector3d d = source.Vector();
    const DualQuaternion pose = DualQuaternion::FromRotationTranslation(rotation, d);
    Eigen::Matrix4d big_d;
    big_d << 0, -d[2], d[1], d[0],  //
        d[2], 0, -d[0], d[1],       //
        -d[1], d[0], 0, d[2],       //
        -d[0], -d[1], -d[2], 0;
    EXPECT_TRUE(pose.g.isApprox(0.5 * big_d * pose.q, kTight)) << "trial " << trial;
  }
}

TEST(SpatialPoseRoundTrip, RandomPoses) {
  RandomPoseSource source(kSeed + 2);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 2));
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Matrix3d rotation = source.Rotation();
    const Eigen::Vector3d translation = source.Vector();
    const DualQuaternion pose = DualQuaternion::FromRotationTranslation(rotation, translation);
    ExpectUnit(pose);
    EXPECT_GE(pose.q[3], 0.0);
    EXPECT_LT((pose.Rotation() - rotation).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((pose.Translation() - translation).norm(), kRoundTrip) << "trial " << trial;
  }
}

TEST(SpatialPoseRoundTrip, SpecialAngles) {
  const std::vector<double> angles = {0.0, M_PI, M_PI - 1e-9, 1e-9, -M_PI + 1e-9};
  const std::vector<Eigen::Vector3d> axes = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                             Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, -2, 3),
                                             Eigen::Vector3d(-0.3, 0.1, 0.9)};
  const Eigen::Vector3d translation(0.7, -1.3, 2.1);
  for (const double angle : angles) {
    for (const Eigen::Vector3d& axis : axes) {
      SCOPED_TRACE("angle " + std::to_string(angle) + " axis " + std::to_string(axis[0]) + "," +
                   std::to_string(axis[1]) + "," + std::to_string(axis[2]));
      const Eigen::Matrix3d rotation = AxisAngleMatrix(axis, angle);
      const DualQuaternion pose = DualQuaternion::FromRotationTranslation(rotation, translation);
      ExpectUnit(pose);
      EXPECT_GE(pose.q[3], 0.0);
      EXPECT_LT((pose.Rotation() - rotation).norm(), kRoundTrip);
      EXPECT_LT((pose.Translation() - translation).norm(), kRoundTrip);
      // q agrees with eq. 4 up to sign.
      const DualQuaternion expected = DualQuaternion::FromAxisAngle(axis, angle, translation);
      const double sign = expected.q.dot(pose.q) < 0.0 ? -1.0 : 1.0;
      EXPECT_LT((sign * expected.q - pose.q).norm(), kRoundTrip);
      EXPECT_LT((sign * expected.g - pose.g).norm(), kRoundTrip);
    }
  }
}

TEST(SpatialPoseRoundTrip, NearHalfTurnKeepsAngle) {
  // theta = pi - 1e-9: q4 = sin(5e-10) must come out with its full relative precision.
  constexpr double kDelta = 1e-9;
  const Eigen::Vector3d axis = Eigen::Vector3d(2, -1, 0.5).normalized();
  const DualQuaternion pose = DualQuaternion::FromRotationTranslation(
      AxisAngleMatrix(axis, M_PI - kDelta), Eigen::Vector3d::Zero());
  Eigen::Vector3d axis_out;
  double angle_out = 0.0;
  pose.ToAxisAngle(&axis_out, &angle_out);
  EXPECT_NEAR(angle_out, M_PI - kDelta, 1e-14);
  EXPECT_LT((axis_out - axis).norm(), kTight);
}

TEST(SpatialPoseEq7, TranslationFromVectorPartOf2gqConjugate) {
  RandomPoseSource source(kSeed + 3);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 3));
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Vector3d d = source.Vector();
    const DualQuaternion pose = DualQuaternion::FromRotationTranslation(source.Rotation(), d);
    const Eigen::Vector4d two_g_q_conjugate =
        2.0 * linkfit::QuaternionProduct(pose.g, linkfit::QuaternionConjugate(pose.q));
    EXPECT_NEAR(two_g_q_conjugate[3], 0.0, kTight) << "trial " << trial;
    EXPECT_LT((two_g_q_conjugate.head<3>() - d).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((pose.Translation() - d).norm(), kRoundTrip) << "trial " << trial;
    // -q is the same pose: eq. 7 is quadratic in (q, g).
    DualQuaternion negated = pose;
    negated.q = -negated.q;
    negated.g = -negated.g;
    EXPECT_LT((negated.Translation() - d).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((negated.Rotation() - pose.Rotation()).norm(), kTight) << "trial " << trial;
  }
}

TEST(SpatialPoseCompose, MatchesMatrixComposition) {
  RandomPoseSource source(kSeed + 4);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 4));
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Matrix3d ra = source.Rotation(), rb = source.Rotation();
    const Eigen::Vector3d da = source.Vector(), db = source.Vector();
    const DualQuaternion a = DualQuaternion::FromRotationTranslation(ra, da);
    const DualQuaternion b = DualQuaternion::FromRotationTranslation(rb, db);
    const DualQuaternion ab = a * b;
    ExpectUnit(ab);
    const Eigen::Matrix4d m = Homogeneous(ra, da) * Homogeneous(rb, db);
    EXPECT_LT((ab.Rotation() - m.topLeftCorner<3, 3>()).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((ab.Translation() - m.topRightCorner<3, 1>()).norm(), kRoundTrip)
        << "trial " << trial;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d c = source.Vector(3.0);
      EXPECT_LT((ab.ToFixed(c) - a.ToFixed(b.ToFixed(c))).norm(), kRoundTrip) << "trial " << trial;
      EXPECT_LT((ab.ToFixed(c) - (m * c.homogeneous()).head<3>()).norm(), kRoundTrip)
          << "trial " << trial;
    }
  }
}

TEST(SpatialPoseCompose, Associative) {
  RandomPoseSource source(kSeed + 5);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 5));
  for (int trial = 0; trial < 50; ++trial) {
    const DualQuaternion a = source.Pose(), b = source.Pose(), c = source.Pose();
    const DualQuaternion left = (a * b) * c, right = a * (b * c);
    EXPECT_LT((left.q - right.q).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((left.g - right.g).norm(), kRoundTrip) << "trial " << trial;
  }
}

TEST(SpatialPoseInverse, ComposesToIdentity) {
  RandomPoseSource source(kSeed + 6);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 6));
  const DualQuaternion identity;
  for (int trial = 0; trial < kTrials; ++trial) {
    const DualQuaternion a = source.Pose();
    const DualQuaternion inverse = a.Inverse();
    ExpectUnit(inverse);
    for (const DualQuaternion& product : {a * inverse, inverse * a}) {
      EXPECT_LT((product.q - identity.q).norm(), kRoundTrip) << "trial " << trial;
      EXPECT_LT(product.g.norm(), kRoundTrip) << "trial " << trial;
      EXPECT_LT(linkfit::PoseError(product, identity, 1.0), kRoundTrip) << "trial " << trial;
    }
    const Eigen::Vector3d c = source.Vector();
    EXPECT_LT((inverse.ToFixed(a.ToFixed(c)) - c).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((inverse.Rotation() - a.Rotation().transpose()).norm(), kRoundTrip)
        << "trial " << trial;
    EXPECT_LT((inverse.Translation() + a.Rotation().transpose() * a.Translation()).norm(),
              kRoundTrip)
        << "trial " << trial;
  }
}

TEST(SpatialPoseAxisAngle, RoundTrip) {
  RandomPoseSource source(kSeed + 7);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 7));
  std::uniform_real_distribution<double> angle_distribution(0.0, M_PI);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Vector3d axis = source.Vector();
    const double angle = angle_distribution(source.engine);
    const Eigen::Vector3d translation = source.Vector();
    const DualQuaternion pose = DualQuaternion::FromAxisAngle(axis, angle, translation);
    ExpectUnit(pose);
    // Eq. 4 directly.
    EXPECT_NEAR(pose.q[3], std::cos(0.5 * angle), kTight);
    EXPECT_LT((pose.q.head<3>() - std::sin(0.5 * angle) * axis.normalized()).norm(), kTight);
    EXPECT_LT((pose.Rotation() - AxisAngleMatrix(axis, angle)).norm(), kRoundTrip);
    EXPECT_LT((pose.Translation() - translation).norm(), kRoundTrip);
    Eigen::Vector3d axis_out;
    double angle_out = -1.0;
    pose.ToAxisAngle(&axis_out, &angle_out);
    EXPECT_NEAR(angle_out, angle, kRoundTrip) << "trial " << trial;
    EXPECT_NEAR(axis_out.norm(), 1.0, kTight) << "trial " << trial;
    EXPECT_LT((axis_out - axis.normalized()).norm(), kRoundTrip) << "trial " << trial;
  }
}

TEST(SpatialPoseAxisAngle, NegativeScalarPartAndIdentity) {
  // An angle of 3pi/2 about s gives q4 < 0; it is the rotation by pi/2 about -s.
  const Eigen::Vector3d axis(0, 1, 0);
  const DualQuaternion pose =
      DualQuaternion::FromAxisAngle(axis, 1.5 * M_PI, Eigen::Vector3d(1, 2, 3));
  EXPECT_LT(pose.q[3], 0.0);
  Eigen::Vector3d axis_out;
  double angle_out = -1.0;
  pose.ToAxisAngle(&axis_out, &angle_out);
  EXPECT_NEAR(angle_out, 0.5 * M_PI, kTight);
  EXPECT_LT((axis_out + axis).norm(), kTight);

  DualQuaternion negated = pose;
  negated.q = -negated.q;
  negated.g = -negated.g;
  Eigen::Vector3d axis_negated;
  double angle_negated = -1.0;
  negated.ToAxisAngle(&axis_negated, &angle_negated);
  EXPECT_NEAR(angle_negated, angle_out, kTight);
  EXPECT_LT((axis_negated - axis_out).norm(), kTight);

  const DualQuaternion identity;
  identity.ToAxisAngle(&axis_out, &angle_out);
  EXPECT_EQ(angle_out, 0.0);
  EXPECT_EQ(axis_out, Eigen::Vector3d(0, 0, 1));
  DualQuaternion minus_identity;
  minus_identity.q = -minus_identity.q;
  minus_identity.ToAxisAngle(&axis_out, &angle_out);
  EXPECT_EQ(angle_out, 0.0);
  EXPECT_EQ(axis_out, Eigen::Vector3d(0, 0, 1));
}

TEST(SpatialPoseError, SignOfQuaternionDoesNotMatter) {
  RandomPoseSource source(kSeed + 8);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 8));
  for (int trial = 0; trial < kTrials; ++trial) {
    const DualQuaternion a = source.Pose();
    DualQuaternion negated = a;
    negated.q = -negated.q;
    negated.g = -negated.g;
    EXPECT_LT(linkfit::PoseError(a, negated, 2.0), kRoundTrip) << "trial " << trial;
    EXPECT_EQ(linkfit::PoseError(a, a, 2.0), 0.0) << "trial " << trial;
    const DualQuaternion b = source.Pose();
    EXPECT_NEAR(linkfit::PoseError(a, b, 2.0), linkfit::PoseError(negated, b, 2.0), kRoundTrip)
        << "trial " << trial;
    EXPECT_NEAR(linkfit::PoseError(a, b, 2.0), linkfit::PoseError(b, a, 2.0), kRoundTrip)
        << "trial " << trial;
  }
}

TEST(SpatialPoseError, KnownRotationAndTranslation) {
  constexpr double kLength = 2.5;
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 1, -1).normalized();
  const Eigen::Vector3d translation(0.3, -0.2, 1.1);
  const DualQuaternion base = DualQuaternion::FromAxisAngle(axis, 0.4, translation);
  // A pure relative rotation: turn the moving frame about its own origin (compose on the moving
  // side), so d stays and R_a R_b^T is a rotation by `angle`.
  for (const double angle : {0.3, 1e-7, 1e-12, M_PI - 1e-6, M_PI}) {
    SCOPED_TRACE("angle " + std::to_string(angle));
    const DualQuaternion turn =
        DualQuaternion::FromAxisAngle(Eigen::Vector3d(0, 1, 2), angle, Eigen::Vector3d::Zero());
    const DualQuaternion turned = base * turn;  // same origin, orientation differs by angle
    EXPECT_LT((turned.Translation() - base.Translation()).norm(), kRoundTrip);
    EXPECT_NEAR(linkfit::PoseError(turned, base, kLength), kLength * angle,
                kRoundTrip * std::max(1.0, angle));
    // Small angles are resolved down to the rounding of q (~1e-16), not to sqrt(eps) ~ 1e-8 as
    // an acos of the trace would be.
    if (angle < 1e-6) {
      EXPECT_NEAR(linkfit::PoseError(turned, base, kLength), kLength * angle, kLength * 1e-14);
    }
  }
  // Pure translation by (3, 4, 0): error 5.
  const DualQuaternion shifted =
      DualQuaternion::FromAxisAngle(axis, 0.4, translation + Eigen::Vector3d(3.0, 4.0, 0.0));
  EXPECT_NEAR(linkfit::PoseError(shifted, base, kLength), 5.0, kRoundTrip);
  // Both: a 0.2 rad turn with L = 2.5 and a 3-4-0 shift: sqrt(25 + 0.25).
  const DualQuaternion both =
      DualQuaternion::FromAxisAngle(Eigen::Vector3d(0, 0, 1), 0.2, Eigen::Vector3d::Zero());
  const DualQuaternion both_shifted =
      DualQuaternion::FromAxisAngle(Eigen::Vector3d(0, 0, 1), 0.0, Eigen::Vector3d(3, 4, 0));
  EXPECT_NEAR(linkfit::PoseError(both, both_shifted, kLength), std::sqrt(25.0 + 0.25), kRoundTrip);
}

TEST(SpatialPoseNormalized, FixesPerturbedDualQuaternion) {
  RandomPoseSource source(kSeed + 9);
  SCOPED_TRACE("seed " + std::to_string(kSeed + 9));
  constexpr double kPerturbation = 1e-3;
  for (int trial = 0; trial < kTrials; ++trial) {
    const DualQuaternion exact = source.Pose();
    DualQuaternion perturbed = exact;
    const double scale = 1.0 + 0.5 * source.uniform(source.engine);
    perturbed.q = scale * exact.q;
    perturbed.g = scale * exact.g;
    // Push g along q: violates eq. 3 without changing the pose.
    perturbed.g += (kPerturbation * source.uniform(source.engine)) * perturbed.q;
    EXPECT_GT(std::abs(perturbed.NormDefect()) + std::abs(perturbed.OrthogonalityDefect()), 0.0);
    const DualQuaternion fixed = perturbed.Normalized();
    ExpectUnit(fixed);
    EXPECT_LT((fixed.q - exact.q).norm(), kRoundTrip) << "trial " << trial;
    EXPECT_LT((fixed.g - exact.g).norm(), kRoundTrip) << "trial " << trial;

    // A general small perturbation lands near the original pose and satisfies eqs 2-3.
    DualQuaternion noisy = exact;
    for (int i = 0; i < 4; ++i) {
      noisy.q[i] += kPerturbation * source.uniform(source.engine);
      noisy.g[i] += kPerturbation * source.uniform(source.engine);
    }
    const DualQuaternion noisy_fixed = noisy.Normalized();
    ExpectUnit(noisy_fixed);
    EXPECT_LT(linkfit::PoseError(noisy_fixed, exact, 1.0), 100.0 * kPerturbation)
        << "trial " << trial;
    // Normalizing a unit dual quaternion changes nothing.
    const DualQuaternion again = exact.Normalized();
    EXPECT_LT((again.q - exact.q).norm(), kTight) << "trial " << trial;
    EXPECT_LT((again.g - exact.g).norm(), kTight) << "trial " << trial;
  }
}

}  // namespace
