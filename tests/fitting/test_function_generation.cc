// Function generation (issue 17, items 7 and 9): random four-bars make pairs, the exact solvers
// give the generator back.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fitting/function_generation.h"
#include "lib/function_samples.h"
#include "tests/support/random_function.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Exact data: the generator's lengths (times the ground) and offsets (radians) back to this.
constexpr double kExactTolerance = 1e-7;

bool SameGenerator(const FunctionFourBar& found, const FunctionFourBar& truth, double tolerance) {
  return found.assembly == truth.assembly &&
         std::abs(found.input_length - truth.input_length) <= tolerance &&
         std::abs(found.coupler_length - truth.coupler_length) <= tolerance &&
         std::abs(found.output_length - truth.output_length) <= tolerance &&
         std::abs(WrapToPi(found.input_offset - truth.input_offset)) <= tolerance &&
         std::abs(WrapToPi(found.output_offset - truth.output_offset)) <= tolerance;
}

TEST(FunctionGeneration, ThreeAbsolutePairsGiveTheGeneratorBack) {
  std::mt19937_64 rng(1701);
  for (int trial = 0; trial < 200; ++trial) {
    const testing::FunctionTask task = testing::RandomFunctionTask(rng, 3, false);
    std::vector<FunctionFourBar> found;
    std::string why;
    ASSERT_EQ(SolveFreudenstein(task.pairs, 1.0, &found, &why), 1) << "trial " << trial << why;
    EXPECT_TRUE(SameGenerator(found[0], task.four_bar, kExactTolerance)) << "trial " << trial;
    const FunctionAnalysis analysis = AnalyzeFunctionFourBar(found[0], task.pairs);
    ASSERT_TRUE(analysis.max_error) << "trial " << trial;
    EXPECT_LT(*analysis.max_error, 1e-9) << "trial " << trial;
    EXPECT_TRUE(analysis.defects.empty()) << "trial " << trial;
  }
}

TEST(FunctionGeneration, FiveRelativePairsGiveEveryFourBarWithTheGenerator) {
  std::mt19937_64 rng(1702);
  int listed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const testing::FunctionTask task = testing::RandomFunctionTask(rng, 5, true);
    std::vector<FunctionFourBar> found;
    ASSERT_GE(SolveRelativeFunction(task.pairs, 1.0, {}, &found), 1) << "trial " << trial;
    ASSERT_LE(found.size(), 3u) << "trial " << trial;  // four roots, one the ground link
    bool generator = false;
    for (const FunctionFourBar& f : found) {
      generator = generator || SameGenerator(f, task.four_bar, kExactTolerance);
      // Every four-bar listed generates the pairs (on the assembly of the first).
      const FunctionAnalysis analysis = AnalyzeFunctionFourBar(f, task.pairs);
      if (analysis.defects.empty()) {
        ASSERT_TRUE(analysis.max_error);
        EXPECT_LT(*analysis.max_error, 1e-7) << "trial " << trial;
      }
    }
    listed += generator;
    EXPECT_TRUE(generator) << "trial " << trial;
  }
  EXPECT_EQ(listed, 200);
}

TEST(FunctionGeneration, ACrankOppositeItsAngleIsNoFourBar) {
  // The pairs of a four-bar with the input angles read half a turn off: Freudenstein's
  // equation is met by a negative input crank, which points opposite its prescribed angle.
  std::mt19937_64 rng(1703);
  const testing::FunctionTask task = testing::RandomFunctionTask(rng, 3, false);
  std::vector<FunctionPair> turned = task.pairs;
  for (FunctionPair& pair : turned) pair.input += kPi;
  std::vector<FunctionFourBar> found;
  std::string why;
  EXPECT_EQ(SolveFreudenstein(turned, 1.0, &found, &why), 0);
  EXPECT_NE(why.find("negative input crank"), std::string::npos) << why;
  EXPECT_TRUE(found.empty());
}

TEST(FunctionGeneration, RepeatedPairsAreDependent) {
  std::vector<FunctionPair> pairs(3);
  pairs[0].input = pairs[1].input = 0.3;
  pairs[0].output = pairs[1].output = 1.2;
  pairs[2].input = 0.8;
  pairs[2].output = 1.5;
  std::vector<FunctionFourBar> found;
  std::string why;
  EXPECT_EQ(SolveFreudenstein(pairs, 1.0, &found, &why), 0);
  EXPECT_NE(why.find("dependent"), std::string::npos) << why;
}

TEST(FunctionGeneration, ManyPairsLinearFitIsExactOnExactData) {
  std::mt19937_64 rng(1704);
  for (int trial = 0; trial < 50; ++trial) {
    const testing::FunctionTask task = testing::RandomFunctionTask(rng, 12, false);
    std::vector<FunctionFourBar> found;
    ASSERT_EQ(SolveFreudenstein(task.pairs, 1.0, &found), 1);
    EXPECT_TRUE(SameGenerator(found[0], task.four_bar, kExactTolerance)) << "trial " << trial;
  }
}

TEST(FunctionGeneration, ChebyshevPointsAndTheSpline) {
  const std::vector<double> points = ChebyshevPoints(1.0, 3.0, 3);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_NEAR(points[0], 2.0 - std::cos(kPi / 6.0), 1e-15);
  EXPECT_NEAR(points[1], 2.0, 1e-15);
  EXPECT_NEAR(points[2], 2.0 + std::cos(kPi / 6.0), 1e-15);
  // A natural cubic spline reproduces a line exactly, and a smooth function from dense samples.
  std::vector<double> x, line, sine;
  for (int i = 0; i <= 40; ++i) {
    x.push_back(0.05 * i * i / 40.0 + 0.05 * i);  // uneven spacing
    line.push_back(3.0 * x.back() - 1.0);
    sine.push_back(std::sin(x.back()));
  }
  const NaturalCubicSpline line_spline(x, line), sine_spline(x, sine);
  // (Away from the ends, where the natural spline's zero curvature is an assumption.)
  for (double at : {0.013, 0.5, 1.111, 3.2}) {
    EXPECT_NEAR(line_spline(at), 3.0 * at - 1.0, 1e-12);
    EXPECT_NEAR(sine_spline(at), std::sin(at), 1e-4) << at;
  }
}

TEST(FunctionAnalysis, BranchAndCircuitDefects) {
  // A double-rocker (the coupler shortest): its input is limited to about 15.6 to 89.8 degrees,
  // and the other assembly is reached only through a stationary configuration.
  FunctionFourBar f;
  f.ground = 1.0;
  f.input_length = 1.5;
  f.coupler_length = 0.6;
  f.output_length = 1.2;
  f.assembly = 1;
  std::vector<FunctionPair> pairs;
  for (double phi : {0.4, 0.8, 1.2}) {
    FunctionPair pair;
    pair.input = phi;
    ASSERT_TRUE(f.Output(phi, &pair.output));
    pairs.push_back(pair);
  }
  FunctionAnalysis analysis = AnalyzeFunctionFourBar(f, pairs);
  EXPECT_FALSE(analysis.input_rotates_fully);
  EXPECT_TRUE(analysis.defects.empty());
  EXPECT_EQ(analysis.grashof, "double-rocker");
  // The last pair on the other assembly: a branch defect.
  ASSERT_TRUE(f.Output(1.2, -1, &pairs[2].output));
  analysis = AnalyzeFunctionFourBar(f, pairs);
  EXPECT_EQ(analysis.defects, std::vector<std::string>{"branch"});
  // A crank-rocker: its assemblies are two circuits.
  f.input_length = 0.4;
  f.coupler_length = 1.1;
  f.output_length = 0.8;
  for (FunctionPair& pair : pairs) ASSERT_TRUE(f.Output(pair.input, &pair.output));
  EXPECT_TRUE(AnalyzeFunctionFourBar(f, pairs).input_rotates_fully);
  ASSERT_TRUE(f.Output(1.2, -1, &pairs[2].output));
  EXPECT_EQ(AnalyzeFunctionFourBar(f, pairs).defects, std::vector<std::string>{"circuit"});
  // An input out of the crank's reach: a circuit defect too.
  f.input_length = 1.5;
  f.coupler_length = 0.6;
  f.output_length = 1.2;
  pairs[2].input = 2.0;
  EXPECT_EQ(AnalyzeFunctionFourBar(f, pairs).defects, std::vector<std::string>{"circuit"});
}

TEST(FunctionAnalysis, TransmissionAngleAgreesWithSampling) {
  std::mt19937_64 rng(1705);
  for (int trial = 0; trial < 50; ++trial) {
    const testing::FunctionTask task = testing::RandomFunctionTask(rng, 4, true);
    const FunctionFourBar& f = task.four_bar;
    const FunctionAnalysis analysis = AnalyzeFunctionFourBar(f, task.pairs);
    ASSERT_TRUE(analysis.transmission_min_deg && analysis.transmission_max_deg);
    double low = 90.0, high = 0.0;
    const double start = task.pairs.front().input, end = task.pairs.back().input;
    for (int k = 0; k <= 2000; ++k) {
      const double phi = start + (end - start) * k / 2000.0;
      const auto at = ConfigurationAt(f, phi, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX());
      ASSERT_TRUE(at);
      const Eigen::Vector2d coupler = at->input_moving - at->output_moving;
      const Eigen::Vector2d crank = at->output_pivot - at->output_moving;
      double mu = std::acos(coupler.normalized().dot(crank.normalized())) * 180.0 / kPi;
      mu = std::min(mu, 180.0 - mu);
      low = std::min(low, mu);
      high = std::max(high, mu);
    }
    EXPECT_NEAR(*analysis.transmission_min_deg, low, 0.05) << "trial " << trial;
    EXPECT_NEAR(*analysis.transmission_max_deg, high, 0.05) << "trial " << trial;
  }
}

}  // namespace
}  // namespace linkfit
