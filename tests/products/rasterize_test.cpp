// DEM rasterization against a brute-force reference: each cell centre is looked up in every kept
// triangle; the rasterizer must give exactly one write to each centre that some kept triangle
// holds (edges and vertices included), none elsewhere, and that triangle's plane.
#include "products/rasterize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "products_test_util.hpp"

namespace tincdt::products {
namespace {

using test::Kind;

constexpr double kNodata = -9999;

Grid make_grid(double min_x, double max_y, double res, std::uint32_t w, std::uint32_t h) {
  Grid g;
  g.min_x = min_x;
  g.max_y = max_y;
  g.resolution = res;
  g.width = w;
  g.height = h;
  return g;
}

// Grids over a TIN of lattice size N at (X0, Y0): centres on the lattice points (vertices and
// hull corners), on half-lattice points (edge midpoints, diagonals), and off the lattice, each
// reaching a little beyond the hull.
std::vector<Grid> grids_for(double x0, double y0, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const auto cells = [n](double res) { return static_cast<std::uint32_t>((n + 2) / res); };
  return {
      make_grid(x0 - 1.5, y0 + n + 1.5, 1.0, cells(1.0), cells(1.0)),
      make_grid(x0 - 1.25, y0 + n + 1.25, 0.5, cells(0.5), cells(0.5)),
      make_grid(x0 - 1, y0 + n + 1, 0.25, cells(0.25), cells(0.25)),
      make_grid(x0 - 1 + u(rng), y0 + n + 1 + u(rng), 0.37, cells(0.37), cells(0.37)),
  };
}

struct Case {
  Kind kind;
  double x0, y0;
};

class RasterizeProperty : public ::testing::TestWithParam<Case> {};

TEST_P(RasterizeProperty, EveryHeldCentreWrittenOnceWithItsTrianglesValue) {
  const Case c = GetParam();
  const int n = 10;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const mesh::Triangulation tin = test::make_tin(c.kind, seed, c.x0, c.y0, n);
    for (const Grid& grid : grids_for(c.x0, c.y0, n, seed)) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", resolution " +
                   std::to_string(grid.resolution));
      std::vector<int> writes(grid.cells(), 0);
      for (TriangleId t = 0; t < tin.triangle_slots(); ++t)
        scan_triangle(tin, grid, t, 0, grid.height,
                      [&](std::uint32_t row, std::uint32_t first, std::uint32_t end) {
                        for (std::uint32_t col = first; col < end; ++col)
                          ++writes[row * grid.width + col];
                      });
      std::vector<double> dem(grid.cells());
      const RasterizeStats stats = rasterize<double>(tin, grid, kNodata, dem, {.threads = 2});

      std::uint64_t held = 0, on_edges = 0;
      for (std::uint32_t row = 0; row < grid.height; ++row) {
        for (std::uint32_t col = 0; col < grid.width; ++col) {
          const Point2 p{grid.centre_x(col), grid.centre_y(row)};
          const std::size_t i = std::size_t{row} * grid.width + col;
          const std::vector<TriangleId> h = test::holders(tin, p);
          if (h.empty()) {
            ASSERT_EQ(writes[i], 0) << "centre (" << p.x << ", " << p.y << ") is in no triangle";
            ASSERT_EQ(dem[i], kNodata);
            continue;
          }
          ++held;
          if (h.size() > 1) ++on_edges;
          ASSERT_EQ(writes[i], 1) << "centre (" << p.x << ", " << p.y << ") held by " << h.size();
          for (const TriangleId t : h)
            ASSERT_NEAR(dem[i], static_cast<double>(test::plane_at(tin, t, p)), 1e-9);
        }
      }
      EXPECT_EQ(stats.cells_with_value, held);
      if (c.kind != Kind::random && grid.resolution != 0.37) {
        EXPECT_GT(on_edges, 0u) << "the degenerate case was not exercised";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Tins, RasterizeProperty,
                         ::testing::Values(Case{Kind::random, 0, 0}, Case{Kind::lattice, 0, 0},
                                           Case{Kind::lattice_holes, 0, 0},
                                           Case{Kind::random, 500000, 4000000},
                                           Case{Kind::lattice_holes, 500000, 4000000}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return std::string(test::kind_name(param.param.kind)) +
                                  (param.param.x0 != 0 ? "_utm" : "");
                         });

TEST(Rasterize, SameResultForAnyThreadCount) {
  for (const Kind kind : {Kind::random, Kind::lattice_holes}) {
    const mesh::Triangulation tin = test::make_tin(kind, 7, 1000, 2000, 40);
    const Grid grid = make_grid(999.5, 2040.5, 0.1, 420, 410);
    std::vector<float> one(grid.cells());
    rasterize<float>(tin, grid, -1.0f, one, {.threads = 1});
    for (const unsigned threads : {2u, 3u, 8u, 0u}) {
      std::vector<float> many(grid.cells(), 42.0f);
      rasterize<float>(tin, grid, -1.0f, many, {.threads = threads});
      EXPECT_EQ(std::memcmp(one.data(), many.data(), one.size() * sizeof(float)), 0)
          << threads << " threads";
    }
  }
}

TEST(Rasterize, ExactOnAPlaneAndNodataOutsideTheHull) {
  // A plane sampled at random points: every held centre is the plane itself.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Point3> pts;
  const auto plane = [](double x, double y) { return 3.25 + 0.5 * x - 0.125 * y; };
  for (int i = 0; i < 2000; ++i) {
    const double x = 600000 + u(rng), y = 5000000 + u(rng);
    pts.push_back({x, y, plane(x - 600000, y - 5000000)});
  }
  const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  const Grid grid = grid_over(kept_extent(tin), 0.5, true);
  std::vector<double> dem(grid.cells());
  rasterize<double>(tin, grid, kNodata, dem);
  std::uint64_t with_value = 0;
  for (std::uint32_t row = 0; row < grid.height; ++row)
    for (std::uint32_t col = 0; col < grid.width; ++col) {
      const double v = dem[std::size_t{row} * grid.width + col];
      if (v == kNodata) continue;
      ++with_value;
      ASSERT_NEAR(v, plane(grid.centre_x(col) - 600000, grid.centre_y(row) - 5000000), 1e-9);
    }
  // The hull of 2000 uniform points covers most of the square.
  EXPECT_GT(with_value, grid.cells() * 9 / 10);
}

TEST(Rasterize, RefusesAWrongBuffer) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 1);
  const Grid grid = make_grid(0, 10, 1, 10, 10);
  std::vector<double> small(99);
  EXPECT_THROW(rasterize<double>(tin, grid, kNodata, small), Error);
}

TEST(Rasterize, ProgressCanCancel) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 3, 0, 0, 30);
  const Grid grid = make_grid(0, 30, 0.01, 3000, 3000);
  std::vector<float> dem(grid.cells());
  int calls = 0;
  const ProgressFn stop_soon = [&](std::string_view stage, double) {
    EXPECT_EQ(stage, "dem");
    return ++calls < 3;
  };
  EXPECT_THROW(rasterize<float>(tin, grid, -1.0f, dem, {.threads = 2, .progress = &stop_soon}),
               Cancelled);
}

TEST(Grid, CoversTheExtentFromItsTopLeftCorner) {
  const BBox box{.min_x = 10.2, .min_y = 20.1, .max_x = 13.9, .max_y = 22.0};
  const Grid g = grid_over(box, 0.5, false);
  EXPECT_EQ(g.min_x, 10.2);
  EXPECT_EQ(g.max_y, 22.0);
  EXPECT_EQ(g.width, 8u);   // 3.7 / 0.5 = 7.4 -> 8
  EXPECT_EQ(g.height, 4u);  // 1.9 / 0.5 = 3.8 -> 4
  EXPECT_GE(g.max_x(), 13.9);
  EXPECT_LE(g.min_y(), 20.1);
  EXPECT_EQ(g.centre_x(0), 10.45);
  EXPECT_EQ(g.centre_y(0), 21.75);
}

TEST(Grid, TargetAlignedSnapsToMultiplesOfTheResolution) {
  const BBox box{.min_x = 10.2, .min_y = 20.1, .max_x = 13.9, .max_y = 22.0};
  const Grid g = grid_over(box, 0.5, true);
  EXPECT_EQ(g.min_x, 10.0);
  EXPECT_EQ(g.max_y, 22.0);
  EXPECT_EQ(g.width, 8u);   // 10 .. 14
  EXPECT_EQ(g.height, 4u);  // 20 .. 22
  // An exact multiple gets no extra cell from rounding: 0.1 does not divide 1 exactly in doubles.
  BBox unit;
  unit.add(0, 0);
  unit.add(1, 0.7);
  const Grid fine = grid_over(unit, 0.1, true);
  EXPECT_EQ(fine.width, 10u);
  EXPECT_EQ(fine.height, 7u);
}

TEST(Grid, RefusesBadResolutionsAndExtents) {
  const BBox box{.min_x = 0, .min_y = 0, .max_x = 1, .max_y = 1};
  EXPECT_THROW(grid_over(box, 0, false), Error);
  EXPECT_THROW(grid_over(box, -1, false), Error);
  EXPECT_THROW(grid_over(box, std::numeric_limits<double>::quiet_NaN(), false), Error);
  EXPECT_THROW(grid_over(BBox{}, 1, false), Error);   // empty
  EXPECT_THROW(grid_over(box, 1e-12, false), Error);  // 10^12 columns
  BBox far;
  far.add(1e9, 1e9);
  far.add(1e9 + 1, 1e9 + 1);
  EXPECT_THROW(grid_over(far, 1e-4, false), Error);  // centres would not be distinct doubles
}

}  // namespace
}  // namespace tincdt::products
