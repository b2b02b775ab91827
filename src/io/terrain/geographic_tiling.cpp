#include "io/terrain/geographic_tiling.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "io/terrain/wgs84.hpp"

namespace tincdt::io::terrain {
namespace {

// Cesium's heightmapTerrainQuality: the vertical error it allows a heightmap, as a fraction of
// the spacing of its samples.
constexpr double kHeightmapTerrainQuality = 0.25;
// The heightmap Cesium's estimate assumes: 65 x 65 samples a tile, two tiles at level 0.
constexpr int kHeightmapSamplesAcross = 65;
constexpr int kRootTiles = 2;

// Degrees spanned by one tile of LEVEL, either way: 180 / 2^level, exact.
double tile_span(int level) {
  return std::ldexp(180.0, -level);
}

// The tiles [first, last] of COUNT, each SPAN wide from ORIGIN, that [LOW, HIGH] touches with
// more than an end.
void covering(double low, double high, double origin, double span, std::uint32_t count,
              std::uint32_t& first, std::uint32_t& last) {
  const double top = static_cast<double>(count - 1);
  const double start = std::clamp(std::floor((low - origin) / span), 0.0, top);
  const double end = std::clamp(std::ceil((high - origin) / span) - 1.0, start, top);
  first = static_cast<std::uint32_t>(start);
  last = static_cast<std::uint32_t>(end);
}

}  // namespace

std::uint32_t tiles_across(int level) {
  assert(level >= 0 && level <= kMaxTileLevel);
  return std::uint32_t{2} << level;
}

std::uint32_t tiles_down(int level) {
  assert(level >= 0 && level <= kMaxTileLevel);
  return std::uint32_t{1} << level;
}

GeoRectangle tile_rectangle(const TileKey& key) {
  assert(key.x < tiles_across(key.level) && key.y < tiles_down(key.level));
  const double span = tile_span(key.level);
  // k * span is exact (k < 2^31, span a power of two times 180), and so is its sum with the
  // origin: both are multiples of span no larger than 360.
  return {-180.0 + key.x * span, -90.0 + key.y * span, -180.0 + (key.x + 1.0) * span,
          -90.0 + (key.y + 1.0) * span};
}

TileRange tiles_covering(const GeoRectangle& rectangle, int level) {
  assert(rectangle.west <= rectangle.east && rectangle.south <= rectangle.north);
  const double span = tile_span(level);
  TileRange range{};
  covering(std::clamp(rectangle.west, -180.0, 180.0), std::clamp(rectangle.east, -180.0, 180.0),
           -180.0, span, tiles_across(level), range.start_x, range.end_x);
  covering(std::clamp(rectangle.south, -90.0, 90.0), std::clamp(rectangle.north, -90.0, 90.0),
           -90.0, span, tiles_down(level), range.start_y, range.end_y);
  return range;
}

double level_zero_geometric_error(double semi_major_axis, int samples_across, int root_tiles) {
  assert(samples_across > 0 && root_tiles > 0);
  const double equator = 2.0 * std::numbers::pi * semi_major_axis;
  return equator * kHeightmapTerrainQuality / (static_cast<double>(samples_across) * root_tiles);
}

double geometric_error_at_level(int level) {
  assert(level >= 0 && level <= kMaxTileLevel);
  return std::ldexp(
      level_zero_geometric_error(wgs84::kSemiMajorAxis, kHeightmapSamplesAcross, kRootTiles),
      -level);
}

}  // namespace tincdt::io::terrain
