#include "terrain/hull_cut.hpp"

#include <algorithm>
#include <cmath>

#include "predicates/predicates.hpp"

namespace tincdt::terrain {
namespace {

using predicates::orient2d;

// Where p -> q crosses the line through a and b (p and q on opposite sides): the point of the
// line (exactly on it when the line is axis-parallel, as a box's edges are), z interpolated
// along p -> q.
Point3 crossing(Point3 p, Point3 q, Point2 a, Point2 b) {
  const double ux = q.x - p.x, uy = q.y - p.y, vx = b.x - a.x, vy = b.y - a.y;
  const double wx = a.x - p.x, wy = a.y - p.y;
  const double denominator = ux * vy - uy * vx;
  const double s = (wx * uy - wy * ux) / denominator;  // along a -> b
  double t = (wx * vy - wy * vx) / denominator;        // along p -> q
  if (!(t >= 0)) t = 0;  // rounding (or 0 / 0) when p or q is almost on the line
  if (t > 1) t = 1;
  if (!std::isfinite(s)) return {p.x + t * ux, p.y + t * uy, p.z + t * (q.z - p.z)};
  return {a.x + s * vx, a.y + s * vy, p.z + t * (q.z - p.z)};
}

// A vertex of a ring being cut, with the hull edges (indices) whose lines it was made on: none
// for the ring's own vertices, one where the ring crosses a hull edge's line, two where a
// stretch along one edge's line (made by an earlier cut) meets the next edge: a hull corner.
struct CutVertex {
  Point3 p;
  int on[2] = {-1, -1};
};

int common_line(const CutVertex& a, const CutVertex& b) {
  for (const int l : a.on)
    if (l >= 0 && (l == b.on[0] || l == b.on[1])) return l;
  return -1;
}

}  // namespace

bool zero_area(const std::vector<Point3>& ring) {
  const Point2 a{ring[0].x, ring[0].y}, b{ring[1].x, ring[1].y};
  return std::all_of(ring.begin() + 2, ring.end(), [&](const Point3& p) {
    return orient2d(a, b, {p.x, p.y}) == 0;
  });
}

// The TIN's convex hull, counter-clockwise, without collinear vertices (the fewest half-planes).
std::vector<Point2> strict_hull(const mesh::Triangulation& tin) {
  const auto slots = static_cast<EdgeId>(3 * tin.triangle_slots());
  EdgeId start = kNoId;
  for (EdgeId e = 0; e < slots && start == kNoId; ++e)
    if (tin.apex(e) == mesh::kInfinite && tin.origin(e) != mesh::kInfinite) start = e;
  std::vector<Point2> hull;
  if (start == kNoId) return hull;
  // Ghost (u, v, inf) lies outside hull edge v -> u; the next ghost, (v, w, inf), is across
  // v -> inf. The chain u, v, w, ... runs clockwise.
  EdgeId e = start;
  do {
    hull.push_back(tin.point(tin.origin(e)));
    e = mesh::next_edge(tin.twin(mesh::next_edge(e)));
  } while (e != start && hull.size() <= tin.vertex_count());
  std::reverse(hull.begin(), hull.end());
  // Drop collinear vertices; on a convex polygon one pass finds them all.
  std::vector<Point2> strict;
  const std::size_t n = hull.size();
  for (std::size_t i = 0; i < n; ++i)
    if (orient2d(hull[(i + n - 1) % n], hull[i], hull[(i + 1) % n]) != 0) strict.push_back(hull[i]);
  // From the least point: the cuts (and interior_point) then depend on the hull alone, not on
  // where its first ghost happens to lie in memory.
  const auto least = std::min_element(strict.begin(), strict.end(), xy_less);
  std::rotate(strict.begin(), least, strict.end());
  return strict;
}

bool inside_or_on(const std::vector<Point2>& hull, Point2 p) {
  for (std::size_t i = 0; i < hull.size(); ++i)
    if (orient2d(hull[i], hull[(i + 1) % hull.size()], p) < 0) return false;
  return true;
}

// A point strictly inside the hull (a hull vertex if the hull is too thin to find one).
Point2 interior_point(const std::vector<Point2>& hull) {
  for (std::size_t i = 1; i + 1 < hull.size(); ++i) {
    const Point2 a = hull[0], b = hull[i], c = hull[i + 1];
    const Point2 m{a.x + ((b.x - a.x) + (c.x - a.x)) / 3, a.y + ((b.y - a.y) + (c.y - a.y)) / 3};
    bool strictly = true;
    for (std::size_t k = 0; k < hull.size() && strictly; ++k)
      strictly = orient2d(hull[k], hull[(k + 1) % hull.size()], m) > 0;
    if (strictly) return m;
  }
  return hull.front();
}

// The part of RING inside the hull: empty when that encloses no area (the ring lies outside, or
// only touches the hull). Where the cut ring follows the hull, its corners are the hull's own
// vertices (so the TIN's vertices there are reused, with their z); where the ring crosses the
// hull, the crossing's z is interpolated along the ring.
std::vector<Point3> cut_to_hull(const std::vector<Point3>& ring, const std::vector<Point2>& hull,
                                Point2 inside) {
  const int n = static_cast<int>(hull.size());
  std::vector<CutVertex> cut, next;
  for (const Point3& p : ring) cut.push_back({p});
  for (int i = 0; i < n && !cut.empty(); ++i) {
    const Point2 a = hull[i], b = hull[(i + 1) % n];
    next.clear();
    for (std::size_t k = 0; k < cut.size(); ++k) {
      const CutVertex& p = cut[k];
      const CutVertex& q = cut[(k + 1) % cut.size()];
      const bool p_in = orient2d(a, b, {p.p.x, p.p.y}) >= 0;
      const bool q_in = orient2d(a, b, {q.p.x, q.p.y}) >= 0;
      if (p_in) next.push_back(p);
      if (p_in == q_in) continue;
      CutVertex x{crossing(p.p, q.p, a, b), {i, -1}};
      if (const int l = common_line(p, q); l >= 0) {
        x.on[1] = l;
        // Along edge l's line, meeting edge i's: their shared hull vertex (edges i - 1 and i
        // share hull[i]; edges 0 and n - 1 share hull[0]); other pairs meet outside the hull,
        // where a later edge cuts them off.
        const int corner = (l + 1) % n == i ? i : ((i + 1) % n == l ? l : -1);
        if (corner >= 0) x.p.x = hull[corner].x, x.p.y = hull[corner].y;
      }
      next.push_back(x);
    }
    cut.swap(next);
  }
  std::vector<Point3> out;
  for (const CutVertex& v : cut) {
    Point3 p = v.p;
    if (!inside_or_on(hull, {p.x, p.y})) {  // a crossing rounded outside: move it in
      const Point3 r = p;
      for (int k = 52; k >= 0; --k) {
        const double f = std::ldexp(1.0, -k);
        p.x = r.x + (inside.x - r.x) * f;
        p.y = r.y + (inside.y - r.y) * f;
        if (inside_or_on(hull, {p.x, p.y})) break;
      }
      if (!inside_or_on(hull, {p.x, p.y})) p.x = inside.x, p.y = inside.y;
    }
    if (out.empty() || out.back().x != p.x || out.back().y != p.y) out.push_back(p);
  }
  while (out.size() > 1 && out.back().x == out.front().x && out.back().y == out.front().y)
    out.pop_back();
  if (out.size() < 3 || zero_area(out)) out.clear();
  return out;
}

}  // namespace tincdt::terrain
