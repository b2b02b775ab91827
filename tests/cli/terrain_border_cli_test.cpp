// --terrain on data whose edge lies just inside a tile border (the equator, the prime meridian):
// the vertices of the edge fall on the border's row of the tile's grid, where the border would
// carry the fill height, not theirs. Every level keeps within its error all the same.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "terrain_support.hpp"

namespace tincdt::test {

using terrain::expect_levels_within;

namespace {

// A 2 km square of points 20 m apart, its first row or column 5 cm from the border along
// (ACROSS_X: x = X0 + 0.05 is the border's side), on a smooth surface well above its lowest
// point, the fill height.
std::string square_beside_border(bool across_x, double x0, double y0) {
  std::string text;
  char line[96];
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) {
      const double a = 20.0 * i, b = 0.05 + 20.0 * j;  // b across the border
      const double z = 50 + 20 * std::sin(a / 97) * std::cos(b / 61) + 0.01 * a;
      std::snprintf(line, sizeof line, "%.2f %.2f %.3f\n", across_x ? x0 + b : x0 + a,
                    across_x ? y0 + a : y0 + b, z);
      text += line;
    }
  return text;
}

TEST(TerrainBorderCli, DataNorthOfTheEquatorKeepsEveryLevelsError) {
  const std::string dir = scratch_dir("terrain_border");
  spit(std::filesystem::path(dir) / "p.xyz", square_beside_border(false, 0, 0));
  const ShellRun r = run_tincdt(dir, "p.xyz --a-srs EPSG:32632 --terrain t");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_GE(expect_levels_within(r.messages), 12) << r;
  EXPECT_FALSE(has(r, "above the level's error")) << r;
}

TEST(TerrainBorderCli, DataEastOfThePrimeMeridianKeepsEveryLevelsError) {
  const std::string dir = scratch_dir("terrain_border");
  spit(std::filesystem::path(dir) / "p.xyz", square_beside_border(true, 0, 4000000));
  const ShellRun r = run_tincdt(dir, "p.xyz --a-srs EPSG:3857 --terrain t");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_GE(expect_levels_within(r.messages), 12) << r;
  EXPECT_FALSE(has(r, "above the level's error")) << r;
}

}  // namespace
}  // namespace tincdt::test
