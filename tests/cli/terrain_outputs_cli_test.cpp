// --terrain DIR as one output: the pyramid is written in a temporary folder beside DIR and moved
// into place with the other outputs, so that a run that fails or is interrupted after hundreds
// of tiles (a second Ctrl-C included, which ends the process at once) leaves no temporary and
// DIR as it was; with --overwrite a pyramid replaces the old one as a whole; a folder that holds
// something else than a pyramid is never replaced.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las' --keep-class '2";

// Every file under DIR by its path relative to DIR, with its bytes.
std::map<std::string, std::string> files_under(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

ShellRun terrain(const std::string& dir, const std::string& options) {
  return run_tincdt(dir, "'" + kSample + "' --terrain t " + options);
}

// SIGINT raised as the stage AT ("STAGE:INT[:COUNT]") starts, as a user's Ctrl-C would arrive.
ShellRun interrupted(const std::string& dir, const std::string& at, const std::string& options) {
  ::setenv("TINCDT_TEST_SIGNAL", at.c_str(), 1);
  const ShellRun r = terrain(dir, options);
  ::unsetenv("TINCDT_TEST_SIGNAL");
  return r;
}

bool died_of_sigint(const ShellRun& r) {
  return r.exit_code == 128 + 2 || r.exit_code == -1;
}

// Levels 0-19 over the sample: a few hundred tiles, more than the 64 temporaries the signal
// handler tracks one by one.
constexpr const char* kManyTiles = "--terrain-levels 0-19";
constexpr const char* kAfterTheTiles = "--contour-lines l.geojson --interval 5";

TEST(TerrainOutputsCli, InterruptedRunLeavesTheOldPyramidAndNoTemporary) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  ASSERT_EQ(terrain(dir, kManyTiles).exit_code, 0);
  const auto before = files_under(dir + "/t");
  ASSERT_GT(before.size(), 64u);
  for (const char* at : {"contour_lines:INT:2", "contour_lines:INT", "commit:INT:2"}) {
    SCOPED_TRACE(at);
    const ShellRun r =
        interrupted(dir, at, "--terrain-levels 0-18 --overwrite " + std::string(kAfterTheTiles));
    EXPECT_TRUE(died_of_sigint(r)) << r;
    EXPECT_EQ(names_in(dir), std::set<std::string>{"t"});
    EXPECT_TRUE(files_under(dir + "/t") == before) << "the old pyramid changed";
  }
}

TEST(TerrainOutputsCli, InterruptedRunMakesNoFolder) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  for (const char* at : {"contour_lines:INT:2", "contour_lines:INT"}) {
    SCOPED_TRACE(at);
    const ShellRun r = interrupted(dir, at, std::string(kManyTiles) + " " + kAfterTheTiles);
    EXPECT_TRUE(died_of_sigint(r)) << r;
    EXPECT_EQ(names_in(dir), std::set<std::string>{});
  }
}

// The contour lines, after the pyramid, are refused (too many for the interval).
TEST(TerrainOutputsCli, FailedRunLeavesTheOldPyramid) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  ASSERT_EQ(terrain(dir, "--terrain-levels 0-3").exit_code, 0);
  const auto before = files_under(dir + "/t");
  const ShellRun r =
      terrain(dir, "--terrain-levels 0-12 --overwrite --contour-lines l.geojson --interval 0.0001");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"t"});
  EXPECT_TRUE(files_under(dir + "/t") == before) << "the old pyramid changed";
}

// Same bytes as a first run into a new folder: nothing of the old pyramid is left.
TEST(TerrainOutputsCli, OverwriteReplacesThePyramidAsAWhole) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  ASSERT_EQ(terrain(dir, "--terrain-levels 0-5").exit_code, 0);
  const ShellRun r = terrain(dir, "--terrain-levels 0-2 --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"t"});
  EXPECT_EQ(names_in(dir + "/t"), (std::set<std::string>{"0", "1", "2", "layer.json"}));
  fs::create_directory(dir + "/fresh");
  ASSERT_EQ(
      run_tincdt(dir + "/fresh", "'" + kSample + "' --terrain t --terrain-levels 0-2").exit_code,
      0);
  EXPECT_TRUE(files_under(dir + "/t") == files_under(dir + "/fresh/t"));
}

TEST(TerrainOutputsCli, AnEmptyFolderIsFilled) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  fs::create_directory(dir + "/t");
  const ShellRun r = terrain(dir, "--terrain-levels 0-2");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(names_in(dir + "/t"), (std::set<std::string>{"0", "1", "2", "layer.json"}));
}

// Even with --overwrite, before the TIN is made.
TEST(TerrainOutputsCli, AFolderOfOtherFilesIsNotReplaced) {
  const std::string dir = scratch_dir("terrain_outputs_cli");
  fs::create_directory(dir + "/t");
  spit(dir + "/t/notes.txt", "mine");
  const ShellRun r = terrain(dir, "--terrain-levels 0-2 --overwrite");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_NE(r.messages.find("t: is a folder without layer.json, which is not replaced: give a "
                            "new or empty folder"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.messages.find("triangulat"), std::string::npos) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"t"});
  EXPECT_EQ(files_under(dir + "/t"), (std::map<std::string, std::string>{{"notes.txt", "mine"}}));
}

}  // namespace
}  // namespace tincdt::test
