// Small hand-built triangulations shared by the writer tests.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::test {

// The south-west corner of the meshes: UTM magnitude, with digits that a writer must keep.
inline constexpr double kX0 = 500000.123456789;
inline constexpr double kY0 = 4000000.987654321;

// Links the twins of the real triangles and closes the hull with ghost triangles.
inline void close_with_ghosts(mesh::Triangulation& tin) {
  auto key = [](VertexId a, VertexId b) { return (std::uint64_t{a} << 32) | b; };
  std::unordered_map<std::uint64_t, EdgeId> edge_of;
  const auto real_slots = static_cast<TriangleId>(tin.triangle_slots());
  for (TriangleId t = 0; t < real_slots; ++t)
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) edge_of[key(tin.origin(e), tin.dest(e))] = e;
  std::vector<std::pair<VertexId, VertexId>> boundary;  // a -> b with no twin
  for (const auto& [k, e] : edge_of) {
    const auto a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xffffffffu);
    const auto it = edge_of.find(key(b, a));
    if (it != edge_of.end()) {
      if (a < b) tin.link(e, it->second);
    } else {
      boundary.emplace_back(a, b);
    }
  }
  std::unordered_map<VertexId, TriangleId> ghost_from;  // first corner -> ghost
  for (const auto& [a, b] : boundary) {
    const TriangleId g = tin.add_triangle(b, a, mesh::kInfinite);
    tin.link(3 * g, edge_of.at(key(a, b)));
    ghost_from[b] = g;
  }
  for (const auto& [first, g] : ghost_from) {
    const VertexId a = tin.triangle(g)[1];  // ghost (first, a, inf): a -> inf meets inf -> a
    tin.link(3 * g + 1, 3 * ghost_from.at(a) + 2);
  }
}

// A unit square at UTM magnitude, vertices 0 (SW), 1 (SE), 2 (NE), 3 (NW): triangles (0, 1, 2)
// (half-edges 0: 0->1, 1: 1->2, 2: 2->0) and (0, 2, 3) (3: 0->2, 4: 2->3, 5: 3->0), closed by
// four ghosts; optionally its diagonal 0-2 constrained.
inline mesh::Triangulation unit_square(bool constrain_diagonal = false) {
  mesh::Triangulation tin;
  tin.add_vertex({kX0, kY0}, 123.456789012345);
  tin.add_vertex({kX0 + 1, kY0}, 124.1);
  tin.add_vertex({kX0 + 1, kY0 + 1}, 0.1 + 0.2);
  tin.add_vertex({kX0, kY0 + 1}, -3.0e-7);
  tin.add_triangle(0, 1, 2);
  tin.add_triangle(0, 2, 3);
  close_with_ghosts(tin);
  if (constrain_diagonal) tin.set_constrained(2, true);  // edge 2 of triangle 0 runs 2 -> 0
  return tin;
}

}  // namespace tincdt::test
