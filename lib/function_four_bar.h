// A planar four-bar function generator: the output crank's angle as a function of the input
// crank's (issue 17, items 6-8).
//
// In the ground frame g (the input pivot A at the origin, the output pivot B at (d, 0); angles
// counter-clockwise from the ground line A -> B) the input pin is P = a (cos t2, sin t2), the
// output pin Q = (d + c cos t4, c sin t4), and the coupler keeps |P - Q| = b. The crank angles
// are t2 = input_offset + phi and t4 = output_offset + psi, with phi, psi a task's angles (absolute
// angles: both offsets 0). Expanding |P - Q|^2 = b^2:
//   2c (a cos t2 - d) cos t4 + 2ac sin t2 sin t4 = a^2 + c^2 + d^2 - b^2 - 2ad cos t2,      (F)
// that is A cos t4 + B sin t4 = C, so t4 = atan2(B, A) + sigma acos(C / hypot(A, B)) with sigma
// = +1 or -1 the assembly, wherever |C| <= hypot(A, B): where |P - B| lies in [|b - c|, b + c],
// and |P - B|^2 = a^2 + d^2 - 2ad cos t2 is a sinusoid of t2 (lib/four_bar_closure.h).
// Dividing (F) by 2ac gives Freudenstein's equation, linear in K = (K1, K2, K3):
//   K1 cos t4 - K2 cos t2 + K3 = cos(t2 - t4),
//   K1 = d / a, K2 = d / c, K3 = (a^2 - b^2 + c^2 + d^2) / (2ac).                         (Fr)
#ifndef LINKFIT_LIB_FUNCTION_FOUR_BAR_H_
#define LINKFIT_LIB_FUNCTION_FOUR_BAR_H_

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace linkfit {

// One precision point of a function task: the input and output crank angles (radians).
struct FunctionPair {
  double input = 0.0;
  double output = 0.0;
  double weight = 1.0;
  bool exact = false;
};

struct FunctionFourBar {
  double ground = 1.0;          // d = |A B|
  double input_length = 1.0;    // a
  double coupler_length = 1.0;  // b
  double output_length = 1.0;   // c
  // t2 = input_offset + phi, t4 = output_offset + psi (radians; 0 for absolute angles).
  double input_offset = 0.0;
  double output_offset = 0.0;
  int assembly = 1;  // sigma, +1 or -1 (file comment)

  // The output angle psi at input angle phi on assembly `sigma` (a task's angles); false where the
  // four-bar does not assemble.
  bool Output(double phi, int sigma, double* psi) const;
  bool Output(double phi, double* psi) const { return Output(phi, assembly, psi); }
  // Whether every length is finite and positive.
  bool Valid() const;
};

// The output crank angle t4 of (F) at crank angle t2 on assembly sigma, for the Ceres refiner
// (T a double or a Jet): false where it does not assemble; then *t4 is the angle at the nearest
// assembly (acos clamped) and *miss = |C| / hypot(A, B) - 1 > 0, else *miss = 0.
template <typename T>
bool OutputCrankAngle(const T& a, const T& b, const T& c, const T& d, const T& t2, int sigma, T* t4,
                      T* miss) {
  using std::acos;
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T coefficient_a = T(2.0) * c * (a * cos(t2) - d);
  const T coefficient_b = T(2.0) * a * c * sin(t2);
  const T coefficient_c = a * a + c * c + d * d - b * b - T(2.0) * a * d * cos(t2);
  const T norm = sqrt(coefficient_a * coefficient_a + coefficient_b * coefficient_b + T(1e-300));
  T ratio = coefficient_c / norm;
  bool assembles = true;
  *miss = T(0.0);
  // acos' derivative is infinite at +-1: the ratio is kept a hair inside.
  constexpr double kInside = 1.0 - 1e-12;
  if (ratio > T(kInside)) {
    if (ratio > T(1.0)) {
      *miss = ratio - T(1.0);
      assembles = false;
    }
    ratio = T(kInside);
  } else if (ratio < T(-kInside)) {
    if (ratio < T(-1.0)) {
      *miss = -ratio - T(1.0);
      assembles = false;
    }
    ratio = T(-kInside);
  }
  *t4 = atan2(coefficient_b, coefficient_a) + T(static_cast<double>(sigma)) * acos(ratio);
  return assembles;
}

// Angle in (-pi, pi].
double WrapToPi(double angle);

// The output error psi(phi) - psi of `pair` on assembly sigma, wrapped, with the output taken at
// the nearest stationary configuration where the input is beyond the crank's reach; *miss (when
// given) is that reach's miss (OutputCrankAngle), 0 within reach. The refiner's, the search's and
// the analysis's error.
double ReachedOutputError(const FunctionFourBar& four_bar, const FunctionPair& pair, int sigma,
                          double* miss = nullptr);

// The four-bar's pivots and pins in Sigma, in the configuration of input angle phi: the task's
// ground line from `input_pivot` (A) to `output_pivot` (B).
struct FunctionConfiguration {
  Eigen::Vector2d input_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d input_moving = Eigen::Vector2d::Zero();
  Eigen::Vector2d output_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d output_moving = Eigen::Vector2d::Zero();
};
std::optional<FunctionConfiguration> ConfigurationAt(const FunctionFourBar& four_bar, double phi,
                                                     const Eigen::Vector2d& input_pivot,
                                                     const Eigen::Vector2d& output_pivot);

// How a four-bar generates the pairs, driven by its input from the first pair's configuration
// (its assembly `four_bar.assembly`):
//   - each pair's output angle on the first pair's circuit: the closure's interval holding the
//     first pair's input, and its assembly (an input that turns fully keeps it; a limited input
//     reaches the other assembly only through a stationary configuration, where it reverses);
//   - "circuit": a pair's input lies in another interval of the closure, or (a full turn) is met
//     on the other assembly only; "branch": a limited input needs the other assembly;
//   - the transmission angle (at the output pin, between coupler and output crank, folded to
//     [0, 90]) over the inputs from the smallest to the largest pair input, as given;
//   - the Grashof class with the input driven (lib/mechanism.h GrashofType).
struct FunctionAnalysis {
  bool assembles_first = false;     // the first pair's input assembles
  std::vector<double> errors;       // psi(phi_j) - psi_j, wrapped; empty when !assembles_first
  std::optional<double> max_error;  // over the pairs (radians), absent: !assembles_first
  std::optional<double> rms_error;  // weighted RMS
  std::string error_note;           // why max_error is absent
  // "assembly" (the first pair's input does not assemble), "circuit", "branch"
  std::vector<std::string> defects;
  bool input_rotates_fully = false;
  bool output_rotates_fully = false;
  std::string grashof;
  std::optional<double> transmission_min_deg;
  std::optional<double> transmission_max_deg;
};

FunctionAnalysis AnalyzeFunctionFourBar(const FunctionFourBar& four_bar,
                                        const std::vector<FunctionPair>& pairs);

// A function's whole input range (its samples, e.g. Task::function_samples), driven from the
// first pair's configuration as AnalyzeFunctionFourBar drives the pairs: the largest output error
// over the samples (the structural error between the precision points, radians) when it reaches
// every one on that circuit and assembly; otherwise absent, and `note` names the first sample it
// does not reach. The transmission angle over the samples' input span (and the first pair's).
struct FunctionRangeAnalysis {
  std::optional<double> max_error;
  std::string note;
  std::optional<double> transmission_min_deg;
  std::optional<double> transmission_max_deg;
};

FunctionRangeAnalysis AnalyzeFunctionRange(const FunctionFourBar& four_bar,
                                           const FunctionPair& first,
                                           const std::vector<FunctionPair>& samples);

// The assembly that meets `pair` best (the smaller output error), or 0 when the pair's input does
// not assemble.
int NearestAssembly(const FunctionFourBar& four_bar, const FunctionPair& pair);

// The structural error over `samples` (e.g. a function's dense samples): the largest |psi(phi) -
// psi| on the four-bar's assembly (radians); absent when one does not assemble.
std::optional<double> LargestOutputError(const FunctionFourBar& four_bar,
                                         const std::vector<FunctionPair>& samples);

// How far the data's precision can move a four-bar fitted to the pairs (exactly or by least
// squares), to first order: with r(p) the pairs' output errors over the parameters p = (a, b, c)
// (and the offsets (o2, o4) when `free_offsets`), J = dr/dp by central differences, W the
// weights, the fit moves by dp = -(J^T W J)^-1 J^T W dr when the data move, and a pair's
// rounding (its input and output each by up to `angle_precision`) moves its error by
// dr_j = (1 + |dpsi/dphi|_j) angle_precision at most. The bound is the worst case
// sum_j |M_kj| dr_j, M = (J^T W J)^-1 J^T W, of the largest of |da|, |db|, |dc|, a |do2|,
// c |do4| (length units). Infinity where J^T W J is singular (the pairs do not determine the
// four-bar) or a pair does not assemble.
double FunctionErrorBound(const FunctionFourBar& four_bar, const std::vector<FunctionPair>& pairs,
                          bool free_offsets, double angle_precision);

}  // namespace linkfit

#endif  // LINKFIT_LIB_FUNCTION_FOUR_BAR_H_
