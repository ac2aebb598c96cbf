#include "lib/result_summary.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace linkfit {
namespace {

using Json = nlohmann::ordered_json;

std::string Number(const Json& value) {
  if (!value.is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value.get<double>());
  return text;
}

std::string Joined(const Json& list) {
  if (!list.is_array() || list.empty()) return "-";
  std::string out;
  for (const Json& item : list) {
    if (!item.is_string()) continue;
    out += (out.empty() ? "" : ",") + item.get<std::string>();
  }
  return out.empty() ? "-" : out;
}

// The fit of a mechanism: its RMS error where least squares gave one, else its largest; and the
// column's name.
std::string Fit(const std::string& problem, const Json& mechanism, std::string* name) {
  struct Field {
    const char* rms;
    const char* max;
    const char* label;  // "<kind> error[, unit]"
  };
  const Field field = problem == "path" ? Field{"rms_point_error", "max_point_error", "point error"}
                      : problem == "function"
                          ? Field{"rms_angle_error_deg", "max_angle_error_deg", "pair error, deg"}
                          : Field{"rms_pose_error", "max_pose_error", "pose error"};
  if (mechanism.contains(field.rms)) {
    *name = std::string("RMS ") + field.label;
    return Number(mechanism[field.rms]);
  }
  *name = std::string("largest ") + field.label;
  return mechanism.contains(field.max) ? Number(mechanism[field.max]) : "-";
}

std::string WorstTransmission(const Json& mechanism) {
  if (mechanism.contains("transmission_angle_deg") &&
      mechanism["transmission_angle_deg"].is_array()) {
    return Number(mechanism["transmission_angle_deg"][0]);
  }
  if (mechanism.contains("transmission_angle_min_deg")) {
    return Number(mechanism["transmission_angle_min_deg"]);
  }
  return "-";
}

// The other link measures: a slider's offset, the coupler point from the input pin.
std::string Other(const Json& links) {
  std::string out;
  for (const char* side : {"input_slider_offset", "output_slider_offset"}) {
    if (links.contains(side))
      out += std::string(out.empty() ? "" : " ") + "e=" + Number(links[side]);
  }
  if (links.contains("coupler_point")) {
    const Json& point = links["coupler_point"];
    out += std::string(out.empty() ? "" : " ") + "p=" + Number(point["distance"]) + "@" +
           Number(point["angle_deg"]);
  }
  return out.empty() ? "-" : out;
}

void Row(const std::vector<std::string>& cells, const std::vector<size_t>& widths,
         std::string* out) {
  for (size_t k = 0; k < cells.size(); ++k) {
    std::string cell = cells[k];
    if (k + 1 < cells.size() && cell.size() < widths[k]) cell.append(widths[k] - cell.size(), ' ');
    *out += (k ? "  " : "") + cell;
  }
  *out += "\n";
}

// The six-bars of a "linkage": "six-bar" result (lib/result_io.cc SixBarToJson), one row each.
void SixBarTable(const Json& six_bars, std::string* out) {
  const auto short_name = [](const Json& body) {
    std::string name = body.is_string() ? body.get<std::string>() : "-";
    return name == "task body" ? std::string("task") : name;
  };
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < six_bars.size(); ++i) {
    const Json& six_bar = six_bars[i];
    const Json lengths = six_bar.value("link_lengths", Json::object());
    const Json joints = six_bar.value("joints_at_first_pose", Json::object());
    const Json links = joints.value("links", Json::array());
    const auto link = [&](size_t l, const char* name) {
      std::string cell = lengths.contains(name) ? Number(lengths[name]) : "-";
      if (links.is_array() && l < links.size()) {
        cell += " " + short_name(links[l].value("from", Json())) + "-" +
                short_name(links[l].value("to", Json()));
      }
      return cell;
    };
    std::string transmission = "-";
    if (six_bar.contains("transmission_angle_min_deg") &&
        six_bar["transmission_angle_min_deg"].is_array() &&
        six_bar["transmission_angle_min_deg"].size() == 2) {
      transmission = Number(six_bar["transmission_angle_min_deg"][0]) + ", " +
                     Number(six_bar["transmission_angle_min_deg"][1]);
    }
    rows.push_back(
        {std::to_string(i + 1), six_bar.value("topology", "-"), six_bar.value("input", "-"),
         lengths.contains("upper_link") ? Number(lengths["upper_link"]) : "-",
         lengths.contains("forearm") ? Number(lengths["forearm"]) : "-", link(0, "first_link"),
         link(1, "second_link"),
         six_bar.contains("rms_pose_error") ? Number(six_bar["rms_pose_error"])
                                            : Number(six_bar.value("max_pose_error", Json())),
         transmission, six_bar.value("input_rotates_fully", false) ? "yes" : "no",
         six_bar.contains("error_bound") ? Number(six_bar["error_bound"]) : "-",
         Joined(six_bar.value("defects", Json())), Joined(six_bar.value("violates", Json()))});
  }
  const std::vector<std::string> header = {
      "#",           "topology",       "input",
      "upper link",  "forearm",        "first link",
      "second link", "RMS pose error", "least transmission (loops), deg",
      "full turn",   "error bound",    "defects",
      "violates"};
  std::vector<size_t> widths(header.size(), 0);
  for (size_t k = 0; k < header.size(); ++k) widths[k] = header[k].size();
  for (const std::vector<std::string>& row : rows) {
    for (size_t k = 0; k < row.size(); ++k) widths[k] = std::max(widths[k], row[k].size());
  }
  Row(header, widths, out);
  for (const std::vector<std::string>& row : rows) Row(row, widths, out);
  *out +=
      "links: lengths; an RR link also names the two bodies it joins (first = the first link, "
      "a new crank)\n";
}

}  // namespace

std::string ResultSummary(const std::string& result_json, const std::string& title) {
  Json result;
  try {
    result = Json::parse(result_json);
  } catch (const Json::exception& error) {
    throw std::invalid_argument(std::string("not a result (JSON): ") + error.what());
  }
  if (!result.is_object() || !result.contains("mechanisms") || !result["mechanisms"].is_array()) {
    throw std::invalid_argument("not a linkfit result: no \"mechanisms\" list");
  }
  const std::string problem = result.value("problem", "motion");
  if (result.contains("six_bars") && result["six_bars"].is_array()) {
    const Json& six_bars = result["six_bars"];
    int sound = 0;
    for (const Json& six_bar : six_bars) {
      bool kinematic = false;
      for (const Json& defect : six_bar.value("defects", Json::array())) {
        kinematic =
            kinematic || (defect.is_string() && defect.get<std::string>() != "transmission");
      }
      sound += kinematic ? 0 : 1;
    }
    std::string out = title.empty() ? "" : title + ": ";
    out += problem + " (planar), six-bars, " + result.value("method", std::string("exact")) + ": " +
           std::to_string(six_bars.size()) + " listed, " + std::to_string(sound) +
           " without a kinematic defect";
    if (result.contains("scale")) out += "; L = " + Number(result["scale"]);
    out += "\n";
    if (six_bars.empty()) {
      out += "(no six-bar listed)\n";
    } else {
      SixBarTable(six_bars, &out);
    }
    for (const Json& note : result.value("notes", Json::array())) {
      if (note.is_string()) out += "note: " + note.get<std::string>() + "\n";
    }
    return out;
  }
  const Json& mechanisms = result["mechanisms"];
  int sound = 0;
  for (const Json& mechanism : mechanisms) {
    bool kinematic = false;
    for (const Json& defect : mechanism.value("defects", Json::array())) {
      kinematic = kinematic || (defect.is_string() && defect.get<std::string>() != "transmission");
    }
    sound += kinematic ? 0 : 1;
  }
  std::string out = title.empty() ? "" : title + ": ";
  out += problem;
  if (result.contains("space") && result["space"].is_string()) {
    out += " (" + result["space"].get<std::string>() + ")";
  }
  if (result.contains("method") && result["method"].is_string()) {
    out += ", " + result["method"].get<std::string>();
  }
  if (result.contains("effort") && result["effort"].is_string()) {
    out += " at " + result["effort"].get<std::string>();
  }
  out += ": " + std::to_string(mechanisms.size()) + " listed, " + std::to_string(sound) +
         " without a kinematic defect";
  if (result.contains("scale")) out += "; L = " + Number(result["scale"]);
  out += "\n";
  std::string fit_name = "fit";
  std::vector<std::vector<std::string>> rows;
  bool any_chosen = false;
  bool angles = false;  // spherical four-bars: links are angles between axes
  bool any_other = false;
  const bool function = problem == "function";
  for (size_t i = 0; i < mechanisms.size(); ++i) {
    const Json& mechanism = mechanisms[i];
    const Json links =
        mechanism.contains("linkage") ? mechanism["linkage"].value("links", Json()) : Json();
    const auto link = [&](const char* name) {
      return links.is_object() && links.contains(name) ? Number(links[name]) : "-";
    };
    std::string name;
    const std::string fit = Fit(problem, mechanism, &name);
    if (i == 0 || fit != "-") fit_name = name;
    // Pivots linkfit chose on minimal data (optimizers/pivot_choice.h): marked, a line says how.
    const bool chosen = mechanism.contains("chosen");
    any_chosen = any_chosen || chosen;
    if (mechanism.contains("linkage") && mechanism["linkage"].contains("units")) angles = true;
    const std::string other = links.is_object() ? Other(links) : "-";
    any_other = any_other || (!other.empty() && other != "-");
    std::vector<std::string> row = {std::to_string(i + 1),
                                    mechanism.value("type", "-") + (chosen ? "*" : ""),
                                    mechanism.value("grashof", "-"),
                                    link("ground"),
                                    link("input"),
                                    link("coupler"),
                                    link("output"),
                                    other,
                                    fit,
                                    WorstTransmission(mechanism),
                                    Joined(mechanism.value("defects", Json())),
                                    Joined(mechanism.value("violates", Json()))};
    // A function generator's structural error over the whole sampled function: the figure a
    // designer reads (its fit is at the precision points only).
    if (function) {
      row.insert(row.begin() + 9, mechanism.contains("function_max_error_deg")
                                      ? Number(mechanism["function_max_error_deg"])
                                      : "-");
    }
    rows.push_back(row);
  }
  std::vector<std::string> header = {
      "#",       "type",    "grashof", "ground", "input",
      "coupler", "output",  "other",   fit_name, "worst transmission, deg",
      "defects", "violates"};
  if (function) header.insert(header.begin() + 9, "structural error, deg");
  std::vector<size_t> widths(header.size(), 0);
  for (size_t k = 0; k < header.size(); ++k) widths[k] = header[k].size();
  for (const std::vector<std::string>& row : rows) {
    for (size_t k = 0; k < row.size(); ++k) widths[k] = std::max(widths[k], row[k].size());
  }
  Row(header, widths, &out);
  for (const std::vector<std::string>& row : rows) Row(row, widths, &out);
  if (rows.empty()) out += "(no mechanism listed)\n";
  if (angles) out += "links: the angles between the joint axes, deg (spherical four-bars)\n";
  if (any_chosen) {
    out +=
        "* pivots chosen by linkfit, not the task's exact solution: \"chosen\" says how, "
        "\"pose_errors\" how well\n";
  }
  for (const Json& note : result.value("notes", Json::array())) {
    if (note.is_string()) out += "note: " + note.get<std::string>() + "\n";
  }
  if (any_other) {
    out +=
        "other: e = a slider's offset from the other pivot (or pin); p = the coupler point's "
        "distance @ angle (deg) from the input pin, from the coupler line\n";
  }
  return out;
}

}  // namespace linkfit
