// The design constraints of a task (lib/design_constraints.h) as smooth penalty residuals of the
// refiners (planar_dyad_refiner.cc, four_bar_refiner.cc, path_refiner.cc), in their scaled
// frames.
//
// Each constraint is an inequality g(x) <= 0 on a dyad's or a four-bar's geometry (a link length
// against its bound, a fixed pivot against its box, a moving pivot against its box in E, the
// crank shorter than every other link and Grashof with it); its residual is sqrt(mu) max(0, g), a
// quadratic penalty. The refiners solve again with mu multiplied by kBoundGrowth until every g is
// within kBoundShiftFrom, then with the bounds held further in by the violation left (the shift
// of the method of multipliers) until within kBoundSlack (a fraction of kConstraintSlack, so that
// the result keeps the constraint as the result file judges it), at most kBoundRounds times: an
// optimum on a bound is approached from outside, to O(1/mu), and the shift moves it onto it. A
// required Grashof kind is one (s + l <= p + q); a Grashof class within its kind is left to the
// ranking. A held transmission angle (the refiners' min_transmission_deg) is a penalty of the same
// kind on the assembled configurations, raised with the bounds' weight (kTransmissionSamples,
// HeldTransmissionSine below).
#ifndef LINKFIT_OPTIMIZERS_DESIGN_BOUNDS_H_
#define LINKFIT_OPTIMIZERS_DESIGN_BOUNDS_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "lib/design_constraints.h"
#include "lib/planar_pose.h"

namespace linkfit {

// The penalty weight of the first round (the points' cost is of order n in the scaled frames),
// its growth per round and the rounds at most.
inline constexpr double kBoundFirstWeight = 1e2;
inline constexpr double kBoundGrowth = 1e2;
inline constexpr int kBoundRounds = 7;
// The violation (scaled, times L) a refinement stops at: inside the result file's slack.
inline constexpr double kBoundSlack = 0.1 * kConstraintSlack;
// Violations up to this (scaled) are not met by a heavier penalty but by holding the bounds
// that much further in (ScaledBounds::inset; NextBoundRound).
inline constexpr double kBoundShiftFrom = 1e-6;
// A held transmission angle: its sine is held at the configuration of each task pose or point
// and at kTransmissionSamples - 1 inputs between each two, with a margin of
// kTransmissionMarginDeg over the minimum asked (the analysis samples the motion more finely),
// until within kTransmissionSlack of it.
inline constexpr int kTransmissionSamples = 3;
inline constexpr double kTransmissionMarginDeg = 1.0;
inline constexpr double kTransmissionSlack = 1e-3;

// The sine a held transmission angle of `min_deg` degrees is held at (the margin added).
inline double HeldTransmissionSine(double min_deg) {
  return std::sin(std::min(90.0, min_deg + kTransmissionMarginDeg) * M_PI / 180.0);
}

// Residuals of one DesignBounds functor (unused ones are 0).
inline constexpr int kBoundResiduals = 33;

// The constraints in a refiner's scaled frames: lengths divided by L, the fixed box in Sigma',
// the moving box in E'. The link bound always applies (by default 100 L).
struct ScaledBounds {
  double max_link = std::numeric_limits<double>::infinity();
  double min_link = 0.0;
  double max_offset = std::numeric_limits<double>::infinity();
  bool fixed_box = false;
  Eigen::Vector2d fixed_min = Eigen::Vector2d::Zero(), fixed_max = Eigen::Vector2d::Zero();
  bool moving_box = false;
  Eigen::Vector2d moving_min = Eigen::Vector2d::Zero(), moving_max = Eigen::Vector2d::Zero();
  bool input_crank = false;  // input_rotates_fully (4R: the crank shortest, Grashof)
  // A required Grashof kind (4R): +1 a Grashof class ("grashof" or one of its classes), -1
  // "non-grashof", 0 none. The class within the kind is left to the ranking.
  int grashof_kind = 0;
  // How far inside every bound the penalty holds the design (scaled): the shift of the method
  // of multipliers, which brings the optimum the penalty approaches from outside onto the bound
  // itself (NextBoundRound). BoundViolation measures against the bounds themselves.
  double inset = 0.0;
};

// `to_fixed` maps Sigma to the scaled frame Sigma', `to_moving` E to E' (each a scale and a
// shift, of the same scale).
inline ScaledBounds ScaleBounds(const DesignConstraints& constraints, double length,
                                const Similarity2& to_fixed, const Similarity2& to_moving) {
  ScaledBounds bounds;
  bounds.max_link = MaxLinkLength(constraints, length) * to_fixed.scale;
  bounds.min_link = constraints.min_link_length.value_or(0.0) * to_fixed.scale;
  if (constraints.max_coupler_point_offset) {
    bounds.max_offset = *constraints.max_coupler_point_offset * to_fixed.scale;
  }
  if (constraints.fixed_pivots_box) {
    bounds.fixed_box = true;
    bounds.fixed_min = to_fixed.Apply(constraints.fixed_pivots_box->min);
    bounds.fixed_max = to_fixed.Apply(constraints.fixed_pivots_box->max);
  }
  if (constraints.moving_pivots_box) {
    bounds.moving_box = true;
    bounds.moving_min = to_moving.Apply(constraints.moving_pivots_box->min);
    bounds.moving_max = to_moving.Apply(constraints.moving_pivots_box->max);
  }
  bounds.input_crank = constraints.input_rotates_fully;
  if (!constraints.grashof.empty()) {
    bounds.grashof_kind = constraints.grashof == "non-grashof"     ? -1
                          : constraints.grashof == "triple-rocker" ? -1
                                                                   : 1;
  }
  return bounds;
}

// Paths: one scaled frame for Sigma and E (E = Sigma at the first point; no moving box).
inline ScaledBounds ScaleBounds(const DesignConstraints& constraints, double length,
                                const Similarity2& to_fixed) {
  return ScaleBounds(constraints, length, to_fixed, to_fixed);
}

// A four-bar's geometry as the penalties see it, in the scaled frames: what the type has (see
// lib/design_constraints.h for which links a type counts).
template <typename T>
struct BoundGeometry {
  bool has_ground = false, has_coupler = false, has_input = false, has_output = false;
  T ground = T(0.0), coupler = T(0.0), input = T(0.0), output = T(0.0);
  int fixed_count = 0, moving_count = 0, offset_count = 0;
  T fixed[2][2] = {{T(0.0), T(0.0)}, {T(0.0), T(0.0)}};   // fixed pivots (Sigma')
  T moving[2][2] = {{T(0.0), T(0.0)}, {T(0.0), T(0.0)}};  // moving pivots (E'; motion)
  T offsets[2] = {T(0.0), T(0.0)};                        // coupler point offsets (paths)
};

template <typename T>
T BoundDistance(const T* a, const T* b) {
  using std::sqrt;
  const T dx = a[0] - b[0], dy = a[1] - b[1];
  const T squared = dx * dx + dy * dy;
  return squared > T(0.0) ? T(sqrt(squared)) : T(0.0);
}

// The constraint values g (<= 0 where kept) of `geometry`; writes kBoundResiduals, 0 where
// unused.
template <typename T>
void BoundValues(const ScaledBounds& bounds, const BoundGeometry<T>& geometry, T* g) {
  int k = 0;
  const auto put = [&](const T& value) { g[k++] = value; };
  const auto link = [&](bool has, const T& length) {
    if (!has) return;
    if (std::isfinite(bounds.max_link)) put(length - T(bounds.max_link));
    if (bounds.min_link > 0.0) put(T(bounds.min_link) - length);
  };
  link(geometry.has_ground, geometry.ground);
  link(geometry.has_coupler, geometry.coupler);
  link(geometry.has_input, geometry.input);
  link(geometry.has_output, geometry.output);
  if (bounds.fixed_box) {
    for (int i = 0; i < geometry.fixed_count; ++i) {
      for (int c = 0; c < 2; ++c) {
        put(T(bounds.fixed_min[c]) - geometry.fixed[i][c]);
        put(geometry.fixed[i][c] - T(bounds.fixed_max[c]));
      }
    }
  }
  if (bounds.moving_box) {
    for (int i = 0; i < geometry.moving_count; ++i) {
      for (int c = 0; c < 2; ++c) {
        put(T(bounds.moving_min[c]) - geometry.moving[i][c]);
        put(geometry.moving[i][c] - T(bounds.moving_max[c]));
      }
    }
  }
  if (std::isfinite(bounds.max_offset)) {
    for (int i = 0; i < geometry.offset_count; ++i) put(geometry.offsets[i] - T(bounds.max_offset));
  }
  // A crank input of a 4R: the crank no longer than any other link, and with the longest no
  // longer than the other two (Grashof with the crank shortest); with x each link in turn, the
  // longest binds.
  if (bounds.input_crank && geometry.has_ground && geometry.has_coupler && geometry.has_input &&
      geometry.has_output) {
    const T& s = geometry.input;
    put(s - geometry.ground);
    put(s - geometry.coupler);
    put(s - geometry.output);
    put(s + geometry.ground - geometry.coupler - geometry.output);
    put(s + geometry.coupler - geometry.ground - geometry.output);
    put(s + geometry.output - geometry.ground - geometry.coupler);
  }
  // A required Grashof kind of a 4R: s + l <= p + q, i.e. 2 (s + l) - (sum of the four) <= 0
  // (s the shortest link, l the longest), or its reverse for a non-Grashof four-bar.
  if (bounds.grashof_kind != 0 && geometry.has_ground && geometry.has_coupler &&
      geometry.has_input && geometry.has_output) {
    using std::max;
    using std::min;
    const T links[4] = {geometry.ground, geometry.coupler, geometry.input, geometry.output};
    const T shortest = min(min(links[0], links[1]), min(links[2], links[3]));
    const T longest = max(max(links[0], links[1]), max(links[2], links[3]));
    const T excess = T(2.0) * (shortest + longest) - (links[0] + links[1] + links[2] + links[3]);
    put(T(bounds.grashof_kind) * excess);
  }
  while (k < kBoundResiduals) put(T(0.0));
}

// A path four-bar's geometry from its blocks (planar_dyad_blocks.h; E = Sigma at the first
// point): the crank B-A, the output's pivots, the coupler point c's offsets from the coupler
// joints.
template <typename T>
BoundGeometry<T> PathBoundGeometry(DyadType output_type, const T* crank_pivot, const T* crank_pin,
                                   const T* output_point, const T* output_second,
                                   const T* output_scalar, const T* coupler_point) {
  BoundGeometry<T> geometry;
  geometry.has_input = true;
  geometry.input = BoundDistance(crank_pin, crank_pivot);
  geometry.fixed_count = 1;
  geometry.fixed[0][0] = crank_pivot[0];
  geometry.fixed[0][1] = crank_pivot[1];
  geometry.offset_count = 1;
  geometry.offsets[0] = BoundDistance(coupler_point, crank_pin);
  const T* output_fixed = output_type == DyadType::kPR ? nullptr : output_point;
  const T* output_moving = output_type == DyadType::kRR   ? output_second
                           : output_type == DyadType::kPR ? output_point
                                                          : nullptr;
  if (output_type == DyadType::kRR) {
    geometry.has_output = true;
    geometry.output = output_scalar[0] < T(0.0) ? T(-output_scalar[0]) : output_scalar[0];
  }
  if (output_fixed != nullptr) {
    geometry.has_ground = true;
    geometry.ground = BoundDistance(crank_pivot, output_fixed);
    geometry.fixed_count = 2;
    geometry.fixed[1][0] = output_fixed[0];
    geometry.fixed[1][1] = output_fixed[1];
  }
  if (output_moving != nullptr) {
    geometry.has_coupler = true;
    geometry.coupler = BoundDistance(crank_pin, output_moving);
    geometry.offset_count = 2;
    geometry.offsets[1] = BoundDistance(coupler_point, output_moving);
  }
  return geometry;
}

// The pivots of a motion dyad from its blocks (planar_dyad_blocks.h: RR (F, M, r), PR (M, n, h),
// RP (F, n, h)): the fixed one, the moving one (null where the type has none).
template <typename T>
const T* BlocksFixedPivot(DyadType type, const T* point) {
  return type == DyadType::kPR ? nullptr : point;
}
template <typename T>
const T* BlocksMovingPivot(DyadType type, const T* point, const T* second) {
  return type == DyadType::kRR ? second : type == DyadType::kPR ? point : nullptr;
}

// A motion four-bar's geometry from its dyads' blocks (planar_dyad_blocks.h): the links its
// types have (lib/design_constraints.h), its fixed pivots (Sigma') and moving pivots (E'). With
// `output_type` absent (has_output false), one dyad alone: its crank, fixed and moving pivot.
template <typename T>
BoundGeometry<T> MotionBoundGeometry(DyadType input_type, const T* input_point,
                                     const T* input_second, const T* input_scalar, bool has_output,
                                     DyadType output_type, const T* output_point,
                                     const T* output_second, const T* output_scalar) {
  BoundGeometry<T> geometry;
  const auto add = [&geometry](DyadType type, const T* point, const T* second) {
    if (const T* fixed = BlocksFixedPivot(type, point)) {
      geometry.fixed[geometry.fixed_count][0] = fixed[0];
      geometry.fixed[geometry.fixed_count++][1] = fixed[1];
    }
    if (const T* moving = BlocksMovingPivot(type, point, second)) {
      geometry.moving[geometry.moving_count][0] = moving[0];
      geometry.moving[geometry.moving_count++][1] = moving[1];
    }
  };
  const auto crank = [](const T* scalar) { return scalar[0] < T(0.0) ? T(-scalar[0]) : scalar[0]; };
  add(input_type, input_point, input_second);
  if (input_type == DyadType::kRR) {
    geometry.has_input = true;
    geometry.input = crank(input_scalar);
  }
  if (!has_output) return geometry;
  add(output_type, output_point, output_second);
  if (output_type == DyadType::kRR) {
    geometry.has_output = true;
    geometry.output = crank(output_scalar);
  }
  const T* input_fixed = BlocksFixedPivot(input_type, input_point);
  const T* output_fixed = BlocksFixedPivot(output_type, output_point);
  if (input_fixed != nullptr && output_fixed != nullptr) {
    geometry.has_ground = true;
    geometry.ground = BoundDistance(input_fixed, output_fixed);
  }
  const T* input_moving = BlocksMovingPivot(input_type, input_point, input_second);
  const T* output_moving = BlocksMovingPivot(output_type, output_point, output_second);
  if (input_moving != nullptr && output_moving != nullptr) {
    geometry.has_coupler = true;
    geometry.coupler = BoundDistance(input_moving, output_moving);
  }
  return geometry;
}

// One dyad alone (MotionBoundGeometry without an output): its crank, fixed and moving pivot.
template <typename T>
BoundGeometry<T> DyadBoundGeometry(DyadType type, const T* point, const T* second,
                                   const T* scalar) {
  return MotionBoundGeometry(type, point, second, scalar, false, type, point, second, scalar);
}

// The penalty residuals sqrt(mu) max(0, g) of `geometry` (kBoundResiduals of them), with
// sqrt(mu) = `sqrt_weight`.
template <typename T>
void BoundPenalties(const ScaledBounds& bounds, const BoundGeometry<T>& geometry,
                    double sqrt_weight, T* residual) {
  T g[kBoundResiduals];
  BoundValues(bounds, geometry, g);
  for (int k = 0; k < kBoundResiduals; ++k) {
    const T held = g[k] + T(bounds.inset);
    residual[k] = held > T(0.0) ? T(sqrt_weight * held) : T(0.0);
  }
}

// The next round onto the bounds of a design `violation` (scaled) past them: a violation over
// kBoundShiftFrom raises the penalty's weight sqrt(mu) by sqrt(kBoundGrowth); a smaller one
// (over kBoundSlack) holds the bounds that much further in (the penalty's optimum moves in by
// about as much, onto the bound: the result keeps it to kBoundSlack, 1e-10 L, without a weight
// that stiffens the solve). Bounds kept, the round is the held transmission angle's: the weight
// it shares with them is raised.
inline void NextBoundRound(double violation, ScaledBounds* bounds, double* sqrt_weight) {
  if (violation > kBoundShiftFrom || violation <= kBoundSlack) {
    *sqrt_weight *= std::sqrt(kBoundGrowth);
  } else {
    bounds->inset += violation;
  }
}

// The largest violation max(0, g) of `geometry` (scaled units).
inline double BoundViolation(const ScaledBounds& bounds, const BoundGeometry<double>& geometry) {
  double g[kBoundResiduals];
  BoundValues(bounds, geometry, g);
  return std::max(0.0, *std::max_element(g, g + kBoundResiduals));
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_DESIGN_BOUNDS_H_
