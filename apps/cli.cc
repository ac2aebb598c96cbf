// The `linkfit` command line (see cli.h). Thin: CLI11 parses the arguments, the library reads,
// solves and writes; this file only maps outcomes to output and exit status.
#include "apps/cli.h"

#include <glog/logging.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/analysis_svg.h"
#include "apps/cad_export.h"
#include "apps/output_file.h"
#include "apps/picture.h"
#include "apps/serve.h"
#include "bench/trade_bench.h"
#include "lib/analysis_io.h"
#include "lib/parallel.h"
#include "lib/result_io.h"
#include "lib/result_summary.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitInternal = 1;
constexpr int kExitBadInput = 2;

// The largest index an option takes (--mechanism, --platform), and the most threads of --jobs.
constexpr long long kMaxIndex = 1000000000;
constexpr long long kMaxJobs = 1024;

constexpr const char* kDescription =
    "linkfit - kinematic synthesis of linkages.\n"
    "Given the poses a body must reach (motion generation) or the points a coupler point must\n"
    "pass (path generation), finds the dyads and four-bars that do it: exactly for minimal\n"
    "data, in the least-squares sense for more.";

constexpr const char* kFooter =
    "Task file: a JSON object (a .jsonl file holds one task per line), e.g.\n"
    "  {\"problem\": \"motion\", \"space\": \"planar\",\n"
    "   \"poses\": [{\"x\": 1.0, \"y\": 2.0, \"theta_deg\": 30.0}, ...],\n"
    "   \"scale\": 1.0, \"options\": {\"effort\": \"balanced\"}}\n"
    "  See 'linkfit solve --help' for every field.\n"
    "Result: JSON on stdout (or -o FILE; one line per task for .jsonl):\n"
    "  {\"problem\", \"space\", \"method\", \"scale\", \"dyads\": [{\"type\": "
    "\"RR\"|\"PR\"|\"RP\", ...}],\n"
    "   \"mechanisms\": [{\"type\", \"dyads\": [input, output], \"max_pose_error\"}], \"roots\",\n"
    "   \"notes\"}; a value that cannot be computed is left out with a \"<field>_note\".\n"
    "  Spatial tasks give SS / PS / SP dyads and a 5-dyad \"platform\" mechanism (whether it\n"
    "  passes every pose on one branch, in which order, and its largest pose error).\n"
    "Exit status: 0 solved (an empty \"dyads\" with notes when nothing was found);\n"
    "  1 internal fault; 2 bad input or usage: one line on stderr naming the file, the item and\n"
    "  what is wrong, and no result file.";

constexpr const char* kSolveFooter =
    "Task fields:\n"
    "  problem   \"motion\" (default): a body through poses; \"path\": a coupler point\n"
    "            through points; \"function\": output crank angles for input crank angles\n"
    "  space     \"planar\" (default) or \"spatial\" (motion only; spherical four-bars\n"
    "            from pure rotations)\n"
    "  poses     motion: planar {\"x\", \"y\", \"theta_deg\"} (at least 3; five give every\n"
    "            dyad exactly), or spatial (at least 1)\n"
    "            one of {\"q\": [q1,q2,q3,q4], \"g\": [g1,g2,g3,g4]} (q4 scalar, g = 1/2 d q),\n"
    "            {\"rotation\": [[3],[3],[3]], \"translation\": [3]} or\n"
    "            {\"axis\": [3], \"angle_deg\": a, \"translation\": [3]};\n"
    "            optional \"weight\" (> 0, default 1) and \"exact\" (true/false)\n"
    "  points    path: {\"x\", \"y\"} with optional \"input_deg\" (all or none), \"weight\",\n"
    "            \"exact\"\n"
    "  scale     characteristic length L (> 0); default: RMS distance of the pose origins or\n"
    "            points from their centroid\n"
    "  moving_pivots, fixed_pivots\n"
    "            planar motion with 3 or 4 poses: [[x, y], ...] pivots in the body frame (on the\n"
    "            circle-point curve) or in the fixed frame (on the center-point curve), one\n"
    "            dyad each; three poses without pivots get a default pair.\n"
    "            Spatial motion with 4 to 6 poses: [[x, y, z], ...], one SS dyad each\n"
    "  platform  spatial motion: five dyad indices for the platform (default: the five\n"
    "            dyads of smallest radius)\n"
    "  precision {\"length\": delta, \"angle_deg\": alpha}; default: read from the digits\n"
    "  constraints\n"
    "            planar motion and path: {\"max_link_length\", \"min_link_length\",\n"
    "            \"fixed_pivots_box\": [[xmin, ymin], [xmax, ymax]], \"moving_pivots_box\" "
    "(motion),\n"
    "            \"input_rotates_fully\": true, \"grashof\": \"crank-rocker\" | ...,\n"
    "            \"min_transmission_angle_deg\" (default 30), \"max_coupler_point_offset\"\n"
    "            (path)}; links default to at most 100 L\n"
    "  pairs     function: {\"input_deg\", \"output_deg\"} (three fix the four-bar with\n"
    "            absolute angles, five with relative ones; more: least squares)\n"
    "  function  function: {\"x\": [...], \"y\": [...], \"input_range_deg\": [a, b],\n"
    "            \"output_range_deg\": [c, d], \"precision_points\": n, \"spacing\":\n"
    "            \"chebyshev\" (default) | \"uniform\"}: y = f(x) as crank angles\n"
    "  angles    function: \"absolute\" (from the ground line; the default for pairs and for\n"
    "            three or four precision points) or \"relative\" (start angles free; the\n"
    "            default for a function with five or more)\n"
    "  ground    function: [[x, y], [x, y]], the input and output pivots (default\n"
    "            [[0, 0], [1, 0]])\n"
    "  linkage   planar motion: \"four-bar\" (default) or \"six-bar\" (five poses exactly, more\n"
    "            by least squares), with\n"
    "  chain     the 3R chain the six-bar is built on: {\"ground_pivot\": [x, y], \"wrist\": [x, "
    "y]\n"
    "            (in the body frame), \"link_lengths\": [upper, forearm], \"elbow\": \"left\" |\n"
    "            \"right\" or \"elbow_at_first_pose\": [x, y]}\n"
    "  options   {\"effort\": \"fast\" | \"balanced\" (default) | \"thorough\"}\n"
    "Planar poses are (x, y, theta): the body frame's origin in the fixed frame and its\n"
    "counter-clockwise turn. Spatial: a body point c is at R c + d. Coincident poses, non-unit "
    "quaternions and unknown fields are\n"
    "errors (exit 2).";

// A whole-number option from `minimum` to `maximum`, refused in one line naming the value (CLI11's
// own range check prints its bounds as floating point, hundreds of digits long).
CLI::Validator WholeNumber(long long minimum, long long maximum) {
  return CLI::Validator(
      [minimum, maximum](std::string& value) -> std::string {
        const auto range = [&]() {
          return "from " + std::to_string(minimum) + " to " + std::to_string(maximum);
        };
        std::string shown = value.substr(0, 40);
        for (char& c : shown) {
          if (c < 0x20 || c >= 0x7f) c = '?';
        }
        if (shown.size() < value.size()) shown += "...";
        long long number = 0;
        const char* end = value.data() + value.size();
        const auto [stop, error] = std::from_chars(value.data(), end, number);
        if (value.empty() || stop != end || error == std::errc::invalid_argument) {
          return "expected a whole number " + range() + ", got '" + shown + "'";
        }
        if (error == std::errc::result_out_of_range || number < minimum || number > maximum) {
          return "expected a whole number " + range() + ", got " + shown;
        }
        return std::string();
      },
      "");  // no description: the option's type reads INT in --help and in messages
}

// Prints "linkfit: <kind>: <message>" on one line of stderr.
void PrintError(const std::string& kind, const std::string& message) {
  std::string line = message;
  std::replace_if(
      line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  std::cerr << "linkfit: " << kind << ": " << line << std::endl;
}

bool IsJsonLines(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".jsonl";
}

struct SolveOutputs {
  std::string result_path;    // -o; empty or "-" for stdout
  std::string svg_path;       // --svg
  std::string animate_path;   // --animate (.svg or .html)
  int animate_index = 1;      // --mechanism: which mechanism to animate (1 = the first listed)
  std::vector<int> platform;  // --platform: five dyad indices (spatial motion)
  std::string effort;         // --effort: overrides the task's options.effort
  int jobs = 0;               // --jobs: threads of a .jsonl batch (0: the machine's)
  bool summary = false;       // --summary: the table on stdout (lib/result_summary.h)
  int curve_points = kDefaultCurvePoints;  // --curve-points: Burmester curves' points written
};

// The command line's overrides of a task: --platform and --effort.
void ApplyOverrides(const SolveOutputs& outputs, const std::string& task_path, Task* task) {
  if (!outputs.platform.empty()) {
    if (task->space != Space::kSpatial) {
      throw InputError(task_path + ": --platform: used by spatial motion problems only");
    }
    task->platform = outputs.platform;
  }
  if (const std::optional<Effort> effort = EffortOfName(outputs.effort)) task->effort = *effort;
}

// The longest line a task or result file may have.
constexpr size_t kMaxLineBytes = size_t{256} << 20;

// Lines of a file read in bounded pieces: a line longer than `max_bytes` is bad input, so a
// device without newlines (/dev/zero) cannot exhaust memory.
class LineReader {
 public:
  LineReader(const std::string& path, size_t max_bytes) : path_(path), max_bytes_(max_bytes) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
      throw InputError(path + ": is a directory, not a task file");
    }
    file_.open(path, std::ios::binary);
    if (!file_) throw InputError(path + ": cannot open file");
  }
  // The next line (without its newline) and its number; false at the end of the file.
  bool Next(std::string* line, size_t* number) {
    line->clear();
    while (true) {
      const size_t newline = buffer_.find('\n', start_);
      if (newline != std::string::npos) {
        line->append(buffer_, start_, newline - start_);
        start_ = newline + 1;
        *number = ++count_;
        return true;
      }
      line->append(buffer_, start_, std::string::npos);
      buffer_.clear();
      start_ = 0;
      if (line->size() > max_bytes_) {
        throw InputError(path_ + ":" + std::to_string(count_ + 1) + ": line too long (more than " +
                         std::to_string(max_bytes_ >> 20) + " MiB)");
      }
      if (!file_) {
        if (file_.bad()) throw InputError(path_ + ": cannot read file");
        if (line->empty()) return false;
        *number = ++count_;
        return true;
      }
      buffer_.resize(kChunk);
      file_.read(buffer_.data(), static_cast<std::streamsize>(kChunk));
      buffer_.resize(static_cast<size_t>(file_.gcount()));
    }
  }

 private:
  static constexpr size_t kChunk = size_t{1} << 20;
  std::string path_;
  size_t max_bytes_;
  std::ifstream file_;
  std::string buffer_;
  size_t start_ = 0;
  size_t count_ = 0;
};

// The lines of a .jsonl batch, read in chunks of kChunkTasks non-blank lines: `chunk(lines,
// sources)` is called for each. Memory holds one chunk, whatever the file's length.
template <typename Chunk>
size_t ForEachChunk(const std::string& task_path, const Chunk& chunk) {
  constexpr size_t kChunkTasks = 4096;
  LineReader reader(task_path, kMaxLineBytes);
  std::vector<std::string> lines, sources;
  size_t count = 0;
  bool more = true;
  while (more) {
    lines.clear();
    sources.clear();
    std::string line;
    size_t number = 0;
    while (lines.size() < kChunkTasks && (more = reader.Next(&line, &number))) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      lines.push_back(line);
      sources.push_back(task_path + ":" + std::to_string(number));
    }
    if (!lines.empty()) chunk(lines, sources);
    count += lines.size();
  }
  if (count == 0) throw InputError(task_path + ": empty file, expected a task");
  return count;
}

// Runs work(i) for the lines of a chunk on `jobs` threads; the first error by position is
// rethrown once all have run.
template <typename Work>
void RunChunk(size_t count, unsigned jobs, const Work& work) {
  std::vector<std::exception_ptr> errors(count);
  ParallelFor(count, jobs, [&](size_t i) {
    try {
      work(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

// `linkfit solve TASKS.jsonl`: every line is read and validated first (a bad line anywhere is
// reported before anything is solved), then read again in chunks, each chunk solved on `jobs`
// threads and written in input order to `out`, which the caller commits once every line is
// solved. A stream (a FIFO, standard input) cannot be read twice: its lines are validated as
// they are solved.
void SolveBatch(const std::string& task_path, const SolveOutputs& options, unsigned jobs,
                OutputFile* out) {
  std::error_code error;
  if (std::filesystem::is_regular_file(task_path, error)) {
    ForEachChunk(task_path, [&](const std::vector<std::string>& lines,
                                const std::vector<std::string>& sources) {
      RunChunk(lines.size(), jobs, [&](size_t i) {
        Task task = ParseTask(lines[i], sources[i]);
        ApplyOverrides(options, task_path, &task);
      });
    });
  }
  // A task a thread: each solve on one (TaskSolverOptions::threads) when the batch runs on more.
  TaskSolverOptions solver;
  solver.threads = jobs > 1 ? 1 : 0;
  std::vector<std::string> texts;
  ForEachChunk(task_path,
               [&](const std::vector<std::string>& lines, const std::vector<std::string>& sources) {
                 texts.assign(lines.size(), std::string());
                 RunChunk(lines.size(), jobs, [&](size_t i) {
                   Task task = ParseTask(lines[i], sources[i]);
                   ApplyOverrides(options, task_path, &task);
                   texts[i] = ResultToJson(SolveTask(task, solver), -1) + "\n";
                 });
                 for (const std::string& text : texts) out->Write(text);
               });
}

// `linkfit solve`: the outputs are checked and prepared first, the task read and validated,
// solved, every picture rendered, and only then is anything written (apps/output_file.h); a
// .jsonl batch streams (SolveBatch).
int Solve(const std::string& task_path, const SolveOutputs& options) {
  const bool batch = IsJsonLines(task_path);
  if (batch && (!options.svg_path.empty() || !options.animate_path.empty())) {
    throw InputError(task_path + ": --svg and --animate draw one task; a .jsonl file holds many");
  }
  if (batch && options.summary) {
    throw InputError(task_path +
                     ": --summary shows one task; for a batch, write it with -o and "
                     "run 'linkfit show' on that file");
  }
  if (options.summary && options.result_path == "-") {
    throw InputError("-o -: --summary prints the table on stdout; write the JSON to a file");
  }
  OutputSet outputs;
  outputs.AddInput(task_path);
  // With --summary and no -o, stdout takes the table and the JSON is not written.
  OutputFile* result_file = options.summary && options.result_path.empty()
                                ? nullptr
                                : &outputs.Add(options.result_path, "-o");
  OutputFile* svg_file =
      options.svg_path.empty() ? nullptr : &outputs.Add(options.svg_path, "--svg");
  OutputFile* animation_file =
      options.animate_path.empty() ? nullptr : &outputs.Add(options.animate_path, "--animate");
  if (batch) {
    SolveBatch(task_path, options, ThreadCount(options.jobs), result_file);
    outputs.CommitAll();
    return kExitOk;
  }
  const std::vector<Task> tasks = ReadTaskFile(task_path);
  const int indent = 2;
  std::string text;
  std::vector<TaskResult> results;
  for (Task task : tasks) {
    ApplyOverrides(options, task_path, &task);
    results.push_back(SolveTask(task));
    if (auto* planar = std::get_if<PlanarMotionResult>(&results.back())) {
      planar->curve_points = options.curve_points;
    }
    text += ResultToJson(results.back(), indent) + "\n";
  }
  if (result_file != nullptr) result_file->Write(text);
  // Everything is rendered before anything is written.
  if (svg_file != nullptr || animation_file != nullptr) {
    const std::string title = std::filesystem::path(task_path).filename().string();
    std::string why;
    std::string svg;
    const auto* spatial = std::get_if<SpatialMotionResult>(&results[0]);
    if (spatial != nullptr && spatial->model == "spherical" && animation_file == nullptr) {
      svg = RenderSphericalSvg(*SphericalTaskPicture(title, tasks[0], *spatial, 12));
    } else if (!TaskPicture(title, tasks[0], results[0], 1, &why)) {
      throw InputError(task_path + ": " + why);
    }
    const auto picture_of = [&](size_t panels) {
      return *TaskPicture(title, tasks[0], results[0], panels, &why);
    };
    if (svg_file != nullptr) svg_file->Write(svg.empty() ? RenderSvg(picture_of(12)) : svg);
    if (animation_file != nullptr) {
      const Picture picture = picture_of(64);
      const size_t index = static_cast<size_t>(options.animate_index - 1);
      if (index >= picture.mechanisms.size()) {
        throw InputError(task_path + ": --mechanism " + std::to_string(options.animate_index) +
                         ": the result lists " + std::to_string(picture.mechanisms.size()) +
                         " mechanisms");
      }
      std::string extension = std::filesystem::path(options.animate_path).extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      animation_file->Write(
          RenderAnimation(picture, index, extension == ".html" || extension == ".htm"));
    }
  }
  outputs.CommitAll();
  if (options.summary) {
    const std::string title = std::filesystem::path(task_path).filename().string();
    for (const TaskResult& result : results)
      std::cout << ResultSummary(ResultToJson(result, -1), title);
  }
  return kExitOk;
}

// `linkfit show RESULT`: the summary table of each result in a file (.json, or one per line of a
// .jsonl), as `linkfit solve --summary` prints it.
int Show(const std::string& result_path) {
  // Read as task files are (LineReader: a directory, an unreadable file or an endless line is
  // bad input, not a crash): one result per line of a .jsonl, or the whole file.
  LineReader reader(result_path, kMaxLineBytes);
  const std::string title = std::filesystem::path(result_path).filename().string();
  const bool lines = IsJsonLines(result_path);
  std::vector<std::string> texts(lines ? 0 : 1);
  std::string line;
  size_t number = 0;
  while (reader.Next(&line, &number)) {
    if (!lines) {
      texts[0] += line + "\n";
    } else if (line.find_first_not_of(" \t\r") != std::string::npos) {
      texts.push_back(line);
    }
  }
  if (!lines && texts[0].find_first_not_of(" \t\r\n") == std::string::npos) texts.clear();
  if (texts.empty()) throw InputError(result_path + ": empty file, expected a result");
  std::string out;
  for (size_t i = 0; i < texts.size(); ++i) {
    try {
      out +=
          ResultSummary(texts[i], texts.size() > 1 ? title + ":" + std::to_string(i + 1) : title);
    } catch (const std::invalid_argument& bad) {
      throw InputError(result_path + (texts.size() > 1 ? ":" + std::to_string(i + 1) : "") + ": " +
                       bad.what());
    }
  }
  std::cout << out;
  return kExitOk;
}

// `linkfit refine`: one task and a design (a result file, or written by hand) of its kind; the
// design's mechanism refined against the task (optimizers/task_solver.h RefineTask), before and
// after in the result.
int Refine(const std::string& task_path, const std::string& design_path,
           const std::string& result_path, int mechanism_index, bool summary) {
  if (summary && result_path == "-") {
    throw InputError("-o -: --summary prints the table on stdout; write the JSON to a file");
  }
  OutputSet outputs;
  outputs.AddInput(task_path);
  outputs.AddInput(design_path);
  // With --summary and no -o, stdout takes the table and the JSON is not written (as solve).
  OutputFile* result_file =
      summary && result_path.empty() ? nullptr : &outputs.Add(result_path, "-o");
  const std::vector<Task> tasks = ReadTaskFile(task_path);
  if (tasks.size() != 1) throw InputError(task_path + ": refine takes one task, not a batch");
  const Task& task = tasks[0];
  const TaskDesign design = ReadTaskDesignFile(design_path, task);
  RefineChoice choice;
  choice.mechanism = mechanism_index - 1;
  choice.task_source = task_path;
  choice.design_source = design_path;
  choice.mechanism_item = design_path + ": --mechanism " + std::to_string(mechanism_index);
  const TaskResult result = RefineTask(task, design, choice);
  if (result_file != nullptr) result_file->Write(ResultToJson(result, 2) + "\n");
  outputs.CommitAll();
  if (summary) {
    std::cout << ResultSummary(ResultToJson(result, -1),
                               std::filesystem::path(task_path).filename().string());
  }
  return kExitOk;
}

// `linkfit analyze`: the kinematics (and statics, with a load) of one mechanism of a result file
// (lib/analysis_io.h), JSON or CSV to -o or stdout.
int Analyze(const std::string& result_path, const std::string& output_path,
            const std::string& svg_path, const std::string& task_path, AnalysisRequest request,
            const std::vector<double>& force) {
  OutputSet outputs;
  outputs.AddInput(result_path);
  if (!task_path.empty()) outputs.AddInput(task_path);
  // With --svg and no -o, only the chart is written.
  OutputFile* output = output_path.empty() && !svg_path.empty()
                           ? nullptr
                           : &outputs.Add(output_path.empty() ? "-" : output_path, "-o");
  OutputFile* svg = svg_path.empty() ? nullptr : &outputs.Add(svg_path, "--svg");
  if (!force.empty()) request.load.coupler_force = Eigen::Vector2d(force[0], force[1]);
  const std::string text = ReadText(result_path, "result");
  std::vector<Task> tasks;
  if (!task_path.empty()) {
    tasks = ReadTaskFile(task_path);
    if (tasks.size() != 1) throw InputError(task_path + ": analyze takes one task, not a batch");
    request.task = &tasks[0];
  }
  const std::string analysis = AnalyzeResultText(text, result_path, request);
  if (output != nullptr) output->Write(analysis);
  if (svg != nullptr) {
    // The chart is drawn from the JSON (analyzed again only when -o takes CSV).
    AnalysisRequest as_json = request;
    as_json.csv = false;
    svg->Write(AnalysisSvg(request.csv ? AnalyzeResultText(text, result_path, as_json) : analysis));
  }
  outputs.CommitAll();
  return kExitOk;
}

// `linkfit export --dxf/--svg`: one mechanism of a result file as a DXF drawing and/or the same
// drawing as SVG (apps/cad_export.h), the task's poses or points on it when given.
int Export(const std::string& result_path, const std::string& dxf_path, const std::string& svg_path,
           const std::string& task_path, CadExportRequest request) {
  if (dxf_path.empty() && svg_path.empty()) {
    throw InputError("export: give --dxf FILE, --svg FILE or both (the drawings to write)");
  }
  OutputSet outputs;
  outputs.AddInput(result_path);
  if (!task_path.empty()) outputs.AddInput(task_path);
  OutputFile* dxf = dxf_path.empty() ? nullptr : &outputs.Add(dxf_path, "--dxf");
  OutputFile* svg = svg_path.empty() ? nullptr : &outputs.Add(svg_path, "--svg");
  const std::string text = ReadText(result_path, "result");
  std::vector<Task> tasks;
  if (!task_path.empty()) {
    tasks = ReadTaskFile(task_path);
    if (tasks.size() != 1) throw InputError(task_path + ": export takes one task, not a batch");
    request.task = &tasks[0];
  }
  if (dxf != nullptr) dxf->Write(ResultDxf(text, result_path, request));
  if (svg != nullptr) svg->Write(ResultSvg(text, result_path, request));
  outputs.CommitAll();
  return kExitOk;
}

// `--mechanism N` of a command that reads one listed mechanism of a result file.
void AddRankOption(CLI::App* command, int* index) {
  command
      ->add_option("--mechanism", *index,
                   "which listed mechanism: its rank, counted from 1 as in --summary")
      ->check(WholeNumber(1, kMaxIndex));
}

int Run(int argc, char** argv) {
  CLI::App app(kDescription, "linkfit");
  app.footer(kFooter);
  app.set_version_flag("--version", "linkfit " LINKFIT_VERSION);
  app.require_subcommand(1);

  std::string task_path;
  SolveOutputs outputs;
  CLI::App* solve = app.add_subcommand("solve", "Synthesize linkages for a task file.");
  solve->footer(kSolveFooter);
  solve->add_option("TASK", task_path, "task file: .json (one task) or .jsonl (one per line)")
      ->required();
  solve->add_option("-o,--output", outputs.result_path,
                    "write the result to this file (written only on success; - for stdout)");
  solve->add_option("--svg", outputs.svg_path,
                    "draw the task and the listed mechanisms (one panel each, best first) to "
                    "this SVG file");
  solve->add_option("--animate", outputs.animate_path,
                    "animate one mechanism through its cycle: an .svg (SMIL) or .html file");
  solve
      ->add_option("--mechanism", outputs.animate_index,
                   "which listed mechanism --animate shows: its rank, counted from 1 as in "
                   "--summary (1 = the first, the best ranked; Python's mechanism= is a list "
                   "index, from 0)")
      ->check(WholeNumber(1, kMaxIndex));
  solve
      ->add_option("--curve-points", outputs.curve_points,
                   "four poses: how many points of each kind of Burmester curve the result file "
                   "carries (default " +
                       std::to_string(kDefaultCurvePoints) +
                       ", a drawing's resolution; the curves are solved far more densely)")
      ->check(WholeNumber(2, 10000000));
  solve->add_flag("--summary", outputs.summary,
                  "print a table of the listed mechanisms (rank, type, Grashof class, link "
                  "lengths, fit, worst transmission angle, defects, violations) on stdout; the "
                  "JSON goes to -o FILE when given");
  solve
      ->add_option("--effort", outputs.effort,
                   "more poses than the minimum: fast (algebraic seeds), balanced (seeds refined "
                   "by Ceres; the default) or thorough (plus an NLopt global search); overrides "
                   "the task's options.effort")
      ->check(CLI::IsMember({"fast", "balanced", "thorough"}));
  solve
      ->add_option("--jobs", outputs.jobs,
                   "a .jsonl batch: solve on this many threads (1 to 1024; 0 or by default: "
                   "every core); results keep the input order")
      ->check(WholeNumber(0, kMaxJobs));
  solve
      ->add_option("--platform", outputs.platform,
                   "spatial motion: the five dyads (indices in the result) to build the platform "
                   "from, e.g. --platform 0,1,2,3,5")
      ->delimiter(',')
      ->expected(5)
      ->check(WholeNumber(0, kMaxIndex));

  std::string refine_task, design_path, refine_output;
  int refine_index = 1;
  bool refine_summary = false;
  CLI::App* refine = app.add_subcommand(
      "refine",
      "Refine a design against a task: a planar four-bar on its pose error, a path four-bar on "
      "its point errors (prescribed or free timing), spatial dyads each on their residuals and "
      "their platform traced, a six-bar on its pose errors (\"linkage\": \"six-bar\").");
  refine
      ->add_option("TASK", refine_task,
                   "task file (.json): planar (four- or six-bar) or spatial motion, or path")
      ->required();
  refine
      ->add_option("DESIGN", design_path,
                   "the design: a result file of `linkfit solve` for the task, or one written "
                   "by hand in the same form (planar: {\"dyads\": [...], \"mechanisms\": "
                   "[{\"dyads\": [input, output]}]}; path: {\"mechanisms\": [{\"type\": "
                   "\"4R\", \"input_pivot\", \"input_moving\", \"output_pivot\", "
                   "\"output_moving\", \"coupler_point\"}]}; spatial: {\"dyads\": [SS, PS or "
                   "SP dyads], \"mechanisms\": [{\"dyads\": [five indices]}]})")
      ->required();
  refine->add_option("-o,--output", refine_output, "write the result to this file");
  refine->add_flag("--summary", refine_summary,
                   "print the refined design's table on stdout (as solve --summary; the JSON "
                   "then goes to -o only)");
  refine
      ->add_option("--mechanism", refine_index,
                   "which mechanism (spatial: platform) of the design to refine: its rank, "
                   "counted from 1 as in --summary (1 = the first listed)")
      ->check(WholeNumber(1, kMaxIndex));

  std::string show_path;
  CLI::App* show = app.add_subcommand(
      "show", "Print the summary table of a result file, as 'linkfit solve --summary' does.");
  show->add_option("RESULT", show_path, "result file: .json (one result) or .jsonl (one per line)")
      ->required();

  std::string analyze_result, analyze_output, analyze_svg, analyze_task;
  AnalysisRequest analysis;
  int analyze_index = 1;
  std::vector<double> analyze_force, analyze_mass;
  std::string analyze_range;
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "Kinematics of a listed four-bar over its input's range: every link's angle, angular "
      "velocity and acceleration, the coupler point's position, velocity and acceleration, the "
      "transmission angle, the mechanical advantage, the dead points; with a load, the input "
      "torque that holds it.");
  analyze->add_option("RESULT", analyze_result, "result file of `linkfit solve` (.json)")
      ->required();
  AddRankOption(analyze, &analyze_index);
  analyze->add_option("--input-speed", analysis.input_speed,
                      "the input crank's constant angular velocity, rad/s (default 1)");
  analyze
      ->add_option("--steps", analysis.steps,
                   "samples over the input's range: a whole turn for a crank, between the dead "
                   "points for a rocker (default 360)")
      ->check(WholeNumber(1, 1000000));
  analyze
      ->add_option("--force", analyze_force,
                   "a load at the coupler point: FX,FY (the result's length unit times "
                   "newtons gives the torque's unit)")
      ->delimiter(',')
      ->expected(2);
  analyze->add_option("--output-torque", analysis.load.output_torque,
                      "a load torque on the output rocker, counter-clockwise");
  analyze->add_option("--slider-force", analysis.load.slider_force,
                      "a load force on the slider, along its line's direction");
  analyze->add_option(
      "--range", analyze_range,
      "the part of the input's range sampled: FROM,TO (the input's angles in degrees), task "
      "(its angles from the first to the last task pose: a six-bar's result gives them) or "
      "whole (a rocking input between its dead points, where its rates grow without bound); "
      "default: a crank's whole turn, a rocking input's task range where known, else whole");
  analyze
      ->add_option("--mass", analyze_mass,
                   "the links' masses in kg: a four-bar's INPUT,COUPLER,OUTPUT (OUTPUT: the "
                   "rocker or the slider), a six-bar's UPPER_LINK,FOREARM,TASK_BODY,FIRST_LINK,"
                   "SECOND_LINK; for the torque that drives them at the input speed (uniform "
                   "bodies: bars, plates on three or more joints); needs --length-unit")
      ->delimiter(',')
      ->expected(3, 5);
  analyze->add_option("--length-unit", analysis.length_unit,
                      "the result's length unit: m, cm, mm, in or ft (torques then in N times "
                      "it)");
  analyze->add_flag("--gravity", analysis.masses.gravity,
                    "the links' weight too, gravity along -y of the result's frame");
  analyze->add_flag("--csv", analysis.csv, "CSV, one row per step, instead of JSON");
  analyze->add_option("--task", analyze_task,
                      "the result's task file: a four-bar's task range (the crank's angles from "
                      "the first pose or point to the last), sampled by default when the input "
                      "rocks; checked against the result");
  analyze->add_option("-o,--output", analyze_output,
                      "write to this file (default: stdout, unless --svg alone is given)");
  analyze->add_option("--svg", analyze_svg,
                      "chart the analysis in this SVG file: angles, angular velocities and "
                      "accelerations, the input torque (or the transmission angle) against the "
                      "input angle, dead points dashed");

  std::string export_result, export_dxf, export_svg, export_task;
  CadExportRequest export_request;
  int export_index = 1;
  double export_input_deg = 0.0;
  CLI::App* export_command = app.add_subcommand(
      "export",
      "Write a listed four-bar, six-bar or spherical four-bar as a DXF drawing for CAD (--dxf) or "
      "as SVG (--svg): "
      "each link on its own layer with its pivots as circles, the coupler body, the coupler "
      "curve, the task's poses or points, dimensions of the link lengths.");
  export_command->add_option("RESULT", export_result, "result file of `linkfit solve` (.json)")
      ->required();
  AddRankOption(export_command, &export_index);
  export_command->add_option("--dxf", export_dxf, "the DXF file to write");
  export_command->add_option("--svg", export_svg,
                             "the same drawing as an SVG file (a group per layer, the result's "
                             "coordinates and units)");
  CLI::Option* input_deg_option = export_command->add_option(
      "--input-deg", export_input_deg,
      "draw the four-bar with its crank at this angle, degrees in the fixed frame (default: at "
      "the first pose)");
  export_command->add_option("--task", export_task,
                             "the result's task file: its poses or points drawn too");

  ServeOptions serve_options;
  long long serve_request_bytes = static_cast<long long>(serve_options.max_request_bytes);
  CLI::App* serve = app.add_subcommand(
      "serve",
      "Start the interactive designer: a local web server with the page (open the URL it "
      "prints) and a JSON API (POST /api/solve, /api/refine, /api/analyze, /api/export); "
      "Ctrl-C stops it.");
  serve->add_option("--port", serve_options.port, "the port to listen on (0: any free one)")
      ->check(WholeNumber(0, 65535));
  serve->add_option("--host", serve_options.host,
                    "the address to listen on (default 127.0.0.1, this machine only; 0.0.0.0 "
                    "serves the network, without authentication)");
  serve->add_option("--web-dir", serve_options.web_dir,
                    "serve the page from this directory (default: the installed page)");
  serve
      ->add_option("--max-request-bytes", serve_request_bytes,
                   "a request's body at most, in bytes (default 8 MiB)")
      ->check(WholeNumber(1024, 1LL << 32));
  serve
      ->add_option("--solve-time-limit", serve_options.solve_time_limit_s,
                   "seconds a solve or refinement of more than the minimal data may run before "
                   "it is stopped (default 120); five poses or fewer are exact and immediate")
      ->check(CLI::Range(0.1, 86400.0));
  serve
      ->add_option("--long-solves", serve_options.long_solves,
                   "long solves run at a time, each in its own process (default: the cores); "
                   "more wait their turn")
      ->check(WholeNumber(0, kMaxJobs));
  serve
      ->add_option("--threads", serve_options.threads,
                   "connections served at once (default 256; a browser holds up to six)")
      ->check(WholeNumber(2, 4096));

  BenchOptions bench_options;
  bool trade_only = false, extremes_only = false, constrained_only = false;
  CLI::App* bench = app.add_subcommand(
      "bench",
      "Measure the speed/accuracy trade of every solver path and effort level on generated "
      "tasks (trade.csv, trade.svg), the stability sweep at the numerical extremes "
      "(extremes.csv) and the first design on tasks whose design constraints bind "
      "(constrained.csv).");
  bench->add_flag("--quick", bench_options.quick, "few tasks per cell: about a minute on one core");
  bench->add_option("-o,--output-dir", bench_options.output_dir,
                    "directory for trade.csv, trade.svg, extremes.csv and constrained.csv "
                    "(default: .)");
  bench->add_option("--seed", bench_options.seed, "seed of the random task families")
      ->check(WholeNumber(0, std::numeric_limits<long long>::max()));
  CLI::Option* trade_flag =
      bench->add_flag("--trade-only", trade_only, "only the speed/accuracy trade");
  CLI::Option* extremes_flag =
      bench->add_flag("--extremes-only", extremes_only, "only the extremes sweep")
          ->excludes(trade_flag);
  bench->add_flag("--constrained-only", constrained_only, "only the constrained families")
      ->excludes(trade_flag)
      ->excludes(extremes_flag);
  bench
      ->add_option("--constrained-tasks", bench_options.constrained_tasks,
                   "tasks per random constrained family (default 40, quick 3)")
      ->check(WholeNumber(1, 1000000));
  bench->add_option("--wrong-dir", bench_options.wrong_dir,
                    "write the task files the extremes sweep answered wrongly (or with a note), "
                    "and those of the constrained families a target missed, here");
  bench->add_option("--family", bench_options.family,
                    "run only this family of the extremes sweep (e.g. rounded), or its rows whose "
                    "variant contains a text (rounded:path 5 points); of the trade, this family "
                    "(untimed path), or its rows of a number of items (untimed path:10); of the "
                    "constrained part, constrained or constrained:<part of a family name>");

  // A first word that is no command (CLI11 would say "A subcommand is required").
  const std::string first = argc > 1 ? argv[1] : "";
  if (!first.empty() && first[0] != '-' && first != "solve" && first != "refine" &&
      first != "bench" && first != "show" && first != "analyze" && first != "export" &&
      first != "serve") {
    PrintError("error", std::string("unknown command '") + argv[1] +
                            "': solve, refine, analyze, export, show, serve or bench (see "
                            "'linkfit --help')");
    return kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
      return app.exit(error);  // --help, --version
    }
    PrintError("error", std::string(error.what()) + " (see 'linkfit --help')");
    return kExitBadInput;
  }
  if (solve->parsed()) return Solve(task_path, outputs);
  if (refine->parsed()) {
    return Refine(refine_task, design_path, refine_output, refine_index, refine_summary);
  }
  if (show->parsed()) return Show(show_path);
  if (export_command->parsed()) {
    export_request.mechanism = export_index - 1;
    if (input_deg_option->count() > 0) export_request.input_deg = export_input_deg;
    return Export(export_result, export_dxf, export_svg, export_task, export_request);
  }
  if (analyze->parsed()) {
    analysis.mechanism = analyze_index - 1;
    if (!analyze_range.empty()) SetAnalysisRange(analyze_range, "--range", &analysis);
    analysis.mass_list = analyze_mass;
    return Analyze(analyze_result, analyze_output, analyze_svg, analyze_task, analysis,
                   analyze_force);
  }
  if (serve->parsed()) {
    serve_options.max_request_bytes = static_cast<size_t>(serve_request_bytes);
    return RunServe(serve_options);
  }
  if (bench->parsed()) {
    bench_options.trade = !extremes_only && !constrained_only;
    bench_options.extremes = !trade_only && !constrained_only;
    bench_options.constrained = !trade_only && !extremes_only;
    return RunBench(bench_options);
  }
  return kExitBadInput;  // unreachable: a subcommand is required
}

}  // namespace

int RunCli(int argc, char** argv) {
  // Ceres reports through glog at ERROR level even when its logging is SILENT (e.g. "Residual
  // and Jacobian evaluation failed" when a refinement steps onto a stationary configuration,
  // which the refiners handle). stderr belongs to the error contract: one line for bad input.
  FLAGS_minloglevel = google::GLOG_FATAL;
  // An interrupted run removes its temporary files and exits 128 + the signal.
  InstallSignalCleanup();
  try {
    return Run(argc, argv);
  } catch (const InputError& error) {
    PrintError("error", error.what());
    return kExitBadInput;
  } catch (const OutputError& error) {
    PrintError("error", error.what());
    return kExitBadInput;
  } catch (const std::exception& error) {
    PrintError("internal error", error.what());
    return kExitInternal;
  } catch (...) {
    PrintError("internal error", "unknown exception");
    return kExitInternal;
  }
}

}  // namespace linkfit
