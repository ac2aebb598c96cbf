#include "apps/output_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

namespace linkfit {
namespace {

// ---- The temporary files the signal handlers remove ----------------------------------------
//
// A fixed table that the handlers read without locks or allocation: a slot's state goes
// 0 (free) -> 1 (being filled) -> 2 (holds a path) and back to 0; the handlers remove only the
// paths of slots in state 2. std::atomic<int> is lock-free here, hence async-signal-safe.

constexpr int kSlots = 64;
struct Slot {
  std::atomic<int> state{0};
  char path[PATH_MAX];
};
Slot g_slots[kSlots];

int RegisterTemporary(const std::string& path) {
  if (path.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;  // more pending outputs than slots: removed by the destructor only
}

void UnregisterTemporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0);
}

void WriteAll(int descriptor, const char* text) {
  size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t written = ::write(descriptor, text, left);
    if (written <= 0) return;
    text += written;
    left -= static_cast<size_t>(written);
  }
}

extern "C" void RemoveTemporariesAndExit(int signal_number) {
  for (Slot& slot : g_slots) {
    if (slot.state.load() == 2) ::unlink(slot.path);
  }
  const char* name = signal_number == SIGINT    ? "SIGINT"
                     : signal_number == SIGTERM ? "SIGTERM"
                     : signal_number == SIGHUP  ? "SIGHUP"
                                                : nullptr;
  // A closed pipe ends the program silently, as it ends any filter.
  if (name != nullptr) {
    WriteAll(STDERR_FILENO, "linkfit: stopped by ");
    WriteAll(STDERR_FILENO, name);
    WriteAll(STDERR_FILENO, ": nothing written\n");
  }
  ::_exit(128 + signal_number);
}

// The cleanup signals blocked in the calling thread while a temporary file is created and
// registered (or unlinked), so that no handler runs in between.
class BlockedSignals {
 public:
  BlockedSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, &previous_);
  }
  ~BlockedSignals() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

 private:
  sigset_t previous_;
};

// ---- Targets ---------------------------------------------------------------------------------

// The descriptor a path names directly (/dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N),
// or -1.
int NamedDescriptor(const std::string& path) {
  if (path == "/dev/stdout") return STDOUT_FILENO;
  if (path == "/dev/stderr") return STDERR_FILENO;
  for (const std::string prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    if (path.rfind(prefix, 0) != 0) continue;
    const std::string number = path.substr(prefix.size());
    if (number.empty() || number.size() > 6 ||
        number.find_first_not_of("0123456789") != std::string::npos) {
      return -1;
    }
    return std::stoi(number);
  }
  return -1;
}

// Paths of the kernel's file systems, where nothing is ever renamed.
bool InDeviceTree(const std::string& path) {
  return path.rfind("/dev/", 0) == 0 || path.rfind("/proc/", 0) == 0 || path.rfind("/sys/", 0) == 0;
}

mode_t CurrentUmask() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}

std::string TemporaryDirectory() {
  const char* directory = std::getenv("TMPDIR");
  if (directory != nullptr && directory[0] != '\0') return directory;
  return "/tmp";
}

// Held in memory up to this many bytes before an in-place output spills to a temporary file.
constexpr size_t kMemoryLimit = size_t{1} << 20;
// Written to the temporary file in pieces of this size.
constexpr size_t kFlushBytes = size_t{64} << 10;

}  // namespace

OutputFile::OutputFile(const std::string& path, const std::string& item)
    : path_(path), item_(item) {
  struct stat status;
  if (path.empty() || path == "-" || NamedDescriptor(path) >= 0) {
    target_ = Target::kDescriptor;
    target_descriptor_ = path.empty() || path == "-" ? STDOUT_FILENO : NamedDescriptor(path);
    const int flags = ::fcntl(target_descriptor_, F_GETFL);
    if (flags == -1) Fail("cannot write", errno);
    if ((flags & O_ACCMODE) == O_RDONLY) Fail("cannot write", EBADF);
    if (::fstat(target_descriptor_, &status) == 0) {
      identity_ = {status.st_dev, status.st_ino};
      character_device_ = S_ISCHR(status.st_mode);
    }
    return;
  }
  target_path_ = path;
  struct stat link;
  if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    char resolved[PATH_MAX];
    if (::realpath(path.c_str(), resolved) == nullptr) {
      Fail("a symbolic link to a missing file or directory", 0);
    }
    target_path_ = resolved;
  }
  const bool exists = ::stat(target_path_.c_str(), &status) == 0;
  if (!exists && errno != ENOENT) Fail("cannot write", errno);
  if (exists) {
    identity_ = {status.st_dev, status.st_ino};
    character_device_ = S_ISCHR(status.st_mode);
    if (S_ISDIR(status.st_mode)) Fail("is a directory", 0);
    if (S_ISSOCK(status.st_mode)) Fail("is a socket, not a file", 0);
    if (!S_ISREG(status.st_mode) || InDeviceTree(target_path_)) {
      target_ = Target::kInPlace;  // written through, never renamed over
      if (::access(target_path_.c_str(), W_OK) != 0) Fail("cannot write", errno);
      return;
    }
    if (::access(target_path_.c_str(), W_OK) != 0) Fail("cannot write", errno);
  } else if (InDeviceTree(target_path_)) {
    Fail("cannot write", ENOENT);  // nothing is created among devices
  }
  // A regular file, or a new one: a temporary file beside it, renamed over it at the commit.
  const std::filesystem::path target(target_path_);
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") Fail("is a directory", 0);
  std::string directory = target.parent_path().string();
  if (directory.empty()) directory = ".";
  if (!exists) {
    std::error_code error;
    new_file_ =
        std::filesystem::weakly_canonical(std::filesystem::absolute(target), error).string();
    if (error) new_file_ = target_path_;
  }
  std::string pattern = directory + "/." + name + ".XXXXXX";
  {
    BlockedSignals blocked;
    temporary_descriptor_ = ::mkostemp(pattern.data(), O_CLOEXEC);
    if (temporary_descriptor_ == -1) Fail("cannot create a file in " + directory, errno);
    temporary_ = pattern;
    registration_ = RegisterTemporary(temporary_);
  }
  // The permissions (and, as root, the owner) of the file it replaces; a new file gets those the
  // umask leaves, as the shell's > would give it.
  const mode_t mode = exists ? (status.st_mode & 07777) : (0666 & ~CurrentUmask());
  if (::fchmod(temporary_descriptor_, mode) != 0) Fail("cannot write", errno);
  if (exists && ::geteuid() == 0 &&
      (status.st_uid != ::geteuid() || status.st_gid != ::getegid())) {
    (void)!::fchown(temporary_descriptor_, status.st_uid, status.st_gid);
  }
}

OutputFile::~OutputFile() {
  if (temporary_descriptor_ != -1) ::close(temporary_descriptor_);
  if (!committed_ && !temporary_.empty()) {
    BlockedSignals blocked;
    ::unlink(temporary_.c_str());
    UnregisterTemporary(registration_);
  }
  // A FIFO whose run failed: its reader, if one waits, gets end of file (as it would from a
  // shell's redirection) rather than waiting for ever; without a reader the open fails at once.
  if (!committed_ && target_ == Target::kInPlace) {
    struct stat status {};
    if (::stat(target_path_.c_str(), &status) == 0 && S_ISFIFO(status.st_mode)) {
      const int descriptor = ::open(target_path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
      if (descriptor != -1) ::close(descriptor);
    }
  }
}

void OutputFile::Fail(const std::string& what, int error) const {
  std::string message = item_ + " " + (path_.empty() ? "-" : path_) + ": ";
  if (target_ == Target::kDescriptor && path_ == "-") message = item_ + ": standard output: ";
  if (target_ == Target::kDescriptor && path_.empty()) message = "standard output: ";
  message += what;
  if (error != 0) message += std::string(" (") + std::strerror(error) + ")";
  throw OutputError(message);
}

void OutputFile::Write(std::string_view text) {
  buffer_.append(text.data(), text.size());
  if (temporary_descriptor_ == -1) {
    if (buffer_.size() <= kMemoryLimit) return;
    // An in-place output grown past memory's share: an unlinked temporary file, which nothing
    // needs to remove.
    std::string pattern = TemporaryDirectory() + "/linkfit-XXXXXX";
    BlockedSignals blocked;
    temporary_descriptor_ = ::mkostemp(pattern.data(), O_CLOEXEC);
    if (temporary_descriptor_ == -1) {
      Fail("cannot create a temporary file in " + TemporaryDirectory(), errno);
    }
    ::unlink(pattern.c_str());
  }
  if (buffer_.size() >= kFlushBytes) Flush();
}

void OutputFile::Flush() {
  const char* data = buffer_.data();
  size_t left = buffer_.size();
  while (left > 0) {
    const ssize_t written = ::write(temporary_descriptor_, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) Fail("cannot write", written < 0 ? errno : ENOSPC);
    data += written;
    left -= static_cast<size_t>(written);
  }
  buffer_.clear();
}

void OutputFile::WriteTo(int descriptor, std::string_view text) {
  const char* data = text.data();
  size_t left = text.size();
  while (left > 0) {
    const ssize_t written = ::write(descriptor, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) Fail("cannot write", written < 0 ? errno : EIO);
    data += written;
    left -= static_cast<size_t>(written);
  }
}

void OutputFile::Commit() {
  if (committed_) return;
  if (target_ == Target::kReplace) {
    Flush();
    if (::fsync(temporary_descriptor_) != 0 && errno != EINVAL) Fail("cannot write", errno);
    const int descriptor = temporary_descriptor_;
    temporary_descriptor_ = -1;
    if (::close(descriptor) != 0) Fail("cannot write", errno);
    BlockedSignals blocked;
    if (::rename(temporary_.c_str(), target_path_.c_str()) != 0) Fail("cannot write", errno);
    UnregisterTemporary(registration_);
    committed_ = true;
    return;
  }
  // In place: the descriptor itself, or the target opened for writing (a FIFO waits for its
  // reader here).
  int descriptor = target_descriptor_;
  if (target_ == Target::kInPlace) {
    do {
      descriptor = ::open(target_path_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    } while (descriptor == -1 && errno == EINTR);
    if (descriptor == -1) Fail("cannot write", errno);
  }
  struct Closer {
    int descriptor;
    bool own;
    ~Closer() {
      if (own) ::close(descriptor);
    }
  } closer{descriptor, target_ == Target::kInPlace};
  if (temporary_descriptor_ != -1) {
    Flush();
    if (::lseek(temporary_descriptor_, 0, SEEK_SET) != 0) Fail("cannot write", errno);
    std::string chunk(kFlushBytes, '\0');
    while (true) {
      const ssize_t got = ::read(temporary_descriptor_, chunk.data(), chunk.size());
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) Fail("cannot write", errno);
      if (got == 0) break;
      WriteTo(descriptor, std::string_view(chunk.data(), static_cast<size_t>(got)));
    }
  } else {
    WriteTo(descriptor, buffer_);
    buffer_.clear();
  }
  committed_ = true;
}

OutputFile& OutputSet::Add(const std::string& path, const std::string& item) {
  auto file = std::make_unique<OutputFile>(path, item);
  const auto identity = file->identity();
  // Character devices (/dev/null) may take several outputs; files and streams may not.
  const bool shareable = identity.second != 0 && file->is_character_device();
  for (const auto& [input, input_identity] : inputs_) {
    if (identity.second != 0 && identity == input_identity) {
      throw OutputError(item + " " + path + ": is " + input + ", which this run reads");
    }
  }
  for (const auto& other : files_) {
    const bool same_file = identity.second != 0 ? identity == other->identity()
                                                : file->new_file() == other->new_file();
    if (same_file && !shareable) {
      throw OutputError(item + " " + (path.empty() ? "-" : path) + ": the same file as " +
                        other->item() + " " + (other->path().empty() ? "-" : other->path()));
    }
  }
  files_.push_back(std::move(file));
  return *files_.back();
}

void OutputSet::AddInput(const std::string& path) {
  struct stat status;
  if (::stat(path.c_str(), &status) == 0) {
    inputs_.push_back({path, {status.st_dev, status.st_ino}});
  }
}

void OutputSet::CommitAll() {
  // Files first: a stream (a pipe) that closes early must not leave them uncommitted.
  for (const auto& file : files_) {
    if (file->replaces()) file->Commit();
  }
  for (const auto& file : files_) file->Commit();
}

void WriteOutputFile(const std::string& path, const std::string& item, std::string_view text) {
  OutputFile file(path, item);
  file.Write(text);
  file.Commit();
}

void InstallSignalCleanup() {
  static std::atomic<bool> installed(false);
  if (installed.exchange(true)) return;
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
    struct sigaction previous;
    if (::sigaction(signal_number, nullptr, &previous) != 0) continue;
    // A signal the caller ignores (nohup, a background job) stays ignored.
    if (previous.sa_handler == SIG_IGN) continue;
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = RemoveTemporariesAndExit;
    sigemptyset(&action.sa_mask);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&action.sa_mask, s);
    ::sigaction(signal_number, &action, nullptr);
  }
}

}  // namespace linkfit
