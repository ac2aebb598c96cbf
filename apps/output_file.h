// The output contract of every file linkfit writes -- results, batch results, pictures, the
// benchmark's tables (user guide, "Output files"):
//
// - a regular file (or a new one) is replaced atomically: the text goes to a temporary file
//   created with mkstemp (O_EXCL, an unpredictable name) in the target's directory, which takes
//   the permissions (and, for root, the owner) of the file it replaces and is renamed over it;
//   a symbolic link is followed, so the file it names is replaced and the link stays;
// - a target that is not a regular file (a FIFO, a character device such as /dev/null, a
//   socket, /dev/stdout or /dev/fd/N) and standard output ("-" or "") are written in place,
//   never renamed over: the text is held in an unlinked temporary file until the commit;
// - every output of a run is written only when the whole run succeeds (OutputSet::CommitAll);
// - temporary files are removed on every exit path: destructors on errors, and the handlers of
//   InstallSignalCleanup on SIGINT, SIGTERM, SIGHUP and SIGPIPE;
// - a target that is a directory, an input of the run or another output of it is refused.
//
// Every refusal is an OutputError of one line naming the option ("-o", "--svg") and the path.
#ifndef LINKFIT_APPS_OUTPUT_FILE_H_
#define LINKFIT_APPS_OUTPUT_FILE_H_

#include <sys/types.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace linkfit {

// An output that cannot be written: like bad input, exit status 2.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One output of a run. The constructor checks the target and creates the temporary file, so a
// target that cannot be written is refused before any work is done.
class OutputFile {
 public:
  // `path`: a file, or "" or "-" for standard output; `item`: how messages name it ("-o").
  OutputFile(const std::string& path, const std::string& item);
  ~OutputFile();  // removes the temporary file unless committed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Appends `text` to the temporary file; throws OutputError when it cannot be written.
  void Write(std::string_view text);
  // Moves the text into place (rename, or a copy to the stream); at most once.
  void Commit();

  const std::string& path() const { return path_; }
  const std::string& item() const { return item_; }
  // The target's (device, inode) once resolved, or (0, 0) when it does not exist yet.
  std::pair<dev_t, ino_t> identity() const { return identity_; }
  // The file to be made, for a target that does not exist yet (absolute, links resolved).
  const std::string& new_file() const { return new_file_; }
  bool is_character_device() const { return character_device_; }
  // Whether the commit renames a temporary file over the target (else it writes in place).
  bool replaces() const { return target_ == Target::kReplace; }

 private:
  enum class Target { kReplace, kInPlace, kDescriptor };
  [[noreturn]] void Fail(const std::string& what, int error) const;
  void Flush();  // the buffer to the temporary file
  void WriteTo(int descriptor, std::string_view text);

  std::string path_;         // as given
  std::string item_;         // "-o", "--svg", ...
  std::string target_path_;  // the file to replace or to open in place (links resolved)
  Target target_ = Target::kReplace;
  int target_descriptor_ = -1;  // kDescriptor: the descriptor to write (1 for standard output)
  std::pair<dev_t, ino_t> identity_{0, 0};
  std::string new_file_;
  bool character_device_ = false;
  std::string buffer_;     // text not yet in the temporary file
  std::string temporary_;  // kReplace: the temporary file's name (registered for signals)
  int temporary_descriptor_ = -1;
  int registration_ = -1;  // slot of the signal handlers' list
  bool committed_ = false;
};

// Every output of one run, created up front and committed together at the end: nothing is
// written unless every output could be prepared and the run succeeded.
class OutputSet {
 public:
  // Refuses (OutputError) a target that is one of `inputs` (task and design files) or another
  // output of the set.
  OutputFile& Add(const std::string& path, const std::string& item);
  // Files the run reads, which no output may replace; `item` names them in messages.
  void AddInput(const std::string& path);
  void CommitAll();

 private:
  std::vector<std::unique_ptr<OutputFile>> files_;
  std::vector<std::pair<std::string, std::pair<dev_t, ino_t>>> inputs_;
};

// Writes `text` to `path` (item `item`) under the contract above.
void WriteOutputFile(const std::string& path, const std::string& item, std::string_view text);

// Installs, once, handlers for SIGINT, SIGTERM, SIGHUP and SIGPIPE that remove every temporary
// file still pending, print one line on stderr (not for SIGPIPE) and exit with 128 + the signal
// (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP). The `linkfit` program calls it; the Python
// module does not (Python owns its signals, and the module writes no files).
void InstallSignalCleanup();

}  // namespace linkfit

#endif  // LINKFIT_APPS_OUTPUT_FILE_H_
