// DEM rasters from a TIN: every cell whose centre lies in a kept triangle gets that triangle's
// linear interpolation at the centre; every other cell (outside the hull, in a removed triangle:
// clipped, erased, trimmed) is nodata.
//
// Triangle by triangle: each kept triangle is scan-converted over the cell centres of its rows,
// so the cost is the number of cells plus a few exact tests per triangle row, with no point
// location. A centre on an edge or a vertex belongs to exactly one kept triangle (owns_point),
// decided with exact orient2d, so no cell is written twice, none is missed where two triangles
// meet, and the result is the same for any triangle order and thread count.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"
#include "products/grid.hpp"

namespace tincdt::products {

// True when the closed kept triangle T holds P and T is the one kept triangle that P is given
// to. The rule, for P in the closed kept region:
//  - P inside T: T.
//  - P inside an edge: the kept triangle on its side when the other side is not kept (hull,
//    hole); between two kept triangles, the one in which the edge runs downwards (dy < 0), or
//    rightwards when horizontal (dy == 0, dx > 0): the two triangles see the edge in opposite
//    directions, so exactly one of them qualifies (the "top-left" fill rule of GPU rasterizers,
//    turned for a y-up map).
//  - P on a vertex w: going counter-clockwise around w from the direction +x, the first kept
//    triangle met (its wedge [first edge, second edge) counted half-open). Around a vertex inside
//    the kept region this is the triangle whose wedge holds +x, as the edge rule would give; on a
//    boundary or beside a hole it still names exactly one triangle.
// False for a triangle that is not kept.
bool owns_point(const mesh::Triangulation& tin, TriangleId t, Point2 p);

// Calls f(row, first_col, end_col) for the cells [first_col, end_col) of rows [row_begin,
// row_end) of GRID whose centres the kept triangle T owns (owns_point): each such cell once,
// row by row, left to right, in runs.
//
// Along a row the centres strictly inside T form one run of columns, found from the row's two
// edge crossings computed in doubles with a bound on their rounding error; only centres within
// that bound of a crossing (none, almost always) and rows along a horizontal edge are decided
// with owns_point.
template <class F>
void scan_triangle(const mesh::Triangulation& tin, const Grid& grid, TriangleId t,
                   std::uint32_t row_begin, std::uint32_t row_end, F&& f);

struct RasterizeOptions {
  unsigned threads = 0;                  // 0 = every hardware thread
  const ProgressFn* progress = nullptr;  // stage "dem"
};

struct RasterizeStats {
  std::uint64_t cells_with_value = 0;
};

// Fills CELLS (grid.cells() values, row-major from the top-left) with the TIN's surface at each
// cell centre, NODATA elsewhere. T is float or double; the interpolation is in double. Rows are
// split into bands shared by the threads; each band rasterizes the triangles that reach it.
template <class T>
RasterizeStats rasterize(const mesh::Triangulation& tin, const Grid& grid, T nodata,
                         std::span<T> cells, const RasterizeOptions& options = {});

// ---- implementation of scan_triangle ------------------------------------------------------

namespace detail {

// First row whose centre is at or below Y (rows go down), in [0, grid.height].
inline std::uint32_t first_row_at_or_below(const Grid& g, double y) {
  double r = std::ceil((g.max_y - y) / g.resolution - 0.5);
  r = std::fmin(std::fmax(r, 0.0), static_cast<double>(g.height));
  auto row = static_cast<std::uint32_t>(r);
  // The estimate is off by at most one; settle it with the defined centres.
  while (row > 0 && g.centre_y(row - 1) <= y) --row;
  while (row < g.height && g.centre_y(row) > y) ++row;
  return row;
}

// First column whose centre is at or right of X (or strictly right with STRICT), in
// [0, grid.width]. INV_RES: 1 / resolution (the estimate needs no exact division).
inline std::uint32_t first_col_right_of(const Grid& g, double inv_res, double x, bool strict) {
  double c = std::ceil((x - g.min_x) * inv_res - 0.5);
  c = std::fmin(std::fmax(c, 0.0), static_cast<double>(g.width));
  auto col = static_cast<std::uint32_t>(c);
  const auto left_of = [strict, x](double cx) { return strict ? cx <= x : cx < x; };
  while (col > 0 && !left_of(g.centre_x(col - 1))) --col;
  while (col < g.width && left_of(g.centre_x(col))) ++col;
  return col;
}

}  // namespace detail

template <class F>
void scan_triangle(const mesh::Triangulation& tin, const Grid& grid, TriangleId t,
                   std::uint32_t row_begin, std::uint32_t row_end, F&& f) {
  if (!tin.is_kept(t)) return;
  const auto c = tin.triangle(t);
  // Corners from the highest y down: top, middle, bottom (the long edge joins top and bottom).
  Point2 top = tin.point(c[0]), mid = tin.point(c[1]), bot = tin.point(c[2]);
  if (mid.y > top.y) std::swap(mid, top);
  if (bot.y > mid.y) std::swap(bot, mid);
  if (mid.y > top.y) std::swap(mid, top);
  // Rows whose centre y is in [bot.y, top.y]: exact comparisons of the defined centres.
  std::uint32_t r0 = detail::first_row_at_or_below(grid, top.y);
  std::uint32_t r1 = detail::first_row_at_or_below(grid, std::nextafter(bot.y, -INFINITY));
  if (r0 < row_begin) r0 = row_begin;
  if (r1 > row_end) r1 = row_end;
  if (r0 >= r1) return;

  // A row's crossing with edge p q is p.x + (y - p.y) * (dx / dy). Its error is at most about
  // 9 eps max(|p.x|, |q.x|) (four rounded operations, |y - p.y| <= |dy|); 32 eps of the largest
  // |x| of the corners, and a floor for subnormal magnitudes, is the margin within which a
  // centre is decided exactly.
  const double x_abs = std::fmax(std::fabs(top.x), std::fmax(std::fabs(mid.x), std::fabs(bot.x)));
  const double margin = 32 * 0x1p-53 * x_abs + 0x1p-1000;
  const double inv_res = 1 / grid.resolution;
  const double slope_long = (bot.x - top.x) / (bot.y - top.y);  // top.y > bot.y: positive area
  const double slope_upper = top.y > mid.y ? (mid.x - top.x) / (mid.y - top.y) : 0;
  const double slope_lower = mid.y > bot.y ? (bot.x - mid.x) / (bot.y - mid.y) : 0;

  for (std::uint32_t row = r0; row < r1; ++row) {
    const double y = grid.centre_y(row);
    const double x_long = top.x + (y - top.y) * slope_long;
    double x_short;
    bool on_horizontal_edge = false;
    if (y > mid.y) {
      x_short = top.x + (y - top.y) * slope_upper;
    } else if (y < mid.y) {
      x_short = mid.x + (y - mid.y) * slope_lower;
    } else {
      // Through the middle corner, and along an edge when it is as high as another corner.
      x_short = mid.x;
      on_horizontal_edge = mid.y == top.y || mid.y == bot.y;
    }
    double x_left = std::fmin(x_long, x_short), x_right = std::fmax(x_long, x_short);
    if (on_horizontal_edge) {
      const double other = mid.y == top.y ? top.x : bot.x;
      x_left = std::fmin(x_left, other);
      x_right = std::fmax(x_right, other);
    }
    // Columns [c_out_l, c_in_l) and [c_in_r, c_out_r) near the crossings are decided exactly,
    // [c_in_l, c_in_r) is strictly inside; along a horizontal edge every column is exact.
    const std::uint32_t c_out_l = detail::first_col_right_of(grid, inv_res, x_left - margin, false);
    const std::uint32_t c_out_r = detail::first_col_right_of(grid, inv_res, x_right + margin, true);
    if (c_out_l >= c_out_r) continue;
    std::uint32_t c_in_l = c_out_l;
    while (c_in_l < c_out_r && grid.centre_x(c_in_l) <= x_left + margin) ++c_in_l;
    std::uint32_t c_in_r = c_out_r;
    while (c_in_r > c_in_l && grid.centre_x(c_in_r - 1) >= x_right - margin) --c_in_r;
    if (on_horizontal_edge) c_in_l = c_in_r = c_out_r;
    for (std::uint32_t col = c_out_l; col < c_in_l; ++col)
      if (owns_point(tin, t, {grid.centre_x(col), y})) f(row, col, col + 1);
    if (c_in_l < c_in_r) f(row, c_in_l, c_in_r);
    for (std::uint32_t col = c_in_r; col < c_out_r; ++col)
      if (owns_point(tin, t, {grid.centre_x(col), y})) f(row, col, col + 1);
  }
}

}  // namespace tincdt::products
