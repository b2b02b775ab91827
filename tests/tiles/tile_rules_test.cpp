// The geometry of tiled jobs (tiles/tile_rules.hpp) against independent references: the tile
// lattice on its edges, the owner point's independence of corner order, the circumdisk bound
// against a long-double circumcircle, the conservative polygon tests against sampled points,
// and the rim against an exact point-in-polygon test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "predicates/predicates.hpp"
#include "tiles/tile_rules.hpp"

namespace {

using namespace tincdt;
using namespace tincdt::tiles;

TEST(TileGrid, EveryValueInExactlyOneCell) {
  std::mt19937_64 rng(7);
  for (const double size : {100.0, 0.1, 1000.0, 3.7, 250.0}) {
    const TileGrid g{size};
    std::uniform_real_distribution<double> at(-2e6, 6e6);
    for (int k = 0; k < 20000; ++k) {
      double v = at(rng);
      if (k % 4 == 0) v = g.edge(static_cast<std::int64_t>(std::floor(v / size)));  // on an edge
      const std::int64_t i = g.cell_of(v);
      EXPECT_LE(g.edge(i), v) << size << " " << v;
      EXPECT_LT(v, g.edge(i + 1)) << size << " " << v;
    }
  }
}

TEST(TileGrid, NeighboursShareTheirEdgeExactly) {
  const TileGrid g{0.3};
  for (std::int64_t col = -5; col < 5; ++col) {
    EXPECT_EQ(g.box(col, 0).max_x, g.box(col + 1, 0).min_x);
    const Point2 on_edge{g.edge(col + 1), 0.1};
    EXPECT_FALSE(g.holds(col, 0, on_edge));
    EXPECT_TRUE(g.holds(col + 1, 0, on_edge));
  }
}

TEST(OwnerPoint, SameBitsInAnyCornerOrder) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> at(-1, 1);
  for (int k = 0; k < 5000; ++k) {
    std::array<Point2, 3> p;
    for (Point2& q : p) q = {273000 + 100 * at(rng), 5274000 + 100 * at(rng)};
    const Point2 ref = owner_point(p[0], p[1], p[2]);
    std::sort(p.begin(), p.end(), [](Point2 a, Point2 b) { return a.x < b.x; });
    do {
      const Point2 c = owner_point(p[0], p[1], p[2]);
      EXPECT_EQ(c.x, ref.x);
      EXPECT_EQ(c.y, ref.y);
    } while (
        std::next_permutation(p.begin(), p.end(), [](Point2 a, Point2 b) { return a.x < b.x; }));
  }
}

// The circumcircle in long double, relative to a.
struct Circle {
  long double cx, cy, r;
};
Circle reference_circle(Point2 a, Point2 b, Point2 c) {
  const long double bx = static_cast<long double>(b.x) - a.x,
                    by = static_cast<long double>(b.y) - a.y;
  const long double cx = static_cast<long double>(c.x) - a.x,
                    cy = static_cast<long double>(c.y) - a.y;
  const long double d = 2 * (bx * cy - by * cx);
  const long double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const long double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
  return {a.x + ux, a.y + uy, std::sqrt(ux * ux + uy * uy)};
}

TEST(CircumdiskBound, HoldsTheCircumcircle) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> at(0, 1);
  int bounded = 0;
  for (int k = 0; k < 200000; ++k) {
    const double x0 = 500000, y0 = 5000000, s = k % 3 == 0 ? 0.05 : 50;
    Point2 a{x0 + s * at(rng), y0 + s * at(rng)}, b{x0 + s * at(rng), y0 + s * at(rng)};
    Point2 c{x0 + s * at(rng), y0 + s * at(rng)};
    if (k % 5 == 0) c = {(a.x + b.x) / 2 + 1e-9 * at(rng), (a.y + b.y) / 2};  // nearly flat
    if (predicates::orient2d(a, b, c) == 0) continue;
    const Disk d = circumdisk_bound(a, b, c);
    if (!std::isfinite(d.radius)) continue;
    ++bounded;
    const Circle ref = reference_circle(a, b, c);
    const long double dx = ref.cx - d.centre.x, dy = ref.cy - d.centre.y;
    // The reference disk inside the bound (long double has 11 more bits than double).
    EXPECT_LE(std::sqrt(dx * dx + dy * dy) + ref.r,
              static_cast<long double>(d.radius) * (1 + 1e-15L))
        << k;
    for (const Point2& p : {a, b, c})
      EXPECT_LE(std::hypot(p.x - d.centre.x, p.y - d.centre.y), d.radius) << k;
  }
  EXPECT_GT(bounded, 150000);
}

TEST(CircumdiskBound, InsideAndMissesAreConservative) {
  const Disk d{{10, 10}, 5};
  EXPECT_TRUE(inside(d, {4, 4, 16, 16}));
  EXPECT_FALSE(inside(d, {5, 4, 16, 16}));  // touching the side is not inside the open box
  EXPECT_TRUE(misses(d, {15.1, 0, 20, 20}));
  EXPECT_FALSE(misses(d, {15, 0, 20, 20}));
  EXPECT_DOUBLE_EQ(reach_beyond(d, {8, 8, 12, 12}), 3);
}

Polygon random_convex(std::mt19937_64& rng, double x0, double y0, double size) {
  std::uniform_real_distribution<double> at(0, size);
  std::vector<Point2> pts;
  for (int i = 0; i < 12; ++i) pts.push_back({x0 + at(rng), y0 + at(rng)});
  return convex_hull(pts);
}

// Calls F(k, polygon, at) for 3000 random convex polygons in [1000, 1010) x [2000, 2010), AT a
// generator of numbers in [0, 1) from SEED.
template <class F>
void for_random_polygons(std::uint64_t seed, F f) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  const auto at = [&] { return uniform(rng); };
  for (int k = 0; k < 3000; ++k) f(k, random_convex(rng, 1000, 2000, 10), at);
}

bool in_polygon(Point2 p, const Polygon& poly) {
  for (std::size_t i = 0; i < poly.size(); ++i)
    if (predicates::orient2d(poly[i], poly[(i + 1) % poly.size()], p) < 0) return false;
  return poly.size() >= 3;
}

TEST(PolygonTests, NeverMissWhatTheyShare) {
  int meets = 0;
  for_random_polygons(3, [&](int k, const Polygon& poly, const auto& at) {
    const Disk d{{1000 + 14 * at() - 2, 2000 + 14 * at() - 2}, 3 * at()};
    const std::array<Point2, 3> tri = {Point2{1000 + 12 * at(), 2000 + 12 * at()},
                                       Point2{1000 + 12 * at(), 2000 + 12 * at()},
                                       Point2{1000 + 12 * at(), 2000 + 12 * at()}};
    const bool ccw = predicates::orient2d(tri[0], tri[1], tri[2]) > 0;
    const Point2 u{1000 + 12 * at(), 2000 + 12 * at()}, v{1000 + 12 * at(), 2000};
    bool disk_shared = false, tri_shared = false, left_shared = false;
    for (int s = 0; s < 400; ++s) {
      const Point2 p{1000 + 12 * at() - 1, 2000 + 12 * at() - 1};
      if (!in_polygon(p, poly)) continue;
      disk_shared |= std::hypot(p.x - d.centre.x, p.y - d.centre.y) <= d.radius;
      if (ccw)
        tri_shared |= predicates::orient2d(tri[0], tri[1], p) >= 0 &&
                      predicates::orient2d(tri[1], tri[2], p) >= 0 &&
                      predicates::orient2d(tri[2], tri[0], p) >= 0;
      left_shared |= predicates::orient2d(u, v, p) > 0;
    }
    EXPECT_TRUE(!disk_shared || may_meet(d, poly, 0)) << k;
    EXPECT_TRUE(!tri_shared || may_meet(tri[0], tri[1], tri[2], poly, 0)) << k;
    EXPECT_TRUE(!left_shared || may_meet_left(u, v, poly, 0)) << k;
    meets += disk_shared + tri_shared + left_shared;
    // Clipping keeps every shared point.
    const Polygon left = clip_left(poly, u, v, 0);
    for (int s = 0; s < 50; ++s) {
      const Point2 p{1000 + 10 * at(), 2000 + 10 * at()};
      if (in_polygon(p, poly) && predicates::orient2d(u, v, p) > 0) {
        // Inside the clipped polygon up to rounding: no edge leaves it far outside.
        EXPECT_TRUE(may_meet(Disk{p, 1e-9}, left, 0)) << k;
      }
    }
  });
  EXPECT_GT(meets, 1000);  // the cases are not all apart
}

// A box is inside a polygon when every point of it is: sampled points of a box said inside are
// inside (strictly), and a box with a sampled point outside is never said inside.
TEST(PolygonTests, BoxInsideHoldsEveryPointOfTheBox) {
  int inside = 0;
  for_random_polygons(5, [&](int k, const Polygon& poly, const auto& at) {
    const double x = 1000 + 12 * at() - 1, y = 2000 + 12 * at() - 1;
    const BBox box{x, y, x + 4 * at(), y + 4 * at()};
    bool all_in = true;
    for (int s = 0; s < 200 && all_in; ++s) {
      const double fx = s < 4 ? s % 2 : at(), fy = s < 4 ? s / 2 : at();  // corners first
      all_in = in_polygon(
          {box.min_x + fx * (box.max_x - box.min_x), box.min_y + fy * (box.max_y - box.min_y)},
          poly);
    }
    // A convex polygon holds a box when it holds its four corners (random: none on an edge).
    const bool said = box_inside(box, poly);
    EXPECT_EQ(said, all_in) << k;
    inside += said;
    EXPECT_FALSE(box_inside(BBox{}, poly));  // an empty box
  });
  EXPECT_GT(inside, 100);
}

TEST(ConvexHull, AgainstEveryPointBeingInside) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> at(0, 40);  // lattice: many collinear points
  for (int k = 0; k < 200; ++k) {
    std::vector<Point2> pts;
    for (int i = 0; i < 60; ++i) pts.push_back({1.0 * at(rng), 1.0 * at(rng)});
    const std::vector<Point2> hull = convex_hull(pts);
    ASSERT_GE(hull.size(), 3u);
    for (std::size_t i = 0; i < hull.size(); ++i) {
      // Strictly convex: no collinear corner.
      EXPECT_GT(
          predicates::orient2d(hull[i], hull[(i + 1) % hull.size()], hull[(i + 2) % hull.size()]),
          0);
    }
    for (const Point2& p : pts) EXPECT_TRUE(in_polygon(p, hull));
  }
}

TEST(Rim, WhatItRefusesIsInsideTheInnerPolygon) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> at(0, 1);
  for (int k = 0; k < 50; ++k) {
    std::vector<Point2> pts;
    for (int i = 0; i < 40; ++i) pts.push_back({600000 + 300 * at(rng), 5000000 + 300 * at(rng)});
    const Rim rim{convex_hull(pts), 5 + 20 * at(rng)};
    const Polygon inner = rim.inner();
    for (int s = 0; s < 2000; ++s) {
      const Point2 p{600000 + 300 * at(rng), 5000000 + 300 * at(rng)};
      if (!in_polygon(p, rim.hull)) continue;
      EXPECT_TRUE(rim.holds(p) || may_meet(Disk{p, 0}, inner, 0)) << k;
    }
  }
}

TEST(MeetsConvex, BoxesAgainstAHull) {
  const std::vector<Point2> hull = convex_hull({{0, 0}, {10, 0}, {0, 10}});
  EXPECT_TRUE(meets_convex({1, 1, 2, 2}, hull));
  EXPECT_TRUE(meets_convex({4, 4, 8, 8}, hull));    // the corner (4, 4) is inside
  EXPECT_FALSE(meets_convex({5, 5, 8, 8}, hull));   // only touches the diagonal at (5, 5)
  EXPECT_FALSE(meets_convex({6, 6, 8, 8}, hull));   // beyond the diagonal
  EXPECT_FALSE(meets_convex({-3, 0, 0, 4}, hull));  // shares a side
  EXPECT_FALSE(meets_convex({-3, -3, -1, -1}, hull));
}

}  // namespace
