// Contour lines traced on a TIN: for each level base + k * interval, or each of a list of fixed
// levels, the line where the TIN's linear surface crosses it, as polylines (closed rings stay
// closed).
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

// Segments a trace may make (one per level crossing a triangle): about 16 bytes each in
// memory and 24 to 40 in a file, so 0.8 GB or so at the bound. An interval far below the TIN's
// detail (0.001 m on a hill of 1,000 points: 5e7 segments) would otherwise fill the disk.
inline constexpr std::uint64_t kMaxContourSegments = 20'000'000;

struct ContourOptions {
  double interval = 0;              // > 0, unless levels are given
  double base = 0;                  // levels are base + k * interval, k any integer
  std::vector<double> levels = {};  // fixed levels (any order) instead of base + k * interval
  std::uint64_t max_segments = kMaxContourSegments;
  unsigned threads = 0;                  // 0 = every hardware thread
  const ProgressFn* progress = nullptr;  // stage "contours"
};

struct ContourLine {
  double level;
  bool closed;        // a ring: its last point repeats its first
  std::size_t first;  // its points are ContourSet::points[first, first + count)
  std::size_t count;  // >= 2; >= 4 for a ring

  bool operator==(const ContourLine&) const = default;
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

// The segments a trace would make: the sum over the kept triangles of the levels crossing each.
// Cheap (no tracing). Throws as trace_contours, but never for the bound.
std::uint64_t count_contour_segments(const mesh::Triangulation& tin, const ContourOptions& options);

// Throws Error for an interval that is not a positive finite number, a non-finite base or
// level, more than 10^7 levels between the lowest and highest kept vertex, or more than
// options.max_segments segments (the estimate in the message, before any tracing); Cancelled
// when the progress callback says stop (it is asked at least every 2^16 triangles).
ContourSet trace_contours(const mesh::Triangulation& tin, const ContourOptions& options);

}  // namespace tincdt::products
