// Contour tracing: the lines lie on the TIN at their level, do not cross, are not duplicated or
// broken, rings are closed; checked on random TINs and on lattices where vertices and whole
// edges lie exactly on the levels, against references computed triangle by triangle.
#include "products/contours.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "products_test_util.hpp"

namespace tincdt::products {
namespace {

using test::Kind;

// z on the TIN at a traced point: the plane of the kept triangle that holds it, or for a
// crossing computed on a hull edge, that lies a rounding off it, the nearest (by distance
// outside; a few units in the last place are allowed). SLACK is how far z can move when the
// point's coordinates move by one unit in the last place: no double point is closer to the level
// than that, so the check is 1e-9 beyond it (it matters at map coordinates on steep triangles:
// 1 ulp of 5e6 is 9e-10).
double tin_z_near(const mesh::Triangulation& tin, Point2 p, double* slack) {
  using L = long double;
  double best = std::numeric_limits<double>::quiet_NaN();
  L best_inside = -INFINITY;  // least distance inside the triangle's edges (< 0: outside)
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    L inside = INFINITY;
    for (int i = 0; i < 3; ++i) {
      const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]);
      const L ex = L(b.x) - a.x, ey = L(b.y) - a.y;
      const L cross = ex * (L(p.y) - a.y) - ey * (L(p.x) - a.x);
      inside = std::min(inside, cross / std::sqrt(ex * ex + ey * ey));
    }
    if (inside <= best_inside) return;
    best_inside = inside;
    best = static_cast<double>(test::plane_at(tin, t, p));
    const L ax = tin.point(c[0]).x, ay = tin.point(c[0]).y;
    const L bx = tin.point(c[1]).x - ax, by = tin.point(c[1]).y - ay;
    const L cx = tin.point(c[2]).x - ax, cy = tin.point(c[2]).y - ay;
    const L det = bx * cy - by * cx;
    const L za = tin.z(c[0]), bz = tin.z(c[1]) - za, cz = tin.z(c[2]) - za;
    const L gx = (bz * cy - cz * by) / det, gy = (cz * bx - bz * cx) / det;
    const double ulp_x = std::nextafter(std::fabs(p.x), INFINITY) - std::fabs(p.x);
    const double ulp_y = std::nextafter(std::fabs(p.y), INFINITY) - std::fabs(p.y);
    *slack = static_cast<double>(std::fabs(gx) * ulp_x + std::fabs(gy) * ulp_y);
  });
  const double ulp = std::nextafter(std::fmax(std::fabs(p.x), std::fabs(p.y)), INFINITY) -
                     std::fmax(std::fabs(p.x), std::fabs(p.y));
  EXPECT_GT(best_inside, -4 * ulp) << "(" << p.x << ", " << p.y << ") is off the TIN";
  return best;
}

struct Segment {
  Point2 a, b;
};

std::map<double, std::vector<Segment>> segments_by_level(const ContourSet& set) {
  std::map<double, std::vector<Segment>> out;
  for (const ContourLine& line : set.lines)
    for (std::size_t i = 0; i + 1 < line.count; ++i)
      out[line.level].push_back({set.points[line.first + i], set.points[line.first + i + 1]});
  return out;
}

double length(const Segment& s) {
  return std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
}

// Checks every property that does not need to know the answer.
void check_lines(const mesh::Triangulation& tin, const ContourSet& set, double base,
                 double interval) {
  using predicates::orient2d;
  double previous_level = -INFINITY;
  for (const ContourLine& line : set.lines) {
    ASSERT_GE(line.level, previous_level) << "lines are ordered by level";
    previous_level = line.level;
    const double k = (line.level - base) / interval;
    EXPECT_NEAR(k, std::round(k), 1e-9) << "level " << line.level << " is not base + k interval";
    const Point2* p = set.points.data() + line.first;
    if (line.closed) {
      ASSERT_GE(line.count, 4u);
      EXPECT_EQ(p[0], p[line.count - 1]) << "ring not closed";
    } else {
      ASSERT_GE(line.count, 2u);
    }
    for (std::size_t i = 0; i < line.count; ++i) {
      double slack = 0;
      const double z = tin_z_near(tin, p[i], &slack);
      ASSERT_NEAR(z, line.level, 1e-9 + slack) << "point " << i << " of a line";
      if (i + 1 < line.count) {
        ASSERT_NE(p[i], p[i + 1]) << "zero-length piece";
      }
      if (i + 2 < line.count) {
        ASSERT_NE(p[i], p[i + 2]) << "there-and-back spike";
      }
    }
    if (line.closed) {
      ASSERT_NE(p[1], p[line.count - 2]) << "spike at the seam";
    }
  }
  // No two pieces of one level cross or overlap.
  for (const auto& [level, segs] : segments_by_level(set)) {
    for (std::size_t i = 0; i < segs.size(); ++i) {
      for (std::size_t j = i + 1; j < segs.size(); ++j) {
        const Segment &s = segs[i], &t = segs[j];
        const int o1 = orient2d(s.a, s.b, t.a), o2 = orient2d(s.a, s.b, t.b);
        const int o3 = orient2d(t.a, t.b, s.a), o4 = orient2d(t.a, t.b, s.b);
        ASSERT_FALSE(o1 * o2 < 0 && o3 * o4 < 0) << "two lines of level " << level << " cross";
        if (o1 == 0 && o2 == 0) {  // collinear: at most a shared end
          const bool horizontal = s.a.y == s.b.y;
          const auto key = [horizontal](Point2 q) { return horizontal ? q.x : q.y; };
          const double s0 = std::min(key(s.a), key(s.b)), s1 = std::max(key(s.a), key(s.b));
          const double t0 = std::min(key(t.a), key(t.b)), t1 = std::max(key(t.a), key(t.b));
          ASSERT_LE(std::min(s1, t1), std::max(s0, t0))
              << "pieces of level " << level << " overlap (a duplicated line)";
        }
      }
    }
  }
}

class ContourProperty : public ::testing::TestWithParam<Kind> {};

TEST_P(ContourProperty, LinesLieOnTheTinAndNeverCrossOrRepeat) {
  const Kind kind = GetParam();
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    const mesh::Triangulation tin = test::make_tin(kind, seed, 300000, 5000000);
    // Integer levels hit the lattice's vertices and flat edges; 0.5 levels cross between them.
    for (const auto& [base, interval] : {std::pair{0.0, 1.0}, {0.5, 1.0}, {0.1, 0.7}}) {
      SCOPED_TRACE(std::string(test::kind_name(kind)) + " seed " + std::to_string(seed) + " base " +
                   std::to_string(base) + " interval " + std::to_string(interval));
      const ContourSet set = trace_contours(tin, {.interval = interval, .base = base});
      ASSERT_FALSE(set.lines.empty());
      check_lines(tin, set, base, interval);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Tins, ContourProperty,
                         ::testing::Values(Kind::random, Kind::lattice, Kind::lattice_holes),
                         [](const ::testing::TestParamInfo<Kind>& param) {
                           return std::string(test::kind_name(param.param));
                         });

// On a random TIN no vertex is on a level: each crossed triangle gives one piece, whose length
// the reference computes from the triangle alone.
TEST(Contours, EachCrossedTriangleGivesOnePieceOfTheRightLength) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    const mesh::Triangulation tin = test::make_tin(Kind::random, seed, 0, 0, 16);
    const double base = 0.05, interval = 0.5;
    const ContourSet set = trace_contours(tin, {.interval = interval, .base = base});
    std::map<double, std::pair<std::size_t, double>> expected;  // level -> pieces, length
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      const double zs[3] = {tin.z(c[0]), tin.z(c[1]), tin.z(c[2])};
      for (int k = 0; k < 30; ++k) {
        const double level = contour_level(base, interval, k);
        std::vector<Point2> hits;
        for (int i = 0; i < 3; ++i) {
          const double za = zs[i], zb = zs[(i + 1) % 3];
          if ((za < level) == (zb < level)) continue;
          const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]);
          const long double t = (static_cast<long double>(level) - za) / (zb - za);
          hits.push_back({static_cast<double>(a.x + t * (b.x - a.x)),
                          static_cast<double>(a.y + t * (b.y - a.y))});
        }
        if (hits.empty()) continue;
        ASSERT_EQ(hits.size(), 2u);
        expected[level].first += 1;
        expected[level].second += length({hits[0], hits[1]});
      }
    });
    const auto got = segments_by_level(set);
    ASSERT_EQ(got.size(), expected.size());
    for (const auto& [level, segs] : got) {
      double total = 0;
      for (const Segment& s : segs) total += length(s);
      EXPECT_EQ(segs.size(), expected[level].first) << "level " << level;
      EXPECT_NEAR(total, expected[level].second, 1e-9 * expected[level].second);
    }
  }
}

// z = y on a lattice: every vertex is on a level and every level runs along lattice edges. Each
// level k gives one straight line along row k, west to east (higher ground on the left), exactly
// once; the top row is the level set of the highest level.
TEST(Contours, LevelsThroughVerticesAndAlongFlatEdges) {
  const int n = 8;
  std::vector<Point3> pts;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) pts.push_back({1000.0 + i, 2000.0 + j, static_cast<double>(j)});
  const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  const ContourSet set = trace_contours(tin, {.interval = 1});
  ASSERT_EQ(set.lines.size(), static_cast<std::size_t>(n));
  for (int k = 1; k <= n; ++k) {
    const ContourLine& line = set.lines[k - 1];
    EXPECT_EQ(line.level, k);
    EXPECT_FALSE(line.closed);
    const Point2 first = set.points[line.first], last = set.points[line.first + line.count - 1];
    EXPECT_EQ(first, (Point2{1000.0, 2000.0 + k}));
    EXPECT_EQ(last, (Point2{1000.0 + n, 2000.0 + k}));
    for (std::size_t i = 0; i < line.count; ++i)
      EXPECT_EQ(set.points[line.first + i].y, 2000.0 + k) << "off the lattice row";
  }
  check_lines(tin, set, 0, 1);
}

// A plateau exactly at a level is outlined once on its lower side; a ridge exactly at a level
// (lower ground on both sides) has no ground above it and gives no line; a valley at a level
// (higher ground on both sides) neither.
TEST(Contours, FlatsRidgesAndValleysAtALevel) {
  const int n = 10;
  const auto lattice = [n](auto z_of_row) {
    std::vector<Point3> pts;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) pts.push_back({1.0 * i, 1.0 * j, z_of_row(j)});
    return delaunay::triangulate(std::move(pts)).tin;
  };
  const mesh::Triangulation plateau = lattice([](int j) { return std::min(j, 5) * 1.0; });
  ContourSet set = trace_contours(plateau, {.interval = 5});
  ASSERT_EQ(set.lines.size(), 1u);
  EXPECT_EQ(set.lines[0].level, 5);
  EXPECT_EQ(set.lines[0].count, static_cast<std::size_t>(n + 1));  // along row 5
  check_lines(plateau, set, 0, 5);

  const mesh::Triangulation ridge = lattice([](int j) { return 5.0 - std::abs(j - 5); });
  set = trace_contours(ridge, {.interval = 1});
  for (const ContourLine& line : set.lines) EXPECT_NE(line.level, 5) << "ridge line at its level";
  EXPECT_EQ(std::count_if(set.lines.begin(), set.lines.end(),
                          [](const ContourLine& l) { return l.level == 4; }),
            2);
  check_lines(ridge, set, 0, 1);

  const mesh::Triangulation valley = lattice([](int j) { return 1.0 + std::abs(j - 5); });
  set = trace_contours(valley, {.interval = 1});
  for (const ContourLine& line : set.lines) EXPECT_NE(line.level, 1) << "valley line at its level";
  check_lines(valley, set, 0, 1);
}

// A cone: every level below the apex is one closed ring around it, counter-clockwise.
TEST(Contours, RingsAroundAHillAreClosedAndCounterClockwise) {
  std::vector<Point3> pts;
  pts.push_back({0, 0, 10});
  for (int r = 1; r <= 5; ++r)
    for (int i = 0; i < 12 * r; ++i) {
      const double a = 2 * M_PI * i / (12 * r);
      pts.push_back({r * std::cos(a), r * std::sin(a), 10.0 - 2 * r});
    }
  const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  const ContourSet set = trace_contours(tin, {.interval = 1.5, .base = 0.25});
  ASSERT_FALSE(set.lines.empty());
  for (const ContourLine& line : set.lines) {
    EXPECT_TRUE(line.closed) << "level " << line.level;
    double area2 = 0;
    for (std::size_t i = 0; i + 1 < line.count; ++i) {
      const Point2 a = set.points[line.first + i], b = set.points[line.first + i + 1];
      area2 += a.x * b.y - a.y * b.x;
    }
    EXPECT_GT(area2, 0) << "ring at " << line.level << " is clockwise";
  }
  check_lines(tin, set, 0.25, 1.5);
}

TEST(Contours, SameResultForAnyThreadCount) {
  const mesh::Triangulation tin = test::make_tin(Kind::lattice_holes, 9, 0, 0, 30);
  const ContourSet one = trace_contours(tin, {.interval = 0.5, .threads = 1});
  for (const unsigned threads : {2u, 3u, 0u}) {
    const ContourSet many = trace_contours(tin, {.interval = 0.5, .threads = threads});
    EXPECT_EQ(many.lines, one.lines);
    EXPECT_EQ(many.points, one.points);
  }
}

TEST(Contours, RefusesBadIntervals) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 1);
  EXPECT_THROW(trace_contours(tin, {.interval = 0}), Error);
  EXPECT_THROW(trace_contours(tin, {.interval = -1}), Error);
  EXPECT_THROW(trace_contours(tin, {.interval = NAN}), Error);
  EXPECT_THROW(trace_contours(tin, {.interval = 1e-9}), Error);  // 10^10 levels
  EXPECT_THROW(trace_contours(tin, {.interval = 1, .base = INFINITY}), Error);
}

}  // namespace
}  // namespace tincdt::products
