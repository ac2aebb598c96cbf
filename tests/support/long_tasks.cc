#include "tests/support/long_tasks.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linkfit::testing {
namespace {

// The four-bar at crank angle phi: the crank pin, the coupler's angle, the coupler point and the
// rocker's angle.
struct FourBarPosition {
  Eigen::Vector2d pin, point;
  double coupler = 0.0, rocker = 0.0;
};

FourBarPosition Position(double phi) {
  FourBarPosition at;
  at.pin = Eigen::Vector2d(std::cos(phi), std::sin(phi));
  const Eigen::Vector2d to = Eigen::Vector2d(4.0, 0.0) - at.pin;
  const double d = to.norm(), l = (3.5 * 3.5 - 9.0 + d * d) / (2.0 * d);
  const double h = std::sqrt(std::max(3.5 * 3.5 - l * l, 0.0));
  const Eigen::Vector2d e = to / d;
  const Eigen::Vector2d pin2 = at.pin + l * e + h * Eigen::Vector2d(-e.y(), e.x());
  at.coupler = std::atan2(pin2.y() - at.pin.y(), pin2.x() - at.pin.x());
  at.point = at.pin + 1.5 * Eigen::Vector2d(std::cos(at.coupler + 0.5), std::sin(at.coupler + 0.5));
  at.rocker = std::atan2(pin2.y(), pin2.x() - 4.0);
  return at;
}

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.8f", value);
  return text;
}

std::string Degrees(double radians) { return Number(radians * 180.0 / M_PI); }

std::string Spatial(double t, bool spherical) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(t, Eigen::Vector3d(std::cos(0.3 * t), std::sin(0.3 * t), 1.0).normalized())
          .toRotationMatrix();
  const Eigen::Vector3d center(1.0, 2.0, 0.5);
  const Eigen::Vector3d translation =
      spherical ? Eigen::Vector3d(center - rotation * center)
                : Eigen::Vector3d(std::cos(t) + 0.2 * t, std::sin(2.0 * t), 0.3 * t);
  std::string text = "{\"rotation\": [";
  for (int r = 0; r < 3; ++r) {
    text += std::string(r ? ", " : "") + "[" + Number(rotation(r, 0)) + ", " +
            Number(rotation(r, 1)) + ", " + Number(rotation(r, 2)) + "]";
  }
  return text + "], \"translation\": [" + Number(translation.x()) + ", " + Number(translation.y()) +
         ", " + Number(translation.z()) + "]}";
}

}  // namespace

const std::vector<std::string>& LongTaskKinds() {
  static const std::vector<std::string> kinds = {"motion",   "timed path", "untimed path",
                                                 "function", "spherical",  "spatial"};
  return kinds;
}

std::string LongTaskText(const std::string& kind, int count, const std::string& effort) {
  std::string head, items;
  if (kind == "motion") {
    head = R"("problem": "motion")";
    items = "poses";
  } else if (kind == "timed path" || kind == "untimed path") {
    head = R"("problem": "path")";
    items = "points";
  } else if (kind == "function") {
    head = R"("problem": "function")";
    items = "pairs";
  } else if (kind == "spherical" || kind == "spatial") {
    head = R"("problem": "motion", "space": "spatial")";
    items = "poses";
  } else {
    throw std::invalid_argument("LongTaskText: unknown kind " + kind);
  }
  std::string text =
      "{" + head + ", \"options\": {\"effort\": \"" + effort + "\"}, \"" + items + "\": [";
  text.reserve(static_cast<size_t>(count) * (kind == "spherical" || kind == "spatial" ? 180 : 60));
  for (int k = 0; k < count; ++k) {
    if (k > 0) text += ", ";
    const double phi = 0.95 * 2.0 * M_PI * k / count + 0.001;
    const FourBarPosition at = Position(phi);
    if (kind == "motion") {
      text += "{\"x\": " + Number(at.pin.x()) + ", \"y\": " + Number(at.pin.y()) +
              ", \"theta_deg\": " + Degrees(at.coupler) + "}";
    } else if (kind == "timed path" || kind == "untimed path") {
      text += "{\"x\": " + Number(at.point.x()) + ", \"y\": " + Number(at.point.y());
      if (kind == "timed path") text += ", \"input_deg\": " + Degrees(phi);
      text += "}";
    } else if (kind == "function") {
      text += "{\"input_deg\": " + Degrees(phi) + ", \"output_deg\": " + Degrees(at.rocker) + "}";
    } else {
      text += Spatial(0.9 * 2.0 * M_PI * k / count, kind == "spherical");
    }
  }
  return text + "]}";
}

}  // namespace linkfit::testing
