#include "tiles/plan_rim.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "predicates/predicates.hpp"
#include "tiles/tile_rules.hpp"

namespace tincdt::tiles::detail {
namespace {

constexpr double kEps = 0x1p-52;

// The edges of a convex polygon as unit left normals: distance(p) = n . (p - a), positive inside.
struct Edges {
  struct Edge {
    Point2 a;
    double nx, ny;
  };
  std::vector<Edge> edges;
  explicit Edges(const std::vector<Point2>& poly) {
    for (std::size_t i = 0; i < poly.size() && poly.size() >= 3; ++i) {
      const Point2 a = poly[i], b = poly[(i + 1) % poly.size()];
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      edges.push_back({a, -(b.y - a.y) / length, (b.x - a.x) / length});
    }
  }
  // The smallest distance of P to an edge line, stopping once it is at most LIMIT.
  double nearest(Point2 p, double limit) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Edge& e : edges) {
      best = std::min(best, e.nx * (p.x - e.a.x) + e.ny * (p.y - e.a.y));
      if (best <= limit) break;
    }
    return best;
  }
};

double magnitude(const BBox& b) {
  return std::max(
      {std::fabs(b.min_x), std::fabs(b.max_x), std::fabs(b.min_y), std::fabs(b.max_y), 1.0});
}

}  // namespace

PointScan scan_points(const std::string& path, const io::PointFilter& filter, double width,
                      unsigned threads, const std::vector<Point2>& hull) {
  const io::CopcNodes copc(path);
  if (!copc.nodes().empty()) return scan_copc(copc, filter, width, threads, hull);
  std::vector<Point3> points;
  io::read_points(path, filter, points, threads);
  return measure_points(points, width);
}

PointScan measure_points(const std::vector<Point3>& points, double width) {
  PointScan s;
  s.points = points.size();
  if (points.empty()) return s;
  // The extremes in eight directions span an octagon inside the hull; the points strictly
  // inside it cannot be hull vertices (Akl and Toussaint, 1978).
  std::size_t ext[8] = {};
  const auto key = [](const Point3& p, int k) {
    switch (k) {
      case 0:
        return p.x;
      case 1:
        return -p.x;
      case 2:
        return p.y;
      case 3:
        return -p.y;
      case 4:
        return p.x + p.y;
      case 5:
        return -(p.x + p.y);
      case 6:
        return p.x - p.y;
      default:
        return p.y - p.x;
    }
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    s.bounds.add(points[i].x, points[i].y);
    for (int k = 0; k < 8; ++k)
      if (key(points[i], k) > key(points[ext[k]], k)) ext[k] = i;
  }
  std::vector<Point2> extremes;
  for (const std::size_t i : ext) extremes.push_back({points[i].x, points[i].y});
  const std::vector<Point2> octagon = tiles::convex_hull(extremes);
  std::vector<Point2> survivors = extremes;
  for (const Point3& p : points) {
    const Point2 q{p.x, p.y};
    bool inside = octagon.size() >= 3;
    for (std::size_t k = 0; k < octagon.size() && inside; ++k)
      inside = predicates::orient2d(octagon[k], octagon[(k + 1) % octagon.size()], q) > 0;
    if (!inside) survivors.push_back(q);
  }
  s.hull = tiles::convex_hull(std::move(survivors));

  // Points near the hull's boundary: the octagon lies inside the hull, so a point deeper than
  // WIDTH inside the octagon is deeper still inside the hull.
  const double err = 64 * kEps * magnitude(s.bounds);
  const double limit = width + 4 * err;
  const Edges oct(octagon), hull(s.hull);
  for (const Point3& p : points) {
    const Point2 q{p.x, p.y};
    if (oct.edges.size() >= 3 && oct.nearest(q, limit) > limit) continue;
    if (hull.edges.size() < 3 || hull.nearest(q, limit) <= limit) s.near_outline.push_back(p);
  }
  return s;
}

bool deep_inside(const BBox& b, const std::vector<Point2>& hull, double width) {
  if (hull.size() < 3 || tiles::empty(b)) return false;
  const Edges e(hull);
  const double limit = width + 64 * kEps * magnitude(b) * 4;
  const Point2 corners[4] = {
      {b.min_x, b.min_y}, {b.max_x, b.min_y}, {b.max_x, b.max_y}, {b.min_x, b.max_y}};
  for (const Point2& c : corners)
    if (e.nearest(c, limit) <= limit) return false;
  return true;
}

}  // namespace tincdt::tiles::detail
