#include "terrain/polygons.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "predicates/predicates.hpp"
#include "terrain/regions.hpp"

namespace tincdt::terrain {

using mesh::Triangulation;
using predicates::orient2d;

PolygonIndex::PolygonIndex(const std::vector<Polygon>& polygons) : polygon_count_(polygons.size()) {
  BBox box;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    for (std::size_t r = 0; r < polygons[i].rings.size(); ++r) {
      const auto& ring = polygons[i].rings[r];
      const std::string name = "polygon " + count_text(i) + ", ring " + count_text(r);
      std::vector<Point2> pts;
      pts.reserve(ring.size());
      for (const Point2& p : ring) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
          throw GeometryError(name + " has a non-finite coordinate");
        if (pts.empty() || !(pts.back() == p)) pts.push_back(p);
      }
      while (pts.size() > 1 && pts.back() == pts.front()) pts.pop_back();
      if (pts.size() < 3) throw GeometryError(name + " has fewer than 3 distinct points");
      for (std::size_t k = 0; k < pts.size(); ++k) {
        const Point2 a = pts[k], b = pts[(k + 1) % pts.size()];
        edges_.push_back({a, b, std::max(a.x, b.x), static_cast<std::uint32_t>(i)});
        box.add(a.x, a.y);
      }
    }
  }
  if (edges_.empty()) return;  // no polygons: nothing is inside
  min_x_ = box.min_x;
  max_x_ = box.max_x;
  min_y_ = box.min_y;
  max_y_ = box.max_y;

  // Strip count: about one strip per two edges, fewer when long edges would be copied into many
  // strips (keeps the index at a few entries per edge whatever the shapes).
  const double height = max_y_ - min_y_;
  double spanned = 0;
  for (const Edge& e : edges_) spanned += std::fabs(e.b.y - e.a.y);
  const double n = static_cast<double>(edges_.size());
  double strips = std::max(1.0, n / 2);
  if (spanned > 0) strips = std::min(strips, std::max(1.0, 4 * n * height / spanned));
  strips = std::min(strips, double{1 << 20});
  const auto count = height > 0 ? static_cast<std::size_t>(strips) : std::size_t{1};
  strip_height_ = height > 0 ? height / static_cast<double>(count) : 1;
  strip_start_.assign(count + 1, 0);

  // Two passes (count, fill) into one array: strip_of is monotone in y, so an edge is in every
  // strip a query point within its y-range can map to.
  for (const Edge& e : edges_) {
    const std::size_t lo = strip_of(std::min(e.a.y, e.b.y)), hi = strip_of(std::max(e.a.y, e.b.y));
    for (std::size_t s = lo; s <= hi; ++s) ++strip_start_[s + 1];
  }
  for (std::size_t s = 0; s < count; ++s) strip_start_[s + 1] += strip_start_[s];
  strip_edges_.resize(strip_start_.back());
  std::vector<std::uint32_t> fill(strip_start_.begin(), strip_start_.end() - 1);
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    const Edge& e = edges_[i];
    const std::size_t lo = strip_of(std::min(e.a.y, e.b.y)), hi = strip_of(std::max(e.a.y, e.b.y));
    for (std::size_t s = lo; s <= hi; ++s) strip_edges_[fill[s]++] = static_cast<std::uint32_t>(i);
  }
}

std::size_t PolygonIndex::strip_of(double y) const {
  const double s = std::floor((y - min_y_) / strip_height_);
  const auto last = static_cast<double>(strip_start_.size() - 2);
  return static_cast<std::size_t>(std::clamp(s, 0.0, last));
}

std::uint32_t PolygonIndex::query(Point2 p, bool boundary_counts) const {
  if (edges_.empty() || p.y < min_y_ || p.y > max_y_ || p.x < min_x_ || p.x > max_x_) return kNoId;
  // Polygon ids of the crossings right of p (and of rings p lies on); a polygon holds p when
  // its id occurs an odd number of times.
  thread_local std::vector<std::uint32_t> hits;
  hits.clear();
  std::uint32_t on_boundary = kNoId;
  const std::size_t s = strip_of(p.y);
  for (std::uint32_t k = strip_start_[s]; k < strip_start_[s + 1]; ++k) {
    const Edge& e = edges_[strip_edges_[k]];
    if (e.max_x < p.x) continue;  // wholly left of p: neither crossed nor touched
    const bool a_below = e.a.y <= p.y, b_below = e.b.y <= p.y;
    if (a_below == b_below) {
      // Not straddling p's horizontal line, but p may still lie on it (horizontal edges, or p at
      // the upper end).
      if (boundary_counts && (e.a.y == p.y || e.b.y == p.y) && orient2d(e.a, e.b, p) == 0 &&
          std::min(e.a.x, e.b.x) <= p.x)
        on_boundary = on_boundary == kNoId ? e.polygon : std::max(on_boundary, e.polygon);
      continue;
    }
    const int o = orient2d(e.a, e.b, p);
    if (o == 0) {  // p on the edge (within its y-range and on its line)
      if (boundary_counts)
        on_boundary = on_boundary == kNoId ? e.polygon : std::max(on_boundary, e.polygon);
      // For the parity, a point on the edge is "left" of it: consistent, and the polygon the
      // edge belongs to is decided by on_boundary anyway when boundaries count.
    }
    // Upward edge (a below): the crossing is right of p when p is left of a -> b; downward, when
    // p is right of a -> b.
    if (a_below ? o > 0 : o < 0) hits.push_back(e.polygon);
  }
  std::sort(hits.begin(), hits.end());
  std::uint32_t best = on_boundary;
  for (std::size_t i = 0; i < hits.size();) {
    std::size_t j = i;
    while (j < hits.size() && hits[j] == hits[i]) ++j;
    if ((j - i) % 2 == 1 && (best == kNoId || hits[i] > best)) best = hits[i];
    i = j;
  }
  return best;
}

std::uint32_t PolygonIndex::polygon_at(Point2 p) const {
  return query(p, false);
}
std::uint32_t PolygonIndex::polygon_at_or_on(Point2 p) const {
  return query(p, true);
}

namespace {

Point2 centroid(const Triangulation& tin, const std::array<VertexId, 3>& c) {
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  // Relative to a: large map coordinates lose no digits to the sum.
  return {a.x + ((b.x - a.x) + (d.x - a.x)) / 3, a.y + ((b.y - a.y) + (d.y - a.y)) / 3};
}

bool strictly_inside(const Triangulation& tin, const std::array<VertexId, 3>& c, Point2 p) {
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
  return orient2d(a, b, p) > 0 && orient2d(b, d, p) > 0 && orient2d(d, a, p) > 0;
}

}  // namespace

// With the rings in the TIN as constrained edges, no triangle's interior meets a ring, so all
// triangles connected across unconstrained edges (a "region") lie in the same polygons. One
// point-in-polygon test per region does: at the centroid of the region's largest triangle. Why
// that point: it is checked with orient2d to be strictly inside its triangle, hence on no ring
// (rings run along edges), so the exact test's answer holds for the whole triangle and region;
// and of all the region's centroids it is the farthest from the triangle's edges, so neither the
// rounding of the centroid nor a ring vertex displaced by an ulp (a constraint crossing rounded
// to doubles) can put it on the wrong side. A centroid of a sliver could fail both ways. Should
// the check ever fail (a region of slivers only), that region falls back to per-triangle tests.
std::vector<std::uint32_t> classify_triangles(const Triangulation& tin, const PolygonIndex& index,
                                              const PolygonOptions& options) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<std::uint32_t> result(slots, kNoId);
  const auto by_centroid = [&](TriangleId t) {
    result[t] = index.polygon_at(centroid(tin, tin.triangle(t)));
  };
  const auto skipped = [&options](TriangleId t) { return options.within && !(*options.within)[t]; };
  if (!options.boundaries_constrained) {
    for (TriangleId t = 0; t < slots; ++t)
      if (!tin.is_ghost(t) && !skipped(t)) by_centroid(t);
    return result;
  }

  for_each_region(
      tin, [&](TriangleId t) { return !skipped(t); },
      [&](std::span<const TriangleId> members) {
        const auto corners = tin.triangle(largest_triangle(tin, members));
        const Point2 c = centroid(tin, corners);
        if (strictly_inside(tin, corners, c)) {
          const std::uint32_t polygon = index.polygon_at(c);
          for (TriangleId t : members) result[t] = polygon;
        } else {
          for (TriangleId t : members) by_centroid(t);
        }
      });
  return result;
}

namespace {

std::uint64_t remove_where(Triangulation& tin, const std::vector<Polygon>& polygons,
                           const PolygonOptions& options, bool inside) {
  const PolygonIndex index(polygons);
  const std::vector<std::uint32_t> cls = classify_triangles(tin, index, options);
  std::uint64_t removed = 0;
  for (TriangleId t = 0; t < cls.size(); ++t) {
    if (!tin.is_kept(t) || (cls[t] != kNoId) != inside) continue;
    tin.set_removed(t, true);
    ++removed;
  }
  return removed;
}

// z_of(polygon index) -> the z to give a vertex of that polygon.
template <class ZOf>
std::uint64_t set_z_where(Triangulation& tin, const std::vector<Polygon>& polygons,
                          const PolygonOptions& options, ZOf z_of) {
  const PolygonIndex index(polygons);
  const std::size_t nv = tin.vertex_count();
  std::vector<std::uint32_t> owner(nv, kNoId);
  if (options.boundaries_constrained) {
    // A vertex is on or inside a polygon exactly when it is a corner of a triangle inside it
    // (rings are edges of the TIN). This also catches vertices made at constraint crossings on a
    // ring, which may sit an ulp off the exact ring line.
    const std::vector<std::uint32_t> cls = classify_triangles(tin, index, options);
    for (TriangleId t = 0; t < cls.size(); ++t) {
      if (cls[t] == kNoId) continue;
      for (VertexId v : tin.triangle(t))
        if (owner[v] == kNoId || cls[t] > owner[v]) owner[v] = cls[t];
    }
  } else {
    for (VertexId v = 0; v < nv; ++v) owner[v] = index.polygon_at_or_on(tin.point(v));
  }
  if (const std::vector<std::uint32_t>* known = options.vertex_polygons)
    for (VertexId v = 0; v < nv && v < known->size(); ++v)
      if ((*known)[v] != kNoId && (owner[v] == kNoId || (*known)[v] > owner[v]))
        owner[v] = (*known)[v];
  std::uint64_t set = 0;
  for (VertexId v = 0; v < nv; ++v) {
    if (owner[v] == kNoId) continue;
    tin.set_z(v, z_of(owner[v]));
    ++set;
  }
  return set;
}

}  // namespace

std::uint64_t remove_outside(Triangulation& tin, const std::vector<Polygon>& polygons,
                             const PolygonOptions& options) {
  return remove_where(tin, polygons, options, false);
}

std::uint64_t remove_inside(Triangulation& tin, const std::vector<Polygon>& polygons,
                            const PolygonOptions& options) {
  return remove_where(tin, polygons, options, true);
}

std::uint64_t set_z_inside(Triangulation& tin, const std::vector<Polygon>& polygons, double z,
                           const PolygonOptions& options) {
  if (!std::isfinite(z)) throw GeometryError("replace polygons need a finite z");
  return set_z_where(tin, polygons, options, [z](std::uint32_t) { return z; });
}

std::uint64_t set_polygon_z_inside(Triangulation& tin, const std::vector<Polygon>& polygons,
                                   const PolygonOptions& options) {
  for (std::size_t i = 0; i < polygons.size(); ++i)
    if (!std::isfinite(polygons[i].z))
      throw GeometryError("replace polygon " + count_text(i) + " has no finite z");
  return set_z_where(tin, polygons, options,
                     [&polygons](std::uint32_t i) { return polygons[i].z; });
}

}  // namespace tincdt::terrain
