#include "terrain/interpolate.hpp"
#include "core/xorshift.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "predicates/predicates.hpp"

namespace tincdt::terrain {

using mesh::Triangulation;
using predicates::orient2d;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Along edge u-v at p (on it), from its lesser end: the same double from either triangle.
double edge_z(const Triangulation& tin, VertexId u, VertexId v, Point2 p) {
  if (xy_less(tin.point(v), tin.point(u))) std::swap(u, v);
  const Point2 a = tin.point(u), b = tin.point(v);
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy);
  return tin.z(u) + t * (tin.z(v) - tin.z(u));
}

// The plane through the corners of t, at p. Barycentric weights from 2x2 determinants of
// coordinate differences relative to one corner, so map coordinates of 10^6 lose no digits.
// The corners are taken from the least, and a point on an edge from that edge alone, so that
// every TIN that holds the triangle (a tile's, the whole one) gives the same double.
double plane_z(const Triangulation& tin, TriangleId t, Point2 p) {
  auto c = tin.triangle(t);
  for (int i = 0; i < 3; ++i)
    if (orient2d(tin.point(c[i]), tin.point(c[(i + 1) % 3]), p) == 0)
      return edge_z(tin, c[i], c[(i + 1) % 3], p);
  const int least = xy_less(tin.point(c[1]), tin.point(c[0]))
                        ? (xy_less(tin.point(c[2]), tin.point(c[1])) ? 2 : 1)
                        : (xy_less(tin.point(c[2]), tin.point(c[0])) ? 2 : 0);
  std::rotate(c.begin(), c.begin() + least, c.end());
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  const double ux = b.x - a.x, uy = b.y - a.y, vx = d.x - a.x, vy = d.y - a.y;
  const double wx = p.x - a.x, wy = p.y - a.y;
  const double det = ux * vy - uy * vx;  // > 0: real triangles are counter-clockwise
  const double lb = (wx * vy - wy * vx) / det, ld = (ux * wy - uy * wx) / det;
  const double za = tin.z(c[0]);
  return za + lb * (tin.z(c[1]) - za) + ld * (tin.z(c[2]) - za);
}

}  // namespace

TriangleId SurfaceSampler::locate(Point2 p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) return kNoId;
  const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
  TriangleId t = start_ < slots ? start_ : kNoId;
  if (t == kNoId || tin_.is_ghost(t)) {
    for (t = 0; t < slots && tin_.is_ghost(t); ++t) {
    }
    if (t == slots) return kNoId;
  }
  // Visibility walk: step across an edge that has p strictly on its far side. The first edge to
  // test is picked at random: with a fixed order this walk can cycle forever on a triangulation
  // that is not Delaunay (constrained TINs, swapped flats); randomised, it ends with probability
  // one, and on real data after about as many steps as the fixed order.
  EdgeId from = kNoId;
  for (;;) {
    const auto first = static_cast<EdgeId>(random_edge(random_));
    EdgeId crossed = kNoId;
    for (EdgeId i = 0; i < 3 && crossed == kNoId; ++i) {
      const EdgeId e = 3 * t + (first + i) % 3;
      if (e == from) continue;  // entered through it: p is on its inner side
      if (orient2d(tin_.point(tin_.origin(e)), tin_.point(tin_.dest(e)), p) < 0) crossed = e;
    }
    if (crossed == kNoId) break;
    from = tin_.twin(crossed);
    const TriangleId next = mesh::triangle_of(from);
    // p is strictly outside a hull edge: the hull is convex, so p is outside the TIN.
    if (tin_.is_ghost(next)) return kNoId;
    start_ = t = next;
  }
  start_ = t;
  return t;
}

double SurfaceSampler::z_at(Point2 p) {
  found_ = kNoId;
  TriangleId t = locate(p);
  if (t == kNoId) return kNaN;
  if (tin_.is_removed(t)) {
    // On an edge shared with a kept triangle, p is on the kept surface's boundary: use that.
    TriangleId kept = kNoId;
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const TriangleId n = mesh::triangle_of(tin_.twin(e));
      if (tin_.is_kept(n) && orient2d(tin_.point(tin_.origin(e)), tin_.point(tin_.dest(e)), p) == 0)
        kept = n;
    }
    if (kept == kNoId) return kNaN;
    t = kept;
  }
  found_ = t;
  return plane_z(tin_, t, p);
}

double interpolate_z(const Triangulation& tin, Point2 p, TriangleId hint) {
  SurfaceSampler sampler(tin, hint);
  return sampler.z_at(p);
}

}  // namespace tincdt::terrain
