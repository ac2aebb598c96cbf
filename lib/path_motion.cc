#include "lib/path_motion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>

#include "lib/four_bar_closure.h"
#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The coupler's turns (cos(theta), sin(theta)) that close the output with the crank pin at `pin`
// (Sigma): AssembleFourBar's equation a cos + b sin = c (OutputTurnEquation) and its label order
// (label 0: theta = atan2(b, a) + acos(c / rho)), solved for the unit vectors without angles,
//   (a c -+ b s, b c +- a s) / rho^2,  s = sqrt(rho^2 - c^2),
// with AssembleFourBar's tangency slack. Returns 0 or 2.
int TurnsAtPin(const PathFourBar& four_bar, const Eigen::Vector2d& pin, double tolerance,
               Eigen::Vector2d turns[2]) {
  double a = 0.0, b = 0.0, c = 0.0, scale = 1.0;
  OutputTurnEquation(four_bar.output, four_bar.input.moving_pivot, pin, &a, &b, &c, &scale);
  const double rho_squared = a * a + b * b;
  if (!(rho_squared > 0.0) || !std::isfinite(rho_squared)) return 0;
  const double rho = std::sqrt(rho_squared);
  double ratio = c / rho;
  if (std::abs(ratio) > 1.0) {
    if (std::abs(ratio) - 1.0 > tolerance / scale) return 0;
    ratio = std::copysign(1.0, ratio);
  }
  const double across = std::sqrt(std::max(1.0 - ratio * ratio, 0.0));
  const double ua = a / rho, ub = b / rho;
  turns[0] = Eigen::Vector2d(ua * ratio - ub * across, ub * ratio + ua * across);
  turns[1] = Eigen::Vector2d(ua * ratio + ub * across, ub * ratio - ua * across);
  return 2;
}

// R(theta) v for the unit vector (cos(theta), sin(theta)).
Eigen::Vector2d Turn(const Eigen::Vector2d& unit, const Eigen::Vector2d& v) {
  return Eigen::Vector2d(unit.x() * v.x() - unit.y() * v.y(), unit.y() * v.x() + unit.x() * v.y());
}

// The configuration with assembly label `label` at crank angle `alpha`, if it assembles.
std::optional<PlanarPose> Configuration(const PathFourBar& four_bar, double alpha, int label,
                                        double tolerance) {
  std::vector<PlanarPose> poses;
  const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha, tolerance, &poses);
  if (count == 0) return std::nullopt;
  return poses[std::min(label, count - 1)];
}

}  // namespace

double FirstCrankAngle(const PathFourBar& four_bar) {
  const Eigen::Vector2d arm = four_bar.input.moving_pivot - four_bar.input.fixed_pivot;
  return std::atan2(arm.y(), arm.x());
}

PathFourBarAnalysis AnalyzePathFourBar(const PathFourBar& four_bar,
                                       const std::vector<Eigen::Vector2d>& points,
                                       const std::vector<double>& input_angles, double length,
                                       const PathAnalysisOptions& options) {
  PathFourBarAnalysis analysis;
  if (points.empty() || points.size() != input_angles.size() ||
      four_bar.input.type != DyadType::kRR) {
    analysis.error_note = "not a crank-driven four-bar with one input angle per point";
    return analysis;
  }
  const double tolerance = options.assembly_tolerance * length;
  const double alpha0 = FirstCrankAngle(four_bar);
  // Where the output closes, as a condition on the crank angle alone (four_bar_closure.h).
  const ClosureScalar closure = InputClosureScalar(four_bar.input, four_bar.output);
  analysis.input_rotates_fully = closure.Holds(alpha0, 2.0 * kPi, tolerance);

  // The crank pin at each point: the arm B -> A turned by psi_j - psi_0.
  const Eigen::Vector2d pivot = four_bar.input.fixed_pivot;
  const Eigen::Vector2d arm = four_bar.input.moving_pivot - pivot;
  const Eigen::Vector2d& m1 = four_bar.input.moving_pivot;        // the pin, in E
  const Eigen::Vector2d point_arm = four_bar.coupler_point - m1;  // pin -> coupler point, in E
  const auto pin_at = [&](size_t j) {
    const double turn = input_angles[j] - input_angles[0];
    return Eigen::Vector2d(pivot + Turn(Eigen::Vector2d(std::cos(turn), std::sin(turn)), arm));
  };

  // The first point's assembly: the configuration nearest E = Sigma (turn nearest 0, the pin
  // being where E has it).
  Eigen::Vector2d turns[2];
  if (TurnsAtPin(four_bar, m1, tolerance, turns) == 0) {
    analysis.error_note = "does not assemble at the first point";
    return analysis;
  }
  analysis.assembles = true;
  analysis.label = 0;
  const auto pose_of = [&](const Eigen::Vector2d& pin, const Eigen::Vector2d& unit) {
    PlanarPose pose;
    pose.theta = std::atan2(unit.y(), unit.x());
    pose.origin_in_fixed = pin - Turn(unit, m1);
    return pose;
  };
  if (PoseError(pose_of(m1, turns[1]), PlanarPose(), length) <
      PoseError(pose_of(m1, turns[0]), PlanarPose(), length)) {
    analysis.label = 1;
  }

  double alpha = alpha0;
  bool branch = false, circuit = false;
  double sum_squared = 0.0, largest = 0.0, nearest_largest = 0.0;
  analysis.point_errors.reserve(points.size());
  analysis.configurations.reserve(points.size());
  for (size_t j = 0; j < points.size(); ++j) {
    const double step = j == 0 ? 0.0 : input_angles[j] - input_angles[j - 1];
    if (j > 0 && !closure.Holds(alpha, step, tolerance)) branch = true;
    alpha += step;
    const Eigen::Vector2d pin = j == 0 ? m1 : pin_at(j);
    if (j > 0 && TurnsAtPin(four_bar, pin, tolerance, turns) == 0) {
      analysis.error_note =
          "cannot be assembled at the input angle of points[" + std::to_string(j) + "]";
      analysis.point_errors.clear();
      analysis.configurations.clear();
      break;
    }
    const Eigen::Vector2d& tracked = turns[analysis.label];
    const Eigen::Vector2d& other = turns[1 - analysis.label];
    const double error = (pin + Turn(tracked, point_arm) - points[j]).norm();
    const double other_error = (pin + Turn(other, point_arm) - points[j]).norm();
    nearest_largest = std::max(nearest_largest, std::min(error, other_error));
    // Met on the other assembly only (at less than half the error).
    if (error > tolerance && other_error < 0.5 * error) {
      if (analysis.input_rotates_fully) {
        circuit = true;
      } else {
        branch = true;
      }
    }
    analysis.point_errors.push_back(error);
    analysis.configurations.push_back(pose_of(pin, tracked));
    sum_squared += error * error;
    largest = std::max(largest, error);
  }
  // A closed path: the closing step from the last point back to the first, a whole turn on.
  const double closing = options.closed ? ClosingInputAngle(input_angles) : input_angles.back();
  if (options.closed && analysis.point_errors.size() == points.size() &&
      !closure.Holds(alpha, closing - input_angles.back(), tolerance)) {
    branch = true;
  }
  if (branch) analysis.defects.push_back("branch");
  if (circuit) analysis.defects.push_back("circuit");
  if (analysis.point_errors.size() == points.size()) {
    analysis.max_point_error = largest;
    analysis.rms_point_error = std::sqrt(sum_squared / static_cast<double>(points.size()));
    analysis.nearest_max_error = nearest_largest;
  }

  if (options.transmission_samples > 0 && !branch && analysis.max_point_error) {
    const double sweep = closing - input_angles.front();
    const int steps = options.transmission_samples;
    TransmissionRangeDeg(
        four_bar.input, four_bar.output, steps,
        [&](int k) {
          return Configuration(four_bar, alpha0 + sweep * k / steps, analysis.label, tolerance);
        },
        &analysis.transmission_min_deg, &analysis.transmission_max_deg);
  }
  return analysis;
}

double ClosingInputAngle(const std::vector<double>& input_angles) {
  if (input_angles.empty()) return 0.0;
  const double first = input_angles.front(), last = input_angles.back();
  double direction = last > first ? 1.0 : last < first ? -1.0 : 0.0;
  if (direction == 0.0 && input_angles.size() > 1) {
    direction = input_angles[1] >= first ? 1.0 : -1.0;
  }
  if (direction == 0.0) direction = 1.0;
  const double turns = std::max(1.0, std::floor(direction * (last - first) / (2.0 * kPi)) + 1.0);
  return first + direction * turns * 2.0 * kPi;
}

namespace {

// The four-bar of PathFourBarErrorBound's parameters (see the header).
PathFourBar FromParameters(const PathFourBar& base, const Eigen::VectorXd& x) {
  PathFourBar four_bar = base;
  const Eigen::Vector2d pivot = x.segment<2>(0), pin = x.segment<2>(2);
  four_bar.input = PlanarDyad::RR(pivot, pin, (pin - pivot).norm());
  const Eigen::Vector2d point = x.segment<2>(4);
  PlanarDyad& output = four_bar.output;
  if (base.output.type == DyadType::kRR) {
    const Eigen::Vector2d moving = x.segment<2>(6);
    output = PlanarDyad::RR(point, moving, (moving - point).norm());
    four_bar.coupler_point = x.segment<2>(8);
    return four_bar;
  }
  const Eigen::Vector2d direction(std::cos(x[6]), std::sin(x[6]));
  // The line passes the pivot's place at the first configuration (E = Sigma there).
  if (output.type == DyadType::kPR) {
    output.moving_pivot = point;
  } else {
    output.fixed_pivot = point;
  }
  output.line_point = point;
  output.line_direction = direction;
  four_bar.coupler_point = x.segment<2>(7);
  return four_bar;
}

// The coupler point's coordinates at the input angles (2 per point), driven from the first
// point's configuration; false when some angle does not assemble.
bool CouplerCoordinates(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                        const std::vector<double>& input_angles, double length,
                        Eigen::VectorXd* coordinates) {
  const PathFourBarAnalysis analysis = AnalyzePathFourBar(four_bar, points, input_angles, length);
  if (analysis.configurations.size() != points.size()) return false;
  coordinates->resize(2 * static_cast<Eigen::Index>(points.size()));
  for (size_t j = 0; j < points.size(); ++j) {
    coordinates->segment<2>(2 * j) = analysis.configurations[j].ToFixed(four_bar.coupler_point);
  }
  return coordinates->allFinite();
}

}  // namespace

double PathFourBarErrorBound(const PathFourBar& given_four_bar,
                             const std::vector<Eigen::Vector2d>& given_points,
                             const std::vector<double>& input_angles,
                             const DataPrecision& precision, double length, bool free_timing) {
  // In a frame at the points' centroid: the central differences below step by 1e-6 L, which at
  // coordinates 10^6 L from the origin would keep only a few digits of the derivatives (and the
  // bound, which decides which four-bars are one, would depend on where the origin is).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : given_points) {
    centroid += point / static_cast<double>(given_points.size());
  }
  Similarity2 to_centroid;
  to_centroid.translation = -centroid;
  PathFourBar four_bar = given_four_bar;
  four_bar.input = TransformDyad(given_four_bar.input, to_centroid, to_centroid);
  four_bar.output = TransformDyad(given_four_bar.output, to_centroid, to_centroid);
  four_bar.coupler_point = given_four_bar.coupler_point - centroid;
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector2d& point : given_points) points.push_back(point - centroid);
  const double unbounded = kInfinity;
  const bool rr = four_bar.output.type == DyadType::kRR;
  const int design_parameters = rr ? 10 : 9;
  const int parameters =
      design_parameters + (free_timing ? static_cast<int>(points.size()) - 1 : 0);
  const int rows = 2 * static_cast<int>(points.size());
  if (rows < parameters || points.size() != input_angles.size() || points.size() < 2 ||
      four_bar.input.type != DyadType::kRR || !(length > 0.0)) {
    return unbounded;
  }
  Eigen::VectorXd x(design_parameters);
  x.segment<2>(0) = four_bar.input.fixed_pivot;
  x.segment<2>(2) = four_bar.input.moving_pivot;
  if (rr) {
    x.segment<2>(4) = four_bar.output.fixed_pivot;
    x.segment<2>(6) = four_bar.output.moving_pivot;
    x.segment<2>(8) = four_bar.coupler_point;
  } else {
    const bool pr = four_bar.output.type == DyadType::kPR;
    x.segment<2>(4) = pr ? four_bar.output.moving_pivot : four_bar.output.fixed_pivot;
    x[6] = std::atan2(four_bar.output.line_direction.y(), four_bar.output.line_direction.x());
    x.segment<2>(7) = four_bar.coupler_point;
  }
  // Central differences: a step of 1e-6 L balances truncation and rounding (errors ~1e-12).
  const double step = 1e-6 * length;
  Eigen::VectorXd plus, minus;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(rows, design_parameters);
  for (int i = 0; i < design_parameters; ++i) {
    // The line angle in radians: a step of 1e-6.
    const double h = !rr && i == 6 ? 1e-6 : step;
    Eigen::VectorXd moved = x;
    moved[i] += h;
    if (!CouplerCoordinates(FromParameters(four_bar, moved), points, input_angles, length, &plus))
      return unbounded;
    moved[i] = x[i] - h;
    if (!CouplerCoordinates(FromParameters(four_bar, moved), points, input_angles, length, &minus))
      return unbounded;
    jacobian.col(i) = (plus - minus) / (2.0 * h);
  }
  // The coordinates' uncertainty: the point's delta and the input angle's alpha times the
  // coupler point's speed along its path (the first angle is the reference: its alpha moves
  // every other point's angle, counted at each of them).
  // Free timing: the angles are parameters, their speed columns of J.
  // Point j's configuration depends on its own angle alone (its turn from the first point, on
  // the first point's assembly), so its speed comes from the first point and j alone: linear
  // in the points, not quadratic.
  Eigen::VectorXd uncertainty = Eigen::VectorXd::Constant(rows, precision.length);
  std::vector<Eigen::Vector2d> speeds(points.size(), Eigen::Vector2d::Zero());
  for (size_t j = 1; j < points.size() && (free_timing || precision.angle > 0.0); ++j) {
    const std::vector<Eigen::Vector2d> pair = {points[0], points[j]};
    std::vector<double> angles = {input_angles[0], input_angles[j] + 1e-6};
    if (!CouplerCoordinates(four_bar, pair, angles, length, &plus)) return unbounded;
    angles[1] = input_angles[j] - 1e-6;
    if (!CouplerCoordinates(four_bar, pair, angles, length, &minus)) return unbounded;
    speeds[j] = (plus - minus).segment<2>(2) / 2e-6;
    if (!free_timing) uncertainty.segment<2>(2 * j) += 2.0 * precision.angle * speeds[j].cwiseAbs();
  }
  uncertainty = uncertainty.cwiseMax(4.0 * std::numeric_limits<double>::epsilon() * length);
  // The design parameters' rows of J^+. Prescribed timing: from the thin SVD of J (2n x 10).
  // Free timing, J = [D S] with S's column j nonzero only in point j's rows (its speed s_j):
  // the angles are eliminated exactly (a Schur complement), each point's rows projected off its
  // speed, P_j = I - s_j s_j^T / |s_j|^2, and the rows are M^-1 [D_j^T P_j]_j with
  // M = sum_j D_j^T P_j D_j -- the same rows as the SVD's of J, in time and memory linear in
  // the points (the SVD of the 2n x (n + 9) matrix is cubic).
  Eigen::MatrixXd pseudo_inverse;
  if (!free_timing) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian,
                                                Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    if (!(sigma[design_parameters - 1] > 1e-12 * sigma[0])) return unbounded;
    pseudo_inverse = svd.matrixV() * sigma.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  } else {
    double largest_speed = 0.0;
    for (const Eigen::Vector2d& speed : speeds)
      largest_speed = std::max(largest_speed, speed.norm());
    Eigen::MatrixXd projected = jacobian.leftCols(design_parameters);  // rows P_j D_j
    for (size_t j = 1; j < points.size(); ++j) {
      const Eigen::Vector2d& speed = speeds[j];
      if (!(speed.norm() > 1e-12 * largest_speed)) return unbounded;
      const Eigen::Matrix2d projector =
          Eigen::Matrix2d::Identity() - speed * speed.transpose() / speed.squaredNorm();
      projected.middleRows<2>(2 * static_cast<Eigen::Index>(j)) =
          projector * projected.middleRows<2>(2 * static_cast<Eigen::Index>(j)).eval();
    }
    // P_j is a projector: D^T P D = (P D)^T (P D), and M^-1 (P D)^T gives the rows.
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(projected,
                                                Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    if (!(sigma[design_parameters - 1] > 1e-12 * sigma[0])) return unbounded;
    pseudo_inverse = svd.matrixV() * sigma.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  }
  const Eigen::VectorXd moves = pseudo_inverse.cwiseAbs() * uncertainty;
  const double size = PathFourBarSize(four_bar, points, length);
  // The points' pairs: B, A, F or M, then (RR) M or (PR, RP) the line angle, then R.
  double bound = 0.0;
  for (const int i : {0, 2, 4, rr ? 6 : -1, rr ? 8 : 7}) {
    if (i >= 0) bound = std::max(bound, std::sqrt(2.0) * std::max(moves[i], moves[i + 1]));
  }
  if (!rr) bound = std::max(bound, moves[6] * size);
  return std::isfinite(bound) ? bound : unbounded;
}

double PathFourBarSize(const PathFourBar& four_bar, const std::vector<Eigen::Vector2d>& points,
                       double length) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : points) {
    centroid += point / static_cast<double>(points.size());
  }
  double size = length;
  for (const Eigen::Vector2d& p :
       {four_bar.input.fixed_pivot, four_bar.input.moving_pivot, four_bar.output.fixed_pivot,
        four_bar.output.moving_pivot, four_bar.coupler_point}) {
    size = std::max(size, (p - centroid).norm());
  }
  return size;
}

std::vector<PathFourBar> CurveCognates(const PathFourBar& four_bar) {
  std::vector<PathFourBar> cognates;
  if (four_bar.input.type != DyadType::kRR || four_bar.output.type != DyadType::kRR) {
    return cognates;
  }
  using Complex = std::complex<double>;
  const auto complex = [](const Eigen::Vector2d& point) { return Complex(point.x(), point.y()); };
  const auto point = [](const Complex& z) { return Eigen::Vector2d(z.real(), z.imag()); };
  const Complex a0 = complex(four_bar.input.fixed_pivot), a = complex(four_bar.input.moving_pivot);
  const Complex b0 = complex(four_bar.output.fixed_pivot);
  const Complex b = complex(four_bar.output.moving_pivot), p = complex(four_bar.coupler_point);
  // The coupler triangle A B P as p = a + z (b - a); the third fixed pivot makes A0 B0 C0
  // similar to it. Each cognate's crank is parallel to a side of the coupler (a parallelogram
  // with the original links) and its coupler is a triangle similar to A B P.
  const Complex z = (p - a) / (b - a), z2 = 1.0 - z;  // z2 = (p - b) / (a - b)
  const Complex c0 = a0 + z * (b0 - a0);
  const Complex e1 = a0 + (p - a), f1 = e1 + z * (a - a0);
  const Complex g1 = b0 + (p - b), h1 = g1 + z2 * (b - b0);
  const auto make = [&](const Complex& fixed_in, const Complex& moving_in, const Complex& fixed_out,
                        const Complex& moving_out) {
    PathFourBar cognate;
    cognate.input =
        PlanarDyad::RR(point(fixed_in), point(moving_in), std::abs(moving_in - fixed_in));
    cognate.output =
        PlanarDyad::RR(point(fixed_out), point(moving_out), std::abs(moving_out - fixed_out));
    cognate.coupler_point = four_bar.coupler_point;
    return cognate;
  };
  for (const auto& [fixed_1, moving_1, fixed_2, moving_2] :
       {std::array<Complex, 4>{a0, a, b0, b}, std::array<Complex, 4>{a0, e1, c0, f1},
        std::array<Complex, 4>{b0, g1, c0, h1}}) {
    cognates.push_back(make(fixed_1, moving_1, fixed_2, moving_2));
    cognates.push_back(make(fixed_2, moving_2, fixed_1, moving_1));
  }
  return cognates;
}

double CurveDistance(const PathFourBar& a, const PathFourBar& b) {
  if (a.input.type != b.input.type || a.output.type != b.output.type) {
    return std::numeric_limits<double>::infinity();
  }
  const auto apart = [&a](const PathFourBar& c) {
    return std::max({(a.input.fixed_pivot - c.input.fixed_pivot).norm(),
                     (a.input.moving_pivot - c.input.moving_pivot).norm(),
                     (a.output.fixed_pivot - c.output.fixed_pivot).norm(),
                     (a.output.moving_pivot - c.output.moving_pivot).norm(),
                     (a.output.LineFoot() - c.output.LineFoot()).norm(),
                     (a.coupler_point - c.coupler_point).norm()});
  };
  const std::vector<PathFourBar> cognates = CurveCognates(b);
  if (cognates.empty()) return apart(b);
  double nearest = std::numeric_limits<double>::infinity();
  for (const PathFourBar& cognate : cognates) nearest = std::min(nearest, apart(cognate));
  return nearest;
}

std::vector<PlanarPose> CouplerCycle(const PathFourBar& four_bar, double length, int samples) {
  std::vector<PlanarPose> curve;
  if (four_bar.input.type != DyadType::kRR || samples < 4) return curve;
  const double tolerance = 1e-9 * length;
  const double alpha0 = FirstCrankAngle(four_bar);
  std::vector<PlanarPose> first;
  const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha0, tolerance, &first);
  if (count == 0) return curve;
  const int label = count == 2 && PoseError(first[1], PlanarPose(), length) <
                                      PoseError(first[0], PlanarPose(), length)
                        ? 1
                        : 0;
  const double step = 2.0 * kPi / samples;
  // Forward from the first point's crank angle while the output closes.
  int forward = 0;
  while (forward < samples &&
         Configuration(four_bar, alpha0 + (forward + 1) * step, label, tolerance)) {
    ++forward;
  }
  if (forward == samples) {
    for (int k = 0; k <= samples; ++k) {
      curve.push_back(*Configuration(four_bar, alpha0 + k * step, label, tolerance));
    }
    return curve;
  }
  int backward = 0;
  while (backward < samples &&
         Configuration(four_bar, alpha0 - (backward + 1) * step, label, tolerance)) {
    ++backward;
  }
  // The crank's reachable arc on this assembly, then back on the other one.
  for (int k = -backward; k <= forward; ++k) {
    curve.push_back(*Configuration(four_bar, alpha0 + k * step, label, tolerance));
  }
  for (int k = forward; k >= -backward; --k) {
    const std::optional<PlanarPose> pose =
        Configuration(four_bar, alpha0 + k * step, 1 - label, tolerance);
    if (pose) curve.push_back(*pose);
  }
  if (!curve.empty()) curve.push_back(curve.front());
  return curve;
}

Similarity2 ScaledPointFrame(const std::vector<Eigen::Vector2d>& points, double length) {
  Similarity2 frame;
  frame.scale = length;
  for (const Eigen::Vector2d& point : points) {
    frame.translation += point / static_cast<double>(points.size());
  }
  return frame;
}

PathFourBar TransformPathFourBar(const PathFourBar& four_bar, const Similarity2& similarity,
                                 bool mirror) {
  const auto reflect = [mirror](const Eigen::Vector2d& p) {
    return Eigen::Vector2d(p.x(), mirror ? -p.y() : p.y());
  };
  const auto dyad = [&](const PlanarDyad& in) {
    PlanarDyad out = in;
    out.fixed_pivot = similarity.Apply(reflect(in.fixed_pivot));
    out.moving_pivot = similarity.Apply(reflect(in.moving_pivot));
    out.line_point = similarity.Apply(reflect(in.line_point));
    out.line_direction = similarity.ApplyToDirection(reflect(in.line_direction));
    out.radius = in.radius * similarity.scale;
    return out;
  };
  PathFourBar out;
  out.input = dyad(four_bar.input);
  out.output = dyad(four_bar.output);
  out.coupler_point = similarity.Apply(reflect(four_bar.coupler_point));
  return out;
}

PathFourBar MoveToFirstConfiguration(const PathFourBar& four_bar, const PlanarPose& first_pose) {
  PathFourBar moved = four_bar;
  moved.input.moving_pivot = first_pose.ToFixed(four_bar.input.moving_pivot);
  if (four_bar.output.type == DyadType::kRP) {
    moved.output.line_point = first_pose.ToFixed(four_bar.output.line_point);
    moved.output.line_direction = first_pose.DirectionToFixed(four_bar.output.line_direction);
  } else {
    moved.output.moving_pivot = first_pose.ToFixed(four_bar.output.moving_pivot);
  }
  moved.coupler_point = first_pose.ToFixed(four_bar.coupler_point);
  return moved;
}

}  // namespace linkfit
