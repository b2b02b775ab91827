// DEM GeoTIFFs: GDAL reads back the grid, values, nodata and CRS; the file is a tiled,
// compressed Cloud-Optimized GeoTIFF with overviews; a failure or a refusal leaves nothing.
#include "io/raster/dem_writer.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "products/grid.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

products::Grid grid_of(std::uint32_t w, std::uint32_t h) {
  products::Grid g;
  g.min_x = 500000.5;
  g.max_y = 4000000.25;
  g.resolution = 0.5;
  g.width = w;
  g.height = h;
  return g;
}

// A smooth surface with a nodata hole, as a rasterized TIN would be.
template <class T>
std::vector<T> cells_of(const products::Grid& g, T nodata) {
  std::vector<T> v(g.cells());
  for (std::uint32_t r = 0; r < g.height; ++r)
    for (std::uint32_t c = 0; c < g.width; ++c) {
      const double dx = c - 0.5 * g.width, dy = r - 0.5 * g.height;
      v[std::size_t{r} * g.width + c] =
          dx * dx + dy * dy < 400 ? nodata : static_cast<T>(100 + 0.01 * dx - 0.02 * dy + 1e-7 * r);
    }
  return v;
}

struct Raster {
  explicit Raster(const std::string& path) {
    GDALAllRegister();
    ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  }
  GDALDatasetUniquePtr ds;
};

TEST(DemWriter, CloudOptimizedGeoTiffWithCrsNodataAndExactValues) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(1300, 1100);  // beyond one 512 tile: overviews
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  DemWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:32611");
  const std::string path = dir + "/dem.tif";
  const DemWriteStats stats = write_dem(path, g, cells, o);
  EXPECT_EQ(stats.bytes, fs::file_size(path));
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.tif"}));

  Raster r(path);
  ASSERT_TRUE(r.ds);
  EXPECT_EQ(r.ds->GetRasterXSize(), 1300);
  EXPECT_EQ(r.ds->GetRasterYSize(), 1100);
  double gt[6];
  ASSERT_EQ(r.ds->GetGeoTransform(gt), CE_None);
  EXPECT_EQ(gt[0], g.min_x);
  EXPECT_EQ(gt[1], 0.5);
  EXPECT_EQ(gt[3], g.max_y);
  EXPECT_EQ(gt[5], -0.5);
  ASSERT_NE(r.ds->GetSpatialRef(), nullptr);
  char* wkt = nullptr;
  r.ds->GetSpatialRef()->exportToWkt(&wkt);
  EXPECT_TRUE(same_crs(wkt, o.crs_wkt));
  CPLFree(wkt);
  const char* layout = r.ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
  ASSERT_NE(layout, nullptr);
  EXPECT_STREQ(layout, "COG");
  EXPECT_STREQ(r.ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE"), "DEFLATE");

  GDALRasterBand* band = r.ds->GetRasterBand(1);
  EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
  int has_nodata = 0;
  EXPECT_EQ(band->GetNoDataValue(&has_nodata), -9999.0);
  EXPECT_TRUE(has_nodata);
  int bx = 0, by = 0;
  band->GetBlockSize(&bx, &by);
  EXPECT_EQ(bx, 512);
  EXPECT_EQ(by, 512);
  EXPECT_GE(band->GetOverviewCount(), 1);
  std::vector<float> back(g.cells());
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 1300, 1100, back.data(), 1300, 1100, GDT_Float32, 0, 0),
            CE_None);
  EXPECT_EQ(std::memcmp(back.data(), cells.data(), back.size() * sizeof(float)), 0);
}

TEST(DemWriter, OverviewsAverageTheCellsWithAValue) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(1301, 1099);  // odd sizes: the last row and column halve alone
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  write_dem(dir + "/dem.tif", g, cells, {});
  Raster raster(dir + "/dem.tif");
  ASSERT_TRUE(raster.ds);
  GDALRasterBand* band = raster.ds->GetRasterBand(1);
  ASSERT_EQ(band->GetOverviewCount(), 2);  // 651 x 550, 326 x 275
  GDALRasterBand* ovr = band->GetOverview(0);
  ASSERT_EQ(ovr->GetXSize(), 651);
  ASSERT_EQ(ovr->GetYSize(), 550);
  std::vector<float> back(651 * 550);
  ASSERT_EQ(ovr->RasterIO(GF_Read, 0, 0, 651, 550, back.data(), 651, 550, GDT_Float32, 0, 0),
            CE_None);
  std::size_t nodata_cells = 0;
  for (std::uint32_t r0 = 0; r0 < 550; ++r0)
    for (std::uint32_t c0 = 0; c0 < 651; ++c0) {
      double sum = 0;
      int n = 0;
      for (std::uint32_t r = 2 * r0; r < std::min(2 * r0 + 2, g.height); ++r)
        for (std::uint32_t c = 2 * c0; c < std::min(2 * c0 + 2, g.width); ++c)
          if (cells[r * g.width + c] != -9999.0f) {
            sum += cells[r * g.width + c];
            ++n;
          }
      const float got = back[r0 * 651 + c0];
      if (n == 0) {
        ++nodata_cells;
        ASSERT_EQ(got, -9999.0f);
      } else {
        ASSERT_FLOAT_EQ(got, static_cast<float>(sum / n)) << r0 << ", " << c0;
      }
    }
  EXPECT_GT(nodata_cells, 0u);
}

TEST(DemWriter, CreationOptionsOverTheDefaults) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(1100, 700);
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  DemWriteOptions o;
  o.creation_options = {"compress=ZSTD", "OVERVIEWS=NONE"};
  write_dem(dir + "/zstd.tif", g, cells, o);
  Raster r(dir + "/zstd.tif");
  ASSERT_TRUE(r.ds);
  EXPECT_STREQ(r.ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE"), "ZSTD");
  EXPECT_EQ(r.ds->GetRasterBand(1)->GetOverviewCount(), 0);
  o.creation_options = {"RESAMPLING=NEAREST"};  // GDAL's own overviews
  write_dem(dir + "/nearest.tif", g, cells, o);
  Raster n(dir + "/nearest.tif");
  ASSERT_TRUE(n.ds);
  EXPECT_EQ(n.ds->GetRasterBand(1)->GetOverviewCount(), 2);  // 550 x 350, 275 x 175
  o.creation_options = {"COMPRESS"};
  EXPECT_THROW(write_dem(dir + "/bad.tif", g, cells, o), OutputError);
  EXPECT_FALSE(fs::exists(dir + "/bad.tif"));
}

TEST(DemWriter, Float64KeepsEveryBit) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(300, 200);
  const std::vector<double> cells = cells_of<double>(g, std::nan(""));
  DemWriteOptions o;
  o.nodata = std::nan("");
  const std::string path = dir + "/dem64.tif";
  write_dem(path, g, cells, o);
  Raster r(path);
  ASSERT_TRUE(r.ds);
  EXPECT_EQ(r.ds->GetSpatialRef(), nullptr);  // no CRS given
  GDALRasterBand* band = r.ds->GetRasterBand(1);
  EXPECT_EQ(band->GetRasterDataType(), GDT_Float64);
  int has_nodata = 0;
  EXPECT_TRUE(std::isnan(band->GetNoDataValue(&has_nodata)));
  EXPECT_TRUE(has_nodata);
  std::vector<double> back(g.cells());
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 300, 200, back.data(), 300, 200, GDT_Float64, 0, 0),
            CE_None);
  for (std::size_t i = 0; i < back.size(); ++i) {
    if (std::isnan(cells[i])) {
      ASSERT_TRUE(std::isnan(back[i]));
    } else {
      ASSERT_EQ(back[i], cells[i]);
    }
  }
}

TEST(DemWriter, RefusalsLeaveNothingBehind) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(20, 10);
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  const std::string path = dir + "/dem.tif";
  test::spit(path, "old");
  DemWriteOptions o;
  EXPECT_THROW(write_dem(path, g, cells, o), OutputError);  // exists, no overwrite
  EXPECT_EQ(test::slurp(path), "old");
  o.nodata = 1e300;  // not a float
  o.overwrite = true;
  EXPECT_THROW(write_dem(path, g, cells, o), OutputError);
  o.nodata = -9999;
  o.crs_wkt = "not a CRS";
  EXPECT_THROW(write_dem(path, g, cells, o), OutputError);
  EXPECT_EQ(test::slurp(path), "old");
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.tif"}));
  o.crs_wkt.clear();
  write_dem(path, g, cells, o);  // with overwrite
  EXPECT_NE(test::slurp(path), "old");
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.tif"}));
  const std::vector<float> wrong(7);
  EXPECT_THROW(write_dem(dir + "/other.tif", g, wrong, o), OutputError);
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.tif"}));
}

TEST(DemWriter, ProgressCanCancel) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(1000, 1000);
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  const ProgressFn stop = [](std::string_view, double f) { return f < 0.3; };
  DemWriteOptions o;
  o.progress = &stop;
  EXPECT_THROW(write_dem(dir + "/dem.tif", g, cells, o), Cancelled);
  EXPECT_TRUE(test::names_in(dir).empty());
}

// ---- formats other than COG ----

TEST(DemFormat, DriverFromTheExtensionOrByName) {
  EXPECT_EQ(dem_driver_for("a/dem.tif", "", false), "COG");
  EXPECT_EQ(dem_driver_for("dem.TIFF", "", true), "COG");
  EXPECT_EQ(dem_driver_for("dem.asc", "", false), "AAIGrid");
  EXPECT_EQ(dem_driver_for("dem.img", "", true), "HFA");
  EXPECT_EQ(dem_driver_for("dem.tif", "GTiff", true), "GTiff");
  EXPECT_EQ(dem_driver_for("dem.whatever", "AAIGrid", false), "AAIGrid");
  const auto refusal = [](const std::string& path, const std::string& format, bool float64) {
    try {
      dem_driver_for(path, format, float64);
    } catch (const OutputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("dem.png", "", false).find("PNG driver (for '.png') cannot store Float32"),
            std::string::npos);
  EXPECT_NE(refusal("dem.asc", "", true).find("AAIGrid"), std::string::npos);
  EXPECT_NE(refusal("dem.qqq", "", false).find("'.qqq'"), std::string::npos);
  EXPECT_NE(refusal("dem", "", false).find("extension"), std::string::npos);
  EXPECT_NE(refusal("dem.vrt", "", false).find("VRT"), std::string::npos);
  EXPECT_NE(refusal("dem.tif", "MEM", false).find("MEM"), std::string::npos);
  EXPECT_NE(refusal("dem.tif", "nope", false).find("'nope'"), std::string::npos);
  EXPECT_NE(refusal("dem.tif", "GPKG", true).find("Float64"), std::string::npos);
}

TEST(DemFormat, CreationOptionsCheckedAgainstTheDriver) {
  const auto refusal = [](const std::string& driver, const std::string& option) {
    try {
      check_dem_creation_options("dem.tif", driver, {option});
    } catch (const OutputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal("COG", "compress=ZSTD"), "accepted");
  EXPECT_EQ(refusal("COG", "BLOCKSIZE=256"), "accepted");
  EXPECT_EQ(refusal("HFA", "BLOCKSIZE=64"), "accepted");
  for (const auto& [driver, option] :
       std::vector<std::pair<std::string, std::string>>{{"COG", "COMPRES=ZSTD"},
                                                        {"COG", "COMPRESS=NOPE"},
                                                        {"COG", "BLOCKSIZE=0"},
                                                        {"COG", "BLOCKSIZE=8"},
                                                        {"COG", "BLOCKSIZE=100"},
                                                        {"COG", "BLOCKSIZE=32768"},
                                                        {"COG", "BLOCKSIZE=x"},
                                                        {"GTiff", "BLOCKYSIZE=0"},
                                                        {"AAIGrid", "COMPRESS=DEFLATE"},
                                                        {"COG", "COMPRESS"}}) {
    const std::string text = refusal(driver, option);
    EXPECT_NE(text.find(option), std::string::npos) << text;
    EXPECT_NE(text.find(driver), std::string::npos) << text;
  }
}

TEST(DemFormat, AsciiGridWithItsPrjMovedIntoPlace) {
  const std::string dir = test::scratch_dir("dem_writer");
  const products::Grid g = grid_of(30, 20);
  const std::vector<float> cells = cells_of<float>(g, -9999.0f);
  DemWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:32611");
  const std::string path = dir + "/dem.asc";
  const DemWriteStats stats = write_dem(path, g, cells, o);
  EXPECT_EQ(stats.driver, "AAIGrid");
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.asc", "dem.prj"}));
  EXPECT_EQ(stats.bytes, fs::file_size(path) + fs::file_size(dir + "/dem.prj"));
  Raster r(path);
  ASSERT_TRUE(r.ds);
  EXPECT_STREQ(r.ds->GetDriver()->GetDescription(), "AAIGrid");
  ASSERT_NE(r.ds->GetSpatialRef(), nullptr);
  std::vector<float> back(g.cells());
  ASSERT_EQ(r.ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 30, 20, back.data(), 30, 20,
                                             GDT_Float32, 0, 0),
            CE_None);
  for (std::size_t i = 0; i < back.size(); ++i) ASSERT_EQ(back[i], cells[i]) << i;
  EXPECT_EQ(dem_side_files(path, "AAIGrid"), std::vector<std::string>{dir + "/dem.prj"});
  // An existing .prj is not replaced without overwrite, and nothing is left behind.
  test::spit(dir + "/other.prj", "old");
  EXPECT_THROW(write_dem(dir + "/other.asc", g, cells, o), OutputError);
  EXPECT_EQ(test::names_in(dir), (std::set<std::string>{"dem.asc", "dem.prj", "other.prj"}));
}

TEST(DemFormat, CrsUnitNames) {
  EXPECT_EQ(crs_unit_name(crs_from_user("EPSG:4326")), "degree");
  EXPECT_EQ(crs_unit_name(crs_from_user("EPSG:32632")), "metre");
  EXPECT_EQ(crs_unit_name(crs_from_user("EPSG:2994")), "foot");
  EXPECT_EQ(crs_unit_name(""), "");
}

}  // namespace
}  // namespace tincdt::io
