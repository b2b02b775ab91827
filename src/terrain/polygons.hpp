// Area features (clip, erase and replace polygons): which triangles and vertices of the TIN lie
// inside a set of polygons, and what to do with them.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

// One polygon: any number of rings, each a list of points in either orientation (a repeated
// closing point is allowed and ignored). Inside means the even-odd rule over all of its rings,
// so a hole is just another ring and no ring needs to be oriented or nested "properly".
struct Polygon {
  std::vector<std::vector<Point2>> rings;
  double z = std::numeric_limits<double>::quiet_NaN();  // for set_polygon_z_inside
};

// The ring edges of a polygon set in horizontal strips, so that a point-in-polygon test looks at
// the few edges whose y-range holds the point instead of all of them. The test is exact: the
// ray to +x crosses edge a -> b when the y-range [a.y, b.y) (half-open, so a ray through a ring
// vertex counts once) holds p.y and orient2d puts p on the edge's left (upward edge) or right
// (downward edge); both are exact comparisons of the input doubles.
class PolygonIndex {
 public:
  // Throws GeometryError for a ring with fewer than 3 distinct points or a non-finite coordinate
  // (naming the polygon and ring).
  explicit PolygonIndex(const std::vector<Polygon>& polygons);

  // The last polygon (largest index) whose interior holds p, or kNoId. "Last" is the precedence
  // rule for overlapping polygons: later ones are painted over earlier ones. A point exactly on a
  // ring is not in that polygon's interior.
  std::uint32_t polygon_at(Point2 p) const;
  // Like polygon_at, but a point on a ring edge (or vertex) counts as inside that polygon.
  std::uint32_t polygon_at_or_on(Point2 p) const;

  std::size_t polygon_count() const { return polygon_count_; }
  std::size_t edge_count() const { return edges_.size(); }

 private:
  struct Edge {
    Point2 a, b;
    double max_x;
    std::uint32_t polygon;
  };
  std::uint32_t query(Point2 p, bool boundary_counts) const;
  std::size_t strip_of(double y) const;

  std::vector<Edge> edges_;
  std::vector<std::uint32_t> strip_start_;  // CSR: strip s holds strip_edges_[start[s], start[s+1])
  std::vector<std::uint32_t> strip_edges_;
  double min_y_ = 0, max_y_ = 0, min_x_ = 0, max_x_ = 0, strip_height_ = 1;
  std::size_t polygon_count_ = 0;
};

struct PolygonOptions {
  // The caller has inserted every ring as constrained edges (the pipeline does, for clip, erase
  // and replace polygons). Then no triangle straddles a ring, and one test per region of
  // triangles connected across unconstrained edges classifies them all (fast, and exact: see
  // polygons.cpp). Set false for rings that are not in the TIN: each triangle is then classified
  // by its own centroid and each vertex by its own point-in-polygon test, which is slower and
  // only as good as a triangle-by-centroid approximation of the outline can be.
  bool boundaries_constrained = true;
  // The triangles to classify (1 per slot; null: all), each region of them connected across
  // unconstrained edges tested at a point of its own: a job over part of the data passes those
  // proven to be the whole job's, which a region of its other triangles could misjudge (they
  // may straddle a ring it did not read). The others count as outside every polygon.
  const std::vector<std::uint8_t>* within = nullptr;
  // Replace: the polygon (index, kNoId for none) of each vertex as known from outside this TIN
  // (1 per vertex; null: none known). A job over part of the data passes it for the vertices
  // on its border, around which it holds only its own side's triangles; each vertex takes the
  // later of this and its own triangles' polygon.
  const std::vector<std::uint32_t>* vertex_polygons = nullptr;
};

// Clip: removes every kept triangle outside all the polygons. Returns triangles removed.
std::uint64_t remove_outside(mesh::Triangulation& tin, const std::vector<Polygon>& polygons,
                             const PolygonOptions& options = {});

// Erase: removes every kept triangle inside a polygon (buildings, lakes as no-data).
std::uint64_t remove_inside(mesh::Triangulation& tin, const std::vector<Polygon>& polygons,
                            const PolygonOptions& options = {});

// Replace: sets every vertex on or inside a polygon to `z` (a lake surface, a flat pad).
// Returns the number of vertices set (on or inside), whether or not their z was already z.
std::uint64_t set_z_inside(mesh::Triangulation& tin, const std::vector<Polygon>& polygons, double z,
                           const PolygonOptions& options = {});

// Replace with each polygon's own z (Polygon::z, which must be finite); where polygons overlap
// or share a boundary, the last one wins.
std::uint64_t set_polygon_z_inside(mesh::Triangulation& tin, const std::vector<Polygon>& polygons,
                                   const PolygonOptions& options = {});

// The polygon (index, or kNoId for none) of every triangle slot, by the rules above; ghost slots
// get kNoId. Exposed for callers that need the classification itself (diagnostics, tests).
std::vector<std::uint32_t> classify_triangles(const mesh::Triangulation& tin,
                                              const PolygonIndex& index,
                                              const PolygonOptions& options = {});

}  // namespace tincdt::terrain
