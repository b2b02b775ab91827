// The Delaunay stage: every point in, an exact Delaunay triangulation out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::delaunay {

// What z a vertex gets when several points share its exact x, y: the z of the first of them in
// input order, their least or greatest z, or their mean (summed in increasing z, so that it does
// not depend on the input order either).
enum class DuplicatePolicy { first, min, max, mean };

// The result never depends on the order of the points in the input (but for `first`, by its
// definition) nor on the thread count: the triangles are the unique Delaunay triangulation with
// cocircular ties broken by predicates::incircle_perturbed, and every vertex id and triangle slot
// is a rule of the point set (Hilbert/BRIO order by coordinates, a split drawn by a hash of them).
struct DelaunayOptions {
  DuplicatePolicy on_duplicate = DuplicatePolicy::mean;
  bool keep_point_map = false;   // fill DelaunayResult::vertex_of_point
  bool keep_duplicates = false;  // fill DelaunayResult::duplicates
  // From this many points on, split them in two halves, triangulated each on its own and merged
  // (parallel_delaunay.hpp); 0 always tries, SIZE_MAX never. A rule of the point count alone.
  std::size_t parallel_min_points = 50000;
  // Threads the stage may use (BuildOptions::threads); 0 = every core. 1 triangulates the two
  // halves one after the other: the same work, to the same bits.
  unsigned threads = 0;
};

struct DelaunayResult {
  // A vertex that several input points with equal x, y were merged into (its x, y and merged z
  // are the TIN's): how many points, and the range of their z.
  struct Duplicate {
    VertexId vertex;
    std::uint32_t points;  // >= 2
    double z_min, z_max;
  };

  mesh::Triangulation tin;
  std::vector<VertexId> vertex_of_point;  // input point i became vertex vertex_of_point[i]
  std::uint64_t duplicates_merged = 0;    // points folded into an earlier one with equal x, y
  std::vector<Duplicate> duplicates;      // with keep_duplicates: one per merged vertex, in order
  std::uint64_t flips = 0;                // Lawson flips while inserting
};

// Triangulates `points` (consumed, to keep the peak memory low; -0.0 coordinates become 0.0).
// Vertices are renumbered in spatial (Hilbert) order. Throws GeometryError for fewer than 3
// distinct points, all points collinear, or a non-finite coordinate.
DelaunayResult triangulate(std::vector<Point3>&& points, const DelaunayOptions& options = {},
                           const ProgressFn* progress = nullptr);

}  // namespace tincdt::delaunay
