// Independent checks of a simplified TIN: where each input point falls (a walk of its own with
// exact orient2d, or brute force) and how far it is from the TIN there; constraints as chains.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <vector>

#include "constraints/constraints.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"
#include "simplify/simplify.hpp"

namespace tincdt::test {

// Whether p lies in the closed real triangle t.
inline bool in_triangle(const mesh::Triangulation& tin, TriangleId t, Point2 p) {
  const auto c = tin.triangle(t);
  for (int i = 0; i < 3; ++i)
    if (predicates::orient2d(tin.point(c[i]), tin.point(c[(i + 1) % 3]), p) < 0) return false;
  return true;
}

// Linear interpolation in triangle t by barycentric weights in long double.
inline double interpolate(const mesh::Triangulation& tin, TriangleId t, Point2 p) {
  const auto c = tin.triangle(t);
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  using L = long double;
  const auto area = [](Point2 u, Point2 v, Point2 w) {
    return (L(v.x) - L(u.x)) * (L(w.y) - L(u.y)) - (L(v.y) - L(u.y)) * (L(w.x) - L(u.x));
  };
  const L total = area(a, b, d);
  const L wa = area(p, b, d) / total, wb = area(a, p, d) / total, wd = area(a, b, p) / total;
  return static_cast<double>(wa * tin.z(c[0]) + wb * tin.z(c[1]) + wd * tin.z(c[2]));
}

// The real triangle holding p: a walk with a random first edge (any triangulation), or every
// triangle in turn when `brute` is set. kNoId if none.
inline TriangleId locate(const mesh::Triangulation& tin, Point2 p, TriangleId start, bool brute,
                         std::uint64_t& random) {
  if (brute) {
    for (TriangleId t = 0; t < tin.triangle_slots(); ++t)
      if (!tin.is_ghost(t) && in_triangle(tin, t, p)) return t;
    return kNoId;
  }
  TriangleId t = start;
  for (std::size_t steps = 0; steps < 4 * tin.triangle_slots() + 16; ++steps) {
    random = random * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto first = static_cast<int>((random >> 33) % 3);
    bool moved = false;
    for (int k = 0; k < 3 && !moved; ++k) {
      const EdgeId e = 3 * t + static_cast<EdgeId>((first + k) % 3);
      if (predicates::orient2d(tin.point(tin.origin(e)), tin.point(tin.dest(e)), p) < 0) {
        const TriangleId u = mesh::triangle_of(tin.twin(e));
        if (tin.is_ghost(u)) return kNoId;
        t = u;
        moved = true;
      }
    }
    if (!moved) return t;
  }
  return kNoId;
}

// The largest |z - TIN(x, y)| over the points, each located independently; ADD_FAILUREs for a
// point outside the TIN.
inline double max_vertical_error(const mesh::Triangulation& tin, std::span<const Point2> xy,
                                 std::span<const double> z, bool brute = false) {
  double worst = 0;
  TriangleId t = 0;
  while (tin.is_ghost(t)) ++t;
  std::uint64_t random = 42;
  for (std::size_t i = 0; i < xy.size(); ++i) {
    const TriangleId u = locate(tin, xy[i], t, brute, random);
    if (u == kNoId) {
      ADD_FAILURE() << "point " << i << " (" << xy[i].x << ", " << xy[i].y
                    << ") is outside the TIN";
      continue;
    }
    t = u;
    worst = std::max(worst, std::fabs(z[i] - interpolate(tin, u, xy[i])));
  }
  return worst;
}

// Empty if segment a-b (vertices of `tin`) is a chain of constrained edges through vertices on
// it; otherwise a description. Vertices made where two segments cross (`rounded`) lie on them
// only up to rounding.
inline std::string constrained_chain(const mesh::Triangulation& tin, VertexId a, VertexId b,
                                     const std::vector<std::uint8_t>& rounded) {
  const Point2 pa = tin.point(a), pb = tin.point(b);
  const auto on_segment = [&](VertexId v) {
    const Point2 p = tin.point(v);
    const double slack = rounded[v] ? 1e-9 * (1 + std::fabs(pa.x) + std::fabs(pa.y)) : 0;
    if (std::min(pa.x, pb.x) - slack > p.x || p.x > std::max(pa.x, pb.x) + slack ||
        std::min(pa.y, pb.y) - slack > p.y || p.y > std::max(pa.y, pb.y) + slack)
      return false;
    if (predicates::orient2d(pa, pb, p) == 0) return true;
    const double cross = (pb.x - pa.x) * (p.y - pa.y) - (pb.y - pa.y) * (p.x - pa.x);
    return rounded[v] && std::fabs(cross) <= slack * std::hypot(pb.x - pa.x, pb.y - pa.y);
  };
  // Edges by origin, built once per call: fine for test sizes.
  std::map<VertexId, std::vector<EdgeId>> out;
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); ++e)
    if (tin.is_constrained(e) && tin.origin(e) < mesh::kInfinite && tin.dest(e) < mesh::kInfinite)
      out[tin.origin(e)].push_back(e);
  std::set<VertexId> seen{a};
  std::vector<VertexId> todo{a};
  while (!todo.empty()) {
    const VertexId v = todo.back();
    todo.pop_back();
    if (v == b) return {};
    for (EdgeId e : out[v]) {
      const VertexId w = tin.dest(e);
      if (on_segment(w) && seen.insert(w).second) todo.push_back(w);
    }
  }
  return "segment " + std::to_string(a) + "-" + std::to_string(b) + " is not a constrained chain";
}

// The TIN as a set of triangles named by their corners' coordinates (rotation-free), to compare
// two results whatever their vertex numbering.
inline std::set<std::array<double, 6>> triangle_set(const mesh::Triangulation& tin) {
  std::set<std::array<double, 6>> s;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    std::array<Point2, 3> p{tin.point(c[0]), tin.point(c[1]), tin.point(c[2])};
    std::rotate(
        p.begin(),
        std::min_element(p.begin(), p.end(),
                         [](Point2 u, Point2 v) { return u.x < v.x || (u.x == v.x && u.y < v.y); }),
        p.end());
    s.insert({p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y});
  });
  return s;
}

}  // namespace tincdt::test
