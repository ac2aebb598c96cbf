#include "fitting/nine_point_path.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "lib/dyad.h"

namespace linkfit {
namespace {

using Complex = std::complex<double>;
using State = NinePointState;
using Parameters = NinePointParameters;

// Unknowns (NinePointState) and parameters (NinePointParameters) by name.
constexpr int kX = 0, kXh = 1, kA = 2, kAh = 3, kY = 4, kYh = 5, kB = 6, kBh = 7;
constexpr int kPoints = 8;  // displacements d_1..d_8 (nine points)
int G(int j) { return 8 + j; }
int Gh(int j) { return 16 + j; }
int D(int j) { return j; }
int Dh(int j) { return 8 + j; }

// One dyad's unknowns: (x, x^, a, a^) or (y, y^, b, b^).
struct DyadUnknowns {
  Complex x, xh, a, ah;
};

DyadUnknowns Dyad(const State& state, int dyad) {
  const int o = 4 * dyad;
  return {state[o], state[o + 1], state[o + 2], state[o + 3]};
}

// D1 (or D2) at point j: g x (a^ - d^) + g^ x^ (a - d) + d (a^ - x^) + d^ (a - x) - d d^.
Complex DyadEquation(const DyadUnknowns& u, Complex g, Complex gh, Complex d, Complex dh) {
  return g * u.x * (u.ah - dh) + gh * u.xh * (u.a - d) + d * (u.ah - u.xh) + dh * (u.a - u.x) -
         d * dh;
}

// LU factorisation with partial pivoting of an 8 x 8 complex matrix, in place (the reduced
// system of every Newton step; measured 2026-11-24: Eigen::PartialPivLU took 0.75 us of the
// 1.4 us a linearisation cost, this loop a third of that).
class Lu8 {
 public:
  // The matrix to factor: fill it, then Factor().
  Complex& operator()(int row, int column) { return a_[row][column]; }
  // False when a pivot is zero or not finite.
  bool Factor() {
    for (int k = 0; k < 8; ++k) {
      int pivot = k;
      double largest = std::norm(a_[k][k]);
      for (int r = k + 1; r < 8; ++r) {
        const double size = std::norm(a_[r][k]);
        if (size > largest) {
          largest = size;
          pivot = r;
        }
      }
      if (!(largest > 0.0) || !std::isfinite(largest)) return false;
      pivot_[k] = pivot;
      if (pivot != k) std::swap(a_[pivot], a_[k]);
      const Complex inverse = 1.0 / a_[k][k];
      for (int r = k + 1; r < 8; ++r) {
        const Complex factor = a_[r][k] * inverse;
        a_[r][k] = factor;
        for (int c = k + 1; c < 8; ++c) a_[r][c] -= factor * a_[k][c];
      }
    }
    return true;
  }
  Eigen::Matrix<Complex, 8, 1> Solve(Eigen::Matrix<Complex, 8, 1> b) const {
    // Whole rows were swapped during the factorisation: P A = L U, P applied first.
    for (int k = 0; k < 8; ++k) {
      if (pivot_[k] != k) std::swap(b[k], b[pivot_[k]]);
    }
    for (int k = 0; k < 8; ++k) {
      for (int r = k + 1; r < 8; ++r) b[r] -= a_[r][k] * b[k];
    }
    for (int k = 7; k >= 0; --k) {
      for (int c = k + 1; c < 8; ++c) b[k] -= a_[k][c] * b[c];
      b[k] /= a_[k][k];
    }
    return b;
  }

 private:
  std::array<std::array<Complex, 8>, 8> a_;
  std::array<int, 8> pivot_;
};

// The linearisation of the system at a point: per point j, the dyad equations' derivatives in
// their dyad's four unknowns (z1, z2), in g_j and g^_j (the 3 x 2 block with D3's row), and in
// the parameters d_j, d^_j (for the homotopy's velocity).
struct Linearization {
  std::array<std::array<Complex, 4>, kPoints> z1, z2;
  std::array<Eigen::Matrix<Complex, 3, 2>, kPoints> g;
  std::array<std::array<Complex, 2>, kPoints> p1, p2;  // d(D1)/d(d, d^), d(D2)/d(d, d^)
  Lu8 lu;  // the reduced system in the dyad unknowns, factored
  std::array<Eigen::Matrix<Complex, 1, 3>, kPoints> null;  // left null vector of g[j]
};

inline void DyadDerivatives(const DyadUnknowns& u, Complex g, Complex gh, Complex d, Complex dh,
                            std::array<Complex, 4>* z, Complex* dg, Complex* dgh,
                            std::array<Complex, 2>* p) {
  (*z)[0] = g * (u.ah - dh) - dh;  // x
  (*z)[1] = gh * (u.a - d) - d;    // x^
  (*z)[2] = gh * u.xh + dh;        // a
  (*z)[3] = g * u.x + d;           // a^
  *dg = u.x * (u.ah - dh);
  *dgh = u.xh * (u.a - d);
  (*p)[0] = -gh * u.xh + u.ah - u.xh - dh;
  (*p)[1] = -g * u.x + u.a - u.x - d;
}

// Builds the linearisation; false when the reduced 8 x 8 system is singular.
bool Linearize(const State& state, const Parameters& parameters, Linearization* lin) {
  const DyadUnknowns u1 = Dyad(state, 0), u2 = Dyad(state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Complex g = state[G(j)], gh = state[Gh(j)];
    const Complex d = parameters[D(j)], dh = parameters[Dh(j)];
    Complex a, b, c, e;
    DyadDerivatives(u1, g, gh, d, dh, &lin->z1[j], &a, &b, &lin->p1[j]);
    DyadDerivatives(u2, g, gh, d, dh, &lin->z2[j], &c, &e, &lin->p2[j]);
    Eigen::Matrix<Complex, 3, 2>& block = lin->g[j];
    block(0, 0) = a;
    block(0, 1) = b;
    block(1, 0) = c;
    block(1, 1) = e;
    block(2, 0) = gh + 1.0;
    block(2, 1) = g + 1.0;
    // The left null vector of the 3 x 2 block: the (bilinear) cross product of its columns.
    const auto& p = lin->g[j].col(0);
    const auto& q = lin->g[j].col(1);
    Eigen::Matrix<Complex, 1, 3> n;
    n << p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0];
    const double norm = std::sqrt(std::norm(n[0]) + std::norm(n[1]) + std::norm(n[2]));
    if (!(norm > 0.0)) return false;
    n *= 1.0 / norm;
    lin->null[j] = n;
    for (int k = 0; k < 4; ++k) {
      lin->lu(j, k) = n[0] * lin->z1[j][k];
      lin->lu(j, 4 + k) = n[1] * lin->z2[j][k];
    }
  }
  return lin->lu.Factor();
}

// Solves J delta = rhs (rhs ordered as the residuals: D1_j, D2_j, D3_j at rows j, 8 + j,
// 16 + j) by eliminating each point's g_j, g^_j: the null vector of its 3 x 2 block removes
// them from its three rows, leaving one row per point in the eight dyad unknowns; then each
// point's pair from its best-conditioned two rows.
State SolveLinearized(const Linearization& lin, const State& rhs) {
  Eigen::Matrix<Complex, 8, 1> reduced;
  for (int j = 0; j < kPoints; ++j) {
    reduced[j] =
        lin.null[j][0] * rhs[j] + lin.null[j][1] * rhs[8 + j] + lin.null[j][2] * rhs[16 + j];
  }
  const Eigen::Matrix<Complex, 8, 1> dz = lin.lu.Solve(reduced);
  State delta;
  delta.head<8>() = dz;
  for (int j = 0; j < kPoints; ++j) {
    Eigen::Matrix<Complex, 3, 1> r;
    r[0] = rhs[j];
    r[1] = rhs[8 + j];
    r[2] = rhs[16 + j];
    for (int k = 0; k < 4; ++k) {
      r[0] -= lin.z1[j][k] * dz[k];
      r[1] -= lin.z2[j][k] * dz[4 + k];
    }
    // The two rows with the largest 2 x 2 determinant.
    const auto& g = lin.g[j];
    int best_first = 0, best_second = 1;
    double best = -1.0;
    for (const auto& [first, second] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
      const double det = std::norm(g(first, 0) * g(second, 1) - g(first, 1) * g(second, 0));
      if (det > best) {
        best = det;
        best_first = first;
        best_second = second;
      }
    }
    const Complex det = g(best_first, 0) * g(best_second, 1) - g(best_first, 1) * g(best_second, 0);
    delta[G(j)] = (r[best_first] * g(best_second, 1) - g(best_first, 1) * r[best_second]) / det;
    delta[Gh(j)] = (g(best_first, 0) * r[best_second] - r[best_first] * g(best_second, 0)) / det;
  }
  return delta;
}

// d residual / ds along the parameter line with direction `dp`.
State ParameterVelocity(const Linearization& lin, const Parameters& dp) {
  State v = State::Zero();
  for (int j = 0; j < kPoints; ++j) {
    v[j] = lin.p1[j][0] * dp[D(j)] + lin.p1[j][1] * dp[Dh(j)];
    v[8 + j] = lin.p2[j][0] * dp[D(j)] + lin.p2[j][1] * dp[Dh(j)];
  }
  return v;
}

// The largest |entry| (by the larger of real and imaginary part: no square roots).
double Norm(const State& state) {
  double largest = 0.0;
  for (int k = 0; k < state.size(); ++k) {
    largest = std::max({largest, std::abs(state[k].real()), std::abs(state[k].imag())});
  }
  return largest;
}

// Newton's method at fixed parameters: up to `iterations` steps; true when the last update is
// below `tolerance` (relative to 1 + |state|) and the updates contract. `first` (when given)
// receives the first update's size, relative: the predictor's error.
// `lin` is scratch space (the tracker's, so that no step builds a fresh one).
bool Correct(const Parameters& parameters, int iterations, double tolerance, Linearization* lin,
             State* state, double* first = nullptr) {
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0; k < iterations; ++k) {
    if (!Linearize(*state, parameters, lin)) return false;
    const State delta = SolveLinearized(*lin, -NinePointResidual(*state, parameters));
    const double size = Norm(delta);
    if (!std::isfinite(size) || (k > 0 && size > 0.5 * previous)) return false;
    *state += delta;
    const double relative = size / (1.0 + Norm(*state));
    if (k == 0 && first) *first = relative;
    if (relative <= tolerance) return true;
    previous = size;
  }
  return false;
}

bool Nondegenerate(const State& state) {
  const double scale = 1.0 + Norm(state);
  const auto apart = [&](int i, int k) { return std::abs(state[i] - state[k]) > 1e-8 * scale; };
  return state.allFinite() && apart(kX, kY) && apart(kXh, kYh) && apart(kX, kA) &&
         apart(kXh, kAh) && apart(kY, kB) && apart(kYh, kBh);
}

// The same solution with the two dyads' roles exchanged.
State Swapped(const State& state) {
  State swapped = state;
  swapped.head<4>() = state.segment<4>(4);
  swapped.segment<4>(4) = state.head<4>();
  return swapped;
}

Complex ComplexOf(const Eigen::Vector2d& point) { return {point.x(), point.y()}; }
Eigen::Vector2d PointOf(Complex z) { return {z.real(), z.imag()}; }

}  // namespace

const NinePointStart& BuiltInNinePointStart() {
  static const NinePointStart start = [] {
#include "fitting/nine_point_start.inc"
    NinePointStart made;
    for (int k = 0; k < 16; ++k) {
      made.parameters[k] =
          Complex(kNinePointStartParameters[2 * k], kNinePointStartParameters[2 * k + 1]);
    }
    for (int orbit = 0; orbit < kNinePointStartOrbits; ++orbit) {
      State state = State::Zero();
      for (int k = 0; k < 8; ++k) {
        state[k] = Complex(kNinePointStartSolutions[16 * orbit + 2 * k],
                           kNinePointStartSolutions[16 * orbit + 2 * k + 1]);
      }
      if (CompleteNinePointState(made.parameters, &state)) made.solutions.push_back(state);
    }
    return made;
  }();
  return start;
}

NinePointState NinePointResidual(const NinePointState& state,
                                 const NinePointParameters& parameters) {
  State residual;
  const DyadUnknowns u1 = Dyad(state, 0), u2 = Dyad(state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Complex g = state[G(j)], gh = state[Gh(j)];
    const Complex d = parameters[D(j)], dh = parameters[Dh(j)];
    residual[j] = DyadEquation(u1, g, gh, d, dh);
    residual[8 + j] = DyadEquation(u2, g, gh, d, dh);
    residual[16 + j] = g * gh + g + gh;
  }
  return residual;
}

bool CompleteNinePointState(const NinePointParameters& parameters, NinePointState* state) {
  const DyadUnknowns u1 = Dyad(*state, 0), u2 = Dyad(*state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Complex d = parameters[D(j)], dh = parameters[Dh(j)];
    // [x (a^ - d^)  x^ (a - d)] [g]     [d (a^ - x^) + d^ (a - x) - d d^]
    // [y (b^ - d^)  y^ (b - d)] [g^] = -[d (b^ - y^) + d^ (b - y) - d d^]
    const Complex m00 = u1.x * (u1.ah - dh), m01 = u1.xh * (u1.a - d);
    const Complex m10 = u2.x * (u2.ah - dh), m11 = u2.xh * (u2.a - d);
    const Complex r0 = -(d * (u1.ah - u1.xh) + dh * (u1.a - u1.x) - d * dh);
    const Complex r1 = -(d * (u2.ah - u2.xh) + dh * (u2.a - u2.x) - d * dh);
    const Complex det = m00 * m11 - m01 * m10;
    if (!(std::abs(det) > 0.0)) return false;
    (*state)[G(j)] = (r0 * m11 - m01 * r1) / det;
    (*state)[Gh(j)] = (m00 * r1 - r0 * m10) / det;
  }
  return state->allFinite();
}

std::vector<NinePointState> NinePointOrbit(const NinePointState& state,
                                           const NinePointParameters& parameters) {
  // The Roberts-Chebyshev cognate (in one orientation): the crank of the cognate is the
  // parallelogram's side, (x, a, y, b) -> ((x - a) y / (x - y), (b x - a y) / (x - y), a - x,
  // a), the same in the hatted unknowns; the rotations follow (CompleteNinePointState).
  const auto cognate = [&](const State& s, State* t) {
    const auto map = [](Complex x, Complex a, Complex y, Complex b, Complex* out) {
      out[0] = (x - a) * y / (x - y);
      out[1] = (b * x - a * y) / (x - y);
      out[2] = a - x;
      out[3] = a;
    };
    Complex plain[4], hatted[4];
    map(s[kX], s[kA], s[kY], s[kB], plain);
    map(s[kXh], s[kAh], s[kYh], s[kBh], hatted);
    *t = s;
    (*t)[kX] = plain[0];
    (*t)[kA] = plain[1];
    (*t)[kY] = plain[2];
    (*t)[kB] = plain[3];
    (*t)[kXh] = hatted[0];
    (*t)[kAh] = hatted[1];
    (*t)[kYh] = hatted[2];
    (*t)[kBh] = hatted[3];
    return t->head<8>().allFinite() && CompleteNinePointState(parameters, t);
  };
  std::vector<State> orbit = {Swapped(state)};
  State first, second;
  if (cognate(state, &first)) {
    orbit.push_back(first);
    orbit.push_back(Swapped(first));
    if (cognate(first, &second)) {
      orbit.push_back(second);
      orbit.push_back(Swapped(second));
    }
  }
  return orbit;
}

bool TrackNinePoint(const NinePointParameters& from, const NinePointParameters& to,
                    const NinePointTrackOptions& options, NinePointState* state) {
  const Parameters dp = to - from;
  Linearization lin;
  // dx/ds = -J^-1 dF/ds.
  const auto velocity = [&](double s, const State& x, State* v) {
    if (!Linearize(x, from + s * dp, &lin)) return false;
    *v = SolveLinearized(lin, -ParameterVelocity(lin, dp));
    return v->allFinite();
  };
  double s = 0.0, h = options.initial_step;
  // The velocity where the step starts: kept when a step is rejected (same s, same state).
  State k1;
  if (!velocity(s, *state, &k1)) return false;
  for (int step = 0; step < options.max_steps && s < 1.0; ++step) {
    h = std::min(h, 1.0 - s);
    // Runge-Kutta 4 predictor, Newton corrector.
    State k2, k3, k4;
    bool ok = velocity(s + 0.5 * h, *state + 0.5 * h * k1, &k2) &&
              velocity(s + 0.5 * h, *state + 0.5 * h * k2, &k3) &&
              velocity(s + h, *state + h * k3, &k4);
    State next = *state + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    double error = 0.0;
    ok = ok && Correct(from + (s + h) * dp, options.corrector_iterations,
                       options.corrector_tolerance, &lin, &next, &error);
    if (!ok) {
      h *= 0.5;
      if (h < options.min_step) return false;
      continue;
    }
    s += h;
    *state = next;
    if (Norm(*state) > options.infinity) return false;
    if (s < 1.0 && !velocity(s, *state, &k1)) return false;
    // The predictor's error grows as h^5: the next step aims at options.predictor_tolerance.
    const double factor =
        error > 0.0 ? 0.9 * std::pow(options.predictor_tolerance / error, 0.2) : 2.0;
    h = std::min(h * std::clamp(factor, 0.5, 2.0), options.max_step);
  }
  if (s < 1.0) return false;
  return Correct(to, 8, 1e-13, &lin, state) ||
         NinePointResidual(*state, to).cwiseAbs().maxCoeff() <= 1e-10 * (1.0 + Norm(*state));
}

NinePointStart ComputeNinePointStart(std::uint64_t seed, int orbits, int max_loops) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto random_complex = [&] { return Complex(normal(rng), normal(rng)); };
  NinePointStart start;
  // One solution made for a random instance: random dyad unknowns and rotations, then each
  // point's d_j, d^_j from D1 and D2 (their difference is linear in d, d^; D1 then quadratic).
  State first;
  for (;;) {
    for (int k = 0; k < 8; ++k) first[k] = random_complex();
    bool made = true;
    for (int j = 0; j < kPoints && made; ++j) {
      const Complex g = random_complex();
      const Complex gh = -g / (1.0 + g);
      first[G(j)] = g;
      first[Gh(j)] = gh;
      // D = c0 + c1 d + c2 d^ - d d^ for each dyad.
      const auto coefficients = [&](const DyadUnknowns& u, Complex* c) {
        c[0] = g * u.x * u.ah + gh * u.xh * u.a;
        c[1] = -gh * u.xh + u.ah - u.xh;
        c[2] = -g * u.x + u.a - u.x;
      };
      Complex c[3], e[3];
      coefficients(Dyad(first, 0), c);
      coefficients(Dyad(first, 1), e);
      const Complex e0 = c[0] - e[0], e1 = c[1] - e[1], e2 = c[2] - e[2];
      // e1 d^2 + (c1 e2 - c2 e1 + e0) d + (c0 e2 - c2 e0) = 0.
      const Complex qa = e1, qb = c[1] * e2 - c[2] * e1 + e0, qc = c[0] * e2 - c[2] * e0;
      const Complex root = (-qb + std::sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
      const Complex dh = -(e0 + e1 * root) / e2;
      start.parameters[D(j)] = root;
      start.parameters[Dh(j)] = dh;
      made = std::isfinite(std::abs(root)) && std::isfinite(std::abs(dh));
    }
    if (made && NinePointResidual(first, start.parameters).cwiseAbs().maxCoeff() < 1e-10 &&
        Nondegenerate(first)) {
      break;
    }
  }
  std::vector<State> known;  // every member of every orbit found
  const auto is_known = [&](const State& state) {
    const double tolerance = 1e-6 * (1.0 + state.head<8>().cwiseAbs().maxCoeff());
    return std::any_of(known.begin(), known.end(), [&](const State& other) {
      return (other.head<8>() - state.head<8>()).cwiseAbs().maxCoeff() <= tolerance;
    });
  };
  const auto add = [&](const State& state) {
    start.solutions.push_back(state);
    known.push_back(state);
    for (const State& member : NinePointOrbit(state, start.parameters)) known.push_back(member);
  };
  add(first);
  NinePointTrackOptions options;
  int idle = 0;
  while (static_cast<int>(start.solutions.size()) < orbits && idle < max_loops) {
    Parameters p1, p2;
    for (int k = 0; k < 16; ++k) {
      p1[k] = random_complex();
      p2[k] = random_complex();
    }
    const size_t before = start.solutions.size();
    for (size_t i = 0; i < before; ++i) {
      State state = start.solutions[i];  // a copy: add() may grow the vector
      if (!TrackNinePoint(start.parameters, p1, options, &state) ||
          !TrackNinePoint(p1, p2, options, &state) ||
          !TrackNinePoint(p2, start.parameters, options, &state) || !Nondegenerate(state) ||
          is_known(state)) {
        continue;
      }
      add(state);
      if (static_cast<int>(start.solutions.size()) >= orbits) break;
    }
    idle = start.solutions.size() > before ? 0 : idle + 1;
  }
  return start;
}

int SolveNinePointPath(const std::vector<Eigen::Vector2d>& points, const NinePointOptions& options,
                       std::vector<PathFourBar>* four_bars, NinePointSummary* summary) {
  const auto clock_start = std::chrono::steady_clock::now();
  four_bars->clear();
  NinePointSummary local;
  // Scaled frame: the first point at the origin, lengths in L (RMS distance from the centroid).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : points) centroid += point / points.size();
  double length = 0.0;
  for (const Eigen::Vector2d& point : points) length += (point - centroid).squaredNorm();
  length = std::sqrt(length / points.size());
  if (points.size() != 9 || !(length > 0.0)) return 0;
  Similarity2 frame;  // the scaled frame (R_0 the origin, lengths in L) -> the task's
  frame.scale = length;
  frame.translation = points[0];
  Parameters target;
  for (int j = 0; j < kPoints; ++j) {
    const Complex d = ComplexOf((points[j + 1] - points[0]) / length);
    target[D(j)] = d;
    target[Dh(j)] = std::conj(d);
  }
  const NinePointStart& start = BuiltInNinePointStart();
  for (State state : start.solutions) {
    ++local.paths;
    if (!TrackNinePoint(start.parameters, target, options.track, &state)) {
      ++local.paths_failed;
      continue;
    }
    const double scale = 1.0 + state.head<8>().cwiseAbs().maxCoeff();
    bool real = Nondegenerate(state);
    for (int k = 0; k < 8 && real; k += 2) {
      real = std::abs(state[k + 1] - std::conj(state[k])) <= options.real_tolerance * scale;
    }
    if (!real) continue;
    ++local.real_solutions;
    std::vector<State> members = {state};
    if (options.cognates) {
      const std::vector<State> orbit = NinePointOrbit(state, target);
      members.insert(members.end(), orbit.begin(), orbit.end());
    } else if (options.swap_dyads) {
      members.push_back(Swapped(state));
    }
    for (const State& member : members) {
      const Complex x = member[kX], a = member[kA], y = member[kY], b = member[kB];
      PathFourBar four_bar;
      four_bar.coupler_point = points[0];
      four_bar.input =
          TransformDyad(PlanarDyad::RR(PointOf(a), PointOf(x), std::abs(x - a)), frame, frame);
      four_bar.output =
          TransformDyad(PlanarDyad::RR(PointOf(b), PointOf(y), std::abs(y - b)), frame, frame);
      four_bars->push_back(four_bar);
    }
  }
  local.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  if (summary) *summary = local;
  return static_cast<int>(four_bars->size());
}

}  // namespace linkfit
