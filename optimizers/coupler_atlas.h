// An atlas of coupler curves, searched by shape: the global stage of untimed path synthesis
// (issue 34). It sees the target's curve as a whole, where the subset seeds see a few of its
// points.
//
// The atlas holds crank-driven four-bars whose crank turns fully, drawn at random from a fixed
// seed (reproducible): 4Rs (crank-rockers and drag links), slider-cranks (PR output) and
// inverted slider-cranks (RP output), each normalised to a crank of length 1 about the origin.
// Every one's coupler curve over a full turn of the crank is described by normalized Fourier
// descriptors (Ullah & Kota, 1997): the curve resampled at kClosedSamples points evenly spaced in
// arc length, its discrete Fourier coefficients c_k, k = -kHarmonics..kHarmonics; the key is
// |c_k| / |c_1| for k != 0, 1, oriented so that |c_1| >= |c_-1| (c_k and c_-k swapped
// otherwise). Magnitudes drop the phases that a rotation (all phases alike) and a start point
// (phase k s) change; c_0 (position) is left out and dividing by |c_1| removes the scale; the
// orientation makes a reversed or mirrored curve's key its own.
//
// Open curves (an arc of a coupler curve: the crank turns part of a turn, or a partial arc of a
// closed curve) are keyed by the same descriptors of the arc retraced: resampled at kOpenSamples
// points in arc length, run forward and back as a closed curve, whose coefficients satisfy
// c_-k = c_k; the key is |c_k| / |c_1|, k = 2..kOpenHarmonics + 1. The open part of the atlas
// holds, for a subset of its four-bars, the arcs of kOpenStarts start angles and the spans of
// kOpenSpans (a sixth to nineteen twentieths of a turn).
//
// A target is matched by its key's nearest neighbours in the atlas (nanoflann k-d trees), then
// each neighbour is aligned to the target by the best similarity transform, over every start
// point, both senses and the mirror image (closed: every cyclic shift of the resampled curve;
// open: the arc's start and span searched about the neighbour's); the aligned four-bar is put in
// the configuration of the target's first point, in the target's frame: a seed for the
// free-timing refiner.
#ifndef LINKFIT_OPTIMIZERS_COUPLER_ATLAS_H_
#define LINKFIT_OPTIMIZERS_COUPLER_ATLAS_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lib/path_motion.h"

namespace linkfit {

inline constexpr int kAtlasHarmonics = 5;  // closed key: k = -5..5 without 0 and 1
inline constexpr int kClosedKeySize = 2 * kAtlasHarmonics - 1;
inline constexpr int kOpenKeySize = 8;  // open key: k = 2..9 of the retraced arc

struct CouplerAtlasOptions {
  std::uint64_t seed = 1997;  // of the random four-bars (Ullah & Kota's year)
  // Four-bars of each type keyed by their closed curves.
  int closed_four_bars = 6000;
  int closed_slider_cranks = 2000;
  int closed_inverted_slider_cranks = 2000;
  // Of those, the first so many of each type also keyed by their arcs.
  int open_four_bars = 1200;
  int open_slider_cranks = 400;
  int open_inverted_slider_cranks = 400;
};

// One aligned candidate.
struct AtlasMatch {
  // In the target's frame, in the configuration of its first point (lib/path_motion.h).
  PathFourBar four_bar;
  double direction = 1.0;    // the crank's sense of turning through the points
  double shape_error = 0.0;  // RMS distance after alignment, relative to the target's RMS size
  int atlas_index = -1;      // the atlas four-bar it came from
  bool closed = false;       // matched as a closed curve (else as an arc)
};

struct AtlasMatchOptions {
  int closed_neighbours = 48;  // nearest closed keys aligned
  int open_neighbours = 96;    // nearest open keys aligned (one alignment per four-bar)
  int kept = 8;                // best aligned candidates returned
  // Match as a closed curve, as an arc, or both (a curve whose ends nearly meet).
  bool match_closed = true;
  bool match_open = true;
};

class CouplerAtlas {
 public:
  // Builds the atlas (about a second).
  explicit CouplerAtlas(const CouplerAtlasOptions& options = {});
  ~CouplerAtlas();
  CouplerAtlas(CouplerAtlas&&) noexcept;
  CouplerAtlas& operator=(CouplerAtlas&&) noexcept;

  // The atlas of the default options, once per process: read from the file `linkfit_atlas`
  // writes at build time (LINKFIT_ATLAS in the environment, else the installed copy, else the
  // build tree's) when it is there and was made with these options, else built.
  static const CouplerAtlas& Shared();

  // Writes the atlas to `path` (binary, with its options); false on failure.
  bool Write(const std::string& path) const;
  // Reads an atlas written by Write with the same options; null when the file is missing,
  // unreadable, or of other options or another format.
  static std::unique_ptr<CouplerAtlas> Read(const std::string& path,
                                            const CouplerAtlasOptions& options = {});

  // Candidates for the curve through `points` (in order; `closed`: the curve returns from the
  // last point to the first), best aligned first, at most options.kept, one per atlas four-bar.
  std::vector<AtlasMatch> Match(const std::vector<Eigen::Vector2d>& points, bool closed,
                                const AtlasMatchOptions& options = {}) const;

  size_t four_bar_count() const;
  size_t closed_key_count() const;
  size_t open_key_count() const;
  const PathFourBar& four_bar(size_t index) const;

 private:
  struct Data;
  struct Empty {};
  explicit CouplerAtlas(Empty);
  void BuildIndexes();
  std::unique_ptr<Data> data_;
};

// The closed and open keys of a curve given as points in order (exposed for the tests).
std::array<float, kClosedKeySize> ClosedShapeKey(const std::vector<Eigen::Vector2d>& points);
std::array<float, kOpenKeySize> OpenShapeKey(const std::vector<Eigen::Vector2d>& points);

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_COUPLER_ATLAS_H_
