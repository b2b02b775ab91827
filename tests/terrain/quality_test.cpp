// Quality statistics on hand-made meshes whose numbers are known.
#include "terrain/quality.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

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

// The per-corner measures the plain way (atan2 of cross and dot per corner, hypot per edge), as
// an independent reference for the pass that compares angles through dot products.
struct Reference {
  std::array<std::uint64_t, 18> angles{};
  double min_angle = 180, max_angle = 0, max_ratio = 0, min_length = HUGE_VAL, max_length = 0;
  std::uint64_t below_20 = 0, edges = 0;
};

Reference reference(const mesh::Triangulation& tin) {
  Reference r;
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    double len[3];
    for (int i = 0; i < 3; ++i) {
      const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]);
      len[i] = std::hypot(b.x - a.x, b.y - a.y);
      const EdgeId e = 3 * t + static_cast<EdgeId>(i);
      if (c[i] < c[(i + 1) % 3] || !tin.is_kept(mesh::triangle_of(tin.twin(e)))) {
        ++r.edges;
        r.min_length = std::min(r.min_length, len[i]);
        r.max_length = std::max(r.max_length, len[i]);
      }
    }
    double smallest = 180;
    for (int i = 0; i < 3; ++i) {
      const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]),
                   d = tin.point(c[(i + 2) % 3]);
      const double bx = b.x - a.x, by = b.y - a.y, dx = d.x - a.x, dy = d.y - a.y;
      const double deg =
          std::atan2(std::fabs(bx * dy - by * dx), bx * dx + by * dy) * 180 / std::numbers::pi;
      smallest = std::min(smallest, deg);
      r.max_angle = std::max(r.max_angle, deg);
      ++r.angles[std::min<std::size_t>(17, static_cast<std::size_t>(deg / 10))];
    }
    r.min_angle = std::min(r.min_angle, smallest);
    if (smallest < 20) ++r.below_20;
    const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
    const double area2 = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    r.max_ratio = std::max(
        r.max_ratio, len[0] * len[1] * len[2] * (len[0] + len[1] + len[2]) / (2 * area2 * area2));
  });
  return r;
}

// Random clouds from uniform to strongly clustered (slivers, near-180-degree angles), some with
// removed triangles: the cheap pass agrees with the reference, and is the same on 1 and 2 threads.
TEST(Quality, AgreesWithAtan2PerCornerOnRandomTins) {
  std::mt19937_64 rng(20260101);
  for (int round = 0; round < 12; ++round) {
    SCOPED_TRACE(round);
    const std::size_t n = round < 6 ? 500 : 70000;  // the large ones span several blocks
    std::uniform_real_distribution<double> u(0, 1000);
    std::normal_distribution<double> g(0, round % 3 == 0 ? 1 : 50);
    std::vector<Point3> pts;
    for (std::size_t i = 0; i < n; ++i) {
      const bool clustered = round % 2 == 1 && i % 3 == 0;
      const double x = clustered ? 500 + g(rng) : u(rng), y = clustered ? 500 + g(rng) : u(rng);
      pts.push_back({273000 + x, 5274000 + y, u(rng) / 10});
    }
    test::Built b = test::build_tin(std::move(pts));
    if (round % 4 == 2) {
      std::size_t k = 0;
      b.tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>&) {
        if (++k % 7 == 0) b.tin.set_removed(t, true);
      });
    }
    const QualityReport q = measure_quality(b.tin, nullptr, 1);
    const Reference r = reference(b.tin);
    EXPECT_EQ(q.triangles, b.tin.triangle_count());
    EXPECT_EQ(q.angle_histogram, r.angles);
    EXPECT_EQ(q.triangles_below_20deg, r.below_20);
    EXPECT_NEAR(q.min_angle_deg, r.min_angle, 1e-9 * std::max(1.0, r.min_angle));
    EXPECT_NEAR(q.max_angle_deg, r.max_angle, 1e-9 * r.max_angle);
    EXPECT_NEAR(q.max_radius_ratio, r.max_ratio, 1e-12 * r.max_ratio);
    EXPECT_EQ(q.edges, r.edges);
    EXPECT_NEAR(q.min_edge_length, r.min_length, 1e-12 * r.min_length);
    EXPECT_NEAR(q.max_edge_length, r.max_length, 1e-12 * r.max_length);
    EXPECT_EQ(std::accumulate(q.edge_length_histogram.begin(), q.edge_length_histogram.end(), 0ull),
              q.edges);
    EXPECT_EQ(measure_quality(b.tin, nullptr, 2).to_json(), q.to_json());
  }
}

}  // namespace
}  // namespace tincdt::terrain
