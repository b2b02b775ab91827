// Contour lines traced on a TIN: for each level base + k * interval, the line where the TIN's
// linear surface crosses it, as polylines (closed rings stay closed).
//
// Each kept triangle crossed by a level gives one segment between the crossings on two of its
// edges; segments are chained through the shared edges (twins), so no point matching is needed.
// Where a vertex lies exactly on a level, the vertex counts as above it (symbolic perturbation:
// z + tiny). Then every crossed edge has one end strictly below and one at or above the level,
// each crossed triangle exactly two crossed edges, and the chains are the level set of the
// perturbed surface: simple curves that never cross or branch. Geometrically, a crossing next to
// a vertex on the level is that vertex itself; this only makes zero-length pieces, which are
// dropped, except along a ridge exactly at the level (lower ground on both sides), which the
// chains would follow twice, once on each side: those halves are left out and the chains
// spliced at the ridge's ends (contours.cpp). So lines through a vertex on the level pass
// exactly through it, a line along a flat edge at the level follows it exactly once, flat
// triangles at the level are outlined on their lower side, a ridge or a valley exactly at the
// level gives no line (no ground above, resp. below, it), and nothing is duplicated, broken or of
// zero length.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::products {

struct ContourOptions {
  double interval = 0;                   // > 0
  double base = 0;                       // levels are base + k * interval, k any integer
  unsigned threads = 0;                  // 0 = every hardware thread
  const ProgressFn* progress = nullptr;  // stage "contours"
};

struct ContourLine {
  double level;
  bool closed;        // a ring: its last point repeats its first
  std::size_t first;  // its points are ContourSet::points[first, first + count)
  std::size_t count;  // >= 2; >= 4 for a ring
};

// Lines ordered by level, then as traced. Along every line the ground above the level is on the
// left (so rings around hills run counter-clockwise).
struct ContourSet {
  std::vector<ContourLine> lines;
  std::vector<Point2> points;
  std::uint64_t levels = 0;  // levels between the lowest and highest kept vertex
};

// Level number k: base + k * interval, the one formula the tracer and its tests use.
inline double contour_level(double base, double interval, std::int64_t k) {
  return base + static_cast<double>(k) * interval;
}

// Throws Error for an interval that is not a positive finite number, a non-finite base, or more
// than 10^7 levels between the lowest and highest kept vertex.
ContourSet trace_contours(const mesh::Triangulation& tin, const ContourOptions& options);

}  // namespace tincdt::products
