// Builders shared by the terrain tests: a constrained Delaunay TIN from points and segments.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::terrain::test {

struct Built {
  mesh::Triangulation tin;
  std::vector<VertexId> vertex_of_point;
  std::vector<constraints::Segment> segments;  // in vertex ids
};

// Triangulates `points` and inserts `segments` (pairs of point indices) as constraints.
inline Built build_tin(std::vector<Point3> points,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments = {}) {
  delaunay::DelaunayResult dt = delaunay::triangulate(std::move(points), {.keep_point_map = true});
  Built b{std::move(dt.tin), std::move(dt.vertex_of_point), {}};
  for (std::uint32_t i = 0; i < segments.size(); ++i)
    b.segments.push_back(
        {b.vertex_of_point[segments[i].first], b.vertex_of_point[segments[i].second], i});
  if (!b.segments.empty()) constraints::insert_constraints(b.tin, b.segments);
  return b;
}

// Adds a closed ring of points to `points` and its edges to `segments`.
inline void add_ring(const std::vector<Point2>& ring, double z, std::vector<Point3>& points,
                     std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments) {
  const auto first = static_cast<std::uint32_t>(points.size());
  for (const Point2& p : ring) points.push_back({p.x, p.y, z});
  const auto n = static_cast<std::uint32_t>(ring.size());
  for (std::uint32_t i = 0; i < n; ++i) segments.push_back({first + i, first + (i + 1) % n});
}

inline double triangle_area(const mesh::Triangulation& tin, const std::array<VertexId, 3>& c) {
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  return 0.5 * ((b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x));
}

inline Point2 triangle_centroid(const mesh::Triangulation& tin, const std::array<VertexId, 3>& c) {
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  return {(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3};
}

inline double kept_area(const mesh::Triangulation& tin) {
  double area = 0;
  tin.for_each_triangle(
      [&](TriangleId, const std::array<VertexId, 3>& c) { area += triangle_area(tin, c); });
  return area;
}

// Signed shoelace area of a ring, relative to its first point (map coordinates would cancel).
inline double ring_area(const std::vector<Point2>& ring) {
  double a = 0;
  const Point2 o = ring[0];
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2 p = ring[i], q = ring[(i + 1) % ring.size()];
    a += (p.x - o.x) * (q.y - o.y) - (q.x - o.x) * (p.y - o.y);
  }
  return a / 2;
}

}  // namespace tincdt::terrain::test
