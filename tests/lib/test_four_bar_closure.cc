// The four-bar's closure in closed form (lib/four_bar_closure.h) against its oracles: the
// assembly at each input value (AssembleFourBar) and the sampled trace (TraceFourBar), on random
// four-bars of all nine dyad-type pairs; and where sampling fails, a feasible arc narrower than a
// sampling step.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "lib/four_bar_closure.h"
#include "lib/four_bar_motion.h"
#include "lib/mechanism.h"
#include "tests/support/moved_design.h"
#include "tests/support/random_mechanism.h"

namespace linkfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance of `value` from the nearest finite interval end (angle inputs: around the turn).
double DistanceToEnd(const FourBarClosure& closure, double value) {
  double nearest = std::numeric_limits<double>::infinity();
  const auto consider = [&](double end) {
    double d = std::abs(value - end);
    if (closure.angle_input) {
      d = std::fmod(d, 2.0 * kPi);
      d = std::min(d, 2.0 * kPi - d);
    }
    nearest = std::min(nearest, d);
  };
  for (const ClosureInterval& interval : closure.intervals) {
    if (closure.full_turn) break;
    if (!interval.open_start) consider(interval.start);
    if (!interval.open_end) consider(interval.end);
  }
  for (double value_at : closure.singular) consider(value_at);
  return nearest;
}

// Calls visit(a, b, trial) for `trials` trials of each of the nine dyad-type pairs (a, b).
template <typename Visit>
void ForEachTypePair(int trials, const Visit& visit) {
  for (DyadType a : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
    for (DyadType b : {DyadType::kRR, DyadType::kPR, DyadType::kRP}) {
      for (int trial = 0; trial < trials; ++trial) visit(a, b, trial);
    }
  }
}

TEST(FourBarClosure, AgreesWithTheAssemblyAtEveryInputValue) {
  std::mt19937_64 rng(1616);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  int checked = 0, assembled = 0, limited = 0;
  for (DyadType a : types) {
    for (DyadType b : types) {
      for (int trial = 0; trial < 30; ++trial) {
        const testing::GeneratedTask task = testing::RandomTask(rng, a, b);
        // Both ways round: each dyad as the input.
        for (int way = 0; way < 2; ++way) {
          const PlanarDyad& input = way == 0 ? task.input : task.output;
          const PlanarDyad& output = way == 0 ? task.output : task.input;
          const FourBarClosure closure = SolveFourBarClosure(input, output);
          SCOPED_TRACE(std::string(DyadTypeName(input.type)) + "+" + DyadTypeName(output.type) +
                       " trial " + std::to_string(trial));
          // The generating motion passes every task pose: each pose's input value assembles.
          for (const PlanarPose& pose : task.poses) {
            EXPECT_GE(ClosureIntervalOf(closure, InputValue(input, pose), 1e-9), 0);
          }
          limited += !closure.full_turn;
          // Input values: a turn, or the slider's task range widened three times each way.
          double lo = -kPi, hi = kPi;
          if (!closure.angle_input) {
            lo = hi = InputValue(input, task.poses[0]);
            for (const PlanarPose& pose : task.poses) {
              lo = std::min(lo, InputValue(input, pose));
              hi = std::max(hi, InputValue(input, pose));
            }
            const double margin = 3.0 * std::max(hi - lo, 1.0);
            lo -= margin;
            hi += margin;
          }
          std::uniform_real_distribution<double> value_of(lo, hi);
          std::vector<PlanarPose> configurations;
          for (int k = 0; k < 400; ++k) {
            const double value = value_of(rng);
            // Within 1e-7 of an end, rounding decides either way.
            if (DistanceToEnd(closure, value) < 1e-7) continue;
            const int count = AssembleFourBar(input, output, value, 0.0, &configurations);
            const int interval = ClosureIntervalOf(closure, value);
            ASSERT_EQ(count > 0, interval >= 0) << "input value " << value;
            if (count > 0) {
              EXPECT_EQ(count, closure.labels);
              ++assembled;
            }
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 200000);
  EXPECT_GT(assembled, checked / 2);
  EXPECT_GT(limited, 100);  // not only full turns
}

// At a finite interval end the two assembly solutions meet: a stationary configuration.
TEST(FourBarClosure, IntervalEndsAreStationaryConfigurations) {
  std::mt19937_64 rng(1617);
  int ends = 0;
  ForEachTypePair(20, [&](DyadType a, DyadType b, int) {
    const testing::GeneratedTask task = testing::RandomTask(rng, a, b);
    const double length = CharacteristicLength(task.poses);
    const FourBarClosure closure = SolveFourBarClosure(task.input, task.output);
    if (closure.full_turn || closure.labels != 2) return;
    std::vector<PlanarPose> configurations;
    for (const ClosureInterval& interval : closure.intervals) {
      for (int side = 0; side < 2; ++side) {
        if (side == 0 ? interval.open_start : interval.open_end) continue;
        const double end = side == 0 ? interval.start : interval.end;
        const int count =
            AssembleFourBar(task.input, task.output, end, 1e-9 * length, &configurations);
        ASSERT_EQ(count, 2) << DyadTypeName(a) << DyadTypeName(b) << " end " << end;
        EXPECT_LT(PoseError(configurations[0], configurations[1], length), 1e-5);
        ++ends;
      }
    }
  });
  EXPECT_GT(ends, 100);
}

// The sampled trace's circuits and full turns agree with the closed form on random four-bars:
// a full turn has a circuit per label that rotates fully; each limited interval is one circuit
// of two branches.
TEST(FourBarClosure, AgreesWithTheSampledTrace) {
  std::mt19937_64 rng(1618);
  int compared = 0;
  ForEachTypePair(20, [&](DyadType a, DyadType b, int trial) {
    const testing::GeneratedTask task = testing::RandomTask(rng, a, b);
    const double length = CharacteristicLength(task.poses);
    const FourBarClosure closure = SolveFourBarClosure(task.input, task.output);
    if (!closure.angle_input || closure.labels != 2) return;
    // Intervals wider than a few sampling steps (0.5 degrees) are what the sampler sees.
    bool wide = true;
    for (const ClosureInterval& interval : closure.intervals) {
      wide = wide && interval.Extent() > 4.0 * kPi / 360.0;
    }
    if (!wide) return;
    const FourBarMotion motion = TraceFourBar(task.input, task.output, task.poses, length);
    SCOPED_TRACE(std::string(DyadTypeName(a)) + DyadTypeName(b) + " trial " +
                 std::to_string(trial));
    if (closure.full_turn) {
      ASSERT_EQ(motion.circuits.size(), 2u);
      for (const FourBarCircuit& circuit : motion.circuits) {
        EXPECT_TRUE(circuit.input_rotates_fully);
      }
    } else {
      ASSERT_EQ(motion.circuits.size(), closure.intervals.size());
      for (const FourBarCircuit& circuit : motion.circuits) {
        EXPECT_EQ(circuit.branches, 2);
        // The sampled extent falls short of the true one by less than two steps.
        const int interval = ClosureIntervalOf(closure, circuit.input_start);
        ASSERT_GE(interval, 0);
        const double extent = closure.intervals[interval].Extent();
        EXPECT_LE(circuit.input_extent, extent + 1e-12);
        EXPECT_GT(circuit.input_extent, extent - 2.0 * circuit.input_step);
      }
    }
    ++compared;
  });
  EXPECT_GT(compared, 60);
}

// A crank whose feasible arc (0.2 degrees) lies between two of the trace's samples (every 0.5
// degrees): the sampled trace finds no motion at all, the closed form finds the arc, and the
// four-bar assembles at its middle.
TEST(FourBarClosure, FindsAnArcBetweenTwoSamples) {
  // Crank about the origin, radius 1; output pivot at distance 2, placed so that the farthest
  // crank position (where |M1 - F2| = 3) lies a quarter step past the sample at -pi.
  const double centre = -kPi + 0.25 * (2.0 * kPi / 720.0);
  const Eigen::Vector2d crank_pin(std::cos(centre), std::sin(centre));
  const Eigen::Vector2d output_pivot = -2.0 * crank_pin;
  // Coupler side |v| = 4 (the rocker's pin on the crank line, in E as in Sigma at the identity)
  // and rocker 1 + 1e-6: the triangle closes only where |M1 - F2| >= 3 - 1e-6, an arc of about
  // 0.2 degrees about `centre`.
  const PlanarDyad input = PlanarDyad::RR(Eigen::Vector2d::Zero(), crank_pin, 1.0);
  const PlanarDyad rocker = PlanarDyad::RR(output_pivot, 5.0 * crank_pin, 1.0 + 1e-6);
  const FourBarClosure closure = SolveFourBarClosure(input, rocker);
  ASSERT_EQ(closure.intervals.size(), 1u);
  const ClosureInterval& arc = closure.intervals[0];
  EXPECT_FALSE(closure.full_turn);
  EXPECT_NEAR(arc.Extent() * 180.0 / kPi, 0.2, 0.05);
  const double middle = 0.5 * (arc.start + arc.end);
  EXPECT_NEAR(std::remainder(middle - centre, 2.0 * kPi), 0.0, 1e-9);
  std::vector<PlanarPose> configurations;
  EXPECT_EQ(AssembleFourBar(input, rocker, middle, 0.0, &configurations), 2);
  // The sampled trace steps over it.
  const FourBarMotion motion = TraceFourBar(input, rocker, {}, 1.0);
  EXPECT_TRUE(motion.circuits.empty());
}

// The closed-form analysis (AnalyzeFourBar) against the sampled one (AnalyzeFourBarSampled) on
// random four-bars of all nine type pairs, each dyad as the input, on their own tasks (5 and 12
// poses) and with the dyads moved 5 % of L off (defects, poses off the circuit): the same
// circuit, defects, full turn and pose error; the exact transmission extremes bracket those of
// 2000 samples of the way within a sample's change.
TEST(FourBarClosure, AnalysisAgreesWithTheSampledOracle) {
  std::mt19937_64 rng(1619);
  const DyadType types[] = {DyadType::kRR, DyadType::kPR, DyadType::kRP};
  int compared = 0, with_defects = 0, transmissions = 0;
  for (DyadType a : types) {
    for (DyadType b : types) {
      for (int trial = 0; trial < 24; ++trial) {
        const int count = trial % 2 ? 12 : 5;
        const testing::GeneratedTask task = testing::RandomTask(rng, a, b, count);
        const double length = CharacteristicLength(task.poses);
        PlanarDyad input = task.input, output = task.output;
        if (trial % 3 == 2) {
          input = testing::MovedPlanarDyad(rng, input, 0.05 * length, length);
          output = testing::MovedPlanarDyad(rng, output, 0.05 * length, length);
        }
        for (int way = 0; way < 2; ++way) {
          const PlanarDyad& in = way == 0 ? input : output;
          const PlanarDyad& out = way == 0 ? output : input;
          SCOPED_TRACE(std::string(DyadTypeName(in.type)) + "+" + DyadTypeName(out.type) +
                       " trial " + std::to_string(trial));
          const FourBarAnalysis closed = AnalyzeFourBar(in, out, task.poses, length);
          const FourBarAnalysis sampled = AnalyzeFourBarSampled(in, out, task.poses, length);
          // A configuration within a sampling step of an input limit can fall either side of the
          // sampler's last sample: compare only where every pose is well inside its interval.
          const FourBarClosure closure = SolveFourBarClosure(in, out);
          bool clear = true;
          for (const FourBarLocation& location : sampled.locations) {
            clear = clear && DistanceToEnd(closure, location.input) > 0.02;
          }
          if (!clear) continue;
          ASSERT_EQ(closed.max_pose_error.has_value(), sampled.max_pose_error.has_value());
          EXPECT_EQ(closed.defects, sampled.defects);
          EXPECT_EQ(closed.input_rotates_fully, sampled.input_rotates_fully);
          if (closed.max_pose_error && closed.defects.empty()) {
            EXPECT_NEAR(*closed.max_pose_error, *sampled.max_pose_error, 1e-9 * length);
          }
          with_defects += !closed.defects.empty();
          if (closed.transmission_min_deg) {
            // The oracle: 2000 samples of the crank's way from the first pose to the last: within
            // its interval for a limited crank (the sampled analysis takes the short way round,
            // which can cross where the four-bar does not assemble), forward for a full turn
            // unless only backward visits the poses in order.
            const auto positive = [](double angle) {
              return std::fmod(std::fmod(angle, 2.0 * kPi) + 2.0 * kPi, 2.0 * kPi);
            };
            const double start = closed.locations.front().input;
            double extent = closed.locations.back().input - start;  // a slider
            if (!closure.angle_input) {
            } else if (closed.input_rotates_fully) {
              double forward = 0.0;
              for (size_t j = 1; j < closed.locations.size(); ++j) {
                forward += positive(closed.locations[j].input - closed.locations[j - 1].input);
              }
              const double end = closed.locations.back().input;
              extent = forward < 2.0 * kPi ? positive(end - start) : -positive(start - end);
            } else {
              const int interval = ClosureIntervalOf(closure, start, 1e-9);
              ASSERT_GE(interval, 0);
              const double origin = closure.intervals[interval].start - 1e-9;
              extent = positive(closed.locations.back().input - origin) - positive(start - origin);
            }
            std::optional<double> low, high;
            std::vector<PlanarPose> configurations;
            TransmissionRangeDeg(
                in, out, 2000,
                [&](int k) -> std::optional<PlanarPose> {
                  if (AssembleFourBar(in, out, start + extent * k / 2000, 1e-9 * length,
                                      &configurations) == 0) {
                    return std::nullopt;
                  }
                  return configurations[0];
                },
                &low, &high);
            ASSERT_TRUE(low.has_value());
            // Exact extremes: at or beyond the sampled ones, by less than a sample's change.
            EXPECT_LE(*closed.transmission_min_deg, *low + 1e-9);
            EXPECT_GE(*closed.transmission_max_deg, *high - 1e-9);
            EXPECT_GT(*closed.transmission_min_deg, *low - 0.2);
            EXPECT_LT(*closed.transmission_max_deg, *high + 0.2);
            ++transmissions;
          }
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_GT(with_defects, 20);
  EXPECT_GT(transmissions, 20);
}

}  // namespace
}  // namespace linkfit
