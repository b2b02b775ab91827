// Contour lines asked to stop midway, in a format whose driver can drop the layer (GeoPackage,
// shapefile) and one whose cannot (GeoJSON): Cancelled, and nothing is left behind.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/vector/contour_writer.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

products::ContourSet some_contours() {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 100), z(0, 20);
  std::vector<Point3> pts;
  for (int i = 0; i < 400; ++i) pts.push_back({300000 + u(rng), 5000000 + u(rng), z(rng)});
  const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  return products::trace_contours(tin, {.interval = 2.5});
}

TEST(ContourCancel, StoppedMidwayLeavesNothing) {
  const products::ContourSet c = some_contours();
  ASSERT_GT(c.lines.size(), 2u);
  for (const char* name : {"lines.gpkg", "lines.shp", "lines.geojson"}) {
    SCOPED_TRACE(name);
    const std::string dir = test::scratch_dir("contour_cancel");
    int reports = 0;
    // The first report, after the first line, goes on; the second, after two, stops.
    const ProgressFn stop = [&](std::string_view stage, double) {
      EXPECT_EQ(stage, "write contours");
      return ++reports < 2;
    };
    ContourWriteOptions o;
    o.progress = &stop;
    EXPECT_THROW(write_contours(dir + "/" + name, c, o), Cancelled);
    EXPECT_EQ(reports, 2);
    EXPECT_EQ(test::names_in(dir), std::set<std::string>{});
  }
}

}  // namespace
}  // namespace tincdt::io
