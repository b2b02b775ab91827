// The product stages end to end: --dem and --contour-lines made from the final TIN (an erased
// hole shows in both), LandXML / GeoPackage / STL through -o, every file in the stats with its
// size and every product stage with its time, and refusals and cancels that leave nothing.
#include <cpl_json.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using test::names_in;
using test::spit;

constexpr double kX0 = 500000, kY0 = 4000000;

// The surface every test samples: a plane, so that any triangulation of it interpolates it
// exactly and the products can be checked cell by cell.
double plane(double x, double y) {
  return 100 + 0.3 * (x - kX0) + 0.2 * (y - kY0);
}

// A jittered 30 x 30 grid over [x0, x0 + 100]^2 and its corners, z on the plane.
std::string xyz_text() {
  std::string s;
  char line[128];
  std::uint32_t state = 12345u;
  const auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return (static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5) * 2;
  };
  std::vector<std::pair<double, double>> xy = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};
  for (int i = 1; i <= 30; ++i)
    for (int j = 1; j <= 30; ++j) xy.push_back({i * 3.2 + jitter(), j * 3.2 + jitter()});
  for (const auto& [x, y] : xy) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", kX0 + x, kY0 + y,
                  plane(kX0 + x, kY0 + y));
    s += line;
  }
  return s;
}

// The hole erased from the TIN: [40, 60]^2.
bool in_hole(double x, double y) {
  return x > kX0 + 40 && x < kX0 + 60 && y > kY0 + 40 && y < kY0 + 60;
}

class Products : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("pipeline_products");
    spit(path("in.xyz"), xyz_text());
    char hole[512];
    std::snprintf(hole, sizeof hole,
                  R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{},)"
                  R"("geometry":{"type":"Polygon","coordinates":[[[%.1f,%.1f],[%.1f,%.1f],)"
                  R"([%.1f,%.1f],[%.1f,%.1f],[%.1f,%.1f]]]}}]})",
                  kX0 + 40, kY0 + 40, kX0 + 60, kY0 + 40, kX0 + 60, kY0 + 60, kX0 + 40, kY0 + 60,
                  kX0 + 40, kY0 + 40);
    spit(path("hole.geojson"), hole);
  }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  pipeline::BuildOptions options(const std::string& out) const {
    pipeline::BuildOptions o;
    o.inputs = {path("in.xyz")};
    o.assign_srs = "EPSG:32611";
    o.output = path(out);
    o.erase = {path("hole.geojson")};
    o.dem.path = path("dem.tif");
    o.dem.resolution = 1;
    o.dem.target_aligned = true;
    o.contour_lines.path = path("lines.gpkg");
    o.contour_lines.interval = 5;
    o.stats_path = path("stats.json");
    return o;
  }

  std::string dir_;
};

TEST_F(Products, DemAndContoursComeFromTheFinalTin) {
  const pipeline::BuildOptions o = options("tin.xml");
  const pipeline::BuildReport r = pipeline::build(o);
  EXPECT_GT(r.erased_triangles, 0u);
  EXPECT_EQ(names_in(dir_), (std::set<std::string>{"dem.tif", "hole.geojson", "in.xyz",
                                                   "lines.gpkg", "stats.json", "tin.xml"}));
  GDALAllRegister();

  // DEM: the plane where the TIN is, nodata in the hole and outside; 100 x 100 cells of 1 m.
  const GDALDatasetUniquePtr dem(GDALDataset::Open(o.dem.path.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(dem);
  EXPECT_EQ(dem->GetRasterXSize(), 100);
  EXPECT_EQ(dem->GetRasterYSize(), 100);
  EXPECT_STREQ(dem->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE"), "COG");
  std::vector<float> cells(100 * 100);
  ASSERT_EQ(dem->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 100, 100, cells.data(), 100, 100,
                                            GDT_Float32, 0, 0),
            CE_None);
  std::uint64_t with_value = 0, in_hole_count = 0;
  for (int row = 0; row < 100; ++row)
    for (int col = 0; col < 100; ++col) {
      const double x = kX0 + col + 0.5, y = kY0 + 100 - row - 0.5;
      const float v = cells[row * 100 + col];
      if (in_hole(x, y)) {
        ++in_hole_count;
        EXPECT_EQ(v, -9999.0f) << "cell in the erased hole at " << x << ", " << y;
      }
      if (v == -9999.0f) continue;
      ++with_value;
      EXPECT_NEAR(v, plane(x, y), 1e-4);
    }
  EXPECT_EQ(in_hole_count, 400u);
  EXPECT_EQ(with_value, r.dem.cells_with_value);
  EXPECT_GT(with_value, 9000u);  // all but the hole and its boundary triangles

  // Contours: on the plane at their level, none inside the hole.
  const GDALDatasetUniquePtr lines(GDALDataset::Open(o.contour_lines.path.c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(lines);
  OGRLayer* layer = lines->GetLayer(0);
  EXPECT_EQ(layer->GetFeatureCount(), static_cast<GIntBig>(r.contour_lines.lines));
  EXPECT_GT(r.contour_lines.lines, 5u);
  for (const auto& f : *layer) {
    const double level = f->GetFieldAsDouble("elev");
    EXPECT_NEAR(std::remainder(level, 5.0), 0.0, 1e-9);
    const OGRLineString* ls = f->GetGeometryRef()->toLineString();
    for (int i = 0; i < ls->getNumPoints(); ++i) {
      EXPECT_NEAR(plane(ls->getX(i), ls->getY(i)), level, 1e-9);
      EXPECT_FALSE(in_hole(ls->getX(i), ls->getY(i)));
    }
  }

  // The stats: every file with its size, every product stage with its time.
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.Load(o.stats_path));
  const CPLJSONObject root = doc.GetRoot();
  std::set<std::string> kinds;
  for (const CPLJSONObject& out : root.GetArray("outputs")) {
    kinds.insert(out.GetString("kind"));
    EXPECT_EQ(static_cast<std::uintmax_t>(out.GetLong("bytes")),
              fs::file_size(out.GetString("path")));
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"tin", "dem", "contour_lines"}));
  std::set<std::string> stages;
  for (const CPLJSONObject& s : root.GetArray("stages")) stages.insert(s.GetString("name"));
  EXPECT_TRUE(stages.count("dem"));
  EXPECT_TRUE(stages.count("contour_lines"));
  EXPECT_EQ(root.GetObj("dem").GetLong("width"), 100);
  EXPECT_EQ(root.GetObj("contour_lines").GetLong("lines"),
            static_cast<long>(r.contour_lines.lines));
  EXPECT_EQ(root.GetString("output_format"), "landxml");
}

TEST_F(Products, GeoPackageAndStlThroughTheOutput) {
  pipeline::BuildOptions o = options("tin.gpkg");
  o.dem = {};
  o.contour_lines = {};
  const pipeline::BuildReport r = pipeline::build(o);
  GDALAllRegister();
  const GDALDatasetUniquePtr gpkg(GDALDataset::Open(o.output.c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(gpkg);
  EXPECT_EQ(gpkg->GetLayer(0)->GetFeatureCount(), static_cast<GIntBig>(r.triangles));
  EXPECT_NE(gpkg->GetLayer(0)->GetSpatialRef(), nullptr);

  o = options("tin.stl");
  o.dem = {};
  o.contour_lines = {};
  o.write.offset_auto = true;
  o.stats_path.clear();
  const pipeline::BuildReport s = pipeline::build(o);
  EXPECT_EQ(fs::file_size(o.output), 84 + 50 * s.triangles);
  EXPECT_TRUE(fs::exists(path("tin.prj")));
}

TEST_F(Products, RefusedBeforeAnyWork) {
  const auto refused = [&](const pipeline::BuildOptions& o) {
    const std::set<std::string> before = names_in(dir_);
    EXPECT_THROW(pipeline::build(o), Error);
    EXPECT_EQ(names_in(dir_), before);
  };
  pipeline::BuildOptions o = options("tin.xml");
  o.dem.resolution = 0;
  refused(o);
  o = options("tin.xml");
  o.contour_lines.interval = -1;
  refused(o);
  o = options("tin.xml");
  o.dem.nodata = 1e300;  // not a Float32
  refused(o);
  o = options("tin.gpkg");
  o.write.offset_auto = true;  // a GeoPackage keeps real coordinates
  refused(o);
  o = options("tin.xml");
  o.contour_lines.path = path("lines.shp");
  spit(path("lines.dbf"), "someone else's");  // a shapefile's sibling, no --overwrite
  refused(o);
}

TEST_F(Products, ADemLargerThanTheMachineIsRefusedAndNothingIsWritten) {
  pipeline::BuildOptions o = options("tin.xml");
  o.dem.resolution = 1e-5;  // 10^7 x 10^7 cells
  try {
    pipeline::build(o);
    FAIL() << "no exception";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.file(), o.dem.path);
    EXPECT_NE(e.detail().find("more than this machine's memory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(names_in(dir_), (std::set<std::string>{"hole.geojson", "in.xyz"}));
}

TEST_F(Products, CancelInAProductStageLeavesNothing) {
  for (const char* at : {"dem", "contour_lines"}) {
    SCOPED_TRACE(at);
    const ProgressFn progress = [&](std::string_view stage, double) { return stage != at; };
    EXPECT_THROW(pipeline::build(options("tin.xml"), &progress), Cancelled);
    EXPECT_EQ(names_in(dir_), (std::set<std::string>{"hole.geojson", "in.xyz"}));
  }
}

}  // namespace
