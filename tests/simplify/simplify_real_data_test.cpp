// Simplification of the shared real pairs (LAS ground points and the contours made from them),
// built as the pipeline builds them: every vertex of the full constrained TIN within the
// tolerance of the result, every contour vertex and segment kept. Skipped without the data.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "simplify/simplify.hpp"
#include "simplify_checks.hpp"
#include "support/shared_data.hpp"

namespace tincdt::simplify {
namespace {

const std::string kData = ::tincdt::test::shared_data();

struct Pair {
  const char* name;
  const char* las;
  const char* contours;
  double max_error;  // in the data's z units
};

class RealPair : public ::testing::TestWithParam<Pair> {};

TEST_P(RealPair, EveryVertexWithinToleranceEveryContourKept) {
  const Pair pair = GetParam();
  const std::string las = kData + "/" + pair.las, shp = kData + "/" + pair.contours;
  if (!std::filesystem::exists(las) || !std::filesystem::exists(shp))
    GTEST_SKIP() << "shared data not found: " << las << ", " << shp;

  std::vector<Point3> points;
  io::PointFilter ground;
  ground.keep_classes = {2};
  io::read_points(las, ground, points);
  const std::size_t n_points = points.size();
  io::LineData lines;
  io::read_lines(shp, {}, lines);
  points.insert(points.end(), lines.vertices.begin(), lines.vertices.end());
  delaunay::DelaunayResult d = delaunay::triangulate(std::move(points), {.keep_point_map = true});
  std::vector<constraints::Segment> segments;
  for (const io::LineData::Segment& s : lines.segments)
    segments.push_back(
        {d.vertex_of_point[n_points + s.a], d.vertex_of_point[n_points + s.b], s.feature});
  const constraints::ConstraintResult c = constraints::insert_constraints(d.tin, segments);
  const mesh::Triangulation& full = d.tin;

  for (double e : {pair.max_error, 4 * pair.max_error}) {
    SimplifyOptions options;
    options.max_error = e;
    const SimplifyResult r = simplify_tin(full, options);
    EXPECT_EQ(r.tin.validate({.delaunay = true}), "");
    EXPECT_LT(r.tin.vertex_count(), full.vertex_count());
    std::vector<VertexId> vertex_of(full.vertex_count(), kNoId);
    for (VertexId v = 0; v < r.tin.vertex_count(); ++v) vertex_of[r.point_of_vertex[v]] = v;
    // Every piece of every contour: an edge of the result.
    for (const constraints::Piece& p : c.pieces) {
      const VertexId a = vertex_of[p.a], b = vertex_of[p.b];
      ASSERT_NE(a, kNoId) << "contour vertex dropped";
      ASSERT_NE(b, kNoId) << "contour vertex dropped";
      const EdgeId f = r.tin.find_edge(a, b);
      ASSERT_NE(f, kNoId) << "contour segment lost";
      EXPECT_TRUE(r.tin.is_constrained(f));
    }
    const double measured = test::max_vertical_error(r.tin, full.points(), full.heights());
    EXPECT_LE(measured, e + 1e-9);
    EXPECT_NEAR(measured, r.report.max_error, 1e-9);
    std::printf("%s, max error %g: %zu of %zu vertices, achieved %.4f, rmse %.4f\n", pair.name, e,
                r.tin.vertex_count(), full.vertex_count(), r.report.max_error, r.report.rmse);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Shared, RealPair,
    ::testing::Values(Pair{"topography", "las/Topography.las",
                           "pair_topography/Topography_contours_1m_3d.shp", 0.1},
                      Pair{"autzen", "las/autzen_trim.las",
                           "pair_autzen/autzen_trim_contours_2ft_3d.shp", 0.3}),
    [](const ::testing::TestParamInfo<Pair>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace tincdt::simplify
