// Long-edge trimming of the TIN's outline ("--max-edge"): the Delaunay stage always fills the
// convex hull, which bridges concave bays and gaps of the data with long, thin triangles.
#pragma once

#include <cstdint>
#include <vector>

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

// For a TIN about to be simplified: trims it as trim_long_edges() does (the data's gaps are
// gaps between its points, not between the fewer vertices a simplified TIN keeps) and makes
// every edge between a kept and a trimmed triangle constrained, so that the simplification
// keeps the trimmed outline. Returns the number of triangles trimmed.
std::uint64_t trim_and_fence(mesh::Triangulation& tin, double max_edge);

// After the simplification of a TIN that trim_and_fence() trimmed: removes the regions of
// triangles (joined across unconstrained edges, so never across the fenced outline) whose
// largest triangle IN_TRIMMED(t) says lies in a trimmed area (slots beyond MARKED count as
// unmarked). The largest triangle's centroid is the farthest from the region's edges, so its
// rounding cannot put it across the outline. Returns the number of triangles removed.
std::uint64_t remove_marked_regions(mesh::Triangulation& tin,
                                    const std::vector<std::uint8_t>& marked);

}  // namespace tincdt::terrain
