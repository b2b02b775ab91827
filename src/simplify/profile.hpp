// Douglas–Peucker on a profile (a height along a line), by vertical error: the kept points make
// the polyline whose linear interpolation is within the tolerance at every given point. The
// tiles of a web-terrain pyramid simplify the TIN's section along each tile border with it, so
// that the two tiles of a border get the same vertices there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace tincdt::simplify {

// The indices of the points (AT[i], HEIGHT[i]) kept, ascending, first and last always: every
// point is within TOLERANCE (vertically) of the polyline through the kept ones; KEEP[i] != 0 forces
// point i. AT must be strictly increasing. Deterministic: ties go to the first point.
std::vector<std::size_t> simplify_profile(std::span<const double> at,
                                          std::span<const double> height, double tolerance,
                                          std::span<const std::uint8_t> keep = {});

// Douglas–Peucker on a 3D polyline (x, y, z in one unit): a point is kept when it is farther than
// TOLERANCE from the chord of its span horizontally, or vertically from the chord's height where
// it projects. The indices kept, ascending, first and last always; KEEP[i] != 0 forces point i.
std::vector<std::size_t> simplify_polyline(std::span<const Point3> points, double tolerance,
                                           std::span<const std::uint8_t> keep = {});

}  // namespace tincdt::simplify
