#include "fitting/six_bar_chains.h"

#include <algorithm>
#include <cmath>

namespace linkfit {
namespace {

constexpr double kDeg = 180.0 / M_PI;

// The wrist's grid in E (times L about E's origin) and the ground pivot's in Sigma (times L about
// the wrist places' centroid, the centre left out: a ground pivot amid the wrist's path).
constexpr double kWristStep = 0.5;
constexpr int kWristHalf = 1;
constexpr double kGroundStep = 0.75;
constexpr int kGroundHalf = 3;
// a12 / a23.
constexpr double kLinkRatios[] = {0.6, 1.0, 1.0 / 0.6};

double Wrap(double angle) { return std::remainder(angle, 2.0 * M_PI); }

// Largest minus smallest of turns unwrapped from the first.
double Spread(const std::vector<double>& turns) {
  double low = 0.0, high = 0.0;
  for (double turn : turns) {
    const double from_first = Wrap(turn - turns.front());
    low = std::min(low, from_first);
    high = std::max(high, from_first);
  }
  return high - low;
}

double Angle(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

}  // namespace

bool JudgeSixBarChain(const std::vector<PlanarPose>& poses, const SixBarChain& chain,
                      const SixBarChainSearchOptions& options, SixBarChainCandidate* candidate) {
  std::vector<Eigen::Vector2d> elbows;
  int unreachable = -1;
  if (!ChainElbows(poses, chain, &elbows, &unreachable)) return false;
  std::vector<double> upper, forearm, elbow_turn, wrist_turn, task_from_upper;
  double margin = 180.0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector2d wrist = poses[k].ToFixed(chain.wrist_in_moving);
    const Eigen::Vector2d to_ground = chain.ground_pivot - elbows[k];
    const Eigen::Vector2d to_wrist = wrist - elbows[k];
    const double beta =
        std::acos(
            std::clamp(to_ground.dot(to_wrist) / (to_ground.norm() * to_wrist.norm()), -1.0, 1.0)) *
        kDeg;
    margin = std::min(margin, std::min(beta, 180.0 - beta));
    upper.push_back(Angle(elbows[k] - chain.ground_pivot));
    forearm.push_back(Angle(to_wrist));
    elbow_turn.push_back(forearm.back() - upper.back());
    wrist_turn.push_back(poses[k].theta - forearm.back());
    task_from_upper.push_back(poses[k].theta - upper.back());
  }
  if (margin < options.min_elbow_angle_deg) return false;
  const double travel = std::max({Spread(upper), Spread(elbow_turn), Spread(wrist_turn)}) * kDeg;
  if (travel > options.max_joint_travel_deg) return false;
  candidate->chain = chain;
  candidate->chain.elbow_at_first_pose = elbows.front();
  candidate->min_elbow_angle_deg = margin;
  candidate->forearm_spread_deg = Spread(forearm) * kDeg;
  candidate->task_from_upper_spread_deg = Spread(task_from_upper) * kDeg;
  candidate->score =
      std::min({margin, candidate->forearm_spread_deg, candidate->task_from_upper_spread_deg});
  return true;
}

std::vector<SixBarChainCandidate> SixBarChainCandidates(const std::vector<PlanarPose>& poses,
                                                        const DesignConstraints& constraints,
                                                        double length,
                                                        const SixBarChainSearchOptions& options) {
  std::vector<SixBarChainCandidate> all;
  const double longest = MaxLinkLength(constraints, length);
  const double shortest = constraints.min_link_length ? *constraints.min_link_length : 0.0;
  for (int wi = -kWristHalf; wi <= kWristHalf; ++wi) {
    for (int wj = -kWristHalf; wj <= kWristHalf; ++wj) {
      const Eigen::Vector2d wrist_in_moving = kWristStep * length * Eigen::Vector2d(wi, wj);
      if (constraints.moving_pivots_box &&
          !InBox(*constraints.moving_pivots_box, wrist_in_moving)) {
        continue;
      }
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for (const PlanarPose& pose : poses) centroid += pose.ToFixed(wrist_in_moving);
      centroid /= static_cast<double>(poses.size());
      for (int gi = -kGroundHalf; gi <= kGroundHalf; ++gi) {
        for (int gj = -kGroundHalf; gj <= kGroundHalf; ++gj) {
          if (gi == 0 && gj == 0) continue;
          const Eigen::Vector2d ground = centroid + kGroundStep * length * Eigen::Vector2d(gi, gj);
          if (constraints.fixed_pivots_box && !InBox(*constraints.fixed_pivots_box, ground)) {
            continue;
          }
          double near = INFINITY, far = 0.0;
          for (const PlanarPose& pose : poses) {
            const double d = (pose.ToFixed(wrist_in_moving) - ground).norm();
            near = std::min(near, d);
            far = std::max(far, d);
          }
          for (double ratio : kLinkRatios) {
            // The elbow angle centred on 90 degrees over the poses (file comment).
            const double forearm =
                std::sqrt((near * near + far * far) / (2.0 * (ratio * ratio + 1.0)));
            const double upper = ratio * forearm;
            if (std::max(upper, forearm) > longest || std::min(upper, forearm) < shortest) continue;
            // The elbow angles at the nearest and farthest wrist (law of cosines): the least
            // margin from the singular places lies at one of them, whichever the elbow's side.
            const auto beta = [&](double d) {
              return std::acos(std::clamp(
                         (upper * upper + forearm * forearm - d * d) / (2.0 * upper * forearm),
                         -1.0, 1.0)) *
                     kDeg;
            };
            const double margin =
                std::min({beta(near), 180.0 - beta(near), beta(far), 180.0 - beta(far)});
            if (margin < options.min_elbow_angle_deg) continue;
            for (bool left : {true, false}) {
              SixBarChain chain;
              chain.ground_pivot = ground;
              chain.wrist_in_moving = wrist_in_moving;
              chain.upper_length = upper;
              chain.forearm_length = forearm;
              chain.elbow_left = left;
              SixBarChainCandidate candidate;
              if (JudgeSixBarChain(poses, chain, options, &candidate)) all.push_back(candidate);
            }
          }
        }
      }
    }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const SixBarChainCandidate& a, const SixBarChainCandidate& b) {
                     return a.score > b.score;
                   });
  std::vector<SixBarChainCandidate> kept;
  for (const SixBarChainCandidate& candidate : all) {
    if (static_cast<int>(kept.size()) >= options.max_candidates) break;
    const bool near_one = std::any_of(kept.begin(), kept.end(), [&](const SixBarChainCandidate& k) {
      return k.chain.elbow_left == candidate.chain.elbow_left &&
             (k.chain.ground_pivot - candidate.chain.ground_pivot).norm() <
                 options.apart * length &&
             (k.chain.wrist_in_moving - candidate.chain.wrist_in_moving).norm() <
                 options.apart * length;
    });
    if (!near_one) kept.push_back(candidate);
  }
  return kept;
}

}  // namespace linkfit
