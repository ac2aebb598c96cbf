// Runs the `linkfit` program as a user's shell would (fork and exec), for the tests that look at
// what a run leaves behind: its exit status or the signal that ended it, its peak memory, its
// standard output and error, with standard output closed or a signal sent mid-run on demand.
#ifndef LINKFIT_TESTS_APPS_PROGRAM_RUN_H_
#define LINKFIT_TESTS_APPS_PROGRAM_RUN_H_

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace linkfit::testing {

inline std::string ReadWholeFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

struct ProgramOptions {
  std::string directory = ".";  // the working directory; .stdout and .stderr are kept there
  bool close_stdout = false;    // start it with standard output closed
  std::string stdout_path;      // standard output to this file (default: .stdout, read back)
  std::vector<std::string> environment;  // NAME=VALUE set in the child
  int signal = 0;                        // sent after signal_after_seconds, when not 0
  double signal_after_seconds = 0.0;
};

struct ProgramResult {
  int status = -1;       // exit status, -1 when a signal ended it
  int signal = 0;        // the signal that ended it
  long max_rss_kb = -1;  // the program's peak resident set size
  double seconds = 0.0;
  std::string out;
  std::string err;
};

// Runs `program args...`.
inline ProgramResult RunProgram(const std::string& program, const std::vector<std::string>& args,
                                const ProgramOptions& options = {}) {
  const std::string out_path =
      options.stdout_path.empty() ? options.directory + "/.stdout" : options.stdout_path;
  const std::string err_path = options.directory + "/.stderr";
  std::vector<std::string> strings = {program};
  strings.insert(strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::vector<std::string> environment = options.environment;
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (err < 0 || chdir(options.directory.c_str()) != 0 || dup2(err, 2) < 0) _exit(127);
    if (options.close_stdout) {
      close(1);
    } else {
      const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (out < 0 || dup2(out, 1) < 0) _exit(127);
    }
    for (std::string& setting : environment) putenv(setting.data());
    execv(argv[0], argv.data());
    _exit(127);
  }
  ProgramResult result;
  if (pid < 0) return result;
  if (options.signal != 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(options.signal_after_seconds));
    kill(pid, options.signal);
  }
  int raw = 0;
  struct rusage usage {};
  if (wait4(pid, &raw, 0, &usage) != pid) return result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  result.signal = WIFSIGNALED(raw) ? WTERMSIG(raw) : 0;
  result.max_rss_kb = usage.ru_maxrss;
  if (options.stdout_path.empty()) result.out = ReadWholeFile(out_path);
  result.err = ReadWholeFile(err_path);
  if (options.stdout_path.empty()) std::remove(out_path.c_str());
  std::remove(err_path.c_str());
  return result;
}

// Whether `err` is one printable line.
inline bool OnePrintableLine(const std::string& err) {
  if (err.empty() || err.find('\n') != err.size() - 1) return false;
  for (size_t i = 0; i + 1 < err.size(); ++i) {
    if (err[i] < 0x20 || err[i] >= 0x7f) return false;
  }
  return true;
}

// A test in a scratch directory of its own (under /tmp, removed after the test): Path names a
// file there, Write writes one (returning its path), Names lists the directory, sorted.
class ScratchDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/linkfit_test_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }
  std::vector<std::string> Names() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  std::string dir_;
};

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_APPS_PROGRAM_RUN_H_
