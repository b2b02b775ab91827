// --terrain DIR from the command line: the quantized-mesh pyramid read back tile by tile (the
// tests' decoder and the independent npm @here/quantized-mesh-decoder), each tile within its
// level's error of the full TIN of the same run, its rectangle covered exactly, neighbours sharing
// their border vertices, layer.json and the metadata naming exactly the tiles written, the same
// bytes from two runs; and the uses refused. On the sample data, and on the shared data's
// pair_topography (with its contours) and autzen_trim.laz (in feet) when present.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "core/json.hpp"
#include "core/number_text.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"
#include "support/web_tools.hpp"
#include "terrain_support.hpp"

namespace tincdt::test::terrain {
namespace {

namespace fs = std::filesystem;

// The sample's ground: its other classes (buildings, trees) put points closer than a tile's
// quantization step at very different heights, which no tile can meet.
const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las' --keep-class '2";
const std::string kContours = std::string(TINCDT_SOURCE_DIR) + "/data/sample_contours.shp";

const json::Value& at(const json::Value& v, const char* key) {
  const json::Value* m = v.find(key);
  if (m == nullptr) throw std::runtime_error(std::string("no member ") + key);
  return *m;
}

// layer.json names exactly the levels and tiles of PYRAMID, its bounds hold every vertex of
// FULL, and it announces the two extensions, with metadataAvailability 1 (each tile's metadata
// lists its children), without which CesiumJS fails on the first tile it reads.
void expect_layer_matches(const json::Value& layer, const std::map<Key, DecodedTile>& pyramid,
                          const std::vector<std::array<double, 3>>& full, int min, int max) {
  EXPECT_EQ(at(layer, "format").string(), "quantized-mesh-1.0");
  EXPECT_EQ(at(layer, "scheme").string(), "tms");
  EXPECT_EQ(at(layer, "projection").string(), "EPSG:4326");
  EXPECT_EQ(at(layer, "minzoom").number(), min);
  EXPECT_EQ(at(layer, "maxzoom").number(), max);
  std::vector<std::string> extensions;
  for (const auto& e : at(layer, "extensions").items()) extensions.push_back(e.string());
  EXPECT_EQ(extensions, (std::vector<std::string>{"octvertexnormals", "metadata"}));
  EXPECT_EQ(at(layer, "metadataAvailability").number(), 1);
  const auto& b = at(layer, "bounds").items();
  for (const auto& p : full) {
    EXPECT_GE(p[0], b[0].number());
    EXPECT_GE(p[1], b[1].number());
    EXPECT_LE(p[0], b[2].number());
    EXPECT_LE(p[1], b[3].number());
  }
  std::set<Key> listed;
  const auto& available = at(layer, "available").items();
  ASSERT_EQ(available.size(), static_cast<std::size_t>(max + 1));
  for (int z = 0; z <= max; ++z) {
    EXPECT_EQ(available[z].items().empty(), z < min) << "level " << z;
    for (const auto& range : available[z].items())
      for (auto x = static_cast<std::uint32_t>(at(range, "startX").number());
           x <= at(range, "endX").number(); ++x)
        for (auto y = static_cast<std::uint32_t>(at(range, "startY").number());
             y <= at(range, "endY").number(); ++y)
          listed.insert({z, x, y});
  }
  std::set<Key> written;
  for (const auto& [key, tile] : pyramid) written.insert(key);
  EXPECT_EQ(listed, written);
}

// TILE covers its square exactly (counter-clockwise triangles whose areas add up to it), lists
// every vertex on each side, carries a normal a vertex, and its metadata names its children.
void expect_tile_well_formed(const Key& key, const DecodedTile& tile,
                             const std::map<Key, DecodedTile>& pyramid) {
  SCOPED_TRACE(std::to_string(key.z) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y));
  std::int64_t twice_area = 0;
  for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3) {
    const auto a = tile.indices[t], b = tile.indices[t + 1], c = tile.indices[t + 2];
    const std::int64_t cross = std::int64_t{tile.u[b] - tile.u[a]} * (tile.v[c] - tile.v[a]) -
                               std::int64_t{tile.v[b] - tile.v[a]} * (tile.u[c] - tile.u[a]);
    EXPECT_GT(cross, 0);
    twice_area += cross;
  }
  EXPECT_EQ(twice_area, std::int64_t{32767} * 32767 * 2);
  for (int side = 0; side < 4; ++side) {
    std::set<std::uint32_t> listed(tile.sides[side].begin(), tile.sides[side].end());
    std::set<std::uint32_t> on;
    for (std::uint32_t i = 0; i < tile.u.size(); ++i)
      if ((side == 0 && tile.u[i] == 0) || (side == 1 && tile.v[i] == 0) ||
          (side == 2 && tile.u[i] == 32767) || (side == 3 && tile.v[i] == 32767))
        on.insert(i);
    EXPECT_EQ(listed, on) << "side " << side;
  }
  ASSERT_TRUE(tile.normals.has_value());
  EXPECT_EQ(tile.normals->size(), tile.u.size());
  ASSERT_TRUE(tile.metadata.has_value());
  std::set<Key> children;
  for (std::uint32_t dx = 0; dx < 2; ++dx)
    for (std::uint32_t dy = 0; dy < 2; ++dy)
      if (pyramid.count({key.z + 1, 2 * key.x + dx, 2 * key.y + dy}))
        children.insert({key.z + 1, 2 * key.x + dx, 2 * key.y + dy});
  const json::Value meta = json::parse(*tile.metadata);
  std::set<Key> named;
  for (const auto& level : at(meta, "available").items())
    for (const auto& range : level.items())
      for (auto x = static_cast<std::uint32_t>(at(range, "startX").number());
           x <= at(range, "endX").number(); ++x)
        for (auto y = static_cast<std::uint32_t>(at(range, "startY").number());
             y <= at(range, "endY").number(); ++y)
          named.insert({key.z + 1, x, y});
  EXPECT_EQ(named, children);
}

// Two tiles side by side hold the same vertices along their common side, at heights within their
// quantization steps.
void expect_same_border(const DecodedTile& a, int side_a, const DecodedTile& b, int side_b) {
  const auto sa = side_of(a, side_a), sb = side_of(b, side_b);
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) {
    EXPECT_EQ(sa[i].first, sb[i].first);
    EXPECT_NEAR(sa[i].second, sb[i].second, half_step(a) + half_step(b) + 1e-9);
  }
}

// Every pair of neighbours of a level shares its border; returns how many pairs there were.
std::size_t expect_no_cracks(const std::map<Key, DecodedTile>& pyramid) {
  std::size_t pairs = 0;
  for (const auto& [key, tile] : pyramid) {
    SCOPED_TRACE(std::to_string(key.z) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y));
    if (auto east = pyramid.find({key.z, key.x + 1, key.y}); east != pyramid.end()) {
      expect_same_border(tile, 2, east->second, 0);
      ++pairs;
    }
    if (auto north = pyramid.find({key.z, key.x, key.y + 1}); north != pyramid.end()) {
      expect_same_border(tile, 3, north->second, 1);
      ++pairs;
    }
  }
  return pairs;
}

// The pyramid in DIR/t against the full TIN DIR/full.ply (.prj): everything above, each level
// within its error; prints the levels' figures under NAME.
void expect_pyramid(const std::string& dir, int min, int max, const std::string& name) {
  const auto pyramid = read_pyramid(dir + "/t");
  const auto full = lon_lat_metres(dir + "/full.ply", dir + "/full.prj");
  const json::Value layer = json::parse(slurp(dir + "/t/layer.json"));
  expect_layer_matches(layer, pyramid, full, min, max);
  for (const auto& [key, tile] : pyramid) expect_tile_well_formed(key, tile, pyramid);
  if (max > min) {
    EXPECT_GT(expect_no_cracks(pyramid), 0u);
  }
  for (const auto& [z, e] : level_errors(pyramid, full)) {
    std::cout << name << " level " << z << ": " << e.tiles << " tiles, " << e.vertices
              << " vertices, max error " << e.max << " m (allowed " << level_error(z) << "), RMSE "
              << e.rmse() << " m over " << e.points << " TIN vertices\n";
    EXPECT_LE(e.max, level_error(z)) << "level " << z;
    EXPECT_GT(e.points, 0u);
  }
}

// The contours of the run (the PLY's constrained edges) follow edges of the tiles of level Z:
// each one's midpoint within the level's error of a tile edge (Douglas–Peucker's tolerance).
void expect_lines_are_edges(const std::string& dir, int z) {
  const auto pyramid = read_pyramid(dir + "/t");
  const auto full = lon_lat_metres(dir + "/full.ply", dir + "/full.prj");
  const auto edges = constrained_edges(dir + "/full.ply");
  ASSERT_GT(edges.size(), 100u);
  const double farthest = farthest_line_from_tile_edges(pyramid, z, full, edges);
  std::cout << "contour edges: farthest from a tile edge at level " << z << ": " << farthest
            << " m\n";
  EXPECT_LE(farthest, level_error(z));
}

// tincdt on the sample in DIR, writing the pyramid t with OPTIONS.
ShellRun terrain_of_sample(const std::string& dir, const std::string& options) {
  return run_tincdt(dir, "'" + kSample + "' --terrain t " + options);
}

TEST(TerrainCli, SamplePyramidWithinErrorsWithoutCracks) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r = run_tincdt(
      dir, "'" + kSample + "' --contours '" + kContours + "' -o full.ply --ply-ascii --terrain t");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const json::Value layer = json::parse(slurp(dir + "/t/layer.json"));
  const int max = static_cast<int>(at(layer, "maxzoom").number());
  EXPECT_GE(max, 15);  // the sample's points are a few metres apart
  expect_pyramid(dir, 0, max, "sample");
  expect_lines_are_edges(dir, max);
}

TEST(TerrainCli, LevelsChosenAndNoTinFileNeeded) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r = terrain_of_sample(dir, "--terrain-levels 0-3");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"t"});
  EXPECT_EQ(names_in(dir + "/t"), (std::set<std::string>{"0", "1", "2", "3", "layer.json"}));
}

TEST(TerrainCli, SameBytesFromTwoRuns) {
  const std::string dir = scratch_dir("terrain_cli");
  const std::string input = "'" + kSample + "' --contours '" + kContours + "'";
  ASSERT_EQ(run_tincdt(dir, input + " --terrain a --threads 1").exit_code, 0);
  ASSERT_EQ(run_tincdt(dir, input + " --terrain b --threads 2").exit_code, 0);
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir + "/a")) {
    if (!e.is_regular_file()) continue;
    const fs::path other = dir + "/b/" + fs::relative(e.path(), dir + "/a").string();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(slurp(e.path()), slurp(other)) << other;
    ++files;
  }
  EXPECT_GT(files, 10u);
}

TEST(TerrainCli, FillHeightBeyondTheData) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r = terrain_of_sample(dir, "--terrain-levels 0-0 --terrain-fill-height 12.5");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  // The data is far inside its root tile: both roots are the fill, flat at 12.5 m.
  const auto pyramid = read_pyramid(dir + "/t");
  EXPECT_EQ(pyramid.size(), 2u);
  for (const auto& [key, tile] : pyramid) {
    EXPECT_EQ(tile.minimum_height, 12.5f);
    EXPECT_EQ(tile.maximum_height, 12.5f);
    EXPECT_EQ(tile.u.size(), 4u);
  }
  EXPECT_EQ(r.messages.find("terrain fill height"), std::string::npos) << r.messages;
}

// By default the fill is the TIN's lowest height, said in the log: the ramps from the data's edge
// to it stay within the data's relief where tiles of two levels meet.
TEST(TerrainCli, FillHeightDefaultsToTheTinsLowest) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r =
      run_tincdt(dir, "'" + kSample + "' -o full.ply --ply-ascii --terrain t --terrain-levels 0-0");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  double lowest = INFINITY;
  for (const auto& p : read_mesh(dir + "/full.ply").v) lowest = std::min(lowest, p[2]);
  EXPECT_NE(
      r.messages.find("terrain fill height: " + number_text(lowest) + " m (the TIN's lowest)"),
      std::string::npos)
      << r.messages;
  const auto pyramid = read_pyramid(dir + "/t");
  EXPECT_EQ(pyramid.size(), 2u);  // both roots, the data far inside one
  for (const auto& [key, tile] : pyramid) {
    EXPECT_NEAR(tile.minimum_height, lowest, 1e-3) << key.z << "/" << key.x;
    EXPECT_NEAR(tile.maximum_height, lowest, 1e-3) << key.z << "/" << key.x;
  }
}

TEST(TerrainCli, NpmDecoderReadsEveryTile) {
  TINCDT_REQUIRE_WEB_TOOL("@here/quantized-mesh-decoder");
  const std::string dir = scratch_dir("terrain_cli");
  ASSERT_EQ(
      run_tincdt(dir, "'" + kSample + "' --contours '" + kContours + "' --terrain t").exit_code, 0);
  const std::string out = dir + "/decoded.txt";
  const std::string command = "node '" TINCDT_DECODE_PYRAMID_SCRIPT "' '" + web_tools().string() +
                              "' '" + dir + "/t' > '" + out + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const auto pyramid = read_pyramid(dir + "/t");
  std::istringstream lines(slurp(out));
  std::size_t read = 0;
  std::string name;
  std::size_t n = 0, triangles = 0, west = 0, south = 0, east = 0, north = 0, normals = 0,
              metadata = 0;
  while (lines >> name >> n >> triangles >> west >> south >> east >> north >> normals >> metadata) {
    SCOPED_TRACE(name);
    const auto first = name.find('/'), second = name.rfind('/');
    const Key key{std::stoi(name.substr(0, first)),
                  static_cast<std::uint32_t>(std::stoul(name.substr(first + 1, second))),
                  static_cast<std::uint32_t>(std::stoul(name.substr(second + 1)))};
    const DecodedTile& tile = pyramid.at(key);
    EXPECT_EQ(n, tile.u.size());
    EXPECT_EQ(triangles, tile.indices.size() / 3);
    EXPECT_EQ(west, tile.sides[0].size());
    EXPECT_EQ(south, tile.sides[1].size());
    EXPECT_EQ(east, tile.sides[2].size());
    EXPECT_EQ(north, tile.sides[3].size());
    EXPECT_EQ(normals, n);
    EXPECT_GT(metadata, 0u);
    ++read;
  }
  EXPECT_EQ(read, pyramid.size());
}

TEST(TerrainCli, UsesRefused) {
  const std::string dir = scratch_dir("terrain_cli");
  const std::pair<std::string, std::string> cases[] = {
      {"--terrain t --terrain-levels 5", "--terrain-levels"},
      {"--terrain t --terrain-levels 3-2", "MIN-MAX"},
      {"--terrain t --terrain-levels a-b", "MIN-MAX"},
      {"--terrain t --terrain-levels 0-31", "MIN-MAX"},
      {"--terrain t --terrain-levels -1-3", "MIN-MAX"},
      {"--terrain t --terrain-levels 3-10",
       "MIN must be 0: CesiumJS loads a terrain from its two "
       "level-0 tiles down"},
      {"--terrain t --terrain-max-tiles 1", "at least 2"},
      {"--terrain t --terrain-max-tiles x", "at least 2"},
      {"-o x.ply --terrain-levels 0-3", "need --terrain"},
      {"-o x.ply --terrain-fill-height 3", "need --terrain"},
      {"-o x.ply --terrain-max-tiles 100", "need --terrain"},
      {"--ply-ascii", "no output"},
  };
  expect_usage_errors(dir, "'" + kSample + "'", cases);
}

TEST(TerrainCli, NoCrsStopsBeforeAnyWork) {
  const std::string dir = scratch_dir("terrain_cli");
  spit(dir + "/p.xyz", "0 0 1\n10 0 2\n0 10 3\n10 10 4\n5 5 5\n");
  const ShellRun r = run_tincdt(dir, "p.xyz --terrain t");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.messages.find("needs the data's CRS"), std::string::npos) << r.messages;
  EXPECT_NE(r.messages.find("--a-srs"), std::string::npos) << r.messages;
  EXPECT_EQ(r.messages.find("triangulat"), std::string::npos) << r.messages;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"p.xyz"});
}

// Levels 0-30 over the sample would be 111 million tiles: refused right after read, naming the
// levels, the count, the limit and the deepest level that fits.
TEST(TerrainCli, TooManyTilesRefusedBeforeAnyWork) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r = terrain_of_sample(dir, "--terrain-levels 0-30");
  EXPECT_EQ(r.exit_code, 2) << r.messages;
  EXPECT_NE(r.messages.find("levels 0-30: the pyramid would have 111,310,668 tiles over the "
                            "data's 0.00212487 x 0.00110371 degrees, more than the limit of "
                            "2,000,000 (--terrain-max-tiles): give --terrain-levels 0-27 "
                            "(1,743,891 tiles), or a higher --terrain-max-tiles"),
            std::string::npos)
      << r.messages;
  EXPECT_EQ(r.messages.find("triangulat"), std::string::npos) << r.messages;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

// The default levels, known once the TIN gives the point spacing, are counted too; a pyramid
// within the limit logs its count.
TEST(TerrainCli, TileLimitAppliesToTheDefaultLevelsAndIsLogged) {
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun refused = terrain_of_sample(dir, "--terrain-max-tiles 20");
  EXPECT_EQ(refused.exit_code, 2) << refused.messages;
  EXPECT_NE(refused.messages.find("the default levels 0-"), std::string::npos) << refused.messages;
  EXPECT_NE(refused.messages.find("more than the limit of 20"), std::string::npos)
      << refused.messages;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
  const ShellRun r = terrain_of_sample(dir, "--terrain-levels 0-12 --terrain-max-tiles 14");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_NE(r.messages.find("terrain: 14 tiles over the data's"), std::string::npos) << r.messages;
}

TEST(TerrainCli, ExistingLayerKeptWithoutOverwrite) {
  const std::string dir = scratch_dir("terrain_cli");
  fs::create_directories(dir + "/t");
  spit(dir + "/t/layer.json", "old");
  const ShellRun r = terrain_of_sample(dir, "--terrain-levels 0-3");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_NE(r.messages.find("already exists"), std::string::npos) << r.messages;
  EXPECT_EQ(names_in(dir + "/t"), std::set<std::string>{"layer.json"});
  EXPECT_EQ(slurp(dir + "/t/layer.json"), "old");
}

TEST(TerrainCli, ErasedAreaIsAHoleAtEveryLevel) {
  const std::string dir = scratch_dir("terrain_cli");
  // A 40 m square inside the sample (EPSG:32632).
  spit(dir + "/erase.geojson",
       R"({"type":"FeatureCollection",)"
       R"("crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::32632"}},)"
       R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Polygon",)"
       R"("coordinates":[[[600250,5190340],[600290,5190340],[600290,5190380],)"
       R"([600250,5190380],[600250,5190340]]]}}]})");
  const ShellRun r =
      run_tincdt(dir, "'" + kSample + "' --erase erase.geojson --terrain t --terrain-levels 0-18");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  OGRSpatialReference utm, geographic;
  utm.importFromEPSG(32632);
  geographic.importFromEPSG(4326);
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  geographic.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_lon_lat(
      OGRCreateCoordinateTransformation(&utm, &geographic));
  double x[4] = {600250, 600290, 600290, 600250}, y[4] = {5190340, 5190340, 5190380, 5190380};
  ASSERT_TRUE(to_lon_lat->Transform(4, x, y));
  const auto in_square = [&](double lon, double lat) {
    for (int k = 0; k < 4; ++k) {
      const int n = (k + 1) % 4;
      if ((x[n] - x[k]) * (lat - y[k]) - (y[n] - y[k]) * (lon - x[k]) <= 0) return false;
    }
    return true;
  };
  std::map<int, double> missing;  // per level: the tiles' squares less their triangles' area
  for (const auto& [key, tile] : read_pyramid(dir + "/t")) {
    double area = 0;
    for (std::size_t t = 0; t + 2 < tile.indices.size(); t += 3) {
      const auto [lon, lat] = centroid(key, tile, t);
      EXPECT_FALSE(in_square(lon, lat)) << key.z << "/" << key.x << "/" << key.y;
      const auto a = tile.indices[t], b = tile.indices[t + 1], c = tile.indices[t + 2];
      area += (static_cast<double>(tile.u[b]) - tile.u[a]) *
                  (static_cast<double>(tile.v[c]) - tile.v[a]) -
              (static_cast<double>(tile.v[b]) - tile.v[a]) *
                  (static_cast<double>(tile.u[c]) - tile.u[a]);
    }
    // Coarser tiles hold the 40 m square in less than their quantization step.
    if (key.z >= 14) missing[key.z] += 1 - area / 2 / (kQ * kQ);
  }
  ASSERT_EQ(missing.size(), 5u);
  for (const auto& [z, m] : missing) EXPECT_GT(m, 0) << "level " << z;
}

TEST(TerrainCli, FailedJobLeavesNoTileNorFolder) {
  const std::string dir = scratch_dir("terrain_cli");
  // The contour lines, after the pyramid, are refused: too many for the interval.
  const ShellRun r =
      terrain_of_sample(dir, "--terrain-levels 0-12 --contour-lines l.geojson --interval 0.0001");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

// ---- the shared data ------------------------------------------------------------------------

TEST(TerrainCli, PairTopographyLevels0To19) {
  TINCDT_REQUIRE_SHARED_DATA("pair_topography");
  const std::string data = shared_data();
  const std::string dir = scratch_dir("terrain_cli");
  const ShellRun r =
      run_tincdt(dir, "'" + data + "/las/Topography.las' --keep-class 2 --contours '" + data +
                          "/pair_topography/Topography_contours_1m_3d.shp' -o full.ply --ply-ascii "
                          "--terrain t --terrain-levels 0-19");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  expect_pyramid(dir, 0, 19, "pair_topography");
  expect_lines_are_edges(dir, 19);
}

TEST(TerrainCli, HexbinGroundAllLevels) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("terrain_cli");
  const std::string input = shared_data() + "/las/hexbin-crop.las";
  const ShellRun r =
      run_tincdt(dir, "'" + input + "' --keep-class 2 -o full.ply --ply-ascii --terrain t");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const json::Value layer = json::parse(slurp(dir + "/t/layer.json"));
  expect_pyramid(dir, 0, static_cast<int>(at(layer, "maxzoom").number()), "hexbin-crop (ground)");
}

TEST(TerrainCli, AutzenHeightsInFeetBecomeMetres) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string dir = scratch_dir("terrain_cli");
  const std::string input = shared_data() + "/laz/autzen_trim.laz";
  const std::string options = " --keep-class 2 -o full.ply --ply-ascii --terrain t";
  const ShellRun r = run_tincdt(dir, "'" + input + "'" + options);
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_NE(r.messages.find("converted to metres"), std::string::npos) << r.messages;
  const json::Value layer = json::parse(slurp(dir + "/t/layer.json"));
  const int max = static_cast<int>(at(layer, "maxzoom").number());
  expect_pyramid(dir, 0, max, "autzen_trim (ground)");
  // The ground, about 406..434 ft: 124..132 m, not the feet (the tiles reaching beyond the
  // data go down to the fill, the lowest).
  float highest = 0;
  for (const auto& [key, tile] : read_pyramid(dir + "/t"))
    if (key.z == max) highest = std::max(highest, tile.maximum_height);
  EXPECT_GT(highest, 125.f);
  EXPECT_LT(highest, 140.f);
}

}  // namespace
}  // namespace tincdt::test::terrain
