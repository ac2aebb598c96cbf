#include "fitting/spatial_motion.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include "fitting/model_choice.h"
#include "lib/text_format.h"

namespace linkfit {
namespace {

// A sphere |x - center| = radius or, when the points are coplanar, a plane n . x = h, fitted
// to points by weighted linear least squares (4 unknowns: 2 center + k = |x|^2).
struct SphereOrPlane {
  bool plane = false;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
};

SphereOrPlane FitSphereOrPlane(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<double>& weights, double length) {
  const int n = static_cast<int>(points.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double weight_sum = 0.0;
  for (int j = 0; j < n; ++j) {
    centroid += weights[j] * points[j];
    weight_sum += weights[j];
  }
  centroid /= weight_sum;
  // The best plane first: the smallest eigenvector of the weighted scatter.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d p = points[j] - centroid;
    scatter += weights[j] * p * p.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  SphereOrPlane out;
  out.normal = eigen.eigenvectors().col(0);
  out.offset = out.normal.dot(centroid);
  double plane_worst = 0.0;
  for (const Eigen::Vector3d& p : points) {
    plane_worst = std::max(plane_worst, std::abs(out.normal.dot(p) - out.offset));
  }
  // Sphere, in coordinates centered at the centroid and scaled by L: 2 p . m + k = |p|^2.
  Eigen::MatrixXd system(n, 4);
  Eigen::VectorXd rhs(n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d p = (points[j] - centroid) / length;
    const double w = std::sqrt(weights[j]);
    system.row(j) << w * 2.0 * p.transpose(), w;
    rhs[j] = w * p.squaredNorm();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(system);
  const Eigen::Vector4d solution = qr.solve(rhs);
  const Eigen::Vector3d center = solution.head<3>();
  const double radius_squared = solution[3] + center.squaredNorm();
  if (qr.rank() == 4 && radius_squared > 0.0 && std::isfinite(radius_squared)) {
    out.center = centroid + length * center;
    out.radius = length * std::sqrt(radius_squared);
    double sphere_worst = 0.0;
    for (const Eigen::Vector3d& p : points) {
      sphere_worst = std::max(sphere_worst, std::abs((p - out.center).norm() - out.radius));
    }
    out.plane = plane_worst <= 1e-9 * length || plane_worst <= sphere_worst;
  } else {
    out.plane = true;
  }
  return out;
}

// Plane-frame axes with the given unit normal as the third column.
Eigen::Matrix3d FrameAbout(const Eigen::Vector3d& normal) {
  Eigen::Vector3d u1, u2;
  NormalTurns(normal, &u1, &u2);
  Eigen::Matrix3d axes;
  axes << u1, u2, normal;
  return axes;
}

void SolvePlanar(const Task& task, const SpatialMotionOptions& options, PlanarEmbedding plane,
                 SpatialMotionResult* result) {
  result->model = "planar";
  Task planar_task;
  planar_task.problem = ProblemKind::kMotion;
  planar_task.space = Space::kPlanar;
  planar_task.planar_poses = plane.poses;
  planar_task.pose_weights = task.pose_weights;
  planar_task.pose_exact = task.pose_exact;
  planar_task.scale = task.scale;
  planar_task.effort = task.effort;
  planar_task.precision = task.precision;
  planar_task.constraints = task.constraints;  // the planar four-bars are judged by them
  const int count = static_cast<int>(plane.poses.size());
  result->notes.push_back(
      "the poses lie in one plane (largest deviation " + Format("%.3g", plane.planarity) +
      "): solved as a planar problem; dyads are given in spatial coordinates, and each pivot "
      "of an RR dyad may slide along the plane normal without changing the motion");
  if (count >= 7) {
    result->notes.push_back(
        "seven or more planar poses: every point of the body moves in a plane parallel to the "
        "plane of motion, so there is a 3-parameter family of PS dyads (seed 000 section 5); "
        "the planar four-bars below are the simpler answer");
  }
  if (count < 3) {
    result->notes.push_back(
        "fewer than three planar poses: every dyad type has a family of "
        "solutions; give at least three poses");
    result->plane = std::move(plane);
    return;
  }
  PlanarMotionResult planar = SolvePlanarMotion(planar_task, options.planar);
  result->method = planar.method;
  result->roots_total = planar.roots_total;
  result->roots_real = planar.roots_real;
  result->planar = std::move(planar);  // its notes are written with the result's
  result->plane = std::move(plane);
}

}  // namespace

namespace {

// How far rounding can move a body point `distance` from a pose's origin, measured against a
// fitted reference: the origin moves by up to sqrt(3) delta and the rotation tilts by up to
// alpha, both doubled for the reference fitted to the poses, kModelUnits of that.
double FitWithinPrecision(const DataPrecision& precision, double distance) {
  return kModelUnits *
         std::hypot(2.0 * std::sqrt(3.0) * precision.length, 2.0 * distance * precision.angle);
}

}  // namespace

double PlanarityTolerance(const Task& task, double length, const SpatialMotionOptions& options) {
  // Measured against the centroid and the first pose, at L from the origin.
  return std::max(options.planarity_tolerance, FitWithinPrecision(task.precision, length) / length);
}

double SpatialTaskLength(const Task& task) {
  if (task.scale) return *task.scale;
  const int n = static_cast<int>(task.spatial_poses.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : task.spatial_poses) centroid += pose.Translation() / n;
  double sum = 0.0;
  for (const DualQuaternion& pose : task.spatial_poses) {
    sum += (pose.Translation() - centroid).squaredNorm();
  }
  const double length = std::sqrt(sum / std::max(n, 1));
  // Origins that coincide to rounding (a spherical motion given in frames at its centre) have
  // no spread to measure: the unit length, as for origins that coincide exactly.
  return length > 1e-12 * centroid.norm() && std::isfinite(length) ? length : 1.0;
}

std::optional<PlanarEmbedding> DetectPlanarMotion(const std::vector<DualQuaternion>& poses,
                                                  double length, double tolerance) {
  const int n = static_cast<int>(poses.size());
  if (n < 2) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const DualQuaternion& pose : poses) centroid += pose.Translation() / n;
  const Eigen::Matrix3d first = poses[0].Rotation();
  // The normal n minimizes sum_j ((d_j - centroid) . n)^2 + L^2 |(Q_j - I) n|^2 with the
  // relative rotations Q_j = R_j R_1^T: both vanish for a planar motion.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Matrix3d> relative(n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d offset = poses[j].Translation() - centroid;
    relative[j] = poses[j].Rotation() * first.transpose();
    const Eigen::Matrix3d tilt = relative[j] - Eigen::Matrix3d::Identity();
    scatter += offset * offset.transpose() + length * length * tilt.transpose() * tilt;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  double worst = 0.0;
  for (int j = 0; j < n; ++j) {
    const double out_of_plane = (poses[j].Translation() - centroid).dot(normal);
    const double tilt = (relative[j] * normal - normal).norm();
    worst = std::max(worst, std::hypot(out_of_plane, length * tilt));
  }
  if (!(worst <= tolerance * length)) return std::nullopt;
  PlanarEmbedding plane;
  plane.origin_in_fixed = centroid;
  plane.axes_in_fixed = FrameAbout(normal);
  plane.axes_in_moving = first.transpose() * plane.axes_in_fixed;
  plane.planarity = worst;
  const Eigen::Vector3d u1 = plane.axes_in_fixed.col(0), u2 = plane.axes_in_fixed.col(1);
  for (int j = 0; j < n; ++j) {
    // E's plane frame maps to Sigma's by Q_j about n, so theta_j is the angle of Q_j u1.
    const Eigen::Vector3d turned = relative[j] * u1;
    const Eigen::Vector3d offset = poses[j].Translation() - centroid;
    plane.poses.emplace_back(offset.dot(u1), offset.dot(u2),
                             std::atan2(turned.dot(u2), turned.dot(u1)));
  }
  return plane;
}

// DetectSphericalMotion: the smallest singular value of [R_j  -I] (units of the largest) for
// which the rotations determine the fixed point (rotations about one axis direction leave a
// line of points: 0).
constexpr double kCenterDetermined = 1e-3;

std::optional<SphericalCenter> FitSphericalCenter(const std::vector<DualQuaternion>& poses,
                                                  double length) {
  const int n = static_cast<int>(poses.size());
  if (n < 3) return std::nullopt;
  // R_j p + d_j = P for every pose: 3n linear equations [R_j  -I] (p, P) = -d_j, in units of L.
  Eigen::MatrixXd a(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (int j = 0; j < n; ++j) {
    a.block<3, 3>(3 * j, 0) = poses[j].Rotation();
    a.block<3, 3>(3 * j, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * j) = -poses[j].Translation() / length;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  // Rotations about one axis direction leave a line of solutions (planar motion's business).
  if (!(sigma(5) > kCenterDetermined * sigma(0))) return std::nullopt;
  const Eigen::VectorXd x = svd.solve(b) * length;
  SphericalCenter center;
  center.in_moving = x.head<3>();
  center.in_fixed = x.tail<3>();
  for (const DualQuaternion& pose : poses) {
    center.sphericity = std::max(
        center.sphericity,
        (pose.Rotation() * center.in_moving + pose.Translation() - center.in_fixed).norm());
  }
  if (!center.in_moving.allFinite() || !center.in_fixed.allFinite()) return std::nullopt;
  return center;
}

double SphericityTolerance(const SphericalCenter& center, double length,
                           const DataPrecision& precision, double tolerance) {
  return std::max(tolerance * length, FitWithinPrecision(precision, center.in_moving.norm()));
}

std::optional<SphericalCenter> DetectSphericalMotion(const std::vector<DualQuaternion>& poses,
                                                     double length, const DataPrecision& precision,
                                                     double tolerance) {
  std::optional<SphericalCenter> center = FitSphericalCenter(poses, length);
  if (!center ||
      !(center->sphericity <= SphericityTolerance(*center, length, precision, tolerance))) {
    return std::nullopt;
  }
  return center;
}

void AddSpatialConstraintsNote(const Task& task, SpatialMotionResult* result) {
  if (!task.constraints.given) return;
  result->notes.push_back(
      "the design constraints judge spherical and planar four-bars only: these poses are solved "
      "as spatial, and their SS / PS dyads and platforms are not judged by them");
}

SpatialMotionResult SolveSpatialMotion(const Task& task, const SpatialMotionOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SpatialMotionResult result;
  const double length = SpatialTaskLength(task);
  result.scale = length;
  const std::vector<DualQuaternion>& poses = task.spatial_poses;
  const int n = static_cast<int>(poses.size());
  const auto finish = [&]() {
    result.solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

  const bool have_pivots =
      !(task.spatial_moving_pivots.empty() && task.spatial_fixed_pivots.empty());
  // One fit of the plane and one of the centre decide: planar or spherical within the data's
  // precision, else nearly spherical (solved as spatial, and said so), else spatial. Coarse data
  // can be both (four digits of dual quaternions: rotations about axes a few 1e-3 apart are
  // planar within their precision): the better fit relative to its tolerance is the model,
  // planar on a tie (measured: a spherical four-bar's five or ten orientations printed so fit
  // the centre at least 18 times better; planar data never fit a centre).
  const double planarity_tolerance = PlanarityTolerance(task, length, options);
  std::optional<PlanarEmbedding> plane =
      have_pivots ? std::nullopt : DetectPlanarMotion(poses, length, planarity_tolerance);
  const std::optional<SphericalCenter> center =
      have_pivots ? std::nullopt : FitSphericalCenter(poses, length);
  const double within =
      center ? SphericityTolerance(*center, length, task.precision, options.sphericity_tolerance)
             : 0.0;
  const bool spherical = center && center->sphericity <= within;
  if (plane && !(spherical &&
                 center->sphericity / within < plane->planarity / (planarity_tolerance * length))) {
    SolvePlanar(task, options, std::move(*plane), &result);
    return finish();
  }
  if (spherical) {
    if (plane) {
      result.notes.push_back(
          "the poses also lie in one plane within the data's precision (largest deviation " +
          Format("%.3g", plane->planarity) +
          "), but fix one point more closely: solved as "
          "spherical");
    }
    SolveSphericalMotion(task, *center, options.spherical, &result);
    return finish();
  }
  std::vector<double> weights = task.pose_weights;
  if (weights.size() != poses.size()) weights.assign(poses.size(), 1.0);
  if (center) {
    if (center->sphericity <= options.nearly_spherical * length) {
      const Eigen::Vector3d& c = center->in_fixed;
      result.notes.push_back(
          "the poses are nearly a spherical motion about [" + Format("%.6g", c.x()) + ", " +
          Format("%.6g", c.y()) + ", " + Format("%.6g", c.z()) + "] (largest deviation " +
          Format("%.3g", center->sphericity) + ", beyond the data's precision " +
          Format("%.3g", within) +
          "): solved as spatial; give the data's precision (\"precision\") if it is coarser");
    }
  }
  AddSpatialConstraintsNote(task, &result);
  if (!task.moving_axes.empty() || !task.fixed_axes.empty()) {
    result.notes.push_back(
        "moving_axes / fixed_axes choose dyads of a spherical motion, but these poses do not fix "
        "one point within the data's precision: no dyad chosen");
    return finish();
  }

  if (n < 7) {
    if (!have_pivots) {
      result.notes.push_back(
          std::to_string(n) + (n == 1 ? " pose leaves a " : " poses leave a ") +
          std::to_string(7 - n) +
          "-parameter family of SS dyads (seven poses determine them); give seven poses, or "
          "moving_pivots / fixed_pivots (with four to six poses) to pick dyads from the family");
      return finish();
    }
    result.method = n == 4 ? "exact" : "least-squares";
    for (const Eigen::Vector3d& pivot : task.spatial_moving_pivots) {
      std::vector<Eigen::Vector3d> points;
      for (const DualQuaternion& pose : poses) points.push_back(pose.ToFixed(pivot));
      const SphereOrPlane fit = FitSphereOrPlane(points, weights, length);
      SpatialDyadReport report;
      report.dyad = fit.plane ? SpatialDyad::PS(pivot, fit.normal, fit.offset)
                              : SpatialDyad::SS(fit.center, pivot, fit.radius);
      report.max_residual = report.dyad.MaxResidual(poses);
      result.dyads.push_back(report);
    }
    for (const Eigen::Vector3d& pivot : task.spatial_fixed_pivots) {
      // The fixed pivot seen from E: e_j = R_j^T (A - d_j); |R c + d - A| = |c - e_j|.
      std::vector<Eigen::Vector3d> points;
      for (const DualQuaternion& pose : poses) {
        points.push_back(pose.Rotation().transpose() * (pivot - pose.Translation()));
      }
      const SphereOrPlane fit = FitSphereOrPlane(points, weights, length);
      SpatialDyadReport report;
      report.dyad = fit.plane ? SpatialDyad::SP(pivot, fit.normal, fit.offset)
                              : SpatialDyad::SS(pivot, fit.center, fit.radius);
      report.max_residual = report.dyad.MaxResidual(poses);
      result.dyads.push_back(report);
    }
    return finish();
  }

  std::vector<SpatialDyad> dyads;
  SpatialBurmesterSummary summary;
  // Rounding by a relative p splits a double root by about sqrt(p): complex roots that close to
  // real are counted (and noted) as nearly real at the data's precision.
  SpatialBurmesterOptions burmester = options.burmester;
  burmester.precision = task.precision;
  burmester.bilinear.nearly_real_share =
      std::max(burmester.bilinear.nearly_real_share,
               10.0 * std::sqrt(RelativePrecision(task.precision, length)));
  SolveSpatialBurmester(poses, weights, burmester, &dyads, &summary);
  result.method = n == 7 ? "exact" : "least-squares";
  result.roots_total = summary.roots_total;
  result.roots_real = summary.roots_real;
  result.condition = summary.condition;
  if (summary.degenerate) {
    result.notes.push_back(
        "the constraint equations are rank-deficient to working precision (ill-conditioned: "
        "condition " +
        Format("%.3g", summary.condition) +
        "): the poses admit a family of dyads, not finitely many; nearly planar or repeated "
        "motions do this");
    return finish();
  }
  if (summary.roots_verified < summary.roots_total) {
    result.notes.push_back(std::to_string(summary.roots_total - summary.roots_verified) +
                           " of the " + std::to_string(summary.roots_total) +
                           " roots did not polish to full accuracy (ill-conditioned task: "
                           "condition estimate " +
                           Format("%.3g", summary.condition) + ")");
  }
  if (summary.nearly_real > 0) {
    result.notes.push_back(
        std::to_string(summary.nearly_real) +
        " complex roots are nearly real (imaginary part below " +
        Format("%.2g", burmester.bilinear.nearly_real_share) +
        "): ill-conditioned near a double root, where rounding of the data can turn two real "
        "dyads into a complex pair (condition estimate " +
        Format("%.3g", summary.condition) + ")");
  }
  if (summary.real_within_precision > 0) {
    result.notes.push_back(std::to_string(summary.real_within_precision) +
                           " complex roots are real within the data's precision (rounding turns "
                           "two nearby dyads into a complex pair): their real parts, fitted to "
                           "the poses, fit them within it and are listed");
  }
  if (summary.imaginary_spheres > 0) {
    result.notes.push_back(std::to_string(summary.imaginary_spheres) +
                           " real roots are spheres of imaginary radius (no physical dyad)");
  }
  int simplified = 0;
  for (const SpatialDyad& dyad : dyads) {
    SpatialDyadReport report;
    report.dyad = dyad;
    // A sphere the data cannot tell from a plane is the plane (fitting/model_choice.h).
    SpatialDyad plane;
    if (SimplerModel(dyad, poses, task.precision, length, &plane)) {
      report.dyad = plane;
      ++simplified;
    }
    report.max_residual = report.dyad.MaxResidual(poses);
    report.error_bound = DyadErrorBound(report.dyad, poses, task.precision, length);
    result.dyads.push_back(report);
  }
  if (simplified > 0) {
    result.notes.push_back(std::to_string(simplified) +
                           (simplified == 1 ? " sphere is" : " spheres are") +
                           " reported as planes (PS or SP): at the data's precision (length " +
                           Format("%.2g", task.precision.length) + ", angle " +
                           Format("%.2g", task.precision.angle * 180.0 / M_PI) +
                           " deg) the poses cannot tell them from their plane readings");
  }
  const double relative = RelativePrecision(task.precision, length);
  const double bound = options.planar.condition_error_factor * summary.condition * relative;
  if (n == 7 && bound > options.planar.error_note) {
    result.notes.push_back(ConditionNote(summary.condition, relative, bound));
  }
  SortDyadsByRadius(&result.dyads);
  if (result.dyads.empty()) result.notes.push_back("no real dyad: all roots are complex");
  return finish();
}

void SortDyadsByRadius(std::vector<SpatialDyadReport>* dyads) {
  const auto key = [](const SpatialDyad& dyad) {
    return dyad.type == SpatialDyadType::kSS ? dyad.radius
                                             : std::numeric_limits<double>::infinity();
  };
  std::stable_sort(dyads->begin(), dyads->end(),
                   [&](const SpatialDyadReport& a, const SpatialDyadReport& b) {
                     return key(a.dyad) < key(b.dyad);
                   });
}

void AddPlatform(const Task& task, const PlatformMotionOptions& options,
                 SpatialMotionResult* result) {
  if (result->model != "spatial") return;
  std::vector<int> chosen = task.platform;
  const int count = static_cast<int>(result->dyads.size());
  if (chosen.empty()) {
    for (int i = 0; i < count && chosen.size() < 5; ++i) {
      if (result->dyads[i].dyad.type != SpatialDyadType::kSP) chosen.push_back(i);
    }
    if (chosen.size() < 5) {
      if (!result->dyads.empty()) {
        result->notes.push_back(
            "fewer than five SS/PS dyads: no platform (a 5-SS platform "
            "needs five)");
      }
      return;
    }
  } else {
    for (int index : chosen) {
      if (index >= count) {
        result->notes.push_back("platform: dyad " + std::to_string(index) + " does not exist (" +
                                std::to_string(count) + " dyads); no platform built");
        return;
      }
    }
  }
  std::vector<SpatialDyad> dyads;
  for (int index : chosen) dyads.push_back(result->dyads[index].dyad);
  const auto start = std::chrono::steady_clock::now();
  const PlatformMotionReport motion =
      TracePlatform(dyads, task.spatial_poses, result->scale, options);
  result->analysis_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  PlatformReport report;
  report.dyads = chosen;
  report.assembles = motion.assembles;
  report.one_branch = motion.one_branch;
  report.closed = motion.closed;
  if (motion.assembles) report.max_pose_error = motion.max_pose_error;
  report.order = motion.order;
  report.note = motion.note;
  report.path = motion.path;
  if (task.platform.empty() && !(motion.assembles && motion.one_branch)) {
    result->notes.push_back(
        "the default platform (the five dyads of smallest radius) does not pass every pose on "
        "one branch; name five other dyads with \"platform\" in the task or --platform");
  }
  result->mechanisms.push_back(report);
}

}  // namespace linkfit
