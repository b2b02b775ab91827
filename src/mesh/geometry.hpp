// Geometric tests on a Triangulation that know about the vertex at infinity.
#pragma once

#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::mesh {

// True if q lies strictly inside segment uv, given that u, v, q are collinear.
inline bool strictly_between(Point2 u, Point2 v, Point2 q) {
  if (u.x != v.x) return (u.x < q.x && q.x < v.x) || (v.x < q.x && q.x < u.x);
  return (u.y < q.y && q.y < v.y) || (v.y < q.y && q.y < u.y);
}

// +1 if finite q lies inside the circle of triangle (a, b, c), given CCW, -1 outside. A real
// triangle's circle is tested with predicates::incircle_perturbed: a point on it counts as inside
// or outside by the symbolic perturbation that makes the Delaunay triangulation unique (0 only for
// q on the line of a degenerate triangle). For a ghost (u, v, inf) the circle is the open
// half-plane left of u -> v plus the open segment uv (the limit of circles through u and v as the
// third point goes to infinity), tested exactly: the hull is never perturbed.
inline int in_circle(const Triangulation& tin, VertexId a, VertexId b, VertexId c, Point2 q) {
  if (c == kInfinite || a == kInfinite || b == kInfinite) {
    const VertexId u = a == kInfinite ? b : (b == kInfinite ? c : a);
    const VertexId v = a == kInfinite ? c : (b == kInfinite ? a : b);
    const Point2 pu = tin.point(u), pv = tin.point(v);
    const int o = predicates::orient2d(pu, pv, q);
    if (o != 0) return o;
    return strictly_between(pu, pv, q) ? 1 : -1;
  }
  return predicates::incircle_perturbed(tin.point(a), tin.point(b), tin.point(c), q);
}

// Whether the edge e may stay: its twin's apex is not inside the (perturbed) circle of e's
// triangle. The answer is the same from both sides of e, and every edge of the unique perturbed
// Delaunay triangulation, and only those, may stay. An edge of the hull (one apex infinite)
// always may; between two ghosts this is the convexity of the hull at their shared vertex.
inline bool is_locally_delaunay(const Triangulation& tin, EdgeId e) {
  const VertexId d = tin.apex(tin.twin(e));
  if (d == kInfinite) return true;
  const VertexId a = tin.origin(e), b = tin.dest(e), c = tin.apex(e);
  if (c == kInfinite && a != kInfinite && b != kInfinite) return true;
  return in_circle(tin, a, b, c, tin.point(d)) <= 0;
}

}  // namespace tincdt::mesh
