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
#include "tile_runs.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"
#include "tiles/tile_job.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

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
                                     double buffer, double resolution,
                                     const pipeline::BuildOptions& base = no_options()) {
  const std::string p = plan(in, dir, size, buffer);
  const tiles::TilePlan tp = tiles::read_plan(p);
  std::int64_t c0 = INT64_MAX, c1 = INT64_MIN, r0 = INT64_MAX, r1 = INT64_MIN;
  for (const tiles::PlanTile& t : tp.tiles) {
    c0 = std::min(c0, t.col);
    c1 = std::max(c1, t.col);
    r0 = std::min(r0, t.row);
    r1 = std::max(r1, t.row);
  }
  pipeline::BuildOptions o = base;
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
    build_tile(p, t.index, dir, resolution, base);
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
  o.max_vertices = 100;
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("--max-vertices"),
            std::string::npos);
  o.max_vertices = 0;
  o.inputs = {"p.xyz"};
  EXPECT_NE(error_of<UsageError>([&] { tiles::build_tile(t, o); }).find("come from the plan"),
            std::string::npos);
}

// --max-edge: the merged tiles are the whole job's trimmed TIN.
TEST(Tiles, TrimmedTilesHoldTheWholeTrimmedTin) {
  const fs::path dir = scratch();
  const Inputs in = gapped_points(dir);
  pipeline::BuildOptions trim;
  trim.max_edge = 12;
  const std::string w = whole(in, dir, trim);
  fs::create_directories(dir / "untrimmed");
  const std::set<Triangle> untrimmed = triangles(whole(in, dir / "untrimmed"));
  const std::set<Triangle> whole_trimmed = triangles(w);
  ASSERT_GT(untrimmed.size(), whole_trimmed.size() + 100);  // the bay and the gap are trimmed
  for (const double size : {100.0, 70.0}) {
    SCOPED_TRACE(size);
    // Tiles, their outlines and the merge checked and merged: the whole job's TIN, its holes
    // and bays included.
    const std::string merged = tiled(in, dir, size, 10, -1, trim);
    expect_same_tin(w, merged);
    EXPECT_EQ(io::read_ply(merged).edges.size(), io::read_ply(w).edges.size());
    // A missing tile leaves a hole that closes like a trimmed area: the marks count the tiles.
    tiles::MergeOptions check;
    check.check_only = true;
    const std::size_t n = tiles::read_plan((dir / "plan.json").string()).tiles.size();
    for (std::size_t i = 0; i < n; ++i)
      check.inputs.push_back((dir / ("tile_" + std::to_string(i) + ".ply")).string());
    EXPECT_TRUE(tiles::merge_tiles(check).trimmed);
    check.inputs.erase(check.inputs.begin() + 1);
    EXPECT_NE(error_of<InputError>([&] {
                tiles::merge_tiles(check);
              }).find("tile 1 of its plan's " + std::to_string(n) + " is missing"),
              std::string::npos);
    check.inputs.push_back(check.inputs.front());
    EXPECT_NE(error_of<InputError>([&] { tiles::merge_tiles(check); }).find("holds tile 0 again"),
              std::string::npos);
  }
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

// Clipped and erased areas are nodata in the tiles' DEMs as in the whole DEM: the neighbours'
// final triangles a tile rasterizes too are clipped and erased like its own.
TEST(TileDems, ClippedTilesMatchTheWholeClippedDem) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(2000, 500000, 4000000, 300, 13))},
                  {write_rings(dir / "rings.geojson", 500150, 4000150, {40, 90})}};
  const auto polygons = [&dir](const std::string& name, const std::string& wkt) {
    std::vector<test::VectorLayer> layers(1);
    layers[0].name = name;
    layers[0].features.push_back({wkt, 0});
    return test::write_vector(dir / (name + ".geojson"), layers, "GeoJSON", "NAME");
  };
  pipeline::BuildOptions o;
  o.clip = {polygons("clip",
                     "POLYGON ((500020.5 4000031.25, 500270.75 4000012.5, "
                     "500288.25 4000240.5, 500041.5 4000290.75, 500020.5 4000031.25))")};
  o.erase = {polygons("erase",
                      "POLYGON ((500090.5 4000110.25, 500160.75 4000095.5, "
                      "500172.25 4000180.5, 500103.5 4000166.75, 500090.5 4000110.25))")};
  expect_tiles_make_the_whole_dem(in, dir, 100, 30, 1, o);
}

// Trimmed areas are nodata in the tiles' DEMs as in the whole DEM.
TEST(TileDems, TrimmedTilesMatchTheWholeTrimmedDem) {
  const fs::path dir = scratch();
  pipeline::BuildOptions trim;
  trim.max_edge = 12;
  expect_tiles_make_the_whole_dem(gapped_points(dir), dir, 100, 10, 1, trim);
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
  // A pyramid's coarse tiles span the plan's tiles: it is built from the merged TIN.
  o.dem = {};
  o.terrain.path = (dir / "web").string();
  const std::string terrain = error_of<UsageError>([&] { tiles::build_tile(t, o); });
  EXPECT_NE(terrain.find("--terrain cannot be used with --plan"), std::string::npos) << terrain;
  EXPECT_FALSE(fs::exists(dir / "web"));
}

// A tile job runs the pipeline's stages with the tile stage after the last that removes
// triangles, and without the simplify and trim stages (the tile stage does both); the
// pipeline's own table has no tile stage.
// The tile stage proves the triangles final before replace, clip and erase classify them; the
// outline is written once they are done.
TEST(Tiles, TheTileStageComesBeforeThePolygonStagesAndTheOutlineAfter) {
  std::vector<std::string> pipeline_names, tile_names;
  for (const pipeline::Stage* s : pipeline::stages()) pipeline_names.emplace_back(s->name);
  for (const pipeline::Stage* s : tiles::tile_stages()) tile_names.emplace_back(s->name);
  EXPECT_EQ(std::count(pipeline_names.begin(), pipeline_names.end(), "tile"), 0);
  const auto erase = std::find(pipeline_names.begin(), pipeline_names.end(), "erase");
  ASSERT_NE(erase, pipeline_names.end());
  pipeline_names.insert(erase + 1, "tile_outline");
  const auto replace = std::find(pipeline_names.begin(), pipeline_names.end(), "replace");
  ASSERT_NE(replace, pipeline_names.end());
  pipeline_names.insert(replace, "tile");
  std::erase(pipeline_names, "simplify");
  std::erase(pipeline_names, "trim");
  EXPECT_EQ(tile_names, pipeline_names);
}

}  // namespace
