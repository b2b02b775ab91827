// Tiled jobs end to end in the library: a plan, every tile built as its own job, the tiles merged;
// the merged TIN must hold exactly the triangles of the whole job (as sets of x, y, z triples),
// and every bad plan, tile or merge must be refused with an error that names it.
#include <gdal_priv.h>
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

#include "core/error.hpp"
#include "io/mesh/ply_reader.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/vector_files.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"
#include "tiles/tile_job.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;

// ---- inputs -------------------------------------------------------------------------------------

double terrain(double x, double y) {
  return 300 + 20 * std::sin(x / 37.0) * std::cos(y / 23.0) + 0.01 * x;
}

// N points uniform over [x0, x0 + side)^2, doubles (no four cocircular, no three collinear).
std::vector<Point3> random_points(int n, double x0, double y0, double side, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(0, side);
  std::vector<Point3> p;
  for (int i = 0; i < n; ++i) {
    const double x = x0 + at(rng), y = y0 + at(rng);
    p.push_back({x, y, terrain(x, y)});
  }
  return p;
}

// LiDAR-like: uniform, every coordinate a whole number of centimetres (ties everywhere).
std::vector<Point3> centimetre_points(int n, double x0, double y0, double side,
                                      std::uint64_t seed) {
  std::vector<Point3> p = random_points(n, x0, y0, side, seed);
  for (Point3& q : p)
    q = {std::round(q.x * 100) / 100, std::round(q.y * 100) / 100, std::round(q.z * 100) / 100};
  return p;
}

// An M x M lattice of STEP: every cell's four corners cocircular.
std::vector<Point3> lattice(int m, double x0, double y0, double step) {
  std::vector<Point3> p;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = x0 + i * step, y = y0 + j * step;
      p.push_back({x, y, terrain(x, y)});
    }
  return p;
}

std::string write_xyz(const fs::path& path, const std::vector<Point3>& points) {
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
std::string write_rings(const fs::path& path, double cx, double cy,
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

// ---- runs ---------------------------------------------------------------------------------------

using Corner = std::array<double, 3>;
using Triangle = std::array<Corner, 3>;

// The triangles of a PLY as vertex triples, each rotated to start at its smallest corner.
std::set<Triangle> triangles(const std::string& ply) {
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

std::string whole(const Inputs& in, const fs::path& dir) {
  pipeline::BuildOptions o;
  o.inputs = in.points;
  o.contours = in.contours;
  o.output = (dir / "whole.ply").string();
  o.write.overwrite = true;
  pipeline::build(o);
  return o.output;
}

std::string plan(const Inputs& in, const fs::path& dir, double size, double buffer,
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
std::string build_tile(const std::string& plan_path, std::int64_t tile, const fs::path& dir,
                       double resolution = 0) {
  tiles::TileOptions t;
  t.plan = plan_path;
  t.tile = tile;
  pipeline::BuildOptions o;
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
std::string tiled(const Inputs& in, const fs::path& dir, double size, double buffer,
                  double rim = -1) {
  const std::string p = plan(in, dir, size, buffer, rim);
  const std::size_t n = tiles::read_plan(p).tiles.size();
  std::vector<std::string> tiles;
  for (std::size_t i = 0; i < n; ++i)
    tiles.push_back(build_tile(p, static_cast<std::int64_t>(i), dir));
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

void expect_same_tin(const std::string& whole_ply, const std::string& merged_ply) {
  const std::set<Triangle> a = triangles(whole_ply), b = triangles(merged_ply);
  EXPECT_EQ(a.size(), b.size());
  std::size_t missing = 0, extra = 0;
  for (const Triangle& t : a) missing += b.count(t) == 0;
  for (const Triangle& t : b) extra += a.count(t) == 0;
  EXPECT_EQ(missing, 0u) << "triangles of the whole TIN missing from the merged tiles";
  EXPECT_EQ(extra, 0u) << "triangles of the merged tiles not in the whole TIN";
}

// ---- DEMs ---------------------------------------------------------------------------------------

struct Raster {
  double gt[6] = {};
  int width = 0, height = 0;
  double nodata = 0;
  std::vector<float> cells;
};

Raster read_raster(const std::string& path) {
  GDALAllRegister();
  const GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  Raster r;
  if (!ds) {
    ADD_FAILURE() << "cannot open " << path;
    return r;
  }
  ds->GetGeoTransform(r.gt);
  r.width = ds->GetRasterXSize();
  r.height = ds->GetRasterYSize();
  GDALRasterBand* band = ds->GetRasterBand(1);
  r.nodata = band->GetNoDataValue();
  r.cells.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height));
  EXPECT_EQ(band->RasterIO(GF_Read, 0, 0, r.width, r.height, r.cells.data(), r.width, r.height,
                           GDT_Float32, 0, 0),
            CE_None);
  return r;
}

// The whole job's DEM over the plan's full tile grid against every tile's DEM, cell for cell at
// the same georeferenced places: each tile's DEM is its box, on the whole grid's cell lattice,
// with the whole job's values; the tiles cover the whole grid once, except tiles the plan leaves
// out (no data near them), which are nodata in the whole DEM.
void expect_tiles_make_the_whole_dem(const Inputs& in, const fs::path& dir, double size,
                                     double buffer, double resolution) {
  const std::string p = plan(in, dir, size, buffer);
  const tiles::TilePlan tp = tiles::read_plan(p);
  std::int64_t c0 = INT64_MAX, c1 = INT64_MIN, r0 = INT64_MAX, r1 = INT64_MIN;
  for (const tiles::PlanTile& t : tp.tiles) {
    c0 = std::min(c0, t.col);
    c1 = std::max(c1, t.col);
    r0 = std::min(r0, t.row);
    r1 = std::max(r1, t.row);
  }
  pipeline::BuildOptions o;
  o.inputs = in.points;
  o.contours = in.contours;
  o.output = (dir / "whole.ply").string();
  o.dem.path = (dir / "whole.tif").string();
  o.dem.resolution = resolution;
  o.dem.extent = BBox{static_cast<double>(c0) * size, static_cast<double>(r0) * size,
                      static_cast<double>(c1 + 1) * size, static_cast<double>(r1 + 1) * size};
  o.write.overwrite = true;
  pipeline::build(o);
  const Raster w = read_raster(o.dem.path);
  const auto cells = static_cast<int>(std::lround(size / resolution));
  ASSERT_EQ(w.width, (c1 - c0 + 1) * cells);
  ASSERT_EQ(w.height, (r1 - r0 + 1) * cells);

  std::vector<int> covered(w.cells.size(), 0);
  std::size_t compared = 0, with_value = 0;
  for (const tiles::PlanTile& t : tp.tiles) {
    SCOPED_TRACE("tile " + std::to_string(t.index));
    build_tile(p, t.index, dir, resolution);
    const Raster r = read_raster((dir / ("tile_" + std::to_string(t.index) + ".tif")).string());
    ASSERT_EQ(r.width, cells);
    ASSERT_EQ(r.height, cells);
    EXPECT_EQ(r.gt[0], static_cast<double>(t.col) * size);
    EXPECT_EQ(r.gt[3], static_cast<double>(t.row + 1) * size);
    EXPECT_EQ(r.gt[1], resolution);
    EXPECT_EQ(r.gt[5], -resolution);
    EXPECT_EQ(r.nodata, w.nodata);
    // Where the tile's top-left cell is in the whole grid: a whole number of cells.
    const double fx = (r.gt[0] - w.gt[0]) / resolution, fy = (w.gt[3] - r.gt[3]) / resolution;
    const auto ox = static_cast<int>(std::lround(fx)), oy = static_cast<int>(std::lround(fy));
    ASSERT_NEAR(fx, ox, 1e-9);
    ASSERT_NEAR(fy, oy, 1e-9);
    std::size_t differ = 0;
    for (int row = 0; row < r.height; ++row)
      for (int col = 0; col < r.width; ++col) {
        const std::size_t k =
            static_cast<std::size_t>(oy + row) * static_cast<std::size_t>(w.width) +
            static_cast<std::size_t>(ox + col);
        const float a = w.cells[k], b = r.cells[static_cast<std::size_t>(row) * r.width + col];
        ++covered[k];
        ++compared;
        with_value += a != w.nodata;
        if (a != b && ++differ <= 3)
          ADD_FAILURE() << "cell (" << col << ", " << row << "): whole " << a << ", tile " << b;
      }
    EXPECT_EQ(differ, 0u);
  }
  for (std::size_t k = 0; k < covered.size(); ++k) {
    EXPECT_LE(covered[k], 1);
    if (covered[k] == 0) {
      EXPECT_EQ(w.cells[k], w.nodata) << "cell " << k << " in no tile";
    }
  }
  EXPECT_GT(with_value, compared / 2);
}

fs::path scratch() {
  return test::scratch_dir("tiles");
}

std::string shared(const std::string& rel) {
  return (fs::path(::tincdt::test::shared_data()) / rel).string();
}

// ---- the merged tiles are the whole TIN
// ----------------------------------------------------------

TEST(Tiles, RandomPointsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, 500000, 4000000, 300, 1))},
                  {}};
  const std::string w = whole(in, dir);
  for (const double size : {100.0, 70.0}) {  // 9 tiles aligned with the data, 25 across it
    SCOPED_TRACE(size);
    expect_same_tin(w, tiled(in, dir, size, 40));
  }
}

TEST(Tiles, FilesSplitAndShuffledGiveTheSameTin) {
  const fs::path dir = scratch();
  std::vector<Point3> pts = random_points(2500, 500000, 4000000, 240, 2);
  const std::string w = whole({{write_xyz(dir / "all.xyz", pts)}, {}}, dir);
  // Quadrant files, each point in the file of its quadrant, shuffled.
  std::shuffle(pts.begin(), pts.end(), std::mt19937_64(3));
  std::vector<std::vector<Point3>> parts(4);
  for (const Point3& p : pts)
    parts[(p.x >= 500120 ? 1 : 0) + (p.y >= 4000120 ? 2 : 0)].push_back(p);
  Inputs in;
  for (int k = 0; k < 4; ++k)
    in.points.push_back(write_xyz(dir / ("part" + std::to_string(k) + ".xyz"), parts[k]));
  expect_same_tin(w, tiled(in, dir, 60, 40));
  expect_same_tin(w, whole(in, dir));
}

TEST(Tiles, ContourLinesMatchTheWholeTin) {
  const fs::path dir = scratch();
  Inputs in{{write_xyz(dir / "points.xyz", random_points(1500, 500000, 4000000, 300, 4))},
            {write_rings(dir / "rings.geojson", 500150, 4000150, {20, 45, 70, 95, 120})}};
  const std::string w = whole(in, dir);
  expect_same_tin(w, tiled(in, dir, 100, 60));
}

TEST(Tiles, TopographyWithItsContoursMatchesTheWholeTin) {
  if (!fs::exists(shared("las/Topography.las"))) GTEST_SKIP() << "no shared data";
  const fs::path dir = scratch();
  const Inputs in{{shared("las/Topography.las")},
                  {shared("pair_topography/Topography_contours_1m_3d.shp")}};
  const std::string w = whole(in, dir);
  expect_same_tin(w, tiled(in, dir, 100, 130));
  // A plan whose buffer is too small for some tiles (40: tile 1 asks for 73): each such tile
  // reads more until it is settled, and the whole is the same.
  expect_same_tin(w, tiled(in, dir, 100, 40));
}

// Cocircular ties: the same triangles need ties broken by a rule of the points alone
// (symbolic perturbation).
TEST(Tiles, LatticeMatchesTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "grid.xyz", lattice(60, 500000, 4000000, 2))}, {}};
  const std::string w = whole(in, dir);
  // Circumradius 1.41: a buffer of a few steps settles every triangle, though the rim's columns
  // fall on tile edges (the large triangles between the buffer and the rim are not near a tile).
  for (const double buffer : {10.0, 3.0}) {
    SCOPED_TRACE(buffer);
    expect_same_tin(w, tiled(in, dir, 30, buffer));
  }
}

TEST(Tiles, CentimetrePointsMatchTheWholeTin) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "cm.xyz", centimetre_points(4000, 500000, 4000000, 120, 5))},
                  {}};
  expect_same_tin(whole(in, dir), tiled(in, dir, 40, 20));
}

// ---- refusals
// -------------------------------------------------------------------------------------

template <class E, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(Tiles, TooSmallABufferNamesTheTileAndWhatItNeeds) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, 500000, 4000000, 300, 6))},
                  {}};
  const std::string p = plan(in, dir, 100, 1);
  tiles::TileOptions t;
  t.plan = p;
  t.tile = 4;
  t.buffer_fixed = true;  // else it grows
  pipeline::BuildOptions o;
  o.output = (dir / "tile_4.ply").string();
  const std::string e = error_of<InputError>([&] { tiles::build_tile(t, o); });
  EXPECT_NE(e.find("plan.json: tile 4: buffer 1 is too small"), std::string::npos) << e;
  EXPECT_NE(e.find("is needed"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir / "tile_4.ply"));
}

TEST(Tiles, ABufferTooSmallGrowsUntilEveryTriangleIsFinal) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, 500000, 4000000, 300, 6))},
                  {}};
  const std::string w = whole(in, dir);
  expect_same_tin(w, tiled(in, dir, 100, 1));
  // The buffer read is in the stats: more than the plan's.
  tiles::TileOptions t;
  t.plan = (dir / "plan.json").string();
  t.tile = 4;
  pipeline::BuildOptions o;
  o.output = (dir / "t4.ply").string();
  o.write.overwrite = true;
  std::vector<std::string> lines;
  const pipeline::LogFn log = [&](int, const std::string& line) { lines.push_back(line); };
  const pipeline::BuildReport r = tiles::build_tile(t, o, nullptr, log);
  ASSERT_EQ(r.figures.size(), 1u);
  EXPECT_EQ(r.figures[0].first, "buffer");
  EXPECT_GT(r.figures[0].second, 1);
  EXPECT_LE(r.figures[0].second, 100);
  bool said = false;
  for (const std::string& line : lines)
    said = said || line.find("tile 4: buffer 1 is too small; reading to ") != std::string::npos;
  EXPECT_TRUE(said);
  // Up to --max-buffer only.
  t.max_buffer = 1.5;
  const auto capped = [&] { tiles::build_tile(t, o); };
  EXPECT_NE(error_of<tiles::BufferTooSmall>(capped).find("may grow to 1.5 at the most"),
            std::string::npos);
}

TEST(Tiles, AMissingTileAndAChangedInputAreRefused) {
  const fs::path dir = scratch();
  const std::string xyz =
      write_xyz(dir / "points.xyz", random_points(500, 500000, 4000000, 100, 7));
  const std::string p = plan({{xyz}, {}}, dir, 50, 20);
  std::string e = error_of<InputError>([&] { build_tile(p, 99, dir); });
  EXPECT_NE(e.find("no tile 99: the plan has tiles 0 to 3"), std::string::npos) << e;
  test::spit(xyz, test::slurp(xyz) + "500050 4000050 7\n");
  e = error_of<InputError>([&] { build_tile(p, 0, dir); });
  EXPECT_NE(e.find("has changed since the plan was made"), std::string::npos) << e;
  test::spit(dir / "plan.json", "{\"tincdt_plan\": 1}");
  e = error_of<InputError>([&] { build_tile(p, 0, dir); });
  EXPECT_NE(e.find("not a valid tincdt plan"), std::string::npos) << e;
}

TEST(Tiles, OptionsThatCannotBeTiledAreRefused) {
  const fs::path dir = scratch();
  const std::string p = plan(
      {{write_xyz(dir / "p.xyz", random_points(300, 500000, 4000000, 100, 8))}, {}}, dir, 50, 20);
  tiles::TileOptions t;
  t.plan = p;
  t.tile = 0;
  pipeline::BuildOptions o;
  o.output = (dir / "t.ply").string();
  o.max_edge = 10;
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("--max-edge"),
            std::string::npos);
  o.max_edge = 0;
  o.max_error = 0.1;
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("--max-error"),
            std::string::npos);
  o.max_error.reset();
  o.inputs = {"p.xyz"};
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("come from the plan"),
            std::string::npos);
}

TEST(Tiles, CrossingLinesAreRefused) {
  const fs::path dir = scratch();
  std::vector<test::VectorLayer> layers(1);
  layers[0].name = "lines";
  layers[0].features = {{"LINESTRING Z (500010 4000010 1, 500090 4000090 2)", 1},
                        {"LINESTRING Z (500010 4000090 3, 500090 4000010 4)", 2}};
  const Inputs in{{write_xyz(dir / "p.xyz", random_points(300, 500000, 4000000, 100, 9))},
                  {test::write_vector(dir / "x.geojson", layers, "GeoJSON", "NAME")}};
  const std::string p = plan(in, dir, 50, 20);
  const std::string e = error_of<InputError>([&] { build_tile(p, 0, dir); });
  EXPECT_NE(e.find("crosses"), std::string::npos) << e;
  EXPECT_NE(e.find("need contours and hard lines that do not cross"), std::string::npos) << e;
}

TEST(Tiles, MergeFindsAMissingTileAndAnOverlap) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "p.xyz", random_points(2000, 500000, 4000000, 200, 10))}, {}};
  const std::string p = plan(in, dir, 100, 40);
  std::vector<std::string> tiles;
  for (int i = 0; i < 4; ++i) tiles.push_back(build_tile(p, i, dir));
  tiles::MergeOptions m;
  m.output = (dir / "merged.ply").string();
  m.inputs = {tiles[0], tiles[1], tiles[3]};  // tile 2 missing: a hole in the hull
  std::string e = error_of<InputError>([&] { tiles::merge_tiles(m); });
  EXPECT_NE(e.find("crack"), std::string::npos) << e;
  m.inputs = {tiles[0], tiles[1], tiles[2], tiles[3], tiles[1]};  // tile 1 twice
  e = error_of<InputError>([&] { tiles::merge_tiles(m); });
  EXPECT_NE(e.find("overlap"), std::string::npos) << e;
  m.check_only = true;
  m.output.clear();
  e = error_of<InputError>([&] { tiles::merge_tiles(m); });
  EXPECT_NE(e.find("overlap"), std::string::npos) << e;
  m.inputs = {tiles[0], tiles[2], tiles[3]};
  e = error_of<InputError>([&] { tiles::merge_tiles(m); });
  EXPECT_NE(e.find("crack"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir / "merged.ply"));
}

// ---- DEM tiles join pixel-aligned into the whole job's DEM

TEST(TileDems, RandomPointsMatchTheWholeDem) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, 500000, 4000000, 300, 11))},
                  {}};
  expect_tiles_make_the_whole_dem(in, dir, 70, 40, 1);
  expect_tiles_make_the_whole_dem(in, dir, 100, 40, 0.5);
}

// Cell centres on the lattice's diagonals: ties between two triangles, decided alike.
TEST(TileDems, LatticeMatchesTheWholeDem) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "grid.xyz", lattice(60, 500000, 4000000, 2))}, {}};
  expect_tiles_make_the_whole_dem(in, dir, 30, 10, 1);
}

TEST(TileDems, ContoursMatchTheWholeDem) {
  const fs::path dir = scratch();
  Inputs in{{write_xyz(dir / "points.xyz", random_points(1500, 500000, 4000000, 300, 12))},
            {write_rings(dir / "rings.geojson", 500150, 4000150, {20, 45, 70, 95, 120})}};
  expect_tiles_make_the_whole_dem(in, dir, 100, 60, 1);
}

TEST(TileDems, AResolutionThatDoesNotDivideTheTileOrAnExtentIsRefused) {
  const fs::path dir = scratch();
  const std::string p = plan(
      {{write_xyz(dir / "p.xyz", random_points(300, 500000, 4000000, 100, 13))}, {}}, dir, 50, 20);
  tiles::TileOptions t;
  t.plan = p;
  t.tile = 0;
  pipeline::BuildOptions o;
  o.output = (dir / "t.ply").string();
  o.dem.path = (dir / "t.tif").string();
  o.dem.resolution = 0.7;
  const std::string e = error_of<UsageError>([&] { tiles::build_tile(t, o); });
  EXPECT_NE(e.find("--resolution 0.7 does not divide the plan's tile size 50"), std::string::npos)
      << e;
  o.dem.resolution = 1;
  o.dem.extent = BBox{500000, 4000000, 500050, 4000050};
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("--dem-extent"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "t.tif"));
}

// A tile job runs the pipeline's stages with the tile stage after the last that removes
// triangles; the pipeline's own table has no tile stage.
TEST(Tiles, TheTileStageFollowsThePolygonStages) {
  std::vector<std::string> pipeline_names, tile_names;
  for (const pipeline::Stage* s : pipeline::stages()) pipeline_names.emplace_back(s->name);
  for (const pipeline::Stage* s : tiles::tile_stages()) tile_names.emplace_back(s->name);
  EXPECT_EQ(std::count(pipeline_names.begin(), pipeline_names.end(), "tile"), 0);
  const auto erase = std::find(pipeline_names.begin(), pipeline_names.end(), "erase");
  ASSERT_NE(erase, pipeline_names.end());
  pipeline_names.insert(erase + 1, "tile");
  EXPECT_EQ(tile_names, pipeline_names);
}

}  // namespace
