// The points of one web-terrain tile's greedy run, shared by the files that gather them
// (tile.cpp: the border and the candidates; lines.cpp: the constrained lines).
// Coordinates are the tile's quantized grid, 0..kQuantizedMax across and up.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/types.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "web_terrain/source.hpp"

namespace tincdt::web_terrain::detail {

inline constexpr double kGridMax = io::terrain::kQuantizedMax;

// The quantized place of AT between FROM and TO.
double grid_place(double at, double from, double to);

// Kept points first (the border, then the lines' vertices, chained by segments), then the
// candidates; one point a grid place.
struct TilePoints {
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<std::uint32_t> kept;
  std::vector<constraints::Segment> segments;
  std::map<std::pair<double, double>, std::uint32_t> at_place;

  // The point at grid place XY: the one there already, else a new kept point at height Z.
  std::uint32_t kept_point(Point2 xy_place, double height) {
    const auto [it, added] =
        at_place.try_emplace({xy_place.x, xy_place.y}, static_cast<std::uint32_t>(xy.size()));
    if (added) {
      xy.push_back(xy_place);
      z.push_back(height);
      kept.push_back(it->second);
    }
    return it->second;
  }
  // The point at grid place XY, if there is one.
  const std::uint32_t* find(Point2 xy_place) const {
    const auto it = at_place.find({xy_place.x, xy_place.y});
    return it == at_place.end() ? nullptr : &it->second;
  }
};

// Adds SOURCE's constrained lines inside R to P, their border crossings at the border's points
// (P holds the border already): each line simplified by 3D Douglas–Peucker within TOLERANCE,
// its vertices kept and its pieces segments. Returns the number of segments added.
std::size_t add_lines(const TerrainSource& source, const io::terrain::GeoRectangle& r,
                      double tolerance, TilePoints& p);

}  // namespace tincdt::web_terrain::detail
