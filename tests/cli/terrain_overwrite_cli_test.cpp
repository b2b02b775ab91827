// --terrain into a folder that exists: with --overwrite, the earlier pyramid's tiles that the new
// one does not write (other levels, other areas) are removed, so that the folder is the fresh
// run's pyramid; a folder holding anything else, or holding an input or another output of the
// run, is refused before any work and left as it was; an empty folder is accepted.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;

// A 100 m square of points 5 m apart (EPSG:32632) whose south-west corner is WEST, SOUTH.
std::string square(double west, double south) {
  std::string text;
  char line[96];
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      std::snprintf(line, sizeof line, "%.1f %.1f %.2f\n", west + 5 * i, south + 5 * j,
                    200 + 0.3 * i + 0.2 * j + ((7 * i + 3 * j) % 5) * 0.4);
      text += line;
    }
  return text;
}

// Two squares 100 km apart: at the levels below the first few, their tiles differ.
const std::string kHere = square(600000, 5190000);
const std::string kThere = square(700000, 5190000);
const std::string kSrs = " --a-srs EPSG:32632";

// Every entry under DIR by its path relative to DIR: a file's bytes, "/" for a folder.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    out[fs::relative(e.path(), dir).string()] = e.is_directory() ? "/" : slurp(e.path());
  return out;
}

// The folder of a fresh run of ARGS into "web" in a folder of its own under DIR.
std::map<std::string, std::string> fresh_pyramid(const std::string& dir, const std::string& input,
                                                 const std::string& args) {
  const std::string fresh = fresh_dir(dir + "/fresh").string();
  spit(fresh + "/p.xyz", input);
  const ShellRun r = run_tincdt(fresh, "p.xyz" + kSrs + " --terrain web " + args);
  EXPECT_EQ(r.exit_code, 0) << r.messages;
  return tree(fresh + "/web");
}

TEST(TerrainOverwriteCli, FewerLevelsLeaveOnlyTheNewPyramid) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  spit(dir + "/p.xyz", kHere);
  ShellRun r = run_tincdt(dir, "p.xyz" + kSrs + " --terrain web --terrain-levels 0-12");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  ASSERT_TRUE(fs::is_directory(dir + "/web/12"));
  r = run_tincdt(dir, "p.xyz" + kSrs + " --overwrite --terrain web --terrain-levels 0-8");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_TRUE(has(r, "removed ")) << r.messages;
  EXPECT_TRUE(has(r, " tiles of the earlier pyramid")) << r.messages;
  for (const char* level : {"9", "10", "11", "12"})
    EXPECT_FALSE(fs::exists(dir + "/web/" + level)) << level;
  const auto expected = fresh_pyramid(dir, kHere, "--terrain-levels 0-8");
  EXPECT_EQ(tree(dir + "/web"), expected);
}

TEST(TerrainOverwriteCli, AnotherAreaLeavesOnlyTheNewPyramid) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  spit(dir + "/here.xyz", kHere);
  spit(dir + "/there.xyz", kThere);
  ShellRun r = run_tincdt(dir, "here.xyz" + kSrs + " --terrain web --terrain-levels 0-10");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const auto earlier = tree(dir + "/web");
  r = run_tincdt(dir, "there.xyz" + kSrs + " --overwrite --terrain web --terrain-levels 0-10");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const auto expected = fresh_pyramid(dir, kThere, "--terrain-levels 0-10");
  EXPECT_NE(earlier, expected);  // the areas' tiles differ, so some had to go
  EXPECT_EQ(tree(dir + "/web"), expected);
}

// An earlier pyramid in DIR/web, and the messages of its run, which show the stages.
ShellRun earlier_pyramid(const std::string& dir) {
  spit(dir + "/p.xyz", kHere);
  const ShellRun r = run_tincdt(dir, "p.xyz" + kSrs + " --terrain web --terrain-levels 0-6");
  EXPECT_EQ(r.exit_code, 0) << r.messages;
  return r;
}

TEST(TerrainOverwriteCli, StrangerInTheFolderRefusedBeforeAnyWork) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  ASSERT_TRUE(has(earlier_pyramid(dir), "[2/"));  // the stages show in the log
  const std::pair<std::string, std::string> strangers[] = {
      {"notes.txt", "'notes.txt'"},
      {"0/0/0.terrain.bak", "'0/0/0.terrain.bak'"},
      {"3/readme", "'3/readme'"},
  };
  for (const auto& [stranger, named] : strangers) {
    SCOPED_TRACE(stranger);
    spit(dir + "/web/" + stranger, "the user's");
    const auto before = tree(dir + "/web");
    for (const std::string overwrite : {" --overwrite", ""}) {
      const ShellRun r =
          run_tincdt(dir, "p.xyz" + kSrs + overwrite + " --terrain web --terrain-levels 0-3");
      EXPECT_EQ(r.exit_code, 1) << r.messages;
      EXPECT_TRUE(has(r, "error: web: holds " + named + ", which is not part of a web terrain"))
          << r.messages;
      EXPECT_FALSE(has(r, "[1/")) << r.messages;
      EXPECT_EQ(tree(dir + "/web"), before);
    }
    fs::remove(dir + "/web/" + stranger);
  }
}

TEST(TerrainOverwriteCli, LinkNamedLikeATileRefusedAndKept) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  earlier_pyramid(dir);
  fs::create_symlink("0.terrain", dir + "/web/0/0/7.terrain");
  const ShellRun r = run_tincdt(dir, "p.xyz" + kSrs + " --overwrite --terrain web");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_TRUE(has(r, "error: web: holds '0/0/7.terrain', which is not part")) << r.messages;
  EXPECT_TRUE(fs::is_symlink(dir + "/web/0/0/7.terrain"));
}

TEST(TerrainOverwriteCli, EarlierTilesWithoutOverwriteRefusedBeforeAnyWork) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  earlier_pyramid(dir);
  ShellRun r = run_tincdt(dir, "p.xyz" + kSrs + " --terrain web --terrain-levels 0-3");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_TRUE(has(r, "web/layer.json: already exists (use --overwrite")) << r.messages;
  EXPECT_FALSE(has(r, "[1/")) << r.messages;
  // Tiles without their layer.json: still an earlier pyramid's.
  fs::remove(dir + "/web/layer.json");
  r = run_tincdt(dir, "p.xyz" + kSrs + " --terrain web --terrain-levels 0-3");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_TRUE(has(r, "web/0/0/0.terrain: already exists (use --overwrite")) << r.messages;
  EXPECT_FALSE(has(r, "[1/")) << r.messages;
}

TEST(TerrainOverwriteCli, InputOrOutputInsideTheFolderRefused) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  fs::create_directory(dir + "/web");
  spit(dir + "/web/pts.xyz", kHere);
  spit(dir + "/p.xyz", kHere);
  const std::pair<std::string, std::string> cases[] = {
      {"web/pts.xyz" + kSrs + " --terrain web",
       "web/pts.xyz: a point file lies inside the web terrain (--terrain) 'web'"},
      {"web/pts.xyz" + kSrs + " --terrain web --overwrite",
       "web/pts.xyz: a point file lies inside the web terrain (--terrain) 'web'"},
      {"p.xyz" + kSrs + " --terrain web -o web/tin.ply",
       "web/tin.ply: the TIN (-o) lies inside the web terrain (--terrain) 'web'"},
      {"p.xyz" + kSrs + " --terrain ./web/ --stats web/../web/stats.json",
       "web/../web/stats.json: the stats file (--stats) lies inside the web terrain (--terrain) "
       "'./web/'"},
  };
  for (const auto& [args, message] : cases) {
    SCOPED_TRACE(args);
    const ShellRun r = run_tincdt(dir, args);
    EXPECT_EQ(r.exit_code, 2) << r.messages;
    EXPECT_TRUE(has(r, message)) << r.messages;
    EXPECT_EQ(tree(dir + "/web"), (std::map<std::string, std::string>{{"pts.xyz", kHere}}));
  }
}

TEST(TerrainOverwriteCli, EmptyFolderAccepted) {
  const std::string dir = scratch_dir("terrain_overwrite_cli");
  fs::create_directory(dir + "/web");
  spit(dir + "/p.xyz", kHere);
  const ShellRun r = run_tincdt(dir, "p.xyz" + kSrs + " --terrain web --terrain-levels 0-5");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_FALSE(has(r, "earlier pyramid")) << r.messages;
  EXPECT_EQ(tree(dir + "/web"), fresh_pyramid(dir, kHere, "--terrain-levels 0-5"));
}

}  // namespace
}  // namespace tincdt::test
