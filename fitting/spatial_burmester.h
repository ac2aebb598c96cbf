// Seven-pose synthesis of spatial SS and PS dyads (the spatial Burmester problem of 5-SS
// platforms), and the algebraic least-squares seed for more poses. Seed 000, sections 3-4.
//
// Formulation. A dyad is a pair of projective points: a = (A1, A2, A3, A4), the sphere
// (A4 != 0, center A/A4) or plane (A4 = 0) in Sigma, and c = (c1, c2, c3, c4), the constrained
// point of E. The constraint of eq. 8 at a pose (R, d) is linear in the 17 constraint-space
// parameters P0 and P = a (x) c (eq. 12, P_{4(j-1)+i} = A_i c_j) with the coefficients of
// eq. 11 (SpatialConstraintRow), eq. 10. P0 = A0 c4 - A4 |c|^2 / c4 carries the free
// coefficient A0, so it is eliminated exactly: subtracting the (weighted) mean row leaves n
// rows on the 16 coordinates of a (x) c, of rank 6 for seven poses. Their row space gives six
// bilinear equations
//   a^T B_k c = 0,  k = 1..6,
// the bilinear conditions of eq. 13 in the form "a (x) c lies in the 10-dimensional null space
// of eq. 16" (for more than seven poses: the span of the 10 smallest right singular vectors,
// section 4.1). Generically they have 20 complex solutions in P^3 x P^3.
//
// Root finding (no homotopy continuation, no univariate elimination, no multistart): the
// Macaulay matrix of the six equations times every cubic monomial in c (120 rows, 140 columns
// of bidegree (1, 4)) has a 20-dimensional null space spanned by the monomial vectors of the 20
// roots (Buchsbaum-Rim: the cokernel of the 6 x 4 linear matrix has Hilbert function 20 from
// degree 3 on). Shifting by the coordinates c_j gives 20 x 20 eigenvalue problems whose common
// eigenvectors are the roots. Every root is then Newton-polished on the bilinear equations.
//
// Preconditions: at least seven poses (eq. 14 needs seven to leave ten dimensions). Data are
// centered and scaled by L before the algebra and the answer is mapped back.
#ifndef LINKFIT_FITTING_SPATIAL_BURMESTER_H_
#define LINKFIT_FITTING_SPATIAL_BURMESTER_H_

#include <Eigen/Core>
#include <array>
#include <complex>
#include <vector>

#include "lib/precision.h"
#include "lib/spatial_dyad.h"
#include "lib/spatial_pose.h"

namespace linkfit {

// Coefficients (K0, K1, ..., K16) of eq. 10 for the pose (R, d), multiplying
// (P0, A1 c1, A2 c1, A3 c1, A4 c1, A1 c2, ..., A4 c4): eq. 11 written with R and d,
//   K0 = 1, K[Ai cj] = 2 R_ij, K[Ai c4] = 2 d_i, K[A4 cj] = -2 (R^T d)_j, K[A4 c4] = -|d|^2.
Eigen::Matrix<double, 17, 1> SpatialConstraintRow(const Eigen::Matrix3d& rotation,
                                                  const Eigen::Vector3d& translation);

using BilinearMatrices = std::array<Eigen::Matrix4d, 6>;

struct BilinearRoot {
  Eigen::Vector4cd a;     // unit norm, phase chosen so that its largest entry is real
  Eigen::Vector4cd c;     // unit norm, phase chosen so that its largest entry is real
  bool real = false;      // polished in real arithmetic to a real root
  double residual = 0.0;  // max_k |a^T B_k c| / max_k ||B_k|| with unit a, c
};

struct BilinearSolverSummary {
  int rank = 0;         // rank of the 120 x 140 Macaulay matrix (120 when generic)
  int roots = 0;        // roots returned (20 when generic)
  int real_roots = 0;   // of which real
  int unconverged = 0;  // roots whose polish did not reach the residual tolerance
  // Complex roots whose imaginary share is at most nearly_real_share: near a double real root,
  // where a one-ulp change of the data can turn two real dyads into a complex pair.
  int nearly_real = 0;
};

struct BilinearSolverOptions {
  // Relative size of the Macaulay matrix's pivots below which its rank is taken as deficient
  // (the equations then have a family of solutions, not 20 points).
  double rank_tolerance = 1e-10;
  // Imaginary part (relative) below which a root is polished in real arithmetic.
  double real_tolerance = 1e-6;
  // Complex roots with an imaginary part (relative) below this are counted as nearly real.
  double nearly_real_share = 1e-3;
  // Newton iterations on the bilinear equations per root.
  int newton_iterations = 4;
  // A polished root is verified when its residual is below this.
  double residual_tolerance = 1e-11;
};

// All solutions of a^T B_k c = 0 (k = 0..5) in P^3 x P^3. Returns the number of roots (20 when
// generic) or -1 when the Macaulay matrix is rank-deficient (a positive-dimensional family).
int SolveBilinearSystem(const BilinearMatrices& matrices, const BilinearSolverOptions& options,
                        std::vector<BilinearRoot>* roots, BilinearSolverSummary* summary = nullptr);

struct SpatialBurmesterOptions {
  BilinearSolverOptions bilinear;  // root finding
  // Singular value ratio sigma_6 / sigma_1 of the centered constraint rows below which the
  // poses are taken as dependent (e.g. planar data: families of dyads, not 20).
  double rank_tolerance = 1e-9;
  // A real root is read as PS (plane) when its plane reading fits within this times L, or
  // fits at least as well as its sphere reading; likewise SP for a moving point at infinity.
  double plane_tolerance = 1e-9;
  // Newton iterations on a real dyad's own geometric equations (seven poses).
  int newton_iterations = 4;
  // The precision of the poses (lib/precision.h; zero: rounding level). With data coarser than
  // rounding, a complex root whose real part, read as a dyad and fitted to the poses by least
  // squares, fits them within precision (fitting/model_choice.h) is kept: rounding turns two
  // nearby real dyads into a complex pair.
  DataPrecision precision;
};

struct SpatialBurmesterSummary {
  int roots_total = 0;            // complex roots of the bilinear system (20 when generic)
  int roots_real = 0;             // real ones among them
  int roots_verified = 0;         // roots whose polished residual is below tolerance
  int imaginary_spheres = 0;      // real roots whose sphere has r^2 < 0 (no physical dyad)
  double condition = 0.0;         // sigma_1 / sigma_6 of the centered n x 16 constraint rows
  double fit_residual = 0.0;      // more than seven poses: RMS algebraic residual of the seed space
  bool degenerate = false;        // rank-deficient rows or Macaulay matrix: a family of dyads
  int nearly_real = 0;            // complex roots near a double real root (BilinearSolverSummary)
  int real_within_precision = 0;  // complex roots kept: real within the data's precision
  double seconds = 0.0;           // wall time of the solve
};

// The six bilinear matrices B_k of the (normalized) poses: the top six right singular vectors
// of the centered, weighted constraint rows, reshaped so that B_k(i, j) multiplies A_i c_j.
// `weights` may be empty. Fills sigma (all 16 singular values) when non-null.
BilinearMatrices SpatialBilinearMatrices(const std::vector<DualQuaternion>& poses,
                                         const std::vector<double>& weights,
                                         Eigen::Matrix<double, 16, 1>* sigma = nullptr);

// Every real SS, PS (and SP: a point of Sigma on a plane of E, the inversion of PS) dyad through
// the poses; for more than seven poses the algebraic least-squares seed. `weights` may be
// empty. Returns the number of dyads written to `dyads`.
int SolveSpatialBurmester(const std::vector<DualQuaternion>& poses,
                          const std::vector<double>& weights,
                          const SpatialBurmesterOptions& options, std::vector<SpatialDyad>* dyads,
                          SpatialBurmesterSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SPATIAL_BURMESTER_H_
