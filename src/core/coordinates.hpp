// The coordinates tincdt accepts from its inputs, and how the readers hand them on.
//
// The predicates are exact for any finite double, but much else is not a predicate: constraint
// crossings, draped heights, centroids, areas and quality figures are computed in doubles from
// products of coordinate differences, which overflow to infinity long before the coordinates do
// (y = 1e308 crossing another segment gives an infinite vertex). Within +-1e15 the product of
// even four differences stays below 1e62, far from overflow, while every real coordinate fits:
// metres on Earth (1e7), millimetres (1e10), geocentric and projected systems alike. A reader
// refuses a coordinate outside it, naming the record, rather than let it through.
#pragma once

#include <cmath>

#include "core/types.hpp"

namespace tincdt {

inline constexpr double kMaxCoordinate = 1e15;
inline constexpr const char* kMaxCoordinateText = "1e15";

// False for NaN, infinities and magnitudes above kMaxCoordinate.
inline bool coordinate_in_range(double v) {
  return std::fabs(v) <= kMaxCoordinate;
}

// -0 becomes +0 (and nothing else changes): -0 == 0, but its bit pattern differs, and hashes,
// duplicate merging and written files must see one zero.
inline double without_signed_zero(double v) {
  return v + 0.0;  // exact; -0 + +0 = +0 in round-to-nearest (no -ffast-math: see predicates)
}

inline Point3 without_signed_zero(Point3 p) {
  return {without_signed_zero(p.x), without_signed_zero(p.y), without_signed_zero(p.z)};
}

}  // namespace tincdt
