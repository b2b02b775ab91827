#include "products/preview.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <span>

#include "core/error.hpp"
#include "products/rasterize.hpp"

namespace tincdt::products {
namespace {

constexpr double kAltitude = 45 * std::numbers::pi / 180;
constexpr double kAzimuths[] = {225, 270, 315, 360};  // degrees clockwise from north

// The grid: SIZE cells on the longer side of the frame, or of the kept extent.
Grid preview_grid(const mesh::Triangulation& tin, const PreviewOptions& options) {
  const std::uint32_t size = options.size;
  const BBox extent = options.frame ? *options.frame : kept_extent(tin);
  if (!(extent.min_x <= extent.max_x)) throw Error("the TIN has no triangle to draw");
  const double longer = std::max(extent.max_x - extent.min_x, extent.max_y - extent.min_y);
  return grid_over(extent, longer > 0 ? longer / size : 1, false);
}

// Brightness 0..1 of the surface with gradient (dzdx, dzdy) (z up, y north).
double multidirectional_shade(double dzdx, double dzdy) {
  const double slope = std::atan(std::hypot(dzdx, dzdy));
  // The downslope direction as an azimuth (clockwise from north), the angle lights are
  // weighted against.
  const double aspect = std::atan2(-dzdx, -dzdy);
  double shade = 0;
  for (const double degrees : kAzimuths) {
    const double azimuth = degrees * std::numbers::pi / 180;
    // gdaldem's weight: cos^2 of the angle between the light and the downslope azimuth, so the
    // light along the slope counts most (its sin^2 takes the aspect counter-clockwise from east).
    const double weight = std::pow(std::cos(aspect - azimuth), 2);
    // Lambert's cosine between the light and the surface normal: brightest facing the light.
    const double lit = std::sin(kAltitude) * std::cos(slope) +
                       std::cos(kAltitude) * std::sin(slope) * std::cos(azimuth - aspect);
    shade += weight * std::max(0.0, lit);
  }
  return shade / 2;  // the four weights, 45 degrees apart, sum to 2
}

// The heights of a 3 x 3 window of a grid of heights (NaN: no value), rows going south, as
// gdaldem -compute_edges makes them: beyond the grid's sides a row or column is extrapolated
// linearly from the two inside it (in the first and last rows a column beyond is the edge
// column again), and a neighbour without a value takes the centre's height.
class Window {
 public:
  Window(const Grid& g, std::span<const double> z) : g_(g), z_(z) {}

  // The height of the neighbour (ROW + dr, COL + dc) of the cell (ROW, COL), which has a value.
  double at(std::int64_t row, std::int64_t col, int dr, int dc) const {
    const double centre = cell(row, col);
    assert(!std::isnan(centre));
    const std::int64_t h = g_.height, w = g_.width;
    std::int64_t r = row + dr, c = col + dc;
    double v = 0;
    if (r < 0 || r >= h) {
      c = std::clamp<std::int64_t>(c, 0, w - 1);
      v = h < 2 ? centre : extrapolated(cell(r < 0 ? 0 : h - 1, c), cell(r < 0 ? 1 : h - 2, c));
    } else if (c < 0 || c >= w) {
      if (w < 2 || row == 0 || row == h - 1)
        v = cell(r, std::clamp<std::int64_t>(c, 0, w - 1));
      else
        v = extrapolated(cell(r, c < 0 ? 0 : w - 1), cell(r, c < 0 ? 1 : w - 2));
    } else {
      v = cell(r, c);
    }
    return std::isnan(v) ? centre : v;
  }

 private:
  double cell(std::int64_t row, std::int64_t col) const {
    return z_[static_cast<std::size_t>(row) * g_.width + static_cast<std::size_t>(col)];
  }
  // The value one cell beyond EDGE, away from INNER (NaN when either has none).
  static double extrapolated(double edge, double inner) { return 2 * edge - inner; }

  const Grid& g_;
  std::span<const double> z_;
};

void shade_cells(const Grid& g, std::span<const double> z, double z_factor, Progress& progress,
                 std::vector<std::uint8_t>& rgba) {
  const Window window(g, z);
  const double scale = z_factor / (8 * g.resolution);
  for (std::uint32_t row = 0; row < g.height; ++row) {
    progress.tick(row);
    for (std::uint32_t col = 0; col < g.width; ++col) {
      const std::size_t i = std::size_t{row} * g.width + col;
      if (std::isnan(z[i])) continue;  // transparent, as rgba was made
      const auto at = [&](int dr, int dc) { return window.at(row, col, dr, dc); };
      const double a = at(-1, -1), b = at(-1, 0), c = at(-1, 1);
      const double d = at(0, -1), f = at(0, 1);
      const double gg = at(1, -1), h = at(1, 0), k = at(1, 1);
      // Horn's 3 x 3 gradient; rows go south, so north is row - 1.
      const double dzdx = ((c + 2 * f + k) - (a + 2 * d + gg)) * scale;
      const double dzdy = ((a + 2 * b + c) - (gg + 2 * h + k)) * scale;
      // gdaldem's greys: 1 (unlit) to 255, 0 being its nodata.
      const auto grey =
          static_cast<std::uint8_t>(std::lround(1 + 254 * multidirectional_shade(dzdx, dzdy)));
      std::uint8_t* px = &rgba[4 * i];
      px[0] = px[1] = px[2] = grey;
      px[3] = 255;
    }
  }
}

// Draws the segment P-Q (TIN coordinates) in COLOUR, pixel by pixel (Bresenham), clipped to
// the grid.
void draw_segment(const Grid& g, Point2 p, Point2 q, const Rgba& colour,
                  std::vector<std::uint8_t>& rgba) {
  const auto col_of = [&](double x) { return std::floor((x - g.min_x) / g.resolution); };
  const auto row_of = [&](double y) { return std::floor((g.max_y - y) / g.resolution); };
  auto x0 = static_cast<std::int64_t>(col_of(p.x)), y0 = static_cast<std::int64_t>(row_of(p.y));
  const auto x1 = static_cast<std::int64_t>(col_of(q.x)),
             y1 = static_cast<std::int64_t>(row_of(q.y));
  const std::int64_t dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const std::int64_t sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  std::int64_t err = dx + dy;
  while (true) {
    if (x0 >= 0 && y0 >= 0 && x0 < g.width && y0 < g.height) {
      const std::size_t i = static_cast<std::size_t>(y0) * g.width + static_cast<std::size_t>(x0);
      std::copy(colour.begin(), colour.end(), rgba.begin() + static_cast<std::ptrdiff_t>(4 * i));
    }
    if (x0 == x1 && y0 == y1) break;
    const std::int64_t e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

// The outline first, the constrained edges over it: a contour along a clip edge shows as a line.
void draw_edges(const mesh::Triangulation& tin, const Grid& g, Progress& progress,
                std::vector<std::uint8_t>& rgba) {
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>&) {
    progress.heartbeat();
    for (int k = 0; k < 3; ++k) {
      const auto e = static_cast<EdgeId>(3 * t + static_cast<std::uint32_t>(k));
      if (!tin.is_kept(mesh::triangle_of(tin.twin(e))))
        draw_segment(g, tin.point(tin.origin(e)), tin.point(tin.dest(e)), kOutlineColour, rgba);
    }
  });
  tin.for_each_constrained_edge([&](EdgeId e) {
    if (tin.is_kept(mesh::triangle_of(e)) || tin.is_kept(mesh::triangle_of(tin.twin(e))))
      draw_segment(g, tin.point(tin.origin(e)), tin.point(tin.dest(e)), kConstraintColour, rgba);
  });
}

// The grid's border pixels, all round.
void draw_frame(const Grid& g, std::vector<std::uint8_t>& rgba) {
  const auto put = [&](std::uint32_t col, std::uint32_t row) {
    const std::size_t i = std::size_t{row} * g.width + col;
    std::copy(kFrameColour.begin(), kFrameColour.end(),
              rgba.begin() + static_cast<std::ptrdiff_t>(4 * i));
  };
  for (std::uint32_t col = 0; col < g.width; ++col) put(col, 0), put(col, g.height - 1);
  for (std::uint32_t row = 0; row < g.height; ++row) put(0, row), put(g.width - 1, row);
}

}  // namespace

PreviewImage render_preview(const mesh::Triangulation& tin, const PreviewOptions& options) {
  if (options.size < 2) throw Error("a preview needs at least 2 pixels a side");
  PreviewImage image;
  image.grid = preview_grid(tin, options);
  const Grid& g = image.grid;
  std::vector<double> z(g.cells());
  rasterize<double>(tin, g, std::nan(""), z,
                    {.threads = options.threads, .progress = options.progress});
  image.rgba.assign(4 * g.cells(), 0);
  // Over the rows shaded; the edges, one report per 2^16 triangles, at the end of it.
  Progress progress(options.progress, "preview", g.height);
  shade_cells(g, z, options.z_factor, progress, image.rgba);
  draw_edges(tin, g, progress, image.rgba);
  progress.finish();
  if (options.frame) draw_frame(g, image.rgba);
  return image;
}

}  // namespace tincdt::products
