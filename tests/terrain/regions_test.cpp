// Regions of a TIN: triangles joined across unconstrained edges, each visited once, each wholly
// on one side of every constrained ring, against a point-in-polygon test of every triangle.
#include "terrain/regions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

// A ring of N points around (50, 50), radius R.
std::vector<Point2> ring(double r, int n) {
  std::vector<Point2> points;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n + 0.1;
    points.push_back({50 + r * std::cos(a), 50 + r * std::sin(a)});
  }
  return points;
}

// Inside the regular polygon of ring(R, N) (its inscribed circle is enough away from the sides).
bool inside(Point2 p, double r, int n) {
  const std::vector<Point2> c = ring(r, n);
  for (int k = 0; k < n; ++k) {
    const Point2 a = c[k], b = c[(k + 1) % n];
    if ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) < 0) return false;
  }
  return true;
}

TEST(Regions, EachTriangleOnceEachRegionOnOneSideOfEveryRing) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> at(0, 100);
    std::vector<Point3> points;
    for (int i = 0; i < 600; ++i) points.push_back({at(rng), at(rng), 0});
    std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
    test::add_ring(ring(20, 7), 0, points, segments);
    test::add_ring(ring(40, 11), 0, points, segments);
    const test::Built b = test::build_tin(points, segments);
    const mesh::Triangulation& tin = b.tin;

    std::vector<int> visits(tin.triangle_slots(), 0);
    std::set<int> sides;
    int regions = 0;
    for_each_region(
        tin, [](TriangleId) { return true; },
        [&](std::span<const TriangleId> members) {
          ++regions;
          std::set<int> side;
          for (const TriangleId t : members) {
            ++visits[t];
            const Point2 c = test::triangle_centroid(tin, tin.triangle(t));
            side.insert(inside(c, 20, 7) + inside(c, 40, 11));
          }
          EXPECT_EQ(side.size(), 1u) << "a region across a ring, seed " << seed;
          sides.insert(*side.begin());
          const TriangleId largest = largest_triangle(tin, members);
          for (const TriangleId t : members)
            EXPECT_LE(test::triangle_area(tin, tin.triangle(t)),
                      test::triangle_area(tin, tin.triangle(largest)));
          const TriangleId below = largest_triangle(tin, members, largest);
          EXPECT_TRUE(below == kNoId || below < largest);
        });
    EXPECT_EQ(regions, 3) << "seed " << seed;  // inside, between and outside the rings
    EXPECT_EQ(sides.size(), 3u);
    for (TriangleId t = 0; t < tin.triangle_slots(); ++t)
      EXPECT_EQ(visits[t], tin.is_ghost(t) ? 0 : 1) << "seed " << seed;
  }
}

// Only the triangles in scope, joined through triangles in scope.
TEST(Regions, ScopeSplitsRegionsAndLeavesTheRestOut) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> at(0, 100);
  std::vector<Point3> points;
  for (int i = 0; i < 800; ++i) points.push_back({at(rng), at(rng), 0});
  const test::Built b = test::build_tin(points);
  const mesh::Triangulation& tin = b.tin;
  // A band across the middle out of scope cuts the TIN into a south and a north region.
  const auto in_scope = [&](TriangleId t) {
    const double y = test::triangle_centroid(tin, tin.triangle(t)).y;
    return y < 40 || y > 60;
  };
  int regions = 0;
  for_each_region(tin, in_scope, [&](std::span<const TriangleId> members) {
    ++regions;
    const bool south = test::triangle_centroid(tin, tin.triangle(members[0])).y < 40;
    for (const TriangleId t : members) {
      EXPECT_TRUE(in_scope(t));
      EXPECT_EQ(test::triangle_centroid(tin, tin.triangle(t)).y < 40, south);
    }
  });
  EXPECT_EQ(regions, 2);
}

}  // namespace
}  // namespace tincdt::terrain
