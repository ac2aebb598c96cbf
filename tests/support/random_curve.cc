#include "tests/support/random_curve.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lib/mechanism.h"
#include "lib/planar_pose.h"

namespace linkfit::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector2d Turned(const Eigen::Vector2d& v, double angle) {
  return Eigen::Vector2d(std::cos(angle) * v.x() - std::sin(angle) * v.y(),
                         std::sin(angle) * v.x() + std::cos(angle) * v.y());
}

// A four-bar whose crank (pivot at the origin, length 1, pin on the x axis) turns fully.
PathFourBar Draw(std::mt19937_64& rng, DyadType output) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto between = [&](double low, double high) { return low + (high - low) * unit(rng); };
  const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
  const Eigen::Vector2d pin(1.0, 0.0);
  PathFourBar four_bar;
  four_bar.input = PlanarDyad::RR(Eigen::Vector2d::Zero(), pin, 1.0);
  for (;;) {
    if (output == DyadType::kRR) {
      const double ground = between(1.5, 4.0), coupler = between(1.5, 4.5),
                   rocker = between(1.5, 4.0);
      std::array<double, 4> links = {1.0, ground, coupler, rocker};
      std::sort(links.begin(), links.end());
      if (links[0] + links[3] > 0.9 * (links[1] + links[2])) continue;
      const Eigen::Vector2d pivot(ground, 0.0);
      const double d = (pivot - pin).norm();
      const double along = (coupler * coupler - rocker * rocker + d * d) / (2.0 * d);
      const double across2 = coupler * coupler - along * along;
      if (!(across2 > 0.0)) continue;
      const Eigen::Vector2d unit_span = (pivot - pin) / d;
      const Eigen::Vector2d moving =
          pin + along * unit_span + side * std::sqrt(across2) * Turned(unit_span, kPi / 2);
      four_bar.output = PlanarDyad::RR(pivot, moving, rocker);
      const Eigen::Vector2d link = moving - pin;
      four_bar.coupler_point =
          pin + between(-0.5, 1.5) * link + between(-1.0, 1.0) * Turned(link, kPi / 2);
    } else if (output == DyadType::kPR) {
      const double coupler = between(1.6, 4.5);
      const double offset = between(-0.8, 0.8) * (coupler - 1.0);
      const double angle = between(-0.3, 0.3);  // the slider's line not along x
      const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
      const Eigen::Vector2d normal = Turned(direction, kPi / 2);
      // The pin on the line {offset * normal + t direction} at distance `coupler` from A.
      const double foot = (pin - offset * normal).dot(direction);
      const double height = std::abs((pin - offset * normal).dot(normal));
      if (!(coupler > height)) continue;
      const Eigen::Vector2d moving =
          offset * normal +
          (foot + side * std::sqrt(coupler * coupler - height * height)) * direction;
      four_bar.output = PlanarDyad::PR(moving, offset * normal, direction);
      const Eigen::Vector2d link = moving - pin;
      four_bar.coupler_point =
          pin + between(-0.5, 1.5) * link + between(-0.8, 0.8) * Turned(link, kPi / 2);
    } else {
      const double ground = between(1.6, 4.0);
      const Eigen::Vector2d pivot(ground, 0.0);
      const double offset = between(-0.8, 0.8) * (ground - 1.0);
      const double turn = std::asin(offset / (ground - 1.0));
      four_bar.output = PlanarDyad::RP(pivot, pivot, Turned(Eigen::Vector2d::UnitX(), turn));
      four_bar.coupler_point =
          pin + ground * Eigen::Vector2d(between(-0.8, 1.2), between(-0.8, 0.8));
    }
    return four_bar;
  }
}

}  // namespace

GeneratedCurve RandomCurve(std::mt19937_64& rng, DyadType output, const CurveOptions& options) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (;;) {
    const PathFourBar drawn = Draw(rng, output);
    // Placed, turned, scaled (and mirrored half the time) at random.
    const double scale = std::exp(std::log(0.2) + unit(rng) * std::log(100.0));
    const double turn = 2.0 * kPi * unit(rng);
    const bool mirror = unit(rng) < 0.5;
    const double reach = options.offset_scale * 3.0 * scale;
    const Eigen::Vector2d shift(reach * (2.0 * unit(rng) - 1.0), reach * (2.0 * unit(rng) - 1.0));
    Similarity2 similarity;
    similarity.scale = scale;
    similarity.angle = turn;
    similarity.translation = shift;
    const PathFourBar placed = TransformPathFourBar(drawn, similarity, mirror);
    // Crank angles: a full turn or an arc, from a random start, either sense, steps uneven.
    const int count = options.count;
    const double span = options.closed ? 2.0 * kPi : options.arc_turns * 2.0 * kPi;
    const int steps = options.closed ? count : count - 1;
    std::vector<double> step(steps);
    double total = 0.0;
    for (double& s : step) {
      s = options.uneven ? 0.5 + unit(rng) : 1.0;
      total += s;
    }
    const double direction = unit(rng) < 0.5 ? -1.0 : 1.0;
    const double start = 2.0 * kPi * unit(rng);
    std::vector<double> angles = {0.0};
    for (int j = 1; j < count; ++j)
      angles.push_back(angles.back() + direction * span * step[j - 1] / total);
    // The configuration at the start angle (the assembly the drawn four-bar has at angle 0,
    // followed there in small steps).
    std::vector<PlanarPose> poses;
    PlanarPose pose;  // identity: the configuration of crank angle 0 (E = Sigma)
    const double alpha0 = FirstCrankAngle(placed);
    bool lost = false;
    const int walk = 720;
    for (int k = 1; k <= walk && !lost; ++k) {
      const double alpha = alpha0 + start * k / walk;
      if (AssembleFourBar(placed.input, placed.output, alpha, 1e-9 * scale, &poses) == 0) {
        lost = true;
        break;
      }
      const int nearest =
          poses.size() == 2 && PoseError(poses[1], pose, scale) < PoseError(poses[0], pose, scale)
              ? 1
              : 0;
      pose = poses[nearest];
    }
    if (lost) continue;
    GeneratedCurve curve;
    curve.four_bar = MoveToFirstConfiguration(placed, pose);
    curve.input_angles = angles;
    curve.closed = options.closed;
    // The points: the four-bar driven from its first configuration.
    std::vector<Eigen::Vector2d> guess(count, curve.four_bar.coupler_point);
    PathAnalysisOptions analysis_options;
    analysis_options.closed = options.closed;
    const PathFourBarAnalysis analysis =
        AnalyzePathFourBar(curve.four_bar, guess, angles, scale, analysis_options);
    if (!analysis.max_point_error || !analysis.input_rotates_fully ||
        analysis.configurations.size() != static_cast<size_t>(count)) {
      continue;
    }
    for (const PlanarPose& at : analysis.configurations) {
      curve.points.push_back(at.ToFixed(curve.four_bar.coupler_point));
    }
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& p : curve.points) centroid += p / count;
    double sum = 0.0;
    for (const Eigen::Vector2d& p : curve.points) sum += (p - centroid).squaredNorm();
    curve.size = std::sqrt(sum / count);
    const PathFourBarAnalysis check =
        AnalyzePathFourBar(curve.four_bar, curve.points, angles, curve.size, analysis_options);
    if (!check.defects.empty() || !check.max_point_error ||
        *check.max_point_error > 1e-9 * curve.size) {
      continue;
    }
    return curve;
  }
}

double CurveRmsDistance(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                        double length, int samples) {
  const std::vector<PlanarPose> cycle = CouplerCycle(four_bar, length, samples);
  if (cycle.size() < 2) return std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector2d> curve;
  for (const PlanarPose& pose : cycle) curve.push_back(pose.ToFixed(four_bar.coupler_point));
  double sum = 0.0;
  for (const Eigen::Vector2d& p : points) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k + 1 < curve.size(); ++k) {
      const Eigen::Vector2d a = curve[k], b = curve[k + 1];
      const Eigen::Vector2d ab = b - a;
      const double t =
          ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      best = std::min(best, (a + t * ab - p).squaredNorm());
    }
    sum += best;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace linkfit::testing
