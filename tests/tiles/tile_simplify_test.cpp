// --max-error in tile jobs: every tile simplified on its own, the tiles merged without a crack
// (the merge welds the border vertices the two tiles of a side share and validates the whole),
// every point of the input within the tolerance of the merged TIN, every constrained edge of the
// full TIN a chain of constrained edges of the merged one, the outline the full TIN's, and the
// vertex count near the single job's simplification of the same input.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
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

// The triangles of a mesh in the cells of a grid, to find the one holding a point.
class Located {
 public:
  explicit Located(const io::PlyMesh& m) : m_(m) {
    for (const Point3& p : m.vertices) {
      min_x_ = std::min(min_x_, p.x);
      min_y_ = std::min(min_y_, p.y);
      max_x_ = std::max(max_x_, p.x);
      max_y_ = std::max(max_y_, p.y);
    }
    n_ = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::sqrt(static_cast<double>(m.faces.size()) / 4)));
    cells_.resize(n_ * n_);
    for (std::uint32_t t = 0; t < m.faces.size(); ++t) {
      const Point3 &a = m.vertices[m.faces[t][0]], &b = m.vertices[m.faces[t][1]],
                   &c = m.vertices[m.faces[t][2]];
      const std::size_t x0 = cell(std::min({a.x, b.x, c.x}), min_x_, max_x_),
                        x1 = cell(std::max({a.x, b.x, c.x}), min_x_, max_x_),
                        y0 = cell(std::min({a.y, b.y, c.y}), min_y_, max_y_),
                        y1 = cell(std::max({a.y, b.y, c.y}), min_y_, max_y_);
      for (std::size_t i = x0; i <= x1; ++i)
        for (std::size_t j = y0; j <= y1; ++j) cells_[j * n_ + i].push_back(t);
    }
  }

  // The height at P, or NaN outside the triangles.
  double height(const Point3& p) const {
    if (p.x < min_x_ || p.x > max_x_ || p.y < min_y_ || p.y > max_y_) return std::nan("");
    for (const std::uint32_t t :
         cells_[cell(p.y, min_y_, max_y_) * n_ + cell(p.x, min_x_, max_x_)]) {
      const auto& f = m_.faces[t];
      const Point3 &a = m_.vertices[f[0]], &b = m_.vertices[f[1]], &c = m_.vertices[f[2]];
      const double d = area2(a, b, c);
      const double u = area2(p, b, c) / d, v = area2(a, p, c) / d, w = 1 - u - v;
      const double slack = -1e-9;
      if (u >= slack && v >= slack && w >= slack) return u * a.z + v * b.z + w * c.z;
    }
    return std::nan("");
  }

 private:
  std::size_t cell(double v, double lo, double hi) const {
    const double f = (v - lo) / (hi - lo) * static_cast<double>(n_);
    return std::min(n_ - 1, static_cast<std::size_t>(std::max(0.0, f)));
  }

  const io::PlyMesh& m_;
  double min_x_ = INFINITY, min_y_ = INFINITY, max_x_ = -INFINITY, max_y_ = -INFINITY;
  std::size_t n_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// The largest vertical distance of a vertex of FULL from SIMPLIFIED (infinity: one outside it).
double largest_error(const io::PlyMesh& full, const io::PlyMesh& simplified) {
  const Located located(simplified);
  double worst = 0;
  for (const Point3& p : full.vertices) {
    const double h = located.height(p);
    worst = std::max(worst, std::isnan(h) ? INFINITY : std::fabs(h - p.z));
  }
  return worst;
}

// How many constrained edges of FULL are not a chain of constrained edges of MERGED: from one
// end to the other, each step to a vertex within a micrometre of the edge, farther along it.
std::size_t broken_constraints(const io::PlyMesh& full, const io::PlyMesh& merged) {
  std::map<std::pair<double, double>, std::uint32_t> at;
  for (std::uint32_t v = 0; v < merged.vertices.size(); ++v)
    at[{merged.vertices[v].x, merged.vertices[v].y}] = v;
  std::vector<std::vector<std::uint32_t>> next(merged.vertices.size());
  for (const io::PlyMesh::Edge& e : merged.edges) {
    next[e.a].push_back(e.b);
    next[e.b].push_back(e.a);
  }
  std::size_t broken = 0;
  for (const io::PlyMesh::Edge& e : full.edges) {
    const Point3 &p = full.vertices[e.a], &q = full.vertices[e.b];
    const auto from = at.find({p.x, p.y}), to = at.find({q.x, q.y});
    if (from == at.end() || to == at.end()) {
      ++broken;
      continue;
    }
    const double dx = q.x - p.x, dy = q.y - p.y, length = std::hypot(dx, dy);
    std::uint32_t v = from->second;
    double done = 0;
    while (v != to->second) {
      std::uint32_t best = kNoId;
      double best_t = INFINITY;
      for (const std::uint32_t w : next[v]) {
        const Point3& r = merged.vertices[w];
        const double t = ((r.x - p.x) * dx + (r.y - p.y) * dy) / (length * length);
        const double off = std::fabs((r.x - p.x) * dy - (r.y - p.y) * dx) / length;
        if (off <= 1e-6 && t > done && t <= 1 + 1e-12 && t < best_t) {
          best = w;
          best_t = t;
        }
      }
      if (best == kNoId) break;
      v = best;
      done = best_t;
    }
    broken += v == to->second ? 0 : 1;
  }
  return broken;
}

struct Measured {
  double error = 0;  // the largest, over the full TIN's vertices
  double ratio = 0;  // merged vertices over the single job's
};

// Plans INPUTS in tiles of SIZE, builds every tile with --max-error TOLERANCE and the options of
// EXACT (validated), merges (checked and validated), and checks the merged TIN against the full
// TIN (EXACT's single job) and the simplified single job.
Measured simplify_in_tiles(const Inputs& in, const fs::path& dir, double size, double tolerance,
                           const pipeline::BuildOptions& exact_options = no_options()) {
  const fs::path exact = dir / "exact", single = dir / "single", tiled_dir = dir / "tiled";
  for (const fs::path& d : {exact, single, tiled_dir}) fs::create_directories(d);
  const io::PlyMesh full = io::read_ply(whole(in, exact, exact_options));
  pipeline::BuildOptions base = exact_options;
  base.max_error = tolerance;
  const io::PlyMesh one = io::read_ply(whole(in, single, base));
  const io::PlyMesh merged = io::read_ply(tiled(in, tiled_dir, size, 40, -1, base));

  Measured m;
  m.error = largest_error(full, merged);
  EXPECT_LE(m.error, tolerance * (1 + 1e-9)) << "a point beyond the tolerance";
  EXPECT_EQ(broken_constraints(full, merged), 0u) << "a constrained edge lost";
  const double area = total_area(full);
  EXPECT_NEAR(total_area(merged), area, 1e-9 * area) << "another outline";
  EXPECT_NEAR(total_area(one), area, 1e-9 * area) << "another outline in the single job";
  EXPECT_LT(merged.vertices.size(), full.vertices.size());
  m.ratio = static_cast<double>(merged.vertices.size()) / static_cast<double>(one.vertices.size());
  std::printf(
      "tiles of %g, --max-error %g: %zu vertices merged, %zu single job, %zu full: "
      "ratio %.3f, largest error %.4g\n",
      size, tolerance, merged.vertices.size(), one.vertices.size(), full.vertices.size(), m.ratio,
      m.error);
  return m;
}

constexpr double kX0 = 500000, kY0 = 4000000;

// IN, data over 300 m, simplified at 0.05 in tiles of 150 (2 x 2) and of 100 (3 x 3), each in
// its folder below DIR: at most MOST times the single job's vertices.
void expect_ratio_in_2x2_and_3x3(const Inputs& in, const fs::path& dir, double most) {
  for (const double size : {150.0, 100.0}) {
    SCOPED_TRACE(size);
    const Measured m = simplify_in_tiles(in, dir / std::to_string(int(size)), size, 0.05);
    EXPECT_LE(m.ratio, most);
  }
}

TEST(TileSimplify, RandomTerrainIn2x2And3x3Tiles) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(4000, kX0, kY0, 300, 11))}, {}};
  expect_ratio_in_2x2_and_3x3(in, dir, 1.06);  // measured 1.050 and 1.046
}

// Every constrained edge that crosses a border gives both tiles a border vertex there, which the
// single job does not need: with lines this dense, more than 1.10.
TEST(TileSimplify, ContoursAndCrossingLinesStayWholeAcrossTheTiles) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, kX0, kY0, 300, 12))},
                  {write_rings(dir / "rings.geojson", kX0 + 150, kY0 + 150, {20, 45, 70, 95, 120}),
                   write_crossing_lines(dir / "lines.geojson", kX0, kY0, 300, 6, 25, 13)}};
  expect_ratio_in_2x2_and_3x3(in, dir, 1.14);  // measured 1.129 and 1.134
}

// A tile that meets the data's hull: the border profiles stop where the hull crosses the sides.
TEST(TileSimplify, TilesAcrossTheDataEdge) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(2500, kX0 + 7, kY0 + 13, 230, 14))},
                  {}};
  const Measured m = simplify_in_tiles(in, dir / "70", 70, 0.1);
  EXPECT_LE(m.ratio, 1.12);  // measured 1.112: 16 tiles of 70 over 230, more border per area
}

// Real LiDAR with its contours (centimetre coordinates, long contour segments across the tiles).
TEST(TileSimplify, TopographyWithItsContours) {
  if (!fs::exists(shared("las/Topography.las"))) GTEST_SKIP() << "no shared data";
  const fs::path dir = scratch();
  const Inputs in{{shared("las/Topography.las")},
                  {shared("pair_topography/Topography_contours_1m_3d.shp")}};
  const Measured m = simplify_in_tiles(in, dir, 100, 0.1);
  EXPECT_LE(m.ratio, 1.04);  // measured 1.028 (16 tiles)
}

// --max-edge with --max-error: the tiles trim the full TIN as the single job does (a bay and a
// gap across the tile borders; a void inside stays), keep the trimmed outline through their
// simplification and remove what lies beyond it: the merged TIN covers exactly the single job's
// trimmed area. The fence crosses the borders many times, each crossing a border vertex.
TEST(TileSimplify, TrimmedTilesKeepTheTrimmedOutline) {
  const fs::path dir = scratch();
  const Inputs in = gapped_points(dir);
  pipeline::BuildOptions trim;
  trim.max_edge = 12;
  for (const double size : {100.0, 70.0}) {
    SCOPED_TRACE(size);
    const Measured m = simplify_in_tiles(in, dir / std::to_string(int(size)), size, 0.05, trim);
    EXPECT_LE(m.ratio, size > 90 ? 1.08 : 1.17);  // measured 1.069 and 1.157 (16 tiles)
  }
}

// A lattice: cocircular ties everywhere, and the hull's sides full of collinear vertices.
TEST(TileSimplify, LatticeTies) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "grid.xyz", lattice(80, kX0, kY0, 2))}, {}};
  const Measured m = simplify_in_tiles(in, dir / "t", 50, 0.05);
  EXPECT_LE(m.ratio, 1.10);
}

// Each simplified tile's DEM holds the merged TIN's height at the centre of every cell of its box
// that the tile's TIN covers.
TEST(TileSimplify, TileDemsAreTheMergedTinsHeights) {
  const fs::path dir = scratch();
  const Inputs in{{write_xyz(dir / "points.xyz", random_points(3000, kX0, kY0, 300, 16))}, {}};
  pipeline::BuildOptions base;
  base.max_error = 0.05;
  const std::string p = plan(in, dir, 100, 40);
  const std::size_t n = tiles::read_plan(p).tiles.size();
  tiles::MergeOptions m;
  for (std::size_t i = 0; i < n; ++i)
    m.inputs.push_back(build_tile(p, static_cast<std::int64_t>(i), dir, 2, base));
  m.output = (dir / "merged.ply").string();
  m.overwrite = true;
  tiles::merge_tiles(m);
  const io::PlyMesh merged = io::read_ply(m.output);
  const Located located(merged);
  GDALAllRegister();
  std::size_t compared = 0, uncovered = 0;
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string tif = (dir / ("tile_" + std::to_string(i) + ".tif")).string();
    const GDALDatasetUniquePtr ds(GDALDataset::Open(tif.c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds) << tif;
    double gt[6];
    ds->GetGeoTransform(gt);
    const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
    GDALRasterBand* band = ds->GetRasterBand(1);
    const double nodata = band->GetNoDataValue();
    std::vector<double> cells(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, w, h, cells.data(), w, h, GDT_Float64, 0, 0), CE_None);
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c) {
        const double v = cells[static_cast<std::size_t>(r) * static_cast<std::size_t>(w) +
                               static_cast<std::size_t>(c)];
        const double z = located.height({gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5], 0});
        if (std::isnan(z)) continue;
        if (v == nodata) {
          ++uncovered;
          continue;
        }
        ++compared;
        worst = std::max(worst, std::fabs(v - z));
      }
  }
  std::printf("%zu cells compared, largest difference %.3g; %zu in the TIN without a value\n",
              compared, worst, uncovered);
  EXPECT_GT(compared, 9u * 2000u);
  EXPECT_LE(worst, 1e-3);                 // the DEM's 32-bit floats
  EXPECT_LE(uncovered, compared / 1000);  // cells in the slivers at the hull (TurnedEnd)
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
