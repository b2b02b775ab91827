#include "terrain/regions.hpp"

namespace tincdt::terrain {

TriangleId largest_triangle(const mesh::Triangulation& tin, std::span<const TriangleId> members,
                            TriangleId below) {
  TriangleId largest = kNoId;
  double largest_area = 0;
  for (const TriangleId t : members) {
    if (t >= below) continue;
    const auto c = tin.triangle(t);
    const Point2 a = tin.point(c[0]), b = tin.point(c[1]), d = tin.point(c[2]);
    const double area = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    if (largest == kNoId || area > largest_area) {
      largest = t;
      largest_area = area;
    }
  }
  return largest;
}

}  // namespace tincdt::terrain
