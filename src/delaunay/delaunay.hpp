// The Delaunay stage: every point in, an exact Delaunay triangulation out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::delaunay {

// What z a vertex gets when several points share its exact x, y.
enum class DuplicatePolicy { first, min, max, mean };

struct DelaunayOptions {
  DuplicatePolicy on_duplicate = DuplicatePolicy::mean;
  bool keep_point_map = false;   // fill DelaunayResult::vertex_of_point
  bool keep_duplicates = false;  // fill DelaunayResult::duplicates
  // From this many points on, split them in two halves triangulated by two threads and merged
  // (parallel_delaunay.hpp); 0 always tries, SIZE_MAX never.
  std::size_t parallel_min_points = 50000;
  // Threads the stage may use (BuildOptions::threads); 0 = every core, 1 = the sequential path.
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

// Triangulates `points` (consumed, to keep the peak memory low). Vertices are renumbered in
// spatial (Hilbert) order. Throws GeometryError for fewer than 3 distinct points, all points
// collinear, or a non-finite coordinate.
DelaunayResult triangulate(std::vector<Point3>&& points, const DelaunayOptions& options = {},
                           const ProgressFn* progress = nullptr);

}  // namespace tincdt::delaunay
