#include "lib/analysis_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/dyad_four_bar_kinematics.h"
#include "lib/planar_pose.h"
#include "lib/six_bar.h"
#include "lib/six_bar_kinematics.h"
#include "lib/spherical_four_bar_kinematics.h"
#include "lib/task.h"
#include "lib/task_io.h"

namespace linkfit {
namespace {

using Json = nlohmann::ordered_json;  // written in the order built

constexpr double kDegree = 180.0 / M_PI;
constexpr int kMaxSteps = 1000000;

// A number for JSON: null where it is not finite (never written as NaN).
Json Number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }
Json Point(const Eigen::Vector2d& point) {
  return Json::array({Number(point.x()), Number(point.y())});
}

// [x, y] at `key` of `object`, named `item` in messages.
Eigen::Vector2d ReadPoint(const Json& object, const char* key, const std::string& item) {
  const auto found = object.find(key);
  if (found == object.end() || !found->is_array() || found->size() != 2 ||
      !(*found)[0].is_number() || !(*found)[1].is_number()) {
    throw InputError(item + "." + key + ": expected [x, y]");
  }
  return Eigen::Vector2d((*found)[0].get<double>(), (*found)[1].get<double>());
}

// The four-bar's joints from a result's mechanism (its "linkage": "joints"), named `item`.
FourBarJoints ReadJoints(const Json& mechanism, const std::string& item) {
  const std::string type = mechanism.value("type", std::string());
  const auto linkage = mechanism.find("linkage");
  if (linkage == mechanism.end() || !linkage->is_object() || !linkage->contains("joints") ||
      !(*linkage)["joints"].is_object()) {
    throw InputError(item + ".linkage.joints: missing (a result file of `linkfit solve` has it)");
  }
  const Json& joints = (*linkage)["joints"];
  const std::string at = item + ".linkage.joints";
  if (type != "4R" && type != "slider-crank") {
    // (`linkfit analyze` takes them before reading a four-bar's joints here.)
    throw InputError(item + ": " + (type.empty() ? "this mechanism" : type) +
                     " four-bars are not drawn yet (4Rs and slider-cranks are)");
  }
  if (!joints.contains("input_pivot")) {
    throw InputError(item +
                     ": a four-bar driven by a slider is not drawn yet (one driven by a crank "
                     "is)");
  }
  FourBarJoints read;
  read.input_pivot = ReadPoint(joints, "input_pivot", at);
  read.input_pin = ReadPoint(joints, "input_pin", at);
  read.output_pin = ReadPoint(joints, "output_pin", at);
  if (joints.contains("coupler_point")) read.coupler_point = ReadPoint(joints, "coupler_point", at);
  if (type == "4R") {
    read.output_pivot = ReadPoint(joints, "output_pivot", at);
    return read;
  }
  const auto line = joints.find("output_slider_line");
  if (line == joints.end() || !line->is_object()) {
    throw InputError(at + ".output_slider_line: missing");
  }
  if (line->value("on", std::string("ground")) != "ground") {
    throw InputError(item + ": a slider-crank whose line turns with the coupler is not drawn yet");
  }
  const auto angle = line->find("angle_deg");
  if (angle == line->end() || !angle->is_number()) {
    throw InputError(at + ".output_slider_line.angle_deg: expected a number");
  }
  read.slider = true;
  read.slider_point = ReadPoint(*line, "point", at + ".output_slider_line");
  const double radians = angle->get<double>() / kDegree;
  read.slider_direction = Eigen::Vector2d(std::cos(radians), std::sin(radians));
  return read;
}

// A number in a message: six significant digits.
std::string Short(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

std::string CsvNumber(const std::optional<double>& value) {
  if (!value || !std::isfinite(*value)) return "";
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", *value);
  return text;
}

// One CSV row of numbers (empty where there is none) and its line end.
void AppendCsvRow(const std::vector<std::optional<double>>& row, std::string* csv) {
  for (size_t c = 0; c < row.size(); ++c) *csv += (c ? "," : "") + CsvNumber(row[c]);
  *csv += "\n";
}

// With the links' masses: `named` (their masses by link, and gravity) as "masses", and per state
// the inertia's and the weight's parts of the input's effort ("inertial_" and "weight_" with
// `effort`, "torque" or "force"; the weight's only with gravity).
template <typename States, typename Inertial, typename Weight>
void PutMassParts(const States& states, Json named, bool gravity, const std::string& effort,
                  const Inertial& inertial, const Weight& weight, Json* out) {
  Json inertial_parts = Json::array(), weight_parts = Json::array();
  for (const auto& state : states) {
    inertial_parts.push_back(Number(inertial(state)));
    weight_parts.push_back(Number(weight(state)));
  }
  named["gravity"] = gravity;
  (*out)["masses"] = named;
  (*out)["inertial_" + effort] = inertial_parts;
  if (gravity) (*out)["weight_" + effort] = weight_parts;
}

// The defects the result lists for a mechanism, as a note (none without).
void AddDefectsNote(const Json& listed, Json* notes) {
  const auto defects = listed.is_object() ? listed.find("defects") : listed.end();
  if (defects == listed.end() || !defects->is_array() || defects->empty()) return;
  std::string names;
  for (const Json& defect : *defects) {
    if (defect.is_string()) names += (names.empty() ? "" : ", ") + defect.get<std::string>();
  }
  notes->push_back("the result lists this mechanism's defects: " + names +
                   " (circuit, branch or order: it does not reach every task pose in one "
                   "motion, so not all of them lie on the motion analyzed here; transmission: "
                   "its transmission angle falls below the minimum)");
}

// The first and last input values sampled (degrees), or nothing without samples.
template <typename States, typename Value>
Json SampledRange(const States& states, const Value& value) {
  if (states.empty()) return Json(nullptr);
  return Json::array({Number(value(states.front())), Number(value(states.back()))});
}

// The analysis over the part of the input's range the request asks for (AnalysisRequest):
// `analyze(range)` analyzes over `range` (radians), or the input's default range without one. A
// rocking input is sampled over `task` (the task's range, where known) unless the request says
// otherwise; *sampled_task tells whether it was. InputError where a range asked for gives no
// states (naming the input's range), or none come at all. `unit` turns the input's values into
// the request's (degrees; 1 for a slider's position, `unit_name` empty).
template <typename Kinematics, typename Analyze>
Kinematics AnalyzeOverTheRange(const AnalysisRequest& request,
                               const std::optional<std::pair<double, double>>& task,
                               const std::string& item, const Analyze& analyze, bool* sampled_task,
                               double unit = kDegree, const std::string& unit_name = " degrees") {
  std::optional<std::pair<double, double>> range;
  if (request.range_deg) {
    range = std::pair{request.range_deg->first / unit, request.range_deg->second / unit};
  } else if (request.task_range) {
    range = task;
  }
  Kinematics kinematics = analyze(range);
  *sampled_task = request.task_range;
  if (!range && !request.whole_range && !kinematics.input_rotates_fully && task) {
    // A rocking input: the part the task uses (its rates grow without bound toward its dead
    // points), where it runs through it on the first configuration's assembly.
    Kinematics on_task = analyze(task);
    if (!on_task.states.empty()) {
      kinematics = std::move(on_task);
      *sampled_task = true;
    }
  }
  if (range && kinematics.states.empty()) {
    const std::string asked = request.range_deg ? "--range " + Short(request.range_deg->first) +
                                                      "," + Short(request.range_deg->second)
                                                : std::string("--range task");
    throw InputError(asked + ": " + kinematics.note + " (its input runs from " +
                     Short(kinematics.range_start * unit) + " to " +
                     Short(kinematics.range_end * unit) + unit_name + ")");
  }
  if (kinematics.states.empty()) throw InputError(item + ": " + kinematics.note);
  return kinematics;
}

// The six-bar's bodies as the analysis names them (lib/six_bar.h SixBarBody 1 to 5).
constexpr const char* kSixBarLinkNames[] = {"upper_link", "forearm", "task_body", "first_link",
                                            "second_link"};

// Body k's direction in Sigma at the reference configuration: the line its angle follows (the
// upper link from the ground pivot to the elbow, the forearm from the elbow to the wrist, the
// task body its frame's x axis, an RR link from its first joint to its second).
double SixBarBodyReferenceAngle(const SixBar& six_bar, int body) {
  const auto direction = [](const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); };
  switch (body) {
    case kSixBarUpperLink:
      return direction(six_bar.elbow - six_bar.ground_pivot);
    case kSixBarForearm:
      return direction(six_bar.wrist - six_bar.elbow);
    case kSixBarTaskBody:
      return six_bar.reference_pose.theta;
    default: {
      const SixBarRRLink& link = six_bar.links[body - kSixBarFirstLink];
      return direction(link.to_joint - link.from_joint);
    }
  }
}

// `linkfit analyze` of six-bar `request.mechanism` of a result (its "six_bars").
std::string SixBarAnalysisText(const std::string& result_text, const std::string& source,
                               const AnalysisRequest& request, const FourBarMasses& units) {
  const int index = request.mechanism;
  const std::string item = source + ": six_bars[" + std::to_string(index) + "]";
  const ResultSixBar read = ReadResultSixBar(result_text, source, index);
  SixBarMasses masses;
  if (!request.mass_list.empty()) {
    if (request.mass_list.size() != 5) {
      throw InputError(
          "--mass: a six-bar takes five masses UPPER_LINK,FOREARM,TASK_BODY,FIRST_LINK,"
          "SECOND_LINK (kg)");
    }
    for (int body = 0; body < 5; ++body) masses.mass[body] = request.mass_list[body];
  }
  masses.length_unit_m = units.length_unit_m;
  masses.gravity = units.gravity;
  const bool massive = masses.Any();
  if (request.load.slider_force != 0.0) throw InputError("--slider-force: a six-bar has no slider");
  const SixBar& six_bar = read.six_bar;
  const int input = read.input;
  const std::vector<SixBarAngles>& at_poses = read.at_poses;
  const double length = read.length;
  const double reference = SixBarInputReferenceAngle(six_bar, input);
  // The task's range: the input's angles from the first pose to the last.
  std::optional<std::pair<double, double>> task;
  if (at_poses.size() >= 2) {
    double low = 0.0, high = 0.0;
    for (const SixBarAngles& at : at_poses) {
      low = std::min(low, at[input - 1] - at_poses[0][input - 1]);
      high = std::max(high, at[input - 1] - at_poses[0][input - 1]);
    }
    if (high - low > 1e-9) task = std::pair{reference + low, reference + high};
  }
  if (request.task_range && !task) {
    throw InputError("--range task: the result gives no turns at the task's poses for " + item);
  }

  SixBarKinematicsOptions options;
  options.input_speed = request.input_speed;
  options.steps = request.steps;
  options.load.tool_force = request.load.coupler_force;
  options.load.task_body_torque = request.load.output_torque;
  options.masses = masses;
  bool sampled_task = false;
  const SixBarKinematics kinematics = AnalyzeOverTheRange<SixBarKinematics>(
      request, task, item,
      [&](const std::optional<std::pair<double, double>>& range) {
        options.range = range;
        return AnalyzeSixBarKinematics(six_bar, input, options, length);
      },
      &sampled_task);
  const bool loaded =
      request.load.coupler_force.norm() > 0.0 || request.load.output_torque != 0.0 || massive;
  // Each body's angle continued from the first step's, which is in (-180, 180].
  double wraps[5];
  for (int body = 1; body <= 5; ++body) {
    const double first =
        SixBarBodyReferenceAngle(six_bar, body) + kinematics.states[0].turns[body - 1];
    wraps[body - 1] = 2.0 * M_PI * std::ceil((first - M_PI) / (2.0 * M_PI));
  }
  const auto angle_deg = [&](const SixBarState& state, int body) {
    return (SixBarBodyReferenceAngle(six_bar, body) + state.turns[body - 1] - wraps[body - 1]) *
           kDegree;
  };
  const auto worst_loop = [](const SixBarState& state) {
    return std::min(state.transmission_deg[0], state.transmission_deg[1]);
  };

  if (request.csv) {
    std::string csv = "input_deg";
    for (const char* name : kSixBarLinkNames) {
      csv += std::string(",") + name + "_angle_deg," + name + "_angular_velocity," + name +
             "_angular_acceleration";
    }
    csv +=
        ",coupler_point_x,coupler_point_y,coupler_point_velocity_x,coupler_point_velocity_y,"
        "coupler_point_acceleration_x,coupler_point_acceleration_y,transmission_angle_deg,"
        "transmission_angle_first_link_deg,transmission_angle_second_link_deg,"
        "mechanical_advantage,input_torque";
    if (massive) csv += ",inertial_torque";
    if (massive && masses.gravity) csv += ",weight_torque";
    csv += "\n";
    for (const SixBarState& state : kinematics.states) {
      std::vector<std::optional<double>> row = {state.input_angle * kDegree};
      for (int body = 1; body <= 5; ++body) {
        row.push_back(angle_deg(state, body));
        row.push_back(state.angular_velocity[body - 1]);
        row.push_back(state.angular_acceleration[body - 1]);
      }
      for (const Eigen::Vector2d* v :
           {&state.tool_point, &state.tool_velocity, &state.tool_acceleration}) {
        row.push_back(v->x());
        row.push_back(v->y());
      }
      row.push_back(worst_loop(state));
      row.push_back(state.transmission_deg[0]);
      row.push_back(state.transmission_deg[1]);
      row.push_back(state.mechanical_advantage);
      row.push_back(state.input_torque);
      if (massive) row.push_back(state.inertial_torque);
      if (massive && masses.gravity) row.push_back(state.weight_torque);
      AppendCsvRow(row, &csv);
    }
    return csv;
  }

  Json out;
  out["mechanism"] = index + 1;
  out["type"] = "six-bar";
  out["topology"] = SixBarTopologyName(six_bar.topology);
  out["input"] = kSixBarLinkNames[input - 1];
  out["input_speed_rad_s"] = request.input_speed;
  out["input_rotates_fully"] = kinematics.input_rotates_fully;
  out["input_range_deg"] = Json::array(
      {Number(kinematics.range_start * kDegree), Number(kinematics.range_end * kDegree)});
  out["sampled_range_deg"] = SampledRange(
      kinematics.states, [](const SixBarState& state) { return state.input_angle * kDegree; });
  if (task) {
    out["task_range_deg"] =
        Json::array({Number(task->first * kDegree), Number(task->second * kDegree)});
  }
  Json input_deg = Json::array(), transmission = Json::array(), advantage = Json::array();
  Json torque = Json::array(), p = Json::array(), v = Json::array(), a = Json::array();
  Json loops[2] = {Json::array(), Json::array()};
  Json links = Json::object();
  double worst = 90.0;
  for (int body = 1; body <= 5; ++body) {
    Json angles = Json::array(), rates = Json::array(), accelerations = Json::array();
    for (const SixBarState& state : kinematics.states) {
      angles.push_back(Number(angle_deg(state, body)));
      rates.push_back(Number(state.angular_velocity[body - 1]));
      accelerations.push_back(Number(state.angular_acceleration[body - 1]));
    }
    links[kSixBarLinkNames[body - 1]] = {{"angle_deg", angles},
                                         {"angular_velocity", rates},
                                         {"angular_acceleration", accelerations}};
  }
  for (const SixBarState& state : kinematics.states) {
    input_deg.push_back(Number(state.input_angle * kDegree));
    p.push_back(Point(state.tool_point));
    v.push_back(Point(state.tool_velocity));
    a.push_back(Point(state.tool_acceleration));
    transmission.push_back(Number(worst_loop(state)));
    for (int l = 0; l < 2; ++l) loops[l].push_back(Number(state.transmission_deg[l]));
    worst = std::min(worst, worst_loop(state));
    advantage.push_back(state.mechanical_advantage ? Number(*state.mechanical_advantage)
                                                   : Json(nullptr));
    torque.push_back(Number(state.input_torque));
  }
  out["input_deg"] = input_deg;
  out["links"] = links;
  out["coupler_point"] = p;
  out["coupler_point_velocity"] = v;
  out["coupler_point_acceleration"] = a;
  out["transmission_angle_deg"] = transmission;
  out["transmission_angles_deg"] = {{"first_link", loops[0]}, {"second_link", loops[1]}};
  out["transmission_angle_worst_deg"] = Number(worst);
  out["mechanical_advantage"] = advantage;
  if (loaded) {
    out["load"] = {{"coupler_force", Point(request.load.coupler_force)},
                   {"output_torque", Number(request.load.output_torque)}};
    out["input_torque"] = torque;
    out["peak_input_torque"] = Number(kinematics.peak_input_torque);
  }
  if (massive) {
    Json named = Json::object();
    for (int body = 0; body < 5; ++body) named[kSixBarLinkNames[body]] = masses.mass[body];
    PutMassParts(
        kinematics.states, named, masses.gravity, "torque",
        [](const SixBarState& state) { return state.inertial_torque; },
        [](const SixBarState& state) { return state.weight_torque; }, &out);
  }
  Json dead = Json::array();
  for (const SixBarState& state : kinematics.dead_points) {
    dead.push_back({{"input_deg", Number(state.input_angle * kDegree)},
                    {"transmission_angles_deg", Json::array({Number(state.transmission_deg[0]),
                                                             Number(state.transmission_deg[1])})},
                    {"coupler_point", Point(state.tool_point)}});
  }
  out["dead_points"] = dead;
  Json notes = Json::array();
  if (!kinematics.note.empty()) notes.push_back(kinematics.note);
  AddDefectsNote(Json::parse(result_text)["six_bars"][index], &notes);
  if (!kinematics.input_rotates_fully) {
    notes.push_back(
        "at a six-bar's dead point the input cannot drive on (its closure's Jacobian in the "
        "other turns is singular); the loops' transmission angles need not be 0 there");
  }
  if (sampled_task && !request.task_range) {
    notes.push_back(
        "the input rocks: sampled over the task's range (the input's angles at the first and "
        "the last pose); --range whole samples all of it between its dead points, where the "
        "rates grow without bound");
  } else if (!kinematics.input_rotates_fully && !request.range_deg && !sampled_task) {
    notes.push_back(
        "the input rocks: its range runs between its two dead points (listed), sampled inside "
        "them; toward them the rates and the torque grow without bound, so their peaks depend "
        "on --steps: give --range FROM,TO for the part the machine uses");
  }
  notes.push_back(
      "the links' angles are the directions in the fixed frame of: the upper link from the "
      "ground pivot to the elbow, the forearm from the elbow to the wrist, the task body's "
      "frame's x axis, each RR link from its first joint to its second; the coupler point is "
      "the tool frame's origin, the output the task body");
  out["units"] = {
      {"angles", "degrees"},
      {"angular_velocity", "rad/s"},
      {"angular_acceleration", "rad/s^2"},
      {"lengths", "the result's"},
      {"transmission_angle", "each loop's, folded into 0-90 degrees"},
      {"torque", request.length_unit.empty() ? std::string("N times the result's length unit")
                                             : "N " + request.length_unit},
      {"mechanical_advantage", "task body torque / input torque"}};
  out["notes"] = notes;
  return out.dump(2) + "\n";
}

// A four-bar kind's masses (planar closed form, spherical, dyad rows: the same three links) from
// the request's, read and checked once (AnalyzeResultText).
template <typename Masses>
Masses ThreeMasses(const FourBarMasses& four_bar) {
  Masses masses;
  masses.input = four_bar.input;
  masses.coupler = four_bar.coupler;
  masses.output = four_bar.output;
  masses.length_unit_m = four_bar.length_unit_m;
  masses.gravity = four_bar.gravity;
  return masses;
}

// `linkfit analyze` of spherical four-bar `request.mechanism` of a result.
std::string SphericalAnalysisText(const Json& result, const std::string& source,
                                  const AnalysisRequest& request, const FourBarMasses& units) {
  const auto mechanisms = result.find("mechanisms");
  if (mechanisms == result.end() || !mechanisms->is_array()) {
    throw InputError(source + ": no \"mechanisms\" (a result file of `linkfit solve` lists them)");
  }
  const int index = request.mechanism;
  if (index < 0 || index >= static_cast<int>(mechanisms->size())) {
    throw InputError(source + ": no mechanism ranked " + std::to_string(index + 1) +
                     " (counted from 1): the result lists " + std::to_string(mechanisms->size()));
  }
  const std::string item = source + ": mechanisms[" + std::to_string(index) + "]";
  SphericalFourBarMasses masses = ThreeMasses<SphericalFourBarMasses>(units);
  // The links' sphere: through the tool frame's origin (|center_in_moving|), else the scale.
  masses.radius = std::max(1e-300, result.value("scale", 1.0));
  const auto spherical = result.find("spherical");
  if (spherical != result.end() && spherical->is_object() &&
      spherical->contains("center_in_moving") && (*spherical)["center_in_moving"].is_array() &&
      (*spherical)["center_in_moving"].size() == 3) {
    double squared = 0.0;
    for (const Json& c : (*spherical)["center_in_moving"]) {
      if (c.is_number()) squared += c.get<double>() * c.get<double>();
    }
    if (squared > 0.0) masses.radius = std::sqrt(squared);
  }
  const bool massive = masses.Any();
  if (request.load.coupler_force.norm() > 0.0 || request.load.slider_force != 0.0) {
    throw InputError(
        "--force, --slider-force: a spherical four-bar's load is a torque about its output's "
        "axis: give --output-torque");
  }
  if (request.task_range) {
    throw InputError(
        "--range task: a four-bar's result does not give its crank's angles at the task's "
        "poses: give --range FROM,TO (degrees)");
  }
  const Json& mechanism = (*mechanisms)[index];
  const auto linkage = mechanism.find("linkage");
  if (!mechanism.is_object() || linkage == mechanism.end() || !linkage->is_object() ||
      !linkage->contains("joints") || !(*linkage)["joints"].is_object()) {
    throw InputError(item + ".linkage.joints: missing (a result file of `linkfit solve` has it)");
  }
  const Json& joints = (*linkage)["joints"];
  const std::string at = item + ".linkage.joints";
  const auto axis = [&](const char* key) {
    const auto found = joints.find(key);
    if (found == joints.end() || !found->is_array() || found->size() != 3 ||
        !(*found)[0].is_number() || !(*found)[1].is_number() || !(*found)[2].is_number()) {
      throw InputError(at + "." + key + ": expected [x, y, z]");
    }
    const Eigen::Vector3d v((*found)[0].get<double>(), (*found)[1].get<double>(),
                            (*found)[2].get<double>());
    if (!(v.norm() > 0.0) || !v.allFinite()) throw InputError(at + "." + key + ": not an axis");
    return v.normalized();
  };
  SphericalFourBarJoints axes;
  axes.input_pivot = axis("input_pivot");
  axes.input_pin = axis("input_pin");
  axes.output_pin = axis("output_pin");
  axes.output_pivot = axis("output_pivot");
  SphericalFourBarKinematicsOptions options;
  options.input_speed = request.input_speed;
  options.steps = request.steps;
  options.output_torque = request.load.output_torque;
  options.masses = masses;
  bool sampled_task = false;
  const SphericalFourBarKinematics kinematics = AnalyzeOverTheRange<SphericalFourBarKinematics>(
      request, std::nullopt, item,
      [&](const std::optional<std::pair<double, double>>& range) {
        options.range = range;
        return AnalyzeSphericalFourBarKinematics(axes, options);
      },
      &sampled_task);
  const bool loaded = request.load.output_torque != 0.0 || massive;
  const auto vector = [](const Eigen::Vector3d& v) {
    return Json::array({Number(v.x()), Number(v.y()), Number(v.z())});
  };

  if (request.csv) {
    std::string csv =
        "input_deg,coupler_rotation_deg,coupler_angular_velocity_x,coupler_angular_velocity_y,"
        "coupler_angular_velocity_z,coupler_angular_acceleration_x,"
        "coupler_angular_acceleration_y,coupler_angular_acceleration_z,output_angle_deg,"
        "output_angular_velocity,output_angular_acceleration,transmission_angle_deg,"
        "mechanical_advantage,input_torque";
    if (massive) csv += ",inertial_torque";
    if (massive && masses.gravity) csv += ",weight_torque";
    csv += "\n";
    for (const SphericalFourBarState& state : kinematics.states) {
      std::vector<std::optional<double>> row = {state.input_angle * kDegree,
                                                state.coupler_rotation * kDegree};
      for (const Eigen::Vector3d* v : {&state.coupler_velocity, &state.coupler_acceleration}) {
        for (int c = 0; c < 3; ++c) row.push_back((*v)[c]);
      }
      row.push_back(state.output_angle * kDegree);
      row.push_back(state.output_velocity);
      row.push_back(state.output_acceleration);
      row.push_back(state.transmission_angle_deg);
      row.push_back(state.mechanical_advantage);
      row.push_back(state.input_torque);
      if (massive) row.push_back(state.inertial_torque);
      if (massive && masses.gravity) row.push_back(state.weight_torque);
      AppendCsvRow(row, &csv);
    }
    return csv;
  }

  Json out;
  out["mechanism"] = index + 1;
  out["type"] = "spherical " + mechanism.value("type", std::string("4R"));
  out["input_speed_rad_s"] = request.input_speed;
  out["input_rotates_fully"] = kinematics.input_rotates_fully;
  out["input_range_deg"] = Json::array(
      {Number(kinematics.range_start * kDegree), Number(kinematics.range_end * kDegree)});
  out["sampled_range_deg"] =
      SampledRange(kinematics.states,
                   [](const SphericalFourBarState& state) { return state.input_angle * kDegree; });
  Json input_deg = Json::array(), transmission = Json::array(), advantage = Json::array();
  Json torque = Json::array(), input_pins = Json::array(), output_pins = Json::array();
  Json crank_rates = Json::array(), crank_accelerations = Json::array();
  Json coupler_angles = Json::array(), coupler_rates = Json::array();
  Json coupler_accelerations = Json::array();
  Json output_angles = Json::array(), output_rates = Json::array();
  Json output_accelerations = Json::array();
  double worst = 90.0;
  for (const SphericalFourBarState& state : kinematics.states) {
    input_deg.push_back(Number(state.input_angle * kDegree));
    crank_rates.push_back(Number(request.input_speed));
    crank_accelerations.push_back(0.0);
    coupler_angles.push_back(Number(state.coupler_rotation * kDegree));
    coupler_rates.push_back(vector(state.coupler_velocity));
    coupler_accelerations.push_back(vector(state.coupler_acceleration));
    output_angles.push_back(Number(state.output_angle * kDegree));
    output_rates.push_back(Number(state.output_velocity));
    output_accelerations.push_back(Number(state.output_acceleration));
    input_pins.push_back(vector(state.input_pin));
    output_pins.push_back(vector(state.output_pin));
    transmission.push_back(Number(state.transmission_angle_deg));
    worst = std::min({worst, state.transmission_angle_deg, 180.0 - state.transmission_angle_deg});
    advantage.push_back(state.mechanical_advantage ? Number(*state.mechanical_advantage)
                                                   : Json(nullptr));
    torque.push_back(Number(state.input_torque));
  }
  out["input_deg"] = input_deg;
  out["links"] = {{"input",
                   {{"angle_deg", input_deg},
                    {"angular_velocity", crank_rates},
                    {"angular_acceleration", crank_accelerations}}},
                  {"coupler",
                   {{"angle_deg", coupler_angles},
                    {"angular_velocity", coupler_rates},
                    {"angular_acceleration", coupler_accelerations}}},
                  {"output",
                   {{"angle_deg", output_angles},
                    {"angular_velocity", output_rates},
                    {"angular_acceleration", output_accelerations}}}};
  out["input_pin"] = input_pins;
  out["output_pin"] = output_pins;
  out["transmission_angle_deg"] = transmission;
  out["transmission_angle_worst_deg"] = Number(worst);
  out["mechanical_advantage"] = advantage;
  if (loaded) {
    out["load"] = {{"output_torque", Number(request.load.output_torque)}};
    out["input_torque"] = torque;
    out["peak_input_torque"] = Number(kinematics.peak_input_torque);
  }
  if (massive) {
    PutMassParts(
        kinematics.states,
        {{"input", Number(masses.input)},
         {"coupler", Number(masses.coupler)},
         {"output", Number(masses.output)},
         {"radius", Number(masses.radius)}},
        masses.gravity, "torque",
        [](const SphericalFourBarState& state) { return state.inertial_torque; },
        [](const SphericalFourBarState& state) { return state.weight_torque; }, &out);
  }
  Json dead = Json::array();
  for (const SphericalFourBarState& state : kinematics.dead_points) {
    dead.push_back({{"input_deg", Number(state.input_angle * kDegree)},
                    {"transmission_angle_deg", Number(state.transmission_angle_deg)},
                    {"input_pin", vector(state.input_pin)},
                    {"output_pin", vector(state.output_pin)}});
  }
  out["dead_points"] = dead;
  Json notes = Json::array();
  if (!kinematics.note.empty()) notes.push_back(kinematics.note);
  AddDefectsNote(mechanism, &notes);
  if (!kinematics.input_rotates_fully && !request.range_deg) {
    notes.push_back(
        "the input is a rocker: its range runs between its two dead points (listed), "
        "sampled inside them; toward them the rates and the torque grow without "
        "bound, so their peaks depend on --steps: give --range FROM,TO for the part "
        "the machine uses");
  }
  notes.push_back(
      "spherical: the input's angle is about the input pivot's axis from the plane of the two "
      "fixed axes, the output's about the output pivot's axis from the same plane (each "
      "counter-clockwise about its axis); the coupler's angle_deg is its rotation from the "
      "first pose, its angular velocity and acceleration vectors [x, y, z] in the fixed "
      "frame; the pins are unit axes through the centre");
  if (massive) {
    notes.push_back(
        "the links are taken as uniform thin arcs of the sphere through the tool frame's origin "
        "(masses.radius) between their axes" +
        std::string(masses.gravity ? "; gravity along -z of the fixed frame" : ""));
  }
  out["units"] = {
      {"angles", "degrees"},
      {"angular_velocity", "rad/s"},
      {"angular_acceleration", "rad/s^2"},
      {"torque", request.length_unit.empty() ? std::string("N times the result's length unit")
                                             : "N " + request.length_unit},
      {"mechanical_advantage", "output torque / input torque"}};
  out["notes"] = notes;
  return out.dump(2) + "\n";
}

// A four-bar's task range: its crank's angles (radians, continued from the first
// configuration's, where the result's joints are) from the first task pose, point or pair to the
// last, least to greatest; none where neither the result nor `task` gives them. Motion: each
// pose carries the input dyad's moving pivot (the result's "dyads", in E) to its crank pin;
// path: the crank turns by input_deg_j - input_deg_0 (free timing: the result's; prescribed:
// the task's points'); function: by the precision pairs' (the task's samples' with a task)
// inputs from the first pair's. Throws InputError where `task` is not this result's task.
std::optional<std::pair<double, double>> FourBarTaskRange(const Json& result, const Json& mechanism,
                                                          const FourBarJoints& joints,
                                                          double length, const Task* task,
                                                          const std::string& source) {
  const std::string problem = result.value("problem", std::string("motion"));
  const Eigen::Vector2d crank = joints.input_pin - joints.input_pivot;
  const double first = std::atan2(crank.y(), crank.x());
  std::vector<double> turns;  // the crank's turn from the first configuration at each item
  const auto mismatch = [&](const std::string& what) {
    throw InputError("--task: " + what + " (is it the task of " + source + "?)");
  };
  if (problem == "motion") {
    if (task == nullptr) return std::nullopt;
    if (task->problem != ProblemKind::kMotion || task->planar_poses.size() < 2) {
      mismatch("not a planar motion task");
    }
    const auto dyads = result.find("dyads");
    const auto indices = mechanism.find("dyads");
    if (dyads == result.end() || indices == mechanism.end() || !indices->is_array() ||
        indices->empty() || !(*indices)[0].is_number_integer()) {
      return std::nullopt;
    }
    const int index = (*indices)[0].get<int>();
    if (index < 0 || index >= static_cast<int>(dyads->size())) return std::nullopt;
    const Json& dyad = (*dyads)[index];
    if (dyad.value("type", std::string()) != "RR") return std::nullopt;
    const Eigen::Vector2d moving =
        ReadPoint(dyad, "moving", source + ": dyads[" + std::to_string(index) + "]");
    // A fitted mechanism passes its first pose within its max_pose_error e (a length: the origin
    // within e, the turn within e / L), so its crank pin within e (1 + |moving| / L).
    const double fit = mechanism.value("max_pose_error", 0.0);
    const double scale = result.value("scale", length);
    const double slack = 1e-6 * length + 1.000001 * fit * (1.0 + moving.norm() / scale);
    double previous = first;
    for (size_t k = 0; k < task->planar_poses.size(); ++k) {
      const Eigen::Vector2d pin = task->planar_poses[k].ToFixed(moving);
      if (k == 0 && (pin - joints.input_pin).norm() > slack) {
        mismatch("its first pose does not put the crank pin where the result's joints have it");
      }
      const Eigen::Vector2d arm = pin - joints.input_pivot;
      double angle = std::atan2(arm.y(), arm.x());
      angle += 2.0 * M_PI * std::round((previous - angle) / (2.0 * M_PI));
      turns.push_back(angle - first);
      previous = angle;
    }
  } else if (problem == "path") {
    if (task != nullptr) {
      if (task->problem != ProblemKind::kPath || task->points.empty()) {
        mismatch("not a path task");
      }
      if (joints.coupler_point) {
        const double slack = 1e-6 * length + 1.000001 * mechanism.value("max_point_error", 0.0);
        if ((task->points[0].point_in_fixed - *joints.coupler_point).norm() > slack) {
          mismatch("its first point is not where the result's coupler point passes it");
        }
      }
    }
    std::vector<double> input_deg;
    const auto fitted = mechanism.find("input_deg");
    if (fitted != mechanism.end() && fitted->is_array()) {
      for (const Json& value : *fitted) {
        if (value.is_number()) input_deg.push_back(value.get<double>());
      }
    } else if (task != nullptr) {
      for (const TimedPoint& point : task->points) {
        if (point.input_angle) input_deg.push_back(*point.input_angle * kDegree);
      }
    }
    for (const double at : input_deg) turns.push_back((at - input_deg.front()) / kDegree);
  } else if (problem == "function") {
    const auto pairs = result.find("precision_points");
    if (pairs == result.end() || !pairs->is_array() || pairs->empty() ||
        !(*pairs)[0].contains("input_deg") || !(*pairs)[0]["input_deg"].is_number()) {
      return std::nullopt;
    }
    const double first_pair = (*pairs)[0]["input_deg"].get<double>() / kDegree;
    if (task != nullptr) {
      if (task->problem != ProblemKind::kFunction) mismatch("not a function task");
      const std::vector<FunctionPair>& samples =
          task->function_samples.empty() ? task->pairs : task->function_samples;
      for (const FunctionPair& pair : samples) turns.push_back(pair.input - first_pair);
    } else {
      for (const Json& pair : *pairs) {
        if (pair.contains("input_deg") && pair["input_deg"].is_number()) {
          turns.push_back(pair["input_deg"].get<double>() / kDegree - first_pair);
        }
      }
    }
  }
  if (turns.size() < 2) return std::nullopt;
  const auto [low, high] = std::minmax_element(turns.begin(), turns.end());
  if (!(*high - *low > 1e-9)) return std::nullopt;
  return std::pair{first + *low, first + *high};
}

// A four-bar's dyads from its "linkage" joints, with E the coupler's frame equal to Sigma at
// the first configuration (the identity pose), for lib/dyad_four_bar_kinematics.h: each side an
// RR (pivot and pin), a PR (pin and a slider line on ground) or an RP (pivot and a line on the
// coupler).
PlanarDyad ReadDyad(const Json& joints, const std::string& side, const std::string& at) {
  const auto line = joints.find(side + "_slider_line");
  if (line == joints.end()) {
    const Eigen::Vector2d pivot = ReadPoint(joints, (side + "_pivot").c_str(), at);
    const Eigen::Vector2d pin = ReadPoint(joints, (side + "_pin").c_str(), at);
    return PlanarDyad::RR(pivot, pin, (pin - pivot).norm());
  }
  const std::string line_at = at + "." + side + "_slider_line";
  if (!line->is_object() || !line->contains("angle_deg") || !(*line)["angle_deg"].is_number()) {
    throw InputError(line_at + ".angle_deg: expected a number");
  }
  const double angle = (*line)["angle_deg"].get<double>() / kDegree;
  const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d point = ReadPoint(*line, "point", line_at);
  if (line->value("on", std::string("ground")) == "ground") {
    return PlanarDyad::PR(ReadPoint(joints, (side + "_pin").c_str(), at), point, direction);
  }
  return PlanarDyad::RP(ReadPoint(joints, (side + "_pivot").c_str(), at), point, direction);
}

// `linkfit analyze` of a planar four-bar the closed form does not take: an inverted
// slider-crank, a double slider, an RPRP, or any four-bar driven by a slider
// (lib/dyad_four_bar_kinematics.h).
std::string DyadFourBarAnalysisText(const Json& result, const Json& mechanism,
                                    const std::string& source, const std::string& item,
                                    const AnalysisRequest& request, const FourBarMasses& units) {
  const std::string type = mechanism.value("type", std::string());
  const DyadFourBarMasses masses = ThreeMasses<DyadFourBarMasses>(units);
  const bool massive = masses.Any();
  const Json& joints = mechanism["linkage"]["joints"];
  const std::string at = item + ".linkage.joints";
  const PlanarDyad input = ReadDyad(joints, "input", at);
  const PlanarDyad output = ReadDyad(joints, "output", at);
  std::optional<Eigen::Vector2d> point;
  if (joints.contains("coupler_point")) point = ReadPoint(joints, "coupler_point", at);
  double length = std::max(1e-300, result.value("scale", 0.0));
  for (const PlanarDyad* dyad : {&input, &output}) {
    if (dyad->type == DyadType::kRR) length = std::max(length, dyad->radius);
  }
  const bool slider_input = input.type == DyadType::kPR;
  // The input's values: degrees for an angle, the result's length for a slider.
  const double unit = slider_input ? 1.0 : kDegree;
  DyadFourBarKinematicsOptions options;
  options.input_speed = request.input_speed;
  options.steps = request.steps;
  options.load.coupler_force = request.load.coupler_force;
  options.load.output_torque = request.load.output_torque;
  options.load.slider_force = request.load.slider_force;
  options.masses = masses;
  if (!point && request.load.coupler_force.norm() > 0.0) {
    throw InputError(source + ": --force: the four-bar has no coupler point: load its output");
  }
  // The task's range: the input's values from the first task pose (or point) to the last.
  // Motion (with the task): each pose's displacement from the first carries the dyads, E being
  // Sigma at the first configuration; path: the crank turns by input_deg_j - input_deg_0 (the
  // result's fitted ones, or the task's).
  std::vector<double> task_values;
  const double first_value = InputValue(input, PlanarPose());
  const std::string problem = result.value("problem", std::string("motion"));
  const auto mismatch = [&](const std::string& what) {
    throw InputError("--task: " + what + " (is it the task of " + source + "?)");
  };
  if (problem == "motion" && request.task != nullptr) {
    const std::vector<PlanarPose>& poses = request.task->planar_poses;
    if (request.task->problem != ProblemKind::kMotion || poses.size() < 2) {
      mismatch("not a planar motion task");
    }
    if (point && (poses[0].origin_in_fixed - *point).norm() > 0.05 * length) {
      mismatch("its first pose is not at the four-bar's coupler point");
    }
    const PlanarPose back = poses[0].Inverse();
    double previous = first_value;
    for (const PlanarPose& pose : poses) {
      double value = InputValue(input, pose * back);
      if (!slider_input) value += 2.0 * M_PI * std::round((previous - value) / (2.0 * M_PI));
      task_values.push_back(value);
      previous = value;
    }
  } else if (problem == "path" && !slider_input) {
    std::vector<double> input_deg;
    const auto fitted = mechanism.find("input_deg");
    if (fitted != mechanism.end() && fitted->is_array()) {
      for (const Json& value : *fitted) {
        if (value.is_number()) input_deg.push_back(value.get<double>());
      }
    } else if (request.task != nullptr) {
      for (const TimedPoint& at : request.task->points) {
        if (at.input_angle) input_deg.push_back(*at.input_angle * kDegree);
      }
    }
    for (const double at : input_deg) {
      task_values.push_back(first_value + (at - input_deg.front()) / kDegree);
    }
  }
  std::optional<std::pair<double, double>> task;
  if (task_values.size() >= 2) {
    const auto [low, high] = std::minmax_element(task_values.begin(), task_values.end());
    if (*high - *low > 1e-9 * (slider_input ? length : 1.0)) task = std::pair{*low, *high};
  }
  if (request.task_range && !task) {
    throw InputError(
        "--range task: the result does not give the input's values at the task's poses or "
        "points: give its task with --task (motion and timed path tasks), or --range FROM,TO");
  }
  bool sampled_task = false;
  const DyadFourBarKinematics kinematics = AnalyzeOverTheRange<DyadFourBarKinematics>(
      request, task, item,
      [&](const std::optional<std::pair<double, double>>& range) {
        options.range = range;
        return AnalyzeDyadFourBarKinematics(input, output, point, PlanarPose(), options, length);
      },
      &sampled_task, unit, slider_input ? "" : " degrees");
  const bool loaded = request.load.coupler_force.norm() > 0.0 ||
                      request.load.output_torque != 0.0 || request.load.slider_force != 0.0 ||
                      massive;
  // Names: the input "input" (a slider's position), the output "output" (a rocker), "slider"
  // (a PR's position) or "block" (an RP's slide along the coupler's line).
  const char* output_name = output.type == DyadType::kRR   ? "output"
                            : output.type == DyadType::kPR ? "slider"
                                                           : "block";
  const char* effort_name = slider_input ? "input_force" : "input_torque";
  // The coupler's line: from the input pin to the output pin where both are on it, else an RP's
  // line; its direction in Sigma at the first configuration.
  double coupler_reference = 0.0;
  if (input.type != DyadType::kRP && output.type != DyadType::kRP) {
    const Eigen::Vector2d along = output.moving_pivot - input.moving_pivot;
    coupler_reference = std::atan2(along.y(), along.x());
  } else {
    const PlanarDyad& rp = input.type == DyadType::kRP ? input : output;
    coupler_reference = std::atan2(rp.line_direction.y(), rp.line_direction.x());
  }
  const auto input_value = [&](const DyadFourBarState& state) {
    // An RP input's value is the coupler's turn: its block's angle is its line's direction.
    return input.type == DyadType::kRP
               ? (std::atan2(input.line_direction.y(), input.line_direction.x()) + state.input) *
                     kDegree
               : state.input * unit;
  };
  const auto output_value = [&](const DyadFourBarState& state) {
    return output.type == DyadType::kRR ? state.output * kDegree : state.output;
  };

  if (request.csv) {
    std::string csv = slider_input ? "input_position" : "input_deg";
    csv += ",coupler_angle_deg,coupler_angular_velocity,coupler_angular_acceleration,";
    csv += output.type == DyadType::kRR
               ? "output_angle_deg,output_angular_velocity,output_angular_acceleration"
               : std::string(output_name) + "_position," + output_name + "_velocity," +
                     output_name + "_acceleration";
    if (point) {
      csv +=
          ",coupler_point_x,coupler_point_y,coupler_point_velocity_x,coupler_point_velocity_y,"
          "coupler_point_acceleration_x,coupler_point_acceleration_y";
    }
    csv += std::string(",transmission_angle_deg,mechanical_advantage,") + effort_name + "\n";
    for (const DyadFourBarState& state : kinematics.states) {
      std::vector<std::optional<double>> row = {
          input_value(state),       (coupler_reference + state.coupler.theta) * kDegree,
          state.velocity[2],        state.acceleration[2],
          output_value(state),      state.output_velocity,
          state.output_acceleration};
      if (point) {
        for (const Eigen::Vector2d* v : {&state.coupler_point, &state.coupler_point_velocity,
                                         &state.coupler_point_acceleration}) {
          row.push_back(v->x());
          row.push_back(v->y());
        }
      }
      row.push_back(state.transmission_angle_deg);
      row.push_back(state.mechanical_advantage);
      row.push_back(state.input_effort);
      AppendCsvRow(row, &csv);
    }
    return csv;
  }

  Json out;
  out["mechanism"] = request.mechanism + 1;
  out["type"] = type;
  out["input"] = slider_input                  ? "slider"
                 : input.type == DyadType::kRP ? "block (turning with the coupler)"
                                               : "crank";
  out["input_speed"] = request.input_speed;
  out["input_rotates_fully"] = kinematics.input_rotates_fully;
  out[slider_input ? "input_range" : "input_range_deg"] =
      Json::array({Number(kinematics.range_start * unit), Number(kinematics.range_end * unit)});
  out[slider_input ? "sampled_range" : "sampled_range_deg"] =
      SampledRange(kinematics.states, input_value);
  if (task) {
    out[slider_input ? "task_range" : "task_range_deg"] =
        Json::array({Number(task->first * unit), Number(task->second * unit)});
  }
  Json inputs = Json::array(), transmission = Json::array(), advantage = Json::array();
  Json effort = Json::array(), p = Json::array(), v = Json::array(), a = Json::array();
  Json values[3][3];
  for (auto& link : values) {
    for (Json& series : link) series = Json::array();
  }
  double worst = 90.0;
  for (const DyadFourBarState& state : kinematics.states) {
    inputs.push_back(Number(input_value(state)));
    values[0][0].push_back(Number(input_value(state)));
    values[0][1].push_back(Number(request.input_speed));
    values[0][2].push_back(0.0);
    values[1][0].push_back(Number((coupler_reference + state.coupler.theta) * kDegree));
    values[1][1].push_back(Number(state.velocity[2]));
    values[1][2].push_back(Number(state.acceleration[2]));
    values[2][0].push_back(Number(output_value(state)));
    values[2][1].push_back(Number(state.output_velocity));
    values[2][2].push_back(Number(state.output_acceleration));
    if (point) {
      p.push_back(Point(state.coupler_point));
      v.push_back(Point(state.coupler_point_velocity));
      a.push_back(Point(state.coupler_point_acceleration));
    }
    transmission.push_back(Number(state.transmission_angle_deg));
    worst = std::min({worst, state.transmission_angle_deg, 180.0 - state.transmission_angle_deg});
    advantage.push_back(state.mechanical_advantage ? Number(*state.mechanical_advantage)
                                                   : Json(nullptr));
    effort.push_back(Number(state.input_effort));
  }
  // The x axis of the charts is "input_deg"; a slider's input is its position.
  out["input_deg"] = inputs;
  if (slider_input) out["input_position"] = inputs;
  Json links = Json::object();
  const char* names[3] = {"input", "coupler", output_name};
  for (int l = 0; l < 3; ++l) {
    const bool linear = (l == 0 && slider_input) || (l == 2 && output.type != DyadType::kRR);
    links[names[l]] = linear ? Json{{"position", values[l][0]},
                                    {"velocity", values[l][1]},
                                    {"acceleration", values[l][2]}}
                             : Json{{"angle_deg", values[l][0]},
                                    {"angular_velocity", values[l][1]},
                                    {"angular_acceleration", values[l][2]}};
  }
  out["links"] = links;
  if (point) {
    out["coupler_point"] = p;
    out["coupler_point_velocity"] = v;
    out["coupler_point_acceleration"] = a;
  }
  out["transmission_angle_deg"] = transmission;
  out["transmission_angle_worst_deg"] = Number(worst);
  out["mechanical_advantage"] = advantage;
  if (loaded) {
    out["load"] = {{"coupler_force", Point(request.load.coupler_force)},
                   {"output_torque", Number(request.load.output_torque)},
                   {"slider_force", Number(request.load.slider_force)}};
    out[effort_name] = effort;
    out[slider_input ? "peak_input_force" : "peak_input_torque"] =
        Number(kinematics.peak_input_effort);
  }
  if (massive) {
    PutMassParts(
        kinematics.states,
        {{"input", Number(masses.input)},
         {"coupler", Number(masses.coupler)},
         {output_name, Number(masses.output)}},
        masses.gravity, slider_input ? "force" : "torque",
        [](const DyadFourBarState& state) { return state.inertial_effort; },
        [](const DyadFourBarState& state) { return state.weight_effort; }, &out);
  }
  Json dead = Json::array();
  for (const DyadFourBarState& state : kinematics.dead_points) {
    Json at_dead = {{slider_input ? "input_position" : "input_deg", Number(input_value(state))},
                    {"transmission_angle_deg", Number(state.transmission_angle_deg)}};
    if (point) at_dead["coupler_point"] = Point(state.coupler_point);
    dead.push_back(at_dead);
  }
  out["dead_points"] = dead;
  Json notes = Json::array();
  if (!kinematics.note.empty()) notes.push_back(kinematics.note);
  AddDefectsNote(mechanism, &notes);
  if (sampled_task && !request.task_range) {
    notes.push_back(
        "the input rocks: sampled over the task's range (its values from the first task pose "
        "to the last); --range whole samples all of it");
  } else if (!kinematics.input_rotates_fully && !request.range_deg && !sampled_task) {
    notes.push_back(
        kinematics.range_bounded
            ? "the input's range runs between its two dead points (listed), sampled inside "
              "them; toward them the rates grow without bound: give --range FROM,TO for the "
              "part the machine uses"
            : "the input's range is not closed by a dead point at one end at least (a slider "
              "sampled within 10 lengths, or a coupler running off): give --range FROM,TO for "
              "the part the machine uses");
  }
  if (slider_input) {
    notes.push_back(
        "driven by its slider: input_position and its speed are in the result's length per "
        "second; input_deg repeats input_position for the charts; input_force holds the load");
  }
  if (output.type == DyadType::kRP) {
    notes.push_back(
        "the block's position is where its fixed pivot lies along the coupler's line (from the "
        "line's point on the coupler); the block turns with the coupler");
  }
  if (!point) notes.push_back("no coupler point in the result: its arrays are left out");
  out["units"] = {{"angles", "degrees"},
                  {"angular_velocity", "rad/s"},
                  {"angular_acceleration", "rad/s^2"},
                  {"lengths", "the result's"},
                  {"mechanical_advantage", "input rate / output rate"}};
  out["notes"] = notes;
  return out.dump(2) + "\n";
}

}  // namespace

// The result's JSON text parsed; InputError naming `source` where it is not JSON.
static Json ParseResult(const std::string& result_text, const std::string& source) {
  try {
    return Json::parse(result_text);
  } catch (const Json::parse_error& error) {
    throw InputError(source + ": not a JSON result file (" + std::string(error.what()) + ")");
  }
}

// ReadResultFourBar of a parsed result.
static ResultFourBar FourBarOfResult(const Json& result, const std::string& source,
                                     int mechanism_index);
// ReadResultDyadFourBar of a parsed result.
static std::optional<ResultDyadFourBar> DyadFourBarOfResult(const Json& result,
                                                            const std::string& source, int index);

ResultFourBar ReadResultFourBar(const std::string& result_text, const std::string& source,
                                int mechanism_index) {
  return FourBarOfResult(ParseResult(result_text, source), source, mechanism_index);
}

static ResultFourBar FourBarOfResult(const Json& result, const std::string& source,
                                     int mechanism_index) {
  if (!result.is_object()) throw InputError(source + ": expected a JSON object (a result file)");
  const auto six_bars = result.find("six_bars");
  if (six_bars != result.end() && six_bars->is_array() && !six_bars->empty()) {
    // (`linkfit analyze` takes them before reading a four-bar.)
    throw InputError(source +
                     ": six-bars are not drawn yet (planar four-bars driven by a crank are; "
                     "`linkfit analyze` analyzes six-bars)");
  }
  const std::string space = result.value("space", std::string("planar"));
  if (space != "planar") {
    if (result.value("model", std::string()) == "spherical") {
      throw InputError(source +
                       ": spherical four-bars are not drawn yet (planar four-bars driven by a "
                       "crank are; `linkfit analyze` analyzes spherical ones)");
    }
    throw InputError(source + ": " + space +
                     " mechanisms are not analyzed or drawn yet (planar four-bars and six-bars "
                     "and spherical four-bars are analyzed)");
  }
  const auto mechanisms = result.find("mechanisms");
  if (mechanisms == result.end() || !mechanisms->is_array()) {
    throw InputError(source + ": no \"mechanisms\" (a result file of `linkfit solve` lists them)");
  }
  if (mechanism_index < 0 || mechanism_index >= static_cast<int>(mechanisms->size())) {
    throw InputError(source + ": no mechanism ranked " + std::to_string(mechanism_index + 1) +
                     " (counted from 1): the result lists " + std::to_string(mechanisms->size()));
  }
  const std::string item = source + ": mechanisms[" + std::to_string(mechanism_index) + "]";
  const Json& mechanism = (*mechanisms)[mechanism_index];
  if (!mechanism.is_object()) throw InputError(item + ": expected an object");
  ResultFourBar read;
  read.joints = ReadJoints(mechanism, item);
  read.type = mechanism.value("type", std::string());
  read.length = std::max({1e-300, (read.joints.input_pin - read.joints.input_pivot).norm(),
                          (read.joints.output_pin - read.joints.input_pin).norm(),
                          result.value("scale", 0.0)});
  return read;
}

std::optional<ResultDyadFourBar> ReadResultDyadFourBar(const std::string& result_text,
                                                       const std::string& source, int index) {
  Json result;
  try {
    result = Json::parse(result_text);
  } catch (const Json::parse_error&) {
    return std::nullopt;  // (ReadResultFourBar says what is wrong)
  }
  return DyadFourBarOfResult(result, source, index);
}

static std::optional<ResultDyadFourBar> DyadFourBarOfResult(const Json& result,
                                                            const std::string& source, int index) {
  const auto mechanisms = result.is_object() ? result.find("mechanisms") : result.end();
  if (result.value("space", std::string("planar")) != "planar" || mechanisms == result.end() ||
      !mechanisms->is_array() || index < 0 || index >= static_cast<int>(mechanisms->size())) {
    return std::nullopt;
  }
  const Json& mechanism = (*mechanisms)[index];
  const std::string type = mechanism.is_object() ? mechanism.value("type", std::string()) : "";
  const auto linkage = mechanism.is_object() ? mechanism.find("linkage") : mechanism.end();
  if (linkage == mechanism.end() || !linkage->is_object() || !linkage->contains("joints") ||
      !(*linkage)["joints"].is_object()) {
    return std::nullopt;
  }
  const Json& joints = (*linkage)["joints"];
  const bool crank = joints.contains("input_pivot") && !joints.contains("input_slider_line");
  const bool closed_form =
      crank && (type == "4R" ||
                (type == "slider-crank" && joints.contains("output_slider_line") &&
                 joints["output_slider_line"].is_object() &&
                 joints["output_slider_line"].value("on", std::string("ground")) == "ground"));
  if (closed_form ||
      !(type == "4R" || type == "slider-crank" || type == "inverted slider-crank" ||
        type == "double slider" || type == "RPRP" || type == "inverted double slider")) {
    return std::nullopt;
  }
  const std::string at = source + ": mechanisms[" + std::to_string(index) + "].linkage.joints";
  ResultDyadFourBar read;
  read.type = type;
  read.input = ReadDyad(joints, "input", at);
  read.output = ReadDyad(joints, "output", at);
  if (joints.contains("coupler_point")) read.coupler_point = ReadPoint(joints, "coupler_point", at);
  read.length = std::max(1e-300, result.value("scale", 0.0));
  for (const PlanarDyad* dyad : {&read.input, &read.output}) {
    if (dyad->type == DyadType::kRR) read.length = std::max(read.length, dyad->radius);
  }
  return read;
}

ResultSixBar ReadResultSixBar(const std::string& result_text, const std::string& source,
                              int index) {
  Json result;
  try {
    result = Json::parse(result_text);
  } catch (const Json::parse_error& error) {
    throw InputError(source + ": not a JSON result file (" + std::string(error.what()) + ")");
  }
  const auto list = result.is_object() ? result.find("six_bars") : result.end();
  if (list == result.end() || !list->is_array() || list->empty()) {
    throw InputError(source + ": no \"six_bars\" (a six-bar result lists them)");
  }
  if (index < 0 || index >= static_cast<int>(list->size())) {
    throw InputError(source + ": no six-bar ranked " + std::to_string(index + 1) +
                     " (counted from 1): the result lists " + std::to_string(list->size()));
  }
  const std::string item = source + ": six_bars[" + std::to_string(index) + "]";
  const Json& entry = (*list)[index];
  if (!entry.is_object() || !entry.contains("task_body_at_first_pose")) {
    throw InputError(item +
                     ".task_body_at_first_pose: missing (a result file of `linkfit solve` "
                     "has it)");
  }
  // The parser places the task body at "task_body_at_first_pose" and reads the turns at as many
  // poses as it is given.
  const auto turns = entry.find("turns_at_poses_deg");
  const size_t pose_count =
      turns != entry.end() && turns->is_array() && !turns->empty() ? turns->size() : 1;
  const SixBarDesign design =
      ParseSixBarDesign(result_text, source, std::vector<PlanarPose>(pose_count));
  ResultSixBar read;
  read.six_bar = design.six_bars[index];
  read.input = design.inputs[index];
  read.at_poses = design.at_poses[index];
  const SixBar& six_bar = read.six_bar;
  read.length =
      std::max({1e-300, result.value("scale", 0.0), (six_bar.elbow - six_bar.ground_pivot).norm(),
                (six_bar.wrist - six_bar.elbow).norm(), six_bar.links[0].Length(),
                six_bar.links[1].Length()});
  return read;
}

std::optional<std::pair<double, double>> ResultFourBarTaskRange(const std::string& result_text,
                                                                const std::string& source,
                                                                int mechanism_index,
                                                                const Task* task) {
  const ResultFourBar four_bar = ReadResultFourBar(result_text, source, mechanism_index);
  const Json result = Json::parse(result_text);
  return FourBarTaskRange(result, result["mechanisms"][mechanism_index], four_bar.joints,
                          four_bar.length, task, source);
}

std::string AnalyzeResultText(const std::string& result_text, const std::string& source,
                              const AnalysisRequest& request) {
  if (!(request.input_speed != 0.0) || !std::isfinite(request.input_speed)) {
    throw InputError("--input-speed: expected a finite number other than 0 (rad/s)");
  }
  if (request.range_deg &&
      !(std::isfinite(request.range_deg->first) && std::isfinite(request.range_deg->second) &&
        request.range_deg->first < request.range_deg->second)) {
    throw InputError("--range: expected two crank angles FROM,TO in degrees, FROM below TO");
  }
  if (request.steps < 1 || request.steps > kMaxSteps) {
    throw InputError("--steps: expected a whole number from 1 to " + std::to_string(kMaxSteps));
  }
  FourBarMasses masses = request.masses;
  for (const double mass : request.mass_list) {
    if (!(std::isfinite(mass) && mass >= 0.0)) {
      throw InputError(
          "--mass: expected the links' masses in kg (a four-bar's INPUT,COUPLER,OUTPUT, a "
          "six-bar's five), none negative");
    }
  }
  if (request.mass_list.size() == 3) {
    masses.input = request.mass_list[0];
    masses.coupler = request.mass_list[1];
    masses.output = request.mass_list[2];
  }
  bool massive = masses.Any();
  for (const double mass : request.mass_list) massive |= mass > 0.0;
  for (const double mass : {masses.input, masses.coupler, masses.output}) {
    if (!(std::isfinite(mass) && mass >= 0.0)) {
      throw InputError("--mass: expected three masses INPUT,COUPLER,OUTPUT in kg, none negative");
    }
  }
  if (masses.gravity && !massive) {
    throw InputError("--gravity: give the links' masses with --mass INPUT,COUPLER,OUTPUT (kg)");
  }
  if (massive || !request.length_unit.empty()) {
    const std::map<std::string, double> metres = {
        {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}};
    const auto unit = metres.find(request.length_unit);
    if (unit == metres.end()) {
      throw InputError(
          "--length-unit: expected m, cm, mm, in or ft (the result's lengths' unit; with "
          "--mass it makes kg and those lengths give the torque in N times that unit)" +
          (request.length_unit.empty() ? std::string() : ", got '" + request.length_unit + "'"));
    }
    masses.length_unit_m = unit->second;
  }
  const Json result = ParseResult(result_text, source);
  {
    const auto six_bars = result.find("six_bars");
    if (result.is_object() && six_bars != result.end() && six_bars->is_array() &&
        !six_bars->empty()) {
      return SixBarAnalysisText(result_text, source, request, masses);
    }
    // Every kind of four-bar below takes three masses.
    if (request.mass_list.size() != 3 && !request.mass_list.empty()) {
      throw InputError("--mass: a four-bar takes three masses INPUT,COUPLER,OUTPUT (kg)");
    }
    if (result.is_object() && result.value("model", std::string()) == "spherical") {
      return SphericalAnalysisText(result, source, request, masses);
    }
    // A planar four-bar the closed form does not take: another type, or driven by a slider.
    if (DyadFourBarOfResult(result, source, request.mechanism)) {
      return DyadFourBarAnalysisText(
          result, result["mechanisms"][request.mechanism], source,
          source + ": mechanisms[" + std::to_string(request.mechanism) + "]", request, masses);
    }
  }
  const ResultFourBar four_bar = FourBarOfResult(result, source, request.mechanism);
  const FourBarJoints& joints = four_bar.joints;
  const double length = four_bar.length;
  const Json& mechanism = result["mechanisms"][request.mechanism];
  const std::optional<std::pair<double, double>> task =
      FourBarTaskRange(result, mechanism, joints, length, request.task, source);
  if (request.task_range && !task) {
    throw InputError(
        "--range task: the result does not give the crank's angles at the task's poses or "
        "points: give its task with --task (motion and timed path tasks), or --range FROM,TO "
        "(degrees)");
  }
  FourBarKinematicsOptions options;
  options.input_speed = request.input_speed;
  options.steps = request.steps;
  options.load = request.load;
  options.masses = masses;
  if (!joints.coupler_point && request.load.coupler_force.norm() > 0.0) {
    throw InputError(source +
                     ": --force: the four-bar has no coupler point (a function "
                     "generator): load its output with --output-torque");
  }
  bool sampled_task = false;
  const FourBarKinematics kinematics = AnalyzeOverTheRange<FourBarKinematics>(
      request, task, source + ": mechanisms[" + std::to_string(request.mechanism) + "]",
      [&](const std::optional<std::pair<double, double>>& range) {
        options.range = range;
        return AnalyzeFourBarKinematics(joints, options, length);
      },
      &sampled_task);
  const bool loaded = request.load.coupler_force.norm() > 0.0 ||
                      request.load.output_torque != 0.0 || request.load.slider_force != 0.0 ||
                      massive;
  const bool point = joints.coupler_point.has_value();
  const char* output_name = joints.slider ? "slider" : "output";

  if (request.csv) {
    std::string csv =
        "input_deg,coupler_angle_deg,coupler_angular_velocity,"
        "coupler_angular_acceleration";
    csv += joints.slider ? ",slider_position,slider_velocity,slider_acceleration"
                         : ",output_angle_deg,output_angular_velocity,output_angular_acceleration";
    if (point) {
      csv +=
          ",coupler_point_x,coupler_point_y,coupler_point_velocity_x,coupler_point_velocity_y,"
          "coupler_point_acceleration_x,coupler_point_acceleration_y";
    }
    csv += ",transmission_angle_deg,mechanical_advantage,input_torque";
    if (massive) csv += ",inertial_torque";
    if (masses.gravity) csv += ",weight_torque";
    csv += "\n";
    for (const FourBarState& state : kinematics.states) {
      std::vector<std::optional<double>> row = {
          state.input_angle * kDegree,
          state.coupler_angle * kDegree,
          state.coupler_velocity,
          state.coupler_acceleration,
          joints.slider ? state.output : state.output * kDegree,
          state.output_velocity,
          state.output_acceleration};
      if (point) {
        for (const Eigen::Vector2d* v : {&state.coupler_point, &state.coupler_point_velocity,
                                         &state.coupler_point_acceleration}) {
          row.push_back(v->x());
          row.push_back(v->y());
        }
      }
      row.push_back(state.transmission_angle_deg);
      row.push_back(state.mechanical_advantage);
      row.push_back(state.input_torque);
      if (massive) row.push_back(state.inertial_torque);
      if (masses.gravity) row.push_back(state.weight_torque);
      AppendCsvRow(row, &csv);
    }
    return csv;
  }

  Json out;
  out["mechanism"] = request.mechanism + 1;
  out["type"] = four_bar.type;
  out["input_speed_rad_s"] = request.input_speed;
  out["input_rotates_fully"] = kinematics.input_rotates_fully;
  out["input_range_deg"] = Json::array(
      {Number(kinematics.range_start * kDegree), Number(kinematics.range_end * kDegree)});
  out["sampled_range_deg"] = SampledRange(
      kinematics.states, [](const FourBarState& state) { return state.input_angle * kDegree; });
  if (task) {
    out["task_range_deg"] =
        Json::array({Number(task->first * kDegree), Number(task->second * kDegree)});
  }
  Json input_deg = Json::array(), transmission = Json::array(), advantage = Json::array();
  Json torque = Json::array(), p = Json::array(), v = Json::array(), a = Json::array();
  Json links = {
      {"input", Json::object()}, {"coupler", Json::object()}, {output_name, Json::object()}};
  Json angles[3] = {Json::array(), Json::array(), Json::array()};
  Json rates[3] = {Json::array(), Json::array(), Json::array()};
  Json accelerations[3] = {Json::array(), Json::array(), Json::array()};
  for (const FourBarState& state : kinematics.states) {
    input_deg.push_back(Number(state.input_angle * kDegree));
    angles[0].push_back(Number(state.input_angle * kDegree));
    rates[0].push_back(Number(request.input_speed));
    accelerations[0].push_back(0.0);
    angles[1].push_back(Number(state.coupler_angle * kDegree));
    rates[1].push_back(Number(state.coupler_velocity));
    accelerations[1].push_back(Number(state.coupler_acceleration));
    angles[2].push_back(Number(joints.slider ? state.output : state.output * kDegree));
    rates[2].push_back(Number(state.output_velocity));
    accelerations[2].push_back(Number(state.output_acceleration));
    if (point) {
      p.push_back(Point(state.coupler_point));
      v.push_back(Point(state.coupler_point_velocity));
      a.push_back(Point(state.coupler_point_acceleration));
    }
    transmission.push_back(Number(state.transmission_angle_deg));
    advantage.push_back(state.mechanical_advantage ? Number(*state.mechanical_advantage)
                                                   : Json(nullptr));
    torque.push_back(Number(state.input_torque));
  }
  out["input_deg"] = input_deg;
  const char* names[3] = {"input", "coupler", output_name};
  for (int l = 0; l < 3; ++l) {
    Json& link = links[names[l]];
    if (l == 2 && joints.slider) {
      link["position"] = angles[l];
      link["velocity"] = rates[l];
      link["acceleration"] = accelerations[l];
    } else {
      link["angle_deg"] = angles[l];
      link["angular_velocity"] = rates[l];
      link["angular_acceleration"] = accelerations[l];
    }
  }
  out["links"] = links;
  if (point) {
    out["coupler_point"] = p;
    out["coupler_point_velocity"] = v;
    out["coupler_point_acceleration"] = a;
  }
  out["transmission_angle_deg"] = transmission;
  // The worst over the steps: the least distance from a dead point, min(mu, 180 - mu).
  double worst = 90.0;
  for (const FourBarState& state : kinematics.states) {
    worst = std::min({worst, state.transmission_angle_deg, 180.0 - state.transmission_angle_deg});
  }
  out["transmission_angle_worst_deg"] = Number(worst);
  out["mechanical_advantage"] = advantage;
  if (loaded) {
    out["load"] = {{"coupler_force", Point(request.load.coupler_force)},
                   {"output_torque", Number(request.load.output_torque)},
                   {"slider_force", Number(request.load.slider_force)}};
    out["input_torque"] = torque;
    out["peak_input_torque"] = Number(kinematics.peak_input_torque);
  }
  if (massive) {
    PutMassParts(
        kinematics.states,
        {{"input", Number(masses.input)},
         {"coupler", Number(masses.coupler)},
         {joints.slider ? "slider" : "output", Number(masses.output)}},
        masses.gravity, "torque", [](const FourBarState& state) { return state.inertial_torque; },
        [](const FourBarState& state) { return state.weight_torque; }, &out);
  }
  Json dead = Json::array();
  for (const FourBarState& state : kinematics.dead_points) {
    Json at = {{"input_deg", Number(state.input_angle * kDegree)},
               {"transmission_angle_deg", Number(state.transmission_angle_deg)},
               {"input_pin", Point(state.input_pin)},
               {"output_pin", Point(state.output_pin)}};
    if (point) at["coupler_point"] = Point(state.coupler_point);
    dead.push_back(at);
  }
  out["dead_points"] = dead;
  Json notes = Json::array();
  if (!kinematics.note.empty()) notes.push_back(kinematics.note);
  AddDefectsNote(mechanism, &notes);
  if (sampled_task && !request.task_range) {
    notes.push_back(
        "the input is a rocker: sampled over the task's range (the crank's angles from the "
        "first task pose to the last); --range whole samples all of it between its dead points, "
        "where the rates grow without bound");
  } else if (!kinematics.input_rotates_fully && !request.range_deg && !sampled_task) {
    notes.push_back(
        "the input is a rocker: its range runs between its two dead points (listed), "
        "sampled inside them; toward them the rates and the torque grow without "
        "bound, so their peaks depend on --steps: give --range FROM,TO for the part "
        "the machine uses, or --task with the result's task for its range");
  }
  if (!point) notes.push_back("no coupler point in the result: its arrays are left out");
  if (massive) {
    notes.push_back(
        std::string("the links are taken as uniform bodies: the crank") +
        (joints.slider ? " a bar" : " and the rocker bars") +
        " between their joints, the coupler " +
        (point ? "a plate on its pins and the coupler point" : "a bar between its pins") +
        (joints.slider ? ", the slider a block" : "") +
        (masses.gravity ? "; gravity along -y" : ""));
  }
  out["units"] = {
      {"angles", "degrees"},
      {"angular_velocity", "rad/s"},
      {"angular_acceleration", "rad/s^2"},
      {"lengths", request.length_unit.empty() ? std::string("the result's") : request.length_unit},
      {"torque", request.length_unit.empty() ? std::string("N times the result's length unit")
                                             : "N " + request.length_unit},
      {"mechanical_advantage",
       joints.slider ? "output force / input torque (1/length)" : "output torque / input torque"}};
  out["notes"] = notes;
  return out.dump(2) + "\n";
}

void SetAnalysisRange(const std::string& range, const std::string& item, AnalysisRequest* request) {
  if (range == "task" || range == "whole") {
    (range == "task" ? request->task_range : request->whole_range) = true;
    return;
  }
  const size_t comma = range.find(',');
  double bounds[2];
  for (int k = 0; k < 2; ++k) {
    const std::string text = k == 0                       ? range.substr(0, comma)
                             : comma == std::string::npos ? ""
                                                          : range.substr(comma + 1);
    char* end = nullptr;
    bounds[k] = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || comma == std::string::npos) {
      throw InputError(item +
                       ": expected FROM,TO (the input's angles in degrees), task or whole, "
                       "got '" +
                       range + "'");
    }
  }
  request->range_deg = std::pair{bounds[0], bounds[1]};
}

}  // namespace linkfit
