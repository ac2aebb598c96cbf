#include "tests/support/random_six_bar.h"

#include <algorithm>
#include <cmath>

namespace linkfit::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLeastRelativeTurn = 20.0 * kPi / 180.0;
constexpr double kLeastPoseTurn = 2.0 * kPi / 180.0;

// The side of the line from the ground pivot to the wrist the elbow is on (+1 left).
double ElbowSide(const SixBar& six_bar, const SixBarAngles& angles) {
  const Eigen::Vector2d g = six_bar.ground_pivot;
  const Eigen::Vector2d e =
      SixBarBodyDisplacement(six_bar, angles, kSixBarUpperLink).ToFixed(six_bar.elbow);
  const Eigen::Vector2d w =
      SixBarBodyDisplacement(six_bar, angles, kSixBarForearm).ToFixed(six_bar.wrist);
  const Eigen::Vector2d a = w - g, b = e - g;
  return a.x() * b.y() - a.y() * b.x() >= 0.0 ? 1.0 : -1.0;
}

}  // namespace

const std::vector<SixBarLayout>& SixBarLayouts() {
  static const std::vector<SixBarLayout> layouts = {
      {SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, kSixBarUpperLink, kSixBarTaskBody},
      {SixBarTopology::kStephensonII, kSixBarGround, kSixBarForearm, kSixBarGround,
       kSixBarTaskBody},
      {SixBarTopology::kStephensonIII, kSixBarGround, kSixBarTaskBody, kSixBarUpperLink,
       kSixBarTaskBody},
      {SixBarTopology::kStephensonI, kSixBarGround, kSixBarTaskBody, kSixBarFirstLink,
       kSixBarUpperLink},
      {SixBarTopology::kStephensonIII, kSixBarGround, kSixBarTaskBody, kSixBarFirstLink,
       kSixBarForearm},
      {SixBarTopology::kWattI, kSixBarGround, kSixBarForearm, kSixBarFirstLink, kSixBarTaskBody},
  };
  return layouts;
}

GeneratedSixBarTask RandomSixBarTask(std::mt19937_64& rng, const SixBarLayout& layout, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), length(0.6, 1.4), angle(-kPi, kPi);
  std::uniform_real_distribution<double> travel(40.0, 100.0);
  const auto point = [&]() { return Eigen::Vector2d(1.5 * unit(rng), 1.5 * unit(rng)); };
  const auto direction = [&]() {
    const double a = angle(rng);
    return Eigen::Vector2d(std::cos(a), std::sin(a));
  };
  for (;;) {
    GeneratedSixBarTask task;
    SixBar& six_bar = task.six_bar;
    six_bar.topology = layout.topology;
    six_bar.ground_pivot = point();
    six_bar.elbow = six_bar.ground_pivot + length(rng) * direction();
    six_bar.wrist = six_bar.elbow + length(rng) * direction();
    six_bar.reference_pose = PlanarPose(six_bar.wrist.x() + 0.5 * unit(rng),
                                        six_bar.wrist.y() + 0.5 * unit(rng), angle(rng));
    six_bar.links[0] = {layout.from0, layout.to0, point(), point()};
    six_bar.links[1] = {layout.from1, layout.to1, point(), point()};
    // Links no shorter than 0.3 (a designer's, and the synthesis's trivial roots apart).
    if (six_bar.links[0].Length() < 0.3 || six_bar.links[1].Length() < 0.3) continue;
    const double total = (rng() % 2 == 0 ? 1.0 : -1.0) * travel(rng) * kPi / 180.0;
    const int steps = static_cast<int>(std::ceil(std::abs(total) * 180.0 / kPi));
    SixBarAngles angles = SixBarAngles::Zero();
    const double side = ElbowSide(six_bar, angles);
    task.configurations.push_back(angles);
    bool ok = true;
    int next = 1;
    for (int s = 1; s <= steps && ok; ++s) {
      ok = DriveSixBar(six_bar, kSixBarUpperLink, total * s / steps, &angles, 1.0,
                       0.5 * kPi / 180.0) &&
           ElbowSide(six_bar, angles) == side;
      // The poses at equal shares of the turn.
      while (ok && next < count &&
             s == static_cast<int>(std::lround(1.0 * steps * next / (count - 1)))) {
        task.configurations.push_back(angles);
        ++next;
      }
    }
    if (!ok || static_cast<int>(task.configurations.size()) != count) continue;
    // Each RR link's two bodies turn apart by at least kLeastRelativeTurn over the poses, and
    // by kLeastPoseTurn between any two: a relative motion of a few degrees is nearly a rigid
    // one, and two relative poses a fraction of a degree apart nearly one (measured: 0.16
    // degrees apart, a root came back to 2e-7), whose Burmester problem gives its roots to a
    // few digits only.
    bool apart = true;
    for (const SixBarRRLink& link : six_bar.links) {
      std::vector<double> relative;
      for (const SixBarAngles& configuration : task.configurations) {
        const auto turn = [&](int body) { return body == 0 ? 0.0 : configuration[body - 1]; };
        relative.push_back(turn(link.to_body) - turn(link.from_body));
      }
      std::sort(relative.begin(), relative.end());
      apart = apart && relative.back() - relative.front() >= kLeastRelativeTurn;
      for (size_t k = 1; k < relative.size(); ++k) {
        apart = apart && relative[k] - relative[k - 1] >= kLeastPoseTurn;
      }
    }
    if (!apart) continue;
    for (const SixBarAngles& configuration : task.configurations) {
      task.poses.push_back(SixBarTaskPose(six_bar, configuration));
    }
    task.chain.ground_pivot = six_bar.ground_pivot;
    task.chain.wrist_in_moving = six_bar.reference_pose.ToMoving(six_bar.wrist);
    task.chain.upper_length = (six_bar.elbow - six_bar.ground_pivot).norm();
    task.chain.forearm_length = (six_bar.wrist - six_bar.elbow).norm();
    task.chain.elbow_at_first_pose = six_bar.elbow;
    return task;
  }
}

}  // namespace linkfit::testing
