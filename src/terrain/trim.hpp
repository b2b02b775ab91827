// Long-edge trimming of the TIN's outline ("--max-edge"): the Delaunay stage always fills the
// convex hull, which bridges concave bays and gaps of the data with long, thin triangles.
#pragma once

#include <cstdint>

#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

struct TrimOptions {
  // A constrained edge (contour, breakline, clip or erase ring) is data, not a bridge over a gap
  // in it: by default its length does not make a triangle "long", so trimming after clipping
  // does not eat in from a clip polygon's long sides, nor along a long contour segment. Set true
  // to measure every edge alike.
  bool constrained_edges_count = false;
};

// Whether real triangle T has an edge longer than MAX_EDGE (horizontal length; constrained edges
// only with OPTIONS.constrained_edges_count): the triangles trim_long_edges() may remove.
bool has_long_edge(const mesh::Triangulation& tin, TriangleId t, double max_edge,
                   const TrimOptions& options = {});

// Removes (Triangulation::set_removed) every boundary triangle that has an edge longer than
// `max_edge` (horizontal length), then the triangles this exposes, until every kept triangle on
// the boundary has all edges <= max_edge. A triangle is on the boundary when a neighbour is a
// ghost or a removed triangle, so trimming works inward from the hull and from earlier removals
// (clip / erase) alike, and it never opens a hole inside the data: a long-edged triangle
// surrounded by short-edged ones stays. A triangle whose edges are all <= max_edge is never
// removed. The topology is untouched (validate() passes as before); the kept part may come
// apart into several pieces, with holes. So the removed triangles are the components of
// long-edged triangles (has_long_edge(), joined across any edge) that touch the hull or an
// earlier removal. Returns the number of triangles removed.
// Throws tincdt::Error unless max_edge > 0 (+infinity removes nothing).
std::uint64_t trim_long_edges(mesh::Triangulation& tin, double max_edge,
                              const TrimOptions& options = {});

}  // namespace tincdt::terrain
