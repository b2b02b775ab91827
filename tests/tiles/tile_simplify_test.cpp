// --max-error in tile jobs: every tile simplified on its own, the tiles merged without a crack
// (the merge welds the border vertices the two tiles of a side share and validates the whole),
// every point of the input within the tolerance of the merged TIN, every constrained edge of the
// full TIN a chain of constrained edges of the merged one, the outline the full TIN's, and the
// vertex count near the single job's simplification of the same input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh/ply_reader.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "tile_runs.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using namespace tincdt::tile_test;

double area2(const Point3& a, const Point3& b, const Point3& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

double total_area(const io::PlyMesh& m) {
  double sum = 0;
  for (const auto& f : m.faces)
    sum += area2(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]) / 2;
  return sum;
}

// The height of M at P, or NaN outside its triangles.
double height_in(const io::PlyMesh& m, const Point3& p) {
  for (const auto& f : m.faces) {
    const Point3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    if (p.x < std::min({a.x, b.x, c.x}) || p.x > std::max({a.x, b.x, c.x}) ||
        p.y < std::min({a.y, b.y, c.y}) || p.y > std::max({a.y, b.y, c.y}))
      continue;
    const double d = area2(a, b, c);
    const double u = area2(p, b, c) / d, v = area2(a, p, c) / d, w = 1 - u - v;
    const double slack = -1e-9;
    if (u >= slack && v >= slack && w >= slack) return u * a.z + v * b.z + w * c.z;
  }
  return std::nan("");
}

// The largest vertical distance of a vertex of FULL from SIMPLIFIED (infinity: one outside it).
double largest_error(const io::PlyMesh& full, const io::PlyMesh& simplified) {
  double worst = 0;
  for (const Point3& p : full.vertices) {
    const double h = height_in(simplified, p);
    worst = std::max(worst, std::isnan(h) ? INFINITY : std::fabs(h - p.z));
  }
  return worst;
}

// How many constrained edges of FULL are not a chain of constrained edges of MERGED (the
// vertices of MERGED within a micrometre of the edge, in order along it).
std::size_t broken_constraints(const io::PlyMesh& full, const io::PlyMesh& merged) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> constrained;
  for (const io::PlyMesh::Edge& e : merged.edges) constrained.insert(std::minmax(e.a, e.b));
  std::size_t broken = 0;
  for (const io::PlyMesh::Edge& e : full.edges) {
    const Point3 &p = full.vertices[e.a], &q = full.vertices[e.b];
    const double dx = q.x - p.x, dy = q.y - p.y, length = std::hypot(dx, dy);
    std::vector<std::pair<double, std::uint32_t>> on;
    bool has_p = false, has_q = false;
    for (std::uint32_t v = 0; v < merged.vertices.size(); ++v) {
      const Point3& r = merged.vertices[v];
      const double t = ((r.x - p.x) * dx + (r.y - p.y) * dy) / (length * length);
      const double off = std::fabs((r.x - p.x) * dy - (r.y - p.y) * dx) / length;
      if (t < -1e-12 || t > 1 + 1e-12 || off > 1e-6) continue;
      on.push_back({t, v});
      has_p = has_p || (r.x == p.x && r.y == p.y);
      has_q = has_q || (r.x == q.x && r.y == q.y);
    }
    std::sort(on.begin(), on.end());
    bool chain = has_p && has_q && on.size() >= 2;
    for (std::size_t i = 1; i < on.size() && chain; ++i)
      chain = constrained.count(std::minmax(on[i - 1].second, on[i].second)) > 0;
    broken += chain ? 0 : 1;
  }
  return broken;
}

struct Measured {
  double error = 0;  // the largest, over the full TIN's vertices
  double ratio = 0;  // merged vertices over the single job's
};

// Plans INPUTS in tiles of SIZE, builds every tile with --max-error TOLERANCE (validated), merges
// (checked and validated), and checks the merged TIN against the full TIN and the single job.
Measured simplify_in_tiles(const Inputs& in, const fs::path& dir, double size, double tolerance) {
  const fs::path exact = dir / "exact", single = dir / "single", tiled_dir = dir / "tiled";
  for (const fs::path& d : {exact, single, tiled_dir}) fs::create_directories(d);
  const io::PlyMesh full = io::read_ply(whole(in, exact));
  pipeline::BuildOptions base;
  base.max_error = tolerance;
  const io::PlyMesh one = io::read_ply(whole(in, single, base));
  const io::PlyMesh merged = io::read_ply(tiled(in, tiled_dir, size, 40, -1, base));

  Measured m;
  m.error = largest_error(full, merged);
  EXPECT_LE(m.error, tolerance * (1 + 1e-9)) << "a point beyond the tolerance";
  EXPECT_EQ(broken_constraints(full, merged), 0u) << "a constrained edge lost";
  EXPECT_NEAR(total_area(merged), total_area(full), 1e-9 * total_area(full)) << "another outline";
  EXPECT_LT(merged.vertices.size(), full.vertices.size());
  m.ratio = static_cast<double>(merged.vertices.size()) / static_cast<double>(one.vertices.size());
  std::printf("tiles of %g, --max-error %g: %zu vertices merged, %zu single job, %zu full: "
              "ratio %.3f, largest error %.4g\n",
              size, tolerance, merged.vertices.size(), one.vertices.size(), full.vertices.size(),
              m.ratio, m.error);
  return m;
}

constexpr double kX0 = 500000, kY0 = 4000000;

TEST(TileSimplify, RandomTerrainIn2x2And3x3Tiles) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(4000, kX0, kY0, 300, 11))}, {}};
  for (const double size : {150.0, 100.0}) {
    SCOPED_TRACE(size);
    const Measured m = simplify_in_tiles(in, dir / std::to_string(int(size)), size, 0.05);
    EXPECT_LE(m.ratio, 1.06);  // measured 1.050 and 1.046
  }
}

// Every constrained edge that crosses a border gives both tiles a border vertex there, which the
// single job does not need: with lines this dense, more than 1.10.
TEST(TileSimplify, ContoursAndCrossingLinesStayWholeAcrossTheTiles) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, kX0, kY0, 300, 12))},
                  {write_rings(dir / "rings.geojson", kX0 + 150, kY0 + 150, {20, 45, 70, 95, 120}),
                   write_crossing_lines(dir / "lines.geojson", kX0, kY0, 300, 6, 25, 13)}};
  for (const double size : {150.0, 100.0}) {
    SCOPED_TRACE(size);
    const Measured m = simplify_in_tiles(in, dir / std::to_string(int(size)), size, 0.05);
    EXPECT_LE(m.ratio, 1.14);  // measured 1.129 and 1.134
  }
}

// A tile that meets the data's hull: the border profiles stop where the hull crosses the sides.
TEST(TileSimplify, TilesAcrossTheDataEdge) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(2500, kX0 + 7, kY0 + 13, 230, 14))},
                  {}};
  const Measured m = simplify_in_tiles(in, dir / "70", 70, 0.1);
  EXPECT_LE(m.ratio, 1.12);  // measured 1.112: 16 tiles of 70 over 230, more border per area
}

// The commands as a user runs them: plan, each tile with --max-error, merge.
TEST(TileSimplifyCli, PlanTilesWithMaxErrorAndMerge) {
  const fs::path dir = test::scratch_dir("tile_simplify_cli");
  write_xyz(dir / "points.xyz", random_points(3000, kX0, kY0, 300, 15));
  write_rings(dir / "rings.geojson", kX0 + 150, kY0 + 150, {30, 60, 90});
  const auto ok = [&](const std::string& args) {
    const test::ShellRun r = test::run_tincdt(dir.string(), args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.messages;
  };
  ok("points.xyz --contours rings.geojson -o full.ply -q");
  ok("plan points.xyz --contours rings.geojson --tile-size 100 --buffer 40 -o plan.json -q");
  const std::size_t n = tiles::read_plan((dir / "plan.json").string()).tiles.size();
  ASSERT_EQ(n, 9u);
  std::string merge = "merge";
  for (std::size_t i = 0; i < n; ++i) {
    const std::string tile = "tile_" + std::to_string(i) + ".ply";
    ok("--plan plan.json --tile " + std::to_string(i) + " --max-error 0.1 -o " + tile +
       " --validate -q");
    merge += " " + tile;
  }
  ok(merge + " -o merged.ply -q");
  const io::PlyMesh full = io::read_ply((dir / "full.ply").string());
  const io::PlyMesh merged = io::read_ply((dir / "merged.ply").string());
  EXPECT_LT(merged.vertices.size(), full.vertices.size() * 4 / 5);
  EXPECT_LE(largest_error(full, merged), 0.1 * (1 + 1e-9));
  EXPECT_EQ(broken_constraints(full, merged), 0u);

  const test::ShellRun refused =
      test::run_tincdt(dir.string(), "--plan plan.json --tile 0 --max-vertices 500 -o t.ply");
  EXPECT_EQ(refused.exit_code, 2) << refused.messages;
  EXPECT_NE(refused.messages.find("--max-vertices cannot be used with --plan"), std::string::npos)
      << refused.messages;
}

}  // namespace
