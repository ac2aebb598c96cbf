#include "optimizers/global_search.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlopt.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include "optimizers/planar_dyad_refiner.h"
#include "optimizers/refiner_input.h"

namespace linkfit {
namespace {

using Clock = std::chrono::steady_clock;

// The objective's value for a point it cannot evaluate (non-finite coordinates or sums): large,
// finite, and worse than any real fit in the scaled problem (weights summing to 1, L = 1).
constexpr double kLargeCost = 1e30;
// Side of the archive's grid cells, in the scaled problem (L = 1; radians for a line angle).
constexpr double kCellWidth = 0.25;
// Each local descent: stop when a step is below this (L or radians), evaluation cap.
constexpr double kLocalTolerance = 1e-13;
constexpr double kLocalFunctionTolerance = 1e-6;  // relative decrease of a step, to stop
constexpr int kLocalEvaluations = 400;
// Levenberg-Marquardt damping of the local descents: start, floor, give-up bound; the smallest
// curvature a damped direction gets.
constexpr double kInitialDamping = 1e-3;
constexpr double kMinDamping = 1e-12;
constexpr double kMaxDamping = 1e12;
constexpr double kMinCurvature = 1e-12;
// MLSL's local BOBYQA: relative step to stop and evaluation cap of one descent.
constexpr double kMlslLocalTolerance = 1e-8;
constexpr int kMlslLocalEvaluations = 1000;
// Two dyads are the same when their pivots, radii and lines agree to this times their scale
// (the larger of L and the pivots' and line points' distances from the frame origins).
constexpr double kDistinct = 1e-3;
// Share of the evaluations and of the time limit given to the global run; the local descents
// have the rest.
constexpr double kGlobalShare = 0.5;
// A local descent that comes this near (in the scaled search space) an optimum already found is
// stopped.
constexpr double kMergeRadius = 0.1;
// Poses marked exact weigh this much more in the search; the polish then meets them exactly.
constexpr double kExactSearchWeight = 100.0;

constexpr int kMaxDimension = 4;
using Point = std::array<double, kMaxDimension>;

// The poses in the centred and scaled frames: Sigma' = (Sigma - centroid) / L, E' = E / L.
struct ScaledTask {
  std::vector<Eigen::Matrix2d> rotations;
  std::vector<Eigen::Vector2d> origins;
  std::vector<double> weights;  // normalized to sum 1
  // The crank's bounds (an RR's radius; lib/design_constraints.h), scaled.
  double min_radius = 0.0;
  double max_radius = std::numeric_limits<double>::infinity();
  // The pivots' boxes (fixed in Sigma', moving in E'), where the task has them.
  std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> fixed_box, moving_box;
};

int Dimension(DyadType type) { return type == DyadType::kRR ? 4 : 3; }

// The search objective of one dyad type in the scaled frames, with its eliminated parameter
// (radius or line offset) in closed form. Coordinates: RR (F, M); PR (M, phi); RP (F, phi), phi
// the line's direction angle (u = (cos phi, sin phi), normal n = (-sin phi, cos phi)).
class Objective {
 public:
  Objective(const ScaledTask& task, DyadType type)
      : task_(task), type_(type), values_(task.origins.size()) {}

  DyadType type() const { return type_; }
  int dimension() const { return Dimension(type_); }

  // Weighted sum of squared residuals about their weighted mean:
  //   RR: rho_j = |R_j M + d_j - F|, r = sum w rho (clamped to the crank's bounds: the cost is
  //       a convex quadratic in r, so the clamped mean is the bounded optimum),
  //                                                            f = sum w (rho_j - r)^2;
  //   PR: s_j = n . (R_j M + d_j),   h = sum w s,              f = sum w (s_j - h)^2;
  //   RP: s_j = n . R_j^T (F - d_j), h = sum w s (line in E),  f = sum w (s_j - h)^2.
  // Two passes (not sum w s^2 - h^2), so that a near-zero optimum keeps its relative accuracy.
  double operator()(const double* x) const {
    for (int i = 0; i < dimension(); ++i) {
      if (!std::isfinite(x[i])) return kLargeCost;
    }
    const size_t count = task_.origins.size();
    double mean = 0.0;
    if (type_ == DyadType::kRR) {
      const Eigen::Vector2d fixed_pivot(x[0], x[1]), moving_pivot(x[2], x[3]);
      for (size_t j = 0; j < count; ++j) {
        values_[j] = (task_.rotations[j] * moving_pivot + task_.origins[j] - fixed_pivot).norm();
        mean += task_.weights[j] * values_[j];
      }
    } else {
      const Eigen::Vector2d point(x[0], x[1]);
      const Eigen::Vector2d normal(-std::sin(x[2]), std::cos(x[2]));
      for (size_t j = 0; j < count; ++j) {
        values_[j] = type_ == DyadType::kPR
                         ? normal.dot(task_.rotations[j] * point + task_.origins[j])
                         : normal.dot(task_.rotations[j].transpose() * (point - task_.origins[j]));
        mean += task_.weights[j] * values_[j];
      }
    }
    if (type_ == DyadType::kRR) mean = ClampRadius(mean);
    double sum = 0.0;
    for (size_t j = 0; j < count; ++j) {
      const double deviation = values_[j] - mean;
      sum += task_.weights[j] * deviation * deviation;
    }
    return std::isfinite(sum) ? std::min(sum, kLargeCost) : kLargeCost;
  }

  // The residuals e_j = sqrt(w_j) (v_j - sum_k w_k v_k) of the same sum (f = |e|^2), v_j the
  // rho_j or s_j above, and their Jacobian, for Gauss-Newton descents. The eliminated parameter
  // is optimal for every x, so the Jacobian of the reduced problem is that of the v_j with
  // their weighted mean removed (variable projection). Returns false if not finite.
  bool Residuals(const Point& x, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian) const {
    const int count = static_cast<int>(task_.origins.size());
    const int n = dimension();
    Eigen::VectorXd values(count);
    Eigen::MatrixXd derivatives(count, n);
    if (type_ == DyadType::kRR) {
      const Eigen::Vector2d fixed_pivot(x[0], x[1]), moving_pivot(x[2], x[3]);
      for (int j = 0; j < count; ++j) {
        const Eigen::Vector2d offset =
            task_.rotations[j] * moving_pivot + task_.origins[j] - fixed_pivot;
        values[j] = offset.norm();
        // d rho / dF = -p / rho, d rho / dM = R^T p / rho (0 where rho = 0: a subgradient).
        const Eigen::Vector2d unit =
            values[j] > 0.0 ? Eigen::Vector2d(offset / values[j]) : Eigen::Vector2d::Zero();
        derivatives.block<1, 2>(j, 0) = -unit.transpose();
        derivatives.block<1, 2>(j, 2) = (task_.rotations[j].transpose() * unit).transpose();
      }
    } else {
      const Eigen::Vector2d point(x[0], x[1]);
      const Eigen::Vector2d direction(std::cos(x[2]), std::sin(x[2]));
      const Eigen::Vector2d normal(-direction.y(), direction.x());  // dn / dphi = -u
      for (int j = 0; j < count; ++j) {
        if (type_ == DyadType::kPR) {
          const Eigen::Vector2d position = task_.rotations[j] * point + task_.origins[j];
          values[j] = normal.dot(position);
          derivatives.block<1, 2>(j, 0) = (task_.rotations[j].transpose() * normal).transpose();
          derivatives(j, 2) = -direction.dot(position);
        } else {
          const Eigen::Vector2d seen = task_.rotations[j].transpose() * (point - task_.origins[j]);
          values[j] = normal.dot(seen);
          derivatives.block<1, 2>(j, 0) = (task_.rotations[j] * normal).transpose();
          derivatives(j, 2) = -direction.dot(seen);
        }
      }
    }
    const Eigen::Map<const Eigen::VectorXd> weights(task_.weights.data(), count);
    const Eigen::VectorXd roots = weights.cwiseSqrt();
    double mean = weights.dot(values);
    Eigen::RowVectorXd mean_derivative = weights.transpose() * derivatives;
    if (type_ == DyadType::kRR && ClampRadius(mean) != mean) {
      mean = ClampRadius(mean);  // a radius on its bound: a constant
      mean_derivative.setZero();
    }
    *residuals = roots.cwiseProduct((values.array() - mean).matrix());
    *jacobian = roots.asDiagonal() * (derivatives.rowwise() - mean_derivative);
    return residuals->allFinite() && jacobian->allFinite();
  }

  // The dyad at x, in the scaled frames.
  PlanarDyad Dyad(const Point& x) const {
    const Eigen::Vector2d point(x[0], x[1]);
    const size_t count = task_.origins.size();
    double mean = 0.0;
    if (type_ == DyadType::kRR) {
      const Eigen::Vector2d moving_pivot(x[2], x[3]);
      for (size_t j = 0; j < count; ++j) {
        mean += task_.weights[j] *
                (task_.rotations[j] * moving_pivot + task_.origins[j] - point).norm();
      }
      return PlanarDyad::RR(point, moving_pivot, ClampRadius(mean));
    }
    const Eigen::Vector2d direction(std::cos(x[2]), std::sin(x[2]));
    const Eigen::Vector2d normal(-direction.y(), direction.x());
    for (size_t j = 0; j < count; ++j) {
      mean += task_.weights[j] *
              (type_ == DyadType::kPR
                   ? normal.dot(task_.rotations[j] * point + task_.origins[j])
                   : normal.dot(task_.rotations[j].transpose() * (point - task_.origins[j])));
    }
    return type_ == DyadType::kPR ? PlanarDyad::PR(point, mean * normal, direction)
                                  : PlanarDyad::RP(point, mean * normal, direction);
  }

 private:
  double ClampRadius(double radius) const {
    return std::clamp(radius, task_.min_radius, std::max(task_.min_radius, task_.max_radius));
  }

  const ScaledTask& task_;
  DyadType type_;
  mutable std::vector<double> values_;  // rho_j or s_j of the last evaluation
};

// The best point evaluated in each cell of a grid over the search box: the archive from which
// the distinct local optima are picked. A cell whose best is better than the best of each of its
// 3^d - 1 neighbours is a local minimum of the sampled objective.
class Archive {
 public:
  // The box [lower, upper] (a line angle last when `periodic_last`), at most `max_cells` cells a
  // side.
  Archive(const std::vector<double>& lower, const std::vector<double>& upper, int max_cells,
          bool periodic_last)
      : dimension_(static_cast<int>(lower.size())),
        lower_(lower),
        upper_(upper),
        periodic_last_(periodic_last) {
    const int dimension = dimension_;
    for (int i = 0; i < dimension; ++i) {
      cells_[i] =
          std::clamp(static_cast<int>(std::ceil((upper[i] - lower[i]) / kCellWidth)), 1, max_cells);
    }
    if (periodic_last) {
      cells_[dimension - 1] = std::max(1, static_cast<int>(std::lround(M_PI / kCellWidth)));
    }
  }

  void Add(const double* x, double value) {
    std::array<int, kMaxDimension> index{};
    for (int i = 0; i < dimension_; ++i) index[i] = CellIndex(i, x[i]);
    Entry& entry = entries_.try_emplace(Key(index), Entry{}).first->second;
    if (value < entry.value) {
      entry.value = value;
      entry.index = index;
      std::copy(x, x + dimension_, entry.point.begin());
    }
  }

  // The cells' local minima, best first.
  std::vector<std::pair<double, Point>> LocalMinima() const {
    std::vector<std::pair<double, Point>> minima;
    int neighbours = 1;
    for (int i = 0; i < dimension_; ++i) neighbours *= 3;
    for (const auto& [key, entry] : entries_) {
      bool minimum = true;
      for (int code = 0; code < neighbours && minimum; ++code) {
        std::array<int, kMaxDimension> index = entry.index;
        bool inside = true;
        int rest = code;
        for (int i = 0; i < dimension_; ++i, rest /= 3) {
          index[i] += rest % 3 - 1;
          if (periodic_last_ && i == dimension_ - 1) {
            index[i] = (index[i] + cells_[i]) % cells_[i];
          } else if (index[i] < 0 || index[i] >= cells_[i]) {
            inside = false;
          }
        }
        const std::uint64_t other_key = Key(index);
        if (!inside || other_key == key) continue;
        const auto other = entries_.find(other_key);
        if (other == entries_.end()) continue;
        // Ties go to the smaller key, so that a plateau still yields one minimum.
        if (other->second.value < entry.value ||
            (other->second.value == entry.value && other_key < key)) {
          minimum = false;
        }
      }
      if (minimum) minima.emplace_back(entry.value, entry.point);
    }
    std::sort(minima.begin(), minima.end());  // by value, ties by point: deterministic
    return minima;
  }

 private:
  struct Entry {
    double value = std::numeric_limits<double>::infinity();
    std::array<int, kMaxDimension> index{};
    Point point{};
  };

  int CellIndex(int i, double value) const {
    if (periodic_last_ && i == dimension_ - 1) {
      const double period = std::floor(value / M_PI);
      const int index = static_cast<int>(std::floor((value - period * M_PI) / M_PI * cells_[i]));
      return std::clamp(index, 0, cells_[i] - 1);
    }
    const double width = upper_[i] - lower_[i];
    const int index =
        width > 0.0 ? static_cast<int>(std::floor((value - lower_[i]) / width * cells_[i])) : 0;
    return std::clamp(index, 0, cells_[i] - 1);
  }
  std::uint64_t Key(const std::array<int, kMaxDimension>& index) const {
    std::uint64_t key = 0;
    for (int i = 0; i < dimension_; ++i) {
      key = key * static_cast<std::uint64_t>(cells_[i]) + static_cast<std::uint64_t>(index[i]);
    }
    return key;
  }

  int dimension_;
  std::vector<double> lower_, upper_;
  bool periodic_last_;
  std::array<int, kMaxDimension> cells_{};
  std::unordered_map<std::uint64_t, Entry> entries_;
};

// Distance of two points of the search space; a line angle (last coordinate when `angular`)
// counts modulo pi.
double PointDistance(const Point& a, const Point& b, int dimension, bool angular) {
  double sum = 0.0;
  for (int i = 0; i < dimension; ++i) {
    double difference = std::abs(a[i] - b[i]);
    if (angular && i == dimension - 1) {
      difference = std::fmod(difference, M_PI);
      difference = std::min(difference, M_PI - difference);
    }
    sum += difference * difference;
  }
  return std::sqrt(sum);
}

// What one run sees: the objective, the archive to fill (the global run), the best point of the
// run (kept even when NLopt throws), the evaluation count, and whether a local descent was
// stopped near an optimum already found.
struct Run {
  const Objective* objective = nullptr;
  Archive* archive = nullptr;
  double best_value = std::numeric_limits<double>::infinity();
  Point best_point{};
  int evaluations = 0;
  bool merged = false;
};

// NLopt's objective callback (derivative-free algorithms: no gradient).
double EvaluateRun(unsigned dimension, const double* x, double* /*gradient*/, void* data) {
  Run& run = *static_cast<Run*>(data);
  const double value = (*run.objective)(x);
  ++run.evaluations;
  if (run.archive != nullptr) run.archive->Add(x, value);
  if (value < run.best_value) {
    run.best_value = value;
    std::copy(x, x + dimension, run.best_point.begin());
  }
  return value;
}

// A damped Gauss-Newton (Levenberg-Marquardt) descent of the reduced least-squares problem from
// `run->best_point` (value `run->best_value`), within the box (the line angle is free), until
// the step is below kLocalTolerance, `max_evaluations` (a residual-and-Jacobian evaluation
// counts as one) or `deadline`; stopped early (run->merged) when it comes within kMergeRadius of
// a known optimum. Gauss-Newton follows the narrow curved valleys of this objective (the
// circling-point curve of the motion runs through every RR optimum) that a derivative-free
// descent creeps along.
void Descend(const Objective& objective, const std::vector<double>& lower,
             const std::vector<double>& upper, int max_evaluations, Clock::time_point deadline,
             const std::vector<Point>& known_optima, Run* run) {
  const int n = objective.dimension();
  const bool angular = objective.type() != DyadType::kRR;
  const int spatial = angular ? n - 1 : n;
  Point x = run->best_point;
  double cost = run->best_value;
  double damping = kInitialDamping;
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
  while (run->evaluations < max_evaluations && Clock::now() < deadline) {
    ++run->evaluations;
    if (!objective.Residuals(x, &residuals, &jacobian)) return;
    const Eigen::VectorXd gradient = jacobian.transpose() * residuals;
    const Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
    bool improved = false;
    while (!improved) {
      if (run->evaluations >= max_evaluations || damping > kMaxDamping) return;
      Eigen::MatrixXd damped = normal;
      damped.diagonal() += damping * normal.diagonal().cwiseMax(kMinCurvature);
      const Eigen::VectorXd step = damped.ldlt().solve(-gradient);
      if (!step.allFinite()) return;
      Point candidate = x;
      double step_norm = 0.0;
      for (int i = 0; i < n; ++i) {
        candidate[i] = x[i] + step[i];
        if (i < spatial) candidate[i] = std::clamp(candidate[i], lower[i], upper[i]);
        step_norm = std::max(step_norm, std::abs(candidate[i] - x[i]));
      }
      if (step_norm <= kLocalTolerance) return;  // converged (or pinned to the box)
      ++run->evaluations;
      const double value = objective(candidate.data());
      if (value < cost) {
        if (cost - value <= kLocalFunctionTolerance * cost) {  // creeping: stop here
          run->best_point = candidate;
          run->best_value = value;
          return;
        }
        x = candidate;
        cost = value;
        damping = std::max(damping / 3.0, kMinDamping);
        improved = true;
      } else {
        damping *= 4.0;
      }
    }
    run->best_point = x;
    run->best_value = cost;
    for (const Point& known : known_optima) {
      if (PointDistance(x, known, n, angular) < kMergeRadius) {
        run->merged = true;
        return;
      }
    }
  }
}

// The dyad's scale in the scaled frames: the larger of L (1) and its pivots' and line points'
// distances from the frame origins.
double DyadScale(const PlanarDyad& dyad) {
  double scale = 1.0;
  if (dyad.type != DyadType::kPR) scale = std::max(scale, dyad.fixed_pivot.norm());
  if (dyad.type != DyadType::kRP) scale = std::max(scale, dyad.moving_pivot.norm());
  if (dyad.type == DyadType::kRR) scale = std::max(scale, std::abs(dyad.radius));
  if (dyad.type != DyadType::kRR) scale = std::max(scale, dyad.line_point.norm());
  return scale;
}

// Distance of two lines (point, unit direction) as lines, over a region of size `scale`: the
// direction difference (up to sign) times the scale, and each line point's distance from the
// other line.
double LineDistance(const PlanarDyad& a, const PlanarDyad& b, double scale) {
  const double sine = std::abs(a.line_direction.x() * b.line_direction.y() -
                               a.line_direction.y() * b.line_direction.x());
  const Eigen::Vector2d normal_a(-a.line_direction.y(), a.line_direction.x());
  const Eigen::Vector2d normal_b(-b.line_direction.y(), b.line_direction.x());
  return std::max({sine * scale, std::abs(normal_a.dot(b.line_point - a.line_point)),
                   std::abs(normal_b.dot(a.line_point - b.line_point))});
}

// Whether two dyads (in the scaled frames) are the same to kDistinct times their scale.
bool SameDyad(const PlanarDyad& a, const PlanarDyad& b) {
  if (a.type != b.type) return false;
  const double scale = std::max(DyadScale(a), DyadScale(b));
  double distance = 0.0;
  if (a.type != DyadType::kPR) distance = (a.fixed_pivot - b.fixed_pivot).norm();
  if (a.type != DyadType::kRP) {
    distance = std::max(distance, (a.moving_pivot - b.moving_pivot).norm());
  }
  if (a.type == DyadType::kRR) {
    distance = std::max(distance, std::abs(a.radius - b.radius));
  } else {
    distance = std::max(distance, LineDistance(a, b, scale));
  }
  return distance <= kDistinct * scale;
}

bool IsFinite(const PlanarDyad& dyad) {
  return dyad.fixed_pivot.allFinite() && dyad.moving_pivot.allFinite() &&
         std::isfinite(dyad.radius) && dyad.line_point.allFinite() &&
         dyad.line_direction.allFinite();
}

// The best distinct local optima of one dyad type, in the scaled frames, best first: a global
// NLopt run over the box (kGlobalShare of the evaluations and of the time) fills the archive,
// Gauss-Newton descents from the archive's local minima spend the rest, and up to
// options.polish_count distinct optima are kept.
// The search box of a pivot: [-half_width, half_width]^2 about the frame's origin, within the
// task's box for that pivot (scaled) where they overlap, else the task's box.
void PivotBox(double half_width,
              const std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& bound,
              double* lower, double* upper) {
  for (int c = 0; c < 2; ++c) {
    lower[c] = -half_width;
    upper[c] = half_width;
    if (!bound) continue;
    const double low = std::max(lower[c], bound->first[c]);
    const double high = std::min(upper[c], bound->second[c]);
    lower[c] = low <= high ? low : bound->first[c];
    upper[c] = low <= high ? high : bound->second[c];
  }
}

std::vector<PlanarDyad> SearchType(const ScaledTask& task, DyadType type,
                                   const GlobalSearchOptions& options, int* evaluations) {
  const auto start = Clock::now();
  const auto deadline =
      start + std::chrono::duration_cast<Clock::duration>(
                  std::chrono::duration<double>(std::min(options.time_limit, 1e9)));
  const Objective objective(task, type);
  const int dimension = objective.dimension();
  const double half_width = options.box_scale;
  const bool angular = type != DyadType::kRR;
  std::vector<double> lower(dimension, -half_width), upper(dimension, half_width);
  // The pivots' boxes: RR (F, M), PR (M), RP (F).
  if (type != DyadType::kPR) PivotBox(half_width, task.fixed_box, &lower[0], &upper[0]);
  if (type == DyadType::kRR) PivotBox(half_width, task.moving_box, &lower[2], &upper[2]);
  if (type == DyadType::kPR) PivotBox(half_width, task.moving_box, &lower[0], &upper[0]);
  if (angular) {
    lower[dimension - 1] = 0.0;
    upper[dimension - 1] = M_PI;
  }
  std::vector<double> x(dimension, 0.0);
  for (int i = 0; i < dimension; ++i) x[i] = std::clamp(0.0, lower[i], upper[i]);
  if (angular) x[dimension - 1] = 0.5 * M_PI;

  const int max_cells = std::max(1, static_cast<int>(std::ceil(2.0 * half_width / kCellWidth)));
  Archive archive(lower, upper, max_cells, angular);
  Run global;
  global.objective = &objective;
  global.archive = &archive;
  nlopt::srand(options.seed);
  nlopt::opt optimizer(NloptAlgorithm(options.algorithm), static_cast<unsigned>(dimension));
  optimizer.set_lower_bounds(lower);
  optimizer.set_upper_bounds(upper);
  optimizer.set_min_objective(EvaluateRun, &global);
  optimizer.set_maxeval(std::max(1, static_cast<int>(kGlobalShare * options.max_evaluations)));
  optimizer.set_maxtime(kGlobalShare * options.time_limit);
  if (options.algorithm == GlobalAlgorithm::kMlsl) {
    nlopt::opt local(nlopt::LN_BOBYQA, static_cast<unsigned>(dimension));
    local.set_xtol_rel(kMlslLocalTolerance);
    local.set_maxeval(kMlslLocalEvaluations);
    optimizer.set_local_optimizer(local);
  }
  RunNlopt(optimizer, x);
  *evaluations += global.evaluations;
  if (global.evaluations == 0) return {};

  // Local descents from the archive's local minima, best first, while the budget and the time
  // last (the best is always kept, descended or not); a descent that comes near an optimum
  // already found is dropped (it would only find it again).
  const std::vector<std::pair<double, Point>> minima = archive.LocalMinima();
  std::vector<Point> known_optima;
  std::vector<std::pair<double, PlanarDyad>> optima;
  int budget = options.max_evaluations - global.evaluations;
  for (const auto& [value, point] : minima) {
    const bool time_left = Clock::now() < deadline;
    if (!optima.empty() && (budget <= 0 || !time_left)) break;
    Run local_run;
    local_run.objective = &objective;
    local_run.best_value = value;
    local_run.best_point = point;
    if (budget > 0 && time_left) {
      Descend(objective, lower, upper, std::min(budget, kLocalEvaluations), deadline, known_optima,
              &local_run);
      *evaluations += local_run.evaluations;
      budget -= local_run.evaluations;
    }
    if (local_run.merged) continue;
    known_optima.push_back(local_run.best_point);
    optima.emplace_back(local_run.best_value, objective.Dyad(local_run.best_point));
  }
  std::stable_sort(optima.begin(), optima.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<PlanarDyad> distinct;
  for (const auto& optimum : optima) {
    const PlanarDyad& dyad = optimum.second;  // not a binding: the lambda below uses it
    if (static_cast<int>(distinct.size()) >= options.polish_count) break;
    if (!IsFinite(dyad)) continue;
    const bool seen = std::any_of(distinct.begin(), distinct.end(),
                                  [&](const PlanarDyad& other) { return SameDyad(dyad, other); });
    if (!seen) distinct.push_back(dyad);
  }
  return distinct;
}

void Validate(const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
              const std::vector<bool>& exact, double length, const GlobalSearchOptions& options) {
  const std::string where = "SearchPlanarDyads: ";
  CheckRefinerInput("SearchPlanarDyads", poses.size(), length, weights, &exact);
  for (const PlanarPose& pose : poses) {
    if (!pose.origin_in_fixed.allFinite() || !std::isfinite(pose.theta)) {
      throw std::invalid_argument(where + "poses must be finite");
    }
  }
  if (options.max_evaluations < 1 || !(options.time_limit > 0.0) || !(options.box_scale > 0.0) ||
      !std::isfinite(options.box_scale) || options.polish_count < 1) {
    throw std::invalid_argument(where + "options need max_evaluations >= 1, time_limit > 0, " +
                                "finite box_scale > 0 and polish_count >= 1");
  }
}

}  // namespace

void RunNlopt(nlopt::opt& optimizer, std::vector<double> x) {
  double value = 0.0;
  try {
    optimizer.optimize(x, value);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
}

nlopt::algorithm NloptAlgorithm(GlobalAlgorithm algorithm) {
  switch (algorithm) {
    case GlobalAlgorithm::kCrs2:
      return nlopt::GN_CRS2_LM;
    case GlobalAlgorithm::kMlsl:
      return nlopt::G_MLSL_LDS;
    case GlobalAlgorithm::kIsres:
      return nlopt::GN_ISRES;
    case GlobalAlgorithm::kDirect:
      return nlopt::GN_DIRECT_L;
  }
  return nlopt::GN_CRS2_LM;
}

const char* GlobalAlgorithmName(GlobalAlgorithm algorithm) {
  switch (algorithm) {
    case GlobalAlgorithm::kCrs2:
      return "crs2";
    case GlobalAlgorithm::kMlsl:
      return "mlsl";
    case GlobalAlgorithm::kIsres:
      return "isres";
    case GlobalAlgorithm::kDirect:
      return "direct";
  }
  return "?";
}

int SearchPlanarDyads(const std::vector<PlanarPose>& poses, const std::vector<double>& weights,
                      const std::vector<bool>& exact, double length,
                      const GlobalSearchOptions& options, std::vector<PlanarDyad>* dyads,
                      GlobalSearchSummary* summary) {
  const auto start = Clock::now();
  Validate(poses, weights, exact, length, options);
  dyads->clear();
  GlobalSearchSummary report;
  report.algorithm = GlobalAlgorithmName(options.algorithm);

  // Centre on the pose-origin centroid, scale by L; weights normalized to sum 1.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const PlanarPose& pose : poses) centroid += pose.origin_in_fixed;
  if (!poses.empty()) centroid /= static_cast<double>(poses.size());
  ScaledTask task;
  double weight_sum = 0.0;
  for (size_t j = 0; j < poses.size(); ++j) {
    task.rotations.push_back(Rotation2(poses[j].theta));
    task.origins.push_back((poses[j].origin_in_fixed - centroid) / length);
    double weight = weights.empty() ? 1.0 : weights[j];
    if (!exact.empty() && exact[j]) weight *= kExactSearchWeight;
    task.weights.push_back(weight);
    weight_sum += weight;
  }
  for (double& weight : task.weights) weight /= weight_sum;
  Similarity2 to_fixed, to_moving;  // scaled frames -> the task's frames
  to_fixed.scale = to_moving.scale = length;
  to_fixed.translation = centroid;
  const Similarity2 from_fixed = to_fixed.Inverse(), from_moving = to_moving.Inverse();
  const DesignConstraints& constraints = options.refiner.constraints;
  task.max_radius = MaxLinkLength(constraints, length) / length;
  task.min_radius = constraints.min_link_length.value_or(0.0) / length;
  if (constraints.fixed_pivots_box) {
    task.fixed_box.emplace(from_fixed.Apply(constraints.fixed_pivots_box->min),
                           from_fixed.Apply(constraints.fixed_pivots_box->max));
  }
  if (constraints.moving_pivots_box) {
    task.moving_box.emplace(from_moving.Apply(constraints.moving_pivots_box->min),
                            from_moving.Apply(constraints.moving_pivots_box->max));
  }

  // Search each type, polish its distinct optima, and keep the distinct polished dyads.
  struct Polished {
    double cost;
    PlanarDyad dyad;         // in the task's frames
    PlanarDyad scaled_dyad;  // in the scaled frames, for comparisons
  };
  std::vector<Polished> polished;
  if (!poses.empty()) {
    for (DyadType type : options.types) {
      for (const PlanarDyad& scaled : SearchType(task, type, options, &report.evaluations)) {
        PlanarDyad dyad = TransformDyad(scaled, to_fixed, to_moving);
        const RefinerSummary refined =
            RefinePlanarDyad(poses, weights, exact, length, &dyad, options.refiner);
        if (!IsFinite(dyad) || !std::isfinite(refined.final_cost)) continue;
        polished.push_back(
            {refined.final_cost, dyad, TransformDyad(dyad, from_fixed, from_moving)});
      }
    }
  }
  std::stable_sort(polished.begin(), polished.end(),
                   [](const Polished& a, const Polished& b) { return a.cost < b.cost; });
  std::vector<const Polished*> kept;
  for (const Polished& candidate : polished) {
    const bool seen = std::any_of(kept.begin(), kept.end(), [&](const Polished* other) {
      return SameDyad(candidate.scaled_dyad, other->scaled_dyad);
    });
    if (seen) continue;
    kept.push_back(&candidate);
    dyads->push_back(candidate.dyad);
  }
  if (!kept.empty()) report.best_cost = kept.front()->cost;
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (summary != nullptr) *summary = report;
  return static_cast<int>(dyads->size());
}

}  // namespace linkfit
