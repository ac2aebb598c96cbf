// A program run as a child process with its inputs on pipes and a time limit: the long solves of
// `linkfit serve` (apps/web_api.h) run in `linkfit solve` / `linkfit refine` children, so a solve
// that passes its limit is killed (the library's solvers cannot be interrupted in a thread), and
// one that crashes takes no request but its own with it.
#ifndef LINKFIT_APPS_CHILD_PROCESS_H_
#define LINKFIT_APPS_CHILD_PROCESS_H_

#include <atomic>
#include <map>
#include <string>
#include <vector>

namespace linkfit {

struct ChildRun {
  std::string program;            // the executable's path
  std::vector<std::string> args;  // its arguments (argv[1...])
  // Text written to the child's descriptor n (0: standard input; 3, 4, ...: the child opens
  // /dev/fd/n), each closed when written.
  std::map<int, std::string> inputs;
  double time_limit_s = 60.0;  // killed (SIGKILL) when it runs longer
  int nice = 10;               // its scheduling niceness (below interactive requests)
  size_t max_output_bytes = size_t{64} << 20;  // killed when its standard output passes this
  // Killed as soon as this turns true (looked at every 20 ms), when given.
  const std::atomic<bool>* cancel = nullptr;
};

struct ChildOutcome {
  int exit_status = -1;  // the child's exit status; -1 when killed or stopped by a signal
  bool timed_out = false;
  bool output_too_long = false;
  bool cancelled = false;
  std::string out;  // its standard output
  std::string err;  // its standard error
  double seconds = 0.0;
};

// Runs `run` and waits for it. Throws std::runtime_error when the child cannot be started.
ChildOutcome RunChild(const ChildRun& run);

}  // namespace linkfit

#endif  // LINKFIT_APPS_CHILD_PROCESS_H_
