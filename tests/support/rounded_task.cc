#include "tests/support/rounded_task.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "fitting/model_choice.h"
#include "fitting/timed_path.h"
#include "lib/task_io.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/random_path.h"
#include "tests/support/random_spatial.h"

namespace linkfit::testing {
namespace {

constexpr double kDegree = M_PI / 180.0;

std::string Array(const std::vector<double>& values, int digits) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + Printed(values[i], digits);
  return out + "]";
}

std::string Items(const char* key, const std::vector<std::string>& items) {
  std::string out = std::string("\"") + key + "\": [";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ",\n  " : "\n  ") + items[i];
  return out + "]";
}

}  // namespace

std::string Printed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%#.*g", digits, value);
  std::string text = buffer;
  // "-157." is not JSON: exponent form keeps the digits ("-1.57e+02").
  if (text.back() == '.') {
    std::snprintf(buffer, sizeof(buffer), "%.*e", digits - 1, value);
    text = buffer;
  }
  return text;
}

std::string PlanarMotionText(const std::vector<PlanarPose>& poses, int digits) {
  std::vector<std::string> items;
  for (const PlanarPose& pose : poses) {
    items.push_back("{\"x\": " + Printed(pose.origin_in_fixed.x(), digits) +
                    ", \"y\": " + Printed(pose.origin_in_fixed.y(), digits) +
                    ", \"theta_deg\": " + Printed(pose.theta / kDegree, digits) + "}");
  }
  return "{\"problem\": \"motion\", " + Items("poses", items) + "}";
}

std::string SpatialMotionText(const std::vector<DualQuaternion>& poses, int digits,
                              SpatialForm form) {
  std::vector<std::string> items;
  for (const DualQuaternion& pose : poses) {
    const Eigen::Vector3d d = pose.Translation();
    const std::string translation = "\"translation\": " + Array({d.x(), d.y(), d.z()}, digits);
    const Eigen::Matrix3d rotation = pose.Rotation();
    switch (form) {
      case SpatialForm::kDualQuaternion:
        items.push_back("{\"q\": " + Array({pose.q[0], pose.q[1], pose.q[2], pose.q[3]}, digits) +
                        ", \"g\": " + Array({pose.g[0], pose.g[1], pose.g[2], pose.g[3]}, digits) +
                        "}");
        break;
      case SpatialForm::kRotationMatrix: {
        std::string rows;
        for (int row = 0; row < 3; ++row) {
          rows += (row ? ", " : "") +
                  Array({rotation(row, 0), rotation(row, 1), rotation(row, 2)}, digits);
        }
        items.push_back("{\"rotation\": [" + rows + "], " + translation + "}");
        break;
      }
      case SpatialForm::kAxisAngle: {
        Eigen::Vector3d axis;
        double angle;
        pose.ToAxisAngle(&axis, &angle);
        items.push_back("{\"axis\": " + Array({axis.x(), axis.y(), axis.z()}, digits) +
                        ", \"angle_deg\": " + Printed(angle / kDegree, digits) + ", " +
                        translation + "}");
        break;
      }
      case SpatialForm::kEulerZYX: {
        // R = R_z(a) R_y(b) R_x(c).
        const double b = std::asin(std::clamp(-rotation(2, 0), -1.0, 1.0));
        const double a = std::atan2(rotation(1, 0), rotation(0, 0));
        const double c = std::atan2(rotation(2, 1), rotation(2, 2));
        items.push_back(
            "{\"euler_deg\": " + Array({a / kDegree, b / kDegree, c / kDegree}, digits) +
            ", \"euler_axes\": \"ZYX\", " + translation + "}");
        break;
      }
    }
  }
  return "{\"problem\": \"motion\", \"space\": \"spatial\", " + Items("poses", items) + "}";
}

std::string PathText(const std::vector<Eigen::Vector2d>& points,
                     const std::vector<double>& input_angles, int digits) {
  std::vector<std::string> items;
  for (size_t i = 0; i < points.size(); ++i) {
    std::string item =
        "{\"x\": " + Printed(points[i].x(), digits) + ", \"y\": " + Printed(points[i].y(), digits);
    if (!input_angles.empty())
      item += ", \"input_deg\": " + Printed(input_angles[i] / kDegree, digits);
    items.push_back(item + "}");
  }
  return "{\"problem\": \"path\", " + Items("points", items) + "}";
}

Task ReadRounded(const std::string& text, Effort effort) {
  Task task = ParseTask(text, "rounded");
  task.effort = effort;
  return task;
}

std::string ParseErrorOf(const std::string& text) {
  try {
    ParseTask(text, "task.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "<no error>";
}

void TimedPoints(const Task& task, std::vector<Eigen::Vector2d>* points,
                 std::vector<double>* input_angles) {
  points->clear();
  input_angles->clear();
  for (const TimedPoint& point : task.points) {
    points->push_back(point.point_in_fixed);
    if (point.input_angle) input_angles->push_back(*point.input_angle);
  }
}

bool SaysTooCoarse(const std::vector<std::string>& notes) {
  return std::any_of(notes.begin(), notes.end(), [](const std::string& note) {
    return note.find("means nothing") != std::string::npos ||
           note.find("not determined by the points at this precision") != std::string::npos ||
           note.find("rounding of the data can turn two real dyads into a complex pair") !=
               std::string::npos ||
           note.find("dependent within the data's precision") != std::string::npos ||
           note.find("rank-deficient") != std::string::npos;
  });
}

namespace {

// RoundedRecovery for any kind of dyad or four-bar: `design(report)` the listed one,
// `distance(design, target, scale)` relative to the target's size `scale = size(target)`; the
// bounds, and `floor(scale)` added to them for rounding, in length units.
template <typename Dyad, typename Report, typename Design, typename Distance, typename Size,
          typename Floor>
double Recovery(const std::vector<Dyad>& targets, const std::vector<Report>& found,
                const Design& design, const Distance& distance, const Size& size,
                const Floor& floor, bool* rough) {
  double best = std::numeric_limits<double>::infinity();
  double nearest = std::numeric_limits<double>::infinity();
  bool nearest_rough = false;
  for (const Dyad& target : targets) {
    const double scale = size(target);
    for (const Report& report : found) {
      if (!report.error_bound) continue;
      const double relative = distance(design(report), target, scale);
      if (!std::isfinite(relative)) continue;
      const double bound = *report.error_bound;
      if (relative < nearest) {
        nearest = relative;
        nearest_rough = !(bound < kRoughBound * scale);
      }
      if (!std::isfinite(bound)) continue;
      best = std::min(best, relative / ((2.0 * bound + floor(scale)) / scale));
    }
  }
  if (rough != nullptr && nearest_rough && !(best <= 1.0)) *rough = true;
  return best;
}

}  // namespace

double RoundedRecovery(const PlanarDyad& expected, const std::vector<DyadReport>& found,
                       const DataPrecision& precision, const std::vector<PlanarPose>& poses,
                       bool* rough) {
  std::vector<PlanarDyad> targets = {expected};
  PlanarDyad simpler;
  if (SimplerModel(expected, poses, precision, CharacteristicLength(poses), &simpler)) {
    targets.push_back(simpler);
  }
  return Recovery(
      targets, found, [](const DyadReport& report) -> const PlanarDyad& { return report.dyad; },
      [](const PlanarDyad& dyad, const PlanarDyad& target, double scale) {
        return DyadDistance(dyad, target, scale);
      },
      [&](const PlanarDyad& target) { return DyadScale(target, poses); },
      [](double scale) { return 1e-9 * scale; }, rough);
}

double RoundedRecovery(const SpatialDyad& expected, const std::vector<SpatialDyadReport>& found,
                       const DataPrecision& precision, const std::vector<DualQuaternion>& poses,
                       double length, bool* rough) {
  std::vector<SpatialDyad> targets = {expected};
  SpatialDyad plane;
  if (SimplerModel(expected, poses, precision, length, &plane)) targets.push_back(plane);
  return Recovery(
      targets, found,
      [](const SpatialDyadReport& report) -> const SpatialDyad& { return report.dyad; },
      [](const SpatialDyad& dyad, const SpatialDyad& target, double) {
        return SpatialDyadDistance(dyad, target);
      },
      [](const SpatialDyad& target) { return SpatialDyadSize(target); },
      [length](double) { return 1e-9 * length; }, rough);
}

bool MeetsPointsWithinPrecision(const PathMechanismReport& report,
                                const std::vector<Eigen::Vector2d>& points,
                                const DataPrecision& precision) {
  if (!report.max_point_error) return false;
  const double length = PathLength(points);
  double reach = 0.0;
  for (const Eigen::Vector2d& point : points) {
    reach = std::max(reach, (point - report.design.input.fixed_pivot).norm());
  }
  // Not below the exact solver's own check (fitting/timed_path.h verify_tolerance).
  return *report.max_point_error <=
         std::max(1e-8 * length, kModelUnits * PointUncertainty(precision, reach, length, 2));
}

double RoundedPathRecovery(const PathFourBar& expected, const PathResult& result,
                           const std::vector<Eigen::Vector2d>& points,
                           const std::vector<double>& input_angles, bool* rough) {
  std::vector<PathFourBar> targets = {expected};
  if (result.timing == "free") {
    const std::vector<PathFourBar> cognates = CurveCognates(expected);
    if (!cognates.empty()) targets = cognates;
  }
  const double length = PathLength(points);
  // Timed: the slider reading of the generating output circle on its coupler poses, when it
  // fits them within their precision (the path solver's model choice, CouplerPosePrecision).
  if (expected.output.type == DyadType::kRR && input_angles.size() == points.size()) {
    const PathFourBarAnalysis analysis = AnalyzePathFourBar(expected, points, input_angles, length);
    const double link = (expected.coupler_point - expected.input.moving_pivot).norm();
    PathFourBar simpler = expected;
    if (analysis.configurations.size() == points.size() &&
        SimplerModel(expected.output, analysis.configurations,
                     CouplerPosePrecision(result.precision, expected.input.radius, link), length,
                     &simpler.output)) {
      targets.push_back(simpler);
    }
  }
  // Only four-bars that meet the points within their precision can be the answer (the
  // generating one does): a listed four-bar missing them by more is a search miss, whose
  // rough bound says nothing about the data.
  std::vector<PathMechanismReport> fitting;
  for (const PathMechanismReport& report : result.mechanisms) {
    if (MeetsPointsWithinPrecision(report, points, result.precision)) fitting.push_back(report);
  }
  const double best = Recovery(
      targets, fitting,
      [](const PathMechanismReport& report) -> const PathFourBar& { return report.design; },
      [](const PathFourBar& four_bar, const PathFourBar& target, double scale) {
        return PathFourBarDistance(four_bar, target, scale);
      },
      [&](const PathFourBar& target) { return PathFourBarSize(target, points, length); },
      [](double scale) { return 1e-9 * scale; }, rough);
  // An output of another type on the generating crank and coupler point (within its bound),
  // whose rough bound says the points do not determine the output: the data cannot give its
  // type either.
  if (rough != nullptr && !(best <= 1.0)) {
    for (const PathFourBar& target : targets) {
      const double scale = PathFourBarSize(target, points, length);
      for (const PathMechanismReport& report : fitting) {
        if (report.design.output.type == target.output.type || !report.error_bound) continue;
        const double bound = *report.error_bound;
        const double crank =
            std::max(DyadDistance(report.design.input, target.input, scale),
                     (report.design.coupler_point - target.coupler_point).norm() / scale);
        if (!(bound < kRoughBound * scale) && crank * scale <= 2.0 * bound) *rough = true;
      }
    }
  }
  return best;
}

}  // namespace linkfit::testing
