// InteriorFilter against orient2d(): whenever the filter says a point is strictly inside, all
// three exact orientations are positive, on random, collinear, near-edge and extreme inputs;
// and it does say so for most points well inside, so that it is of use.
#include "predicates/interior_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "predicates/predicates.hpp"

namespace tincdt::predicates {
namespace {

bool exactly_inside(Point2 a, Point2 b, Point2 c, Point2 q) {
  return orient2d(a, b, q) > 0 && orient2d(b, c, q) > 0 && orient2d(c, a, q) > 0;
}

// Checks the filter on q and on the points a few ulps around it; returns how often it held.
int check(const InteriorFilter& filter, Point2 a, Point2 b, Point2 c, Point2 q) {
  int held = 0;
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      Point2 p = q;
      for (int k = 0; k < std::abs(dx); ++k)
        p.x = std::nextafter(p.x, dx > 0 ? INFINITY : -INFINITY);
      for (int k = 0; k < std::abs(dy); ++k)
        p.y = std::nextafter(p.y, dy > 0 ? INFINITY : -INFINITY);
      if (filter.surely_inside(p)) {
        ++held;
        EXPECT_TRUE(exactly_inside(a, b, c, p))
            << "triangle (" << a.x << ", " << a.y << ") (" << b.x << ", " << b.y << ") (" << c.x
            << ", " << c.y << "), point (" << p.x << ", " << p.y << ")";
      }
    }
  }
  return held;
}

// Random counter-clockwise triangles around `centre` of about `size`, and points in their box,
// on their edges (at fractions that round) and at their corners. `useful`: the filter holds at
// the centroids of fat triangles (not where products underflow past its guard term).
void random_cases(double centre, double size, unsigned seed, bool useful = true) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto point = [&] { return Point2{centre + size * unit(rng), centre + size * unit(rng)}; };
  int well_inside = 0, held_there = 0;
  for (int i = 0; i < 2000; ++i) {
    Point2 a = point(), b = point(), c = point();
    if (orient2d(a, b, c) == 0) continue;
    if (orient2d(a, b, c) < 0) std::swap(b, c);
    const InteriorFilter filter(a, b, c);
    // The centroid (rounded) of a triangle that is not too thin is well inside.
    const Point2 g{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
    // (Fatness in units of `size`, which neither underflow nor overflow.)
    const auto unit_point = [&](Point2 p) {
      return Point2{(p.x - centre) / size, (p.y - centre) / size};
    };
    const Point2 ua = unit_point(a), ub = unit_point(b), uc = unit_point(c);
    const double area = std::fabs((ub.x - ua.x) * (uc.y - ua.y) - (ub.y - ua.y) * (uc.x - ua.x));
    const double longest =
        std::max({std::hypot(ub.x - ua.x, ub.y - ua.y), std::hypot(uc.x - ub.x, uc.y - ub.y),
                  std::hypot(ua.x - uc.x, ua.y - uc.y)});
    // (And, so that rounding the centroid cannot matter, all points 4 ulps around it inside.)
    const auto ulps = [](double v, int k) {
      for (int j = 0; j < std::abs(k); ++j) v = std::nextafter(v, k > 0 ? INFINITY : -INFINITY);
      return v;
    };
    bool around = true;
    for (int k : {-4, 4})
      for (int l : {-4, 4}) around &= exactly_inside(a, b, c, {ulps(g.x, k), ulps(g.y, l)});
    if (area > 0.01 * longest * longest && around) {
      ++well_inside;
      held_there += filter.surely_inside(g);
    }
    check(filter, a, b, c, g);
    for (const Point2 corner : {a, b, c}) check(filter, a, b, c, corner);
    for (double t : {0.5, 1.0 / 3, 0.1, 1e-9}) {
      check(filter, a, b, c, {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      check(filter, a, b, c, {b.x + t * (c.x - b.x), b.y + t * (c.y - b.y)});
      check(filter, a, b, c, {c.x + t * (a.x - c.x), c.y + t * (a.y - c.y)});
    }
    for (int k = 0; k < 20; ++k) check(filter, a, b, c, point());
    // Clockwise, it never holds.
    const InteriorFilter reversed(a, c, b);
    EXPECT_FALSE(reversed.surely_inside(g));
  }
  ASSERT_GT(well_inside, 100);
  if (useful) {
    EXPECT_EQ(held_there, well_inside) << "the filter misses centroids of fat triangles";
  }
}

TEST(InteriorFilter, RandomTriangles) {
  random_cases(0, 1, 1);
}
TEST(InteriorFilter, RandomUtmTriangles) {
  random_cases(5.0e6, 50, 2);
}
TEST(InteriorFilter, TinyTriangles) {
  random_cases(1e-300, 1e-300, 3, false);
}
TEST(InteriorFilter, SubnormalTriangles) {
  random_cases(0, 1e-310, 4, false);
}
TEST(InteriorFilter, LargeTriangles) {
  random_cases(1e150, 1e150, 5);
}
TEST(InteriorFilter, HugeTriangles) {
  random_cases(1e300, 1e300, 7, false);
}  // products overflow
TEST(InteriorFilter, UtmSliversAtTheirLimits) {
  random_cases(4.2e6, 1e-6, 6);
}

// Grid cells and their diagonals, as in a DEM: points on edges and on the diagonal's lattice
// points never count as inside.
TEST(InteriorFilter, LatticePointsOnEdges) {
  for (double origin : {0.0, 500000.0, 4.5e6}) {
    const Point2 a{origin, origin}, b{origin + 64, origin + 32}, c{origin + 16, origin + 48};
    const InteriorFilter filter(a, b, c);
    int held = 0;
    for (int x = -2; x <= 66; ++x)
      for (int y = -2; y <= 50; ++y) held += check(filter, a, b, c, {origin + x, origin + y});
    EXPECT_GT(held, 1000);
  }
}

// Flat triangles (exactly: small integers times a power of two, so every sum is exact): no
// point is inside, in either order.
TEST(InteriorFilter, CollinearTrianglesNeverHold) {
  std::mt19937_64 rng(8);
  std::uniform_int_distribution<int> coordinate(-1000000, 1000000), offset(-64, 64);
  for (double scale : {1.0, 0x1p-20, 0x1p20}) {
    for (int i = 0; i < 500; ++i) {
      const Point2 a{scale * coordinate(rng), scale * coordinate(rng)};
      const Point2 step{scale * offset(rng), scale * offset(rng)};
      const Point2 b{a.x + step.x, a.y + step.y}, c{a.x + 3 * step.x, a.y + 3 * step.y};
      const Point2 mid{a.x + 1.5 * step.x, a.y + 1.5 * step.y};
      EXPECT_EQ(check(InteriorFilter(a, b, c), a, b, c, mid), 0);
      EXPECT_EQ(check(InteriorFilter(a, c, b), a, c, b, mid), 0);
      EXPECT_EQ(check(InteriorFilter(a, c, b), a, c, b, b), 0);
    }
  }
}

// Past 2^500 a product could overflow, and one infinite product passes any finite bound: the
// filter then never answers.
TEST(InteriorFilter, NeverSureWhereProductsCouldOverflow) {
  EXPECT_TRUE(InteriorFilter({0, 0}, {0x1p499, 0}, {0, 0x1p499}).surely_inside({0x1p497, 0x1p497}));
  EXPECT_FALSE(
      InteriorFilter({0, 0}, {0x1p501, 0}, {0, 0x1p501}).surely_inside({0x1p499, 0x1p499}));
  EXPECT_TRUE(std::isinf(cross_bound({1, 1}, 0x1p500)));
  EXPECT_TRUE(std::isinf(cross_bound({1, 1}, std::nan(""))));
}

TEST(InteriorFilter, OverflowAndNaNNeverHold) {
  const double big = std::numeric_limits<double>::max();
  const Point2 a{-big, -big}, b{big, -big}, c{0, big};
  const InteriorFilter filter(a, b, c);  // edges overflow to infinity
  EXPECT_FALSE(filter.surely_inside({0, 0}));
  const InteriorFilter unit({0, 0}, {1, 0}, {0, 1});
  EXPECT_TRUE(unit.surely_inside({0.25, 0.25}));
  EXPECT_FALSE(unit.surely_inside({std::nan(""), 0.25}));
  EXPECT_FALSE(unit.surely_inside({0.25, INFINITY}));
}

}  // namespace
}  // namespace tincdt::predicates
