#include "tests/support/bilinear_homotopy.h"

#include <Eigen/LU>
#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <random>

namespace linkfit::testing {
namespace {

using Complex = std::complex<double>;
using Vector4c = Eigen::Vector4cd;
using Matrix4c = Eigen::Matrix4cd;
using Vector8c = Eigen::Matrix<Complex, 8, 1>;
using Matrix8c = Eigen::Matrix<Complex, 8, 8>;

constexpr int kEquations = 6;
constexpr int kPaths = 20;  // C(6, 3)

// x^T y, without the conjugation of Eigen's dot().
Complex Bilinear(const Vector4c& x, const Vector4c& y) { return x.cwiseProduct(y).sum(); }

// The homotopy H(x, t) = (1 - t) gamma g(x) + t f(x), x = (a, c), with the chart equations
// u . a = 1, v . c = 1 as rows 6 and 7.
struct Homotopy {
  std::array<Matrix4c, kEquations> b;  // the target B_k divided by ||B_k||
  std::array<Vector4c, kEquations> l;  // start system factors l_k . a
  std::array<Vector4c, kEquations> m;  // and m_k . c
  Vector4c u;                          // chart of a
  Vector4c v;                          // chart of c
  Complex gamma;

  // H, its Jacobian H_x and its derivative H_t at (x, t); any output may be null.
  void Evaluate(const Vector8c& x, double t, Vector8c* h, Matrix8c* jacobian, Vector8c* h_t) const {
    const Vector4c a = x.head<4>();
    const Vector4c c = x.tail<4>();
    const Complex start_weight = (1.0 - t) * gamma;
    for (int k = 0; k < kEquations; ++k) {
      const Vector4c bc = b[k] * c;
      const Complex f = Bilinear(a, bc);
      const Complex la = Bilinear(l[k], a);
      const Complex mc = Bilinear(m[k], c);
      const Complex g = la * mc;
      if (h != nullptr) (*h)(k) = start_weight * g + t * f;
      if (h_t != nullptr) (*h_t)(k) = f - gamma * g;
      if (jacobian != nullptr) {
        const Vector4c bta = b[k].transpose() * a;
        jacobian->block<1, 4>(k, 0) = (start_weight * mc) * l[k].transpose() + t * bc.transpose();
        jacobian->block<1, 4>(k, 4) = (start_weight * la) * m[k].transpose() + t * bta.transpose();
      }
    }
    if (h != nullptr) {
      (*h)(6) = Bilinear(u, a) - 1.0;
      (*h)(7) = Bilinear(v, c) - 1.0;
    }
    if (h_t != nullptr) (*h_t).tail<2>().setZero();
    if (jacobian != nullptr) {
      jacobian->bottomRows<2>().setZero();
      jacobian->block<1, 4>(6, 0) = u.transpose();
      jacobian->block<1, 4>(7, 4) = v.transpose();
    }
  }

  // dx/dt = -H_x^{-1} H_t; false if not finite.
  bool Tangent(const Vector8c& x, double t, Vector8c* dx) const {
    Matrix8c jacobian;
    Vector8c h_t;
    Evaluate(x, t, nullptr, &jacobian, &h_t);
    *dx = -Eigen::PartialPivLU<Matrix8c>(jacobian).solve(h_t);
    return dx->allFinite();
  }
};

// Step control of one tracking attempt; later attempts are more cautious.
struct TrackSettings {
  double initial_step;
  double max_step;
  int corrector_iterations;  // at most this many Newton steps per corrector
  double corrector_tolerance;
};

constexpr std::array<TrackSettings, 3> kAttempts = {{
    {0.02, 0.1, 3, 1e-9},
    {0.005, 0.02, 2, 1e-10},
    {0.001, 0.004, 2, 1e-11},
}};
constexpr double kMinStep = 1e-12;
constexpr int kMaxSteps = 20000;
constexpr double kDivergenceNorm = 1e8;  // |x| beyond this in the chart: the path diverges
constexpr double kContraction = 0.5;     // each Newton step must shrink by this factor
constexpr double kSameRoot = 1e-6;       // projective distance (sine of angle) of equal roots
constexpr double kTwoPi = 6.283185307179586;

// Newton's method on H(., t) from *x: converged within the settings, contracting every step.
bool Correct(const Homotopy& homotopy, double t, const TrackSettings& settings, Vector8c* x) {
  double previous = std::numeric_limits<double>::infinity();
  for (int i = 0; i < settings.corrector_iterations; ++i) {
    Vector8c h;
    Matrix8c jacobian;
    homotopy.Evaluate(*x, t, &h, &jacobian, nullptr);
    const Vector8c dx = -Eigen::PartialPivLU<Matrix8c>(jacobian).solve(h);
    if (!dx.allFinite()) return false;
    *x += dx;
    const double size = dx.norm();
    if (size <= settings.corrector_tolerance * (1.0 + x->norm())) return true;
    if (size > kContraction * previous) return false;
    previous = size;
  }
  return false;
}

// Tracks *x from t = 0 to t = 1: true if it got there.
bool Track(const Homotopy& homotopy, const TrackSettings& settings, Vector8c* x) {
  double t = 0.0;
  double step = settings.initial_step;
  int successes = 0;
  for (int steps = 0; steps < kMaxSteps && t < 1.0; ++steps) {
    step = std::min(step, 1.0 - t);
    const bool last = (1.0 - t - step) <= 1e-14;
    const double next_t = last ? 1.0 : t + step;
    const double h = next_t - t;
    // RK4 predictor.
    Vector8c k1, k2, k3, k4;
    bool ok = homotopy.Tangent(*x, t, &k1) &&
              homotopy.Tangent(*x + 0.5 * h * k1, t + 0.5 * h, &k2) &&
              homotopy.Tangent(*x + 0.5 * h * k2, t + 0.5 * h, &k3) &&
              homotopy.Tangent(*x + h * k3, next_t, &k4);
    Vector8c candidate = *x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    ok = ok && candidate.allFinite() && Correct(homotopy, next_t, settings, &candidate);
    if (ok) {
      *x = candidate;
      t = next_t;
      if (x->norm() > kDivergenceNorm) return false;
      if (++successes >= 3) {
        step = std::min(2.0 * step, settings.max_step);
        successes = 0;
      }
    } else {
      step *= 0.5;
      successes = 0;
      if (step < kMinStep) return false;
    }
  }
  return t >= 1.0;
}

// Newton's method on f (H at t = 1) to full precision: true if it converged.
bool Refine(const Homotopy& homotopy, Vector8c* x) {
  bool converged = false;
  double previous = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 20; ++i) {
    Vector8c h;
    Matrix8c jacobian;
    homotopy.Evaluate(*x, 1.0, &h, &jacobian, nullptr);
    const Vector8c dx = -Eigen::PartialPivLU<Matrix8c>(jacobian).solve(h);
    if (!dx.allFinite()) return false;
    const double size = dx.norm();
    if (converged && size >= previous) break;  // at the rounding floor: keep the last iterate
    *x += dx;
    if (size <= 1e-11 * x->norm()) converged = true;
    if (converged && size <= 1e-15 * x->norm()) break;
    previous = size;
  }
  return converged && x->allFinite() && x->norm() <= kDivergenceNorm;
}

// Unit norm, and the entry of largest modulus real and positive.
Vector4c Normalized(const Vector4c& x) {
  Eigen::Index largest = 0;
  x.cwiseAbs().maxCoeff(&largest);
  const Complex phase = x(largest) / std::abs(x(largest));
  return x / (phase * x.norm());
}

// Sine of the angle between the lines through unit vectors x and y.
double ProjectiveDistance(const Vector4c& x, const Vector4c& y) {
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) sum += std::norm(x(i) * y(j) - x(j) * y(i));
  }
  return std::sqrt(sum);
}

bool SameRoot(const HomotopyRoot& p, const HomotopyRoot& q) {
  return ProjectiveDistance(p.a, q.a) < kSameRoot && ProjectiveDistance(p.c, q.c) < kSameRoot;
}

Vector4c RandomComplexUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Vector4c x;
  for (int i = 0; i < 4; ++i) x(i) = Complex(normal(rng), normal(rng));
  return x.normalized();
}

// The solution x of the rows `rows` . x = 0 and `chart` . x = 1.
Vector4c SolveChart(const std::array<Vector4c, 3>& rows, const Vector4c& chart) {
  Matrix4c system;
  for (int i = 0; i < 3; ++i) system.row(i) = rows[i].transpose();
  system.row(3) = chart.transpose();
  return Eigen::PartialPivLU<Matrix4c>(system).solve(Vector4c::UnitW());
}

}  // namespace

int SolveBilinearByHomotopy(const std::array<Eigen::Matrix4d, 6>& matrices, std::uint64_t seed,
                            std::vector<HomotopyRoot>* roots) {
  // Each equation is tracked divided by its own norm (the roots do not change); the residual is
  // reported relative to the largest norm.
  std::array<double, kEquations> norms;
  double largest_norm = 0.0;
  for (int k = 0; k < kEquations; ++k) {
    norms[k] = matrices[k].norm();
    largest_norm = std::max(largest_norm, norms[k]);
  }

  Homotopy homotopy;
  for (int k = 0; k < kEquations; ++k) {
    homotopy.b[k] = matrices[k].cast<Complex>();
    if (norms[k] > 0.0) homotopy.b[k] /= norms[k];
  }
  std::mt19937_64 rng(seed);
  for (int k = 0; k < kEquations; ++k) {
    homotopy.l[k] = RandomComplexUnit(rng);
    homotopy.m[k] = RandomComplexUnit(rng);
  }
  homotopy.u = RandomComplexUnit(rng);
  homotopy.v = RandomComplexUnit(rng);
  const double angle = std::uniform_real_distribution<double>(0.0, kTwoPi)(rng);
  homotopy.gamma = std::polar(1.0, angle);

  // Start solutions: subset S of 3 equations vanishing through a, the others through c.
  std::vector<Vector8c> starts;
  for (int mask = 0; mask < (1 << kEquations); ++mask) {
    if (std::bitset<kEquations>(mask).count() != 3) continue;
    std::array<Vector4c, 3> a_rows, c_rows;
    int na = 0, nc = 0;
    for (int k = 0; k < kEquations; ++k) {
      if (mask & (1 << k)) {
        a_rows[na++] = homotopy.l[k];
      } else {
        c_rows[nc++] = homotopy.m[k];
      }
    }
    Vector8c start;
    start << SolveChart(a_rows, homotopy.u), SolveChart(c_rows, homotopy.v);
    starts.push_back(start);
  }

  roots->assign(kPaths, HomotopyRoot());
  // Tracks path i with the given settings into (*roots)[i].
  auto run_path = [&](int i, const TrackSettings& settings) {
    Vector8c x = starts[i];
    HomotopyRoot& root = (*roots)[i];
    root.converged = Track(homotopy, settings, &x) && Refine(homotopy, &x);
    root.a = Normalized(x.head<4>());
    root.c = Normalized(x.tail<4>());
    double residual = 0.0;
    for (int k = 0; k < kEquations; ++k) {
      residual = std::max(residual, norms[k] * std::abs(Bilinear(root.a, homotopy.b[k] * root.c)));
    }
    root.residual = largest_norm > 0.0 ? residual / largest_norm : residual;
    if (!root.a.allFinite() || !root.c.allFinite() || !std::isfinite(residual)) {
      root.converged = false;
    }
  };
  // Paths to track again: failed ones, and those ending on another path's root.
  auto suspicious = [&]() {
    std::vector<int> paths;
    for (int i = 0; i < kPaths; ++i) {
      bool bad = !(*roots)[i].converged;
      for (int j = 0; j < kPaths && !bad; ++j) {
        bad = j != i && (*roots)[j].converged && SameRoot((*roots)[i], (*roots)[j]);
      }
      if (bad) paths.push_back(i);
    }
    return paths;
  };

  for (int i = 0; i < kPaths; ++i) run_path(i, kAttempts[0]);
  for (std::size_t attempt = 1; attempt < kAttempts.size(); ++attempt) {
    const std::vector<int> paths = suspicious();
    if (paths.empty()) break;
    for (int i : paths) run_path(i, kAttempts[attempt]);
  }
  // A root reached by two paths counts once.
  for (int i = 0; i < kPaths; ++i) {
    for (int j = 0; j < i && (*roots)[i].converged; ++j) {
      if ((*roots)[j].converged && SameRoot((*roots)[i], (*roots)[j])) {
        (*roots)[i].converged = false;
      }
    }
  }
  return static_cast<int>(std::count_if(roots->begin(), roots->end(),
                                        [](const HomotopyRoot& r) { return r.converged; }));
}

}  // namespace linkfit::testing
