// The final TIN as the web-terrain pyramid reads it: its kept triangles with the vertices in
// longitude and latitude on WGS 84 (degrees) and heights in metres, a grid index over them, the
// height anywhere (the fill height beyond the data) and the TIN's section along a meridian or a
// parallel, which both tiles beside a tile border read alike.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/lon_lat.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::web_terrain {

using io::terrain::GeoRectangle;

// Metres per degree of latitude, near enough for spacing and tolerance estimates.
inline constexpr double kMetresPerDegree = 111320.0;

// A point of a section: its place along the line (latitude along a meridian, longitude along a
// parallel) and its height.
struct SectionPoint {
  double at;
  double height;
  bool on_constraint = false;  // where a constrained edge (a contour, a hard line) meets the line
};

class TerrainSource {
 public:
  // TIN's kept triangles, its coordinates in CRS_WKT transformed (InputError naming WHAT when
  // there is no CRS or PROJ fails); beyond them FILL_HEIGHT, by default the lowest of their
  // heights. PROJ runs on THREADS threads (0 = one per core).
  TerrainSource(const mesh::Triangulation& tin, const std::string& crs_wkt, const std::string& what,
                std::optional<double> fill_height, std::size_t threads = 1);

  const std::vector<Point3>& vertices() const { return vertices_; }
  const GeoRectangle& bounds() const { return bounds_; }
  const io::terrain::HeightUnits& units() const { return units_; }
  double fill_height() const { return fill_height_; }
  std::size_t triangle_count() const { return triangles_.size(); }

  // The TIN's height at LON, LAT, or the fill height outside every triangle.
  double height_at(double lon, double lat) const;

  // Whether LON, LAT is in a triangle the TIN removed (clip, erase, --max-edge): a hole, which
  // the tiles leave without triangles too.
  bool in_hole(double lon, double lat) const;

  // The vertices inside RECTANGLE (sides included), cell by cell of the index: an order that
  // depends on the TIN only.
  std::vector<std::uint32_t> vertices_in(const GeoRectangle& rectangle) const;

  // The TIN's section along the meridian LON = AT (ALONG_MERIDIAN) or the parallel LAT = AT,
  // from FROM to TO (FROM < TO): where the line crosses an edge or meets a vertex, strictly
  // between the ends, sorted; the ends with height_at(). The same arguments give the same points.
  std::vector<SectionPoint> section(bool along_meridian, double at, double from, double to) const;
  // The vertices within HALF_WIDTH of that line, strictly between FROM and TO, where the line
  // beside them is outside the TIN and in no hole: the data's outline just inside the line,
  // which a tile's grid puts on the line, so that the line carries the data's heights there, not
  // the fill's. Each at its place along the line, sorted.
  std::vector<SectionPoint> outline_beside(bool along_meridian, double at, double from, double to,
                                           double half_width) const;

  // The constrained edges (contours, hard lines) of kept triangles and the outline of the holes
  // (clip, erase, --max-edge), each from its lower-numbered vertex, and those whose box meets
  // RECTANGLE, ascending.
  const std::vector<std::array<std::uint32_t, 2>>& constrained_edges() const {
    return constrained_;
  }
  std::vector<std::uint32_t> constrained_edges_in(const GeoRectangle& rectangle) const;
  // Whether constrained edge E (an index into constrained_edges()) only bounds a hole, no
  // contour, hard line, clip or erase ring: --max-edge's outline, the hull beside a hole.
  bool outline_only(std::uint32_t e) const { return outline_only_[e] != 0; }
  bool is_constrained(std::uint32_t a, std::uint32_t b) const;

  // The mean spacing of the vertices in metres: the square root of the triangles' area per
  // vertex.
  double point_spacing_metres() const;

 private:
  struct Cells {
    double west = 0, south = 0, width = 1, height = 1;
    std::uint32_t across = 1, down = 1;
    std::vector<std::uint32_t> begin;  // CSR: cell c holds items[begin[c], begin[c + 1])
    std::vector<std::uint32_t> items;
  };
  // The cells' geometry over the bounds, the same for the four indexes; then their contents.
  void set_cells();
  void build_index();
  // Numbers the vertices cell by cell (rows south to north, each west to east), in a cell by
  // longitude, then latitude: a tile's vertices are a few runs of the array, read in order, and
  // the numbers, which break ties between vertices, depend on the TIN alone, not on the order
  // it stores them in. Renumbers the triangles and NUMBER (the TIN's vertex to ours).
  void number_by_cell(std::vector<std::uint32_t>& number);
  void collect_holes(const mesh::Triangulation& tin, const std::vector<std::uint32_t>& number,
                     const std::string& crs_wkt, const std::string& what);
  void collect_constraints(const mesh::Triangulation& tin,
                           const std::vector<std::uint32_t>& number);
  // The TIN's height at LON, LAT, none outside every triangle.
  std::optional<double> tin_height(double lon, double lat) const;
  std::uint32_t column(double lon) const;
  std::uint32_t row(double lat) const;
  template <class F>
  void for_cells(const GeoRectangle& r, const Cells& cells, F&& f) const;

  std::vector<Point3> vertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;    // counter-clockwise in lon/lat
  std::vector<std::array<std::uint32_t, 2>> constrained_;  // sorted
  // Sorted: the edges of constrained_ that are no kept triangle's, a hole's side on the hull.
  std::vector<std::array<std::uint32_t, 2>> hull_outline_;
  std::vector<std::uint8_t> outline_only_;    // per constrained_ edge
  std::vector<std::array<Point2, 3>> holes_;  // removed triangles, counter-clockwise
  std::vector<std::uint8_t> on_constraint_;   // per vertex
  GeoRectangle bounds_{0, 0, 0, 0};
  io::terrain::HeightUnits units_;
  double fill_height_;
  Cells triangle_cells_;
  Cells vertex_cells_;  // no items: cell c holds the vertices numbered begin[c] to begin[c + 1]
  Cells constraint_cells_;
  Cells hole_cells_;
};

}  // namespace tincdt::web_terrain
