// Tests of the coupler-curve atlas (optimizers/coupler_atlas.h): its keys and candidates do not
// depend on where the target is, how it is turned or scaled, where it starts or which way it
// runs; it finds curves of four-bars it does not hold; it reads back what it writes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "optimizers/coupler_atlas.h"
#include "tests/support/random_curve.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Eigen::Vector2d> Moved(const std::vector<Eigen::Vector2d>& points, double scale,
                                   double angle, const Eigen::Vector2d& shift) {
  std::vector<Eigen::Vector2d> moved;
  const Eigen::Matrix2d rotation =
      (Eigen::Matrix2d() << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle))
          .finished();
  for (const Eigen::Vector2d& p : points) moved.push_back(scale * rotation * p + shift);
  return moved;
}

std::set<int> Indices(const std::vector<AtlasMatch>& matches) {
  std::set<int> indices;
  for (const AtlasMatch& match : matches) indices.insert(match.atlas_index);
  return indices;
}

// The best candidate's curve passes the target's points: its RMS distance from them, relative
// to the target's size.
double BestCurveFit(const std::vector<AtlasMatch>& matches, const testing::GeneratedCurve& curve) {
  double best = std::numeric_limits<double>::infinity();
  for (const AtlasMatch& match : matches) {
    best = std::min(
        best, testing::CurveRmsDistance(match.four_bar, curve.points, curve.size) / curve.size);
  }
  return best;
}

TEST(CouplerAtlas, KeysAreInvariant) {
  std::mt19937_64 rng(3401);
  for (const DyadType output : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
    testing::CurveOptions options;
    options.count = 200;
    options.uneven = false;
    const testing::GeneratedCurve closed = testing::RandomCurve(rng, output, options);
    options.closed = false;
    const testing::GeneratedCurve open = testing::RandomCurve(rng, output, options);
    const auto closed_key = ClosedShapeKey(closed.points);
    const auto open_key = OpenShapeKey(open.points);
    std::vector<Eigen::Vector2d> restarted(closed.points.begin() + 37, closed.points.end());
    restarted.insert(restarted.end(), closed.points.begin(), closed.points.begin() + 37);
    std::vector<Eigen::Vector2d> reversed(closed.points.rbegin(), closed.points.rend());
    std::vector<Eigen::Vector2d> open_reversed(open.points.rbegin(), open.points.rend());
    for (const auto& points :
         {Moved(closed.points, 1e3, 0.7, Eigen::Vector2d(1e4, -3e3)), restarted, reversed}) {
      const auto key = ClosedShapeKey(points);
      for (int k = 0; k < kClosedKeySize; ++k) EXPECT_NEAR(key[k], closed_key[k], 2e-3);
    }
    for (const auto& points :
         {Moved(open.points, 1e-3, -2.0, Eigen::Vector2d(5.0, 7.0)), open_reversed}) {
      const auto key = OpenShapeKey(points);
      for (int k = 0; k < kOpenKeySize; ++k) EXPECT_NEAR(key[k], open_key[k], 2e-3);
    }
  }
}

TEST(CouplerAtlas, CandidatesAreInvariantAndFitCurvesItDoesNotHold) {
  const CouplerAtlas& atlas = CouplerAtlas::Shared();
  EXPECT_EQ(atlas.four_bar_count(), 10000u);
  std::mt19937_64 rng(3402);
  int closed_fits = 0, open_fits = 0, tried = 0;
  for (int trial = 0; trial < 4; ++trial) {
    for (const DyadType output : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
      ++tried;
      testing::CurveOptions options;
      options.count = 60;
      const testing::GeneratedCurve closed = testing::RandomCurve(rng, output, options);
      AtlasMatchOptions closed_only;
      closed_only.match_open = false;
      const std::vector<AtlasMatch> matches = atlas.Match(closed.points, true, closed_only);
      ASSERT_FALSE(matches.empty());
      // Within 5 % of the curve's size: a seed in the refiner's reach.
      if (BestCurveFit(matches, closed) < 0.05) ++closed_fits;
      // Moved, turned, scaled, restarted and reversed: the same candidates, as well aligned.
      std::vector<Eigen::Vector2d> changed =
          Moved(closed.points, 37.0, 2.1, Eigen::Vector2d(-400.0, 900.0));
      std::rotate(changed.begin(), changed.begin() + 23, changed.end());
      std::reverse(changed.begin(), changed.end());
      const std::vector<AtlasMatch> again = atlas.Match(changed, true, closed_only);
      EXPECT_EQ(Indices(again), Indices(matches));
      ASSERT_EQ(again.size(), matches.size());
      for (size_t i = 0; i < matches.size(); ++i) {
        EXPECT_NEAR(again[i].shape_error, matches[i].shape_error, 1e-6);
      }

      options.closed = false;
      options.arc_turns = 0.25 + 0.5 * trial / 3.0;
      const testing::GeneratedCurve open = testing::RandomCurve(rng, output, options);
      AtlasMatchOptions open_only;
      open_only.match_closed = false;
      const std::vector<AtlasMatch> open_matches = atlas.Match(open.points, false, open_only);
      ASSERT_FALSE(open_matches.empty());
      if (BestCurveFit(open_matches, open) < 0.05) ++open_fits;
      std::vector<Eigen::Vector2d> open_changed =
          Moved(open.points, 0.01, -1.0, Eigen::Vector2d(3.0, 3.0));
      std::reverse(open_changed.begin(), open_changed.end());
      EXPECT_EQ(Indices(atlas.Match(open_changed, false, open_only)), Indices(open_matches));
    }
  }
  std::printf("closed curves fitted within 5 %%: %d of %d, arcs: %d of %d\n", closed_fits, tried,
              open_fits, tried);
  EXPECT_GE(closed_fits, tried - 1);
  EXPECT_GE(open_fits, tried - 1);
}

TEST(CouplerAtlas, ReadsWhatItWritesAndRefusesOtherFiles) {
  CouplerAtlasOptions small;
  small.seed = 7;
  small.closed_four_bars = 60;
  small.closed_slider_cranks = 20;
  small.closed_inverted_slider_cranks = 20;
  small.open_four_bars = small.open_slider_cranks = small.open_inverted_slider_cranks = 5;
  const CouplerAtlas built(small);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("linkfit_atlas_test_" + std::to_string(::getpid()));
  ASSERT_TRUE(built.Write(path.string()));
  const std::unique_ptr<CouplerAtlas> read = CouplerAtlas::Read(path.string(), small);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->closed_key_count(), built.closed_key_count());
  EXPECT_EQ(read->open_key_count(), built.open_key_count());
  std::mt19937_64 rng(3403);
  const testing::GeneratedCurve curve = testing::RandomCurve(rng, DyadType::kRR, {});
  EXPECT_EQ(Indices(read->Match(curve.points, true)), Indices(built.Match(curve.points, true)));
  // Built again from the same seed: the same atlas.
  EXPECT_EQ(Indices(CouplerAtlas(small).Match(curve.points, true)),
            Indices(built.Match(curve.points, true)));
  // Other options, or a damaged file: not read.
  CouplerAtlasOptions other = small;
  other.seed = 8;
  EXPECT_FALSE(CouplerAtlas::Read(path.string(), other));
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(200);
    file.put('\x5a');
  }
  EXPECT_FALSE(CouplerAtlas::Read(path.string(), small));
  std::filesystem::resize_file(path, 100);
  EXPECT_FALSE(CouplerAtlas::Read(path.string(), small));
  std::filesystem::remove(path);
  EXPECT_FALSE(CouplerAtlas::Read(path.string(), small));
}

}  // namespace
}  // namespace linkfit
