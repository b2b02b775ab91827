// The preview picture: its size, transparency where there is no surface, the edges drawn in
// their colours, and shading that is brighter where a slope faces the lights (north-west) than
// where it faces away, on TINs built in the test.
#include "products/preview.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"

namespace tincdt::products {
namespace {

// A lattice of (N + 1) x (M + 1) points over [0, N] x [0, M] with heights z(x, y).
mesh::Triangulation lattice(int n, int m, const std::function<double(double, double)>& z) {
  std::vector<Point3> pts;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= m; ++j) pts.push_back({double(i), double(j), z(i, j)});
  return delaunay::triangulate(std::move(pts)).tin;
}

Rgba pixel(const PreviewImage& image, std::uint32_t col, std::uint32_t row) {
  const std::size_t i = 4 * (std::size_t{row} * image.grid.width + col);
  return {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2], image.rgba[i + 3]};
}

// The pixel over the point (x, y) of the TIN.
Rgba pixel_at(const PreviewImage& image, double x, double y) {
  const Grid& g = image.grid;
  return pixel(image, static_cast<std::uint32_t>((x - g.min_x) / g.resolution),
               static_cast<std::uint32_t>((g.max_y - y) / g.resolution));
}

TEST(Preview, TheLongerSideHasTheSizeAndTheShapeIsKept) {
  const mesh::Triangulation tin = lattice(20, 10, [](double, double) { return 0.0; });
  const PreviewImage image = render_preview(tin, {.size = 64});
  EXPECT_EQ(image.grid.width, 64u);
  EXPECT_EQ(image.grid.height, 32u);
  EXPECT_EQ(image.rgba.size(), 4u * 64 * 32);
  EXPECT_THROW(render_preview(tin, {.size = 1}), Error);
}

TEST(Preview, AFlatSurfaceIsEvenlyLitAndOpaque) {
  const PreviewImage image =
      render_preview(lattice(10, 10, [](double, double) { return 5.0; }), {.size = 40});
  // Away from the outline (drawn in red on the border pixels): the flat grey of sin(45 deg).
  for (std::uint32_t row = 2; row + 2 < image.grid.height; ++row)
    for (std::uint32_t col = 2; col + 2 < image.grid.width; ++col) {
      const Rgba p = pixel(image, col, row);
      ASSERT_EQ(p[3], 255) << col << " " << row;
      ASSERT_NEAR(p[0], 255 * std::sin(std::numbers::pi / 4), 1) << col << " " << row;
      ASSERT_EQ(p[0], p[1]);
      ASSERT_EQ(p[0], p[2]);
    }
}

TEST(Preview, SlopesFacingTheLightsAreBrighter) {
  // Heights falling towards the north-west (facing the lights) on the left half, towards the
  // south-east on the right: a valley along x = 20 would blur that, so two separate TINs.
  const auto faces_nw = [](double x, double y) { return 0.5 * x - 0.5 * y; };
  const auto faces_se = [](double x, double y) { return -0.5 * x + 0.5 * y; };
  const PreviewImage lit = render_preview(lattice(10, 10, faces_nw), {.size = 40});
  const PreviewImage dark = render_preview(lattice(10, 10, faces_se), {.size = 40});
  EXPECT_GT(int(pixel_at(lit, 5, 5)[0]), int(pixel_at(dark, 5, 5)[0]) + 50);
  // Steeper faces away from the light go darker.
  const auto steep_se = [](double x, double y) { return -2.0 * x + 2.0 * y; };
  const PreviewImage darker = render_preview(lattice(10, 10, steep_se), {.size = 40});
  EXPECT_LT(pixel_at(darker, 5, 5)[0], pixel_at(dark, 5, 5)[0]);
}

TEST(Preview, NoSurfaceIsTransparent) {
  // A triangle's TIN: the bounding box's upper-left half holds no surface.
  std::vector<Point3> pts = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}};
  mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  PreviewImage image = render_preview(tin, {.size = 50});
  EXPECT_EQ(pixel_at(image, 2, 8)[3], 0);
  EXPECT_EQ(pixel_at(image, 8, 2)[3], 255);

  // Removed (clipped, erased) triangles too, with the outline drawn around the hole.
  mesh::Triangulation grid = lattice(10, 10, [](double, double) { return 1.0; });
  for (TriangleId t = 0; t < grid.triangle_slots(); ++t) {
    if (grid.is_ghost(t)) continue;
    const auto c = grid.triangle(t);
    double cx = 0, cy = 0;
    for (const VertexId v : c) cx += grid.point(v).x / 3, cy += grid.point(v).y / 3;
    if (cx > 4 && cx < 6 && cy > 4 && cy < 6) grid.set_removed(t, true);
  }
  grid.recount();
  image = render_preview(grid, {.size = 100});
  EXPECT_EQ(pixel_at(image, 5.02, 5.03)[3], 0);
  EXPECT_EQ(pixel_at(image, 2.5, 2.5)[3], 255);
  EXPECT_EQ(pixel_at(image, 4.55, 4.0), kOutlineColour);  // the hole's lower side, y = 4
}

TEST(Preview, ConstrainedEdgesAreDrawnOverTheSurface) {
  mesh::Triangulation tin = lattice(10, 10, [](double, double) { return 1.0; });
  tin.build_vertex_index();
  // The lattice's vertical edges at x = 5, from y = 2 to y = 8, as a constrained line.
  int marked = 0;
  for (int y = 2; y < 8; ++y) {
    VertexId a = kNoId, b = kNoId;
    for (VertexId v = 0; v < tin.vertex_count(); ++v) {
      if (tin.point(v).x == 5 && tin.point(v).y == y) a = v;
      if (tin.point(v).x == 5 && tin.point(v).y == y + 1) b = v;
    }
    const EdgeId e = tin.find_edge(a, b);
    ASSERT_NE(e, kNoId);
    tin.set_constrained(e, true);
    ++marked;
  }
  ASSERT_EQ(marked, 6);
  const PreviewImage image = render_preview(tin, {.size = 100});
  for (const double y : {2.5, 4.0, 7.5}) EXPECT_EQ(pixel_at(image, 5.0, y), kConstraintColour) << y;
  EXPECT_NE(pixel_at(image, 5.0, 9.0), kConstraintColour);  // beyond the line's end
  EXPECT_NE(pixel_at(image, 3.0, 4.0), kConstraintColour);
}

TEST(Preview, AFrameSetsTheExtentAndIsDrawnAllRound) {
  const mesh::Triangulation tin = lattice(10, 10, [](double, double) { return 1.0; });
  const BBox frame{-5, -5, 15, 25};  // min_x, min_y, max_x, max_y: beyond the TIN
  const PreviewImage image = render_preview(tin, {.size = 60, .frame = frame});
  EXPECT_EQ(image.grid.width, 40u);
  EXPECT_EQ(image.grid.height, 60u);
  EXPECT_EQ(image.grid.min_x, -5);
  EXPECT_EQ(image.grid.max_y, 25);
  for (std::uint32_t col = 0; col < image.grid.width; ++col) {
    EXPECT_EQ(pixel(image, col, 0), kFrameColour);
    EXPECT_EQ(pixel(image, col, image.grid.height - 1), kFrameColour);
  }
  EXPECT_EQ(pixel(image, 0, 30), kFrameColour);
  EXPECT_EQ(pixel_at(image, 12, 20)[3], 0);  // inside the frame, outside the TIN
  EXPECT_EQ(pixel_at(image, 5, 5)[3], 255);
}

}  // namespace
}  // namespace tincdt::products
