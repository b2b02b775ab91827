// Quality statistics of a TIN (the "quality" block of --stats): shape of the triangles, flat
// triangles, edge lengths, area. Only kept triangles count (not ghosts, not removed ones).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

struct QualityReport {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::uint64_t triangles = 0;
  std::uint64_t vertices = 0;  // vertices that are a corner of a kept triangle
  double area_2d = 0;          // horizontal area of the kept triangles
  double area_3d = 0;          // surface area of the same triangles

  // Angles (degrees) of every corner of every triangle; NaN without triangles.
  double min_angle_deg = kNaN;
  double max_angle_deg = kNaN;
  std::array<std::uint64_t, 18> angle_histogram{};  // bin k: [10k, 10k + 10) degrees, 180 in 17
  std::uint64_t triangles_below_20deg = 0;          // smallest angle < 20 degrees
  // Circumradius / inradius: 2 for an equilateral triangle, large for slivers.
  double max_radius_ratio = kNaN;

  // Three corners at the same z and, when contour flags were given, all three on contours.
  std::uint64_t flat_triangles = 0;
  bool flats_need_contours = false;  // whether the contour flags were part of the rule

  // Edges of the kept triangles, each counted once (horizontal length).
  std::uint64_t edges = 0;
  double min_edge_length = kNaN;
  double mean_edge_length = kNaN;
  double max_edge_length = kNaN;
  // Log-spaced bins, four per decade, on the grid 10^(k/4) so that reports of different TINs
  // share bin edges: edge_length_bin_edges has one more entry than edge_length_histogram; bin i
  // holds lengths in [edges[i], edges[i + 1]).
  std::vector<double> edge_length_bin_edges;
  std::vector<std::uint64_t> edge_length_histogram;

  // One JSON object (no trailing newline), keys as the members above; NaN becomes null.
  std::string to_json() const;
};

// Measures the kept triangles of `tin` in one pass on THREADS (0 = every core), with the same
// result for any thread count. `on_contour`, when given, flags the vertices that lie on contour
// lines (index = VertexId; vertices past its end count as not on a contour), and a triangle is
// then flat only if its three corners are flagged and share one z. Angles are compared through
// dot products and squared lengths; only the smallest and largest are measured in degrees.
QualityReport measure_quality(const mesh::Triangulation& tin,
                              const std::vector<std::uint8_t>* on_contour = nullptr,
                              unsigned threads = 0);

// The flat-triangle rule shared with flats.hpp.
inline bool is_flat(const mesh::Triangulation& tin, const std::array<VertexId, 3>& c,
                    const std::vector<std::uint8_t>* on_contour) {
  if (tin.z(c[0]) != tin.z(c[1]) || tin.z(c[0]) != tin.z(c[2])) return false;
  if (!on_contour) return true;
  for (VertexId v : c)
    if (v >= on_contour->size() || !(*on_contour)[v]) return false;
  return true;
}

}  // namespace tincdt::terrain
