// Long-edge trimming: concave outlines are not bridged, the TIN stays valid, and nothing
// with short edges (or inside the data) is removed.
#include "terrain/trim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.hpp"
#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

using test::build_tin;

double longest_edge(const mesh::Triangulation& tin, const std::array<VertexId, 3>& c) {
  double m = 0;
  for (int i = 0; i < 3; ++i) {
    const Point2 a = tin.point(c[i]), b = tin.point(c[(i + 1) % 3]);
    m = std::max(m, std::hypot(a.x - b.x, a.y - b.y));
  }
  return m;
}

// Jittered unit grid over the cells of a shape given by `in(x, y)`.
template <class In>
std::vector<Point3> jittered_grid(int nx, int ny, In in, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<Point3> pts;
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      if (in(i, j)) pts.push_back({i + jitter(rng), j + jitter(rng), 0.1 * i});
  return pts;
}

// A "C": bottom arm, spine and top arm of width 6 around a 24 x 18 gap open to the right.
bool in_c(int i, int j) {
  return j <= 6 || j >= 24 || i <= 6;
}

TEST(Trim, ConcaveCIsNotBridged) {
  auto b = build_tin(jittered_grid(30, 30, in_c));
  const std::size_t before = b.tin.triangle_count();
  const double max_edge = 2.0;
  const std::uint64_t removed = trim_long_edges(b.tin, max_edge);
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(b.tin.triangle_count(), before - removed);
  EXPECT_EQ(b.tin.validate(), "");

  // No kept triangle reaches into the gap or has an edge over the limit; every triangle whose
  // edges are all short is still there.
  std::uint64_t short_triangles = 0, long_kept = 0, in_gap = 0;
  const auto slots = static_cast<TriangleId>(b.tin.triangle_slots());
  for (TriangleId t = 0; t < slots; ++t) {
    if (b.tin.is_ghost(t)) continue;
    const auto c = b.tin.triangle(t);
    const bool is_short = longest_edge(b.tin, c) <= max_edge;
    if (is_short) {
      ++short_triangles;
      EXPECT_TRUE(b.tin.is_kept(t)) << "short triangle " << t << " removed";
    }
    if (b.tin.is_kept(t)) {
      if (!is_short) ++long_kept;
      const Point2 g = test::triangle_centroid(b.tin, c);
      if (g.x > 7.5 && g.y > 7.5 && g.y < 22.5) ++in_gap;
    }
  }
  EXPECT_EQ(long_kept, 0u);
  EXPECT_EQ(in_gap, 0u);
  EXPECT_EQ(b.tin.triangle_count(), short_triangles);
  // The kept area is the C's (up to the jitter along its outline), far below the hull's.
  const double c_area = 30.0 * 30.0 - 24.0 * 18.0;
  EXPECT_NEAR(test::kept_area(b.tin), c_area, 0.05 * c_area);
}

TEST(Trim, InteriorHoleIsNotOpened) {
  // A gap in the middle of the data: its long triangles are not on the boundary.
  auto b = build_tin(jittered_grid(
      30, 30, [](int i, int j) { return !(i >= 12 && i <= 18 && j >= 12 && j <= 18); }));
  std::uint64_t long_inside = 0;
  b.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    if (longest_edge(b.tin, c) > 2.0) {
      const Point2 g = test::triangle_centroid(b.tin, c);
      if (g.x > 11 && g.x < 19 && g.y > 11 && g.y < 19) ++long_inside;
    }
  });
  ASSERT_GT(long_inside, 0u);
  const std::size_t before = b.tin.triangle_count();
  trim_long_edges(b.tin, 2.0);
  // Only hull slivers of the jittered square outline may go; the hole's triangles stay.
  std::uint64_t long_inside_after = 0;
  b.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    const Point2 g = test::triangle_centroid(b.tin, c);
    if (longest_edge(b.tin, c) > 2.0 && g.x > 11 && g.x < 19 && g.y > 11 && g.y < 19)
      ++long_inside_after;
  });
  EXPECT_EQ(long_inside_after, long_inside);
  // What did go are slivers under the outer hull, which skips over points of the jittered edge.
  const auto slots = static_cast<TriangleId>(b.tin.triangle_slots());
  std::uint64_t removed = 0;
  for (TriangleId t = 0; t < slots; ++t) {
    if (b.tin.is_ghost(t) || b.tin.is_kept(t)) continue;
    ++removed;
    const Point2 g = test::triangle_centroid(b.tin, b.tin.triangle(t));
    EXPECT_TRUE(g.x < 1 || g.x > 29 || g.y < 1 || g.y > 29) << g.x << "," << g.y;
  }
  EXPECT_EQ(b.tin.triangle_count() + removed, before);
  EXPECT_EQ(b.tin.validate(), "");
}

TEST(Trim, SplitsIntoParts) {
  // Two blobs 20 apart: the bridge goes, both blobs stay whole.
  auto b = build_tin(jittered_grid(50, 10, [](int i, int) { return i <= 15 || i >= 35; }));
  const std::uint64_t removed = trim_long_edges(b.tin, 2.0);
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(b.tin.validate(), "");
  // Count the pieces of kept triangles joined across edges.
  const auto slots = static_cast<TriangleId>(b.tin.triangle_slots());
  std::vector<int> seen(slots, 0);
  int parts = 0;
  for (TriangleId s = 0; s < slots; ++s) {
    if (!b.tin.is_kept(s) || seen[s]) continue;
    ++parts;
    std::vector<TriangleId> stack{s};
    seen[s] = 1;
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
        const TriangleId n = mesh::triangle_of(b.tin.twin(e));
        if (b.tin.is_kept(n) && !seen[n]) {
          seen[n] = 1;
          stack.push_back(n);
        }
      }
    }
  }
  EXPECT_EQ(parts, 2);
}

TEST(Trim, WorksInwardFromEarlierRemovals) {
  // The interior gap again; erase one of its triangles (as an erase polygon would): now the gap's
  // long triangles are exposed and go, and the short ones around stay.
  auto b = build_tin(jittered_grid(
      30, 30, [](int i, int j) { return !(i >= 12 && i <= 18 && j >= 12 && j <= 18); }));
  const auto in_gap = [&](const std::array<VertexId, 3>& c) {
    const Point2 g = test::triangle_centroid(b.tin, c);
    return g.x > 11 && g.x < 19 && g.y > 11 && g.y < 19;
  };
  const auto slots = static_cast<TriangleId>(b.tin.triangle_slots());
  TriangleId seed = kNoId;
  for (TriangleId t = 0; t < slots && seed == kNoId; ++t)
    if (!b.tin.is_ghost(t) && in_gap(b.tin.triangle(t)) &&
        longest_edge(b.tin, b.tin.triangle(t)) > 4)
      seed = t;
  ASSERT_NE(seed, kNoId);
  b.tin.set_removed(seed, true);
  EXPECT_GT(trim_long_edges(b.tin, 2.0), 0u);
  std::uint64_t long_in_gap = 0;
  for (TriangleId t = 0; t < slots; ++t) {
    if (b.tin.is_ghost(t)) continue;
    const auto c = b.tin.triangle(t);
    if (longest_edge(b.tin, c) <= 2.0) {
      EXPECT_TRUE(b.tin.is_kept(t));
    }
    if (b.tin.is_kept(t) && in_gap(c) && longest_edge(b.tin, c) > 2.0) ++long_in_gap;
  }
  EXPECT_EQ(long_in_gap, 0u);
  EXPECT_EQ(b.tin.validate(), "");
}

TEST(Trim, ConstrainedEdgesAreDataNotBridges) {
  // Bottom row every 3 units, rows above every 1.5: the bottom triangles have one edge of 3 (the
  // others <= 2.13). Unconstrained, those edges are bridges over missing data and go at 2.5; as
  // constraints (a breakline along the edge of the data) they are data and stay, unless asked.
  std::vector<Point3> pts;
  for (int i = 0; i <= 10; ++i) pts.push_back({3.0 * i, 0, 0});
  for (int j = 1; j <= 6; ++j)
    for (int i = 0; i <= 20; ++i) pts.push_back({1.5 * i, 1.5 * j, 0});
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bottom;
  for (std::uint32_t i = 0; i < 10; ++i) bottom.push_back({i, i + 1});

  auto plain = build_tin(pts);
  EXPECT_EQ(trim_long_edges(plain.tin, 2.5), 10u);
  EXPECT_EQ(plain.tin.validate(), "");
  auto constrained = build_tin(pts, bottom);
  mesh::Triangulation copy = constrained.tin;
  EXPECT_EQ(trim_long_edges(constrained.tin, 2.5), 0u);
  EXPECT_EQ(trim_long_edges(copy, 2.5, {.constrained_edges_count = true}), 10u);
}

TEST(Trim, RejectsBadLimits) {
  auto b = build_tin(jittered_grid(3, 3, [](int, int) { return true; }));
  EXPECT_THROW(trim_long_edges(b.tin, 0), Error);
  EXPECT_THROW(trim_long_edges(b.tin, -1), Error);
  EXPECT_THROW(trim_long_edges(b.tin, std::nan("")), Error);
  EXPECT_EQ(trim_long_edges(b.tin, HUGE_VAL), 0u);
}

}  // namespace
}  // namespace tincdt::terrain
