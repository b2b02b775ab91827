// Crossing contours and hard lines through the command line of tiled jobs, as a user runs them:
// plan, every tile, merge, against the whole job (triangle sets, exact coordinates); and the
// options a tile job still refuses, each a usage error that names it and says why.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "tile_runs.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

TEST(TileLinesCli, CrossingContoursAndHardLinesPlanTileMergeAsTheWholeJob) {
  const fs::path dir = test::scratch_dir("tile_lines_cli");
  const double x0 = 500000, y0 = 4000000;
  write_xyz(dir / "points.xyz", random_points(3000, x0, y0, 300, 41));
  write_crossing_lines(dir / "lines.geojson", x0, y0, 300, 10, 31, 42);
  // Hard lines across the contours and each other, each one long segment.
  write_straight_lines(dir / "roads.geojson", {{x0 + 12, y0 + 8, x0 + 290, y0 + 281},
                                               {x0 + 5, y0 + 270, x0 + 294, y0 + 30}});
  const std::string lines = " --contours lines.geojson --breaklines roads.geojson";
  test::expect_success(dir, "points.xyz" + lines + " -o whole.ply -q");
  test::expect_success(dir,
                       "plan points.xyz" + lines + " --tile-size 150 --buffer 30 -o plan.json -q");
  const std::size_t n = tiles::read_plan((dir / "plan.json").string()).tiles.size();
  ASSERT_GE(n, 4u);
  std::string merge = "merge";
  for (std::size_t i = 0; i < n; ++i) {
    const std::string tile = "tile_" + std::to_string(i);
    test::expect_success(dir, "--plan plan.json --tile " + std::to_string(i) + " -o " + tile +
                                  ".ply --stats " + tile + ".json -q");
    merge += " " + tile + ".ply";
    // The buffer the tile read, in its stats: the plan's, or more where it had to grow.
    const std::string stats = test::slurp(dir / (tile + ".json"));
    EXPECT_NE(stats.find("\"figures\": {\n    \"buffer\": "), std::string::npos) << stats;
  }
  test::expect_success(dir, merge + " -o merged.ply -q");
  expect_same_tin((dir / "whole.ply").string(), (dir / "merged.ply").string());
}

TEST(TileLinesCli, OptionsATileCannotProveAreRefusedEachByName) {
  const fs::path dir = test::scratch_dir("tile_lines_cli_refusals");
  const std::pair<std::string, std::string> cases[] = {
      {"--fix-flats", "--fix-flats cannot be used with --plan: a flat area"},
      {"--restore aspect", "--restore aspect cannot be used with --plan: the triangles it leaves"},
      {"--restore none", "(build without --plan for it)"},
  };
  test::expect_usage_errors(dir.string(), "--plan plan.json --tile 0 -o t.ply", cases);
}

}  // namespace
