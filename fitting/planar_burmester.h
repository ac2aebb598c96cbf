// Type and dimensional synthesis of planar dyads for five poses (the Burmester problem), and
// the algebraic least-squares seed for more poses.
//
// Formulation (seed 001, eqs 6 and 9, homogenized as in seed 000's constraint space): the
// general constraint K0 |P|^2 + 2 K1 X + 2 K2 Y + K3 = 0 (seed 001 eq. 6, Z = 1) on the
// point P = R(theta) m + d of E is LINEAR in the 8 homogeneous coefficients
//   z = (K0, K0 mx, K0 my, K1, K2, K1 mx + K2 my, K2 mx - K1 my, K3 + K0 |m|^2),
// with a row per pose that is a quadratic form in the image coordinates X1..X4 of the pose
// (seed 001 eq. 2; see ConstraintRow). Five poses leave a 3-dimensional null space, a
// projective plane, and the two quadric relations
//   Q1: z0 z5 - z1 z3 - z2 z4 = 0,   Q2: z0 z6 - z1 z4 + z2 z3 = 0
// cut it in 4 points (two conics): the Burmester dyads. Every dyad type is a finite
// projective point of this space: z0 = K0 != 0 is an RR dyad (fixed pivot -K/K0, moving pivot
// (z1, z2)/z0); z0 = 0 with K != 0 is a PR dyad (a slider, not an overflowing radius);
// z0 = K = 0 is an RP dyad, the limit of an RR dyad whose moving pivot runs to infinity in E
// along n = (z1, z2): z = (0, n, 0, 0, -F . n, Fx ny - Fy nx, 2h) with the fixed pivot F on the
// line n . p_E = h of E. (Solving the inverted motion gives the same RP dyads as its PR dyads; the
// tests use that as a cross-check.) No grid search, no multistart: the conic pencil is split
// exactly and every root is polished by Newton's method.
//
// Preconditions: at least five poses, not all of the same orientation. Data are centred and
// scaled by L before the algebra and the answer is mapped back.
#ifndef LINKFIT_FITTING_PLANAR_BURMESTER_H_
#define LINKFIT_FITTING_PLANAR_BURMESTER_H_

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "lib/precision.h"

namespace linkfit {

using ConstraintVector = Eigen::Matrix<double, 8, 1>;
using ComplexConstraintVector = Eigen::Matrix<std::complex<double>, 8, 1>;

// The row a of one pose, such that a . z = 0 is the dyad constraint (see file comment).
ConstraintVector ConstraintRow(const PlanarPose& pose);

struct PlanarBurmesterOptions {
  // A root whose imaginary part is below this (relative to its largest component) is taken
  // to real arithmetic and accepted as real if Newton's method then converges.
  double real_tolerance = 1e-5;
  // Newton iterations per real root: on the two conics in the null-space plane, then (five
  // poses) on the dyad's own geometric equations.
  int newton_iterations = 4;
  // A root with K0 != 0 whose slider reading (K0 := 0) fits the poses within
  // slider_tolerance * L is reported as PR: its radius exceeds anything a designer builds.
  double slider_tolerance = 1e-9;
  // Singular value ratio sigma_5 / sigma_1 below which the five rows are taken as dependent
  // (the task has a family of dyads, not four).
  double rank_tolerance = 1e-10;
  // The precision of the poses (lib/precision.h; zero: rounding level). A circle whose slider
  // reading fits the poses within it is typed as the slider (fitting/model_choice.h), and rows
  // dependent within family_units times its relative size are a family of dyads.
  DataPrecision precision;
  double family_units = 1.0;
  // The two conics share a component (a curve of dyads, e.g. the Cardan motion) when their
  // pencil's determinant coefficients all stay below this times condition * relative precision
  // (the size of the coefficients' rounding), where that product is at least 1e-2. Measured on
  // double sliders (Cardan motions, condition about 1e6) printed to 8, 6 and 4 digits and on
  // random four-bars: linkfit bench, rounded data.
  double conic_family_units = 0.02;
};

struct PlanarBurmesterSummary {
  int roots_total = 0;  // roots of the direct problem, complex ones included (4)
  int roots_real = 0;   // real ones among them
  // Complex roots whose real part, read as a dyad, fits the poses within the data's precision
  // (rounding turned two nearby real dyads into a complex pair); their dyads are returned.
  int real_within_precision = 0;
  double condition = 0.0;     // sigma_1 / sigma_5 of the 5 x 8 constraint matrix
  double fit_residual = 0.0;  // more than 5 poses: RMS algebraic residual of the seed space
  bool degenerate = false;    // rank-deficient rows: infinitely many dyads
};

// All roots (complex included) of the two conics restricted to the null space `basis`
// (8 x 3): the points of P^7 in the span of the columns with Q1 = Q2 = 0. Returns the count
// (4), or -1 when the conics share a component (a curve of dyads).
int IntersectConstraintConics(const Eigen::Matrix<double, 8, 3>& basis,
                              std::vector<ComplexConstraintVector>* roots);

// Every real dyad (RR, PR and RP) through the poses; for more than five
// poses the algebraic least-squares seed (the three smallest right singular vectors).
// Returns the number of dyads written to `dyads`.
int SolvePlanarBurmester(const std::vector<PlanarPose>& poses,
                         const PlanarBurmesterOptions& options, std::vector<PlanarDyad>* dyads,
                         PlanarBurmesterSummary* summary = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_BURMESTER_H_
