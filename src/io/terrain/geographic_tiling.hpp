// Cesium's default terrain tiling: the geographic TMS scheme of quantized-mesh-1.0 layers
// (EPSG:4326, longitude and latitude in degrees). Level 0 has two root tiles, west and east of
// the prime meridian, each 180 degrees square; every level splits each tile in four. x counts
// from the antimeridian eastwards, y from the south pole northwards (TMS, not slippy-map).
// Also the geometric error Cesium assumes for a tile of a level, which chooses the level it
// draws at a given distance.
#pragma once

#include <cstdint>

namespace tincdt::io::terrain {

// The deepest level whose tile counts fit in 32 bits (2^31 columns).
inline constexpr int kMaxTileLevel = 30;

// A longitude/latitude rectangle in degrees, west <= east and south <= north.
struct GeoRectangle {
  double west;
  double south;
  double east;
  double north;
  friend bool operator==(const GeoRectangle&, const GeoRectangle&) = default;
};

// One tile of the scheme.
struct TileKey {
  int level;
  std::uint32_t x;  // 0 at the antimeridian, eastwards
  std::uint32_t y;  // 0 at the south pole, northwards
  friend bool operator==(const TileKey&, const TileKey&) = default;
};

// The tiles x in [start_x, end_x] and y in [start_y, end_y] of one level, ends included: the
// form layer.json's "available" and the metadata extension give them in.
struct TileRange {
  std::uint32_t start_x;
  std::uint32_t start_y;
  std::uint32_t end_x;
  std::uint32_t end_y;
  friend bool operator==(const TileRange&, const TileRange&) = default;
};

// Columns and rows of tiles at LEVEL (0 <= LEVEL <= kMaxTileLevel).
std::uint32_t tiles_across(int level);
std::uint32_t tiles_down(int level);

// The rectangle of KEY. Exact: every side is a multiple of a power-of-two fraction of 360
// degrees, so a child's sides equal its parent's bit for bit and neighbours share theirs.
GeoRectangle tile_rectangle(const TileKey& key);

// The tiles of LEVEL that RECTANGLE touches with more than a side: a rectangle ending exactly
// on a tile border does not take the tile beyond it. Parts outside the globe are ignored; a
// rectangle of no width or height still gets the one tile holding it.
TileRange tiles_covering(const GeoRectangle& rectangle, int level);

// The geometric error Cesium estimates for a level-0 heightmap tile: the ellipsoid's equator
// split into SAMPLES_ACROSS * ROOT_TILES heightmap samples, times its terrain quality (a quarter
// of the sample spacing). About 77,067 m for 65 samples, 2 root tiles and WGS 84.
double level_zero_geometric_error(double semi_major_axis, int samples_across, int root_tiles);

// What Cesium assumes for a tile of LEVEL of this scheme on WGS 84: the level-0 error of a
// 65-sample heightmap, halved per level.
double geometric_error_at_level(int level);

}  // namespace tincdt::io::terrain
