// Douglas–Peucker on a profile (a height along a line), by vertical error: the kept points make
// the polyline whose linear interpolation is within the tolerance at every given point. The
// tiles of a web-terrain pyramid simplify the TIN's section along each tile border with it, so
// that the two tiles of a border get the same vertices there.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace tincdt::simplify {

// The indices of the points (AT[i], HEIGHT[i]) kept, ascending, first and last always: every
// point is within TOLERANCE (vertically) of the polyline through the kept ones. AT must be
// strictly increasing. Deterministic: ties go to the first point.
std::vector<std::size_t> simplify_profile(std::span<const double> at,
                                          std::span<const double> height, double tolerance);

}  // namespace tincdt::simplify
