#include "web_terrain/source.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <span>
#include <tuple>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/parallel.hpp"

namespace tincdt::web_terrain {
namespace {

// How many items ahead the passes over the TIN in its own order ask for the memory they will
// read: its vertices are in insertion order, not by place, so nearly every read is a miss.
constexpr std::size_t kAhead = 16;

// Asks for ARRAY's items at the corners of the triangle kAhead after triangle I.
template <class T>
void prefetch_corners_ahead(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                            std::size_t i, const T* array) {
  if (i + kAhead < triangles.size())
    for (const std::uint32_t v : triangles[i + kAhead]) __builtin_prefetch(&array[v]);
}

double orient(const Point3& a, const Point3& b, double x, double y) {
  return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
}

// CSR rows from per-cell counts: begin[c] = start of cell c. The memberships of one index are
// counted in 64 bits and refused beyond 32.
void prefix_sums(std::vector<std::uint32_t>& begin) {
  std::uint64_t sum = 0;
  for (std::uint32_t& b : begin) {
    const std::uint32_t n = b;
    b = static_cast<std::uint32_t>(sum);
    sum += n;
    if (sum > UINT32_MAX)
      throw GeometryError(
          "the TIN's triangles overlap more than 2^32 cells of the web-terrain index");
  }
}

}  // namespace

TerrainSource::TerrainSource(const mesh::Triangulation& tin, const std::string& crs_wkt,
                             const std::string& what, std::optional<double> fill_height,
                             std::size_t threads)
    : fill_height_(fill_height.value_or(0)) {
  // Only the vertices of kept triangles are the TIN's (numbered by place once transformed); only
  // they go through PROJ, so that a removed outlier cannot fail the pyramid.
  // The large arrays here on huge pages: a page fault each 4 kB costs seconds over a big TIN.
  std::vector<std::uint32_t> number = large_vector<std::uint32_t>(tin.vertex_count());
  std::fill(number.begin(), number.end(), UINT32_MAX);
  vertices_.reserve(tin.vertex_count());
  advise_huge_pages(vertices_);
  triangles_.reserve(tin.triangle_count());
  advise_huge_pages(triangles_);
  const std::size_t slots = tin.triangle_slots();
  tin.for_each_triangle([&](TriangleId id, const std::array<VertexId, 3>& c) {
    if (id + kAhead < slots)
      for (const VertexId v : tin.triangle(static_cast<TriangleId>(id + kAhead)))
        if (v < number.size()) {
          __builtin_prefetch(&number[v]);
          __builtin_prefetch(&tin.points()[v]);
        }
    std::array<std::uint32_t, 3> t{};
    for (int i = 0; i < 3; ++i) {
      if (number[c[i]] == UINT32_MAX) {
        number[c[i]] = static_cast<std::uint32_t>(vertices_.size());
        const Point2 p = tin.point(c[i]);
        vertices_.push_back({p.x, p.y, tin.z(c[i])});
      }
      t[i] = number[c[i]];
    }
    triangles_.push_back(t);
  });
  // A PROJ transformation is not shared between threads: one a part.
  parallel_parts(part_count(threads, vertices_.size()), vertices_.size(),
                 [&](std::size_t part, std::size_t first, std::size_t last) {
                   const io::terrain::HeightUnits units = io::terrain::to_lon_lat_metres(
                       crs_wkt, std::span(vertices_).subspan(first, last - first), what);
                   if (part == 0) units_ = units;
                 });
  // Projections keep orientation but a CRS with a flipped axis does not.
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    prefetch_corners_ahead(triangles_, i, vertices_.data());
    auto& t = triangles_[i];
    if (orient(vertices_[t[0]], vertices_[t[1]], vertices_[t[2]].x, vertices_[t[2]].y) < 0)
      std::swap(t[1], t[2]);
  }
  if (!vertices_.empty()) {
    bounds_ = {vertices_[0].x, vertices_[0].y, vertices_[0].x, vertices_[0].y};
    for (const Point3& p : vertices_) {
      bounds_.west = std::min(bounds_.west, p.x);
      bounds_.east = std::max(bounds_.east, p.x);
      bounds_.south = std::min(bounds_.south, p.y);
      bounds_.north = std::max(bounds_.north, p.y);
    }
    // The lowest, not 0: coarse and fine tiles ramp from the data's edge down to the fill over
    // different widths, and where they meet their ramps differ by up to the drop to the fill.
    if (!fill_height) {
      fill_height_ = vertices_[0].z;
      for (const Point3& p : vertices_) fill_height_ = std::min(fill_height_, p.z);
    }
  }
  set_cells();
  number_by_cell(number);
  collect_constraints(tin, number);
  collect_holes(tin, number, crs_wkt, what);
  build_index();
}

void TerrainSource::number_by_cell(std::vector<std::uint32_t>& number) {
  const std::size_t n = vertices_.size();
  std::vector<std::uint32_t> cell = large_vector<std::uint32_t>(n);
  std::vector<std::uint32_t> begin(std::size_t{vertex_cells_.across} * vertex_cells_.down + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = row(vertices_[i].y) * vertex_cells_.across + column(vertices_[i].x);
    ++begin[cell[i]];
  }
  prefix_sums(begin);
  vertex_cells_.begin = begin;  // the vertices of cell c are numbered begin[c] to begin[c + 1]
  std::vector<std::uint32_t> order = large_vector<std::uint32_t>(n);  // old numbers, cell by cell
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) __builtin_prefetch(&begin[cell[i + kAhead]]);
    order[begin[cell[i]]++] = static_cast<std::uint32_t>(i);
  }
  const auto before = [this](std::uint32_t a, std::uint32_t b) {
    const Point3 &p = vertices_[a], &q = vertices_[b];
    return std::tie(p.x, p.y, p.z, a) < std::tie(q.x, q.y, q.z, b);
  };
  std::size_t first = 0;
  for (std::size_t c = 0; c + 1 < begin.size(); ++c) {  // cell c now ends at begin[c]
    for (std::size_t i = begin[c]; i < begin[c + 1] && c + 2 < begin.size(); ++i)
      __builtin_prefetch(&vertices_[order[i]]);  // the next cell's, while this one sorts
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(first),
              order.begin() + static_cast<std::ptrdiff_t>(begin[c]), before);
    first = begin[c];
  }
  std::vector<std::uint32_t> renumber = large_vector<std::uint32_t>(n);
  std::vector<Point3> sorted = large_vector<Point3>(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) {
      __builtin_prefetch(&renumber[order[i + kAhead]], 1);
      __builtin_prefetch(&vertices_[order[i + kAhead]]);
    }
    renumber[order[i]] = static_cast<std::uint32_t>(i);
    sorted[i] = vertices_[order[i]];
  }
  vertices_.swap(sorted);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    prefetch_corners_ahead(triangles_, i, renumber.data());
    for (std::uint32_t& v : triangles_[i]) v = renumber[v];
  }
  for (std::uint32_t& v : number)
    if (v != UINT32_MAX) v = renumber[v];
}

void TerrainSource::collect_constraints(const mesh::Triangulation& tin,
                                        const std::vector<std::uint32_t>& number) {
  on_constraint_.assign(vertices_.size(), 0);
  const auto add = [&](EdgeId e) {
    std::uint32_t a = number[tin.origin(e)], b = number[tin.dest(e)];
    if (a == UINT32_MAX || b == UINT32_MAX) return false;
    if (a > b) std::swap(a, b);
    constrained_.push_back({a, b});
    on_constraint_[a] = on_constraint_[b] = 1;
    return true;
  };
  tin.for_each_constrained_edge([&](EdgeId e) {
    if (tin.is_kept(mesh::triangle_of(e)) || tin.is_kept(mesh::triangle_of(tin.twin(e)))) add(e);
  });
  std::vector<std::array<std::uint32_t, 2>> lines = constrained_;
  std::sort(lines.begin(), lines.end());
  // The outline of the holes, where a removed triangle meets a kept one or the hull: lines of
  // every tile, so that a tile's triangles end at a hole's edge, not across it, whatever made
  // the hole. Clip and erase rings are constrained edges already; --max-edge's outline is not.
  for (std::size_t t = 0; t < tin.triangle_slots(); ++t) {
    const auto id = static_cast<TriangleId>(t);
    if (tin.is_ghost(id) || !tin.is_removed(id)) continue;
    for (EdgeId e = 3 * id; e < 3 * id + 3; ++e) {
      const TriangleId other = mesh::triangle_of(tin.twin(e));
      if (!tin.is_ghost(other) && tin.is_removed(other)) continue;
      // On the hull, the edge is no kept triangle's: section() finds it among these.
      if (add(e) && tin.is_ghost(other)) hull_outline_.push_back(constrained_.back());
    }
  }
  std::sort(hull_outline_.begin(), hull_outline_.end());
  std::sort(constrained_.begin(), constrained_.end());
  constrained_.erase(std::unique(constrained_.begin(), constrained_.end()), constrained_.end());
  outline_only_.reserve(constrained_.size());
  for (const auto& e : constrained_)
    outline_only_.push_back(std::binary_search(lines.begin(), lines.end(), e) ? 0 : 1);
}

void TerrainSource::collect_holes(const mesh::Triangulation& tin,
                                  const std::vector<std::uint32_t>& number,
                                  const std::string& crs_wkt, const std::string& what) {
  // The corners that are no kept triangle's vertex, transformed once each; a hole with a corner
  // PROJ cannot place is left out (it is no part of the TIN).
  std::vector<std::uint32_t> extra(number.size(), UINT32_MAX);
  std::vector<Point3> corners;
  std::vector<TriangleId> removed;
  for (std::size_t t = 0; t < tin.triangle_slots(); ++t) {
    const auto id = static_cast<TriangleId>(t);
    if (tin.is_ghost(id) || !tin.is_removed(id)) continue;
    removed.push_back(id);
    for (const VertexId v : tin.triangle(id))
      if (number[v] == UINT32_MAX && extra[v] == UINT32_MAX) {
        extra[v] = static_cast<std::uint32_t>(corners.size());
        const Point2 p = tin.point(v);
        corners.push_back({p.x, p.y, tin.z(v)});
      }
  }
  std::vector<std::uint8_t> placed(corners.size(), 1);
  try {
    io::terrain::to_lon_lat_metres(crs_wkt, corners, what);
  } catch (const InputError&) {
    for (std::size_t i = 0; i < corners.size(); ++i) {
      Point3 one = corners[i];
      try {
        io::terrain::to_lon_lat_metres(crs_wkt, std::span<Point3>(&one, 1), what);
        corners[i] = one;
      } catch (const InputError&) {
        placed[i] = 0;
      }
    }
  }
  for (const TriangleId id : removed) {
    const auto c = tin.triangle(id);
    std::array<Point2, 3> h{};
    bool known = true;
    for (int i = 0; i < 3; ++i) {
      const bool kept = number[c[i]] != UINT32_MAX;
      known = known && (kept || placed[extra[c[i]]]);
      const Point3& p = kept ? vertices_[number[c[i]]] : corners[extra[c[i]]];
      h[i] = {p.x, p.y};
    }
    if (!known) continue;
    if ((h[1].x - h[0].x) * (h[2].y - h[0].y) - (h[1].y - h[0].y) * (h[2].x - h[0].x) < 0)
      std::swap(h[1], h[2]);
    holes_.push_back(h);
  }
}

bool TerrainSource::in_hole(double lon, double lat) const {
  bool found = false;
  for_cells({lon, lat, lon, lat}, hole_cells_, [&](std::size_t cell) {
    for (std::uint32_t i = hole_cells_.begin[cell]; !found && i < hole_cells_.begin[cell + 1];
         ++i) {
      const auto& h = holes_[hole_cells_.items[i]];
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const Point2 &a = h[k], &b = h[(k + 1) % 3];
        inside = (b.x - a.x) * (lat - a.y) - (b.y - a.y) * (lon - a.x) > 0;
      }
      found = inside;
    }
  });
  return found;
}

bool TerrainSource::is_constrained(std::uint32_t a, std::uint32_t b) const {
  if (a > b) std::swap(a, b);
  return std::binary_search(constrained_.begin(), constrained_.end(),
                            std::array<std::uint32_t, 2>{a, b});
}

std::vector<std::uint32_t> TerrainSource::constrained_edges_in(const GeoRectangle& r) const {
  std::vector<std::uint32_t> out;
  for_cells(r, constraint_cells_, [&](std::size_t cell) {
    for (std::uint32_t i = constraint_cells_.begin[cell]; i < constraint_cells_.begin[cell + 1];
         ++i)
      out.push_back(constraint_cells_.items[i]);
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void TerrainSource::set_cells() {
  Cells cells;
  cells.west = bounds_.west;
  cells.south = bounds_.south;
  const double w = std::max(bounds_.east - bounds_.west, 1e-12);
  const double h = std::max(bounds_.north - bounds_.south, 1e-12);
  // About 16 triangles a cell, in cells about as wide as high: a triangle meets one to four
  // cells, so smaller cells list each triangle several times, and a large TIN's index takes
  // longer to fill than the tiles take to read (2M points: 4.6 s a pyramid at 16, 5.4 s at 2).
  const double n = std::max(1.0, static_cast<double>(triangles_.size()) / 16);
  const double side = std::sqrt(w * h / n);
  cells.across = static_cast<std::uint32_t>(std::clamp(std::ceil(w / side), 1.0, 4096.0));
  cells.down = static_cast<std::uint32_t>(std::clamp(std::ceil(h / side), 1.0, 4096.0));
  cells.width = w / cells.across;
  cells.height = h / cells.down;
  triangle_cells_ = cells;
  vertex_cells_ = cells;
  constraint_cells_ = cells;
  hole_cells_ = cells;
}

void TerrainSource::build_index() {
  const auto fill = [&](Cells& c, std::size_t count, auto&& rect_of) {
    c.begin.assign(std::size_t{c.across} * c.down + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<std::uint32_t> next;
      if (pass == 1) {
        prefix_sums(c.begin);
        c.items.reserve(c.begin.back());
        advise_huge_pages(c.items);
        c.items.resize(c.begin.back());
        next.assign(c.begin.begin(), c.begin.end() - 1);
      }
      for (std::size_t i = 0; i < count; ++i)
        for_cells(rect_of(i), c, [&](std::size_t cell) {
          if (pass == 0) {
            if (c.begin[cell] == UINT32_MAX)
              throw GeometryError("a cell of the web-terrain index meets more than 2^32 triangles");
            ++c.begin[cell];
          } else {
            c.items[next[cell]++] = static_cast<std::uint32_t>(i);
          }
        });
    }
  };
  fill(triangle_cells_, triangles_.size(), [&](std::size_t t) {
    prefetch_corners_ahead(triangles_, t, vertices_.data());
    const Point3 &a = vertices_[triangles_[t][0]], &b = vertices_[triangles_[t][1]],
                 &c = vertices_[triangles_[t][2]];
    return GeoRectangle{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}),
                        std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y})};
  });
  fill(constraint_cells_, constrained_.size(), [&](std::size_t e) {
    const Point3 &a = vertices_[constrained_[e][0]], &b = vertices_[constrained_[e][1]];
    return GeoRectangle{std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x),
                        std::max(a.y, b.y)};
  });
  fill(hole_cells_, holes_.size(), [&](std::size_t t) {
    const auto& tri = holes_[t];
    return GeoRectangle{
        std::min({tri[0].x, tri[1].x, tri[2].x}), std::min({tri[0].y, tri[1].y, tri[2].y}),
        std::max({tri[0].x, tri[1].x, tri[2].x}), std::max({tri[0].y, tri[1].y, tri[2].y})};
  });
}

std::uint32_t TerrainSource::column(double lon) const {
  const double c = std::floor((lon - triangle_cells_.west) / triangle_cells_.width);
  return static_cast<std::uint32_t>(std::clamp(c, 0.0, triangle_cells_.across - 1.0));
}

std::uint32_t TerrainSource::row(double lat) const {
  const double r = std::floor((lat - triangle_cells_.south) / triangle_cells_.height);
  return static_cast<std::uint32_t>(std::clamp(r, 0.0, triangle_cells_.down - 1.0));
}

// Calls F(cell) for every cell of CELLS that R overlaps (none when R misses the bounds).
template <class F>
void TerrainSource::for_cells(const GeoRectangle& r, const Cells& cells, F&& f) const {
  if (r.east < bounds_.west || r.west > bounds_.east || r.north < bounds_.south ||
      r.south > bounds_.north)
    return;
  const std::uint32_t x0 = column(r.west), x1 = column(r.east);
  const std::uint32_t y0 = row(r.south), y1 = row(r.north);
  for (std::uint32_t y = y0; y <= y1; ++y)
    for (std::uint32_t x = x0; x <= x1; ++x) f(std::size_t{y} * cells.across + x);
}

double TerrainSource::height_at(double lon, double lat) const {
  return tin_height(lon, lat).value_or(fill_height_);
}

std::optional<double> TerrainSource::tin_height(double lon, double lat) const {
  // Inside a triangle: its plane. On an edge, rounding can put the point a hair outside both
  // triangles: then the one it is least outside, if that is within rounding of its area.
  std::optional<double> found;
  double best = -1;
  bool done = false;
  for_cells({lon, lat, lon, lat}, triangle_cells_, [&](std::size_t cell) {
    for (std::uint32_t i = triangle_cells_.begin[cell];
         !done && i < triangle_cells_.begin[cell + 1]; ++i) {
      const auto& t = triangles_[triangle_cells_.items[i]];
      const Point3 &a = vertices_[t[0]], &b = vertices_[t[1]], &c = vertices_[t[2]];
      const double area = orient(a, b, c.x, c.y);
      if (!(area > 0)) continue;
      const double wa = orient(b, c, lon, lat), wb = orient(c, a, lon, lat),
                   wc = orient(a, b, lon, lat);
      const double least = std::min({wa, wb, wc}) / area;
      if (least < -1e-12 || least <= best) continue;
      best = least;
      found = (wa * a.z + wb * b.z + wc * c.z) / (wa + wb + wc);
      done = least >= 0;
    }
  });
  return found;
}

std::vector<std::uint32_t> TerrainSource::vertices_in(const GeoRectangle& r) const {
  // A coarse tile holds every vertex: room for the cells' vertices at once, not by doubling.
  std::size_t most = 0;
  for_cells(r, vertex_cells_, [&](std::size_t cell) {
    most += vertex_cells_.begin[cell + 1] - vertex_cells_.begin[cell];
  });
  std::vector<std::uint32_t> out;
  out.reserve(most);
  advise_huge_pages(out);
  for_cells(r, vertex_cells_, [&](std::size_t cell) {
    for (std::uint32_t i = vertex_cells_.begin[cell]; i < vertex_cells_.begin[cell + 1]; ++i) {
      const Point3& p = vertices_[i];
      if (p.x >= r.west && p.x <= r.east && p.y >= r.south && p.y <= r.north) out.push_back(i);
    }
  });
  return out;
}

std::vector<SectionPoint> TerrainSource::section(bool along_meridian, double at, double from,
                                                 double to) const {
  assert(from < to);
  // In the line's frame: u across the line (0 on it), s along it.
  const auto u_of = [&](const Point3& p) { return (along_meridian ? p.x : p.y) - at; };
  const auto s_of = [&](const Point3& p) { return along_meridian ? p.y : p.x; };
  std::vector<SectionPoint> out;
  const GeoRectangle r =
      along_meridian ? GeoRectangle{at, from, at, to} : GeoRectangle{from, at, to, at};
  // Each edge from its lower-numbered end, so that both its triangles compute the same.
  const auto cross = [&](std::uint32_t ia, std::uint32_t ib) {
    if (ia > ib) std::swap(ia, ib);
    const Point3 &a = vertices_[ia], &b = vertices_[ib];
    const double ua = u_of(a), ub = u_of(b);
    if (ua == 0) out.push_back({s_of(a), a.z, on_constraint_[ia] != 0});
    if (ub == 0) out.push_back({s_of(b), b.z, on_constraint_[ib] != 0});
    if ((ua < 0 && ub > 0) || (ua > 0 && ub < 0)) {
      const double f = ua / (ua - ub);
      out.push_back(
          {s_of(a) + f * (s_of(b) - s_of(a)), a.z + f * (b.z - a.z), is_constrained(ia, ib)});
    }
  };
  for_cells(r, triangle_cells_, [&](std::size_t cell) {
    for (std::uint32_t i = triangle_cells_.begin[cell]; i < triangle_cells_.begin[cell + 1]; ++i) {
      const auto& t = triangles_[triangle_cells_.items[i]];
      for (int k = 0; k < 3; ++k) cross(t[k], t[(k + 1) % 3]);
    }
  });
  // The holes' outline along the hull, which no kept triangle has: where the line leaves a hole
  // for the fill beyond the data, a vertex of both tiles of the border.
  if (!hull_outline_.empty())
    for_cells(r, constraint_cells_, [&](std::size_t cell) {
      for (std::uint32_t i = constraint_cells_.begin[cell]; i < constraint_cells_.begin[cell + 1];
           ++i) {
        const auto& e = constrained_[constraint_cells_.items[i]];
        if (std::binary_search(hull_outline_.begin(), hull_outline_.end(), e)) cross(e[0], e[1]);
      }
    });
  std::erase_if(out, [&](const SectionPoint& p) { return !(p.at > from && p.at < to); });
  std::sort(out.begin(), out.end(), [](const SectionPoint& a, const SectionPoint& b) {
    if (a.at != b.at) return a.at < b.at;
    if (a.on_constraint != b.on_constraint) return a.on_constraint;
    return a.height < b.height;
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const SectionPoint& a, const SectionPoint& b) { return a.at == b.at; }),
            out.end());
  const double h_from = along_meridian ? height_at(at, from) : height_at(from, at);
  const double h_to = along_meridian ? height_at(at, to) : height_at(to, at);
  out.insert(out.begin(), {from, h_from, false});
  out.push_back({to, h_to, false});
  return out;
}

std::vector<SectionPoint> TerrainSource::outline_beside(bool along_meridian, double at, double from,
                                                        double to, double half_width) const {
  assert(from < to && half_width >= 0);
  const GeoRectangle band = along_meridian
                                ? GeoRectangle{at - half_width, from, at + half_width, to}
                                : GeoRectangle{from, at - half_width, to, at + half_width};
  std::vector<SectionPoint> out;
  for (const std::uint32_t id : vertices_in(band)) {
    const Point3& p = vertices_[id];
    const double s = along_meridian ? p.y : p.x;
    if (!(s > from && s < to)) continue;
    const double lon = along_meridian ? at : s, lat = along_meridian ? s : at;
    if (tin_height(lon, lat) || in_hole(lon, lat)) continue;
    out.push_back({s, p.z, false});
  }
  std::sort(out.begin(), out.end(), [](const SectionPoint& a, const SectionPoint& b) {
    return a.at != b.at ? a.at < b.at : a.height < b.height;
  });
  return out;
}

double TerrainSource::point_spacing_metres() const {
  double area = 0;  // square degrees scaled to metres below
  for (const auto& t : triangles_)
    area += 0.5 * orient(vertices_[t[0]], vertices_[t[1]], vertices_[t[2]].x, vertices_[t[2]].y);
  const double lat = 0.5 * (bounds_.south + bounds_.north) * std::numbers::pi / 180;
  const double square_metres = area * kMetresPerDegree * kMetresPerDegree * std::cos(lat);
  if (vertices_.empty() || !(square_metres > 0)) return 0;
  return std::sqrt(square_metres / static_cast<double>(vertices_.size()));
}

}  // namespace tincdt::web_terrain
