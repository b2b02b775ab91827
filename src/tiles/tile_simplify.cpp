#include "tiles/tile_simplify.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "pipeline/surface.hpp"
#include "predicates/predicates.hpp"
#include "simplify/profile.hpp"
#include "simplify/simplify.hpp"
#include "simplify/simplify_input.hpp"
#include "terrain/polygons.hpp"
#include "tiles/tile_job.hpp"

namespace tincdt::tiles::detail {
namespace {

using mesh::Triangulation;
using predicates::orient2d;

double across(const Side& s, Point2 p) {
  return s.vertical ? p.x : p.y;
}
double along(const Side& s, Point2 p) {
  return s.vertical ? p.y : p.x;
}
Point2 point_on(const Side& s, double place) {
  return s.vertical ? Point2{s.at, place} : Point2{place, s.at};
}

// Where edge P-Q crosses the side's line strictly between its ends: (place along the line,
// height). From the ends in (x, y) order, so that every tile computes the same doubles.
std::optional<std::pair<double, double>> crossing(const Side& s, Point2 p, double zp, Point2 q,
                                                  double zq) {
  if (xy_less(q, p)) {
    std::swap(p, q);
    std::swap(zp, zq);
  }
  const double cp = across(s, p), cq = across(s, q);
  if (!((cp < s.at && s.at < cq) || (cq < s.at && s.at < cp))) return std::nullopt;
  const double t = (s.at - cp) / (cq - cp);
  return std::pair{along(s, p) + t * (along(s, q) - along(s, p)), zp + t * (zq - zp)};
}

// The height of edge P-Q at C, a point on it: from the ends in (x, y) order.
double edge_height(Point2 p, double zp, Point2 q, double zq, Point2 c) {
  if (xy_less(q, p)) {
    std::swap(p, q);
    std::swap(zp, zq);
  }
  const double t = q.x != p.x ? (c.x - p.x) / (q.x - p.x) : (c.y - p.y) / (q.y - p.y);
  return zp + t * (zq - zp);
}

// The height of the plane through the three corners at C: from the corners in (x, y) order.
double plane_height(std::array<Point3, 3> p, Point2 c) {
  std::sort(p.begin(), p.end(), [](const Point3& a, const Point3& b) {
    return xy_less({a.x, a.y}, {b.x, b.y});
  });
  const double ux = p[1].x - p[0].x, uy = p[1].y - p[0].y, uz = p[1].z - p[0].z;
  const double vx = p[2].x - p[0].x, vy = p[2].y - p[0].y, vz = p[2].z - p[0].z;
  const double det = ux * vy - uy * vx;
  const double gx = (uz * vy - uy * vz) / det, gy = (ux * vz - uz * vx) / det;
  return p[0].z + gx * (c.x - p[0].x) + gy * (c.y - p[0].y);
}

// The TIN's height at C, by a rule of the triangle (or edge, or vertex) holding it alone;
// nothing outside the TIN.
std::optional<double> height_at(const Triangulation& tin, Point2 c) {
  for (std::size_t t = 0; t < tin.triangle_slots(); ++t) {
    if (tin.is_ghost(static_cast<TriangleId>(t))) continue;
    const auto v = tin.triangle(static_cast<TriangleId>(t));
    const Point2 p[3] = {tin.point(v[0]), tin.point(v[1]), tin.point(v[2])};
    if (c.x < std::min({p[0].x, p[1].x, p[2].x}) || c.x > std::max({p[0].x, p[1].x, p[2].x}) ||
        c.y < std::min({p[0].y, p[1].y, p[2].y}) || c.y > std::max({p[0].y, p[1].y, p[2].y}))
      continue;
    int o[3];
    for (int i = 0; i < 3; ++i) o[i] = orient2d(p[i], p[(i + 1) % 3], c);
    if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;
    for (int i = 0; i < 3; ++i)
      if (p[i] == c) return tin.z(v[i]);
    for (int i = 0; i < 3; ++i)
      if (o[i] == 0)
        return edge_height(p[i], tin.z(v[i]), p[(i + 1) % 3], tin.z(v[(i + 1) % 3]), c);
    return plane_height({Point3{p[0].x, p[0].y, tin.z(v[0])}, Point3{p[1].x, p[1].y, tin.z(v[1])},
                         Point3{p[2].x, p[2].y, tin.z(v[2])}},
                        c);
  }
  return std::nullopt;
}

// ---- the tile's points ------------------------------------------------------------------------

// The points of the tile's greedy run: the border vertices (kept), the TIN's vertices strictly
// inside the tile (candidates).
using TilePoints = simplify::SimplifyInput;

// The tile's sides, counter-clockwise from the south west corner; north and west run backwards
// (each side's section is computed by increasing place, as its other tile computes it).
struct TileSides {
  std::array<Side, 4> side;
  std::array<bool, 4> backwards{false, false, true, true};
  explicit TileSides(const BBox& b)
      : side{Side{false, b.min_y, b.min_x, b.max_x, b.max_y - b.min_y},
             Side{true, b.max_x, b.min_y, b.max_y, b.max_x - b.min_x},
             Side{false, b.max_y, b.min_x, b.max_x, b.max_y - b.min_y},
             Side{true, b.min_x, b.min_y, b.max_y, b.max_x - b.min_x}} {}
};

bool in_closed(const BBox& b, Point2 p) {
  return b.min_x <= p.x && p.x <= b.max_x && b.min_y <= p.y && p.y <= b.max_y;
}

// The tile's border: each side's section simplified at TOLERANCE, its points kept and chained
// by segments, counter-clockwise around the tile; the hull edges the tile takes whole (see
// TurnedEnd).
struct Border {
  double error = 0;                                            // the largest of a section point
  std::vector<std::pair<std::uint32_t, std::uint32_t>> chain;  // the tile on the left
  // Each border point (a tile point) and what it lies on in the TIN (SectionPoint).
  struct Place {
    std::uint32_t point;
    VertexId vertex;
    EdgeId edge;
  };
  std::vector<Place> places;
  std::vector<std::pair<Point2, Point2>> whole_edges;
  std::optional<Point2> stuck;  // Section::stuck, of any side
};

Border add_border(const Triangulation& tin, const BBox& box, const TileSides& sides,
                  std::span<const std::uint8_t> on_constraint, double tolerance,
                  TilePoints& points) {
  Border border;
  for (int k = 0; k < 4; ++k) {
    const Side& side = sides.side[k];
    const Section section = tin_section(tin, side, on_constraint);
    if (section.stuck) border.stuck = section.stuck;
    std::vector<double> place, height;
    std::vector<std::uint8_t> forced;
    for (const SectionPoint& s : section.points) {
      place.push_back(s.along);
      height.push_back(s.z);
      forced.push_back(s.forced ? 1 : 0);
    }
    const std::vector<std::size_t> kept =
        simplify::simplify_profile(place, height, tolerance, forced);
    for (std::size_t j = 1; j < kept.size(); ++j) {
      const std::size_t a = kept[j - 1], b = kept[j];
      const double slope = (height[b] - height[a]) / (place[b] - place[a]);
      for (std::size_t i = a + 1; i < b; ++i)
        border.error = std::max(border.error,
                                std::fabs(height[i] - (height[a] + slope * (place[i] - place[a]))));
    }
    std::vector<std::pair<Point3, SectionPoint>> path;  // the point, what it lies on
    if (section.first) path.push_back({section.first->vertex, {.vertex = section.first->id}});
    for (const std::size_t i : kept) {
      const Point2 p = point_on(side, place[i]);
      path.push_back({{p.x, p.y, height[i]}, section.points[i]});
    }
    if (section.last) path.push_back({section.last->vertex, {.vertex = section.last->id}});
    if (sides.backwards[k]) std::reverse(path.begin(), path.end());
    std::uint32_t previous = kNoId;
    for (const auto& [p, on] : path) {
      const std::uint32_t id = points.add_kept({p.x, p.y}, p.z);
      border.places.push_back({id, on.vertex, on.edge});
      if (previous != kNoId && previous != id) {
        points.segments.push_back({previous, id, 0});
        border.chain.push_back({previous, id});
      }
      previous = id;
    }
    for (const std::optional<TurnedEnd>& end : {section.first, section.last})
      if (end && !in_closed(box, {end->vertex.x, end->vertex.y}))
        border.whole_edges.push_back({end->hull_a, end->hull_b});
  }
  return border;
}

// The parts of constrained edge A-B in the tile's closed box, as pairs of the tile's points:
// cut where the edge crosses the sides (the same doubles as the sections') and at a corner on it.
// IA, IB: the tile's points at A and B (kNoId: none).
std::vector<std::pair<std::uint32_t, std::uint32_t>> cut_to_tile(
    const BBox& box, const TileSides& sides, const TilePoints& points, const Border& border,
    Point2 a, double za, std::uint32_t ia, Point2 b, double zb, std::uint32_t ib) {
  for (const auto& [p, q] : border.whole_edges)
    if ((p == a && q == b) || (p == b && q == a)) {
      const std::uint32_t u = ia != kNoId ? ia : points.find(a);
      const std::uint32_t v = ib != kNoId ? ib : points.find(b);
      if (u == kNoId || v == kNoId)
        throw InternalError(
            "tile simplification: a hull edge the tile takes whole ends outside it");
      return {{u, v}};
    }
  const double dx = b.x - a.x, dy = b.y - a.y;
  struct On {
    double place;  // along A-B
    Point2 at;
    std::uint32_t id;
  };
  std::vector<On> on;
  const auto add = [&](Point2 p, std::uint32_t id) {
    on.push_back({(p.x - a.x) * dx + (p.y - a.y) * dy, p, id != kNoId ? id : points.find(p)});
  };
  if (in_closed(box, a)) add(a, ia);
  if (in_closed(box, b)) add(b, ib);
  // A crossing the border turned away from (TurnedEnd) is no point of the tile.
  for (const Side& s : sides.side)
    if (const auto c = crossing(s, a, za, b, zb);
        c && s.lo <= c->first && c->first <= s.hi && points.find(point_on(s, c->first)) != kNoId)
      add(point_on(s, c->first), kNoId);
  for (const Point2 c : {Point2{box.min_x, box.min_y}, Point2{box.max_x, box.min_y},
                         Point2{box.max_x, box.max_y}, Point2{box.min_x, box.max_y}})
    if (orient2d(a, b, c) == 0 && (c.x - a.x) * dx + (c.y - a.y) * dy > 0 &&
        (c.x - b.x) * dx + (c.y - b.y) * dy < 0)
      add(c, kNoId);
  std::sort(on.begin(), on.end(), [](const On& p, const On& q) {
    return p.place < q.place || (p.place == q.place && xy_less(p.at, q.at));
  });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> parts;
  for (std::size_t i = 1; i < on.size(); ++i) {
    const Point2 p = on[i - 1].at, q = on[i].at;
    if (p == q || !in_closed(box, {(p.x + q.x) / 2, (p.y + q.y) / 2})) continue;
    const std::uint32_t u = on[i - 1].id, v = on[i].id;
    if (u == kNoId || v == kNoId) {
      char where[96];
      std::snprintf(where, sizeof where, "(%.17g, %.17g)", u == kNoId ? p.x : q.x,
                    u == kNoId ? p.y : q.y);
      throw InternalError(std::string("tile simplification: a constrained edge ends at ") + where +
                          ", which is no point of the tile");
    }
    parts.push_back({u, v});
  }
  return parts;
}

}  // namespace

namespace {

// What a section point was found as: a side's end, a vertex on the line, or where an edge
// crosses it (the half-edge as found: of a real triangle).
struct Found {
  SectionPoint point;
  int rank;  // at one place, the first kept: an end, then a vertex, then a crossing
};

// Where the section ends at END (a crossing of a hull edge) and NEXT is the point beside it,
// the hull edge's end the border turns to (see TurnedEnd), if NEXT lies on the triangle's
// other edges.
std::optional<TurnedEnd> turned_end(const Triangulation& tin, const Side& side, const Found& end,
                                    const Found& next) {
  if (end.rank != 2 || !tin.is_ghost(mesh::triangle_of(tin.twin(end.point.edge))))
    return std::nullopt;
  const TriangleId t = mesh::triangle_of(end.point.edge);
  const VertexId u = tin.origin(end.point.edge), w = tin.dest(end.point.edge);
  VertexId to = kNoId;
  if (next.rank == 2 && (mesh::triangle_of(next.point.edge) == t ||
                         mesh::triangle_of(tin.twin(next.point.edge)) == t)) {
    const VertexId a = tin.origin(next.point.edge), b = tin.dest(next.point.edge);
    to = a == u || b == u ? u : w;  // the end the two crossed edges share
  } else if (next.rank == 1 && tin.apex(end.point.edge) == next.point.vertex) {
    to = xy_less(tin.point(u), tin.point(w)) ? u : w;
  }
  if (to == kNoId) return std::nullopt;
  const Point2 p = tin.point(to);
  if (along(side, p) < side.lo || along(side, p) > side.hi ||
      std::fabs(across(side, p) - side.at) > side.depth)
    return std::nullopt;
  return TurnedEnd{{p.x, p.y, tin.z(to)}, to, tin.point(u), tin.point(w)};
}

}  // namespace

Section tin_section(const Triangulation& tin, const Side& side,
                    std::span<const std::uint8_t> on_constraint) {
  std::vector<Found> found;
  for (const double end : {side.lo, side.hi})
    if (const auto h = height_at(tin, point_on(side, end))) found.push_back({{end, *h, false}, 0});
  for (VertexId v = 0; v < tin.vertex_count(); ++v) {
    const Point2 p = tin.point(v);
    if (across(side, p) == side.at && side.lo <= along(side, p) && along(side, p) <= side.hi)
      found.push_back(
          {{along(side, p), tin.z(v), v < on_constraint.size() && on_constraint[v], v}, 1});
  }
  for (std::size_t t = 0; t < tin.triangle_slots(); ++t) {
    if (tin.is_ghost(static_cast<TriangleId>(t))) continue;
    for (EdgeId e = static_cast<EdgeId>(3 * t); e < 3 * t + 3; ++e) {
      const EdgeId twin = tin.twin(e);
      if (!(e < twin || tin.is_ghost(mesh::triangle_of(twin)))) continue;  // each edge once
      const VertexId u = tin.origin(e), w = tin.dest(e);
      const auto c = crossing(side, tin.point(u), tin.z(u), tin.point(w), tin.z(w));
      if (c && side.lo <= c->first && c->first <= side.hi)
        found.push_back({{c->first, c->second, tin.is_constrained(e), kNoId, e}, 2});
    }
  }
  // Two edges may cross the line at one place (rounded), with heights an ulp apart: the lower
  // height is kept, whatever the order the tile's TIN holds them in (a NaN last).
  const auto lower = [](double a, double b) { return std::isnan(b) ? !std::isnan(a) : a < b; };
  std::sort(found.begin(), found.end(), [&lower](const Found& a, const Found& b) {
    if (a.point.along != b.point.along) return a.point.along < b.point.along;
    return a.rank != b.rank ? a.rank < b.rank : lower(a.point.z, b.point.z);
  });
  std::vector<Found> merged;
  for (const Found& f : found) {
    if (!merged.empty() && merged.back().point.along == f.point.along) {
      merged.back().point.forced = merged.back().point.forced || f.point.forced;
      continue;
    }
    merged.push_back(f);
  }
  Section section;
  if (merged.size() >= 2) {
    section.first = turned_end(tin, side, merged.front(), merged[1]);
    section.last = turned_end(tin, side, merged.back(), merged[merged.size() - 2]);
    const auto leaves_hull = [&](const Found& f) {
      return f.rank == 2 && tin.is_ghost(mesh::triangle_of(tin.twin(f.point.edge)));
    };
    if (!section.first && leaves_hull(merged.front()))
      section.stuck = point_on(side, merged.front().point.along);
    if (!section.last && leaves_hull(merged.back()))
      section.stuck = point_on(side, merged.back().point.along);
  }
  for (std::size_t i = 0; i < merged.size(); ++i) {
    if ((i == 0 && section.first) || (i + 1 == merged.size() && section.last)) continue;
    section.points.push_back(merged[i].point);
  }
  return section;
}

namespace {

// The TIN's constrained edges cut to the tile as segments, and the job's pieces as pieces of the
// tile's points (with their sources).
void add_constraints(const TileJob& job, const TileSides& sides, const Border& border,
                     std::span<const std::uint32_t> point_of_full, TilePoints& points,
                     std::vector<constraints::Piece>& pieces) {
  const Triangulation& tin = job.mesh.tin;
  const BBox& box = job.tile.box;
  const auto cut = [&](VertexId a, VertexId b) {
    const Point2 p = tin.point(a), q = tin.point(b);
    if (std::max(p.x, q.x) < box.min_x || std::min(p.x, q.x) > box.max_x ||
        std::max(p.y, q.y) < box.min_y || std::min(p.y, q.y) > box.max_y)
      return std::vector<std::pair<std::uint32_t, std::uint32_t>>{};
    return cut_to_tile(box, sides, points, border, p, tin.z(a), point_of_full[a], q, tin.z(b),
                       point_of_full[b]);
  };
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (const constraints::Segment& s : points.segments) seen.insert(std::minmax(s.a, s.b));
  std::vector<constraints::Segment> added;
  tin.for_each_constrained_edge([&](EdgeId e) {
    for (const auto& [u, v] : cut(tin.origin(e), tin.dest(e)))
      if (seen.insert(std::minmax(u, v)).second) added.push_back({u, v, 0});
  });
  points.segments.insert(points.segments.end(), added.begin(), added.end());
  for (const constraints::Piece& p : job.pieces)
    for (const auto& [u, v] : cut(p.a, p.b)) pieces.push_back({u, v, p.source});
}

// The vertices the earlier stages name, renumbered: POINT_OF_FULL maps the full TIN's vertices
// to the tile's points, VERTEX_OF_POINT those to the simplified TIN's vertices.
void renumber(TileJob& job, std::span<const std::uint32_t> point_of_full,
              std::span<const VertexId> vertex_of_point, std::vector<constraints::Piece> pieces) {
  const auto vertex_of = [&](VertexId v) {
    const std::uint32_t p = v < point_of_full.size() ? point_of_full[v] : kNoId;
    return p == kNoId ? kNoId : vertex_of_point[p];
  };
  const Triangulation& full = job.mesh.tin;
  job.given_segments.clear();
  for (constraints::Piece& p : pieces) {
    p = {vertex_of_point[p.a], vertex_of_point[p.b], p.source};
    job.given_segments.push_back({p.a, p.b, p.source});
  }
  job.pieces = std::move(pieces);
  std::erase_if(job.crossings, [&](constraints::Crossing& x) {
    x.vertex = vertex_of(x.vertex);
    return x.vertex == kNoId;
  });
  job.duplicate_at.clear();
  for (delaunay::DelaunayResult::Duplicate& d : job.mesh.duplicates) {
    const Point2 at = full.point(d.vertex);
    job.duplicate_at.push_back({at.x, at.y, full.z(d.vertex)});
    d.vertex = vertex_of(d.vertex);
  }
}

std::uint32_t later(std::uint32_t a, std::uint32_t b) {
  return a == kNoId ? b : (b == kNoId ? a : std::max(a, b));
}

// --replace: the polygon the replace stage gives each border vertex of the simplified TIN
// (VERTEX_OF_POINT: of each tile point; kNoId: none), as the polygons of the job's TIN around
// its place (the later one): the simplified TIN holds only the tile's side of it. The job's
// triangles there are final (they meet the side), classified as the stage does.
std::vector<std::uint32_t> border_polygons(const TileJob& job, const Border& border,
                                           const TilePoints& points,
                                           std::span<const VertexId> vertex_of_point,
                                           std::size_t vertex_count) {
  const Triangulation& tin = job.mesh.tin;
  const std::vector<terrain::Polygon> polygons = pipeline::detail::polygons_of(job.replace.data);
  terrain::PolygonOptions options;
  options.within = &job.proven_triangles;
  const std::vector<std::uint32_t> of_triangle =
      terrain::classify_triangles(tin, terrain::PolygonIndex(polygons), options);
  std::vector<std::uint32_t> of_vertex(tin.vertex_count(), kNoId);
  for (TriangleId t = 0; t < of_triangle.size(); ++t)
    if (of_triangle[t] != kNoId)
      for (const VertexId v : tin.triangle(t)) of_vertex[v] = later(of_vertex[v], of_triangle[t]);
  // A side's end: every triangle whose closed area holds it (a few per tile: a scan).
  const auto at_place = [&](Point2 c) {
    std::uint32_t polygon = kNoId;
    for (TriangleId t = 0; t < of_triangle.size(); ++t) {
      if (of_triangle[t] == kNoId) continue;
      const auto v = tin.triangle(t);
      if (orient2d(tin.point(v[0]), tin.point(v[1]), c) >= 0 &&
          orient2d(tin.point(v[1]), tin.point(v[2]), c) >= 0 &&
          orient2d(tin.point(v[2]), tin.point(v[0]), c) >= 0)
        polygon = later(polygon, of_triangle[t]);
    }
    return polygon;
  };
  std::vector<std::uint32_t> known(vertex_count, kNoId);
  for (const Border::Place& p : border.places) {
    const VertexId v = vertex_of_point[p.point];
    if (v == kNoId) continue;
    const std::uint32_t polygon = p.vertex != kNoId ? of_vertex[p.vertex]
                                  : p.edge != kNoId
                                      ? later(of_triangle[mesh::triangle_of(p.edge)],
                                              of_triangle[mesh::triangle_of(tin.twin(p.edge))])
                                      : at_place(points.xy[p.point]);
    known[v] = later(known[v], polygon);
  }
  return known;
}

// Removes the triangles of TIN outside the tile: those not reached from the inner side of the
// border CHAIN (tile points, the tile on the left) without crossing it. The hull of the tile's
// points may reach beyond the border where it turns to a hull edge's end (TurnedEnd).
void remove_outside(Triangulation& tin,
                    std::span<const std::pair<std::uint32_t, std::uint32_t>> chain,
                    std::span<const VertexId> vertex_of_point) {
  if (chain.empty()) return;
  std::set<std::pair<VertexId, VertexId>> walls;
  std::vector<TriangleId> todo;
  std::vector<std::uint8_t> inside(tin.triangle_slots(), 0);
  for (const auto& [a, b] : chain) {
    const VertexId u = vertex_of_point[a], v = vertex_of_point[b];
    const EdgeId e = u == kNoId || v == kNoId ? kNoId : tin.find_edge(u, v);
    if (e == kNoId) {
      const Point2 p = u == kNoId ? Point2{0, 0} : tin.point(u), q = v == kNoId ? p : tin.point(v);
      char where[160];
      std::snprintf(where, sizeof where, "(%.17g, %.17g) to (%.17g, %.17g)", p.x, p.y, q.x, q.y);
      throw InternalError(std::string("tile simplification: the border segment from ") + where +
                          " is no edge of the tile's TIN");
    }
    walls.insert(std::minmax(u, v));
    todo.push_back(mesh::triangle_of(e));
  }
  while (!todo.empty()) {
    const TriangleId t = todo.back();
    todo.pop_back();
    if (inside[t] || tin.is_ghost(t)) continue;
    inside[t] = 1;
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e)
      if (walls.count(std::minmax(tin.origin(e), tin.dest(e))) == 0)
        todo.push_back(mesh::triangle_of(tin.twin(e)));
  }
  for (std::size_t t = 0; t < inside.size(); ++t)
    if (!inside[t] && !tin.is_ghost(static_cast<TriangleId>(t)))
      tin.set_removed(static_cast<TriangleId>(t), true);
}

}  // namespace

std::optional<Triangulation> simplify_tile(TileJob& job) {
  const TileSetup& tile = job.tile;
  const Triangulation& full = job.mesh.tin;
  const double tolerance = job.options.max_error.value_or(0);
  std::vector<std::uint8_t> on_constraint(full.vertex_count(), 0);
  full.for_each_constrained_edge(
      [&](EdgeId e) { on_constraint[full.origin(e)] = on_constraint[full.dest(e)] = 1; });

  const TileSides sides(tile.box);
  TilePoints points;
  const Border border = add_border(full, tile.box, sides, on_constraint, tolerance, points);
  if (border.stuck) {
    char at[80];
    std::snprintf(at, sizeof at, "(%.3f, %.3f)", border.stuck->x, border.stuck->y);
    job.warn("tile " + std::to_string(tile.index) + ": the data's hull crosses the border at " +
             at +
             " in a triangle that reaches beyond the two tiles of that border: the border ends "
             "there, a hair off the hull, and the merge may find the outline not quite convex "
             "(larger tiles avoid it)");
  }
  std::vector<std::uint32_t> point_of_full(full.vertex_count(), kNoId);
  const BBox& b = tile.box;
  for (VertexId v = 0; v < full.vertex_count(); ++v) {
    const Point2 p = full.point(v);
    if (b.min_x < p.x && p.x < b.max_x && b.min_y < p.y && p.y < b.max_y)
      point_of_full[v] = points.add_candidate(p, full.z(v));
    else if (in_closed(b, p))
      point_of_full[v] = points.find(p);  // on a border: a border vertex, or left out
  }
  if (points.xy.size() < 3 || simplify::hull_corners(points.xy).size() < 3) {
    job.debug("tile " + std::to_string(tile.index) + ": no area of the TIN to simplify");
    return std::nullopt;  // the tile owns no triangle (the TIN only touches it)
  }
  std::vector<constraints::Piece> pieces;
  add_constraints(job, sides, border, point_of_full, points, pieces);

  simplify::SimplifyOptions options;
  options.max_error = tolerance;
  options.threads = job.options.threads;
  simplify::SimplifyResult r = simplify::simplify(points.xy, points.z, points.kept, points.segments,
                                                  options, job.stage_progress());
  std::vector<VertexId> vertex_of_point(points.xy.size(), kNoId);
  for (VertexId v = 0; v < r.tin.vertex_count(); ++v)
    if (r.point_of_vertex[v] != kNoId) vertex_of_point[r.point_of_vertex[v]] = v;
  remove_outside(r.tin, border.chain, vertex_of_point);
  if (!job.replace.data.features.empty())
    job.known_replace_polygons =
        border_polygons(job, border, points, vertex_of_point, r.tin.vertex_count());
  renumber(job, point_of_full, vertex_of_point, std::move(pieces));
  release(job.mesh.vertex_of_point);
  std::optional<Triangulation> replaced = std::move(job.mesh.tin);
  job.mesh.tin = std::move(r.tin);
  job.dem_extra_triangles.clear();  // the tile's TIN covers the tile: its DEM needs no other

  pipeline::BuildReport::Simplify& s = job.report.simplify;
  s.ran = true;
  s.points = r.report.points;
  s.vertices = r.report.vertices;
  s.max_error = std::max(r.report.max_error, border.error);
  s.rmse = r.report.rmse;
  job.info("tile " + std::to_string(tile.index) + ": simplified to " +
           count_text(r.report.vertices, "vertex", "vertices") + " (" +
           count_text(points.kept.size()) + " on the border, " +
           count_text(r.report.points, "point") + ")");
  return replaced;
}

}  // namespace tincdt::tiles::detail
