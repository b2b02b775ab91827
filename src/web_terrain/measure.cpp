// The error of a web-terrain tile as a client sees it: the vertices quantized as the file holds
// them, the surface interpolated linearly in the quantized u, v, and compared with every vertex of
// the full TIN in the tile's rectangle at its place on the tile's grid.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "core/rounding.hpp"
#include "io/terrain/quantized_mesh_detail.hpp"
#include "web_terrain/tile.hpp"

namespace tincdt::web_terrain {
namespace {

using io::terrain::kQuantizedMax;

constexpr std::size_t kVerticesBetweenReports = std::size_t{1} << 16;

struct Corner {
  double u, v, h;
};

double orient(const Corner& a, const Corner& b, double u, double v) {
  return (b.u - a.u) * (v - a.v) - (b.v - a.v) * (u - a.u);
}

// The triangles of a tile in a grid of cells over its quantized square.
struct TriangleGrid {
  std::uint32_t side;
  std::vector<std::vector<std::uint32_t>> cells;

  std::uint32_t cell_of(double q) const {
    const double c = std::floor(q / (kQuantizedMax + 1.0) * side);
    return static_cast<std::uint32_t>(std::clamp(c, 0.0, side - 1.0));
  }
};

TriangleGrid grid_of(const std::vector<std::array<Corner, 3>>& triangles) {
  TriangleGrid g;
  g.side = static_cast<std::uint32_t>(
      std::clamp(std::sqrt(static_cast<double>(triangles.size())), 1.0, 256.0));
  g.cells.resize(std::size_t{g.side} * g.side);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& c = triangles[t];
    const auto x0 = g.cell_of(std::min({c[0].u, c[1].u, c[2].u}));
    const auto x1 = g.cell_of(std::max({c[0].u, c[1].u, c[2].u}));
    const auto y0 = g.cell_of(std::min({c[0].v, c[1].v, c[2].v}));
    const auto y1 = g.cell_of(std::max({c[0].v, c[1].v, c[2].v}));
    for (auto y = y0; y <= y1; ++y)
      for (auto x = x0; x <= x1; ++x)
        g.cells[std::size_t{y} * g.side + x].push_back(static_cast<std::uint32_t>(t));
  }
  return g;
}

struct SurfacePoint {
  double height = 0;
  bool in_hole = false;
  std::uint32_t triangle = UINT32_MAX;  // the one that gave the height
};

// How far U, V lies outside triangle C, in grid steps (0 inside or on it).
double distance_outside(const std::array<Corner, 3>& c, double u, double v) {
  double farthest = 0;
  for (int i = 0; i < 3; ++i) {
    const Corner &a = c[i], &b = c[(i + 1) % 3];
    const double side = orient(a, b, u, v);
    if (side < 0) farthest = std::max(farthest, -side / std::hypot(b.u - a.u, b.v - a.v));
  }
  return farthest;
}

// The barycentric weights of a point in a triangle, and the height they give.
struct Weights {
  double a, b, c;
  double least() const { return std::min({a, b, c}); }
  double height(const std::array<Corner, 3>& t) const {
    return a * t[0].h + b * t[1].h + c * t[2].h;
  }
};

// The weights of U, V in triangle C of AREA.
Weights weights(const std::array<Corner, 3>& c, double area, double u, double v) {
  return {orient(c[1], c[2], u, v) / area, orient(c[2], c[0], u, v) / area,
          orient(c[0], c[1], u, v) / area};
}

bool strictly_inside(const std::array<Corner, 3>& c, double area, double u, double v) {
  return area > 0 && orient(c[1], c[2], u, v) > 0 && orient(c[2], c[0], u, v) > 0 &&
         orient(c[0], c[1], u, v) > 0;
}

// The surface's height at U, V: the triangle of the cell that holds the point best (the least
// negative barycentric weight, for a point on an edge rounded off it). A point whose triangle is
// a hole's is in the hole unless a shown triangle is within a grid step (its place is rounded).
// LAST, the shown triangle that held the previous point strictly inside, is tried first: the
// vertices come cell by cell, neighbours mostly in one triangle. Places and corners are whole
// grid steps, so orient() is exact: a point strictly inside a triangle is in no other, and that
// triangle is the one the weights would choose.
SurfacePoint surface_at(const std::vector<std::array<Corner, 3>>& triangles,
                        const std::vector<double>& areas, std::span<const std::uint8_t> hole,
                        const TriangleGrid& g, double u, double v, std::uint32_t& last) {
  if (last != UINT32_MAX && strictly_inside(triangles[last], areas[last], u, v))
    return {weights(triangles[last], areas[last], u, v).height(triangles[last]), false, last};
  const std::vector<std::uint32_t>& cell =
      g.cells[std::size_t{g.cell_of(v)} * g.side + g.cell_of(u)];
  std::uint32_t best_triangle = UINT32_MAX;
  SurfacePoint out;
  for (const std::uint32_t t : cell) {
    if (strictly_inside(triangles[t], areas[t], u, v)) {
      out.height = weights(triangles[t], areas[t], u, v).height(triangles[t]);
      best_triangle = t;
      if (hole.empty() || !hole[t]) last = t;
      break;
    }
  }
  if (best_triangle == UINT32_MAX) {  // on an edge, or rounded off the triangles
    double best = -INFINITY;
    for (const std::uint32_t t : cell) {
      if (!(areas[t] > 0)) continue;
      const Weights w = weights(triangles[t], areas[t], u, v);
      if (w.least() <= best) continue;
      best = w.least();
      best_triangle = t;
      out.height = w.height(triangles[t]);
    }
  }
  out.triangle = best_triangle;
  if (best_triangle == UINT32_MAX || hole.empty() || !hole[best_triangle]) return out;
  out.in_hole = std::none_of(cell.begin(), cell.end(), [&](std::uint32_t t) {
    return !hole[t] && distance_outside(triangles[t], u, v) <= 1;
  });
  return out;
}

}  // namespace

TileError measure_tile(const TerrainSource& source, const io::terrain::TileMesh& mesh,
                       std::span<const std::uint8_t> hole, std::span<const std::uint32_t> vertices,
                       const ProgressFn* progress, double limit,
                       std::vector<std::uint32_t>* above) {
  const io::terrain::detail::QuantizedVertices q = io::terrain::detail::quantize_vertices(mesh);
  const double low = q.minimum_height, high = q.maximum_height;
  std::vector<std::array<Corner, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    std::array<Corner, 3> c{};
    for (int i = 0; i < 3; ++i)
      c[i] = {static_cast<double>(q.u[t[i]]), static_cast<double>(q.v[t[i]]),
              low + (high - low) * (q.height[t[i]] / static_cast<double>(kQuantizedMax))};
    triangles.push_back(c);
  }
  std::vector<double> areas;
  areas.reserve(triangles.size());
  for (const auto& c : triangles) areas.push_back(orient(c[0], c[1], c[2].u, c[2].v));
  const TriangleGrid grid = grid_of(triangles);
  const io::terrain::GeoRectangle& r = mesh.rectangle;
  TileError error;
  std::uint32_t last = UINT32_MAX;
  struct Farthest {
    double error = 0;
    std::uint32_t vertex = UINT32_MAX;
  };
  std::vector<Farthest> farthest(above ? triangles.size() : 0);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    // A tile over a large TIN measures millions of vertices: a request to stop gets through.
    if (i % kVerticesBetweenReports == 0 && progress && *progress && !(*progress)("", 0))
      throw Cancelled();
    const Point3& p = source.vertices()[vertices[i]];
    // At the vertex's place on the tile's grid, the finest a tile can place it: beside a steep
    // triangle (the fill's ramp down from the data's outline) half a step sideways is a height.
    const double u = round_half_away((p.x - r.west) / (r.east - r.west) * kQuantizedMax);
    const double v = round_half_away((p.y - r.south) / (r.north - r.south) * kQuantizedMax);
    const SurfacePoint s = surface_at(triangles, areas, hole, grid, u, v, last);
    const double e = std::fabs(p.z - s.height);
    error.hidden += s.in_hole ? 1 : 0;
    if (above && e > limit && s.triangle != UINT32_MAX && e > farthest[s.triangle].error)
      farthest[s.triangle] = {e, vertices[i]};
    error.max = std::max(error.max, e);
    error.sum_squares += e * e;
    ++error.count;
  }
  if (above) {
    for (const Farthest& f : farthest)
      if (f.vertex != UINT32_MAX) above->push_back(f.vertex);
    std::sort(above->begin(), above->end());
  }
  return error;
}

}  // namespace tincdt::web_terrain
