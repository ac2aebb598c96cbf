#include "fitting/nine_point_path.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "lib/dyad.h"
#include "lib/parallel.h"

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

// A complex number for the tracker's inner loops, with the plain formulas: std::complex's
// product checks every result for NaN (C99 Annex G recovery of infinities) and its quotient
// calls the library, which took a third of a linearisation's time; the tracker's values are
// finite and far from overflow (a path beyond NinePointTrackOptions::infinity has failed).
struct Plain {
  double re = 0.0, im = 0.0;
  Plain() = default;
  Plain(double real, double imaginary) : re(real), im(imaginary) {}
  Plain(const Complex& z) : re(z.real()), im(z.imag()) {}  // NOLINT(google-explicit-constructor)
  Complex ToComplex() const { return {re, im}; }
};
inline Plain operator+(const Plain& a, const Plain& b) { return {a.re + b.re, a.im + b.im}; }
inline Plain operator-(const Plain& a, const Plain& b) { return {a.re - b.re, a.im - b.im}; }
inline Plain operator-(const Plain& a) { return {-a.re, -a.im}; }
inline Plain operator*(const Plain& a, const Plain& b) {
  return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
}
inline Plain operator*(double a, const Plain& b) { return {a * b.re, a * b.im}; }
inline Plain& operator-=(Plain& a, const Plain& b) { return a = a - b; }
inline double SquaredNorm(const Plain& z) { return z.re * z.re + z.im * z.im; }
// 1 / z (no scaling against overflow).
inline Plain Reciprocal(const Plain& z) {
  const double size = SquaredNorm(z);
  return {z.re / size, -z.im / size};
}

// One dyad's unknowns: (x, x^, a, a^) or (y, y^, b, b^).
template <typename T>
struct DyadOf {
  T x, xh, a, ah;
};
using DyadUnknowns = DyadOf<Complex>;

template <typename T = Complex>
DyadOf<T> Dyad(const State& state, int dyad) {
  const int o = 4 * dyad;
  return {state[o], state[o + 1], state[o + 2], state[o + 3]};
}

// D1 (or D2) at point j: g x (a^ - d^) + g^ x^ (a - d) + d (a^ - x^) + d^ (a - x) - d d^.
inline Plain DyadEquation(const DyadOf<Plain>& u, Plain g, Plain gh, Plain d, Plain dh) {
  return g * u.x * (u.ah - dh) + gh * u.xh * (u.a - d) + d * (u.ah - u.xh) + dh * (u.a - u.x) -
         d * dh;
}

// LU factorisation with partial pivoting of an 8 x 8 complex matrix, in place (the reduced
// system of every Newton step). Real and imaginary parts are kept apart and the pivots'
// reciprocals stored, so that the elimination is plain real arithmetic and a solve divides
// nothing (measured 2026-11-24: a linearisation and solve took 1.1 us with std::complex
// entries, whose products check for NaN and whose quotients call the library; 0.6 us so).
class Lu8 {
 public:
  // The matrix to factor: set every entry, then Factor().
  void Set(int row, int column, const Plain& value) {
    re_[row][column] = value.re;
    im_[row][column] = value.im;
  }
  // False when a pivot is zero or not finite.
  bool Factor() {
    for (int k = 0; k < 8; ++k) {
      int pivot = k;
      double largest = re_[k][k] * re_[k][k] + im_[k][k] * im_[k][k];
      for (int r = k + 1; r < 8; ++r) {
        const double size = re_[r][k] * re_[r][k] + im_[r][k] * im_[r][k];
        if (size > largest) {
          largest = size;
          pivot = r;
        }
      }
      if (!(largest > 0.0) || !std::isfinite(largest)) return false;
      pivot_[k] = pivot;
      if (pivot != k) {
        std::swap(re_[pivot], re_[k]);
        std::swap(im_[pivot], im_[k]);
      }
      const double inverse_re = re_[k][k] / largest, inverse_im = -im_[k][k] / largest;
      inverse_re_[k] = inverse_re;
      inverse_im_[k] = inverse_im;
      for (int r = k + 1; r < 8; ++r) {
        const double factor_re = re_[r][k] * inverse_re - im_[r][k] * inverse_im;
        const double factor_im = re_[r][k] * inverse_im + im_[r][k] * inverse_re;
        re_[r][k] = factor_re;
        im_[r][k] = factor_im;
        for (int c = k + 1; c < 8; ++c) {
          re_[r][c] -= factor_re * re_[k][c] - factor_im * im_[k][c];
          im_[r][c] -= factor_re * im_[k][c] + factor_im * re_[k][c];
        }
      }
    }
    return true;
  }
  std::array<Plain, 8> Solve(const std::array<Plain, 8>& rhs) const {
    double b_re[8], b_im[8];
    for (int k = 0; k < 8; ++k) {
      b_re[k] = rhs[k].re;
      b_im[k] = rhs[k].im;
    }
    // Whole rows were swapped during the factorisation: P A = L U, P applied first.
    for (int k = 0; k < 8; ++k) {
      if (pivot_[k] != k) {
        std::swap(b_re[k], b_re[pivot_[k]]);
        std::swap(b_im[k], b_im[pivot_[k]]);
      }
    }
    for (int k = 0; k < 8; ++k) {
      for (int r = k + 1; r < 8; ++r) {
        b_re[r] -= re_[r][k] * b_re[k] - im_[r][k] * b_im[k];
        b_im[r] -= re_[r][k] * b_im[k] + im_[r][k] * b_re[k];
      }
    }
    std::array<Plain, 8> x;
    for (int k = 7; k >= 0; --k) {
      double sum_re = b_re[k], sum_im = b_im[k];
      for (int c = k + 1; c < 8; ++c) {
        sum_re -= re_[k][c] * b_re[c] - im_[k][c] * b_im[c];
        sum_im -= re_[k][c] * b_im[c] + im_[k][c] * b_re[c];
      }
      b_re[k] = sum_re * inverse_re_[k] - sum_im * inverse_im_[k];
      b_im[k] = sum_re * inverse_im_[k] + sum_im * inverse_re_[k];
      x[k] = Plain(b_re[k], b_im[k]);
    }
    return x;
  }

 private:
  double re_[8][8], im_[8][8];            // the factors L (below the diagonal) and U
  double inverse_re_[8], inverse_im_[8];  // 1 / U's diagonal
  std::array<int, 8> pivot_;
};

// The linearisation of the system at a point: per point j, the dyad equations' derivatives in
// their dyad's four unknowns (z1, z2) and in g_j and g^_j (the 3 x 2 block with D3's row), the
// block's left null vector, and the two of its rows that determine g_j, g^_j best.
struct Linearization {
  std::array<std::array<Plain, 4>, kPoints> z1, z2;
  std::array<std::array<Plain, 2>, kPoints> g0, g1, g2;  // the rows of the 3 x 2 blocks
  Lu8 lu;  // the reduced system in the dyad unknowns, factored
  std::array<std::array<Plain, 3>, kPoints> null;  // left null vector of the blocks
  std::array<std::array<int, 2>, kPoints> rows;    // the rows of largest 2 x 2 determinant
  std::array<Plain, kPoints> inverse_det;          // 1 / that determinant
};

inline void DyadDerivatives(const DyadOf<Plain>& u, Plain g, Plain gh, Plain d, Plain dh,
                            std::array<Plain, 4>* z, std::array<Plain, 2>* dg) {
  (*z)[0] = g * (u.ah - dh) - dh;  // x
  (*z)[1] = gh * (u.a - d) - d;    // x^
  (*z)[2] = gh * u.xh + dh;        // a
  (*z)[3] = g * u.x + d;           // a^
  (*dg)[0] = u.x * (u.ah - dh);    // g
  (*dg)[1] = u.xh * (u.a - d);     // g^
}

// Builds the linearisation; false when the reduced 8 x 8 system is singular.
bool Linearize(const State& state, const Parameters& parameters, Linearization* lin) {
  const DyadOf<Plain> u1 = Dyad<Plain>(state, 0), u2 = Dyad<Plain>(state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Plain g = state[G(j)], gh = state[Gh(j)];
    const Plain d = parameters[D(j)], dh = parameters[Dh(j)];
    std::array<Plain, 2>&row0 = lin->g0[j], &row1 = lin->g1[j], &row2 = lin->g2[j];
    DyadDerivatives(u1, g, gh, d, dh, &lin->z1[j], &row0);
    DyadDerivatives(u2, g, gh, d, dh, &lin->z2[j], &row1);
    row2 = {Plain(gh.re + 1.0, gh.im), Plain(g.re + 1.0, g.im)};  // D3
    // The left null vector of the 3 x 2 block: the (bilinear) cross product of its columns,
    // whose entries are the 2 x 2 determinants of the block's rows (up to sign). The largest
    // picks the two rows that determine g_j, g^_j best.
    const Plain det01 = row0[0] * row1[1] - row0[1] * row1[0];
    const Plain det02 = row0[0] * row2[1] - row0[1] * row2[0];
    const Plain det12 = row1[0] * row2[1] - row1[1] * row2[0];
    const double norms[3] = {SquaredNorm(det01), SquaredNorm(det02), SquaredNorm(det12)};
    const double norm = std::sqrt(norms[0] + norms[1] + norms[2]);
    if (!(norm > 0.0)) return false;
    int best = norms[1] > norms[0] ? 1 : 0;
    if (norms[2] > norms[best]) best = 2;
    static constexpr std::array<std::array<int, 2>, 3> kPairs = {{{0, 1}, {0, 2}, {1, 2}}};
    lin->rows[j] = kPairs[best];
    lin->inverse_det[j] = Reciprocal(best == 0 ? det01 : best == 1 ? det02 : det12);
    const double scale = 1.0 / norm;
    const std::array<Plain, 3> n = {scale * det12, scale * -det02, scale * det01};
    lin->null[j] = n;
    for (int k = 0; k < 4; ++k) {
      lin->lu.Set(j, k, n[0] * lin->z1[j][k]);
      lin->lu.Set(j, 4 + k, n[1] * lin->z2[j][k]);
    }
  }
  return lin->lu.Factor();
}

// Solves J delta = rhs (rhs ordered as the residuals: D1_j, D2_j, D3_j at rows j, 8 + j,
// 16 + j) by eliminating each point's g_j, g^_j: the null vector of its 3 x 2 block removes
// them from its three rows, leaving one row per point in the eight dyad unknowns; then each
// point's pair from its best-conditioned two rows.
State SolveLinearized(const Linearization& lin, const State& rhs) {
  std::array<Plain, 8> reduced;
  for (int j = 0; j < kPoints; ++j) {
    const std::array<Plain, 3>& n = lin.null[j];
    reduced[j] = n[0] * rhs[j] + n[1] * rhs[8 + j] + n[2] * rhs[16 + j];
  }
  const std::array<Plain, 8> dz = lin.lu.Solve(reduced);
  State delta;
  for (int k = 0; k < 8; ++k) delta[k] = dz[k].ToComplex();
  for (int j = 0; j < kPoints; ++j) {
    Plain r[3] = {rhs[j], rhs[8 + j], rhs[16 + j]};
    for (int k = 0; k < 4; ++k) {
      r[0] -= lin.z1[j][k] * dz[k];
      r[1] -= lin.z2[j][k] * dz[4 + k];
    }
    const std::array<Plain, 2>* block[3] = {&lin.g0[j], &lin.g1[j], &lin.g2[j]};
    const std::array<Plain, 2>& first = *block[lin.rows[j][0]];
    const std::array<Plain, 2>& second = *block[lin.rows[j][1]];
    const Plain r_first = r[lin.rows[j][0]], r_second = r[lin.rows[j][1]];
    const Plain inverse = lin.inverse_det[j];
    delta[G(j)] = ((r_first * second[1] - first[1] * r_second) * inverse).ToComplex();
    delta[Gh(j)] = ((first[0] * r_second - r_first * second[0]) * inverse).ToComplex();
  }
  return delta;
}

// d residual / ds at `state` along the parameter line with direction `dp`: D1_j and D2_j
// change with d_j, d^_j (at the rates -g^ x^ + a^ - x^ - d^ and -g x + a - x - d), D3_j not.
State ParameterVelocity(const State& state, const Parameters& parameters, const Parameters& dp) {
  State v = State::Zero();
  const DyadOf<Plain> u1 = Dyad<Plain>(state, 0), u2 = Dyad<Plain>(state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Plain g = state[G(j)], gh = state[Gh(j)];
    const Plain d = parameters[D(j)], dh = parameters[Dh(j)];
    const Plain rate = dp[D(j)], rate_h = dp[Dh(j)];
    const auto velocity = [&](const DyadOf<Plain>& u) {
      return (-gh * u.xh + u.ah - u.xh - dh) * rate + (-g * u.x + u.a - u.x - d) * rate_h;
    };
    v[j] = velocity(u1).ToComplex();
    v[8 + j] = velocity(u2).ToComplex();
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
  const DyadOf<Plain> u1 = Dyad<Plain>(state, 0), u2 = Dyad<Plain>(state, 1);
  for (int j = 0; j < kPoints; ++j) {
    const Plain g = state[G(j)], gh = state[Gh(j)];
    const Plain d = parameters[D(j)], dh = parameters[Dh(j)];
    residual[j] = DyadEquation(u1, g, gh, d, dh).ToComplex();
    residual[8 + j] = DyadEquation(u2, g, gh, d, dh).ToComplex();
    residual[16 + j] = (g * gh + g + gh).ToComplex();
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
    const Parameters parameters = from + s * dp;
    if (!Linearize(x, parameters, &lin)) return false;
    *v = SolveLinearized(lin, -ParameterVelocity(x, parameters, dp));
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
    // The next step's velocity with the corrector's last linearization, made at most
    // options.corrector_tolerance (relative) away: as good as a fresh one for the predictor.
    if (s < 1.0) {
      k1 = SolveLinearized(lin, -ParameterVelocity(*state, from + s * dp, dp));
      if (!k1.allFinite()) return false;
    }
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
  // The paths are independent: tracked on options.threads, then read in the start's order.
  const size_t count = start.solutions.size();
  std::vector<State> ends = start.solutions;
  std::vector<char> tracked(count, 0);
  ParallelFor(count, ThreadCount(options.threads), [&](size_t i) {
    tracked[i] = TrackNinePoint(start.parameters, target, options.track, &ends[i]);
  });
  for (size_t i = 0; i < count; ++i) {
    const State& state = ends[i];
    ++local.paths;
    if (!tracked[i]) {
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
