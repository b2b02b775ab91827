#include "tiles/merge.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/quoted_text.hpp"
#include "io/crs.hpp"
#include "io/mesh/ply_reader.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/output_set.hpp"
#include "mesh/geometry.hpp"
#include "mesh/triangulation.hpp"
#include "pipeline/file_checks.hpp"
#include "predicates/predicates.hpp"
#include "tiles/merge_outline.hpp"

namespace tincdt::tiles {
namespace {

std::string at(Point2 p) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f)", p.x, p.y);
  return buf;
}

Point2 xy(const Point3& p) {
  return {p.x, p.y};
}

// Whether D may lie beside edge a -> b of the counter-clockwise triangle a, b, c: not strictly
// inside its circle (the same test Triangulation::validate() makes).
bool delaunay_across(Point2 a, Point2 b, Point2 c, Point2 d) {
  return predicates::incircle(a, b, c, d) <= 0;
}

// ---- welding vertices by their exact x, y
// --------------------------------------------------------

class Welder {
 public:
  // The id of P, a new one when its x, y are new. When they are not, the z must agree.
  std::uint32_t add(const Point3& p, std::uint32_t tile, const std::vector<std::string>& names) {
    if (2 * (points_.size() + 1) > slots_.size()) grow();
    std::size_t i = hash(p) & (slots_.size() - 1);
    while (slots_[i] != kNoId) {
      const Point3& q = points_[slots_[i]];
      if (q.x == p.x && q.y == p.y) {
        if (q.z != p.z) {
          char buf[96];
          std::snprintf(buf, sizeof buf, ": z %.17g here, %.17g in ", p.z, q.z);
          throw InputError(names[tile], "vertex at " + at(xy(p)),
                           std::string("the tiles disagree on its height") + buf +
                               names[tile_[slots_[i]]] + " (tiles of different runs?)");
        }
        return slots_[i];
      }
      i = (i + 1) & (slots_.size() - 1);
    }
    slots_[i] = static_cast<std::uint32_t>(points_.size());
    points_.push_back(p);
    tile_.push_back(tile);
    return slots_[i];
  }

  const std::vector<Point3>& points() const { return points_; }
  std::uint32_t tile_of(std::uint32_t v) const { return tile_[v]; }

 private:
  static std::size_t hash(const Point3& p) {
    std::uint64_t h = std::bit_cast<std::uint64_t>(p.x) * 0x9E3779B97F4A7C15ULL;
    h ^= std::bit_cast<std::uint64_t>(p.y) + 0x632BE59BD9B4E019ULL + (h << 6) + (h >> 2);
    h *= 0xC2B2AE3D27D4EB4FULL;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
  void grow() {
    std::vector<std::uint32_t> old(std::max<std::size_t>(1024, 2 * slots_.size()), kNoId);
    old.swap(slots_);
    for (std::uint32_t v = 0; v < points_.size(); ++v) {
      std::size_t i = hash(points_[v]) & (slots_.size() - 1);
      while (slots_[i] != kNoId) i = (i + 1) & (slots_.size() - 1);
      slots_[i] = v;
    }
  }

  std::vector<std::uint32_t> slots_;
  std::vector<Point3> points_;
  std::vector<std::uint32_t> tile_;
};

// ---- half-edges of a triangle soup ------------------------------------------------------------

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{a} << 32) | b;
}

// Half-edge e = 3 t + i runs from corner i to corner i + 1 of triangle t. Sorted (key, e) pairs,
// so that a half-edge's twin is found by its reversed key.
class HalfEdges {
 public:
  explicit HalfEdges(const std::vector<std::array<std::uint32_t, 3>>& tris) {
    keys_.reserve(3 * tris.size());
    for (std::uint32_t t = 0; t < tris.size(); ++t)
      for (std::uint32_t i = 0; i < 3; ++i)
        keys_.push_back({edge_key(tris[t][i], tris[t][(i + 1) % 3]), 3 * t + i});
    std::sort(keys_.begin(), keys_.end());
  }
  // The half-edge a -> b, kNoId when none. Two with the same key: *twice set.
  std::uint32_t find(std::uint32_t a, std::uint32_t b, bool* twice = nullptr) const {
    const std::uint64_t k = edge_key(a, b);
    auto it =
        std::lower_bound(keys_.begin(), keys_.end(), std::pair<std::uint64_t, std::uint32_t>{k, 0});
    if (it == keys_.end() || it->first != k) return kNoId;
    if (twice) *twice = it + 1 != keys_.end() && (it + 1)->first == k;
    return it->second;
  }
  // The first pair of half-edges with the same origin and destination, if any.
  bool repeated(std::uint32_t& e, std::uint32_t& f) const {
    for (std::size_t i = 1; i < keys_.size(); ++i)
      if (keys_[i].first == keys_[i - 1].first) {
        e = keys_[i - 1].second;
        f = keys_[i].second;
        return true;
      }
    return false;
  }

 private:
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys_;
};

// ---- borders and outlines -----------------------------------------------------------------------

using detail::Border;

bool border_less(const Border& p, const Border& q) {
  // By the undirected edge: its smaller end, then its larger end.
  const Point2 p0 = std::min(xy(p.a), xy(p.b), xy_less), p1 = std::max(xy(p.a), xy(p.b), xy_less);
  const Point2 q0 = std::min(xy(q.a), xy(q.b), xy_less), q1 = std::max(xy(q.a), xy(q.b), xy_less);
  if (xy_less(p0, q0)) return true;
  if (xy_less(q0, p0)) return false;
  return xy_less(p1, q1);
}

bool same_edge(const Border& p, const Border& q) {
  return !border_less(p, q) && !border_less(q, p);
}

// The border edges of one tile's TIN, after checking that no edge is used twice on one side.
void borders_of(const io::PlyMesh& m, std::uint32_t tile, const std::vector<std::string>& names,
                std::vector<Border>& out) {
  const HalfEdges half(m.faces);
  std::uint32_t e = 0, f = 0;
  if (half.repeated(e, f)) {
    const Point3& p = m.vertices[m.faces[e / 3][e % 3]];
    throw InputError(names[tile], "triangles " + count_text(e / 3) + " and " + count_text(f / 3),
                     "overlap: both have the edge from " + at(xy(p)) + " on the same side");
  }
  std::vector<std::uint64_t> constrained;
  for (const io::PlyMesh::Edge& c : m.edges) {
    constrained.push_back(edge_key(c.a, c.b));
    constrained.push_back(edge_key(c.b, c.a));
  }
  std::sort(constrained.begin(), constrained.end());
  for (std::uint32_t t = 0; t < m.faces.size(); ++t)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t a = m.faces[t][i], b = m.faces[t][(i + 1) % 3];
      if (half.find(b, a) != kNoId) continue;
      out.push_back({m.vertices[a], m.vertices[b], m.vertices[m.faces[t][(i + 2) % 3]],
                     std::binary_search(constrained.begin(), constrained.end(), edge_key(a, b)),
                     tile});
    }
}

// Pairs the border edges of different tiles. Returns the edges left unmatched; throws for an
// overlap, a height disagreement or a seam edge that is not Delaunay.
std::vector<Border> match_borders(std::vector<Border> borders,
                                  const std::vector<std::string>& names, std::uint64_t& matched) {
  std::sort(borders.begin(), borders.end(), border_less);
  std::vector<Border> left;
  for (std::size_t i = 0; i < borders.size();) {
    std::size_t j = i + 1;
    while (j < borders.size() && same_edge(borders[i], borders[j])) ++j;
    const Border& p = borders[i];
    if (j - i == 1) {
      left.push_back(p);
    } else {
      const Border& q = borders[i + 1];
      const bool opposite = xy(p.a) == xy(q.b) && xy(p.b) == xy(q.a);
      if (j - i > 2 || !opposite)
        throw InputError(names[q.tile], "edge from " + at(xy(p.a)) + " to " + at(xy(p.b)),
                         "overlap: " + names[p.tile] + " has a triangle on the same side of it");
      if (p.a.z != q.b.z || p.b.z != q.a.z)
        throw InputError(names[q.tile], "edge from " + at(xy(p.a)) + " to " + at(xy(p.b)),
                         "the tiles disagree on its heights with " + names[p.tile]);
      if (!p.constrained && !q.constrained &&
          !delaunay_across(xy(p.a), xy(p.b), xy(p.apex), xy(q.apex)))
        throw InputError(names[q.tile], "edge from " + at(xy(p.a)) + " to " + at(xy(p.b)),
                         "the triangles on its two sides (this tile and " + names[p.tile] +
                             ") are not Delaunay across it: tiles of different inputs or runs?");
      ++matched;
    }
    i = j;
  }
  return left;
}

// The border edges left over must be the convex hull: one loop, counter-clockwise, turning left
// (or going straight) at every vertex.
void check_hull(std::vector<Border> hull, const std::vector<std::string>& names) {
  if (hull.empty()) throw InputError(names.front(), "", "the tiles hold no triangle");
  const auto by_start = [](const Border& p, const Border& q) { return xy_less(xy(p.a), xy(q.a)); };
  std::sort(hull.begin(), hull.end(), by_start);
  for (std::size_t i = 1; i < hull.size(); ++i)
    if (xy(hull[i].a) == xy(hull[i - 1].a))
      throw InputError(names[hull[i].tile], "vertex at " + at(xy(hull[i].a)),
                       "a crack: two edges of the outline leave this vertex (a tile missing, or "
                       "tiles of different runs)");
  std::size_t loops = 0, walked = 0;
  std::vector<char> seen(hull.size(), 0);
  for (std::size_t s = 0; s < hull.size(); ++s) {
    if (seen[s]) continue;
    ++loops;
    std::size_t e = s;
    while (!seen[e]) {
      seen[e] = 1;
      ++walked;
      const Border probe{hull[e].b, {}, {}, false, 0};
      const auto it = std::lower_bound(hull.begin(), hull.end(), probe, by_start);
      if (it == hull.end() || xy(it->a) != xy(hull[e].b))
        throw InputError(names[hull[e].tile], "vertex at " + at(xy(hull[e].b)),
                         "a crack: the outline stops here");
      const Border& next = *it;
      if (predicates::orient2d(xy(hull[e].a), xy(hull[e].b), xy(next.b)) < 0)
        throw InputError(names[hull[e].tile], "vertex at " + at(xy(hull[e].b)),
                         "a crack or a missing tile: the outline of the tiles turns inward here, "
                         "so it is not the convex hull");
      e = static_cast<std::size_t>(it - hull.begin());
    }
  }
  if (loops != 1)
    throw InputError(names.front(), "",
                     "a crack: the outline of the tiles is " + count_text(loops) +
                         " loops, not one (a hole between tiles, or tiles of different runs)");
}

// The border edges left over from trimmed tiles: the hull where nothing was trimmed, and the
// outlines of the trimmed areas. They must close into loops: at every vertex as many edges arrive
// as leave. (A missing tile leaves a loop too: TrimmedTiles counts the tiles.)
void check_loops(std::vector<Border> left, const std::vector<std::string>& names) {
  if (left.empty()) throw InputError(names.front(), "", "the tiles hold no triangle");
  std::vector<std::pair<Point2, int>> ends;  // +1 per edge leaving, -1 per edge arriving
  for (const Border& b : left) ends.insert(ends.end(), {{xy(b.a), 1}, {xy(b.b), -1}});
  std::sort(ends.begin(), ends.end(),
            [](const auto& p, const auto& q) { return xy_less(p.first, q.first); });
  for (std::size_t i = 0; i < ends.size();) {
    int balance = 0;
    std::size_t j = i;
    for (; j < ends.size() && ends[j].first == ends[i].first; ++j) balance += ends[j].second;
    if (balance != 0)
      throw InputError(names.front(), "vertex at " + at(ends[i].first),
                       "a crack: the outline of the tiles stops here");
    i = j;
  }
}

// The plan's tiles that trimmed inputs hold, from their marks (detail::TileMark): as a missing
// tile's hole cannot be told from a trimmed area, they are counted instead. Either every input is
// marked or none.
class TrimmedTiles {
 public:
  void add(const std::string& name, const std::optional<std::string>& text) {
    if (!text) {
      if (unmarked_.empty()) unmarked_ = name;
      return;
    }
    const std::optional<detail::TileMark> mark = detail::parse_mark(*text);
    if (!mark) throw InputError(name, "header", "a bad trimmed line: " + quoted_text(*text));
    if (marked_.empty()) {
      count_ = mark->count;
      marked_ = name;
    } else if (mark->count != count_) {
      throw InputError(name, "header",
                       "is a tile of a plan of " + count_text(mark->count, "tile") + ", " +
                           marked_ + " of " + count_text(count_));
    }
    // The indices held, not a flag per tile: nothing is allocated from the count a file states.
    for (const std::uint32_t t : mark->tiles) {
      const auto at = std::lower_bound(seen_.begin(), seen_.end(), t);
      if (at != seen_.end() && *at == t)
        throw InputError(name, "header", "holds tile " + std::to_string(t) + " again");
      seen_.insert(at, t);
    }
  }
  bool any() const { return !marked_.empty(); }
  // Every input marked; with WHOLE, every tile of the plan there.
  void check(bool whole) const {
    if (!any()) return;
    if (!unmarked_.empty())
      throw InputError(
          unmarked_, "",
          "was not trimmed, but " + marked_ + " was (--max-edge): tiles of different runs");
    if (!whole || seen_.size() == count_) return;
    std::uint32_t missing = 0;  // the first index not held: seen_ is sorted and unique
    while (missing < seen_.size() && seen_[missing] == missing) ++missing;
    throw InputError(
        marked_, "",
        "tile " + std::to_string(missing) + " of its plan's " + count_text(count_) + " is missing");
  }
  std::string text() const { return any() ? detail::mark_text({count_, seen_}) : ""; }

 private:
  std::uint32_t count_ = 0;
  std::vector<std::uint32_t> seen_;  // sorted
  std::string marked_, unmarked_;
};

// ---- the whole merge --------------------------------------------------------------------------

MergeReport merge_outlines(const MergeOptions& options, const LogFn& log) {
  MergeReport r;
  std::vector<Border> borders;
  std::string crs;
  TrimmedTiles trimmed;
  for (std::uint32_t t = 0; t < options.inputs.size(); ++t) {
    const io::PlyMesh m = io::read_ply(options.inputs[t]);
    if (crs.empty()) crs = m.crs;
    trimmed.add(options.inputs[t], m.trimmed);
    ++r.tiles;
    r.vertices += m.vertices.size();
    r.triangles += m.faces.size();
    if (m.outline) {
      for (const io::PlyMesh::Edge& e : m.edges)
        borders.push_back({m.vertices[e.a], m.vertices[e.b], m.vertices[e.apex], e.constrained, t});
    } else {
      borders_of(m, t, options.inputs, borders);
    }
    if (log)
      log(log_debug, options.inputs[t] + ": " + count_text(m.faces.size(), "triangle") + ", " +
                         count_text(borders.size(), "border edge") + " so far");
  }
  std::vector<Border> left = match_borders(std::move(borders), options.inputs, r.seam_edges);
  r.hull_edges = left.size();
  r.trimmed = trimmed.any();
  trimmed.check(!options.outline);
  if (options.outline) {
    io::OutputSet set(options.overwrite);
    detail::write_outline(set.add(options.output, "outline"), left, crs, trimmed.text());
    set.commit();
  } else if (r.trimmed) {
    check_loops(std::move(left), options.inputs);
  } else {
    check_hull(std::move(left), options.inputs);
  }
  return r;
}

// The tiles' triangles over one set of vertices, welded by their exact x, y.
struct WeldedTiles {
  Welder welder;
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<std::uint32_t> tri_tile;
  std::vector<std::array<std::uint32_t, 2>> constrained;
  std::string crs;
  Point3 offset{0, 0, 0};
  bool one_offset = true;  // all tiles share the first tile's offset, so the output may keep it
  TrimmedTiles trimmed;  // the tiles' marks when trimmed (--max-edge): borders not all seams, hull
};

WeldedTiles weld_tiles(const std::vector<std::string>& names, const LogFn& log, MergeReport& r) {
  WeldedTiles w;
  for (std::uint32_t t = 0; t < names.size(); ++t) {
    const io::PlyMesh m = io::read_ply(names[t]);
    if (m.outline)
      throw InputError(names[t], "", "is a tile outline: merge outlines with --check or --outline");
    w.trimmed.add(names[t], m.trimmed);
    if (t == 0) {
      w.crs = m.crs;
      w.offset = m.offset;
    } else if (!(m.offset == w.offset)) {
      w.one_offset = false;
    }
    std::vector<std::uint32_t> id(m.vertices.size());
    for (std::size_t v = 0; v < m.vertices.size(); ++v)
      id[v] = w.welder.add(m.vertices[v], t, names);
    for (const auto& f : m.faces) {
      w.tris.push_back({id[f[0]], id[f[1]], id[f[2]]});
      w.tri_tile.push_back(t);
    }
    for (const io::PlyMesh::Edge& e : m.edges) w.constrained.push_back({id[e.a], id[e.b]});
    ++r.tiles;
    if (log) log(log_debug, names[t] + ": " + count_text(m.faces.size(), "triangle"));
  }
  if (w.tris.empty()) throw InputError(names.front(), "", "the tiles hold no triangle");
  r.vertices = w.welder.points().size();
  r.triangles = w.tris.size();
  return w;
}

// Each half-edge's twin (kNoId on the border) and the border half-edges, which must be the hull.
struct SeamedEdges {
  std::vector<std::uint32_t> twin;
  std::vector<std::uint32_t> border_edge;
};

SeamedEdges pair_half_edges(const WeldedTiles& w, const HalfEdges& half,
                            const std::vector<std::string>& names, MergeReport& r) {
  const std::vector<Point3>& points = w.welder.points();
  const auto& tris = w.tris;
  std::uint32_t e = 0, f = 0;
  if (half.repeated(e, f)) {
    const Point3& p = points[tris[e / 3][e % 3]];
    throw InputError(
        names[w.tri_tile[f / 3]], "edge from " + at(xy(p)),
        "overlap: " + names[w.tri_tile[e / 3]] + " has a triangle on the same side of it");
  }
  SeamedEdges s;
  s.twin.assign(3 * tris.size(), kNoId);
  std::vector<Border> border;
  for (std::uint32_t h = 0; h < s.twin.size(); ++h) {
    const std::uint32_t a = tris[h / 3][h % 3], b = tris[h / 3][(h + 1) % 3];
    s.twin[h] = half.find(b, a);
    if (s.twin[h] != kNoId) {
      if (w.tri_tile[h / 3] != w.tri_tile[s.twin[h] / 3] && a < b) ++r.seam_edges;
      continue;
    }
    border.push_back(
        {points[a], points[b], points[tris[h / 3][(h + 2) % 3]], false, w.tri_tile[h / 3]});
    s.border_edge.push_back(h);
  }
  if (w.trimmed.any())
    check_loops(border, names);
  else
    check_hull(border, names);
  r.hull_edges = border.size();
  return s;
}

// The TIN: the triangles, then one ghost per border edge, chained around the hull. Trimmed tiles
// leave several loops, which may meet at a vertex: there the ghosts are chained in any order
// (nothing walks them; the writers need every half-edge twinned).
mesh::Triangulation link_tin(const WeldedTiles& w, const SeamedEdges& s) {
  const std::vector<Point3>& points = w.welder.points();
  const auto& tris = w.tris;
  mesh::Triangulation tin;
  tin.reserve_vertices(points.size());
  for (const Point3& p : points) tin.add_vertex({p.x, p.y}, p.z);
  tin.reserve_triangles(tris.size() + s.border_edge.size());
  for (const auto& t : tris) tin.add_triangle(t[0], t[1], t[2]);
  for (std::uint32_t h = 0; h < s.twin.size(); ++h)
    if (s.twin[h] != kNoId && h < s.twin[h]) tin.link(h, s.twin[h]);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out, into;  // (vertex, ghost edge)
  for (const std::uint32_t h : s.border_edge) {
    const std::uint32_t a = tris[h / 3][h % 3], b = tris[h / 3][(h + 1) % 3];
    const TriangleId g = tin.add_triangle(b, a, mesh::kInfinite);  // b -> a, a -> inf, inf -> b
    tin.link(h, 3 * g);
    out.emplace_back(a, 3 * g + 1);
    into.emplace_back(b, 3 * g + 2);
  }
  // As many ghost edges leave each vertex as arrive (check_hull(), check_loops()).
  std::sort(out.begin(), out.end());
  std::sort(into.begin(), into.end());
  assert(out.size() == into.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    assert(out[i].first == into[i].first);
    tin.link(out[i].second, into[i].second);
  }
  return tin;
}

// The first unconstrained edge between two triangles that is not locally Delaunay, "" when none.
std::string non_delaunay_edge(const mesh::Triangulation& tin) {
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); ++e) {
    const EdgeId f = tin.twin(e);
    if (f < e || tin.is_constrained(e) || tin.is_ghost(mesh::triangle_of(e)) ||
        tin.is_ghost(mesh::triangle_of(f)))
      continue;
    const Point2 a = tin.point(tin.origin(e)), b = tin.point(tin.dest(e));
    if (!delaunay_across(a, b, tin.point(tin.apex(e)), tin.point(tin.apex(f))))
      return "the edge from " + at(a) + " to " + at(b) + " is not Delaunay";
  }
  return {};
}

// Marks the tiles' constrained edges, then checks the whole: a seam that is not Delaunay or a
// constraint that does not survive the weld means tiles that do not belong together.
void constrain_and_validate(mesh::Triangulation& tin, const WeldedTiles& w, const HalfEdges& half,
                            const std::vector<std::string>& names) {
  for (const auto& c : w.constrained) {
    std::uint32_t h = half.find(c[0], c[1]);
    if (h == kNoId) h = half.find(c[1], c[0]);
    if (h == kNoId)
      throw InputError(names[w.welder.tile_of(c[0])],
                       "constrained edge at " + at(xy(w.welder.points()[c[0]])),
                       "is no edge of the merged triangles");
    tin.set_constrained(h, true);
  }
  tin.recount();
  // With holes, Triangulation::validate() (one convex hull) does not apply; what tiles of
  // different inputs or runs would break is the Delaunay property across their seams.
  const std::string problem = w.trimmed.any() ? non_delaunay_edge(tin) : tin.validate();
  if (!problem.empty())
    throw InputError(
        names.front(), "",
        "the merged TIN is not valid: " + problem + " (tiles of different inputs or runs?)");
}

void write_merged(const MergeOptions& options, const mesh::Triangulation& tin,
                  const WeldedTiles& w) {
  io::TinWriteOptions out_options;
  out_options.format = io::format_from_path(options.output);
  out_options.overwrite = options.overwrite;
  if (w.one_offset) out_options.offset = w.offset;
  if (!w.crs.empty()) out_options.crs_wkt = io::crs_from_user(w.crs);
  io::OutputSet set(options.overwrite);
  io::OutputFile& out = set.add(options.output, "tin");
  io::write_tin(out, tin, out_options);
  out.close();
  if (io::wants_prj(*out_options.format, out_options.crs_wkt)) {
    io::OutputFile& prj = set.add(io::prj_path(options.output), "prj");
    io::write_prj(prj, out_options.crs_wkt);
    prj.close();
  }
  set.commit();
}

MergeReport merge_whole(const MergeOptions& options, const LogFn& log) {
  MergeReport r;
  const WeldedTiles welded = weld_tiles(options.inputs, log, r);
  r.trimmed = welded.trimmed.any();
  welded.trimmed.check(true);
  const HalfEdges half(welded.tris);
  const SeamedEdges seamed = pair_half_edges(welded, half, options.inputs, r);
  mesh::Triangulation tin = link_tin(welded, seamed);
  constrain_and_validate(tin, welded, half, options.inputs);
  if (options.check_only) return r;
  write_merged(options, tin, welded);
  return r;
}

}  // namespace

MergeReport merge_tiles(const MergeOptions& options, const LogFn& log) {
  if (options.inputs.empty()) throw UsageError("no tiles to merge");
  if (!options.check_only) {
    pipeline::FilePlan files;
    for (const std::string& p : options.inputs) files.inputs.push_back({p, "a tile"});
    files.outputs.push_back(
        {options.output, options.outline ? "the outline (-o)" : "the TIN (-o)"});
    pipeline::check_files(files, options.overwrite);
  }
  if (options.check_only || options.outline) return merge_outlines(options, log);
  return merge_whole(options, log);
}

}  // namespace tincdt::tiles
