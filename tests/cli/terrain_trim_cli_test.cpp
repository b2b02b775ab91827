// --max-edge with --terrain: the gap that trimming opens between two clusters of points is a hole
// of the pyramid at every level, as a clip or erase polygon's is, and the data beside it stays
// covered; bays trimmed into a steep surface keep every level within its error. The tiles are
// read back by the tests' own decoder.
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "terrain_support.hpp"

namespace tincdt::test::terrain {
namespace {

// Two 100 m squares of points 5 m apart (EPSG:32632), 200 m apart along x: the convex hull
// bridges the gap with triangles whose edges are 200 m long, which --max-edge 20 removes.
constexpr double kWest = 600000, kSouth = 5190000;
constexpr double kGapWest = kWest + 100, kGapEast = kWest + 300, kGapNorth = kSouth + 100;

std::string two_clusters() {
  std::string text;
  char line[96];
  for (const double offset : {0.0, 300.0})
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j) {
        const double x = kWest + offset + 5 * i, y = kSouth + 5 * j;
        const double z = 200 + 0.1 * (offset + 5 * i) + 0.25 * j + ((7 * i + 3 * j) % 5) * 0.4;
        std::snprintf(line, sizeof line, "%.1f %.1f %.2f\n", x, y, z);
        text += line;
      }
  return text;
}

// Points of EPSG:32632 in longitude, latitude.
std::vector<std::array<double, 2>> lon_lat(const std::vector<std::array<double, 2>>& utm) {
  OGRSpatialReference from, to;
  from.importFromEPSG(32632);
  to.importFromEPSG(4326);
  from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&from, &to));
  std::vector<std::array<double, 2>> out;
  for (auto p : utm) {
    EXPECT_TRUE(t->Transform(1, &p[0], &p[1]));
    out.push_back(p);
  }
  return out;
}

// The points of a grid STEP metres apart over X0..X1, Y0..Y1 (EPSG:32632), in longitude,
// latitude.
std::vector<std::array<double, 2>> grid(double x0, double x1, double y0, double y1, double step) {
  std::vector<std::array<double, 2>> utm;
  for (double x = x0; x <= x1; x += step)
    for (double y = y0; y <= y1; y += step) utm.push_back({x, y});
  return lon_lat(utm);
}

// The least barycentric weight of LON, LAT in the triangles of TILE (rectangle R) that holds it
// best, on the tile's continuous u, v: > 0 strictly inside a triangle, < 0 outside all.
double best_weight(const DecodedTile& tile, const GeoRectangle& r, double lon, double lat) {
  const double u = (lon - r.west) / (r.east - r.west) * kQ;
  const double v = (lat - r.south) / (r.north - r.south) * kQ;
  double best = -INFINITY;
  for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3) {
    double x[3], y[3];
    for (int i = 0; i < 3; ++i) {
      x[i] = tile.u[tile.indices[t + i]];
      y[i] = tile.v[tile.indices[t + i]];
    }
    const double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    const double w0 = ((x[2] - x[1]) * (v - y[1]) - (y[2] - y[1]) * (u - x[1])) / area;
    const double w1 = ((x[0] - x[2]) * (v - y[2]) - (y[0] - y[2]) * (u - x[2])) / area;
    best = std::max(best, std::min({w0, w1, 1 - w0 - w1}));
  }
  return best;
}

bool strictly_in(const GeoRectangle& r, const std::array<double, 2>& p) {
  return p[0] > r.west && p[0] < r.east && p[1] > r.south && p[1] < r.north;
}

TEST(TerrainTrimCli, TrimmedGapIsAHoleAtEveryLevel) {
  const std::string dir = scratch_dir("terrain_trim_cli");
  spit(dir + "/p.xyz", two_clusters());
  const ShellRun r =
      run_tincdt(dir, "p.xyz --a-srs EPSG:32632 --max-edge 20 --terrain t --terrain-levels 0-18");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const auto corners = lon_lat(
      {{kGapWest, kSouth}, {kGapEast, kSouth}, {kGapEast, kGapNorth}, {kGapWest, kGapNorth}});
  const auto in_gap = [&](double lon, double lat) {
    for (int k = 0; k < 4; ++k) {
      const auto &a = corners[k], &b = corners[(k + 1) % 4];
      if ((b[0] - a[0]) * (lat - a[1]) - (b[1] - a[1]) * (lon - a[0]) <= 0) return false;
    }
    return true;
  };
  // Well inside the gap and well inside the data: 10 m from the gap's sides.
  const auto gap = grid(kGapWest + 10, kGapEast - 10, kSouth + 10, kGapNorth - 10, 10);
  auto data = grid(kWest + 10, kWest + 90, kSouth + 10, kSouth + 90, 10);
  const auto east_data = grid(kGapEast + 10, kGapEast + 90, kSouth + 10, kSouth + 90, 10);
  data.insert(data.end(), east_data.begin(), east_data.end());

  std::map<int, int> covered_gap, uncovered_data;
  std::set<int> levels;
  for (const auto& [key, tile] : read_pyramid(dir + "/t")) {
    const GeoRectangle g = rectangle_of(key);
    levels.insert(key.z);
    for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3) {
      const auto [lon, lat] = centroid(key, tile, t);
      EXPECT_FALSE(in_gap(lon, lat)) << key.z << "/" << key.x << "/" << key.y;
    }
    for (const auto& p : gap)
      if (strictly_in(g, p) && best_weight(tile, g, p[0], p[1]) > 0) ++covered_gap[key.z];
    for (const auto& p : data)
      if (strictly_in(g, p) && best_weight(tile, g, p[0], p[1]) < -1e-6) ++uncovered_data[key.z];
  }
  EXPECT_EQ(levels.size(), 19u);
  // A level whose error is above the gap's 100 m width may simplify the gap's outline away (its
  // triangles' centroids stay out of it, above); from level 10, 75 m, the gap is a hole.
  for (const int z : levels) {
    if (level_error(z) < kGapNorth - kSouth) {
      EXPECT_EQ(covered_gap[z], 0) << "level " << z;
    }
    EXPECT_EQ(uncovered_data[z], 0) << "level " << z;
  }
}

// A 600 m square of points 2 m apart on a steep surface (EPSG:32632), with four wavy bays cut
// into it from its sides: --max-edge 4 trims them, and their outlines are lines of the tiles.
std::string steep_square_with_bays() {
  struct Bay {
    double x, y, radius;
    int waves;
  };
  constexpr Bay kBays[] = {{0, 300, 90, 3}, {600, 180, 110, 5}, {320, 0, 80, 4}, {450, 600, 95, 2}};
  std::string text;
  char line[96];
  for (int i = 0; i <= 300; ++i)
    for (int j = 0; j <= 300; ++j) {
      const double x = 2.0 * i, y = 2.0 * j;
      const bool in_bay = std::any_of(std::begin(kBays), std::end(kBays), [&](const Bay& b) {
        const double a = std::atan2(y - b.y, x - b.x);
        return std::hypot(x - b.x, y - b.y) < b.radius * (1 + 0.35 * std::sin(b.waves * a));
      });
      if (in_bay) continue;
      const double z = 300 + 0.8 * x + 40 * std::sin(y / 45) + 15 * std::cos((x + y) / 70);
      std::snprintf(line, sizeof line, "%.2f %.2f %.3f\n", kWest + x, kSouth + y, z);
      text += line;
    }
  return text;
}

// A simplified outline leaves some data on a hole's side of it: those vertices are measured
// against the tile's surface there, not against a triangle beside the hole (where a steep slope
// made tens of metres of error, and the greedy insertion then took nearly every point). A vertex
// a level shows is within its error; few are hidden.
TEST(TerrainTrimCli, BaysInASteepSurfaceKeepEveryLevelsError) {
  const std::string dir = scratch_dir("terrain_trim_cli");
  spit(dir + "/p.xyz", steep_square_with_bays());
  const ShellRun r = run_tincdt(
      dir, "p.xyz --a-srs EPSG:32632 --max-edge 4 -o full.ply --ply-ascii --terrain t -v");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_GE(expect_levels_within(r.messages), 17) << r.messages;
  EXPECT_FALSE(has(r, "above the level's error")) << r.messages;
  EXPECT_TRUE(has(r, "under holes (their outline simplified at this level)")) << r.messages;

  const auto full = lon_lat_metres(dir + "/full.ply", dir + "/full.prj");
  std::map<int, std::size_t> vertices, hidden;
  for (const auto& [key, tile] : read_pyramid(dir + "/t")) {
    const GeoRectangle g = rectangle_of(key);
    vertices[key.z] += tile.u.size();
    for (const auto& p : full) {
      if (!strictly_in(g, {p[0], p[1]})) continue;
      if (best_weight(tile, g, p[0], p[1]) < -1e-3) {
        ++hidden[key.z];
        continue;
      }
      EXPECT_LE(std::fabs(p[2] - surface_at(tile, g, p[0], p[1])), level_error(key.z))
          << "level " << key.z << " at " << p[0] << ", " << p[1];
    }
  }
  for (const auto& [z, count] : vertices) {
    EXPECT_LE(count, full.size() / 10) << "level " << z;
    EXPECT_LE(hidden[z], full.size() / 20) << "level " << z;
  }
}

}  // namespace
}  // namespace tincdt::test::terrain
