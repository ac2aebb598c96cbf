// Planar six-bar linkages built on a 3R serial chain (McCarthy and Soh, Geometric Design of
// Linkages, 2nd ed., 2011, ch. 6): ground (body 0); the upper link (body 1), turning about the
// ground pivot G; the forearm (body 2), joined to it at the elbow; and the task body E (body 3),
// joined to the forearm at the wrist. Two RR links make the chain's three freedoms one. Each joins
// two bodies: two of the chain's, or (a "new crank") the first RR link itself (body 4), turning
// about its ground pivot, and a chain body. The second RR link is body 5.
//
// Every joint is given by where it is in Sigma at the reference configuration (the first task
// pose), and every body's frame is Sigma at the reference: a body's configuration is the planar
// displacement from its reference place, T_k(p) = T_parent(k)(x_k) + R(alpha_k) (p - x_k), with
// x_k the joint by which body k hangs from its parent in the tree 0 <- 1 <- 2 <- 3 (and each RR
// link from its first body), and alpha_k its turn from the reference. The loop closures are the
// two RR links' second joints: T_link(p) = T_body(p) at the joint's reference place p.
#ifndef LINKFIT_LIB_SIX_BAR_H_
#define LINKFIT_LIB_SIX_BAR_H_

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lib/planar_pose.h"
#include "lib/six_bar_frames.h"

namespace linkfit {

// The six-bar's kind: which of its links are ternary and whether they are adjacent (Watt) or
// not (Stephenson), and which link is ground. A 3R chain grounded at one end admits these four.
enum class SixBarTopology { kWattI, kStephensonI, kStephensonII, kStephensonIII };

// "Watt I", "Stephenson I", ...
const char* SixBarTopologyName(SixBarTopology topology);

// The bodies of a six-bar (see the file comment).
enum SixBarBody : int {
  kSixBarGround = 0,
  kSixBarUpperLink = 1,
  kSixBarForearm = 2,
  kSixBarTaskBody = 3,
  kSixBarFirstLink = 4,
  kSixBarSecondLink = 5,
};

// An RR link: the body it hangs from (its first joint) and the body its second joint closes on,
// both joints in Sigma at the reference configuration.
struct SixBarRRLink {
  int from_body = kSixBarGround;
  int to_body = kSixBarTaskBody;
  Eigen::Vector2d from_joint = Eigen::Vector2d::Zero();
  Eigen::Vector2d to_joint = Eigen::Vector2d::Zero();
  double Length() const { return (to_joint - from_joint).norm(); }
};

struct SixBar {
  SixBarTopology topology = SixBarTopology::kWattI;
  // The 3R chain's joints at the reference configuration, in Sigma.
  Eigen::Vector2d ground_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d elbow = Eigen::Vector2d::Zero();
  Eigen::Vector2d wrist = Eigen::Vector2d::Zero();
  // The task body's pose at the reference configuration (E in Sigma): the first task pose.
  PlanarPose reference_pose;
  // links[0] is body 4, links[1] body 5; links[1] may hang from body 4 (a new crank).
  std::array<SixBarRRLink, 2> links;
};

// The joints as numbers (lib/six_bar_frames.h SixBarJoint order).
std::array<double, kSixBarJointCount> SixBarJointNumbers(const SixBar& six_bar);

// The joints of each body (SixBarBody order) as indices of the seven joints (SixBarJoint / 2:
// the ground pivot, the elbow, the wrist, each RR link's first and second joint), in the order
// SixBarBodyJoints lists them.
std::array<std::vector<int>, 6> SixBarBodyJointIndices(const SixBar& six_bar);

// The joints of each body (SixBarBody order) at the reference configuration, in Sigma: ground's
// pivots (the ground pivot, then each RR link's joint on ground), the upper link's (ground pivot,
// elbow, then RR joints on it), the forearm's (elbow, wrist, ...), the task body's (wrist, ...),
// and each RR link's own two (and, on a new crank, the second link's joint on it).
std::array<std::vector<Eigen::Vector2d>, 6> SixBarBodyJoints(const SixBar& six_bar);

// The turns alpha_1 .. alpha_5 of bodies 1 to 5 from the reference (radians).
using SixBarAngles = Eigen::Matrix<double, 5, 1>;

// Body k's displacement from its reference place at `angles` (k = 0 .. 5).
PlanarPose SixBarBodyDisplacement(const SixBar& six_bar, const SixBarAngles& angles, int body);

// The task body's pose (E in Sigma) at `angles`.
PlanarPose SixBarTaskPose(const SixBar& six_bar, const SixBarAngles& angles);

// The two loop closures (4 residuals, length units): each RR link's second joint on the link
// minus the same joint on the body it closes on.
Eigen::Vector4d SixBarClosure(const SixBar& six_bar, const SixBarAngles& angles);

// Assembles the six-bar with the turn of body `input` (1, 4 or 5: a link turning about ground)
// set to `input_angle`, by Newton's method from `angles` (read as the start, written with the
// result). Returns false where it does not converge to `tolerance` (length units) in
// `max_iterations`, or the closure's Jacobian is singular there (a dead point).
bool AssembleSixBar(const SixBar& six_bar, int input, double input_angle, SixBarAngles* angles,
                    double tolerance, int max_iterations = 30);

// A 3R chain the six-bar is built on: its ground pivot, its wrist in E, its two link lengths,
// and which of the two elbow places it takes at the first pose: the one nearer
// `elbow_at_first_pose` when given, else the one to the left of the line from the ground pivot
// to the wrist (`elbow_left`) or to its right. At later poses the elbow stays on the same side
// of that line (the inverse kinematics' branch followed through the poses).
struct SixBarChain {
  Eigen::Vector2d ground_pivot = Eigen::Vector2d::Zero();
  Eigen::Vector2d wrist_in_moving = Eigen::Vector2d::Zero();
  double upper_length = 1.0;    // ground pivot to elbow (a12)
  double forearm_length = 1.0;  // elbow to wrist (a23)
  std::optional<Eigen::Vector2d> elbow_at_first_pose;
  bool elbow_left = true;
  // Held by least squares and refinement (the ground pivot, both link lengths and the wrist in
  // E kept; optimizers/six_bar_refiner.h SixBarRefinerOptions::held_chain); else every joint is
  // free, the chain's too.
  bool hold = false;
};

// The chain's elbow at each pose (Sigma), or false (and summary->unreachable_pose) where a pose
// puts the wrist out of the chain's reach.
bool ChainElbows(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                 std::vector<Eigen::Vector2d>* elbows, int* unreachable_pose);

// How a six-bar's positions under an input are found.
enum class SixBarPositions {
  // In closed form where the input leaves two RR dyads (Assur groups of class II) that close one
  // after the other: each dyad's middle joint on the circles about its two known joints (a
  // circle intersection), its assembly the side of the line through them that joint is on. The
  // chain's own topology decides: Watt I under every input, Stephenson II under the upper and
  // first links and the new-crank Stephenson I are dyads; Stephenson III and Stephenson II under
  // its second link leave a triad, placed by continuation. Else:
  kClosedFormWhereItCan,
  kContinuation,  // always by continuation (Newton's method on the loop closures)
};

// One assembly of a six-bar under an input, to place it at other input turns on the same one:
// the sides of its dyads (closed form), or the sign of the free turns' Jacobian's determinant
// (continuation).
struct SixBarAssembly {
  std::array<int, 2> sides = {1, 1};
  double determinant = 0.0;
};

// The six-bar's positions under body `input` (a grounded link: 1, 4 or 5), by `positions`.
class SixBarDriver {
 public:
  SixBarDriver(const SixBar& six_bar, int input, double length,
               SixBarPositions positions = SixBarPositions::kClosedFormWhereItCan);

  // Whether the positions are in closed form (else by continuation).
  bool closed_form() const { return dyad_count_ == 2; }

  // The assembly `angles` are in (closed form: read from them; continuation: they are assembled
  // to 1e-10 L at their input turn first); false where they do not assemble there or are at a
  // dead point.
  bool AssemblyOf(const SixBarAngles& angles, SixBarAssembly* assembly) const;

  // The six-bar in `assembly` at the input turn `input_angle`, into `angles` (continuation: from
  // them as the start, to `tolerance` times the length): false beyond a dead point (no such
  // assembly there) or, by continuation, where Newton's method reaches another assembly.
  bool Place(const SixBarAssembly& assembly, double input_angle, SixBarAngles* angles,
             double tolerance = 1e-10) const;

  // Drives the six-bar (DriveSixBar, whose contract this keeps). In closed form: in even steps
  // of at most `max_step`, a dead point where a dyad does not close at a step, or where between
  // two steps its least angle (golden-section search where it falls below 15 degrees at either)
  // does; every turn continued from the last step's (no jump of a whole turn).
  bool Drive(double to_angle, SixBarAngles* angles, double max_step,
             const std::function<void(const SixBarAngles&)>& visit = nullptr) const;

 private:
  // One dyad: bodies a and b joined at joint j, hanging from known joints ja (on a) and jb (on
  // b), at distances ra and rb from j; each body's other joints.
  struct Dyad {
    int a = 0, b = 0, j = 0, ja = 0, jb = 0;
    double ra = 0.0, rb = 0.0;
    Eigen::Vector2d lever_a, lever_b;  // j - ja, j - jb at the reference configuration
    std::vector<int> joints_a, joints_b;
  };
  // The dyads at input turn `input_angle` on `sides`: the turns (continued from those in
  // `angles`; none where it is null), and the least of the dyads' sin^2 of the angle between
  // their two bodies at j (negative where one does not close: that one's, the later ones not
  // placed). False where a dyad does not close.
  bool Close(double input_angle, const std::array<int, 2>& sides, SixBarAngles* angles,
             double* margin) const;
  std::array<int, 2> Sides(const SixBarAngles& angles) const;

  const SixBar& six_bar_;
  int input_ = 1;
  double length_ = 1.0;
  std::array<Eigen::Vector2d, 7> reference_;  // the joints at the reference configuration
  std::vector<int> ground_joints_, input_joints_;
  int input_hinge_ = 0;  // the input's joint on ground
  std::array<Dyad, 2> dyads_;
  int dyad_count_ = 0;
};

// Drives the six-bar by body `input` from `angles` (an assembly) to the input turn `to_angle`,
// in closed form where it can (SixBarDriver::Drive), else by continuation: steps of at most
// `max_step` radians, each predicted along the closure's tangent and corrected by Newton's method
// (AssembleSixBar), accepted when that converges in a few iterations, moves the turns by a small
// share of the predicted move and keeps the sign of the free turns' Jacobian's determinant (else
// a jump toward another assembly, or over a dead point, is possible: the step is halved; it grows
// again while the corrections stay small). `visit`, when given, sees each configuration reached.
// Returns false at a dead point (by continuation: the step falls below 1e-8 radians); `angles` is
// then the last assembly reached.
bool DriveSixBar(const SixBar& six_bar, int input, double to_angle, SixBarAngles* angles,
                 double length, double max_step,
                 const std::function<void(const SixBarAngles&)>& visit = nullptr,
                 SixBarPositions positions = SixBarPositions::kClosedFormWhereItCan);

// Whether body `body`'s turn can drive the six-bar: a link turning about a ground pivot.
bool SixBarGroundedLink(const SixBar& six_bar, int body);

// The transmission angle of each RR link's loop at a configuration, folded into [0, 90] degrees
// as a four-bar's (lib/four_bar_motion.h TransmissionAngleDeg): at the joint J where the link
// closes on its body, the angle between the link and that body's lever from J to the joint by
// which the body hangs from its parent (the loop's coupler-rocker angle); 90 is best, 0 a dead
// point of the loop.
std::array<double, 2> SixBarTransmissionDeg(const SixBar& six_bar, const SixBarAngles& angles);

// The six-bar driven by body `input` through task poses it reaches at `at_poses` (the turns at
// each pose, e.g. from the chain's inverse kinematics): by continuation along the input's turn
// (DriveSixBar, steps of at most `step` radians) from the first pose to each next.
//   order:   the input's turns at the poses do not run one way;
//   branch:  a dead point (singular closure) lies between two poses: the input cannot drive on;
//   circuit: the continuation arrives at a pose's input turn in another assembly than the pose's.
// With `full_turn`, whether a whole turn of the input from the first pose meets no dead point
// (not tried after a branch defect, which stops it). Without `refine_transmission`, the least
// transmission angles are the least of the configurations reached (not refined between them: at
// most a few degrees above, for a quick judgement).
struct SixBarAnalysis {
  std::vector<std::string> defects;
  std::vector<double> input_angles;  // the input's turn from the first pose at each pose
  // The smallest transmission angle of each RR link from the first pose to the last (over the
  // driven range where a defect stops it), degrees: the least of the configurations the
  // continuation reaches, refined by golden-section search over the input where the least may
  // lie between two (measured against half-degree steps: within 0.1 degrees, tests).
  std::array<double, 2> transmission_min_deg = {90.0, 90.0};
  bool input_rotates_fully = false;  // a whole turn of the input meets no dead point
};
// The largest continuation step of AnalyzeSixBar: four degrees (measured: the same defects and
// whole turns as half-degree steps on the random six-bars of the tests).
inline constexpr double kSixBarDriveStep = 4.0 * M_PI / 180.0;
SixBarAnalysis AnalyzeSixBar(const SixBar& six_bar, const std::vector<SixBarAngles>& at_poses,
                             int input, double length, double step = kSixBarDriveStep,
                             bool full_turn = true, bool refine_transmission = true,
                             SixBarPositions positions = SixBarPositions::kClosedFormWhereItCan);

// Whether a whole turn of body `input` from the assembly `angles` meets no dead point
// (DriveSixBar).
bool SixBarInputRotatesFully(const SixBar& six_bar, const SixBarAngles& angles, int input,
                             double length, double step = kSixBarDriveStep,
                             SixBarPositions positions = SixBarPositions::kClosedFormWhereItCan);

// The configurations over the input's range from the assembly `at_first` (DriveSixBar, steps of at
// most `step`): a whole turn when it meets no dead point (from `at_first` on, the input rising);
// else the rocker's range from the dead point behind to the dead point ahead, the input rising
// through `at_first`. Each drive stops after a whole turn.
std::vector<SixBarAngles> SixBarSweep(const SixBar& six_bar, const SixBarAngles& at_first,
                                      int input, double length, double step = kSixBarDriveStep);

}  // namespace linkfit

#endif  // LINKFIT_LIB_SIX_BAR_H_
