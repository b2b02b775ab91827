// Flat triangles of a contour-only TIN: a hill of concentric (wavy) contour rings at 10, 20 and
// 30 with a narrow valley cut into the 20 ring. The top ring holds nothing but flats, the valley
// between the arms of the 20 ring too; fix_flat_triangles must remove them all, keep every
// constraint and give the new vertices plausible heights.
#include "terrain/flats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/geometry.hpp"
#include "terrain/interpolate.hpp"
#include "terrain/quality.hpp"
#include "terrain_test_util.hpp"

namespace tincdt::terrain {
namespace {

// The ground: z = 40 - rho / 2 with rho = r / wobble(theta), so the contour at level L is the
// wavy ring r = (80 - 2L) * wobble(theta) (the hilltop, at rho = 0, is at 40).
double wobble(double theta) {
  return 1 + 0.08 * std::sin(5 * theta + 0.4);
}
double ground(Point2 p) {
  const double r = std::hypot(p.x, p.y), theta = std::atan2(p.y, p.x);
  return 40 - r / wobble(theta) / 2;
}

// The valley: the 20 ring is pulled in towards the top around theta = 0.
double notch(double theta) {
  return 1 - 0.4 * std::exp(-(theta / 0.1) * (theta / 0.1));
}
// Between the arms of the notch: outside the (pulled-in) 20 ring, inside where it would be.
bool in_valley(Point2 p) {
  const double r = std::hypot(p.x, p.y), theta = std::atan2(p.y, p.x);
  return std::fabs(theta) < 0.3 && r > 40 * wobble(theta) * notch(theta) && r < 39 * wobble(theta);
}

// Ring at `level`, resampled along its length every `step` units.
std::vector<Point2> contour_ring(double level, bool with_notch, double step) {
  const double base = 80 - 2 * level;
  std::vector<Point2> dense;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double theta = -std::numbers::pi + 2 * std::numbers::pi * k / n;
    const double r = base * wobble(theta) * (with_notch ? notch(theta) : 1.0);
    dense.push_back({r * std::cos(theta), r * std::sin(theta)});
  }
  std::vector<Point2> ring{dense[0]};
  double run = 0;
  for (int k = 1; k < n; ++k) {
    run += std::hypot(dense[k].x - dense[k - 1].x, dense[k].y - dense[k - 1].y);
    if (run >= step) {
      ring.push_back(dense[k]);
      run = 0;
    }
  }
  return ring;
}

struct Hill {
  test::Built b;
  std::vector<std::uint8_t> on_contour;
};

Hill make_hill() {
  std::vector<Point3> pts;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  for (double level : {10.0, 20.0, 30.0})
    test::add_ring(contour_ring(level, level == 20, 2.5), level, pts, segs);
  Hill h{test::build_tin(std::move(pts), segs), {}};
  h.on_contour.assign(h.b.tin.vertex_count(), 1);
  return h;
}

std::uint64_t count_non_delaunay(const mesh::Triangulation& tin) {
  std::uint64_t n = 0;
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); ++e)
    if (tin.origin(e) < tin.dest(e) && tin.dest(e) != mesh::kInfinite && !tin.is_constrained(e) &&
        !mesh::is_locally_delaunay(tin, e))
      ++n;
  return n;
}

void expect_constraints_kept(const test::Built& b) {
  mesh::Triangulation copy = b.tin;
  copy.build_vertex_index();
  for (const auto& s : b.segments) {
    const EdgeId e = copy.find_edge(s.a, s.b);
    ASSERT_NE(e, kNoId) << "segment " << s.source << " is no longer an edge";
    EXPECT_TRUE(copy.is_constrained(e));
  }
}

// Heights of the new vertices: above 30 (at most half an interval) on the top, between 10 and
// 20 in the valley, and never outside the levels around them. Returns how many were in the valley.
int expect_plausible_heights(const mesh::Triangulation& tin, const FlatFixReport& r) {
  int valley = 0;
  for (VertexId v = r.first_new_vertex; v < tin.vertex_count(); ++v) {
    const Point2 p = tin.point(v);
    const double z = tin.z(v);
    const double rho = std::hypot(p.x, p.y) / wobble(std::atan2(p.y, p.x));
    if (rho < 20) {
      EXPECT_GT(z, 30);
      EXPECT_LE(z, 35);
    } else if (in_valley(p)) {
      ++valley;
      EXPECT_GT(z, 10);
      EXPECT_LT(z, 20);
    } else if (rho > 60) {  // bays of the lowest ring, open to the outside: falling below 10
      EXPECT_GE(z, 5);
      EXPECT_LT(z, 10);
    } else {
      EXPECT_GT(z, 10);
      EXPECT_LT(z, 30);
    }
  }
  return valley;
}

// Mean |TIN - ground| over a grid of points near the top (rho < 18).
double top_error(const mesh::Triangulation& tin) {
  double sum = 0;
  int n = 0;
  SurfaceSampler sampler(tin);
  for (double x = -17; x <= 17; x += 0.5)
    for (double y = -17; y <= 17; y += 0.5) {
      const Point2 p{x, y};
      if (std::hypot(x, y) / wobble(std::atan2(y, x)) >= 18) continue;
      sum += std::fabs(sampler.z_at(p) - ground(p));
      ++n;
    }
  return sum / n;
}

TEST(Flats, HillTopAndValleyAreFixed) {
  Hill h = make_hill();
  // Where the flats are before: on the top, in the valley.
  std::uint64_t top = 0, valley = 0;
  h.b.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    if (!is_flat(h.b.tin, c, &h.on_contour)) return;
    const Point2 g = test::triangle_centroid(h.b.tin, c);
    if (std::hypot(g.x, g.y) < 20 * 0.92) ++top;
    if (in_valley(g)) ++valley;
  });
  EXPECT_GT(top, 20u);
  EXPECT_GT(valley, 3u);
  const double error_before = top_error(h.b.tin);

  const FlatFixReport r = fix_flat_triangles(h.b.tin, h.on_contour);
  std::printf(
      "[ info ] flats %llu -> %llu after %llu swaps -> %llu; %llu vertices (%llu "
      "interpolated, %llu extrapolated); %llu non-Delaunay edges\n",
      (unsigned long long)r.flats_before, (unsigned long long)r.flats_after_swaps,
      (unsigned long long)r.swaps, (unsigned long long)r.flats_after,
      (unsigned long long)r.vertices_added, (unsigned long long)r.vertices_interpolated,
      (unsigned long long)r.vertices_extrapolated, (unsigned long long)r.non_delaunay_edges);
  EXPECT_GE(r.flats_before, top + valley);
  EXPECT_EQ(r.flats_after_swaps, r.flats_before - r.swaps);  // one flat less per swap
  EXPECT_EQ(r.flats_after, 0u);
  EXPECT_EQ(count_flat_triangles(h.b.tin, h.on_contour), 0u);
  EXPECT_EQ(measure_quality(h.b.tin, &h.on_contour).flat_triangles, 0u);
  EXPECT_GT(r.vertices_added, 0u);
  EXPECT_EQ(r.first_new_vertex + r.vertices_added, h.b.tin.vertex_count());
  EXPECT_EQ(r.vertices_added, r.vertices_interpolated + r.vertices_extrapolated);
  EXPECT_GT(r.vertices_extrapolated, 0u);  // the top has no other level inside its ring
  EXPECT_EQ(h.b.tin.validate({.delaunay = false}), "");
  EXPECT_EQ(r.non_delaunay_edges, count_non_delaunay(h.b.tin));
  EXPECT_LE(r.non_delaunay_edges, r.swaps);
  EXPECT_EQ(
      h.b.tin.triangle_count(), 2 * h.b.tin.vertex_count() - 2 - [&] {
        std::size_t hull = 0;  // Euler: real triangles = 2n - 2 - hull vertices
        for (EdgeId e = 0; e < 3 * h.b.tin.triangle_slots(); ++e)
          hull += h.b.tin.apex(e) == mesh::kInfinite;
        return hull;
      }());
  expect_constraints_kept(h.b);

  expect_plausible_heights(h.b.tin, r);
  // The top is now a dome closer to the ground than the terrace was.
  const double error_after = top_error(h.b.tin);
  std::printf("[ info ] mean |TIN - ground| on the top: %.3f before, %.3f after\n", error_before,
              error_after);
  EXPECT_LT(error_after, 0.6 * error_before);
}

TEST(Flats, WithoutSwapsTheTinStaysConstrainedDelaunay) {
  Hill h = make_hill();
  ASSERT_EQ(h.b.tin.validate(), "");
  const FlatFixReport r = fix_flat_triangles(h.b.tin, h.on_contour, {.swap = false});
  EXPECT_EQ(r.swaps, 0u);
  EXPECT_EQ(r.flats_after, 0u);
  EXPECT_EQ(r.non_delaunay_edges, 0u);
  EXPECT_EQ(h.b.tin.validate(), "");  // every unconstrained edge locally Delaunay
  expect_constraints_kept(h.b);
  // Without swaps the valley's flats get Steiner vertices, interpolated between 20 and 10.
  EXPECT_GT(expect_plausible_heights(h.b.tin, r), 0);
  EXPECT_GT(r.vertices_interpolated, 0u);
  EXPECT_GT(r.vertices_extrapolated, 0u);
}

TEST(Flats, SwapsAloneAndTheirAccount) {
  Hill h = make_hill();
  const FlatFixReport r = fix_flat_triangles(h.b.tin, h.on_contour, {.insert = false});
  EXPECT_GT(r.swaps, 0u);
  EXPECT_EQ(r.vertices_added, 0u);
  EXPECT_EQ(r.flats_after, r.flats_before - r.swaps);
  EXPECT_EQ(r.flats_after, r.flats_left_not_tried);
  EXPECT_GT(r.flats_after, 0u);  // the top cannot be swapped away
  EXPECT_EQ(h.b.tin.validate({.delaunay = false}), "");
  expect_constraints_kept(h.b);
}

TEST(Flats, ContourFlagsDecide) {
  // Not flagged as contour vertices: nothing is flat, nothing changes.
  Hill h = make_hill();
  const std::vector<std::uint8_t> none(h.b.tin.vertex_count(), 0);
  const FlatFixReport r = fix_flat_triangles(h.b.tin, none);
  EXPECT_EQ(r.flats_before, 0u);
  EXPECT_EQ(r.vertices_added + r.swaps, 0u);
}

TEST(Flats, OneLevelOnlyIsExplained) {
  // A single contour ring: no other level anywhere, so no height can be derived.
  std::vector<Point3> pts;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  test::add_ring(contour_ring(20, false, 4), 20, pts, segs);
  Hill h{test::build_tin(std::move(pts), segs), {}};
  h.on_contour.assign(h.b.tin.vertex_count(), 1);
  const FlatFixReport r = fix_flat_triangles(h.b.tin, h.on_contour);
  EXPECT_GT(r.flats_before, 0u);
  EXPECT_EQ(r.vertices_added, 0u);
  EXPECT_EQ(r.flats_after, r.flats_left_no_level);
  EXPECT_GT(r.flats_after, 0u);
}

TEST(Flats, RunsBeforeClipping) {
  Hill h = make_hill();
  h.b.tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>&) {
    if (t % 7 == 0) h.b.tin.set_removed(t, true);
  });
  EXPECT_THROW(fix_flat_triangles(h.b.tin, h.on_contour), Error);
}

}  // namespace
}  // namespace tincdt::terrain
