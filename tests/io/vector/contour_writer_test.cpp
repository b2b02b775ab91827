// Contour lines through OGR: read back in GeoPackage, shapefile and GeoJSON, every line with its
// points, its z and its elevation field, and the CRS; the format from the extension or named;
// refusals and a write asked to stop leave nothing behind.
#include "io/vector/contour_writer.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

products::ContourSet sample_contours() {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 100), z(0, 20);
  std::vector<Point3> pts;
  for (int i = 0; i < 400; ++i) pts.push_back({300000 + u(rng), 5000000 + u(rng), z(rng)});
  const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
  return products::trace_contours(tin, {.interval = 2.5});
}

// Reads LAYER back and compares it with C line by line (features in order).
void expect_same_lines(OGRLayer* layer, const products::ContourSet& c, const char* field) {
  ASSERT_NE(layer, nullptr);
  ASSERT_EQ(layer->GetFeatureCount(), static_cast<GIntBig>(c.lines.size()));
  layer->ResetReading();
  for (const products::ContourLine& line : c.lines) {
    const OGRFeatureUniquePtr f(layer->GetNextFeature());
    ASSERT_TRUE(f);
    EXPECT_EQ(f->GetFieldAsDouble(field), line.level);
    const OGRGeometry* g = f->GetGeometryRef();
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(wkbFlatten(g->getGeometryType()), wkbLineString);
    const auto* ls = g->toLineString();
    ASSERT_EQ(static_cast<std::size_t>(ls->getNumPoints()), line.count);
    for (int k = 0; k < ls->getNumPoints(); ++k) {
      const Point2 p = c.points[line.first + static_cast<std::size_t>(k)];
      ASSERT_EQ(ls->getX(k), p.x);
      ASSERT_EQ(ls->getY(k), p.y);
      ASSERT_EQ(ls->getZ(k), line.level);
    }
    EXPECT_EQ(line.closed, ls->get_IsClosed() != 0);
  }
}

TEST(ContourWriter, GeoPackageShapefileAndGeoJsonReadBack) {
  const std::string dir = test::scratch_dir("contour_writer");
  const products::ContourSet c = sample_contours();
  ASSERT_GT(c.lines.size(), 10u);
  ContourWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:32611");
  GDALAllRegister();
  for (const auto& [name, driver] : {std::pair{"lines.gpkg", "GPKG"},
                                     {"lines.shp", "ESRI Shapefile"},
                                     {"lines.geojson", "GeoJSON"}}) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    const ContourWriteStats stats = write_contours(path, c, o);
    EXPECT_EQ(stats.driver, driver);
    EXPECT_EQ(stats.lines, c.lines.size());
    EXPECT_GT(stats.bytes, 0u);
    const GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    ASSERT_TRUE(ds);
    EXPECT_STREQ(ds->GetDriver()->GetDescription(), driver);
    OGRLayer* layer = ds->GetLayer(0);
    expect_same_lines(layer, c, "elev");
    ASSERT_NE(layer->GetSpatialRef(), nullptr);
    char* wkt = nullptr;
    layer->GetSpatialRef()->exportToWkt(&wkt);
    EXPECT_TRUE(same_crs(wkt, o.crs_wkt));
    CPLFree(wkt);
  }
  // The shapefile's siblings came along; no temporary is left.
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"lines.dbf", "lines.geojson", "lines.gpkg",
                                                        "lines.prj", "lines.shp", "lines.shx"}));
}

TEST(ContourWriter, NamedFormatAndFieldWinOverTheExtension) {
  const std::string dir = test::scratch_dir("contour_writer");
  const products::ContourSet c = sample_contours();
  ContourWriteOptions o;
  o.format = "GeoJSON";
  o.elevation_field = "height";
  const std::string path = dir + "/lines.gpkg";
  EXPECT_EQ(write_contours(path, c, o).driver, "GeoJSON");
  GDALAllRegister();
  const GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetDriver()->GetDescription(), "GeoJSON");
  expect_same_lines(ds->GetLayerByName("contours"), c, "height");
}

TEST(ContourWriter, RefusalsLeaveNothingBehind) {
  const std::string dir = test::scratch_dir("contour_writer");
  const products::ContourSet c = sample_contours();
  ContourWriteOptions o;
  EXPECT_THROW(write_contours(dir + "/lines.unknownext", c, o), OutputError);
  EXPECT_THROW(write_contours(dir + "/lines", c, o), OutputError);
  o.format = "NoSuchDriver";
  EXPECT_THROW(write_contours(dir + "/lines.gpkg", c, o), OutputError);
  o.format.clear();
  test::spit(dir + "/old.gpkg", "old");
  EXPECT_THROW(write_contours(dir + "/old.gpkg", c, o), OutputError);
  // A shapefile whose sibling exists is refused as a whole without --overwrite.
  test::spit(dir + "/s.dbf", "old");
  EXPECT_THROW(write_contours(dir + "/s.shp", c, o), OutputError);
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"old.gpkg", "s.dbf"}));
  EXPECT_EQ(test::slurp(dir + "/s.dbf"), "old");
  o.overwrite = true;
  write_contours(dir + "/s.shp", c, o);
  EXPECT_NE(test::slurp(dir + "/s.dbf"), "old");
}

// Asked to stop midway, in a format whose driver can drop the layer (GeoPackage, shapefile) and
// one whose cannot (GeoJSON): Cancelled, and nothing is left behind.
TEST(ContourCancel, StoppedMidwayLeavesNothing) {
  const products::ContourSet c = sample_contours();
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
