// Property tests of the Delaunay stage, triangulate(), on both of its paths: the sequential one
// and the two-thread one (parallel_delaunay.hpp), which triangulate() takes from a size threshold
// on and which each case below forces. validate() on thousands of random and degenerate inputs,
// checked against independent references (brute-force empty circles, hull size, point map); on
// the parallel path also that it did split and that it agrees with the sequential result.
#include "delaunay/delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "predicates/predicates.hpp"
#include "support/delaunay_checks.hpp"

namespace tincdt::delaunay {
namespace {

using test::globally_delaunay;
using test::hull_vertex_count;
using test::takes_parallel_path;

constexpr std::size_t kNever = std::numeric_limits<std::size_t>::max();

struct Path {
  const char* name;
  std::size_t parallel_min_points;  // 0: always split in two; kNever: one thread
};

void PrintTo(const Path& path, std::ostream* os) {
  *os << path.name;
}

std::vector<Point2> xy_of(const std::vector<Point3>& points) {
  std::vector<Point2> xy;
  xy.reserve(points.size());
  for (const Point3& p : points) xy.push_back({p.x, p.y});
  return xy;
}

DelaunayResult run(std::vector<Point3> points, std::size_t parallel_min_points,
                   DuplicatePolicy policy = DuplicatePolicy::mean) {
  DelaunayOptions options;
  options.on_duplicate = policy;
  options.keep_point_map = true;
  options.parallel_min_points = parallel_min_points;
  return triangulate(std::move(points), options);
}

class Delaunay : public ::testing::TestWithParam<Path> {
 protected:
  bool parallel() const { return GetParam().parallel_min_points != kNever; }

  DelaunayOptions options() const {
    DelaunayOptions o;
    o.parallel_min_points = GetParam().parallel_min_points;
    return o;
  }

  DelaunayResult run(std::vector<Point3> points,
                     DuplicatePolicy policy = DuplicatePolicy::mean) const {
    return delaunay::run(std::move(points), GetParam().parallel_min_points, policy);
  }

  // A valid TIN of every point: 2n - 2 - h triangles, each point at a vertex of its exact x, y,
  // empty circumcircles when BRUTE_FORCE. On the parallel path the input must split in two, and
  // the result must have the sequential one's vertices, triangle count and heights.
  void expect_valid(const std::vector<Point3>& points, bool brute_force,
                    DuplicatePolicy policy = DuplicatePolicy::mean) const {
    const DelaunayResult r = run(points, policy);
    const mesh::Triangulation& tin = r.tin;
    ASSERT_EQ(tin.validate(), "");
    const std::size_t nv = tin.vertex_count();
    EXPECT_EQ(nv + r.duplicates_merged, points.size());
    EXPECT_EQ(tin.triangle_count(), 2 * nv - 2 - hull_vertex_count(xy_of(points)));
    ASSERT_EQ(r.vertex_of_point.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      ASSERT_EQ(tin.point(r.vertex_of_point[i]), (Point2{points[i].x, points[i].y}));
    if (brute_force) {
      EXPECT_TRUE(globally_delaunay(tin));
    }
    if (!parallel()) return;
    EXPECT_TRUE(takes_parallel_path(points));
    const DelaunayResult seq = delaunay::run(points, kNever, policy);
    EXPECT_EQ(nv, seq.tin.vertex_count());
    EXPECT_EQ(r.duplicates_merged, seq.duplicates_merged);
    EXPECT_EQ(tin.triangle_count(), seq.tin.triangle_count());
    for (std::size_t i = 0; i < points.size(); ++i)
      ASSERT_EQ(tin.z(r.vertex_of_point[i]), seq.tin.z(seq.vertex_of_point[i]));
  }
};

INSTANTIATE_TEST_SUITE_P(Path, Delaunay,
                         ::testing::Values(Path{"sequential", kNever}, Path{"parallel", 0}),
                         [](const ::testing::TestParamInfo<Path>& p) { return p.param.name; });

// ---- random and large ----

// Calls F(rng, seed) for the seeds 0..COUNT-1, each with its own generator and the seed in the
// trace of a failure.
template <class F>
void for_each_seed(unsigned count, F&& f) {
  for (unsigned seed = 0; seed < count; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    f(rng, seed);
  }
}

TEST_P(Delaunay, RandomUniformManySeeds) {
  for_each_seed(400, [&](std::mt19937_64& rng, unsigned) {
    const std::size_t n = 4 + rng() % 400;  // from 4: fewer cannot be split in two
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<Point3> pts;
    for (std::size_t i = 0; i < n; ++i) pts.push_back({u(rng), u(rng), u(rng)});
    expect_valid(pts, n < 150);
  });
}

TEST_P(Delaunay, UtmOffsetsAndLargeRandom) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 10000);
  std::vector<Point3> pts;
  for (int i = 0; i < 60000; ++i) pts.push_back({500000 + u(rng), 4000000 + u(rng), u(rng)});
  expect_valid(pts, false);
}

TEST_P(Delaunay, ClusteredAndTinyScales) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  std::vector<Point3> pts;
  for (int c = 0; c < 20; ++c) {
    const double cx = g(rng) * 1000, cy = g(rng) * 1000, s = std::pow(10.0, -(c % 8));
    for (int i = 0; i < 200; ++i) pts.push_back({cx + g(rng) * s, cy + g(rng) * s, 0});
  }
  expect_valid(pts, false);
}

// ---- degenerate: lattices, collinear runs, cocircular points, one-ulp perturbations ----

TEST_P(Delaunay, RowMajorLatticesAreAllCocircular) {
  for (int k : {2, 3, 5, 17, 64, 150}) {
    for (double origin_x : {0.0, 500000.0}) {
      for (int extra : {0, 1, 7}) {
        std::vector<Point3> pts;  // row-major, like a raster export
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k + extra; ++i)
            pts.push_back({origin_x + i * 0.5, 4000000.0 + j * 0.5, 1.0});
        SCOPED_TRACE("k " + std::to_string(k) + " extra " + std::to_string(extra));
        expect_valid(pts, k <= 17);
      }
    }
  }
}

TEST_P(Delaunay, TallLatticesSplitInsideAColumn) {
  // Three or five columns: no split between two columns is near the middle, so the halves meet
  // inside the middle column and each hull has a long slanted edge facing the other half.
  for (int columns : {2, 3, 5}) {
    for (int rows : {40, 301}) {
      std::vector<Point3> pts;
      for (int j = 0; j < rows; ++j)
        for (int i = 0; i < columns; ++i) pts.push_back({500000.0 + i, 4000000.0 + j, 0});
      SCOPED_TRACE(std::to_string(columns) + " x " + std::to_string(rows));
      expect_valid(pts, rows < 50);
    }
  }
}

TEST_P(Delaunay, CollinearRunsAndHullCollinearPoints) {
  for_each_seed(100, [&](std::mt19937_64& rng, unsigned) {
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
    expect_valid(pts, true);
  });
}

TEST_P(Delaunay, StartsWithCollinearPrefix) {
  // The first points in insertion order may be collinear; whatever the order, the result holds.
  std::vector<Point3> pts;
  for (int i = 0; i < 1000; ++i) pts.push_back({static_cast<double>(i), 0, 0});
  pts.push_back({500, 1, 0});
  pts.push_back({500, -1, 0});
  expect_valid(pts, false);
}

TEST_P(Delaunay, PointsOnTwoVerticalLines) {
  for (int a : {2, 3, 10, 101}) {
    for (int b : {2, 5, 100}) {
      for (double shift : {0.0, 0.25, 1000.0}) {
        std::vector<Point3> pts;
        for (int i = 0; i < a; ++i) pts.push_back({500000.0, 4000000.0 + i, 0});
        for (int i = 0; i < b; ++i) pts.push_back({500001.0, 4000000.0 + shift + i, 0});
        SCOPED_TRACE(std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(shift));
        expect_valid(pts, a + b < 150);
      }
    }
  }
}

TEST_P(Delaunay, CocircularPointsAndCentre) {
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

TEST_P(Delaunay, OneUlpPerturbationsAtUtmMagnitude) {
  for_each_seed(50, [&](std::mt19937_64& rng, unsigned) {
    std::vector<Point3> pts;
    for (const Point2 p : test::one_ulp_lattice(12, rng)) pts.push_back({p.x, p.y, 0});
    expect_valid(pts, true);
  });
}

TEST_P(Delaunay, HalvesOfDifferentShapes) {
  for_each_seed(60, [&](std::mt19937_64& rng, unsigned seed) {
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Point3> pts;
    const int n = 50 + static_cast<int>(rng() % 300);
    const double lift = seed % 2 ? 1e4 : -300;
    for (int i = 0; i < n; ++i) {
      pts.push_back({1e-3 * u(rng), 100 * u(rng), 0});               // thin vertical sliver
      pts.push_back({10 + 1000 * u(rng), lift + 1000 * u(rng), 0});  // a wide blob, higher or lower
    }
    expect_valid(pts, n < 70);
  });
}

// ---- duplicates ----

TEST_P(Delaunay, DuplicatesMergedByPolicy) {
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
    const DelaunayResult r = run(pts, c.policy);
    EXPECT_EQ(r.duplicates_merged, 3u);
    EXPECT_EQ(r.tin.vertex_count(), 4u);
    EXPECT_EQ(r.tin.validate(), "");
    EXPECT_DOUBLE_EQ(r.tin.z(r.vertex_of_point[3]), c.z11);
    EXPECT_DOUBLE_EQ(r.tin.z(r.vertex_of_point[0]), c.z00);
    EXPECT_EQ(r.vertex_of_point[3], r.vertex_of_point[4]);
    EXPECT_EQ(r.vertex_of_point[0], r.vertex_of_point[6]);
  }
}

TEST_P(Delaunay, ManyDuplicatesInRandomOrder) {
  std::mt19937_64 rng(11);
  std::vector<Point3> pts;
  for (int i = 0; i < 3000; ++i)
    pts.push_back({static_cast<double>(rng() % 40), static_cast<double>(rng() % 40), 1.0});
  expect_valid(pts, false);
}

TEST_P(Delaunay, HalvesOfDifferentSizesThroughDuplicates) {
  // The pivot splits the points, not the distinct ones: a few heavily repeated points on one side.
  for_each_seed(40, [&](std::mt19937_64& rng, unsigned seed) {
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Point3> pts;
    const int few = 2 + static_cast<int>(seed % 4);
    for (int k = 0; k < few; ++k) {
      const Point3 p{u(rng), u(rng), u(rng)};
      for (int r = 0; r < 20; ++r) pts.push_back({p.x, p.y, p.z + r});
    }
    for (int i = 0; i < 300; ++i) pts.push_back({2 + u(rng), 10 * u(rng) - 5, u(rng)});
    std::shuffle(pts.begin(), pts.end(), rng);
    for (DuplicatePolicy policy : {DuplicatePolicy::first, DuplicatePolicy::min,
                                   DuplicatePolicy::max, DuplicatePolicy::mean})
      expect_valid(pts, false, policy);
  });
}

TEST_P(Delaunay, KeepDuplicatesListsEachMergedVertex) {
  // One group in each half (the pivot splits near x = 50), so on the parallel path the right
  // one's vertex is offset by the left half's vertex count.
  for_each_seed(20, [&](std::mt19937_64& rng, unsigned) {
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<Point3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back({u(rng), u(rng), 0});
    for (double z : {5.0, 1.0, 9.0}) pts.push_back({10.5, 20.25, z});
    for (double z : {-3.0, 4.0}) pts.push_back({90.5, 70.25, z});
    std::shuffle(pts.begin(), pts.end(), rng);
    if (parallel()) {
      ASSERT_TRUE(takes_parallel_path(pts));
    }
    DelaunayOptions o = options();
    o.keep_duplicates = true;
    o.keep_point_map = true;
    for (DuplicatePolicy policy : {DuplicatePolicy::first, DuplicatePolicy::mean}) {
      o.on_duplicate = policy;
      const DelaunayResult r = triangulate(std::vector<Point3>(pts), o);
      ASSERT_EQ(r.tin.validate(), "");
      EXPECT_EQ(r.duplicates_merged, 3u);
      ASSERT_EQ(r.duplicates.size(), 2u);
      std::uint64_t merged = 0;
      for (const DelaunayResult::Duplicate& d : r.duplicates) merged += d.points - 1;
      EXPECT_EQ(merged, r.duplicates_merged);
      const DelaunayResult::Duplicate a = r.duplicates[0], b = r.duplicates[1];  // vertex order
      EXPECT_LT(a.vertex, b.vertex);
      EXPECT_EQ(r.tin.point(a.vertex), (Point2{10.5, 20.25}));
      EXPECT_EQ(a.points, 3u);
      EXPECT_EQ(a.z_min, 1.0);
      EXPECT_EQ(a.z_max, 9.0);
      EXPECT_EQ(r.tin.point(b.vertex), (Point2{90.5, 70.25}));
      EXPECT_EQ(b.points, 2u);
      EXPECT_EQ(b.z_min, -3.0);
      EXPECT_EQ(b.z_max, 4.0);
      if (policy == DuplicatePolicy::mean) {
        EXPECT_DOUBLE_EQ(r.tin.z(a.vertex), 5.0);
        EXPECT_DOUBLE_EQ(r.tin.z(b.vertex), 0.5);
      }
      for (std::size_t i = 0; i < pts.size(); ++i) {
        if (pts[i].x == 10.5 && pts[i].y == 20.25) {
          EXPECT_EQ(r.vertex_of_point[i], a.vertex);
        }
        if (pts[i].x == 90.5 && pts[i].y == 70.25) {
          EXPECT_EQ(r.vertex_of_point[i], b.vertex);
        }
      }
    }
  });
}

// ---- refusals and cancelling ----

TEST_P(Delaunay, RejectsDegenerateInput) {
  EXPECT_THROW(run({}), GeometryError);
  EXPECT_THROW(run({{0, 0, 0}, {1, 1, 1}}), GeometryError);
  EXPECT_THROW(run({{0, 0, 0}, {1, 1, 1}, {0, 0, 5}, {1, 1, 2}}), GeometryError);
  EXPECT_THROW(run({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}), GeometryError);
  EXPECT_THROW(run({{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}}), GeometryError);
  try {
    run({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
    FAIL();
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos);
  }
}

TEST_P(Delaunay, ProgressCanCancel) {
  std::vector<Point3> pts;
  for (int i = 0; i < 60000; ++i) pts.push_back({std::sin(i) * 100, std::cos(i * 1.3) * 100, 0});
  int calls = 0;
  ProgressFn fn = [&](std::string_view stage, double) {
    EXPECT_EQ(stage, "delaunay");
    return ++calls < 3;
  };
  EXPECT_THROW(triangulate(std::move(pts), options(), &fn), Cancelled);
  EXPECT_EQ(calls, 3);
}

// ---- options that do not depend on the path ----

TEST(DelaunayDefaults, DuplicatesAreCountedButNotListed) {
  std::vector<Point3> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 1, 5}, {0, 0, 2}};
  const DelaunayResult r = triangulate(std::move(pts));
  EXPECT_EQ(r.duplicates_merged, 2u);
  EXPECT_TRUE(r.duplicates.empty());
}

}  // namespace
}  // namespace tincdt::delaunay
