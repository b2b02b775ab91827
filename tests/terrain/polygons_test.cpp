// Clip, erase and replace polygons: exact classification, exact areas when the rings are in the
// TIN, the fast region path agreeing with triangle-by-triangle tests.
#include "terrain/polygons.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "core/error.hpp"
#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

using test::build_tin;

// An independent even-odd test in plain doubles (fine away from the rings).
bool inside_naive(const std::vector<std::vector<Point2>>& rings, Point2 p) {
  bool in = false;
  for (const auto& ring : rings)
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Point2 a = ring[i], b = ring[j];
      if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
        in = !in;
    }
  return in;
}

double distance_to_rings(const std::vector<std::vector<Point2>>& rings, Point2 p) {
  double best = HUGE_VAL;
  for (const auto& ring : rings)
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point2 a = ring[i], b = ring[(i + 1) % ring.size()];
      const double dx = b.x - a.x, dy = b.y - a.y;
      const double t =
          std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      best = std::min(best, std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy));
    }
  return best;
}

double surface(double x, double y) {
  return 100 + 0.2 * x - 0.1 * y;
}

// A jittered grid over [0, 100]^2 (with large map offsets) and a polygon with a hole, whose rings
// are points of the TIN and constrained edges.
struct Scene {
  test::Built b;
  Polygon polygon;
  double area = 0;
};

Scene make_scene(double x0 = 0, double y0 = 0) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.8, 0.8);
  std::vector<Point3> pts;
  for (int i = 0; i <= 25; ++i)
    for (int j = 0; j <= 25; ++j) {
      const double x = 4 * i + jitter(rng), y = 4 * j + jitter(rng);
      pts.push_back({x0 + x, y0 + y, surface(x, y)});
    }
  Scene s;
  std::vector<Point2> outer, hole;
  for (int k = 0; k < 13; ++k) {  // an irregular 13-gon, counter-clockwise
    const double a = 2 * std::numbers::pi * k / 13;
    const double r = 38 + 6 * std::sin(3 * a);
    outer.push_back({x0 + 50 + r * std::cos(a), y0 + 50 + r * std::sin(a)});
  }
  for (int k = 0; k < 5; ++k) {  // a pentagon hole, clockwise
    const double a = -2 * std::numbers::pi * k / 5 + 0.3;
    hole.push_back({x0 + 55 + 11 * std::cos(a), y0 + 48 + 11 * std::sin(a)});
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  for (const auto* ring : {&outer, &hole}) {
    const auto first = static_cast<std::uint32_t>(pts.size());
    for (const Point2& p : *ring) pts.push_back({p.x, p.y, surface(p.x - x0, p.y - y0)});
    const auto n = static_cast<std::uint32_t>(ring->size());
    for (std::uint32_t i = 0; i < n; ++i) segs.push_back({first + i, first + (i + 1) % n});
  }
  s.b = build_tin(std::move(pts), segs);
  s.area = std::fabs(test::ring_area(outer)) - std::fabs(test::ring_area(hole));
  s.polygon.rings = {outer, hole};
  return s;
}

TEST(PolygonIndex, EvenOddWithHolesAndBoundaries) {
  Polygon p;
  p.rings = {{{0, 0}, {0, 10}, {10, 10}, {10, 0}, {0, 0}},  // clockwise, closing point repeated
             {{3, 3}, {7, 3}, {7, 7}, {3, 7}}};
  const PolygonIndex index({p});
  EXPECT_EQ(index.edge_count(), 8u);
  EXPECT_EQ(index.polygon_at({1, 1}), 0u);
  EXPECT_EQ(index.polygon_at({5, 5}), kNoId);  // in the hole
  EXPECT_EQ(index.polygon_at({11, 5}), kNoId);
  EXPECT_EQ(index.polygon_at({-1, 5}), kNoId);
  EXPECT_EQ(index.polygon_at({9.999999999999998, 9.999999999999998}), 0u);
  EXPECT_EQ(index.polygon_at({10.000000000000002, 5}), kNoId);
  // On the rings: only polygon_at_or_on counts them.
  for (Point2 q : {Point2{10, 5}, Point2{0, 0}, Point2{5, 10}, Point2{5, 0}, Point2{3, 5},
                   Point2{7, 7}, Point2{10, 10}}) {
    EXPECT_EQ(index.polygon_at_or_on(q), 0u) << q.x << "," << q.y;
  }
  EXPECT_EQ(index.polygon_at_or_on({11, 10}), kNoId);
  EXPECT_EQ(index.polygon_at_or_on({5, 5}), kNoId);
}

TEST(PolygonIndex, RayThroughVerticesCountsOnce) {
  Polygon diamond;
  diamond.rings = {{{0, 5}, {5, 0}, {10, 5}, {5, 10}}};
  const PolygonIndex index({diamond});
  EXPECT_EQ(index.polygon_at({2, 5}), 0u);      // ray through vertex (10, 5)
  EXPECT_EQ(index.polygon_at({-2, 5}), kNoId);  // through (0, 5) and (10, 5)
  EXPECT_EQ(index.polygon_at({5, 9.5}), 0u);
  EXPECT_EQ(index.polygon_at({5, 10}), kNoId);  // the top vertex itself
  EXPECT_EQ(index.polygon_at_or_on({5, 10}), 0u);
}

TEST(PolygonIndex, LaterPolygonsWinAndBadRingsThrow) {
  Polygon big, small;
  big.rings = {{{0, 0}, {10, 0}, {10, 10}, {0, 10}}};
  small.rings = {{{2, 2}, {4, 2}, {4, 4}, {2, 4}}};
  const PolygonIndex index({big, small});
  EXPECT_EQ(index.polygon_at({3, 3}), 1u);
  EXPECT_EQ(index.polygon_at({6, 6}), 0u);
  EXPECT_EQ(PolygonIndex({}).polygon_at({0, 0}), kNoId);

  Polygon bad;
  bad.rings = {{{0, 0}, {1, 1}, {0, 0}}};
  EXPECT_THROW(PolygonIndex({big, bad}), GeometryError);
  bad.rings = {{{0, 0}, {1, 1}, {std::nan(""), 0}}};
  EXPECT_THROW(PolygonIndex({bad}), GeometryError);
}

TEST(Polygons, ClipKeepsExactlyThePolygon) {
  for (double offset : {0.0, 5e5}) {  // also at UTM-sized coordinates
    Scene s = make_scene(offset, 8 * offset);
    const std::size_t before = s.b.tin.triangle_count();
    const std::uint64_t removed = remove_outside(s.b.tin, {s.polygon});
    EXPECT_GT(removed, 0u);
    EXPECT_EQ(s.b.tin.triangle_count(), before - removed);
    EXPECT_EQ(s.b.tin.validate(), "");
    std::uint64_t outside = 0;
    s.b.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      if (!inside_naive(s.polygon.rings, test::triangle_centroid(s.b.tin, c))) ++outside;
    });
    EXPECT_EQ(outside, 0u);
    EXPECT_NEAR(test::kept_area(s.b.tin), s.area, 1e-9 * s.area);
  }
}

TEST(Polygons, EraseKeepsTheRest) {
  Scene s = make_scene();
  const double total = test::kept_area(s.b.tin);
  const std::size_t before = s.b.tin.triangle_count();
  mesh::Triangulation copy = s.b.tin;
  const std::uint64_t removed = remove_inside(s.b.tin, {s.polygon});
  EXPECT_NEAR(test::kept_area(s.b.tin), total - s.area, 1e-9 * total);
  s.b.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    EXPECT_FALSE(inside_naive(s.polygon.rings, test::triangle_centroid(s.b.tin, c)));
  });
  // Clip and erase split the triangles between them.
  EXPECT_EQ(removed + remove_outside(copy, {s.polygon}), before);
  EXPECT_EQ(s.b.tin.validate(), "");
}

TEST(Polygons, ReplaceSetsVerticesOnAndInside) {
  Scene s = make_scene();
  const std::vector<double> z0 = s.b.tin.heights();
  const std::uint64_t set = set_z_inside(s.b.tin, {s.polygon}, 123.0);
  std::uint64_t expected = 0;
  for (VertexId v = 0; v < s.b.tin.vertex_count(); ++v) {
    const Point2 p = s.b.tin.point(v);
    const double d = distance_to_rings(s.polygon.rings, p);
    if (d < 1e-9 || inside_naive(s.polygon.rings, p)) {
      ++expected;
      EXPECT_EQ(s.b.tin.z(v), 123.0) << "vertex " << v << " on or inside";
    } else {
      EXPECT_EQ(s.b.tin.z(v), z0[v]) << "vertex " << v << " outside";
    }
  }
  EXPECT_EQ(set, expected);
  EXPECT_GT(set, 20u);
  EXPECT_THROW(set_z_inside(s.b.tin, {s.polygon}, std::nan("")), GeometryError);
}

TEST(Polygons, PerPolygonZLaterWins) {
  // Rings not in the TIN: the per-vertex path. Two overlapping squares.
  Scene s = make_scene();
  Polygon a, b;
  a.rings = {{{10, 10}, {60, 10}, {60, 60}, {10, 60}}};
  a.z = 1;
  b.rings = {{{40, 40}, {90, 40}, {90, 90}, {40, 90}}};
  b.z = 2;
  const std::vector<double> z0 = s.b.tin.heights();
  set_polygon_z_inside(s.b.tin, {a, b}, {.boundaries_constrained = false});
  for (VertexId v = 0; v < s.b.tin.vertex_count(); ++v) {
    const Point2 p = s.b.tin.point(v);
    const bool in_a = p.x >= 10 && p.x <= 60 && p.y >= 10 && p.y <= 60;
    const bool in_b = p.x >= 40 && p.x <= 90 && p.y >= 40 && p.y <= 90;
    EXPECT_EQ(s.b.tin.z(v), in_b ? 2.0 : in_a ? 1.0 : z0[v]);
  }
  Polygon no_z = a;
  no_z.z = std::nan("");
  EXPECT_THROW(set_polygon_z_inside(s.b.tin, {no_z}), GeometryError);
}

TEST(Polygons, ManyRingVerticesOverManyTriangles) {
  // A wavy ring of 10,000 vertices in a 301 x 301 grid (~180,000 triangles): the region path
  // and the per-triangle path (which never looks at constraints) must agree triangle for
  // triangle, and the clipped area must be the ring's.
  std::vector<Point3> pts;
  for (int i = 0; i <= 300; ++i)
    for (int j = 0; j <= 300; ++j) pts.push_back({i / 3.0, j / 3.0, 0});
  std::vector<Point2> ring;
  const int n = 10000;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    const double r = 40 + 3 * std::sin(37 * a);
    ring.push_back({50.0001 + r * std::cos(a), 49.9999 + r * std::sin(a)});
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  test::add_ring(ring, 0, pts, segs);
  auto b = build_tin(std::move(pts), segs);
  Polygon p;
  p.rings = {ring};
  const PolygonIndex index({p});

  const auto t0 = std::chrono::steady_clock::now();
  const auto by_region = classify_triangles(b.tin, index);
  const auto t1 = std::chrono::steady_clock::now();
  const auto by_triangle = classify_triangles(b.tin, index, {.boundaries_constrained = false});
  const auto t2 = std::chrono::steady_clock::now();
  std::uint64_t differ = 0, inside = 0;
  for (std::size_t t = 0; t < by_region.size(); ++t) {
    differ += by_region[t] != by_triangle[t];
    inside += by_region[t] == 0;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(inside, 10000u);
  std::printf("[ info ] %zu triangles, %d ring vertices: regions %.3f s, per triangle %.3f s\n",
              b.tin.triangle_count(), n, std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count());
  remove_outside(b.tin, {p});
  const double area = std::fabs(test::ring_area(ring));
  EXPECT_NEAR(test::kept_area(b.tin), area, 1e-9 * area);
}

}  // namespace
}  // namespace tincdt::terrain
