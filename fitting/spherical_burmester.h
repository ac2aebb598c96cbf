// Spherical RR dyads through the orientations of a spherical motion: five orientations exactly
// (the spherical Burmester problem), the algebraic least-squares seed for more, the dyad of a
// chosen axis for three or four, and the axis cones of four.
//
// Formulation (seed 000's constraint space, section 7's spherical motion: lib/spherical_dyad.h).
// The constraint u . R_j v = cos(alpha) is linear in the nine products z = u (x) v
// (z_{3i+k} = u_i v_k, coefficient R_j(i, k)) and in cos(alpha). Subtracting the weighted mean
// row eliminates cos(alpha) (as the spatial solver eliminates P0) and leaves rows of rank 4 for
// five orientations; their row space gives four bilinear equations
//   u^T B_k v = 0,  k = 1..4
// (more orientations: the four largest right singular vectors of the rows, the algebraic
// least-squares fit, as spatial_burmester.h section 4.1). Four bilinear equations on P^2 x P^2
// have six solutions (the degree of the Segre variety P^2 x P^2): up to six real dyads, complex
// roots counted, where the planar problem has four.
//
// Root finding (no homotopy, no multistart): the equations times v_1, v_2, v_3 make a 12 x 18
// Macaulay matrix on the monomials u_i v_a v_b; its null space is six-dimensional and spanned by
// the roots' monomial vectors (there is no syzygy of that degree). Shifting the degree-(1, 1)
// monomials by two linear forms of v gives a 6 x 6 eigenvalue problem whose eigenvectors are
// the roots; each real root is Newton-polished on the equations.
//
// Four orientations leave three equations: the fixed axes of the dyads form the cubic cone
// det[B_1^T u, B_2^T u, B_3^T u] = 0 (the center-axis cone) and the moving axes the cubic cone
// det[B_1 v, B_2 v, B_3 v] = 0 (the circle-axis cone), the spherical Burmester curves. Each is
// traced in closed form: the planes through a line of the cone meet it in two more lines, the
// roots of a binary quadratic.
//
// Preconditions: rotation matrices (orthonormal, det +1) of a motion about one point; five or
// more orientations for SolveSphericalBurmester, not all about one axis.
#ifndef LINKFIT_FITTING_SPHERICAL_BURMESTER_H_
#define LINKFIT_FITTING_SPHERICAL_BURMESTER_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "lib/precision.h"
#include "lib/spherical_dyad.h"

namespace linkfit {

using SphericalBilinear = std::array<Eigen::Matrix3d, 4>;

struct SphericalBurmesterOptions {
  // A root whose imaginary share (of its unit u and v, phase-normalized) is below this is polished
  // in real arithmetic and accepted as real if Newton's method then converges.
  double real_tolerance = 1e-5;
  int newton_iterations = 8;
  // sigma_4 / sigma_1 of the centred rows below which the orientations leave a family of dyads.
  double rank_tolerance = 1e-10;
  // The data's precision (its angle: the rotations'). Rounding can split a double root into a
  // complex pair: the real part of a complex root, fitted to the orientations by least squares,
  // is kept as a dyad when it misses none by more than kModelUnits (fitting/model_choice.h) times
  // that angle (never below rounding), as the spatial solver keeps them.
  DataPrecision precision;
};

struct SphericalBurmesterSummary {
  int roots_total = 0;            // roots of the bilinear system, complex included (6)
  int roots_real = 0;             // real ones among them
  int nearly_real = 0;            // complex roots within real_tolerance that did not polish
  int real_within_precision = 0;  // complex roots kept: their real parts fit within precision
  double condition = 0.0;         // sigma_1 / sigma_4 of the centred rows
  double fit_residual = 0.0;      // more than five orientations: the seed space's RMS residual
  bool degenerate = false;        // rank-deficient: a family of dyads
};

// The bilinear equations of the orientations (file comment), B_k of unit Frobenius norm, and the
// singular values of the weighted centred rows (largest first). `equations` = 4 for five or more
// orientations, 3 for four.
void SphericalEquations(const std::vector<Eigen::Matrix3d>& rotations,
                        const std::vector<double>& weights, int equations,
                        std::vector<Eigen::Matrix3d>* bilinear, Eigen::VectorXd* singular_values);

// Every real dyad through five orientations; for more, the algebraic least-squares seed. Returns
// the number of dyads written, canonical (SphericalDyad::Make), alpha the weighted mean angle.
int SolveSphericalBurmester(const std::vector<Eigen::Matrix3d>& rotations,
                            const std::vector<double>& weights,
                            const SphericalBurmesterOptions& options,
                            std::vector<SphericalDyad>* dyads,
                            SphericalBurmesterSummary* summary = nullptr);

// The dyad of a chosen moving axis (in E), three or more orientations: the fixed axis is the
// normal of the plane through (three) or best fitting (more) the axis's positions R_j v on the
// sphere. Four orientations: the axis is first moved to the nearest line of the circle-axis cone
// (*moved_deg says how far). Returns false when the positions do not determine a plane.
bool SphericalDyadFromMovingAxis(const std::vector<Eigen::Matrix3d>& rotations,
                                 const std::vector<double>& weights,
                                 const Eigen::Vector3d& moving_axis, SphericalDyad* dyad,
                                 double* moved_deg);

// The same from a chosen fixed axis (in Sigma), by inversion (the center-axis cone).
bool SphericalDyadFromFixedAxis(const std::vector<Eigen::Matrix3d>& rotations,
                                const std::vector<double>& weights,
                                const Eigen::Vector3d& fixed_axis, SphericalDyad* dyad,
                                double* moved_deg);

// The center-axis and circle-axis cones of exactly four orientations as polylines of unit
// vectors (each a line of the cone, taken with the sign that continues its polyline); `samples`
// planes of the pencil. Returns false for other counts or a degenerate task.
struct SphericalBurmesterCones {
  std::vector<std::vector<Eigen::Vector3d>> center_axes;  // fixed axes, Sigma
  std::vector<std::vector<Eigen::Vector3d>> circle_axes;  // moving axes, E
};
bool SampleSphericalBurmesterCones(const std::vector<Eigen::Matrix3d>& rotations, int samples,
                                   SphericalBurmesterCones* cones);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SPHERICAL_BURMESTER_H_
