#include "apps/cad_export.h"

#include <dl_dxf.h>
#include <stdlib.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "lib/analysis_io.h"
#include "lib/dyad_four_bar_kinematics.h"
#include "lib/four_bar_kinematics.h"
#include "lib/six_bar.h"
#include "lib/six_bar_kinematics.h"
#include "lib/spatial_pose.h"
#include "lib/spherical_four_bar_kinematics.h"
#include "lib/task_io.h"

namespace linkfit {
namespace {

constexpr double kDegree = 180.0 / M_PI;

// The drawing's layers, their colours (AutoCAD colour index) and the same colours in SVG (on
// white: the index's yellow a darker one, its white black).
struct Layer {
  const char* name;
  int color;
  const char* svg_color;
};
// A four-bar draws on GROUND, INPUT, COUPLER and OUTPUT; a six-bar on GROUND and a layer per
// moving body (lib/six_bar.h SixBarBody order).
constexpr Layer kLayers[] = {
    {"GROUND", 8, "#808080"},    {"INPUT", 1, "#d62728"},       {"COUPLER", 5, "#1f5fbf"},
    {"OUTPUT", 3, "#2ca02c"},    {"UPPER_LINK", 1, "#d62728"},  {"FOREARM", 4, "#1f77b4"},
    {"TASK_BODY", 3, "#2ca02c"}, {"FIRST_LINK", 30, "#ff7f0e"}, {"SECOND_LINK", 6, "#9467bd"},
    {"CURVE", 6, "#b02cb0"},     {"TASK", 2, "#c08000"},        {"DIMENSIONS", 7, "#000000"}};
constexpr const char* kSixBarLayers[] = {"GROUND",    "UPPER_LINK", "FOREARM",
                                         "TASK_BODY", "FIRST_LINK", "SECOND_LINK"};

// What a drawing is made of, on the layers above; the DXF and the SVG write it.
class Drawing {
 public:
  virtual ~Drawing() = default;
  virtual void Line(const char* layer, const Eigen::Vector2d& a, const Eigen::Vector2d& b) = 0;
  virtual void Circle(const char* layer, const Eigen::Vector2d& at, double radius) = 0;
  virtual void Polyline(const char* layer, const std::vector<Eigen::Vector2d>& points,
                        bool closed) = 0;
  // An aligned dimension of the length from a to b, its line `offset` to the left of a -> b,
  // its text the length.
  virtual void Dimension(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double offset) = 0;
  // In space (a spherical four-bar): a polyline through `points`, a text of `height` at `at`.
  virtual void Polyline3(const char* layer, const std::vector<Eigen::Vector3d>& points,
                         bool closed) = 0;
  virtual void Text3(const char* layer, const Eigen::Vector3d& at, double height,
                     const std::string& text) = 0;
};

// The length as a dimension's text.
std::string LengthText(double length) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", length);
  return text;
}

// Writes the entities through dxflib's writer.
class DxfDrawing : public Drawing {
 public:
  DxfDrawing(DL_Dxf* dxf, DL_WriterA* writer) : dxf_(dxf), writer_(writer) {}

  DL_Attributes On(const char* layer) const {
    return DL_Attributes(layer, 256, -1, "BYLAYER", 1.0);
  }

  void Line(const char* layer, const Eigen::Vector2d& a, const Eigen::Vector2d& b) override {
    dxf_->writeLine(*writer_, DL_LineData(a.x(), a.y(), 0.0, b.x(), b.y(), 0.0), On(layer));
  }
  void Circle(const char* layer, const Eigen::Vector2d& at, double radius) override {
    dxf_->writeCircle(*writer_, DL_CircleData(at.x(), at.y(), 0.0, radius), On(layer));
  }
  void Polyline(const char* layer, const std::vector<Eigen::Vector2d>& points,
                bool closed) override {
    if (points.size() < 2) return;
    dxf_->writePolyline(*writer_,
                        DL_PolylineData(static_cast<int>(points.size()), 0, 0, closed ? 1 : 0),
                        On(layer));
    for (const Eigen::Vector2d& p : points) {
      dxf_->writeVertex(*writer_, DL_VertexData(p.x(), p.y(), 0.0, 0.0));
    }
    dxf_->writePolylineEnd(*writer_);
  }
  void Dimension(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double offset) override {
    const Eigen::Vector2d along = b - a;
    if (!(along.norm() > 0.0)) return;
    const Eigen::Vector2d normal = Eigen::Vector2d(-along.y(), along.x()).normalized();
    const Eigen::Vector2d line = b + offset * normal;
    const Eigen::Vector2d middle = 0.5 * (a + b) + offset * normal;
    // Its text the length itself (a program that does not measure the dimension shows it).
    // A rotated linear dimension along a -> b measures the true length in every reader (an
    // aligned one leaves its direction to the reader: ezdxf measures it along x).
    DL_DimensionData dimension(line.x(), line.y(), 0.0, middle.x(), middle.y(), 0.0,
                               0x0,  // rotated, horizontal or vertical
                               5,    // attachment: middle centre
                               1, 1.0, LengthText(along.norm()), "Standard", 0.0);
    // Its constructor leaves the arrows' flags unset (written as whatever the memory held).
    dimension.arrow1Flipped = false;
    dimension.arrow2Flipped = false;
    // (dxflib takes the angle in radians and writes it in degrees.)
    const double angle = std::atan2(along.y(), along.x());
    dxf_->writeDimLinear(*writer_, dimension,
                         DL_DimLinearData(a.x(), a.y(), 0.0, b.x(), b.y(), 0.0, angle, 0.0),
                         On("DIMENSIONS"));
  }

  void Polyline3(const char* layer, const std::vector<Eigen::Vector3d>& points,
                 bool closed) override {
    // As lines: dxflib writes an AutoCAD 2000 polyline as a flat LWPOLYLINE (no z per vertex).
    for (size_t k = 0; k + 1 < points.size() + (closed ? 1 : 0); ++k) {
      const Eigen::Vector3d& a = points[k];
      const Eigen::Vector3d& b = points[(k + 1) % points.size()];
      dxf_->writeLine(*writer_, DL_LineData(a.x(), a.y(), a.z(), b.x(), b.y(), b.z()), On(layer));
    }
  }
  void Text3(const char* layer, const Eigen::Vector3d& at, double height,
             const std::string& text) override {
    // Centred (1) on its middle (2) at `at`.
    dxf_->writeText(*writer_,
                    DL_TextData(at.x(), at.y(), at.z(), at.x(), at.y(), at.z(), height, 1.0, 0, 1,
                                2, text, "Standard", 0.0),
                    On(layer));
  }

 private:
  DL_Dxf* dxf_;
  DL_WriterA* writer_;
};

// Writes the entities as SVG: a group per layer (its id the layer's name), strokes only, in
// the result's coordinates (y up: the groups sit in one that flips y), numbers to 9 digits.
class SvgDrawing : public Drawing {
 public:
  // `stroke` the lines' width; coordinates within `tiny` of 0 are written as 0.
  SvgDrawing(double stroke, double tiny) : stroke_(stroke), tiny_(tiny) {}

  void Line(const char* layer, const Eigen::Vector2d& a, const Eigen::Vector2d& b) override {
    Extend(a);
    Extend(b);
    Add(layer, "<line x1=\"" + N(a.x()) + "\" y1=\"" + N(a.y()) + "\" x2=\"" + N(b.x()) +
                   "\" y2=\"" + N(b.y()) + "\"/>");
  }
  void Circle(const char* layer, const Eigen::Vector2d& at, double radius) override {
    Extend(at, radius);
    Add(layer,
        "<circle cx=\"" + N(at.x()) + "\" cy=\"" + N(at.y()) + "\" r=\"" + N(radius) + "\"/>");
  }
  void Polyline(const char* layer, const std::vector<Eigen::Vector2d>& points,
                bool closed) override {
    if (points.size() < 2) return;
    std::string list;
    for (const Eigen::Vector2d& p : points) {
      Extend(p);
      list += (list.empty() ? "" : " ") + N(p.x()) + "," + N(p.y());
    }
    Add(layer, std::string(closed ? "<polygon" : "<polyline") + " points=\"" + list + "\"/>");
  }
  void Dimension(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double offset) override {
    const Eigen::Vector2d along = b - a;
    if (!(along.norm() > 0.0)) return;
    const Eigen::Vector2d normal = Eigen::Vector2d(-along.y(), along.x()).normalized();
    // Extension lines, the dimension line and its text, upright along the line (read from
    // below or from the right).
    const Eigen::Vector2d from = a + offset * normal, to = b + offset * normal;
    Line("DIMENSIONS", a + 0.2 * offset * normal, from + 0.2 * offset * normal);
    Line("DIMENSIONS", b + 0.2 * offset * normal, to + 0.2 * offset * normal);
    Line("DIMENSIONS", from, to);
    double angle = std::atan2(along.y(), along.x()) * kDegree;
    if (angle > 90.0) angle -= 180.0;
    if (angle <= -90.0) angle += 180.0;
    // The text (as high as the DXF's, a thirtieth of the links) centred beyond the line.
    const double font = 10.0 * stroke_;
    const Eigen::Vector2d middle = 0.5 * (from + to) + (offset > 0.0 ? 0.8 : -0.8) * font * normal;
    // The text is drawn in a frame flipped back to y down, at 10 units scaled to its height
    // (renderers draw a font of a fraction of a unit poorly: a result in metres).
    Add("DIMENSIONS", "<text transform=\"translate(" + N(middle.x()) + "," + N(middle.y()) +
                          ") scale(" + N(font / 10.0) + "," + N(-font / 10.0) + ") rotate(" +
                          N(-angle) +
                          ")\" text-anchor=\"middle\" dominant-baseline=\"middle\" "
                          "font-size=\"10\" stroke=\"none\" fill=\"currentColor\">" +
                          LengthText(along.norm()) + "</text>");
  }

  // Space drawn as an orthographic view: a point p at view (p - origin) (2 x 3 rows: the
  // screen's x and y axes in Sigma).
  void SetView(const Eigen::Matrix<double, 2, 3>& view, const Eigen::Vector3d& origin) {
    view_ = view;
    origin_ = origin;
  }
  void Polyline3(const char* layer, const std::vector<Eigen::Vector3d>& points,
                 bool closed) override {
    std::vector<Eigen::Vector2d> seen;
    for (const Eigen::Vector3d& p : points) seen.push_back(view_ * (p - origin_));
    Polyline(layer, seen, closed);
  }
  void Text3(const char* layer, const Eigen::Vector3d& at, double height,
             const std::string& text) override {
    const Eigen::Vector2d seen = view_ * (at - origin_);
    Extend(seen);
    Add(layer, "<text transform=\"translate(" + N(seen.x()) + "," + N(seen.y()) + ") scale(" +
                   N(height / 10.0) + "," + N(-height / 10.0) +
                   ")\" text-anchor=\"middle\" dominant-baseline=\"middle\" font-size=\"10\" "
                   "stroke=\"none\" fill=\"currentColor\">" +
                   text + "</text>");
  }

  // The SVG document: the drawing's extent plus a margin, the layers in kLayers' order.
  std::string Document() const {
    Eigen::Vector2d low = low_, high = high_;
    if (!(low.x() <= high.x())) low = high = Eigen::Vector2d::Zero();
    const double margin = 0.08 * std::max((high - low).maxCoeff(), 1e-9);
    low -= Eigen::Vector2d::Constant(margin);
    high += Eigen::Vector2d::Constant(margin);
    const Eigen::Vector2d size = high - low;
    std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" + N(low.x()) + " " +
           N(-high.y()) + " " + N(size.x()) + " " + N(size.y()) + "\" width=\"800\" height=\"" +
           N(800.0 * size.y() / size.x()) + "\">\n";
    svg += "<!-- linkfit export: the result's coordinates and units, y up -->\n";
    svg += "<g transform=\"scale(1,-1)\" fill=\"none\" stroke-width=\"" + N(stroke_) +
           "\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
    for (const Layer& layer : kLayers) {
      const auto found = groups_.find(layer.name);
      if (found == groups_.end()) continue;
      svg += "<g id=\"" + std::string(layer.name) + "\" stroke=\"" + layer.svg_color +
             "\" color=\"" + layer.svg_color + "\">\n" + found->second + "</g>\n";
    }
    svg += "</g>\n</svg>\n";
    return svg;
  }

 private:
  std::string N(double value) const {
    if (std::abs(value) < tiny_) value = 0.0;
    char text[32];
    std::snprintf(text, sizeof(text), "%.9g", value);
    return text;
  }
  void Add(const char* layer, const std::string& element) { groups_[layer] += element + "\n"; }
  // Every point drawn widens the drawing's extent.
  void Extend(const Eigen::Vector2d& p, double radius = 0.0) {
    low_ = low_.cwiseMin(p - Eigen::Vector2d::Constant(radius));
    high_ = high_.cwiseMax(p + Eigen::Vector2d::Constant(radius));
  }

  double stroke_, tiny_;
  Eigen::Matrix<double, 2, 3> view_ = Eigen::Matrix<double, 2, 3>::Identity();
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  std::map<std::string, std::string> groups_;
  Eigen::Vector2d low_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high_ = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
};

// A temporary file's name (dxflib writes to a path); removed by the destructor.
class TemporaryPath {
 public:
  TemporaryPath() {
    std::string pattern = (std::filesystem::temp_directory_path() / "linkfit_dxf_XXXXXX").string();
    const int descriptor = mkstemp(pattern.data());
    if (descriptor < 0) throw std::runtime_error("cannot create a temporary file for the DXF");
    close(descriptor);
    path_ = pattern;
  }
  ~TemporaryPath() { std::remove(path_.c_str()); }
  TemporaryPath(const TemporaryPath&) = delete;
  TemporaryPath& operator=(const TemporaryPath&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// A four-bar of a result, in the configuration drawn, with its coupler curve.
struct FourBarDrawing {
  FourBarJoints joints;
  FourBarState drawn;
  FourBarKinematics kinematics;  // over the input's range: the curve, a slider's travel
  double links = 1.0;            // crank and coupler together: the drawing's scale
  double pivot_radius = 1.0;
};

FourBarDrawing PrepareFourBar(const std::string& result_text, const std::string& source,
                              const CadExportRequest& request) {
  const ResultFourBar four_bar = ReadResultFourBar(result_text, source, request.mechanism);
  // The task drawn must be this result's (refused otherwise, as `linkfit analyze --task`).
  if (request.task != nullptr) {
    ResultFourBarTaskRange(result_text, source, request.mechanism, request.task);
  }
  FourBarDrawing drawing;
  const FourBarJoints& joints = drawing.joints = four_bar.joints;
  // The configuration drawn: the first pose's, or the crank at the given angle.
  const Eigen::Vector2d crank = joints.input_pin - joints.input_pivot;
  const double reference = std::atan2(crank.y(), crank.x());
  const double input_angle = request.input_deg ? *request.input_deg / kDegree : reference;
  FourBarKinematicsOptions sweep;
  sweep.steps = request.curve_steps;
  drawing.kinematics = AnalyzeFourBarKinematics(joints, sweep, four_bar.length);
  if (!PlaceFourBar(joints, input_angle, four_bar.length, &drawing.drawn)) {
    const auto shown = [](double value) {
      char text[32];
      std::snprintf(text, sizeof(text), "%.6g", value);
      return std::string(text);
    };
    throw InputError("--input-deg " + shown(input_angle * kDegree) +
                     ": the four-bar does not reach it on its circuit (its crank turns from " +
                     shown(drawing.kinematics.range_start * kDegree) + " to " +
                     shown(drawing.kinematics.range_end * kDegree) + " degrees)");
  }
  drawing.links = crank.norm() + (joints.output_pin - joints.input_pin).norm();
  // Pivots a thirtieth of crank and coupler together, at most a sixth of the shortest link.
  double shortest = std::min(crank.norm(), (joints.output_pin - joints.input_pin).norm());
  if (!joints.slider) {
    shortest = std::min({shortest, (joints.output_pin - joints.output_pivot).norm(),
                         (joints.output_pivot - joints.input_pivot).norm()});
  }
  drawing.pivot_radius = std::min(drawing.links / 30.0, shortest / 6.0);
  return drawing;
}

// The task's poses as frames (x axis twice as long as y) and its points as small circles.
void DrawTask(const Task& task, double axis, double radius, Drawing* drawing) {
  for (const PlanarPose& pose : task.planar_poses) {
    const Eigen::Vector2d origin = pose.origin_in_fixed;
    const Eigen::Vector2d x(std::cos(pose.theta), std::sin(pose.theta));
    drawing->Line("TASK", origin, origin + axis * x);
    drawing->Line("TASK", origin, origin + 0.5 * axis * Eigen::Vector2d(-x.y(), x.x()));
  }
  for (const TimedPoint& point : task.points) drawing->Circle("TASK", point.point_in_fixed, radius);
}

// The four-bar's entities, on their layers.
void DrawFourBar(const FourBarDrawing& four_bar, const Task* task, Drawing* drawing) {
  const FourBarJoints& joints = four_bar.joints;
  const FourBarState& drawn = four_bar.drawn;
  const double links = four_bar.links, pivot_radius = four_bar.pivot_radius;
  const auto pivot = [&](const char* layer, const Eigen::Vector2d& at) {
    drawing->Circle(layer, at, pivot_radius);
  };
  const Eigen::Vector2d a0 = joints.input_pivot, a = drawn.input_pin, b = drawn.output_pin;
  // Ground: its pivots (a slider's line over the output's travel).
  pivot("GROUND", a0);
  if (joints.slider) {
    double low = drawn.output, high = drawn.output;
    for (const FourBarState& state : four_bar.kinematics.states) {
      low = std::min(low, state.output);
      high = std::max(high, state.output);
    }
    const double margin = 0.1 * links;
    drawing->Line("GROUND", joints.slider_point + (low - margin) * joints.slider_direction,
                  joints.slider_point + (high + margin) * joints.slider_direction);
  } else {
    pivot("GROUND", joints.output_pivot);
    drawing->Line("GROUND", a0, joints.output_pivot);
  }
  // The input crank, the coupler body, the output rocker or slider block.
  drawing->Line("INPUT", a0, a);
  pivot("INPUT", a0);
  pivot("INPUT", a);
  std::vector<Eigen::Vector2d> body = {a, b};
  if (joints.coupler_point && (drawn.coupler_point - a).norm() > 1e-9 * links &&
      (drawn.coupler_point - b).norm() > 1e-9 * links) {
    body.push_back(drawn.coupler_point);
  }
  drawing->Polyline("COUPLER", body, body.size() > 2);
  pivot("COUPLER", a);
  pivot("COUPLER", b);
  if (joints.coupler_point) pivot("COUPLER", drawn.coupler_point);
  if (joints.slider) {
    const Eigen::Vector2d u = joints.slider_direction, n(-u.y(), u.x());
    const double half = 2.0 * pivot_radius;
    drawing->Polyline("OUTPUT",
                      {b - half * u - 0.6 * half * n, b + half * u - 0.6 * half * n,
                       b + half * u + 0.6 * half * n, b - half * u + 0.6 * half * n},
                      true);
    pivot("OUTPUT", b);
  } else {
    drawing->Line("OUTPUT", joints.output_pivot, b);
    pivot("OUTPUT", joints.output_pivot);
    pivot("OUTPUT", b);
  }
  // The coupler curve over the input's range (closed for a crank).
  if (joints.coupler_point) {
    std::vector<Eigen::Vector2d> curve;
    for (const FourBarState& state : four_bar.kinematics.states) {
      curve.push_back(state.coupler_point);
    }
    drawing->Polyline("CURVE", curve, four_bar.kinematics.input_rotates_fully);
  }
  if (task != nullptr) DrawTask(*task, 0.1 * links, 0.5 * pivot_radius, drawing);
  // The link lengths.
  const double offset = 2.5 * pivot_radius;
  drawing->Dimension(a0, a, offset);
  drawing->Dimension(a, b, offset);
  if (!joints.slider) {
    drawing->Dimension(joints.output_pivot, b, -offset);
    drawing->Dimension(a0, joints.output_pivot, -offset);
  }
}

// A six-bar of a result in the configuration drawn, with the tool point's curve.
struct SixBarSketch {
  SixBar six_bar;
  SixBarAngles turns = SixBarAngles::Zero();
  std::vector<Eigen::Vector2d> curve;
  bool closed_curve = false;
  double links = 1.0, pivot_radius = 1.0;
};

SixBarSketch PrepareSixBar(const std::string& result_text, const std::string& source,
                           const CadExportRequest& request) {
  const ResultSixBar read = ReadResultSixBar(result_text, source, request.mechanism);
  SixBarSketch sketch;
  sketch.six_bar = read.six_bar;
  const SixBar& six_bar = sketch.six_bar;
  SixBarKinematicsOptions sweep;
  sweep.steps = request.curve_steps;
  const SixBarKinematics kinematics =
      AnalyzeSixBarKinematics(six_bar, read.input, sweep, read.length);
  for (const SixBarState& state : kinematics.states) sketch.curve.push_back(state.tool_point);
  sketch.closed_curve = kinematics.input_rotates_fully;
  if (request.task != nullptr) {
    // The task drawn must be this result's: its first pose the task body's at the first pose.
    const std::vector<PlanarPose>& poses = request.task->planar_poses;
    const PlanarPose& first = six_bar.reference_pose;
    if (poses.empty() ||
        (poses[0].origin_in_fixed - first.origin_in_fixed).norm() > 1e-6 * read.length ||
        std::abs(std::remainder(poses[0].theta - first.theta, 2.0 * M_PI)) > 1e-6) {
      throw InputError(
          "--task: its first pose is not the six-bar's task body at its first pose "
          "(is it the task of " +
          source + "?)");
    }
  }
  if (request.input_deg) {
    // The input turned to the angle asked for, on the first pose's assembly.
    const double reference = SixBarInputReferenceAngle(six_bar, read.input);
    double turn = std::remainder(*request.input_deg / kDegree - reference, 2.0 * M_PI);
    if (!kinematics.input_rotates_fully &&
        (reference + turn < kinematics.range_start || reference + turn > kinematics.range_end)) {
      turn += turn < 0.0 ? 2.0 * M_PI : -2.0 * M_PI;
    }
    const SixBarDriver driver(six_bar, read.input, read.length);
    if (!driver.Drive(turn, &sketch.turns, kSixBarDriveStep)) {
      char text[160];
      std::snprintf(text, sizeof(text),
                    "--input-deg %.6g: the six-bar does not reach it on its assembly (its input "
                    "turns from %.6g to %.6g degrees)",
                    *request.input_deg, kinematics.range_start * kDegree,
                    kinematics.range_end * kDegree);
      throw InputError(text);
    }
  }
  sketch.links =
      (six_bar.elbow - six_bar.ground_pivot).norm() + (six_bar.wrist - six_bar.elbow).norm();
  double shortest = std::numeric_limits<double>::infinity();
  const std::array<std::vector<Eigen::Vector2d>, 6> bodies = SixBarBodyJoints(six_bar);
  for (const std::vector<Eigen::Vector2d>& joints : bodies) {
    for (size_t i = 0; i < joints.size(); ++i) {
      for (size_t j = i + 1; j < joints.size(); ++j) {
        const double side = (joints[i] - joints[j]).norm();
        if (side > 1e-9 * sketch.links) shortest = std::min(shortest, side);
      }
    }
  }
  sketch.pivot_radius = std::min(sketch.links / 30.0, shortest / 6.0);
  return sketch;
}

void DrawSixBar(const SixBarSketch& sketch, const Task* task, Drawing* drawing) {
  const SixBar& six_bar = sketch.six_bar;
  const std::array<std::vector<Eigen::Vector2d>, 6> bodies = SixBarBodyJoints(six_bar);
  const double offset = 2.5 * sketch.pivot_radius;
  for (int body = 0; body < 6; ++body) {
    const char* layer = kSixBarLayers[body];
    const PlanarPose moved = SixBarBodyDisplacement(six_bar, sketch.turns, body);
    std::vector<Eigen::Vector2d> joints;
    for (const Eigen::Vector2d& joint : bodies[body]) joints.push_back(moved.ToFixed(joint));
    // The task body carries the tool frame's origin, the point the task moves.
    if (body == kSixBarTaskBody) {
      joints.push_back(moved.ToFixed(six_bar.reference_pose.origin_in_fixed));
    }
    for (const Eigen::Vector2d& joint : joints) drawing->Circle(layer, joint, sketch.pivot_radius);
    if (joints.size() >= 2) drawing->Polyline(layer, joints, joints.size() > 2);
    // Its dimensions: every pair of joints of a moving body (ground: between its pivots).
    for (size_t i = 0; i < joints.size(); ++i) {
      for (size_t j = i + 1; j < joints.size(); ++j) {
        if ((joints[i] - joints[j]).norm() > 1e-9 * sketch.links) {
          drawing->Dimension(joints[i], joints[j], body == 0 ? -offset : offset);
        }
      }
    }
  }
  drawing->Polyline("CURVE", sketch.curve, sketch.closed_curve);
  if (task != nullptr) DrawTask(*task, 0.1 * sketch.links, 0.5 * sketch.pivot_radius, drawing);
}

// A four-bar of another type (or driven by a slider) in the configuration drawn, with its
// coupler curve.
struct DyadSketch {
  ResultDyadFourBar four_bar;
  PlanarPose pose;  // the coupler drawn (E in Sigma; E is Sigma at the first configuration)
  std::vector<Eigen::Vector2d> curve;
  bool closed_curve = false;
  double slider_low = 0.0, slider_high = 0.0;  // a PR's pin's travel along its line
  double links = 1.0, pivot_radius = 1.0;
};

DyadSketch PrepareDyadFourBar(const ResultDyadFourBar& four_bar, const std::string& source,
                              const CadExportRequest& request) {
  DyadSketch sketch;
  sketch.four_bar = four_bar;
  const PlanarDyad& input = four_bar.input;
  const PlanarDyad& output = four_bar.output;
  if (request.task != nullptr && four_bar.coupler_point) {
    // The task drawn must be this result's: its first pose's origin or point at the coupler
    // point (within the fit's error).
    const Task& task = *request.task;
    const std::optional<Eigen::Vector2d> first =
        !task.planar_poses.empty() ? std::optional(task.planar_poses[0].origin_in_fixed)
        : !task.points.empty()     ? std::optional(task.points[0].point_in_fixed)
                                   : std::nullopt;
    if (!first || (*first - *four_bar.coupler_point).norm() > 0.05 * four_bar.length) {
      throw InputError(
          "--task: its first pose or point is not at the four-bar's coupler point "
          "(is it the task of " +
          source + "?)");
    }
  }
  DyadFourBarKinematicsOptions sweep;
  sweep.steps = request.curve_steps;
  const DyadFourBarKinematics kinematics = AnalyzeDyadFourBarKinematics(
      input, output, four_bar.coupler_point, PlanarPose(), sweep, four_bar.length);
  for (const DyadFourBarState& state : kinematics.states) {
    sketch.curve.push_back(state.coupler_point);
  }
  sketch.closed_curve = kinematics.input_rotates_fully;
  if (request.input_deg) {
    // The input's value asked for (an angle in degrees; a slider's position), reached on the
    // first configuration's assembly.
    const double value =
        input.type == DyadType::kPR ? *request.input_deg : *request.input_deg / kDegree;
    DyadFourBarKinematicsOptions at;
    at.steps = 1;
    at.range =
        std::pair{value, value + 1e-9 * (input.type == DyadType::kPR ? four_bar.length : 1.0)};
    DyadFourBarKinematics placed = AnalyzeDyadFourBarKinematics(
        input, output, four_bar.coupler_point, PlanarPose(), at, four_bar.length);
    if (placed.states.empty()) {
      const double unit = input.type == DyadType::kPR ? 1.0 : kDegree;
      char text[200];
      std::snprintf(text, sizeof(text),
                    "--input-deg %.6g: the four-bar does not reach it on its circuit (its input "
                    "runs from %.6g to %.6g%s)",
                    *request.input_deg, kinematics.range_start * unit, kinematics.range_end * unit,
                    input.type == DyadType::kPR ? "" : " degrees");
      throw InputError(text);
    }
    sketch.pose = placed.states[0].coupler;
  }
  // A PR's travel along its line over the input's range.
  for (const PlanarDyad* dyad : {&input, &output}) {
    if (dyad->type != DyadType::kPR) continue;
    sketch.slider_low = sketch.slider_high =
        dyad->line_direction.dot(sketch.pose.ToFixed(dyad->moving_pivot) - dyad->line_point);
    for (const DyadFourBarState& state : kinematics.states) {
      const double at =
          dyad->line_direction.dot(state.coupler.ToFixed(dyad->moving_pivot) - dyad->line_point);
      sketch.slider_low = std::min(sketch.slider_low, at);
      sketch.slider_high = std::max(sketch.slider_high, at);
    }
  }
  // The links' scale: the RR links and the coupler's pins apart.
  double links = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (const PlanarDyad* dyad : {&input, &output}) {
    if (dyad->type == DyadType::kRR) {
      links += dyad->radius;
      shortest = std::min(shortest, dyad->radius);
    }
  }
  if (input.type != DyadType::kRP && output.type != DyadType::kRP) {
    const double coupler = (output.moving_pivot - input.moving_pivot).norm();
    links += coupler;
    shortest = std::min(shortest, coupler);
  }
  if (input.type != DyadType::kPR && output.type != DyadType::kPR) {
    links = std::max(links, (output.fixed_pivot - input.fixed_pivot).norm());  // the ground
  }
  if (!(links > 0.0)) links = four_bar.length;
  sketch.links = links;
  sketch.pivot_radius = std::min(links / 30.0, std::isfinite(shortest) ? shortest / 6.0 : links);
  return sketch;
}

void DrawDyadFourBar(const DyadSketch& sketch, const Task* task, Drawing* drawing) {
  const PlanarDyad& input = sketch.four_bar.input;
  const PlanarDyad& output = sketch.four_bar.output;
  const PlanarPose& pose = sketch.pose;
  const double r = sketch.pivot_radius, links = sketch.links;
  // A slider block at `at` along `direction` (a rectangle 4 r by 2.4 r).
  const auto block = [&](const char* layer, const Eigen::Vector2d& at,
                         const Eigen::Vector2d& direction) {
    const Eigen::Vector2d u = direction.normalized(), n(-u.y(), u.x());
    const double half = 2.0 * r;
    drawing->Polyline(layer,
                      {at - half * u - 0.6 * half * n, at + half * u - 0.6 * half * n,
                       at + half * u + 0.6 * half * n, at - half * u + 0.6 * half * n},
                      true);
  };
  std::vector<Eigen::Vector2d> body;  // the coupler's points: its pins and coupler point
  std::vector<Eigen::Vector2d> ground;
  for (const auto& [dyad, layer] : {std::pair{&input, "INPUT"}, std::pair{&output, "OUTPUT"}}) {
    switch (dyad->type) {
      case DyadType::kRR: {
        const Eigen::Vector2d pin = pose.ToFixed(dyad->moving_pivot);
        drawing->Circle("GROUND", dyad->fixed_pivot, r);
        drawing->Line(layer, dyad->fixed_pivot, pin);
        drawing->Circle(layer, dyad->fixed_pivot, r);
        drawing->Circle(layer, pin, r);
        drawing->Dimension(dyad->fixed_pivot, pin, 2.5 * r);
        ground.push_back(dyad->fixed_pivot);
        body.push_back(pin);
        break;
      }
      case DyadType::kPR: {
        const Eigen::Vector2d pin = pose.ToFixed(dyad->moving_pivot);
        const double margin = 0.1 * links;
        drawing->Line("GROUND",
                      dyad->line_point + (sketch.slider_low - margin) * dyad->line_direction,
                      dyad->line_point + (sketch.slider_high + margin) * dyad->line_direction);
        block(layer, pin, dyad->line_direction);
        drawing->Circle(layer, pin, r);
        body.push_back(pin);
        break;
      }
      case DyadType::kRP: {
        // The block turns about its ground pivot and slides on the coupler's line.
        const Eigen::Vector2d direction = Rotation2(pose.theta) * dyad->line_direction;
        drawing->Circle("GROUND", dyad->fixed_pivot, r);
        block(layer, dyad->fixed_pivot, direction);
        drawing->Circle(layer, dyad->fixed_pivot, r);
        const Eigen::Vector2d foot = pose.ToFixed(dyad->line_point);
        const double along = direction.dot(dyad->fixed_pivot - foot);
        drawing->Line("COUPLER", foot + (std::min(along, 0.0) - 0.6 * links) * direction,
                      foot + (std::max(along, 0.0) + 0.6 * links) * direction);
        ground.push_back(dyad->fixed_pivot);
        body.push_back(foot);
        break;
      }
    }
  }
  if (ground.size() == 2) {
    drawing->Line("GROUND", ground[0], ground[1]);
    drawing->Dimension(ground[0], ground[1], -2.5 * r);
  }
  const std::optional<Eigen::Vector2d>& point = sketch.four_bar.coupler_point;
  if (point) body.push_back(pose.ToFixed(*point));
  // The coupler body through its points (distinct ones), a circle at the coupler point.
  std::vector<Eigen::Vector2d> distinct;
  for (const Eigen::Vector2d& p : body) {
    bool seen = false;
    for (const Eigen::Vector2d& q : distinct) seen |= (p - q).norm() <= 1e-9 * links;
    if (!seen) distinct.push_back(p);
  }
  if (distinct.size() >= 2) drawing->Polyline("COUPLER", distinct, distinct.size() > 2);
  if (point) drawing->Circle("COUPLER", pose.ToFixed(*point), r);
  if (input.type != DyadType::kRP && output.type != DyadType::kRP) {
    drawing->Dimension(pose.ToFixed(input.moving_pivot), pose.ToFixed(output.moving_pivot),
                       2.5 * r);
  }
  drawing->Polyline("CURVE", sketch.curve, sketch.closed_curve);
  if (task != nullptr) DrawTask(*task, 0.1 * links, 0.5 * r, drawing);
}

// A spherical four-bar of a result: its axes (unit, through the centre) in the configuration
// drawn, the sphere it is drawn on (about the result's centre, through the tool frame's origin),
// the path of a coupler point.
struct SphericalSketch {
  SphericalFourBarJoints axes;  // drawn
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1.0;
  std::vector<Eigen::Vector3d> curve;
  bool closed_curve = false;
  std::array<double, 4> links_deg = {0.0, 0.0, 0.0, 0.0};  // ground, input, coupler, output
};

SphericalSketch PrepareSpherical(const nlohmann::json& result, const std::string& source,
                                 const CadExportRequest& request) {
  const auto& mechanisms = result.at("mechanisms");
  const int index = request.mechanism;
  if (!mechanisms.is_array() || index < 0 || index >= static_cast<int>(mechanisms.size())) {
    throw InputError(source + ": no mechanism ranked " + std::to_string(index + 1) +
                     " (counted from 1): the result lists " +
                     std::to_string(mechanisms.is_array() ? mechanisms.size() : 0));
  }
  const std::string item = source + ": mechanisms[" + std::to_string(index) + "]";
  const auto vector = [&](const nlohmann::json& value, const std::string& what) {
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
        !value[2].is_number()) {
      throw InputError(what + ": expected [x, y, z]");
    }
    return Eigen::Vector3d(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
  };
  const nlohmann::json& joints = mechanisms[index]["linkage"]["joints"];
  const std::string at = item + ".linkage.joints";
  SphericalFourBarJoints first;
  first.input_pivot = vector(joints["input_pivot"], at + ".input_pivot").normalized();
  first.input_pin = vector(joints["input_pin"], at + ".input_pin").normalized();
  first.output_pin = vector(joints["output_pin"], at + ".output_pin").normalized();
  first.output_pivot = vector(joints["output_pivot"], at + ".output_pivot").normalized();
  SphericalSketch sketch;
  sketch.centre = vector(result["center"], source + ".center");
  // The tool frame's origin's sphere: |center_in_moving| (the centre seen from the tool frame).
  Eigen::Vector3d centre_in_moving = Eigen::Vector3d::Zero();
  if (result.contains("spherical") && result["spherical"].contains("center_in_moving")) {
    centre_in_moving =
        vector(result["spherical"]["center_in_moving"], source + ".spherical.center_in_moving");
  }
  sketch.radius = centre_in_moving.norm() > 0.0 ? centre_in_moving.norm()
                                                : std::max(result.value("scale", 1.0), 1e-9);
  // The coupler point drawn: the tool frame's origin where the task gives its first pose (which
  // must put the centre where the result has it), else the coupler's arc's middle.
  Eigen::Vector3d point =
      sketch.centre + sketch.radius * (first.input_pin + first.output_pin).normalized();
  if (request.task != nullptr) {
    const std::vector<DualQuaternion>& poses = request.task->spatial_poses;
    if (poses.empty() ||
        (poses[0].Rotation() * centre_in_moving + poses[0].Translation() - sketch.centre).norm() >
            1e-6 * std::max(1.0, sketch.radius)) {
      throw InputError(
          "--task: its first pose does not carry the result's centre to where the "
          "result has it (is it the task of " +
          source + "?)");
    }
    point = poses[0].Translation();
  }
  SphericalFourBarKinematicsOptions sweep;
  sweep.steps = request.curve_steps;
  const SphericalFourBarKinematics kinematics = AnalyzeSphericalFourBarKinematics(first, sweep);
  for (const SphericalFourBarState& state : kinematics.states) {
    sketch.curve.push_back(sketch.centre + state.coupler_rotation_matrix * (point - sketch.centre));
  }
  sketch.closed_curve = kinematics.input_rotates_fully;
  sketch.axes = first;
  if (request.input_deg) {
    SphericalFourBarState placed;
    if (!PlaceSphericalFourBar(first, *request.input_deg / kDegree, &placed)) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "--input-deg %.6g: the four-bar does not reach it on its circuit (its input "
                    "turns from %.6g to %.6g degrees)",
                    *request.input_deg, kinematics.range_start * kDegree,
                    kinematics.range_end * kDegree);
      throw InputError(text);
    }
    sketch.axes.input_pin = placed.input_pin;
    sketch.axes.output_pin = placed.output_pin;
  }
  const auto degrees = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegree;
  };
  const SphericalFourBarJoints& axes = sketch.axes;
  sketch.links_deg = {
      degrees(axes.input_pivot, axes.output_pivot), degrees(axes.input_pivot, axes.input_pin),
      degrees(axes.input_pin, axes.output_pin), degrees(axes.output_pin, axes.output_pivot)};
  return sketch;
}

// The four-bar on its sphere: each axis a line from the centre, each link the arc between its
// two axes, the coupler point's path, the links' angles as text, the task's frames.
void DrawSpherical(const SphericalSketch& sketch, const Task* task, Drawing* drawing) {
  const Eigen::Vector3d& c = sketch.centre;
  const double r = sketch.radius;
  const SphericalFourBarJoints& axes = sketch.axes;
  const auto arc = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    std::vector<Eigen::Vector3d> points;
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    for (int k = 0; k <= 32; ++k) {
      const double t = k / 32.0;
      const Eigen::Vector3d direction =
          angle > 1e-12
              ? (std::sin((1.0 - t) * angle) * a + std::sin(t * angle) * b) / std::sin(angle)
              : a;
      points.push_back(c + r * direction);
    }
    return points;
  };
  const auto axis = [&](const char* layer, const Eigen::Vector3d& u) {
    drawing->Polyline3(layer, {c, c + 1.15 * r * u}, false);
  };
  axis("GROUND", axes.input_pivot);
  axis("GROUND", axes.output_pivot);
  axis("INPUT", axes.input_pin);
  axis("OUTPUT", axes.output_pin);
  drawing->Polyline3("GROUND", arc(axes.input_pivot, axes.output_pivot), false);
  drawing->Polyline3("INPUT", arc(axes.input_pivot, axes.input_pin), false);
  drawing->Polyline3("COUPLER", arc(axes.input_pin, axes.output_pin), false);
  drawing->Polyline3("OUTPUT", arc(axes.output_pin, axes.output_pivot), false);
  drawing->Polyline3("CURVE", sketch.curve, sketch.closed_curve);
  // The links' angles, at each arc's middle a little outside the sphere.
  const std::pair<Eigen::Vector3d, Eigen::Vector3d> links[4] = {
      {axes.input_pivot, axes.output_pivot},
      {axes.input_pivot, axes.input_pin},
      {axes.input_pin, axes.output_pin},
      {axes.output_pin, axes.output_pivot}};
  for (int l = 0; l < 4; ++l) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.6g deg", sketch.links_deg[l]);
    drawing->Text3("DIMENSIONS", c + 1.1 * r * (links[l].first + links[l].second).normalized(),
                   r / 15.0, text);
  }
  if (task != nullptr) {
    for (const DualQuaternion& pose : task->spatial_poses) {
      const Eigen::Matrix3d rotation = pose.Rotation();
      const Eigen::Vector3d origin = pose.Translation();
      drawing->Polyline3("TASK", {origin, origin + 0.15 * r * rotation.col(0)}, false);
      drawing->Polyline3("TASK", {origin, origin + 0.075 * r * rotation.col(1)}, false);
    }
  }
}

// What a result's mechanism draws: its scale (the text's and the lines' size) and its entities.
struct Sketch {
  double scale = 1.0;
  std::function<void(Drawing*)> draw;
  std::shared_ptr<SphericalSketch> spherical;  // a spherical four-bar: the SVG's view
};

Sketch PrepareSketch(const std::string& result_text, const std::string& source,
                     const CadExportRequest& request) {
  bool six_bar = false, spherical = false;
  nlohmann::json result;
  try {
    result = nlohmann::json::parse(result_text);
    six_bar = result.is_object() && result.contains("six_bars") && result["six_bars"].is_array() &&
              !result["six_bars"].empty();
    spherical = result.is_object() && result.value("model", std::string()) == "spherical" &&
                result.contains("center") && result.contains("mechanisms");
  } catch (const nlohmann::json::parse_error&) {
    // ReadResultFourBar says what is wrong.
  }
  Sketch sketch;
  if (spherical) {
    auto prepared = std::make_shared<SphericalSketch>(PrepareSpherical(result, source, request));
    sketch.scale = prepared->radius;
    sketch.spherical = prepared;
    const Task* task = request.task;
    sketch.draw = [prepared, task](Drawing* drawing) { DrawSpherical(*prepared, task, drawing); };
    return sketch;
  }
  if (six_bar) {
    auto prepared = std::make_shared<SixBarSketch>(PrepareSixBar(result_text, source, request));
    sketch.scale = prepared->links;
    const Task* task = request.task;
    sketch.draw = [prepared, task](Drawing* drawing) { DrawSixBar(*prepared, task, drawing); };
    return sketch;
  }
  if (const std::optional<ResultDyadFourBar> other =
          ReadResultDyadFourBar(result_text, source, request.mechanism)) {
    auto prepared = std::make_shared<DyadSketch>(PrepareDyadFourBar(*other, source, request));
    sketch.scale = prepared->links;
    const Task* task = request.task;
    sketch.draw = [prepared, task](Drawing* drawing) { DrawDyadFourBar(*prepared, task, drawing); };
    return sketch;
  }
  auto prepared = std::make_shared<FourBarDrawing>(PrepareFourBar(result_text, source, request));
  sketch.scale = prepared->links;
  const Task* task = request.task;
  sketch.draw = [prepared, task](Drawing* drawing) { DrawFourBar(*prepared, task, drawing); };
  return sketch;
}

}  // namespace

std::string ResultDxf(const std::string& result_text, const std::string& source,
                      const CadExportRequest& request) {
  const Sketch sketch = PrepareSketch(result_text, source, request);
  TemporaryPath file;
  DL_Dxf dxf;
  DL_WriterA* writer = dxf.out(file.path().c_str(), DL_Codes::AC1015);
  if (writer == nullptr) throw std::runtime_error("cannot write the DXF's temporary file");
  // Header, tables (line types, layers, text style, dimension style), blocks: as dxflib's own
  // examples order them.
  dxf.writeHeader(*writer);
  writer->sectionEnd();
  writer->sectionTables();
  dxf.writeVPort(*writer);
  writer->tableLinetypes(3);
  dxf.writeLinetype(*writer, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
  dxf.writeLinetype(*writer, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
  dxf.writeLinetype(*writer, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
  writer->tableEnd();
  writer->tableLayers(static_cast<int>(std::size(kLayers)) + 1);
  dxf.writeLayer(*writer, DL_LayerData("0", 0), DL_Attributes("", 7, 0x00ffffff, 15, "CONTINUOUS"));
  for (const Layer& layer : kLayers) {
    dxf.writeLayer(*writer, DL_LayerData(layer.name, 0),
                   DL_Attributes("", layer.color, -1, 15, "CONTINUOUS"));
  }
  writer->tableEnd();
  writer->tableStyle(1);
  DL_StyleData style("Standard", 0, 0.0, 1.0, 0.0, 0, 2.5, "txt", "");
  style.bold = false;
  style.italic = false;
  dxf.writeStyle(*writer, style);
  writer->tableEnd();
  dxf.writeView(*writer);
  dxf.writeUcs(*writer);
  writer->tableAppid(1);
  dxf.writeAppid(*writer, "ACAD");
  writer->tableEnd();
  // Dimension text about a thirtieth of the links' length.
  const double text = sketch.scale / 30.0;
  dxf.writeDimStyle(*writer, text, 0.25 * text, 0.25 * text, 0.25 * text, text);
  dxf.writeBlockRecord(*writer);
  writer->tableEnd();
  writer->sectionEnd();
  writer->sectionBlocks();
  for (const char* block : {"*Model_Space", "*Paper_Space", "*Paper_Space0"}) {
    dxf.writeBlock(*writer, DL_BlockData(block, 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*writer, block);
  }
  writer->sectionEnd();

  writer->sectionEntities();
  DxfDrawing drawing(&dxf, writer);
  sketch.draw(&drawing);
  writer->sectionEnd();
  dxf.writeObjects(*writer, "LINKFIT");
  dxf.writeObjectsEnd(*writer);
  writer->dxfEOF();
  writer->close();
  delete writer;
  std::ifstream in(file.path(), std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string ResultSvg(const std::string& result_text, const std::string& source,
                      const CadExportRequest& request) {
  const Sketch sketch = PrepareSketch(result_text, source, request);
  SvgDrawing drawing(sketch.scale / 300.0, 1e-9 * sketch.scale);
  if (sketch.spherical) {
    // Seen from outside along the mean of its axes, Sigma's z (else y) up, the centre at 0.
    const SphericalFourBarJoints& axes = sketch.spherical->axes;
    Eigen::Vector3d toward =
        axes.input_pivot + axes.output_pivot + axes.input_pin + axes.output_pin;
    toward = toward.norm() > 1e-9 ? toward.normalized() : axes.input_pivot;
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - toward.z() * toward;
    if (up.norm() < 1e-6) up = Eigen::Vector3d::UnitY() - toward.y() * toward;
    up.normalize();
    Eigen::Matrix<double, 2, 3> view;
    view.row(0) = up.cross(toward).transpose();
    view.row(1) = up.transpose();
    drawing.SetView(view, sketch.spherical->centre);
  }
  sketch.draw(&drawing);
  return drawing.Document();
}

}  // namespace linkfit
