// A north-up raster grid in the TIN's coordinates, laid out as GDAL lays it out: the top-left
// corner (min_x, max_y), square cells of `resolution`, row 0 at the top. Cell centres are
// defined by centre_x() / centre_y(), the one formula every caller (rasterizer, tests, writers)
// uses, so "the centre of a cell" is an exact double that exact predicates can be asked about.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::products {

struct Grid {
  double min_x = 0;  // left edge of column 0
  double max_y = 0;  // top edge of row 0
  double resolution = 1;
  std::uint32_t width = 0;
  std::uint32_t height = 0;

  double centre_x(std::uint32_t col) const { return min_x + (col + 0.5) * resolution; }
  double centre_y(std::uint32_t row) const { return max_y - (row + 0.5) * resolution; }
  double max_x() const { return min_x + width * resolution; }
  double min_y() const { return max_y - height * resolution; }
  std::size_t cells() const { return std::size_t{width} * height; }
  // GDAL's geotransform: {min_x, resolution, 0, max_y, 0, -resolution}.
  void geotransform(double out[6]) const;
};

// The smallest grid of cells of RESOLUTION whose top-left corner is (extent.min_x, extent.max_y)
// and that covers EXTENT (an extent that is an exact multiple of the resolution, up to rounding
// of 1e-9 cell, gets no extra column or row). With TARGET_ALIGNED (gdalwarp -tap) the extent is
// first widened to multiples of the resolution, so grids of the same resolution line up cell for
// cell. Throws Error for a resolution that is not a positive finite number, an empty or
// non-finite extent, a grid of more than 2^31 - 1 columns or rows, or a resolution too fine for
// the magnitude of the coordinates (below 2^-40 of it: cell centres would not be distinct
// doubles).
Grid grid_over(const BBox& extent, double resolution, bool target_aligned);

// The x, y extent of the kept (real, not removed) triangles' corners; empty (min > max) when
// there are none.
BBox kept_extent(const mesh::Triangulation& tin);

}  // namespace tincdt::products
