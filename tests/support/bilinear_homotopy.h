// An independent root finder for six bilinear equations a^T B_k c = 0 on P^3 x P^3, used by the
// tests to cross-check the production solver of the seven-pose spatial Burmester problem (a is
// the homogeneous sphere center, c the homogeneous moving point of a 5-SS platform dyad).
//
// Method: a multihomogeneous homotopy with exactly 20 paths (the degree of the Segre variety
// P^3 x P^3 in P^15). Start system g_k = (l_k . a)(m_k . c) with random complex l_k, m_k; its 20
// solutions pick 3 of the 6 equations to vanish through a and the other 3 through c. The paths
// of H = (1 - t) gamma g + t f (random complex gamma) are tracked from t = 0 to 1 in random
// complex affine charts u . a = 1, v . c = 1, by an RK4 predictor and a Newton corrector with
// adaptive steps, and refined at t = 1 by Newton's method on f. Roots with a_4 = 0 or c_4 = 0
// (points at infinity) are finite in the random chart, and so are found like any other.
#ifndef LINKFIT_TESTS_SUPPORT_BILINEAR_HOMOTOPY_H_
#define LINKFIT_TESTS_SUPPORT_BILINEAR_HOMOTOPY_H_

#include <Eigen/Core>
#include <array>
#include <complex>
#include <cstdint>
#include <vector>

namespace linkfit::testing {

struct HomotopyRoot {
  Eigen::Vector4cd a;      // normalized to unit norm
  Eigen::Vector4cd c;      // normalized to unit norm
  bool converged = false;  // the path reached t = 1 and Newton converged
  double residual = 0.0;   // max_k |a^T B_k c| with unit a, c, divided by max_k ||B_k||
};

// All 20 paths of the multihomogeneous homotopy for a^T B_k c = 0, k = 0..5. Returns the number
// of converged roots; `roots` receives all 20 (converged or not).
//
// Details: ||B_k|| is the Frobenius norm. Besides unit norm, a and c are phase-normalized: the
// entry of largest modulus is real and positive, so a real root has (numerically) zero
// imaginary parts. The random start system, gamma and charts are drawn from std::mt19937_64
// seeded with `seed`: the result is deterministic for a given seed. Paths that fail (step size
// underflow, divergence in the chart) or end on the same root as another path are tracked
// again with more cautious step control before they are reported as not converged; a path that
// still ends on a root an earlier path reached is reported as not converged too, so that the
// converged roots are distinct.
int SolveBilinearByHomotopy(const std::array<Eigen::Matrix4d, 6>& matrices, std::uint64_t seed,
                            std::vector<HomotopyRoot>* roots);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_BILINEAR_HOMOTOPY_H_
