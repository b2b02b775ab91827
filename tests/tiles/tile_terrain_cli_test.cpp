// The large-area route to a web-terrain pyramid, as docs/web_terrain.md gives it: tile jobs
// (given the CRS the inputs lack, as the single job is), merge, then one --terrain job on the
// merged TIN with the lines given again. Its pyramid is the single job's, byte for byte: the
// merged TIN is the single job's, and the pyramid is a function of the TIN.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "tile_runs.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

// Every file under DIR by its path relative to DIR, with its bytes.
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = test::slurp(e.path());
  return out;
}

TEST(TileTerrainCli, ThePyramidOfTheMergedTilesIsTheSingleJobsByteForByte) {
  const fs::path dir = test::scratch_dir("tile_terrain_cli");
  const double x0 = 500000, y0 = 4000000;
  write_xyz(dir / "points.xyz", random_points(3000, x0, y0, 300, 77));
  write_rings(dir / "rings.geojson", x0 + 150, y0 + 150, {30, 60, 95, 130});
  const std::string lines = " --contours rings.geojson --a-srs EPSG:32632";
  test::expect_success(dir, "points.xyz" + lines + " --terrain whole_web -o whole.ply -q");
  test::expect_success(
      dir,
      "plan points.xyz --contours rings.geojson --tile-size 150 --buffer 30 -o plan.json "
      "-q");
  const std::size_t n = tiles::read_plan((dir / "plan.json").string()).tiles.size();
  ASSERT_GE(n, 4u);
  std::string merge = "merge";
  for (std::size_t i = 0; i < n; ++i) {
    const std::string tile = "tile_" + std::to_string(i) + ".ply";
    test::expect_success(dir, "--plan plan.json --tile " + std::to_string(i) + " -o " + tile +
                                  " --a-srs EPSG:32632 -q");
    merge += " " + tile;
  }
  test::expect_success(dir, merge + " -o merged.ply -q");
  expect_same_tin((dir / "whole.ply").string(), (dir / "merged.ply").string());
  test::expect_success(dir, "merged.ply" + lines + " --terrain tiled_web -q");

  const auto whole = files_under(dir / "whole_web");
  const auto tiled = files_under(dir / "tiled_web");
  ASSERT_GT(whole.size(), 2u);  // layer.json and tiles
  ASSERT_EQ(whole.size(), tiled.size());
  for (const auto& [path, bytes] : whole) {
    const auto it = tiled.find(path);
    ASSERT_NE(it, tiled.end()) << path << " is missing from the tiled route's pyramid";
    EXPECT_TRUE(it->second == bytes) << path << " differs";
  }
}

}  // namespace
