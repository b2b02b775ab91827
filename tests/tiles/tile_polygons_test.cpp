// Clip and erase polygons in tiled jobs: the rings are cut to the whole data's hull (the plan's),
// 2D rings draped only on triangles proven final, their crossings with contours made from the
// whole segments, and the triangles classified by regions of final triangles; the merged tiles
// are the whole job's TIN (triangle sets, exact coordinates), tiles wholly clipped away included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "pipeline/build.hpp"
#include "tile_runs.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

// A polygon of N corners around (cx, cy), radius R with a wobble (no two sides parallel to the
// tile borders), 2D, or 3D at the terrain's height plus LIFT.
std::string polygon_wkt(double cx, double cy, double r, int n, bool three_d, double lift = 0) {
  std::string wkt = three_d ? "POLYGON Z ((" : "POLYGON ((";
  for (int k = 0; k <= n; ++k) {
    const double a = 2 * M_PI * (k % n) / n + 0.3;
    const double rk = r * (1 + 0.25 * std::sin(3.0 * (k % n) + 1));
    const double x = cx + rk * std::cos(a), y = cy + rk * std::sin(a);
    char v[120];
    if (three_d)
      std::snprintf(v, sizeof v, "%s%.17g %.17g %.17g", k ? ", " : "", x, y,
                    terrain_height(x, y) + lift);
    else
      std::snprintf(v, sizeof v, "%s%.17g %.17g", k ? ", " : "", x, y);
    wkt += v;
  }
  return wkt + "))";
}

std::string write_polygons(const fs::path& path, const std::vector<std::string>& wkts) {
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "polygons";
  for (const std::string& wkt : wkts) layers[0].features.push_back({wkt, 0});
  return test::write_vector(path, layers, "GeoJSON", "NAME");
}

constexpr double kX0 = 500000, kY0 = 4000000;

// Points, contour rings and crossing lines over a 300 m square.
Inputs terrain(const fs::path& dir, std::uint64_t seed) {
  return {{write_xyz(dir / "points.xyz", random_points(2500, kX0, kY0, 300, seed))},
          {write_rings(dir / "rings.geojson", kX0 + 150, kY0 + 150, {40, 80, 120}),
           write_crossing_lines(dir / "lines.geojson", kX0, kY0, 300, 6, 21, seed + 1)}};
}

// A clip polygon across the data's hull (part of it outside the data) and erase polygons across
// tile borders and contours, one inside another's hole-free area.
pipeline::BuildOptions polygon_options(const fs::path& dir, bool three_d) {
  pipeline::BuildOptions o;
  o.clip = {write_polygons(dir / "clip.geojson",
                           {polygon_wkt(kX0 + 130, kY0 + 140, 150, 9, three_d, 1)})};
  o.erase = {write_polygons(dir / "erase.geojson",
                            {polygon_wkt(kX0 + 150, kY0 + 100, 30, 7, three_d, -1),
                             polygon_wkt(kX0 + 60, kY0 + 200, 22, 5, three_d, 2),
                             polygon_wkt(kX0 + 210, kY0 + 205, 45, 6, three_d, 0)})};
  return o;
}

// The tiles' faces, each tile's count in FACES; and every vertex a tile wrote has a height (a
// draped vertex the tile could not settle is in none of its triangles).
std::size_t tile_faces(const fs::path& dir, std::size_t n, std::vector<std::size_t>& faces) {
  std::size_t total = 0;
  faces.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const io::PlyMesh m = io::read_ply((dir / ("tile_" + std::to_string(i) + ".ply")).string());
    for (const Point3& p : m.vertices) EXPECT_TRUE(std::isfinite(p.z)) << "tile " << i;
    faces.push_back(m.faces.size());
    total += m.faces.size();
  }
  return total;
}

// Tiles of 150 and of 100 with O: the merged tiles are the whole job's TIN W, and the tiles'
// faces are its triangles once each, every vertex with a height.
void expect_tiles_make(const std::string& w, const Inputs& in, const fs::path& dir,
                       const pipeline::BuildOptions& o) {
  for (const double size : {150.0, 100.0}) {
    SCOPED_TRACE(size);
    expect_same_tin(w, tiled(in, dir, size, 25, -1, o));
    std::vector<std::size_t> faces;
    const std::size_t n = tiles::read_plan((dir / "plan.json").string()).tiles.size();
    EXPECT_EQ(tile_faces(dir, n, faces), triangles(w).size());
  }
}

TEST(TilePolygons, DrapedClipAndErasePolygonsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 41);
  const pipeline::BuildOptions o = polygon_options(dir, false);
  const std::string w = whole(in, dir, o);
  ASSERT_GT(triangles(w).size(), 1000u);
  expect_tiles_make(w, in, dir, o);
}

// Each tile inserts only the erase polygons near it (footprints on a 5 x 5 grid, the rim narrow
// enough to hold none), and the merged tiles are the whole job's TIN.
TEST(TilePolygons, ATileInsertsOnlyTheErasePolygonsNearIt) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 41);
  std::vector<std::string> footprints;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const double x = kX0 + 30 + 60 * i, y = kY0 + 30 + 60 * j;
      char wkt[240];
      std::snprintf(wkt, sizeof wkt,
                    "POLYGON ((%.3f %.3f, %.3f %.3f, %.3f %.3f, %.3f %.3f, %.3f %.3f))", x - 4,
                    y - 3, x + 4, y - 4, x + 3, y + 4, x - 4, y + 3, x - 4, y - 3);
      footprints.push_back(wkt);
    }
  pipeline::BuildOptions o;
  o.erase = {write_polygons(dir / "footprints.geojson", footprints)};
  const std::string w = whole(in, dir, o);
  expect_same_tin(w, tiled(in, dir, 100, 25, 10, o));

  tiles::TileOptions t;
  t.plan = (dir / "plan.json").string();
  o.output = (dir / "tile.ply").string();
  o.write.overwrite = true;
  std::uint64_t used = 0;
  for (std::int64_t i = 0; i < 9; ++i) {
    t.tile = i;
    for (const pipeline::BuildReport::Input& input : tiles::build_tile(t, o).inputs)
      if (input.kind == "erase") {
        EXPECT_EQ(input.features_read, 25u);
        used += input.features_used;
      }
  }
  EXPECT_EQ(used, 49u);  // 4 in a corner tile's buffered box, 6 at a side, 9 in the middle
}

// A clip polygon in the middle: the tiles it misses keep no triangle, and merge takes them as
// they are.
TEST(TilePolygons, TilesWhollyClippedAwayAreEmpty) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 42);
  pipeline::BuildOptions o;
  o.clip = {
      write_polygons(dir / "clip.geojson", {polygon_wkt(kX0 + 150, kY0 + 150, 60, 8, false)})};
  const std::string w = whole(in, dir, o);
  expect_same_tin(w, tiled(in, dir, 100, 25, -1, o));
  std::vector<std::size_t> faces;
  EXPECT_EQ(tile_faces(dir, 9, faces), triangles(w).size());
  const auto empty = std::count(faces.begin(), faces.end(), 0u);
  EXPECT_GE(empty, 1);  // a corner tile at least
  EXPECT_LE(empty, 6);  // the middle one and its sides hold some
}

TEST(TilePolygons, ClipAndErasePolygonsWithTheirOwnHeightsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 43);
  const pipeline::BuildOptions o = polygon_options(dir, true);
  const std::string w = whole(in, dir, o);
  ASSERT_GT(triangles(w).size(), 1000u);
  expect_same_tin(w, tiled(in, dir, 120, 25, -1, o));
}

// 2D polylines across [x0, x0 + side)^2 like write_crossing_lines(), without heights: soft lines
// that cross each other, the contours and the tile borders.
std::string write_soft_lines(const fs::path& path, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> across(20, 280), jitter(-6, 6);
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "soft";
  for (int i = 0; i < n; ++i) {
    const double course = across(rng);
    std::string wkt = "LINESTRING (";
    for (int k = 0; k < 12; ++k) {
      const double along = 10 + 280.0 * k / 11, off = course + jitter(rng);
      char v[80];
      std::snprintf(v, sizeof v, "%s%.17g %.17g", k ? ", " : "", kX0 + (i % 2 == 0 ? along : off),
                    kY0 + (i % 2 == 0 ? off : along));
      wkt += v;
    }
    layers[0].features.push_back({wkt + ")", 0});
  }
  return test::write_vector(path, layers, "GeoJSON", "NAME");
}

// Soft lines are draped as 2D rings are; where two cross, the vertex takes the mean of the
// heights along both whole segments, whose far ends a tile must have settled too.
TEST(TilePolygons, SoftLinesMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 45);
  pipeline::BuildOptions o = polygon_options(dir, false);
  o.soft_lines = {write_soft_lines(dir / "soft.geojson", 6, 46)};
  const std::string w = whole(in, dir, o);
  ASSERT_GT(triangles(w).size(), 1000u);
  expect_tiles_make(w, in, dir, o);
}

// A soft line beyond the data's hull has nothing to be draped on, in a tile as in the whole job,
// even where the tile's own TIN does not reach.
TEST(TilePolygons, ASoftLineBeyondTheDataIsAnErrorInEveryTile) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(800, kX0, kY0, 300, 47))}, {}};
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "soft";
  layers[0].features.push_back({"LINESTRING (500150 4000150, 500150 4000400)", 0});
  pipeline::BuildOptions o;
  o.soft_lines = {test::write_vector(dir / "soft.geojson", layers, "GeoJSON", "NAME")};
  const std::string p = plan(in, dir, 150, 25);
  for (const std::int64_t tile : {0, 3}) {  // one the line reaches, one it does not
    tiles::TileOptions t;
    t.plan = p;
    t.tile = tile;
    o.output = (dir / "tile.ply").string();
    try {
      tiles::build_tile(t, o);
      ADD_FAILURE() << "tile " << tile << ": no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), o.soft_lines[0]);
      EXPECT_NE(std::string(e.what()).find("lies outside the TIN"), std::string::npos) << e.what();
    }
  }
}

// A flat convex polygon at Z, its corners counter-clockwise.
struct FlatPolygon {
  std::vector<Point2> corners;
  double z;

  std::string wkt() const {
    std::string text = "POLYGON Z ((";
    for (std::size_t k = 0; k <= corners.size(); ++k) {
      const Point2 c = corners[k % corners.size()];
      char v[120];
      std::snprintf(v, sizeof v, "%s%.17g %.17g %.17g", k ? ", " : "", c.x, c.y, z);
      text += v;
    }
    return text + "))";
  }
  // On or inside, within a micrometre: inside every side.
  bool holds(const Point3& p) const {
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const Point2 a = corners[k], b = corners[(k + 1) % corners.size()];
      const double cross = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
      if (cross / std::hypot(b.x - a.x, b.y - a.y) < -1e-6) return false;
    }
    return true;
  }
};

// N corners on the circle of radius R around (CX, CY).
FlatPolygon regular(double cx, double cy, double r, int n, double z) {
  FlatPolygon p{{}, z};
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n + 0.2;
    p.corners.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return p;
}

// Replace polygons (lakes, pads) over tile borders, one across a contour ring and one across a
// clip ring, the third inside the first, and a rectangle with a side on a tile border (x = 100
// in tiles of 100 and of 150), whose vertices there the tile beyond sees outside it.
const FlatPolygon kReplaced[] = {
    regular(kX0 + 100, kY0 + 150, 35, 9, 5290),
    regular(kX0 + 200, kY0 + 100, 28, 7, 5310),
    regular(kX0 + 120, kY0 + 170, 20, 6, 5280),
    {{{kX0 + 100, kY0 + 20}, {kX0 + 125, kY0 + 20}, {kX0 + 125, kY0 + 45}, {kX0 + 100, kY0 + 45}},
     5300}};

pipeline::BuildOptions replace_options(const fs::path& dir) {
  pipeline::BuildOptions o = polygon_options(dir, false);
  std::vector<std::string> wkts;
  for (const FlatPolygon& p : kReplaced) wkts.push_back(p.wkt());
  o.replace = {write_polygons(dir / "replace.geojson", wkts)};
  return o;
}

// Every vertex on or inside takes the polygon's height, later polygons winning, in every tile as
// in the whole job, which needs every triangle around a kept corner proven.
TEST(TilePolygons, ReplacePolygonsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 48);
  const pipeline::BuildOptions o = replace_options(dir);
  const std::string w = whole(in, dir, o);
  ASSERT_GT(triangles(w).size(), 1000u);
  std::size_t replaced = 0;
  for (const Triangle& t : triangles(w))
    for (const Corner& c : t)
      replaced += c[2] == 5290 || c[2] == 5310 || c[2] == 5280 || c[2] == 5300;
  ASSERT_GT(replaced, 100u);
  expect_tiles_make(w, in, dir, o);
}

// With --max-error: each tile's border vertex takes its height from the polygons around it on
// both sides of the border, so the tiles agree on it (the merge checks every seam's heights),
// and every vertex of the merged TIN on or inside a polygon has the last one's height.
TEST(TilePolygons, ReplacePolygonsInSimplifiedTiles) {
  const fs::path dir = scratch();
  const Inputs in = terrain(dir, 48);
  pipeline::BuildOptions o = replace_options(dir);
  o.max_error = 0.05;
  for (const double size : {150.0, 100.0, 70.0}) {
    SCOPED_TRACE(size);
    const io::PlyMesh merged = io::read_ply(tiled(in, dir, size, 25, -1, o));
    std::size_t replaced = 0;
    for (const Point3& p : merged.vertices) {
      const FlatPolygon* last = nullptr;
      for (const FlatPolygon& polygon : kReplaced)
        if (polygon.holds(p)) last = &polygon;
      if (last) {
        EXPECT_EQ(p.z, last->z) << "at " << p.x - kX0 << " " << p.y - kY0;
        ++replaced;
      } else {
        EXPECT_TRUE(p.z != 5290 && p.z != 5310 && p.z != 5280 && p.z != 5300)
            << "at " << p.x - kX0 << " " << p.y - kY0;
      }
    }
    EXPECT_GT(replaced, 50u);
  }
}

// A ring segment far longer than a tile, through centimetre points: the thin triangles along it
// reach along all of it, and the error says to split the segments. Split, the tiles settle.
TEST(TilePolygons, LongRingSegmentsThroughDensePointsAskToBeSplit) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", centimetre_points(30000, kX0, kY0, 300, 49))}, {}};
  // A triangle across the area, its sides split into pieces of at most STEP.
  const auto triangle = [](double step) {
    const Point2 corners[3] = {{kX0 + 5, kY0 + 7}, {kX0 + 296, kY0 + 120}, {kX0 + 40, kY0 + 291}};
    std::vector<Point2> ring;
    for (int k = 0; k < 3; ++k) {
      const Point2 a = corners[k], b = corners[(k + 1) % 3];
      const int pieces = static_cast<int>(std::ceil(std::hypot(b.x - a.x, b.y - a.y) / step));
      for (int i = 0; i < pieces; ++i)
        ring.push_back({a.x + (b.x - a.x) * i / pieces, a.y + (b.y - a.y) * i / pieces});
    }
    ring.push_back(ring.front());
    std::string wkt = "POLYGON ((";
    for (std::size_t i = 0; i < ring.size(); ++i) {
      char v[80];
      std::snprintf(v, sizeof v, "%s%.17g %.17g", i ? ", " : "", ring[i].x, ring[i].y);
      wkt += v;
    }
    return wkt + "))";
  };
  const std::string p = plan(in, dir, 100, 20);
  tiles::TileOptions t;
  t.plan = p;
  pipeline::BuildOptions o;
  o.output = (dir / "tile.ply").string();
  o.write.overwrite = true;
  o.clip = {write_polygons(dir / "long.geojson", {triangle(1000)})};
  std::size_t asked = 0;
  const std::size_t n = tiles::read_plan(p).tiles.size();
  for (std::size_t i = 0; i < n; ++i) {
    t.tile = static_cast<std::int64_t>(i);
    try {
      tiles::build_tile(t, o);
    } catch (const tiles::BufferTooSmall& e) {
      EXPECT_NE(std::string(e.what()).find("ogr2ogr -segmentize"), std::string::npos) << e.what();
      ++asked;
    }
  }
  EXPECT_GT(asked, 0u);
  o.clip = {write_polygons(dir / "split.geojson", {triangle(10)})};
  const std::string w = whole(in, dir, o);
  expect_same_tin(w, tiled(in, dir, 100, 20, -1, o));
}

// The rings are cut to the data's hull, which a plan without a rim does not hold.
TEST(TilePolygons, APlanWithoutAHullIsRefusedNamingThePlan) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(500, kX0, kY0, 300, 44))}, {}};
  const std::string p = plan(in, dir, 150, 25, 0);
  tiles::TileOptions t;
  t.plan = p;
  t.tile = 0;
  pipeline::BuildOptions o = polygon_options(dir, false);
  o.output = (dir / "tile_0.ply").string();
  try {
    tiles::build_tile(t, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p);
    EXPECT_NE(std::string(e.what()).find("made with --rim 0"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.output));
}

}  // namespace
