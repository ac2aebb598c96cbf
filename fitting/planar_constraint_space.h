// The constraint space of planar dyads, shared by the five-pose solver (planar_burmester.cc)
// and the four-pose curves (planar_burmester_curves.cc). Seed 001 eqs 6 and 9, homogenized as in
// seed 000's constraint space (planar_burmester.h file comment): a dyad is a point z of P^7 with
// a . z = 0 for the row a of every pose (ConstraintRow) on the two quadrics
//   Q1: z0 z5 - z1 z3 - z2 z4 = 0,   Q2: z0 z6 - z1 z4 + z2 z3 = 0.
// This unit holds the pieces both solvers use: the pose frames and the normalization of a
// motion, the bilinear forms of Q1 and Q2 and their restriction to a subspace, Newton's method on
// the restricted conics, the readings of a root as an RR, PR or RP dyad (seed 001 eqs 10 and 13)
// with the typing rule, and the polish of a dyad on its own geometric equations.
// Internal to the fitting library: none of it is part of the public API.
#ifndef LINKFIT_FITTING_PLANAR_CONSTRAINT_SPACE_H_
#define LINKFIT_FITTING_PLANAR_CONSTRAINT_SPACE_H_

#include <Eigen/Core>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fitting/planar_burmester.h"
#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {
namespace internal {

// A pose with its rotation matrix evaluated once (residuals are evaluated many times).
struct PoseFrame {
  Eigen::Matrix2d rotation;
  Eigen::Vector2d origin;
};

// The frames of `poses`, in order.
std::vector<PoseFrame> MakeFrames(const std::vector<PlanarPose>& poses);

// Largest |residual| of `dyad` over the frames (inline: the solvers' inner loops call it).
inline double MaxResidual(const PlanarDyad& dyad, const std::vector<PoseFrame>& frames) {
  double worst = 0.0;
  for (const PoseFrame& frame : frames) {
    worst = std::max(worst, std::abs(dyad.Residual(frame.rotation, frame.origin)));
  }
  return worst;
}

// A motion centred and scaled: the fixed frame by its pose-origin centroid and L, the moving
// frame by L. `to_original_*` map the normalized frames back.
struct NormalizedMotion {
  std::vector<PlanarPose> poses;
  Similarity2 to_original_fixed;
  Similarity2 to_original_moving;
  double length = 1.0;  // L (1 when the poses do not define one)
};

// Normalizes `poses` (see NormalizedMotion).
NormalizedMotion Normalize(const std::vector<PlanarPose>& poses);

// The symmetric bilinear forms of the two quadric relations (file comment), for any
// 8-vectors u and v: BilinearQ1(z, z) = Q1(z), BilinearQ2(z, z) = Q2(z).
template <typename U, typename V>
auto BilinearQ1(const U& u, const V& v) {
  return 0.5 * (u[0] * v[5] + u[5] * v[0] - u[1] * v[3] - u[3] * v[1] - u[2] * v[4] - u[4] * v[2]);
}
template <typename U, typename V>
auto BilinearQ2(const U& u, const V& v) {
  return 0.5 * (u[0] * v[6] + u[6] * v[0] - u[1] * v[4] - u[4] * v[1] + u[2] * v[3] + u[3] * v[2]);
}

// How RestrictedConics fills its matrices: every entry evaluated (the off-diagonal pairs may
// then differ by rounding), or the upper triangle evaluated and mirrored (exactly symmetric).
enum class ConicFill { kEvaluateAll, kMirrorUpper };

// The two quadric relations restricted to the span of the N columns of `basis`:
// a^T A1 a = Q1(basis a), a^T A2 a = Q2(basis a). Conics for N = 3 (a plane of P^7), quadric
// surfaces for N = 4.
template <int N>
void RestrictedConics(const Eigen::Matrix<double, 8, N>& basis, ConicFill fill,
                      Eigen::Matrix<double, N, N>* a1, Eigen::Matrix<double, N, N>* a2) {
  for (int i = 0; i < N; ++i) {
    if (fill == ConicFill::kEvaluateAll) {
      for (int j = 0; j < N; ++j) {
        (*a1)(i, j) = BilinearQ1(basis.col(i), basis.col(j));
        (*a2)(i, j) = BilinearQ2(basis.col(i), basis.col(j));
      }
    } else {
      for (int j = i; j < N; ++j) {
        (*a1)(i, j) = (*a1)(j, i) = BilinearQ1(basis.col(i), basis.col(j));
        (*a2)(i, j) = (*a2)(j, i) = BilinearQ2(basis.col(i), basis.col(j));
      }
    }
  }
}

// Newton's method in real arithmetic on a^T M1 a = a^T M2 a = 0 in the chart a0 . a = a0 . a0
// (a0 the normalized start), at most `iterations` steps, each kept only if it lowers the
// residual; *a is returned normalized. Returns the final relative conic residual (infinity when
// a conic is zero).
double PolishRealRoot(const Eigen::Matrix3d& m1, const Eigen::Matrix3d& m2, int iterations,
                      Eigen::Vector3d* a);

// A real root read as a dyad, with its largest residual over the poses.
struct DyadReading {
  PlanarDyad dyad;
  double max_residual = std::numeric_limits<double>::infinity();
};

// The readings of a real constraint vector z as a dyad in the frames, sliders first: PR (K0 := 0,
// seed 001 eq. 13), RP (K0 := 0 and K := 0: the limit of an RR dyad whose moving pivot runs to
// infinity along n, z -> (0, n, 0, 0, -F . n, Fx ny - Fy nx, 2h), i.e. the fixed pivot F stays on
// the line n . p_E = h of E) and RR (K0 != 0, seed 001 eq. 10). Without `sliders` only the RR
// reading. Returns the count (0 to 3).
int ReadingsOf(const ConstraintVector& z, const std::vector<PoseFrame>& frames, bool sliders,
               DyadReading readings[3]);

// The typing rule: a slider reading (listed first) is taken when it fits the poses within
// `slider_tolerance` (raised to the circle's own rounding floor, 4 eps r: a centre r away is
// stored to ulp(r)) or at least as well as the circle reading, so that a radius beyond what
// rounding can tell from infinity is reported as a slider, consistently in both directions.
// Returns the index of the chosen reading (-1 when count is 0).
int ChooseReading(const DyadReading readings[3], int count, double slider_tolerance);

// Gauss-Newton on a dyad's own geometric equations at the first kPoses frames, residual_j = the
// signed distance of the constrained point from its circle or line (the design's residual). The
// projective root fixes the dyad; its reading in pivot coordinates, e.g. F = -K/K0, loses digits
// when the pivots are far from the pose origins (K0 small against |z|), which this polish in the
// dyad's own parameters restores to rounding level. Parameters: RR (F, m, r); PR (m, line normal
// angle, offset); RP (F, line normal angle in E, offset); a slider with kParameters = 5 carries
// a zero fifth parameter (a zero Jacobian column). The step: Newton's for a square Jacobian,
// least squares for more poses than parameters, the minimum-norm J^T (J J^T)^-1 r for fewer (it
// moves the dyad to the nearest one of the poses). Returns the polished dyad when it fits the
// frames at least as well, else `dyad`. An RR dyad needs kParameters = 5.
template <int kPoses, int kParameters>
PlanarDyad PolishDyadFixed(const PlanarDyad& dyad, const std::vector<PoseFrame>& frames,
                           int iterations) {
  static_assert(kParameters == 4 || kParameters == 5, "a dyad has 4 or 5 parameters");
  using Parameters = Eigen::Matrix<double, kParameters, 1>;
  const bool rr = dyad.type == DyadType::kRR;
  const bool slider = dyad.type == DyadType::kPR;
  if constexpr (kParameters == 4) {
    if (rr) return dyad;
  }
  Parameters x = Parameters::Zero();
  if (rr) {
    if constexpr (kParameters == 5) x << dyad.fixed_pivot, dyad.moving_pivot, dyad.radius;
  } else {
    const Eigen::Vector2d normal(-dyad.line_direction.y(), dyad.line_direction.x());
    x.template head<4>() << (slider ? dyad.moving_pivot : dyad.fixed_pivot),
        std::atan2(normal.y(), normal.x()), normal.dot(dyad.line_point);
  }
  auto make = [&](const Parameters& p) {
    if constexpr (kParameters == 5) {
      if (rr) return PlanarDyad::RR(p.template segment<2>(0), p.template segment<2>(2), p[4]);
    }
    const Eigen::Vector2d normal(std::cos(p[2]), std::sin(p[2]));
    const Eigen::Vector2d direction(-normal.y(), normal.x());
    return slider ? PlanarDyad::PR(p.template head<2>(), p[3] * normal, direction)
                  : PlanarDyad::RP(p.template head<2>(), p[3] * normal, direction);
  };
  PlanarDyad best = dyad;
  double best_residual = MaxResidual(dyad, frames);
  Eigen::Matrix<double, kPoses, kParameters> jacobian =
      Eigen::Matrix<double, kPoses, kParameters>::Zero();
  Eigen::Matrix<double, kPoses, 1> residual;
  for (int iteration = 0; iteration < iterations && best_residual > 0.0; ++iteration) {
    for (int j = 0; j < kPoses; ++j) {
      const Eigen::Matrix2d& rotation = frames[j].rotation;
      const Eigen::Vector2d& origin = frames[j].origin;
      if (rr) {
        if constexpr (kParameters == 5) {
          // |R m + d - F| - r; u the unit vector from F to the moving pivot.
          const Eigen::Vector2d arm =
              rotation * x.template segment<2>(2) + origin - x.template head<2>();
          const double distance = arm.norm();
          const Eigen::Vector2d u = arm / distance;
          residual[j] = distance - x[4];
          jacobian.template block<1, 2>(j, 0) = -u.transpose();
          jacobian.template block<1, 2>(j, 2) = u.transpose() * rotation;
          jacobian(j, 4) = -1.0;
        }
      } else {
        const Eigen::Vector2d normal(std::cos(x[2]), std::sin(x[2]));
        const Eigen::Vector2d normal_rate(-normal.y(), normal.x());
        // PR: the moving pivot in Sigma on n . P = h; RP: the fixed pivot in E on n . p = h.
        const Eigen::Vector2d point =
            slider ? Eigen::Vector2d(rotation * x.template head<2>() + origin)
                   : Eigen::Vector2d(rotation.transpose() * (x.template head<2>() - origin));
        residual[j] = normal.dot(point) - x[3];
        jacobian.template block<1, 2>(j, 0) =
            slider ? Eigen::RowVector2d(normal.transpose() * rotation)
                   : Eigen::RowVector2d((rotation * normal).transpose());
        jacobian(j, 2) = normal_rate.dot(point);
        jacobian(j, 3) = -1.0;
      }
    }
    Parameters step;
    if constexpr (kPoses == kParameters) {
      step = jacobian.partialPivLu().solve(residual);
    } else if constexpr (kPoses > kParameters) {
      step = jacobian.householderQr().solve(residual);
    } else {
      const Eigen::Matrix<double, kPoses, kPoses> gram = jacobian * jacobian.transpose();
      step = jacobian.transpose() * gram.partialPivLu().solve(residual);
    }
    if (!step.allFinite()) break;
    x -= step;
    const PlanarDyad candidate = make(x);
    const double candidate_residual = MaxResidual(candidate, frames);
    if (!(candidate_residual <= best_residual)) break;
    best = candidate;
    best_residual = candidate_residual;
  }
  return best;
}

// PolishDyadFixed with the parameter count of each caller: five poses (planar_burmester.cc),
// Newton for RR and least squares on 4 parameters for sliders; four poses (curves), minimum-norm
// steps on 5 parameters for every type (for a slider the same as Newton's step up to rounding).
template <int kPoses>
PlanarDyad PolishDyad(const PlanarDyad& dyad, const std::vector<PoseFrame>& frames,
                      int iterations) {
  if constexpr (kPoses > 4) {
    return dyad.type == DyadType::kRR ? PolishDyadFixed<kPoses, 5>(dyad, frames, iterations)
                                      : PolishDyadFixed<kPoses, 4>(dyad, frames, iterations);
  } else {
    return PolishDyadFixed<kPoses, 5>(dyad, frames, iterations);
  }
}

}  // namespace internal
}  // namespace linkfit

#endif  // LINKFIT_FITTING_PLANAR_CONSTRAINT_SPACE_H_
