// Private to the parallel Delaunay path: what the split, the halves and the merge share, and the
// triangulation of one half into its own range of triangle slots.
#pragma once

#include <cassert>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "core/types.hpp"
#include "mesh/point_insertion.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::delaunay::detail {

inline GeometryError internal_error(const std::string& what) {
  return GeometryError("internal: parallel Delaunay merge: " + what);
}

// Vertices [first, last), all on one line (at least two): the doubly covered segment, 2k - 2
// ghosts from `slot` on.
void build_segment(mesh::Triangulation& tin, VertexId first, VertexId last, TriangleId slot);

// A half-edge of a ghost in slots [first, last) whose apex is the infinite vertex.
EdgeId find_ghost(const mesh::Triangulation& tin, TriangleId first, TriangleId last);

// Triangulates vertices [first, last) (distinct, at least two) into slots from `slot` on; returns
// a ghost half-edge and adds the flips to `flips`. Every 1024 insertions calls `tick(i)`, and
// returns kNoId at once if that is false.
template <class Tick>
EdgeId triangulate_half(mesh::Triangulation& tin, VertexId first, VertexId last, TriangleId slot,
                        std::uint64_t& flips, Tick&& tick) {
  if (last < first + 2) throw internal_error("a half needs two vertices");
  const TriangleId end_slot = slot + 2 * (last - first) - 2;
  VertexId third = first + 2;
  int turn = 0;
  for (; third < last; ++third) {
    turn = predicates::orient2d(tin.point(first), tin.point(first + 1), tin.point(third));
    if (turn != 0) break;
  }
  if (third == last) {
    build_segment(tin, first, last, slot);
    return 3 * slot;
  }
  mesh::PointInserter inserter(tin, slot);
  if (turn > 0) {
    inserter.start(first, first + 1, third);
  } else {
    inserter.start(first + 1, first, third);
  }
  for (VertexId v = first + 2; v < last; ++v) {
    if (v == third) continue;
    inserter.insert(v);
    assert(inserter.next_slot() <= end_slot);  // the half's range holds its 2k - 2 triangles
    if (((v - first) & 1023) == 0 && !tick(v - first)) return kNoId;
  }
  if (inserter.next_slot() != end_slot) throw internal_error("a half used the wrong slot count");
  flips += inserter.flips();
  return find_ghost(tin, slot, end_slot);
}

}  // namespace tincdt::delaunay::detail
