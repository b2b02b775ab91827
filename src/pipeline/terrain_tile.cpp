#include "pipeline/terrain_tile.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <tuple>
#include <vector>

#include "io/terrain/quantized_mesh_detail.hpp"
#include "simplify/profile.hpp"
#include "simplify/simplify.hpp"

namespace tincdt::pipeline::terrain {
namespace {

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

// A side of a tile: where its points go on the quantized grid.
enum class Side { south, east, north, west };

// The quantized place of AT between FROM and TO.
double grid_place(double at, double from, double to) {
  return std::round((at - from) / (to - from) * kMax);
}

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
  const std::vector<SectionPoint> section = source.section(meridian, at, from, to);
  std::vector<double> place, height;
  for (std::size_t i = 0; i < section.size(); ++i) {
    const bool end = i == 0 || i + 1 == section.size();
    const double q = end ? (i == 0 ? 0.0 : kMax) : grid_place(section[i].at, from, to);
    if (!end && (q <= 0 || q >= kMax || (!place.empty() && q == place.back()))) continue;
    place.push_back(q);
    height.push_back(section[i].height);
  }
  std::vector<std::pair<double, double>> out;
  for (const std::size_t i : simplify::simplify_profile(place, height, tolerance))
    out.emplace_back(place[i], height[i]);
  return out;
}

// The points of a tile's greedy run: the border first (kept, chained by segments), then the
// candidates.
struct TilePoints {
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<std::uint32_t> kept;
  std::vector<constraints::Segment> segments;
};

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
      const auto id = static_cast<std::uint32_t>(p.xy.size());
      p.xy.push_back(xy);
      p.z.push_back(v[i].second);
      p.kept.push_back(id);
      if (id > 0) p.segments.push_back({id - 1, id, 0});
    }
  }
  p.segments.push_back({static_cast<std::uint32_t>(p.xy.size() - 1), 0, 0});
}

// The full TIN's vertices strictly inside the rectangle's grid, one per grid place.
void add_candidates(const TerrainSource& source, const GeoRectangle& r, TilePoints& p) {
  std::vector<std::tuple<double, double, std::uint32_t>> cells;
  for (const std::uint32_t id : source.vertices_in(r)) {
    const Point3& v = source.vertices()[id];
    const double u = grid_place(v.x, r.west, r.east), w = grid_place(v.y, r.south, r.north);
    if (u >= 1 && u <= kMax - 1 && w >= 1 && w <= kMax - 1) cells.emplace_back(u, w, id);
  }
  std::sort(cells.begin(), cells.end());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto& [u, w, id] = cells[i];
    if (i > 0 && std::get<0>(cells[i - 1]) == u && std::get<1>(cells[i - 1]) == w) continue;
    p.xy.push_back({u, w});
    p.z.push_back(source.vertices()[id].z);
  }
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

void TileError::add(const TileError& other) {
  max = std::max(max, other.max);
  sum_squares += other.sum_squares;
  count += other.count;
}

BuiltTile build_tile(const TerrainSource& source, const io::terrain::TileKey& key, double error) {
  const GeoRectangle r = io::terrain::tile_rectangle(key);
  TilePoints p;
  add_border(source, r, kBorderShare * error, p);
  const std::size_t border = p.xy.size();
  add_candidates(source, r, p);
  const auto [low, high] = std::minmax_element(p.z.begin(), p.z.end());
  // A height step of the tile's quantization, at most.
  const double step = (*high - *low) / kMax;
  double tolerance = std::max(0.0, error - step);
  BuiltTile best;
  for (int attempt = 0; attempt < kTries; ++attempt) {
    simplify::SimplifyOptions options;
    options.max_error = tolerance;
    options.threads = 1;
    const simplify::SimplifyResult result =
        simplify::simplify(p.xy, p.z, p.kept, p.segments, options);
    assert(result.tin.vertex_count() >= border);
    (void)border;
    BuiltTile tile{tile_mesh(r, result.tin), {}};
    tile.error = measure_tile(source, tile.mesh);
    // A tighter run is kept only when it meets the error. One that does not met an error no
    // vertex can remove: the quantized grid moves a point of a near-vertical face (a wall, a
    // tree) by up to half a step. The sparsest tile is kept then.
    if (attempt == 0 || tile.error.max <= error) best = std::move(tile);
    if (best.error.max <= error || tolerance == 0) break;
    tolerance = std::max(0.0, tolerance - (best.error.max - error) - 0.1 * error);
  }
  return best;
}

}  // namespace tincdt::pipeline::terrain
