// Tests of fitting/polynomial.h: real roots of cubics, roots of binary quadratics.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fitting/polynomial.h"

namespace {

using Complex = std::complex<double>;

constexpr double kRelative = 1e-12;   // relative residual / relative root accuracy
constexpr double kDoubleRoot = 1e-7;  // relative accuracy of a double root (about sqrt(eps))
constexpr uint64_t kSeed = 1234567;   // fixed seed of the random tests here
constexpr int kTrials = 2000;

// ---------------------------------------------------------------------------------------------
// Cubics.

struct Cubic {
  double c3, c2, c1, c0;
  double operator()(double t) const { return ((c3 * t + c2) * t + c1) * t + c0; }
  // The size of the terms at t: the scale a residual is measured against.
  double Magnitude(double t) const {
    const double a = std::abs(t);
    return ((std::abs(c3) * a + std::abs(c2)) * a + std::abs(c1)) * a + std::abs(c0);
  }
};

// k (t - r0)(t - r1)(t - r2).
Cubic FromRealRoots(double r0, double r1, double r2, double k = 1.0) {
  return {k, -k * (r0 + r1 + r2), k * (r0 * r1 + r0 * r2 + r1 * r2), -k * (r0 * r1 * r2)};
}

// k (t - r)(t - (p + iq))(t - (p - iq)).
Cubic FromRealAndComplexPair(double r, double p, double q, double k = 1.0) {
  const double norm = p * p + q * q;
  return {k, -k * (r + 2.0 * p), k * (2.0 * p * r + norm), -k * (r * norm)};
}

std::string Describe(const Cubic& cubic, int count, const double roots[3]) {
  std::ostringstream out;
  out.precision(17);
  out << "cubic " << cubic.c3 << " t^3 + " << cubic.c2 << " t^2 + " << cubic.c1 << " t + "
      << cubic.c0 << "; count " << count << " roots";
  for (int i = 0; i < count; ++i) out << " " << roots[i];
  return out.str();
}

// Solves `cubic`, checks count, order and residuals, and returns the roots.
std::vector<double> SolveAndCheck(const Cubic& cubic, const std::string& where) {
  double roots[3] = {0.0, 0.0, 0.0};
  const int count = linkfit::SolveCubicReal(cubic.c3, cubic.c2, cubic.c1, cubic.c0, roots);
  const std::string what = where + ": " + Describe(cubic, std::max(0, std::min(count, 3)), roots);
  EXPECT_GE(count, 1) << what;
  EXPECT_LE(count, 3) << what;
  if (count < 1 || count > 3) return {};
  for (int i = 0; i < count; ++i) {
    EXPECT_TRUE(std::isfinite(roots[i])) << what;
    EXPECT_LE(std::abs(cubic(roots[i])), kRelative * cubic.Magnitude(roots[i]))
        << what << " root " << i;
    if (i > 0) {
      EXPECT_LE(roots[i - 1], roots[i]) << what << " not ascending";
    }
  }
  return std::vector<double>(roots, roots + count);
}

// The relative accuracy to expect of a simple root r: kRelative, or a few rounding errors
// times the relative condition number sum |c_i r^i| / |r p'(r)| when that is larger.
double ConditionTolerance(const Cubic& cubic, double r) {
  const double derivative = (3.0 * cubic.c3 * r + 2.0 * cubic.c2) * r + cubic.c1;
  const double condition = cubic.Magnitude(r) / std::max(std::abs(r * derivative), 1e-300);
  return std::max(kRelative, 16.0 * std::numeric_limits<double>::epsilon() * condition);
}

// The distance from `expected` to the nearest returned root, relative to |expected|.
double NearestRelative(const std::vector<double>& roots, double expected) {
  double best = std::numeric_limits<double>::infinity();
  for (double root : roots) best = std::min(best, std::abs(root - expected));
  return best / std::max(std::abs(expected), std::numeric_limits<double>::min());
}

TEST(PolynomialCubic, ThreeDistinctRealRoots) {
  const double cases[][3] = {{1.0, 2.0, 3.0},    {-1.0, 0.0, 1.0}, {-5.0, 0.5, 7.25},
                             {-3.0, -2.0, -1.0}, {0.1, 0.2, 0.3},  {-100.0, 1.0, 2.0},
                             {2.0, -7.0, 0.25}};
  for (const auto& r : cases) {
    for (const double k : {1.0, -3.0, 1e-8, 1e8}) {
      const Cubic cubic = FromRealRoots(r[0], r[1], r[2], k);
      std::ostringstream where;
      where << "roots " << r[0] << " " << r[1] << " " << r[2] << " k " << k;
      const std::vector<double> roots = SolveAndCheck(cubic, where.str());
      ASSERT_EQ(roots.size(), 3u) << where.str();
      std::vector<double> expected(r, r + 3);
      std::sort(expected.begin(), expected.end());
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(roots[i], expected[i], kRelative * std::max(1.0, std::abs(expected[i])))
            << where.str() << " root " << i;
      }
    }
  }
}

TEST(PolynomialCubic, OneRealRootAndComplexPair) {
  // The last case has the pair 1e-3 from the real root: its condition number is about 1e8, so
  // the root is known only to ConditionTolerance (the residual test is unchanged).
  const double cases[][3] = {{1.0, 0.0, 1.0}, {-2.0, 3.0, 0.5}, {0.0, 1.0, 2.0},
                             {5.0, 5.0, 2.0}, {-1e3, 1.0, 1.0}, {1e-3, -10.0, 20.0},
                             {5.0, 5.0, 1e-3}};
  for (const auto& c : cases) {
    for (const double k : {1.0, -0.5, 1e6}) {
      const Cubic cubic = FromRealAndComplexPair(c[0], c[1], c[2], k);
      std::ostringstream where;
      where << "real " << c[0] << " pair " << c[1] << " +- " << c[2] << "i k " << k;
      const std::vector<double> roots = SolveAndCheck(cubic, where.str());
      ASSERT_EQ(roots.size(), 1u) << where.str();
      EXPECT_NEAR(roots[0], c[0], ConditionTolerance(cubic, c[0]) * std::max(1.0, std::abs(c[0])))
          << where.str();
    }
  }
}

TEST(PolynomialCubic, DoubleRoot) {
  // (t - d)^2 (t - s): the simple root s to full accuracy, the double root d to about
  // sqrt(eps) and not lost (a double root is two coincident real roots).
  const double cases[][2] = {{1.0, 2.0}, {2.0, 1.0}, {-1.0, 3.0}, {0.5, -4.0}, {3.0, 0.0}};
  for (const auto& c : cases) {
    const double d = c[0], s = c[1];
    const Cubic cubic = FromRealRoots(d, d, s);
    std::ostringstream where;
    where << "double " << d << " simple " << s;
    const std::vector<double> roots = SolveAndCheck(cubic, where.str());
    ASSERT_FALSE(roots.empty()) << where.str();
    EXPECT_LE(NearestRelative(roots, s), kRelative) << where.str();
    EXPECT_LE(NearestRelative(roots, d), kDoubleRoot) << where.str();
  }
}

TEST(PolynomialCubic, TripleRoot) {
  const Cubic cubic = FromRealRoots(2.0, 2.0, 2.0);
  const std::vector<double> roots = SolveAndCheck(cubic, "triple root 2");
  ASSERT_FALSE(roots.empty());
  // A triple root is known to about cbrt(eps).
  EXPECT_LE(NearestRelative(roots, 2.0), 1e-5);
}

TEST(PolynomialCubic, WidelyScaledRoots) {
  const double cases[][3] = {
      {1e-6, 1.0, 1e6}, {-1e6, 1e-6, 1.0}, {1e-6, 2e-6, 1e6}, {-1e6, -1.0, 1e-6}, {1e-6, 1e6, 2e6}};
  for (const auto& r : cases) {
    for (const double k : {1.0, 1e-3}) {
      const Cubic cubic = FromRealRoots(r[0], r[1], r[2], k);
      std::ostringstream where;
      where << "roots " << r[0] << " " << r[1] << " " << r[2] << " k " << k;
      const std::vector<double> roots = SolveAndCheck(cubic, where.str());
      EXPECT_EQ(roots.size(), 3u) << where.str();
      for (int i = 0; i < 3; ++i) {
        EXPECT_LE(NearestRelative(roots, r[i]), kRelative) << where.str() << " root " << r[i];
      }
    }
  }
  // One real root far from a small complex pair, and the other way round.
  for (const auto& c : {std::array<double, 3>{1e6, 1e-6, 1e-6}, {1e-6, 1e6, 1e6}}) {
    const Cubic cubic = FromRealAndComplexPair(c[0], c[1], c[2]);
    std::ostringstream where;
    where << "real " << c[0] << " pair " << c[1] << " +- " << c[2] << "i";
    const std::vector<double> roots = SolveAndCheck(cubic, where.str());
    ASSERT_EQ(roots.size(), 1u) << where.str();
    EXPECT_LE(NearestRelative(roots, c[0]), kRelative) << where.str();
  }
}

TEST(PolynomialCubic, RandomRoots) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0), log_scale(-3.0, 3.0);
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::string where = "seed " + std::to_string(kSeed) + " trial " + std::to_string(trial);
    const double k = std::pow(10.0, log_scale(rng)) * (trial % 2 ? 1.0 : -1.0);
    if (trial % 3 == 0) {
      // One real root and a complex pair.
      const double r = uniform(rng), p = uniform(rng), q = std::abs(uniform(rng)) + 0.1;
      const Cubic cubic = FromRealAndComplexPair(r, p, q, k);
      const std::vector<double> roots = SolveAndCheck(cubic, where);
      ASSERT_EQ(roots.size(), 1u) << where;
      EXPECT_LE(NearestRelative(roots, r), 1e-9 * std::max(1.0, 10.0 / std::abs(r))) << where;
    } else {
      std::vector<double> r = {uniform(rng), uniform(rng), uniform(rng)};
      std::sort(r.begin(), r.end());
      if (r[1] - r[0] < 0.1 || r[2] - r[1] < 0.1) continue;  // separated roots only
      const Cubic cubic = FromRealRoots(r[0], r[1], r[2], k);
      const std::vector<double> roots = SolveAndCheck(cubic, where);
      ASSERT_EQ(roots.size(), 3u) << where;
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(roots[i], r[i], 1e-9) << where << " root " << i;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Binary quadratics a alpha^2 + 2 b alpha beta + c beta^2 = 0.

struct Quadratic {
  Complex a, b, c;
  Complex operator()(Complex alpha, Complex beta) const {
    return a * alpha * alpha + 2.0 * b * alpha * beta + c * beta * beta;
  }
  double Magnitude(Complex alpha, Complex beta) const {
    const double x = std::abs(alpha), y = std::abs(beta);
    return std::abs(a) * x * x + 2.0 * std::abs(b) * x * y + std::abs(c) * y * y;
  }
};

// a (x - x0)(x - x1) = a x^2 - a (x0 + x1) x + a x0 x1.
Quadratic FromRoots(Complex x0, Complex x1, Complex a = 1.0) {
  return {a, -0.5 * a * (x0 + x1), a * x0 * x1};
}

struct Roots {
  Complex alpha[2], beta[2];
};

// Solves, checks both pairs are non-zero and satisfy the quadratic.
Roots SolveQuadraticAndCheck(const Quadratic& q, const std::string& where) {
  Roots roots;
  linkfit::SolveBinaryQuadratic(q.a, q.b, q.c, roots.alpha, roots.beta);
  for (int i = 0; i < 2; ++i) {
    std::ostringstream what;
    what.precision(17);
    what << where << ": a " << q.a << " b " << q.b << " c " << q.c << " root " << i << " ("
         << roots.alpha[i] << " : " << roots.beta[i] << ")";
    const double size = std::hypot(std::abs(roots.alpha[i]), std::abs(roots.beta[i]));
    EXPECT_GT(size, 0.0) << what.str();
    EXPECT_TRUE(std::isfinite(size)) << what.str();
    EXPECT_LE(std::abs(q(roots.alpha[i], roots.beta[i])),
              kRelative * q.Magnitude(roots.alpha[i], roots.beta[i]))
        << what.str();
  }
  return roots;
}

// The affine roots x = alpha / beta match {x0, x1} in some order, each to relative `tolerance`.
void ExpectAffineRoots(const Roots& roots, Complex x0, Complex x1, double tolerance,
                       const std::string& where) {
  ASSERT_NE(roots.beta[0], Complex(0.0)) << where;
  ASSERT_NE(roots.beta[1], Complex(0.0)) << where;
  const Complex y0 = roots.alpha[0] / roots.beta[0], y1 = roots.alpha[1] / roots.beta[1];
  auto close = [tolerance](Complex got, Complex want) {
    return std::abs(got - want) <= tolerance * std::max(std::abs(want), 1e-300);
  };
  const bool direct = close(y0, x0) && close(y1, x1);
  const bool swapped = close(y0, x1) && close(y1, x0);
  EXPECT_TRUE(direct || swapped) << where << ": got " << y0 << ", " << y1 << " expected " << x0
                                 << ", " << x1;
}

TEST(PolynomialBinaryQuadratic, KnownComplexAndRealRoots) {
  const Complex i(0.0, 1.0);
  struct Case {
    Complex x0, x1, a;
  };
  const Case cases[] = {
      {1.0, 2.0, 1.0},
      {-3.0, 0.5, 2.0},
      {i, -i, 1.0},
      {1.0 + 2.0 * i, 1.0 - 2.0 * i, -4.0},
      {2.0 + i, -1.0 + 3.0 * i, 1.0 - i},
      {0.0, 5.0, 1.0},
      {-7.0 * i, 0.25, 3.0 * i},
      {1e3, -1e3, 1e-3},
  };
  for (const Case& c : cases) {
    std::ostringstream where;
    where << "roots " << c.x0 << " " << c.x1 << " a " << c.a;
    const Roots roots = SolveQuadraticAndCheck(FromRoots(c.x0, c.x1, c.a), where.str());
    ExpectAffineRoots(roots, c.x0, c.x1, kRelative, where.str());
  }
  // x^2 + 1 with real coefficients: +-i.
  const Roots roots = SolveQuadraticAndCheck({1.0, 0.0, 1.0}, "x^2 + 1");
  ExpectAffineRoots(roots, i, -i, kRelative, "x^2 + 1");
  // Real coefficients with real roots give real roots.
  const Roots real = SolveQuadraticAndCheck({1.0, -1.5, 2.0}, "x^2 - 3x + 2");
  ExpectAffineRoots(real, 1.0, 2.0, kRelative, "x^2 - 3x + 2");
  for (int k = 0; k < 2; ++k) {
    EXPECT_LE(std::abs((real.alpha[k] / real.beta[k]).imag()), 1e-300) << "root " << k;
  }
}

TEST(PolynomialBinaryQuadratic, RootAtInfinityWhenLeadingCoefficientVanishes) {
  // 2 b x + c = 0 with a = 0: one root -c / (2 b), one at infinity (beta = 0).
  const Complex i(0.0, 1.0);
  for (const Complex b : {Complex(1.0), Complex(-1.0), Complex(0.5, -2.0), -3.0 * i}) {
    for (const Complex c : {Complex(4.0), Complex(0.0), Complex(-1.0, 1.0)}) {
      std::ostringstream where;
      where << "a 0 b " << b << " c " << c;
      const Quadratic q{0.0, b, c};
      const Roots roots = SolveQuadraticAndCheck(q, where.str());
      const int infinite = roots.beta[0] == Complex(0.0) ? 0 : 1;
      EXPECT_EQ(roots.beta[infinite], Complex(0.0)) << where.str();
      EXPECT_NE(roots.alpha[infinite], Complex(0.0)) << where.str();
      const int finite = 1 - infinite;
      ASSERT_NE(roots.beta[finite], Complex(0.0)) << where.str();
      const Complex x = roots.alpha[finite] / roots.beta[finite];
      EXPECT_LE(std::abs(x - (-c / (2.0 * b))), kRelative * std::max(1.0, std::abs(c / b)))
          << where.str();
    }
  }
  // a = b = 0: c beta^2 = 0, both roots at infinity.
  const Roots both = SolveQuadraticAndCheck({0.0, 0.0, 2.0}, "a 0 b 0 c 2");
  EXPECT_EQ(both.beta[0], Complex(0.0));
  EXPECT_EQ(both.beta[1], Complex(0.0));
  // b = c = 0: a alpha^2 = 0, both roots at zero.
  const Roots zeros = SolveQuadraticAndCheck({2.0, 0.0, 0.0}, "a 2 b 0 c 0");
  EXPECT_EQ(zeros.alpha[0], Complex(0.0));
  EXPECT_EQ(zeros.alpha[1], Complex(0.0));
  EXPECT_NE(zeros.beta[0], Complex(0.0));
  EXPECT_NE(zeros.beta[1], Complex(0.0));
}

TEST(PolynomialBinaryQuadratic, DoubleRoot) {
  const Complex i(0.0, 1.0);
  for (const Complex x : {Complex(3.0), Complex(-0.5), 2.0 - i, 1e-4 * i}) {
    for (const Complex a : {Complex(1.0), Complex(-2.0, 1.0)}) {
      std::ostringstream where;
      where << "double root " << x << " a " << a;
      const Roots roots = SolveQuadraticAndCheck(FromRoots(x, x, a), where.str());
      // Exact coefficients of a double root: b^2 = a c up to rounding, so the root is known
      // to about sqrt(eps).
      ExpectAffineRoots(roots, x, x, kDoubleRoot, where.str());
    }
  }
  // Exactly representable: (x - 3)^2 = x^2 - 6 x + 9.
  const Roots roots = SolveQuadraticAndCheck({1.0, -3.0, 9.0}, "(x - 3)^2");
  ExpectAffineRoots(roots, 3.0, 3.0, kRelative, "(x - 3)^2");
}

TEST(PolynomialBinaryQuadratic, NoCancellationWhenBSquaredDominates) {
  const Complex i(0.0, 1.0);
  // x^2 - (1e8 + 1e-8) x + 1: roots 1e8 and 1e-8.
  for (const double sign : {1.0, -1.0}) {
    const Complex x0 = sign * 1e8, x1 = sign * 1e-8;
    std::ostringstream where;
    where << "roots " << x0 << " " << x1;
    const Roots roots = SolveQuadraticAndCheck(FromRoots(x0, x1), where.str());
    ExpectAffineRoots(roots, x0, x1, kRelative, where.str());
  }
  // The same along the imaginary axis and along a diagonal: the sign choice must use the
  // complex b, not its real part.
  for (const Complex direction : {i, Complex(1.0, 1.0) / std::sqrt(2.0), Complex(-0.6, 0.8)}) {
    const Complex x0 = 1e8 * direction, x1 = 1e-8 * direction;
    std::ostringstream where;
    where << "roots " << x0 << " " << x1;
    const Roots roots = SolveQuadraticAndCheck(FromRoots(x0, x1), where.str());
    ExpectAffineRoots(roots, x0, x1, kRelative, where.str());
  }
}

TEST(PolynomialBinaryQuadratic, RandomComplexRoots) {
  std::mt19937_64 rng(kSeed + 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0), log_scale(-4.0, 4.0);
  auto random_complex = [&]() {
    return std::pow(10.0, log_scale(rng)) * Complex(uniform(rng), uniform(rng));
  };
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::string where =
        "seed " + std::to_string(kSeed + 1) + " trial " + std::to_string(trial);
    const Complex x0 = random_complex(), x1 = random_complex(), a = random_complex();
    // Separated roots only: near-double roots are ill conditioned.
    if (std::abs(x0 - x1) < 0.1 * std::max(std::abs(x0), std::abs(x1))) continue;
    const Roots roots = SolveQuadraticAndCheck(FromRoots(x0, x1, a), where);
    ExpectAffineRoots(roots, x0, x1, 1e-10, where);
  }
}

}  // namespace
