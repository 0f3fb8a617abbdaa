// The work directory of a tiled run (issue 40): slipfit's own by its marker, one run at a time by
// its lock, never holding the input, and cleaned of the tiling's own files only.
#include "tiling/work_directory.h"

#include "slipfit/pipeline/errors.h"

#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <set>

namespace slipfit::testing {
namespace {

namespace fs = std::filesystem;
using pipeline::RunError;
using pipeline::tiling::checkWorkDirectory;
using pipeline::tiling::isTileName;
using pipeline::tiling::readRunToken;
using pipeline::tiling::WorkDirectory;
using ::testing::HasSubstr;

void put(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// The message of the RunError that \a f throws ("" when it throws none).
template <typename F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}

/// Every file under \a dir, as paths relative to it.
std::set<std::string> filesUnder(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (!e.is_directory())
      names.insert(fs::relative(e.path(), dir).string());
  return names;
}

TEST(WorkDirectory, ANewOrEmptyDirectoryIsClaimedWithItsMarkerLockAndToken) {
  for (const bool exists : {false, true}) {
    const std::string dir = scratchDir(exists ? "wd_empty" : "wd_new") + "/work";
    if (exists)
      fs::create_directories(dir);
    const WorkDirectory claimed(dir, "");
    EXPECT_EQ(filesUnder(dir),
              (std::set<std::string>{".slipfit-lock", ".slipfit-run", ".slipfit-workdir"}));
    EXPECT_EQ(readRunToken(dir), claimed.token());
    EXPECT_FALSE(claimed.token().empty());
  }
}

// The case of the issue: a workdir of the user's holding tiles/, runs/ and a manifest.yaml of
// their own was emptied; now it is refused, by `validate` (checkWorkDirectory) and `run` alike,
// and nothing in it changes.
TEST(WorkDirectory, ADirectoryThatIsNotEmptyAndNotSlipfitsIsRefusedAndLeftAlone) {
  const std::string dir = scratchDir("wd_users");
  put(dir + "/tiles/tile_0_0.ply", "theirs\n");
  put(dir + "/runs/history.txt", "theirs\n");
  put(dir + "/manifest.yaml", "theirs: 1\n");
  const std::set<std::string> before = filesUnder(dir);
  for (const std::string& message :
       {refusal([&] { checkWorkDirectory(dir, ""); }), refusal([&] { WorkDirectory w(dir, ""); })})
    EXPECT_THAT(message, HasSubstr("tiling.workdir '" + dir +
                                   "': not a slipfit work directory (no .slipfit-workdir in it) "
                                   "and not empty; give an empty or new one"));
  EXPECT_EQ(filesUnder(dir), before);
  EXPECT_EQ(refusal([&] { WorkDirectory w(scratchDir("wd_file"), ""); }), "");
  put(dir + "/../wd_plain_file", "x");
  EXPECT_THAT(refusal([&] { checkWorkDirectory(dir + "/../wd_plain_file", ""); }),
              HasSubstr("is not a directory"));
}

// An input inside the work directory (an earlier run's tile given as input, directly or through
// a symbolic link to a folder of it) is refused before anything is removed.
TEST(WorkDirectory, AnInputInsideItIsRefusedThroughLinksToo) {
  const std::string dir = scratchDir("wd_input") + "/work";
  fs::create_directories(dir);
  { const WorkDirectory claimed(dir, ""); }
  put(dir + "/tiles/tile_0_0.ply", "an earlier tile\n");
  const std::string link = scratchDir("wd_input_link");
  fs::create_directory_symlink(dir + "/tiles", link);
  for (const std::string& input : {dir + "/tiles/tile_0_0.ply", link + "/tile_0_0.ply"}) {
    EXPECT_THAT(refusal([&] { checkWorkDirectory(dir, input); }),
                HasSubstr("holds the input '" + input + "'"));
    EXPECT_THAT(refusal([&] { WorkDirectory w(dir, input); }), HasSubstr("holds the input"));
  }
  EXPECT_EQ(slurp(dir + "/tiles/tile_0_0.ply"), "an earlier tile\n");
  // Beside it, not inside: accepted.
  put(dir + "/../beside.ply", "x");
  EXPECT_EQ(refusal([&] { checkWorkDirectory(dir, dir + "/../beside.ply"); }), "");
}

// Two runs on one work directory: the second is refused while the first holds the lock, and
// takes it once the first has ended (a killed run's lock ends with its process).
TEST(WorkDirectory, ASecondRunIsRefusedWhileTheFirstHoldsTheLock) {
  const std::string dir = scratchDir("wd_lock");
  std::optional<WorkDirectory> first(std::in_place, dir, "");
  put(dir + "/manifest.yaml", "the first run's\n");
  const std::string message = refusal([&] { WorkDirectory second(dir, ""); });
  EXPECT_THAT(message, HasSubstr("tiling.workdir '" + dir + "': in use by another slipfit run"));
  EXPECT_THAT(message, HasSubstr("process " + std::to_string(::getpid())));
  const std::string token = first->token();
  EXPECT_EQ(readRunToken(dir), token);  // the refused run changed nothing
  first.reset();
  const WorkDirectory second(dir, "");
  EXPECT_NE(second.token(), token);
  EXPECT_EQ(slurp(dir + "/manifest.yaml"), "the first run's\n");
}

// The clean-up removes the tiling's own files by their names and nothing else: a file of the
// user's put into the work directory, and the target of a symbolic link, survive it.
TEST(WorkDirectory, OnlyTheTilingsOwnFilesAreRemoved) {
  const std::string dir = scratchDir("wd_clean");
  const WorkDirectory claimed(dir, "");
  for (const std::string& name :
       {"manifest.yaml", "analysis", "tiles/tile_0_0.ply", "tiles/tile_-3_12.ply", "runs/config",
        "runs/analysis", "runs/tile_0_0/segments.ply", "runs/tile_0_0/done",
        "runs/tile_-3_12/primitives.yaml"})
    put(dir + "/" + name, "slipfit's\n");
  for (const std::string& name : {"tiles/notes.txt", "tiles/tile_0.ply", "runs/history.txt",
                                  "runs/tile_0_0x/keep.txt", "mine.txt"})
    put(dir + "/" + name, "the user's\n");
  const std::string outside = scratchFile("wd_clean_target.ply", "the user's\n");
  fs::create_symlink(outside, dir + "/tiles/tile_1_1.ply");
  claimed.removeTiling();
  EXPECT_EQ(filesUnder(dir),
            (std::set<std::string>{".slipfit-lock", ".slipfit-run", ".slipfit-workdir", "mine.txt",
                                   "runs/history.txt", "runs/tile_0_0x/keep.txt", "tiles/notes.txt",
                                   "tiles/tile_0.ply"}));
  EXPECT_EQ(slurp(outside), "the user's\n");
}

// A run that fails before its first tile leaves no work directory it created.
TEST(WorkDirectory, AClaimThatEndsWithoutTilesLeavesNothing) {
  const std::string dir = scratchDir("wd_failed") + "/work";
  { const WorkDirectory claimed(dir, ""); }
  EXPECT_FALSE(fs::exists(dir));
  // One that existed before stays, with its marker.
  fs::create_directories(dir);
  { const WorkDirectory claimed(dir, ""); }
  EXPECT_TRUE(fs::is_regular_file(dir + "/.slipfit-workdir"));
}

// tile_<i>_<j>, or tile_<i>_<j>_<level> for a quarter of a split tile (tiling.max_points).
TEST(WorkDirectory, TileNamesAreTwoIntegersAndALevel) {
  EXPECT_TRUE(isTileName("tile_0_0.ply", ".ply"));
  EXPECT_TRUE(isTileName("tile_-12_7", ""));
  EXPECT_TRUE(isTileName("tile_-12_7_3", ""));
  EXPECT_TRUE(isTileName("tile_5_-3_2.ply", ".ply"));
  for (const char* name :
       {"tile_0.ply", "tile_0_0_-1.ply", "tile_0_0_1_1.ply", "tile__0.ply", "tile_a_0.ply",
        "tile_0_0.ply.bak", "tiles_0_0.ply", "tile_0_-.ply", "tile_0_0"})
    EXPECT_FALSE(isTileName(name, ".ply")) << name;
}

}  // namespace
}  // namespace slipfit::testing
