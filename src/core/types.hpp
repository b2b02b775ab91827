// Ids and small geometric value types shared by every module.
#pragma once

#include <cstdint>
#include <limits>

namespace tincdt {

using VertexId = std::uint32_t;
using TriangleId = std::uint32_t;
// A half-edge is corner i of triangle t, stored at index 3 * t + i; it runs from
// corner i to corner (i + 1) % 3.
using EdgeId = std::uint32_t;

inline constexpr std::uint32_t kNoId = std::numeric_limits<std::uint32_t>::max();

struct Point2 {
  double x;
  double y;
  friend bool operator==(const Point2&, const Point2&) = default;
};

// The order by x, then y: where every job must pick the same point or corner whatever the
// order in memory (hull starts, canonical triangles, the split of the Delaunay halves).
inline bool xy_less(Point2 a, Point2 b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

struct Point3 {
  double x;
  double y;
  double z;
  friend bool operator==(const Point3&, const Point3&) = default;
};

struct BBox {
  double min_x = std::numeric_limits<double>::infinity();
  double min_y = std::numeric_limits<double>::infinity();
  double max_x = -std::numeric_limits<double>::infinity();
  double max_y = -std::numeric_limits<double>::infinity();

  void add(double x, double y) {
    if (x < min_x) min_x = x;
    if (x > max_x) max_x = x;
    if (y < min_y) min_y = y;
    if (y > max_y) max_y = y;
  }
};

}  // namespace tincdt
