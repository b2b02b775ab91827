// The order in which points enter the Delaunay stage.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace tincdt::delaunay {

// Index along the Hilbert curve of cell (x, y) of a 2^bits x 2^bits grid.
std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y, int bits);

// Point indices in insertion order: biased randomized insertion order (BRIO) rounds, a small
// random sample first and each round about 8 times the previous, every round sorted along a
// Hilbert curve so that each point lands near the one before it. The round is drawn from a hash
// of the coordinates, so points with equal x, y share round and cell and come out adjacent.
std::vector<std::uint32_t> insertion_order(const std::vector<Point3>& points, const BBox& box);

}  // namespace tincdt::delaunay
