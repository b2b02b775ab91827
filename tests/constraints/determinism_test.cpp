// The constraint stage gives the unique constrained Delaunay triangulation (ties broken by the
// symbolic perturbation): on lattices with contour-like and lattice-aligned constraints, and on
// the real pair_topography cloud with its contours, every way of building the Delaunay
// triangulation first (sequential, two halves on one or two threads, shuffled input) and any
// order of non-crossing segments give the same triangles and constrained edges, checked against
// an independent brute-force reference on the small inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "support/determinism.hpp"
#include "support/perturbed_delaunay.hpp"
#include "support/shared_data.hpp"

namespace tincdt::constraints {
namespace {

namespace fs = std::filesystem;
using mesh::Triangulation;
using test::Int128;
using test::IntegerFrame;
using test::IntPoint;

struct Input {
  std::vector<Point3> points;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;  // point indices
};

using Way = test::DelaunayWay;
using test::kHalvesOneThread;
using test::kHalvesTwoThreads;
using test::kSequential;
constexpr Way kDefaultOneThread{"default, 1 thread",
                                delaunay::DelaunayOptions{}.parallel_min_points, 1};
constexpr Way kDefaultTwoThreads{"default, 2 threads",
                                 delaunay::DelaunayOptions{}.parallel_min_points, 2};

struct Built {
  Triangulation tin;
  std::vector<Segment> segments;
  ConstraintResult result;
};

// The CDT of `in`, its points permuted by `order` (a permutation of the point indices, or empty).
Built build(const Input& in, const Way& way, const std::vector<std::uint32_t>& order = {},
            bool reverse_segments = false, Restore restore = Restore::delaunay) {
  std::vector<std::uint32_t> position(in.points.size());  // input index -> index passed on
  std::vector<Point3> points;
  points.reserve(in.points.size());
  for (std::uint32_t k = 0; k < in.points.size(); ++k) {
    const std::uint32_t i = order.empty() ? k : order[k];
    position[i] = k;
    points.push_back(in.points[i]);
  }
  delaunay::DelaunayOptions options;
  options.keep_point_map = true;
  options.parallel_min_points = way.parallel_min_points;
  options.threads = way.threads;
  delaunay::DelaunayResult dt = delaunay::triangulate(std::move(points), options);
  Built b{std::move(dt.tin), {}, {}};
  for (std::uint32_t s = 0; s < in.segments.size(); ++s) {
    const auto [i, j] = in.segments[reverse_segments ? in.segments.size() - 1 - s : s];
    b.segments.push_back({dt.vertex_of_point[position[i]], dt.vertex_of_point[position[j]], s});
  }
  b.result = insert_constraints(b.tin, b.segments, {.restore = restore});
  return b;
}

::testing::AssertionResult same_bits(const Triangulation& a, const Triangulation& b) {
  if (auto same = test::same_vertices_and_corners(a, b); !same) return same;
  for (EdgeId e = 0; e < a.corners().size(); ++e)
    if (a.is_constrained(e) != b.is_constrained(e))
      return ::testing::AssertionFailure() << "constraint flags differ at " << e;
  return ::testing::AssertionSuccess();
}

// The constrained edges as a canonical set of coordinate pairs.
std::vector<std::array<double, 4>> constrained_set(const Triangulation& tin) {
  std::vector<std::array<double, 4>> set;
  tin.for_each_constrained_edge([&](EdgeId e) {
    Point2 a = tin.point(tin.origin(e)), b = tin.point(tin.dest(e));
    if (std::tie(b.x, b.y) < std::tie(a.x, a.y)) std::swap(a, b);
    set.push_back({a.x, a.y, b.x, b.y});
  });
  std::sort(set.begin(), set.end());
  return set;
}

::testing::AssertionResult same_cdt(const Triangulation& a, const Triangulation& b) {
  if (test::triangle_set(a) != test::triangle_set(b))
    return ::testing::AssertionFailure() << "the triangle sets differ";
  if (constrained_set(a) != constrained_set(b))
    return ::testing::AssertionFailure() << "the constrained edges differ";
  return ::testing::AssertionSuccess();
}

// ---- an independent reference: the constrained perturbed Delaunay property by brute force ----

bool crosses(IntPoint a, IntPoint b, IntPoint c, IntPoint d) {  // open segments cross properly
  return test::orientation(a, b, c) * test::orientation(a, b, d) < 0 &&
         test::orientation(c, d, a) * test::orientation(c, d, b) < 0;
}

bool on_closed_segment(IntPoint p, IntPoint c, IntPoint d) {
  return test::orientation(c, d, p) == 0 && std::min(c.x, d.x) <= p.x &&
         p.x <= std::max(c.x, d.x) && std::min(c.y, d.y) <= p.y && p.y <= std::max(c.y, d.y);
}

// Whether constraint cd hides q from a: they cross, or the sight line runs through an end of cd
// other than a and q.
bool hides(IntPoint a, IntPoint q, IntPoint c, IntPoint d) {
  if (crosses(a, q, c, d)) return true;
  return (!(c == a) && !(c == q) && on_closed_segment(c, a, q)) ||
         (!(d == a) && !(d == q) && on_closed_segment(d, a, q));
}

// Empty if no vertex inside a triangle's perturbed circle is visible from all three of its
// corners (Definition 2 of the constraint paper, with the perturbed circle), where the
// constraints are the input segments (integer points; collinear vertices on them included as
// blockers since the sight line through a vertex is hidden).
std::string perturbed_cdt_violation(const Triangulation& tin, const IntegerFrame& frame,
                                    const std::vector<std::pair<IntPoint, IntPoint>>& segments) {
  std::vector<IntPoint> v;
  for (const Point2& p : tin.points()) v.push_back(frame.to_int(p));
  const auto visible = [&](IntPoint from, IntPoint q) {
    for (const auto& [c, d] : segments)
      if (hides(from, q, c, d)) return false;
    return true;
  };
  std::string problem;
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    if (!problem.empty()) return;
    for (VertexId q = 0; q < v.size() && problem.empty(); ++q) {
      if (q == c[0] || q == c[1] || q == c[2]) continue;
      if (test::perturbed_in_circle(v[c[0]], v[c[1]], v[c[2]], v[q]) <= 0) continue;
      if (visible(v[c[0]], v[q]) && visible(v[c[1]], v[q]) && visible(v[c[2]], v[q]))
        problem = "triangle " + std::to_string(t) + " sees vertex " + std::to_string(q) +
                  " inside its perturbed circle";
    }
  });
  return problem;
}

// ---- the checks
// ------------------------------------------------------------------------------------

// Builds the CDT every way, shuffled too, and with the segments in reverse order when they do
// not cross; checks each and that all are one. Returns the sequential one.
Built expect_one_cdt(const Input& in, bool segments_cross, int shuffles = 2,
                     std::vector<Way> ways = {kSequential, kHalvesOneThread, kHalvesTwoThreads}) {
  Built reference = build(in, ways.front());
  EXPECT_EQ(reference.tin.validate(), "");
  EXPECT_EQ(check_segments(reference.tin, reference.segments, reference.result.pieces), "");
  std::mt19937_64 rng(3);
  for (const Way& way : ways) {
    SCOPED_TRACE(way.name);
    const Built first = build(in, way);
    EXPECT_EQ(first.tin.validate(), "");
    EXPECT_TRUE(same_cdt(first.tin, reference.tin));
    for (int s = 0; s < shuffles; ++s) {
      std::vector<std::uint32_t> order(in.points.size());
      for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
      std::shuffle(order.begin(), order.end(), rng);
      EXPECT_TRUE(same_bits(build(in, way, order).tin, first.tin)) << "shuffle " << s;
    }
    if (!segments_cross) {
      // The CDT of a set of points and non-crossing segments is unique: any insertion order.
      const Built reversed = build(in, way, {}, true);
      EXPECT_EQ(reversed.tin.validate(), "");
      EXPECT_TRUE(same_cdt(reversed.tin, reference.tin)) << "segments reversed";
    }
  }
  return reference;
}

// The input for integer points and segments between them.
Input to_input(const std::vector<IntPoint>& ints,
               const std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments,
               const IntegerFrame& frame) {
  Input in;
  for (const IntPoint& q : ints) {
    const Point2 p = frame.to_double(q);
    in.points.push_back({p.x, p.y, static_cast<double>((q.x * 5 + q.y * 3) % 13)});
  }
  in.segments = segments;
  return in;
}

void expect_unique_cdt(const std::vector<IntPoint>& ints,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments,
                       const IntegerFrame& frame) {
  const Built b = expect_one_cdt(to_input(ints, segments, frame), false);
  std::vector<std::pair<IntPoint, IntPoint>> int_segments;
  for (const auto& [i, j] : segments) int_segments.push_back({ints[i], ints[j]});
  EXPECT_EQ(perturbed_cdt_violation(b.tin, frame, int_segments), "");
}

const std::array<IntegerFrame, 3> kFrames{IntegerFrame{0, 0, 1}, IntegerFrame{500000, 4000000, 0.5},
                                          IntegerFrame{273357.25, 5274357.125, 0.0078125}};

// Lattice points (spacing `spacing`) of a w x h lattice, then the points of `extra`; returns the
// index of each extra point (an existing lattice point if it coincides).
struct PointSet {
  std::vector<IntPoint> points;
  std::uint32_t add(IntPoint p) {
    for (std::uint32_t i = 0; i < points.size(); ++i)
      if (points[i] == p) return i;
    points.push_back(p);
    return static_cast<std::uint32_t>(points.size() - 1);
  }
};

PointSet lattice(int w, int h, int spacing) {
  PointSet s;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) s.points.push_back({i * spacing, j * spacing});
  return s;
}

// A closed ring through the integer points of the circle of radius r (5, 25, 65...) around c,
// in angular order.
std::vector<IntPoint> ring(IntPoint c, std::int64_t r) {
  std::vector<IntPoint> p;
  for (std::int64_t x = -r; x <= r; ++x)
    for (std::int64_t y = -r; y <= r; ++y)
      if (x * x + y * y == r * r) p.push_back({x, y});
  std::sort(p.begin(), p.end(), [](IntPoint a, IntPoint b) {
    const auto half = [](IntPoint q) { return q.y < 0 || (q.y == 0 && q.x < 0); };
    if (half(a) != half(b)) return half(a) < half(b);
    return Int128{a.x} * b.y - Int128{a.y} * b.x > 0;
  });
  for (IntPoint& q : p) q = {c.x + q.x, c.y + q.y};
  return p;
}

TEST(DeterministicCdt, LatticeWithConcentricContourRings) {
  // Contours around a hill: concentric rings through integer points of circles, on a lattice
  // whose cells are all cocircular; ring vertices fall both on and off the lattice.
  for (const IntegerFrame& frame : kFrames) {
    for (const int spacing : {5, 10}) {
      PointSet s = lattice(150 / spacing + 1, 150 / spacing + 1, spacing);
      std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
      for (const std::int64_t r : {25, 65}) {
        const std::vector<IntPoint> rp = ring({75, 75}, r);
        for (std::size_t k = 0; k < rp.size(); ++k)
          segments.push_back({s.add(rp[k]), s.add(rp[(k + 1) % rp.size()])});
      }
      SCOPED_TRACE("spacing " + std::to_string(spacing));
      expect_unique_cdt(s.points, segments, frame);
    }
  }
}

TEST(DeterministicCdt, LatticeWithLatticeAlignedBreaklines) {
  // Breaklines through lattice points: along rows and columns, diagonals, knight's-move slopes,
  // an L-shaped ridge; they share vertices but never cross.
  for (const IntegerFrame& frame : kFrames) {
    PointSet s = lattice(20, 16, 1);
    const auto at = [&](int x, int y) { return s.add({x, y}); };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> segments = {
        {at(0, 3), at(19, 3)},   {at(2, 0), at(2, 15)}, {at(4, 5), at(12, 13)},
        {at(12, 13), at(16, 5)}, {at(5, 4), at(11, 7)}, {at(11, 7), at(17, 4)},
        {at(3, 14), at(9, 14)},  {at(9, 14), at(9, 9)}, {at(18, 15), at(17, 7)}};
    expect_unique_cdt(s.points, segments, frame);
  }
}

TEST(DeterministicCdt, RandomSubsetsOfLatticesWithPolylines) {
  for (unsigned seed = 0; seed < 25; ++seed) {
    std::mt19937_64 rng(seed);
    const int w = 8 + static_cast<int>(rng() % 20), h = 8 + static_cast<int>(rng() % 20);
    PointSet s;
    for (const IntPoint& q : lattice(w, h, 4).points)
      if (rng() % 10 < 6) s.points.push_back(q);
    // A few monotone polylines (contour-like, never crossing: each in its own horizontal band)
    // with vertices anywhere on the integer grid.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
    const int bands = 3;
    for (int band = 0; band < bands; ++band) {
      const int y0 = band * 4 * h / bands + 1, y1 = (band + 1) * 4 * h / bands - 1;
      std::uint32_t last = kNoId;
      for (int x = 0; x <= 4 * (w - 1); x += 1 + static_cast<int>(rng() % 7)) {
        const std::uint32_t v = s.add({x, y0 + static_cast<int>(rng() % (y1 - y0 + 1))});
        if (last != kNoId && last != v) segments.push_back({last, v});
        last = v;
      }
    }
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_unique_cdt(s.points, segments, kFrames[seed % kFrames.size()]);
  }
}

TEST(DeterministicCdt, CrossingConstraintsSplitTheSameWay) {
  // Crossing segments make Steiner vertices; with the segments in one order, every way of
  // building the Delaunay triangulation first gives the same ones and the same CDT.
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    const PointSet s = lattice(25, 25, 1);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
    for (int k = 0; k < 12; ++k) {
      const auto a = static_cast<std::uint32_t>(rng() % s.points.size());
      const auto b = static_cast<std::uint32_t>(rng() % s.points.size());
      if (a != b) segments.push_back({a, b});
    }
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Built b = expect_one_cdt(to_input(s.points, segments, kFrames[seed % 3]), true);
    EXPECT_GT(b.result.crossings.size(), 0u);
  }
}

TEST(DeterministicCdt, AspectAndNoRestorationDependOnTheSegmentsOnly) {
  // Not unique triangulations (they depend on the order of the segments), but with the segments
  // in one order, the same triangles whatever the Delaunay path, threads or point order.
  PointSet s = lattice(31, 31, 5);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
  for (const std::int64_t r : {25, 65}) {
    const std::vector<IntPoint> rp = ring({75, 75}, r);
    for (std::size_t k = 0; k < rp.size(); ++k)
      segments.push_back({s.add(rp[k]), s.add(rp[(k + 1) % rp.size()])});
  }
  const Input in = to_input(s.points, segments, kFrames[1]);
  std::vector<std::uint32_t> order(in.points.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(4);
  std::shuffle(order.begin(), order.end(), rng);
  for (const Restore restore : {Restore::aspect, Restore::none}) {
    const Built reference = build(in, kSequential, {}, false, restore);
    EXPECT_EQ(reference.tin.validate({.delaunay = false}), "");
    for (const Way& way : {kSequential, kHalvesOneThread, kHalvesTwoThreads}) {
      SCOPED_TRACE(way.name);
      const Built first = build(in, way, {}, false, restore);
      EXPECT_TRUE(same_cdt(first.tin, reference.tin));
      EXPECT_TRUE(same_bits(build(in, way, order, false, restore).tin, first.tin));
    }
  }
}

// ---- real data: the pair_topography cloud and its contours -----------------------------------

TEST(DeterministicCdt, PairTopographyWithItsContours) {
  const fs::path data = fs::path(::tincdt::test::shared_data());
  const fs::path cloud = data / "las" / "Topography.las";
  const fs::path contours = data / "pair_topography" / "Topography_contours_1m_3d.shp";
  if (!fs::exists(cloud) || !fs::exists(contours)) GTEST_SKIP() << "no shared data at " << data;
  for (const bool ground_only : {true, false}) {
    Input in;
    io::PointFilter filter;
    if (ground_only) filter.keep_classes = {2};
    io::read_points(cloud.string(), filter, in.points);
    io::LineData lines;
    io::read_lines(contours.string(), {}, lines);
    const auto first_line_vertex = static_cast<std::uint32_t>(in.points.size());
    in.points.insert(in.points.end(), lines.vertices.begin(), lines.vertices.end());
    for (const io::LineData::Segment& s : lines.segments)
      in.segments.push_back({first_line_vertex + s.a, first_line_vertex + s.b});
    SCOPED_TRACE(ground_only ? "ground points" : "all points");
    ASSERT_GT(in.segments.size(), 9000u);
    // Small enough: every way by the threshold; all points: the default threshold too (73,403
    // points take the two-halves path by themselves).
    std::vector<Way> ways = {kSequential, kHalvesOneThread, kHalvesTwoThreads};
    if (!ground_only) ways = {kSequential, kDefaultOneThread, kDefaultTwoThreads};
    const Built b = expect_one_cdt(in, false, 1, ways);
    EXPECT_EQ(b.result.crossings.size(), 0u);
  }
}

}  // namespace
}  // namespace tincdt::constraints
