// The 3R chain of a six-bar task when the task leaves it out (issue 36): candidate chains whose
// inverse kinematics reach every pose on one elbow, with elbow angles away from the stretched and
// folded (singular) places and joint travel a designer would accept, ordered by how well their
// relative motions condition the Burmester problems the synthesis solves on them
// (fitting/six_bar_synthesis.h). The solvers synthesize six-bars on the first candidates and keep
// the chain whose first six-bar ranks best (optimizers/task_solver.h SolveSixBarChosenChain).
//
// The search: the wrist on a grid in E about E's origin, the ground pivot on a grid in Sigma about
// the wrist's places, three ratios of the two link lengths, both elbows. Each (ground pivot, wrist)
// pair fixes the wrist's distances d_k from the ground pivot at the poses; for a ratio r = a12/a23
// the links are sized so that the elbow's interior angle beta_k (d_k^2 = a12^2 + a23^2 - 2 a12 a23
// cos beta_k) is centred on 90 degrees over the poses: a23^2 = (d_min^2 + d_max^2) / (2 (r^2 + 1)).
#ifndef LINKFIT_FITTING_SIX_BAR_CHAINS_H_
#define LINKFIT_FITTING_SIX_BAR_CHAINS_H_

#include <vector>

#include "lib/design_constraints.h"
#include "lib/planar_pose.h"
#include "lib/six_bar.h"

namespace linkfit {

struct SixBarChainSearchOptions {
  int max_candidates = 8;  // the best this many, set apart (below)
  // Every pose's elbow angle within [min, 180 - min] degrees (away from the chain's singular,
  // stretched and folded, places).
  double min_elbow_angle_deg = 20.0;
  // Each joint's travel over the poses (the ground pivot's, the elbow's, the wrist's relative
  // turn) at most this, degrees.
  double max_joint_travel_deg = 120.0;
  // Two candidates with the same elbow side whose ground pivots and wrists are both within this
  // (times L) are one: the second is not kept.
  double apart = 0.5;
};

// A candidate chain and how it was judged.
struct SixBarChainCandidate {
  SixBarChain chain;                 // elbow_at_first_pose set: the elbow at the first pose
  double min_elbow_angle_deg = 0.0;  // the least of min(beta_k, 180 - beta_k) over the poses
  // The rotation spreads (largest minus smallest turn over the poses, degrees) of the two relative
  // motions only the chain makes: the forearm's (from ground) and the task body's from the upper
  // link. A small spread makes their Burmester roots ill-conditioned.
  double forearm_spread_deg = 0.0, task_from_upper_spread_deg = 0.0;
  double score = 0.0;  // the least of the three above: candidates are ordered by it, largest first
};

// The chain's elbow angles, joint travels and spreads through `poses` (false where it cannot reach
// a pose or breaks options' elbow angle or travel).
bool JudgeSixBarChain(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                      const SixBarChainSearchOptions& options, SixBarChainCandidate* candidate);

// The candidate chains through `poses` (characteristic length `length`) that keep `constraints`
// (the ground pivot in the fixed-pivot box, the wrist in the moving-pivot box, both links within
// the link bounds), best first, at most options.max_candidates, each at least options.apart from
// those before it. Empty where none is acceptable.
std::vector<SixBarChainCandidate> SixBarChainCandidates(const std::vector<PlanarPose>& poses,
                                                        const DesignConstraints& constraints,
                                                        double length,
                                                        const SixBarChainSearchOptions& options);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_SIX_BAR_CHAINS_H_
