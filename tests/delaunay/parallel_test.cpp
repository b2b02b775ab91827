// Property tests of the two-thread Delaunay path (parallel_delaunay.hpp): the merge of two
// triangulations on its own, on every kind of split, each result checked by validate() and the
// triangle count 2n - 2 - h; and what only triangulate()'s parallel path does (the default
// threshold, the fallback, the merged-duplicate list against the sequential one). The property
// tests of triangulate() run on both paths in delaunay_test.cpp.
#include "delaunay/parallel_delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <tuple>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "predicates/predicates.hpp"
#include "support/delaunay_checks.hpp"

namespace tincdt::delaunay {
namespace {

using mesh::Triangulation;
using test::globally_delaunay;
using test::hull_vertex_count;
using test::takes_parallel_path;

constexpr std::size_t kNever = std::numeric_limits<std::size_t>::max();

bool lex_less(Point2 a, Point2 b) {
  return std::tie(a.x, a.y) < std::tie(b.x, b.y);
}

// ---- the merge on its own
// -------------------------------------------------------------------------

// Triangulates left (all lexicographically smaller) and right separately into one Triangulation,
// in the given vertex order, merges them and checks the result.
void expect_merge_valid(const std::vector<Point2>& left, const std::vector<Point2>& right,
                        bool brute_force) {
  Triangulation tin;
  for (Point2 p : left) tin.add_vertex(p, 0);
  for (Point2 p : right) tin.add_vertex(p, 0);
  const auto nl = static_cast<VertexId>(left.size());
  const auto nv = static_cast<VertexId>(tin.vertex_count());
  for (std::size_t t = 0; t + 2 < 2 * std::size_t{nv}; ++t) tin.add_triangle(kNoId, kNoId, kNoId);
  const EdgeId gl = triangulate_range(tin, 0, nl, 0);
  const EdgeId gr = triangulate_range(tin, nl, nv, 2 * nl - 2);
  merge_triangulations(tin, gl, gr, 2 * nv - 4, 2 * nv - 3);
  tin.recount();
  ASSERT_EQ(tin.validate(), "");
  std::vector<Point2> all = left;
  all.insert(all.end(), right.begin(), right.end());
  EXPECT_EQ(tin.triangle_count(), 2 * std::size_t{nv} - 2 - hull_vertex_count(all));
  if (brute_force) {
    EXPECT_TRUE(globally_delaunay(tin));
  }
}

// The same merge mirrored in x (and shifted by SHIFT): RIGHT's mirror image becomes the left half.
void expect_mirrored_merge_valid(const std::vector<Point2>& left, const std::vector<Point2>& right,
                                 double shift) {
  std::vector<Point2> mirrored_left, mirrored_right;
  for (Point2 p : right) mirrored_left.push_back({-p.x, p.y});
  for (Point2 p : left) mirrored_right.push_back({-p.x + shift, p.y});
  expect_merge_valid(mirrored_left, mirrored_right, true);
}

// Distinct points, sorted, split at `m`; each side shuffled into a random insertion order.
void expect_split_valid(std::vector<Point2> points, std::size_t m, std::mt19937_64& rng,
                        bool brute_force) {
  std::sort(points.begin(), points.end(), lex_less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  ASSERT_GE(points.size(), 4u);
  m = std::clamp<std::size_t>(m, 2, points.size() - 2);
  std::vector<Point2> left(points.begin(), points.begin() + static_cast<std::ptrdiff_t>(m));
  std::vector<Point2> right(points.begin() + static_cast<std::ptrdiff_t>(m), points.end());
  std::shuffle(left.begin(), left.end(), rng);
  std::shuffle(right.begin(), right.end(), rng);
  expect_merge_valid(left, right, brute_force);
}

bool all_collinear(const std::vector<Point2>& p) {
  for (std::size_t i = 2; i < p.size(); ++i)
    if (predicates::orient2d(p[0], p[1], p[i]) != 0) return false;
  return true;
}

TEST(Merge, RandomSplitsOfRandomSets) {
  for (unsigned seed = 0; seed < 500; ++seed) {
    std::mt19937_64 rng(seed);
    const std::size_t n = 4 + rng() % 120;
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<Point2> pts;
    for (std::size_t i = 0; i < n; ++i) pts.push_back({u(rng), u(rng)});
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_split_valid(pts, rng() % n, rng, true);
  }
}

TEST(Merge, EverySplitOfSmallLattices) {
  std::mt19937_64 rng(1);
  for (int w : {2, 3, 4, 7})
    for (int h : {2, 3, 5, 8})
      for (double origin : {0.0, 500000.0}) {
        std::vector<Point2> pts;
        for (int j = 0; j < h; ++j)
          for (int i = 0; i < w; ++i) pts.push_back({origin + i, 4000000.0 + j * 0.5});
        for (std::size_t m = 2; m + 2 <= pts.size(); ++m) {
          SCOPED_TRACE("lattice " + std::to_string(w) + "x" + std::to_string(h) + " split " +
                       std::to_string(m));
          expect_split_valid(pts, m, rng, true);
        }
      }
}

TEST(Merge, CollinearHalvesAndTwoLines) {
  std::mt19937_64 rng(2);
  for (int a = 2; a <= 7; ++a)
    for (int b = 2; b <= 7; ++b) {
      // Two vertical lines (collinear facing sides), with equal or shifted heights.
      for (double shift : {0.0, 0.5, 3.0, -10.0}) {
        std::vector<Point2> left, right;
        for (int i = 0; i < a; ++i) left.push_back({0, static_cast<double>(i)});
        for (int i = 0; i < b; ++i) right.push_back({1, shift + i});
        SCOPED_TRACE(std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(shift));
        expect_merge_valid(left, right, true);
        // The same two columns split inside the first one, and along one line through both.
        std::vector<Point2> all = left;
        all.insert(all.end(), right.begin(), right.end());
        for (std::size_t m = 2; m + 2 <= all.size(); ++m) expect_split_valid(all, m, rng, true);
      }
      // A horizontal segment left, a blob right: above, below, on both sides of its line.
      for (double dy : {-50.0, 0.0, 50.0}) {
        std::vector<Point2> left, right;
        for (int i = 0; i < a; ++i) left.push_back({static_cast<double>(i), 0});
        std::uniform_real_distribution<double> u(-20, 20), ux(0, 20);
        for (int i = 0; i < b + 1; ++i) right.push_back({a + 1 + ux(rng), dy + u(rng)});
        if (all_collinear(right)) continue;
        expect_merge_valid(left, right, true);
        expect_mirrored_merge_valid(left, right, 1000);  // the blob left, the segment right
      }
    }
}

TEST(Merge, HalfInsideTheOthersWedge) {
  // The left half lies inside the union's hull but for one vertex: its whole hull faces the
  // right half (the tangents meet at that vertex).
  std::mt19937_64 rng(3);
  const std::vector<Point2> tri = {{0, 0}, {1, 1}, {1, -1}};
  const std::vector<Point2> seg = {{0, 0}, {1, 0}, {2, 0}, {5, 0}};
  for (double spread : {100.0, 10.0, 2.0}) {
    std::vector<Point2> right = {{10, -spread}, {10, spread}, {10, 5}, {20, 0}, {15, 3}};
    expect_merge_valid(tri, right, true);
    expect_merge_valid(seg, right, true);
    std::vector<Point2> two = {{0, 0}, {3, 0}};
    expect_merge_valid(two, right, true);
    expect_mirrored_merge_valid(tri, right, 30);  // the right half inside the left one's wedge
  }
}

TEST(Merge, DifferentSizesAndShapes) {
  for (unsigned seed = 0; seed < 200; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const std::size_t nl = 2 + rng() % (seed % 2 ? 6 : 150);
    const std::size_t nr = 2 + rng() % (seed % 3 ? 150 : 6);
    const double lift = std::array<double, 5>{0, 1, -1, 1e3, -1e4}[seed % 5];
    std::vector<Point2> left, right;
    for (std::size_t i = 0; i < nl; ++i)  // a thin vertical sliver or a blob
      left.push_back(
          {seed % 4 == 0 ? 1e-3 * u(rng) : u(rng), seed % 4 == 0 ? 100 * u(rng) : u(rng)});
    for (std::size_t i = 0; i < nr; ++i)  // a wide blob, maybe far above or below
      right.push_back({2 + 50 * u(rng), lift + 50 * (u(rng) - 0.5)});
    if (all_collinear(left) && all_collinear(right) && all_collinear({left[0], left[1], right[0]}))
      continue;
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_merge_valid(left, right, nl + nr < 200);
  }
}

TEST(Merge, CocircularAcrossTheSplit) {
  std::mt19937_64 rng(4);
  // Pythagorean points on circles of radius 5 * 13 * 17 and 5 * 13, centre included or not.
  for (int r : {1105, 65}) {
    std::vector<Point2> pts;
    for (int x = -r; x <= r; ++x) {
      const int y2 = r * r - x * x;
      const int y = static_cast<int>(std::lround(std::sqrt(static_cast<double>(y2))));
      if (y * y == y2) {
        pts.push_back({500000.0 + x, 4000000.0 + y});
        if (y) pts.push_back({500000.0 + x, 4000000.0 - y});
      }
    }
    for (int with_centre = 0; with_centre < 2; ++with_centre) {
      if (with_centre) pts.push_back({500000.0, 4000000.0});
      for (std::size_t m = 2; m + 2 <= pts.size(); ++m) {
        SCOPED_TRACE("r " + std::to_string(r) + " split " + std::to_string(m));
        expect_split_valid(pts, m, rng, true);
      }
    }
  }
}

TEST(Merge, OneUlpPerturbedLattices) {
  for (unsigned seed = 0; seed < 60; ++seed) {
    std::mt19937_64 rng(seed);
    const std::vector<Point2> pts = test::one_ulp_lattice(9, rng);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_split_valid(pts, 2 + rng() % 77, rng, true);
  }
}

// ---- triangulate() on the parallel path: what only it does (every property test of
// triangulate() runs on both paths, in delaunay_test.cpp) ----

DelaunayResult run(std::vector<Point3> points, std::size_t parallel_min_points) {
  DelaunayOptions options;
  options.parallel_min_points = parallel_min_points;
  return triangulate(std::move(points), options);
}

TEST(ParallelDelaunay, TheDefaultThresholdSplitsLargeInputs) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 10000);
  std::vector<Point3> pts;
  for (int i = 0; i < 60000; ++i) pts.push_back({500000 + u(rng), 4000000 + u(rng), u(rng)});
  ASSERT_GE(pts.size(), DelaunayOptions{}.parallel_min_points);
  EXPECT_TRUE(takes_parallel_path(pts));
  const DelaunayResult r = triangulate(std::move(pts));
  EXPECT_EQ(r.tin.validate(), "");
}

TEST(ParallelDelaunay, KeepDuplicatesMatchesTheSequentialPath) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<Point3> pts;  // many groups of every size, on both sides
    for (int i = 0; i < 3000; ++i)
      pts.push_back({static_cast<double>(rng() % 40), static_cast<double>(rng() % 40),
                     static_cast<double>(rng() % 1000)});
    SCOPED_TRACE("seed " + std::to_string(seed));
    ASSERT_TRUE(takes_parallel_path(pts));
    DelaunayOptions options;
    options.keep_duplicates = true;
    options.parallel_min_points = 0;
    const DelaunayResult par = triangulate(std::vector<Point3>(pts), options);
    // The slots were made for every point; those the duplicates leave unused must be gone.
    EXPECT_EQ(par.tin.triangle_slots(), 2 * par.tin.vertex_count() - 2);
    EXPECT_EQ(par.tin.validate(), "");
    options.parallel_min_points = kNever;
    const DelaunayResult seq = triangulate(std::vector<Point3>(pts), options);
    ASSERT_EQ(par.duplicates.size(), seq.duplicates.size());
    std::uint64_t merged = 0;
    using Row = std::tuple<double, double, std::uint32_t, double, double>;
    std::vector<Row> rows_par, rows_seq;
    for (const DelaunayResult::Duplicate& d : par.duplicates) {
      merged += d.points - 1;
      const Point2 p = par.tin.point(d.vertex);
      rows_par.emplace_back(p.x, p.y, d.points, d.z_min, d.z_max);
    }
    for (const DelaunayResult::Duplicate& d : seq.duplicates) {
      const Point2 p = seq.tin.point(d.vertex);
      rows_seq.emplace_back(p.x, p.y, d.points, d.z_min, d.z_max);
    }
    EXPECT_EQ(merged, par.duplicates_merged);
    std::sort(rows_par.begin(), rows_par.end());
    std::sort(rows_seq.begin(), rows_seq.end());
    EXPECT_EQ(rows_par, rows_seq);
    for (std::size_t k = 1; k < par.duplicates.size(); ++k)
      EXPECT_LT(par.duplicates[k - 1].vertex, par.duplicates[k].vertex);
  }
}

TEST(ParallelDelaunay, FallsBackWhenTheSplitIsUseless) {
  // All collinear: the sequential path's error.
  std::vector<Point3> line;
  for (int i = 0; i < 100; ++i) line.push_back({static_cast<double>(i), 2.0 * i, 0});
  EXPECT_FALSE(takes_parallel_path(line));
  EXPECT_THROW(run(line, 0), GeometryError);
  // One side with a single distinct point: sequential, still correct.
  std::vector<Point3> pts;
  for (int i = 0; i < 100; ++i) pts.push_back({0, 0, static_cast<double>(i)});
  for (int i = 0; i < 100; ++i) pts.push_back({1.0 + i % 10, static_cast<double>(i / 10), 0});
  const DelaunayResult r = run(pts, 0);
  EXPECT_EQ(r.tin.validate(), "");
  EXPECT_EQ(r.tin.vertex_count(), 101u);
  EXPECT_THROW(run({{0, 0, 0}, {1, 1, 1}, {0, 0, 5}, {1, 1, 2}}, 0), GeometryError);
  EXPECT_THROW(run({}, 0), GeometryError);
}

}  // namespace
}  // namespace tincdt::delaunay
