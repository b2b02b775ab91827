// Tiled jobs in the library tests: inputs (random terrains, contour rings), the whole job, a plan,
// every tile built as its own job and merged, and the comparison of the merged TIN with the whole
// job's as sets of triangles with exact coordinates. Header-only, for the tiles tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "io/mesh/ply_reader.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/vector_files.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"
#include "tiles/tile_job.hpp"

namespace tincdt::tile_test {

namespace fs = std::filesystem;

// ---- inputs -------------------------------------------------------------------------------------

inline double terrain_height(double x, double y) {
  return 300 + 20 * std::sin(x / 37.0) * std::cos(y / 23.0) + 0.01 * x;
}

// N points uniform over [x0, x0 + side)^2, doubles (no four cocircular, no three collinear).
inline std::vector<Point3> random_points(int n, double x0, double y0, double side,
                                         std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(0, side);
  std::vector<Point3> p;
  for (int i = 0; i < n; ++i) {
    const double x = x0 + at(rng), y = y0 + at(rng);
    p.push_back({x, y, terrain_height(x, y)});
  }
  return p;
}

// LiDAR-like: uniform, every coordinate a whole number of centimetres (ties everywhere).
inline std::vector<Point3> centimetre_points(int n, double x0, double y0, double side,
                                             std::uint64_t seed) {
  std::vector<Point3> p = random_points(n, x0, y0, side, seed);
  for (Point3& q : p)
    q = {std::round(q.x * 100) / 100, std::round(q.y * 100) / 100, std::round(q.z * 100) / 100};
  return p;
}

// An M x M lattice of STEP: every cell's four corners cocircular.
inline std::vector<Point3> lattice(int m, double x0, double y0, double step) {
  std::vector<Point3> p;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = x0 + i * step, y = y0 + j * step;
      p.push_back({x, y, terrain_height(x, y)});
    }
  return p;
}

inline std::string write_xyz(const fs::path& path, const std::vector<Point3>& points) {
  std::string s;
  char line[128];
  for (const Point3& p : points) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
    s += line;
  }
  test::spit(path, s);
  return path.string();
}

// Closed 3D polylines around (cx, cy), one per radius: contour-like lines that never cross.
inline std::string write_rings(const fs::path& path, double cx, double cy,
                               const std::vector<double>& radii) {
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "rings";
  for (const double r : radii) {
    std::string wkt = "LINESTRING Z (";
    for (int k = 0; k <= 48; ++k) {
      const double a = 2 * M_PI * (k % 48) / 48 + r;  // a different phase per ring
      char v[96];
      std::snprintf(v, sizeof v, "%s%.6f %.6f %.3f", k ? ", " : "", cx + r * std::cos(a),
                    cy + r * std::sin(a), 280 + r / 10);
      wkt += v;
    }
    layers[0].features.push_back({wkt + ")", 280 + r / 10});
  }
  return test::write_vector(path, layers, "GeoJSON", "NAME");
}

// N polylines across [x0, x0 + side)^2, alternately west to east and south to north, each of
// VERTICES vertices jittered off its own straight course, at the terrain's height plus a lift of
// its own: long segments that cross each other (at heights that disagree) and the tile borders.
inline std::string write_crossing_lines(const fs::path& path, double x0, double y0, double side,
                                        int n, int vertices, std::uint64_t seed) {
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
inline std::string write_straight_lines(const fs::path& path,
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

// ---- runs ---------------------------------------------------------------------------------------

using Corner = std::array<double, 3>;
using Triangle = std::array<Corner, 3>;

// The triangles of a PLY as vertex triples, each rotated to start at its smallest corner.
inline std::set<Triangle> triangles(const std::string& ply) {
  const io::PlyMesh m = io::read_ply(ply);
  std::set<Triangle> set;
  for (const auto& f : m.faces) {
    Triangle t;
    for (int i = 0; i < 3; ++i) {
      const Point3& p = m.vertices[f[i]];
      t[i] = {p.x, p.y, p.z};
    }
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    set.insert(t);
  }
  return set;
}

struct Inputs {
  std::vector<std::string> points;
  std::vector<std::string> contours;
};

// For --max-edge: uniform points with a round void inside (kept: its long triangles do not reach
// the hull), a bay cut in from the east side and a gap along the north (trimmed from the hull,
// across tile borders); contour rings across all three.
inline Inputs gapped_points(const fs::path& dir) {
  std::vector<Point3> points;
  for (const Point3& p : random_points(6000, 500000, 4000000, 300, 11)) {
    const double x = p.x - 500000, y = p.y - 4000000;
    const bool void_inside = std::hypot(x - 120, y - 130) < 30;
    const bool bay = x > 170 && std::fabs(y - 150) < 25;
    const bool gap = y > 260 && std::fabs(x - 90) < 40;
    if (!void_inside && !bay && !gap) points.push_back(p);
  }
  return {{write_xyz(dir / "points.xyz", points)},
          {write_rings(dir / "rings.geojson", 500150, 4000150, {35, 75, 115})}};
}

inline const pipeline::BuildOptions& no_options() {
  static const pipeline::BuildOptions none;
  return none;
}

// BASE: the job's options beside its inputs (surface features, ...), the same for the whole job
// and every tile.
inline std::string whole(const Inputs& in, const fs::path& dir,
                         const pipeline::BuildOptions& base = no_options()) {
  pipeline::BuildOptions o = base;
  o.inputs = in.points;
  o.contours = in.contours;
  o.output = (dir / "whole.ply").string();
  o.write.overwrite = true;
  pipeline::build(o);
  return o.output;
}

inline std::string plan(const Inputs& in, const fs::path& dir, double size, double buffer,
                        double rim = -1) {
  tiles::PlanOptions po;
  po.inputs = in.points;
  po.contours = in.contours;
  po.tile_size = size;
  po.buffer = buffer;
  po.rim_width = rim;
  po.output = (dir / "plan.json").string();
  po.overwrite = true;
  std::vector<Point3> rim_points;
  tiles::TilePlan p = tiles::make_plan(po, rim_points);
  tiles::write_plan(p, rim_points, po.output, true);
  return po.output;
}

// Tile TILE of the plan; with RESOLUTION > 0 also its DEM, tile_TILE.tif.
inline std::string build_tile(const std::string& plan_path, std::int64_t tile, const fs::path& dir,
                              double resolution = 0,
                              const pipeline::BuildOptions& base = no_options()) {
  tiles::TileOptions t;
  t.plan = plan_path;
  t.tile = tile;
  pipeline::BuildOptions o = base;
  o.output = (dir / ("tile_" + std::to_string(tile) + ".ply")).string();
  if (resolution > 0) {
    o.dem.path = (dir / ("tile_" + std::to_string(tile) + ".tif")).string();
    o.dem.resolution = resolution;
    // The quality pass runs beside the outputs; the DEM, which keeps the neighbours' final
    // triangles while it rasterizes, waits for it (stage_quality.cpp).
    o.stats_path = (dir / ("tile_" + std::to_string(tile) + ".json")).string();
  }
  t.outline = (dir / ("tile_" + std::to_string(tile) + ".outline.ply")).string();
  o.write.overwrite = true;
  o.validate = true;
  const pipeline::BuildReport r = tiles::build_tile(t, o);
  if (resolution > 0) {
    EXPECT_TRUE(r.quality_measured);
    EXPECT_EQ(r.quality.triangles, r.triangles) << "tile " << tile;  // its own triangles only
  }
  return o.output;
}

// Plans, builds every tile, merges; returns the merged TIN. Also checks the seams from the
// tiles' outlines, two halves at a time, as a run too large to merge would.
inline std::string tiled(const Inputs& in, const fs::path& dir, double size, double buffer,
                         double rim = -1, const pipeline::BuildOptions& base = no_options()) {
  const std::string p = plan(in, dir, size, buffer, rim);
  const std::size_t n = tiles::read_plan(p).tiles.size();
  std::vector<std::string> tiles;
  for (std::size_t i = 0; i < n; ++i)
    tiles.push_back(build_tile(p, static_cast<std::int64_t>(i), dir, 0, base));
  tiles::MergeOptions check;
  check.check_only = true;
  check.inputs = tiles;
  const tiles::MergeReport all = tiles::merge_tiles(check);
  std::vector<std::string> outlines;
  for (std::size_t half = 0; half < 2; ++half) {
    tiles::MergeOptions o;
    o.outline = true;
    o.overwrite = true;
    for (std::size_t i = half; i < n; i += 2) o.inputs.push_back(tiles[i]);
    o.output = (dir / ("outline_" + std::to_string(half) + ".ply")).string();
    tiles::merge_tiles(o);
    outlines.push_back(o.output);
  }
  check.inputs = outlines;
  const tiles::MergeReport r = tiles::merge_tiles(check);
  EXPECT_GT(r.seam_edges, 0u);
  // The outlines the tile jobs wrote themselves: the same seams.
  check.inputs.clear();
  for (const std::string& t : tiles)
    check.inputs.push_back(fs::path(t).replace_extension(".outline.ply").string());
  EXPECT_EQ(tiles::merge_tiles(check).seam_edges, all.seam_edges);
  tiles::MergeOptions m;
  m.inputs = tiles;
  m.output = (dir / "merged.ply").string();
  m.overwrite = true;
  tiles::merge_tiles(m);
  return m.output;
}

inline void expect_same_tin(const std::string& whole_ply, const std::string& merged_ply) {
  const std::set<Triangle> a = triangles(whole_ply), b = triangles(merged_ply);
  EXPECT_EQ(a.size(), b.size());
  std::size_t missing = 0, extra = 0;
  std::string first_missing, first_extra;
  const auto text = [](const Triangle& t) {
    char s[240];
    std::snprintf(s, sizeof s,
                  " (first: %.17g %.17g %.17g / %.17g %.17g %.17g / %.17g %.17g %.17g)", t[0][0],
                  t[0][1], t[0][2], t[1][0], t[1][1], t[1][2], t[2][0], t[2][1], t[2][2]);
    return std::string(s);
  };
  for (const Triangle& t : a)
    if (b.count(t) == 0 && missing++ == 0) first_missing = text(t);
  for (const Triangle& t : b)
    if (a.count(t) == 0 && extra++ == 0) first_extra = text(t);
  EXPECT_EQ(missing, 0u) << "triangles of the whole TIN missing from the merged tiles"
                         << first_missing;
  EXPECT_EQ(extra, 0u) << "triangles of the merged tiles not in the whole TIN" << first_extra;
}

inline fs::path scratch() {
  return test::scratch_dir("tiles");
}

inline std::string shared(const std::string& rel) {
  return (fs::path(::tincdt::test::shared_data()) / rel).string();
}

}  // namespace tincdt::tile_test
