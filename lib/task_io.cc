// Task file reading and validation (see task_io.h). Every problem becomes one InputError
// line "<source>: <item>: <what is wrong>"; nothing malformed reaches the solvers.
#include "lib/task_io.h"

#include <Eigen/LU>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <unordered_set>
#include <utility>

namespace linkfit {
namespace {

using Json = nlohmann::json;

// JSON nested deeper than this is rejected before it reaches the parser.
constexpr int kMaxDepth = 64;
// Longest excerpt of user text (keys, strings, parser reasons) quoted in a message.
constexpr size_t kMaxQuoted = 60;
// Rotation matrices must be orthonormal with determinant +1 to within this.
constexpr double kRotationTolerance = 1e-6;

// Task files larger than this are refused (100000 poses take about 10 MB).
constexpr size_t kMaxFileBytes = size_t{256} << 20;

constexpr double kDegree = M_PI / 180.0;

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
    return key == "poses" || key == "points" ? key : "";
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
  bool number_integer(Json::number_integer_t value) {
    return Scalar([&] { return dom_.number_integer(value); });
  }
  bool number_unsigned(Json::number_unsigned_t value) {
    return Scalar([&] { return dom_.number_unsigned(value); });
  }
  bool number_float(Json::number_float_t value, const std::string& text) {
    return Scalar([&] { return dom_.number_float(value, text); });
  }
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
};

// Validates the fields of one task; `source` prefixes every message.
class TaskParser {
 public:
  TaskParser(const std::string& source, const TaskReadOptions& options)
      : source_(source), options_(options) {}

  PlanarDesign ParseDesignText(const std::string& text) const {
    const Json root = ParseJson(text);
    if (!root.is_object()) Fail("top level", "expected an object, got " + Describe(root));
    const Json& dyads = Field(root, "", "dyads");
    if (!dyads.is_array() || dyads.empty()) {
      Fail("dyads", "expected a non-empty array of dyads, got " + Describe(dyads));
    }
    PlanarDesign design;
    for (size_t i = 0; i < dyads.size(); ++i) {
      const std::string item = IndexItem("dyads", i);
      const Json& dyad = Object(dyads[i], item);
      const Json& type = Field(dyad, item, "type");
      const std::string name = type.is_string() ? type.get<std::string>() : "";
      const auto point = [&](const char* key) {
        return Vector<2>(Field(dyad, item, key), KeyItem(item, key));
      };
      const auto direction = [&]() {
        const double angle =
            Number(Field(dyad, item, "line_angle_deg"), KeyItem(item, "line_angle_deg")) * kDegree;
        return Eigen::Vector2d(std::cos(angle), std::sin(angle));
      };
      if (name == "RR") {
        const double radius = Positive(Field(dyad, item, "radius"), KeyItem(item, "radius"));
        design.dyads.push_back(PlanarDyad::RR(point("fixed"), point("moving"), radius));
      } else if (name == "PR") {
        design.dyads.push_back(PlanarDyad::PR(point("moving"), point("line_point"), direction()));
      } else if (name == "RP") {
        design.dyads.push_back(PlanarDyad::RP(point("fixed"), point("line_point"), direction()));
      } else {
        Fail(KeyItem(item, "type"), "expected \"RR\", \"PR\" or \"RP\", got " + Describe(type));
      }
    }
    if (root.contains("mechanisms")) {
      const Json& mechanisms = root.at("mechanisms");
      if (!mechanisms.is_array()) {
        Fail("mechanisms", "expected an array, got " + Describe(mechanisms));
      }
      for (size_t m = 0; m < mechanisms.size(); ++m) {
        const std::string item = IndexItem("mechanisms", m);
        const Json& pair = Field(Object(mechanisms[m], item), item, "dyads");
        const std::string pair_item = KeyItem(item, "dyads");
        if (!pair.is_array() || pair.size() != 2) {
          Fail(pair_item, "expected [input, output] dyad indices, got " + Describe(pair));
        }
        int index[2];
        for (int k = 0; k < 2; ++k) {
          if (!pair[k].is_number_integer() || pair[k].get<long long>() < 0 ||
              pair[k].get<long long>() >= static_cast<long long>(design.dyads.size())) {
            Fail(IndexItem(pair_item, k), "expected a dyad index below " +
                                              std::to_string(design.dyads.size()) + ", got " +
                                              Describe(pair[k]));
          }
          index[k] = static_cast<int>(pair[k].get<long long>());
        }
        if (index[0] == index[1]) Fail(pair_item, "a four-bar needs two different dyads");
        design.mechanisms.emplace_back(index[0], index[1]);
      }
    }
    return design;
  }

  Task Parse(const std::string& text) const {
    const Json root = ParseJson(text);
    if (!root.is_object()) Fail("top level", "expected an object, got " + Describe(root));
    CheckKeys(root, "",
              {"problem", "space", "poses", "points", "scale", "options", "moving_pivots",
               "fixed_pivots", "platform"});

    Task task;
    task.problem =
        ParseEnum<ProblemKind>(root, "", "problem", ProblemKind::kMotion,
                               {{"motion", ProblemKind::kMotion}, {"path", ProblemKind::kPath}});
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

    if (task.problem == ProblemKind::kMotion) {
      if (root.contains("points")) Fail("points", "not used by motion problems (give \"poses\")");
      const Json& poses = Items(
          root, "poses", task.space == Space::kPlanar ? 3 : 1,
          task.space == Space::kPlanar ? "planar motion synthesis" : "spatial motion synthesis");
      if (task.space == Space::kPlanar) {
        ParsePlanarPoses(poses, &task);
        task.moving_pivots = Pivots<2>(root, "moving_pivots");
        task.fixed_pivots = Pivots<2>(root, "fixed_pivots");
        if (task.planar_poses.size() >= 5 &&
            !(task.moving_pivots.empty() && task.fixed_pivots.empty())) {
          Fail(task.moving_pivots.empty() ? "fixed_pivots" : "moving_pivots",
               "used with three or four poses only (five poses determine the dyads)");
        }
      } else {
        ParseSpatialPoses(poses, &task);
        task.spatial_moving_pivots = Pivots<3>(root, "moving_pivots");
        task.spatial_fixed_pivots = Pivots<3>(root, "fixed_pivots");
        const size_t count = task.spatial_poses.size();
        if ((count < 4 || count >= 7) &&
            !(task.spatial_moving_pivots.empty() && task.spatial_fixed_pivots.empty())) {
          Fail(task.spatial_moving_pivots.empty() ? "fixed_pivots" : "moving_pivots",
               count < 4 ? "need at least four poses (a sphere through the pivot's positions)"
                         : "used with four to six poses only (seven poses determine the dyads)");
        }
        task.platform = Platform(root);
      }
    } else {
      if (task.space == Space::kSpatial) Fail("space", "path problems are planar only");
      if (root.contains("poses")) Fail("poses", "not used by path problems (give \"points\")");
      ParsePoints(Items(root, "points", 1, "path synthesis"), &task);
    }
    if (task.problem != ProblemKind::kMotion) {
      for (const char* key : {"moving_pivots", "fixed_pivots"}) {
        if (root.contains(key)) Fail(key, "used by motion problems only");
      }
    }
    if ((task.space != Space::kSpatial || task.problem != ProblemKind::kMotion) &&
        root.contains("platform")) {
      Fail("platform", "used by spatial motion problems only");
    }
    return task;
  }

 private:
  [[noreturn]] void Fail(const std::string& item, const std::string& what) const {
    throw InputError(source_ + ": " + item + ": " + what);
  }

  // Parses the text after rejecting deep nesting; syntax errors give line and column.
  Json ParseJson(const std::string& text) const {
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
      throw InputError(source_ + ": no JSON text (empty input)");
    }
    CheckDepth(text);
    Json root;
    TrackingSax sax(&root, source_, options_);
    const ParsePath& path = sax.path();
    try {
      Json::sax_parse(text, &sax);
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
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string item = IndexItem("poses", i);
      const Json& pose = Object(poses[i], item);
      CheckKeys(pose, item, {"x", "y", "theta_deg", "weight", "exact"});
      const double x = Number(Field(pose, item, "x"), KeyItem(item, "x"));
      const double y = Number(Field(pose, item, "y"), KeyItem(item, "y"));
      const double theta_deg = Number(Field(pose, item, "theta_deg"), KeyItem(item, "theta_deg"));
      task->planar_poses.emplace_back(x, y, WrapAngle(theta_deg * kDegree));
      double weight;
      bool exact;
      ParseWeightAndExact(pose, item, &weight, &exact);
      task->pose_weights.push_back(weight);
      task->pose_exact.push_back(exact);
    }
    std::vector<Eigen::Vector2d> origins;
    origins.reserve(task->planar_poses.size());
    for (const PlanarPose& pose : task->planar_poses) origins.push_back(pose.origin_in_fixed);
    const double length = Length(origins, task->scale, "poses", "pose origins");
    const double tolerance = options_.coincident_tolerance * length;
    CheckCoincident<4>(
        "poses", task->planar_poses.size(),
        [&](size_t i) {
          const PlanarPose& pose = task->planar_poses[i];
          return Eigen::Vector4d(pose.origin_in_fixed.x(), pose.origin_in_fixed.y(),
                                 length * std::cos(pose.theta), length * std::sin(pose.theta));
        },
        1.0, tolerance,
        [&](size_t i, size_t j) {
          return PoseError(task->planar_poses[i], task->planar_poses[j], length) <= tolerance;
        });
  }

  DualQuaternion ParseSpatialPose(const Json& pose, const std::string& item) const {
    const bool dual = pose.contains("q") || pose.contains("g");
    const bool matrix = pose.contains("rotation");
    const bool axis = pose.contains("axis") || pose.contains("angle_deg");
    if (dual + matrix + axis != 1) {
      Fail(item,
           "give exactly one of {\"q\", \"g\"}, {\"rotation\", \"translation\"} or "
           "{\"axis\", \"angle_deg\", \"translation\"}");
    }
    if (dual) {
      CheckKeys(pose, item, {"q", "g", "weight", "exact"});
      const Eigen::Vector4d q = Vector<4>(Field(pose, item, "q"), KeyItem(item, "q"));
      const Eigen::Vector4d g = Vector<4>(Field(pose, item, "g"), KeyItem(item, "g"));
      DualQuaternion dq;
      dq.q = q;
      dq.g = g;
      if (!(std::abs(dq.NormDefect()) <= options_.unit_tolerance)) {
        Fail(KeyItem(item, "q"), "not a unit quaternion (|q| = " + FormatNumber(q.norm()) + ")");
      }
      // q . g is relative to |q| |g|: g carries the length unit of the translation.
      const double q_dot_g = dq.OrthogonalityDefect();
      if (!(std::abs(q_dot_g) <= options_.unit_tolerance * q.norm() * g.norm())) {
        Fail(KeyItem(item, "g"), "q . g = " + FormatNumber(q_dot_g) + ", must be 0");
      }
      return dq.Normalized();
    }
    if (matrix) {
      CheckKeys(pose, item, {"rotation", "translation", "weight", "exact"});
      const std::string rotation_item = KeyItem(item, "rotation");
      const Eigen::Matrix3d rotation = Matrix3(Field(pose, item, "rotation"), rotation_item);
      const Eigen::Vector3d translation =
          Vector<3>(Field(pose, item, "translation"), KeyItem(item, "translation"));
      const double defect =
          (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
      if (!(defect <= kRotationTolerance)) {
        Fail(rotation_item,
             "not orthonormal (largest entry of R^T R - I is " + FormatNumber(defect) + ")");
      }
      const double determinant = rotation.determinant();
      if (!(std::abs(determinant - 1.0) <= kRotationTolerance)) {
        Fail(rotation_item, "determinant is " + FormatNumber(determinant) +
                                ", must be +1 (a reflection is not a rotation)");
      }
      return DualQuaternion::FromRotationTranslation(rotation, translation).Normalized();
    }
    CheckKeys(pose, item, {"axis", "angle_deg", "translation", "weight", "exact"});
    const std::string axis_item = KeyItem(item, "axis");
    const Eigen::Vector3d axis_vector = Vector<3>(Field(pose, item, "axis"), axis_item);
    const double angle_deg = Number(Field(pose, item, "angle_deg"), KeyItem(item, "angle_deg"));
    const Eigen::Vector3d translation =
        Vector<3>(Field(pose, item, "translation"), KeyItem(item, "translation"));
    if (!(axis_vector.norm() > 0.0)) Fail(axis_item, "zero vector, the axis needs a direction");
    return DualQuaternion::FromAxisAngle(axis_vector, angle_deg * kDegree, translation)
        .Normalized();
  }

  void ParseSpatialPoses(const Json& poses, Task* task) const {
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string item = IndexItem("poses", i);
      const Json& pose = Object(poses[i], item);
      task->spatial_poses.push_back(ParseSpatialPose(pose, item));
      double weight;
      bool exact;
      ParseWeightAndExact(pose, item, &weight, &exact);
      task->pose_weights.push_back(weight);
      task->pose_exact.push_back(exact);
    }
    std::vector<Eigen::Vector3d> origins;
    origins.reserve(task->spatial_poses.size());
    for (const DualQuaternion& pose : task->spatial_poses) origins.push_back(pose.Translation());
    const double length = Length(origins, task->scale, "poses", "pose origins");
    const double tolerance = options_.coincident_tolerance * length;
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
        std::sqrt(2.0), tolerance,
        [&](size_t i, size_t j) {
          return PoseError(task->spatial_poses[i], task->spatial_poses[j], length) <= tolerance;
        });
  }

  void ParsePoints(const Json& points, Task* task) const {
    for (size_t i = 0; i < points.size(); ++i) {
      const std::string item = IndexItem("points", i);
      const Json& point = Object(points[i], item);
      CheckKeys(point, item, {"x", "y", "input_deg", "weight", "exact"});
      TimedPoint timed;
      timed.point_in_fixed.x() = Number(Field(point, item, "x"), KeyItem(item, "x"));
      timed.point_in_fixed.y() = Number(Field(point, item, "y"), KeyItem(item, "y"));
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
    std::vector<Eigen::Vector2d> locations;
    locations.reserve(task->points.size());
    for (const TimedPoint& point : task->points) locations.push_back(point.point_in_fixed);
    const double length = Length(locations, task->scale, "points", "points");
    const double tolerance = options_.coincident_tolerance * length;
    // A point passed twice at different input angles (a crossing curve) is not a duplicate.
    const auto feature = [&](size_t i) {
      const TimedPoint& point = task->points[i];
      const double angle = point.input_angle.value_or(0.0);
      return Eigen::Vector4d(point.point_in_fixed.x(), point.point_in_fixed.y(),
                             length * std::cos(angle), length * std::sin(angle));
    };
    CheckCoincident<4>(
        "points", task->points.size(), feature, 1.0, tolerance, [&](size_t i, size_t j) {
          const TimedPoint& a = task->points[i];
          const TimedPoint& b = task->points[j];
          const double angle = WrapAngle(a.input_angle.value_or(0.0) - b.input_angle.value_or(0.0));
          return std::hypot((a.point_in_fixed - b.point_in_fixed).norm(), length * angle) <=
                 tolerance;
        });
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
        if ((j < best_second || (j == best_second && i < best_first)) && coincide(i, j)) {
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

namespace {

// The whole file, read in bounded chunks (a device such as /dev/zero cannot exhaust memory).
std::string ReadText(const std::string& path, const char* what) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(path + ": is a directory, not a " + what + " file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open file");
  std::string text;
  std::vector<char> chunk(1 << 20);
  while (file) {
    file.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<size_t>(file.gcount()));
    if (text.size() > kMaxFileBytes) {
      throw InputError(path + ": file too large (more than " + std::to_string(kMaxFileBytes >> 20) +
                       " MiB)");
    }
  }
  if (file.bad()) throw InputError(path + ": cannot read file");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(path + ": empty file, expected a " + what);
  }
  return text;
}

}  // namespace

PlanarDesign ReadDesignFile(const std::string& path) {
  return ParseDesign(ReadText(path, "design"), path);
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
