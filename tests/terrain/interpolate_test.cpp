// Linear interpolation on the TIN: exact on a plane, NaN where there is no surface.
#include "terrain/interpolate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

constexpr double kX0 = 512345.0, kY0 = 4123456.0;  // UTM-sized offsets

double plane(double x, double y) {
  return 0.37 * (x - kX0) - 0.81 * (y - kY0) + 245.5;
}

test::Built plane_tin(bool with_constraints) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 200);
  std::vector<Point3> pts;
  for (int i = 0; i < 3000; ++i) {
    const double x = kX0 + u(rng), y = kY0 + u(rng);
    pts.push_back({x, y, plane(x, y)});
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  if (with_constraints)  // long crossing-free constraints make the TIN far from Delaunay
    for (std::uint32_t i = 0; i + 1 < 200; i += 2) segs.push_back({i, i + 1});
  return test::build_tin(std::move(pts), segs);
}

TEST(Interpolate, ExactOnAPlane) {
  for (bool constrained : {false, true}) {
    auto b = plane_tin(constrained);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(20, 180);  // well inside the hull
    SurfaceSampler sampler(b.tin);
    for (int i = 0; i < 5000; ++i) {
      const Point2 p{kX0 + u(rng), kY0 + u(rng)};
      EXPECT_NEAR(interpolate_z(b.tin, p), plane(p.x, p.y), 1e-9);
      EXPECT_NEAR(sampler.z_at(p), plane(p.x, p.y), 1e-9);
      EXPECT_NE(sampler.last_triangle(), kNoId);
    }
    // At the vertices themselves.
    for (VertexId v = 0; v < 50; ++v)
      EXPECT_NEAR(interpolate_z(b.tin, b.tin.point(v)), b.tin.z(v), 1e-9);
  }
}

TEST(Interpolate, NaNOutsideTheHullAndInRemovedTriangles) {
  auto b = plane_tin(false);
  EXPECT_TRUE(std::isnan(interpolate_z(b.tin, {kX0 - 1, kY0 + 100})));
  EXPECT_TRUE(std::isnan(interpolate_z(b.tin, {kX0 + 100, kY0 + 201})));
  EXPECT_TRUE(std::isnan(interpolate_z(b.tin, {std::nan(""), kY0})));

  const Point2 p{kX0 + 100.25, kY0 + 99.75};
  SurfaceSampler sampler(b.tin);
  ASSERT_FALSE(std::isnan(sampler.z_at(p)));
  const TriangleId t = sampler.last_triangle();
  b.tin.set_removed(t, true);
  EXPECT_TRUE(std::isnan(interpolate_z(b.tin, p, t)));
  EXPECT_TRUE(std::isnan(interpolate_z(b.tin, p)));
  // A corner of the removed triangle is still on the kept surface around it.
  const VertexId corner = b.tin.triangle(t)[0];
  EXPECT_NEAR(interpolate_z(b.tin, b.tin.point(corner), t), b.tin.z(corner), 1e-9);
}

TEST(Interpolate, HintIsOnlyAStart) {
  auto b = plane_tin(true);
  const Point2 p{kX0 + 50.5, kY0 + 150.5};
  const double expected = plane(p.x, p.y);
  for (TriangleId t = 0; t < b.tin.triangle_slots(); t += 97)  // ghosts included
    EXPECT_NEAR(interpolate_z(b.tin, p, t), expected, 1e-9);
  EXPECT_NEAR(interpolate_z(b.tin, p, kNoId), expected, 1e-9);
  EXPECT_NEAR(interpolate_z(b.tin, p, 1u << 30), expected, 1e-9);  // out of range: ignored
}

// The same points with a few far away make another TIN in memory (other slots, corners in
// another rotation) with the same triangles inside: every height there must be the same double,
// also on an edge, which both of its triangles hold (a tile drapes a ring vertex as the whole
// job does, from a TIN of part of the data).
TEST(Interpolate, GivesTheSameDoubleInAnyTinThatHoldsTheTriangle) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(0, 200), height(100, 900);
  for (const bool lattice : {false, true}) {
    SCOPED_TRACE(lattice ? "lattice" : "random");
    std::vector<Point3> points;
    if (lattice) {  // every grid line a chain of edges
      for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 40; ++j) points.push_back({kX0 + 5 * i, kY0 + 5 * j, height(rng)});
    } else {
      for (int i = 0; i < 2000; ++i) points.push_back({kX0 + u(rng), kY0 + u(rng), height(rng)});
    }
    std::vector<Point3> more = points;
    for (const auto& [dx, dy] : {std::pair{-900.0, -700.0}, {1300.0, -500.0}, {700.0, 1100.0}})
      more.push_back({kX0 + dx, kY0 + dy, height(rng)});
    const mesh::Triangulation a = test::build_tin(points).tin, b = test::build_tin(more).tin;
    for (int i = 0; i < 4000; ++i) {
      Point2 p{kX0 + 10 + u(rng) * 0.9, kY0 + 10 + u(rng) * 0.9};
      if (lattice && i % 2 == 0) p.x = kX0 + 5 * std::floor((p.x - kX0) / 5);  // on a grid line
      const double za = interpolate_z(a, p), zb = interpolate_z(b, p);
      ASSERT_FALSE(std::isnan(za));
      EXPECT_EQ(za, zb) << "at (" << p.x << ", " << p.y << ")";
    }
  }
}

}  // namespace
}  // namespace tincdt::terrain
