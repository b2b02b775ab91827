#include "mesh/triangulation.hpp"

#include <gtest/gtest.h>

#include "mesh/geometry.hpp"
#include "mesh/point_insertion.hpp"

namespace tincdt::mesh {
namespace {

// Unit square split by diagonal 0-2, closed by four ghosts.
//   3---2
//   | / |
//   0---1
Triangulation square(double y2 = 1.0) {
  Triangulation tin;
  tin.add_vertex({0, 0}, 0);
  tin.add_vertex({1, 0}, 0);
  tin.add_vertex({1, y2}, 0);
  tin.add_vertex({0, 1}, 0);
  const TriangleId t0 = tin.add_triangle(0, 1, 2);
  const TriangleId t1 = tin.add_triangle(0, 2, 3);
  const TriangleId g01 = tin.add_triangle(1, 0, kInfinite);
  const TriangleId g12 = tin.add_triangle(2, 1, kInfinite);
  const TriangleId g23 = tin.add_triangle(3, 2, kInfinite);
  const TriangleId g30 = tin.add_triangle(0, 3, kInfinite);
  tin.link(3 * t0 + 2, 3 * t1);        // 2 -> 0 / 0 -> 2
  tin.link(3 * t0, 3 * g01);           // 0 -> 1
  tin.link(3 * t0 + 1, 3 * g12);       // 1 -> 2
  tin.link(3 * t1 + 1, 3 * g23);       // 2 -> 3
  tin.link(3 * t1 + 2, 3 * g30);       // 3 -> 0
  tin.link(3 * g01 + 1, 3 * g30 + 2);  // 0 -> inf
  tin.link(3 * g12 + 1, 3 * g01 + 2);  // 1 -> inf
  tin.link(3 * g23 + 1, 3 * g12 + 2);  // 2 -> inf
  tin.link(3 * g30 + 1, 3 * g23 + 2);  // 3 -> inf
  return tin;
}

TEST(Triangulation, HandBuiltSquareIsValid) {
  const Triangulation tin = square(0.9);  // 3 lies outside circle (0, 1, 2): 0-2 is Delaunay
  EXPECT_EQ(tin.validate(), "");
  EXPECT_EQ(tin.triangle_count(), 2u);
}

TEST(Triangulation, CocircularSquareTakesThePerturbedDiagonal) {
  // All four corners are on one circle. The perturbation counts the lexicographically largest
  // corner, 2 = (1, 1), as just outside the circle of the other three, so 3 is inside circle
  // (0, 1, 2) and only the diagonal 1-3 is locally Delaunay, seen from either side.
  Triangulation tin = square();
  EXPECT_FALSE(is_locally_delaunay(tin, 2));
  EXPECT_FALSE(is_locally_delaunay(tin, tin.twin(2)));
  EXPECT_NE(tin.validate(), "");
  tin.flip(2);
  EXPECT_TRUE(is_locally_delaunay(tin, 2));
  EXPECT_TRUE(is_locally_delaunay(tin, tin.twin(2)));
  EXPECT_EQ(tin.validate(), "");
}

TEST(Triangulation, FlipReplacesTheDiagonalAndKeepsValidity) {
  Triangulation tin = square(1.2);  // 0-2 is now not Delaunay: 3 lies inside circle (0, 1, 2)
  EXPECT_NE(tin.validate(), "");
  EXPECT_EQ(tin.validate({.delaunay = false}), "");
  EXPECT_FALSE(is_locally_delaunay(tin, 2));
  tin.flip(2);
  EXPECT_EQ(tin.validate(), "");
  EXPECT_EQ(tin.origin(2), 3u);  // e keeps its index and now runs d -> c
  EXPECT_EQ(tin.dest(2), 1u);
  tin.flip(2);  // flipping back restores the original diagonal
  EXPECT_EQ(tin.validate({.delaunay = false}), "");
  EXPECT_EQ(std::min(tin.origin(2), tin.dest(2)), 0u);
}

TEST(Triangulation, FlipCarriesConstraintFlags) {
  Triangulation tin = square(1.2);
  tin.set_constrained(0, true);  // 0 -> 1, an outer edge of the flipped pair
  tin.flip(2);
  EXPECT_EQ(tin.validate(), "");
  int constrained = 0;
  tin.for_each_constrained_edge([&](EdgeId e) {
    ++constrained;
    EXPECT_EQ(tin.origin(e), 0u);
    EXPECT_EQ(tin.dest(e), 1u);
  });
  EXPECT_EQ(constrained, 1);
}

TEST(Triangulation, EmptySlotsAreAddedAndDroppedWithTheirFlags) {
  Triangulation tin = square(0.9);
  tin.set_constrained(0, true);
  tin.set_removed(1, true);
  tin.add_empty_triangles(3);
  ASSERT_EQ(tin.triangle_slots(), 9u);
  EXPECT_EQ(tin.triangle_count(), 1u);  // one removed; empty slots are no triangles
  for (TriangleId t = 6; t < 9; ++t) {
    EXPECT_FALSE(tin.is_removed(t));
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      EXPECT_EQ(tin.origin(e), kNoId);
      EXPECT_EQ(tin.twin(e), kNoId);
      EXPECT_FALSE(tin.is_constrained(e));
    }
  }
  tin.truncate_triangles(6);
  tin.set_removed(1, false);
  EXPECT_EQ(tin.validate(), "");
  EXPECT_TRUE(tin.is_constrained(0));
}

TEST(Triangulation, ValidateFindsBrokenTopologyAndOrientation) {
  {
    Triangulation tin = square();
    tin.link(0, 1);  // nonsense twins
    EXPECT_NE(tin.validate(), "");
  }
  {
    Triangulation tin = square();
    tin.set_corners(0, 0, 2, 1);  // clockwise
    EXPECT_NE(tin.validate(), "");
  }
  {
    Triangulation tin = square();
    tin.add_vertex({5, 5}, 0);  // a vertex in no triangle
    EXPECT_NE(tin.validate(), "");
  }
}

// A point inserted outside the hull flips edges between ghosts, whose vertex is
// kInfinite; with the vertex index on (the surface-feature stage), flip() wrote past its end.
TEST(Triangulation, InsertingOutsideTheHullKeepsTheVertexIndex) {
  Triangulation tin = square(0.8);  // not cocircular: its diagonal 0-2 is the Delaunay one
  tin.build_vertex_index();
  PointInserter inserter(tin);
  // Each sees several hull edges, so the fan is mended by flips between ghosts.
  for (const Point2 p : {Point2{3, 0.5}, Point2{-2, -2}, Point2{0.5, 4}, Point2{6, 6}}) {
    const VertexId v = tin.add_vertex(p, 0);
    inserter.insert(v);
  }
  tin.recount();
  EXPECT_EQ(tin.validate(), "");
  for (VertexId v = 0; v < tin.vertex_count(); ++v) EXPECT_EQ(tin.origin(tin.edge_from(v)), v);
  EXPECT_NE(tin.find_edge(4, 1), kNoId);  // (3, 0.5) now joins both right-hand corners
  EXPECT_NE(tin.find_edge(4, 2), kNoId);
}

// A LAS X scale of 5e-324 makes every x a multiple of the smallest subnormal. The TIN
// is valid (checked exactly), but summing atan2 turning angles called its thin hull unwound.
TEST(Triangulation, ValidateIsExactForAHullOfSubnormalWidth) {
  constexpr double kTiny = 4.9406564584124654e-324;  // 2^-1074
  Triangulation tin;
  tin.add_vertex({0, 0}, 0);
  tin.add_vertex({20 * kTiny, 500}, 0);
  tin.add_vertex({0, 1000}, 0);
  PointInserter inserter(tin);
  inserter.start(0, 1, 2);
  std::uint64_t state = 88172645463325252ULL;
  const auto next = [&] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (int i = 0; i < 300; ++i) {
    const Point2 p{static_cast<double>(next() % 41) * kTiny,
                   static_cast<double>(next() % 100001) / 100};
    if (inserter.locate(p).kind == Location::on_vertex) continue;
    inserter.insert(tin.add_vertex(p, 0));
  }
  tin.recount();
  EXPECT_GT(tin.triangle_count(), 100u);
  EXPECT_EQ(tin.validate(), "");
}

}  // namespace
}  // namespace tincdt::mesh
