// Independent references for the unique (symbolically perturbed) Delaunay triangulation: a brute
// force check built on perturbed_incircle_reference.hpp (integer coordinates, no code from
// src/predicates), and the triangle set that two TINs of one point set must share.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"
#include "support/perturbed_incircle_reference.hpp"

namespace tincdt::test {

// Number of convex hull vertices, collinear ones included (gift wrapping, O(n h)).
inline std::size_t hull_size(std::vector<IntPoint> p) {
  std::sort(p.begin(), p.end(), lex_less);
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p.size();
  std::size_t count = 0;
  IntPoint current = p.front();  // lexicographically smallest: on the hull
  do {
    ++count;
    // The next hull vertex counter-clockwise: every point left of or on current -> next, the
    // nearest one when several lie ahead on that line.
    IntPoint next = p[0] == current ? p[1] : p[0];
    for (const IntPoint& q : p) {
      if (q == current) continue;
      const int o = orientation(current, next, q);
      const Int128 ahead = Int128{q.x - current.x} * (next.x - current.x) +
                           Int128{q.y - current.y} * (next.y - current.y);
      const Int128 reach = Int128{next.x - current.x} * (next.x - current.x) +
                           Int128{next.y - current.y} * (next.y - current.y);
      if (o < 0 || (o == 0 && ahead > 0 && ahead < reach)) next = q;
    }
    current = next;
    if (count > p.size()) return 0;  // cannot happen; keeps a broken test from spinning
  } while (!(current == p.front()));
  return count;
}

// Empty if the real triangles of `tin` are the perturbed Delaunay triangulation of its vertices:
// each one counter-clockwise with no vertex inside its perturbed circle (so each is a triangle of
// that unique triangulation), and as many as it has (2n - 2 - h). O(n t): small inputs only.
inline std::string perturbed_delaunay_violation(const mesh::Triangulation& tin,
                                                const IntegerFrame& frame) {
  std::vector<IntPoint> v;
  v.reserve(tin.vertex_count());
  for (const Point2& p : tin.points()) v.push_back(frame.to_int(p));
  std::string problem;
  std::size_t triangles = 0;
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    ++triangles;
    if (!problem.empty()) return;
    if (orientation(v[c[0]], v[c[1]], v[c[2]]) <= 0) {
      problem = "triangle " + std::to_string(t) + " is not counter-clockwise";
      return;
    }
    for (VertexId q = 0; q < v.size(); ++q) {
      if (q == c[0] || q == c[1] || q == c[2]) continue;
      if (perturbed_in_circle(v[c[0]], v[c[1]], v[c[2]], v[q]) > 0) {
        problem = "vertex " + std::to_string(q) + " is inside the perturbed circle of triangle " +
                  std::to_string(t);
        return;
      }
    }
  });
  if (!problem.empty()) return problem;
  const std::size_t expected = 2 * v.size() - 2 - hull_size(v);
  if (triangles != expected)
    return std::to_string(triangles) + " triangles, expected " + std::to_string(expected);
  return {};
}

// The real triangles as a canonical set: each triangle's corners (x, y, z) in lexicographic order,
// the triangles sorted. Equal sets mean the same TIN, whatever the vertex ids and slots.
inline std::vector<std::array<Point3, 3>> triangle_set(const mesh::Triangulation& tin) {
  const auto less = [](const Point3& a, const Point3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  };
  std::vector<std::array<Point3, 3>> set;
  set.reserve(tin.triangle_count());
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    std::array<Point3, 3> t;
    for (std::size_t i = 0; i < 3; ++i) {
      const Point2 p = tin.point(c[i]);
      t[i] = {p.x, p.y, tin.z(c[i])};
    }
    std::sort(t.begin(), t.end(), less);
    set.push_back(t);
  });
  std::sort(set.begin(), set.end(), [&](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), less);
  });
  return set;
}

}  // namespace tincdt::test
