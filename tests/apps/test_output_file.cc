// The output contract (apps/output_file.h) in the program's own process: a regular target
// replaced atomically with its permissions kept, symbolic links followed, streams and devices
// written in place, temporary names that cannot be planted, nothing written before the commit
// and nothing left behind.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "apps/output_file.h"
#include "tests/apps/program_run.h"

namespace linkfit {
namespace {

using testing::ReadWholeFile;

using OutputFileTest = testing::ScratchDirectoryTest;

// Before this contract the temporary files had predictable names (.NAME.tmp.<pid> beside the
// target, /tmp/linkfit-result.<pid> for standard output) and were opened without O_EXCL: a link
// planted there had its target overwritten.
TEST_F(OutputFileTest, PlantedLinksAtTheOldNamesAreNotFollowed) {
  Write("victim", "precious\n");
  const std::string pid = std::to_string(getpid());
  ASSERT_EQ(symlink(Path("victim").c_str(), Path(".out.json.tmp." + pid).c_str()), 0);
  const std::string old_stdout_name = "/tmp/linkfit-result." + pid;
  std::filesystem::remove(old_stdout_name);
  ASSERT_EQ(symlink(Path("victim").c_str(), old_stdout_name.c_str()), 0);
  WriteOutputFile(Path("out.json"), "-o", "result\n");
  EXPECT_EQ(ReadWholeFile(Path("out.json")), "result\n");
  EXPECT_EQ(ReadWholeFile(Path("victim")), "precious\n");
  std::filesystem::remove(old_stdout_name);
}

TEST_F(OutputFileTest, NothingIsWrittenBeforeTheCommitAndNothingIsLeft) {
  Write("out.json", "old\n");
  {
    OutputFile file(Path("out.json"), "-o");
    file.Write("new\n");
    EXPECT_EQ(ReadWholeFile(Path("out.json")), "old\n");
    EXPECT_EQ(Names().size(), 2u);  // the target and its temporary file beside it
    // Not committed: the destructor removes the temporary file.
  }
  EXPECT_EQ(Names(), std::vector<std::string>{"out.json"});
  EXPECT_EQ(ReadWholeFile(Path("out.json")), "old\n");
  OutputFile file(Path("out.json"), "-o");
  file.Write("new\n");
  file.Commit();
  EXPECT_EQ(ReadWholeFile(Path("out.json")), "new\n");
  EXPECT_EQ(Names(), std::vector<std::string>{"out.json"});
}

TEST_F(OutputFileTest, PermissionsOfTheReplacedFileAndNewFilesByTheUmask) {
  Write("kept.json", "old\n");
  ASSERT_EQ(chmod(Path("kept.json").c_str(), 0640), 0);
  WriteOutputFile(Path("kept.json"), "-o", "new\n");
  struct stat status;
  ASSERT_EQ(stat(Path("kept.json").c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 07777, 0640u);
  const mode_t mask = umask(022);
  WriteOutputFile(Path("new.json"), "-o", "new\n");
  umask(mask);
  ASSERT_EQ(stat(Path("new.json").c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 07777, 0644u);  // not mkstemp's 0600
}

TEST_F(OutputFileTest, ALinkIsFollowedAndStays) {
  Write("real.json", "old\n");
  ASSERT_EQ(symlink("real.json", Path("link.json").c_str()), 0);
  WriteOutputFile(Path("link.json"), "-o", "new\n");
  EXPECT_TRUE(std::filesystem::is_symlink(Path("link.json")));
  EXPECT_EQ(ReadWholeFile(Path("real.json")), "new\n");
  // A link to nothing is refused rather than guessed at.
  ASSERT_EQ(symlink("missing/file.json", Path("dangling.json").c_str()), 0);
  EXPECT_THROW(WriteOutputFile(Path("dangling.json"), "-o", "x"), OutputError);
}

TEST_F(OutputFileTest, AFifoIsWrittenInPlace) {
  ASSERT_EQ(mkfifo(Path("pipe").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&]() { received = ReadWholeFile(Path("pipe")); });
  // More than the part held in memory, so that the unlinked temporary file is used too.
  const std::string text(3 << 20, 'x');
  WriteOutputFile(Path("pipe"), "-o", text);
  reader.join();
  EXPECT_EQ(received, text);
  struct stat status;
  ASSERT_EQ(lstat(Path("pipe").c_str(), &status), 0);
  EXPECT_TRUE(S_ISFIFO(status.st_mode));
  EXPECT_EQ(Names(), std::vector<std::string>{"pipe"});
}

TEST_F(OutputFileTest, DevNullStaysADevice) {
  WriteOutputFile("/dev/null", "-o", "discarded\n");
  struct stat status;
  ASSERT_EQ(stat("/dev/null", &status), 0);
  EXPECT_TRUE(S_ISCHR(status.st_mode));
  // Two outputs of one run may both be /dev/null; two to one file may not.
  OutputSet outputs;
  outputs.Add("/dev/null", "-o");
  EXPECT_NO_THROW(outputs.Add("/dev/null", "--svg"));
  OutputSet same;
  same.Add(Path("a.json"), "-o");
  EXPECT_THROW(same.Add(Path("a.json"), "--svg"), OutputError);
}

TEST_F(OutputFileTest, RefusalsNameTheOptionAndThePath) {
  Write("task.json", "{}");
  OutputSet outputs;
  outputs.AddInput(Path("task.json"));
  try {
    outputs.Add(Path("task.json"), "-o");
    ADD_FAILURE() << "the task file itself was accepted as the output";
  } catch (const OutputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "-o " + Path("task.json") + ": is " + Path("task.json") + ", which this run reads");
  }
  EXPECT_EQ(ReadWholeFile(Path("task.json")), "{}");
  try {
    OutputFile file(dir_, "--svg");
    ADD_FAILURE() << "a directory was accepted";
  } catch (const OutputError& error) {
    EXPECT_EQ(std::string(error.what()), "--svg " + dir_ + ": is a directory");
  }
  try {
    OutputFile file(Path("missing/out.json"), "--animate");
    ADD_FAILURE() << "a file in a missing directory was accepted";
  } catch (const OutputError& error) {
    EXPECT_EQ(std::string(error.what())
                  .rfind("--animate " + Path("missing/out.json") + ": cannot create a file in " +
                             Path("missing"),
                         0),
              0u)
        << error.what();
  }
}

TEST_F(OutputFileTest, CommitAllWritesEveryOutputOrNone) {
  OutputSet outputs;
  OutputFile& result = outputs.Add(Path("out.json"), "-o");
  OutputFile& picture = outputs.Add(Path("out.svg"), "--svg");
  result.Write("{}\n");
  picture.Write("<svg/>\n");
  EXPECT_EQ(Names().size(), 2u);  // two temporary files, no target yet
  outputs.CommitAll();
  EXPECT_EQ(Names(), (std::vector<std::string>{"out.json", "out.svg"}));
}

}  // namespace
}  // namespace linkfit
