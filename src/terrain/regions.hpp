// Regions of a TIN: its real triangles joined across unconstrained edges. Where rings or an
// outline are constrained edges, a region lies wholly on one side of each, so one point of it
// answers for all of it (polygons.cpp, trim.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

// Calls VISIT(members) with the triangles of each region of the real triangles IN_SCOPE(t)
// accepts, joined across unconstrained edges through such triangles only; removed triangles
// count like the others (they are still in the topology).
template <class InScope, class Visit>
void for_each_region(const mesh::Triangulation& tin, InScope in_scope, Visit visit) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<std::uint8_t> seen(slots, 0);
  std::vector<TriangleId> stack, members;
  for (TriangleId seed = 0; seed < slots; ++seed) {
    if (tin.is_ghost(seed) || seen[seed] || !in_scope(seed)) continue;
    members.clear();
    stack.assign(1, seed);
    seen[seed] = 1;
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      members.push_back(t);
      for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
        if (tin.is_constrained(e)) continue;
        const TriangleId n = mesh::triangle_of(tin.twin(e));
        if (tin.is_ghost(n) || seen[n] || !in_scope(n)) continue;
        seen[n] = 1;
        stack.push_back(n);
      }
    }
    visit(std::span<const TriangleId>(members));
  }
}

// The member of largest area among MEMBERS below slot BELOW (kNoId if none): its centroid is the
// farthest of all their centroids from its triangle's edges, so rounding cannot put it across
// one.
TriangleId largest_triangle(const mesh::Triangulation& tin, std::span<const TriangleId> members,
                            TriangleId below = kNoId);

}  // namespace tincdt::terrain
