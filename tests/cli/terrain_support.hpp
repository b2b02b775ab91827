// For the web-terrain CLI tests: a pyramid read back (every tile by the tests' own decoder,
// tests/io/terrain/tile_support.hpp), the full TIN of the same run in longitude, latitude and
// metres (its PLY and .prj, transformed by GDAL here, not by tincdt), and the measures the tests
// assert: each tile's error against the full TIN, the borders neighbours share.
#pragma once

#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "io/terrain/tile_support.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"

namespace tincdt::test::terrain {

constexpr double kQ = 32767.0;

struct Key {
  int z;
  std::uint32_t x, y;
  auto operator<=>(const Key&) const = default;
};

// Every tile of the pyramid in DIR, decoded.
inline std::map<Key, DecodedTile> read_pyramid(const std::filesystem::path& dir) {
  std::map<Key, DecodedTile> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.path().extension() != ".terrain") continue;
    const auto rel = std::filesystem::relative(e.path(), dir);
    auto it = rel.begin();
    const int z = std::stoi((it++)->string());
    const auto x = static_cast<std::uint32_t>(std::stoul((it++)->string()));
    const auto y = static_cast<std::uint32_t>(std::stoul(it->stem().string()));
    out[{z, x, y}] = decode_tile(slurp(e.path()));
  }
  return out;
}

// The rectangle of a tile of Cesium's geographic scheme, from its definition.
inline GeoRectangle rectangle_of(const Key& k) {
  const double span = 180.0 / std::ldexp(1.0, k.z);
  return {-180 + k.x * span, -90 + k.y * span, -180 + (k.x + 1) * span, -90 + (k.y + 1) * span};
}

// Cesium's level error: a 65-sample heightmap's, the equator over 2 x 64 spacings, a quarter.
// The longitude and latitude of the centroid of triangle T (its first index) of TILE at KEY.
inline std::array<double, 2> centroid(const Key& key, const DecodedTile& tile, std::size_t t) {
  const GeoRectangle g = rectangle_of(key);
  double lon = 0, lat = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    lon += g.west + (g.east - g.west) * tile.u[tile.indices[t + i]] / kQ / 3;
    lat += g.south + (g.north - g.south) * tile.v[tile.indices[t + i]] / kQ / 3;
  }
  return {lon, lat};
}

inline double level_error(int z) {
  return 2 * std::numbers::pi * kA * 0.25 / (65 * 2) / std::ldexp(1.0, z);
}

// The vertices of the PLY (ASCII) at PLY_PATH in longitude, latitude and metres: the CRS of its
// .prj to EPSG:4326, heights in the CRS's linear unit (their vertical unit when it has one).
inline std::vector<std::array<double, 3>> lon_lat_metres(const std::string& ply_path,
                                                         const std::string& prj_path) {
  const MeshFile mesh = read_mesh(ply_path);
  OGRSpatialReference source, target;
  const std::string prj = slurp(prj_path);
  EXPECT_EQ(source.importFromWkt(prj.c_str()), OGRERR_NONE);
  target.importFromEPSG(4326);
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  const double unit = source.IsProjected() ? source.GetLinearUnits() : 1.0;
  std::unique_ptr<OGRCoordinateTransformation> t(
      OGRCreateCoordinateTransformation(&source, &target));
  std::vector<std::array<double, 3>> out;
  for (const auto& v : mesh.v) {
    double x = v[0], y = v[1];
    EXPECT_TRUE(t->Transform(1, &x, &y));
    out.push_back({x, y, v[2] * unit});
  }
  return out;
}

// The decoded surface of TILE (rectangle R) at LON, LAT on the tile's grid (the nearest u, v a
// tile can hold): linear in the quantized u, v over the triangle that holds the point best.
inline double surface_at(const DecodedTile& tile, const GeoRectangle& r, double lon, double lat) {
  const double u = std::round((lon - r.west) / (r.east - r.west) * kQ);
  const double v = std::round((lat - r.south) / (r.north - r.south) * kQ);
  const double low = tile.minimum_height, high = tile.maximum_height;
  double best = -INFINITY, height = NAN;
  for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3) {
    double x[3], y[3], h[3];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t k = tile.indices[t + i];
      x[i] = tile.u[k];
      y[i] = tile.v[k];
      h[i] = low + (high - low) * tile.height[k] / kQ;
    }
    const double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    const double w0 = ((x[2] - x[1]) * (v - y[1]) - (y[2] - y[1]) * (u - x[1])) / area;
    const double w1 = ((x[0] - x[2]) * (v - y[2]) - (y[0] - y[2]) * (u - x[2])) / area;
    const double w2 = 1 - w0 - w1;
    const double worst = std::min({w0, w1, w2});
    if (worst <= best) continue;
    best = worst;
    height = w0 * h[0] + w1 * h[1] + w2 * h[2];
  }
  return height;
}

struct LevelError {
  std::size_t tiles = 0, vertices = 0, points = 0;
  double max = 0, sum_squares = 0;
  double rmse() const { return points ? std::sqrt(sum_squares / static_cast<double>(points)) : 0; }
};

// Per level, the error of the tiles against the full TIN's vertices inside them (sides
// included).
inline std::map<int, LevelError> level_errors(const std::map<Key, DecodedTile>& pyramid,
                                              const std::vector<std::array<double, 3>>& full) {
  std::map<int, LevelError> out;
  for (const auto& [key, tile] : pyramid) {
    const GeoRectangle r = rectangle_of(key);
    LevelError& e = out[key.z];
    ++e.tiles;
    e.vertices += tile.u.size();
    for (const auto& p : full) {
      if (p[0] < r.west || p[0] > r.east || p[1] < r.south || p[1] > r.north) continue;
      const double d = std::fabs(p[2] - surface_at(tile, r, p[0], p[1]));
      e.max = std::max(e.max, d);
      e.sum_squares += d * d;
      ++e.points;
    }
  }
  return out;
}

// The constrained edges of the PLY (ASCII) at PLY_PATH, as indices into its vertices.
inline std::vector<std::array<std::size_t, 2>> constrained_edges(const std::string& ply_path) {
  return read_mesh(ply_path).e;
}

// The largest horizontal distance, in metres, from the midpoint of an edge of EDGES lying inside
// a tile of level Z of PYRAMID to the nearest edge of that tile's TIN.
inline double farthest_line_from_tile_edges(const std::map<Key, DecodedTile>& pyramid, int z,
                                            const std::vector<std::array<double, 3>>& full,
                                            const std::vector<std::array<std::size_t, 2>>& edges) {
  double farthest = 0;
  for (const auto& [key, tile] : pyramid) {
    if (key.z != z) continue;
    const GeoRectangle r = rectangle_of(key);
    const double lat = (r.south + r.north) / 2 * std::numbers::pi / 180;
    const double mx = (r.east - r.west) / kQ * 111320 * std::cos(lat);
    const double my = (r.north - r.south) / kQ * 111320;
    const auto inside = [&](const std::array<double, 3>& p) {
      return p[0] > r.west && p[0] < r.east && p[1] > r.south && p[1] < r.north;
    };
    for (const auto& e : edges) {
      const auto &a = full[e[0]], &b = full[e[1]];
      if (!inside(a) || !inside(b)) continue;
      const double px = ((a[0] + b[0]) / 2 - r.west) / (r.east - r.west) * kQ * mx;
      const double py = ((a[1] + b[1]) / 2 - r.south) / (r.north - r.south) * kQ * my;
      double nearest = INFINITY;
      for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3)
        for (int i = 0; i < 3; ++i) {
          const auto k0 = tile.indices[t + i], k1 = tile.indices[t + (i + 1) % 3];
          const double x0 = tile.u[k0] * mx, y0 = tile.v[k0] * my;
          const double dx = tile.u[k1] * mx - x0, dy = tile.v[k1] * my - y0;
          const double f =
              std::clamp(((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
          nearest = std::min(nearest, std::hypot(x0 + f * dx - px, y0 + f * dy - py));
        }
      farthest = std::max(farthest, nearest);
    }
  }
  return farthest;
}

// The vertices of TILE on one side (0 west, 1 south, 2 east, 3 north): their place along it and
// their decoded height, sorted.
inline std::vector<std::pair<std::uint16_t, double>> side_of(const DecodedTile& tile, int side) {
  std::vector<std::pair<std::uint16_t, double>> out;
  const double low = tile.minimum_height, high = tile.maximum_height;
  for (std::size_t i = 0; i < tile.u.size(); ++i) {
    const bool on = side == 0   ? tile.u[i] == 0
                    : side == 1 ? tile.v[i] == 0
                    : side == 2 ? tile.u[i] == 32767
                                : tile.v[i] == 32767;
    if (on)
      out.emplace_back(side % 2 == 0 ? tile.v[i] : tile.u[i],
                       low + (high - low) * tile.height[i] / kQ);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Half a height step of TILE's quantization.
inline double half_step(const DecodedTile& tile) {
  return (static_cast<double>(tile.maximum_height) - tile.minimum_height) / kQ / 2;
}

// Every "terrain level N: ... max error E m (allowed A)" of the log has E <= A; the count.
inline int expect_levels_within(const std::string& log) {
  static const std::regex level(
      R"(terrain level (\d+): .*max error ([0-9.,]+) m \(allowed ([0-9.,]+)\))");
  const auto number = [](std::string s) {
    std::erase(s, ',');
    return std::stod(s);
  };
  int levels = 0;
  for (std::sregex_iterator m(log.begin(), log.end(), level), end; m != end; ++m, ++levels)
    EXPECT_LE(number((*m)[2]), number((*m)[3])) << "level " << (*m)[1];
  return levels;
}

}  // namespace tincdt::test::terrain
