// Target curves of path synthesis without timing (issue 34): the coupler curves of random
// crank-driven four-bars whose crank turns fully (4R, slider-crank, inverted slider-crank),
// sampled as a designer would give them: a closed full cycle, an open arc of part of the cycle,
// unevenly spaced. Drawn independently of the coupler atlas (optimizers/coupler_atlas.h): other
// proportions, placed, turned and scaled at random.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_CURVE_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_CURVE_H_

#include <Eigen/Core>
#include <random>
#include <vector>

#include "lib/dyad.h"
#include "lib/path_motion.h"

namespace linkfit::testing {

struct GeneratedCurve {
  PathFourBar four_bar;  // in the first point's configuration (lib/path_motion.h)
  std::vector<Eigen::Vector2d> points;
  std::vector<double> input_angles;  // radians from the first point's (0), monotonic
  bool closed = false;               // a full turn (the points do not repeat the first)
  double size = 1.0;                 // the curve's RMS distance from its centroid
};

struct CurveOptions {
  int count = 30;             // points
  bool closed = true;         // a full cycle, else an arc
  double arc_turns = 0.5;     // an arc's share of the cycle
  bool uneven = true;         // crank steps varying by up to half their mean
  double offset_scale = 1.0;  // curves drawn up to this far from the origin, times their size
};

// A random four-bar with an RR crank and an `output` dyad whose crank turns fully, without a
// defect through the points, its coupler point within the proportions designers use, and
// the points of its coupler curve.
GeneratedCurve RandomCurve(std::mt19937_64& rng, DyadType output, const CurveOptions& options);

// The RMS distance of `points` from the coupler curve of `four_bar` over a full crank turn (or
// its reachable range) sampled at `samples` crank angles (the nearest sample, then the nearest
// point of the segments next to it): the untimed fit of a design to a target.
double CurveRmsDistance(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                        double length, int samples = 2048);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_CURVE_H_
