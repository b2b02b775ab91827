// The web-terrain stage's progress: each level's share in proportion to its work (its tiles,
// and the TIN's vertices measured once per level), so that the one-tile coarse levels of a
// small area move the fraction little and the many tiles of the finest levels most; and the
// fraction never goes back and ends at 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"

namespace tincdt {
namespace {

TEST(TerrainProgress, LevelsWeighedByTheirWork) {
  const std::string dir = test::scratch_dir("terrain_progress");
  pipeline::BuildOptions o;
  o.inputs = {std::string(TINCDT_SOURCE_DIR) + "/data/sample.las"};
  o.terrain.path = dir + "/t";
  o.terrain.max_level = 19;  // 20 levels, the first 15 a tile or two each over the sample
  std::vector<double> seen;
  const ProgressFn progress = [&](std::string_view stage, double fraction) {
    if (stage == "web_terrain") seen.push_back(fraction);
    return true;
  };
  pipeline::build(o, &progress);

  ASSERT_GT(seen.size(), 50u);
  double largest_step = 0;
  for (std::size_t i = 1; i < seen.size(); ++i) {
    ASSERT_GE(seen[i], seen[i - 1]) << "at " << i;
    largest_step = std::max(largest_step, seen[i] - seen[i - 1]);
  }
  EXPECT_NEAR(seen.back(), 1.0, 1e-9);
  // An equal share a level would move 1/20 at each one-tile level; by their work, a one-tile
  // level is the TIN's vertices measured once and one tile, of the 20 levels' measures and the
  // finest levels' hundreds of tiles.
  EXPECT_LT(largest_step, 0.8 / 20);
}

}  // namespace
}  // namespace tincdt
