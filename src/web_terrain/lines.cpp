// The constrained lines (contours, hard lines) of a web-terrain tile: the full TIN's constrained
// edges clipped to the tile's rectangle, chained, simplified by 3D Douglas–Peucker within the
// tile's tolerance and put on its grid as kept vertices joined by segments, so that the tile's
// TIN holds them as edges. Where an edge crosses a side, the crossing is computed exactly as
// TerrainSource::section() computes it, so it is the border vertex both tiles of that side hold.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <variant>
#include <vector>

#include "simplify/profile.hpp"
#include "web_terrain/tile_points.hpp"

namespace tincdt::web_terrain::detail {
namespace {

using io::terrain::GeoRectangle;

// A node of a line in the tile: a vertex of the TIN inside the rectangle, or a point on a side
// (at a grid place).
struct Node {
  double u, v, z;  // grid coordinates (continuous inside, whole on a side), metres
  bool on_side;
  std::uint64_t id;  // vertex id, or the grid place's key for a point on a side
};

std::uint64_t place_key(double u, double v) {
  return (std::uint64_t{1} << 63) | (static_cast<std::uint64_t>(u) << 16) |
         static_cast<std::uint64_t>(v);
}

// The nodes of the edge A-B (A the lower-numbered vertex) met in the order along it: its ends
// and its crossings with the four sides' lines, each as section() finds them.
std::vector<std::pair<double, Node>> edge_nodes(const Point3& a, const Point3& b, std::uint32_t ia,
                                                std::uint32_t ib, const GeoRectangle& r) {
  std::vector<std::pair<double, Node>> out;
  const auto u_of = [&](double lon) { return (lon - r.west) / (r.east - r.west) * kGridMax; };
  const auto v_of = [&](double lat) { return (lat - r.south) / (r.north - r.south) * kGridMax; };
  out.push_back({0.0, {u_of(a.x), v_of(a.y), a.z, false, ia}});
  out.push_back({1.0, {u_of(b.x), v_of(b.y), b.z, false, ib}});
  for (int side = 0; side < 4; ++side) {
    const bool meridian = side == 0 || side == 2;  // west, east
    const double at = side == 0 ? r.west : side == 1 ? r.south : side == 2 ? r.east : r.north;
    const double ua = (meridian ? a.x : a.y) - at, ub = (meridian ? b.x : b.y) - at;
    if (!((ua < 0 && ub > 0) || (ua > 0 && ub < 0))) continue;
    const double f = ua / (ua - ub);
    const double sa = meridian ? a.y : a.x, sb = meridian ? b.y : b.x;
    const double s = sa + f * (sb - sa), h = a.z + f * (b.z - a.z);
    const double from = meridian ? r.south : r.west, to = meridian ? r.north : r.east;
    if (!(s > from && s < to)) continue;
    const double q = grid_place(s, from, to);
    const double side_place = side < 2 ? 0.0 : kGridMax;
    const double u = meridian ? side_place : q, v = meridian ? q : side_place;
    out.push_back({f, {u, v, h, true, place_key(u, v)}});
  }
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  return out;
}

bool strictly_inside(double u, double v) {
  return u > 0 && u < kGridMax && v > 0 && v < kGridMax;
}

// A node on the rectangle's boundary that section() did not make (a vertex exactly on a side)
// is the side's point at its place.
Node settle(Node n) {
  if (n.on_side || strictly_inside(n.u, n.v)) return n;
  n.u = std::round(std::clamp(n.u, 0.0, kGridMax));
  n.v = std::round(std::clamp(n.v, 0.0, kGridMax));
  n.on_side = true;
  n.id = place_key(n.u, n.v);
  return n;
}

// The pieces of the constrained edges inside R, as pairs of nodes.
std::vector<std::pair<Node, Node>> pieces_in(const TerrainSource& source, const GeoRectangle& r,
                                             bool with_outline) {
  std::vector<std::pair<Node, Node>> out;
  for (const std::uint32_t e : source.constrained_edges_in(r)) {
    if (!with_outline && source.outline_only(e)) continue;
    const auto [ia, ib] = source.constrained_edges()[e];
    const auto nodes = edge_nodes(source.vertices()[ia], source.vertices()[ib], ia, ib, r);
    for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
      const Node &n0 = nodes[i].second, &n1 = nodes[i + 1].second;
      if (!strictly_inside((n0.u + n1.u) / 2, (n0.v + n1.v) / 2)) continue;
      const Node a = settle(n0), b = settle(n1);
      // Along a side (both ends on the same side line), the border holds it; a piece straight
      // across the tile is the line's.
      const bool same_side_u = a.u == b.u && (a.u == 0 || a.u == kGridMax);
      const bool same_side_v = a.v == b.v && (a.v == 0 || a.v == kGridMax);
      if (a.on_side && b.on_side && (same_side_u || same_side_v)) continue;
      if (a.id != b.id) out.push_back({a, b});
    }
  }
  return out;
}

// The pieces chained into lines: from each end (a node not met by exactly two pieces), then
// the closed rings that remain, from their smallest node. In the order of the nodes' ids.
std::vector<std::vector<Node>> chains_of(const std::vector<std::pair<Node, Node>>& pieces) {
  std::map<std::uint64_t, std::vector<std::size_t>> at;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    at[pieces[i].first.id].push_back(i);
    at[pieces[i].second.id].push_back(i);
  }
  std::vector<bool> used(pieces.size(), false);
  std::vector<std::vector<Node>> out;
  const auto walk = [&](const Node& start) {
    std::vector<Node> line{start};
    for (Node here = start;;) {
      std::size_t next = pieces.size();
      for (const std::size_t i : at[here.id])
        if (!used[i]) {
          next = i;
          break;
        }
      if (next == pieces.size()) break;
      used[next] = true;
      here = pieces[next].first.id == here.id ? pieces[next].second : pieces[next].first;
      line.push_back(here);
      if (at[here.id].size() != 2) break;
    }
    if (line.size() > 1) out.push_back(std::move(line));
  };
  for (int pass = 0; pass < 2; ++pass)
    for (const auto& [id, list] : at)
      for (const std::size_t i : list) {
        if (used[i] || (pass == 0 && list.size() == 2)) continue;
        walk(pieces[i].first.id == id ? pieces[i].first : pieces[i].second);
      }
  return out;
}

// Whether POINTS all lie within TOLERANCE of the first, horizontally and vertically.
bool within(const std::vector<Point3>& points, double tolerance) {
  for (const Point3& q : points)
    if (std::fabs(q.x - points[0].x) > tolerance || std::fabs(q.y - points[0].y) > tolerance ||
        std::fabs(q.z - points[0].z) > tolerance)
      return false;
  return true;
}

}  // namespace

std::size_t add_lines(const TerrainSource& source, const GeoRectangle& r, double tolerance,
                      bool with_outline, TilePoints& p) {
  const double lat = (r.south + r.north) / 2 * std::numbers::pi / 180;
  const double mx = (r.east - r.west) / kGridMax * kMetresPerDegree * std::cos(lat);
  const double my = (r.north - r.south) / kGridMax * kMetresPerDegree;
  std::size_t added = 0;
  for (const std::vector<Node>& line : chains_of(pieces_in(source, r, with_outline))) {
    std::vector<Point3> metres;
    std::vector<std::uint8_t> keep;
    for (const Node& n : line) {
      metres.push_back({n.u * mx, n.v * my, n.z});
      keep.push_back(n.on_side ? 1 : 0);
    }
    if (within(metres, tolerance) && !line.front().on_side && !line.back().on_side)
      continue;  // a line smaller than the tolerance is no feature at this level
    // A ring keeps its farthest node too, so that it does not fold onto its start.
    if (line.front().id == line.back().id && line.size() > 3) keep[line.size() / 2] = 1;
    std::uint32_t previous = UINT32_MAX;
    for (const std::size_t i : simplify::simplify_polyline(metres, tolerance, keep)) {
      const Node& n = line[i];
      const Point2 place{std::round(n.u), std::round(n.v)};
      std::uint32_t id = 0;
      if (n.on_side) {
        id = p.find(place);
        if (id == kNoId) continue;  // the border has no vertex there: no crossing
      } else {
        if (!strictly_inside(place.x, place.y)) continue;  // within half a step of a side
        id = p.add_kept(place, n.z);
      }
      if (previous != UINT32_MAX && id != previous) {
        p.segments.push_back({previous, id, 1});
        ++added;
      }
      previous = id;
    }
  }
  return added;
}

}  // namespace tincdt::web_terrain::detail
