// Crossing contours and hard lines in tiled jobs: every crossing vertex is made from the two whole
// segments, so every tile that holds both makes the same one, and the merged tiles are the whole
// job's TIN (triangle sets, exact coordinates).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "pipeline/build.hpp"
#include "support/vector_files.hpp"
#include "tile_runs.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

// N polylines across [x0, x0 + side)^2, alternately west to east and south to north, each of
// VERTICES vertices jittered off its own straight course, at the terrain's height plus a lift of
// its own: long segments that cross each other (at heights that disagree) and the tile borders.
std::string write_crossing_lines(const fs::path& path, double x0, double y0, double side, int n,
                                 int vertices, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> across(0.05 * side, 0.95 * side);
  std::uniform_real_distribution<double> jitter(-0.02 * side, 0.02 * side);
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "lines";
  for (int i = 0; i < n; ++i) {
    const double course = across(rng);
    std::string wkt = "LINESTRING Z (";
    for (int k = 0; k < vertices; ++k) {
      const double along = side * (0.03 + 0.94 * k / (vertices - 1)), off = course + jitter(rng);
      const double x = x0 + (i % 2 == 0 ? along : off), y = y0 + (i % 2 == 0 ? off : along);
      char v[96];
      std::snprintf(v, sizeof v, "%s%.17g %.17g %.17g", k ? ", " : "", x, y,
                    terrain_height(x, y) + i);
      wkt += v;
    }
    layers[0].features.push_back({wkt + ")", 0});
  }
  return test::write_vector(path, layers, "GeoJSON", "NAME");
}

// Straight lines of one segment each between the given ends, at the terrain's height 5 above:
// every other line crosses them, each crossing splitting the long segment anew.
std::string write_straight_lines(const fs::path& path,
                                 const std::vector<std::array<double, 4>>& ends) {
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "straight";
  for (const auto& [x0, y0, x1, y1] : ends) {
    char wkt[200];
    std::snprintf(wkt, sizeof wkt, "LINESTRING Z (%.17g %.17g %.17g, %.17g %.17g %.17g)", x0, y0,
                  terrain_height(x0, y0) + 5, x1, y1, terrain_height(x1, y1) + 5);
    layers[0].features.push_back({wkt, 0});
  }
  return test::write_vector(path, layers, "GeoJSON", "NAME");
}

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
