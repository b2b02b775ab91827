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
// gaps between its points, not between the fewer vertices a simplified TIN keeps) and fences the
// trimmed triangles (fence_trimmed()). Returns the trimmed triangles, 1 per slot.
std::vector<std::uint8_t> trim_and_fence(mesh::Triangulation& tin, double max_edge);

// Makes every edge between a triangle TRIMMED marks (1 per slot) and a real triangle it does not
// mark constrained, so that a simplification keeps the trimmed outline.
void fence_trimmed(mesh::Triangulation& tin, const std::vector<std::uint8_t>& trimmed);

// The triangles of SIMPLIFIED (1 per slot), a simplification of FULL whose trimmed triangles
// TRIMMED marks (1 per slot of FULL), whose centroid lies in a trimmed triangle: what
// remove_marked_regions() reads.
std::vector<std::uint8_t> mark_trimmed_areas(const mesh::Triangulation& full,
                                             const std::vector<std::uint8_t>& trimmed,
                                             const mesh::Triangulation& simplified);

// After the simplification of a TIN whose trimmed triangles were fenced: removes the regions of
// triangles (joined across unconstrained edges, so never across the fenced outline) whose
// largest triangle MARKED says lies in a trimmed area (slots beyond MARKED count as unmarked).
// The largest triangle's centroid is the farthest from the region's edges, so its rounding
// cannot put it across the outline. Returns the number of triangles removed.
std::uint64_t remove_marked_regions(mesh::Triangulation& tin,
                                    const std::vector<std::uint8_t>& marked);

}  // namespace tincdt::terrain
