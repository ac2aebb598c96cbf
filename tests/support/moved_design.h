// Designs moved off their generators, as a designer's sketch or a coarse earlier result is: the
// starts of the refinement tests and of linkfit_bench's refine rows (optimizers/task_solver.h
// RefineTask).
#ifndef LINKFIT_TESTS_SUPPORT_MOVED_DESIGN_H_
#define LINKFIT_TESTS_SUPPORT_MOVED_DESIGN_H_

#include <random>

#include "lib/dyad.h"
#include "lib/path_motion.h"
#include "lib/spatial_dyad.h"

namespace linkfit::testing {

// Every pivot and point moved by up to `offset` in each coordinate (uniform), a slider's line
// also turned by up to `offset` / `length` radians, an RR radius re-read from its moved pivots.
PlanarDyad MovedPlanarDyad(std::mt19937_64& rng, const PlanarDyad& dyad, double offset,
                           double length);
// The crank and output dyad as MovedPlanarDyad, and the coupler point moved.
PathFourBar MovedPathFourBar(std::mt19937_64& rng, const PathFourBar& four_bar, double offset,
                             double length);
// Pivots moved by up to `offset` in each coordinate, a radius or plane offset changed by up to
// `offset`, a plane normal turned by about `offset` / `length`.
SpatialDyad MovedSpatialDyad(std::mt19937_64& rng, const SpatialDyad& dyad, double offset,
                             double length);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_MOVED_DESIGN_H_
