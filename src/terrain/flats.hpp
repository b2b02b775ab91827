// Flat triangles of contour TINs: three corners on contours at one z. Between the arms of a
// contour that bends around a ridge or into a valley, and inside the top ring of a hill, the
// (constrained) Delaunay triangulation joins vertices of the same contour, and the TIN shows a
// terrace at that level where the ground keeps rising or falling.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

struct FlatFixOptions {
  // Phase 1: flip an unconstrained edge of a flat triangle when the flip gives two triangles that
  // are not flat. This follows the terrain rather than the empty-circle rule: the flipped edges
  // are, by choice, not locally Delaunay (see FlatFixReport::non_delaunay_edges). Off: only
  // phase 2 runs, and a constrained Delaunay TIN stays one. On the five contour / DEM pairs of
  // the shared data, swaps + Steiner vertices gave the lower RMSE against the DEM on four (much
  // lower for coarse intervals: 100 m contours 15.98 vs 17.53 m) with 2-8x fewer new vertices;
  // Steiner vertices alone won on the dense 2 m lidR contours (0.401 vs 0.409 m).
  bool swap = true;
  // Phase 2: insert a vertex on the contours' medial axis in each flat triangle that is left,
  // with z from the neighbouring contour levels.
  bool insert = true;
  // Where a flat region has no other level on its side of the contour (a hilltop, a pit, a ridge
  // ending at the TIN's edge), z is extrapolated with the slope found outside; the true ground
  // there stays within one contour interval of the level (or another contour would show), and
  // the extrapolation is capped at this fraction of the interval.
  double extrapolation_cap = 0.5;
};

struct FlatFixReport {
  std::uint64_t flats_before = 0;
  std::uint64_t flats_after_swaps = 0;
  std::uint64_t flats_after = 0;
  std::uint64_t swaps = 0;
  std::uint64_t vertices_added = 0;         // new vertices are [first_new_vertex, vertex_count())
  std::uint64_t vertices_interpolated = 0;  // z between the region's level and the next one
  std::uint64_t vertices_extrapolated = 0;  // hilltops, pits: z from the slope outside
  VertexId first_new_vertex = 0;
  // Why flats are left (flats_after = the sum of these):
  std::uint64_t flats_left_no_level = 0;   // no other level on either side of their contour
  std::uint64_t flats_left_unplaced = 0;   // no point for a vertex strictly inside (degenerate)
  std::uint64_t flats_left_not_tried = 0;  // phase 2 off
  // Unconstrained edges that are not locally Delaunay at the end: those left by phase-1 swaps (a
  // Steiner vertex may have flipped some away). Restoring them would flip the swaps back and
  // re-create the flats, so the function leaves them; 0 when swap = false on a Delaunay input.
  std::uint64_t non_delaunay_edges = 0;
};

// Removes flat triangles from `tin` (swaps first, then Steiner vertices); see FlatFixOptions.
// `on_contour[v]` flags the vertices that lie on contour lines (vertices past its end count as
// not on one; the new vertices are not on contours). Constrained edges are never flipped or
// split, so every constraint stays an edge. Steiner vertices go in through mesh::PointInserter,
// which keeps the Delaunay property around them. Runs before any clipping: throws tincdt::Error
// if a triangle is removed already.
FlatFixReport fix_flat_triangles(mesh::Triangulation& tin,
                                 const std::vector<std::uint8_t>& on_contour,
                                 const FlatFixOptions& options = {});

// Flat triangles among the kept triangles (the rule of quality.hpp's is_flat with contours).
std::uint64_t count_flat_triangles(const mesh::Triangulation& tin,
                                   const std::vector<std::uint8_t>& on_contour);

}  // namespace tincdt::terrain
