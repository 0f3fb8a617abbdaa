// OutputFiles: temporary files created exclusively, never followed through a planted symlink,
// and a commit that is all or nothing (issue 15).
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/errors.h"

#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

namespace slipfit::testing {
namespace {

using pipeline::OutputFiles;
using pipeline::RunError;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::set<std::string> entries(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    names.insert(e.path().filename().string());
  return names;
}

TEST(OutputFiles, TemporaryNamesAreFreshHiddenAndKeepTheExtension) {
  const std::string dir = scratchDir("out_names");
  OutputFiles out(dir);
  std::string first, second;
  out.add("a.ply", [&](const std::string& p) { first = p; });
  out.add("b.ply", [&](const std::string& p) { second = p; });
  EXPECT_NE(first, second);
  for (const std::string& p : {first, second}) {
    const std::string name = fs::path(p).filename().string();
    EXPECT_EQ(name.front(), '.') << name;
    EXPECT_EQ(fs::path(p).extension(), ".ply") << name;
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(p))) << "created before the writer runs";
  }
  const auto written = out.commit();
  EXPECT_EQ(written.size(), 2u);
  EXPECT_EQ(entries(dir), (std::set<std::string>{"a.ply", "b.ply"}));
}

TEST(OutputFiles, FilesGetTheModeOfTheUmaskNotMkstempsPrivateMode) {
  const std::string dir = scratchDir("out_mode");
  const mode_t mask = ::umask(022);
  {
    OutputFiles out(dir);
    out.addText("r.yaml", "x: 1\n");
    out.commit();
  }
  ::umask(mask);
  struct stat st = {};
  ASSERT_EQ(::stat((dir + "/r.yaml").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);
}

TEST(OutputFiles, ATemporaryFileSwappedForASymlinkIsRefusedAndItsTargetUntouched) {
  const std::string dir = scratchDir("out_symlink");
  fs::create_directories(dir);
  const std::string victim = scratchFile("victim.txt", "the user's data\n");
  {
    OutputFiles out(dir);
    try {
      out.add("r.ply", [&](const std::string& p) {
        // Another user replaces the file after its creation (in a directory without the
        // sticky bit): the commit must not rename the planted link into place.
        fs::remove(p);
        fs::create_symlink(victim, p);
      });
      FAIL() << "a swapped temporary file was accepted";
    } catch (const RunError& e) {
      EXPECT_THAT(e.what(), HasSubstr("was replaced by another file while it was written"));
    }
  }
  EXPECT_EQ(contents(victim), "the user's data\n");
  EXPECT_FALSE(fs::exists(fs::symlink_status(dir + "/r.ply")));
}

TEST(OutputFiles, TwoOutputsOfOneNameAreRefused) {
  const std::string dir = scratchDir("out_twice");
  OutputFiles out(dir);
  out.addText("primitives.yaml", "a\n");
  EXPECT_THROW(out.addText("primitives.yaml", "b\n"), RunError);
}

/// rename(2) that fails on its n-th call, as a full or failing file system would.
class FailingRename : public OutputFiles {
 public:
  FailingRename(std::string dir, int fail_at) : OutputFiles(std::move(dir)), fail_at_(fail_at) {}

 protected:
  int renameFile(const char* from, const char* to) override {
    if (++calls_ == fail_at_) {
      errno = EIO;
      return -1;
    }
    return OutputFiles::renameFile(from, to);
  }

 private:
  int fail_at_, calls_ = 0;
};

TEST(OutputFiles, AFailedRenamePutsEveryEarlierOutputBack) {
  for (int fail_at = 1; fail_at <= 3; ++fail_at) {
    const std::string dir = scratchDir("out_rollback");
    fs::create_directories(dir);
    write(dir + "/a.yaml", "old a\n");  // a previous run's output
    write(dir + "/notes.txt", "the user's\n");
    {
      FailingRename out(dir, fail_at);
      out.addText("a.yaml", "new a\n");
      out.addText("b.yaml", "new b\n");  // no previous file
      out.addText("c.yaml", "new c\n");
      try {
        out.commit();
        FAIL() << "the failing rename was not reported";
      } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("cannot rename into place"));
        EXPECT_THAT(e.what(), HasSubstr("nothing is committed"));
      }
    }
    EXPECT_EQ(entries(dir), (std::set<std::string>{"a.yaml", "notes.txt"}))
        << "rename " << fail_at << " failed";
    EXPECT_EQ(contents(dir + "/a.yaml"), "old a\n") << "rename " << fail_at << " failed";
  }
}

TEST(OutputFiles, ACommitReplacesPreviousOutputsAndLeavesNoBackup) {
  const std::string dir = scratchDir("out_replace");
  fs::create_directories(dir);
  write(dir + "/a.yaml", "old a\n");
  OutputFiles out(dir);
  out.addText("a.yaml", "new a\n");
  out.commit();
  EXPECT_EQ(contents(dir + "/a.yaml"), "new a\n");
  EXPECT_EQ(entries(dir), (std::set<std::string>{"a.yaml"}));
}

TEST(OutputFiles, AFinalNameThatIsADirectoryStopsTheCommitBeforeAnyRename) {
  const std::string dir = scratchDir("out_dir_in_way");
  fs::create_directories(dir + "/b.yaml");
  OutputFiles out(dir);
  out.addText("a.yaml", "a\n");
  out.addText("b.yaml", "b\n");
  EXPECT_THROW(out.commit(), RunError);
  EXPECT_FALSE(fs::exists(dir + "/a.yaml"));
}

/// A process id that is no process's: a child that has exited and been reaped.
pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0)
    ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

/// The temporary name OutputFiles gives \a name in \a dir, with its pid part replaced by \a pid
/// (what a run of that process would have left).
std::string temporaryOf(const std::string& dir, const std::string& name, long pid) {
  std::string tmp;
  {
    OutputFiles out(dir);
    out.add(name, [&](const std::string& p) { tmp = fs::path(p).filename().string(); });
  }  // not committed: removed
  // .<stem>.tmp.<host>-<pid>.<6 characters><extension>: the digits after the host's dash.
  const std::size_t dash = tmp.find('-', tmp.rfind(".tmp.")), dot = tmp.find('.', dash);
  return tmp.substr(0, dash + 1) + std::to_string(pid) + tmp.substr(dot);
}

// Issue 40: a run killed by SIGKILL (no handler runs) leaves its temporary files; the next run in
// the directory removes those of dead processes of this host and says so, and nothing else.
TEST(OutputFiles, LeftoversOfAKilledRunAreRemovedAndNothingElse) {
  const std::string dir = scratchDir("out_leftovers");
  fs::create_directories(dir);
  const pid_t dead = deadPid();
  const std::string left = temporaryOf(dir, "segments.ply", dead);
  const std::string alive = temporaryOf(dir, "cloud.ply", 1);  // init: always alive
  std::string other_host = temporaryOf(dir, "report.yaml", dead);
  other_host.replace(other_host.find(".tmp.") + 5, 8, "00000000");
  const std::string kept_aside = temporaryOf(dir, "primitives.yaml", dead) + ".previous";
  const std::string users = ".segments.tmp.notes.ply";  // not the pattern
  for (const std::string& name : {left, alive, other_host, kept_aside, users})
    write(dir + "/" + name, name + "\n");
  // The input, even when its name has the pattern, is never touched.
  const std::string input = temporaryOf(dir, "input.ply", dead);
  write(dir + "/" + input, "points\n");

  const std::vector<std::string> done = pipeline::removeLeftovers(dir, dir + "/" + input);
  EXPECT_THAT(
      done, ::testing::UnorderedElementsAre(
                "removed " + left, "put back primitives.yaml (kept aside as " + kept_aside + ")"));
  EXPECT_EQ(entries(dir),
            (std::set<std::string>{alive, other_host, users, input, "primitives.yaml"}));
  EXPECT_EQ(contents(dir + "/primitives.yaml"), kept_aside + "\n");
  // A kept-aside file whose name is taken again (the commit had renamed the new file in): removed.
  write(dir + "/" + kept_aside, "old\n");
  EXPECT_THAT(pipeline::removeLeftovers(dir, dir + "/" + input),
              ::testing::ElementsAre("removed " + kept_aside));
  EXPECT_EQ(contents(dir + "/primitives.yaml"), kept_aside + "\n");
}

}  // namespace
}  // namespace slipfit::testing
