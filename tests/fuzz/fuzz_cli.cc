// libFuzzer target for the command line's option handling: the input is the argument list, one
// argument per line, given to RunCli (apps/cli.h) as `linkfit ARG...` in a scratch directory
// that holds small task files (task.json, task.jsonl, path.json, function.json) and a result of
// the first (result.json) to name. Whatever the arguments, the run ends with exit 0, or with
// exit 2 and one line "linkfit: error: ..." on standard error; exit 1 (an internal error), a
// crash or a sanitizer report is a finding. Arguments stay in the scratch directory ('/' is
// read as '_'); `bench` (minutes of benchmarks) is not run. Built with -fsanitize=fuzzer by
// scripts/fuzz.sh; replay_main.cc runs it on tests/fuzz/cli_corpus/ in every build
// (FuzzCliCorpusReplay).
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "apps/cli.h"

namespace {

constexpr size_t kMaxArguments = 24;
constexpr size_t kMaxArgumentLength = 256;

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_cli: %s\n", what.c_str());
  std::abort();
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// The scratch directory (the working directory from the first input on), its fixtures by name,
// and the file that takes standard error.
struct Scratch {
  std::filesystem::path directory;
  std::map<std::string, std::string> fixtures;
  std::filesystem::path errors;
};

int RunQuietly(const Scratch& scratch, std::vector<std::string> arguments, std::string* errors);

const Scratch& GetScratch() {
  static const Scratch scratch = [] {
    Scratch made;
    std::string directory = (std::filesystem::temp_directory_path() / "linkfit-fuzz-cli.XXXXXX");
    if (mkdtemp(directory.data()) == nullptr) Finding("cannot create a scratch directory");
    made.directory = directory;
    made.errors = made.directory.string() + ".stderr";
    // Removed when the run ends (libFuzzer ends with exit(), the replay by returning from main).
    static std::filesystem::path removed_at_exit;
    removed_at_exit = made.directory;
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(removed_at_exit, ignored);
      std::filesystem::remove(removed_at_exit.string() + ".stderr", ignored);
    });
    const std::filesystem::path data = LINKFIT_SOURCE_DIR "/data";
    made.fixtures["task.json"] = ReadFile(data / "four_bar_5_poses.json");
    made.fixtures["task.jsonl"] = ReadFile(data / "batch.jsonl");
    made.fixtures["path.json"] = ReadFile(data / "path_5_points.json");
    made.fixtures["function.json"] = ReadFile(data / "function_3_pairs.json");
    for (const auto& [name, text] : made.fixtures) {
      if (text.empty()) Finding("missing fixture " + name);
    }
    std::filesystem::current_path(made.directory);
    for (const auto& [name, text] : made.fixtures) WriteFile(name, text);
    std::string errors;
    if (RunQuietly(made, {"solve", "task.json", "-o", "result.json"}, &errors) != 0) {
      Finding("the fixture task does not solve: " + errors);
    }
    made.fixtures["result.json"] = ReadFile("result.json");
    return made;
  }();
  return scratch;
}

// RunCli with standard output to /dev/null and standard error to scratch.errors (read back).
int RunQuietly(const Scratch& scratch, std::vector<std::string> arguments, std::string* errors) {
  std::fflush(stdout);
  std::fflush(stderr);
  const int saved_out = dup(STDOUT_FILENO), saved_err = dup(STDERR_FILENO);
  const int null = open("/dev/null", O_WRONLY);
  const int sink = open(scratch.errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (saved_out < 0 || saved_err < 0 || null < 0 || sink < 0) Finding("cannot redirect output");
  dup2(null, STDOUT_FILENO);
  dup2(sink, STDERR_FILENO);
  std::vector<char*> argv = {const_cast<char*>("linkfit")};
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  const int code = linkfit::RunCli(static_cast<int>(argv.size()) - 1, argv.data());
  std::fflush(stdout);
  std::fflush(stderr);
  dup2(saved_out, STDOUT_FILENO);
  dup2(saved_err, STDERR_FILENO);
  for (const int fd : {saved_out, saved_err, null, sink}) close(fd);
  *errors = ReadFile(scratch.errors);
  return code;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Scratch& scratch = GetScratch();
  std::vector<std::string> arguments(1);
  for (size_t k = 0; k < size; ++k) {
    const char c = static_cast<char>(data[k]);
    if (c == '\n') {
      if (arguments.size() == kMaxArguments) return 0;
      arguments.emplace_back();
    } else {
      // In the scratch directory: no other directory can be named; no NUL inside an argument.
      arguments.back().push_back(c == '/' || c == '\0' ? '_' : c);
      if (arguments.back().size() > kMaxArgumentLength) return 0;
    }
  }
  if (std::find(arguments.begin(), arguments.end(), "bench") != arguments.end()) return 0;

  std::string errors;
  const int code = RunQuietly(scratch, arguments, &errors);
  if (code != 0 && code != 2) Finding("exit " + std::to_string(code) + ": " + errors);
  if (code == 2) {
    const bool one_line = !errors.empty() && errors.find('\n') == errors.size() - 1;
    if (errors.rfind("linkfit: error: ", 0) != 0 || !one_line) {
      Finding("exit 2 without one line \"linkfit: error: ...\": " + errors);
    }
  }
  // Back to the fixtures alone.
  for (const auto& entry : std::filesystem::directory_iterator(scratch.directory)) {
    const std::string name = entry.path().filename().string();
    if (scratch.fixtures.count(name) == 0) std::filesystem::remove_all(entry.path());
  }
  for (const auto& [name, text] : scratch.fixtures) WriteFile(scratch.directory / name, text);
  return 0;
}
