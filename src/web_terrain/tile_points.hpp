// The points of one web-terrain tile's greedy run, shared by the files that gather them
// (tile.cpp: the border and the candidates; lines.cpp: the constrained lines).
// Coordinates are the tile's quantized grid, 0..kQuantizedMax across and up.
#pragma once

#include <cstddef>

#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "simplify/simplify_input.hpp"
#include "web_terrain/source.hpp"

namespace tincdt::web_terrain::detail {

inline constexpr double kGridMax = io::terrain::kQuantizedMax;

// The quantized place of AT between FROM and TO.
double grid_place(double at, double from, double to);

// Kept points first (the border, then the lines' vertices, chained by segments), then the
// candidates; one point a grid place.
using TilePoints = simplify::SimplifyInput;

// Adds SOURCE's constrained lines inside R to P, their border crossings at the border's points
// (P holds the border already): each line simplified by 3D Douglas–Peucker within TOLERANCE,
// its vertices kept and its pieces segments; the holes' outline (TerrainSource::outline_only)
// only WITH_OUTLINE. Returns the number of segments added.
std::size_t add_lines(const TerrainSource& source, const io::terrain::GeoRectangle& r,
                      double tolerance, bool with_outline, TilePoints& p);

}  // namespace tincdt::web_terrain::detail
