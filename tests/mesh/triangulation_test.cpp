#include "mesh/triangulation.hpp"

#include <gtest/gtest.h>

#include "mesh/geometry.hpp"

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

}  // namespace
}  // namespace tincdt::mesh
