// Four-bar function generation (issue 17, item 7): four-bars whose output crank angle psi is a
// prescribed function of the input crank angle phi, through precision pairs (phi_j, psi_j).
// The four-bar and its closure are lib/function_four_bar.h; the ground d = |A B| is given.
//
// Absolute angles (both measured from the ground line): Freudenstein's equation (Fr),
//   K1 cos psi_j - K2 cos phi_j + K3 = cos(phi_j - psi_j),
// is linear in K: three pairs give one four-bar exactly (a = d / K1, c = d / K2,
// b^2 = a^2 + c^2 + d^2 - 2ac K3), more pairs the weighted linear least-squares seed. A K1 or K2
// of the wrong sign puts a crank opposite its prescribed angle and b^2 <= 0 closes no coupler:
// such a solution is no four-bar for the pairs, and the solver says why.
//
// Relative angles (only differences matter; the cranks' offsets are unknowns): the output link's
// motion relative to the input link is a planar motion, and a four-bar's coupler is an RR dyad
// of it (the kinematic inversion on the input link). In the input link's frame I (origin A,
// turned by phi_j) the output link's frame O (origin B, turned by psi_j) is at the pose
//   origin R(-phi_j) (d, 0), angle psi_j - phi_j,
// and an RR dyad of these poses, fixed pivot P_I in I and moving pivot Q_O in O, radius r, is
// the four-bar with input crank a = |P_I| at offset atan2(P_I), output crank c = |Q_O| at offset
// atan2(Q_O) and coupler b = r. Five pairs: the Burmester problem of five poses
// (fitting/planar_burmester.h, seed 001), whose four roots include the ground link itself
// (P_I = A, Q_O = B, r = d): up to three four-bars. More pairs: the algebraic least-squares dyads
// of the same poses. Sliders (PR, RP roots) are not cranks and are dropped.
//
// Preconditions: pairs of distinct inputs; d > 0. Angles in radians.
#ifndef LINKFIT_FITTING_FUNCTION_GENERATION_H_
#define LINKFIT_FITTING_FUNCTION_GENERATION_H_

#include <string>
#include <vector>

#include "lib/function_four_bar.h"
#include "lib/planar_pose.h"
#include "lib/precision.h"

namespace linkfit {

struct FunctionGenerationOptions {
  // A relative root whose input and output cranks are both shorter than this times d is the
  // ground link (the trivial root), not a four-bar.
  double trivial_tolerance = 1e-6;
  // The data's precision (the pairs' angles); passed to the Burmester solver's model choices.
  DataPrecision precision;
};

// Absolute angles, three or more pairs: the four-bar of Freudenstein's equation, exact for three
// pairs and the weighted linear least-squares fit beyond (exact pairs weighted 1e6 times). Its
// assembly is the one that meets the first pair. Returns 1, or 0 with the reason in *why (no
// real four-bar: a crank opposite its angle, no coupler, dependent pairs).
int SolveFreudenstein(const std::vector<FunctionPair>& pairs, double ground,
                      std::vector<FunctionFourBar>* four_bars, std::string* why = nullptr);

// Relative angles, five or more pairs: every four-bar from the RR dyads of the output's motion
// relative to the input (exact for five pairs, the algebraic least-squares seeds beyond), each in
// the assembly that meets the first pair. Returns the count; *why says why there are none.
int SolveRelativeFunction(const std::vector<FunctionPair>& pairs, double ground,
                          const FunctionGenerationOptions& options,
                          std::vector<FunctionFourBar>* four_bars, std::string* why = nullptr);

// The relative poses of the output link in the input link's frame (file comment), one per pair.
std::vector<PlanarPose> RelativeOutputPoses(const std::vector<FunctionPair>& pairs, double ground);

// Relative angles with the offsets given: Freudenstein's linear least squares with the cranks
// at t2 = input_offset + phi_j, t4 = output_offset + psi_j (the search's inner problem). Returns
// 1 or 0 as SolveFreudenstein.
int FreudensteinWithOffsets(const std::vector<FunctionPair>& pairs, double ground,
                            double input_offset, double output_offset,
                            std::vector<FunctionFourBar>* four_bars, std::string* why = nullptr);

}  // namespace linkfit

#endif  // LINKFIT_FITTING_FUNCTION_GENERATION_H_
