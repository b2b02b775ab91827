// Clip and erase rings cut to the TIN's convex hull: the hull without collinear vertices, rings
// inside kept whole, rings across the hull cut along it (its corners reused), rings outside or
// only touching it left out.
#include "terrain/hull_cut.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "predicates/predicates.hpp"
#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

using test::build_tin;

// A 5 x 5 lattice on [0, 4]^2: its hull is the square, with collinear points on every side.
mesh::Triangulation square_tin() {
  std::vector<Point3> points;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) points.push_back({double(i), double(j), double(i + j)});
  return build_tin(std::move(points)).tin;
}

double area(const std::vector<Point3>& ring) {
  double a = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point3& p = ring[i];
    const Point3& q = ring[(i + 1) % ring.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return std::fabs(a) / 2;
}

TEST(HullCut, TheHullHasOnlyItsCorners) {
  const std::vector<Point2> hull = strict_hull(square_tin());
  ASSERT_EQ(hull.size(), 4u);
  double signed_area = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Point2 p = hull[i], q = hull[(i + 1) % hull.size()];
    EXPECT_TRUE((p.x == 0 || p.x == 4) && (p.y == 0 || p.y == 4));
    signed_area += p.x * q.y - q.x * p.y;
  }
  EXPECT_EQ(signed_area / 2, 16);  // counter-clockwise
  const Point2 inside = interior_point(hull);
  EXPECT_TRUE(inside.x > 0 && inside.x < 4 && inside.y > 0 && inside.y < 4);
  EXPECT_TRUE(inside_or_on(hull, {4, 2}));
  EXPECT_FALSE(inside_or_on(hull, {4.5, 2}));
}

// The hull by gift wrapping from the least point (an independent reference): counter-clockwise,
// each next vertex the farthest point with nothing to its right.
std::vector<Point2> wrapped_hull(const std::vector<Point3>& points) {
  const auto less = [](Point2 a, Point2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); };
  Point2 start{points[0].x, points[0].y};
  for (const Point3& p : points)
    if (less({p.x, p.y}, start)) start = {p.x, p.y};
  std::vector<Point2> hull;
  Point2 at = start;
  do {
    hull.push_back(at);
    Point2 next = at;
    for (const Point3& p : points) {
      const Point2 q{p.x, p.y};
      if (q.x == at.x && q.y == at.y) continue;
      const int o = next.x == at.x && next.y == at.y ? -1 : predicates::orient2d(at, next, q);
      const auto far = [&](Point2 r) { return std::hypot(r.x - at.x, r.y - at.y); };
      if (o < 0 || (o == 0 && far(q) > far(next))) next = q;
    }
    at = next;
  } while ((at.x != start.x || at.y != start.y) && hull.size() <= points.size());
  return hull;
}

TEST(HullCut, TheHullStartsAtItsLeastPointWhateverTheOrderOfThePoints) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(0, 100);
  for (int round = 0; round < 20; ++round) {
    std::vector<Point3> points;
    const int n = 20 + round * 15;
    for (int i = 0; i < n; ++i) points.push_back({coordinate(rng), coordinate(rng), 0});
    if (round % 4 == 0) points.push_back({0, 50, 0}), points.push_back({0, 60, 0});
    const std::vector<Point2> reference = wrapped_hull(points);
    for (int order = 0; order < 3; ++order) {
      std::shuffle(points.begin(), points.end(), rng);
      const std::vector<Point2> hull = strict_hull(build_tin(points).tin);
      ASSERT_EQ(hull.size(), reference.size()) << "round " << round;
      for (std::size_t i = 0; i < hull.size(); ++i) {
        EXPECT_EQ(hull[i].x, reference[i].x) << "round " << round << ", vertex " << i;
        EXPECT_EQ(hull[i].y, reference[i].y) << "round " << round << ", vertex " << i;
      }
    }
  }
}

TEST(HullCut, RingsAcrossTheHullAreCutAlongIt) {
  const std::vector<Point2> hull = strict_hull(square_tin());
  const Point2 inside = interior_point(hull);
  // Half outside: x from 2 to 6, z along the ring.
  const std::vector<Point3> half = {{2, 1, 0}, {6, 1, 4}, {6, 3, 4}, {2, 3, 0}};
  const std::vector<Point3> cut = cut_to_hull(half, hull, inside);
  ASSERT_EQ(cut.size(), 4u);
  EXPECT_EQ(area(cut), 4);
  for (const Point3& p : cut) {
    EXPECT_TRUE(inside_or_on(hull, {p.x, p.y}));
    if (p.x == 4) {
      EXPECT_EQ(p.z, 2);  // interpolated along the ring
    }
  }
  // Around a corner of the hull: the corner itself is a vertex of the cut ring.
  const std::vector<Point3> corner = {{3, 3, 0}, {5, 3, 0}, {5, 5, 0}, {3, 5, 0}};
  const std::vector<Point3> around = cut_to_hull(corner, hull, inside);
  EXPECT_EQ(area(around), 1);
  bool has_corner = false;
  for (const Point3& p : around) has_corner = has_corner || (p.x == 4 && p.y == 4);
  EXPECT_TRUE(has_corner);
  // Wholly outside, and touching the hull along one side only: nothing left.
  EXPECT_TRUE(cut_to_hull({{5, 1, 0}, {6, 1, 0}, {6, 2, 0}}, hull, inside).empty());
  EXPECT_TRUE(cut_to_hull({{4, 1, 0}, {6, 1, 0}, {6, 2, 0}, {4, 2, 0}}, hull, inside).empty());
}

TEST(HullCut, ZeroAreaRings) {
  EXPECT_TRUE(zero_area({{0, 0, 0}, {1, 1, 0}, {3, 3, 0}}));
  EXPECT_FALSE(zero_area({{0, 0, 0}, {1, 1, 0}, {3, 2, 0}}));
}

}  // namespace
}  // namespace tincdt::terrain
