#include "optimizers/coupler_atlas.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <nanoflann.hpp>
#include <random>
#include <utility>

#include "lib/mechanism.h"
#include "lib/planar_pose.h"

namespace linkfit {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;
// Samples of a crank turn (one degree) from which curves and arcs are taken.
constexpr int kCycleSamples = 360;
// Points of a closed curve and of an arc, evenly spaced in arc length, for keys and alignment.
constexpr int kClosedSamples = 64;
constexpr int kOpenSamples = 32;
// A closed candidate is aligned at this many times the target's samples.
constexpr int kShiftRefinement = 4;
// The open part's arcs: start angles every 360 / kOpenStarts degrees, and these spans (degrees).
constexpr int kOpenStarts = 12;
constexpr int kOpenSpans[] = {60, 90, 135, 180, 225, 270, 320};
// Slack of assembly while sampling, relative to the crank.
constexpr double kAssemblyTolerance = 1e-9;
constexpr char kMagic[16] = "linkfit-atlas-2";

double Uniform(std::mt19937_64& rng, double low, double high) {
  // The top 53 bits: the same numbers on every platform (std::uniform_real_distribution is not).
  return low + (high - low) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double LogUniform(std::mt19937_64& rng, double low, double high) {
  return std::exp(Uniform(rng, std::log(low), std::log(high)));
}

Eigen::Vector2d Perpendicular(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// The coupler point over a whole crank turn from the reference configuration (E = Sigma), on
// its assembly, at `samples` evenly spaced crank angles; false when some angle does not assemble.
bool CycleCurve(const PathFourBar& four_bar, int samples, std::vector<Eigen::Vector2d>* curve,
                std::vector<PlanarPose>* poses = nullptr) {
  const double alpha0 = FirstCrankAngle(four_bar);
  const double tolerance = kAssemblyTolerance * four_bar.input.radius;
  std::vector<PlanarPose> here;
  const int count = AssembleFourBar(four_bar.input, four_bar.output, alpha0, tolerance, &here);
  if (count == 0) return false;
  const int label =
      count == 2 && PoseError(here[1], PlanarPose(), 1.0) < PoseError(here[0], PlanarPose(), 1.0)
          ? 1
          : 0;
  curve->resize(samples);
  if (poses) poses->resize(samples);
  for (int k = 0; k < samples; ++k) {
    const int assembled = AssembleFourBar(four_bar.input, four_bar.output,
                                          alpha0 + 2.0 * kPi * k / samples, tolerance, &here);
    if (assembled == 0) return false;
    const PlanarPose& pose = here[std::min(label, assembled - 1)];
    (*curve)[k] = pose.ToFixed(four_bar.coupler_point);
    if (poses) (*poses)[k] = pose;
  }
  return true;
}

// `count` points evenly spaced in arc length along the polyline `points` (closed: back to the
// first), the first at points[0]; `at` gets each one's place as a fractional index of `points`.
std::vector<Complex> ResampleByArcLength(const std::vector<Eigen::Vector2d>& points, bool closed,
                                         int count, std::vector<double>* at = nullptr) {
  const size_t n = points.size();
  const size_t segments = closed ? n : n - 1;
  std::vector<double> arc(segments + 1, 0.0);
  for (size_t i = 0; i < segments; ++i) {
    arc[i + 1] = arc[i] + (points[(i + 1) % n] - points[i]).norm();
  }
  const double total = arc.back();
  const double step = total / (closed ? count : count - 1);
  std::vector<Complex> resampled(count);
  if (at) at->resize(count);
  size_t segment = 0;
  for (int k = 0; k < count; ++k) {
    const double target = k * step;
    while (segment + 1 < segments && arc[segment + 1] < target) ++segment;
    const double span = arc[segment + 1] - arc[segment];
    const double fraction = span > 0.0 ? std::clamp((target - arc[segment]) / span, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d point =
        points[segment] + fraction * (points[(segment + 1) % n] - points[segment]);
    resampled[k] = Complex(point.x(), point.y());
    if (at) (*at)[k] = static_cast<double>(segment) + fraction;
  }
  return resampled;
}

// The Fourier coefficients c_k, 0 < |k| <= harmonics, of the closed polygon through `points`
// run at unit speed (period T its perimeter): with u_j the unit direction of the side that ends
// at vertex j and s_j the arc length there, integrating by parts twice gives
//   c_k = -T / (2 pi k)^2 sum_j (u_{j+1} - u_j) exp(-2 pi i k s_j / T),
// exact for the polygon, whatever vertex it starts at (a start moves every phase, k s_0).
std::vector<Complex> PolygonCoefficients(const std::vector<Eigen::Vector2d>& points,
                                         int harmonics) {
  const size_t n = points.size();
  std::vector<Complex> directions(n);  // of the side from vertex j to j + 1
  std::vector<double> arc(n + 1, 0.0);
  for (size_t j = 0; j < n; ++j) {
    const Eigen::Vector2d side = points[(j + 1) % n] - points[j];
    const double length = side.norm();
    directions[j] = length > 0.0 ? Complex(side.x(), side.y()) / length : Complex(0.0, 0.0);
    arc[j + 1] = arc[j] + length;
  }
  const double period = arc[n];
  std::vector<Complex> coefficients(2 * harmonics + 1, 0.0);
  if (!(period > 0.0)) return coefficients;
  // Sides of zero length carry the direction before them (no turn there).
  for (size_t j = 0; j < n; ++j) {
    if (directions[j] == Complex(0.0, 0.0)) directions[j] = directions[(j + n - 1) % n];
  }
  for (size_t j = 0; j < n; ++j) {
    // The turn at vertex j (between the side into it and the side out of it), at arc s_j.
    const Complex turn = directions[j] - directions[(j + n - 1) % n];
    if (turn == Complex(0.0, 0.0)) continue;
    const Complex step = std::polar(1.0, -2.0 * kPi * arc[j] / period);
    Complex phase = step;
    for (int k = 1; k <= harmonics; ++k, phase *= step) {
      coefficients[harmonics + k] += turn * phase;
      coefficients[harmonics - k] += turn * std::conj(phase);
    }
  }
  for (int k = 1; k <= harmonics; ++k) {
    const double factor = -period / std::pow(2.0 * kPi * k, 2);
    coefficients[harmonics + k] *= factor;
    coefficients[harmonics - k] *= factor;
  }
  return coefficients;
}

std::array<float, kClosedKeySize> ClosedKeyOf(const std::vector<Eigen::Vector2d>& polygon) {
  const std::vector<Complex> c = PolygonCoefficients(polygon, kAtlasHarmonics);
  std::array<double, 2 * kAtlasHarmonics + 1> magnitude;
  for (int k = 0; k <= 2 * kAtlasHarmonics; ++k) magnitude[k] = std::abs(c[k]);
  // Oriented: the curve run the other way (or mirrored) has c_k and c_-k swapped.
  if (magnitude[kAtlasHarmonics - 1] > magnitude[kAtlasHarmonics + 1]) {
    std::reverse(magnitude.begin(), magnitude.end());
  }
  const double first = magnitude[kAtlasHarmonics + 1];
  std::array<float, kClosedKeySize> key{};
  int i = 0;
  for (int k = -kAtlasHarmonics; k <= kAtlasHarmonics; ++k) {
    if (k == 0 || k == 1) continue;
    key[i++] = first > 0.0 ? static_cast<float>(magnitude[k + kAtlasHarmonics] / first) : 0.0f;
  }
  return key;
}

std::array<float, kOpenKeySize> OpenKeyOf(const std::vector<Eigen::Vector2d>& arc) {
  // Forward and back: z_0 .. z_{m-1}, z_{m-2} .. z_1, a closed polygon with c_-k = c_k.
  std::vector<Eigen::Vector2d> retraced(arc);
  for (int k = static_cast<int>(arc.size()) - 2; k >= 1; --k) retraced.push_back(arc[k]);
  const std::vector<Complex> c = PolygonCoefficients(retraced, kOpenKeySize + 1);
  const double first = std::abs(c[kOpenKeySize + 2]);
  std::array<float, kOpenKeySize> key{};
  for (int k = 0; k < kOpenKeySize; ++k) {
    key[k] = first > 0.0 ? static_cast<float>(std::abs(c[kOpenKeySize + 3 + k]) / first) : 0.0f;
  }
  return key;
}

// A target of alignment: its points, centred, their mean and sum of squares.
struct AlignTarget {
  std::vector<Complex> centred;
  Complex mean = 0.0;
  double squares = 0.0;
  explicit AlignTarget(const std::vector<Complex>& points) : centred(points) {
    for (const Complex& z : points) mean += z / static_cast<double>(points.size());
    for (Complex& z : centred) {
      z -= mean;
      squares += std::norm(z);
    }
  }
};

// The best similarity a s + b onto the target (equal counts) in the least-squares sense:
// returns the residual sum of squares and sets a, b. With t centred, sum conj(s - s_mean) t =
// sum conj(s) t, and sum |s - s_mean|^2 = sum |s|^2 - N |s_mean|^2.
double Align(const AlignTarget& target, const std::vector<Complex>& source, Complex* a,
             Complex* b) {
  const double n = static_cast<double>(source.size());
  Complex cross = 0.0, sum = 0.0;
  double squares = 0.0;
  for (size_t k = 0; k < source.size(); ++k) {
    cross += std::conj(source[k]) * target.centred[k];
    sum += source[k];
    squares += std::norm(source[k]);
  }
  const Complex mean = sum / n;
  const double ss = squares - n * std::norm(mean);
  if (!(ss > 1e-300)) {
    *a = 0.0;
    *b = target.mean;
    return target.squares;
  }
  *a = cross / ss;
  *b = target.mean - *a * mean;
  return std::max(0.0, target.squares - std::norm(cross) / ss);
}

// A four-bar mapped by z -> a S(z) + b, S the mirror (conjugation) when `mirror`.
PathFourBar Transformed(const PathFourBar& four_bar, bool mirror, Complex a, Complex b) {
  Similarity2 similarity;
  similarity.scale = std::abs(a);
  similarity.angle = std::arg(a);
  similarity.translation = Eigen::Vector2d(b.real(), b.imag());
  return TransformPathFourBar(four_bar, similarity, mirror);
}

// Random four-bars whose crank (length 1, pivot at the origin) turns fully, in the configuration
// of crank angle 0 (E = Sigma there).
PathFourBar RandomFourBar(std::mt19937_64& rng, DyadType output_type) {
  const Eigen::Vector2d crank_pivot(0.0, 0.0), crank_pin(1.0, 0.0);
  const double side = Uniform(rng, 0.0, 1.0) < 0.5 ? -1.0 : 1.0;
  PathFourBar four_bar;
  four_bar.input = PlanarDyad::RR(crank_pivot, crank_pin, 1.0);
  if (output_type == DyadType::kRR) {
    for (;;) {
      // Crank-rockers (the crank shortest) and a fifth drag links (the ground shortest).
      const bool drag_link = Uniform(rng, 0.0, 1.0) < 0.2;
      const double ground = drag_link ? Uniform(rng, 0.15, 0.85) : LogUniform(rng, 1.1, 5.0);
      const double coupler = LogUniform(rng, 1.1, 5.0), rocker = LogUniform(rng, 1.1, 5.0);
      std::array<double, 4> links = {1.0, ground, coupler, rocker};
      std::sort(links.begin(), links.end());
      // Grashof with a margin (away from change points).
      if (links[0] + links[3] > 0.95 * (links[1] + links[2])) continue;
      const Eigen::Vector2d ground_pivot(ground, 0.0);
      const Eigen::Vector2d span = ground_pivot - crank_pin;
      const double d = span.norm();
      // The coupler-rocker pin: the circles (A, coupler) and (D, rocker) meet.
      const double along = (coupler * coupler - rocker * rocker + d * d) / (2.0 * d);
      const double across2 = coupler * coupler - along * along;
      if (!(across2 > 0.0)) continue;
      const Eigen::Vector2d unit = span / d;
      const Eigen::Vector2d pin =
          crank_pin + along * unit + side * std::sqrt(across2) * Perpendicular(unit);
      four_bar.output = PlanarDyad::RR(ground_pivot, pin, rocker);
      const Eigen::Vector2d link = pin - crank_pin;
      four_bar.coupler_point = crank_pin + Uniform(rng, -1.0, 2.0) * link +
                               Uniform(rng, -1.5, 1.5) * Perpendicular(link);
      return four_bar;
    }
  }
  if (output_type == DyadType::kPR) {
    // Slider-crank: the slider's line y = e, the coupler longer than the crank plus |e|.
    const double coupler = LogUniform(rng, 1.3, 5.0);
    const double offset = Uniform(rng, -0.9, 0.9) * (coupler - 1.0);
    const Eigen::Vector2d pin(1.0 + side * std::sqrt(coupler * coupler - offset * offset), offset);
    four_bar.output = PlanarDyad::PR(pin, Eigen::Vector2d(0.0, offset), Eigen::Vector2d::UnitX());
    const Eigen::Vector2d link = pin - crank_pin;
    four_bar.coupler_point =
        crank_pin + Uniform(rng, -1.0, 2.0) * link + Uniform(rng, -1.0, 1.0) * Perpendicular(link);
    return four_bar;
  }
  // Inverted slider-crank: the ground pivot F slides on a line of the coupler that passes e from
  // the crank pin; the crank turns fully when |e| < |F| - 1.
  const double ground = LogUniform(rng, 1.3, 5.0);
  const Eigen::Vector2d ground_pivot(ground, 0.0);
  const Eigen::Vector2d to_pivot = (ground_pivot - crank_pin) / (ground - 1.0);
  const double offset = Uniform(rng, -0.9, 0.9) * (ground - 1.0);
  const double turn = std::asin(offset / (ground - 1.0));
  const Eigen::Vector2d direction(std::cos(turn) * to_pivot.x() - std::sin(turn) * to_pivot.y(),
                                  std::sin(turn) * to_pivot.x() + std::cos(turn) * to_pivot.y());
  four_bar.output = PlanarDyad::RP(ground_pivot, ground_pivot, direction);
  four_bar.coupler_point =
      crank_pin + ground * Eigen::Vector2d(Uniform(rng, -1.0, 1.5), Uniform(rng, -1.0, 1.0));
  return four_bar;
}

template <int Dim>
struct KeyCloud {
  const std::vector<std::array<float, Dim>>* keys = nullptr;
  size_t kdtree_get_point_count() const { return keys->size(); }
  float kdtree_get_pt(size_t index, size_t dimension) const { return (*keys)[index][dimension]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

template <int Dim>
using KeyTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, KeyCloud<Dim>>,
                                        KeyCloud<Dim>, Dim, std::uint32_t>;

struct OpenWindow {
  std::int32_t four_bar = 0;
  std::int32_t start = 0;  // in cycle samples (degrees)
  std::int32_t span = 0;
};

// The arc of `cycle` (kCycleSamples points of a turn) from sample `start` over `span` samples
// (wrapping).
std::vector<Eigen::Vector2d> Arc(const std::vector<Eigen::Vector2d>& cycle, int start, int span) {
  std::vector<Eigen::Vector2d> arc;
  arc.reserve(span + 1);
  for (int k = 0; k <= span; ++k) {
    arc.push_back(cycle[((start + k) % kCycleSamples + kCycleSamples) % kCycleSamples]);
  }
  return arc;
}

void Mix(std::uint64_t* hash, const void* bytes, size_t size) {
  const unsigned char* p = static_cast<const unsigned char*>(bytes);
  for (size_t i = 0; i < size; ++i) {
    *hash ^= p[i];
    *hash *= 1099511628211ull;  // FNV-1a
  }
}

}  // namespace

struct CouplerAtlas::Data {
  CouplerAtlasOptions options;
  std::vector<PathFourBar> four_bars;
  // One per four-bar, in its order (closed_keys[i] is four_bars[i]'s).
  std::vector<std::array<float, kClosedKeySize>> closed_keys;
  std::vector<std::array<float, kOpenKeySize>> open_keys;
  std::vector<OpenWindow> open_windows;
  KeyCloud<kClosedKeySize> closed_cloud;
  KeyCloud<kOpenKeySize> open_cloud;
  std::unique_ptr<KeyTree<kClosedKeySize>> closed_tree;
  std::unique_ptr<KeyTree<kOpenKeySize>> open_tree;
};

std::array<float, kClosedKeySize> ClosedShapeKey(const std::vector<Eigen::Vector2d>& points) {
  return ClosedKeyOf(points);
}

std::array<float, kOpenKeySize> OpenShapeKey(const std::vector<Eigen::Vector2d>& points) {
  return OpenKeyOf(points);
}

CouplerAtlas::CouplerAtlas(Empty) : data_(std::make_unique<Data>()) {}
CouplerAtlas::~CouplerAtlas() = default;
CouplerAtlas::CouplerAtlas(CouplerAtlas&&) noexcept = default;
CouplerAtlas& CouplerAtlas::operator=(CouplerAtlas&&) noexcept = default;

CouplerAtlas::CouplerAtlas(const CouplerAtlasOptions& options) : CouplerAtlas(Empty()) {
  data_->options = options;
  std::mt19937_64 rng(options.seed);
  const std::pair<DyadType, std::pair<int, int>> kinds[] = {
      {DyadType::kRR, {options.closed_four_bars, options.open_four_bars}},
      {DyadType::kPR, {options.closed_slider_cranks, options.open_slider_cranks}},
      {DyadType::kRP,
       {options.closed_inverted_slider_cranks, options.open_inverted_slider_cranks}}};
  std::vector<Eigen::Vector2d> cycle;
  for (const auto& [type, counts] : kinds) {
    for (int i = 0; i < counts.first; ++i) {
      PathFourBar four_bar;
      do {
        four_bar = RandomFourBar(rng, type);
      } while (!CycleCurve(four_bar, kCycleSamples, &cycle));
      const std::int32_t index = static_cast<std::int32_t>(data_->four_bars.size());
      data_->four_bars.push_back(four_bar);
      data_->closed_keys.push_back(ClosedKeyOf(cycle));
      if (i >= counts.second) continue;
      for (int s = 0; s < kOpenStarts; ++s) {
        for (const int span : kOpenSpans) {
          const int start = s * kCycleSamples / kOpenStarts;
          data_->open_keys.push_back(OpenKeyOf(Arc(cycle, start, span)));
          data_->open_windows.push_back({index, start, span});
        }
      }
    }
  }
  BuildIndexes();
}

void CouplerAtlas::BuildIndexes() {
  data_->closed_cloud.keys = &data_->closed_keys;
  data_->open_cloud.keys = &data_->open_keys;
  const nanoflann::KDTreeSingleIndexAdaptorParams params(16);
  data_->closed_tree =
      std::make_unique<KeyTree<kClosedKeySize>>(kClosedKeySize, data_->closed_cloud, params);
  data_->open_tree =
      std::make_unique<KeyTree<kOpenKeySize>>(kOpenKeySize, data_->open_cloud, params);
}

size_t CouplerAtlas::four_bar_count() const { return data_->four_bars.size(); }
size_t CouplerAtlas::closed_key_count() const { return data_->closed_keys.size(); }
size_t CouplerAtlas::open_key_count() const { return data_->open_keys.size(); }
const PathFourBar& CouplerAtlas::four_bar(size_t index) const { return data_->four_bars[index]; }

namespace {

// The file's contents in order, each value through `io` (writing or reading).
template <typename Io>
bool Serialize(Io& io, CouplerAtlasOptions* options, std::vector<PathFourBar>* four_bars,
               std::vector<std::array<float, kClosedKeySize>>* closed_keys,
               std::vector<std::array<float, kOpenKeySize>>* open_keys,
               std::vector<OpenWindow>* open_windows) {
  std::uint64_t counts[3] = {four_bars->size(), closed_keys->size(), open_keys->size()};
  if (!io(&options->seed, sizeof(options->seed))) return false;
  int* ints[] = {&options->closed_four_bars,
                 &options->closed_slider_cranks,
                 &options->closed_inverted_slider_cranks,
                 &options->open_four_bars,
                 &options->open_slider_cranks,
                 &options->open_inverted_slider_cranks};
  for (int* value : ints) {
    std::int32_t v = *value;
    if (!io(&v, sizeof(v))) return false;
    *value = v;
  }
  if (!io(counts, sizeof(counts))) return false;
  constexpr std::uint64_t kMost = 1u << 24;
  if (counts[0] > kMost || counts[1] > kMost || counts[2] > kMost) return false;
  four_bars->resize(counts[0]);
  closed_keys->resize(counts[1]);
  open_keys->resize(counts[2]);
  open_windows->resize(counts[2]);
  for (PathFourBar& four_bar : *four_bars) {
    for (PlanarDyad* dyad : {&four_bar.input, &four_bar.output}) {
      std::int32_t type = static_cast<std::int32_t>(dyad->type);
      if (!io(&type, sizeof(type))) return false;
      dyad->type = static_cast<DyadType>(type);
      if (!io(dyad->fixed_pivot.data(), 2 * sizeof(double)) ||
          !io(dyad->moving_pivot.data(), 2 * sizeof(double)) ||
          !io(&dyad->radius, sizeof(double)) || !io(dyad->line_point.data(), 2 * sizeof(double)) ||
          !io(dyad->line_direction.data(), 2 * sizeof(double))) {
        return false;
      }
    }
    if (!io(four_bar.coupler_point.data(), 2 * sizeof(double))) return false;
  }
  return io(closed_keys->data(), closed_keys->size() * sizeof((*closed_keys)[0])) &&
         io(open_keys->data(), open_keys->size() * sizeof((*open_keys)[0])) &&
         io(open_windows->data(), open_windows->size() * sizeof(OpenWindow));
}

bool SameOptions(const CouplerAtlasOptions& a, const CouplerAtlasOptions& b) {
  return a.seed == b.seed && a.closed_four_bars == b.closed_four_bars &&
         a.closed_slider_cranks == b.closed_slider_cranks &&
         a.closed_inverted_slider_cranks == b.closed_inverted_slider_cranks &&
         a.open_four_bars == b.open_four_bars && a.open_slider_cranks == b.open_slider_cranks &&
         a.open_inverted_slider_cranks == b.open_inverted_slider_cranks;
}

}  // namespace

bool CouplerAtlas::Write(const std::string& path) const {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return false;
  std::uint64_t hash = 14695981039346656037ull;
  const auto write = [&](void* bytes, size_t size) {
    Mix(&hash, bytes, size);
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    return static_cast<bool>(out);
  };
  out.write(kMagic, sizeof(kMagic));
  CouplerAtlasOptions options = data_->options;
  std::vector<PathFourBar> four_bars = data_->four_bars;
  std::vector<std::array<float, kClosedKeySize>> closed_keys = data_->closed_keys;
  std::vector<std::array<float, kOpenKeySize>> open_keys = data_->open_keys;
  std::vector<OpenWindow> open_windows = data_->open_windows;
  if (!Serialize(write, &options, &four_bars, &closed_keys, &open_keys, &open_windows)) {
    return false;
  }
  out.write(reinterpret_cast<const char*>(&hash), sizeof(hash));
  out.close();
  return static_cast<bool>(out);
}

std::unique_ptr<CouplerAtlas> CouplerAtlas::Read(const std::string& path,
                                                 const CouplerAtlasOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return nullptr;
  char magic[sizeof(kMagic)];
  if (!in.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) {
    return nullptr;
  }
  std::uint64_t hash = 14695981039346656037ull;
  const auto read = [&](void* bytes, size_t size) {
    if (!in.read(static_cast<char*>(bytes), static_cast<std::streamsize>(size))) return false;
    Mix(&hash, bytes, size);
    return true;
  };
  std::unique_ptr<CouplerAtlas> atlas(new CouplerAtlas(Empty()));
  Data& data = *atlas->data_;
  if (!Serialize(read, &data.options, &data.four_bars, &data.closed_keys, &data.open_keys,
                 &data.open_windows)) {
    return nullptr;
  }
  std::uint64_t stored = 0;
  if (!in.read(reinterpret_cast<char*>(&stored), sizeof(stored)) || stored != hash ||
      !SameOptions(data.options, options)) {
    return nullptr;
  }
  if (data.closed_keys.size() != data.four_bars.size()) return nullptr;
  for (const OpenWindow& window : data.open_windows) {
    if (window.four_bar < 0 || static_cast<size_t>(window.four_bar) >= data.four_bars.size())
      return nullptr;
  }
  atlas->BuildIndexes();
  return atlas;
}

const CouplerAtlas& CouplerAtlas::Shared() {
  static const CouplerAtlas* shared = [] {
    std::vector<std::string> paths;
    if (const char* given = std::getenv("LINKFIT_ATLAS")) paths.push_back(given);
#ifdef LINKFIT_ATLAS_INSTALLED
    paths.push_back(LINKFIT_ATLAS_INSTALLED);
#endif
#ifdef LINKFIT_ATLAS_BUILT
    paths.push_back(LINKFIT_ATLAS_BUILT);
#endif
    for (const std::string& path : paths) {
      if (std::unique_ptr<CouplerAtlas> read = Read(path)) return read.release();
    }
    return new CouplerAtlas(CouplerAtlasOptions());
  }();
  return *shared;
}

std::vector<AtlasMatch> CouplerAtlas::Match(const std::vector<Eigen::Vector2d>& points, bool closed,
                                            const AtlasMatchOptions& options) const {
  std::vector<AtlasMatch> matches;
  if (points.size() < 3) return matches;
  // The target's size: RMS distance from its centroid.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p / static_cast<double>(points.size());
  double size = 0.0;
  for (const Eigen::Vector2d& p : points) size += (p - centroid).squaredNorm();
  size = std::sqrt(size / static_cast<double>(points.size()));
  if (!(size > 0.0)) return matches;
  std::vector<Eigen::Vector2d> cycle;
  std::vector<PlanarPose> poses;
  // The matched four-bar in the target's frame at the target's first point: `index`'s four-bar
  // at cycle sample `sample` (fractional), mirrored or not, mapped by a z + b.
  const auto candidate = [&](int index, double sample, bool mirror, bool reversed, Complex a,
                             Complex b, double residual, int count, bool as_closed) {
    const PathFourBar& four_bar = data_->four_bars[index];
    AtlasMatch match;
    const double alpha = FirstCrankAngle(four_bar) + 2.0 * kPi * sample / kCycleSamples;
    std::vector<PlanarPose> here;
    const int assembled =
        AssembleFourBar(four_bar.input, four_bar.output, alpha, kAssemblyTolerance, &here);
    if (assembled == 0) return;
    // The assembly of the cycle: the one nearest the sampled pose at the nearest sample.
    const PlanarPose& sampled = poses[static_cast<int>(std::lround(sample)) % kCycleSamples];
    const int label =
        assembled == 2 && PoseError(here[1], sampled, 1.0) < PoseError(here[0], sampled, 1.0) ? 1
                                                                                              : 0;
    match.four_bar = Transformed(MoveToFirstConfiguration(four_bar, here[label]), mirror, a, b);
    match.direction = (reversed ? -1.0 : 1.0) * (mirror ? -1.0 : 1.0);
    match.shape_error = std::sqrt(residual / count) / size;
    match.atlas_index = index;
    match.closed = as_closed;
    matches.push_back(match);
  };
  if (closed && options.match_closed) {
    // Resampled from the vertex farthest from the centroid (the same vertex however the target
    // is moved, turned, scaled, restarted or reversed), the target's first point `first_offset`
    // samples on.
    size_t canonical = 0;
    for (size_t j = 1; j < points.size(); ++j) {
      if ((points[j] - centroid).squaredNorm() > (points[canonical] - centroid).squaredNorm()) {
        canonical = j;
      }
    }
    std::vector<Eigen::Vector2d> from_canonical(points.begin() + canonical, points.end());
    from_canonical.insert(from_canonical.end(), points.begin(), points.begin() + canonical);
    double perimeter = 0.0, to_first = 0.0;
    for (size_t j = 0; j < from_canonical.size(); ++j) {
      if (j == from_canonical.size() - canonical) to_first = perimeter;
      perimeter += (from_canonical[(j + 1) % from_canonical.size()] - from_canonical[j]).norm();
    }
    const double first_offset = perimeter > 0.0 ? to_first / perimeter * kClosedSamples : 0.0;
    const AlignTarget target(ResampleByArcLength(from_canonical, true, kClosedSamples));
    const std::array<float, kClosedKeySize> key = ClosedKeyOf(points);
    const int wanted = std::min<int>(options.closed_neighbours, data_->closed_keys.size());
    std::vector<std::uint32_t> found(wanted);
    std::vector<float> distances(wanted);
    const size_t count =
        data_->closed_tree->knnSearch(key.data(), wanted, found.data(), distances.data());
    for (size_t f = 0; f < count; ++f) {
      const int index = static_cast<int>(found[f]);
      if (!CycleCurve(data_->four_bars[index], kCycleSamples, &cycle, &poses)) continue;
      // The candidate at kShiftRefinement times the target's samples: shifts of a fraction of
      // their spacing.
      constexpr int kFine = kShiftRefinement * kClosedSamples;
      std::vector<double> at;
      const std::vector<Complex> curve = ResampleByArcLength(cycle, true, kFine, &at);
      double best = std::numeric_limits<double>::infinity();
      int best_shift = 0;
      bool best_mirror = false, best_reversed = false;
      Complex best_a, best_b;
      std::vector<Complex> source(kClosedSamples);
      for (const bool mirror : {false, true}) {
        for (const bool reversed : {false, true}) {
          for (int shift = 0; shift < kFine; ++shift) {
            for (int n = 0; n < kClosedSamples; ++n) {
              const int step = kShiftRefinement * n;
              const int k = ((shift + (reversed ? -step : step)) % kFine + kFine) % kFine;
              source[n] = mirror ? std::conj(curve[k]) : curve[k];
            }
            Complex a, b;
            const double residual = Align(target, source, &a, &b);
            if (residual < best) {
              best = residual;
              best_shift = shift;
              best_mirror = mirror;
              best_reversed = reversed;
              best_a = a;
              best_b = b;
            }
          }
        }
      }
      // The target's first point, first_offset target samples from its resampled start: on the
      // candidate's fine curve at `place`, a cycle sample between at[] of its neighbours.
      const double place =
          best_shift + (best_reversed ? -1.0 : 1.0) * first_offset * kShiftRefinement;
      const double wrapped = std::fmod(std::fmod(place, kFine) + kFine, static_cast<double>(kFine));
      const int below = static_cast<int>(std::floor(wrapped)) % kFine;
      const int above = (below + 1) % kFine;
      double upper = at[above];
      if (upper < at[below]) upper += kCycleSamples;  // across the cycle's start
      const double sample =
          std::fmod(at[below] + (wrapped - std::floor(wrapped)) * (upper - at[below]),
                    static_cast<double>(kCycleSamples));
      candidate(index, sample, best_mirror, best_reversed, best_a, best_b, best, kClosedSamples,
                true);
    }
  }
  if (options.match_open) {
    const AlignTarget target(ResampleByArcLength(points, false, kOpenSamples));
    const std::array<float, kOpenKeySize> key = OpenKeyOf(points);
    const int wanted = std::min<int>(options.open_neighbours, data_->open_keys.size());
    std::vector<std::uint32_t> found(wanted);
    std::vector<float> distances(wanted);
    const size_t count =
        data_->open_tree->knnSearch(key.data(), wanted, found.data(), distances.data());
    std::vector<int> aligned;  // four-bars aligned already (the nearest window of each)
    for (size_t f = 0; f < count; ++f) {
      const OpenWindow& window = data_->open_windows[found[f]];
      if (std::find(aligned.begin(), aligned.end(), window.four_bar) != aligned.end()) continue;
      aligned.push_back(window.four_bar);
      if (!CycleCurve(data_->four_bars[window.four_bar], kCycleSamples, &cycle, &poses)) continue;
      double best = std::numeric_limits<double>::infinity();
      int best_start = window.start, best_span = window.span;
      bool best_mirror = false, best_reversed = false;
      Complex best_a, best_b;
      // The arc's start and span searched about the window's: a coarse pass, then a fine one.
      const auto search = [&](int center_start, int center_span, int start_step,
                              const std::vector<double>& factors) {
        for (int ds = -2; ds <= 2; ++ds) {
          for (const double factor : factors) {
            const int start = center_start + ds * start_step;
            const int span =
                std::clamp(static_cast<int>(std::lround(center_span * factor)), 8, kCycleSamples);
            const std::vector<Complex> arc =
                ResampleByArcLength(Arc(cycle, start, span), false, kOpenSamples);
            std::vector<Complex> source(kOpenSamples);
            for (const bool mirror : {false, true}) {
              for (const bool reversed : {false, true}) {
                for (int n = 0; n < kOpenSamples; ++n) {
                  const Complex z = arc[reversed ? kOpenSamples - 1 - n : n];
                  source[n] = mirror ? std::conj(z) : z;
                }
                Complex a, b;
                const double residual = Align(target, source, &a, &b);
                if (residual < best) {
                  best = residual;
                  best_start = start;
                  best_span = span;
                  best_mirror = mirror;
                  best_reversed = reversed;
                  best_a = a;
                  best_b = b;
                }
              }
            }
          }
        }
      };
      const int step = kCycleSamples / kOpenStarts / 2;
      search(window.start, window.span, step, {0.8, 0.9, 1.0, 1.1, 1.25});
      search(best_start, best_span, std::max(1, step / 4), {0.95, 1.0, 1.05});
      const double first = best_reversed ? best_start + best_span : best_start;
      const double sample = std::fmod(std::fmod(first, kCycleSamples) + kCycleSamples,
                                      static_cast<double>(kCycleSamples));
      candidate(window.four_bar, sample, best_mirror, best_reversed, best_a, best_b, best,
                kOpenSamples, false);
    }
  }
  std::sort(matches.begin(), matches.end(),
            [](const AtlasMatch& a, const AtlasMatch& b) { return a.shape_error < b.shape_error; });
  // One per atlas four-bar (closed and open matches of one can both come).
  std::vector<AtlasMatch> kept;
  for (const AtlasMatch& match : matches) {
    if (static_cast<int>(kept.size()) >= options.kept) break;
    bool listed = false;
    for (const AtlasMatch& other : kept) listed = listed || other.atlas_index == match.atlas_index;
    if (!listed) kept.push_back(match);
  }
  return kept;
}

}  // namespace linkfit
