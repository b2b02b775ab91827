#include "products/grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "products/short_number.hpp"

namespace tincdt::products {
namespace {

// Cells along one axis to cover LENGTH: rounded up, except that a count within 1e-9 of a whole
// number is taken as that number (an extent of 100 m at 0.1 m is 1000 cells, not 1001).
double cells_to_cover(double length, double resolution) {
  const double n = length / resolution;
  const double whole = std::round(n);
  if (std::fabs(n - whole) <= 1e-9 * std::max(1.0, whole)) return std::max(1.0, whole);
  return std::max(1.0, std::ceil(n));
}

}  // namespace

void Grid::geotransform(double out[6]) const {
  out[0] = min_x;
  out[1] = resolution;
  out[2] = 0;
  out[3] = max_y;
  out[4] = 0;
  out[5] = -resolution;
}

Grid grid_over(const BBox& extent, double resolution, bool target_aligned) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw Error("the DEM resolution must be a positive number, not " + short_number(resolution));
  if (!(extent.min_x <= extent.max_x) || !(extent.min_y <= extent.max_y) ||
      !std::isfinite(extent.min_x) || !std::isfinite(extent.max_x) ||
      !std::isfinite(extent.min_y) || !std::isfinite(extent.max_y))
    throw Error("the DEM extent is empty or not finite");
  double min_x = extent.min_x, max_x = extent.max_x;
  double min_y = extent.min_y, max_y = extent.max_y;
  if (target_aligned) {
    min_x = std::floor(min_x / resolution) * resolution;
    min_y = std::floor(min_y / resolution) * resolution;
    max_x = std::ceil(max_x / resolution) * resolution;
    max_y = std::ceil(max_y / resolution) * resolution;
  }
  const double magnitude =
      std::max({std::fabs(min_x), std::fabs(max_x), std::fabs(min_y), std::fabs(max_y)});
  if (resolution < std::ldexp(magnitude, -40))
    throw Error("the DEM resolution " + short_number(resolution) +
                " is too fine for coordinates of magnitude " + short_number(magnitude));
  const double width = cells_to_cover(max_x - min_x, resolution);
  const double height = cells_to_cover(max_y - min_y, resolution);
  constexpr double kMaxCells = 2147483647.0;  // GDAL's raster sizes are int
  if (width > kMaxCells || height > kMaxCells)
    throw Error("a DEM of " + short_number(width) + " x " + short_number(height) +
                " cells is too large (at most 2^31 - 1 columns and rows)");
  Grid g;
  g.min_x = min_x;
  g.max_y = max_y;
  g.resolution = resolution;
  g.width = static_cast<std::uint32_t>(width);
  g.height = static_cast<std::uint32_t>(height);
  return g;
}

BBox kept_extent(const mesh::Triangulation& tin) {
  BBox box;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    for (const VertexId v : c) {
      const Point2 p = tin.point(v);
      box.add(p.x, p.y);
    }
  });
  return box;
}

}  // namespace tincdt::products
