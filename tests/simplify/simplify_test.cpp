// Greedy-insertion simplification on random and degenerate inputs, each result checked against
// independent references: every point located again and measured, every constraint a chain of
// constrained edges, the constrained Delaunay property, determinism under input order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "simplify/simplify.hpp"
#include "simplify_checks.hpp"

namespace tincdt::simplify {
namespace {

using constraints::Segment;

constexpr double kX0 = 500000.125, kY0 = 4000000.5;  // UTM magnitude

struct Input {
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<std::uint32_t> kept;
  std::vector<Segment> segments;
};

double terrain(double x, double y) {
  return 100 + 20 * std::sin(x / 37.0) * std::cos(y / 23.0) + 0.01 * x +
         3 * std::sin(x * y / 400.0);
}

// n random points in a 200 m square with a rough terrain, optionally a closed ring and a line
// across it as constraints (they cross: the crossings become vertices of their own).
Input random_input(std::uint32_t seed, std::size_t n, bool features) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 200), noise(-0.3, 0.3);
  Input in;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    in.xy.push_back({kX0 + x, kY0 + y});
    in.z.push_back(terrain(x, y) + noise(rng));
  }
  if (features) {
    const auto ring = static_cast<std::uint32_t>(in.xy.size());
    const int k = 24;
    for (int i = 0; i < k; ++i) {
      const double a = 2 * M_PI * i / k, x = 100 + 60 * std::cos(a), y = 100 + 60 * std::sin(a);
      in.xy.push_back({kX0 + x, kY0 + y});
      in.z.push_back(terrain(x, y));
    }
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(k); ++i)
      in.segments.push_back({ring + i, ring + (i + 1) % k, 1});
    const auto line = static_cast<std::uint32_t>(in.xy.size());
    in.xy.push_back({kX0 + 10, kY0 + 37});
    in.z.push_back(terrain(10, 37));
    in.xy.push_back({kX0 + 190, kY0 + 151});
    in.z.push_back(terrain(190, 151));
    in.segments.push_back({line, line + 1, 2});
    in.kept.push_back(static_cast<std::uint32_t>(seed % n));  // one more kept point
  }
  return in;
}

// The properties every result must have.
void check(const Input& in, const SimplifyOptions& options, const SimplifyResult& r,
           bool brute = false) {
  const mesh::Triangulation& tin = r.tin;
  EXPECT_EQ(tin.validate({.delaunay = true}), "");
  EXPECT_EQ(r.report.points, in.xy.size());
  EXPECT_EQ(r.report.vertices, tin.vertex_count());
  ASSERT_EQ(r.point_of_vertex.size(), tin.vertex_count());

  // Vertices are input points, each at most once, with their own z; kept points are vertices.
  std::vector<VertexId> vertex_of(in.xy.size(), kNoId);
  for (VertexId v = 0; v < tin.vertex_count(); ++v) {
    const std::uint32_t p = r.point_of_vertex[v];
    if (p == kNoId) continue;  // a crossing of two segments
    ASSERT_LT(p, in.xy.size());
    EXPECT_EQ(vertex_of[p], kNoId) << "point " << p << " is two vertices";
    vertex_of[p] = v;
    EXPECT_EQ(tin.point(v), in.xy[p]);
    EXPECT_EQ(tin.z(v), in.z[p]);
  }
  for (std::uint32_t p : in.kept) EXPECT_NE(vertex_of[p], kNoId) << "kept point " << p;
  std::vector<std::uint8_t> crossing(tin.vertex_count(), 0);
  for (VertexId v = 0; v < tin.vertex_count(); ++v) crossing[v] = r.point_of_vertex[v] == kNoId;
  for (const Segment& s : in.segments) {
    ASSERT_NE(vertex_of[s.a], kNoId);
    ASSERT_NE(vertex_of[s.b], kNoId);
    EXPECT_EQ(test::constrained_chain(tin, vertex_of[s.a], vertex_of[s.b], crossing), "");
  }

  // Every point within the tolerance (unless the vertex budget stopped it), as reported.
  const double measured = test::max_vertical_error(tin, in.xy, in.z, brute);
  const double slack = 1e-9 * (1 + std::fabs(in.z.empty() ? 0 : in.z[0]));
  EXPECT_NEAR(measured, r.report.max_error, slack);
  if (!r.report.stopped_at_max_vertices) {
    EXPECT_LE(measured, options.max_error + slack);
  }
  if (options.max_vertices) {
    EXPECT_LE(tin.vertex_count(),
              std::max<std::size_t>(options.max_vertices, r.report.kept_vertices));
  }
  EXPECT_GE(r.report.rmse, 0);
  EXPECT_LE(r.report.rmse, r.report.max_error + slack);
}

// The same points in another order (kept points and segments renumbered).
Input shuffled(const Input& in, std::uint32_t seed) {
  std::vector<std::uint32_t> order(in.xy.size());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  std::vector<std::uint32_t> where(in.xy.size());
  Input out;
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    out.xy.push_back(in.xy[order[i]]);
    out.z.push_back(in.z[order[i]]);
    where[order[i]] = i;
  }
  for (std::uint32_t k : in.kept) out.kept.push_back(where[k]);
  for (const Segment& s : in.segments) out.segments.push_back({where[s.b], where[s.a], s.source});
  std::reverse(out.segments.begin(), out.segments.end());
  return out;
}

SimplifyResult run(const Input& in, const SimplifyOptions& options) {
  return simplify(in.xy, in.z, in.kept, in.segments, options);
}

struct Case {
  std::uint32_t seed;
  std::size_t n;
  double max_error;
  bool features;
};

class RandomTerrain : public ::testing::TestWithParam<Case> {};

TEST_P(RandomTerrain, EveryPointWithinToleranceAndEveryConstraintKept) {
  const Case c = GetParam();
  const Input in = random_input(c.seed, c.n, c.features);
  SimplifyOptions options;
  options.max_error = c.max_error;
  const SimplifyResult r = run(in, options);
  check(in, options, r, c.n <= 600);
  if (c.max_error >= 1) {
    EXPECT_LT(r.report.vertices, in.xy.size()) << "nothing was simplified";
  }
  const auto crossings = static_cast<std::uint64_t>(
      std::count(r.point_of_vertex.begin(), r.point_of_vertex.end(), kNoId));
  EXPECT_EQ(r.report.vertices, r.report.kept_vertices + crossings + r.report.inserted);

  // Input order, thread count: same triangles.
  const Input other = shuffled(in, c.seed + 1);
  options.threads = 1;
  const SimplifyResult r2 = run(other, options);
  EXPECT_EQ(test::triangle_set(r.tin), test::triangle_set(r2.tin));
  EXPECT_EQ(r.report.max_error, r2.report.max_error);
}

std::vector<Case> random_cases() {
  std::vector<Case> cases;
  std::uint32_t seed = 1;
  for (std::size_t n : {60, 500, 4000})
    for (double e : {0.0, 0.1, 1.0, 5.0})
      for (bool f : {false, true}) cases.push_back({seed++, n, e, f});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Simplify, RandomTerrain, ::testing::ValuesIn(random_cases()),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           const Case& c = param.param;
                           return "n" + std::to_string(c.n) + "_e" +
                                  std::to_string(static_cast<int>(c.max_error * 10)) +
                                  (c.features ? "_features" : "_points");
                         });

// Two chunks of the initial location and of the large first rescans: the same TIN as one.
TEST(Simplify, ThreadsDoNotChangeTheResult) {
  const Input in = random_input(99, 140000, true);
  SimplifyOptions one, two;
  one.max_error = two.max_error = 0.5;
  one.threads = 1;
  two.threads = 2;
  const SimplifyResult a = run(in, one), b = run(in, two);
  EXPECT_EQ(test::triangle_set(a.tin), test::triangle_set(b.tin));
  EXPECT_EQ(a.report.max_error, b.report.max_error);
  EXPECT_EQ(a.report.rmse, b.report.rmse);
  check(in, one, a);
}

// Inputs of 65536 points or more start from the insertions of a coarse run on a thinned subset
// (chosen by a hash of x, y): the result must still not depend on the input order.
TEST(Simplify, SeededLargeInputDoesNotDependOnOrder) {
  const Input in = random_input(7, 140000, true);
  SimplifyOptions options;
  options.max_error = 0.5;
  const SimplifyResult a = run(in, options), b = run(shuffled(in, 8), options);
  EXPECT_EQ(test::triangle_set(a.tin), test::triangle_set(b.tin));
  EXPECT_EQ(a.report.max_error, b.report.max_error);
  EXPECT_EQ(a.report.inserted, b.report.inserted);
  check(in, options, a);
}

// From 2^18 points on, the points' box is cut into regions simplified on their own (on all
// threads) that seed the run on all points: still every point within the tolerance, every
// constraint kept (the ring and the line cross the regions' edges), the same TIN for any thread
// count and input order, and about as few vertices as one greedy run (a vertex budget turns
// both the regions and the coarse seeds off).
TEST(Simplify, RegionsDoNotChangeWithThreadsOrOrder) {
  Input in = random_input(21, 300000, true);
  // Short lines across the regions' shared edge x = 100, their ends on spikes: each region
  // gets the end on its side as a plain point, and inserts it.
  for (int k = 0; k < 20; ++k) {
    const auto first = static_cast<std::uint32_t>(in.xy.size());
    for (double x : {90.0, 110.0}) {
      const double y = 5 + 9.5 * k;
      in.xy.push_back({kX0 + x, kY0 + y});
      in.z.push_back(terrain(x, y) + 3);
    }
    in.segments.push_back({first, first + 1, 3});
  }
  SimplifyOptions options;
  options.max_error = 0.5;
  options.threads = 1;
  const SimplifyResult a = run(in, options);
  EXPECT_EQ(a.report.regions, 4u);
  check(in, options, a);
  // Those ends count once, as kept: the hull corners, the kept points and the segments' ends.
  std::set<std::uint32_t> kept(in.kept.begin(), in.kept.end());
  for (std::uint32_t i : hull_corners(in.xy)) kept.insert(i);
  for (const Segment& g : in.segments) kept.insert({g.a, g.b});
  EXPECT_EQ(a.report.kept_vertices, kept.size());
  const auto crossings = static_cast<std::uint64_t>(
      std::count(a.point_of_vertex.begin(), a.point_of_vertex.end(), kNoId));
  EXPECT_EQ(a.report.vertices, a.report.kept_vertices + crossings + a.report.inserted);
  options.threads = 2;
  const SimplifyResult b = run(in, options);
  EXPECT_EQ(test::triangle_set(a.tin), test::triangle_set(b.tin));
  EXPECT_EQ(a.report.max_error, b.report.max_error);
  EXPECT_EQ(a.report.rmse, b.report.rmse);
  options.threads = 3;
  const SimplifyResult c = run(shuffled(in, 22), options);
  EXPECT_EQ(test::triangle_set(a.tin), test::triangle_set(c.tin));
  EXPECT_EQ(a.report.max_error, c.report.max_error);

  options.max_vertices = 1u << 30;
  const SimplifyResult one = run(in, options);
  EXPECT_EQ(one.report.regions, 0u);
  EXPECT_LE(static_cast<double>(a.report.vertices),
            1.02 * static_cast<double>(one.report.vertices));
  std::printf("regions: %llu vertices, one greedy run: %llu\n",
              static_cast<unsigned long long>(a.report.vertices),
              static_cast<unsigned long long>(one.report.vertices));
}

// The regions' progress reaches the caller from its own thread only, never goes back, and a
// request to stop during the regions (or an exception from the callback) ends the run: the
// callback is not called again, and its exception is the one that comes out.
TEST(Simplify, RegionsReportProgressAndCanCancel) {
  const Input in = random_input(23, 300000, false);
  SimplifyOptions options;
  options.max_error = 0.5;
  options.threads = 2;
  std::vector<double> seen;
  bool other_thread = false;
  const std::thread::id caller = std::this_thread::get_id();
  ProgressFn report = [&](std::string_view stage, double f) {
    EXPECT_EQ(stage, "simplify");
    other_thread |= std::this_thread::get_id() != caller;
    seen.push_back(f);
    return true;
  };
  const SimplifyResult r = simplify(in.xy, in.z, {}, {}, options, &report);
  EXPECT_EQ(r.report.regions, 4u);
  EXPECT_FALSE(other_thread);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_GT(std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0 && f < 0.5; }), 0);
  bool asked_to_stop = false, called_after = false;
  ProgressFn cancel = [&](std::string_view, double f) {
    called_after |= asked_to_stop;
    asked_to_stop |= f >= 0.3;
    return !asked_to_stop;
  };
  EXPECT_THROW(simplify(in.xy, in.z, {}, {}, options, &cancel), Cancelled);
  EXPECT_TRUE(asked_to_stop);
  EXPECT_FALSE(called_after);
  ProgressFn throws = [](std::string_view, double f) {
    if (f > 0.3) throw std::runtime_error("from the callback");
    return true;
  };
  EXPECT_THROW(simplify(in.xy, in.z, {}, {}, options, &throws), std::runtime_error);
}

// Regions whose points are all on one line, or none, seed nothing; bad input found inside a
// region is reported as the run on all points reports it.
TEST(Simplify, DegenerateRegionsAreLeftToTheLastRun) {
  Input in = random_input(25, 300000, false);
  for (Point2& p : in.xy) p.x = kX0 + (p.x - kX0) / 2;  // the left half of the box
  for (int i = 0; i < 2000; ++i) {                      // and a line at its right edge
    in.xy.push_back({kX0 + 200, kY0 + 0.1 * i});
    in.z.push_back(100 + 0.001 * i * i);
  }
  SimplifyOptions options;
  options.max_error = 0.5;
  const SimplifyResult r = run(in, options);
  EXPECT_EQ(r.report.regions, 2u);  // the two on the right hold only the line
  check(in, options, r);

  // An L: the top right cell holds no point at all (an empty set of points is not all points).
  Input l = random_input(26, 300000, false);
  for (Point2& p : l.xy)
    if (p.x > kX0 + 100 && p.y > kY0 + 100) p.x -= 100;
  const SimplifyResult r2 = run(l, options);
  EXPECT_EQ(r2.report.regions, 3u);
  check(l, options, r2);

  in.xy.push_back(in.xy[10]);
  in.z.push_back(in.z[10] + 1);
  in.kept = {10, static_cast<std::uint32_t>(in.xy.size() - 1)};
  EXPECT_THROW(run(in, options), GeometryError);
}

// A grid: every cell cocircular, many points on every long edge, and equal errors everywhere
// (integer heights): the ties are broken by the points, whatever their order.
TEST(Simplify, GridWithTiesIsDeterministic) {
  Input in;
  for (int j = 0; j < 70; ++j)
    for (int i = 0; i < 70; ++i) {
      in.xy.push_back({kX0 + i, kY0 + j});
      in.z.push_back(std::round(5 * std::sin(i / 9.0) + 4 * std::cos(j / 7.0)));
    }
  for (double e : {0.0, 0.5, 2.0}) {
    SimplifyOptions options;
    options.max_error = e;
    const SimplifyResult r = run(in, options);
    check(in, options, r);
    const SimplifyResult r2 = run(shuffled(in, 7), options);
    EXPECT_EQ(test::triangle_set(r.tin), test::triangle_set(r2.tin)) << "max error " << e;
  }
}

// A straight feature with candidate points exactly on it, others beside it, and a feature
// along the hull: the constraints stay chains, points on them may split them.
TEST(Simplify, PointsOnCollinearConstraints) {
  Input in;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 64);
  for (int i = 0; i <= 64; ++i) {  // on the diagonal, only the ends kept
    in.xy.push_back({kX0 + i, kY0 + i});
    in.z.push_back(10 + 0.5 * std::sin(i / 3.0) * 4);
  }
  in.segments.push_back({0, 64, 0});
  for (int i = 8; i < 64; i += 8) {  // most of the south edge of the hull, in pieces
    in.xy.push_back({kX0 + i, kY0});
    in.z.push_back(9 + (i % 16 ? 1.0 : 0.0));
  }
  in.xy.push_back({kX0 + 64, kY0});
  in.z.push_back(9);
  for (std::uint32_t k = 65; k + 1 < in.xy.size(); ++k) in.segments.push_back({k, k + 1, 1});
  for (int i = 0; i < 1500; ++i) {
    const double x = u(rng), y = u(rng);
    in.xy.push_back({kX0 + x, kY0 + y});
    in.z.push_back(10 + std::sin(x / 5) * std::cos(y / 4) * 3);
  }
  for (double e : {0.0, 0.2, 2.0}) {
    SimplifyOptions options;
    options.max_error = e;
    const SimplifyResult r = run(in, options);
    check(in, options, r, true);
  }
}

TEST(Simplify, MaxVerticesStopsTheLoop) {
  const Input in = random_input(3, 3000, false);
  SimplifyOptions options;
  options.max_error = 0;
  options.max_vertices = 50;
  const SimplifyResult r = run(in, options);
  EXPECT_TRUE(r.report.stopped_at_max_vertices);
  EXPECT_EQ(r.tin.vertex_count(), 50u);
  EXPECT_GT(r.report.max_error, 0);
  check(in, options, r);
  // Its max error is what the next insertion would have fixed: larger than with more vertices.
  options.max_vertices = 100;
  EXPECT_LE(run(in, options).report.max_error, r.report.max_error);
}

TEST(Simplify, PlaneKeepsOnlyTheHullCorners) {
  Input in;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 100);
  for (int i = 0; i < 2000; ++i) {
    const double x = std::round(u(rng) * 8) / 8, y = std::round(u(rng) * 8) / 8;
    in.xy.push_back({x, y});
    in.z.push_back(3 + x / 4 - y / 8);  // exact in binary
  }
  // The points on a 1/8 grid repeat; keep the first of each x, y (z is the plane's anyway).
  std::set<std::pair<double, double>> seen;
  Input distinct;
  for (std::size_t i = 0; i < in.xy.size(); ++i) {
    if (!seen.insert({in.xy[i].x, in.xy[i].y}).second) continue;
    distinct.xy.push_back(in.xy[i]);
    distinct.z.push_back(in.z[i]);
  }
  in = std::move(distinct);
  SimplifyOptions options;
  const SimplifyResult r = run(in, options);
  EXPECT_EQ(r.report.inserted, 0u);
  EXPECT_EQ(r.report.vertices, hull_corners(in.xy).size());
  EXPECT_EQ(r.report.max_error, 0);
  check(in, options, r);
}

TEST(Simplify, DegenerateInputsAreGeometryErrors) {
  SimplifyOptions options;
  std::vector<Point2> xy{{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  std::vector<double> z{0, 1, 2, 3};
  EXPECT_THROW(simplify(xy, z, {}, {}, options), GeometryError);  // collinear
  xy = {{0, 0}, {1, 0}};
  z = {0, 0};
  EXPECT_THROW(simplify(xy, z, {}, {}, options), GeometryError);  // fewer than 3
  xy = {{0, 0}, {1, 0}, {0, 1}, {0, 1}};
  z = {0, 0, 0, 5};
  const std::vector<std::uint32_t> both{2, 3};
  EXPECT_THROW(simplify(xy, z, both, {}, options), GeometryError);  // duplicate kept points
  options.max_error = -1;
  EXPECT_THROW(simplify(xy, z, {}, {}, options), Error);
}

TEST(Simplify, ProgressIsReportedAndCanCancel) {
  const Input in = random_input(4, 2000, false);
  SimplifyOptions options;
  options.max_error = 0.05;
  double last = -1;
  ProgressFn report = [&](std::string_view stage, double f) {
    EXPECT_EQ(stage, "simplify");
    last = f;
    return true;
  };
  simplify(in.xy, in.z, {}, {}, options, &report);
  EXPECT_EQ(last, 1.0);
  ProgressFn cancel = [](std::string_view, double f) { return f < 0.3; };
  EXPECT_THROW(simplify(in.xy, in.z, {}, {}, options, &cancel), Cancelled);
}

// The reference: Jarvis march keeping only strict turns.
std::vector<Point2> jarvis(const std::vector<Point2>& p) {
  std::size_t start = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (p[i].x < p[start].x || (p[i].x == p[start].x && p[i].y < p[start].y)) start = i;
  std::vector<Point2> hull;
  std::size_t cur = start;
  do {
    hull.push_back(p[cur]);
    std::size_t next = cur == 0 ? 1 : 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i] == p[cur]) continue;
      const int o = predicates::orient2d(p[cur], p[next], p[i]);
      const auto d2 = [&](Point2 q) {
        return (q.x - p[cur].x) * (q.x - p[cur].x) + (q.y - p[cur].y) * (q.y - p[cur].y);
      };
      if (o < 0 || (o == 0 && d2(p[i]) > d2(p[next]))) next = i;
    }
    cur = next;
  } while (!(p[cur] == p[start]) && hull.size() <= p.size());
  return hull;
}

TEST(HullCorners, MatchesJarvisMarchOnRandomAndDegenerateSets) {
  std::mt19937 rng(17);
  for (int round = 0; round < 60; ++round) {
    std::vector<Point2> p;
    const int n = 3 + round * 7;
    std::uniform_int_distribution<int> small(0, 6);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < n; ++i) {
      if (round % 3 == 0)
        p.push_back({static_cast<double>(small(rng)), static_cast<double>(small(rng))});  // grid
      else if (round % 3 == 1)
        p.push_back({kX0 + u(rng), kY0 + u(rng)});
      else {
        const double a = u(rng) * M_PI;  // on a circle, plus its centre
        p.push_back({std::cos(a), std::sin(a)});
      }
    }
    if (round % 3 == 2) p.push_back({0, 0});
    const std::vector<std::uint32_t> corners = hull_corners(p);
    std::vector<Point2> got;
    for (std::uint32_t i : corners) got.push_back(p[i]);
    EXPECT_EQ(got, jarvis(p)) << "round " << round;

    // Of a subset named by ids: the hull of those points alone.
    std::vector<std::uint32_t> ids;
    std::vector<Point2> subset;
    for (std::uint32_t i = 0; i < p.size(); ++i)
      if (i % 3 != 1 || i < 3) ids.push_back(i), subset.push_back(p[i]);
    got.clear();
    for (std::uint32_t i : hull_corners(p, ids)) got.push_back(p[i]);
    EXPECT_EQ(got, jarvis(subset)) << "round " << round << ", a subset";
  }
}

// The pipeline's form: the constrained TIN of all points in, every vertex of it within the
// tolerance of the result and every constrained edge of it an edge of the result. The last one
// is large enough for regions, whose edges the ring and the line cross.
TEST(SimplifyTin, KeepsEveryConstrainedEdgeOfTheFullTin) {
  for (std::uint32_t seed : {31u, 32u, 33u, 34u}) {
    const Input in = random_input(seed, seed == 34 ? 300000 : 5000, true);
    std::vector<Point3> pts;
    for (std::size_t i = 0; i < in.xy.size(); ++i) pts.push_back({in.xy[i].x, in.xy[i].y, in.z[i]});
    delaunay::DelaunayResult d = delaunay::triangulate(std::move(pts), {.keep_point_map = true});
    std::vector<Segment> segs;
    for (const Segment& s : in.segments)
      segs.push_back({d.vertex_of_point[s.a], d.vertex_of_point[s.b], s.source});
    constraints::insert_constraints(d.tin, segs);
    const mesh::Triangulation& full = d.tin;

    SimplifyOptions options;
    options.max_error = 0.2;
    const SimplifyResult r = simplify_tin(full, options);
    EXPECT_EQ(r.report.regions, seed == 34 ? 4u : 0u);
    EXPECT_EQ(r.tin.validate({.delaunay = true}), "");
    EXPECT_LT(r.tin.vertex_count(), full.vertex_count());
    std::vector<VertexId> vertex_of(full.vertex_count(), kNoId);
    for (VertexId v = 0; v < r.tin.vertex_count(); ++v) {
      ASSERT_NE(r.point_of_vertex[v], kNoId);  // the full TIN's crossings are its vertices
      vertex_of[r.point_of_vertex[v]] = v;
    }
    std::size_t edges = 0;
    full.for_each_constrained_edge([&](EdgeId e) {
      ++edges;
      const VertexId a = vertex_of[full.origin(e)], b = vertex_of[full.dest(e)];
      ASSERT_NE(a, kNoId);
      ASSERT_NE(b, kNoId);
      const EdgeId f = r.tin.find_edge(a, b);
      ASSERT_NE(f, kNoId) << "constrained edge lost";
      EXPECT_TRUE(r.tin.is_constrained(f));
    });
    EXPECT_GT(edges, 24u);
    const double measured = test::max_vertical_error(r.tin, full.points(), full.heights());
    EXPECT_LE(measured, options.max_error + 1e-9);
    EXPECT_NEAR(measured, r.report.max_error, 1e-9);
  }
}

}  // namespace
}  // namespace tincdt::simplify
