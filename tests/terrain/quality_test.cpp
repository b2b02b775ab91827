// Quality statistics on hand-made meshes whose numbers are known.
#include "terrain/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "mesh/point_insertion.hpp"
#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

// A triangulation of exactly the given points (3 or 4, in general position).
mesh::Triangulation small_tin(const std::vector<Point3>& pts) {
  mesh::Triangulation tin;
  for (const Point3& p : pts) tin.add_vertex({p.x, p.y}, p.z);
  mesh::PointInserter ins(tin);
  ins.start(0, 1, 2);
  for (VertexId v = 3; v < pts.size(); ++v) ins.insert(v);
  tin.recount();
  return tin;
}

TEST(Quality, EquilateralTriangle) {
  const double h = std::sqrt(3.0) / 2;
  const mesh::Triangulation tin = small_tin({{0, 0, 5}, {1, 0, 5}, {0.5, h, 5}});
  const QualityReport q = measure_quality(tin);
  EXPECT_EQ(q.triangles, 1u);
  EXPECT_EQ(q.vertices, 3u);
  EXPECT_NEAR(q.min_angle_deg, 60, 1e-12);
  EXPECT_NEAR(q.max_angle_deg, 60, 1e-12);
  EXPECT_NEAR(q.max_radius_ratio, 2, 1e-12);
  EXPECT_EQ(q.triangles_below_20deg, 0u);
  EXPECT_NEAR(q.area_2d, h / 2, 1e-15);
  EXPECT_NEAR(q.area_3d, h / 2, 1e-15);
  // The three 60-degree angles land in [60, 70) (or [50, 60) by a rounding hair).
  EXPECT_EQ(q.angle_histogram[5] + q.angle_histogram[6], 3u);
  EXPECT_EQ(q.flat_triangles, 1u);  // equal z, no contour rule
  EXPECT_EQ(q.edges, 3u);
  EXPECT_NEAR(q.min_edge_length, 1, 1e-15);
  EXPECT_NEAR(q.max_edge_length, 1, 1e-15);
  ASSERT_EQ(q.edge_length_bin_edges.size(), q.edge_length_histogram.size() + 1);
  EXPECT_EQ(std::accumulate(q.edge_length_histogram.begin(), q.edge_length_histogram.end(),
                            std::uint64_t{0}),
            3u);
  EXPECT_LE(q.edge_length_bin_edges.front(), 1.0);
  EXPECT_GT(q.edge_length_bin_edges.back(), 1.0);

  // With contour flags the triangle is flat only if all three corners are flagged.
  std::vector<std::uint8_t> on{1, 1, 0};
  EXPECT_EQ(measure_quality(tin, &on).flat_triangles, 0u);
  on[2] = 1;
  EXPECT_EQ(measure_quality(tin, &on).flat_triangles, 1u);
}

TEST(Quality, RightTriangleAndSliver) {
  // Unit square split along a diagonal, plus a sliver off its right side.
  const mesh::Triangulation tin =
      small_tin({{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {1, 1, 1}, {3, 0.5, 2}});
  const QualityReport q = measure_quality(tin);
  ASSERT_EQ(q.triangles, 3u);
  EXPECT_EQ(q.vertices, 5u);
  EXPECT_NEAR(q.area_2d, 1 + 0.5 * 1 * 2, 1e-12);
  // The narrow triangle's angle at (3, 0.5) is 2 atan(1/4); its others are 90 - atan(1/4).
  EXPECT_NEAR(q.min_angle_deg, 28.072486935852954, 1e-9);
  EXPECT_NEAR(q.max_angle_deg, 90, 1e-9);
  EXPECT_EQ(q.angle_histogram[9], 2u);  // the two right angles
  EXPECT_EQ(q.angle_histogram[4], 4u);  // four 45-degree angles
  EXPECT_EQ(q.angle_histogram[2], 1u);
  EXPECT_EQ(q.angle_histogram[7], 2u);
  EXPECT_EQ(q.triangles_below_20deg, 0u);
  EXPECT_EQ(q.edges, 7u);
  // R/r: 1 + sqrt(2) for the right isosceles halves, abc(a + b + c) / (8 A^2) = 2.7216... for
  // the narrow one (a = b = sqrt(4.25), c = 1, A = 1).
  EXPECT_NEAR(q.max_radius_ratio, 2.721649863609382, 1e-9);
  EXPECT_EQ(q.flat_triangles, 0u);
}

TEST(Quality, OnlyKeptTrianglesAndJson) {
  mesh::Triangulation tin = small_tin({{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {1, 1, 1}});
  QualityReport q = measure_quality(tin);
  EXPECT_EQ(q.triangles, 2u);
  EXPECT_EQ(q.edges, 5u);
  const std::string json = q.to_json();
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.back(), '}');
  EXPECT_NE(json.find("\"triangles\":2,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"area_2d\":1,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"angle_histogram\":[0,0,0,0,4,0,0,0,0,2,0,0,0,0,0,0,0,0]"),
            std::string::npos)
      << json;

  tin.for_each_triangle(
      [&](TriangleId t, const std::array<VertexId, 3>&) { tin.set_removed(t, true); });
  q = measure_quality(tin);
  EXPECT_EQ(q.triangles, 0u);
  EXPECT_EQ(q.vertices, 0u);
  EXPECT_TRUE(std::isnan(q.min_angle_deg));
  const std::string empty = q.to_json();
  EXPECT_NE(empty.find("\"min_angle_deg\":null"), std::string::npos) << empty;
  EXPECT_NE(empty.find("\"edge_length_bin_edges\":[]"), std::string::npos) << empty;
}

}  // namespace
}  // namespace tincdt::terrain
