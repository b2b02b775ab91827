// The triangulation: flat arrays of 32-bit ids, built for flips, walks and constraint flags.
//
// Triangles are stored as three corners each, counter-clockwise seen from above. Half-edge
// e = 3 * t + i runs from corner i to corner i + 1 (mod 3) of triangle t; twin(e) is the same
// edge seen from the neighbouring triangle. The convex hull is closed by "ghost" triangles whose
// third vertex is kInfinite, so every half-edge has a twin and there are no boundary special
// cases in the hot loops. A ghost (u, v, kInfinite) lies outside hull edge v -> u: its "circle"
// is the open half-plane left of u -> v plus the open segment uv.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tincdt::mesh {

inline constexpr VertexId kInfinite = kNoId - 1;

inline constexpr EdgeId next_edge(EdgeId e) {
  return e % 3 == 2 ? e - 2 : e + 1;
}
inline constexpr EdgeId prev_edge(EdgeId e) {
  return e % 3 == 0 ? e + 2 : e - 1;
}
inline constexpr TriangleId triangle_of(EdgeId e) {
  return e / 3;
}

struct ValidateOptions {
  bool delaunay = true;  // also check that every unconstrained edge is locally Delaunay
};

class Triangulation {
 public:
  // ---- vertices -------------------------------------------------------------------------
  std::size_t vertex_count() const { return xy_.size(); }
  Point2 point(VertexId v) const { return xy_[v]; }
  double z(VertexId v) const { return z_[v]; }
  const std::vector<Point2>& points() const { return xy_; }
  const std::vector<double>& heights() const { return z_; }
  VertexId add_vertex(Point2 p, double z);
  void set_z(VertexId v, double z) { z_[v] = z; }
  void reserve_vertices(std::size_t n);

  // ---- triangles and half-edges ---------------------------------------------------------
  // Triangle slots, ghosts included.
  std::size_t triangle_slots() const { return corner_.size() / 3; }
  VertexId origin(EdgeId e) const { return corner_[e]; }
  VertexId dest(EdgeId e) const { return corner_[next_edge(e)]; }
  VertexId apex(EdgeId e) const { return corner_[prev_edge(e)]; }
  EdgeId twin(EdgeId e) const { return twin_[e]; }
  std::array<VertexId, 3> triangle(TriangleId t) const {
    return {corner_[3 * t], corner_[3 * t + 1], corner_[3 * t + 2]};
  }
  bool is_ghost(TriangleId t) const {
    return corner_[3 * t] == kInfinite || corner_[3 * t + 1] == kInfinite ||
           corner_[3 * t + 2] == kInfinite;
  }
  // Real (finite, not removed) triangles.
  std::size_t triangle_count() const { return real_triangles_; }

  // Calls f(TriangleId, std::array<VertexId, 3>) for every real triangle that is not removed,
  // corners counter-clockwise.
  template <class F>
  void for_each_triangle(F&& f) const {
    const std::size_t n = triangle_slots();
    for (std::size_t t = 0; t < n; ++t) {
      const auto tri = triangle(static_cast<TriangleId>(t));
      if (tri[0] >= kInfinite || tri[1] >= kInfinite || tri[2] >= kInfinite) continue;
      if (!removed_.empty() && removed_[t]) continue;
      f(static_cast<TriangleId>(t), tri);
    }
  }

  // ---- removal (clip, erase, long-edge trimming) ----------------------------------------
  // A removed triangle keeps its place in the topology (so walks, flips and validate() work as
  // before) but is no part of the TIN: for_each_triangle() and the writers skip it.
  bool is_removed(TriangleId t) const { return !removed_.empty() && removed_[t] != 0; }
  void set_removed(TriangleId t, bool on);
  // True for a real triangle that is not removed.
  bool is_kept(TriangleId t) const { return !is_ghost(t) && !is_removed(t); }

  // ---- constraints ----------------------------------------------------------------------
  bool has_constraints() const { return !constrained_.empty(); }
  bool is_constrained(EdgeId e) const { return !constrained_.empty() && constrained_[e] != 0; }
  // Marks both half-edges of e.
  void set_constrained(EdgeId e, bool on);
  // Calls f(EdgeId) once per constrained edge (the half-edge with origin < dest).
  template <class F>
  void for_each_constrained_edge(F&& f) const {
    for (std::size_t e = 0; e < constrained_.size(); ++e)
      if (constrained_[e] && corner_[e] < corner_[next_edge(static_cast<EdgeId>(e))])
        f(static_cast<EdgeId>(e));
  }

  // ---- editing (used by the Delaunay and constraint stages) -------------------------------
  // Appends a triangle with corners a, b, c (CCW) and no twins yet; returns its id.
  TriangleId add_triangle(VertexId a, VertexId b, VertexId c);
  // Appends COUNT slots with no corners and no twins (kNoId), for a builder that fills them.
  void add_empty_triangles(std::size_t count);
  void set_corners(TriangleId t, VertexId a, VertexId b, VertexId c);
  void link(EdgeId e, EdgeId f) {
    twin_[e] = f;
    twin_[f] = e;
  }
  void reserve_triangles(std::size_t n);
  // Drops the slots from SLOTS on, which must be unused: no twin set, not counted as triangles
  // (slots made for more points than turned out distinct).
  void truncate_triangles(std::size_t slots);
  void set_corner(EdgeId e, VertexId v) { corner_[e] = v; }
  // Flips the diagonal of the convex quadrilateral around e. With e = a -> b in triangle
  // (a, b, c) and its twin b -> a in (b, a, d), the two slots become (d, c, a) and (c, d, b),
  // each rotated so that e keeps its index and now runs d -> c (its twin c -> d). Outer
  // half-edges keep their twins and constraint flags: in e's triangle, next(e) = c -> a and
  // prev(e) = a -> d; in the twin's, next = d -> b and prev = b -> c.
  void flip(EdgeId e);
  // Any half-edge leaving v: an index built on demand (on THREADS, 0 = all), then kept up to
  // date by flip() and PointInserter.
  void build_vertex_index(unsigned threads = 0);
  bool has_vertex_index() const { return !vertex_edge_.empty(); }
  EdgeId edge_from(VertexId v) const { return vertex_edge_[v]; }
  void set_edge_from(VertexId v, EdgeId e) { vertex_edge_[v] = e; }
  // The half-edge u -> v, or kNoId; needs the vertex index. Costs the degree of u.
  EdgeId find_edge(VertexId u, VertexId v) const;
  // Recounts the real triangles (after bulk edits).
  void recount();

  // Raw arrays for the writers and the hot loops of the builders.
  const std::vector<VertexId>& corners() const { return corner_; }

  // ---- checks -------------------------------------------------------------------------------
  // Empty if the triangulation is valid, otherwise a description of the first problem found:
  // twin symmetry, CCW real triangles, a convex hull closed by ghosts, Euler's formula, every
  // vertex used, and (optionally) every unconstrained edge locally Delaunay.
  std::string validate(ValidateOptions options = {}) const;

  // Memory held by the arrays, in bytes.
  std::size_t memory_bytes() const;

 private:
  std::vector<Point2> xy_;
  std::vector<double> z_;
  std::vector<VertexId> corner_;           // 3 per triangle slot
  std::vector<EdgeId> twin_;               // 3 per triangle slot
  std::vector<std::uint8_t> constrained_;  // 3 per triangle slot, empty until constraints exist
  std::vector<EdgeId> vertex_edge_;        // empty until build_vertex_index()
  std::vector<std::uint8_t> removed_;      // 1 per triangle slot, empty until a removal
  std::size_t real_triangles_ = 0;
};

}  // namespace tincdt::mesh
