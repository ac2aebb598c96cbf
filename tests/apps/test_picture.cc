// Tests of the pictures (apps/picture.h): the SVG must be well-formed XML (xmllint), free of
// NaN/Inf, and render (rsvg-convert) to a PNG with ink where the panels are; the animation must
// have one animated frame group per cycle pose in which the moving parts move and the fixed
// ones stay; the HTML page must carry the frames and the script that steps through them.
// Set PICTURE_KEEP_DIR to keep the rendered files for a look.
#include <gtest/gtest.h>
#include <png.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "apps/picture.h"
#include "lib/mechanism.h"
#include "lib/six_bar.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

using Vec = Eigen::Vector2d;

constexpr double kAssemblyTolerance = 1e-9;
constexpr int kCycleSteps = 360;
// A picture "has ink" where at least this many pixels are not near white.
constexpr int kMinInkPixels = 2000;
// A colour "is there" when at least this many pixels are near it.
constexpr int kMinColourPixels = 40;
// Largest document coordinate accepted (the drawings are a few thousand pixels wide).
constexpr double kMaxDocumentCoordinate = 5000.0;

// ---------------------------------------------------------------------------------------------
// Mechanisms made by hand, with their cycles.

// Intersection of the circles (c0, r0) and (c1, r1) to the left of c0 -> c1.
Vec CircleIntersection(const Vec& c0, double r0, const Vec& c1, double r1) {
  const Vec d = c1 - c0;
  const double dist = d.norm();
  const double a = (r0 * r0 - r1 * r1 + dist * dist) / (2.0 * dist);
  const double h = std::sqrt(std::max(0.0, r0 * r0 - a * a));
  const Vec u = d / dist;
  return c0 + a * u + h * Vec(-u.y(), u.x());
}

// The coupler poses over a full turn of the input crank, each assembled configuration taken
// nearest the previous one (the branch of `start`).
std::vector<PlanarPose> CrankCycle(const PlanarDyad& input, const PlanarDyad& output,
                                   const PlanarPose& start, int steps) {
  std::vector<PlanarPose> cycle;
  PlanarPose previous = start;
  const double phi0 = InputValue(input, start);
  std::vector<PlanarPose> assembled;
  for (int k = 0; k < steps; ++k) {
    const double phi = phi0 + 2.0 * M_PI * k / steps;
    if (AssembleFourBar(input, output, phi, kAssemblyTolerance, &assembled) == 0) continue;
    const PlanarPose* best = &assembled[0];
    for (const PlanarPose& pose : assembled) {
      if (PoseError(pose, previous, 1.0) < PoseError(*best, previous, 1.0)) best = &pose;
    }
    previous = *best;
    cycle.push_back(*best);
  }
  return cycle;
}

void FillCurves(PictureMechanism* mechanism, int steps) {
  mechanism->cycle = CrankCycle(mechanism->input, mechanism->output, mechanism->first_pose, steps);
  mechanism->coupler_curve.clear();
  for (const PlanarPose& pose : mechanism->cycle) {
    mechanism->coupler_curve.push_back(pose.origin_in_fixed);
  }
}

// A crank-rocker: ground A0 B0 = 4, crank 1, coupler 3.5, rocker 3; E's origin is a coupler
// point above the coupler link.
PictureMechanism FourBar(const Vec& output_pivot = Vec(4.0, 0.0), int steps = kCycleSteps) {
  const Vec a0(0.0, 0.0);
  const double crank = 1.0, coupler = 3.5;
  const double rocker = (output_pivot - a0).norm() - 1.0;  // = 3 for the default pivot
  const Vec a = a0 + crank * Vec(std::cos(M_PI / 3.0), std::sin(M_PI / 3.0));
  const Vec b = CircleIntersection(a, coupler, output_pivot, rocker);  // the upper branch
  const double theta = std::atan2((b - a).y(), (b - a).x());
  PlanarPose pose;
  pose.theta = theta;
  pose.origin_in_fixed = a + Rotation2(theta) * Vec(1.2, 1.0);
  PictureMechanism m;
  m.title = "1: 4R, crank-rocker";
  m.input = PlanarDyad::RR(a0, pose.ToMoving(a), crank);
  m.output = PlanarDyad::RR(output_pivot, pose.ToMoving(b), rocker);
  m.first_pose = pose;
  FillCurves(&m, steps);
  return m;
}

// A slider-crank: crank 1 about the origin, coupler 3, slider on the line y = -0.5.
PictureMechanism SliderCrank(int steps = kCycleSteps) {
  const Vec a0(0.0, 0.0), line_point(0.0, -0.5), direction(1.0, 0.0);
  const double crank = 1.0, coupler = 3.0;
  const Vec a = a0 + crank * Vec(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0));
  const double dy = a.y() - line_point.y();
  const Vec b(a.x() + std::sqrt(coupler * coupler - dy * dy), line_point.y());
  const double theta = std::atan2((b - a).y(), (b - a).x());
  PlanarPose pose;
  pose.theta = theta;
  pose.origin_in_fixed = 0.5 * (a + b) + Rotation2(theta) * Vec(0.0, 0.8);
  PictureMechanism m;
  m.title = "2: slider-crank";
  m.labels = {"defect: branch", "remark: the slider line is y = -0.5"};
  m.input = PlanarDyad::RR(a0, pose.ToMoving(a), crank);
  m.output = PlanarDyad::PR(pose.ToMoving(b), line_point, direction);
  m.first_pose = pose;
  FillCurves(&m, steps);
  return m;
}

// An inverted slider-crank (RR + RP): crank 1 about the origin; the coupler carries a line
// through its crank pin that slides in a block turning about (3, 0).
PictureMechanism InvertedSliderCrank(int steps = kCycleSteps) {
  const Vec a0(0.0, 0.0), b0(3.0, 0.0);
  const Vec a = a0 + Vec(std::cos(M_PI / 4.0), std::sin(M_PI / 4.0));
  const double theta = std::atan2((b0 - a).y(), (b0 - a).x());
  PlanarPose pose;
  pose.theta = theta;
  pose.origin_in_fixed = a + Rotation2(theta) * Vec(0.8, 0.7);
  PictureMechanism m;
  m.title = "3: inverted slider-crank";
  m.input = PlanarDyad::RR(a0, pose.ToMoving(a), 1.0);
  m.output = PlanarDyad::RP(b0, pose.ToMoving(a), Vec(1.0, 0.0));  // the line is E's x-axis
  m.first_pose = pose;
  FillCurves(&m, steps);
  return m;
}

// Five task poses taken from the four-bar's cycle.
std::vector<PlanarPose> TaskPoses(const PictureMechanism& m) {
  std::vector<PlanarPose> poses;
  for (size_t k = 0; k < 5; ++k) poses.push_back(m.cycle[k * m.cycle.size() / 5]);
  return poses;
}

// Stand-ins for Burmester curves: a parabola running far out of the view, and a circle.
void AddCurves(Picture* picture) {
  std::vector<Vec> center, circle;
  for (int k = -100; k <= 100; ++k) center.emplace_back(0.2 * k, 0.05 * k * k * 0.04 - 1.0);
  for (int k = 0; k <= 100; ++k) {
    const double t = 2.0 * M_PI * k / 100;
    circle.emplace_back(2.0 + 1.5 * std::cos(t), 1.5 + 1.5 * std::sin(t));
  }
  picture->center_point_curves = {center};
  picture->circle_point_curves = {circle};
}

Picture TwoMechanisms() {
  Picture picture;
  picture.title = "two mechanisms";
  picture.mechanisms = {FourBar(), SliderCrank()};
  picture.task_poses = TaskPoses(picture.mechanisms[0]);
  picture.length = CharacteristicLength(picture.task_poses);
  AddCurves(&picture);
  return picture;
}

// ---------------------------------------------------------------------------------------------
// Files, tools, pixels.

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  const unsigned char* At(int x, int y) const {
    return &rgba[4 * (static_cast<size_t>(y) * static_cast<size_t>(width) + x)];
  }
};

bool ReadPng(const std::string& path, Image* image) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return false;
  png.format = PNG_FORMAT_RGBA;
  image->rgba.assign(PNG_IMAGE_SIZE(png), 0);
  if (!png_image_finish_read(&png, nullptr, image->rgba.data(), 0, nullptr)) {
    png_image_free(&png);
    return false;
  }
  image->width = static_cast<int>(png.width);
  image->height = static_cast<int>(png.height);
  return true;
}

// Pixels in columns [x0, x1) that are not near white (any channel below 200).
int CountInk(const Image& image, int x0, int x1) {
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const unsigned char* p = image.At(x, y);
      if (p[3] > 128 && std::min({p[0], p[1], p[2]}) < 200) ++count;
    }
  }
  return count;
}

// Pixels in columns [x0, x1) near the colour "#rrggbb" (sum of channel differences < 60).
int CountColour(const Image& image, const std::string& hex, int x0, int x1) {
  const int r = std::stoi(hex.substr(1, 2), nullptr, 16);
  const int g = std::stoi(hex.substr(3, 2), nullptr, 16);
  const int b = std::stoi(hex.substr(5, 2), nullptr, 16);
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const unsigned char* p = image.At(x, y);
      if (p[3] > 128 && std::abs(p[0] - r) + std::abs(p[1] - g) + std::abs(p[2] - b) < 60) {
        ++count;
      }
    }
  }
  return count;
}

int CountOf(const std::string& text, const std::string& what) {
  int count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++count;
  }
  return count;
}

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// All numbers in the geometric attributes of the document.
std::vector<double> AttributeNumbers(const std::string& svg) {
  static const std::regex attribute(
      R"re(\s(?:x|y|x1|y1|x2|y2|cx|cy|r|width|height|points|d)="([^"]*)")re");
  static const std::regex number(R"re([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)re");
  std::vector<double> numbers;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), attribute);
       it != std::sregex_iterator(); ++it) {
    const std::string value = (*it)[1];
    for (auto n = std::sregex_iterator(value.begin(), value.end(), number);
         n != std::sregex_iterator(); ++n) {
      numbers.push_back(std::stod(n->str()));
    }
  }
  return numbers;
}

// The contents of each <g class="frame"> group, in order.
std::vector<std::string> Frames(const std::string& svg) {
  std::vector<std::string> frames;
  const std::string open = "<g class=\"frame\"";
  for (size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1)) {
    const size_t end = svg.find("</g>", at);
    frames.push_back(svg.substr(at, end - at));
  }
  return frames;
}

// The four coordinates of the first <line> in `text`.
std::vector<double> FirstLine(const std::string& text) {
  static const std::regex line(R"re(<line x1="([^"]*)" y1="([^"]*)" x2="([^"]*)" y2="([^"]*)")re");
  std::smatch match;
  if (!std::regex_search(text, match, line)) return {};
  return {std::stod(match[1]), std::stod(match[2]), std::stod(match[3]), std::stod(match[4])};
}

class PictureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/linkfit_picture_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override {
    if (const char* keep = std::getenv("PICTURE_KEEP_DIR")) {
      std::filesystem::create_directories(keep);
      for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
        std::filesystem::copy(entry.path(), std::filesystem::path(keep) / entry.path().filename(),
                              std::filesystem::copy_options::overwrite_existing);
      }
    }
    std::filesystem::remove_all(dir_);
  }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }

  // Runs a shell command; its exit status, with its stderr (if any) in *err.
  int Run(const std::string& command, std::string* err) const {
    const std::string err_path = Path("stderr.txt");
    const int status = std::system((command + " 2>" + err_path).c_str());
    *err = ReadFile(err_path);
    std::filesystem::remove(err_path);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Checks `svg` is well-formed XML without NaN or Inf, renders it to PNG and reads it back.
  void CheckAndRender(const std::string& name, const std::string& svg, Image* image) const {
    const std::string svg_path = Write(name + ".svg", svg);
    std::string err;
    EXPECT_EQ(Run("xmllint --noout '" + svg_path + "'", &err), 0) << err;
    const std::string lower = Lower(svg);
    EXPECT_EQ(lower.find("nan"), std::string::npos) << name;
    EXPECT_EQ(lower.find("inf"), std::string::npos) << name;
    for (double v : AttributeNumbers(svg)) {
      ASSERT_TRUE(std::isfinite(v)) << name;
      ASSERT_LE(std::abs(v), kMaxDocumentCoordinate) << name;
    }
    const std::string png_path = Path(name + ".png");
    ASSERT_EQ(Run("rsvg-convert -o '" + png_path + "' '" + svg_path + "'", &err), 0) << err;
    ASSERT_TRUE(ReadPng(png_path, image)) << png_path;
    ASSERT_GT(image->width, 100);
    ASSERT_GT(image->height, 100);
  }

  std::string dir_;
};

// ---------------------------------------------------------------------------------------------

TEST_F(PictureTest, HandMadeMechanismsAreSound) {
  const PictureMechanism four_bar = FourBar();
  EXPECT_EQ(GrashofType(four_bar.input, four_bar.output, 1.0), "crank-rocker");
  EXPECT_EQ(four_bar.cycle.size(), static_cast<size_t>(kCycleSteps));  // a full crank turn
  const PictureMechanism slider = SliderCrank();
  EXPECT_EQ(slider.cycle.size(), static_cast<size_t>(kCycleSteps));
  for (const PictureMechanism* m : {&four_bar, &slider}) {
    EXPECT_LT(m->input.MaxResidual(m->cycle), 1e-9);
    EXPECT_LT(m->output.MaxResidual(m->cycle), 1e-9);
  }
}

TEST_F(PictureTest, PanelsOfFourBarAndSliderCrankHaveInk) {
  const Picture picture = TwoMechanisms();
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("two", svg, &image));
  EXPECT_EQ(CountOf(svg, "<clipPath"), 2);
  EXPECT_NE(svg.find("1: 4R, crank-rocker"), std::string::npos);
  EXPECT_NE(svg.find("defect: branch"), std::string::npos);
  EXPECT_NE(svg.find("stroke-dasharray=\"9 5\""), std::string::npos);  // the slider line
  EXPECT_NE(svg.find("coupler curve"), std::string::npos);             // the legend
  EXPECT_GT(image.width, image.height);                                // two panels in a row
  const int half = image.width / 2;
  EXPECT_GT(CountInk(image, 0, image.width), 2 * kMinInkPixels);
  for (int side = 0; side < 2; ++side) {
    const int x0 = side * half, x1 = x0 + half;
    SCOPED_TRACE(side == 0 ? "left panel" : "right panel");
    EXPECT_GT(CountInk(image, x0, x1), kMinInkPixels);
    EXPECT_GT(CountColour(image, "#1f77b4", x0, x1), kMinColourPixels);  // coupler curve
    EXPECT_GT(CountColour(image, "#d62728", x0, x1), kMinColourPixels);  // task x axes
    EXPECT_GT(CountColour(image, "#2ca02c", x0, x1), kMinColourPixels);  // task y axes
    EXPECT_GT(CountColour(image, "#9467bd", x0, x1), kMinColourPixels);  // center-point curve
    EXPECT_GT(CountColour(image, "#ff7f0e", x0, x1), kMinColourPixels);  // circle-point curve
    EXPECT_GT(CountColour(image, "#333333", x0, x1), kMinColourPixels);  // links
  }
}

TEST_F(PictureTest, TaskOnlyPictureHasOnePanelWithNumberedPoses) {
  Picture picture;
  picture.title = "task.json";
  picture.task_poses = TaskPoses(FourBar());
  picture.length = CharacteristicLength(picture.task_poses);
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("task", svg, &image));
  EXPECT_EQ(CountOf(svg, "<clipPath"), 1);
  for (int i = 1; i <= 5; ++i) {
    EXPECT_NE(svg.find(">" + std::to_string(i) + "</text>"), std::string::npos) << i;
  }
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels / 2);
  EXPECT_GT(CountColour(image, "#d62728", 0, image.width), 5 * kMinColourPixels);
  EXPECT_GT(CountColour(image, "#2ca02c", 0, image.width), 5 * kMinColourPixels);
}

TEST_F(PictureTest, PathPointsAreMarked) {
  Picture picture;
  picture.title = "path";
  const PictureMechanism m = FourBar();
  for (size_t k = 0; k < 5; ++k) {
    picture.path_points.push_back(m.coupler_curve[k * m.coupler_curve.size() / 5]);
  }
  picture.mechanisms = {m};
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("path", svg, &image));
  EXPECT_GT(CountColour(image, "#c51b8a", 0, image.width), kMinColourPixels);
  EXPECT_NE(svg.find("path point"), std::string::npos);
}

// Issue 35: the task's pivot boxes are drawn (the fixed pivots' in Sigma in every panel, the
// moving pivots' where E is in each), in the legend and in the picture's JSON; a listed four-bar
// that breaks a constraint says so on its panel.
TEST_F(PictureTest, PivotBoxesAreDrawnAndViolationsNamed) {
  Picture picture = TwoMechanisms();
  PlanarBox fixed;
  fixed.min = Vec(-1.0, -1.0);
  fixed.max = Vec(5.0, 1.0);
  PlanarBox moving;
  moving.min = Vec(-0.5, -0.5);
  moving.max = Vec(0.5, 0.5);
  picture.fixed_pivots_box = fixed;
  picture.moving_pivots_box = moving;
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("boxes", svg, &image));
  EXPECT_NE(svg.find("fixed-pivot box"), std::string::npos);
  EXPECT_NE(svg.find("moving-pivot box (in E)"), std::string::npos);
  EXPECT_EQ(CountOf(svg, "stroke-dasharray=\"8 4\""), 3);  // two panels and the legend
  EXPECT_EQ(CountOf(svg, "stroke-dasharray=\"3 3\""), 3);
  const int half = image.width / 2;
  for (int side = 0; side < 2; ++side) {
    SCOPED_TRACE(side == 0 ? "left panel" : "right panel");
    EXPECT_GT(CountColour(image, "#2e7d32", side * half, side * half + half), kMinColourPixels);
  }
  const nlohmann::json json = nlohmann::json::parse(PictureToJson(picture));
  EXPECT_EQ(json.at("fixed_pivots_box"), nlohmann::json({-1.0, -1.0, 5.0, 1.0}));
  EXPECT_EQ(json.at("moving_pivots_box"), nlohmann::json({-0.5, -0.5, 0.5, 0.5}));
  // Without boxes: neither drawn nor written.
  const Picture plain = TwoMechanisms();
  EXPECT_EQ(RenderSvg(plain).find("pivot box"), std::string::npos);
  EXPECT_FALSE(nlohmann::json::parse(PictureToJson(plain)).contains("fixed_pivots_box"));

  // A solved task whose box no exact four-bar keeps: its panels name the broken constraint.
  const PictureMechanism four_bar = FourBar();
  Task task = PlanarMotionTask(TaskPoses(four_bar));
  PlanarBox far;
  far.min = Vec(100.0, 100.0);
  far.max = Vec(101.0, 101.0);
  task.constraints.fixed_pivots_box = far;
  task.constraints.given = true;
  const TaskResult result = SolveTask(task);
  const std::optional<Picture> solved = TaskPicture("boxed", task, result, 4);
  ASSERT_TRUE(solved.has_value());
  ASSERT_TRUE(solved->fixed_pivots_box.has_value());
  ASSERT_FALSE(solved->mechanisms.empty());
  const PlanarMotionResult& motion = std::get<PlanarMotionResult>(result);
  int violating = 0;
  for (size_t k = 0; k < solved->mechanisms.size(); ++k) {
    const std::vector<std::string>& labels = solved->mechanisms[k].labels;
    for (const std::string& bound : motion.mechanisms[k].violates) {
      ++violating;
      EXPECT_NE(std::find(labels.begin(), labels.end(), "violates " + bound), labels.end())
          << solved->mechanisms[k].title;
    }
  }
  EXPECT_GT(violating, 0);  // the exact four-bars, listed after those that keep the box
}

TEST_F(PictureTest, FarPivotDoesNotCollapseTheView) {
  Picture near_picture, far_picture;
  near_picture.mechanisms = {FourBar()};
  near_picture.task_poses = TaskPoses(near_picture.mechanisms[0]);
  near_picture.length = CharacteristicLength(near_picture.task_poses);
  far_picture = near_picture;
  // The output pivot a million characteristic lengths away (its cycle is then not needed).
  PictureMechanism& far = far_picture.mechanisms[0];
  const double distance = 1e6 * far_picture.length;
  far.output.fixed_pivot = Vec(distance, 0.0);
  far.output.radius = (far.first_pose.ToFixed(far.output.moving_pivot) - Vec(distance, 0.0)).norm();
  far.coupler_curve.push_back(Vec(-distance, distance));  // a wild curve point too
  Image near_image, far_image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("near", RenderSvg(near_picture), &near_image));
  const std::string svg = RenderSvg(far_picture);
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("far", svg, &far_image));
  EXPECT_NE(svg.find("B0 ("), std::string::npos);  // the arrow towards the far pivot
  EXPECT_GT(CountColour(far_image, "#8b0000", 0, far_image.width), kMinColourPixels);
  // The task frames are as visible as without the far pivot.
  const int near_red = CountColour(near_image, "#d62728", 0, near_image.width);
  const int far_red = CountColour(far_image, "#d62728", 0, far_image.width);
  EXPECT_GT(far_red, near_red / 2);
  EXPECT_GT(CountInk(far_image, 0, far_image.width), kMinInkPixels);
}

TEST_F(PictureTest, NonFiniteAndEmptyInputGiveValidDocuments) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Picture picture = TwoMechanisms();
  picture.task_poses.push_back(PlanarPose(nan, 1.0, 0.0));
  picture.task_poses.push_back(PlanarPose(1.0, 1.0, inf));
  picture.mechanisms[0].coupler_curve.insert(picture.mechanisms[0].coupler_curve.begin() + 10,
                                             Vec(nan, 0.0));
  picture.mechanisms[1].output.line_direction = Vec(0.0, 0.0);
  picture.mechanisms[1].input.fixed_pivot = Vec(inf, 0.0);
  picture.center_point_curves.push_back({Vec(nan, nan), Vec(1e300, -1e300), Vec(0.0, 0.0)});
  picture.length = nan;
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("nonfinite", RenderSvg(picture), &image));
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels);

  Picture empty;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("empty", RenderSvg(empty), &image));
  PictureMechanism bare;  // all defaults: two RR dyads at the origin
  bare.first_pose = PlanarPose(nan, nan, nan);
  empty.mechanisms = {bare, bare, bare};
  empty.length = 0.0;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("bare", RenderSvg(empty), &image));
  ASSERT_NO_FATAL_FAILURE(
      CheckAndRender("bare_animation", RenderAnimation(empty, 0, false), &image));
}

TEST_F(PictureTest, TextIsEscaped) {
  Picture picture = TwoMechanisms();
  picture.title = "a<b & \"c\" > 'd'";
  picture.mechanisms[0].title = "</svg><script>x</script>";
  picture.mechanisms[0].labels = {"tab\there", "bad utf-8 \xff\xfe here", "\xce\xb8 = 30\xc2\xb0"};
  for (int i = 0; i < 12; ++i) picture.mechanisms[1].labels.push_back("label " + std::to_string(i));
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("escaped", svg, &image));
  EXPECT_NE(svg.find("a&lt;b &amp; &quot;c&quot; &gt; &#39;d&#39;"), std::string::npos);
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_NE(svg.find("\xce\xb8 = 30\xc2\xb0"), std::string::npos);  // UTF-8 kept
  EXPECT_NE(svg.find("more"), std::string::npos);                   // too many labels
}

TEST_F(PictureTest, AnimationMovesTheMovingPartsOnly) {
  const Picture picture = TwoMechanisms();
  const std::string svg = RenderAnimation(picture, 0, false);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("animation", svg, &image));
  const std::vector<std::string> frames = Frames(svg);
  ASSERT_GE(frames.size(), 60u);
  ASSERT_LE(frames.size(), picture.mechanisms[0].cycle.size());
  EXPECT_EQ(CountOf(svg, "<animate "), static_cast<int>(frames.size()));
  EXPECT_NE(svg.find("calcMode=\"discrete\""), std::string::npos);
  EXPECT_NE(svg.find("dur=\"4s\""), std::string::npos);
  EXPECT_NE(svg.find("repeatCount=\"indefinite\""), std::string::npos);
  EXPECT_EQ(CountOf(svg, "visibility=\"visible\">"), 1);  // frame 0 shows without animation
  // The crank: its end at the fixed pivot stays, its end at the moving pivot goes round.
  const std::vector<double> first = FirstLine(frames[0]);
  ASSERT_EQ(first.size(), 4u);
  double moved = 0.0;
  for (const std::string& frame : frames) {
    const std::vector<double> line = FirstLine(frame);
    ASSERT_EQ(line.size(), 4u);
    EXPECT_NEAR(line[0], first[0], 0.01);
    EXPECT_NEAR(line[1], first[1], 0.01);
    moved = std::max(moved, std::hypot(line[2] - first[2], line[3] - first[3]));
  }
  EXPECT_GT(moved, 20.0);  // pixels: the crank turned
  // The ground symbols are outside the frames.
  for (const std::string& frame : frames) EXPECT_EQ(frame.find(">A0<"), std::string::npos);
  EXPECT_NE(svg.find(">A0</text>"), std::string::npos);
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels);
  EXPECT_GT(CountColour(image, "#1f77b4", 0, image.width), kMinColourPixels);
  EXPECT_GT(CountColour(image, "#333333", 0, image.width), kMinColourPixels);
}

TEST_F(PictureTest, SliderCrankAnimationMovesTheBlock) {
  Picture picture;
  picture.mechanisms = {SliderCrank(72)};
  const std::string svg = RenderAnimation(picture, 0, false);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("slider_animation", svg, &image));
  const std::vector<std::string> frames = Frames(svg);
  ASSERT_EQ(frames.size(), 72u);
  EXPECT_EQ(CountOf(svg, "<animate "), 72);
  EXPECT_NE(frames[0], frames[36]);
  // The block is the grey polygon of each frame: it is somewhere else half a turn later.
  const std::string block = "fill=\"#d9d9d9\"";
  EXPECT_EQ(CountOf(frames[0], block), 1);
  const size_t at0 = frames[0].rfind("<polygon points=\"", frames[0].find(block));
  const size_t at36 = frames[36].rfind("<polygon points=\"", frames[36].find(block));
  EXPECT_NE(frames[0].substr(at0, 60), frames[36].substr(at36, 60));
  // The slider line is drawn once, outside the frames.
  EXPECT_EQ(CountOf(svg, "stroke-dasharray=\"9 5\""), 1);
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels);
}

TEST_F(PictureTest, InvertedSliderCrankTurnsItsBlockWithTheCoupler) {
  Picture picture;
  picture.title = "inverted";
  picture.mechanisms = {InvertedSliderCrank(), FourBar(), SliderCrank()};
  EXPECT_EQ(picture.mechanisms[0].cycle.size(), static_cast<size_t>(kCycleSteps));
  EXPECT_LT(picture.mechanisms[0].output.MaxResidual(picture.mechanisms[0].cycle), 1e-9);
  const std::string svg = RenderSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("inverted", svg, &image));
  EXPECT_EQ(CountOf(svg, "<clipPath"), 3);
  const int third = image.width / 3;
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    EXPECT_GT(CountInk(image, k * third, (k + 1) * third), kMinInkPixels);
    EXPECT_GT(CountColour(image, "#1f77b4", k * third, (k + 1) * third), kMinColourPixels);
  }
  const std::string animation = RenderAnimation(picture, 0, false);
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("inverted_animation", animation, &image));
  const std::vector<std::string> frames = Frames(animation);
  ASSERT_FALSE(frames.empty());
  const std::string block = "fill=\"#d9d9d9\"";
  for (const std::string& frame : frames) ASSERT_EQ(CountOf(frame, block), 1);
  // The block turns about the fixed pivot: its outline differs a quarter turn later.
  const size_t quarter = frames.size() / 4;
  const size_t at0 = frames[0].rfind("<polygon points=\"", frames[0].find(block));
  const size_t at1 = frames[quarter].rfind("<polygon points=\"", frames[quarter].find(block));
  EXPECT_NE(frames[0].substr(at0, 60), frames[quarter].substr(at1, 60));
  EXPECT_GT(CountColour(image, "#d9d9d9", 0, image.width), 50);
}

TEST_F(PictureTest, HtmlPageStepsThroughTheFrames) {
  const Picture picture = TwoMechanisms();
  const std::string html = RenderAnimation(picture, 1, true);
  Write("animation.html", html);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<script>"), std::string::npos);
  EXPECT_NE(html.find("setInterval"), std::string::npos);
  EXPECT_NE(html.find("querySelectorAll('#drawing g.frame')"), std::string::npos);
  EXPECT_EQ(html.find("<animate"), std::string::npos);  // the script animates instead
  const std::string lower = Lower(html);
  EXPECT_EQ(lower.find("nan"), std::string::npos);
  EXPECT_EQ(lower.find("inf"), std::string::npos);
  const std::vector<std::string> frames = Frames(html);
  EXPECT_GE(frames.size(), 60u);
  // The embedded drawing is well-formed and renders.
  const size_t begin = html.find("<svg"), end = html.find("</svg>");
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  Image image;
  ASSERT_NO_FATAL_FAILURE(
      CheckAndRender("html_drawing", html.substr(begin, end + 6 - begin), &image));
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels);
}

TEST_F(PictureTest, AnimationWithoutMechanismOrCycleIsStillADrawing) {
  Picture picture = TwoMechanisms();
  Image image;
  const std::string missing = RenderAnimation(picture, 7, false);
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("missing", missing, &image));
  EXPECT_NE(missing.find("no mechanism 8"), std::string::npos);
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels / 2);
  picture.mechanisms[0].cycle.clear();
  const std::string still = RenderAnimation(picture, 0, false);
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("still", still, &image));
  EXPECT_TRUE(Frames(still).empty());
  EXPECT_GT(CountColour(image, "#333333", 0, image.width), kMinColourPixels);
}

// ---------------------------------------------------------------------------------------------
// Spherical pictures.

// Tolerance on directions and projected points, of numbers computed the same way.
constexpr double kSphereTolerance = 1e-12;

Eigen::Vector3d Vector3(const nlohmann::json& v) {
  return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}

Vec Vector2(const nlohmann::json& v) { return Vec(v[0].get<double>(), v[1].get<double>()); }

// The runs of a polyline's JSON draw `points` (unit vectors) projected on (right, up), in order,
// each run solid exactly where both ends of its segments face the viewer.
void ExpectRunsDraw(const nlohmann::json& runs, const std::vector<Eigen::Vector3d>& points,
                    const Eigen::Vector3d& toward, const Eigen::Vector3d& right,
                    const Eigen::Vector3d& up, const std::string& what) {
  SCOPED_TRACE(what);
  size_t next = 0;  // the 3-D point the next run starts at
  for (const nlohmann::json& run : runs) {
    const nlohmann::json& drawn = run["points"];
    ASSERT_GE(drawn.size(), 2u);
    for (size_t k = 0; k < drawn.size(); ++k) {
      ASSERT_LT(next + k, points.size());
      const Eigen::Vector3d& x = points[next + k];
      EXPECT_NEAR(Vector2(drawn[k]).x(), x.dot(right), kSphereTolerance);
      EXPECT_NEAR(Vector2(drawn[k]).y(), x.dot(up), kSphereTolerance);
      EXPECT_LE(Vector2(drawn[k]).norm(), 1.0 + kSphereTolerance);  // inside the sphere's disk
      if (k > 0) {
        const bool front = points[next + k - 1].dot(toward) >= 0.0 && x.dot(toward) >= 0.0;
        EXPECT_EQ(run["front"].get<bool>(), front) << k;
      }
    }
    next += drawn.size() - 1;
  }
  EXPECT_EQ(next + 1, points.size()) << "the runs end where the polyline ends";
}

// The bundled spherical four-bar (data/spherical_four_bar_5_poses.json, its first orientation
// the identity), solved: one panel per listed four-bar, in ranked order, each viewed along the mean
// of its axes at the first pose with Sigma's z-axis up, its ground pivots its fixed axes and its
// links at the first pose of the angles of its dyads; the JSON draws that geometry projected on
// the view (solid and dashed as the SVG), and the SVG is sound with ink in the colours of the
// drawing.
TEST_F(PictureTest, SphericalPictureDrawsTheListedFourBarsOnTheirViews) {
  const Task task =
      ParseTask(ReadFile(LINKFIT_SOURCE_DIR "/data/spherical_four_bar_5_poses.json"), "sphere");
  const TaskResult solved = SolveTask(task);
  ASSERT_TRUE(std::holds_alternative<SpatialMotionResult>(solved));
  const SpatialMotionResult& result = std::get<SpatialMotionResult>(solved);
  ASSERT_EQ(result.model, "spherical");
  ASSERT_GE(result.spherical_mechanisms.size(), 2u);
  const Eigen::Matrix3d first = task.spatial_poses[0].Rotation();
  ASSERT_TRUE(first.isIdentity(1e-12));
  const size_t max_panels = 1;  // fewer panels than four-bars: the best ranked
  for (size_t panels : {max_panels, size_t{12}}) {
    const std::optional<SphericalPicture> picture =
        SphericalTaskPicture("sphere", task, result, panels);
    ASSERT_TRUE(picture);
    ASSERT_EQ(picture->panels.size(), std::min(panels, result.spherical_mechanisms.size()));
    EXPECT_TRUE(picture->center.isApprox(result.spherical->in_fixed));
    const nlohmann::json json = nlohmann::json::parse(SphericalPictureToJson(*picture));
    EXPECT_EQ(json["kind"], "spherical");
    EXPECT_NE(json["heading"].get<std::string>().find("orthographic view"), std::string::npos);
    ASSERT_EQ(json["mechanisms"].size(), picture->panels.size());
    for (size_t i = 0; i < picture->panels.size(); ++i) {
      SCOPED_TRACE("panel " + std::to_string(i + 1));
      const SphericalPanel& panel = picture->panels[i];
      const nlohmann::json& drawn = json["mechanisms"][i];
      const MechanismReport& mechanism = result.spherical_mechanisms[i];
      const SphericalDyad& input = result.spherical_dyads[mechanism.input_dyad].dyad;
      const SphericalDyad& output = result.spherical_dyads[mechanism.output_dyad].dyad;
      EXPECT_EQ(panel.title.rfind(std::to_string(i + 1) + ": spherical 4R, ", 0), 0u);
      EXPECT_EQ(drawn["title"], panel.title);
      EXPECT_TRUE(panel.fixed_axes[0].isApprox(input.fixed_axis, kSphereTolerance));
      EXPECT_TRUE(panel.fixed_axes[1].isApprox(output.fixed_axis, kSphereTolerance));
      // The links at the first pose: the cranks at their dyads' angles, the coupler's arc the
      // angle of its moving axes, the pins near where the first orientation puts them.
      EXPECT_NEAR(DirectionAngle(panel.fixed_axes[0], panel.pins[0]), input.angle, 1e-9);
      EXPECT_NEAR(DirectionAngle(panel.fixed_axes[1], panel.pins[1]), output.angle, 1e-9);
      EXPECT_NEAR(DirectionAngle(panel.pins[0], panel.pins[1]),
                  DirectionAngle(input.moving_axis, output.moving_axis), 1e-9);
      EXPECT_LT((panel.pins[0] - first * input.moving_axis).norm(), 1e-4);
      EXPECT_LT((panel.pins[1] - first * output.moving_axis).norm(), 1e-4);
      EXPECT_EQ(panel.task_couplers.size(), task.spatial_poses.size());
      ASSERT_GT(panel.input_pin_path.size(), 100u);
      for (const Eigen::Vector3d& pin : panel.input_pin_path) {
        EXPECT_NEAR(DirectionAngle(input.fixed_axis, pin), input.angle, 1e-9);
      }
      // The view.
      const Eigen::Vector3d toward =
          (input.fixed_axis + output.fixed_axis + first * (input.moving_axis + output.moving_axis))
              .normalized();
      const Eigen::Vector3d right = Vector3(drawn["right"]), up = Vector3(drawn["up"]);
      EXPECT_TRUE(Vector3(drawn["toward"]).isApprox(toward, kSphereTolerance));
      EXPECT_NEAR(up.dot(toward), 0.0, kSphereTolerance);
      EXPECT_NEAR(up.norm(), 1.0, kSphereTolerance);
      EXPECT_GT(up.z(), 0.0);                                           // Sigma's z-axis up
      EXPECT_TRUE(right.isApprox(up.cross(toward), kSphereTolerance));  // right-handed
      for (int k = 0; k < 3; ++k) {
        const Vec axis = Vector2(drawn["sigma_axes"][k]);
        EXPECT_NEAR(axis.x(), right[k], kSphereTolerance);
        EXPECT_NEAR(axis.y(), up[k], kSphereTolerance);
      }
      for (int k = 0; k < 2; ++k) {
        for (const auto& [key, where] :
             {std::pair<const char*, Eigen::Vector3d>{"fixed_pivots", panel.fixed_axes[k]},
              {"pins", panel.pins[k]}}) {
          const nlohmann::json& mark = drawn[key][k];
          EXPECT_NEAR(Vector2(mark["at"]).x(), where.dot(right), kSphereTolerance) << key;
          EXPECT_NEAR(Vector2(mark["at"]).y(), where.dot(up), kSphereTolerance) << key;
          EXPECT_EQ(mark["front"].get<bool>(), where.dot(toward) >= 0.0) << key;
        }
      }
      for (const auto& [key, points] :
           {std::pair<const char*, const std::vector<Eigen::Vector3d>*>{"ground", &panel.ground},
            {"input_link", &panel.input_link},
            {"output_link", &panel.output_link},
            {"coupler", &panel.coupler},
            {"input_pin_path", &panel.input_pin_path},
            {"output_pin_path", &panel.output_pin_path}}) {
        ExpectRunsDraw(drawn[key], *points, toward, right, up, key);
      }
      for (size_t j = 0; j < panel.task_couplers.size(); ++j) {
        ExpectRunsDraw(drawn["task_couplers"][j], panel.task_couplers[j], toward, right, up,
                       "task coupler " + std::to_string(j));
      }
    }
    const std::string svg = RenderSphericalSvg(*picture);
    Image image;
    ASSERT_NO_FATAL_FAILURE(CheckAndRender("sphere" + std::to_string(panels), svg, &image));
    EXPECT_NE(svg.find("sphere: spherical motion about ["), std::string::npos);
    EXPECT_EQ(CountOf(svg, ": spherical 4R, "), static_cast<int>(picture->panels.size()));
    for (const char* colour : {"#1f77b4", "#9467bd", "#d62728", "#333333"}) {
      EXPECT_GT(CountColour(image, colour, 0, image.width), kMinColourPixels) << colour;
    }
  }
  // The Python module's picture is the spherical one.
  std::string why;
  const nlohmann::json any = nlohmann::json::parse(TaskPictureJson("", task, solved, 12, &why));
  EXPECT_EQ(any["kind"], "spherical");
  EXPECT_EQ(any["mechanisms"].size(), std::min<size_t>(12, result.spherical_mechanisms.size()));
}

// A spherical result without four-bars is a bare sphere; another result has no spherical picture.
// A six-bar result's picture (issue 36): a panel per six-bar drawn by its joints, where the result
// puts them at the first pose; its animation moves the six-bar as one: every body rigid (the
// distances between its joints kept), the ground's joints still, the task body's wrist and E
// where the frame's pose puts them; the SVGs are sound and have ink.
TEST_F(PictureTest, SixBarsAreDrawnByTheirJointsAndMoveAsOne) {
  const Task task =
      ReadTaskFile(std::string(LINKFIT_SOURCE_DIR) + "/data/six_bar_5_poses.json").front();
  const TaskResult result = SolveTask(task);
  const PlanarMotionResult& motion = std::get<PlanarMotionResult>(result);
  ASSERT_GE(motion.six_bars.size(), 2u);
  const std::optional<Picture> picture = TaskPicture("six-bars", task, result, 12);
  ASSERT_TRUE(picture.has_value());
  ASSERT_EQ(picture->mechanisms.size(), std::min<size_t>(12, motion.six_bars.size()));
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("six_bars", RenderSvg(*picture), &image));
  EXPECT_GT(CountInk(image, 0, image.width), kMinInkPixels);
  EXPECT_GT(CountColour(image, "#333333", 0, image.width), kMinColourPixels);  // links
  EXPECT_GT(CountColour(image, "#1f77b4", 0, image.width), kMinColourPixels);  // curves
  const nlohmann::json drawn = nlohmann::json::parse(PictureToJson(*picture));
  for (size_t m = 0; m < picture->mechanisms.size(); ++m) {
    SCOPED_TRACE("six-bar " + std::to_string(m + 1));
    const SixBar& six_bar = motion.six_bars[m].six_bar;
    const PictureMechanism& mechanism = picture->mechanisms[m];
    ASSERT_TRUE(mechanism.joints.has_value());
    const PictureMechanism::Joints& joints = *mechanism.joints;
    // Where the result says: G, the elbow, the wrist, then each RR link's two joints.
    const std::vector<Vec> expected = {six_bar.ground_pivot,
                                       six_bar.elbow,
                                       six_bar.wrist,
                                       six_bar.links[0].from_joint,
                                       six_bar.links[0].to_joint,
                                       six_bar.links[1].from_joint,
                                       six_bar.links[1].to_joint};
    ASSERT_EQ(joints.at_first.size(), expected.size());
    for (size_t j = 0; j < expected.size(); ++j) {
      EXPECT_LT((joints.at_first[j] - expected[j]).norm(), 1e-12) << joints.names[j];
      const nlohmann::json& place = drawn["mechanisms"][m]["joints"]["at_first_pose"][j];
      EXPECT_NEAR(place[0].get<double>(), expected[j].x(), 1e-12);
      EXPECT_NEAR(place[1].get<double>(), expected[j].y(), 1e-12);
    }
    EXPECT_EQ(drawn["mechanisms"][m].contains("input"), false);
    // The ground: G and every RR link's joint on it.
    std::vector<int> ground = {0};
    for (int l = 0; l < 2; ++l) {
      if (six_bar.links[l].from_body == kSixBarGround) ground.push_back(3 + 2 * l);
    }
    EXPECT_EQ(joints.bodies[kSixBarGround], ground);
    ASSERT_GE(mechanism.cycle.size(), 10u);
    ASSERT_EQ(joints.cycle.size(), mechanism.cycle.size());
    const Vec wrist_in_e = six_bar.reference_pose.ToMoving(six_bar.wrist);
    double moved = 0.0;
    for (size_t k = 0; k < joints.cycle.size(); ++k) {
      const std::vector<Vec>& places = joints.cycle[k];
      for (size_t b = 0; b < joints.bodies.size(); ++b) {
        for (const int i : joints.bodies[b]) {
          for (const int j : joints.bodies[b]) {
            EXPECT_NEAR((places[i] - places[j]).norm(),
                        (joints.at_first[i] - joints.at_first[j]).norm(), 1e-9)
                << "body " << b << " frame " << k;
          }
          if (b == kSixBarGround) {
            EXPECT_LT((places[i] - joints.at_first[i]).norm(), 1e-12);
          }
        }
      }
      EXPECT_LT((mechanism.cycle[k].ToFixed(wrist_in_e) - places[2]).norm(), 1e-9) << k;
      moved = std::max(moved, (places[2] - joints.at_first[2]).norm());
    }
    EXPECT_GT(moved, 0.05 * picture->length);
  }
  const std::string animation = RenderAnimation(*picture, 0, false);
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("six_bar_animation", animation, &image));
  EXPECT_GE(Frames(animation).size(), 10u);
  EXPECT_NE(animation.find(">G</text>"), std::string::npos);
  EXPECT_NE(animation.find(">wrist</text>"), std::string::npos);
  // The animation starts at the first pose.
  EXPECT_LT(PoseError(picture->mechanisms[0].cycle.front(), task.planar_poses.front(), 1.0), 1e-9);
}

// A newcomer's task (issue 36): a tray through five poses in mm on a chain of its own; every
// six-bar animates (a rocker whose first pose is at the start of its range crashed the cycle's
// there-and-back), each animation a sound document with the six-bar's frames.
TEST_F(PictureTest, EverySixBarOfATaskAnimates) {
  const Task task = ParseTask(
      R"({"problem": "motion", "linkage": "six-bar",
          "poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 40, "y": 12, "theta_deg": 10},
                    {"x": 78, "y": 30, "theta_deg": 22}, {"x": 110, "y": 55, "theta_deg": 35},
                    {"x": 135, "y": 85, "theta_deg": 50}],
          "chain": {"ground_pivot": [60, -60], "wrist": [0, 0], "link_lengths": [90, 80],
                    "elbow": "left"}})",
      "tray.json");
  const TaskResult result = SolveTask(task);
  const size_t listed = std::get<PlanarMotionResult>(result).six_bars.size();
  ASSERT_GT(listed, 0u);
  const std::optional<Picture> picture = TaskPicture("tray", task, result, listed);
  ASSERT_TRUE(picture.has_value());
  ASSERT_EQ(picture->mechanisms.size(), listed);
  for (size_t m = 0; m < listed; ++m) {
    SCOPED_TRACE("six-bar " + std::to_string(m + 1));
    const std::string animation = RenderAnimation(*picture, m, true);
    EXPECT_NE(animation.find("frame0"), std::string::npos);
    EXPECT_EQ(Lower(animation).find("nan"), std::string::npos);
  }
  Image image;
  ASSERT_NO_FATAL_FAILURE(
      CheckAndRender("tray_animation", RenderAnimation(*picture, 0, false), &image));
}

TEST_F(PictureTest, SphericalPictureWithoutFourBarsIsTheBareSphere) {
  SphericalPicture picture;
  picture.center = Eigen::Vector3d(1.0, 2.0, 3.0);
  const std::string svg = RenderSphericalSvg(picture);
  Image image;
  ASSERT_NO_FATAL_FAILURE(CheckAndRender("bare", svg, &image));
  EXPECT_NE(svg.find("task: no four-bar listed"), std::string::npos);
  EXPECT_GT(CountColour(image, "#9aa7b5", 0, image.width), kMinColourPixels);
  const nlohmann::json json = nlohmann::json::parse(SphericalPictureToJson(picture));
  EXPECT_TRUE(json["mechanisms"].empty());
  EXPECT_EQ(json["heading"],
            "spherical motion about [1, 2, 3], orthographic view of the unit sphere");
  Task task;
  task.space = Space::kSpatial;
  SpatialMotionResult platform;
  platform.model = "spatial";
  EXPECT_FALSE(SphericalTaskPicture("", task, platform, 12));
  std::string why;
  EXPECT_TRUE(TaskPictureJson("", task, TaskResult(platform), 12, &why).empty());
  EXPECT_NE(why.find("spatial platform"), std::string::npos) << why;
}

}  // namespace
}  // namespace linkfit
