// `linkfit bench`: the extremes sweep must find no wrong and no non-finite answer, the planar /
// spatial switch must not flap, the trade table must come out as CSV and SVG, its spherical rows
// must solve exact data, on the trade's tasks a higher effort level must never be worse than a
// lower one, and the constrained families must come out as CSV (their targets are measured by
// the bench, not here).
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/constrained_bench.h"
#include "bench/extremes_bench.h"
#include "bench/trade_bench.h"
#include "gtest/gtest.h"

namespace linkfit {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

int Count(const std::string& text, const std::string& what) {
  int count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++count;
  }
  return count;
}

TEST(ExtremesBench, NoWrongOrNonFiniteAnswerAndNoFlapping) {
  BenchOptions options;
  options.quick = true;
  const std::vector<ExtremeRow> rows = RunExtremesBench(options, nullptr);
  ASSERT_GE(rows.size(), 50u);
  int tasks = 0, right = 0;
  for (const ExtremeRow& row : rows) {
    SCOPED_TRACE(row.family + ": " + row.variant);
    EXPECT_GT(row.tasks, 0);
    EXPECT_EQ(row.right + row.noted + row.wrong + row.non_finite, row.tasks);
    if (row.family == "rounded" && row.variant.find("free timing") != std::string::npos) {
      // Free timing's search does not always reach an exact fit (measured in trade.csv): a
      // wrong answer there must be such a miss (no listed four-bar meets the points within
      // their precision), never a wrong four-bar that fits them.
      const std::string misses = "search miss " + std::to_string(row.wrong);
      EXPECT_TRUE(row.wrong == 0 || row.detail.find(misses) != std::string::npos) << row.detail;
    } else {
      EXPECT_EQ(row.wrong, 0) << "worst error " << row.worst_error << ", " << row.detail;
    }
    EXPECT_EQ(row.non_finite, 0) << row.detail;
    tasks += row.tasks;
    right += row.right;
    if (row.family == "planarity") {
      // Every task of a tilt level gets the same model: planar below the tolerance (1e-8 L),
      // spatial above it.
      const bool below = row.variant.find("tilted 0 ") != std::string::npos ||
                         row.variant.find("tilted 1e-09") != std::string::npos ||
                         row.variant.find("tilted 3e-09") != std::string::npos;
      EXPECT_EQ(row.detail,
                std::string(below ? "planar " : "spatial ") + std::to_string(row.tasks));
    }
    if (row.family == "slider" && row.variant.find("slider-crank") != std::string::npos) {
      EXPECT_EQ(row.detail, "PR " + std::to_string(row.tasks));  // a slider is a slider
    }
    if (row.family == "slider" && (row.variant.find("radius 100 L") != std::string::npos ||
                                   row.variant.find("radius 10000 L") != std::string::npos)) {
      EXPECT_EQ(row.detail, "RR " + std::to_string(row.tasks));  // a circle is a circle
    }
    if (row.family == "slider" && row.variant.find("radius 1e+08 L") != std::string::npos) {
      // A centre 1e8 L away is stored to ulp(1e8): no better than the slider.
      EXPECT_EQ(row.detail, "PR " + std::to_string(row.tasks));
    }
  }
  // Notes are for the truly ill-conditioned cases: most tasks come back right.
  EXPECT_GE(right, 0.9 * tasks);
  const std::string csv = ExtremesCsv(rows);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "family,variant,tolerance,tasks,right,noted,wrong,non_finite,worst_error,detail");
  EXPECT_EQ(Count(csv, "\n"), static_cast<int>(rows.size()) + 1);
}

TEST(TradeBench, CsvAndSvgOfATable) {
  std::vector<TradeRow> rows;
  for (const double noise : {0.0, 1e-3, 1e-2}) {
    for (const char* effort : {"fast", "balanced", "thorough"}) {
      TradeRow row;
      row.family = "planar motion";
      row.items = 10;
      row.noise = noise;
      row.path = "planar least squares";
      row.effort = effort;
      row.tasks = 4;
      row.median_ms = effort[0] == 'f' ? 2.0 : effort[0] == 'b' ? 20.0 : 200.0;
      row.worst_ms = 2 * row.median_ms;
      row.median_error = noise == 0.0 ? 1e-15 : effort[0] == 'f' ? 3.0 : 0.9;
      row.worst_error = noise == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
      row.success_share = 0.75;
      if (effort[0] != 'f') row.optimum_share = 1.0;
      rows.push_back(row);
    }
    TradeRow exact;
    exact.family = "timed path";
    exact.items = 5;
    exact.noise = noise;
    exact.path = "path exact";
    exact.effort = "exact";
    exact.tasks = 10;
    exact.median_ms = 0.05;
    exact.median_error = noise == 0.0 ? 1e-14 : 1e-12;
    exact.success_share = 1.0;
    rows.push_back(exact);
  }
  const std::string csv = TradeCsv(rows);
  std::istringstream lines(csv);
  std::string header, first;
  std::getline(lines, header);
  std::getline(lines, first);
  EXPECT_EQ(header,
            "family,path,effort,tasks,median_ms,worst_ms,median_error,worst_error,success_share,"
            "items,noise,error_unit,optimum_share");
  // Not measured (fast here, minimal data): an empty optimum_share.
  EXPECT_EQ(first,
            "planar motion 10 poses noise 0,planar least squares,fast,4,2,4,1e-15,0,0.75,"
            "10,0,L,");
  EXPECT_NE(csv.find("timed path 5 points noise 0.01,path exact,exact,10,0.05,0,1e-12,0,1,5,"
                     "0.01,ratio,\n"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",inf,0.75,10,0.001,ratio,1\n"), std::string::npos);  // no solution: inf
  const std::string svg = TradeSvg(rows);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(Count(svg, "</svg>"), 1);
  // Three panels, two curves each (the least-squares path and the exact one).
  EXPECT_EQ(Count(svg, "<polyline"), 6);
  EXPECT_EQ(Count(svg, "nan"), 0);
  EXPECT_EQ(Count(svg, "inf"), 0);
}

// `--family` picks trade rows too: a family, and its rows of a number of items.
TEST(TradeBench, FamilyRunsOnlyItsRows) {
  BenchOptions options;
  options.quick = true;
  options.family = "timed path:5";
  const std::vector<TradeRow> rows = RunTradeBench(options, nullptr);
  ASSERT_EQ(rows.size(), 3u);  // the exact solver at three noise levels
  for (const TradeRow& row : rows) {
    EXPECT_EQ(row.family, "timed path");
    EXPECT_EQ(row.items, 5);
    EXPECT_EQ(row.path, "path exact");
  }
  options.family = "rounded";  // an extremes family: no trade rows
  EXPECT_TRUE(RunTradeBench(options, nullptr).empty());
}

// The spherical motion rows, quick: on exact data the exact solver of five orientations and every
// effort level of ten orientations find the generating four-bar (or one as good) in every task,
// each result recognised as spherical (a task solved otherwise counts as a miss). Not twenty
// orientations: drawing such a task takes about 0.1 s (SphericalFourBarRotations' spacing).
TEST(TradeBench, SphericalMotionSolvesExactData) {
  BenchOptions options;
  options.quick = true;
  std::vector<TradeRow> rows;
  for (const char* family : {"spherical motion:5", "spherical motion:10"}) {
    options.family = family;
    const std::vector<TradeRow> part = RunTradeBench(options, nullptr);
    rows.insert(rows.end(), part.begin(), part.end());
  }
  ASSERT_EQ(rows.size(), 3u + 3u * 3u);  // three noise levels: exact, or three efforts
  for (const TradeRow& row : rows) {
    SCOPED_TRACE(row.family + " " + std::to_string(row.items) + ", noise " +
                 FormatNumber(row.noise) + ", " + row.effort);
    EXPECT_EQ(row.path, row.items == 5 ? "spherical exact" : "spherical least squares");
    EXPECT_GT(row.tasks, 0);
    if (row.noise == 0.0) {
      EXPECT_EQ(row.success_share, 1.0) << "worst error " << row.worst_error << " L";
    } else {
      EXPECT_TRUE(std::isfinite(row.median_error)) << row.median_error;
    }
  }
}

// Effort levels compared like for like: each task of a trade family (trade_bench.h: the same
// generator and the same final error, in L for exact data, against the generating mechanism's
// for noisy data) solved at fast, balanced and thorough. A higher level keeps the candidates of
// a lower one, so it is never worse: only rounding may tell two equal answers apart.
constexpr double kEffortRelativeSlack = 1e-9;
constexpr double kEffortAbsoluteSlack = 1e-12;  // L (exact data) or ratio (noisy data)

// Tasks drawn from seeds first_seed, first_seed + 1, ...
void ExpectEffortOrder(const std::string& family, int items, double noise, uint64_t first_seed,
                       int tasks) {
  const Effort efforts[] = {Effort::kFast, Effort::kBalanced, Effort::kThorough};
  const char* names[] = {"fast", "balanced", "thorough"};
  for (int t = 0; t < tasks; ++t) {
    const uint64_t seed = first_seed + t;
    double error[3];
    for (int level = 0; level < 3; ++level) {
      std::mt19937_64 rng(seed);  // the same task at every effort level
      error[level] = RunTradeTask(family, items, noise, efforts[level], rng).error;
    }
    for (int level = 1; level < 3; ++level) {
      EXPECT_LE(error[level],
                error[level - 1] * (1.0 + kEffortRelativeSlack) + kEffortAbsoluteSlack)
          << family << ", " << items << " items, noise " << noise << ", seed " << seed << ": "
          << names[level] << " worse than " << names[level - 1] << std::setprecision(17)
          << " (fast " << error[0] << ", balanced " << error[1] << ", thorough " << error[2] << ")";
    }
  }
}

// Before the lower levels' candidates were kept, noisy seeds 6, 10, 12 and 20 had a higher level
// worse (a search or refined dyad pushing balanced's four-bar out, or out of the refined few; a
// mechanism-level refinement worse once re-analysed).
TEST(EffortOrder, PlanarMotionLeastSquares) {
  for (const double noise : {0.0, 1e-3, 1e-2}) ExpectEffortOrder("planar motion", 10, noise, 1, 24);
}

TEST(EffortOrder, TimedPathPrescribedTiming) {
  for (const double noise : {0.0, 1e-2}) ExpectEffortOrder("timed path", 10, noise, 1, 8);
}

// Noisy seed 102: fast's four-bars were the only defect-free ones, and balanced refined them away.
TEST(EffortOrder, PathFreeTiming) {
  ExpectEffortOrder("untimed path", 10, 0.0, 100, 3);
  ExpectEffortOrder("untimed path", 10, 1e-2, 100, 4);
}

// A tiny constrained bench: two tasks of one random family and one classic problem, each row
// with finite figures, the CSV with its header and one line per row.
TEST(ConstrainedBench, RowsComeOutAsCsv) {
  BenchOptions options;
  options.constrained_tasks = 2;
  for (const std::string family :
       {"constrained:10 points, fixed box", "constrained:classic: 5 points timed"}) {
    options.family = family;
    const std::vector<ConstrainedRow> rows = RunConstrainedBench(options, nullptr);
    ASSERT_EQ(rows.size(), 2u) << family;  // balanced and thorough
    for (const ConstrainedRow& row : rows) {
      SCOPED_TRACE(row.family + ", " + row.effort);
      EXPECT_EQ(row.tasks, family.find("classic") != std::string::npos ? 1 : 2);
      for (const double figure :
           {row.median_ms, row.worst_ms, row.share_within_10pct, row.share_first_is_best,
            row.share_bound_active, row.long_median_ms}) {
        EXPECT_TRUE(std::isfinite(figure)) << figure;
        EXPECT_GE(figure, 0.0);
      }
      EXPECT_LE(row.share_within_10pct, 1.0);
      EXPECT_LE(row.share_first_is_best, 1.0);
      EXPECT_LE(row.median_ms, row.worst_ms);
      EXPECT_GT(row.median_ratio, 0.0);  // inf where the first does not keep the constraints
    }
    const std::string csv = ConstrainedCsv(rows);
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "family,effort,tasks,median_ms,worst_ms,share_within_10pct,share_first_is_best,"
              "median_ratio,worst_ratio,share_bound_active,long_median_ms,detail");
    EXPECT_EQ(Count(csv, "\n"), 3);
    EXPECT_EQ(Count(csv, "nan"), 0);
  }
  options.family = "rounded";  // another part's family: no constrained rows
  EXPECT_TRUE(RunConstrainedBench(options, nullptr).empty());
}

TEST(BenchCli, WritesTheSweepAndRefusesAnUnwritableDirectory) {
  char pattern[] = "/tmp/linkfit_bench_XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::string dir = pattern;
  const std::string command = std::string("'") + LINKFIT_BINARY +
                              "' bench --quick --extremes-only -o '" + dir + "/out' >'" + dir +
                              "/stdout' 2>'" + dir + "/stderr'";
  int raw = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 0) << ReadFile(dir + "/stderr");
  EXPECT_EQ(ReadFile(dir + "/stderr"), "");
  const std::string csv = ReadFile(dir + "/out/extremes.csv");
  EXPECT_EQ(csv.rfind("family,variant,", 0), 0u);
  EXPECT_NE(ReadFile(dir + "/stdout").find("stability at the extremes"), std::string::npos);
  // The constrained part alone, one classic problem (five timed points: solved exactly).
  raw = std::system((std::string("'") + LINKFIT_BINARY +
                     "' bench --constrained-only --family 'constrained:5 points timed' -o '" + dir +
                     "/constrained' >'" + dir + "/stdout' 2>'" + dir + "/stderr'")
                        .c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 0) << ReadFile(dir + "/stderr");
  const std::string constrained = ReadFile(dir + "/constrained/constrained.csv");
  EXPECT_EQ(constrained.rfind("family,effort,tasks,", 0), 0u);
  EXPECT_EQ(Count(constrained, "\n"), 3) << constrained;
  EXPECT_FALSE(std::filesystem::exists(dir + "/constrained/trade.csv"));
  // A file where the directory should be: exit 2, one line.
  std::ofstream(dir + "/file") << "x";
  raw = std::system((std::string("'") + LINKFIT_BINARY + "' bench --quick -o '" + dir +
                     "/file' >/dev/null 2>'" + dir + "/stderr'")
                        .c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 2);
  const std::string error = ReadFile(dir + "/stderr");
  EXPECT_EQ(Count(error, "\n"), 1) << error;
  EXPECT_NE(error.find("cannot create the output directory"), std::string::npos) << error;
  // Two "only" flags: a usage error.
  for (const char* flags : {"--trade-only --extremes-only", "--constrained-only --trade-only",
                            "--extremes-only --constrained-only"}) {
    raw = std::system((std::string("'") + LINKFIT_BINARY + "' bench " + flags + " >/dev/null 2>'" +
                       dir + "/stderr'")
                          .c_str());
    ASSERT_TRUE(WIFEXITED(raw));
    EXPECT_EQ(WEXITSTATUS(raw), 2) << flags;
    EXPECT_EQ(Count(ReadFile(dir + "/stderr"), "\n"), 1) << flags;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace linkfit
