#include "tiles/tile_rules.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "predicates/predicates.hpp"

namespace tincdt::tiles {
namespace {

constexpr double kEps = 0x1p-52;  // one ulp of 1.0: a generous bound per rounding

}  // namespace

std::int64_t TileGrid::cell_of(double v) const {
  auto i = static_cast<std::int64_t>(std::floor(v / size));
  // The quotient can round across an edge: settle with the edges themselves.
  while (edge(i) > v) --i;
  while (edge(i + 1) <= v) ++i;
  return i;
}

Point2 owner_point(Point2 a, Point2 b, Point2 c) {
  if (xy_less(b, a)) std::swap(a, b);
  if (xy_less(c, b)) std::swap(b, c);
  if (xy_less(b, a)) std::swap(a, b);
  return {(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
}

Disk circumdisk_bound(Point2 a, Point2 b, Point2 c) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Relative to a: the translated coordinates carry a relative error of one rounding each.
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double d = 2.0 * (bx * cy - by * cx);
  const double d_mag = 2.0 * (std::fabs(bx * cy) + std::fabs(by * cx));
  // |computed d - d| <= ~6 eps d_mag (the inputs' error included): below that, no sign, no bound.
  if (!(std::fabs(d) > 64.0 * kEps * d_mag)) return {{a.x, a.y}, kInf};
  const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
  // First-order bounds: each numerator is off by ~8 eps of its magnitude, d by ~6 eps of d_mag;
  // 32 covers both with room, and the guard on d keeps the second-order terms below it.
  const double inv_d = 1.0 / std::fabs(d);
  const double ex =
      32.0 * kEps * (std::fabs(cy) * b2 + std::fabs(by) * c2 + std::fabs(ux) * d_mag) * inv_d;
  const double ey =
      32.0 * kEps * (std::fabs(bx) * c2 + std::fabs(cx) * b2 + std::fabs(uy) * d_mag) * inv_d;
  const Point2 centre{a.x + ux, a.y + uy};
  // The true disk passes through a and is centred within (ex, ey) of a + (ux, uy): it lies in the
  // disk around the computed centre of radius |u| + 2 (ex + ey), plus the roundings of the centre
  // and of the comparisons that will use it.
  const double slack = 8.0 * kEps *
                       (std::fabs(a.x) + std::fabs(a.y) + std::fabs(ux) + std::fabs(uy) +
                        std::fabs(centre.x) + std::fabs(centre.y));
  const double radius = std::sqrt(ux * ux + uy * uy) * (1.0 + 8.0 * kEps) + 2.0 * (ex + ey) + slack;
  if (!std::isfinite(radius) || !std::isfinite(centre.x) || !std::isfinite(centre.y))
    return {{a.x, a.y}, kInf};
  return {centre, radius};
}

bool inside(const Disk& d, const BBox& b) {
  // The radius' slack covers the rounding of these differences.
  return d.centre.x - d.radius > b.min_x && d.centre.x + d.radius < b.max_x &&
         d.centre.y - d.radius > b.min_y && d.centre.y + d.radius < b.max_y;
}

bool misses(const Disk& d, const BBox& r) {
  if (!std::isfinite(d.radius)) return false;
  const double dx = std::max({r.min_x - d.centre.x, 0.0, d.centre.x - r.max_x});
  const double dy = std::max({r.min_y - d.centre.y, 0.0, d.centre.y - r.max_y});
  return std::hypot(dx, dy) > d.radius * (1.0 + 8.0 * kEps);
}

double reach_beyond(const Disk& d, const BBox& q) {
  return std::max({q.min_x - (d.centre.x - d.radius), d.centre.x + d.radius - q.max_x,
                   q.min_y - (d.centre.y - d.radius), d.centre.y + d.radius - q.max_y, 0.0});
}

std::vector<BBox> data_outside(const std::vector<BBox>& data, const BBox& b) {
  std::vector<BBox> out;
  for (const BBox& r : data) {
    if (empty(r)) continue;
    if (r.min_x <= b.min_x) out.push_back({r.min_x, r.min_y, std::min(r.max_x, b.min_x), r.max_y});
    if (r.max_x >= b.max_x) out.push_back({std::max(r.min_x, b.max_x), r.min_y, r.max_x, r.max_y});
    if (r.min_y <= b.min_y) out.push_back({r.min_x, r.min_y, r.max_x, std::min(r.max_y, b.min_y)});
    if (r.max_y >= b.max_y) out.push_back({r.min_x, std::max(r.min_y, b.max_y), r.max_x, r.max_y});
  }
  return out;
}

bool reaches_left_of(Point2 u, Point2 v, const BBox& r) {
  const Point2 corners[4] = {
      {r.min_x, r.min_y}, {r.max_x, r.min_y}, {r.max_x, r.max_y}, {r.min_x, r.max_y}};
  for (const Point2& p : corners)
    if (predicates::orient2d(u, v, p) > 0) return true;
  return false;
}

bool box_inside(const BBox& r, const Polygon& p) {
  if (p.size() < 3 || empty(r)) return false;
  const Point2 corners[4] = {
      {r.min_x, r.min_y}, {r.max_x, r.min_y}, {r.max_x, r.max_y}, {r.min_x, r.max_y}};
  for (std::size_t i = 0; i < p.size(); ++i)
    for (const Point2& c : corners)
      if (predicates::orient2d(p[i], p[(i + 1) % p.size()], c) <= 0) return false;
  return true;
}

Polygon box_polygon(const BBox& b) {
  if (empty(b)) return {};
  return {{b.min_x, b.min_y}, {b.max_x, b.min_y}, {b.max_x, b.max_y}, {b.min_x, b.max_y}};
}

namespace {

// Signed distance of P from the line a -> b, positive on the left; length must be |b - a|.
double side(Point2 a, Point2 b, double length, Point2 p) {
  return ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / length;
}

// A bound on the rounding of side() for these points.
double side_error(Point2 a, Point2 b, Point2 p) {
  return 16 * kEps *
         (std::fabs(a.x) + std::fabs(a.y) + std::fabs(b.x) + std::fabs(b.y) + std::fabs(p.x) +
          std::fabs(p.y));
}

double distance_to_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

}  // namespace

Polygon clip_left(const Polygon& p, Point2 a, Point2 b, double grow) {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  if (p.empty() || !(length > 0)) return p;
  Polygon out;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 u = p[i], v = p[(i + 1) % n];
    const double su = side(a, b, length, u) + grow, sv = side(a, b, length, v) + grow;
    if (su >= 0) out.push_back(u);
    if ((su >= 0) != (sv >= 0)) {
      const double t = su / (su - sv);
      out.push_back({u.x + t * (v.x - u.x), u.y + t * (v.y - u.y)});
    }
  }
  return out;
}

bool may_meet(const Disk& d, const Polygon& p, double margin) {
  if (p.empty()) return false;
  if (!std::isfinite(d.radius)) return true;
  const std::size_t n = p.size();
  bool inside = true;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 u = p[i], v = p[(i + 1) % n];
    const double length = std::hypot(v.x - u.x, v.y - u.y);
    if (length > 0 && side(u, v, length, d.centre) < 0) inside = false;
    nearest = std::min(nearest, distance_to_segment(d.centre, u, v));
  }
  return inside || nearest <= d.radius + margin;
}

bool may_meet(Point2 a, Point2 b, Point2 c, const Polygon& p, double margin) {
  if (p.empty()) return false;
  // Separating axes: an edge of either with the other wholly beyond it (by more than MARGIN).
  const auto separates = [margin](Point2 u, Point2 v, const Point2* q, std::size_t m) {
    const double length = std::hypot(v.x - u.x, v.y - u.y);
    if (!(length > 0)) return false;
    for (std::size_t i = 0; i < m; ++i)
      if (side(u, v, length, q[i]) > -margin) return false;
    return true;
  };
  const Point2 tri[3] = {a, b, c};
  for (int i = 0; i < 3; ++i)
    if (separates(tri[i], tri[(i + 1) % 3], p.data(), p.size())) return false;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (separates(p[i], p[(i + 1) % p.size()], tri, 3)) return false;
  return true;
}

bool may_meet_left(Point2 u, Point2 v, const Polygon& p, double margin) {
  const double length = std::hypot(v.x - u.x, v.y - u.y);
  if (!(length > 0)) return !p.empty();
  for (const Point2& q : p)
    if (side(u, v, length, q) > -margin) return true;
  return false;
}

bool Rim::holds(Point2 p) const {
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Point2 a = hull[i], b = hull[(i + 1) % hull.size()];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (side(a, b, length, p) <= width) return true;
  }
  return false;
}

Polygon Rim::inner() const {
  if (hull.size() < 3) return {};
  BBox b;
  for (const Point2& p : hull) b.add(p.x, p.y);
  Polygon out = box_polygon(b);
  for (std::size_t i = 0; i < hull.size() && !out.empty(); ++i) {
    const Point2 a = hull[i], c = hull[(i + 1) % hull.size()];
    const double length = std::hypot(c.x - a.x, c.y - a.y);
    // holds() refuses points whose computed distance exceeds the width; their true distance
    // exceeds it less a rounding bound: shrink by the width less that bound.
    const double err = side_error(a, c, {b.max_x, b.max_y}) + side_error(a, c, {b.min_x, b.min_y});
    const double shift = width - err;
    const Point2 nx{-(c.y - a.y) / length * shift, (c.x - a.x) / length * shift};  // left normal
    out = clip_left(out, {a.x + nx.x, a.y + nx.y}, {c.x + nx.x, c.y + nx.y}, err);
  }
  return out;
}

std::vector<Point2> convex_hull(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(), xy_less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  // Andrew's monotone chain: lower hull left to right, then upper hull right to left.
  std::vector<Point2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && predicates::orient2d(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && predicates::orient2d(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

bool meets_convex(const BBox& r, const std::vector<Point2>& hull) {
  if (hull.size() < 3 || empty(r)) return false;
  BBox hb;
  for (const Point2& p : hull) hb.add(p.x, p.y);
  if (!(r.min_x < hb.max_x && hb.min_x < r.max_x && r.min_y < hb.max_y && hb.min_y < r.max_y))
    return false;
  // Separating axes: the box's (tested above) and each hull edge's outward normal.
  const Point2 corners[4] = {
      {r.min_x, r.min_y}, {r.max_x, r.min_y}, {r.max_x, r.max_y}, {r.min_x, r.max_y}};
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Point2 u = hull[i], v = hull[(i + 1) % hull.size()];
    bool all_outside = true;
    for (const Point2& p : corners)
      if (predicates::orient2d(u, v, p) > 0) all_outside = false;
    if (all_outside) return false;
  }
  return true;
}

}  // namespace tincdt::tiles
