// Clip and erase rings cut to the TIN's convex hull: the hull without collinear vertices, rings
// inside kept whole, rings across the hull cut along it (its corners reused), rings outside or
// only touching it left out.
#include "terrain/hull_cut.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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
