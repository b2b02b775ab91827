// Error-bounded simplification (Garland & Heckbert 1995, greedy insertion) that keeps every
// constraint: start from the constrained Delaunay triangulation of the kept vertices (feature
// vertices and the corners of the points' convex hull), then insert, one at a time, the input
// point farthest (vertically) from the current TIN, until every point is within max_error or
// the TIN has max_vertices vertices. Points are the only candidates: no vertex is invented.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/progress.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::simplify {

struct SimplifyOptions {
  double max_error = 0;          // vertical tolerance, in z units; >= 0
  std::size_t max_vertices = 0;  // stop when the TIN has this many vertices; 0 = no limit
  unsigned threads = 0;          // 0 = all cores; the result does not depend on it
};

struct SimplifyReport {
  std::uint64_t points = 0;         // input points, kept ones included
  std::uint64_t kept_vertices = 0;  // vertices the TIN started with (features, hull corners)
  std::uint64_t vertices = 0;       // vertices of the result
  std::uint64_t inserted = 0;       // points inserted by the greedy loop
  double max_error = 0;             // achieved: the largest |z - TIN(x, y)| over all points
  double rmse = 0;                  // root mean square of the same, over all points
  bool stopped_at_max_vertices = false;
  std::uint32_t regions = 0;  // simplified on their own first, on all threads (0: none)
};

struct SimplifyResult {
  mesh::Triangulation tin;  // constrained Delaunay; vertex index built
  // Input point index of each vertex; kNoId for a vertex made where two segments cross.
  std::vector<std::uint32_t> point_of_vertex;
  SimplifyReport report;
};

// Simplifies the surface of the points (xy[i], z[i]), whose x, y must be distinct (the
// Delaunay stage merges duplicates). Points `kept` stay as vertices, and every segment (its ends
// are point indices) becomes a chain of constrained edges: two crossing segments meet at a new
// vertex; a point lying on a segment splits it when it is inserted. The corners of the points'
// convex hull are kept too, so the result covers every point. Ties in error go by x, then y: the
// result depends neither on the order of the points nor on the thread count. Throws
// GeometryError when the points are all collinear or fewer than 3, or when a point that must
// become a vertex shares x, y with another.
SimplifyResult simplify(std::span<const Point2> xy, std::span<const double> z,
                        std::span<const std::uint32_t> kept,
                        std::span<const constraints::Segment> segments,
                        const SimplifyOptions& options, const ProgressFn* progress = nullptr);

// The pipeline's form: simplifies a constrained TIN whose vertices are the (merged) input
// points. Its constrained edges and their vertices and the strict corners of its hull are kept;
// every other vertex is a candidate. The result's point_of_vertex maps to `full`'s vertices,
// and every constrained edge of `full` is an edge of the result.
SimplifyResult simplify_tin(const mesh::Triangulation& full, const SimplifyOptions& options,
                            const ProgressFn* progress = nullptr);

// The strict corners of the convex hull of the points (no point on an edge between two
// corners), counter-clockwise, starting at the lexicographically smallest point.
std::vector<std::uint32_t> hull_corners(std::span<const Point2> xy);
// The same for the points xy[i], i in `ids` (all points if empty).
std::vector<std::uint32_t> hull_corners(std::span<const Point2> xy,
                                        std::span<const std::uint32_t> ids);

}  // namespace tincdt::simplify
