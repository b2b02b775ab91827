// predicates::incircle_perturbed against two independent references: the symbolic definition in
// integers (support/perturbed_incircle_reference.hpp) and an explicit numeric perturbation; and
// the properties the triangulation code relies on (agreement with incircle, the determinant's
// behaviour under permutations, no ties).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "predicates/predicates.hpp"
#include "support/perturbed_incircle_reference.hpp"

namespace tincdt::predicates {
namespace {

using test::Int128;
using test::IntegerFrame;
using test::IntPoint;

// Origins where the library sees UTM-like doubles; the steps are powers of two, so every point
// of the frame is exact.
const std::array<IntegerFrame, 4> kFrames{IntegerFrame{0, 0, 1}, IntegerFrame{500000, 4000000, 1},
                                          IntegerFrame{500000, 4000000, 0.015625},
                                          IntegerFrame{-273357.5, 5274357.25, 0.25}};

int library(const IntegerFrame& f, IntPoint a, IntPoint b, IntPoint c, IntPoint d) {
  return incircle_perturbed(f.to_double(a), f.to_double(b), f.to_double(c), f.to_double(d));
}

// The perturbation made explicit for tiny coordinates: lift p to K (x^2 + y^2) + B^r(p), where
// r(p) in 0..3 is p's rank among the four (largest last). With |cofactor| < 2^10 and B = 2^12,
// each eps term outweighs all smaller ones together, and K = 2^50 outweighs all eps terms, so the
// sign is the symbolic one. No cofactor expansion and no ordering of terms by hand.
int explicit_perturbation(IntPoint a, IntPoint b, IntPoint c, IntPoint d) {
  const std::array<IntPoint, 4> p{a, b, c, d};
  std::array<int, 4> rank{};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) rank[i] += test::lex_less(p[j], p[i]);
  const auto lift = [&](std::size_t i) {
    const Int128 x = p[i].x, y = p[i].y;
    return (Int128{1} << 50) * (x * x + y * y) + (Int128{1} << (12 * rank[i]));
  };
  // det[x y lift 1] by subtracting row d: a 3x3 determinant.
  std::array<std::array<Int128, 3>, 3> m{};
  for (std::size_t i = 0; i < 3; ++i)
    m[i] = {Int128{p[i].x - d.x}, Int128{p[i].y - d.y}, lift(i) - lift(3)};
  const Int128 det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return (det > 0) - (det < 0);
}

TEST(IncirclePerturbed, MatchesTheDefinitionOnEveryQuadrupleOfASmallLattice) {
  // Every ordered quadruple of distinct points of a 4 x 4 lattice: plenty of cocircular ones
  // (every rectangle, and more), collinear triples, and both orientations.
  std::vector<IntPoint> lattice;
  for (std::int64_t x = 0; x < 4; ++x)
    for (std::int64_t y = 0; y < 4; ++y) lattice.push_back({x, y});
  int ties = 0;
  for (const IntegerFrame& frame : kFrames) {
    for (const IntPoint a : lattice)
      for (const IntPoint b : lattice)
        for (const IntPoint c : lattice)
          for (const IntPoint d : lattice) {
            if (a == b || a == c || a == d || b == c || b == d || c == d) continue;
            const int expected = test::perturbed_in_circle(a, b, c, d);
            ASSERT_EQ(explicit_perturbation(a, b, c, d), expected);
            ASSERT_EQ(library(frame, a, b, c, d), expected)
                << a.x << "," << a.y << " " << b.x << "," << b.y << " " << c.x << "," << c.y << " "
                << d.x << "," << d.y;
            ties += incircle(frame.to_double(a), frame.to_double(b), frame.to_double(c),
                             frame.to_double(d)) == 0;
          }
  }
  EXPECT_GT(ties, 10000);
}

// Integer points on circles x^2 + y^2 = r^2 with many of them (r = 5^k, 65, 325): cocircular
// sets that are not lattice rectangles.
std::vector<IntPoint> points_on_circle(std::int64_t r) {
  std::vector<IntPoint> points;
  for (std::int64_t x = -r; x <= r; ++x) {
    for (std::int64_t y = -r; y <= r; ++y)
      if (x * x + y * y == r * r) points.push_back({x, y});
  }
  return points;
}

TEST(IncirclePerturbed, MatchesTheDefinitionOnPointsOfCircles) {
  std::mt19937_64 rng(11);
  for (const std::int64_t r : {5, 25, 65, 125, 325}) {
    const std::vector<IntPoint> circle = points_on_circle(r);
    ASSERT_GE(circle.size(), 12u);
    std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
    std::uniform_int_distribution<std::int64_t> near(-r - 2, r + 2);
    for (int k = 0; k < 4000; ++k) {
      std::array<IntPoint, 4> q;
      for (IntPoint& p : q) p = circle[pick(rng)];
      if (k % 4 == 0) q[3] = {near(rng), near(rng)};  // sometimes off the circle
      bool distinct = true;
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = i + 1; j < 4; ++j) distinct &= !(q[i] == q[j]);
      if (!distinct) continue;
      for (const IntegerFrame& frame : kFrames)
        ASSERT_EQ(library(frame, q[0], q[1], q[2], q[3]),
                  test::perturbed_in_circle(q[0], q[1], q[2], q[3]));
    }
  }
}

TEST(IncirclePerturbed, AgreesWithIncircleWhereverThatIsNotZero) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(0, 100);
  std::uniform_int_distribution<int> cm(0, 2000);
  for (int k = 0; k < 200000; ++k) {
    std::array<Point2, 4> p;
    for (Point2& q : p) {
      // Half random doubles, half cm-quantized UTM points (decimal steps: no exact frame).
      q = k % 2 ? Point2{u(rng), u(rng)}
                : Point2{500000 + cm(rng) * 0.01, 4000000 + cm(rng) * 0.01};
    }
    const int exact = incircle(p[0], p[1], p[2], p[3]);
    const int perturbed = incircle_perturbed(p[0], p[1], p[2], p[3]);
    if (exact != 0) {
      ASSERT_EQ(perturbed, exact);
    }
  }
}

// The sign of a permutation of (0, 1, 2, 3).
int parity(const std::array<int, 4>& perm) {
  int inversions = 0;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
  return inversions % 2 ? -1 : 1;
}

TEST(IncirclePerturbed, ChangesWithThePermutationLikeADeterminantAndNeverTies) {
  // Cocircular quadruples: unit cells and rectangles of cm-quantized UTM lattices (decimal: the
  // doubles are not exact multiples of 0.01, yet axis-aligned rectangles stay cocircular), and
  // points of a circle. Every permutation multiplies the sign by its parity, so the two triangles
  // of an edge agree on whether it is locally Delaunay, and a flip makes it so.
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<int> cm(0, 500);
  std::vector<std::array<Point2, 4>> cases;
  for (int k = 0; k < 3000; ++k) {
    const double x0 = 500000 + cm(rng) * 0.01, x1 = x0 + (1 + cm(rng)) * 0.01;
    const double y0 = 4000000 + cm(rng) * 0.01, y1 = y0 + (1 + cm(rng)) * 0.01;
    cases.push_back({Point2{x0, y0}, Point2{x1, y0}, Point2{x1, y1}, Point2{x0, y1}});
  }
  const std::vector<IntPoint> circle = points_on_circle(65);
  const IntegerFrame frame = kFrames[2];
  for (std::size_t i = 0; i + 3 < circle.size(); i += 3)
    cases.push_back({frame.to_double(circle[i]), frame.to_double(circle[i + 1]),
                     frame.to_double(circle[i + 2]), frame.to_double(circle[i + 3])});
  for (const auto& q : cases) {
    ASSERT_EQ(incircle(q[0], q[1], q[2], q[3]), 0);
    const int base = incircle_perturbed(q[0], q[1], q[2], q[3]);
    ASSERT_NE(base, 0);
    std::array<int, 4> perm{0, 1, 2, 3};
    do {
      ASSERT_EQ(incircle_perturbed(q[perm[0]], q[perm[1]], q[perm[2]], q[perm[3]]),
                parity(perm) * base);
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
}

TEST(IncirclePerturbed, TheLexicographicallyLargestCornerCountsAsOutside) {
  // The unit square: (1, 1) is the largest, so it is outside the circle of the other three and
  // the Delaunay diagonal is (1, 0)-(0, 1), for any placement of the square.
  for (const IntegerFrame& f : kFrames) {
    const Point2 sw = f.to_double({0, 0}), se = f.to_double({1, 0});
    const Point2 ne = f.to_double({1, 1}), nw = f.to_double({0, 1});
    // Diagonal se-nw: each apex is outside the other triangle's circle.
    EXPECT_EQ(incircle_perturbed(sw, se, nw, ne), -1);
    EXPECT_EQ(incircle_perturbed(se, ne, nw, sw), -1);
    // Diagonal sw-ne: each apex is inside the other triangle's circle.
    EXPECT_EQ(incircle_perturbed(sw, se, ne, nw), 1);
    EXPECT_EQ(incircle_perturbed(sw, ne, nw, se), 1);
  }
}

TEST(IncirclePerturbed, ZeroOnlyWhenAllFourAreOnOneLine) {
  const Point2 a{500000, 4000000}, b{500001, 4000000.5}, c{500002, 4000001}, d{500004, 4000002};
  EXPECT_EQ(incircle_perturbed(a, b, c, d), 0);
  EXPECT_EQ(incircle_perturbed(b, d, a, c), 0);
  // Three on a line, the fourth off it: a cofactor decides.
  const Point2 off{500001, 4000003};
  EXPECT_NE(incircle_perturbed(a, b, c, off), 0);
  EXPECT_NE(incircle_perturbed(a, b, off, c), 0);
}

}  // namespace
}  // namespace tincdt::predicates
