#include "optimizers/spherical_search.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "fitting/spherical_motion.h"
#include "optimizers/refiner_input.h"

namespace linkfit {
namespace {

using Clock = std::chrono::steady_clock;

// The objective's value for a point it cannot evaluate: large, finite, and worse than any real
// fit (weights summing to 1, residuals in radians).
constexpr double kLargeCost = 1e30;
// Side of the archive's cells on the unit sphere, radians (rows of equal height in z, columns of
// equal width in phi: equal areas).
constexpr double kCellWidth = 0.15;
// Each local descent: stop when a tangent step is below this (radians), or when a step lowers
// the cost by less than this share of it; evaluation cap.
constexpr double kLocalTolerance = 1e-12;
constexpr double kLocalFunctionTolerance = 1e-6;
constexpr int kLocalEvaluations = 200;
// Levenberg-Marquardt damping of the local descents: start, floor, give-up bound; the smallest
// curvature a damped direction gets.
constexpr double kInitialDamping = 1e-3;
constexpr double kMinDamping = 1e-12;
constexpr double kMaxDamping = 1e12;
constexpr double kMinCurvature = 1e-12;
// MLSL's local BOBYQA: relative step to stop and evaluation cap of one descent.
constexpr double kMlslLocalTolerance = 1e-8;
constexpr int kMlslLocalEvaluations = 500;
// Two dyads are the same when their axes (either sign) and angles agree to this (radians).
constexpr double kDistinct = 1e-3;
// Share of the evaluations and of the time left after the cells' centres that the NLopt run
// gets; the local descents have the rest.
constexpr double kGlobalShare = 0.5;
// A local descent whose moving axis comes this near (radians) an optimum already found is
// stopped.
constexpr double kMergeRadius = 0.05;
// Orientations marked exact weigh this much more in the search; the polish then meets them.
constexpr double kExactSearchWeight = 100.0;

// The moving axis at search coordinates (z, phi): the equal-area map of the upper hemisphere.
Eigen::Vector3d AxisAt(double z, double phi) {
  const double height = std::clamp(z, -1.0, 1.0);
  const double radius = std::sqrt(std::max(0.0, 1.0 - height * height));
  return {radius * std::cos(phi), radius * std::sin(phi), height};
}

// Two unit vectors spanning the tangent plane of the unit sphere at `axis`.
Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d other =
      std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = (other - other.dot(axis) * axis).normalized();
  basis.col(1) = axis.cross(basis.col(0));
  return basis;
}

// How far apart two axes are as lines through the centre (chord, either sign).
double AxisDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::min((a - b).norm(), (a + b).norm());
}

// The search objective of the moving axis v, with the fixed axis and the cone angle in closed
// form (file comment).
class Objective {
 public:
  // `weights` normalized to sum 1.
  Objective(const std::vector<Eigen::Matrix3d>& rotations, const std::vector<double>& weights)
      : rotations_(rotations),
        weights_(weights),
        positions_(rotations.size()),
        angles_(rotations.size()) {}

  // f(v) = sum_j w_j (theta_j - alpha)^2 with u the plane fit of the x_j = R_j v and alpha the
  // weighted mean of theta_j = angle(u, x_j); u and alpha written when asked. Two passes (not
  // sum w theta^2 - alpha^2), so that a near-zero optimum keeps its relative accuracy.
  double operator()(const Eigen::Vector3d& moving_axis, Eigen::Vector3d* fixed_axis = nullptr,
                    double* angle = nullptr) const {
    if (!moving_axis.allFinite()) return kLargeCost;
    const size_t count = rotations_.size();
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (size_t j = 0; j < count; ++j) {
      positions_[j] = rotations_[j] * moving_axis;
      centroid += weights_[j] * positions_[j];
    }
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t j = 0; j < count; ++j) {
      const Eigen::Vector3d offset = positions_[j] - centroid;
      scatter.noalias() += weights_[j] * offset * offset.transpose();
    }
    if (!scatter.allFinite()) return kLargeCost;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    Eigen::Vector3d normal = solver.eigenvectors().col(0);
    if (normal.dot(centroid) < 0.0) normal = -normal;
    double mean = 0.0;
    for (size_t j = 0; j < count; ++j) {
      angles_[j] = DirectionAngle(normal, positions_[j]);
      mean += weights_[j] * angles_[j];
    }
    double sum = 0.0;
    for (size_t j = 0; j < count; ++j) {
      const double deviation = angles_[j] - mean;
      sum += weights_[j] * deviation * deviation;
    }
    if (fixed_axis != nullptr) *fixed_axis = normal;
    if (angle != nullptr) *angle = mean;
    return std::isfinite(sum) ? std::min(sum, kLargeCost) : kLargeCost;
  }

  // The residuals e_j = sqrt(w_j) (theta_j - alpha) of f at v (f = |e|^2) and their Jacobian in
  // the tangent coordinates t of v' = normalize(v + basis t). u and alpha are eliminated
  // (variable projection, Kaufman's Jacobian): the columns of v,
  //   d theta_j / dt = -u^T R_j basis / sin(theta_j),
  // projected off the span of those of u (tangent coordinates s of u, d theta_j / ds =
  // -x_j^T tangent(u) / sin(theta_j)) and of alpha (-1), all rows times sqrt(w_j); a row with
  // sin(theta_j) = 0 gets 0 (a subgradient). Returns false if not finite.
  bool Residuals(const Eigen::Vector3d& moving_axis, const Eigen::Matrix<double, 3, 2>& basis,
                 Eigen::VectorXd* residuals, Eigen::MatrixX2d* jacobian) const {
    Eigen::Vector3d normal;
    double mean = 0.0;
    if ((*this)(moving_axis, &normal, &mean) >= kLargeCost) return false;
    const int count = static_cast<int>(rotations_.size());
    const Eigen::Matrix<double, 3, 2> normal_basis = TangentBasis(normal);
    residuals->resize(count);
    jacobian->resize(count, 2);
    Eigen::MatrixX3d eliminated(count, 3);  // the columns of u (two) and alpha
    for (int j = 0; j < count; ++j) {
      const double root = std::sqrt(weights_[j]);
      const double sine = normal.cross(positions_[j]).norm();
      const double factor = sine > 0.0 ? -root / sine : 0.0;
      (*residuals)[j] = root * (angles_[j] - mean);
      jacobian->row(j) = factor * (normal.transpose() * rotations_[j] * basis);
      eliminated.block<1, 2>(j, 0) = factor * (positions_[j].transpose() * normal_basis);
      eliminated(j, 2) = -root;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixX3d> qr(eliminated);
    *jacobian -= eliminated * qr.solve(*jacobian);
    return residuals->allFinite() && jacobian->allFinite();
  }

  // The canonical dyad of moving axis v with its closed-form fixed axis and angle.
  SphericalDyad Dyad(const Eigen::Vector3d& moving_axis) const {
    Eigen::Vector3d normal;
    double mean = 0.0;
    (*this)(moving_axis, &normal, &mean);
    return SphericalDyad::Make(normal, moving_axis, mean);
  }

 private:
  const std::vector<Eigen::Matrix3d>& rotations_;
  const std::vector<double>& weights_;
  mutable std::vector<Eigen::Vector3d> positions_;  // x_j of the last evaluation
  mutable std::vector<double> angles_;              // theta_j of the last evaluation
};

// The best point evaluated in each cell of an equal-area grid over the hemisphere: the archive
// from which the distinct local optima are picked. A cell whose best is better than the best of
// each of its eight neighbours (phi periodic; across the equator or the pole, the cell of the
// opposite phi) is a local minimum of the sampled objective.
class Archive {
 public:
  Archive()
      : rows_(std::max(1, static_cast<int>(std::ceil(1.0 / kCellWidth)))),
        columns_(2 * std::max(1, static_cast<int>(std::ceil(M_PI / kCellWidth)))),
        entries_(static_cast<size_t>(rows_ * columns_)) {}

  int cells() const { return rows_ * columns_; }
  // The centre (z, phi) of cell `index`.
  std::pair<double, double> Centre(int index) const {
    return {(index / columns_ + 0.5) / rows_, (index % columns_ + 0.5) * 2.0 * M_PI / columns_};
  }

  void Add(double z, double phi, double value) {
    const int row = std::clamp(static_cast<int>(std::floor(z * rows_)), 0, rows_ - 1);
    const double turns = phi / (2.0 * M_PI);
    const int column = std::clamp(
        static_cast<int>(std::floor((turns - std::floor(turns)) * columns_)), 0, columns_ - 1);
    Entry& entry = entries_[static_cast<size_t>(row * columns_ + column)];
    if (value < entry.value) entry = {value, z, phi};
  }

  // The cells' local minima (value, z, phi), best first.
  std::vector<std::array<double, 3>> LocalMinima() const {
    std::vector<std::array<double, 3>> minima;
    for (int index = 0; index < cells(); ++index) {
      const Entry& entry = entries_[static_cast<size_t>(index)];
      if (!(entry.value < std::numeric_limits<double>::infinity())) continue;
      const int row = index / columns_, column = index % columns_;
      bool minimum = true;
      for (int dr = -1; dr <= 1 && minimum; ++dr) {
        for (int dc = -1; dc <= 1 && minimum; ++dc) {
          int other_row = row + dr, other_column = column + dc;
          if (other_row < 0 || other_row >= rows_) {  // across the equator or the pole
            other_row = row;
            other_column += columns_ / 2;
          }
          other_column = (other_column % columns_ + columns_) % columns_;
          const int other = other_row * columns_ + other_column;
          if (other == index) continue;
          const double value = entries_[static_cast<size_t>(other)].value;
          // Ties go to the smaller index, so that a plateau still yields one minimum.
          if (value < entry.value || (value == entry.value && other < index)) minimum = false;
        }
      }
      if (minimum) minima.push_back({entry.value, entry.z, entry.phi});
    }
    std::sort(minima.begin(), minima.end());  // by value, ties by point: deterministic
    return minima;
  }

 private:
  struct Entry {
    double value = std::numeric_limits<double>::infinity();
    double z = 0.0, phi = 0.0;
  };

  int rows_, columns_;
  std::vector<Entry> entries_;
};

// What the global run sees: the objective, the archive to fill, its best point (kept even when
// NLopt throws) and the evaluation count.
struct Run {
  const Objective* objective = nullptr;
  Archive* archive = nullptr;
  double best_value = std::numeric_limits<double>::infinity();
  int evaluations = 0;
};

double Evaluate(Run* run, double z, double phi) {
  const double value = (*run->objective)(AxisAt(z, phi));
  ++run->evaluations;
  run->archive->Add(z, phi, value);
  run->best_value = std::min(run->best_value, value);
  return value;
}

// NLopt's objective callback (derivative-free algorithms: no gradient).
double EvaluateRun(unsigned /*dimension*/, const double* x, double* /*gradient*/, void* data) {
  return Evaluate(static_cast<Run*>(data), x[0], x[1]);
}

// A local descent's state: where it is, its cost, its evaluations, and whether it was stopped
// near an optimum already found.
struct Descent {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double value = kLargeCost;
  int evaluations = 0;
  bool merged = false;
};

// Damped Gauss-Newton on the sphere from descent->axis, at most max_evaluations evaluations
// (a residual evaluation counts one) and until the deadline; the best point so far is kept.
void Descend(const Objective& objective, int max_evaluations, Clock::time_point deadline,
             const std::vector<Eigen::Vector3d>& known_optima, Descent* descent) {
  Eigen::Vector3d axis = descent->axis;
  double cost = descent->value;
  double damping = kInitialDamping;
  Eigen::VectorXd residuals;
  Eigen::MatrixX2d jacobian;
  while (descent->evaluations < max_evaluations && Clock::now() < deadline) {
    ++descent->evaluations;
    const Eigen::Matrix<double, 3, 2> basis = TangentBasis(axis);
    if (!objective.Residuals(axis, basis, &residuals, &jacobian)) return;
    const Eigen::Vector2d gradient = jacobian.transpose() * residuals;
    const Eigen::Matrix2d normal = jacobian.transpose() * jacobian;
    bool improved = false;
    while (!improved) {
      if (descent->evaluations >= max_evaluations || damping > kMaxDamping) return;
      Eigen::Matrix2d damped = normal;
      damped.diagonal() += damping * normal.diagonal().cwiseMax(kMinCurvature);
      const Eigen::Vector2d step = damped.ldlt().solve(-gradient);
      if (!step.allFinite() || step.norm() <= kLocalTolerance) return;  // converged
      const Eigen::Vector3d candidate = (axis + basis * step).normalized();
      ++descent->evaluations;
      const double value = objective(candidate);
      if (value < cost) {
        if (cost - value <= kLocalFunctionTolerance * cost) {  // creeping: stop here
          descent->axis = candidate;
          descent->value = value;
          return;
        }
        axis = candidate;
        cost = value;
        damping = std::max(damping / 3.0, kMinDamping);
        improved = true;
      } else {
        damping *= 4.0;
      }
    }
    descent->axis = axis;
    descent->value = cost;
    for (const Eigen::Vector3d& known : known_optima) {
      if (AxisDistance(axis, known) < kMergeRadius) {
        descent->merged = true;
        return;
      }
    }
  }
}

double SecondsLeft(Clock::time_point deadline) {
  return std::chrono::duration<double>(deadline - Clock::now()).count();
}

// The distinct local optima of the objective, best first, at most options.polish_count: the
// archive filled with the cells' centres and the NLopt run, then descents from its local minima.
std::vector<SphericalDyad> SearchOptima(const Objective& objective,
                                        const SphericalSearchOptions& options,
                                        Clock::time_point start, SphericalSearchSummary* report) {
  const auto deadline =
      start + std::chrono::duration_cast<Clock::duration>(
                  std::chrono::duration<double>(std::min(options.time_limit, 1e9)));
  Archive archive;
  Run global;
  global.objective = &objective;
  global.archive = &archive;
  for (int index = 0; index < archive.cells() && global.evaluations < options.max_evaluations;
       ++index) {
    const auto [z, phi] = archive.Centre(index);
    Evaluate(&global, z, phi);
  }
  const int nlopt_budget =
      static_cast<int>(kGlobalShare * (options.max_evaluations - global.evaluations));
  const double nlopt_time = kGlobalShare * SecondsLeft(deadline);
  if (nlopt_budget >= 1 && nlopt_time > 0.0) {
    nlopt::srand(options.seed);
    nlopt::opt optimizer(NloptAlgorithm(options.algorithm), 2);
    optimizer.set_lower_bounds({0.0, 0.0});
    optimizer.set_upper_bounds({1.0, 2.0 * M_PI});
    optimizer.set_min_objective(EvaluateRun, &global);
    optimizer.set_maxeval(nlopt_budget);
    optimizer.set_maxtime(nlopt_time);
    if (options.algorithm == GlobalAlgorithm::kMlsl) {
      nlopt::opt local(nlopt::LN_BOBYQA, 2);
      local.set_xtol_rel(kMlslLocalTolerance);
      local.set_maxeval(kMlslLocalEvaluations);
      optimizer.set_local_optimizer(local);
    }
    RunNlopt(optimizer, {0.5, M_PI});
  }
  report->evaluations += global.evaluations;
  if (global.evaluations == 0) return {};

  // Local descents from the archive's local minima, best first, while the budget and the time
  // last (the best is always kept, descended or not); a descent that comes near an optimum
  // already found is dropped (it would only find it again).
  std::vector<Eigen::Vector3d> known_optima;
  std::vector<std::pair<double, SphericalDyad>> optima;
  int budget = options.max_evaluations - global.evaluations;
  for (const auto& [value, z, phi] : archive.LocalMinima()) {
    const bool time_left = Clock::now() < deadline;
    if (!optima.empty() && (budget <= 0 || !time_left)) break;
    Descent descent;
    descent.axis = AxisAt(z, phi);
    descent.value = value;
    if (budget > 0 && time_left) {
      Descend(objective, std::min(budget, kLocalEvaluations), deadline, known_optima, &descent);
      report->evaluations += descent.evaluations;
      budget -= descent.evaluations;
    }
    if (descent.merged) continue;
    known_optima.push_back(descent.axis);
    optima.emplace_back(descent.value, objective.Dyad(descent.axis));
  }
  report->optima = static_cast<int>(optima.size());
  std::stable_sort(optima.begin(), optima.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<SphericalDyad> distinct;
  for (const auto& optimum : optima) {
    const SphericalDyad& dyad = optimum.second;  // not a binding: the lambda below uses it
    if (static_cast<int>(distinct.size()) >= options.polish_count) break;
    if (!dyad.AllFinite()) continue;
    const bool seen = std::any_of(
        distinct.begin(), distinct.end(),
        [&](const SphericalDyad& other) { return SameSphericalDyad(dyad, other, kDistinct); });
    if (!seen) distinct.push_back(dyad);
  }
  return distinct;
}

void Validate(const std::vector<Eigen::Matrix3d>& rotations, const std::vector<double>& weights,
              const std::vector<bool>& exact, const SphericalSearchOptions& options) {
  const std::string where = "SearchSphericalDyads: ";
  CheckRefinerInput("SearchSphericalDyads", rotations.size(), 1.0, weights, &exact);
  for (const Eigen::Matrix3d& rotation : rotations) {
    if (!rotation.allFinite()) throw std::invalid_argument(where + "rotations must be finite");
  }
  if (options.max_evaluations < 1 || !(options.time_limit > 0.0) || options.polish_count < 1) {
    throw std::invalid_argument(where +
                                "options need max_evaluations >= 1, time_limit > 0 and "
                                "polish_count >= 1");
  }
}

}  // namespace

int SearchSphericalDyads(const std::vector<Eigen::Matrix3d>& rotations,
                         const std::vector<double>& weights, const std::vector<bool>& exact,
                         const SphericalSearchOptions& options, std::vector<SphericalDyad>* dyads,
                         SphericalSearchSummary* summary) {
  const auto start = Clock::now();
  Validate(rotations, weights, exact, options);
  dyads->clear();
  SphericalSearchSummary report;
  report.algorithm = GlobalAlgorithmName(options.algorithm);
  const size_t count = rotations.size();
  std::vector<std::pair<double, SphericalDyad>> polished;
  if (count >= 5) {
    std::vector<double> search_weights(count);
    double weight_sum = 0.0;
    for (size_t j = 0; j < count; ++j) {
      search_weights[j] = weights.empty() ? 1.0 : weights[j];
      if (!exact.empty() && exact[j]) search_weights[j] *= kExactSearchWeight;
      weight_sum += search_weights[j];
    }
    for (double& weight : search_weights) weight /= weight_sum;
    const Objective objective(rotations, search_weights);
    for (SphericalDyad dyad : SearchOptima(objective, options, start, &report)) {
      const RefinerSummary refined =
          RefineSphericalDyad(rotations, weights, exact, &dyad, options.refiner);
      if (!dyad.AllFinite() || !std::isfinite(refined.final_cost)) continue;
      polished.emplace_back(refined.final_cost, dyad);
    }
  }
  std::stable_sort(polished.begin(), polished.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& entry : polished) {
    const double cost = entry.first;
    const SphericalDyad& dyad = entry.second;  // not a binding: the lambda below uses it
    const bool seen = std::any_of(dyads->begin(), dyads->end(), [&](const SphericalDyad& other) {
      return SameSphericalDyad(dyad, other, kDistinct);
    });
    if (seen) continue;
    if (dyads->empty()) report.best_cost = cost;
    dyads->push_back(dyad);
  }
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (summary != nullptr) *summary = report;
  return static_cast<int>(dyads->size());
}

}  // namespace linkfit
