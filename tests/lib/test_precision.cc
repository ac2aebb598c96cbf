// Tests of data precision (lib/precision.h) and of how the task reader uses it: precision
// inferred from the digits or given, input repaired within it and refused beyond it, the pose
// forms that tables use, closed motions and paths, poses equal within precision.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "lib/precision.h"
#include "lib/task_io.h"
#include "tests/support/rounded_task.h"

namespace linkfit {
namespace {

constexpr double kDegree = M_PI / 180.0;

// `value` printed as a table prints it: `digits` significant digits (%g), or with `decimals`
// fixed decimals when digits is 0.
std::string Printed(double value, int digits, int decimals = 0) {
  char buffer[64];
  if (digits > 0) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  }
  return buffer;
}

std::string PrintedArray(const std::vector<double>& values, int digits, int decimals = 0) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) {
    out += (i ? ", " : "") + Printed(values[i], digits, decimals);
  }
  return out + "]";
}

std::string ErrorOf(const std::string& text) { return testing::ParseErrorOf(text); }

bool HasNoteWith(const Task& task, const std::string& words) {
  for (const std::string& note : task.input_notes) {
    if (note.find(words) != std::string::npos) return true;
  }
  return false;
}

TEST(WrittenDigits, ReadsTheLastAndLeadingDigit) {
  struct Case {
    const char* text;
    int last, lead;
    bool zero;
  };
  for (const Case& c : std::vector<Case>{{"12.3456", -4, 1, false},
                                         {"-0.01230", -5, -2, false},
                                         {"1200", 0, 3, false},
                                         {"1.5e-3", -4, -3, false},
                                         {"2E+2", 2, 2, false},
                                         {"0.000", -3, -3, true},
                                         {"0", 0, 0, true},
                                         {"34.641016151377549", -15, 1, false}}) {
    WrittenDigits digits;
    ASSERT_TRUE(ReadWrittenDigits(c.text, &digits)) << c.text;
    EXPECT_EQ(digits.last, c.last) << c.text;
    EXPECT_EQ(digits.zero, c.zero) << c.text;
    if (!c.zero) {
      EXPECT_EQ(digits.lead, c.lead) << c.text;
    }
  }
  WrittenDigits digits;
  EXPECT_FALSE(ReadWrittenDigits("", &digits));
  EXPECT_FALSE(ReadWrittenDigits("1e", &digits));
  EXPECT_FALSE(ReadWrittenDigits("abc", &digits));
  // Absurd exponents are clamped, not overflowed.
  ASSERT_TRUE(ReadWrittenDigits("1e-99999999999999999999", &digits));
  EXPECT_EQ(digits.last, -400);
}

double HalfUnitOf(const std::vector<std::string>& texts) {
  DigitTally tally;
  for (const std::string& text : texts) {
    WrittenDigits digits;
    EXPECT_TRUE(ReadWrittenDigits(text, &digits)) << text;
    tally.Add(digits);
  }
  return tally.HalfUnit();
}

TEST(DigitTally, FixedDecimalsGiveTheFinestDecimal) {
  // Four decimals, as %.4f prints them (zeros kept), with a number written shorter by hand.
  EXPECT_DOUBLE_EQ(HalfUnitOf({"12.3456", "0.5000", "-3.1416", "100.2500", "0.0000", "2.5"}), 5e-5);
  // A zero shows the decimals %#.6g gives it, more than any number of the table: not the table's.
  EXPECT_DOUBLE_EQ(HalfUnitOf({"0.00000", "42.4494", "-30.6617", "64.5089", "-7.10340"}), 5e-5);
  EXPECT_DOUBLE_EQ(HalfUnitOf({"0.000", "0.00"}), 5e-4);
}

TEST(DigitTally, SignificantDigitsGiveTheCoarsestNumber) {
  // Six significant digits: 123.456 carries 5e-4, 0.0123456 carries 5e-8; the data are good
  // to the coarser. "1.5" (1.50000 with zeros dropped) and "100" count with six digits too.
  EXPECT_DOUBLE_EQ(HalfUnitOf({"123.456", "0.0123456", "1.5", "-45.6789"}), 5e-4);
  EXPECT_DOUBLE_EQ(HalfUnitOf({"0.0123456", "1.5", "-4.56789"}), 5e-6);
  // %g drops trailing zeros: 100.25 of a six-digit table is 100.250, good to 5e-4, when the
  // table shows it is one (most numbers with six digits, of several magnitudes).
  EXPECT_DOUBLE_EQ(HalfUnitOf({"12.3456", "0.5", "-3.1416", "100.25", "2.71828", "0.123457"}),
                   5e-4);
}

// Issue 34: fixed decimals are the default reading; significant digits only where the table
// evidently is one. Tables of 1, 2 and 3 decimals of values 0.01 to 100 (trailing zeros dropped
// by hand or kept) have the precision of their finest decimal.
TEST(DigitTally, FixedDecimalsOfMixedMagnitudes) {
  EXPECT_DOUBLE_EQ(HalfUnitOf({"0.05", "0.15", "1.1", "0.5", "0.75", "1.0", "0.25", "0.6"}), 0.005);
  // Only one number of four printed: as likely four fixed decimals as six significant digits.
  EXPECT_DOUBLE_EQ(HalfUnitOf({"12.3456", "0.5", "-3.1416", "100.25"}), 5e-5);
  std::mt19937 rng(34);
  for (int decimals = 1; decimals <= 3; ++decimals) {
    for (double across : {1.0, 10.0, 100.0}) {
      std::uniform_real_distribution<double> value(-across, across);
      std::vector<std::string> texts;
      for (int i = 0; i < 40; ++i) {
        std::string text = Printed(value(rng), 0, decimals);
        // Some tables drop trailing zeros.
        if (i % 2 == 0) {
          while (text.find('.') != std::string::npos &&
                 (text.back() == '0' || text.back() == '.')) {
            text.pop_back();
          }
          if (text.empty() || text == "-") text = "0";
        }
        texts.push_back(text);
      }
      EXPECT_DOUBLE_EQ(HalfUnitOf(texts), 0.5 * std::pow(10.0, -decimals))
          << decimals << " decimals, values up to " << across;
    }
  }
}

TEST(DigitTally, FullPrecisionIsRoundingLevel) {
  EXPECT_LT(HalfUnitOf({"18.75", "32.4759526419165", "6.51180666250989"}), 1e-13);
  EXPECT_LT(HalfUnitOf({"0.1", "0.30000000000000004", "1.0"}), 1e-16);
}

// Five poses of a four-bar's coupler printed with `decimals` fixed decimals.
std::string PlanarTaskText(int decimals, const std::string& extra = "") {
  const double poses[5][3] = {{0.123456789, 0.5, 3.3333333},
                              {1.1, 0.2, 10.123456},
                              {2.25, 1.05, 20.5},
                              {1.0, 2.123456, 30.987654},
                              {0.1, 1.000001, 40.4}};
  std::string text = "{\"poses\": [";
  for (int i = 0; i < 5; ++i) {
    text += std::string(i ? ", " : "") + "{\"x\": " + Printed(poses[i][0], 0, decimals) +
            ", \"y\": " + Printed(poses[i][1], 0, decimals) +
            ", \"theta_deg\": " + Printed(poses[i][2], 0, decimals) + "}";
  }
  return text + "]" + extra + "}";
}

TEST(TaskPrecision, InferredFromTheDigits) {
  const Task task = ParseTask(PlanarTaskText(4), "task.json");
  EXPECT_EQ(task.precision.source, "digits");
  EXPECT_DOUBLE_EQ(task.precision.length, 5e-5);
  EXPECT_NEAR(task.precision.angle, 5e-5 * kDegree, 1e-20);
  EXPECT_TRUE(task.input_notes.empty());
  // Integers are exact design values: a task of integers is full precision.
  const Task integers = ParseTask(
      R"({"poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 10, "y": 0, "theta_deg": 30},
                    {"x": 20, "y": 5, "theta_deg": 60}, {"x": 25, "y": 15, "theta_deg": 90},
                    {"x": 20, "y": 25, "theta_deg": 120}]})",
      "task.json");
  EXPECT_LT(integers.precision.length, 1e-14);
  EXPECT_LT(integers.precision.angle, 1e-15);
}

TEST(TaskPrecision, GivenInTheTask) {
  Task task = ParseTask(PlanarTaskText(4, R"(, "precision": {"length": 0.01, "angle_deg": 0.1})"),
                        "task.json");
  EXPECT_EQ(task.precision.source, "task");
  EXPECT_DOUBLE_EQ(task.precision.length, 0.01);
  EXPECT_NEAR(task.precision.angle, 0.1 * kDegree, 1e-18);
  // One of the two given: the other from the digits, said in a note.
  task = ParseTask(PlanarTaskText(4, R"(, "precision": {"length": 0.01})"), "task.json");
  EXPECT_EQ(task.precision.source, "task");
  EXPECT_NEAR(task.precision.angle, 5e-5 * kDegree, 1e-20);
  EXPECT_TRUE(HasNoteWith(task, "precision.angle_deg not given")) << task.input_notes.size();
  EXPECT_EQ(ErrorOf(PlanarTaskText(4, R"(, "precision": {"length": -1})")),
            "task.json: precision.length: must not be negative, got -1");
  EXPECT_EQ(ErrorOf(PlanarTaskText(4, R"(, "precision": {"lenght": 1})")),
            "task.json: precision.lenght: unknown field (known fields: length, angle_deg)");
  EXPECT_EQ(ErrorOf(PlanarTaskText(4, R"(, "precision": {})")),
            "task.json: precision: give \"length\", \"angle_deg\" or both");
}

// Seven random spatial poses.
std::vector<std::pair<Eigen::Quaterniond, Eigen::Vector3d>> RandomPoses(unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::vector<std::pair<Eigen::Quaterniond, Eigen::Vector3d>> poses;
  for (int i = 0; i < 7; ++i) {
    Eigen::Quaterniond q(normal(random), normal(random), normal(random), normal(random));
    q.normalize();
    poses.emplace_back(q, Eigen::Vector3d(normal(random), normal(random), normal(random)) * 50.0);
  }
  return poses;
}

// The pose as (q, g) of seed 000 (q = (x, y, z, w), g = 1/2 d q).
std::string DualQuaternionText(const Eigen::Quaterniond& q, const Eigen::Vector3d& d, int digits) {
  const Eigen::Quaterniond g = Eigen::Quaterniond(0.0, d.x(), d.y(), d.z()) * q;
  return "{\"q\": " + PrintedArray({q.x(), q.y(), q.z(), q.w()}, digits) +
         ", \"g\": " + PrintedArray({0.5 * g.x(), 0.5 * g.y(), 0.5 * g.z(), 0.5 * g.w()}, digits) +
         "}";
}

std::string MatrixText(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& d, int digits,
                       int decimals = 0) {
  std::string text = "{\"rotation\": [";
  for (int row = 0; row < 3; ++row) {
    text += std::string(row ? ", " : "") +
            PrintedArray({rotation(row, 0), rotation(row, 1), rotation(row, 2)}, digits, decimals);
  }
  return text + "], \"translation\": " + PrintedArray({d.x(), d.y(), d.z()}, digits, decimals) +
         "}";
}

std::string SpatialText(const std::vector<std::string>& poses) {
  // One pose has no spread of origins: its tasks give the scale.
  std::string text = std::string("{\"space\": \"spatial\", ") +
                     (poses.size() == 1 ? "\"scale\": 1, " : "") + "\"poses\": [";
  for (size_t i = 0; i < poses.size(); ++i) text += (i ? ", " : "") + poses[i];
  return text + "]}";
}

TEST(TaskRepair, QuaternionsPrintedToSixDigitsAreRepaired) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const auto poses = RandomPoses(seed);
    std::vector<std::string> texts;
    for (const auto& [q, d] : poses) texts.push_back(DualQuaternionText(q, d, 6));
    const Task task = ParseTask(SpatialText(texts), "task.json");
    ASSERT_EQ(task.spatial_poses.size(), 7u);
    for (size_t i = 0; i < poses.size(); ++i) {
      const DualQuaternion& parsed = task.spatial_poses[i];
      EXPECT_NEAR(parsed.q.norm(), 1.0, 1e-15);
      EXPECT_NEAR(parsed.q.dot(parsed.g), 0.0, 1e-13);
      // Back to the generating pose within what six digits allow.
      EXPECT_LT((parsed.Rotation() - poses[i].first.toRotationMatrix()).norm(), 1e-5);
      EXPECT_LT((parsed.Translation() - poses[i].second).norm(), 1e-3);
    }
    EXPECT_TRUE(HasNoteWith(task, "input repaired within its precision")) << seed;
  }
}

TEST(TaskRepair, RotationsPrintedToFourDecimalsAreRepaired) {
  const auto poses = RandomPoses(7);
  std::vector<std::string> texts;
  for (const auto& [q, d] : poses) texts.push_back(MatrixText(q.toRotationMatrix(), d, 0, 4));
  const Task task = ParseTask(SpatialText(texts), "task.json");
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Matrix3d rotation = task.spatial_poses[i].Rotation();
    EXPECT_LT((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_LT((rotation - poses[i].first.toRotationMatrix()).cwiseAbs().maxCoeff(), 2e-4);
  }
  EXPECT_TRUE(HasNoteWith(task, "rotation matrices made orthonormal"));
  // Entries to 5e-5: the rotation is known to about twice that (lib/task_io.cc).
  EXPECT_NEAR(task.precision.length, 5e-5, 1e-18);
  EXPECT_NEAR(task.precision.angle, 1e-4, 1e-18);
}

TEST(TaskRepair, BeyondPrecisionIsRefusedWithWhatWouldBeAccepted) {
  const auto poses = RandomPoses(3);
  std::vector<std::string> texts;
  for (const auto& [q, d] : poses) texts.push_back(MatrixText(q.toRotationMatrix(), d, 0, 4));
  // One entry off by 50 units of the fourth decimal.
  Eigen::Matrix3d wrong = poses[4].first.toRotationMatrix();
  wrong(1, 2) += 5e-3;
  texts[4] = MatrixText(wrong, poses[4].second, 0, 4);
  const std::string message = ErrorOf(SpatialText(texts));
  EXPECT_EQ(
      message.rfind("task.json: poses[4].rotation: not orthonormal: an entry of R^T R - I is ", 0),
      0u)
      << message;
  EXPECT_NE(message.find("(5e-05 per entry) accepts at most"), std::string::npos) << message;
  // A quaternion off in its fifth of six digits.
  texts.clear();
  for (const auto& [q, d] : poses) texts.push_back(DualQuaternionText(q, d, 6));
  Eigen::Quaterniond off = poses[2].first;
  off.x() += 3e-4;
  texts[2] = DualQuaternionText(off, poses[2].second, 6);
  EXPECT_EQ(ErrorOf(SpatialText(texts)).rfind("task.json: poses[2].q: not a unit quaternion: ", 0),
            0u);
}

// R_axis(angle) for axis 'X', 'Y' or 'Z'.
Eigen::Matrix3d Turn(char axis, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis - 'X')).toRotationMatrix();
}

TEST(TaskForms, EulerAnglesInAllTwelveSequences) {
  const char* sequences[] = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX",
                             "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"};
  const double a = 30.0, b = -50.0, c = 120.0;
  for (const char* sequence : sequences) {
    const std::string pose = std::string("{\"euler_deg\": [30, -50, 120], \"euler_axes\": \"") +
                             sequence + "\", \"translation\": [1, 2, 3]}";
    const Task task = ParseTask(SpatialText({pose}), "task.json");
    const Eigen::Matrix3d expected = Turn(sequence[0], a * kDegree) *
                                     Turn(sequence[1], b * kDegree) *
                                     Turn(sequence[2], c * kDegree);
    EXPECT_LT((task.spatial_poses[0].Rotation() - expected).norm(), 1e-14) << sequence;
    EXPECT_LT((task.spatial_poses[0].Translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-14);
  }
  // "YXZ" is R_y(a) R_x(b) R_z(c): rotations about the moving frame's axes in the order named.
  const Task task = ParseTask(
      SpatialText({R"({"euler_deg": [90, 0, 0], "euler_axes": "YXZ", "translation": [0, 0, 0]})"}),
      "task.json");
  EXPECT_LT((task.spatial_poses[0].Rotation() * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitZ())
                .norm(),
            1e-15);
  for (const char* bad : {"XXY", "XY", "xyz", "ABC", "XYZX"}) {
    const std::string message =
        ErrorOf(SpatialText({std::string(R"({"euler_deg": [1, 2, 3], "euler_axes": ")") + bad +
                             R"(", "translation": [0, 0, 0]})"}));
    EXPECT_EQ(message.rfind("task.json: poses[0].euler_axes: expected one of the 12 axis", 0), 0u)
        << message;
  }
  EXPECT_EQ(ErrorOf(SpatialText({R"({"euler_deg": [1, 2, 3], "translation": [0, 0, 0]})"})),
            "task.json: poses[0].euler_axes: missing field");
}

TEST(TaskForms, FrameFromOriginXAxisAndADirectionInItsPlane) {
  // x along (1, 1, 0); the second direction (0, 1, 0) is not perpendicular to it.
  const Task task = ParseTask(
      SpatialText({R"({"translation": [5, 6, 7], "x_axis": [2, 2, 0], "y_axis": [0, 3, 0]})"}),
      "task.json");
  const Eigen::Matrix3d rotation = task.spatial_poses[0].Rotation();
  EXPECT_LT((rotation.col(0) - Eigen::Vector3d(1, 1, 0).normalized()).norm(), 1e-15);
  EXPECT_LT((rotation.col(2) - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((rotation.col(1) - Eigen::Vector3d(-1, 1, 0).normalized()).norm(), 1e-15);
  EXPECT_LT((task.spatial_poses[0].Translation() - Eigen::Vector3d(5, 6, 7)).norm(), 1e-14);
  EXPECT_EQ(
      ErrorOf(SpatialText(
                  {R"({"translation": [5, 6, 7], "x_axis": [2, 2, 0], "y_axis": [-1, -1, 0]})"}))
          .rfind("task.json: poses[0].y_axis: parallel to x_axis", 0),
      0u);
  // Parallel within the digits: 0.0001 off a parallel vector printed to four decimals.
  EXPECT_EQ(
      ErrorOf(
          SpatialText(
              {R"({"translation": [5, 6, 7], "x_axis": [1.0000, 0.0000, 0.0000], "y_axis": [1.0000, 0.0001, 0.0000]})"}))
          .rfind("task.json: poses[0].y_axis: parallel to x_axis", 0),
      0u);
  EXPECT_EQ(ErrorOf(SpatialText(
                {R"({"translation": [5, 6, 7], "x_axis": [0, 0, 0], "y_axis": [0, 1, 0]})"})),
            "task.json: poses[0].x_axis: zero vector, the x axis needs a direction");
}

TEST(TaskClosure, ClosedMotionIsUsedOnce) {
  // The five poses, then the first again as a table of a closed motion prints it.
  std::string text = PlanarTaskText(4);
  text.insert(text.rfind(']'), R"(, {"x": 0.1235, "y": 0.5000, "theta_deg": 363.3333})");
  const Task task = ParseTask(text, "task.json");
  EXPECT_TRUE(task.closed);
  EXPECT_EQ(task.planar_poses.size(), 5u);
  EXPECT_EQ(task.pose_weights.size(), 5u);
  EXPECT_TRUE(HasNoteWith(task, "poses[5] repeats poses[0] within the data's precision"));
  // A pose beyond the precision is a sixth pose.
  text = PlanarTaskText(4);
  text.insert(text.rfind(']'), R"(, {"x": 0.1237, "y": 0.5000, "theta_deg": 3.3333})");
  EXPECT_FALSE(ParseTask(text, "task.json").closed);
}

TEST(TaskClosure, ClosedPathPrescribedAndFree) {
  std::string points;
  for (int i = 0; i <= 6; ++i) {
    const double angle = (i % 6) * 60.0 * kDegree;
    points += std::string(i ? ", " : "") + "{\"x\": " + Printed(2.0 * std::cos(angle), 0, 4) +
              ", \"y\": " + Printed(std::sin(angle), 0, 4) +
              ", \"input_deg\": " + Printed(60.0 * i + 10.0, 0, 2) + "}";
  }
  Task task = ParseTask("{\"problem\": \"path\", \"points\": [" + points + "]}", "task.json");
  EXPECT_TRUE(task.closed);
  EXPECT_EQ(task.points.size(), 6u);
  EXPECT_TRUE(HasNoteWith(task, "a closed path"));
  // Without the input angles: free timing, closed the same way.
  std::string untimed;
  for (int i = 0; i <= 6; ++i) {
    const double angle = (i % 6) * 60.0 * kDegree;
    untimed += std::string(i ? ", " : "") + "{\"x\": " + Printed(2.0 * std::cos(angle), 0, 4) +
               ", \"y\": " + Printed(std::sin(angle), 0, 4) + "}";
  }
  task = ParseTask("{\"problem\": \"path\", \"points\": [" + untimed + "]}", "task.json");
  EXPECT_TRUE(task.closed);
  EXPECT_EQ(task.points.size(), 6u);
  // The same point passed at another crank angle is a crossing, not a closure.
  const std::string crossing = points.substr(0, points.rfind("370.00")) + "200.00}";
  task = ParseTask("{\"problem\": \"path\", \"points\": [" + crossing + "]}", "task.json");
  EXPECT_FALSE(task.closed);
  EXPECT_EQ(task.points.size(), 7u);
}

TEST(TaskCoincidence, OnlyItemsEqualInPrintAreCoincident) {
  // Measured to 1e-3 (given), printed to four decimals: 4e-4 apart they differ in print, and a
  // least-squares task takes both (issue 34: never refused as coincident).
  const std::string given = R"(, "precision": {"length": 0.001})";
  std::string text = PlanarTaskText(4, given);
  text.insert(text.rfind(']'), R"(, {"x": 2.2504, "y": 1.0500, "theta_deg": 20.5000})");
  EXPECT_EQ(ErrorOf(text), "<no error>");
  text = PlanarTaskText(4, given);
  text.insert(text.rfind(']'), R"(, {"x": 2.2500, "y": 1.0500, "theta_deg": 20.5001})");
  EXPECT_EQ(ErrorOf(text), "<no error>");
  // Printed identically, with or without trailing zeros: coincident.
  text = PlanarTaskText(4);
  text.insert(text.rfind(']'), R"(, {"x": 2.2500, "y": 1.0500, "theta_deg": 20.5000})");
  EXPECT_EQ(ErrorOf(text), "task.json: poses[5]: coincides with poses[2]");
  text = PlanarTaskText(4, given);
  text.insert(text.rfind(']'), R"(, {"x": 2.25, "y": 1.05, "theta_deg": 20.5})");
  EXPECT_EQ(ErrorOf(text), "task.json: poses[5]: coincides with poses[2]");
}

// Issue 34: a closed curve printed to two decimals by hand ("0.05", "0.15", "1.1", "0.0"):
// known to 0.005, its neighbours 0.05 apart are distinct points.
TEST(TaskCoincidence, TwoDecimalTableOfACurveIsRead) {
  const Task task = ParseTask(
      R"({"problem": "path", "points": [
      {"x": 0.5, "y": 1.1}, {"x": 0.3, "y": 1.1}, {"x": 0.1, "y": 0.9}, {"x": 0.05, "y": 0.75},
      {"x": 0.0, "y": 0.5}, {"x": 0.03, "y": 0.3}, {"x": 0.1, "y": 0.25}, {"x": 0.15, "y": 0.2},
      {"x": 0.3, "y": 0.4}, {"x": 0.6, "y": 0.9}]})",
      "task.json");
  EXPECT_DOUBLE_EQ(task.precision.length, 0.005);
  EXPECT_EQ(task.points.size(), 10u);
}
}  // namespace
}  // namespace linkfit
