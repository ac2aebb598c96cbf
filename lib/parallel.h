// Runs independent work items on a pool of threads: the batch mode of `linkfit solve` and the
// Python module's solve_many (a task a thread), and within one solve its independent stages
// (the nine-point homotopy's paths, the free-timing refinements of a stage's candidates:
// TaskSolverOptions::threads).
#ifndef LINKFIT_LIB_PARALLEL_H_
#define LINKFIT_LIB_PARALLEL_H_

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace linkfit {

// The threads `requested` asks for: itself when positive, else the machine's (at least one).
inline unsigned ThreadCount(int requested) {
  return requested > 0 ? static_cast<unsigned>(requested)
                       : std::max(1u, std::thread::hardware_concurrency());
}

// Runs work(i) for every i in [0, count) on `jobs` threads, the calling one among them, each
// taking the next index in turn; returns when all are done. An exception work(i) throws is
// rethrown then (of several, the one of the smallest i).
template <typename Work>
void ParallelFor(size_t count, unsigned jobs, const Work& work) {
  std::atomic<size_t> next(0);
  std::vector<std::exception_ptr> errors(count);
  const auto run = [&]() {
    for (size_t i = next++; i < count; i = next++) {
      try {
        work(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < std::min<size_t>(jobs, count); ++w) pool.emplace_back(run);
  run();
  for (std::thread& thread : pool) thread.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace linkfit

#endif  // LINKFIT_LIB_PARALLEL_H_
