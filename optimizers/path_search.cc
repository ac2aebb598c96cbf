#include "optimizers/path_search.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <nlopt.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "fitting/planar_burmester.h"
#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "optimizers/design_bounds.h"
#include "optimizers/planar_dyad_blocks.h"
#include "optimizers/refiner_input.h"

namespace linkfit {
namespace {

using Clock = std::chrono::steady_clock;

// The objective's value where it cannot evaluate (non-finite values, no crank, no output dyad):
// large, finite, and worse than any real fit in the scaled problem (weights summing to 1, L = 1).
constexpr double kLargeCost = 1e30;
// Points marked exact weigh this much more in the search; the refinement then meets them.
constexpr double kExactSearchWeight = 100.0;
// Two archived cranks closer than this (scaled, largest of |dB| and |dA|) are one basin: the
// archive keeps the better.
constexpr double kArchiveRadius = 0.1;
// Refined four-bars whose parameters all agree to this (times L) are one.
constexpr double kDistinct = 1e-3;
// A Burmester dyad this near the crank (scaled, in F, m and r) is the crank itself (the coupler
// poses q_j are the crank's motion, so the crank always fits them): not an output.
constexpr double kCrankDyad = 1e-2;
// A crank or coupler link shorter than this (scaled) is degenerate.
constexpr double kShortLink = 1e-9;
// DrivableOutput: the radius this fraction of the allowed range inside it.
constexpr double kDrivableMargin = 1e-3;
// Seconds every NLopt run gets at least, whatever the runs before it took.
constexpr double kLeastRunTime = 1e-3;

// The task in the scaled frames Sigma' = E' = (Sigma - centroid) / L.
struct ScaledTask {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;  // normalized to sum 1, exact points weighted up
  std::vector<double> turns;    // psi_j - psi_0
  ScaledBounds bounds;          // the design bounds (design_bounds.h)
};

// Weight of the squared violation of the design bounds in the objective (the points' cost is a
// weighted mean of squared errors in units of L).
constexpr double kSearchBoundWeight = 1e2;

// The objective over the crank x = (B, A) (scaled; A is the pin at the first point, in Sigma
// and in E):
//   A_j = B + R(t_j) (A - B),  l_j = |R_j - A_j|,  l = sum w l_j,
//   f = sum w (l_j - l)^2 + min over output dyads D of sum w D.Residual(q_j)^2,
// q_j the coupler pose that turns the first point's coupler line A -> R_0 onto A_j -> R_j
// (theta_j = angle(R_j - A_j) - angle(R_0 - A_0), origin A_j - R(theta_j) A; q_0 = identity),
// the dyads D the algebraic least-squares Burmester dyads of the q_j other than the crank.
class Objective {
 public:
  explicit Objective(const ScaledTask& task) : task_(task) {}

  double operator()(const double* x) const { return Evaluate(x, nullptr); }

  // The value at x; with `outputs`, also every output dyad with its cost, best first.
  double Evaluate(const double* x, std::vector<std::pair<double, PlanarDyad>>* outputs) const {
    const Eigen::Vector2d crank_pivot(x[0], x[1]), crank_pin(x[2], x[3]);
    if (!crank_pivot.allFinite() || !crank_pin.allFinite()) return kLargeCost;
    const Eigen::Vector2d arm = crank_pin - crank_pivot;
    if (!(arm.norm() > kShortLink)) return kLargeCost;
    const size_t count = task_.points.size();
    std::vector<double> links(count);
    std::vector<PlanarPose> poses(count);
    double mean = 0.0, first_angle = 0.0;
    for (size_t j = 0; j < count; ++j) {
      const Eigen::Vector2d pin = crank_pivot + Rotation2(task_.turns[j]) * arm;
      const Eigen::Vector2d link = task_.points[j] - pin;
      links[j] = link.norm();
      if (!(links[j] > kShortLink)) return kLargeCost;
      mean += task_.weights[j] * links[j];
      const double angle = std::atan2(link.y(), link.x());
      if (j == 0) first_angle = angle;
      poses[j].theta = angle - first_angle;
      poses[j].origin_in_fixed = pin - Rotation2(poses[j].theta) * crank_pin;
    }
    double link_cost = 0.0;
    for (size_t j = 0; j < count; ++j) {
      link_cost += task_.weights[j] * (links[j] - mean) * (links[j] - mean);
    }
    std::vector<PlanarDyad> dyads;
    SolvePlanarBurmester(poses, PlanarBurmesterOptions(), &dyads);
    // The design bounds, each output dyad with the crank and the coupler point R_0.
    const auto violation = [&](const PlanarDyad& output) {
      const DyadBlocks blocks = ToBlocks(output);
      return BoundViolation(
          task_.bounds,
          PathBoundGeometry(blocks.type, crank_pivot.data(), crank_pin.data(), blocks.point,
                            blocks.second, blocks.scalar, task_.points.front().data()));
    };
    double best = kLargeCost;
    for (const PlanarDyad& dyad : dyads) {
      if (dyad.type == DyadType::kRR && (dyad.fixed_pivot - crank_pivot).norm() < kCrankDyad &&
          (dyad.moving_pivot - crank_pin).norm() < kCrankDyad &&
          std::abs(dyad.radius - arm.norm()) < kCrankDyad) {
        continue;
      }
      double cost = 0.0;
      for (size_t j = 0; j < count; ++j) {
        const double residual = dyad.Residual(poses[j]);
        cost += task_.weights[j] * residual * residual;
      }
      const double outside = violation(dyad);
      cost += kSearchBoundWeight * outside * outside;
      if (!std::isfinite(cost)) continue;
      best = std::min(best, cost);
      if (outputs != nullptr) outputs->emplace_back(cost, dyad);
    }
    if (outputs != nullptr) {
      std::stable_sort(outputs->begin(), outputs->end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    const double value = link_cost + best;
    return std::isfinite(value) ? std::min(value, kLargeCost) : kLargeCost;
  }

 private:
  const ScaledTask& task_;
};

// The best evaluated cranks, one per basin (kArchiveRadius), best first.
class Archive {
 public:
  using Crank = std::array<double, 4>;  // (B, A)

  explicit Archive(int capacity) : capacity_(capacity) {}

  void Offer(const double* x, double value) {
    if (!(value < kLargeCost)) return;
    const Crank crank = {x[0], x[1], x[2], x[3]};
    for (auto& [kept_value, kept] : entries_) {
      const double distance = std::max(std::hypot(kept[0] - crank[0], kept[1] - crank[1]),
                                       std::hypot(kept[2] - crank[2], kept[3] - crank[3]));
      if (distance < kArchiveRadius) {
        if (value < kept_value) {
          kept_value = value;
          kept = crank;
          Sort();
        }
        return;
      }
    }
    if (static_cast<int>(entries_.size()) < capacity_) {
      entries_.emplace_back(value, crank);
    } else if (value < entries_.back().first) {
      entries_.back() = {value, crank};
    } else {
      return;
    }
    Sort();
  }

  const std::vector<std::pair<double, Crank>>& entries() const { return entries_; }

 private:
  void Sort() { std::sort(entries_.begin(), entries_.end()); }

  int capacity_;
  std::vector<std::pair<double, Crank>> entries_;
};

// What NLopt's callback sees.
struct Run {
  const Objective* objective = nullptr;
  Archive* archive = nullptr;
  int evaluations = 0;
};

double EvaluateRun(unsigned /*dimension*/, const double* x, double* /*gradient*/, void* data) {
  Run& run = *static_cast<Run*>(data);
  const double value = (*run.objective)(x);
  ++run.evaluations;
  run.archive->Offer(x, value);
  return value;
}

nlopt::algorithm ToNlopt(GlobalAlgorithm algorithm) {
  // In the order of GlobalAlgorithm's enumerators.
  constexpr nlopt::algorithm kAlgorithms[] = {nlopt::GN_CRS2_LM, nlopt::G_MLSL_LDS, nlopt::GN_ISRES,
                                              nlopt::GN_DIRECT_L};
  return kAlgorithms[static_cast<int>(algorithm)];
}

// Whether two four-bars (task units) agree to kDistinct * length in every parameter.
bool SameFourBar(const PathFourBar& a, const PathFourBar& b, double length) {
  if (a.output.type != b.output.type) return false;
  const DyadBlocks x = ToBlocks(a.output), y = ToBlocks(b.output);
  const double distance =
      std::max({(a.input.fixed_pivot - b.input.fixed_pivot).norm(),
                (a.input.moving_pivot - b.input.moving_pivot).norm(),
                (a.coupler_point - b.coupler_point).norm(),
                std::hypot(x.point[0] - y.point[0], x.point[1] - y.point[1]),
                std::hypot(x.second[0] - y.second[0], x.second[1] - y.second[1]) *
                    (a.output.type == DyadType::kRR ? 1.0 : length),
                std::abs(x.scalar[0] - y.scalar[0])});
  return distance <= kDistinct * length;
}

}  // namespace

bool DrivableOutput(const PlanarDyad& output, const Eigen::Vector2d& crank_pivot,
                    const Eigen::Vector2d& crank_pin, const std::vector<double>& turns,
                    PlanarDyad* drivable) {
  if (output.type != DyadType::kRR) return false;
  // The output's moving pivot is its coupler side's length from the crank pin; at point j the
  // pin is d_j from the fixed pivot, so the radius must lie in [|d_j - c|, d_j + c].
  const double side = (output.moving_pivot - crank_pin).norm();
  double low = 0.0, high = std::numeric_limits<double>::infinity();
  for (const double turn : turns) {
    const Eigen::Vector2d pin = crank_pivot + Rotation2(turn) * (crank_pin - crank_pivot);
    const double distance = (pin - output.fixed_pivot).norm();
    low = std::max(low, std::abs(distance - side));
    high = std::min(high, distance + side);
  }
  if (!(low < high)) return false;
  const double margin = kDrivableMargin * (high - low);
  *drivable = output;
  drivable->radius = std::clamp(std::abs(output.radius), low + margin, high - margin);
  return true;
}

int SearchPathFourBars(const std::vector<Eigen::Vector2d>& points,
                       const std::vector<double>& weights, const std::vector<bool>& exact,
                       const std::vector<double>& input_angles, double length,
                       const PathSearchOptions& options, std::vector<PathFourBar>* four_bars,
                       PathSearchSummary* summary) {
  const auto start = Clock::now();
  const std::string where = "SearchPathFourBars: ";
  CheckRefinerInput("SearchPathFourBars", points.size(), length, weights, &exact);
  if (input_angles.size() != points.size() || points.size() < 2) {
    throw std::invalid_argument(where + "at least two points, one input angle each, are needed");
  }
  for (size_t j = 0; j < points.size(); ++j) {
    if (!points[j].allFinite() || !std::isfinite(input_angles[j])) {
      throw std::invalid_argument(where + "points and input angles must be finite");
    }
  }
  if (options.max_evaluations < 1 || !(options.time_limit > 0.0) || !(options.box_scale > 0.0) ||
      !std::isfinite(options.box_scale) || options.refine_count < 1 || options.runs < 1) {
    throw std::invalid_argument(where + "options need max_evaluations >= 1, time_limit > 0, " +
                                "finite box_scale > 0, refine_count >= 1 and runs >= 1");
  }
  four_bars->clear();
  PathSearchSummary report;
  report.algorithm = GlobalAlgorithmName(options.algorithm);

  // Centre on the points' centroid, scale by L; weights normalized to sum 1.
  const Similarity2 to_task = ScaledPointFrame(points, length);
  const Similarity2 to_scaled = to_task.Inverse();
  ScaledTask task;
  double weight_sum = 0.0;
  for (size_t j = 0; j < points.size(); ++j) {
    task.points.push_back(to_scaled.Apply(points[j]));
    task.turns.push_back(input_angles[j] - input_angles.front());
    const double weight = (weights.empty() ? 1.0 : weights[j]) *
                          (!exact.empty() && exact[j] ? kExactSearchWeight : 1.0);
    task.weights.push_back(weight);
    weight_sum += weight;
  }
  for (double& weight : task.weights) weight /= weight_sum;
  task.bounds = ScaleBounds(options.refiner.constraints, length, to_scaled);

  // Fewer than five points give no output dyad (planar_burmester.h): nothing to search.
  std::vector<std::pair<double, PathFourBar>> refined;
  if (points.size() >= 5) {
    const Objective objective(task);
    Archive archive(options.refine_count);
    Run run;
    run.objective = &objective;
    run.archive = &archive;
    // The crank's box: B within box_scale of the centroid and in the fixed pivots' box (that
    // box alone where the two do not meet), A within the longest link of B's box.
    std::vector<double> lower(4, -options.box_scale), upper(4, options.box_scale);
    if (task.bounds.fixed_box) {
      for (int c = 0; c < 2; ++c) {
        lower[c] = std::max(lower[c], task.bounds.fixed_min[c]);
        upper[c] = std::min(upper[c], task.bounds.fixed_max[c]);
        if (!(lower[c] <= upper[c])) {
          lower[c] = task.bounds.fixed_min[c];
          upper[c] = task.bounds.fixed_max[c];
        }
        const double reach = std::min(task.bounds.max_link, 2.0 * options.box_scale);
        lower[2 + c] = lower[c] - reach;
        upper[2 + c] = upper[c] + reach;
      }
    }
    // The runs share the budget: each its part of the evaluations and of the time left.
    const auto search_start = Clock::now();
    for (int r = 0; r < options.runs; ++r) {
      nlopt::srand(options.seed + static_cast<std::uint64_t>(r));
      nlopt::opt optimizer(ToNlopt(options.algorithm), 4);
      optimizer.set_lower_bounds(lower);
      optimizer.set_upper_bounds(upper);
      optimizer.set_min_objective(EvaluateRun, &run);
      optimizer.set_maxeval(std::max(1, options.max_evaluations / options.runs));
      const double spent = std::chrono::duration<double>(Clock::now() - search_start).count();
      optimizer.set_maxtime(
          std::max(kLeastRunTime, (options.time_limit - spent) / (options.runs - r)));
      if (options.algorithm == GlobalAlgorithm::kMlsl) {
        nlopt::opt descent(nlopt::LN_BOBYQA, 4);
        descent.set_xtol_rel(1e-8);
        descent.set_maxeval(1000);
        optimizer.set_local_optimizer(descent);
      }
      // A crank from the centroid (the box's centre) to half a unit away starts each run (B = A
      // is no crank).
      const double centre[2] = {0.5 * (lower[0] + upper[0]), 0.5 * (lower[1] + upper[1])};
      std::vector<double> x = {
          centre[0], centre[1],
          centre[0] + 0.5 * std::min({options.box_scale, 1.0, upper[2] - centre[0]}), centre[1]};
      double value = 0.0;
      try {
        optimizer.optimize(x, value);
      } catch (const std::exception&) {
        // roundoff_limited, forced_stop and failures: the archive holds what was found.
      }
    }
    report.evaluations = run.evaluations;

    // Each archived crank with its output dyad and coupler point R_0, refined.
    for (const auto& entry : archive.entries()) {
      const Archive::Crank& crank = entry.second;
      std::vector<std::pair<double, PlanarDyad>> outputs;
      objective.Evaluate(crank.data(), &outputs);
      const Eigen::Vector2d crank_pivot(crank[0], crank[1]), crank_pin(crank[2], crank[3]);
      // Every output dyad of the crank (the best alone may not assemble at every point).
      for (const auto& output : outputs) {
        PathFourBar four_bar;
        four_bar.input =
            TransformDyad(PlanarDyad::RR(crank_pivot, crank_pin, (crank_pin - crank_pivot).norm()),
                          to_task, to_task);
        four_bar.output = TransformDyad(output.second, to_task, to_task);
        four_bar.coupler_point = points.front();
        std::vector<double> angles = input_angles;
        RefinerSummary result = RefinePathFourBar(points, weights, exact, length, false, &angles,
                                                  &four_bar, options.refiner);
        PlanarDyad drivable;
        if (!std::isfinite(result.final_cost) &&
            DrivableOutput(output.second, crank_pivot, crank_pin, task.turns, &drivable)) {
          four_bar.output = TransformDyad(drivable, to_task, to_task);
          angles = input_angles;
          result = RefinePathFourBar(points, weights, exact, length, false, &angles, &four_bar,
                                     options.refiner);
        }
        if (std::isfinite(result.final_cost)) refined.emplace_back(result.final_cost, four_bar);
      }
    }
  }
  std::stable_sort(refined.begin(), refined.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [cost, candidate] : refined) {
    const PathFourBar& four_bar = candidate;
    const bool seen =
        std::any_of(four_bars->begin(), four_bars->end(),
                    [&](const PathFourBar& other) { return SameFourBar(four_bar, other, length); });
    if (seen) continue;
    if (four_bars->empty()) report.best_cost = cost;
    four_bars->push_back(four_bar);
  }
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (summary != nullptr) *summary = report;
  return static_cast<int>(four_bars->size());
}

}  // namespace linkfit
