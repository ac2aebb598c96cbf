// The `linkfit` command line (see cli.h). Thin: CLI11 parses the arguments, the library reads,
// solves and writes; this file only maps outcomes to output and exit status.
#include "apps/cli.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fitting/planar_motion.h"
#include "lib/result_io.h"
#include "lib/task_io.h"

namespace linkfit {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitInternal = 1;
constexpr int kExitBadInput = 2;

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
    "Exit status: 0 solved (an empty \"dyads\" with notes when nothing was found);\n"
    "  1 internal fault; 2 bad input or usage: one line on stderr naming the file, the item and\n"
    "  what is wrong, and no result file.";

constexpr const char* kSolveFooter =
    "Task fields:\n"
    "  problem   \"motion\" (default) or \"path\"\n"
    "  space     \"planar\" (default) or \"spatial\" (motion only)\n"
    "  poses     motion: planar {\"x\", \"y\", \"theta_deg\"} (at least 5), or spatial (at least "
    "1)\n"
    "            one of {\"q\": [q1,q2,q3,q4], \"g\": [g1,g2,g3,g4]} (q4 scalar, g = 1/2 d q),\n"
    "            {\"rotation\": [[3],[3],[3]], \"translation\": [3]} or\n"
    "            {\"axis\": [3], \"angle_deg\": a, \"translation\": [3]};\n"
    "            optional \"weight\" (> 0, default 1) and \"exact\" (true/false)\n"
    "  points    path: {\"x\", \"y\"} with optional \"input_deg\" (all or none), \"weight\",\n"
    "            \"exact\"\n"
    "  scale     characteristic length L (> 0); default: RMS distance of the pose origins or\n"
    "            points from their centroid\n"
    "  options   {\"effort\": \"fast\" | \"balanced\" (default) | \"thorough\"}\n"
    "Poses are (x, y, theta): the body frame's origin in the fixed frame and its\n"
    "counter-clockwise turn. Coincident poses, non-unit quaternions and unknown fields are\n"
    "errors (exit 2).";

// Bad output path: like bad input, exit 2.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

// Writes `text` to a temporary file next to `path` and renames it into place, so a reader
// never sees a partial result and a failure leaves no file behind.
void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::filesystem::path target(path);
  const std::filesystem::path temporary =
      target.parent_path() /
      ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()));
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    if (file) file << text;
    file.close();
    if (!file) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw OutputError(path + ": cannot write file");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, target, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw OutputError(path + ": cannot write file (" + error.message() + ")");
  }
}

// `linkfit solve`: every task is read and validated before anything is solved or written.
int Solve(const std::string& task_path, const std::string& output_path) {
  const std::vector<Task> tasks = ReadTaskFile(task_path);
  const int indent = IsJsonLines(task_path) ? -1 : 2;
  std::string text;
  for (const Task& task : tasks) text += ResultToJson(SolveTask(task), indent) + "\n";
  if (output_path.empty() || output_path == "-") {
    std::cout << text << std::flush;
    if (!std::cout) throw std::runtime_error("cannot write to standard output");
  } else {
    WriteFileAtomically(output_path, text);
  }
  return kExitOk;
}

int Run(int argc, char** argv) {
  CLI::App app(kDescription, "linkfit");
  app.footer(kFooter);
  app.set_version_flag("--version", "linkfit 0.1.0");
  app.require_subcommand(1);

  std::string task_path, output_path;
  CLI::App* solve = app.add_subcommand("solve", "Synthesize linkages for a task file.");
  solve->footer(kSolveFooter);
  solve->add_option("TASK", task_path, "task file: .json (one task) or .jsonl (one per line)")
      ->required();
  solve->add_option("-o,--output", output_path,
                    "write the result to this file (written only on success; - for stdout)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
      return app.exit(error);  // --help, --version
    }
    PrintError("error", std::string(error.what()) + " (see 'linkfit --help')");
    return kExitBadInput;
  }
  if (solve->parsed()) return Solve(task_path, output_path);
  return kExitBadInput;  // unreachable: a subcommand is required
}

}  // namespace

int RunCli(int argc, char** argv) {
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
