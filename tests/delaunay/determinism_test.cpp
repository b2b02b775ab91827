// The Delaunay stage's result is a rule of the point set alone. On inputs full of cocircular ties
// (lattices, jittered and thinned lattices, points on circles, cm-quantized LiDAR-like clouds,
// the shared LAS files) every way of running it gives the same triangles: the sequential path and
// the two-halves path, one thread or two, any order of the input. Within one path the arrays are
// the same bits, and so are the files written from them. The triangles are checked against an
// independent brute-force reference of the unique perturbed Delaunay triangulation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/points/point_reader.hpp"
#include "support/determinism.hpp"
#include "support/files.hpp"
#include "support/perturbed_delaunay.hpp"
#include "support/shared_data.hpp"

namespace tincdt::delaunay {
namespace {

namespace fs = std::filesystem;
using mesh::Triangulation;
using test::IntegerFrame;
using test::IntPoint;

// ---- ways of running the Delaunay stage ---------------------------------------------------------

using Way = test::DelaunayWay;
using test::kHalvesOneThread;
using test::kHalvesTwoThreads;
using test::kSequential;

DelaunayResult triangulate_as(std::vector<Point3> points, const Way& way,
                              DuplicatePolicy policy = DuplicatePolicy::mean) {
  DelaunayOptions options;
  options.on_duplicate = policy;
  options.parallel_min_points = way.parallel_min_points;
  options.threads = way.threads;
  return triangulate(std::move(points), options);
}

// Everything a writer reads, bit for bit: vertex coordinates and heights, triangle corners (so
// also their order and rotation), twins.
::testing::AssertionResult same_bits(const Triangulation& a, const Triangulation& b) {
  if (auto same = test::same_vertices_and_corners(a, b); !same) return same;
  for (EdgeId e = 0; e < a.corners().size(); ++e)
    if (a.twin(e) != b.twin(e)) return ::testing::AssertionFailure() << "twins differ at " << e;
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult same_triangles(const Triangulation& a, const Triangulation& b) {
  const auto sa = test::triangle_set(a), sb = test::triangle_set(b);
  if (sa.size() != sb.size())
    return ::testing::AssertionFailure() << sa.size() << " vs " << sb.size() << " triangles";
  for (std::size_t i = 0; i < sa.size(); ++i) {
    if (sa[i] != sb[i]) {
      const Point3 p = sa[i][0];
      return ::testing::AssertionFailure()
             << "triangle sets differ, first at a triangle with corner (" << p.x << ", " << p.y
             << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

// Runs every way, checks validate() on each, the same triangles everywhere, the same bits for
// every shuffle within one way, and returns the sequential result.
DelaunayResult expect_one_result(const std::vector<Point3>& points, int shuffles = 3,
                                 DuplicatePolicy policy = DuplicatePolicy::mean) {
  DelaunayResult reference = triangulate_as(points, kSequential, policy);
  EXPECT_EQ(reference.tin.validate(), "");
  for (const Way& way : {kSequential, kHalvesOneThread, kHalvesTwoThreads}) {
    SCOPED_TRACE(way.name);
    const DelaunayResult first = triangulate_as(points, way, policy);
    EXPECT_EQ(first.tin.validate(), "");
    EXPECT_TRUE(same_triangles(first.tin, reference.tin));
    std::mt19937_64 rng(77);
    for (int s = 0; s < shuffles; ++s) {
      std::vector<Point3> shuffled = points;
      std::shuffle(shuffled.begin(), shuffled.end(), rng);
      const DelaunayResult again = triangulate_as(std::move(shuffled), way, policy);
      EXPECT_TRUE(same_bits(again.tin, first.tin)) << "shuffle " << s;
    }
  }
  // One thread or two: the same bits.
  EXPECT_TRUE(same_bits(triangulate_as(points, kHalvesOneThread, policy).tin,
                        triangulate_as(points, kHalvesTwoThreads, policy).tin));
  return reference;
}

// The library's points for integer points of a frame, with a z that varies.
std::vector<Point3> to_points(const std::vector<IntPoint>& ints, const IntegerFrame& frame) {
  std::vector<Point3> points;
  points.reserve(ints.size());
  for (const IntPoint& q : ints) {
    const Point2 p = frame.to_double(q);
    points.push_back({p.x, p.y, static_cast<double>((q.x * 7 + q.y * 3) % 11)});
  }
  return points;
}

// Every check, the brute-force reference included when small enough.
void expect_unique_delaunay(const std::vector<IntPoint>& ints, const IntegerFrame& frame) {
  const DelaunayResult r = expect_one_result(to_points(ints, frame));
  if (ints.size() <= 1500) {
    EXPECT_EQ(test::perturbed_delaunay_violation(r.tin, frame), "");
  }
}

const std::array<IntegerFrame, 3> kFrames{IntegerFrame{0, 0, 1}, IntegerFrame{500000, 4000000, 0.5},
                                          IntegerFrame{273357.25, 5274357.125, 0.0078125}};

// ---- inputs full of ties ------------------------------------------------------------------------

std::vector<IntPoint> lattice(int w, int h, int spacing = 1) {
  std::vector<IntPoint> p;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) p.push_back({i * spacing, j * spacing});
  return p;
}

TEST(DeterministicDelaunay, Lattices) {
  for (const IntegerFrame& frame : kFrames)
    for (const auto& [w, h] : {std::pair{2, 2}, {3, 2}, {5, 5}, {13, 7}, {2, 40}, {31, 29}}) {
      SCOPED_TRACE(std::to_string(w) + " x " + std::to_string(h));
      expect_unique_delaunay(lattice(w, h), frame);
    }
}

TEST(DeterministicDelaunay, LatticesWithCmJitter) {
  // A 1 m lattice in cm units: some points moved by a few cm, most left on the lattice, so ties
  // remain everywhere between jittered ones.
  for (unsigned seed = 0; seed < 30; ++seed) {
    std::mt19937_64 rng(seed);
    const int w = 4 + static_cast<int>(rng() % 25), h = 4 + static_cast<int>(rng() % 25);
    std::vector<IntPoint> p = lattice(w, h, 100);
    std::uniform_int_distribution<int> jitter(-3, 3);
    for (IntPoint& q : p)
      if (rng() % 3 == 0) q = {q.x + jitter(rng), q.y + jitter(rng)};
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_unique_delaunay(p, kFrames[seed % kFrames.size()]);
  }
}

TEST(DeterministicDelaunay, RandomSubsetsOfLattices) {
  for (unsigned seed = 0; seed < 40; ++seed) {
    std::mt19937_64 rng(seed);
    const int w = 3 + static_cast<int>(rng() % 30), h = 3 + static_cast<int>(rng() % 30);
    const unsigned keep = 2 + static_cast<unsigned>(rng() % 8);  // out of 10
    std::vector<IntPoint> p;
    for (const IntPoint& q : lattice(w, h))
      if (rng() % 10 < keep) p.push_back(q);
    if (p.size() < 3) continue;
    // Skip all-collinear subsets: no triangulation exists.
    bool collinear = true;
    for (std::size_t i = 2; i < p.size() && collinear; ++i)
      collinear = test::orientation(p[0], p[1], p[i]) == 0;
    if (collinear) continue;
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_unique_delaunay(p, kFrames[seed % kFrames.size()]);
  }
}

// Integer points of the circle x^2 + y^2 = r^2 around (cx, cy).
std::vector<IntPoint> circle(std::int64_t cx, std::int64_t cy, std::int64_t r) {
  std::vector<IntPoint> p;
  for (std::int64_t x = -r; x <= r; ++x)
    for (std::int64_t y = -r; y <= r; ++y)
      if (x * x + y * y == r * r) p.push_back({cx + x, cy + y});
  return p;
}

TEST(DeterministicDelaunay, PointsOnCircles) {
  // Radii with many integer points (5^k, 65, 325), concentric and overlapping: every circle is
  // one big cocircular set, and their points also fall on many other common circles.
  const std::vector<std::vector<std::array<std::int64_t, 3>>> sets = {
      {{0, 0, 25}},
      {{0, 0, 65}},
      {{0, 0, 5}, {0, 0, 25}, {0, 0, 65}, {0, 0, 125}},
      {{0, 0, 65}, {30, 0, 65}, {0, 40, 25}, {-50, -50, 325}},
      {{0, 0, 325}, {0, 0, 0}},
  };
  for (std::size_t k = 0; k < sets.size(); ++k) {
    std::vector<IntPoint> p;
    for (const auto& [cx, cy, r] : sets[k]) {
      const std::vector<IntPoint> c = r == 0 ? std::vector<IntPoint>{{cx, cy}} : circle(cx, cy, r);
      p.insert(p.end(), c.begin(), c.end());
    }
    std::sort(p.begin(), p.end(), test::lex_less);
    p.erase(std::unique(p.begin(), p.end()), p.end());
    SCOPED_TRACE("set " + std::to_string(k));
    for (const IntegerFrame& frame : kFrames) expect_unique_delaunay(p, frame);
  }
}

// A LiDAR-like cloud in cm: scan lines about 50 cm apart, points about 30 cm apart along them,
// both with cm noise, so rectangles (cocircular) and repeated x or y abound; some points repeated
// with another z (multiple returns).
std::vector<IntPoint> lidar_like(std::mt19937_64& rng, int lines, int per_line) {
  std::uniform_int_distribution<int> noise(-2, 2);
  std::vector<IntPoint> p;
  for (int l = 0; l < lines; ++l)
    for (int i = 0; i < per_line; ++i) p.push_back({i * 30 + noise(rng), l * 50 + noise(rng)});
  return p;
}

TEST(DeterministicDelaunay, LidarLikeCmQuantized) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<IntPoint> p =
        lidar_like(rng, 5 + static_cast<int>(rng() % 20), 5 + static_cast<int>(rng() % 40));
    std::sort(p.begin(), p.end(), test::lex_less);
    p.erase(std::unique(p.begin(), p.end()), p.end());
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_unique_delaunay(p, kFrames[seed % kFrames.size()]);
  }
}

TEST(DeterministicDelaunay, DecimalCmCoordinatesAndDuplicates) {
  // Real LAS coordinates: integers times 0.01 plus an offset, not exact in binary; the same
  // point returned several times with different z.
  for (unsigned seed = 0; seed < 10; ++seed) {
    std::mt19937_64 rng(seed + 100);
    std::vector<Point3> points;
    std::uniform_real_distribution<double> z(400, 420);
    for (const IntPoint& q : lidar_like(rng, 40, 60)) {
      const Point3 p{636001.76 + static_cast<double>(q.x) * 0.01,
                     848935.2 + static_cast<double>(q.y) * 0.01, z(rng)};
      points.push_back(p);
      if (rng() % 5 == 0) points.push_back({p.x, p.y, z(rng)});
      if (rng() % 7 == 0) points.push_back({p.x, p.y, z(rng)});
    }
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_one_result(points);
  }
}

// ---- the default threshold: big enough for the two-halves path by itself -----------------------

TEST(DeterministicDelaunay, DefaultOptionsOnALargeLattice) {
  // 300 x 300 points: above DelaunayOptions::parallel_min_points, so the default options take
  // the two-halves path; a few holes and cm jitter make it less regular.
  std::mt19937_64 rng(5);
  std::vector<Point3> points;
  for (int j = 0; j < 300; ++j)
    for (int i = 0; i < 300; ++i) {
      if (rng() % 50 == 0) continue;
      const double jx = rng() % 20 == 0 ? 0.01 * static_cast<double>(rng() % 5) : 0.0;
      points.push_back({500000.0 + i + jx, 4000000.0 + j, static_cast<double>(rng() % 100)});
    }
  ASSERT_GT(points.size(), DelaunayOptions{}.parallel_min_points);
  DelaunayOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const DelaunayResult a = triangulate(std::vector<Point3>(points), one);
  const DelaunayResult b = triangulate(std::vector<Point3>(points), two);
  std::shuffle(points.begin(), points.end(), rng);
  const DelaunayResult c = triangulate(std::vector<Point3>(points), two);
  const DelaunayResult seq = triangulate_as(points, kSequential);
  ASSERT_EQ(a.tin.validate(), "");
  EXPECT_TRUE(same_bits(a.tin, b.tin));
  EXPECT_TRUE(same_bits(a.tin, c.tin));
  EXPECT_TRUE(same_triangles(a.tin, seq.tin));

  // And so the files: every writer output is the same bytes.
  const fs::path dir = test::fresh_dir(fs::path(TINCDT_TEST_TMP) / "determinism");
  const std::array<const DelaunayResult*, 3> results{&a, &b, &c};
  for (const std::string name : {"t.ply", "t.obj"}) {
    for (std::size_t k = 0; k < results.size(); ++k)
      io::write_tin((dir / (std::to_string(k) + name)).string(), results[k]->tin, {});
    const std::string bytes = test::slurp(dir / ("0" + name));
    EXPECT_GT(bytes.size(), 1000000u);
    EXPECT_EQ(test::slurp(dir / ("1" + name)), bytes) << name;
    EXPECT_EQ(test::slurp(dir / ("2" + name)), bytes) << name;
  }
}

// ---- the shared LAS files -----------------------------------------------------------------------

TEST(DeterministicDelaunay, SharedLasFiles) {
  const fs::path las = fs::path(::tincdt::test::shared_data()) / "las";
  if (!fs::is_directory(las)) GTEST_SKIP() << "no shared data at " << las;
  int files = 0;
  for (const auto& entry : fs::directory_iterator(las)) {
    if (entry.path().extension() != ".las") continue;
    std::vector<Point3> points;
    io::read_points(entry.path().string(), {}, points);
    if (points.size() < 100) continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++files;
    expect_one_result(points, 1);
    // The default options (two halves above 50000 points): one thread or two, any order.
    DelaunayOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const DelaunayResult a = triangulate(std::vector<Point3>(points), one);
    std::mt19937_64 rng(files);
    std::shuffle(points.begin(), points.end(), rng);
    const DelaunayResult b = triangulate(std::move(points), two);
    EXPECT_TRUE(same_bits(a.tin, b.tin));
  }
  EXPECT_GE(files, 10);
}

// ---- duplicates and signed zeros
// ------------------------------------------------------------------

TEST(DeterministicDelaunay, MeanOfDuplicatesIsTheSameBitsInAnyOrder) {
  // z values whose running mean depends on the order of summation.
  std::mt19937_64 rng(9);
  std::vector<Point3> points;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) points.push_back({i * 0.25, j * 0.25, 0.1 * i});
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 400; ++k) {
    const double x = static_cast<double>(rng() % 30) * 0.25,
                 y = static_cast<double>(rng() % 30) * 0.25;
    const double z = std::ldexp(u(rng), static_cast<int>(rng() % 60));
    points.push_back({x, y, z});
  }
  for (const DuplicatePolicy policy :
       {DuplicatePolicy::mean, DuplicatePolicy::min, DuplicatePolicy::max}) {
    expect_one_result(points, 4, policy);
  }
}

TEST(DeterministicDelaunay, FirstDuplicateIsFirstInInputOrder) {
  std::mt19937_64 rng(10);
  std::vector<Point3> points;
  for (int i = 0; i < 2000; ++i)
    points.push_back({static_cast<double>(rng() % 25), static_cast<double>(rng() % 25),
                      static_cast<double>(i)});  // z = input index
  for (const Way& way : {kSequential, kHalvesTwoThreads}) {
    for (int s = 0; s < 3; ++s) {
      std::shuffle(points.begin(), points.end(), rng);
      DelaunayOptions options;
      options.on_duplicate = DuplicatePolicy::first;
      options.keep_point_map = true;
      options.parallel_min_points = way.parallel_min_points;
      const DelaunayResult r = triangulate(std::vector<Point3>(points), options);
      ASSERT_EQ(r.tin.validate(), "");
      std::vector<double> first(r.tin.vertex_count(), -1);
      for (std::size_t i = 0; i < points.size(); ++i)
        if (first[r.vertex_of_point[i]] < 0) first[r.vertex_of_point[i]] = points[i].z;
      for (VertexId v = 0; v < r.tin.vertex_count(); ++v) ASSERT_EQ(r.tin.z(v), first[v]);
    }
  }
}

TEST(DeterministicDelaunay, NegativeZeroIsZero) {
  // -0 and 0 are one point, whatever the order or the path.
  const std::vector<Point3> points = {{5, 5, 1}, {-0.0, -0.0, 2}, {0, 0, 3}, {5, 0, 0}};
  for (const Way& way : {kSequential, kHalvesOneThread, kHalvesTwoThreads}) {
    std::vector<Point3> p = points;
    std::sort(p.begin(), p.end(), [](const Point3& a, const Point3& b) { return a.z < b.z; });
    do {
      const DelaunayResult r = triangulate_as(p, way);
      ASSERT_EQ(r.tin.vertex_count(), 3u);
      EXPECT_EQ(r.duplicates_merged, 1u);
      ASSERT_EQ(r.tin.validate(), "");
      for (VertexId v = 0; v < r.tin.vertex_count(); ++v) {
        EXPECT_FALSE(std::signbit(r.tin.point(v).x));
        EXPECT_FALSE(std::signbit(r.tin.point(v).y));
        if (r.tin.point(v).x == 0) {
          EXPECT_EQ(r.tin.z(v), 2.5);
        }
      }
    } while (std::next_permutation(p.begin(), p.end(),
                                   [](const Point3& a, const Point3& b) { return a.z < b.z; }));
  }
  // Also when -0.0 is the only zero, and in y only.
  const DelaunayResult r = triangulate_as({{-0.0, 1, 0}, {1, -0.0, 0}, {1, 1, 0}}, kSequential);
  for (const Point2& v : r.tin.points()) {
    EXPECT_FALSE(std::signbit(v.x));
    EXPECT_FALSE(std::signbit(v.y));
  }
}

}  // namespace
}  // namespace tincdt::delaunay
