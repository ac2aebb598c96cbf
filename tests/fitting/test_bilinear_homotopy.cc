#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "tests/support/bilinear_homotopy.h"

namespace linkfit {
namespace {

using testing::HomotopyRoot;
using testing::SolveBilinearByHomotopy;
using Matrices = std::array<Eigen::Matrix4d, 6>;

constexpr int kRoots = 20;
constexpr double kResidualTolerance = 1e-10;
// 1 - |<x, y>|^2 / (|x|^2 |y|^2) below this: the same point of P^3.
constexpr double kSamePointTolerance = 1e-16;
// Two roots are distinct if a or c differ by more than this (same measure).
constexpr double kDistinctTolerance = 1e-12;
// Largest imaginary part of a real root (after the solver's phase normalization).
constexpr double kRealTolerance = 1e-8;

// 1 - |<x, y>|^2 / (|x|^2 |y|^2), by the Lagrange identity as the squared norm of x ^ y over
// |x|^2 |y|^2, free of the cancellation of the direct formula.
double ProjectiveDistance2(const Eigen::Vector4cd& x, const Eigen::Vector4cd& y) {
  double wedge = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) wedge += std::norm(x(i) * y(j) - x(j) * y(i));
  }
  return wedge / (x.squaredNorm() * y.squaredNorm());
}

// The larger of the projective distances of the a and of the c parts.
double RootDistance2(const Eigen::Vector4cd& a0, const Eigen::Vector4cd& c0,
                     const Eigen::Vector4cd& a1, const Eigen::Vector4cd& c1) {
  return std::max(ProjectiveDistance2(a0, a1), ProjectiveDistance2(c0, c1));
}

// max_k |a^T B_k c| for unit a, c over max_k ||B_k||, recomputed here.
double Residual(const Matrices& matrices, const HomotopyRoot& root) {
  const Eigen::Vector4cd a = root.a.normalized();
  const Eigen::Vector4cd c = root.c.normalized();
  double scale = 0.0;
  double residual = 0.0;
  for (const Eigen::Matrix4d& b : matrices) {
    scale = std::max(scale, b.norm());
    const std::complex<double> value = a.transpose() * b.cast<std::complex<double>>() * c;
    residual = std::max(residual, std::abs(value));
  }
  return residual / scale;
}

bool IsReal(const HomotopyRoot& root) {
  return root.a.imag().cwiseAbs().maxCoeff() < kRealTolerance &&
         root.c.imag().cwiseAbs().maxCoeff() < kRealTolerance;
}

Eigen::Vector4d RandomVector(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Vector4d x;
  for (int i = 0; i < 4; ++i) x(i) = normal(rng);
  return x;
}

Matrices RandomSystem(std::mt19937_64& rng) {
  Matrices matrices;
  for (Eigen::Matrix4d& b : matrices) {
    for (int j = 0; j < 16; ++j) b(j) = std::normal_distribution<double>()(rng);
  }
  return matrices;
}

// Six random matrices from the 10-dimensional space of M with a_i^T M c_i = 0, i = 0..5.
Matrices PlantedSystem(std::mt19937_64& rng, const std::vector<Eigen::Vector4d>& a,
                       const std::vector<Eigen::Vector4d>& c) {
  Eigen::MatrixXd conditions(6, 16);
  for (int i = 0; i < 6; ++i) {
    const Eigen::Matrix4d outer = a[i] * c[i].transpose();  // a^T M c = <outer, M>
    conditions.row(i) = Eigen::Map<const Eigen::Matrix<double, 1, 16>>(outer.data());
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(conditions, Eigen::ComputeFullV);
  const Eigen::MatrixXd kernel = svd.matrixV().rightCols(10);
  Matrices matrices;
  for (Eigen::Matrix4d& b : matrices) {
    Eigen::VectorXd weights(10);
    for (int j = 0; j < 10; ++j) weights(j) = std::normal_distribution<double>()(rng);
    const Eigen::VectorXd entries = kernel * weights;
    b = Eigen::Map<const Eigen::Matrix4d>(entries.data());
  }
  return matrices;
}

// 20 converged roots of small residual (reported and recomputed), pairwise distinct.
void ExpectAllRoots(const Matrices& matrices, const std::vector<HomotopyRoot>& roots,
                    int converged) {
  EXPECT_EQ(converged, kRoots);
  ASSERT_EQ(roots.size(), static_cast<std::size_t>(kRoots));
  for (int i = 0; i < kRoots; ++i) {
    SCOPED_TRACE("root " + std::to_string(i));
    EXPECT_TRUE(roots[i].converged);
    EXPECT_NEAR(roots[i].a.norm(), 1.0, 1e-14);
    EXPECT_NEAR(roots[i].c.norm(), 1.0, 1e-14);
    EXPECT_LT(roots[i].residual, kResidualTolerance);
    EXPECT_LT(Residual(matrices, roots[i]), kResidualTolerance);
    for (int j = 0; j < i; ++j) {
      EXPECT_GT(RootDistance2(roots[i].a, roots[i].c, roots[j].a, roots[j].c), kDistinctTolerance)
          << "roots " << j << " and " << i << " coincide";
    }
  }
}

// The planted (a_i, c_i) are among the roots.
void ExpectPlantedFound(const std::vector<HomotopyRoot>& roots,
                        const std::vector<Eigen::Vector4d>& a,
                        const std::vector<Eigen::Vector4d>& c) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const HomotopyRoot& root : roots) {
      if (!root.converged) continue;
      nearest = std::min(nearest, RootDistance2(root.a, root.c, a[i].cast<std::complex<double>>(),
                                                c[i].cast<std::complex<double>>()));
    }
    EXPECT_LT(nearest, kSamePointTolerance) << "planted root " << i << " not found";
  }
}

TEST(BilinearHomotopyTest, FindsPlantedRoots) {
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::vector<Eigen::Vector4d> a, c;
    for (int i = 0; i < 6; ++i) {
      a.push_back(RandomVector(rng));
      c.push_back(RandomVector(rng));
    }
    const Matrices matrices = PlantedSystem(rng, a, c);
    std::vector<HomotopyRoot> roots;
    const int converged = SolveBilinearByHomotopy(matrices, seed + 100, &roots);
    ExpectAllRoots(matrices, roots, converged);
    ExpectPlantedFound(roots, a, c);
    // The planted roots are real, so at least 6 real roots.
    EXPECT_GE(std::count_if(roots.begin(), roots.end(), IsReal), 6);
  }
}

TEST(BilinearHomotopyTest, RandomRealSystemsHaveTwentyRootsInConjugatePairs) {
  for (std::uint64_t seed = 11; seed <= 30; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const Matrices matrices = RandomSystem(rng);
    std::vector<HomotopyRoot> roots;
    const int converged = SolveBilinearByHomotopy(matrices, seed, &roots);
    ExpectAllRoots(matrices, roots, converged);

    const int real = static_cast<int>(std::count_if(roots.begin(), roots.end(), IsReal));
    EXPECT_EQ(real % 2, 0) << real << " real roots";
    for (int i = 0; i < static_cast<int>(roots.size()); ++i) {
      if (IsReal(roots[i])) continue;
      const Eigen::Vector4cd a = roots[i].a.conjugate();
      const Eigen::Vector4cd c = roots[i].c.conjugate();
      int partner = -1;
      for (int j = 0; j < static_cast<int>(roots.size()); ++j) {
        if (j != i && RootDistance2(roots[j].a, roots[j].c, a, c) < kSamePointTolerance) {
          partner = j;
        }
      }
      EXPECT_GE(partner, 0) << "root " << i << " has no complex conjugate";
    }
  }
}

TEST(BilinearHomotopyTest, FindsRootsAtInfinity) {
  for (std::uint64_t seed : {41u, 42u, 43u, 44u, 45u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::vector<Eigen::Vector4d> a, c;
    for (int i = 0; i < 6; ++i) {
      a.push_back(RandomVector(rng));
      c.push_back(RandomVector(rng));
    }
    c[0](3) = 0.0;  // a moving point at infinity
    a[1](3) = 0.0;  // a sphere center at infinity: a plane constraint
    const Matrices matrices = PlantedSystem(rng, a, c);
    std::vector<HomotopyRoot> roots;
    const int converged = SolveBilinearByHomotopy(matrices, seed, &roots);
    ExpectAllRoots(matrices, roots, converged);
    ExpectPlantedFound(roots, a, c);
  }
}

TEST(BilinearHomotopyTest, RootsDoNotDependOnTheHomotopySeed) {
  for (std::uint64_t seed : {51u, 52u, 53u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const Matrices matrices = RandomSystem(rng);
    std::vector<HomotopyRoot> first, second;
    ASSERT_EQ(SolveBilinearByHomotopy(matrices, seed, &first), kRoots);
    ASSERT_EQ(SolveBilinearByHomotopy(matrices, seed + 1000, &second), kRoots);
    for (int i = 0; i < kRoots; ++i) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const HomotopyRoot& other : second) {
        nearest = std::min(nearest, RootDistance2(first[i].a, first[i].c, other.a, other.c));
      }
      EXPECT_LT(nearest, kSamePointTolerance) << "root " << i << " of the first solve";
    }
  }
}

TEST(BilinearHomotopyTest, IsDeterministicGivenTheSeed) {
  std::mt19937_64 rng(61);
  const Matrices matrices = RandomSystem(rng);
  std::vector<HomotopyRoot> first, second;
  const int converged = SolveBilinearByHomotopy(matrices, 7, &first);
  EXPECT_EQ(SolveBilinearByHomotopy(matrices, 7, &second), converged);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].a, second[i].a);
    EXPECT_EQ(first[i].c, second[i].c);
    EXPECT_EQ(first[i].converged, second[i].converged);
    EXPECT_EQ(first[i].residual, second[i].residual);
  }
}

}  // namespace
}  // namespace linkfit
