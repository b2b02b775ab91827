// Tiled jobs over one COPC file: each tile job reads only the nodes its buffered box meets, yet the
// merged tiles are the whole job's TIN, triangle for triangle; the bytes each tile reads are in
// its report and in --stats (inputs[].bytes_read).
#include <cpl_json.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "io/mesh/ply_reader.hpp"
#include "io/points/point_reader.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"
#include "tile_runs.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"
#include "tiles/plan_rim.hpp"
#include "tiles/tile_job.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;

using tile_test::Triangle;
using tile_test::triangles;

std::string shared(const std::string& rel) {
  return (fs::path(test::shared_data()) / rel).string();
}

// lone-star.copc.laz is tagged geocentric (EPSG:4978) although its coordinates are projected: a
// CRS a .prj cannot hold. Its jobs give the projected CRS with --override-srs.
struct Run {
  std::string input;
  double tile_size = 0;
  double buffer = 0;
  std::string override_srs;
};

struct TiledResult {
  std::string whole, merged;
  std::uint64_t file_bytes = 0;
  std::uint64_t whole_bytes_read = 0;
  std::vector<std::uint64_t> tile_bytes_read;
};

pipeline::BuildOptions job_options(const Run& run, const fs::path& output) {
  pipeline::BuildOptions o;
  o.output = output.string();
  o.write.overwrite = true;
  o.override_srs = run.override_srs;
  return o;
}

TiledResult tiled(const Run& run, const fs::path& dir) {
  TiledResult r;
  r.file_bytes = fs::file_size(run.input);
  pipeline::BuildOptions w = job_options(run, dir / "whole.ply");
  w.inputs = {run.input};
  const pipeline::BuildReport whole = pipeline::build(w);
  r.whole = w.output;
  r.whole_bytes_read = whole.inputs.at(0).bytes_read;

  tiles::PlanOptions po;
  po.inputs = {run.input};
  po.tile_size = run.tile_size;
  po.buffer = run.buffer;
  po.output = (dir / "plan.json").string();
  po.overwrite = true;
  std::vector<Point3> rim;
  tiles::TilePlan plan = tiles::make_plan(po, rim);
  tiles::write_plan(plan, rim, po.output, true);

  tiles::MergeOptions m;
  for (std::size_t i = 0; i < plan.tiles.size(); ++i) {
    tiles::TileOptions t;
    t.plan = po.output;
    t.tile = static_cast<std::int64_t>(i);
    t.max_buffer = 4 * run.tile_size;  // the tiles along the hull's long edges need more
    const pipeline::BuildOptions o = job_options(run, dir / ("tile_" + std::to_string(i) + ".ply"));
    const pipeline::BuildReport report = tiles::build_tile(t, o);
    r.tile_bytes_read.push_back(report.inputs.at(0).bytes_read);
    m.inputs.push_back(o.output);
  }
  m.output = (dir / "merged.ply").string();
  m.overwrite = true;
  tiles::merge_tiles(m);
  r.merged = m.output;
  return r;
}

void expect_same_tin(const std::string& whole, const std::string& merged) {
  const std::set<Triangle> a = triangles(whole), b = triangles(merged);
  EXPECT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the merged tiles are not the whole job's TIN";
}

// RUN tiled into TILES tiles, checked to merge into the whole job's TIN, which reads the whole
// file.
TiledResult tiled_as_whole(const Run& run, std::size_t tiles) {
  const TiledResult r = tiled(run, test::scratch_dir("copc_tiles"));
  EXPECT_EQ(r.tile_bytes_read.size(), tiles);
  expect_same_tin(r.whole, r.merged);
  EXPECT_EQ(r.whole_bytes_read, r.file_bytes);
  return r;
}

TEST(CopcTiles, SimpleInTwentyFourTilesIsTheWholeTin) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const TiledResult r = tiled_as_whole({shared("laz/simple.copc.laz"), 1000, 300, ""}, 24);
  // Every tile reads part of the file: about a fifth to a half of this small one, whose header,
  // VLRs and hierarchy alone are a ninth of it.
  for (const std::uint64_t bytes : r.tile_bytes_read) {
    EXPECT_LT(bytes, r.file_bytes * 6 / 10);
    EXPECT_GT(bytes, r.file_bytes / 9);
  }
}

TEST(CopcTiles, LoneStarInTwentyFiveTilesIsTheWholeTin) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const TiledResult r = tiled_as_whole({shared("copc/lone-star.copc.laz"), 8, 2, "EPSG:32614"}, 25);
  // Three levels only: every tile reads the root node (16 % of the file). The corner tiles that
  // need no larger buffer read under a third of the file.
  const std::uint64_t least = *std::min_element(r.tile_bytes_read.begin(), r.tile_bytes_read.end());
  EXPECT_LT(least, r.file_bytes / 4);
  EXPECT_GT(least, 431475u);  // the root node's chunk
}

// The plan's rim from the hierarchy: the two level-2 nodes deep inside the hull of the others
// are not read, and the hull, the bounds and the points near the outline (in order) are those
// of the whole file.
TEST(CopcTiles, ThePlanSkipsTheNodesDeepInsideTheHull) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const std::string path = shared("copc/lone-star.copc.laz");
  const double width = 0.5;
  const tiles::detail::PointScan by_nodes = tiles::detail::scan_points(path, {}, width, 1);
  std::vector<Point3> all;
  io::read_points(path, {}, all, 1);
  const tiles::detail::PointScan whole = tiles::detail::measure_points(all, width);
  EXPECT_EQ(by_nodes.nodes, 15u);
  EXPECT_EQ(by_nodes.unread_nodes, 2u);
  EXPECT_EQ(by_nodes.points + by_nodes.unread_points, 518862u);
  EXPECT_LT(by_nodes.points, 518862u * 2 / 3);
  ASSERT_EQ(by_nodes.hull.size(), whole.hull.size());
  for (std::size_t i = 0; i < whole.hull.size(); ++i) {
    EXPECT_EQ(by_nodes.hull[i].x, whole.hull[i].x);
    EXPECT_EQ(by_nodes.hull[i].y, whole.hull[i].y);
  }
  EXPECT_EQ(by_nodes.bounds.min_x, whole.bounds.min_x);
  EXPECT_EQ(by_nodes.bounds.max_y, whole.bounds.max_y);
  ASSERT_EQ(by_nodes.near_outline.size(), whole.near_outline.size());
  for (std::size_t i = 0; i < whole.near_outline.size(); ++i) {
    ASSERT_EQ(by_nodes.near_outline[i].x, whole.near_outline[i].x) << i;
    ASSERT_EQ(by_nodes.near_outline[i].z, whole.near_outline[i].z) << i;
  }
}

TEST(CopcTiles, StatsTellTheBytesEachTileRead) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const fs::path dir = test::scratch_dir("copc_tiles");
  const std::string input = shared("laz/simple.copc.laz");
  const test::ShellRun plan = test::run_tincdt(
      dir.string(), "plan '" + input + "' --tile-size 1000 --buffer 300 -o plan.json");
  ASSERT_EQ(plan.exit_code, 0) << plan.messages;
  const test::ShellRun tile =
      test::run_tincdt(dir.string(), "--plan plan.json --tile 0 -o tile.ply --stats tile.json");
  ASSERT_EQ(tile.exit_code, 0) << tile.messages;
  const test::ShellRun whole =
      test::run_tincdt(dir.string(), "'" + input + "' -o whole.ply --stats whole.json");
  ASSERT_EQ(whole.exit_code, 0) << whole.messages;
  const auto bytes_read = [&](const char* name) {
    CPLJSONDocument doc;
    EXPECT_TRUE(doc.Load((dir / name).string()));
    const CPLJSONArray inputs = doc.GetRoot().GetArray("inputs");
    EXPECT_EQ(inputs.Size(), 1);
    return inputs.Size() == 1 ? inputs[0].GetLong("bytes_read", -1) : -1;
  };
  const auto size = static_cast<long long>(fs::file_size(input));
  EXPECT_EQ(bytes_read("whole.json"), size);
  const long long tile_bytes = bytes_read("tile.json");
  EXPECT_GT(tile_bytes, 0);
  EXPECT_LT(tile_bytes, size / 3);
}

}  // namespace
