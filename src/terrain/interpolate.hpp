// Heights on the TIN surface: linear interpolation in the triangle holding a point (draping soft
// lines and 2D polygon rings, comparing a TIN with a DEM).
#pragma once

#include <cstdint>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

// The z of the TIN's surface at p: the plane through the corners of the (closed) triangle that
// holds p. NaN outside the convex hull, inside a removed triangle (clipped, erased or trimmed: no
// surface there) and on a TIN without triangles. `hint` is a triangle to start the walk from
// (e.g. the last one found for a nearby point); kNoId starts anywhere.
double interpolate_z(const mesh::Triangulation& tin, Point2 p, TriangleId hint = kNoId);

// The same for many points in a row: each walk starts where the previous one ended, so points
// in spatial order (a polyline, a raster row) cost a few steps each.
class SurfaceSampler {
 public:
  // `start`: a triangle to begin the first walk from; kNoId starts anywhere.
  explicit SurfaceSampler(const mesh::Triangulation& tin, TriangleId start = kNoId)
      : tin_(tin), start_(start) {}
  double z_at(Point2 p);
  // The real triangle whose closed area holds P, removed or not (kNoId outside the hull).
  TriangleId locate(Point2 p);
  // The triangle that held the last point (kNoId if it was outside the hull).
  TriangleId last_triangle() const { return found_; }

 private:
  const mesh::Triangulation& tin_;
  TriangleId start_ = kNoId;
  TriangleId found_ = kNoId;
  std::uint64_t random_ = 0x9e3779b97f4a7c15ULL;
};

}  // namespace tincdt::terrain
