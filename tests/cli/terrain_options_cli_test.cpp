// The --terrain settings without --terrain: refused whenever given, even at their default value,
// and accepted with it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <utility>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las' --keep-class '2";

TEST(TerrainOptionsCli, SettingsWithoutTerrainRefusedAtAnyValue) {
  const std::string dir = scratch_dir("terrain_options_cli");
  const std::pair<std::string, std::string> cases[] = {
      // The defaults themselves: given is given.
      {"-o x.ply --terrain-max-tiles 2000000", "need --terrain"},
      {"-o x.ply --terrain-fill-height 0", "need --terrain"},
      {"-o x.ply --terrain-levels 0-0", "need --terrain"},
      {"-o x.ply --terrain-max-tiles 5", "need --terrain"},
      {"--dem d.tif --resolution 10 --terrain-max-tiles 2000000", "need --terrain"},
  };
  expect_usage_errors(dir, "'" + kSample + "'", cases);
}

TEST(TerrainOptionsCli, DefaultMaxTilesGivenWithTerrainAccepted) {
  const std::string dir = scratch_dir("terrain_options_cli");
  const ShellRun r = run_tincdt(dir, "'" + kSample +
                                         "' --terrain t --terrain-levels 0-3 "
                                         "--terrain-max-tiles 2000000");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_TRUE(has(r, "(at most 2,000,000)")) << r.messages;
  // The count, checked right after read with the levels given, is logged once, from the TIN.
  const std::string line = "tiles over the data's";
  const std::size_t first = r.messages.find(line);
  ASSERT_NE(first, std::string::npos) << r.messages;
  EXPECT_EQ(r.messages.find(line, first + 1), std::string::npos) << r.messages;
  EXPECT_TRUE(std::filesystem::exists(dir + "/t/layer.json"));
}

TEST(TerrainOptionsCli, MaxTilesDefaultInHelp) {
  const std::string dir = scratch_dir("terrain_options_cli");
  const std::string out = dir + "/help.txt";
  ASSERT_EQ(std::system(("'" TINCDT_EXE "' --help > '" + out + "'").c_str()), 0);
  const std::string help = slurp(out);
  const std::size_t at = help.find("--terrain-max-tiles");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NE(help.find("2000000", at), std::string::npos) << help.substr(at, 300);
}

}  // namespace
}  // namespace tincdt::test
