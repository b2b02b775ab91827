// Inserting one point into a (constrained) Delaunay triangulation: locate, split, restore.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/triangulation.hpp"

namespace tincdt::mesh {

struct Location {
  enum Kind { in_triangle, on_edge, on_vertex } kind;
  EdgeId edge;  // in_triangle: an edge of that triangle (a ghost's finite edge outside the hull);
                // on_edge: the edge p lies on; on_vertex: an edge leaving that vertex
};

// Locates by walking from the last triangle it made, splits the triangle (or edge) holding the
// point into a fan and Lawson-flips the fan's outer edges until each is locally Delaunay or
// constrained. Ghost triangles make points outside the hull the same case as points inside.
// Splitting a constrained edge leaves both halves constrained.
class PointInserter {
 public:
  explicit PointInserter(Triangulation& tin) : tin_(tin) { stack_.reserve(64); }
  // Takes new triangles from the pre-sized slots first_slot, first_slot + 1, ... instead of
  // appending them, so that two inserters can fill disjoint ranges of one Triangulation at once.
  // (Triangle counts are then left to Triangulation::recount().)
  PointInserter(Triangulation& tin, TriangleId first_slot) : tin_(tin), next_slot_(first_slot) {
    stack_.reserve(64);
  }
  // The slot the next new triangle takes, in the pre-sized mode.
  TriangleId next_slot() const { return next_slot_; }

  // Starts an empty triangulation with the counter-clockwise triangle (a, b, c).
  void start(VertexId a, VertexId b, VertexId c);

  // Where p is, walking from `hint` (a triangle) or from the last triangle made.
  // On a Delaunay triangulation the walk visits edges in a fixed order (fastest); with
  // constraints it picks its first edge at random, which terminates on any triangulation.
  Location locate(Point2 p, TriangleId hint = kNoId);

  // Inserts existing vertex v (not yet in any triangle) at its location.
  void insert(VertexId v, const Location& at);
  void insert(VertexId v) { insert(v, locate(tin_.point(v))); }

  // Flips counted since construction.
  std::uint64_t flips() const { return flips_; }

 private:
  template <int K>
  void make_fan(const VertexId (&ring)[K], const EdgeId (&outer)[K], const TriangleId (&slots)[K],
                VertexId v);
  void restore(Point2 p);
  TriangleId new_slot(VertexId a, VertexId b, VertexId c);

  Triangulation& tin_;
  std::vector<EdgeId> stack_;
  TriangleId last_ = 0;
  std::uint64_t flips_ = 0;
  std::uint64_t random_ = 0x9e3779b97f4a7c15ULL;
  TriangleId next_slot_ = kNoId;  // kNoId: append
};

}  // namespace tincdt::mesh
