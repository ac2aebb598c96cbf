#include "apps/analysis_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace linkfit {
namespace {

using Json = nlohmann::ordered_json;

// The panels' size and margins (px).
constexpr double kWidth = 720.0, kPanelHeight = 170.0, kLeft = 70.0, kRight = 110.0, kTop = 28.0,
                 kBottom = 22.0;
constexpr const char* kDeadPoint = "#7f7f7f";

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return text;
}

std::string Coordinate(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", value);
  return text;
}

std::string Escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else {
      out += c;
    }
  }
  return out;
}

struct Series {
  std::string label, colour;
  std::vector<double> values;  // NaN where null
};

std::vector<double> Values(const Json& array) {
  std::vector<double> values;
  for (const Json& value : array) {
    if (value.is_array()) {  // a vector (a spherical coupler's angular velocity): its length
      double squared = 0.0;
      for (const Json& c : value)
        squared += c.is_number() ? c.get<double>() * c.get<double>() : NAN;
      values.push_back(std::sqrt(squared));
      continue;
    }
    values.push_back(value.is_number() ? value.get<double>() : std::nan(""));
  }
  return values;
}

// One panel at vertical offset `top`: its series against x, the dead points as dashed lines.
std::string Panel(double top, const std::string& title, const std::string& unit,
                  const std::vector<double>& x, const std::vector<Series>& series,
                  const std::vector<double>& dead, double x_low, double x_high) {
  double low = INFINITY, high = -INFINITY;
  for (const Series& s : series) {
    for (const double v : s.values) {
      if (std::isfinite(v)) {
        low = std::min(low, v);
        high = std::max(high, v);
      }
    }
  }
  if (!std::isfinite(low)) low = high = 0.0;
  if (high - low < 1e-12 * std::max(1.0, std::abs(high))) {
    low -= 1.0;
    high += 1.0;
  }
  const double plot_width = kWidth - kLeft - kRight, plot_height = kPanelHeight - kTop - kBottom;
  const auto px = [&](double value) {
    return kLeft + (value - x_low) / (x_high - x_low) * plot_width;
  };
  const auto py = [&](double value) {
    return top + kTop + (high - value) / (high - low) * plot_height;
  };
  std::string svg = "<g>\n<text x=\"" + Coordinate(kLeft) + "\" y=\"" + Coordinate(top + 16) +
                    "\" font-size=\"12\">" + Escaped(title) + " (" + Escaped(unit) + ")</text>\n";
  svg += "<rect x=\"" + Coordinate(kLeft) + "\" y=\"" + Coordinate(top + kTop) + "\" width=\"" +
         Coordinate(plot_width) + "\" height=\"" + Coordinate(plot_height) +
         "\" fill=\"none\" stroke=\"#999\"/>\n";
  // The range's ends at the panel's top and bottom edges.
  for (const auto& [value, shift] : {std::pair{high, 10.0}, std::pair{low, -2.0}}) {
    svg += "<text x=\"" + Coordinate(kLeft - 4) + "\" y=\"" + Coordinate(py(value) + shift) +
           "\" font-size=\"10\" text-anchor=\"end\">" + Number(value) + "</text>\n";
  }
  if (low < 0.0 && high > 0.0) {
    svg += "<line x1=\"" + Coordinate(kLeft) + "\" x2=\"" + Coordinate(kLeft + plot_width) +
           "\" y1=\"" + Coordinate(py(0.0)) + "\" y2=\"" + Coordinate(py(0.0)) +
           "\" stroke=\"#ddd\"/>\n";
  }
  for (size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    std::string points;
    for (size_t i = 0; i < x.size() && i < s.values.size(); ++i) {
      if (!std::isfinite(s.values[i])) continue;
      points += Coordinate(px(x[i])) + "," + Coordinate(py(s.values[i])) + " ";
    }
    svg += "<polyline class=\"series\" data-label=\"" + Escaped(s.label) +
           "\" fill=\"none\" stroke=\"" + s.colour + "\" stroke-width=\"1.4\" points=\"" + points +
           "\"/>\n";
    svg += "<text x=\"" + Coordinate(kWidth - kRight + 8) + "\" y=\"" +
           Coordinate(top + kTop + 12 + 14 * k) + "\" font-size=\"11\" fill=\"" + s.colour + "\">" +
           Escaped(s.label) + "</text>\n";
  }
  for (const double at : dead) {
    svg += "<line class=\"dead-point\" x1=\"" + Coordinate(px(at)) + "\" x2=\"" +
           Coordinate(px(at)) + "\" y1=\"" + Coordinate(top + kTop) + "\" y2=\"" +
           Coordinate(top + kTop + plot_height) + "\" stroke=\"" + kDeadPoint +
           "\" stroke-dasharray=\"4 3\"/>\n";
  }
  return svg + "</g>\n";
}

}  // namespace

std::string AnalysisSvg(const std::string& analysis_json) {
  const Json analysis = Json::parse(analysis_json);
  const std::vector<double> x = Values(analysis["input_deg"]);
  double x_low = INFINITY, x_high = -INFINITY;
  for (const double v : x) {
    x_low = std::min(x_low, v);
    x_high = std::max(x_high, v);
  }
  // The dead points next to the samples (a rocker's range sampled whole: within a tenth of the
  // span beyond them); those far off (a part of the range sampled) are left out of the chart.
  std::vector<double> dead;
  const double reach = 0.1 * (x_high - x_low);
  for (const Json& point : analysis["dead_points"]) {
    const Json& at = point.contains("input_deg") ? point["input_deg"] : point["input_position"];
    if (!at.is_number()) continue;
    const double v = at.get<double>();
    if (v < x_low - reach || v > x_high + reach) continue;
    dead.push_back(v);
  }
  for (const double v : dead) {
    x_low = std::min(x_low, v);
    x_high = std::max(x_high, v);
  }
  if (!(x_high > x_low)) {
    x_low -= 1.0;
    x_high += 1.0;
  }
  const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd"};
  struct Kind {
    const char* title;
    const char* unit;
    const char* angle_key;
    const char* slider_key;
  };
  // A slider's position and rates share the panels (their units said where there is one).
  bool slider = false;
  for (const auto& [name, link] : analysis["links"].items()) slider |= link.contains("position");
  const Kind kinds[] = {
      {"link angles", slider ? "deg; a slider: length" : "deg", "angle_deg", "position"},
      {"angular velocities", slider ? "rad/s; a slider: length/s" : "rad/s", "angular_velocity",
       "velocity"},
      {"angular accelerations", slider ? "rad/s^2; a slider: length/s^2" : "rad/s^2",
       "angular_acceleration", "acceleration"}};
  std::string body;
  double top = 30.0;
  for (const Kind& kind : kinds) {
    std::vector<Series> series;
    int c = 0;
    for (const auto& [name, link] : analysis["links"].items()) {
      const char* key = link.contains(kind.angle_key) ? kind.angle_key : kind.slider_key;
      series.push_back({name, colours[c++ % 5], Values(link[key])});
    }
    body += Panel(top, kind.title, kind.unit, x, series, dead, x_low, x_high);
    top += kPanelHeight;
  }
  const bool force_input = analysis.contains("input_force");
  if (analysis.contains("input_torque") || force_input) {
    // Its unit where the analysis says (a length unit given), else force times length.
    std::string unit = force_input ? "force" : "force x length";
    if (!force_input && analysis.contains("units") && analysis["units"].contains("torque")) {
      unit = analysis["units"]["torque"].get<std::string>();
    }
    const char* key = force_input ? "input_force" : "input_torque";
    body += Panel(
        top,
        std::string(force_input ? "input force" : "input torque") + " holding the load, peak " +
            Number(analysis[force_input ? "peak_input_force" : "peak_input_torque"].get<double>()),
        unit, x, {{force_input ? "force" : "torque", "#333333", Values(analysis[key])}}, dead,
        x_low, x_high);
  } else {
    body += Panel(top, "transmission angle", "deg", x,
                  {{"transmission", "#333333", Values(analysis["transmission_angle_deg"])}}, dead,
                  x_low, x_high);
  }
  top += kPanelHeight;
  const std::string height = Coordinate(top + 30.0);
  std::string svg =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
      Coordinate(kWidth) + "\" height=\"" + height + "\" viewBox=\"0 0 " + Coordinate(kWidth) +
      " " + height +
      "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" "
      "fill=\"white\"/>\n<text x=\"" +
      Coordinate(kLeft) + "\" y=\"18\" font-size=\"13\">" +
      Escaped(analysis.value("type", std::string("four-bar"))) + " " +
      Number(analysis["mechanism"].get<double>()) + ": against the input" +
      (analysis.contains("input_position") ? std::string(" position")
                                           : std::string(" angle, deg")) +
      " (dead points dashed)</text>\n";
  svg += body;
  // The input's values under the last panel: five ticks from end to end.
  const double plot_width = kWidth - kLeft - kRight;
  for (int k = 0; k <= 4; ++k) {
    const double at = x_low + (x_high - x_low) * k / 4.0;
    svg += "<text x=\"" + Coordinate(kLeft + plot_width * k / 4.0) + "\" y=\"" +
           Coordinate(top - kBottom + 14) + "\" font-size=\"10\" text-anchor=\"middle\">" +
           Number(at) + "</text>\n";
  }
  const bool position = analysis.contains("input_position");
  svg += "<text x=\"" + Coordinate(kLeft) + "\" y=\"" + Coordinate(top + 14) +
         "\" font-size=\"11\">input " + (position ? "position " : "angle ") + Number(x_low) +
         " to " + Number(x_high) + (position ? "" : " deg") + "</text>\n</svg>\n";
  return svg;
}

}  // namespace linkfit
