// SVG pictures of tasks and mechanisms (see picture.h).
//
// Every panel has its own view: a similarity from Sigma (y up) to the panel's plot area
// (SVG pixels, y down) chosen to fit the task poses, the path points and whatever of the
// mechanism lies within reach of them. Geometry is clipped against the view in Sigma before it
// is written, so no coordinate in the document is far outside the drawing, whatever the input;
// elements beyond the view get an arrow at the edge of the plot with their coordinates.
// Non-finite input points are skipped.
#include "apps/picture.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "fitting/spherical_motion.h"
#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"
#include "lib/path_motion.h"
#include "lib/six_bar.h"

namespace linkfit {
namespace {

using Vec = Eigen::Vector2d;

// Colours.
constexpr const char* kTaskXColour = "#d62728";         // task frame x-axis
constexpr const char* kTaskYColour = "#2ca02c";         // task frame y-axis
constexpr const char* kCouplerCurveColour = "#1f77b4";  // path of E's origin
constexpr const char* kCenterCurveColour = "#9467bd";   // center-point curves
constexpr const char* kCircleCurveColour = "#ff7f0e";   // circle-point curves
constexpr const char* kPathPointColour = "#c51b8a";     // path points
constexpr const char* kLinkColour = "#333333";          // cranks, pivots, ground
constexpr const char* kCouplerFill = "#bcbd22";         // coupler body
constexpr const char* kCouplerStroke = "#6b6b12";
constexpr const char* kBlockFill = "#d9d9d9";      // slider blocks
constexpr const char* kOffViewColour = "#8b0000";  // arrows to elements beyond the view
constexpr const char* kBoxColour = "#2e7d32";      // the constraints' pivot boxes
constexpr const char* kGridColour = "#ececec";
constexpr const char* kGridTextColour = "#9a9a9a";

// Layout, in SVG pixels.
constexpr double kGap = 10.0;  // between panels and around the document
constexpr double kPad = 10.0;  // inside a panel
constexpr double kDocTitleHeight = 30.0;
constexpr double kTitleLine = 18.0;  // panel title
constexpr double kLabelLine = 14.0;  // each label line
constexpr int kMaxLabelLines = 6;
constexpr double kLegendLine = 18.0;
constexpr double kLabelCharWidth = 6.3;  // average glyph width at 11 px
constexpr double kPlotPadding = 30.0;    // between the fitted region and the plot's edge
constexpr double kPivotRadius = 4.0;
constexpr double kBlockLength = 28.0, kBlockWidth = 14.0;

// Points farther than this (in any coordinate) are treated as invalid: their differences
// would overflow.
constexpr double kHuge = 1e150;
// Elements within this many characteristic lengths of the task region enlarge the view.
constexpr double kReach = 20.0;
constexpr double kAnimationPeriodSeconds = 4.0;
constexpr size_t kMaxAnimationFrames = 180;

bool Ok(double v) { return std::isfinite(v) && std::abs(v) < kHuge; }
bool Ok(const Vec& p) { return Ok(p.x()) && Ok(p.y()); }
bool Ok(const PlanarPose& pose) { return Ok(pose.origin_in_fixed) && Ok(pose.theta); }

std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  if (n < 0) return "";
  return std::string(buffer, std::min<size_t>(static_cast<size_t>(n), sizeof buffer - 1));
}

// A document coordinate: limited precision, never NaN or -0.
std::string Num(double v) {
  if (!std::isfinite(v) || std::abs(v) < 1e-9) return "0";
  return Format("%.5g", v);
}

// A coordinate of Sigma, as written in labels.
std::string Coord(double v) {
  if (!std::isfinite(v)) return "?";
  if (v == 0.0) return "0";
  return Format("%.4g", v);
}

std::string Point(const Vec& p) { return Num(p.x()) + "," + Num(p.y()); }

// Text for XML character data and attribute values: escapes markup characters, drops what XML
// 1.0 forbids (control characters, invalid UTF-8 become '?' or a space), cuts at `max_chars`
// code points with an ellipsis.
std::string Escape(const std::string& text, size_t max_chars = 400) {
  std::string out;
  size_t chars = 0, i = 0;
  while (i < text.size()) {
    if (chars >= max_chars) {
      out += "\xe2\x80\xa6";  // U+2026
      break;
    }
    const unsigned char c = static_cast<unsigned char>(text[i]);
    ++chars;
    if (c < 0x80) {
      ++i;
      switch (c) {
        case '&':
          out += "&amp;";
          break;
        case '<':
          out += "&lt;";
          break;
        case '>':
          out += "&gt;";
          break;
        case '"':
          out += "&quot;";
          break;
        case '\'':
          out += "&#39;";
          break;
        default:
          out += (c < 0x20 || c == 0x7f) ? ' ' : static_cast<char>(c);
      }
      continue;
    }
    // A multi-byte sequence: check its length, continuation bytes and code point.
    size_t length = 0;
    unsigned int code = 0;
    if ((c & 0xe0) == 0xc0) {
      length = 2;
      code = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      length = 3;
      code = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      length = 4;
      code = c & 0x07;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) {
      const unsigned char next = static_cast<unsigned char>(text[i + k]);
      valid = (next & 0xc0) == 0x80;
      code = (code << 6) | (next & 0x3f);
    }
    static const unsigned int kMinimum[5] = {0, 0, 0x80, 0x800, 0x10000};
    valid = valid && code >= kMinimum[length] && code <= 0x10ffff &&
            !(code >= 0xd800 && code <= 0xdfff) && code != 0xfffe && code != 0xffff;
    if (valid) {
      out.append(text, i, length);
      i += length;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

Vec SafeDirection(const Vec& d) {
  if (!Ok(d)) return Vec::UnitX();
  const double n = d.norm();
  if (!(n > 1e-300) || !std::isfinite(n)) return Vec::UnitX();
  return d / n;
}

Vec Perp(const Vec& v) { return Vec(-v.y(), v.x()); }

struct Box {
  double x0 = std::numeric_limits<double>::infinity();
  double y0 = std::numeric_limits<double>::infinity();
  double x1 = -std::numeric_limits<double>::infinity();
  double y1 = -std::numeric_limits<double>::infinity();

  bool Empty() const { return !(x0 <= x1 && y0 <= y1); }
  void Add(const Vec& p) {
    if (!Ok(p)) return;
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  double Width() const { return x1 - x0; }
  double Height() const { return y1 - y0; }
  Vec Center() const { return Vec(0.5 * (x0 + x1), 0.5 * (y0 + y1)); }
  Box Expanded(double margin) const {
    return Box{x0 - margin, y0 - margin, x1 + margin, y1 + margin};
  }
  bool Contains(const Vec& p) const {
    return Ok(p) && p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
  }
  double Distance(const Vec& p) const {
    const double dx = std::max({x0 - p.x(), 0.0, p.x() - x1});
    const double dy = std::max({y0 - p.y(), 0.0, p.y() - y1});
    return std::hypot(dx, dy);
  }
};

// Liang-Barsky: restricts [*t0, *t1] so that p + t d stays in `box`; false when nothing stays.
bool ClipParameter(const Box& box, const Vec& p, const Vec& d, double* t0, double* t1) {
  const double ps[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double qs[4] = {p.x() - box.x0, box.x1 - p.x(), p.y() - box.y0, box.y1 - p.y()};
  for (int k = 0; k < 4; ++k) {
    if (ps[k] == 0.0) {
      if (qs[k] < 0.0) return false;
      continue;
    }
    const double r = qs[k] / ps[k];
    if (ps[k] < 0.0) {
      if (r > *t1) return false;
      *t0 = std::max(*t0, r);
    } else {
      if (r < *t0) return false;
      *t1 = std::min(*t1, r);
    }
  }
  return *t0 <= *t1 && std::isfinite(*t0) && std::isfinite(*t1);
}

// Sutherland-Hodgman clipping of a polygon against a box.
std::vector<Vec> ClipPolygon(const std::vector<Vec>& polygon, const Box& box) {
  std::vector<Vec> current = polygon;
  for (int edge = 0; edge < 4 && !current.empty(); ++edge) {
    auto inside = [&](const Vec& p) {
      switch (edge) {
        case 0:
          return p.x() >= box.x0;
        case 1:
          return p.x() <= box.x1;
        case 2:
          return p.y() >= box.y0;
        default:
          return p.y() <= box.y1;
      }
    };
    auto cross = [&](const Vec& a, const Vec& b) {
      double t = 0.0;
      switch (edge) {
        case 0:
          t = (box.x0 - a.x()) / (b.x() - a.x());
          break;
        case 1:
          t = (box.x1 - a.x()) / (b.x() - a.x());
          break;
        case 2:
          t = (box.y0 - a.y()) / (b.y() - a.y());
          break;
        default:
          t = (box.y1 - a.y()) / (b.y() - a.y());
      }
      return Vec(a + t * (b - a));
    };
    std::vector<Vec> next;
    for (size_t i = 0; i < current.size(); ++i) {
      const Vec& a = current[i];
      const Vec& b = current[(i + 1) % current.size()];
      if (inside(b)) {
        if (!inside(a)) next.push_back(cross(a, b));
        next.push_back(b);
      } else if (inside(a)) {
        next.push_back(cross(a, b));
      }
    }
    current.swap(next);
  }
  return current;
}

// Convex hull (Andrew's monotone chain), counter-clockwise; duplicates removed.
std::vector<Vec> ConvexHull(std::vector<Vec> points) {
  std::sort(points.begin(), points.end(), [](const Vec& a, const Vec& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  auto turn = [](const Vec& o, const Vec& a, const Vec& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Vec> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// "Nice" grid step near `raw`: 1, 2 or 5 times a power of ten.
double NiceStep(double raw) {
  if (!(raw > 0.0) || !std::isfinite(raw)) return 0.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / power;
  return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * power;
}

// The map from Sigma to a plot area of the document.
struct View {
  Box world;           // the part of Sigma shown; exactly fills the plot area
  double scale = 1.0;  // pixels per length unit
  double left = 0.0, top = 0.0, width = 1.0, height = 1.0;  // plot area, in pixels
  Box clip;  // `world` with a few pixels of margin, for clipping geometry

  Vec Px(const Vec& p) const {
    return Vec(left + (p.x() - world.x0) * scale, top + (world.y1 - p.y()) * scale);
  }
  // A unit direction of Sigma in pixels (y flipped).
  static Vec PxDirection(const Vec& d) { return Vec(d.x(), -d.y()); }
  bool Shows(const Vec& p) const { return world.Contains(p); }
};

View FitView(const Box& box, double left, double top, double width, double height) {
  View view;
  view.left = left;
  view.top = top;
  view.width = width;
  view.height = height;
  double w = box.Width(), h = box.Height();
  const Vec center = box.Center();
  const double extent = std::max({w, h, 1e-9 * (1.0 + center.norm()), 1e-300});
  w = std::max(w, extent * 1e-3);
  h = std::max(h, extent * 1e-3);
  // Room at the edges for the symbols drawn around points (ground, blocks, labels).
  const double padding = std::min(kPlotPadding, 0.2 * std::min(width, height));
  view.scale = std::min((width - 2.0 * padding) / w, (height - 2.0 * padding) / h);
  const double half_w = 0.5 * width / view.scale, half_h = 0.5 * height / view.scale;
  view.world =
      Box{center.x() - half_w, center.y() - half_h, center.x() + half_w, center.y() + half_h};
  view.clip = view.world.Expanded(3.0 / view.scale);
  return view;
}

// The characteristic length used for the sizes of marks and the reach of the view.
double MarkLength(const Picture& picture) {
  if (Ok(picture.length) && picture.length > 0.0) return picture.length;
  std::vector<PlanarPose> poses;
  for (const PlanarPose& pose : picture.task_poses) {
    if (Ok(pose.origin_in_fixed)) poses.push_back(pose);
  }
  for (const Vec& p : picture.path_points) {
    if (Ok(p)) poses.emplace_back(p.x(), p.y(), 0.0);
  }
  const double length = CharacteristicLength(poses);
  return Ok(length) && length > 0.0 ? length : 1.0;
}

// The coupler curve of a mechanism: given, or the origins of its cycle.
std::vector<Vec> CouplerCurve(const PictureMechanism& mechanism) {
  if (!mechanism.coupler_curve.empty()) return mechanism.coupler_curve;
  std::vector<Vec> curve;
  for (const PlanarPose& pose : mechanism.cycle) curve.push_back(pose.origin_in_fixed);
  return curve;
}

bool HasMovingPivot(const PlanarDyad& dyad) { return dyad.type != DyadType::kRP; }
bool HasFixedPivot(const PlanarDyad& dyad) { return dyad.type != DyadType::kPR; }

// The region of Sigma a panel shows: the task (poses, path points), and the elements of the
// mechanism and the curves within reach of it, with a margin.
Box PanelBox(const Picture& picture, const PictureMechanism* mechanism, double length,
             bool with_cycle) {
  Box core;
  for (const PlanarPose& pose : picture.task_poses) core.Add(pose.origin_in_fixed);
  for (const Vec& p : picture.path_points) core.Add(p);
  if (core.Empty() && mechanism != nullptr) {
    core.Add(mechanism->first_pose.origin_in_fixed);
    for (const Vec& p : CouplerCurve(*mechanism)) {
      if (core.Empty()) core.Add(p);
    }
  }
  if (core.Empty()) core.Add(Vec::Zero());
  const double size = std::max(core.Width(), core.Height());
  const double reach = kReach * std::max(length, 0.5 * size);
  Box box = core;
  auto consider = [&](const Vec& p, double within) {
    if (Ok(p) && core.Distance(p) <= within) box.Add(p);
  };
  if (picture.fixed_pivots_box) {
    consider(picture.fixed_pivots_box->min, reach);
    consider(picture.fixed_pivots_box->max, reach);
  }
  if (mechanism != nullptr && mechanism->joints) {
    for (const Vec& p : mechanism->joints->at_first) consider(p, reach);
    if (with_cycle) {
      for (const std::vector<Vec>& places : mechanism->joints->cycle) {
        for (const Vec& p : places) consider(p, reach);
      }
    }
    consider(mechanism->first_pose.origin_in_fixed, reach);
    for (const Vec& p : CouplerCurve(*mechanism)) consider(p, reach);
  } else if (mechanism != nullptr) {
    std::vector<PlanarPose> poses = {mechanism->first_pose};
    if (with_cycle) poses.insert(poses.end(), mechanism->cycle.begin(), mechanism->cycle.end());
    for (const PlanarDyad* dyad : {&mechanism->input, &mechanism->output}) {
      if (HasFixedPivot(*dyad)) consider(dyad->fixed_pivot, reach);
    }
    for (const PlanarPose& pose : poses) {
      if (!Ok(pose)) continue;
      consider(pose.origin_in_fixed, reach);
      for (const PlanarDyad* dyad : {&mechanism->input, &mechanism->output}) {
        if (HasMovingPivot(*dyad)) consider(pose.ToFixed(dyad->moving_pivot), reach);
      }
    }
    for (const Vec& p : CouplerCurve(*mechanism)) consider(p, reach);
  }
  // The Burmester curves run off to infinity: only their part near the task counts.
  for (const auto* curves : {&picture.center_point_curves, &picture.circle_point_curves}) {
    for (const auto& curve : *curves) {
      for (const Vec& p : curve) consider(p, 1.5 * length);
    }
  }
  const double extent = std::max(box.Width(), box.Height());
  return box.Expanded(std::max(0.03 * extent, 0.15 * length));
}

// Writes SVG elements into a string.
class Svg {
 public:
  std::string& text() { return text_; }
  void Raw(const std::string& s) { text_ += s; }

  void Line(const Vec& a, const Vec& b, const std::string& style) {
    text_ += "<line x1=\"" + Num(a.x()) + "\" y1=\"" + Num(a.y()) + "\" x2=\"" + Num(b.x()) +
             "\" y2=\"" + Num(b.y()) + "\" " + style + "/>\n";
  }
  void Circle(const Vec& c, double r, const std::string& style) {
    text_ += "<circle cx=\"" + Num(c.x()) + "\" cy=\"" + Num(c.y()) + "\" r=\"" + Num(r) + "\" " +
             style + "/>\n";
  }
  void Polygon(const std::vector<Vec>& points, const std::string& style) {
    if (points.empty()) return;
    text_ += "<polygon points=\"";
    for (size_t i = 0; i < points.size(); ++i) text_ += (i ? " " : "") + Point(points[i]);
    text_ += "\" " + style + "/>\n";
  }
  void Path(const std::string& d, const std::string& style) {
    if (!d.empty()) text_ += "<path d=\"" + d + "\" " + style + "/>\n";
  }
  void Rect(double x, double y, double w, double h, const std::string& style) {
    text_ += "<rect x=\"" + Num(x) + "\" y=\"" + Num(y) + "\" width=\"" + Num(w) + "\" height=\"" +
             Num(h) + "\" " + style + "/>\n";
  }
  // `text` is escaped here.
  void Text(const Vec& at, const std::string& text, const std::string& style,
            size_t max_chars = 400) {
    text_ += "<text x=\"" + Num(at.x()) + "\" y=\"" + Num(at.y()) + "\" " + style + ">" +
             Escape(text, max_chars) + "</text>\n";
  }

 private:
  std::string text_;
};

// Text with a white halo, legible over lines.
std::string Halo(const std::string& fill, double size, const std::string& extra = "") {
  return "font-size=\"" + Num(size) + "\" fill=\"" + fill +
         "\" stroke=\"#ffffff\" stroke-width=\"3\" stroke-linejoin=\"round\" "
         "paint-order=\"stroke\"" +
         (extra.empty() ? "" : " " + extra);
}

// Path data ("M x y L x y ...") of a polyline of Sigma clipped to the view; breaks at invalid
// points.
std::string PolylinePath(const View& view, const std::vector<Vec>& points, bool closed = false) {
  std::string d;
  bool open = false;
  Vec last_px(0.0, 0.0);
  const size_t n = points.size();
  const size_t segments = closed && n > 2 ? n : (n > 0 ? n - 1 : 0);
  for (size_t i = 0; i < segments; ++i) {
    const Vec& a = points[i];
    const Vec& b = points[(i + 1) % n];
    if (!Ok(a) || !Ok(b)) {
      open = false;
      continue;
    }
    double t0 = 0.0, t1 = 1.0;
    if (!ClipParameter(view.clip, a, b - a, &t0, &t1)) {
      open = false;
      continue;
    }
    const Vec pa = view.Px(a + t0 * (b - a)), pb = view.Px(a + t1 * (b - a));
    if (!open || t0 > 0.0 || (pa - last_px).norm() > 0.5) {
      d += (d.empty() ? "M" : " M") + Num(pa.x()) + " " + Num(pa.y());
      last_px = pa;
    }
    if ((pb - last_px).norm() >= 0.3 || t1 < 1.0 || i + 1 == segments) {
      d += " L" + Num(pb.x()) + " " + Num(pb.y());
      last_px = pb;
    }
    open = t1 >= 1.0;
  }
  return d;
}

// A segment of Sigma clipped to the view, as a line element.
void ClippedSegment(Svg* svg, const View& view, const Vec& a, const Vec& b,
                    const std::string& style) {
  if (!Ok(a) || !Ok(b)) return;
  double t0 = 0.0, t1 = 1.0;
  if (!ClipParameter(view.clip, a, b - a, &t0, &t1)) return;
  svg->Line(view.Px(a + t0 * (b - a)), view.Px(a + t1 * (b - a)), style);
}

// An infinite line of Sigma clipped to the view; false when it misses the view.
bool ClippedLine(Svg* svg, const View& view, const Vec& point, const Vec& direction,
                 const std::string& style) {
  if (!Ok(point)) return false;
  const Vec d = SafeDirection(direction);
  double t0 = -std::numeric_limits<double>::infinity();
  double t1 = std::numeric_limits<double>::infinity();
  if (!ClipParameter(view.clip, point, d, &t0, &t1)) return false;
  svg->Line(view.Px(point + t0 * d), view.Px(point + t1 * d), style);
  return true;
}

// An arrow of `length` pixels from `from` in pixel direction `dir` (unit), with a head.
void Arrow(Svg* svg, const Vec& from, const Vec& dir, double length, const char* colour,
           double width) {
  const Vec tip = from + length * dir, n = Perp(dir);
  const double head = std::min(7.0, 0.45 * length);
  svg->Line(from, tip - 0.8 * head * dir,
            "stroke=\"" + std::string(colour) + "\" stroke-width=\"" + Num(width) + "\"");
  svg->Polygon({tip, tip - head * dir + 0.5 * head * n, tip - head * dir - 0.5 * head * n},
               "fill=\"" + std::string(colour) + "\"");
}

// Ground symbol (triangle on a hatched base) with the pivot circle, apex at `p` (pixels).
void Ground(Svg* svg, const Vec& p) {
  const Vec base(0.0, 12.0);
  svg->Polygon({p, p + base + Vec(-7.0, 0.0), p + base + Vec(7.0, 0.0)},
               "fill=\"#ffffff\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.5\"");
  std::string d = "M" + Num(p.x() - 11.0) + " " + Num(p.y() + 12.0) + " L" + Num(p.x() + 11.0) +
                  " " + Num(p.y() + 12.0);
  for (int k = 0; k < 5; ++k) {
    const double x = p.x() - 9.0 + 5.0 * k;
    d += " M" + Num(x) + " " + Num(p.y() + 12.0) + " L" + Num(x - 4.0) + " " + Num(p.y() + 17.0);
  }
  svg->Path(d, "fill=\"none\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.2\"");
  svg->Circle(p, kPivotRadius,
              "fill=\"#ffffff\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.5\"");
}

// A slider block centred at `p` (pixels) along pixel direction `dir`.
void Block(Svg* svg, const Vec& p, const Vec& dir) {
  const Vec u = 0.5 * kBlockLength * dir, v = 0.5 * kBlockWidth * Perp(dir);
  svg->Polygon({p - u - v, p + u - v, p + u + v, p - u + v}, "fill=\"" + std::string(kBlockFill) +
                                                                 "\" stroke=\"" + kLinkColour +
                                                                 "\" stroke-width=\"1.5\"");
}

const char* DyadName(int which) { return which == 0 ? "A" : "B"; }

// The parts of the mechanism that move, at coupler pose `pose`: cranks, the coupler body,
// lines fixed in E (RP), slider blocks, moving pivots, E's origin.
void DrawMovingParts(Svg* svg, const View& view, const PictureMechanism& mechanism,
                     const PlanarPose& pose, double length) {
  if (!Ok(pose)) return;
  const PlanarDyad* dyads[2] = {&mechanism.input, &mechanism.output};
  const Vec origin = pose.origin_in_fixed;
  std::vector<Vec> body = {origin};
  Vec moving[2];
  for (int k = 0; k < 2; ++k) {
    moving[k] = pose.ToFixed(dyads[k]->moving_pivot);
    if (HasMovingPivot(*dyads[k]) && Ok(moving[k])) body.push_back(moving[k]);
  }
  // Lines fixed in E (RP): the coupler reaches them where its points project onto them.
  struct Rod {
    Vec point, direction;
    double t0, t1;
  };
  std::vector<Rod> rods;
  const std::vector<Vec> coupler_points = body;
  for (int k = 0; k < 2; ++k) {
    if (dyads[k]->type != DyadType::kRP) continue;
    Rod rod;
    rod.point = pose.ToFixed(dyads[k]->line_point);
    rod.direction = SafeDirection(pose.DirectionToFixed(dyads[k]->line_direction));
    if (!Ok(rod.point)) continue;
    // Measure along the rod from the foot of E's origin (the line point may be far away).
    rod.point += (origin - rod.point).dot(rod.direction) * rod.direction;
    double lo = 0.0, hi = 0.0;
    for (const Vec& p : coupler_points) {
      const double t = (p - rod.point).dot(rod.direction);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
      body.push_back(rod.point + t * rod.direction);
    }
    if (Ok(dyads[k]->fixed_pivot)) {
      const double t = (dyads[k]->fixed_pivot - rod.point).dot(rod.direction);
      if (Ok(t)) {
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
    }
    rod.t0 = lo - 0.6 * length;
    rod.t1 = hi + 0.6 * length;
    rods.push_back(rod);
  }
  const std::string link =
      "stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"3\" stroke-linecap=\"round\"";
  for (int k = 0; k < 2; ++k) {
    if (dyads[k]->type == DyadType::kRR) {
      ClippedSegment(svg, view, dyads[k]->fixed_pivot, moving[k], link);
    }
  }
  // The coupler body.
  std::vector<Vec> hull = ConvexHull(body);
  const std::string body_style = "fill=\"" + std::string(kCouplerFill) +
                                 "\" fill-opacity=\"0.35\" stroke=\"" + kCouplerStroke +
                                 "\" stroke-width=\"2\" stroke-linejoin=\"round\"";
  if (hull.size() >= 3) {
    std::vector<Vec> clipped = ClipPolygon(hull, view.clip);
    for (Vec& p : clipped) p = view.Px(p);
    svg->Polygon(clipped, body_style);
  } else if (hull.size() == 2) {
    ClippedSegment(svg, view, hull[0], hull[1],
                   "stroke=\"" + std::string(kCouplerStroke) + "\" stroke-width=\"4\"");
  }
  for (const Rod& rod : rods) {
    ClippedSegment(svg, view, rod.point + rod.t0 * rod.direction,
                   rod.point + rod.t1 * rod.direction,
                   "stroke=\"" + std::string(kCouplerStroke) +
                       "\" stroke-width=\"3\" stroke-linecap=\"round\"");
  }
  // Blocks: PR at the moving pivot along the slider line, RP at the fixed pivot along the rod.
  size_t rod_index = 0;
  for (int k = 0; k < 2; ++k) {
    if (dyads[k]->type == DyadType::kPR && view.Shows(moving[k])) {
      Block(svg, view.Px(moving[k]), View::PxDirection(SafeDirection(dyads[k]->line_direction)));
    } else if (dyads[k]->type == DyadType::kRP && rod_index < rods.size()) {
      const Rod& rod = rods[rod_index++];
      if (view.Shows(dyads[k]->fixed_pivot)) {
        Block(svg, view.Px(dyads[k]->fixed_pivot), View::PxDirection(rod.direction));
      }
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (HasMovingPivot(*dyads[k]) && view.Shows(moving[k])) {
      const Vec p = view.Px(moving[k]);
      svg->Circle(
          p, kPivotRadius,
          "fill=\"#ffffff\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.5\"");
      svg->Text(p + Vec(7.0, -6.0), DyadName(k), Halo(kLinkColour, 11.0));
    }
  }
  if (view.Shows(origin)) {
    svg->Circle(view.Px(origin), 3.0, "fill=\"" + std::string(kCouplerCurveColour) + "\"");
  }
}

// A linkage drawn by its joints (PictureMechanism::Joints) with them at `places` and E at `pose`:
// each binary link a bar, each body of three or more joints a plate (the task body with E's
// origin, in the coupler's colours), the joints as pins.
void DrawJointedParts(Svg* svg, const View& view, const PictureMechanism::Joints& joints,
                      const std::vector<Vec>& places, const PlanarPose& pose) {
  const std::string link =
      "stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"3\" stroke-linecap=\"round\"";
  for (size_t b = 1; b < joints.bodies.size(); ++b) {
    std::vector<Vec> body;
    for (const int j : joints.bodies[b]) {
      if (j >= 0 && static_cast<size_t>(j) < places.size() && Ok(places[j])) {
        body.push_back(places[j]);
      }
    }
    const bool task = static_cast<int>(b) == joints.task_body;
    if (task && Ok(pose)) body.push_back(pose.origin_in_fixed);
    const std::vector<Vec> hull = ConvexHull(body);
    if (hull.size() >= 3) {
      std::vector<Vec> clipped = ClipPolygon(hull, view.clip);
      for (Vec& p : clipped) p = view.Px(p);
      svg->Polygon(clipped, "fill=\"" + std::string(task ? kCouplerFill : "#9aa7b4") +
                                "\" fill-opacity=\"0.35\" stroke=\"" +
                                (task ? kCouplerStroke : kLinkColour) +
                                "\" stroke-width=\"2\" stroke-linejoin=\"round\"");
    } else if (hull.size() == 2) {
      ClippedSegment(
          svg, view, hull[0], hull[1],
          task ? "stroke=\"" + std::string(kCouplerStroke) + "\" stroke-width=\"4\"" : link);
    }
  }
  const std::vector<int> ground = joints.bodies.empty() ? std::vector<int>() : joints.bodies[0];
  // Each moving joint's name at the first of eight places around it whose box (about 6.5 px a
  // character, 11 px high) meets no name placed before and no other joint: joints a few pixels
  // apart (a new crank's pin beside the link's) keep their names apart.
  std::vector<Vec> pins;
  for (const Vec& place : places) {
    if (view.Shows(place)) pins.push_back(view.Px(place));
  }
  struct Box {
    double left, top, right, bottom;
  };
  std::vector<Box> placed;
  const auto name_box = [](const Vec& at, size_t characters) {
    return Box{at.x(), at.y() - 10.0, at.x() + 6.5 * static_cast<double>(characters), at.y() + 2.0};
  };
  const auto free = [&](const Box& box, const Vec& own) {
    for (const Box& other : placed) {
      if (box.left < other.right && other.left < box.right && box.top < other.bottom &&
          other.top < box.bottom) {
        return false;
      }
    }
    for (const Vec& pin : pins) {
      if ((pin - own).norm() < 1e-9) continue;
      if (pin.x() + kPivotRadius > box.left && pin.x() - kPivotRadius < box.right &&
          pin.y() + kPivotRadius > box.top && pin.y() - kPivotRadius < box.bottom) {
        return false;
      }
    }
    return true;
  };
  for (size_t j = 0; j < places.size(); ++j) {
    if (!view.Shows(places[j])) continue;
    const Vec p = view.Px(places[j]);
    svg->Circle(
        p, kPivotRadius,
        "fill=\"#ffffff\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.5\"");
    // The ground's joints are named with their symbols (DrawGround), the moving ones here.
    if (j < joints.names.size() &&
        std::find(ground.begin(), ground.end(), static_cast<int>(j)) == ground.end()) {
      const std::string& name = joints.names[j];
      const double width = 6.5 * static_cast<double>(name.size());
      const Vec offsets[] = {Vec(7.0, -6.0),           Vec(7.0, 14.0),
                             Vec(-7.0 - width, -6.0),  Vec(-7.0 - width, 14.0),
                             Vec(-0.5 * width, -10.0), Vec(-0.5 * width, 20.0),
                             Vec(10.0, 4.0),           Vec(-10.0 - width, 4.0)};
      Vec at = p + offsets[0];
      for (const Vec& offset : offsets) {
        if (free(name_box(p + offset, name.size()), p)) {
          at = p + offset;
          break;
        }
      }
      placed.push_back(name_box(at, name.size()));
      svg->Text(at, name, Halo(kLinkColour, 11.0));
    }
  }
  if (Ok(pose) && view.Shows(pose.origin_in_fixed)) {
    svg->Circle(view.Px(pose.origin_in_fixed), 3.0,
                "fill=\"" + std::string(kCouplerCurveColour) + "\"");
  }
}

// The moving parts at frame `frame` of the mechanism's cycle, or at its first pose (`frame` past
// the cycle).
void DrawMechanismAt(Svg* svg, const View& view, const PictureMechanism& mechanism, size_t frame,
                     double length) {
  const bool first = frame >= mechanism.cycle.size();
  const PlanarPose& pose = first ? mechanism.first_pose : mechanism.cycle[frame];
  if (mechanism.joints) {
    const PictureMechanism::Joints& joints = *mechanism.joints;
    DrawJointedParts(svg, view, joints,
                     first || frame >= joints.cycle.size() ? joints.at_first : joints.cycle[frame],
                     first || frame >= joints.cycle.size() ? mechanism.first_pose : pose);
    return;
  }
  DrawMovingParts(svg, view, mechanism, pose, length);
}

// The parts that stay: slider lines (under everything else of the mechanism).
void DrawFixedLines(Svg* svg, const View& view, const PictureMechanism& mechanism) {
  if (mechanism.joints) return;
  for (const PlanarDyad* dyad : {&mechanism.input, &mechanism.output}) {
    if (dyad->type == DyadType::kPR) {
      ClippedLine(svg, view, dyad->line_point, dyad->line_direction,
                  "stroke=\"#555555\" stroke-width=\"1.5\" stroke-dasharray=\"9 5\"");
    }
  }
}

// The parts that stay: ground symbols at the fixed pivots (over everything else).
void DrawGround(Svg* svg, const View& view, const PictureMechanism& mechanism) {
  if (mechanism.joints) {
    const PictureMechanism::Joints& joints = *mechanism.joints;
    for (const int j : joints.bodies.empty() ? std::vector<int>() : joints.bodies[0]) {
      if (j < 0 || static_cast<size_t>(j) >= joints.at_first.size()) continue;
      if (!view.Shows(joints.at_first[j])) continue;
      const Vec p = view.Px(joints.at_first[j]);
      Ground(svg, p);
      if (static_cast<size_t>(j) < joints.names.size()) {
        svg->Text(p + Vec(9.0, 4.0), joints.names[j], Halo(kLinkColour, 11.0));
      }
    }
    return;
  }
  const PlanarDyad* dyads[2] = {&mechanism.input, &mechanism.output};
  for (int k = 0; k < 2; ++k) {
    if (HasFixedPivot(*dyads[k]) && view.Shows(dyads[k]->fixed_pivot)) {
      const Vec p = view.Px(dyads[k]->fixed_pivot);
      Ground(svg, p);
      svg->Text(p + Vec(9.0, 4.0), std::string(DyadName(k)) + "0", Halo(kLinkColour, 11.0));
    }
  }
}

// Arrows at the edge of the plot towards elements beyond the view.
class OffViewMarkers {
 public:
  explicit OffViewMarkers(const View& view) : view_(view) {}

  void Mark(Svg* svg, const Vec& target, const std::string& name) {
    if (!Ok(target) || view_.Shows(target)) return;
    const Vec center = view_.world.Center();
    Vec d = target - center;
    const double big = std::max(std::abs(d.x()), std::abs(d.y()));
    if (!(big > 0.0)) return;
    d /= big;
    const Vec dir = SafeDirection(View::PxDirection(d));
    const Vec center_px = view_.Px(center);
    const double inset = 6.0;
    const double half_w = 0.5 * view_.width - inset, half_h = 0.5 * view_.height - inset;
    const double t = std::min(std::abs(dir.x()) > 1e-12 ? half_w / std::abs(dir.x()) : 1e300,
                              std::abs(dir.y()) > 1e-12 ? half_h / std::abs(dir.y()) : 1e300);
    const Vec tip = center_px + t * dir;
    Arrow(svg, tip - 22.0 * dir, dir, 22.0, kOffViewColour, 2.0);
    // The label, inside the plot next to the arrow's tail.
    Vec at = tip - 28.0 * dir;
    std::string anchor = "middle";
    if (dir.x() > 0.35) anchor = "end";
    if (dir.x() < -0.35) anchor = "start";
    at.y() += dir.y() > 0.35 ? -4.0 : dir.y() < -0.35 ? 12.0 : 4.0;
    const double step = dir.y() > 0.35 ? -13.0 : 13.0;
    for (bool moved = true; moved;) {
      moved = false;
      for (const Vec& placed : placed_) {
        if ((placed - at).norm() < 12.0) {
          at.y() += step;
          moved = true;
        }
      }
    }
    placed_.push_back(at);
    svg->Text(at, name + " (" + Coord(target.x()) + ", " + Coord(target.y()) + ")",
              Halo(kOffViewColour, 10.0, "text-anchor=\"" + anchor + "\""));
  }
  bool any() const { return !placed_.empty(); }

 private:
  const View& view_;
  std::vector<Vec> placed_;
};

// Which kinds of elements a document shows, for its legend.
struct Shown {
  bool task = false, coupler_curve = false, center_curves = false, circle_curves = false;
  bool path_points = false, mechanism = false, slider = false, off_view = false;
  bool fixed_box = false, moving_box = false;
  bool jointed = false;  // a linkage drawn by its joints (six-bars)
};

// The corners of a pivot box, mapped by `pose` (its frame's pose in Sigma).
std::vector<Vec> BoxCorners(const PlanarBox& box, const PlanarPose& pose) {
  return {pose.ToFixed(box.min), pose.ToFixed(Vec(box.max.x(), box.min.y())), pose.ToFixed(box.max),
          pose.ToFixed(Vec(box.min.x(), box.max.y()))};
}

// The style of a pivot box: a dashed outline, lightly filled; the fixed pivots' long dashes, the
// moving pivots' short ones.
std::string PivotBoxStyle(bool moving) {
  return "fill=\"" + std::string(kBoxColour) + "\" fill-opacity=\"0.06\" stroke=\"" + kBoxColour +
         "\" stroke-width=\"1.5\" stroke-dasharray=\"" + (moving ? "3 3" : "8 4") + "\"";
}

// A pivot box (PivotBoxStyle) through `corners` (in Sigma).
void DrawPivotBox(Svg* svg, const View& view, const std::vector<Vec>& corners, bool moving) {
  std::vector<Vec> pixels;
  for (const Vec& corner : corners) {
    if (!Ok(corner)) return;
    pixels.push_back(view.Px(corner));
  }
  svg->Polygon(pixels, PivotBoxStyle(moving));
}

// Light grid with values at the left and bottom edges; the frame Sigma when in view and
// `sigma_axes`.
void DrawGrid(Svg* svg, const View& view, bool sigma_axes) {
  const Box& w = view.world;
  const double step = NiceStep(std::max(w.Width(), w.Height()) / 7.0);
  if (!(step > 0.0)) return;
  const double kx0 = std::ceil(w.x0 / step), kx1 = std::floor(w.x1 / step);
  const double ky0 = std::ceil(w.y0 / step), ky1 = std::floor(w.y1 / step);
  if (!(kx1 - kx0 < 60.0 && ky1 - ky0 < 60.0)) return;
  std::string d;
  Svg text;
  const std::string grid_text = "font-size=\"9\" fill=\"" + std::string(kGridTextColour) + "\"";
  for (double k = kx0; k <= kx1; k += 1.0) {
    const double x = view.Px(Vec(k * step, 0.0)).x();
    d += " M" + Num(x) + " " + Num(view.top) + " V" + Num(view.top + view.height);
    if (x < view.left + 28.0) continue;  // the corner belongs to the y values
    text.Text(Vec(x + 2.0, view.top + view.height - 3.0), Format("%.6g", k * step + 0.0),
              grid_text);
  }
  for (double k = ky0; k <= ky1; k += 1.0) {
    const double y = view.Px(Vec(0.0, k * step)).y();
    d += " M" + Num(view.left) + " " + Num(y) + " H" + Num(view.left + view.width);
    if (y > view.top + view.height - 14.0 || y < view.top + 10.0) continue;
    text.Text(Vec(view.left + 2.0, y - 2.0), Format("%.6g", k * step + 0.0), grid_text);
  }
  svg->Path(d.substr(1), "fill=\"none\" stroke=\"" + std::string(kGridColour) + "\"");
  svg->Raw(text.text());
  if (sigma_axes && view.world.Expanded(-12.0 / view.scale).Contains(Vec::Zero())) {
    const Vec o = view.Px(Vec::Zero());
    Arrow(svg, o, Vec(1.0, 0.0), 22.0, "#b0b0b0", 1.2);
    Arrow(svg, o, Vec(0.0, -1.0), 22.0, "#b0b0b0", 1.2);
    svg->Text(o + Vec(-12.0, 12.0), "\xce\xa3", "font-size=\"10\" fill=\"#a0a0a0\"");
  }
}

// Task poses as small frames, numbered from 1; path points as numbered crosses.
void DrawTask(Svg* svg, const View& view, const Picture& picture, double length) {
  const double arrow = std::clamp(0.25 * length * view.scale, 14.0, 45.0);
  for (size_t i = 0; i < picture.task_poses.size(); ++i) {
    const PlanarPose& pose = picture.task_poses[i];
    if (!Ok(pose.origin_in_fixed) || !view.Shows(pose.origin_in_fixed)) continue;
    const Vec o = view.Px(pose.origin_in_fixed);
    Vec label_dir(-1.0, 1.0);
    if (Ok(pose.theta)) {
      const Vec x_dir = View::PxDirection(Vec(std::cos(pose.theta), std::sin(pose.theta)));
      const Vec y_dir = View::PxDirection(Vec(-std::sin(pose.theta), std::cos(pose.theta)));
      Arrow(svg, o, x_dir, arrow, kTaskXColour, 2.0);
      Arrow(svg, o, y_dir, arrow, kTaskYColour, 2.0);
      label_dir = -(x_dir + y_dir);
    }
    svg->Circle(o, 2.2, "fill=\"#222222\"");
    svg->Text(o + 11.0 * SafeDirection(label_dir) + Vec(0.0, 4.0), std::to_string(i + 1),
              Halo("#222222", 11.0, "font-weight=\"bold\" text-anchor=\"middle\""));
  }
  const std::string cross = "stroke=\"" + std::string(kPathPointColour) + "\" stroke-width=\"2\"";
  for (size_t i = 0; i < picture.path_points.size(); ++i) {
    const Vec& p = picture.path_points[i];
    if (!view.Shows(p)) continue;
    const Vec o = view.Px(p);
    svg->Line(o + Vec(-5.0, -5.0), o + Vec(5.0, 5.0), cross);
    svg->Line(o + Vec(-5.0, 5.0), o + Vec(5.0, -5.0), cross);
    svg->Text(o + Vec(7.0, 13.0), std::to_string(i + 1),
              Halo(kPathPointColour, 11.0, "font-weight=\"bold\""));
  }
}

void DrawCurves(Svg* svg, const View& view, const std::vector<std::vector<Vec>>& curves,
                const char* colour, const std::string& dash) {
  for (const auto& curve : curves) {
    svg->Path(PolylinePath(view, curve),
              "fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"1.6\"" + dash);
  }
}

// Everything of a panel inside its plot area except the moving parts of the mechanism; the
// moving parts are drawn by `moving` between the slider lines and the ground symbols.
template <typename MovingParts>
void DrawPlot(Svg* svg, const View& view, const Picture& picture, const PictureMechanism* mechanism,
              double length, int clip_id, Shown* shown, MovingParts moving) {
  const std::string clip = "clip" + std::to_string(clip_id);
  svg->Raw("<clipPath id=\"" + clip + "\"><rect x=\"" + Num(view.left) + "\" y=\"" + Num(view.top) +
           "\" width=\"" + Num(view.width) + "\" height=\"" + Num(view.height) +
           "\"/></clipPath>\n");
  svg->Rect(view.left, view.top, view.width, view.height, "fill=\"#ffffff\" stroke=\"#d0d0d0\"");
  svg->Raw("<g clip-path=\"url(#" + clip + ")\">\n");
  // The axes of Sigma, unless a ground symbol sits on its origin.
  bool sigma_axes = true;
  if (mechanism != nullptr && mechanism->joints) {
    for (const Vec& p : mechanism->joints->at_first) {
      if (Ok(p) && p.norm() * view.scale < 30.0) sigma_axes = false;
    }
  } else if (mechanism != nullptr) {
    for (const PlanarDyad* dyad : {&mechanism->input, &mechanism->output}) {
      if (HasFixedPivot(*dyad) && Ok(dyad->fixed_pivot) &&
          dyad->fixed_pivot.norm() * view.scale < 30.0) {
        sigma_axes = false;
      }
    }
  }
  DrawGrid(svg, view, sigma_axes);
  if (picture.fixed_pivots_box) {
    DrawPivotBox(svg, view, BoxCorners(*picture.fixed_pivots_box, PlanarPose()), false);
    shown->fixed_box = true;
  }
  if (picture.moving_pivots_box && mechanism != nullptr && Ok(mechanism->first_pose)) {
    DrawPivotBox(svg, view, BoxCorners(*picture.moving_pivots_box, mechanism->first_pose), true);
    shown->moving_box = true;
  }
  DrawCurves(svg, view, picture.center_point_curves, kCenterCurveColour, "");
  DrawCurves(svg, view, picture.circle_point_curves, kCircleCurveColour,
             " stroke-dasharray=\"6 3\"");
  shown->center_curves |= !picture.center_point_curves.empty();
  shown->circle_curves |= !picture.circle_point_curves.empty();
  if (mechanism != nullptr) {
    const std::vector<Vec> curve = CouplerCurve(*mechanism);
    svg->Path(PolylinePath(view, curve), "fill=\"none\" stroke=\"" +
                                             std::string(kCouplerCurveColour) +
                                             "\" stroke-width=\"2\" stroke-linejoin=\"round\"");
    shown->coupler_curve |= curve.size() > 1;
  }
  DrawTask(svg, view, picture, length);
  shown->task |= !picture.task_poses.empty();
  shown->path_points |= !picture.path_points.empty();
  if (mechanism != nullptr) {
    shown->mechanism = true;
    shown->jointed |= mechanism->joints.has_value();
    for (const PlanarDyad* dyad : {&mechanism->input, &mechanism->output}) {
      shown->slider |= !mechanism->joints && dyad->type != DyadType::kRR;
    }
    DrawFixedLines(svg, view, *mechanism);
    moving(svg);
    DrawGround(svg, view, *mechanism);
  } else {
    moving(svg);
  }
  svg->Raw("</g>\n");
  // Elements beyond the view.
  if (mechanism != nullptr && mechanism->joints) {
    OffViewMarkers markers(view);
    const PictureMechanism::Joints& joints = *mechanism->joints;
    for (size_t j = 0; j < joints.at_first.size(); ++j) {
      markers.Mark(svg, joints.at_first[j], j < joints.names.size() ? joints.names[j] : "");
    }
    if (Ok(mechanism->first_pose)) markers.Mark(svg, mechanism->first_pose.origin_in_fixed, "E");
  } else if (mechanism != nullptr) {
    OffViewMarkers markers(view);
    const PlanarDyad* dyads[2] = {&mechanism->input, &mechanism->output};
    for (int k = 0; k < 2; ++k) {
      if (HasFixedPivot(*dyads[k])) {
        markers.Mark(svg, dyads[k]->fixed_pivot, std::string(DyadName(k)) + "0");
      }
    }
    if (Ok(mechanism->first_pose)) {
      for (int k = 0; k < 2; ++k) {
        if (HasMovingPivot(*dyads[k])) {
          markers.Mark(svg, mechanism->first_pose.ToFixed(dyads[k]->moving_pivot), DyadName(k));
        }
      }
      markers.Mark(svg, mechanism->first_pose.origin_in_fixed, "E");
    }
    for (int k = 0; k < 2; ++k) {
      if (dyads[k]->type != DyadType::kPR || !Ok(dyads[k]->line_point)) continue;
      const Vec d = SafeDirection(dyads[k]->line_direction);
      double t0 = -std::numeric_limits<double>::infinity();
      double t1 = std::numeric_limits<double>::infinity();
      if (!ClipParameter(view.world, dyads[k]->line_point, d, &t0, &t1)) {
        const Vec c = view.world.Center();
        const Vec foot = dyads[k]->line_point + (c - dyads[k]->line_point).dot(d) * d;
        markers.Mark(svg, foot, std::string("slider line ") + DyadName(k));
      }
    }
    shown->off_view |= markers.any();
  }
}

// The legend: one line (wrapped when needed) of symbols and names; returns its height.
double DrawLegend(Svg* svg, const Picture& picture, const Shown& shown, double left, double top,
                  double width) {
  struct Item {
    std::string name;
    int symbol;
  };
  std::vector<Item> items;
  if (shown.task) items.push_back({"task pose n (x, y axes)", 0});
  if (shown.path_points) items.push_back({"path point n", 1});
  if (shown.coupler_curve) items.push_back({picture.coupler_curve_label, 2});
  if (shown.center_curves) items.push_back({"center-point curve", 3});
  if (shown.circle_curves) items.push_back({"circle-point curve", 4});
  if (shown.jointed) {
    items.push_back({"fixed pivot (G the chain's)", 5});
    items.push_back({"joint", 6});
    items.push_back({"task body", 7});
  } else if (shown.mechanism) {
    items.push_back({"fixed pivot A0, B0", 5});
    items.push_back({"moving pivot A, B", 6});
    items.push_back({"coupler", 7});
  }
  if (shown.slider) items.push_back({"slider", 8});
  if (shown.fixed_box) items.push_back({"fixed-pivot box", 10});
  if (shown.moving_box) items.push_back({"moving-pivot box (in E)", 11});
  if (shown.off_view) items.push_back({"beyond the view", 9});
  if (items.empty()) items.push_back({"empty task", -1});
  double x = left, y = top + 12.0;
  const double x_end = left + width;
  for (const Item& item : items) {
    const double item_width = 34.0 + kLabelCharWidth * static_cast<double>(item.name.size());
    if (x + item_width > x_end && x > left) {
      x = left;
      y += kLegendLine;
    }
    const Vec s(x + 12.0, y - 4.0);
    switch (item.symbol) {
      case 0:
        Arrow(svg, s + Vec(-8.0, 5.0), Vec(1.0, 0.0), 18.0, kTaskXColour, 2.0);
        Arrow(svg, s + Vec(-8.0, 5.0), Vec(0.0, -1.0), 12.0, kTaskYColour, 2.0);
        break;
      case 1:
        svg->Line(s + Vec(-5.0, -5.0), s + Vec(5.0, 5.0),
                  "stroke=\"" + std::string(kPathPointColour) + "\" stroke-width=\"2\"");
        svg->Line(s + Vec(-5.0, 5.0), s + Vec(5.0, -5.0),
                  "stroke=\"" + std::string(kPathPointColour) + "\" stroke-width=\"2\"");
        break;
      case 2:
      case 3:
      case 4: {
        const char* colour = item.symbol == 2   ? kCouplerCurveColour
                             : item.symbol == 3 ? kCenterCurveColour
                                                : kCircleCurveColour;
        svg->Line(s + Vec(-10.0, 0.0), s + Vec(10.0, 0.0),
                  "stroke=\"" + std::string(colour) + "\" stroke-width=\"2\"" +
                      (item.symbol == 4 ? " stroke-dasharray=\"6 3\"" : ""));
        break;
      }
      case 5:
        Ground(svg, s + Vec(0.0, -6.0));
        break;
      case 6:
        svg->Circle(
            s, kPivotRadius,
            "fill=\"#ffffff\" stroke=\"" + std::string(kLinkColour) + "\" stroke-width=\"1.5\"");
        break;
      case 7:
        svg->Polygon({s + Vec(-10.0, 5.0), s + Vec(10.0, 5.0), s + Vec(2.0, -6.0)},
                     "fill=\"" + std::string(kCouplerFill) + "\" fill-opacity=\"0.35\" stroke=\"" +
                         kCouplerStroke + "\" stroke-width=\"1.5\"");
        break;
      case 8:
        svg->Line(s + Vec(-12.0, 0.0), s + Vec(12.0, 0.0),
                  "stroke=\"#555555\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"");
        svg->Rect(s.x() - 7.0, s.y() - 5.0, 14.0, 10.0,
                  "fill=\"" + std::string(kBlockFill) + "\" stroke=\"" + kLinkColour + "\"");
        break;
      case 9:
        Arrow(svg, s + Vec(-10.0, 0.0), Vec(1.0, 0.0), 20.0, kOffViewColour, 2.0);
        break;
      case 10:
      case 11:
        svg->Polygon(
            {s + Vec(-10.0, -6.0), s + Vec(10.0, -6.0), s + Vec(10.0, 6.0), s + Vec(-10.0, 6.0)},
            PivotBoxStyle(item.symbol == 11));
        break;
      default:
        break;
    }
    svg->Text(Vec(x + 28.0, y), item.name, "font-size=\"11\" fill=\"#333333\"");
    x += item_width;
  }
  return y - top + 8.0;
}

std::string SvgOpen(double width, double height, bool xml_declaration, const std::string& id) {
  std::string s = xml_declaration ? "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" : "";
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\"" +
       (id.empty() ? std::string() : " id=\"" + id + "\"") + " width=\"" + Num(width) +
       "\" height=\"" + Num(height) + "\" viewBox=\"0 0 " + Num(width) + " " + Num(height) +
       "\" font-family=\"DejaVu Sans, Verdana, Arial, sans-serif\">\n";
  return s;
}

// Title and label lines at the top of a panel; returns nothing, the caller reserves the space.
void DrawPanelHeader(Svg* svg, double left, double top, double width, const std::string& title,
                     const std::vector<std::string>& labels, int label_lines) {
  const size_t title_chars = static_cast<size_t>(std::max(8.0, width / 7.6));
  const size_t label_chars = static_cast<size_t>(std::max(8.0, width / kLabelCharWidth));
  svg->Text(Vec(left, top + 14.0), title, "font-size=\"13\" font-weight=\"bold\" fill=\"#222222\"",
            title_chars);
  const size_t shown = std::min(labels.size(), static_cast<size_t>(label_lines));
  for (size_t i = 0; i < shown; ++i) {
    std::string text = labels[i];
    if (i + 1 == shown && labels.size() > shown) {
      text = "\xe2\x80\xa6 and " + std::to_string(labels.size() - shown + 1) + " more";
    }
    // Defects and broken bounds in red; "no defects" in green.
    const char* colour = text == "no defects" ? "#2e7d32" : "#a0302a";
    svg->Text(Vec(left, top + kTitleLine + kLabelLine * static_cast<double>(i + 1) - 2.0), text,
              std::string("font-size=\"11\" fill=\"") + colour + "\"", label_chars);
  }
}

// Frames of a cycle to animate: all of them, or an evenly spaced subset.
std::vector<size_t> AnimationFrames(size_t count) {
  std::vector<size_t> frames;
  if (count <= kMaxAnimationFrames) {
    for (size_t i = 0; i < count; ++i) frames.push_back(i);
  } else {
    for (size_t i = 0; i < kMaxAnimationFrames; ++i)
      frames.push_back(i * count / kMaxAnimationFrames);
  }
  return frames;
}

// A six-bar's panel (lib/six_bar.h): drawn by its joints (the ground pivot G, the elbow, the
// wrist, each RR link's two) at the first pose and through its input's range from there
// (SixBarSweep: a whole turn, or the rocker's range there and back).
PictureMechanism SixBarPanel(const SixBarReport& report, size_t index, double length) {
  static const char* const kBodies[] = {"ground",    "upper link", "forearm",
                                        "task body", "first link", "second link"};
  const SixBar& six_bar = report.six_bar;
  PictureMechanism mechanism;
  mechanism.title = std::to_string(index + 1) + ": " + SixBarTopologyName(six_bar.topology) +
                    ", driven by the " + kBodies[report.input];
  for (const std::string& defect : report.defects) mechanism.labels.push_back(defect + " defect");
  if (report.defects.empty()) mechanism.labels.push_back("no defects");
  for (const std::string& bound : report.violates) mechanism.labels.push_back("violates " + bound);
  mechanism.labels.push_back(Format("transmission angles >= %.0f, %.0f deg",
                                    report.transmission_min_deg[0],
                                    report.transmission_min_deg[1]));
  if (report.input_rotates_fully) mechanism.labels.push_back("the input turns fully");
  mechanism.first_pose = six_bar.reference_pose;
  // The joints: each on the body that hangs from it (its place is that body's point).
  struct Joint {
    int body;
    Vec point;
    const char* name;
  };
  const bool crank = six_bar.links[1].from_body == kSixBarFirstLink;
  const std::vector<Joint> joints = {
      {kSixBarUpperLink, six_bar.ground_pivot, "G"},
      {kSixBarForearm, six_bar.elbow, "elbow"},
      {kSixBarTaskBody, six_bar.wrist, "wrist"},
      {kSixBarFirstLink, six_bar.links[0].from_joint, "A0"},
      {kSixBarFirstLink, six_bar.links[0].to_joint, "A"},
      {kSixBarSecondLink, six_bar.links[1].from_joint, crank ? "B1" : "B0"},
      {kSixBarSecondLink, six_bar.links[1].to_joint, "B"}};
  PictureMechanism::Joints drawn;
  drawn.task_body = kSixBarTaskBody;
  for (const std::vector<int>& body : SixBarBodyJointIndices(six_bar)) drawn.bodies.push_back(body);
  for (const Joint& joint : joints) drawn.names.push_back(joint.name);
  const auto places = [&](const SixBarAngles& angles) {
    std::vector<Vec> at;
    for (const Joint& joint : joints) {
      at.push_back(SixBarBodyDisplacement(six_bar, angles, joint.body).ToFixed(joint.point));
    }
    return at;
  };
  drawn.at_first = places(SixBarAngles::Zero());
  std::vector<SixBarAngles> sweep =
      SixBarSweep(six_bar, SixBarAngles::Zero(), report.input, length);
  for (const SixBarAngles& angles : sweep) {
    mechanism.coupler_curve.push_back(SixBarTaskPose(six_bar, angles).origin_in_fixed);
  }
  // A rocker's range there and back, from the first pose (where the sweep has it: its turns
  // zero) on.
  if (!report.input_rotates_fully && sweep.size() > 2) {
    size_t first = 0;
    for (size_t k = 0; k < sweep.size(); ++k) {
      if (sweep[k].cwiseAbs().maxCoeff() < sweep[first].cwiseAbs().maxCoeff()) first = k;
    }
    std::vector<SixBarAngles> cycle(sweep.begin() + first, sweep.end());
    cycle.insert(cycle.end(), sweep.rbegin() + 1, sweep.rend());
    if (first > 1) cycle.insert(cycle.end(), sweep.begin() + 1, sweep.begin() + first);
    sweep = std::move(cycle);
  }
  const size_t stride = std::max<size_t>(1, sweep.size() / 120);
  for (size_t k = 0; k < sweep.size(); k += stride) {
    mechanism.cycle.push_back(SixBarTaskPose(six_bar, sweep[k]));
    drawn.cycle.push_back(places(sweep[k]));
  }
  mechanism.joints = std::move(drawn);
  return mechanism;
}

// The picture of a solved planar motion task: its poses, its mechanisms in ranked order (at
// most `max_panels`), and for four poses the Burmester curves.
Picture MakePicture(const std::string& title, const Task& task, const PlanarMotionResult& result,
                    size_t max_panels) {
  Picture picture;
  picture.title = title;
  picture.task_poses = task.planar_poses;
  picture.length = result.scale;
  picture.fixed_pivots_box = task.constraints.fixed_pivots_box;
  picture.moving_pivots_box = task.constraints.moving_pivots_box;
  for (const TimedPoint& point : task.points) picture.path_points.push_back(point.point_in_fixed);
  picture.center_point_curves = result.center_point_curves;
  if (!task.planar_poses.empty()) {
    // Circle points live in E: draw them where E is at the first pose.
    for (const std::vector<Eigen::Vector2d>& polyline : result.circle_point_curves) {
      std::vector<Eigen::Vector2d> in_fixed;
      for (const Eigen::Vector2d& point : polyline) {
        in_fixed.push_back(task.planar_poses.front().ToFixed(point));
      }
      picture.circle_point_curves.push_back(in_fixed);
    }
  }
  for (size_t m = 0; m < result.mechanisms.size() && m < max_panels; ++m) {
    const MechanismReport& report = result.mechanisms[m];
    PictureMechanism mechanism;
    mechanism.input = result.dyads[report.input_dyad].dyad;
    mechanism.output = result.dyads[report.output_dyad].dyad;
    mechanism.title = std::to_string(m + 1) + ": " + FourBarTypeName(report.type) +
                      (report.grashof.empty() ? "" : ", " + report.grashof) + ", dyads " +
                      std::to_string(report.input_dyad) + "+" + std::to_string(report.output_dyad);
    for (const std::string& defect : report.defects) mechanism.labels.push_back(defect + " defect");
    if (report.defects.empty()) mechanism.labels.push_back("no defects");
    for (const std::string& bound : report.violates)
      mechanism.labels.push_back("violates " + bound);
    if (report.transmission_min_deg) {
      char text[64];
      std::snprintf(text, sizeof(text), "transmission angle >= %.0f deg",
                    *report.transmission_min_deg);
      mechanism.labels.push_back(text);
    }
    // The circuit's coupler poses: traced here (the analysis behind the ranking does not).
    std::vector<PlanarPose> cycle = report.cycle;
    if (cycle.empty() && !task.planar_poses.empty()) {
      FourBarMotionOptions trace;
      trace.trace_cycle = true;
      cycle =
          AnalyzeFourBar(mechanism.input, mechanism.output, task.planar_poses, result.scale, trace)
              .cycle;
    }
    // The links at the first pose: the assembled configuration on the mechanism's circuit
    // nearest the first task pose.
    mechanism.first_pose = task.planar_poses.front();
    double nearest = std::numeric_limits<double>::infinity();
    for (const PlanarPose& pose : cycle) {
      const double error = PoseError(pose, task.planar_poses.front(), result.scale);
      if (error < nearest) {
        nearest = error;
        mechanism.first_pose = pose;
      }
    }
    for (const PlanarPose& pose : cycle) mechanism.coupler_curve.push_back(pose.origin_in_fixed);
    // About 120 frames for the animation.
    const size_t stride = std::max<size_t>(1, cycle.size() / 120);
    for (size_t k = 0; k < cycle.size(); k += stride) mechanism.cycle.push_back(cycle[k]);
    picture.mechanisms.push_back(std::move(mechanism));
  }
  for (size_t m = 0; m < result.six_bars.size() && m < max_panels; ++m) {
    picture.mechanisms.push_back(SixBarPanel(result.six_bars[m], m, result.scale));
  }
  return picture;
}

// The picture of a solved path task: its points, and its four-bars (at most `max_panels`) at
// the first point with the coupler point's curve. E is drawn with its origin at the coupler
// point, so that the coupler body and the traced curve are the coupler point's.
Picture MakePathPicture(const std::string& title, const Task& task, const PathResult& result,
                        size_t max_panels) {
  Picture picture;
  picture.title = title;
  picture.length = result.scale;
  picture.coupler_curve_label = "coupler curve (coupler point)";
  picture.fixed_pivots_box = task.constraints.fixed_pivots_box;
  for (const TimedPoint& point : task.points) picture.path_points.push_back(point.point_in_fixed);
  for (size_t m = 0; m < result.mechanisms.size() && m < max_panels; ++m) {
    const PathMechanismReport& report = result.mechanisms[m];
    const PathFourBar& design = report.design;
    // E' = E moved to the coupler point: p_E' = p_E - coupler point.
    const PlanarPose shift(design.coupler_point.x(), design.coupler_point.y(), 0.0);
    const auto to_shifted = [&](PlanarDyad dyad) {
      dyad.moving_pivot -= design.coupler_point;
      if (dyad.type == DyadType::kRP) dyad.line_point -= design.coupler_point;
      return dyad;
    };
    PictureMechanism mechanism;
    mechanism.input = to_shifted(design.input);
    mechanism.output = to_shifted(design.output);
    mechanism.first_pose = shift;
    mechanism.title = std::to_string(m + 1) + ": " + FourBarTypeName(report.type) +
                      (report.grashof.empty() ? "" : ", " + report.grashof);
    for (const std::string& defect : report.defects) mechanism.labels.push_back(defect + " defect");
    if (report.defects.empty()) mechanism.labels.push_back("no defects");
    for (const std::string& bound : report.violates)
      mechanism.labels.push_back("violates " + bound);
    char text[64];
    if (report.max_point_error) {
      std::snprintf(text, sizeof(text), "max point error %.3g", *report.max_point_error);
      mechanism.labels.push_back(text);
    }
    const std::vector<PlanarPose> cycle = CouplerCycle(design, result.scale);
    for (const PlanarPose& pose : cycle) {
      mechanism.coupler_curve.push_back(pose.ToFixed(design.coupler_point));
    }
    const size_t stride = std::max<size_t>(1, cycle.size() / 120);
    for (size_t k = 0; k < cycle.size(); k += stride) mechanism.cycle.push_back(cycle[k] * shift);
    picture.mechanisms.push_back(std::move(mechanism));
  }
  return picture;
}

// The planar view of a result: a planar result, or the planar synthesis of planar data in a
// spatial task (with the task's poses in the plane). Null for a spatial result.
const PlanarMotionResult* PlanarView(const TaskResult& result, const Task& task,
                                     Task* planar_task) {
  if (const auto* planar = std::get_if<PlanarMotionResult>(&result)) {
    *planar_task = task;
    return planar;
  }
  const auto* spatial_result = std::get_if<SpatialMotionResult>(&result);
  if (spatial_result == nullptr) return nullptr;
  const SpatialMotionResult& spatial = *spatial_result;
  if (!spatial.planar || !spatial.plane) return nullptr;
  *planar_task = task;
  planar_task->space = Space::kPlanar;
  planar_task->planar_poses = spatial.plane->poses;
  return &*spatial.planar;
}

// An orthographic view of the unit sphere about a spherical motion's centre: points of the sphere
// (unit vectors of Sigma) projected along `toward` (the viewer's direction) to
// (x . right, x . up), Sigma's z-axis up where it can be.
struct SphereView {
  Eigen::Vector3d toward = Eigen::Vector3d::UnitZ(), right = Eigen::Vector3d::UnitX(),
                  up = Eigen::Vector3d::UnitY();

  explicit SphereView(const Eigen::Vector3d& direction) {
    toward = direction.allFinite() && direction.norm() > 1e-9 ? direction.normalized()
                                                              : Eigen::Vector3d::UnitZ();
    Eigen::Vector3d z = Eigen::Vector3d::UnitZ() - toward.z() * toward;
    if (z.norm() < 1e-6) z = Eigen::Vector3d::UnitY() - toward.y() * toward;
    up = z.normalized();
    right = up.cross(toward);
  }
  Vec Project(const Eigen::Vector3d& x) const { return Vec(x.dot(right), x.dot(up)); }
  bool Front(const Eigen::Vector3d& x) const { return x.dot(toward) >= 0.0; }
};

// A piece of a polyline of the sphere as drawn: projected, on the near hemisphere (solid) or not
// (dashed).
struct SphereRun {
  bool front = true;
  std::vector<Vec> points;
};

// A polyline of the sphere in runs of segments on the near hemisphere (both ends near) and on the
// far one; a run starts where the last ended. Non-finite points break the polyline.
std::vector<SphereRun> SphereRuns(const SphereView& view,
                                  const std::vector<Eigen::Vector3d>& points) {
  std::vector<SphereRun> runs;
  bool open = false;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const Eigen::Vector3d& a = points[i];
    const Eigen::Vector3d& b = points[i + 1];
    if (!a.allFinite() || !b.allFinite()) {
      open = false;
      continue;
    }
    const bool front = view.Front(a) && view.Front(b);
    if (!open || runs.back().front != front) runs.push_back(SphereRun{front, {view.Project(a)}});
    runs.back().points.push_back(view.Project(b));
    open = true;
  }
  return runs;
}

// The great-circle arc from a to b (unit vectors), sampled.
std::vector<Eigen::Vector3d> GreatArc(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  constexpr int kSteps = 32;
  const double angle = DirectionAngle(a, b);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k <= kSteps; ++k) {
    const double t = static_cast<double>(k) / kSteps;
    if (angle < 1e-9) {
      points.push_back(a);
      continue;
    }
    points.push_back(((std::sin((1.0 - t) * angle) * a + std::sin(t * angle) * b) / std::sin(angle))
                         .normalized());
  }
  return points;
}

// The panel of one listed spherical four-bar (number `index` from 0): its title and labels, its
// view, the links at the first pose's nearer assembly, the coupler at every task pose and the
// crank pins' paths over the circuit (`cycle_steps` samples).
SphericalPanel MakeSphericalPanel(size_t index, const MechanismReport& mechanism,
                                  const SphericalFourBar& four_bar, const SphericalMotion& motion,
                                  int cycle_steps) {
  SphericalPanel panel;
  std::string defects;
  for (const std::string& defect : mechanism.defects) {
    defects += (defects.empty() ? "" : ", ") + defect;
  }
  panel.title = std::to_string(index + 1) + ": spherical 4R, " +
                (mechanism.grashof.empty() ? std::string("?") : mechanism.grashof);
  panel.labels.push_back(defects.empty() ? "no defect" : "defects: " + defects);
  if (mechanism.max_pose_error) {
    panel.labels.push_back("max pose error " + Format("%.3g", *mechanism.max_pose_error));
  }
  const Eigen::Vector3d& u1 = four_bar.input.fixed_axis;
  const Eigen::Vector3d& u2 = four_bar.output.fixed_axis;
  const Eigen::Vector3d& v1 = four_bar.input.moving_axis;
  const Eigen::Vector3d& v2 = four_bar.output.moving_axis;
  const Eigen::Matrix3d rotation0 =
      motion.rotations.empty() ? Eigen::Matrix3d::Identity() : motion.rotations[0];
  panel.toward = u1 + u2 + rotation0 * (v1 + v2);
  for (const Eigen::Matrix3d& rotation : motion.rotations) {
    panel.task_couplers.push_back(GreatArc(rotation * v1, rotation * v2));
  }
  const SphericalFourBarAnalysis analysis = AnalyzeSphericalFourBar(four_bar, motion, cycle_steps);
  for (const Eigen::Matrix3d& rotation : analysis.cycle) {
    panel.input_pin_path.push_back(rotation * v1);
    panel.output_pin_path.push_back(rotation * v2);
  }
  // The links at the first pose's assembly (the nearer one).
  Eigen::Matrix3d configurations[2];
  double input_angle = 0.0;
  const int count =
      motion.rotations.empty()
          ? 0
          : AssembleSphericalFourBarAt(four_bar, rotation0, 1e-9, configurations, &input_angle);
  Eigen::Matrix3d first = rotation0;
  if (count == 2) {
    first = motion.PoseError(configurations[1], first) < motion.PoseError(configurations[0], first)
                ? configurations[1]
                : configurations[0];
  }
  panel.fixed_axes[0] = u1;
  panel.fixed_axes[1] = u2;
  panel.pins[0] = first * v1;
  panel.pins[1] = first * v2;
  panel.ground = GreatArc(u1, u2);
  panel.input_link = GreatArc(u1, panel.pins[0]);
  panel.output_link = GreatArc(u2, panel.pins[1]);
  panel.coupler = GreatArc(panel.pins[0], panel.pins[1]);
  return panel;
}

// What a spherical picture's heading says after the task's title.
std::string SphericalHeading(const Eigen::Vector3d& c) {
  return "spherical motion about [" + Coord(c.x()) + ", " + Coord(c.y()) + ", " + Coord(c.z()) +
         "], orthographic view of the unit sphere";
}

// A panel's disk in the document: the view's plane (the unit sphere, y up) to pixels (y down).
struct Disk {
  Vec center = Vec::Zero();
  double radius = 1.0;
  Vec Px(const Vec& p) const { return center + radius * Vec(p.x(), -p.y()); }
};

// Draws a polyline of the sphere, solid on the near hemisphere and dashed on the far.
void SpherePolyline(Svg* svg, const SphereView& view, const Disk& disk,
                    const std::vector<Eigen::Vector3d>& points, const std::string& colour,
                    double width) {
  for (const SphereRun& run : SphereRuns(view, points)) {
    std::string d;
    for (const Vec& p : run.points) {
      const Vec px = disk.Px(p);
      d += (d.empty() ? "M" : " L") + Num(px.x()) + " " + Num(px.y());
    }
    svg->Path(d, "fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" +
                     Num(run.front ? width : 0.6 * width) +
                     "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"" +
                     (run.front ? "" : " stroke-dasharray=\"3,3\" opacity=\"0.6\""));
  }
}

// One spherical four-bar's panel drawing: the sphere, Sigma's axes, the task's coupler arcs
// (thin), the crank pins' paths over the circuit, and the links at the first pose.
void DrawSphericalPanel(Svg* svg, const Disk& disk, const SphericalPanel& panel) {
  const SphereView view(panel.toward);
  svg->Circle(disk.center, disk.radius, "fill=\"#f3f6fa\" stroke=\"#9aa7b5\" stroke-width=\"1\"");
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    const Vec axis = view.Project(Eigen::Vector3d::Unit(i));
    svg->Line(disk.center, disk.Px(0.25 * axis), "stroke=\"#9a9a9a\" stroke-width=\"1\"");
    svg->Text(disk.Px(0.3 * axis), names[i], "font-size=\"10\" fill=\"#9a9a9a\"");
  }
  for (const auto& arc : panel.task_couplers) {
    SpherePolyline(svg, view, disk, arc, kTaskXColour, 1.2);
  }
  SpherePolyline(svg, view, disk, panel.input_pin_path, kCouplerCurveColour, 1.0);
  SpherePolyline(svg, view, disk, panel.output_pin_path, kCenterCurveColour, 1.0);
  SpherePolyline(svg, view, disk, panel.ground, "#777777", 2.0);
  SpherePolyline(svg, view, disk, panel.input_link, kLinkColour, 3.0);
  SpherePolyline(svg, view, disk, panel.output_link, kLinkColour, 3.0);
  SpherePolyline(svg, view, disk, panel.coupler, kCouplerStroke, 4.0);
  for (const Eigen::Vector3d& pin : panel.pins) {
    svg->Circle(disk.Px(view.Project(pin)), kPivotRadius,
                std::string("fill=\"#ffffff\" stroke=\"") + kLinkColour +
                    "\" stroke-width=\"1.5\"" + (view.Front(pin) ? "" : " opacity=\"0.5\""));
  }
  for (const Eigen::Vector3d& pivot : panel.fixed_axes) {
    const Vec at = disk.Px(view.Project(pivot));
    svg->Polygon({at, at + Vec(-7.0, 11.0), at + Vec(7.0, 11.0)},
                 std::string("fill=\"") + kLinkColour + "\"" +
                     (view.Front(pivot) ? "" : " opacity=\"0.5\""));
  }
  svg->Text(disk.Px(view.Project(panel.fixed_axes[0])) + Vec(8.0, -6.0), "input",
            Halo(kLinkColour, 10.0));
  svg->Text(disk.Px(view.Project(panel.fixed_axes[1])) + Vec(8.0, -6.0), "output",
            Halo(kLinkColour, 10.0));
}

}  // namespace

std::string RenderSvg(const Picture& picture) {
  const double length = MarkLength(picture);
  const size_t panels = std::max<size_t>(1, picture.mechanisms.size());
  const size_t columns = panels == 1 ? 1 : (panels == 2 || panels == 4) ? 2 : 3;
  const size_t rows = (panels + columns - 1) / columns;
  const double plot_w = panels == 1 ? 640.0 : 440.0;
  const double plot_h = panels == 1 ? 480.0 : 360.0;
  size_t most_labels = 0;
  for (const PictureMechanism& m : picture.mechanisms)
    most_labels = std::max(most_labels, m.labels.size());
  const int label_lines = static_cast<int>(std::min<size_t>(most_labels, kMaxLabelLines));
  const double header = kTitleLine + kLabelLine * label_lines + 6.0;
  const double panel_w = plot_w + 2.0 * kPad;
  const double panel_h = kPad + header + plot_h + kPad;
  const double width = kGap + static_cast<double>(columns) * (panel_w + kGap);
  const double panels_bottom = kDocTitleHeight + static_cast<double>(rows) * (panel_h + kGap);

  Svg body;
  Shown shown;
  for (size_t i = 0; i < panels; ++i) {
    const PictureMechanism* mechanism =
        picture.mechanisms.empty() ? nullptr : &picture.mechanisms[i];
    const double left = kGap + static_cast<double>(i % columns) * (panel_w + kGap);
    const double top = kDocTitleHeight + static_cast<double>(i / columns) * (panel_h + kGap);
    body.Rect(left, top, panel_w, panel_h, "rx=\"4\" fill=\"#fafafa\" stroke=\"#c8c8c8\"");
    DrawPanelHeader(&body, left + kPad, top + kPad, plot_w,
                    mechanism ? mechanism->title : std::string("task"),
                    mechanism ? mechanism->labels : std::vector<std::string>(), label_lines);
    const View view = FitView(PanelBox(picture, mechanism, length, false), left + kPad,
                              top + kPad + header, plot_w, plot_h);
    DrawPlot(&body, view, picture, mechanism, length, static_cast<int>(i), &shown, [&](Svg* svg) {
      if (mechanism != nullptr) {
        DrawMechanismAt(svg, view, *mechanism, mechanism->cycle.size(), length);
      }
    });
  }
  Svg legend;
  const double legend_h =
      DrawLegend(&legend, picture, shown, kGap, panels_bottom, width - 2.0 * kGap);
  const double height = panels_bottom + legend_h + kGap;

  std::string out = SvgOpen(width, height, true, "");
  out += "<title>" + Escape(picture.title.empty() ? "linkfit" : picture.title) + "</title>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  Svg title;
  title.Text(Vec(kGap, 21.0), picture.title.empty() ? "linkfit" : picture.title,
             "font-size=\"16\" font-weight=\"bold\" fill=\"#111111\"",
             static_cast<size_t>(width / 9.0));
  out += title.text() + body.text() + legend.text() + "</svg>\n";
  return out;
}

std::string RenderAnimation(const Picture& picture, size_t index, bool html) {
  const double length = MarkLength(picture);
  const PictureMechanism* mechanism =
      index < picture.mechanisms.size() ? &picture.mechanisms[index] : nullptr;
  const double plot_w = 640.0, plot_h = 480.0;
  const double header = kTitleLine + kLabelLine + 6.0;
  const double panel_w = plot_w + 2.0 * kPad;
  const double panel_h = kPad + header + plot_h + kPad;
  const double width = panel_w + 2.0 * kGap;
  const double left = kGap, top = kDocTitleHeight;

  std::vector<size_t> frames;
  if (mechanism != nullptr) frames = AnimationFrames(mechanism->cycle.size());
  std::string note;
  if (mechanism == nullptr) {
    note = "no mechanism " + std::to_string(index + 1) + " to animate (" +
           std::to_string(picture.mechanisms.size()) + " in the picture)";
  } else if (frames.empty()) {
    note = "no cycle to animate: drawn at its first pose";
  } else {
    note = "cycle of " + std::to_string(mechanism->cycle.size()) + " coupler poses, " +
           Format("%g", kAnimationPeriodSeconds) + " s per turn" +
           (frames.size() < mechanism->cycle.size()
                ? " (" + std::to_string(frames.size()) + " frames shown)"
                : "");
  }

  Svg body;
  Shown shown;
  body.Rect(left, top, panel_w, panel_h, "rx=\"4\" fill=\"#fafafa\" stroke=\"#c8c8c8\"");
  DrawPanelHeader(&body, left + kPad, top + kPad, plot_w,
                  mechanism ? mechanism->title : std::string("task"), {note}, 1);
  const View view = FitView(PanelBox(picture, mechanism, length, true), left + kPad,
                            top + kPad + header, plot_w, plot_h);
  const std::string period = Format("%gs", kAnimationPeriodSeconds);
  DrawPlot(&body, view, picture, mechanism, length, 0, &shown, [&](Svg* svg) {
    if (mechanism == nullptr) return;
    if (frames.empty()) {
      DrawMechanismAt(svg, view, *mechanism, mechanism->cycle.size(), length);
      return;
    }
    const double n = static_cast<double>(frames.size());
    for (size_t k = 0; k < frames.size(); ++k) {
      // Frame 0 is visible without animation (static renderers show it).
      svg->Raw("<g class=\"frame\" id=\"frame" + std::to_string(k) + "\" visibility=\"" +
               (k == 0 ? "visible" : "hidden") + "\">\n");
      if (!html && frames.size() > 1) {
        const std::string begin = Format("%.6g", static_cast<double>(k) / n);
        const std::string end = Format("%.6g", static_cast<double>(k + 1) / n);
        std::string values, times;
        if (k == 0) {
          values = "visible;hidden";
          times = "0;" + end;
        } else if (k + 1 == frames.size()) {
          values = "hidden;visible";
          times = "0;" + begin;
        } else {
          values = "hidden;visible;hidden";
          times = "0;" + begin + ";" + end;
        }
        svg->Raw("<animate attributeName=\"visibility\" values=\"" + values + "\" keyTimes=\"" +
                 times + "\" calcMode=\"discrete\" dur=\"" + period +
                 "\" repeatCount=\"indefinite\"/>\n");
      }
      DrawMechanismAt(svg, view, *mechanism, frames[k], length);
      svg->Raw("</g>\n");
    }
  });
  Svg legend;
  const double panels_bottom = top + panel_h + kGap;
  const double legend_h =
      DrawLegend(&legend, picture, shown, kGap, panels_bottom, width - 2.0 * kGap);
  const double height = panels_bottom + legend_h + kGap;
  std::string doc_title = picture.title.empty() ? "linkfit" : picture.title;
  if (mechanism != nullptr && !mechanism->title.empty())
    doc_title += " \xe2\x80\x94 " + mechanism->title;

  std::string svg = SvgOpen(width, height, !html, html ? "drawing" : "");
  if (!html) svg += "<title>" + Escape(doc_title) + "</title>\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  Svg title;
  title.Text(Vec(kGap, 21.0), doc_title, "font-size=\"16\" font-weight=\"bold\" fill=\"#111111\"",
             static_cast<size_t>(width / 9.0));
  svg += title.text() + body.text() + legend.text() + "</svg>\n";
  if (!html) return svg;

  const std::string count = std::to_string(frames.size());
  const int interval_ms =
      frames.empty()
          ? 1000
          : std::max(10, static_cast<int>(std::lround(1000.0 * kAnimationPeriodSeconds /
                                                      static_cast<double>(frames.size()))));
  std::string page =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
      Escape(doc_title) +
      "</title>\n<style>\nbody { font-family: sans-serif; margin: 16px; color: #222; }\n"
      "#controls { margin: 8px 0; display: flex; gap: 10px; align-items: center; }\n"
      "#controls input { width: 320px; }\n</style>\n</head>\n<body>\n"
      "<div id=\"controls\">\n<button id=\"play\" type=\"button\">pause</button>\n"
      "<input id=\"step\" type=\"range\" min=\"0\" max=\"" +
      std::to_string(frames.empty() ? 0 : frames.size() - 1) +
      "\" value=\"0\" aria-label=\"frame\">\n<span id=\"counter\">" +
      (frames.empty() ? std::string("no frames") : "1 / " + count) + "</span>\n</div>\n";
  page += svg;
  page +=
      "<script>\n"
      "// Steps through the frames of the drawing: one <g class=\"frame\"> visible at a time.\n"
      "(function () {\n"
      "  var frames = document.querySelectorAll('#drawing g.frame');\n"
      "  var play = document.getElementById('play');\n"
      "  var step = document.getElementById('step');\n"
      "  var counter = document.getElementById('counter');\n"
      "  var current = 0, playing = true;\n"
      "  if (frames.length === 0) { play.disabled = true; step.disabled = true; return; }\n"
      "  function show(k) {\n"
      "    frames[current].setAttribute('visibility', 'hidden');\n"
      "    current = ((k % frames.length) + frames.length) % frames.length;\n"
      "    frames[current].setAttribute('visibility', 'visible');\n"
      "    step.value = current;\n"
      "    counter.textContent = (current + 1) + ' / ' + frames.length;\n"
      "  }\n"
      "  play.addEventListener('click', function () {\n"
      "    playing = !playing;\n"
      "    play.textContent = playing ? 'pause' : 'play';\n"
      "  });\n"
      "  step.addEventListener('input', function () {\n"
      "    playing = false;\n"
      "    play.textContent = 'play';\n"
      "    show(parseInt(step.value, 10));\n"
      "  });\n"
      "  setInterval(function () { if (playing) show(current + 1); }, " +
      std::to_string(interval_ms) +
      ");\n"
      "})();\n"
      "</script>\n</body>\n</html>\n";
  return page;
}

std::optional<Picture> TaskPicture(const std::string& title, const Task& task,
                                   const TaskResult& result, size_t max_panels, std::string* why) {
  if (const auto* path = std::get_if<PathResult>(&result)) {
    return MakePathPicture(title, task, *path, max_panels);
  }
  Task planar_task;
  const PlanarMotionResult* planar = PlanarView(result, task, &planar_task);
  if (planar == nullptr) {
    if (why != nullptr) {
      const auto* spatial = std::get_if<SpatialMotionResult>(&result);
      *why = std::holds_alternative<FunctionResult>(result)
                 ? "function generators are not drawn: pictures draw motion and path tasks"
             : spatial != nullptr && spatial->model == "spherical"
                 ? "a spherical result is drawn by --svg (an orthographic view of the sphere); "
                   "animations draw planar mechanisms"
                 : "pictures draw planar mechanisms; this task's result is a spatial platform";
    }
    return std::nullopt;
  }
  return MakePicture(title, planar_task, *planar, max_panels);
}

std::string PictureToJson(const Picture& picture) {
  using Json = nlohmann::json;
  const auto point = [](const Vec& p) { return Ok(p) ? Json({p.x(), p.y()}) : Json(nullptr); };
  const auto polyline = [&](const std::vector<Vec>& points) {
    Json list = Json::array();
    for (const Vec& p : points) {
      if (Ok(p)) list.push_back(point(p));
    }
    return list;
  };
  const auto pose = [](const PlanarPose& q) {
    return Json({q.origin_in_fixed.x(), q.origin_in_fixed.y(), q.theta});
  };
  const auto dyad = [&](const PlanarDyad& d) {
    Json object;
    object["type"] = d.type == DyadType::kRR ? "RR" : d.type == DyadType::kPR ? "PR" : "RP";
    object["fixed"] = point(d.fixed_pivot);
    object["moving"] = point(d.moving_pivot);
    object["line_point"] = point(d.line_point);
    object["line_direction"] = point(SafeDirection(d.line_direction));
    return object;
  };
  const double length = MarkLength(picture);
  Json root;
  root["kind"] = "planar";
  root["title"] = picture.title;
  root["length"] = length;
  root["coupler_curve_label"] = picture.coupler_curve_label;
  root["task_poses"] = Json::array();
  for (const PlanarPose& q : picture.task_poses) {
    if (Ok(q)) root["task_poses"].push_back(pose(q));
  }
  root["path_points"] = polyline(picture.path_points);
  for (const char* key : {"center_point_curves", "circle_point_curves"}) {
    const auto& curves = std::string(key) == "center_point_curves" ? picture.center_point_curves
                                                                   : picture.circle_point_curves;
    root[key] = Json::array();
    for (const auto& curve : curves) root[key].push_back(polyline(curve));
  }
  if (picture.fixed_pivots_box) {
    const PlanarBox& box = *picture.fixed_pivots_box;
    root["fixed_pivots_box"] = Json({box.min.x(), box.min.y(), box.max.x(), box.max.y()});
  }
  if (picture.moving_pivots_box) {
    const PlanarBox& box = *picture.moving_pivots_box;
    root["moving_pivots_box"] = Json({box.min.x(), box.min.y(), box.max.x(), box.max.y()});
  }
  const auto view = [](const Box& box) { return Json({box.x0, box.y0, box.x1, box.y1}); };
  root["view"] = view(PanelBox(picture, nullptr, length, false));
  root["mechanisms"] = Json::array();
  for (const PictureMechanism& mechanism : picture.mechanisms) {
    Json object;
    object["title"] = mechanism.title;
    object["labels"] = mechanism.labels;
    if (mechanism.joints) {
      Json joints;
      joints["bodies"] = mechanism.joints->bodies;
      joints["task_body"] = mechanism.joints->task_body;
      joints["names"] = mechanism.joints->names;
      joints["at_first_pose"] = Json::array();
      for (const Vec& p : mechanism.joints->at_first) joints["at_first_pose"].push_back(point(p));
      object["joints"] = joints;
    } else {
      object["input"] = dyad(mechanism.input);
      object["output"] = dyad(mechanism.output);
    }
    object["first_pose"] = pose(mechanism.first_pose);
    object["coupler_curve"] = polyline(CouplerCurve(mechanism));
    object["view"] = view(PanelBox(picture, &mechanism, length, false));
    root["mechanisms"].push_back(object);
  }
  return root.dump();
}

std::optional<SphericalPicture> SphericalTaskPicture(const std::string& title, const Task& task,
                                                     const SpatialMotionResult& result,
                                                     size_t max_panels) {
  if (result.model != "spherical" || !result.spherical) return std::nullopt;
  constexpr int kCycleSteps = 240;  // samples of the pins' paths over the circuit
  const SphericalMotion motion = TaskSphericalMotion(task, *result.spherical, result.scale);
  SphericalPicture picture;
  picture.title = title;
  picture.center = result.spherical->in_fixed;
  const size_t panels = std::min(max_panels, result.spherical_mechanisms.size());
  for (size_t i = 0; i < panels; ++i) {
    const MechanismReport& mechanism = result.spherical_mechanisms[i];
    const SphericalFourBar four_bar =
        MakeSphericalFourBar(result.spherical_dyads[mechanism.input_dyad].dyad,
                             result.spherical_dyads[mechanism.output_dyad].dyad);
    picture.panels.push_back(MakeSphericalPanel(i, mechanism, four_bar, motion, kCycleSteps));
  }
  return picture;
}

std::string RenderSphericalSvg(const SphericalPicture& picture) {
  const size_t panels = std::max<size_t>(1, picture.panels.size());
  const size_t columns = panels == 1 ? 1 : (panels == 2 || panels == 4) ? 2 : 3;
  const size_t rows = (panels + columns - 1) / columns;
  const double plot = panels == 1 ? 480.0 : 340.0;
  const int label_lines = 2;
  const double header = kTitleLine + kLabelLine * label_lines + 6.0;
  const double panel_w = plot + 2.0 * kPad, panel_h = kPad + header + plot + kPad;
  const double width = kGap + static_cast<double>(columns) * (panel_w + kGap);
  const double height = kDocTitleHeight + static_cast<double>(rows) * (panel_h + kGap) + 28.0;
  Svg body;
  for (size_t i = 0; i < panels; ++i) {
    const double left = kGap + static_cast<double>(i % columns) * (panel_w + kGap);
    const double top = kDocTitleHeight + static_cast<double>(i / columns) * (panel_h + kGap);
    body.Rect(left, top, panel_w, panel_h, "rx=\"4\" fill=\"#fafafa\" stroke=\"#c8c8c8\"");
    const Disk disk{Vec(left + kPad + 0.5 * plot, top + kPad + header + 0.5 * plot), 0.42 * plot};
    if (picture.panels.empty()) {
      DrawPanelHeader(&body, left + kPad, top + kPad, plot, "task: no four-bar listed", {},
                      label_lines);
      body.Circle(disk.center, disk.radius,
                  "fill=\"#f3f6fa\" stroke=\"#9aa7b5\" stroke-width=\"1\"");
      continue;
    }
    const SphericalPanel& panel = picture.panels[i];
    DrawPanelHeader(&body, left + kPad, top + kPad, plot, panel.title, panel.labels, label_lines);
    DrawSphericalPanel(&body, disk, panel);
  }
  Svg legend;
  const double y = height - 16.0;
  double x = kGap;
  for (const auto& [colour, name] :
       {std::pair<const char*, const char*>{kTaskXColour, "coupler arc at each task pose"},
        {kCouplerCurveColour, "input crank pin's path"},
        {kCenterCurveColour, "output crank pin's path"},
        {"#9aa7b5", "far hemisphere dashed"}}) {
    legend.Line(Vec(x, y - 4.0), Vec(x + 22.0, y - 4.0),
                std::string("stroke=\"") + colour + "\" stroke-width=\"2\"");
    legend.Text(Vec(x + 28.0, y), name, "font-size=\"11\" fill=\"#333333\"");
    x += 40.0 + 6.2 * std::string(name).size();
  }
  const std::string title = picture.title.empty() ? std::string("linkfit") : picture.title;
  std::string out = SvgOpen(width, height, true, "");
  out += "<title>" + Escape(title) + "</title>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  Svg heading;
  heading.Text(Vec(kGap, 21.0), title + ": " + SphericalHeading(picture.center),
               "font-size=\"16\" font-weight=\"bold\" fill=\"#111111\"",
               static_cast<size_t>(width / 9.0));
  out += heading.text() + body.text() + legend.text() + "</svg>\n";
  return out;
}

std::string SphericalPictureToJson(const SphericalPicture& picture) {
  using Json = nlohmann::json;
  const auto vector = [](const Eigen::Vector3d& v) { return Json({v.x(), v.y(), v.z()}); };
  const auto point = [](const Vec& p) { return Json({p.x(), p.y()}); };
  Json root;
  root["kind"] = "spherical";
  root["title"] = picture.title;
  root["heading"] = SphericalHeading(picture.center);
  root["center"] = vector(picture.center);
  root["mechanisms"] = Json::array();
  for (const SphericalPanel& panel : picture.panels) {
    const SphereView view(panel.toward);
    const auto runs = [&](const std::vector<Eigen::Vector3d>& points) {
      Json list = Json::array();
      for (const SphereRun& run : SphereRuns(view, points)) {
        Json drawn = Json::array();
        for (const Vec& p : run.points) drawn.push_back(point(p));
        list.push_back({{"front", run.front}, {"points", drawn}});
      }
      return list;
    };
    const auto marks = [&](const Eigen::Vector3d(&axes)[2]) {
      Json list = Json::array();
      for (const Eigen::Vector3d& axis : axes) {
        list.push_back({{"at", point(view.Project(axis))}, {"front", view.Front(axis)}});
      }
      return list;
    };
    Json object;
    object["title"] = panel.title;
    object["labels"] = panel.labels;
    object["toward"] = vector(view.toward);
    object["right"] = vector(view.right);
    object["up"] = vector(view.up);
    object["sigma_axes"] = Json::array();
    for (int i = 0; i < 3; ++i) {
      object["sigma_axes"].push_back(point(view.Project(Eigen::Vector3d::Unit(i))));
    }
    object["ground"] = runs(panel.ground);
    object["input_link"] = runs(panel.input_link);
    object["output_link"] = runs(panel.output_link);
    object["coupler"] = runs(panel.coupler);
    object["input_pin_path"] = runs(panel.input_pin_path);
    object["output_pin_path"] = runs(panel.output_pin_path);
    object["task_couplers"] = Json::array();
    for (const auto& arc : panel.task_couplers) object["task_couplers"].push_back(runs(arc));
    object["fixed_pivots"] = marks(panel.fixed_axes);
    object["pins"] = marks(panel.pins);
    root["mechanisms"].push_back(object);
  }
  return root.dump();
}

std::string TaskPictureJson(const std::string& title, const Task& task, const TaskResult& result,
                            size_t max_panels, std::string* why) {
  if (const auto* spatial = std::get_if<SpatialMotionResult>(&result)) {
    if (const auto picture = SphericalTaskPicture(title, task, *spatial, max_panels)) {
      return SphericalPictureToJson(*picture);
    }
  }
  const std::optional<Picture> picture = TaskPicture(title, task, result, max_panels, why);
  return picture ? PictureToJson(*picture) : std::string();
}

}  // namespace linkfit
