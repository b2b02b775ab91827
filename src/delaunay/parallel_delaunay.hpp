// The two-thread path of the Delaunay stage: split the points in two by a lexicographic (x, y)
// pivot, triangulate each half in its own thread, then merge the two triangulations.
//
// The halves are separable (every left point is lexicographically smaller than every right
// point), so their convex hulls are disjoint. The merge finds the two common tangents, fills the
// gap between the facing hull chains with a zipper of triangles (each step advances on whichever
// chain keeps the new triangle inside the gap, preferring the Delaunay choice by the perturbed
// incircle test), and then Lawson-flips the new triangles and their neighbours until every edge
// is locally Delaunay. Cocircular ties are broken by predicates::incircle_perturbed, as in the
// sequential insertion, so the merge gives the same (unique) triangulation. Both halves write into
// disjoint slot ranges of one Triangulation, so the triangle arrays exist only once.
#pragma once

#include <cstdint>
#include <vector>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::delaunay {

// Triangulates `input` (finite points, bounding box `box`) with two threads. Returns false, with
// `input` and `result` untouched, when the points cannot be split into two halves that each have
// two distinct points, or when all points are collinear: the caller then runs the sequential
// path (which also reports those inputs' errors). Otherwise consumes `input` and fills `result`
// as triangulate() does.
bool triangulate_in_two(std::vector<Point3>& input, const BBox& box, const DelaunayOptions& options,
                        const ProgressFn* progress, DelaunayResult& result);

// Triangulates vertices [first, last) of `tin` (distinct, at least two; collinear is allowed and
// gives the doubly covered segment) into its slots [slot, slot + 2k - 2), which must exist, in
// vertex order. Returns a ghost half-edge with the infinite vertex as apex; adds the flips to
// `flips` if not null. Two calls on disjoint ranges may run at once.
EdgeId triangulate_range(mesh::Triangulation& tin, VertexId first, VertexId last, TriangleId slot,
                         std::uint64_t* flips = nullptr);

// Merges two Delaunay triangulations held in one Triangulation into the Delaunay triangulation of
// their union. Every vertex of the left one must be lexicographically (x, then y) smaller than
// every vertex of the right one. Each is closed by its own ghosts; a set of collinear points may
// be given as its doubly covered segment (2k - 2 ghosts and no real triangle). `left_ghost` and
// `right_ghost` are half-edges of a ghost of each, with the infinite vertex as apex; `spare0`
// and `spare1` are two unused slots. Returns the number of flips.
std::uint64_t merge_triangulations(mesh::Triangulation& tin, EdgeId left_ghost, EdgeId right_ghost,
                                   TriangleId spare0, TriangleId spare1);

}  // namespace tincdt::delaunay
