// Task file reading and validation (see task_io.h). Every problem becomes one InputError
// line "<source>: <item>: <what is wrong>"; nothing malformed reaches the solvers.
#include "lib/task_io.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <unordered_set>
#include <utility>

#include "lib/function_samples.h"

namespace linkfit {
namespace {

using Json = nlohmann::json;

// JSON nested deeper than this is rejected before it reaches the parser.
constexpr int kMaxDepth = 64;
// Longest excerpt of user text (keys, strings, parser reasons) quoted in a message.
constexpr size_t kMaxQuoted = 60;
// Rounding slack of the unit conditions, in units of double epsilon.
constexpr double kRoundingUnits = 16.0;

// Task files larger than this are refused (100000 poses take about 10 MB).
constexpr size_t kMaxFileBytes = size_t{256} << 20;

constexpr double kDegree = M_PI / 180.0;
constexpr double kPi = M_PI;
// How far from the poses a given pivot may lie, times L (TaskParser::CheckPivotReach).
constexpr double kMaxPivotReach = 1e8;

// Keeps a message on one printable ASCII line and bounded in length.
std::string Sanitize(const std::string& text, size_t max_length) {
  std::string out;
  for (char c : text) {
    if (out.size() >= max_length) {
      out += "...";
      break;
    }
    const unsigned char u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u >= 0x7f) ? '?' : c;
  }
  return out;
}

// A user-given string, quoted and escaped for a message.
std::string Quote(const std::string& text) {
  return Sanitize(Json(text).dump(-1, ' ', true, Json::error_handler_t::replace), kMaxQuoted);
}

// The item name of field `key` inside `parent` ("poses[2]" + "x" -> "poses[2].x").
std::string KeyItem(const std::string& parent, const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  const std::string name = plain ? Sanitize(key, kMaxQuoted) : Quote(key);
  return parent.empty() ? name : parent + "." + name;
}

std::string IndexItem(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

// "a string", "an object", ... for "expected X, got Y" messages.
std::string Describe(const Json& value) {
  if (value.is_null()) return "null";
  if (value.is_boolean()) return "a boolean";
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_array()) return "an array";
  if (value.is_object()) return "an object";
  return "an unsupported value";
}

std::string FormatNumber(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// 1-based line and column of a 0-based byte offset into `text`.
std::pair<size_t, size_t> LineColumn(const std::string& text, size_t offset) {
  offset = std::min(offset, text.size());
  const size_t line =
      1 + static_cast<size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
  const size_t last_newline = offset == 0 ? std::string::npos : text.rfind('\n', offset - 1);
  const size_t column = last_newline == std::string::npos ? offset + 1 : offset - last_newline;
  return {line, column};
}

// "7 poses given" ("1 pose given"): `plural` is "poses" or "points".
std::string ItemCount(const std::string& plural, size_t count) {
  const std::string noun = count == 1 ? plural.substr(0, plural.size() - 1) : plural;
  return std::to_string(count) + " " + noun + " given";
}

// The message for more poses or points than the limit, the same from the parser and from the
// later count.
std::string OverLimit(const std::string& plural, size_t count, size_t limit) {
  return ItemCount(plural, count) + ", more than the limit of " + std::to_string(limit);
}

// JSON values per pose or point that a task may hold before it is refused as too large. The
// largest pose form (rotation matrix, translation, weight, exact) is 20 values; pivots, platform
// and options add a few hundred at most, covered by kExtraItems.
constexpr size_t kValuesPerItem = 32;
constexpr size_t kExtraItems = 128;

// Tracks where the parser is (for messages about a value the parser itself rejects, such as
// 1e999) and rejects duplicate keys, which nlohmann would otherwise silently resolve.
class ParsePath {
 public:
  // The item the parser is at: the innermost container and its current key or index.
  std::string Current() const {
    std::string item;
    for (const Frame& frame : frames_) {
      // An object before its first key is itself the item.
      if (!frame.is_array && frame.keys.empty()) break;
      item = frame.is_array ? IndexItem(item, frame.count) : KeyItem(item, frame.key);
    }
    return item;
  }

  // Open containers, the top-level value included.
  size_t depth() const { return frames_.size(); }
  // The elements completed so far in the innermost container when it is an array.
  size_t ArrayCount() const {
    return !frames_.empty() && frames_.back().is_array ? frames_.back().count : 0;
  }
  // "poses" or "points" when the innermost container is that array of the top-level object,
  // else empty.
  std::string ItemList() const {
    if (frames_.size() != 2 || frames_[0].is_array || !frames_[1].is_array) return "";
    const std::string& key = frames_[0].key;
    return key == "poses" || key == "points" || key == "pairs" ? key : "";
  }

  // The field of a pose or point the parser is in ("x" inside poses[3], "q" inside
  // poses[3].q[1]), or null elsewhere.
  const std::string* ItemField() const {
    if (frames_.size() < 3 || frames_[0].is_array || !frames_[1].is_array || frames_[2].is_array ||
        (frames_[0].key != "poses" && frames_[0].key != "points" && frames_[0].key != "pairs")) {
      return nullptr;
    }
    return &frames_[2].key;
  }

  void Start(bool is_array) { frames_.push_back(Frame{is_array, 0, {}, {}}); }
  // False when the current object already has this key.
  bool Key(const std::string& key) {
    Frame& frame = frames_.back();
    frame.key = key;
    return frame.keys.insert(key).second;
  }
  // A value (scalar or completed container) ends: the enclosing array moves on.
  void Value() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().count;
  }
  void End() {
    frames_.pop_back();
    Value();
  }

 private:
  struct Frame {
    bool is_array;
    size_t count;                          // arrays: elements completed so far
    std::string key;                       // objects: the current key
    std::unordered_set<std::string> keys;  // objects: keys seen so far
  };
  std::vector<Frame> frames_;
};

// The kinds of numbers whose written digits set the task's precision (lib/precision.h).
enum DigitKind {
  kLengthDigits,      // x, y, translation: lengths
  kHalfLengthDigits,  // g: half a translation (seed 000 eq. 5)
  kDegreeDigits,      // theta_deg, angle_deg, euler_deg, input_deg
  kUnitDigits,        // rotation matrix entries, axis components: radians of rotation
  kQuaternionDigits,  // q: half radians of rotation
  kDirectionDigits,   // x_axis, y_axis: lengths along a direction
  kDigitKinds
};

using DigitTallies = std::array<DigitTally, kDigitKinds>;

// The kind of a pose or point field, or -1 for fields that carry no data precision (weight).
int DigitKindOf(const std::string& field) {
  if (field == "x" || field == "y" || field == "translation") return kLengthDigits;
  if (field == "g") return kHalfLengthDigits;
  if (field == "theta_deg" || field == "angle_deg" || field == "euler_deg" ||
      field == "input_deg" || field == "output_deg") {
    return kDegreeDigits;
  }
  if (field == "rotation" || field == "axis") return kUnitDigits;
  if (field == "q") return kQuaternionDigits;
  if (field == "x_axis" || field == "y_axis") return kDirectionDigits;
  return -1;
}

// SAX handler: nlohmann's own DOM builder, with the path tracked alongside. (nlohmann's
// callback parser is quadratic in the length of an array of objects, so it is not used.)
// Memory stays bounded while parsing: "poses" or "points" beyond options.max_items are
// counted but not built (the count is then reported as by TaskParser::Items), and a text of
// more JSON values than such a task can hold is refused at the first value too many.
class TrackingSax {
 public:
  TrackingSax(Json* root, const std::string& source, const TaskReadOptions& options)
      : dom_(*root, true),
        source_(source),
        max_items_(options.max_items),
        max_values_(options.max_items >
                            std::numeric_limits<size_t>::max() / kValuesPerItem - kExtraItems
                        ? std::numeric_limits<size_t>::max()
                        : kValuesPerItem * (options.max_items + kExtraItems)) {}
  const ParsePath& path() const { return path_; }

  bool null() {
    return Scalar([&] { return dom_.null(); });
  }
  bool boolean(bool value) {
    return Scalar([&] { return dom_.boolean(value); });
  }
  // Integers (no decimal point, no exponent) are exact design values (0, 90, 100 mm): they
  // carry no evidence of a table's precision.
  bool number_integer(Json::number_integer_t value) {
    return Scalar([&] { return dom_.number_integer(value); });
  }
  bool number_unsigned(Json::number_unsigned_t value) {
    return Scalar([&] { return dom_.number_unsigned(value); });
  }
  bool number_float(Json::number_float_t value, const std::string& text) {
    WrittenDigits digits;
    if (ReadWrittenDigits(text, &digits)) Tally(digits);
    return Scalar([&] { return dom_.number_float(value, text); });
  }
  // The written digits of the pose and point fields, by kind.
  const DigitTallies& tallies() const { return tallies_; }
  bool string(std::string& value) {
    return Scalar([&] { return dom_.string(value); });
  }
  bool binary(Json::binary_t& value) {
    return Scalar([&] { return dom_.binary(value); });
  }
  bool start_object(std::size_t size) {
    const bool keep = Keep();
    path_.Start(false);
    return !keep || dom_.start_object(size);
  }
  bool key(std::string& key) {
    if (!path_.Key(key)) throw InputError(source_ + ": " + path_.Current() + ": field given twice");
    return skip_depth_ > 0 || dom_.key(key);
  }
  bool end_object() {
    path_.End();
    return skip_depth_ > 0 || dom_.end_object();
  }
  bool start_array(std::size_t size) {
    const bool keep = Keep();
    path_.Start(true);
    return !keep || dom_.start_array(size);
  }
  bool end_array() {
    if (skip_depth_ > 0 && path_.depth() == skip_depth_) {
      // The end of the poses or points beyond the limit: all are counted now.
      const std::string list = path_.ItemList();
      throw InputError(source_ + ": " + list + ": " +
                       OverLimit(list, path_.ArrayCount(), max_items_));
    }
    path_.End();
    return skip_depth_ > 0 || dom_.end_array();
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& last_token, const Exception& error) {
    return dom_.parse_error(position, last_token, error);  // throws
  }

 private:
  // Called as a value begins: whether it goes into the DOM. Starts skipping at the first pose
  // or point beyond the limit; refuses the value beyond the budget.
  bool Keep() {
    if (skip_depth_ > 0) return false;
    if (path_.ArrayCount() >= max_items_ && !path_.ItemList().empty()) {
      skip_depth_ = path_.depth();
      return false;
    }
    if (++values_ > max_values_) {
      const std::string item = path_.Current();
      throw InputError(source_ + ": " + (item.empty() ? "top level" : item) +
                       ": too many JSON values (more than " + std::to_string(max_values_) +
                       "; a task has at most " + std::to_string(max_items_) + " poses or points)");
    }
    return true;
  }

  // Counts the digits of a number of a pose or point field (not of skipped items).
  void Tally(const WrittenDigits& digits) {
    if (skip_depth_ > 0) return;
    const std::string* field = path_.ItemField();
    if (field == nullptr) return;
    const int kind = DigitKindOf(*field);
    if (kind >= 0) tallies_[kind].Add(digits);
  }

  template <typename Add>
  bool Scalar(const Add& add) {
    const bool result = !Keep() || add();
    path_.Value();
    return result;
  }

  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  ParsePath path_;
  std::string source_;
  size_t max_items_;
  size_t max_values_;
  size_t values_ = 0;      // values built into the DOM so far
  size_t skip_depth_ = 0;  // when skipping: the depth of the poses or points array, else 0
  DigitTallies tallies_;
};

// What the parser repaired within precision, for the result's notes.
struct RepairLog {
  int quaternions = 0;       // unit dual quaternions normalized
  int rotations = 0;         // rotation matrices made orthonormal
  double largest = 0.0;      // largest correction of one entry
  std::string largest_item;  // where it was made

  void Add(bool quaternion, double correction, const std::string& item) {
    (quaternion ? quaternions : rotations) += 1;
    if (correction > largest) {
      largest = correction;
      largest_item = item;
    }
  }
};

// Validates the fields of one task; `source` prefixes every message.
class TaskParser {
 public:
  TaskParser(const std::string& source, const TaskReadOptions& options)
      : source_(source), options_(options) {}

  // A design's optional "mechanisms": each {"dyads": [...]} of `count` different indices below
  // `dyads`; `expected` says what the list is in messages.
  std::vector<std::vector<int>> MechanismDyads(const Json& root, size_t count, size_t dyads,
                                               const std::string& expected) const {
    std::vector<std::vector<int>> all;
    if (!root.contains("mechanisms")) return all;
    const Json& mechanisms = root.at("mechanisms");
    if (!mechanisms.is_array()) {
      Fail("mechanisms", "expected an array, got " + Describe(mechanisms));
    }
    for (size_t m = 0; m < mechanisms.size(); ++m) {
      const std::string item = IndexItem("mechanisms", m);
      const Json& list = Field(Object(mechanisms[m], item), item, "dyads");
      const std::string list_item = KeyItem(item, "dyads");
      if (!list.is_array() || list.size() != count) {
        Fail(list_item, "expected " + expected + ", got " + Describe(list));
      }
      std::vector<int> indices;
      for (size_t k = 0; k < count; ++k) {
        if (!list[k].is_number_integer() || list[k].get<long long>() < 0 ||
            list[k].get<long long>() >= static_cast<long long>(dyads)) {
          Fail(IndexItem(list_item, k), "expected a dyad index below " + std::to_string(dyads) +
                                            ", got " + Describe(list[k]));
        }
        const int index = static_cast<int>(list[k].get<long long>());
        if (std::find(indices.begin(), indices.end(), index) != indices.end()) {
          Fail(count == 2 ? list_item : IndexItem(list_item, k),
               count == 2 ? "a four-bar needs two different dyads"
                          : "dyad " + std::to_string(index) + " given twice");
        }
        indices.push_back(index);
      }
      all.push_back(indices);
    }
    return all;
  }

  // A design's JSON: an object whose `key` is a non-empty array (of `what`, for messages).
  Json DesignRoot(const std::string& text, const char* key, const std::string& what) const {
    Json root = ParseJson(text);
    if (!root.is_object()) Fail("top level", "expected an object, got " + Describe(root));
    const Json& list = Field(root, "", key);
    if (!list.is_array() || list.empty()) {
      Fail(key, "expected a non-empty array of " + what + ", got " + Describe(list));
    }
    return root;
  }

  // Calls visit(item, entry, type, name) for each entry of the design list root[key] (an
  // object with a "type"): `item` names the entry in messages, `name` is the type's text ("" when
  // it is not a string).
  template <typename Visit>
  void ForEachTypedEntry(const Json& root, const char* key, const Visit& visit) const {
    const Json& entries = root.at(key);
    for (size_t i = 0; i < entries.size(); ++i) {
      const std::string item = IndexItem(key, i);
      const Json& entry = Object(entries[i], item);
      const Json& type = Field(entry, item, "type");
      visit(item, entry, type, type.is_string() ? type.get<std::string>() : std::string());
    }
  }

  // The unit direction of a line given by its angle in degrees, object[key].
  Eigen::Vector2d DirectionDeg(const Json& object, const std::string& item, const char* key) const {
    const double angle = Number(Field(object, item, key), KeyItem(item, key)) * kDegree;
    return Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }

  PlanarDesign ParseDesignText(const std::string& text) const {
    const Json root = DesignRoot(text, "dyads", "dyads");
    PlanarDesign design;
    ForEachTypedEntry(
        root, "dyads",
        [&](const std::string& item, const Json& dyad, const Json& type, const std::string& name) {
          const auto point = [&](const char* key) {
            return Vector<2>(Field(dyad, item, key), KeyItem(item, key));
          };
          const auto direction = [&]() { return DirectionDeg(dyad, item, "line_angle_deg"); };
          if (name == "RR") {
            const double radius = Positive(Field(dyad, item, "radius"), KeyItem(item, "radius"));
            design.dyads.push_back(PlanarDyad::RR(point("fixed"), point("moving"), radius));
          } else if (name == "PR") {
            design.dyads.push_back(
                PlanarDyad::PR(point("moving"), point("line_point"), direction()));
          } else if (name == "RP") {
            design.dyads.push_back(
                PlanarDyad::RP(point("fixed"), point("line_point"), direction()));
          } else {
            Fail(KeyItem(item, "type"), "expected \"RR\", \"PR\" or \"RP\", got " + Describe(type));
          }
        });
    for (const std::vector<int>& pair :
         MechanismDyads(root, 2, design.dyads.size(), "[input, output] dyad indices")) {
      design.mechanisms.emplace_back(pair[0], pair[1]);
    }
    return design;
  }

  PathDesign ParsePathDesignText(const std::string& text) const {
    const Json root = DesignRoot(text, "mechanisms", "path four-bars");
    PathDesign design;
    ForEachTypedEntry(
        root, "mechanisms",
        [&](const std::string& item, const Json& mechanism, const Json& type,
            const std::string& name) {
          const auto point = [&](const char* key) {
            return Vector<2>(Field(mechanism, item, key), KeyItem(item, key));
          };
          if (name != "4R" && name != "slider-crank" && name != "inverted slider-crank") {
            Fail(KeyItem(item, "type"),
                 "expected \"4R\", \"slider-crank\" or \"inverted slider-crank\" (a crank-driven "
                 "path four-bar), got " +
                     Describe(type));
          }
          PathFourBar four_bar;
          const Eigen::Vector2d input_pivot = point("input_pivot");
          const Eigen::Vector2d input_moving = point("input_moving");
          const double crank = (input_moving - input_pivot).norm();
          if (!(crank > 0.0)) Fail(KeyItem(item, "input_moving"), "the crank has no length");
          four_bar.input = PlanarDyad::RR(input_pivot, input_moving, crank);
          const auto line_direction = [&]() {
            return DirectionDeg(mechanism, item, "output_line_angle_deg");
          };
          if (name == "4R") {
            const Eigen::Vector2d pivot = point("output_pivot"), moving = point("output_moving");
            const double rocker = (moving - pivot).norm();
            if (!(rocker > 0.0)) Fail(KeyItem(item, "output_moving"), "the rocker has no length");
            four_bar.output = PlanarDyad::RR(pivot, moving, rocker);
          } else if (name == "slider-crank") {
            four_bar.output = PlanarDyad::PR(point("output_moving"), point("output_line_point"),
                                             line_direction());
          } else {
            four_bar.output =
                PlanarDyad::RP(point("output_pivot"), point("output_line_point"), line_direction());
          }
          four_bar.coupler_point = point("coupler_point");
          std::vector<double> angles;
          if (mechanism.contains("input_deg")) {
            const Json& values = mechanism.at("input_deg");
            const std::string key = KeyItem(item, "input_deg");
            if (!values.is_array())
              Fail(key, "expected an array of numbers, got " + Describe(values));
            for (size_t j = 0; j < values.size(); ++j) {
              angles.push_back(Number(values[j], IndexItem(key, j)) * kDegree);
            }
          }
          design.four_bars.push_back(four_bar);
          design.input_angles.push_back(angles);
        });
    return design;
  }

  SpatialDesign ParseSpatialDesignText(const std::string& text) const {
    const Json root = DesignRoot(text, "dyads", "spatial dyads");
    SpatialDesign design;
    ForEachTypedEntry(
        root, "dyads",
        [&](const std::string& item, const Json& dyad, const Json& type, const std::string& name) {
          const auto point = [&](const char* key) {
            return Vector<3>(Field(dyad, item, key), KeyItem(item, key));
          };
          const auto normal = [&](const char* key) {
            const Eigen::Vector3d vector = point(key);
            if (!(vector.norm() > 0.0)) Fail(KeyItem(item, key), "a plane normal must not be zero");
            return vector;
          };
          const auto number = [&](const char* key) {
            return Number(Field(dyad, item, key), KeyItem(item, key));
          };
          if (name == "SS") {
            const double radius = Positive(Field(dyad, item, "radius"), KeyItem(item, "radius"));
            design.dyads.push_back(SpatialDyad::SS(point("fixed"), point("moving"), radius));
          } else if (name == "PS") {
            design.dyads.push_back(
                SpatialDyad::PS(point("moving"), normal("plane_normal"), number("plane_offset")));
          } else if (name == "SP") {
            design.dyads.push_back(SpatialDyad::SP(point("fixed"), normal("plane_normal_in_moving"),
                                                   number("plane_offset_in_moving")));
          } else {
            const bool planar = name == "RR" || name == "PR" || name == "RP";
            Fail(KeyItem(item, "type"),
                 "expected \"SS\", \"PS\" or \"SP\", got " +
                     (planar
                          ? "\"" + name + "\" (a planar dyad: refine planar data as a planar task)"
                          : Describe(type)));
          }
        });
    design.platforms =
        MechanismDyads(root, 5, design.dyads.size(), "the platform's five dyad indices");
    return design;
  }

  SixBarDesign ParseSixBarDesignText(const std::string& text,
                                     const std::vector<PlanarPose>& poses) const {
    const Json root = DesignRoot(text, "six_bars", "six-bars");
    static const char* const kBodies[] = {"ground",    "upper link", "forearm",
                                          "task body", "first link", "second link"};
    const auto body = [&](const Json& value, const std::string& item) {
      for (int k = 0; k < 6; ++k) {
        if (value.is_string() && value.get<std::string>() == kBodies[k]) return k;
      }
      Fail(item,
           "expected \"ground\", \"upper link\", \"forearm\", \"task body\", \"first link\" "
           "or \"second link\", got " +
               Describe(value));
    };
    SixBarDesign design;
    const Json& list = root.at("six_bars");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string item = IndexItem("six_bars", i);
      const Json& entry = Object(list[i], item);
      SixBar six_bar;
      six_bar.topology =
          ParseEnum<SixBarTopology>(entry, item, "topology", SixBarTopology::kWattI,
                                    {{"Watt I", SixBarTopology::kWattI},
                                     {"Stephenson I", SixBarTopology::kStephensonI},
                                     {"Stephenson II", SixBarTopology::kStephensonII},
                                     {"Stephenson III", SixBarTopology::kStephensonIII}});
      const std::string joints_item = KeyItem(item, "joints_at_first_pose");
      const Json& joints = Object(Field(entry, item, "joints_at_first_pose"), joints_item);
      const auto point = [&](const Json& object, const std::string& at, const char* key) {
        return Vector<2>(Field(object, at, key), KeyItem(at, key));
      };
      six_bar.ground_pivot = point(joints, joints_item, "ground_pivot");
      six_bar.elbow = point(joints, joints_item, "elbow");
      six_bar.wrist = point(joints, joints_item, "wrist");
      const std::string links_item = KeyItem(joints_item, "links");
      const Json& links = Field(joints, joints_item, "links");
      if (!links.is_array() || links.size() != 2) {
        Fail(links_item, "expected the two RR links, got " + Describe(links));
      }
      for (int l = 0; l < 2; ++l) {
        const std::string link_item = IndexItem(links_item, l);
        const Json& link = Object(links[l], link_item);
        SixBarRRLink& rr = six_bar.links[l];
        rr.from_body = body(Field(link, link_item, "from"), KeyItem(link_item, "from"));
        rr.to_body = body(Field(link, link_item, "to"), KeyItem(link_item, "to"));
        rr.from_joint = point(link, link_item, "from_joint");
        rr.to_joint = point(link, link_item, "to_joint");
      }
      // The bodies a six-bar on a 3R chain may join (fitting/six_bar_synthesis.h).
      const SixBarRRLink& first = six_bar.links[0];
      const SixBarRRLink& second = six_bar.links[1];
      const bool first_ok = first.from_body == kSixBarGround &&
                            (first.to_body == kSixBarForearm || first.to_body == kSixBarTaskBody);
      const bool second_ok =
          (second.from_body == kSixBarGround || second.from_body == kSixBarUpperLink ||
           second.from_body == kSixBarFirstLink) &&
          second.to_body >= kSixBarUpperLink && second.to_body <= kSixBarTaskBody &&
          second.to_body != second.from_body;
      if (!first_ok || !second_ok) {
        Fail(links_item,
             "not a six-bar on the chain: the first link joins ground and the forearm or the "
             "task body, the second ground, the upper link or the first link and a chain body");
      }
      six_bar.reference_pose = poses.front();
      if (entry.contains("task_body_at_first_pose")) {
        const std::string at = KeyItem(item, "task_body_at_first_pose");
        const Eigen::Vector3d pose = Vector<3>(entry.at("task_body_at_first_pose"), at);
        six_bar.reference_pose = PlanarPose(pose.x(), pose.y(), pose.z() * M_PI / 180.0);
      }
      int input = kSixBarUpperLink;
      if (entry.contains("input")) input = body(entry.at("input"), KeyItem(item, "input"));
      if (!SixBarGroundedLink(six_bar, input)) {
        Fail(KeyItem(item, "input"), "not a link turning about ground");
      }
      // Each pose's turns, where the design was made for as many poses as the task has (a
      // design of other poses is placed at the task's by its upper link's range).
      std::vector<SixBarAngles> turns;
      if (entry.contains("turns_at_poses_deg")) {
        const std::string at = KeyItem(item, "turns_at_poses_deg");
        const Json& value = entry.at("turns_at_poses_deg");
        if (!value.is_array()) Fail(at, "expected lists of five turns, got " + Describe(value));
        for (size_t k = 0; k < value.size() && value.size() == poses.size(); ++k) {
          turns.push_back(Vector<5>(value[k], IndexItem(at, k)) * (M_PI / 180.0));
        }
      }
      design.six_bars.push_back(six_bar);
      design.inputs.push_back(input);
      design.at_poses.push_back(turns);
    }
    return design;
  }

  Task Parse(const std::string& text) const {
    DigitTallies tallies;
    const Json root = ParseJson(text, &tallies);
    if (!root.is_object()) Fail("top level", "expected an object, got " + Describe(root));
    CheckKeys(root, "",
              {"problem", "space", "poses", "points", "scale", "precision", "options",
               "moving_pivots", "fixed_pivots", "moving_axes", "fixed_axes", "platform",
               "constraints", "pairs", "angles", "ground", "function", "linkage", "chain"});

    Task task;
    task.problem = ParseEnum<ProblemKind>(root, "", "problem", ProblemKind::kMotion,
                                          {{"motion", ProblemKind::kMotion},
                                           {"path", ProblemKind::kPath},
                                           {"function", ProblemKind::kFunction}});
    task.space = ParseEnum<Space>(root, "", "space", Space::kPlanar,
                                  {{"planar", Space::kPlanar}, {"spatial", Space::kSpatial}});
    if (root.contains("options")) {
      const Json& options = root.at("options");
      if (!options.is_object()) Fail("options", "expected an object, got " + Describe(options));
      CheckKeys(options, "options", {"effort"});
      task.effort = ParseEnum<Effort>(options, "options", "effort", Effort::kBalanced,
                                      {{"fast", Effort::kFast},
                                       {"balanced", Effort::kBalanced},
                                       {"thorough", Effort::kThorough}});
    }
    if (root.contains("scale")) task.scale = Positive(root.at("scale"), "scale");
    ReadPrecision(root, tallies, &task);

    if (task.problem == ProblemKind::kMotion) {
      if (root.contains("points")) Fail("points", "not used by motion problems (give \"poses\")");
      const Json& poses = Items(
          root, "poses", task.space == Space::kPlanar ? 3 : 1,
          task.space == Space::kPlanar ? "planar motion synthesis" : "spatial motion synthesis");
      if (task.space == Space::kPlanar) {
        ParsePlanarPoses(poses, &task);
        task.moving_pivots = Pivots<2>(root, "moving_pivots");
        task.fixed_pivots = Pivots<2>(root, "fixed_pivots");
        std::vector<Eigen::Vector2d> origins;
        for (const PlanarPose& pose : task.planar_poses) origins.push_back(pose.origin_in_fixed);
        CheckPivotReach(task.moving_pivots, task.fixed_pivots, origins, task.scale);
        if (task.planar_poses.size() >= 5 &&
            !(task.moving_pivots.empty() && task.fixed_pivots.empty())) {
          Fail(task.moving_pivots.empty() ? "fixed_pivots" : "moving_pivots",
               "used with three or four poses only (five poses determine the dyads)");
        }
      } else {
        ParseSpatialPoses(poses, &task);
        task.spatial_moving_pivots = Pivots<3>(root, "moving_pivots");
        task.spatial_fixed_pivots = Pivots<3>(root, "fixed_pivots");
        std::vector<Eigen::Vector3d> origins;
        for (const DualQuaternion& pose : task.spatial_poses) origins.push_back(pose.Translation());
        CheckPivotReach(task.spatial_moving_pivots, task.spatial_fixed_pivots, origins, task.scale);
        const size_t count = task.spatial_poses.size();
        if ((count < 4 || count >= 7) &&
            !(task.spatial_moving_pivots.empty() && task.spatial_fixed_pivots.empty())) {
          Fail(task.spatial_moving_pivots.empty() ? "fixed_pivots" : "moving_pivots",
               count < 4 ? "need at least four poses (a sphere through the pivot's positions)"
                         : "used with four to six poses only (seven poses determine the dyads)");
        }
        task.moving_axes = Axes(root, "moving_axes");
        task.fixed_axes = Axes(root, "fixed_axes");
        if ((count < 3 || count > 4) && !(task.moving_axes.empty() && task.fixed_axes.empty())) {
          Fail(task.moving_axes.empty() ? "fixed_axes" : "moving_axes",
               count < 3 ? "need three or four poses (a circle of the sphere through the axis's "
                           "positions)"
                         : "used with three or four poses only (five orientations determine the "
                           "spherical dyads)");
        }
        task.platform = Platform(root);
      }
    } else if (task.problem == ProblemKind::kFunction) {
      if (task.space == Space::kSpatial) Fail("space", "function problems are planar only");
      for (const char* key : {"poses", "points"}) {
        if (root.contains(key)) {
          Fail(key, "not used by function problems (give \"pairs\" or \"function\")");
        }
      }
      if (task.scale) Fail("scale", "not used by function problems (the ground's length is L)");
      ParseFunctionTask(root, &task);
    } else {
      if (task.space == Space::kSpatial) Fail("space", "path problems are planar only");
      if (root.contains("poses")) Fail("poses", "not used by path problems (give \"points\")");
      ParsePoints(Items(root, "points", 1, "path synthesis"), &task);
    }
    if (task.problem != ProblemKind::kFunction) {
      for (const char* key : {"pairs", "angles", "ground", "function"}) {
        if (root.contains(key)) Fail(key, "used by function problems only");
      }
    }
    if (task.problem != ProblemKind::kMotion) {
      for (const char* key : {"moving_pivots", "fixed_pivots"}) {
        if (root.contains(key)) Fail(key, "used by motion problems only");
      }
    }
    if (task.space != Space::kSpatial || task.problem != ProblemKind::kMotion) {
      for (const char* key : {"moving_axes", "fixed_axes"}) {
        if (root.contains(key))
          Fail(key, "used by spatial motion problems only (spherical motion)");
      }
    }
    if ((task.space != Space::kSpatial || task.problem != ProblemKind::kMotion) &&
        root.contains("platform")) {
      Fail("platform", "used by spatial motion problems only");
    }
    if (root.contains("constraints")) ReadConstraints(root.at("constraints"), &task);
    ReadSixBar(root, &task);
    return task;
  }

  // "linkage": "six-bar" and its "chain" (planar motion, five poses; lib/six_bar.h): the 3R
  // chain's ground pivot (Sigma), wrist (E), link lengths and elbow, every pose within its reach.
  void ReadSixBar(const Json& root, Task* task) const {
    task->six_bar =
        ParseEnum<bool>(root, "", "linkage", false, {{"four-bar", false}, {"six-bar", true}});
    if (!task->six_bar) {
      if (root.contains("chain")) Fail("chain", "used with \"linkage\": \"six-bar\" only");
      return;
    }
    if (task->problem != ProblemKind::kMotion || task->space != Space::kPlanar) {
      Fail("linkage", "six-bars are synthesized for planar motion only");
    }
    if (task->planar_poses.size() < 5) {
      Fail("poses", "a six-bar task takes five poses (exactly) or more (least squares); got " +
                        std::to_string(task->planar_poses.size()));
    }
    if (!root.contains("chain")) return;  // linkfit chooses one (fitting/six_bar_chains.h)
    const Json& value = Object(root.at("chain"), "chain");
    CheckKeys(value, "chain",
              {"ground_pivot", "wrist", "link_lengths", "elbow_at_first_pose", "elbow", "hold"});
    SixBarChain chain;
    chain.ground_pivot = Vector<2>(Field(value, "chain", "ground_pivot"), "chain.ground_pivot");
    chain.wrist_in_moving = Vector<2>(Field(value, "chain", "wrist"), "chain.wrist");
    const Json& lengths = Field(value, "chain", "link_lengths");
    if (!lengths.is_array() || lengths.size() != 2) {
      Fail("chain.link_lengths", "expected [upper, forearm], got " + Describe(lengths));
    }
    chain.upper_length = Positive(lengths[0], "chain.link_lengths[0]");
    chain.forearm_length = Positive(lengths[1], "chain.link_lengths[1]");
    if (value.contains("elbow_at_first_pose") && value.contains("elbow")) {
      Fail("chain.elbow", "give \"elbow\" or \"elbow_at_first_pose\", not both");
    }
    if (value.contains("elbow_at_first_pose")) {
      chain.elbow_at_first_pose =
          Vector<2>(value.at("elbow_at_first_pose"), "chain.elbow_at_first_pose");
    }
    chain.elbow_left =
        ParseEnum<bool>(value, "chain", "elbow", true, {{"left", true}, {"right", false}});
    if (value.contains("hold")) chain.hold = Bool(value.at("hold"), "chain.hold");
    std::vector<Eigen::Vector2d> elbows;
    int unreachable = -1;
    if (!ChainElbows(task->planar_poses, chain, &elbows, &unreachable)) {
      const Eigen::Vector2d wrist = task->planar_poses[unreachable].ToFixed(chain.wrist_in_moving);
      Fail(IndexItem("poses", unreachable),
           "out of the chain's reach: its wrist is " +
               FormatNumber((wrist - chain.ground_pivot).norm()) +
               " from the ground pivot, the links reach " +
               FormatNumber(std::abs(chain.upper_length - chain.forearm_length)) + " to " +
               FormatNumber(chain.upper_length + chain.forearm_length));
    }
    task->chain = chain;
  }

 private:
  [[noreturn]] void Fail(const std::string& item, const std::string& what) const {
    throw InputError(source_ + ": " + item + ": " + what);
  }

  // Parses the text after rejecting deep nesting; syntax errors give line and column.
  Json ParseJson(const std::string& text, DigitTallies* tallies = nullptr) const {
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
      throw InputError(source_ + ": no JSON text (empty input)");
    }
    CheckDepth(text);
    Json root;
    TrackingSax sax(&root, source_, options_);
    const ParsePath& path = sax.path();
    try {
      Json::sax_parse(text, &sax);
      if (tallies != nullptr) *tallies = sax.tallies();
      return root;
    } catch (const Json::parse_error& error) {
      // byte is the 1-based index of the last character read (size + 1 at the end).
      const size_t last = error.byte == 0 ? 0 : std::min<size_t>(error.byte - 1, text.size());
      const auto [line, column] = LineColumn(text, last);
      // Where the parser was: the value being read, or the last key or element before the
      // fault.
      const std::string item = path.Current();
      // NaN and Infinity, as some JSON writers emit them, are not JSON: say so plainly.
      size_t token = last;
      while (token > 0 && (std::isalpha(static_cast<unsigned char>(text[token - 1])) ||
                           text[token - 1] == '-')) {
        --token;
      }
      const std::string word = text.substr(token, 9);
      if (word.rfind("NaN", 0) == 0 || word.rfind("nan", 0) == 0 || word.rfind("Inf", 0) == 0 ||
          word.rfind("-Inf", 0) == 0 || word.rfind("inf", 0) == 0 || word.rfind("-inf", 0) == 0) {
        Fail(item.empty() ? "top level" : item, "NaN and Infinity are not numbers (line " +
                                                    std::to_string(line) + ", column " +
                                                    std::to_string(column) + ")");
      }
      throw InputError(source_ + ": malformed JSON at line " + std::to_string(line) + ", column " +
                       std::to_string(column) + (item.empty() ? "" : " (near " + item + ")") +
                       ": " + ParserReason(error.what()));
    } catch (const Json::out_of_range& error) {
      // 406: a number such as 1e999 overflows to infinity.
      const std::string item = path.Current().empty() ? "top level" : path.Current();
      if (error.id == 406) Fail(item, "not a finite number (" + ParserReason(error.what()) + ")");
      Fail(item, ParserReason(error.what()));
    } catch (const Json::exception& error) {
      throw InputError(source_ + ": malformed JSON: " + ParserReason(error.what()));
    }
  }

  // nlohmann's parser is iterative, but deep values are still costly to build and destroy,
  // and nothing in a task needs more than a few levels: reject deep input up front.
  void CheckDepth(const std::string& text) const {
    int depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < text.size(); ++i) {
      const char c = text[i];
      if (in_string) {
        if (c == '\\') {
          ++i;
        } else if (c == '"') {
          in_string = false;
        }
      } else if (c == '"') {
        in_string = true;
      } else if (c == '[' || c == '{') {
        if (++depth > kMaxDepth) {
          const auto [line, column] = LineColumn(text, i);
          throw InputError(source_ + ": malformed JSON at line " + std::to_string(line) +
                           ", column " + std::to_string(column) + ": nested deeper than " +
                           std::to_string(kMaxDepth) + " levels");
        }
      } else if (c == ']' || c == '}') {
        --depth;
      }
    }
  }

  // The part of a nlohmann message after "[json.exception...] parse error at ...: ".
  static std::string ParserReason(const std::string& what) {
    std::string reason = what;
    if (reason.rfind("[json.exception.", 0) == 0) {
      const size_t bracket = reason.find("] ");
      if (bracket != std::string::npos) reason = reason.substr(bracket + 2);
    }
    if (reason.rfind("parse error", 0) == 0) {
      const size_t colon = reason.find(": ");
      if (colon != std::string::npos) reason = reason.substr(colon + 2);
    }
    return Sanitize(reason, 160);
  }

  void CheckKeys(const Json& object, const std::string& item,
                 std::initializer_list<const char*> allowed) const {
    for (const auto& entry : object.items()) {
      const bool known = std::any_of(allowed.begin(), allowed.end(),
                                     [&](const char* name) { return entry.key() == name; });
      if (!known) {
        std::string names;
        for (const char* name : allowed) names += std::string(names.empty() ? "" : ", ") + name;
        Fail(KeyItem(item, entry.key()), "unknown field (known fields: " + names + ")");
      }
    }
  }

  const Json& Field(const Json& object, const std::string& item, const char* key) const {
    const auto it = object.find(key);
    if (it == object.end()) Fail(KeyItem(item, key), "missing field");
    return *it;
  }

  double Number(const Json& value, const std::string& item) const {
    if (!value.is_number()) Fail(item, "expected a number, got " + Describe(value));
    const double number = value.get<double>();
    if (!std::isfinite(number)) Fail(item, "not a finite number");
    return number;
  }

  double Positive(const Json& value, const std::string& item) const {
    const double number = Number(value, item);
    if (!(number > 0.0)) Fail(item, "must be positive, got " + FormatNumber(number));
    return number;
  }

  double NonNegative(const Json& value, const std::string& item) const {
    const double number = Number(value, item);
    if (!(number >= 0.0)) Fail(item, "must not be negative, got " + FormatNumber(number));
    return number;
  }

  bool Bool(const Json& value, const std::string& item) const {
    if (!value.is_boolean()) Fail(item, "expected true or false, got " + Describe(value));
    return value.get<bool>();
  }

  // An optional array of [x, y] (N = 2) or [x, y, z] (N = 3) points.
  template <int N>
  std::vector<Eigen::Matrix<double, N, 1>> Pivots(const Json& root, const char* key) const {
    std::vector<Eigen::Matrix<double, N, 1>> pivots;
    if (!root.contains(key)) return pivots;
    const Json& value = root.at(key);
    if (!value.is_array()) {
      Fail(key, std::string("expected an array of ") + (N == 2 ? "[x, y]" : "[x, y, z]") +
                    " points, got " + Describe(value));
    }
    if (value.size() > 16) Fail(key, "at most 16 pivots, got " + std::to_string(value.size()));
    for (size_t i = 0; i < value.size(); ++i)
      pivots.push_back(Vector<N>(value[i], IndexItem(key, i)));
    return pivots;
  }

  // Pivots the task gives (moving ones in E, from its origin; fixed ones in Sigma, from the pose
  // origins' centroid) within kMaxPivotReach L: farther, a pivot's circle (or sphere) through its
  // positions is lost in the rounding of its coordinates, and at 1e200 its squares overflow
  // (a pivot that far runs on a line: a slider, which pivots do not ask for).
  template <typename Vec>
  void CheckPivotReach(const std::vector<Vec>& moving, const std::vector<Vec>& fixed,
                       const std::vector<Vec>& origins, const std::optional<double>& scale) const {
    if (moving.empty() && fixed.empty()) return;
    Vec centroid = Vec::Zero();
    for (const Vec& origin : origins) centroid += origin / static_cast<double>(origins.size());
    double sum = 0.0;
    for (const Vec& origin : origins) sum += (origin - centroid).squaredNorm();
    const double length = scale ? *scale : std::sqrt(sum / static_cast<double>(origins.size()));
    if (!(length > 0.0) || !std::isfinite(length)) return;  // the poses' own checks say why
    for (const bool in_moving : {true, false}) {
      const std::vector<Vec>& pivots = in_moving ? moving : fixed;
      for (size_t i = 0; i < pivots.size(); ++i) {
        const double reach =
            (in_moving ? pivots[i] : Vec(pivots[i] - centroid)).stableNorm() / length;
        if (reach <= kMaxPivotReach) continue;
        char text[160];
        std::snprintf(text, sizeof(text),
                      "%.3g L from %s, farther than %.0e L: its circle through the poses is lost "
                      "in rounding (a pivot that far runs on a line, a slider)",
                      reach, in_moving ? "the moving frame's origin" : "the poses", kMaxPivotReach);
        Fail(IndexItem(in_moving ? "moving_pivots" : "fixed_pivots", i), text);
      }
    }
  }

  // Axes through a spherical motion's centre: non-zero directions [x, y, z].
  std::vector<Eigen::Vector3d> Axes(const Json& root, const char* key) const {
    std::vector<Eigen::Vector3d> axes = Pivots<3>(root, key);
    for (size_t i = 0; i < axes.size(); ++i) {
      if (!(axes[i].norm() > 0.0)) Fail(IndexItem(key, i), "a zero vector is not a direction");
    }
    return axes;
  }

  // An axis-aligned box [[xmin, ymin], [xmax, ymax]].
  PlanarBox Box(const Json& value, const std::string& item) const {
    if (!value.is_array() || value.size() != 2) {
      Fail(item, "expected [[xmin, ymin], [xmax, ymax]], got " + Describe(value));
    }
    PlanarBox box;
    box.min = Vector<2>(value[0], IndexItem(item, 0));
    box.max = Vector<2>(value[1], IndexItem(item, 1));
    for (int i = 0; i < 2; ++i) {
      if (!(box.min[i] <= box.max[i])) {
        Fail(item, std::string("the lower corner's ") + (i == 0 ? "x" : "y") + " (" +
                       FormatNumber(box.min[i]) + ") is above the upper corner's (" +
                       FormatNumber(box.max[i]) + ")");
      }
    }
    return box;
  }

  // "constraints" (lib/design_constraints.h): planar motion and path problems; spatial motion
  // takes those of a spherical four-bar's class and transmission only (its links are angles).
  void ReadConstraints(const Json& value, Task* task) const {
    const char* item = "constraints";
    if (!value.is_object()) Fail(item, "expected an object, got " + Describe(value));
    CheckKeys(
        value, item,
        {"max_link_length", "min_link_length", "max_coupler_point_offset", "fixed_pivots_box",
         "moving_pivots_box", "input_rotates_fully", "grashof", "min_transmission_angle_deg"});
    if (task->space == Space::kSpatial) {
      for (const char* key : {"max_link_length", "min_link_length", "max_coupler_point_offset",
                              "fixed_pivots_box", "moving_pivots_box"}) {
        if (value.contains(key)) {
          Fail(KeyItem(item, key),
               "not used by spatial tasks: spherical four-bars' links are angles and their pivots "
               "axes (spatial tasks take input_rotates_fully, grashof and "
               "min_transmission_angle_deg)");
        }
      }
    }
    DesignConstraints& constraints = task->constraints;
    constraints.given = true;
    const auto positive = [&](const char* key, std::optional<double>* out) {
      if (value.contains(key)) *out = Positive(value.at(key), KeyItem(item, key));
    };
    positive("max_link_length", &constraints.max_link_length);
    positive("min_link_length", &constraints.min_link_length);
    positive("max_coupler_point_offset", &constraints.max_coupler_point_offset);
    if (constraints.min_link_length && constraints.max_link_length &&
        !(*constraints.min_link_length <= *constraints.max_link_length)) {
      Fail(KeyItem(item, "min_link_length"),
           "above max_link_length (" + FormatNumber(*constraints.max_link_length) + ")");
    }
    if (constraints.max_coupler_point_offset && task->problem != ProblemKind::kPath) {
      Fail(KeyItem(item, "max_coupler_point_offset"), "used by path problems only");
    }
    if (value.contains("fixed_pivots_box")) {
      if (task->problem == ProblemKind::kFunction) {
        Fail(KeyItem(item, "fixed_pivots_box"),
             "not used by function problems (their fixed pivots are the task's \"ground\")");
      }
      constraints.fixed_pivots_box =
          Box(value.at("fixed_pivots_box"), KeyItem(item, "fixed_pivots_box"));
    }
    if (value.contains("moving_pivots_box")) {
      if (task->problem != ProblemKind::kMotion) {
        Fail(KeyItem(item, "moving_pivots_box"),
             "used by motion problems only (a path four-bar's coupler has no frame of the task)");
      }
      constraints.moving_pivots_box =
          Box(value.at("moving_pivots_box"), KeyItem(item, "moving_pivots_box"));
    }
    if (value.contains("input_rotates_fully")) {
      constraints.input_rotates_fully =
          Bool(value.at("input_rotates_fully"), KeyItem(item, "input_rotates_fully"));
    }
    if (value.contains("grashof")) {
      const Json& grashof = value.at("grashof");
      const std::string names =
          "\"grashof\", \"non-grashof\", \"crank-rocker\", \"double-crank\", "
          "\"double-rocker\", \"rocker-crank\", \"triple-rocker\" or \"change-point\"";
      if (!grashof.is_string()) {
        Fail(KeyItem(item, "grashof"), "expected " + names + ", got " + Describe(grashof));
      }
      const std::string& name = grashof.get_ref<const std::string&>();
      for (const char* known : {"grashof", "non-grashof", "crank-rocker", "double-crank",
                                "double-rocker", "rocker-crank", "triple-rocker", "change-point"}) {
        if (name == known) constraints.grashof = name;
      }
      if (constraints.grashof.empty()) {
        Fail(KeyItem(item, "grashof"), "expected " + names + ", got " + Quote(name));
      }
    }
    if (value.contains("min_transmission_angle_deg")) {
      const std::string key = KeyItem(item, "min_transmission_angle_deg");
      const double angle = NonNegative(value.at("min_transmission_angle_deg"), key);
      if (!(angle <= 90.0)) Fail(key, "at most 90, got " + FormatNumber(angle));
      constraints.min_transmission_angle_deg = angle;
    }
  }

  // An optional array of five distinct dyad indices.
  std::vector<int> Platform(const Json& root) const {
    std::vector<int> platform;
    if (!root.contains("platform")) return platform;
    const Json& value = root.at("platform");
    if (!value.is_array() || value.size() != 5) {
      Fail("platform", "expected an array of five dyad indices, got " + Describe(value));
    }
    for (size_t i = 0; i < value.size(); ++i) {
      const std::string item = IndexItem("platform", i);
      const Json& index = value[i];
      if (!index.is_number_integer() || index.get<long long>() < 0 ||
          index.get<long long>() > 1000) {
        Fail(item, "expected a dyad index (an integer from 0), got " + Describe(index));
      }
      const int dyad = static_cast<int>(index.get<long long>());
      if (std::find(platform.begin(), platform.end(), dyad) != platform.end()) {
        Fail(item, "dyad " + std::to_string(dyad) + " named twice");
      }
      platform.push_back(dyad);
    }
    return platform;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> Vector(const Json& value, const std::string& item) const {
    const std::string expected = "expected an array of " + std::to_string(N) + " numbers";
    if (!value.is_array()) Fail(item, expected + ", got " + Describe(value));
    if (value.size() != static_cast<size_t>(N)) {
      Fail(item, expected + ", got " + std::to_string(value.size()) + " elements");
    }
    Eigen::Matrix<double, N, 1> vector;
    for (int i = 0; i < N; ++i) vector[i] = Number(value[i], IndexItem(item, i));
    return vector;
  }

  Eigen::Matrix3d Matrix3(const Json& value, const std::string& item) const {
    const std::string expected = "expected 3 rows of 3 numbers";
    if (!value.is_array()) Fail(item, expected + ", got " + Describe(value));
    if (value.size() != 3) Fail(item, expected + ", got " + std::to_string(value.size()) + " rows");
    Eigen::Matrix3d matrix;
    for (int row = 0; row < 3; ++row) matrix.row(row) = Vector<3>(value[row], IndexItem(item, row));
    return matrix;
  }

  template <typename Enum>
  Enum ParseEnum(const Json& object, const std::string& parent, const char* key, Enum fallback,
                 std::initializer_list<std::pair<const char*, Enum>> choices) const {
    const auto it = object.find(key);
    if (it == object.end()) return fallback;
    std::string names;
    for (const auto& choice : choices) {
      names += std::string(names.empty() ? "" : " or ") + "\"" + choice.first + "\"";
    }
    const std::string item = KeyItem(parent, key);
    if (!it->is_string()) Fail(item, "expected " + names + ", got " + Describe(*it));
    for (const auto& choice : choices) {
      if (it->get_ref<const std::string&>() == choice.first) return choice.second;
    }
    Fail(item, "expected " + names + ", got " + Quote(it->get<std::string>()));
  }

  // The array `key` of `root`, with its length checked against `minimum` and the limit.
  const Json& Items(const Json& root, const char* key, size_t minimum,
                    const std::string& purpose) const {
    const Json& items = Field(root, "", key);
    if (!items.is_array()) Fail(key, "expected an array, got " + Describe(items));
    if (items.size() < minimum) {
      Fail(key, ItemCount(key, items.size()) + ", " + purpose + " needs at least " +
                    std::to_string(minimum));
    }
    // TrackingSax already stops at the limit while parsing; this is the check of record.
    if (items.size() > options_.max_items) {
      Fail(key, OverLimit(key, items.size(), options_.max_items));
    }
    return items;
  }

  // Reads "precision" and the digits' half units (lib/precision.h) into the parser's state;
  // the task's precision is completed by FinishPrecision once the poses are read.
  void ReadPrecision(const Json& root, const DigitTallies& tallies, Task* task) const {
    for (int kind = 0; kind < kDigitKinds; ++kind) half_units_[kind] = tallies[kind].HalfUnit();
    given_length_ = given_angle_ = -1.0;
    repairs_ = RepairLog();
    if (!root.contains("precision")) return;
    const Json& precision = Object(root.at("precision"), "precision");
    CheckKeys(precision, "precision", {"length", "angle_deg"});
    if (precision.empty()) Fail("precision", "give \"length\", \"angle_deg\" or both");
    if (precision.contains("length")) {
      given_length_ = NonNegative(precision.at("length"), "precision.length");
    }
    if (precision.contains("angle_deg")) {
      given_angle_ = NonNegative(precision.at("angle_deg"), "precision.angle_deg") * kDegree;
      if (!(given_angle_ < M_PI)) Fail("precision.angle_deg", "must be below 180");
    }
    task->precision.source = "task";
  }

  // Half units of one kind for repair tolerances: the digits', or what the given precision
  // implies for such a number (`per_length` and `per_angle` convert), whichever is larger.
  double RepairHalfUnit(int kind, double per_length, double per_angle) const {
    double half_unit = half_units_[kind];
    if (given_length_ > 0.0) half_unit = std::max(half_unit, per_length * given_length_);
    if (given_angle_ > 0.0) half_unit = std::max(half_unit, per_angle * given_angle_);
    return half_unit;
  }

  // The task's precision: given, or from the digits (lengths; angles and dimensionless entries
  // as radians of rotation), never below the rounding of the largest coordinate.
  // `direction_norm` is the shortest x_axis / y_axis vector (directions given by lengths).
  void FinishPrecision(double largest_coordinate, double direction_norm, Task* task) const {
    // What rounding every entry by its half unit h can do to a pose: a quaternion (4 entries)
    // turns by up to 2 |e| = 4 h; a rotation matrix or axis by up to about 2 h; a translation
    // d = 2 g q* moves by up to 4 h_g + 2 |d| h_q (seed 000 eq. 7).
    double length =
        std::max(half_units_[kLengthDigits],
                 4.0 * half_units_[kHalfLengthDigits] +
                     2.0 * largest_coordinate * std::sqrt(3.0) * half_units_[kQuaternionDigits]);
    double angle = std::max({half_units_[kDegreeDigits] * kDegree, 2.0 * half_units_[kUnitDigits],
                             4.0 * half_units_[kQuaternionDigits]});
    if (direction_norm > 0.0)
      angle = std::max(angle, half_units_[kDirectionDigits] / direction_norm);
    const bool given = task->precision.source == "task";
    if (given && given_length_ < 0.0) {
      task->input_notes.push_back("precision.length not given: inferred from the digits as " +
                                  PrecisionText(length));
    }
    if (given && given_angle_ < 0.0) {
      task->input_notes.push_back("precision.angle_deg not given: inferred from the digits as " +
                                  PrecisionText(angle / kDegree));
    }
    if (given_length_ >= 0.0) length = given_length_;
    if (given_angle_ >= 0.0) angle = given_angle_;
    const double epsilon = std::numeric_limits<double>::epsilon();
    task->precision.length = std::max(length, epsilon * largest_coordinate);
    task->precision.angle = std::max(angle, epsilon * M_PI);
    if (repairs_.quaternions + repairs_.rotations > 0) {
      std::string what;
      if (repairs_.quaternions > 0) {
        what = std::to_string(repairs_.quaternions) +
               (repairs_.quaternions == 1 ? " dual quaternion" : " dual quaternions") +
               " made unit (q normalized, its component removed from g)";
      }
      if (repairs_.rotations > 0) {
        what += std::string(what.empty() ? "" : " and ") + std::to_string(repairs_.rotations) +
                (repairs_.rotations == 1 ? " rotation matrix" : " rotation matrices") +
                " made orthonormal (the nearest rotation)";
      }
      task->input_notes.push_back("input repaired within its precision: " + what +
                                  "; largest correction " + PrecisionText(repairs_.largest) + " (" +
                                  repairs_.largest_item + ")");
    }
  }

  void ParseWeightAndExact(const Json& object, const std::string& item, double* weight,
                           bool* exact) const {
    *weight =
        object.contains("weight") ? Positive(object.at("weight"), KeyItem(item, "weight")) : 1.0;
    *exact = object.contains("exact") ? Bool(object.at("exact"), KeyItem(item, "exact")) : false;
  }

  const Json& Object(const Json& value, const std::string& item) const {
    if (!value.is_object()) Fail(item, "expected an object, got " + Describe(value));
    return value;
  }

  void ParsePlanarPoses(const Json& poses, Task* task) const {
    double largest = 0.0;
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string item = IndexItem("poses", i);
      const Json& pose = Object(poses[i], item);
      CheckKeys(pose, item, {"x", "y", "theta_deg", "weight", "exact"});
      const double x = Number(Field(pose, item, "x"), KeyItem(item, "x"));
      const double y = Number(Field(pose, item, "y"), KeyItem(item, "y"));
      const double theta_deg = Number(Field(pose, item, "theta_deg"), KeyItem(item, "theta_deg"));
      largest = std::max({largest, std::abs(x), std::abs(y)});
      task->planar_poses.emplace_back(x, y, WrapAngle(theta_deg * kDegree));
      double weight;
      bool exact;
      ParseWeightAndExact(pose, item, &weight, &exact);
      task->pose_weights.push_back(weight);
      task->pose_exact.push_back(exact);
    }
    FinishPrecision(largest, 0.0, task);
    std::vector<Eigen::Vector2d> origins;
    origins.reserve(task->planar_poses.size());
    for (const PlanarPose& pose : task->planar_poses) origins.push_back(pose.origin_in_fixed);
    const double length = Length(origins, task->scale, "poses", "pose origins");
    const auto coincide = [&](size_t i, size_t j, bool within_precision) {
      const PlanarPose& a = task->planar_poses[i];
      const PlanarPose& b = task->planar_poses[j];
      return Coincide(
          PoseError(a, b, length), (a.origin_in_fixed - b.origin_in_fixed).cwiseAbs().maxCoeff(),
          std::abs(WrapAngle(a.theta - b.theta)), length, 1.0, task->precision, within_precision);
    };
    if (CloseLoop("poses", coincide, 3, "planar motion synthesis", task)) {
      task->planar_poses.pop_back();
      origins.pop_back();
    }
    CheckCoincident<4>(
        "poses", task->planar_poses.size(),
        [&](size_t i) {
          const PlanarPose& pose = task->planar_poses[i];
          return Eigen::Vector4d(pose.origin_in_fixed.x(), pose.origin_in_fixed.y(),
                                 length * std::cos(pose.theta), length * std::sin(pose.theta));
        },
        1.0, CoincidentWindow(1.0, length), coincide);
  }

  // Two poses or points are coincident when their pose error is within coincident_tolerance
  // * L (equal as printed: rounding apart). Only a last item that closes a loop (CloseLoop) is
  // also matched `within_precision`: every coordinate within delta and the angle within alpha
  // (spatial: the rotation between them within 2 alpha, as rounding every entry of a rotation can
  // turn it by up to about sqrt(2) alpha). Two items that differ in print are never refused as
  // coincident (issue 34: a two-decimal table's neighbours are 0.05 apart at precision 0.005).
  bool Coincide(double pose_error, double largest_offset, double angle, double length,
                double angle_units, const DataPrecision& precision, bool within_precision) const {
    return pose_error <= options_.coincident_tolerance * length ||
           (within_precision && largest_offset <= precision.length &&
            angle <= angle_units * precision.angle);
  }

  // The distance along a sort key within which coincident items lie (CheckCoincident): the
  // feature distance that Coincide allows without `within_precision`, `lipschitz` times the pose
  // error bound.
  double CoincidentWindow(double lipschitz, double length) const {
    return lipschitz * options_.coincident_tolerance * length;
  }

  // A last pose or point that repeats the first within precision closes the motion or path:
  // the repeat is dropped (the caller pops it), its weight and exact flag merged into the
  // first, task->closed set and a note added. `coincide(i, j)` compares two items; `minimum`
  // is what the problem needs of the items that remain.
  template <typename Coincide>
  bool CloseLoop(const char* key, const Coincide& coincide, size_t minimum,
                 const std::string& purpose, Task* task) const {
    const bool poses = std::string(key) == "poses";
    const size_t count = poses ? task->pose_weights.size() : task->points.size();
    if (count < 3 || !coincide(0, count - 1, true)) return false;
    const std::string last = IndexItem(key, count - 1);
    if (count - 1 < minimum) {
      Fail(last, "repeats " + std::string(key) + "[0] (a closed " + (poses ? "motion" : "path") +
                     "), which leaves " + ItemCount(key, count - 1) + "; " + purpose +
                     " needs at least " + std::to_string(minimum));
    }
    if (poses) {
      task->pose_weights[0] = std::max(task->pose_weights[0], task->pose_weights.back());
      task->pose_exact[0] = task->pose_exact[0] || task->pose_exact.back();
      task->pose_weights.pop_back();
      task->pose_exact.pop_back();
      task->input_notes.push_back(
          last +
          " repeats poses[0] within the data's precision: a closed motion; the pose is "
          "used once");
    } else {
      task->points[0].weight = std::max(task->points[0].weight, task->points.back().weight);
      task->points[0].exact = task->points[0].exact || task->points.back().exact;
      task->points.pop_back();
      task->input_notes.push_back(
          last +
          " repeats points[0] within the data's precision: a closed path, the input "
          "crank makes a whole turn from points[0] back to it");
    }
    task->closed = true;
    return true;
  }

  // One spatial pose in any of its five forms (README, "Task file"); unit conditions repaired
  // within the precision of the digits and refused beyond it.
  DualQuaternion ParseSpatialPose(const Json& pose, const std::string& item) const {
    const bool dual = pose.contains("q") || pose.contains("g");
    const bool matrix = pose.contains("rotation");
    const bool axis = pose.contains("axis") || pose.contains("angle_deg");
    const bool euler = pose.contains("euler_deg") || pose.contains("euler_axes");
    const bool frame = pose.contains("x_axis") || pose.contains("y_axis");
    if (dual + matrix + axis + euler + frame != 1) {
      Fail(item,
           "give exactly one of {\"q\", \"g\"}, {\"rotation\", \"translation\"}, "
           "{\"axis\", \"angle_deg\", \"translation\"}, {\"euler_deg\", \"euler_axes\", "
           "\"translation\"} or {\"translation\", \"x_axis\", \"y_axis\"}");
    }
    const double epsilon = std::numeric_limits<double>::epsilon();
    if (dual) {
      CheckKeys(pose, item, {"q", "g", "weight", "exact"});
      const std::string q_item = KeyItem(item, "q"), g_item = KeyItem(item, "g");
      DualQuaternion dq;
      dq.q = Vector<4>(Field(pose, item, "q"), q_item);
      dq.g = Vector<4>(Field(pose, item, "g"), g_item);
      // First-order bounds of what rounding each component to its half unit can do to
      // |q| - 1 (seed 000 eq. 2) and to q . g (eq. 3).
      const double q_half = RepairHalfUnit(kQuaternionDigits, 0.0, 0.5);
      const double g_half = RepairHalfUnit(kHalfLengthDigits, 0.5, 0.0);
      const double q_sum = dq.q.cwiseAbs().sum(), g_sum = dq.g.cwiseAbs().sum();
      const double norm_off = std::abs(dq.q.norm() - 1.0);
      const double norm_allowed = options_.repair_units * q_sum * q_half + kRoundingUnits * epsilon;
      if (!(norm_off <= norm_allowed)) {
        Fail(q_item, "not a unit quaternion: |q| = " + FormatNumber(dq.q.norm()) + ", off by " +
                         PrecisionText(norm_off) + "; the precision of its digits (" +
                         PrecisionText(q_half) + " per component) accepts at most " +
                         PrecisionText(norm_allowed));
      }
      const double q_dot_g = dq.OrthogonalityDefect();
      const double dot_allowed = options_.repair_units * (g_sum * q_half + q_sum * g_half) +
                                 kRoundingUnits * epsilon * dq.q.norm() * dq.g.norm();
      if (!(std::abs(q_dot_g) <= dot_allowed)) {
        Fail(g_item, "q . g = " + FormatNumber(q_dot_g) +
                         ", must be 0; the precision of the digits accepts at most " +
                         PrecisionText(dot_allowed));
      }
      const DualQuaternion unit = dq.Normalized();
      NoteRepair(
          true,
          std::max((unit.q - dq.q).cwiseAbs().maxCoeff(),
                   (unit.g - dq.g).cwiseAbs().maxCoeff() / std::max(1.0, g_sum)),
          std::max((unit.q - dq.q).cwiseAbs().maxCoeff(), (unit.g - dq.g).cwiseAbs().maxCoeff()),
          item);
      return unit;
    }
    const std::string translation_item = KeyItem(item, "translation");
    if (matrix) {
      CheckKeys(pose, item, {"rotation", "translation", "weight", "exact"});
      const std::string rotation_item = KeyItem(item, "rotation");
      const Eigen::Matrix3d rotation = Matrix3(Field(pose, item, "rotation"), rotation_item);
      const Eigen::Vector3d translation =
          Vector<3>(Field(pose, item, "translation"), translation_item);
      // Entry (i, j) of R^T R - I moves by at most sum_k (|R_ki| + |R_kj|) h when every entry
      // moves by its half unit h.
      const double half = RepairHalfUnit(kUnitDigits, 0.0, 1.0);
      const Eigen::Matrix3d defect = rotation.transpose() * rotation - Eigen::Matrix3d::Identity();
      const Eigen::RowVector3d column_sums = rotation.cwiseAbs().colwise().sum();
      double worst_ratio = 0.0, worst_defect = 0.0, worst_allowed = 0.0;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const double allowed = options_.repair_units * (column_sums[i] + column_sums[j]) * half +
                                 kRoundingUnits * epsilon;
          const double ratio = std::abs(defect(i, j)) / allowed;
          if (!(ratio <= worst_ratio)) {
            worst_ratio = ratio;
            worst_defect = std::abs(defect(i, j));
            worst_allowed = allowed;
          }
        }
      }
      if (!(worst_ratio <= 1.0)) {
        Fail(rotation_item, "not orthonormal: an entry of R^T R - I is " +
                                PrecisionText(worst_defect) + "; the precision of its digits (" +
                                PrecisionText(half) + " per entry) accepts at most " +
                                PrecisionText(worst_allowed));
      }
      const double determinant = rotation.determinant();
      if (!(determinant > 0.0)) {
        Fail(rotation_item, "determinant is " + FormatNumber(determinant) +
                                ", must be +1 (a reflection is not a rotation)");
      }
      // The nearest rotation (Frobenius norm): U V^T of the singular value decomposition.
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation,
                                                  Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Eigen::Matrix3d nearest = svd.matrixU() * svd.matrixV().transpose();
      const double correction = (nearest - rotation).cwiseAbs().maxCoeff();
      NoteRepair(false, correction, correction, rotation_item);
      return DualQuaternion::FromRotationTranslation(nearest, translation).Normalized();
    }
    if (axis) {
      CheckKeys(pose, item, {"axis", "angle_deg", "translation", "weight", "exact"});
      const std::string axis_item = KeyItem(item, "axis");
      const Eigen::Vector3d axis_vector = Vector<3>(Field(pose, item, "axis"), axis_item);
      const double angle_deg = Number(Field(pose, item, "angle_deg"), KeyItem(item, "angle_deg"));
      const Eigen::Vector3d translation =
          Vector<3>(Field(pose, item, "translation"), translation_item);
      if (!(axis_vector.norm() > 0.0)) Fail(axis_item, "zero vector, the axis needs a direction");
      return DualQuaternion::FromAxisAngle(axis_vector, angle_deg * kDegree, translation)
          .Normalized();
    }
    if (euler) {
      CheckKeys(pose, item, {"euler_deg", "euler_axes", "translation", "weight", "exact"});
      const Eigen::Vector3d angles =
          Vector<3>(Field(pose, item, "euler_deg"), KeyItem(item, "euler_deg")) * kDegree;
      const std::string axes_item = KeyItem(item, "euler_axes");
      const Json& axes = Field(pose, item, "euler_axes");
      const std::string sequence = axes.is_string() ? axes.get<std::string>() : "";
      const bool valid = sequence.size() == 3 &&
                         std::all_of(sequence.begin(), sequence.end(),
                                     [](char c) { return c == 'X' || c == 'Y' || c == 'Z'; }) &&
                         sequence[0] != sequence[1] && sequence[1] != sequence[2];
      if (!valid) {
        Fail(axes_item,
             "expected one of the 12 axis sequences \"XYZ\", \"XZY\", \"YXZ\", \"YZX\", "
             "\"ZXY\", \"ZYX\", \"XYX\", \"XZX\", \"YXY\", \"YZY\", \"ZXZ\", \"ZYZ\" "
             "(R = R_1(a) R_2(b) R_3(c), about the moving frame's axes), got " +
                 (axes.is_string() ? Quote(sequence) : Describe(axes)));
      }
      const Eigen::Vector3d translation =
          Vector<3>(Field(pose, item, "translation"), translation_item);
      Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d unit = Eigen::Vector3d::Unit(sequence[k] - 'X');
        rotation = rotation * Eigen::AngleAxisd(angles[k], unit).toRotationMatrix();
      }
      return DualQuaternion::FromRotationTranslation(rotation, translation).Normalized();
    }
    CheckKeys(pose, item, {"translation", "x_axis", "y_axis", "weight", "exact"});
    const std::string x_item = KeyItem(item, "x_axis"), y_item = KeyItem(item, "y_axis");
    const Eigen::Vector3d translation =
        Vector<3>(Field(pose, item, "translation"), translation_item);
    const Eigen::Vector3d u = Vector<3>(Field(pose, item, "x_axis"), x_item);
    const Eigen::Vector3d v = Vector<3>(Field(pose, item, "y_axis"), y_item);
    if (!(u.norm() > 0.0)) Fail(x_item, "zero vector, the x axis needs a direction");
    if (!(v.norm() > 0.0)) Fail(y_item, "zero vector, it needs a direction");
    // v may be parallel to u only beyond what the digits tell apart.
    const double half = RepairHalfUnit(kDirectionDigits, 1.0, 0.0);
    const double sine = u.cross(v).norm() / (u.norm() * v.norm());
    const double allowed =
        options_.repair_units * std::sqrt(3.0) * half * (1.0 / u.norm() + 1.0 / v.norm()) +
        kRoundingUnits * epsilon;
    if (!(sine > allowed)) {
      Fail(y_item, "parallel to x_axis (sine of the angle between them " + PrecisionText(sine) +
                       ", at most " + PrecisionText(allowed) +
                       " at the precision of the digits): it must point into the xy plane");
    }
    direction_norm_ = direction_norm_ > 0.0 ? std::min({direction_norm_, u.norm(), v.norm()})
                                            : std::min(u.norm(), v.norm());
    Eigen::Matrix3d rotation;
    rotation.col(0) = u.normalized();
    rotation.col(2) = u.cross(v).normalized();
    rotation.col(1) = rotation.col(2).cross(rotation.col(0));
    return DualQuaternion::FromRotationTranslation(rotation, translation).Normalized();
  }

  // Counts a repair whose largest entry correction is beyond rounding (`relative` judges that,
  // `correction` is reported).
  void NoteRepair(bool quaternion, double relative, double correction,
                  const std::string& item) const {
    if (relative > 64.0 * std::numeric_limits<double>::epsilon()) {
      repairs_.Add(quaternion, correction, item);
    }
  }

  void ParseSpatialPoses(const Json& poses, Task* task) const {
    double largest = 0.0;
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string item = IndexItem("poses", i);
      const Json& pose = Object(poses[i], item);
      task->spatial_poses.push_back(ParseSpatialPose(pose, item));
      largest = std::max(largest, task->spatial_poses.back().Translation().cwiseAbs().maxCoeff());
      double weight;
      bool exact;
      ParseWeightAndExact(pose, item, &weight, &exact);
      task->pose_weights.push_back(weight);
      task->pose_exact.push_back(exact);
    }
    FinishPrecision(largest, direction_norm_, task);
    std::vector<Eigen::Vector3d> origins;
    origins.reserve(task->spatial_poses.size());
    for (const DualQuaternion& pose : task->spatial_poses) origins.push_back(pose.Translation());
    const double length = Length(origins, task->scale, "poses", "pose origins");
    const auto coincide = [&](size_t i, size_t j, bool within_precision) {
      const DualQuaternion& a = task->spatial_poses[i];
      const DualQuaternion& b = task->spatial_poses[j];
      const double error = PoseError(a, b, length);
      const double offset = (a.Translation() - b.Translation()).cwiseAbs().maxCoeff();
      // The rotation angle between them: the pose error of the rotations alone, at L = 1.
      DualQuaternion rotation_a, rotation_b;
      rotation_a.q = a.q;
      rotation_b.q = b.q;
      const double angle = PoseError(rotation_a, rotation_b, 1.0);
      return Coincide(error, offset, angle, length, 2.0, task->precision, within_precision);
    };
    if (CloseLoop("poses", coincide, 1, "spatial motion synthesis", task)) {
      task->spatial_poses.pop_back();
      origins.pop_back();
    }
    // Features: translation and L R e1, L R e2; |R_a e - R_b e| <= angle(R_a R_b^T), so the
    // feature distance is at most sqrt(2) times the pose error.
    std::vector<Eigen::Matrix3d> rotations;
    rotations.reserve(task->spatial_poses.size());
    for (const DualQuaternion& pose : task->spatial_poses) rotations.push_back(pose.Rotation());
    CheckCoincident<9>(
        "poses", task->spatial_poses.size(),
        [&](size_t i) {
          Eigen::Matrix<double, 9, 1> feature;
          feature << origins[i], length * rotations[i].col(0), length * rotations[i].col(1);
          return feature;
        },
        1.0, CoincidentWindow(std::sqrt(2.0), length), coincide);
  }

  // Function problems (issue 17): "pairs" of crank angles, or a "function" given as samples of
  // y = f(x) mapped linearly onto input and output ranges; "angles" and "ground".
  void ParseFunctionTask(const Json& root, Task* task) const {
    if (root.contains("ground")) {
      const Json& ground = root.at("ground");
      if (!ground.is_array() || ground.size() != 2) {
        Fail("ground", "expected [[x, y], [x, y]] (the input pivot, then the output pivot), got " +
                           Describe(ground));
      }
      task->ground_input = Vector<2>(ground[0], "ground[0]");
      task->ground_output = Vector<2>(ground[1], "ground[1]");
      const double length = (task->ground_output - task->ground_input).norm();
      if (!(length > 0.0) || !std::isfinite(length)) {
        Fail("ground", length > 0.0 ? "coordinates too large" : "the two pivots coincide");
      }
    }
    if (root.contains("pairs") == root.contains("function")) {
      Fail(root.contains("pairs") ? "function" : "pairs",
           root.contains("pairs") ? "give \"pairs\" or \"function\", not both"
                                  : "missing field (give \"pairs\" or a \"function\")");
    }
    const bool samples = root.contains("function");
    // A function's pairs are relative (the start angles free) by default, but fewer than five
    // relative pairs fix no four-bar: three or four precision points are read as the textbooks
    // read them, absolute (measured from the ground line), and a note says so (issue 35).
    bool few_points = false;
    if (samples && root.at("function").is_object()) {
      const Json& function = root.at("function");
      if (function.contains("precision_points")) {
        const Json& count = function.at("precision_points");
        few_points =
            count.is_number_integer() && count.get<long long>() >= 3 && count.get<long long>() < 5;
      } else if (function.contains("x") && function.at("x").is_array()) {
        few_points = function.at("x").size() >= 3 && function.at("x").size() < 5;
      }
    }
    const std::string angles =
        root.contains("angles")
            ? ParseEnum<std::string>(root, "", "angles", "absolute",
                                     {{"absolute", "absolute"}, {"relative", "relative"}})
            : (samples && !few_points ? "relative" : "absolute");
    if (samples && few_points && !root.contains("angles")) {
      task->input_notes.push_back(
          "angles read as absolute (from the ground line, as the input and output ranges give "
          "them): fewer than five precision points fix no four-bar with free start angles; give "
          "five or more for \"angles\": \"relative\"");
    }
    task->relative_angles = angles == "relative";
    const size_t minimum = task->relative_angles ? 5 : 3;
    const std::string purpose =
        task->relative_angles
            ? "function generation with relative angles (five pairs determine the four-bars; "
              "give \"angles\": \"absolute\" for three)"
            : "function generation with absolute angles (three pairs determine the four-bar)";
    if (samples) {
      ParseFunctionSamples(root.at("function"), minimum, purpose, task);
    } else {
      const Json& pairs = Items(root, "pairs", minimum, purpose);
      for (size_t i = 0; i < pairs.size(); ++i) {
        const std::string item = IndexItem("pairs", i);
        const Json& pair = Object(pairs[i], item);
        CheckKeys(pair, item, {"input_deg", "output_deg", "weight", "exact"});
        FunctionPair parsed;
        parsed.input = Number(Field(pair, item, "input_deg"), KeyItem(item, "input_deg")) * kDegree;
        parsed.output =
            Number(Field(pair, item, "output_deg"), KeyItem(item, "output_deg")) * kDegree;
        ParseWeightAndExact(pair, item, &parsed.weight, &parsed.exact);
        task->pairs.push_back(parsed);
      }
    }
    FinishPrecision(
        task->ground_input.cwiseAbs().maxCoeff() + task->ground_output.cwiseAbs().maxCoeff(), 0.0,
        task);
    // Two pairs at one input angle (modulo a turn, equal as printed: within rounding) ask one
    // four-bar for two outputs there, or repeat a pair: no four-bar is determined by them. Input
    // angles that differ in print are never refused (issue 34).
    // Sorted by their angle on the circle, a pair within the tolerance of another is within it
    // of its neighbour (time n log n: comparing every two took 50 s for 100,000 pairs); the
    // pair named is the first in the list that repeats an earlier one.
    const size_t count = task->pairs.size();
    std::vector<std::pair<double, size_t>> on_circle;
    on_circle.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      const double angle = WrapAngle(task->pairs[i].input);
      on_circle.emplace_back(angle < 0.0 ? angle + 2.0 * kPi : angle, i);
    }
    std::sort(on_circle.begin(), on_circle.end());
    size_t repeat = count, repeated = count;
    for (size_t k = 0; k < count && count > 1; ++k) {
      const auto& [a, i] = on_circle[k];
      const auto& [b, j] = on_circle[(k + 1) % count];
      const double apart = k + 1 < count ? b - a : b + 2.0 * kPi - a;
      if (!(apart <= options_.coincident_tolerance)) continue;
      if (std::max(i, j) < repeat) {
        repeat = std::max(i, j);
        repeated = std::min(i, j);
      }
    }
    if (repeat < count) {
      Fail(samples ? "function" : IndexItem("pairs", repeat),
           "the same input angle as " +
               (samples ? "another precision point" : IndexItem("pairs", repeated)) +
               " (each input angle gives one output)");
    }
  }

  // "function": {"x": [...], "y": [...], "input_range_deg": [start, end], "output_range_deg":
  // [start, end], "precision_points": n, "spacing": "chebyshev" | "uniform"}. x runs over
  // [x_0, x_last] as the input over its range and f(x) over [f(x_0), f(x_last)] as the output
  // over its range. With precision_points, the pairs are n points so spaced (f between samples
  // by the natural cubic spline through them); without, every sample is a pair (least squares).
  void ParseFunctionSamples(const Json& value, size_t minimum, const std::string& purpose,
                            Task* task) const {
    const std::string item = "function";
    const Json& function = Object(value, item);
    CheckKeys(function, item,
              {"x", "y", "input_range_deg", "output_range_deg", "precision_points", "spacing"});
    const auto numbers = [&](const char* key) {
      const Json& list = Field(function, item, key);
      const std::string list_item = KeyItem(item, key);
      if (!list.is_array()) Fail(list_item, "expected an array of numbers, got " + Describe(list));
      if (list.size() > options_.max_items) {
        Fail(list_item, OverLimit(list_item, list.size(), options_.max_items));
      }
      std::vector<double> out;
      for (size_t i = 0; i < list.size(); ++i)
        out.push_back(Number(list[i], IndexItem(list_item, i)));
      return out;
    };
    const std::vector<double> x = numbers("x"), y = numbers("y");
    if (x.size() != y.size()) {
      Fail(KeyItem(item, "y"),
           std::to_string(y.size()) + " values for " + std::to_string(x.size()) + " x values");
    }
    if (x.size() < 2) Fail(KeyItem(item, "x"), "at least two samples are needed");
    for (size_t i = 1; i < x.size(); ++i) {
      if (!(x[i] > x[i - 1])) Fail(IndexItem(KeyItem(item, "x"), i), "x must increase");
    }
    const auto range = [&](const char* key) {
      const std::vector<double> pair = numbers(key);
      if (pair.size() != 2) Fail(KeyItem(item, key), "expected [start, end] in degrees");
      if (!(pair[0] != pair[1])) Fail(KeyItem(item, key), "the range is empty (start = end)");
      return std::pair<double, double>(pair[0] * kDegree, pair[1] * kDegree);
    };
    // Plain variables, not structured bindings: a lambda below uses them (Clang 14, which the
    // fuzz build uses, cannot capture bindings).
    const std::pair<double, double> input_range = range("input_range_deg");
    const std::pair<double, double> output_range = range("output_range_deg");
    const double input_start = input_range.first, input_end = input_range.second;
    const double output_start = output_range.first, output_end = output_range.second;
    if (!(y.back() != y.front())) {
      Fail(KeyItem(item, "y"),
           "f(x) is the same at both ends of the range: the output range "
           "cannot be mapped onto it");
    }
    const auto pair_at = [&](double xv, double yv) {
      FunctionPair pair;
      pair.input =
          input_start + (xv - x.front()) / (x.back() - x.front()) * (input_end - input_start);
      pair.output =
          output_start + (yv - y.front()) / (y.back() - y.front()) * (output_end - output_start);
      return pair;
    };
    for (size_t i = 0; i < x.size(); ++i) task->function_samples.push_back(pair_at(x[i], y[i]));
    if (!function.contains("precision_points")) {
      if (function.contains("spacing")) {
        Fail(KeyItem(item, "spacing"), "used with \"precision_points\" only");
      }
      if (x.size() < minimum) {
        Fail(KeyItem(item, "x"), std::to_string(x.size()) + " samples, " + purpose +
                                     " needs at least " + std::to_string(minimum));
      }
      task->pairs = task->function_samples;
      return;
    }
    const Json& count_value = function.at("precision_points");
    const std::string count_item = KeyItem(item, "precision_points");
    if (!count_value.is_number_integer() || count_value.get<long long>() < 1) {
      Fail(count_item, "expected a positive integer, got " + Describe(count_value));
    }
    const long long count = count_value.get<long long>();
    if (count < static_cast<long long>(minimum) || count > 1000) {
      Fail(count_item,
           count > 1000 ? "at most 1000"
           : count < 3  ? std::to_string(count) +
                             " points: a function needs at least three precision points (three or "
                             "four are read as absolute angles, five or more as relative)"
                       : std::to_string(count) + " points, " + purpose + " needs at least " +
                             std::to_string(minimum));
    }
    const std::string spacing =
        ParseEnum<std::string>(function, item, "spacing", "chebyshev",
                               {{"chebyshev", "chebyshev"}, {"uniform", "uniform"}});
    std::vector<double> points;
    if (spacing == "chebyshev") {
      points = ChebyshevPoints(x.front(), x.back(), static_cast<int>(count));
    } else {
      for (long long k = 0; k < count; ++k) {
        points.push_back(x.front() + (x.back() - x.front()) * static_cast<double>(k) /
                                         static_cast<double>(count - 1));
      }
    }
    const NaturalCubicSpline spline(x, y);
    for (double xv : points) task->pairs.push_back(pair_at(xv, spline(xv)));
  }

  void ParsePoints(const Json& points, Task* task) const {
    double largest = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
      const std::string item = IndexItem("points", i);
      const Json& point = Object(points[i], item);
      CheckKeys(point, item, {"x", "y", "input_deg", "weight", "exact"});
      TimedPoint timed;
      timed.point_in_fixed.x() = Number(Field(point, item, "x"), KeyItem(item, "x"));
      timed.point_in_fixed.y() = Number(Field(point, item, "y"), KeyItem(item, "y"));
      largest = std::max(largest, timed.point_in_fixed.cwiseAbs().maxCoeff());
      // Timing is all or nothing: a mixed task has no meaning.
      const bool timed_first = points[0].is_object() && points[0].contains("input_deg");
      if (point.contains("input_deg") != timed_first) {
        const std::string input_item = KeyItem(item, "input_deg");
        Fail(input_item, timed_first ? "missing field (points[0] has one; give it for all "
                                       "points or for none)"
                                     : "given, but points[0] has none (give it for all "
                                       "points or for none)");
      }
      if (timed_first) {
        timed.input_angle = Number(point.at("input_deg"), KeyItem(item, "input_deg")) * kDegree;
      }
      ParseWeightAndExact(point, item, &timed.weight, &timed.exact);
      task->points.push_back(timed);
    }
    FinishPrecision(largest, 0.0, task);
    std::vector<Eigen::Vector2d> locations;
    locations.reserve(task->points.size());
    for (const TimedPoint& point : task->points) locations.push_back(point.point_in_fixed);
    const double length = Length(locations, task->scale, "points", "points");
    // A point passed twice at different input angles (a crossing curve) is not a duplicate;
    // the same point at the same crank angle modulo a turn is.
    const auto feature = [&](size_t i) {
      const TimedPoint& point = task->points[i];
      const double angle = point.input_angle.value_or(0.0);
      return Eigen::Vector4d(point.point_in_fixed.x(), point.point_in_fixed.y(),
                             length * std::cos(angle), length * std::sin(angle));
    };
    const auto coincide = [&](size_t i, size_t j, bool within_precision) {
      const TimedPoint& a = task->points[i];
      const TimedPoint& b = task->points[j];
      const double angle =
          std::abs(WrapAngle(a.input_angle.value_or(0.0) - b.input_angle.value_or(0.0)));
      return Coincide(std::hypot((a.point_in_fixed - b.point_in_fixed).norm(), length * angle),
                      (a.point_in_fixed - b.point_in_fixed).cwiseAbs().maxCoeff(), angle, length,
                      1.0, task->precision, within_precision);
    };
    if (CloseLoop("points", coincide, 1, "path synthesis", task)) {
      locations.pop_back();
    }
    // Untimed, points equal in print are a curve traced finer than its digits, or one that
    // crosses itself: the coupler passes each where its curve passes it (noted, not refused).
    // Timed, the same point at the same crank angle is a duplicate.
    const bool untimed = !task->points.empty() && !task->points.front().input_angle;
    if (!untimed) {
      CheckCoincident<4>("points", task->points.size(), feature, 1.0, CoincidentWindow(1.0, length),
                         coincide);
      return;
    }
    const int repeats = static_cast<int>(task->points.size()) - DistinctPoints(task->points);
    if (repeats > 0) {
      task->input_notes.push_back(
          std::to_string(repeats) +
          " point(s) equal in print to another (a curve traced finer than its digits, or crossing "
          "itself): each is passed where the coupler curve passes it");
    }
  }

  // The characteristic length: `scale` when given, else the RMS distance of `origins` from
  // their centroid. Also rejects coordinates so large that the RMS overflows.
  template <typename Vec>
  double Length(const std::vector<Vec>& origins, const std::optional<double>& scale,
                const std::string& item, const std::string& what) const {
    Vec centroid = Vec::Zero();
    for (const Vec& origin : origins) centroid += origin / static_cast<double>(origins.size());
    double sum = 0.0;
    for (const Vec& origin : origins) sum += (origin - centroid).squaredNorm();
    const double rms = std::sqrt(sum / static_cast<double>(origins.size()));
    if (!std::isfinite(rms)) {
      Fail(item, "coordinates too large (their spread overflows a double)");
    }
    if (scale) return *scale;
    if (!(rms > 0.0)) Fail(item, "all " + what + " coincide; give \"scale\"");
    return rms;
  }

  // Finds two items i < j with coincide(i, j) and reports the one with the smallest j.
  // `feature` maps an item to a vector whose distances are at most `lipschitz` times the
  // coincidence distance, so sorting along a generic direction and comparing neighbours
  // within the window `lipschitz * tolerance` finds every coincident pair in O(n log n)
  // unless many items crowd a single hyperplane.
  template <int N, typename Feature, typename Coincide>
  void CheckCoincident(const std::string& item, size_t count, const Feature& feature,
                       double lipschitz, double tolerance, const Coincide& coincide) const {
    Eigen::Matrix<double, N, 1> direction;
    for (int k = 0; k < N; ++k) direction[k] = 1.0 + 0.61803398875 * k - 0.1 * k * k / N;
    direction.normalize();
    std::vector<double> key(count);
    double largest = 0.0;
    for (size_t i = 0; i < count; ++i) {
      key[i] = direction.dot(feature(i));
      largest = std::max(largest, std::abs(key[i]));
    }
    std::vector<size_t> order(count);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
    // Slack for the rounding of the keys themselves.
    const double window = lipschitz * tolerance * (1.0 + 1e-9) +
                          64.0 * std::numeric_limits<double>::epsilon() * largest;
    size_t best_first = 0, best_second = count;
    for (size_t a = 0; a < count; ++a) {
      for (size_t b = a + 1; b < count && key[order[b]] - key[order[a]] <= window; ++b) {
        const size_t i = std::min(order[a], order[b]), j = std::max(order[a], order[b]);
        if ((j < best_second || (j == best_second && i < best_first)) && coincide(i, j, false)) {
          best_first = i;
          best_second = j;
        }
      }
    }
    if (best_second < count) {
      Fail(IndexItem(item, best_second), "coincides with " + IndexItem(item, best_first));
    }
  }

  std::string source_;
  TaskReadOptions options_;
  // Per task being parsed: the half units of each kind of digits, the precision the task
  // gives (negative: not given), and what was repaired.
  mutable std::array<double, kDigitKinds> half_units_{};
  mutable double given_length_ = -1.0;
  mutable double given_angle_ = -1.0;
  mutable RepairLog repairs_;
  mutable double direction_norm_ = 0.0;  // shortest x_axis / y_axis vector so far (0: none)
};

bool HasJsonlExtension(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string lower = extension;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower == ".jsonl";
}

}  // namespace

Task ParseTask(const std::string& json_text, const std::string& source,
               const TaskReadOptions& options) {
  return TaskParser(source, options).Parse(json_text);
}

PlanarDesign ParseDesign(const std::string& json_text, const std::string& source) {
  return TaskParser(source, TaskReadOptions()).ParseDesignText(json_text);
}

std::string ReadText(const std::string& path, const char* what) {
  const std::string limit =
      "file too large (more than " + std::to_string(kMaxFileBytes >> 20) + " MiB)";
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status)) {
    throw InputError(path + ": is a directory, not a " + what + " file");
  }
  if (std::filesystem::is_regular_file(status)) {
    const auto size = std::filesystem::file_size(path, error);
    if (!error && size > kMaxFileBytes) throw InputError(path + ": " + limit);
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open file");
  std::vector<std::string> chunks;
  size_t total = 0;
  constexpr size_t kChunk = size_t{1} << 20;
  while (file) {
    std::string chunk(kChunk, '\0');
    file.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    chunk.resize(static_cast<size_t>(file.gcount()));
    total += chunk.size();
    if (total > kMaxFileBytes) throw InputError(path + ": " + limit);
    if (!chunk.empty()) chunks.push_back(std::move(chunk));
  }
  if (file.bad()) throw InputError(path + ": cannot read file");
  std::string text;
  text.reserve(total);
  for (std::string& chunk : chunks) {
    text += chunk;
    std::string().swap(chunk);
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(path + ": empty file, expected a " + what);
  }
  return text;
}

PlanarDesign ReadDesignFile(const std::string& path) {
  return ParseDesign(ReadText(path, "design"), path);
}

PathDesign ParsePathDesign(const std::string& json_text, const std::string& source) {
  return TaskParser(source, TaskReadOptions()).ParsePathDesignText(json_text);
}

SpatialDesign ParseSpatialDesign(const std::string& json_text, const std::string& source) {
  return TaskParser(source, TaskReadOptions()).ParseSpatialDesignText(json_text);
}

SixBarDesign ParseSixBarDesign(const std::string& json_text, const std::string& source,
                               const std::vector<PlanarPose>& poses) {
  return TaskParser(source, TaskReadOptions()).ParseSixBarDesignText(json_text, poses);
}

TaskDesign ParseTaskDesign(const std::string& json_text, const std::string& source,
                           const Task& task) {
  if (task.six_bar) return ParseSixBarDesign(json_text, source, task.planar_poses);
  if (task.problem == ProblemKind::kFunction) {
    throw InputError(source +
                     ": a function task's four-bars are refined by `linkfit solve` "
                     "(least squares beyond three absolute or five relative pairs); "
                     "refine takes motion and path designs");
  }
  if (task.problem == ProblemKind::kPath) return ParsePathDesign(json_text, source);
  if (task.space == Space::kSpatial) return ParseSpatialDesign(json_text, source);
  return ParseDesign(json_text, source);
}

TaskDesign ReadTaskDesignFile(const std::string& path, const Task& task) {
  return ParseTaskDesign(ReadText(path, "design"), path, task);
}

std::vector<Task> ReadTaskFile(const std::string& path, const TaskReadOptions& options) {
  const std::string text = ReadText(path, "task");
  std::vector<Task> tasks;
  if (!HasJsonlExtension(path)) {
    tasks.push_back(ParseTask(text, path, options));
    return tasks;
  }
  size_t line_number = 0;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const std::string line = text.substr(start, end - start);
    if (line.find_first_not_of(" \t\r") != std::string::npos) {
      tasks.push_back(ParseTask(line, path + ":" + std::to_string(line_number), options));
    }
    start = end + 1;
  }
  return tasks;
}

}  // namespace linkfit
