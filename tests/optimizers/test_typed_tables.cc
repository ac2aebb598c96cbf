// Tables typed as people type them (issue 35, item 3): the same poses written with their trailing
// zeros ("1.200") and without them (Python's json.dump writes 1.2) give the same precision and
// the same first mechanism; where the precision as written cannot tell a slider from a circle
// that a finer table would list, a note says so and which way the data lean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "lib/task_io.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

// `value` to `decimals` fixed decimals, its trailing zeros kept, or dropped as Python's repr of
// the rounded float drops them (one digit after the point stays: "3.0").
std::string Fixed(double value, int decimals, bool keep_zeros, const std::string& padding = "") {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  std::string written = text;
  if (written[0] == '-' && std::stod(written) == 0.0) written = written.substr(1);  // -0.00
  if (!keep_zeros) {
    while (written.back() == '0' && written[written.size() - 2] != '.') written.pop_back();
  }
  return written + padding;
}

std::string Table(const std::vector<PlanarPose>& poses, int decimals, bool keep_zeros,
                  const std::string& padding = "") {
  std::string text = "{\"problem\": \"motion\", \"space\": \"planar\", \"poses\": [";
  for (size_t j = 0; j < poses.size(); ++j) {
    text +=
        (j > 0 ? ", " : "") + std::string("{\"x\": ") +
        Fixed(poses[j].origin_in_fixed.x(), decimals, keep_zeros, padding) +
        ", \"y\": " + Fixed(poses[j].origin_in_fixed.y(), decimals, keep_zeros, padding) +
        ", \"theta_deg\": " + Fixed(poses[j].theta * 180.0 / M_PI, decimals, keep_zeros, padding) +
        "}";
  }
  return text + "]}";
}

std::vector<PlanarPose> Scaled(std::vector<PlanarPose> poses, double factor) {
  for (PlanarPose& pose : poses) pose.origin_in_fixed *= factor;
  return poses;
}

// Random 4Rs and slider-cranks (scaled to a table's tens of units), five and twelve poses,
// printed to 2, 3 and 4 decimals both ways: the same precision, the same first type and the
// same first four-bar.
TEST(TypedTables, TrailingZerosDoNotChangeTheAnswer) {
  std::mt19937_64 rng(3531);
  for (const int count : {5, 12}) {
    for (const bool slider : {false, true}) {
      const testing::GeneratedTask generated = slider ? testing::RandomSliderCrankTask(rng, count)
                                                      : testing::RandomFourBarTask(rng, count);
      const std::vector<PlanarPose> poses = Scaled(generated.poses, 20.0);
      for (const int decimals : {2, 3, 4}) {
        SCOPED_TRACE(std::to_string(count) + " poses, " + (slider ? "slider-crank" : "4R") + ", " +
                     std::to_string(decimals) + " decimals");
        const Task padded = ParseTask(Table(poses, decimals, true), "padded.json");
        const Task dropped = ParseTask(Table(poses, decimals, false), "dropped.json");
        EXPECT_EQ(padded.precision.length, dropped.precision.length);
        EXPECT_EQ(padded.precision.angle, dropped.precision.angle);
        const PlanarMotionResult a = SolvePlanarTask(padded);
        const PlanarMotionResult b = SolvePlanarTask(dropped);
        ASSERT_EQ(a.mechanisms.empty(), b.mechanisms.empty());
        if (a.mechanisms.empty()) continue;
        const MechanismReport& first_a = a.mechanisms.front();
        const MechanismReport& first_b = b.mechanisms.front();
        EXPECT_EQ(first_a.type, first_b.type);
        EXPECT_EQ(first_a.max_pose_error, first_b.max_pose_error);
        const PlanarDyad& input_a = a.dyads[first_a.input_dyad].dyad;
        const PlanarDyad& input_b = b.dyads[first_b.input_dyad].dyad;
        EXPECT_EQ(input_a.fixed_pivot, input_b.fixed_pivot);
        EXPECT_EQ(input_a.moving_pivot, input_b.moving_pivot);
      }
    }
  }
}

// Five poses of a 4R whose output crank (300 units, 30 times its input crank) bows off a line
// by about a hundredth of the table's size over the poses. Printed to 2 decimals the precision
// cannot tell the crank from a slider: the slider-crank comes first, and a note says that the
// same numbers with two more decimals would list the 4R and which way the data lean. The same
// numbers padded with two zeros (4 decimals claimed) list the 4R first, without that note.
TEST(TypedTables, WhenThePrecisionCannotTellTheModelsApartANoteSaysWhichWayTheDataLean) {
  const Eigen::Vector2d input_pivot(0.0, -10.0), output_pivot(20.0, -300.0);
  const double crank = 10.0, coupler = 20.0, output_crank = 300.0;
  std::vector<PlanarPose> poses;
  double theta = 0.0;  // the coupler's angle, followed continuously
  for (int k = 0; k < 5; ++k) {
    const double phi = (90.0 - 25.0 * k) * M_PI / 180.0;
    const Eigen::Vector2d pin = input_pivot + crank * Eigen::Vector2d(std::cos(phi), std::sin(phi));
    for (int iteration = 0; iteration < 60; ++iteration) {  // |pin + c e(theta) - B| = R
      const Eigen::Vector2d e(std::cos(theta), std::sin(theta));
      const Eigen::Vector2d arm = pin + coupler * e - output_pivot;
      const double f = arm.squaredNorm() - output_crank * output_crank;
      const double df = 2.0 * arm.dot(coupler * Eigen::Vector2d(-e.y(), e.x()));
      theta -= f / df;
    }
    poses.emplace_back(pin.x(), pin.y(), theta);
  }
  const auto has_lean_note = [](const PlanarMotionResult& result) {
    for (const std::string& note : result.notes) {
      if (note.find("the data lean to the") != std::string::npos) return true;
    }
    return false;
  };
  const PlanarMotionResult coarse = SolvePlanarTask(ParseTask(Table(poses, 2, false), "t.json"));
  ASSERT_FALSE(coarse.mechanisms.empty());
  EXPECT_EQ(coarse.mechanisms.front().type, FourBarType::kSliderCrank);
  EXPECT_TRUE(has_lean_note(coarse));
  const PlanarMotionResult padded =
      SolvePlanarTask(ParseTask(Table(poses, 2, true, "00"), "t.json"));
  ASSERT_FALSE(padded.mechanisms.empty());
  EXPECT_EQ(padded.mechanisms.front().type, FourBarType::k4R);
  EXPECT_FALSE(has_lean_note(padded));
}

}  // namespace
}  // namespace linkfit
