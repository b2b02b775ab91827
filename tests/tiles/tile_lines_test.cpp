// Crossing contours and hard lines in tiled jobs: every crossing vertex is made from the two whole
// segments, so every tile that holds both makes the same one, and the merged tiles are the whole
// job's TIN (triangle sets, exact coordinates).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/build.hpp"
#include "tile_runs.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

std::uint64_t crossings_of_whole_job(const Inputs& in, const fs::path& dir) {
  pipeline::BuildOptions o;
  o.inputs = in.points;
  o.contours = in.contours;
  o.output = (dir / "crossings.ply").string();
  o.write.overwrite = true;
  return pipeline::build(o).crossings;
}

// Dense lines across each other and across long straight segments: each long segment is split
// at crossings along its whole length, some far outside a tile, and each crossing vertex must not
// depend on them.
TEST(TileLines, CrossingLinesMatchTheWholeTin) {
  const fs::path dir = scratch();
  const double x0 = 500000, y0 = 4000000;
  const Inputs in{
      {write_xyz(dir / "points.xyz", random_points(3000, x0, y0, 300, 21))},
      {write_crossing_lines(dir / "lines.geojson", x0, y0, 300, 12, 31, 22),
       write_straight_lines(dir / "straight.geojson", {{x0 + 10, y0 + 12, x0 + 291, y0 + 287},
                                                       {x0 + 7, y0 + 280, x0 + 289, y0 + 9},
                                                       {x0 + 60, y0 + 5, x0 + 250, y0 + 294}})}};
  ASSERT_GT(crossings_of_whole_job(in, dir), 60u);
  const std::string w = whole(in, dir);
  for (const double size : {150.0, 120.0}) {
    SCOPED_TRACE(size);
    expect_same_tin(w, tiled(in, dir, size, 30));
  }
}

// Crossing lines over contour rings, the lines reaching beyond the points (their crossings near
// the data's hull, where the tiles read the rim), and a buffer that has to grow.
TEST(TileLines, CrossingLinesOverRingsAndBeyondThePointsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(1200, 500020, 4000020, 260, 23))},
                  {write_rings(dir / "rings.geojson", 500150, 4000150, {30, 60, 90, 120}),
                   write_crossing_lines(dir / "lines.geojson", 500000, 4000000, 300, 8, 31, 24)}};
  ASSERT_GT(crossings_of_whole_job(in, dir), 50u);
  const std::string w = whole(in, dir);
  expect_same_tin(w, tiled(in, dir, 150, 10));
}

}  // namespace
