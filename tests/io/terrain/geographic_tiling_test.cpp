// Cesium's geographic TMS scheme: the tiles the quantized-mesh specification lists, children
// covering their parent exactly, the tiles covering a rectangle, and the geometric error Cesium
// assumes per level.
#include "io/terrain/geographic_tiling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace tincdt::io::terrain {
namespace {

TEST(GeographicTiling, TilesOfTheSpecification) {
  EXPECT_EQ(tiles_across(0), 2u);
  EXPECT_EQ(tiles_down(0), 1u);
  EXPECT_EQ(tiles_across(3), 16u);
  EXPECT_EQ(tiles_down(3), 8u);
  EXPECT_EQ(tile_rectangle({0, 0, 0}), (GeoRectangle{-180, -90, 0, 90}));
  EXPECT_EQ(tile_rectangle({0, 1, 0}), (GeoRectangle{0, -90, 180, 90}));
  EXPECT_EQ(tile_rectangle({1, 0, 0}), (GeoRectangle{-180, -90, -90, 0}));
  EXPECT_EQ(tile_rectangle({1, 1, 0}), (GeoRectangle{-90, -90, 0, 0}));
  EXPECT_EQ(tile_rectangle({1, 2, 0}), (GeoRectangle{0, -90, 90, 0}));
  EXPECT_EQ(tile_rectangle({1, 3, 0}), (GeoRectangle{90, -90, 180, 0}));
  EXPECT_EQ(tile_rectangle({1, 0, 1}), (GeoRectangle{-180, 0, -90, 90}));
  EXPECT_EQ(tile_rectangle({1, 1, 1}), (GeoRectangle{-90, 0, 0, 90}));
  EXPECT_EQ(tile_rectangle({1, 2, 1}), (GeoRectangle{0, 0, 90, 90}));
  EXPECT_EQ(tile_rectangle({1, 3, 1}), (GeoRectangle{90, 0, 180, 90}));
  // The last tile of the deepest level ends exactly at the corner of the world.
  const int top = kMaxTileLevel;
  EXPECT_EQ(tile_rectangle({top, tiles_across(top) - 1, tiles_down(top) - 1}).east, 180.0);
  EXPECT_EQ(tile_rectangle({top, tiles_across(top) - 1, tiles_down(top) - 1}).north, 90.0);
  EXPECT_EQ(tile_rectangle({top, 0, 0}).east, -180 + std::ldexp(180.0, -top));
}

// The four children of a tile meet at its middle and share its sides bit for bit.
TEST(GeographicTiling, ChildrenCoverTheirParentExactly) {
  for (const TileKey parent : {TileKey{0, 1, 0}, TileKey{5, 37, 11}, TileKey{17, 200001, 70001},
                               TileKey{29, 1000000007, 300000001}}) {
    const GeoRectangle p = tile_rectangle(parent);
    const double middle_lon = (p.west + p.east) / 2, middle_lat = (p.south + p.north) / 2;
    for (const std::uint32_t east : {0u, 1u}) {
      for (const std::uint32_t north : {0u, 1u}) {
        SCOPED_TRACE(std::string(north ? "north" : "south") + (east ? "east" : "west"));
        const GeoRectangle c =
            tile_rectangle({parent.level + 1, 2 * parent.x + east, 2 * parent.y + north});
        EXPECT_EQ(c.west, east ? middle_lon : p.west);
        EXPECT_EQ(c.east, east ? p.east : middle_lon);
        EXPECT_EQ(c.south, north ? middle_lat : p.south);
        EXPECT_EQ(c.north, north ? p.north : middle_lat);
      }
    }
  }
}

TEST(GeographicTiling, TilesCoveringARectangle) {
  // Zurich at level 12: one tile, the one whose rectangle holds it.
  const TileRange zurich = tiles_covering({8.5, 47.35, 8.52, 47.37}, 12);
  EXPECT_EQ(zurich.start_x, zurich.end_x);
  EXPECT_EQ(zurich.start_y, zurich.end_y);
  const GeoRectangle z = tile_rectangle({12, zurich.start_x, zurich.start_y});
  EXPECT_LE(z.west, 8.5);
  EXPECT_GE(z.east, 8.52);
  EXPECT_LE(z.south, 47.35);
  EXPECT_GE(z.north, 47.37);
  // Ending on a tile border does not take the tile beyond.
  EXPECT_EQ(tiles_covering({-90, 0, 0, 90}, 1), (TileRange{1, 1, 1, 1}));
  EXPECT_EQ(tiles_covering({-90.5, -0.5, 0.5, 90}, 1), (TileRange{0, 0, 2, 1}));
  // The whole world, and beyond it.
  EXPECT_EQ(tiles_covering({-180, -90, 180, 90}, 0), (TileRange{0, 0, 1, 0}));
  EXPECT_EQ(tiles_covering({-200, -100, 200, 100}, 2), (TileRange{0, 0, 7, 3}));
  // A point on a border still has a tile.
  EXPECT_EQ(tiles_covering({0, 0, 0, 0}, 1), (TileRange{2, 1, 2, 1}));
}

TEST(GeographicTiling, GeometricErrorPerLevel) {
  // Cesium's estimate for WGS 84, 65 samples, 2 root tiles: 6378137 * 2 pi * 0.25 / 130.
  const double level0 = geometric_error_at_level(0);
  EXPECT_NEAR(level0, 77067, 1.0);
  EXPECT_DOUBLE_EQ(level_zero_geometric_error(6378137.0, 65, 2), level0);
  EXPECT_DOUBLE_EQ(level_zero_geometric_error(6378137.0, 65, 1), 2 * level0);
  for (int level = 1; level <= 20; ++level)
    EXPECT_EQ(geometric_error_at_level(level), geometric_error_at_level(level - 1) / 2);
  EXPECT_NEAR(geometric_error_at_level(14), 77067.34 / 16384, 1e-3);
}

}  // namespace
}  // namespace tincdt::io::terrain
