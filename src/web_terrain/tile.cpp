#include "web_terrain/tile.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <iterator>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "core/radix_sort.hpp"
#include "io/terrain/quantized_mesh_detail.hpp"
#include "simplify/profile.hpp"
#include "simplify/simplify.hpp"
#include "web_terrain/tile_points.hpp"

namespace tincdt::web_terrain {
namespace {

using detail::grid_place;
using detail::TilePoints;
using io::terrain::GeoRectangle;
using io::terrain::kQuantizedMax;
using io::terrain::TileMesh;

constexpr double kMax = kQuantizedMax;
// The sides' tolerance, a fraction of the level's error: the same for both tiles of a border,
// whatever their height ranges, with room left for the quantization of the heights.
constexpr double kBorderShare = 0.75;
// Tries of the greedy insertion at a tighter tolerance when the measured error is above the
// level's (the quantization of the vertices moved the surface).
constexpr int kTries = 3;
// Tries of a coarse tile from its children's vertices, each adding the farthest of the TIN's
// vertices in each triangle the last left above half the error, before it takes every vertex under
// it: a try is a pass over the tile's vertices, a greedy run over all of them far more (how many
// tries large pyramids need: docs/benchmarks.md).
constexpr int kTriesFromChildren = 12;

// A side of a tile: where its points go on the quantized grid.
enum class Side { south, east, north, west };

// SIDE's vertices, (place along the side 0..kMax, height), from its first corner to its last
// (west to east, south to north).
std::vector<std::pair<double, double>> side_vertices(const TerrainSource& source,
                                                     const GeoRectangle& r, Side side,
                                                     double tolerance) {
  const bool meridian = side == Side::east || side == Side::west;
  const double at = side == Side::south   ? r.south
                    : side == Side::north ? r.north
                    : side == Side::west  ? r.west
                                          : r.east;
  const double from = meridian ? r.south : r.west, to = meridian ? r.north : r.east;
  std::vector<SectionPoint> section = source.section(meridian, at, from, to);
  // The data's outline within half a grid step beyond the side: its vertices' grid places are
  // on the side, where the section says the fill. The side is as long as the tile is wide, so
  // both tiles of the side find the same vertices.
  const std::vector<SectionPoint> outline =
      source.outline_beside(meridian, at, from, to, (to - from) / kMax / 2);
  if (!outline.empty()) {
    section.insert(section.end() - 1, outline.begin(), outline.end());
    std::stable_sort(section.begin() + 1, section.end() - 1,
                     [](const SectionPoint& a, const SectionPoint& b) { return a.at < b.at; });
  }
  std::vector<double> place, height;
  std::vector<std::uint8_t> forced;  // where a constrained line crosses: a vertex of both tiles
  for (std::size_t i = 0; i < section.size(); ++i) {
    const bool end = i == 0 || i + 1 == section.size();
    const double q = end ? (i == 0 ? 0.0 : kMax) : grid_place(section[i].at, from, to);
    if (!end && (q <= 0 || q >= kMax)) continue;
    if (!place.empty() && q == place.back()) {
      // One point a grid place: a line's crossing before any other, else the first.
      if (end || !section[i].on_constraint || forced.back()) continue;
      place.pop_back();
      height.pop_back();
      forced.pop_back();
    }
    place.push_back(q);
    height.push_back(section[i].height);
    forced.push_back(section[i].on_constraint ? 1 : 0);
  }
  std::vector<std::pair<double, double>> out;
  for (const std::size_t i : simplify::simplify_profile(place, height, tolerance, forced))
    out.emplace_back(place[i], height[i]);
  return out;
}

void add_border(const TerrainSource& source, const GeoRectangle& r, double tolerance,
                TilePoints& p) {
  // Counter-clockwise: south west to east, east south to north, north east to west, west north
  // to south; each side's last corner is the next side's first.
  const Side sides[] = {Side::south, Side::east, Side::north, Side::west};
  for (const Side side : sides) {
    auto v = side_vertices(source, r, side, tolerance);
    if (side == Side::north || side == Side::west) std::reverse(v.begin(), v.end());
    for (std::size_t i = 0; i + 1 < v.size(); ++i) {  // the last is the next side's first
      const double q = v[i].first;
      const Point2 xy = side == Side::south   ? Point2{q, 0}
                        : side == Side::east  ? Point2{kMax, q}
                        : side == Side::north ? Point2{q, kMax}
                                              : Point2{0, q};
      const std::uint32_t id = p.add_kept(xy, v[i].second);
      if (id > 0) p.segments.push_back({id - 1, id, 0});
    }
  }
  p.segments.push_back({static_cast<std::uint32_t>(p.xy.size() - 1), 0, 0});
}

// KEYS (place << 32 | id) in order of their places. A coarse tile has every vertex of the TIN as
// a candidate, where a comparison sort would be most of the tile's work.
void sort_by_place(std::vector<std::uint64_t>& keys) {
  constexpr std::size_t kRadixFrom = 4096;
  if (keys.size() < kRadixFrom) {
    std::sort(keys.begin(), keys.end());
    return;
  }
  std::vector<std::uint64_t> buffer(keys.size());
  radix_sort_by_key(keys.data(), buffer.data(), keys.size());
}

// The candidates of a tile's greedy run (after its kept points): the TIN's vertex of each.
struct Candidates {
  std::uint32_t first = 0;            // the points of TilePoints from here on
  std::vector<std::uint32_t> vertex;  // the TIN's vertex of point first + i
};

// Of the TIN's vertices IDS (ascending), those strictly inside the rectangle's grid, one per grid
// place: the lowest id of a place, the places in order of u, then v.
Candidates add_candidates(const TerrainSource& source, const GeoRectangle& r,
                          std::span<const std::uint32_t> ids, TilePoints& p) {
  assert(std::is_sorted(ids.begin(), ids.end()));
  // u and v are whole places below 2^15: (u, v, i) in one key.
  std::vector<std::uint64_t> keys;
  keys.reserve(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Point3& v = source.vertices()[ids[i]];
    const double u = grid_place(v.x, r.west, r.east), w = grid_place(v.y, r.south, r.north);
    if (u >= 1 && u <= kMax - 1 && w >= 1 && w <= kMax - 1)
      keys.push_back(static_cast<std::uint64_t>(u) << 47 | static_cast<std::uint64_t>(w) << 32 | i);
  }
  sort_by_place(keys);
  Candidates c{static_cast<std::uint32_t>(p.xy.size()), {}};
  for (std::size_t i = 0; i < keys.size();) {
    const std::uint64_t place = keys[i] >> 32;
    const std::uint32_t id = ids[static_cast<std::uint32_t>(keys[i])];  // the least: sorted
    while (++i < keys.size() && keys[i] >> 32 == place) {
    }
    const auto u = static_cast<double>(place >> 15), w = static_cast<double>(place & 0x7fff);
    // Unless a line's vertex is there.
    if (p.add_candidate({u, w}, source.vertices()[id].z) >= c.first) c.vertex.push_back(id);
  }
  return c;
}

double degrees_at(double q, double low, double high) {
  return q >= kMax ? high : q <= 0 ? low : low + q / kMax * (high - low);
}

TileMesh tile_mesh(const GeoRectangle& r, const mesh::Triangulation& tin) {
  TileMesh m;
  m.rectangle = r;
  m.vertices.reserve(tin.vertex_count());
  for (std::size_t i = 0; i < tin.vertex_count(); ++i) {
    const Point2 p = tin.point(static_cast<VertexId>(i));
    m.vertices.push_back({degrees_at(p.x, r.west, r.east), degrees_at(p.y, r.south, r.north),
                          tin.z(static_cast<VertexId>(i))});
  }
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    m.triangles.push_back({c[0], c[1], c[2]});
  });
  return m;
}

}  // namespace

double detail::grid_place(double at, double from, double to) {
  return std::round((at - from) / (to - from) * kMax);
}

void TileError::add(const TileError& other) {
  max = std::max(max, other.max);
  sum_squares += other.sum_squares;
  count += other.count;
  hidden += other.hidden;
}

namespace {

// Throws GeometryError when a triangle of MESH has no area once quantized: lines that cross on
// the grid meet at a vertex between its places, which quantization can put on a line.
void check_quantized_triangles(const TileMesh& mesh) {
  const io::terrain::detail::QuantizedVertices q = io::terrain::detail::quantize_vertices(mesh);
  for (const auto& t : mesh.triangles) {
    const std::int64_t cross =
        (std::int64_t{q.u[t[1]]} - q.u[t[0]]) * (std::int64_t{q.v[t[2]]} - q.v[t[0]]) -
        (std::int64_t{q.v[t[1]]} - q.v[t[0]]) * (std::int64_t{q.u[t[2]]} - q.u[t[0]]);
    if (cross <= 0) throw GeometryError("a tile triangle has no area on the quantized grid");
  }
}

// One flag a triangle of MESH: its centroid is in a hole of SOURCE. The holes' rings are
// constrained lines of the full TIN, so the tile's TIN has edges along them where it holds them.
std::vector<std::uint8_t> hole_triangles(const TerrainSource& source, const TileMesh& mesh) {
  std::vector<std::uint8_t> hole(mesh.triangles.size());
  for (std::size_t t = 0; t < hole.size(); ++t) {
    const auto& c = mesh.triangles[t];
    const Point3 &a = mesh.vertices[c[0]], &b = mesh.vertices[c[1]], &d = mesh.vertices[c[2]];
    hole[t] = source.in_hole((a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3) ? 1 : 0;
  }
  return hole;
}

void drop_triangles(const std::vector<std::uint8_t>& hole, TileMesh& mesh) {
  std::size_t kept = 0;
  for (std::size_t t = 0; t < hole.size(); ++t)
    if (!hole[t]) mesh.triangles[kept++] = mesh.triangles[t];
  mesh.triangles.resize(kept);
}

// Throws Cancelled when PROGRESS (may be null) asks to stop: between the passes over every vertex
// of a tile, which take a while over a large TIN.
void poll(const ProgressFn* progress) {
  if (progress && *progress && !(*progress)("", 0)) throw Cancelled();
}

// Which of the source's lines a tile holds: all, all but the holes' outline, none.
enum class Lines { all, features, none };

// The tile's kept points: its border and its lines (LINES of them).
TilePoints kept_points(const TerrainSource& source, const GeoRectangle& r, double error,
                       Lines lines, std::size_t& line_segments) {
  TilePoints p;
  add_border(source, r, kBorderShare * error, p);
  line_segments = lines == Lines::none
                      ? 0
                      : detail::add_lines(source, r, kBorderShare * error, lines == Lines::all, p);
  return p;
}

// The greedy runs on P: at the tolerance that leaves room for the quantization of the heights,
// then tighter while the measured error is above ERROR.
BuiltTile greedy_tile(const TerrainSource& source, const GeoRectangle& r,
                      std::span<const std::uint32_t> inside, const TilePoints& p,
                      const Candidates& candidates, double error, int tries,
                      std::vector<std::uint32_t>* above, const ProgressFn* progress) {
  poll(progress);
  const auto [low, high] = std::minmax_element(p.z.begin(), p.z.end());
  // A height step of the tile's quantization, at most.
  const double step = (*high - *low) / kMax;
  double tolerance = std::max(0.0, error - step);
  BuiltTile best;
  for (int attempt = 0; attempt < tries; ++attempt) {
    simplify::SimplifyOptions options;
    options.max_error = tolerance;
    options.threads = 1;
    BuiltTile tile;
    try {
      const simplify::SimplifyResult result =
          simplify::simplify(p.xy, p.z, p.kept, p.segments, options, progress);
      assert(result.tin.vertex_count() >= p.kept.size());
      tile.mesh = tile_mesh(r, result.tin);
      for (const std::uint32_t point : result.point_of_vertex)
        if (point != kNoId && point >= candidates.first)
          tile.tin_vertices.push_back(candidates.vertex[point - candidates.first]);
      std::sort(tile.tin_vertices.begin(), tile.tin_vertices.end());
      check_quantized_triangles(tile.mesh);
    } catch (const GeometryError&) {
      if (attempt == 0) throw;
      break;  // a tighter run that fails keeps the best tile so far
    }
    // The surface is measured whole: a hole is where it is not shown, not a height.
    const std::vector<std::uint8_t> hole = hole_triangles(source, tile.mesh);
    if (above) above->clear();
    // Above half the error: the points a greedy insertion would take next, so that few tries do.
    tile.error = measure_tile(source, tile.mesh, hole, inside, progress, error / 2, above);
    drop_triangles(hole, tile.mesh);
    // A tighter run is kept only when it meets the error. One that does not met an error no
    // vertex can remove: the quantized grid moves a point of a near-vertical face (a wall, a
    // tree) by up to half a step. The sparsest tile is kept then.
    if (attempt == 0 || tile.error.max <= error) best = std::move(tile);
    if (best.error.max <= error || tolerance == 0) break;
    tolerance = std::max(0.0, tolerance - (best.error.max - error) - 0.1 * error);
  }
  return best;
}

// The tile over R from KEPT and candidates: with FINER given (a coarse tile), those of the TIN's
// vertices, and the farthest in each triangle that a try leaves above half the error; else, or
// when that does not meet the error, the TIN's vertices INSIDE.
BuiltTile fit(const TerrainSource& source, const GeoRectangle& r,
              std::span<const std::uint32_t> inside, const TilePoints& kept,
              const std::vector<std::uint32_t>* finer, double error, const ProgressFn* progress) {
  if (finer) {
    // The children's vertices hold the finer level's error: most often enough for the tile's.
    std::vector<std::uint32_t> ids = *finer, above, more;
    for (int attempt = 0; attempt < kTriesFromChildren; ++attempt) {
      TilePoints p = kept;
      const Candidates candidates = add_candidates(source, r, ids, p);
      BuiltTile tile = greedy_tile(source, r, inside, p, candidates, error, 1, &above, progress);
      if (tile.error.max <= error) return tile;
      more.clear();
      std::set_union(ids.begin(), ids.end(), above.begin(), above.end(), std::back_inserter(more));
      ids.swap(more);
    }
  }
  TilePoints p = kept;
  const Candidates candidates = add_candidates(source, r, inside, p);
  BuiltTile tile = greedy_tile(source, r, inside, p, candidates, error, kTries, nullptr, progress);
  tile.chose_from_all = finer != nullptr;
  return tile;
}

}  // namespace

BuiltTile build_tile(const TerrainSource& source, const io::terrain::TileKey& key, double error,
                     const ProgressFn* progress, const std::vector<std::uint32_t>* finer) {
  const GeoRectangle r = io::terrain::tile_rectangle(key);
  const std::vector<std::uint32_t> inside = source.vertices_in(r);
  poll(progress);
  // Lines simplified onto the grid can overlap where the full TIN's do not; the tile is then
  // made without the holes' outline, then without any line (its error still holds).
  std::size_t all = 0, features = 0;
  try {
    BuiltTile tile = fit(source, r, inside, kept_points(source, r, error, Lines::all, all), finer,
                         error, progress);
    tile.line_segments = all;
    return tile;
  } catch (const GeometryError&) {
    if (all == 0) throw;
  }
  const TilePoints p = kept_points(source, r, error, Lines::features, features);
  if (features > 0 && features != all) {
    try {
      BuiltTile tile = fit(source, r, inside, p, finer, error, progress);
      tile.line_segments = features;
      tile.outline_dropped = true;
      return tile;
    } catch (const GeometryError&) {
    }
  }
  std::size_t none = 0;
  BuiltTile tile = fit(source, r, inside, kept_points(source, r, error, Lines::none, none), finer,
                       error, progress);
  tile.lines_dropped = true;
  return tile;
}

}  // namespace tincdt::web_terrain
