// RunChild (child_process.h): posix_spawn with pipes on the child's descriptors, and one poll
// loop that writes its inputs and reads its outputs together (neither side can block the other
// on a full pipe) until it exits or its time is up.
#include "apps/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace linkfit {
namespace {

// A descriptor closed when it goes out of scope.
class Descriptor {
 public:
  Descriptor() = default;
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(Descriptor&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  Descriptor& operator=(Descriptor&& other) noexcept {
    if (this != &other) {
      Close();
      fd_ = other.fd_;
      other.fd_ = -1;
    }
    return *this;
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { Close(); }
  int get() const { return fd_; }
  void Close() {
    if (fd_ != -1) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

// A pipe whose both ends are closed on exec: the child gets its end through a dup2 of the spawn,
// and no other child started meanwhile by another thread inherits either end.
void MakePipe(Descriptor* read_end, Descriptor* write_end) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  }
  *read_end = Descriptor(fds[0]);
  *write_end = Descriptor(fds[1]);
}

void SetNonBlocking(int fd) { ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK); }

// An input being written to the child.
struct Feed {
  Descriptor fd;
  const std::string* text = nullptr;
  size_t written = 0;
};

constexpr size_t kErrKept = size_t{64} << 10;

}  // namespace

ChildOutcome RunChild(const ChildRun& run) {
  const auto start = std::chrono::steady_clock::now();
  ChildOutcome outcome;
  Descriptor out_read, out_write, err_read, err_write;
  MakePipe(&out_read, &out_write);
  MakePipe(&err_read, &err_write);
  std::vector<Feed> feeds;
  std::vector<Descriptor> child_ends;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  for (const auto& [target, text] : run.inputs) {
    Descriptor read_end, write_end;
    MakePipe(&read_end, &write_end);
    posix_spawn_file_actions_adddup2(&actions, read_end.get(), target);
    child_ends.push_back(std::move(read_end));
    feeds.push_back(Feed{std::move(write_end), &text, 0});
  }
  if (run.inputs.count(0) == 0)
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_write.get(), 1);
  posix_spawn_file_actions_adddup2(&actions, err_write.get(), 2);
  // Nothing else of this process's: httplib accepts its connections without close-on-exec, and
  // a child holding them would keep a client's connection open past the server's life.
  const int first_unused = run.inputs.empty() ? 3 : std::max(3, run.inputs.rbegin()->first + 1);
  posix_spawn_file_actions_addclosefrom_np(&actions, first_unused);
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(run.program.c_str()));
  for (const std::string& arg : run.args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned =
      ::posix_spawn(&pid, run.program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    throw std::runtime_error("cannot run " + run.program + ": " + std::strerror(spawned));
  }
  // The child is killed and reaped however this function ends (a failed poll, an exception).
  struct Reaper {
    pid_t pid;
    bool reaped = false;
    ~Reaper() {
      if (reaped) return;
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, nullptr, 0) == -1 && errno == EINTR) {
      }
    }
  } reaper{pid};
  ::setpriority(PRIO_PROCESS, static_cast<id_t>(pid), run.nice);
  // The child's ends are its own now: closed here, so its exit gives the parent end-of-file.
  child_ends.clear();
  out_write.Close();
  err_write.Close();
  for (Feed& feed : feeds) SetNonBlocking(feed.fd.get());
  SetNonBlocking(out_read.get());
  SetNonBlocking(err_read.get());

  const auto deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(run.time_limit_s));
  char buffer[1 << 16];
  while (out_read.get() != -1 || err_read.get() != -1) {
    std::vector<pollfd> polled;
    for (Feed& feed : feeds) {
      if (feed.fd.get() != -1) polled.push_back(pollfd{feed.fd.get(), POLLOUT, 0});
    }
    for (const Descriptor* fd : {&out_read, &err_read}) {
      if (fd->get() != -1) polled.push_back(pollfd{fd->get(), POLLIN, 0});
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      outcome.timed_out = true;
      break;
    }
    if (run.cancel != nullptr && run.cancel->load()) {
      outcome.cancelled = true;
      break;
    }
    const int wait_ms = static_cast<int>(left.count()) + 1;
    const int ready = ::poll(polled.data(), polled.size(),
                             run.cancel != nullptr ? std::min(wait_ms, 20) : wait_ms);
    if (ready < 0 && errno != EINTR) {
      outcome.timed_out = true;  // cannot wait on it any more: stopped as at its limit
      break;
    }
    for (Feed& feed : feeds) {
      if (feed.fd.get() == -1) continue;
      const size_t left_bytes = feed.text->size() - feed.written;
      const ssize_t n = left_bytes == 0
                            ? 0
                            : ::write(feed.fd.get(), feed.text->data() + feed.written, left_bytes);
      if (n > 0) feed.written += static_cast<size_t>(n);
      // Written, or the child closed its end (EPIPE: it read what it needed, or failed).
      if (feed.written == feed.text->size() || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        feed.fd.Close();
      }
    }
    for (auto [fd, text] :
         {std::pair{&out_read, &outcome.out}, std::pair{&err_read, &outcome.err}}) {
      if (fd->get() == -1) continue;
      while (true) {
        const ssize_t n = ::read(fd->get(), buffer, sizeof(buffer));
        if (n > 0) {
          text->append(buffer, static_cast<size_t>(n));
          continue;
        }
        if (n == 0 || (errno != EAGAIN && errno != EINTR)) fd->Close();
        break;
      }
    }
    // Standard error: its last line is the message; a child that writes on and on keeps 64 KiB.
    if (outcome.err.size() > kErrKept) outcome.err.erase(0, outcome.err.size() - kErrKept);
    if (outcome.out.size() > run.max_output_bytes) {
      outcome.output_too_long = true;
      break;
    }
  }
  if (outcome.timed_out || outcome.output_too_long || outcome.cancelled) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) == -1 && errno == EINTR) {
  }
  reaper.reaped = true;
  outcome.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

}  // namespace linkfit
