// The products on real data (../shared/data, skipped when absent): the ground points of
// pair_topography, alone and with the pair's 1 m contours as hard lines (every contour vertex
// then lies exactly on a level, with flat triangles along bends). The DEM equals a walk-based
// point location (terrain::SurfaceSampler) in every cell; the contours at 1 m lie on the TIN
// at their level and no two lines of one level cross.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "predicates/predicates.hpp"
#include "products/contours.hpp"
#include "products/rasterize.hpp"
#include "support/shared_data.hpp"
#include "terrain/interpolate.hpp"

namespace tincdt::products {
namespace {

const std::string kData = ::tincdt::test::shared_data();
const std::string kPoints = kData + "/xyz/Topography_ground.xyz";
const std::string kContours = kData + "/pair_topography/Topography_contours_1m_3d.shp";

mesh::Triangulation topography(bool with_contours) {
  std::vector<Point3> pts;
  io::read_xyz(kPoints, pts);
  const auto n_points = static_cast<std::uint32_t>(pts.size());
  io::LineData lines;
  if (with_contours) {
    io::read_lines(kContours, {}, lines);
    pts.insert(pts.end(), lines.vertices.begin(), lines.vertices.end());
  }
  auto dt = delaunay::triangulate(std::move(pts), {.keep_point_map = true});
  if (with_contours) {
    std::vector<constraints::Segment> segs;
    for (const io::LineData::Segment& s : lines.segments)
      segs.push_back(
          {dt.vertex_of_point[n_points + s.a], dt.vertex_of_point[n_points + s.b], s.feature});
    constraints::insert_constraints(dt.tin, segs);
  }
  return std::move(dt.tin);
}

class RealData : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kPoints) || !std::filesystem::exists(kContours))
      GTEST_SKIP() << "no shared data at " << kData;
  }
};

TEST_P(RealData, DemEqualsPointLocationInEveryCell) {
  const mesh::Triangulation tin = topography(GetParam());
  const Grid grid = grid_over(kept_extent(tin), 0.5, true);
  std::vector<double> dem(grid.cells());
  rasterize<double>(tin, grid, -9999, dem);
  terrain::SurfaceSampler sampler(tin);
  std::uint64_t with_value = 0;
  for (std::uint32_t row = 0; row < grid.height; ++row)
    for (std::uint32_t col = 0; col < grid.width; ++col) {
      const double expected = sampler.z_at({grid.centre_x(col), grid.centre_y(row)});
      const double got = dem[std::size_t{row} * grid.width + col];
      if (std::isnan(expected)) {
        ASSERT_EQ(got, -9999) << "row " << row << ", col " << col;
      } else {
        ++with_value;
        ASSERT_NEAR(got, expected, 1e-9) << "row " << row << ", col " << col;
      }
    }
  EXPECT_GT(with_value, grid.cells() * 9 / 10);
}

// z of the TIN at P, a crossing computed on an edge: the linear interpolation along the nearest
// edge of the triangle the walk finds and its neighbours (all kept triangles when P is a rounding
// outside the hull), in long double; the evaluation of a sliver's plane would be ill-conditioned.
// SLACK: how far z moves along that edge when P moves by one unit in the last place.
double z_on_tin(const mesh::Triangulation& tin, terrain::SurfaceSampler& sampler, Point2 p,
                double* slack) {
  using L = long double;
  std::vector<TriangleId> candidates;
  if (!std::isnan(sampler.z_at(p))) {
    const TriangleId t = sampler.last_triangle();
    candidates.push_back(t);
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) candidates.push_back(mesh::triangle_of(tin.twin(e)));
  } else {
    tin.for_each_triangle(
        [&](TriangleId t, const std::array<VertexId, 3>&) { candidates.push_back(t); });
  }
  L best_d = INFINITY, best_z = NAN, best_slope = 0;
  for (const TriangleId t : candidates) {
    if (!tin.is_kept(t)) continue;
    const auto c = tin.triangle(t);
    for (int i = 0; i < 3; ++i) {
      const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]);
      const L ex = L(b.x) - a.x, ey = L(b.y) - a.y, len = std::sqrt(ex * ex + ey * ey);
      const L s = std::clamp(((L(p.x) - a.x) * ex + (L(p.y) - a.y) * ey) / (len * len), L(0), L(1));
      const L d = std::hypot(a.x + s * ex - p.x, a.y + s * ey - p.y);
      if (d < best_d) {
        const L za = tin.z(c[i]), zb = tin.z(c[(i + 1) % 3]);
        best_d = d;
        best_z = za + s * (zb - za);
        best_slope = std::fabs(zb - za) / len;
      }
    }
  }
  const double ulp = std::nextafter(std::fmax(std::fabs(p.x), std::fabs(p.y)), INFINITY) -
                     std::fmax(std::fabs(p.x), std::fabs(p.y));
  EXPECT_LT(best_d, 4 * ulp) << "(" << p.x << ", " << p.y << ") is on no edge";
  *slack = static_cast<double>(best_slope) * 2 * ulp;
  return static_cast<double>(best_z);
}

TEST_P(RealData, ContoursLieOnTheTinAndNeverCross) {
  const mesh::Triangulation tin = topography(GetParam());
  const ContourSet set = trace_contours(tin, {.interval = 1});
  ASSERT_GT(set.lines.size(), 20u);
  terrain::SurfaceSampler sampler(tin);
  // 1e-9 beyond the rounding of the points themselves (1 ulp of 5274600 is 9.3e-10 m).
  double worst = 0;
  for (const ContourLine& line : set.lines) {
    if (line.closed) {
      ASSERT_EQ(set.points[line.first], set.points[line.first + line.count - 1]);
    }
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      double slack = 0;
      const double z = z_on_tin(tin, sampler, set.points[i], &slack);
      ASSERT_NEAR(z, line.level, 1e-9 + slack) << "level " << line.level;
      worst = std::max(worst, std::fabs(z - line.level));
    }
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("largest_z_error", text);
  // No two pieces of one level cross: pieces bucketed in 4 m cells, pairs within a cell.
  std::map<std::pair<double, std::int64_t>, std::vector<std::pair<Point2, Point2>>> cells;
  const auto key = [](double v) { return static_cast<std::int64_t>(std::floor(v / 4)); };
  for (const ContourLine& line : set.lines)
    for (std::size_t i = line.first; i + 1 < line.first + line.count; ++i) {
      const Point2 a = set.points[i], b = set.points[i + 1];
      for (std::int64_t cx = key(std::min(a.x, b.x)); cx <= key(std::max(a.x, b.x)); ++cx)
        for (std::int64_t cy = key(std::min(a.y, b.y)); cy <= key(std::max(a.y, b.y)); ++cy)
          cells[{line.level, cx * 1000003 + cy}].push_back({a, b});
    }
  using predicates::orient2d;
  std::uint64_t pairs = 0;
  for (const auto& [k, segs] : cells)
    for (std::size_t i = 0; i < segs.size(); ++i)
      for (std::size_t j = i + 1; j < segs.size(); ++j) {
        const auto& [a, b] = segs[i];
        const auto& [c, d] = segs[j];
        ++pairs;
        const bool cross =
            orient2d(a, b, c) * orient2d(a, b, d) < 0 && orient2d(c, d, a) * orient2d(c, d, b) < 0;
        ASSERT_FALSE(cross) << "level " << k.first << ": (" << a.x << ", " << a.y << ")";
      }
  EXPECT_GT(pairs, 1000u);
}

INSTANTIATE_TEST_SUITE_P(Topography, RealData, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param) {
                           return param.param ? "with_contours" : "points_only";
                         });

}  // namespace
}  // namespace tincdt::products
