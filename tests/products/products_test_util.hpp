// TINs and brute-force references shared by the products tests. The references look at every
// kept triangle for every query (no walk, no ownership rule) and interpolate in long double.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::products::test {

// Kinds of TIN the properties are checked on.
enum class Kind {
  random,        // uniform random x, y, z
  lattice,       // integer lattice, integer z: every grid centre and level hits vertices and edges
  lattice_holes  // the lattice with a random third of the triangles removed
};

inline const char* kind_name(Kind k) {
  switch (k) {
    case Kind::random:
      return "random";
    case Kind::lattice:
      return "lattice";
    case Kind::lattice_holes:
      return "lattice_holes";
  }
  return "?";
}

// X0, Y0: an offset of map-coordinate size added to every point.
inline mesh::Triangulation make_tin(Kind kind, std::uint32_t seed, double x0 = 0, double y0 = 0,
                                    int n = 12) {
  std::mt19937 rng(seed);
  std::vector<Point3> pts;
  if (kind == Kind::random) {
    std::uniform_real_distribution<double> u(0, n), z(0, 10);
    for (int i = 0; i < n * n; ++i) pts.push_back({x0 + u(rng), y0 + u(rng), z(rng)});
  } else {
    std::uniform_int_distribution<int> z(0, 6);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) pts.push_back({x0 + i, y0 + j, static_cast<double>(z(rng))});
  }
  mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  if (kind == Kind::lattice_holes) {
    std::bernoulli_distribution drop(1.0 / 3);
    for (TriangleId t = 0; t < tin.triangle_slots(); ++t)
      if (!tin.is_ghost(t) && drop(rng)) tin.set_removed(t, true);
    tin.recount();
  }
  return tin;
}

inline bool closed_contains(const mesh::Triangulation& tin, TriangleId t, Point2 p) {
  const auto c = tin.triangle(t);
  for (int i = 0; i < 3; ++i)
    if (predicates::orient2d(tin.point(c[i]), tin.point(c[(i + 1) % 3]), p) < 0) return false;
  return true;
}

// The plane of triangle t at p, in long double, from barycentric weights.
inline long double plane_at(const mesh::Triangulation& tin, TriangleId t, Point2 p) {
  const auto c = tin.triangle(t);
  using L = long double;
  const L ax = tin.point(c[0]).x, ay = tin.point(c[0]).y;
  const L bx = tin.point(c[1]).x - ax, by = tin.point(c[1]).y - ay;
  const L cx = tin.point(c[2]).x - ax, cy = tin.point(c[2]).y - ay;
  const L px = p.x - ax, py = p.y - ay;
  const L det = bx * cy - by * cx;
  const L wb = (px * cy - py * cx) / det, wc = (bx * py - by * px) / det;
  return (1 - wb - wc) * tin.z(c[0]) + wb * tin.z(c[1]) + wc * tin.z(c[2]);
}

// Every kept triangle whose closed area holds p.
inline std::vector<TriangleId> holders(const mesh::Triangulation& tin, Point2 p) {
  std::vector<TriangleId> out;
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>&) {
    if (closed_contains(tin, t, p)) out.push_back(t);
  });
  return out;
}

}  // namespace tincdt::products::test
