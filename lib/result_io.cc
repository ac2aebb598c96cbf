// Result file writing (see result_io.h and the design's "Result file"). Field order follows
// the design; a value that is not finite is left out and a "<field>_note" says why.
#include "lib/result_io.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

namespace linkfit {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kNotFinite = "not finite";

// A path four-bar's `input_deg` (InputAngleAsWritten reads it back as task_io does).
double InputDegrees(double radians) { return radians * 180.0 / M_PI + 0.0; }

// object[key] = value, or object[key + "_note"] when the value is not finite. Adding 0.0
// writes -0 as 0.
void PutNumber(Json* object, const std::string& key, double value) {
  if (std::isfinite(value)) {
    (*object)[key] = value + 0.0;
  } else {
    (*object)[key + "_note"] = kNotFinite;
  }
}

void PutPoint(Json* object, const std::string& key, const Eigen::Vector2d& point) {
  if (point.allFinite()) {
    (*object)[key] = Json::array({point.x() + 0.0, point.y() + 0.0});
  } else {
    (*object)[key + "_note"] = kNotFinite;
  }
}

void PutPoint3(Json* object, const std::string& key, const Eigen::Vector3d& point) {
  if (point.allFinite()) {
    (*object)[key] = Json::array({point.x() + 0.0, point.y() + 0.0, point.z() + 0.0});
  } else {
    (*object)[key + "_note"] = kNotFinite;
  }
}

// "error_bound" (or `key`): how far the data's precision can move the dyad, or a note when the
// data do not determine it at their precision.
void PutErrorBound(
    Json* object, const std::optional<double>& error_bound,
    const char* undetermined = "the poses do not determine this dyad at the data's precision",
    const char* key = "error_bound") {
  if (!error_bound) return;
  if (std::isfinite(*error_bound)) {
    PutNumber(object, key, *error_bound);
  } else {
    (*object)["error_bound_note"] = undetermined;
  }
}

// A least-squares dyad's "rms_residual", and the seed's in "before_refinement" (when refined).
void PutLeastSquares(Json* object, const std::optional<double>& rms_residual,
                     const std::optional<double>& seed_rms_residual) {
  if (rms_residual) PutNumber(object, "rms_residual", *rms_residual);
  if (seed_rms_residual) {
    Json seed;
    PutNumber(&seed, "rms_residual", *seed_rms_residual);
    (*object)["before_refinement"] = seed;
  }
}

Json SpatialDyadToJson(const SpatialDyadReport& report) {
  const SpatialDyad& dyad = report.dyad;
  Json object;
  object["type"] = SpatialDyadTypeName(dyad.type);
  switch (dyad.type) {
    case SpatialDyadType::kSS:
      PutPoint3(&object, "fixed", dyad.fixed_pivot);
      PutPoint3(&object, "moving", dyad.moving_pivot);
      PutNumber(&object, "radius", dyad.radius);
      break;
    case SpatialDyadType::kPS:
      PutPoint3(&object, "moving", dyad.moving_pivot);
      PutPoint3(&object, "plane_normal", dyad.plane_normal);
      PutNumber(&object, "plane_offset", dyad.plane_offset);
      break;
    case SpatialDyadType::kSP:
      // The plane n . x = h lives in E.
      PutPoint3(&object, "fixed", dyad.fixed_pivot);
      PutPoint3(&object, "plane_normal_in_moving", dyad.plane_normal);
      PutNumber(&object, "plane_offset_in_moving", dyad.plane_offset);
      break;
  }
  PutNumber(&object, "max_residual", report.max_residual);
  PutErrorBound(&object, report.error_bound);
  if (report.rms_residual) PutNumber(&object, "rms_residual", *report.rms_residual);
  if (report.seed_max_residual) {
    Json seed;
    PutNumber(&seed, "max_residual", *report.seed_max_residual);
    if (report.seed_rms_residual) PutNumber(&seed, "rms_residual", *report.seed_rms_residual);
    object["before_refinement"] = seed;
  }
  return object;
}

// A planar dyad of planar data in a spatial task, in spatial coordinates: pivots on the plane
// of motion (Sigma) and on E's matching plane; the joint axes are the plane normal. The fixed
// pivot is thus the point of the plane of motion nearest the center of any sphere of the dyad's
// family (seed 000 eqs 37-38), found directly by solving in the plane.
Json EmbeddedDyadToJson(const DyadReport& report, const PlanarEmbedding& plane) {
  const PlanarDyad& dyad = report.dyad;
  const auto fixed = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(plane.origin_in_fixed + plane.axes_in_fixed.leftCols<2>() * p);
  };
  const auto moving = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(plane.axes_in_moving.leftCols<2>() * p);
  };
  Json object;
  object["type"] = DyadTypeName(dyad.type);
  switch (dyad.type) {
    case DyadType::kRR:
      PutPoint3(&object, "fixed", fixed(dyad.fixed_pivot));
      PutPoint3(&object, "moving", moving(dyad.moving_pivot));
      PutNumber(&object, "radius", dyad.radius);
      PutPoint3(&object, "axis", plane.axes_in_fixed.col(2));
      break;
    case DyadType::kPR:
      PutPoint3(&object, "moving", moving(dyad.moving_pivot));
      PutPoint3(&object, "line_point", fixed(dyad.LineFoot()));
      PutPoint3(&object, "line_direction", plane.axes_in_fixed.leftCols<2>() * dyad.line_direction);
      break;
    case DyadType::kRP:
      PutPoint3(&object, "fixed", fixed(dyad.fixed_pivot));
      PutPoint3(&object, "line_point_in_moving", moving(dyad.LineFoot()));
      PutPoint3(&object, "line_direction_in_moving",
                plane.axes_in_moving.leftCols<2>() * dyad.line_direction);
      break;
  }
  PutNumber(&object, "max_residual", report.max_residual);
  PutErrorBound(&object, report.error_bound);
  return object;
}

Json DyadToJson(const DyadReport& report) {
  const PlanarDyad& dyad = report.dyad;
  Json object;
  object["type"] = DyadTypeName(dyad.type);
  switch (dyad.type) {
    case DyadType::kRR:
      PutPoint(&object, "fixed", dyad.fixed_pivot);
      PutPoint(&object, "moving", dyad.moving_pivot);
      PutNumber(&object, "radius", dyad.radius);
      break;
    case DyadType::kPR:
      PutPoint(&object, "moving", dyad.moving_pivot);
      PutPoint(&object, "line_point", dyad.LineFoot());
      PutNumber(&object, "line_angle_deg", dyad.LineAngleDeg());
      break;
    case DyadType::kRP:
      PutPoint(&object, "fixed", dyad.fixed_pivot);
      PutPoint(&object, "line_point", dyad.LineFoot());
      PutNumber(&object, "line_angle_deg", dyad.LineAngleDeg());
      break;
  }
  PutNumber(&object, "max_residual", report.max_residual);
  PutErrorBound(&object, report.error_bound);
  PutLeastSquares(&object, report.rms_residual, report.seed_rms_residual);
  return object;
}

// A spherical dyad: its axes through the centre (unit; fixed in Sigma, moving in E) and the
// constant angle between them.
Json SphericalDyadToJson(const SphericalDyadReport& report) {
  Json object;
  object["type"] = "RR";
  PutPoint3(&object, "fixed_axis", report.dyad.fixed_axis);
  PutPoint3(&object, "moving_axis", report.dyad.moving_axis);
  PutNumber(&object, "angle_deg", report.dyad.angle * 180.0 / M_PI);
  PutNumber(&object, "max_residual", report.max_residual);
  if (report.error_bound) {
    PutErrorBound(&object, *report.error_bound * 180.0 / M_PI,
                  "the orientations do not determine this dyad at the data's precision",
                  "error_bound_deg");
  }
  PutLeastSquares(&object, report.rms_residual, report.seed_rms_residual);
  return object;
}

// The four-bar as a designer reads it, one layout for every problem (issue 35): its joints in
// Sigma in one configuration and its links by name. `input` and `output` hold that configuration
// in Sigma (their moving pivots, and an RP's line on the coupler, where the coupler has them);
// `coupler_point` is the coupler's traced point (path) or the body frame's origin (motion).
Json LinkageToJson(const PlanarDyad& input, const PlanarDyad& output,
                   const std::optional<Eigen::Vector2d>& coupler_point) {
  Json joints, links;
  const FourBarLinks named = MotionFourBarLinks(input, output);
  if (named.ground) PutNumber(&links, "ground", *named.ground);
  if (named.input) PutNumber(&links, "input", *named.input);
  if (named.coupler) PutNumber(&links, "coupler", *named.coupler);
  if (named.output) PutNumber(&links, "output", *named.output);
  for (const auto& [side, dyad] : {std::pair<std::string, const PlanarDyad*>{"input", &input},
                                   std::pair<std::string, const PlanarDyad*>{"output", &output}}) {
    if (dyad->type != DyadType::kPR) PutPoint(&joints, side + "_pivot", dyad->fixed_pivot);
    if (dyad->type != DyadType::kRP) PutPoint(&joints, side + "_pin", dyad->moving_pivot);
    if (dyad->type == DyadType::kRR) continue;
    // A slider's line: fixed in Sigma (PR), or carried by the coupler (RP), where it is now;
    // its offset, how far it passes from the other side's pivot (PR) or pin (RP).
    Json line;
    PutPoint(&line, "point", dyad->LineFoot());
    PutNumber(&line, "angle_deg", dyad->LineAngleDeg());
    line["on"] = dyad->type == DyadType::kPR ? "ground" : "coupler";
    joints[side + "_slider_line"] = line;
    const PlanarDyad& other = dyad == &input ? output : input;
    if (other.type == DyadType::kRR) {
      const Eigen::Vector2d normal =
          Eigen::Vector2d(-dyad->line_direction.y(), dyad->line_direction.x()).normalized();
      const Eigen::Vector2d& reference =
          dyad->type == DyadType::kPR ? other.fixed_pivot : other.moving_pivot;
      PutNumber(&links, side + "_slider_offset",
                std::abs(normal.dot(reference - dyad->LineFoot())));
    }
  }
  if (coupler_point) {
    PutPoint(&joints, "coupler_point", *coupler_point);
    // The coupler point from the input pin: its distance, and its angle from the coupler line
    // (input pin to output pin), counter-clockwise; 0 for a point at the pin.
    if (input.type != DyadType::kRP && output.type != DyadType::kRP) {
      const Eigen::Vector2d along = output.moving_pivot - input.moving_pivot;
      const Eigen::Vector2d to_point = *coupler_point - input.moving_pivot;
      const bool at_pin = !(to_point.norm() > 1e-9 * std::max(1.0, along.norm()));
      Json offset;
      PutNumber(&offset, "distance", to_point.norm());
      PutNumber(&offset, "angle_deg",
                at_pin ? 0.0
                       : std::atan2(along.x() * to_point.y() - along.y() * to_point.x(),
                                    along.dot(to_point)) *
                             180.0 / M_PI);
      links["coupler_point"] = offset;
    }
  }
  return Json{{"joints", joints}, {"links", links}};
}

// A spherical four-bar in the same layout (issue 35): its joints are axes through the centre
// (unit vectors in Sigma, the pins carried by the body at `rotation`) and its links the angles
// between them, in degrees ("units" says so).
Json SphericalLinkageToJson(const SphericalDyad& input, const SphericalDyad& output,
                            const Eigen::Matrix3d& rotation) {
  Json joints, links;
  const auto degrees = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return DirectionAngle(a, b) * 180.0 / M_PI;
  };
  PutNumber(&links, "ground", degrees(input.fixed_axis, output.fixed_axis));
  PutNumber(&links, "input", input.angle * 180.0 / M_PI);
  PutNumber(&links, "coupler", degrees(input.moving_axis, output.moving_axis));
  PutNumber(&links, "output", output.angle * 180.0 / M_PI);
  PutPoint3(&joints, "input_pivot", input.fixed_axis.normalized());
  PutPoint3(&joints, "input_pin", (rotation * input.moving_axis).normalized());
  PutPoint3(&joints, "output_pivot", output.fixed_axis.normalized());
  PutPoint3(&joints, "output_pin", (rotation * output.moving_axis).normalized());
  return Json{{"joints", joints},
              {"links", links},
              {"units",
               {{"joints", "unit axes through the centre, in Sigma"},
                {"links", "deg: the angles between the axes (arcs of the unit sphere)"}}}};
}

Json MechanismToJson(const MechanismReport& report) {
  Json object;
  object["type"] = FourBarTypeName(report.type);
  object["dyads"] = Json::array({report.input_dyad, report.output_dyad});
  if (report.max_pose_error && std::isfinite(*report.max_pose_error)) {
    object["max_pose_error"] = *report.max_pose_error;
  } else if (report.max_pose_error) {
    object["max_pose_error_note"] = kNotFinite;
  } else {
    object["max_pose_error_note"] =
        report.pose_error_note.empty() ? "not computed" : report.pose_error_note;
  }
  if (report.rms_pose_error) PutNumber(&object, "rms_pose_error", *report.rms_pose_error);
  if (report.exact_pose_error) PutNumber(&object, "exact_pose_error", *report.exact_pose_error);
  if (report.seed_max_pose_error) {
    Json seed;
    PutNumber(&seed, "max_pose_error", *report.seed_max_pose_error);
    object["before_refinement"] = seed;
  }
  if (!report.chosen.empty()) {
    object["chosen"] = report.chosen;
    if (std::all_of(report.pose_errors.begin(), report.pose_errors.end(),
                    [](double error) { return std::isfinite(error); })) {
      object["pose_errors"] = report.pose_errors;
    } else {
      object["pose_errors_note"] = kNotFinite;
    }
  }
  if (!report.grashof.empty()) object["grashof"] = report.grashof;
  object["defects"] = report.defects;
  object["violates"] = report.violates;
  object["full_rotation"] = {{"input", report.input_rotates_fully},
                             {"output", report.output_rotates_fully}};
  if (report.transmission_min_deg && report.transmission_max_deg &&
      std::isfinite(*report.transmission_min_deg) && std::isfinite(*report.transmission_max_deg)) {
    object["transmission_angle_deg"] =
        Json::array({*report.transmission_min_deg, *report.transmission_max_deg});
  } else {
    object["transmission_angle_note"] =
        report.transmission_note.empty() ? "not computed" : report.transmission_note;
  }
  return object;
}

Json PathMechanismToJson(const PathMechanismReport& report) {
  const PathFourBar& design = report.design;
  Json object;
  object["type"] = FourBarTypeName(report.type);
  PutPoint(&object, "input_pivot", design.input.fixed_pivot);
  PutPoint(&object, "input_moving", design.input.moving_pivot);
  if (design.output.type != DyadType::kPR) {
    PutPoint(&object, "output_pivot", design.output.fixed_pivot);
  }
  if (design.output.type != DyadType::kRP) {
    PutPoint(&object, "output_moving", design.output.moving_pivot);
  }
  if (design.output.type != DyadType::kRR) {
    // PR: the slider line in Sigma; RP: the line of the coupler, where it is at the first point.
    PutPoint(&object, "output_line_point", design.output.LineFoot());
    PutNumber(&object, "output_line_angle_deg", design.output.LineAngleDeg());
  }
  PutPoint(&object, "coupler_point", design.coupler_point);
  if (report.exact_point_error) PutNumber(&object, "exact_point_error", *report.exact_point_error);
  if (report.max_point_error) {
    PutNumber(&object, "max_point_error", *report.max_point_error);
  } else {
    object["max_point_error_note"] = report.error_note.empty() ? "not computed" : report.error_note;
  }
  if (report.rms_point_error) PutNumber(&object, "rms_point_error", *report.rms_point_error);
  PutErrorBound(&object, report.error_bound,
                "the points do not determine this four-bar at the data's precision");
  if (report.seed_max_point_error) {
    Json seed;
    PutNumber(&seed, "max_point_error", *report.seed_max_point_error);
    object["before_refinement"] = seed;
  }
  object["defects"] = report.defects;
  object["violates"] = report.violates;
  if (!report.grashof.empty()) object["grashof"] = report.grashof;
  object["input_rotates_fully"] = report.input_rotates_fully;
  if (report.transmission_min_deg && report.transmission_max_deg) {
    PutNumber(&object, "transmission_angle_min_deg", *report.transmission_min_deg);
    PutNumber(&object, "transmission_angle_max_deg", *report.transmission_max_deg);
  }
  if (!report.input_angles.empty()) {
    Json angles = Json::array();
    for (double angle : report.input_angles) angles.push_back(InputDegrees(angle));
    object["input_deg"] = angles;
  }
  return object;
}

Json FunctionMechanismToJson(const FunctionMechanismReport& report) {
  const FunctionFourBar& design = report.design;
  constexpr double kDeg = 180.0 / M_PI;
  Json object;
  object["type"] = "4R";
  if (report.first) {
    PutPoint(&object, "input_pivot", report.first->input_pivot);
    PutPoint(&object, "input_moving", report.first->input_moving);
    PutPoint(&object, "output_pivot", report.first->output_pivot);
    PutPoint(&object, "output_moving", report.first->output_moving);
  }
  PutNumber(&object, "ground_length", design.ground);
  PutNumber(&object, "input_length", design.input_length);
  PutNumber(&object, "coupler_length", design.coupler_length);
  PutNumber(&object, "output_length", design.output_length);
  // Relative angles: the cranks' directions are offset + the task's angle (from the ground line).
  PutNumber(&object, "input_offset_deg", design.input_offset * kDeg + 0.0);
  PutNumber(&object, "output_offset_deg", design.output_offset * kDeg + 0.0);
  if (report.exact_angle_error) {
    PutNumber(&object, "exact_angle_error_deg", *report.exact_angle_error * kDeg);
  }
  if (report.max_angle_error) {
    PutNumber(&object, "max_angle_error_deg", *report.max_angle_error * kDeg);
  } else {
    object["max_angle_error_note"] = report.error_note.empty() ? "not computed" : report.error_note;
  }
  if (report.rms_angle_error) {
    PutNumber(&object, "rms_angle_error_deg", *report.rms_angle_error * kDeg);
  }
  if (report.function_max_error) {
    PutNumber(&object, "function_max_error_deg", *report.function_max_error * kDeg);
  } else if (!report.function_error_note.empty()) {
    object["function_max_error_deg_note"] = report.function_error_note;
  }
  PutErrorBound(&object, report.error_bound,
                "the pairs do not determine this four-bar at the data's precision");
  if (report.seed_max_angle_error) {
    Json seed;
    PutNumber(&seed, "max_angle_error_deg", *report.seed_max_angle_error * kDeg);
    object["before_refinement"] = seed;
  }
  object["defects"] = report.defects;
  object["violates"] = report.violates;
  if (!report.grashof.empty()) object["grashof"] = report.grashof;
  object["input_rotates_fully"] = report.input_rotates_fully;
  object["output_rotates_fully"] = report.output_rotates_fully;
  if (report.transmission_min_deg && report.transmission_max_deg) {
    PutNumber(&object, "transmission_angle_min_deg", *report.transmission_min_deg);
    PutNumber(&object, "transmission_angle_max_deg", *report.transmission_max_deg);
  }
  return object;
}

Json StagesToJson(const std::vector<StageReport>& stages) {
  Json list = Json::array();
  for (const StageReport& stage : stages) {
    Json object;
    object["stage"] = stage.name;
    PutNumber(&object, "time_ms", stage.seconds * 1000.0);
    if (stage.best_dyad_rms) PutNumber(&object, "best_dyad_rms_residual", *stage.best_dyad_rms);
    if (stage.best_max_pose_error) {
      PutNumber(&object, "best_max_pose_error", *stage.best_max_pose_error);
    }
    if (stage.best_max_point_error) {
      PutNumber(&object, "best_max_point_error", *stage.best_max_point_error);
    }
    if (stage.best_max_angle_error) {
      PutNumber(&object, "best_max_angle_error_deg", *stage.best_max_angle_error * 180.0 / M_PI);
    }
    list.push_back(object);
  }
  return list;
}

// Puts arrays of plain numbers (points, index pairs) of pretty-printed JSON on one line:
// "[\n    1.5,\n    2\n  ]" -> "[1.5, 2]". Only text outside strings is touched.
std::string CompactNumberArrays(const std::string& text) {
  // The characters of a number array's inside (a table, not strchr per character: results with
  // Burmester curves hold ten thousand points).
  static const std::array<bool, 256> kNumeric = [] {
    std::array<bool, 256> table{};
    for (const char c : std::string("0123456789+-.eE, \n")) {
      table[static_cast<unsigned char>(c)] = true;
    }
    return table;
  }();
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      out += c;
      if (c == '\\') {
        out += text[++i];
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') in_string = true;
    if (c != '[') {
      out += c;
      continue;
    }
    // Find the matching ']' if everything up to it is numbers, commas and white space.
    size_t end = i + 1;
    while (end < text.size() && kNumeric[static_cast<unsigned char>(text[end])]) ++end;
    if (end >= text.size() || text[end] != ']') {
      out += c;
      continue;
    }
    out += '[';
    bool pending_space = false;
    for (size_t k = i + 1; k < end; ++k) {
      const char d = text[k];
      if (d == ' ' || d == '\n') continue;
      if (pending_space) out += ' ';
      out += d;
      pending_space = d == ',';
    }
    out += ']';
    i = end;
  }
  return out;
}

// "precision": the data precision the solve assumed (lib/precision.h), and "closed" when the
// task's last pose or point repeated the first.
void PutPrecision(Json* root, const DataPrecision& precision, bool closed) {
  Json object;
  PutNumber(&object, "length", precision.length);
  PutNumber(&object, "angle_deg", precision.angle * 180.0 / M_PI);
  object["source"] = precision.source;
  (*root)["precision"] = object;
  if (closed) (*root)["closed"] = true;
}

// "constraints": the design constraints the result was judged by (lib/design_constraints.h),
// the task's and the defaults in force, which "defaults" names. `lengths` false (spherical
// four-bars, whose links are angles): only the class and transmission constraints.
void PutConstraints(Json* root, const DesignConstraints& constraints, double scale,
                    bool lengths = true) {
  Json object;
  Json defaults = Json::array();
  if (lengths) {
    PutNumber(&object, "max_link_length", MaxLinkLength(constraints, scale));
    if (!constraints.max_link_length) defaults.push_back("max_link_length");
  }
  if (constraints.min_link_length) {
    PutNumber(&object, "min_link_length", *constraints.min_link_length);
  }
  if (constraints.max_coupler_point_offset) {
    PutNumber(&object, "max_coupler_point_offset", *constraints.max_coupler_point_offset);
  }
  for (const auto& [key, box] : {std::pair{"fixed_pivots_box", &constraints.fixed_pivots_box},
                                 std::pair{"moving_pivots_box", &constraints.moving_pivots_box}}) {
    if (*box) {
      object[key] = Json::array({Json::array({(*box)->min.x(), (*box)->min.y()}),
                                 Json::array({(*box)->max.x(), (*box)->max.y()})});
    }
  }
  if (constraints.input_rotates_fully) object["input_rotates_fully"] = true;
  if (!constraints.grashof.empty()) object["grashof"] = constraints.grashof;
  PutNumber(&object, "min_transmission_angle_deg", MinTransmissionAngleDeg(constraints));
  if (!constraints.min_transmission_angle_deg) defaults.push_back("min_transmission_angle_deg");
  if (!defaults.empty()) object["defaults"] = defaults;
  (*root)["constraints"] = object;
}

std::string Dump(const Json& root, int indent) {
  // Notes are library text, but never let a stray byte turn into an exception here.
  const std::string text =
      root.dump(indent < 0 ? -1 : indent, ' ', false, Json::error_handler_t::replace);
  return indent < 0 ? text : CompactNumberArrays(text);
}

// A six-bar (lib/six_bar.h) as a result lists it: its joints at the first task pose in Sigma, its
// links by name and length, the body that drives it, and its analysis.
Json SixBarToJson(const SixBarReport& report) {
  static const char* const kBodies[] = {"ground",    "upper link", "forearm",
                                        "task body", "first link", "second link"};
  const SixBar& six_bar = report.six_bar;
  const auto point = [](const Eigen::Vector2d& p) { return Json::array({p.x(), p.y()}); };
  Json object;
  object["linkage"] = "six-bar";
  object["topology"] = SixBarTopologyName(six_bar.topology);
  object["input"] = kBodies[report.input];
  Json joints;
  joints["ground_pivot"] = point(six_bar.ground_pivot);
  joints["elbow"] = point(six_bar.elbow);
  joints["wrist"] = point(six_bar.wrist);
  Json links = Json::array();
  for (const SixBarRRLink& link : six_bar.links) {
    Json entry;
    entry["from"] = kBodies[link.from_body];
    entry["to"] = kBodies[link.to_body];
    entry["from_joint"] = point(link.from_joint);
    entry["to_joint"] = point(link.to_joint);
    PutNumber(&entry, "length", link.Length());
    links.push_back(entry);
  }
  joints["links"] = links;
  object["joints_at_first_pose"] = joints;
  const PlanarPose& task_body = six_bar.reference_pose;
  object["task_body_at_first_pose"] =
      Json::array({task_body.origin_in_fixed.x(), task_body.origin_in_fixed.y(),
                   task_body.theta * 180.0 / M_PI});
  Json lengths;
  PutNumber(&lengths, "upper_link", (six_bar.elbow - six_bar.ground_pivot).norm());
  PutNumber(&lengths, "forearm", (six_bar.wrist - six_bar.elbow).norm());
  PutNumber(&lengths, "first_link", six_bar.links[0].Length());
  PutNumber(&lengths, "second_link", six_bar.links[1].Length());
  object["link_lengths"] = lengths;
  object["defects"] = report.defects;
  object["violates"] = report.violates;
  object["transmission_angle_min_deg"] =
      Json::array({report.transmission_min_deg[0], report.transmission_min_deg[1]});
  object["input_rotates_fully"] = report.input_rotates_fully;
  PutNumber(&object, "max_pose_error", report.max_pose_error);
  PutNumber(&object, "rms_pose_error", report.rms_pose_error);
  PutErrorBound(&object, report.error_bound,
                "the poses do not determine this six-bar's links at the data's precision");
  Json angles = Json::array();
  for (double angle : report.input_angles) angles.push_back(InputDegrees(angle));
  object["input_deg"] = angles;
  // Each pose's configuration, for `linkfit refine` (a circuit defect puts poses on another
  // assembly than the input's continuation reaches).
  Json turns = Json::array();
  for (const SixBarAngles& at : report.at_poses) {
    Json pose = Json::array();
    for (int k = 0; k < 5; ++k) pose.push_back(at[k] * 180.0 / M_PI);
    turns.push_back(pose);
  }
  if (!report.at_poses.empty()) object["turns_at_poses_deg"] = turns;
  return object;
}

}  // namespace

double InputAngleAsWritten(double radians) {
  return InputDegrees(radians) * (M_PI / 180.0);  // task_io: input_deg times kDegree
}

std::string ResultToJson(const SpatialMotionResult& result, int indent) {
  Json root;
  root["problem"] = "motion";
  root["space"] = "spatial";
  root["model"] = result.model;
  root["method"] = result.method;
  PutNumber(&root, "scale", result.scale);
  PutPrecision(&root, result.precision, result.closed);
  if (result.spherical) {
    PutPoint3(&root, "center", result.spherical->in_fixed);
    Json sphere;
    PutPoint3(&sphere, "center_in_moving", result.spherical->in_moving);
    PutNumber(&sphere, "largest_deviation", result.spherical->sphericity);
    root["spherical"] = sphere;
  }
  root["dyads"] = Json::array();
  root["mechanisms"] = Json::array();
  if (result.model == "spherical") {
    PutConstraints(&root, result.constraints, result.scale, false);
    for (const SphericalDyadReport& dyad : result.spherical_dyads) {
      root["dyads"].push_back(SphericalDyadToJson(dyad));
    }
    for (const MechanismReport& mechanism : result.spherical_mechanisms) {
      Json object = MechanismToJson(mechanism);
      if (mechanism.first_rotation) {
        object["linkage"] = SphericalLinkageToJson(
            result.spherical_dyads[mechanism.input_dyad].dyad,
            result.spherical_dyads[mechanism.output_dyad].dyad, *mechanism.first_rotation);
      }
      root["mechanisms"].push_back(object);
    }
    if (!result.center_axis_curves.empty() || !result.circle_axis_curves.empty()) {
      Json cones;
      for (const auto& [name, polylines] : {std::pair{"center_axes", &result.center_axis_curves},
                                            std::pair{"circle_axes", &result.circle_axis_curves}}) {
        Json list = Json::array();
        for (const std::vector<Eigen::Vector3d>& polyline : *polylines) {
          Json points = Json::array();
          for (const Eigen::Vector3d& point : polyline) {
            if (point.allFinite()) points.push_back(Json::array({point.x(), point.y(), point.z()}));
          }
          if (!points.empty()) list.push_back(points);
        }
        cones[name] = list;
      }
      root["burmester_cones"] = cones;
    }
  } else if (result.plane && result.planar) {
    const PlanarEmbedding& plane = *result.plane;
    Json frame;
    PutPoint3(&frame, "origin", plane.origin_in_fixed);
    PutPoint3(&frame, "normal", plane.axes_in_fixed.col(2));
    PutPoint3(&frame, "x_axis", plane.axes_in_fixed.col(0));
    PutPoint3(&frame, "y_axis", plane.axes_in_fixed.col(1));
    PutPoint3(&frame, "x_axis_in_moving", plane.axes_in_moving.col(0));
    PutPoint3(&frame, "y_axis_in_moving", plane.axes_in_moving.col(1));
    PutNumber(&frame, "largest_deviation", plane.planarity);
    root["plane"] = frame;
    for (const DyadReport& dyad : result.planar->dyads) {
      root["dyads"].push_back(EmbeddedDyadToJson(dyad, plane));
    }
    for (const MechanismReport& mechanism : result.planar->mechanisms) {
      root["mechanisms"].push_back(MechanismToJson(mechanism));
    }
  } else {
    for (const SpatialDyadReport& dyad : result.dyads) {
      root["dyads"].push_back(SpatialDyadToJson(dyad));
    }
    for (const PlatformReport& platform : result.mechanisms) {
      Json object;
      object["type"] = "platform";
      object["dyads"] = platform.dyads;
      object["assembles"] = platform.assembles;
      object["one_branch"] = platform.one_branch;
      object["closed_loop"] = platform.closed;
      if (platform.max_pose_error) {
        PutNumber(&object, "max_pose_error", *platform.max_pose_error);
      } else {
        object["max_pose_error_note"] = "the platform does not assemble at the first pose";
      }
      object["order"] = platform.order;
      if (!platform.note.empty()) object["note"] = platform.note;
      root["mechanisms"].push_back(object);
    }
  }
  if (result.roots_total > 0) {
    root["roots"] = Json{{"total", result.roots_total}, {"real", result.roots_real}};
  }
  std::vector<std::string> notes = result.notes;
  if (result.planar) {
    notes.insert(notes.end(), result.planar->notes.begin(), result.planar->notes.end());
  }
  if (!notes.empty()) root["notes"] = notes;
  PutNumber(&root, "solve_time_ms", result.solve_seconds * 1000.0);
  if (result.refine_seconds > 0.0)
    PutNumber(&root, "refine_time_ms", result.refine_seconds * 1000.0);
  if (result.search_seconds > 0.0)
    PutNumber(&root, "search_time_ms", result.search_seconds * 1000.0);
  return Dump(root, indent);
}

std::string ResultToJson(const TaskResult& result, int indent) {
  return std::visit([indent](const auto& value) { return ResultToJson(value, indent); }, result);
}

// The polylines simplified (Ramer-Douglas-Peucker) to at most `max_points` points in all, each
// keeping its ends: the tolerance is the smallest (by bisection on the extent's scale) that
// leaves no more. Unchanged when they have no more already.
std::vector<std::vector<Eigen::Vector2d>> SimplifiedPolylines(
    const std::vector<std::vector<Eigen::Vector2d>>& polylines, size_t max_points) {
  size_t total = 0;
  Eigen::AlignedBox2d box;
  for (const std::vector<Eigen::Vector2d>& polyline : polylines) {
    total += polyline.size();
    for (const Eigen::Vector2d& point : polyline) {
      if (point.allFinite()) box.extend(point);
    }
  }
  if (total <= max_points || box.isEmpty()) return polylines;
  const auto simplify = [&](double tolerance) {
    std::vector<std::vector<Eigen::Vector2d>> out;
    for (const std::vector<Eigen::Vector2d>& polyline : polylines) {
      const size_t n = polyline.size();
      std::vector<char> keep(n, n <= 2);
      if (n > 2) {
        keep[0] = keep[n - 1] = 1;
        std::vector<std::pair<size_t, size_t>> stack = {{0, n - 1}};
        while (!stack.empty()) {
          const auto [first, last] = stack.back();
          stack.pop_back();
          const Eigen::Vector2d a = polyline[first], b = polyline[last];
          const Eigen::Vector2d chord = b - a;
          double farthest = -1.0;
          size_t at = first;
          for (size_t k = first + 1; k < last; ++k) {
            const Eigen::Vector2d p = polyline[k] - a;
            const double t = chord.squaredNorm() > 0.0
                                 ? std::clamp(p.dot(chord) / chord.squaredNorm(), 0.0, 1.0)
                                 : 0.0;
            const double distance = (p - t * chord).norm();
            if (!(distance <= farthest)) farthest = distance, at = k;
          }
          if (at > first && !(farthest <= tolerance)) {
            keep[at] = 1;
            stack.push_back({first, at});
            stack.push_back({at, last});
          }
        }
      }
      std::vector<Eigen::Vector2d> kept;
      for (size_t k = 0; k < n; ++k) {
        if (keep[k]) kept.push_back(polyline[k]);
      }
      out.push_back(kept);
    }
    return out;
  };
  const auto count = [](const std::vector<std::vector<Eigen::Vector2d>>& lines) {
    size_t points = 0;
    for (const auto& line : lines) points += line.size();
    return points;
  };
  double low = 0.0, high = box.diagonal().norm();
  std::vector<std::vector<Eigen::Vector2d>> best = simplify(high);
  for (int round = 0; round < 40; ++round) {
    const double middle = 0.5 * (low + high);
    std::vector<std::vector<Eigen::Vector2d>> trial = simplify(middle);
    if (count(trial) <= max_points) {
      high = middle;
      best = std::move(trial);
    } else {
      low = middle;
    }
  }
  return best;
}

std::string ResultToJson(const PlanarMotionResult& result, int indent) {
  Json root;
  root["problem"] = ProblemKindName(result.problem);
  root["space"] = SpaceName(result.space);
  root["method"] = result.method;
  PutNumber(&root, "scale", result.scale);
  PutPrecision(&root, result.precision, result.closed);
  PutConstraints(&root, result.constraints, result.scale);
  root["dyads"] = Json::array();
  for (const DyadReport& dyad : result.dyads) root["dyads"].push_back(DyadToJson(dyad));
  root["mechanisms"] = Json::array();
  for (const MechanismReport& mechanism : result.mechanisms) {
    Json object = MechanismToJson(mechanism);
    if (mechanism.first_configuration) {
      // The dyads where the coupler is in its configuration nearest the first task pose.
      const PlanarPose& pose = *mechanism.first_configuration;
      Similarity2 coupler;
      coupler.angle = pose.theta;
      coupler.translation = pose.origin_in_fixed;
      const auto at_pose = [&](int index) {
        return TransformDyad(result.dyads[index].dyad, Similarity2(), coupler);
      };
      object["linkage"] = LinkageToJson(at_pose(mechanism.input_dyad),
                                        at_pose(mechanism.output_dyad), pose.origin_in_fixed);
    }
    root["mechanisms"].push_back(object);
  }
  if (result.chain) {
    const SixBarChain& chain = *result.chain;
    Json object;
    object["ground_pivot"] = Json::array({chain.ground_pivot.x(), chain.ground_pivot.y()});
    object["wrist"] = Json::array({chain.wrist_in_moving.x(), chain.wrist_in_moving.y()});
    object["link_lengths"] = Json::array({chain.upper_length, chain.forearm_length});
    if (chain.elbow_at_first_pose) {
      object["elbow_at_first_pose"] =
          Json::array({chain.elbow_at_first_pose->x(), chain.elbow_at_first_pose->y()});
    } else {
      object["elbow"] = chain.elbow_left ? "left" : "right";
    }
    if (chain.hold) object["hold"] = true;
    root["chain"] = object;
    if (result.chain_chosen) root["chain_chosen"] = true;
  }
  if (result.six_bar || result.chain) {
    root["six_bars"] = Json::array();
    for (const SixBarReport& report : result.six_bars) {
      root["six_bars"].push_back(SixBarToJson(report));
    }
  }
  if (result.roots_total > 0) {
    root["roots"] = Json{{"total", result.roots_total}, {"real", result.roots_real}};
  }
  if (!result.center_point_curves.empty() || !result.circle_point_curves.empty()) {
    Json curves;
    for (const auto& [name, polylines] :
         {std::pair{"center_points", &result.center_point_curves},
          std::pair{"circle_points", &result.circle_point_curves}}) {
      Json list = Json::array();
      for (const std::vector<Eigen::Vector2d>& polyline :
           SimplifiedPolylines(*polylines, static_cast<size_t>(std::max(result.curve_points, 2)))) {
        Json points = Json::array();
        for (const Eigen::Vector2d& point : polyline) {
          if (point.allFinite()) points.push_back(Json::array({point.x(), point.y()}));
        }
        if (!points.empty()) list.push_back(points);
      }
      curves[name] = list;
    }
    root["burmester_curves"] = curves;
  }
  if (!result.effort.empty()) root["effort"] = result.effort;
  if (!result.stages.empty()) root["stages"] = StagesToJson(result.stages);
  if (!result.notes.empty()) root["notes"] = result.notes;
  PutNumber(&root, "solve_time_ms", result.solve_seconds * 1000.0);
  return Dump(root, indent);
}

std::string ResultToJson(const PathResult& result, int indent) {
  Json root;
  root["problem"] = "path";
  root["space"] = "planar";
  root["method"] = result.method;
  root["timing"] = result.timing;
  PutNumber(&root, "scale", result.scale);
  PutPrecision(&root, result.precision, false);
  root["closed"] = result.closed;
  PutConstraints(&root, result.constraints, result.scale);
  root["mechanisms"] = Json::array();
  for (const PathMechanismReport& mechanism : result.mechanisms) {
    Json object = PathMechanismToJson(mechanism);
    object["linkage"] = LinkageToJson(mechanism.design.input, mechanism.design.output,
                                      mechanism.design.coupler_point);
    root["mechanisms"].push_back(object);
  }
  if (result.four_bars_total > 0) {
    root["roots"] = Json{{"cranks", result.crank_roots_total},
                         {"real_cranks", result.crank_roots_real},
                         {"four_bars", result.four_bars_total}};
  }
  if (!result.effort.empty()) root["effort"] = result.effort;
  if (!result.stages.empty()) root["stages"] = StagesToJson(result.stages);
  if (!result.notes.empty()) root["notes"] = result.notes;
  PutNumber(&root, "solve_time_ms", result.solve_seconds * 1000.0);
  return Dump(root, indent);
}

std::string ResultToJson(const FunctionResult& result, int indent) {
  Json root;
  root["problem"] = "function";
  root["method"] = result.method;
  root["angles"] = result.relative_angles ? "relative" : "absolute";
  root["ground"] = Json::array({Json::array({result.ground_input.x(), result.ground_input.y()}),
                                Json::array({result.ground_output.x(), result.ground_output.y()})});
  PutNumber(&root, "scale", result.scale);
  PutPrecision(&root, result.precision, false);
  PutConstraints(&root, result.constraints, result.scale);
  if (!result.precision_points.empty()) {
    Json points = Json::array();
    for (const FunctionPair& pair : result.precision_points) {
      points.push_back(Json{{"input_deg", pair.input * 180.0 / M_PI + 0.0},
                            {"output_deg", pair.output * 180.0 / M_PI + 0.0}});
    }
    root["precision_points"] = points;
  }
  root["mechanisms"] = Json::array();
  for (const FunctionMechanismReport& mechanism : result.mechanisms) {
    Json object = FunctionMechanismToJson(mechanism);
    if (mechanism.first) {
      const FunctionConfiguration& at = *mechanism.first;
      object["linkage"] = LinkageToJson(
          PlanarDyad::RR(at.input_pivot, at.input_moving, mechanism.design.input_length),
          PlanarDyad::RR(at.output_pivot, at.output_moving, mechanism.design.output_length),
          std::nullopt);
    }
    root["mechanisms"].push_back(object);
  }
  if (!result.effort.empty()) root["effort"] = result.effort;
  if (!result.stages.empty()) root["stages"] = StagesToJson(result.stages);
  if (!result.notes.empty()) root["notes"] = result.notes;
  PutNumber(&root, "solve_time_ms", result.solve_seconds * 1000.0);
  return Dump(root, indent);
}

}  // namespace linkfit
