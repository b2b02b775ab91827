// Property tests of the Delaunay stage: validate() on thousands of random and degenerate inputs,
// checked against independent references (brute-force empty circles, hull size, point map).
#include "delaunay/delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include "core/error.hpp"
#include "predicates/predicates.hpp"
#include "support/delaunay_checks.hpp"

namespace tincdt::delaunay {
namespace {

using mesh::Triangulation;
using test::globally_delaunay;
using test::hull_vertex_count;

void expect_valid(const std::vector<Point3>& points, bool brute_force) {
  std::vector<Point2> xy;
  for (const Point3& p : points) xy.push_back({p.x, p.y});
  std::vector<Point3> copy = points;
  DelaunayResult r = triangulate(std::move(copy), {DuplicatePolicy::mean, true});
  const Triangulation& tin = r.tin;
  ASSERT_EQ(tin.validate(), "");
  const std::size_t h = hull_vertex_count(xy);
  const std::size_t nv = tin.vertex_count();
  EXPECT_EQ(nv + r.duplicates_merged, points.size());
  EXPECT_EQ(tin.triangle_count(), 2 * nv - 2 - h);
  // No point lost: each maps to a vertex at its exact x, y.
  ASSERT_EQ(r.vertex_of_point.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    ASSERT_EQ(tin.point(r.vertex_of_point[i]), (Point2{points[i].x, points[i].y}));
  if (brute_force) {
    EXPECT_TRUE(globally_delaunay(tin));
  }
}

TEST(Delaunay, RandomUniformManySeeds) {
  for (unsigned seed = 0; seed < 400; ++seed) {
    std::mt19937_64 rng(seed);
    const std::size_t n = 3 + rng() % 300;
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<Point3> pts;
    for (std::size_t i = 0; i < n; ++i) pts.push_back({u(rng), u(rng), u(rng)});
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_valid(pts, n < 120);
  }
}

TEST(Delaunay, UtmOffsetsAndLargeRandom) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 10000);
  std::vector<Point3> pts;
  for (int i = 0; i < 50000; ++i) pts.push_back({500000 + u(rng), 4000000 + u(rng), u(rng)});
  expect_valid(pts, false);
}

TEST(Delaunay, LatticesAreAllCocircular) {
  for (int k : {2, 3, 5, 17, 64}) {
    for (double origin_x : {0.0, 500000.0}) {
      std::vector<Point3> pts;  // row-major, like a raster export
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k + 1; ++i)
          pts.push_back({origin_x + i * 0.5, 4000000.0 + j * 0.5, 1.0});
      SCOPED_TRACE("k " + std::to_string(k));
      expect_valid(pts, k <= 17);
    }
  }
}

TEST(Delaunay, CollinearRunsAndHullCollinearPoints) {
  for (unsigned seed = 0; seed < 100; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<Point3> pts;
    // The border of a square, densely sampled (collinear hull points), plus lines inside.
    const int m = 2 + static_cast<int>(rng() % 20);
    for (int i = 0; i <= m; ++i) {
      const double s = 10.0 * i / m;
      pts.push_back({s, 0, 0});
      pts.push_back({s, 10, 0});
      pts.push_back({0, s, 0});
      pts.push_back({10, s, 0});
      pts.push_back({s, s, 0});             // diagonal
      pts.push_back({s, 10 - s, 0});        // anti-diagonal
      pts.push_back({s, 5 + 1e-9 * i, 0});  // a nearly straight run
    }
    std::shuffle(pts.begin(), pts.end(), rng);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_valid(pts, true);
  }
}

TEST(Delaunay, StartsWithCollinearPrefix) {
  // The first points in insertion order may be collinear; whatever the order, the result holds.
  std::vector<Point3> pts;
  for (int i = 0; i < 1000; ++i) pts.push_back({static_cast<double>(i), 0, 0});
  pts.push_back({500, 1, 0});
  pts.push_back({500, -1, 0});
  expect_valid(pts, false);
}

TEST(Delaunay, CocircularPointsAndCentre) {
  std::vector<Point3> pts;
  // Points on a circle exactly representable: Pythagorean triples of radius 5 * 13 * 17.
  const int r = 1105;
  for (int x = -r; x <= r; ++x) {
    const int y2 = r * r - x * x;
    const int y = static_cast<int>(std::lround(std::sqrt(static_cast<double>(y2))));
    if (y * y == y2) {
      pts.push_back({500000.0 + x, 4000000.0 + y, 0});
      if (y) pts.push_back({500000.0 + x, 4000000.0 - y, 0});
    }
  }
  ASSERT_GT(pts.size(), 16u);
  expect_valid(pts, true);
  pts.push_back({500000.0, 4000000.0, 0});
  expect_valid(pts, true);
}

TEST(Delaunay, OneUlpPerturbationsAtUtmMagnitude) {
  for (unsigned seed = 0; seed < 50; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<Point3> pts;
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i) {
        double x = 500000.0 + i, y = 4000000.0 + j;
        const int dx = static_cast<int>(rng() % 3) - 1, dy = static_cast<int>(rng() % 3) - 1;
        if (dx) x = std::nextafter(x, dx > 0 ? 1e300 : -1e300);
        if (dy) y = std::nextafter(y, dy > 0 ? 1e300 : -1e300);
        pts.push_back({x, y, 0});
      }
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_valid(pts, true);
  }
}

TEST(Delaunay, ClusteredAndTinyScales) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  std::vector<Point3> pts;
  for (int c = 0; c < 20; ++c) {
    const double cx = g(rng) * 1000, cy = g(rng) * 1000, s = std::pow(10.0, -(c % 8));
    for (int i = 0; i < 200; ++i) pts.push_back({cx + g(rng) * s, cy + g(rng) * s, 0});
  }
  expect_valid(pts, false);
}

TEST(Delaunay, DuplicatesMergedByPolicy) {
  const std::vector<Point3> base = {{0, 0, 1}, {1, 0, 2}, {0, 1, 3}, {1, 1, 4}};
  std::vector<Point3> pts = base;
  pts.push_back({1, 1, 10});
  pts.push_back({1, 1, 7});
  pts.push_back({0, 0, -5});
  struct Case {
    DuplicatePolicy policy;
    double z11, z00;
  };
  for (const Case& c : {Case{DuplicatePolicy::first, 4, 1}, Case{DuplicatePolicy::min, 4, -5},
                        Case{DuplicatePolicy::max, 10, 1}, Case{DuplicatePolicy::mean, 7, -2}}) {
    std::vector<Point3> copy = pts;
    DelaunayResult r = triangulate(std::move(copy), {c.policy, true});
    EXPECT_EQ(r.duplicates_merged, 3u);
    EXPECT_EQ(r.tin.vertex_count(), 4u);
    EXPECT_EQ(r.tin.validate(), "");
    EXPECT_DOUBLE_EQ(r.tin.z(r.vertex_of_point[3]), c.z11);
    EXPECT_DOUBLE_EQ(r.tin.z(r.vertex_of_point[0]), c.z00);
    EXPECT_EQ(r.vertex_of_point[3], r.vertex_of_point[4]);
    EXPECT_EQ(r.vertex_of_point[0], r.vertex_of_point[6]);
  }
}

TEST(Delaunay, KeepDuplicatesListsEachMergedVertex) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Point3> pts;
  for (int i = 0; i < 200; ++i) pts.push_back({u(rng), u(rng), 0});
  for (double z : {5.0, 1.0, 9.0}) pts.push_back({10.5, 20.25, z});
  for (double z : {-3.0, 4.0}) pts.push_back({90.5, 70.25, z});
  std::shuffle(pts.begin(), pts.end(), rng);
  DelaunayOptions options;
  options.keep_duplicates = true;
  options.parallel_min_points = std::numeric_limits<std::size_t>::max();
  for (DuplicatePolicy policy : {DuplicatePolicy::first, DuplicatePolicy::mean}) {
    options.on_duplicate = policy;
    std::vector<Point3> copy = pts;
    const DelaunayResult r = triangulate(std::move(copy), options);
    ASSERT_EQ(r.tin.validate(), "");
    EXPECT_EQ(r.duplicates_merged, 3u);
    ASSERT_EQ(r.duplicates.size(), 2u);
    std::uint64_t merged = 0;
    for (const DelaunayResult::Duplicate& d : r.duplicates) merged += d.points - 1;
    EXPECT_EQ(merged, r.duplicates_merged);
    auto dups = r.duplicates;  // by x, whatever the vertex order
    std::sort(dups.begin(), dups.end(), [&](const auto& a, const auto& b) {
      return r.tin.point(a.vertex).x < r.tin.point(b.vertex).x;
    });
    EXPECT_EQ(r.tin.point(dups[0].vertex), (Point2{10.5, 20.25}));
    EXPECT_EQ(dups[0].points, 3u);
    EXPECT_EQ(dups[0].z_min, 1.0);
    EXPECT_EQ(dups[0].z_max, 9.0);
    EXPECT_EQ(r.tin.point(dups[1].vertex), (Point2{90.5, 70.25}));
    EXPECT_EQ(dups[1].points, 2u);
    EXPECT_EQ(dups[1].z_min, -3.0);
    EXPECT_EQ(dups[1].z_max, 4.0);
    EXPECT_LT(r.duplicates[0].vertex, r.duplicates[1].vertex);  // in vertex order
    if (policy == DuplicatePolicy::mean) {
      EXPECT_DOUBLE_EQ(r.tin.z(dups[0].vertex), 5.0);
      EXPECT_DOUBLE_EQ(r.tin.z(dups[1].vertex), 0.5);
    }
  }
  // Off by default.
  const DelaunayResult off = triangulate(std::move(pts));
  EXPECT_EQ(off.duplicates_merged, 3u);
  EXPECT_TRUE(off.duplicates.empty());
}

TEST(Delaunay, ManyDuplicatesInRandomOrder) {
  std::mt19937_64 rng(11);
  std::vector<Point3> pts;
  for (int i = 0; i < 3000; ++i)
    pts.push_back({static_cast<double>(rng() % 40), static_cast<double>(rng() % 40), 1.0});
  expect_valid(pts, false);
}

TEST(Delaunay, RejectsDegenerateInput) {
  EXPECT_THROW(triangulate({}), GeometryError);
  EXPECT_THROW(triangulate({{0, 0, 0}, {1, 1, 1}}), GeometryError);
  EXPECT_THROW(triangulate({{0, 0, 0}, {1, 1, 1}, {0, 0, 5}, {1, 1, 2}}), GeometryError);
  EXPECT_THROW(triangulate({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}), GeometryError);
  EXPECT_THROW(triangulate({{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}}), GeometryError);
  try {
    triangulate({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
    FAIL();
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos);
  }
}

TEST(Delaunay, ProgressCanCancel) {
  std::vector<Point3> pts;
  for (int i = 0; i < 20000; ++i) pts.push_back({std::sin(i) * 100, std::cos(i * 1.3) * 100, 0});
  int calls = 0;
  ProgressFn fn = [&](std::string_view stage, double) {
    EXPECT_EQ(stage, "delaunay");
    return ++calls < 3;
  };
  EXPECT_THROW(triangulate(std::move(pts), {}, &fn), Cancelled);
  EXPECT_EQ(calls, 3);
}

}  // namespace
}  // namespace tincdt::delaunay
