// The report every least-squares refiner returns (spatial dyads now; planar dyads and four-bars
// later): the weighted cost and residual statistics before and after, and what the solver did.
// All costs and residuals are in the task's own length units, after the refiner has undone
// its internal centring and scaling.
#ifndef LINKFIT_OPTIMIZERS_REFINER_SUMMARY_H_
#define LINKFIT_OPTIMIZERS_REFINER_SUMMARY_H_

#include <string>

namespace linkfit {

struct RefinerSummary {
  double initial_cost = 0.0;   // 1/2 sum w_j e_j^2 of the seed, length units squared
  double final_cost = 0.0;     // the same for the returned design
  double initial_rms = 0.0;    // sqrt(sum w e^2 / sum w) of the seed, length units
  double final_rms = 0.0;      // the same for the returned design
  double initial_max = 0.0;    // max |e_j| of the seed, length units
  double final_max = 0.0;      // the same for the returned design
  int iterations = 0;          // solver iterations, summed over every model refined
  double seconds = 0.0;        // wall time of the whole refinement
  bool model_changed = false;  // the design changed type (for a spatial dyad: SS <-> PS)
  // RefineFourBar and RefinePathFourBar: false when the returned design's last solve stopped at
  // its iteration limit (a slow descent), so that a refinement from it may still gain.
  bool converged = true;
  std::string message;  // Ceres termination message, with the refiner's own notes
};

// A design refined in rounds (the solvers' listed four-bars, issue 35) goes on while a round
// lowers its error by more than kRoundGain, or by more than kDescentGain where the round stopped
// at its iteration limit (RefinerSummary::converged false): a slow descent along a curved valley
// of the fit can take a thousand Levenberg-Marquardt steps, and one round's gain there is no
// guide to the next; one that crawls slower is at its optimum as far as 1 % tells.
inline constexpr double kRoundGain = 0.005;
inline constexpr double kDescentGain = 0.0005;
inline bool Gains(double before, double after, double share) {
  return after < (1.0 - share) * before;
}
inline bool AnotherRound(double before, double after, bool converged) {
  return Gains(before, after, converged ? kRoundGain : kDescentGain);
}

// Within one refinement (the path refinements of `linkfit refine`), the solve again from where
// the last one stopped: after one that stopped at its iteration limit while it gains more than
// kDescentGain (a slow descent), after one that stopped on a tolerance while it gains more than
// kRestartGain. Where steps would break assembly (a point near a dead point), Levenberg-Marquardt's
// trust region collapses and it stops on its step tolerance short of the optimum, a stall a fresh
// solve often passes; from an optimum, a fresh solve stops at once.
inline constexpr double kRestartGain = 1e-9;
inline bool SolveAgain(double before, double after, bool converged) {
  return Gains(before, after, converged ? kRestartGain : kDescentGain);
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_REFINER_SUMMARY_H_
