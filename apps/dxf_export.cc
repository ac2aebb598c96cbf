#include "apps/dxf_export.h"

#include <dl_dxf.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "lib/analysis_io.h"
#include "lib/four_bar_kinematics.h"
#include "lib/task_io.h"

namespace linkfit {
namespace {

constexpr double kDegree = 180.0 / M_PI;

// The drawing's layers and their colours (AutoCAD colour index).
struct Layer {
  const char* name;
  int color;
};
constexpr Layer kLayers[] = {{"GROUND", 8}, {"INPUT", 1}, {"COUPLER", 5},   {"OUTPUT", 3},
                             {"CURVE", 6},  {"TASK", 2},  {"DIMENSIONS", 7}};

// Writes the entities through dxflib's writer, on the layers above.
class Drawing {
 public:
  Drawing(DL_Dxf* dxf, DL_WriterA* writer, double pivot_radius)
      : dxf_(dxf), writer_(writer), pivot_radius_(pivot_radius) {}

  DL_Attributes On(const char* layer) const {
    return DL_Attributes(layer, 256, -1, "BYLAYER", 1.0);
  }

  void Line(const char* layer, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    dxf_->writeLine(*writer_, DL_LineData(a.x(), a.y(), 0.0, b.x(), b.y(), 0.0), On(layer));
  }
  void Pivot(const char* layer, const Eigen::Vector2d& at) {
    dxf_->writeCircle(*writer_, DL_CircleData(at.x(), at.y(), 0.0, pivot_radius_), On(layer));
  }
  void Polyline(const char* layer, const std::vector<Eigen::Vector2d>& points, bool closed) {
    if (points.size() < 2) return;
    dxf_->writePolyline(*writer_,
                        DL_PolylineData(static_cast<int>(points.size()), 0, 0, closed ? 1 : 0),
                        On(layer));
    for (const Eigen::Vector2d& p : points) {
      dxf_->writeVertex(*writer_, DL_VertexData(p.x(), p.y(), 0.0, 0.0));
    }
    dxf_->writePolylineEnd(*writer_);
  }
  // An aligned dimension of the length from a to b, its line `offset` to the left of a -> b.
  void Dimension(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double offset) {
    const Eigen::Vector2d along = b - a;
    if (!(along.norm() > 0.0)) return;
    const Eigen::Vector2d normal = Eigen::Vector2d(-along.y(), along.x()).normalized();
    const Eigen::Vector2d line = b + offset * normal;
    const Eigen::Vector2d middle = 0.5 * (a + b) + offset * normal;
    // Its text the length itself (a program that does not measure the dimension shows it).
    char text[32];
    std::snprintf(text, sizeof(text), "%.6g", along.norm());
    DL_DimensionData dimension(line.x(), line.y(), 0.0, middle.x(), middle.y(), 0.0,
                               0x1,  // aligned
                               5,    // attachment: middle centre
                               1, 1.0, text, "Standard", 0.0);
    // Its constructor leaves the arrows' flags unset (written as whatever the memory held).
    dimension.arrow1Flipped = false;
    dimension.arrow2Flipped = false;
    dxf_->writeDimAligned(*writer_, dimension,
                          DL_DimAlignedData(a.x(), a.y(), 0.0, b.x(), b.y(), 0.0),
                          On("DIMENSIONS"));
  }

 private:
  DL_Dxf* dxf_;
  DL_WriterA* writer_;
  double pivot_radius_;
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

}  // namespace

std::string ResultDxf(const std::string& result_text, const std::string& source,
                      const DxfExportRequest& request) {
  const ResultFourBar four_bar = ReadResultFourBar(result_text, source, request.mechanism);
  const FourBarJoints& joints = four_bar.joints;
  // The configuration drawn: the first pose's, or the crank at the given angle.
  FourBarState drawn;
  const Eigen::Vector2d crank = joints.input_pin - joints.input_pivot;
  const double reference = std::atan2(crank.y(), crank.x());
  const double input_angle = request.input_deg ? *request.input_deg / kDegree : reference;
  FourBarKinematicsOptions sweep;
  sweep.steps = request.curve_steps;
  const FourBarKinematics kinematics = AnalyzeFourBarKinematics(joints, sweep, four_bar.length);
  if (!PlaceFourBar(joints, input_angle, four_bar.length, &drawn)) {
    const auto shown = [](double value) {
      char text[32];
      std::snprintf(text, sizeof(text), "%.6g", value);
      return std::string(text);
    };
    throw InputError("--input-deg " + shown(input_angle * kDegree) +
                     ": the four-bar does not reach it on its circuit (its crank turns from " +
                     shown(kinematics.range_start * kDegree) + " to " +
                     shown(kinematics.range_end * kDegree) + " degrees)");
  }
  const double links = crank.norm() + (joints.output_pin - joints.input_pin).norm();
  // Pivots a thirtieth of crank and coupler together, at most a sixth of the shortest link.
  double shortest = std::min(crank.norm(), (joints.output_pin - joints.input_pin).norm());
  if (!joints.slider) {
    shortest = std::min({shortest, (joints.output_pin - joints.output_pivot).norm(),
                         (joints.output_pivot - joints.input_pivot).norm()});
  }
  const double pivot_radius = std::min(links / 30.0, shortest / 6.0);

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
  const double text = links / 30.0;
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
  Drawing drawing(&dxf, writer, pivot_radius);
  const Eigen::Vector2d a0 = joints.input_pivot, a = drawn.input_pin, b = drawn.output_pin;
  // Ground: its pivots (a slider's line over the output's travel).
  drawing.Pivot("GROUND", a0);
  if (joints.slider) {
    double low = drawn.output, high = drawn.output;
    for (const FourBarState& state : kinematics.states) {
      low = std::min(low, state.output);
      high = std::max(high, state.output);
    }
    const double margin = 0.1 * links;
    drawing.Line("GROUND", joints.slider_point + (low - margin) * joints.slider_direction,
                 joints.slider_point + (high + margin) * joints.slider_direction);
  } else {
    drawing.Pivot("GROUND", joints.output_pivot);
    drawing.Line("GROUND", a0, joints.output_pivot);
  }
  // The input crank, the coupler body, the output rocker or slider block.
  drawing.Line("INPUT", a0, a);
  drawing.Pivot("INPUT", a0);
  drawing.Pivot("INPUT", a);
  std::vector<Eigen::Vector2d> body = {a, b};
  if (joints.coupler_point && (drawn.coupler_point - a).norm() > 1e-9 * links &&
      (drawn.coupler_point - b).norm() > 1e-9 * links) {
    body.push_back(drawn.coupler_point);
  }
  drawing.Polyline("COUPLER", body, body.size() > 2);
  drawing.Pivot("COUPLER", a);
  drawing.Pivot("COUPLER", b);
  if (joints.coupler_point) drawing.Pivot("COUPLER", drawn.coupler_point);
  if (joints.slider) {
    const Eigen::Vector2d u = joints.slider_direction, n(-u.y(), u.x());
    const double half = 2.0 * pivot_radius;
    drawing.Polyline("OUTPUT",
                     {b - half * u - 0.6 * half * n, b + half * u - 0.6 * half * n,
                      b + half * u + 0.6 * half * n, b - half * u + 0.6 * half * n},
                     true);
    drawing.Pivot("OUTPUT", b);
  } else {
    drawing.Line("OUTPUT", joints.output_pivot, b);
    drawing.Pivot("OUTPUT", joints.output_pivot);
    drawing.Pivot("OUTPUT", b);
  }
  // The coupler curve over the input's range (closed for a crank).
  if (joints.coupler_point) {
    std::vector<Eigen::Vector2d> curve;
    for (const FourBarState& state : kinematics.states) curve.push_back(state.coupler_point);
    drawing.Polyline("CURVE", curve, kinematics.input_rotates_fully);
  }
  // The task: each pose as its frame (x axis twice as long as y), each point as a small circle.
  if (request.task != nullptr) {
    const double axis = 0.1 * links;
    for (const PlanarPose& pose : request.task->planar_poses) {
      const Eigen::Vector2d origin = pose.origin_in_fixed;
      const Eigen::Vector2d x(std::cos(pose.theta), std::sin(pose.theta));
      drawing.Line("TASK", origin, origin + axis * x);
      drawing.Line("TASK", origin, origin + 0.5 * axis * Eigen::Vector2d(-x.y(), x.x()));
    }
    Drawing points(&dxf, writer, 0.5 * pivot_radius);
    for (const TimedPoint& point : request.task->points) points.Pivot("TASK", point.point_in_fixed);
  }
  // The link lengths.
  const double offset = 2.5 * pivot_radius;
  drawing.Dimension(a0, a, offset);
  drawing.Dimension(a, b, offset);
  if (!joints.slider) {
    drawing.Dimension(joints.output_pivot, b, -offset);
    drawing.Dimension(a0, joints.output_pivot, -offset);
  }
  writer->sectionEnd();
  dxf.writeObjects(*writer, "LINKFIT");
  dxf.writeObjectsEnd(*writer);
  writer->dxfEOF();
  writer->close();
  delete writer;
  std::ifstream in(file.path(), std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace linkfit
