// DEM and contour outputs as a GDAL user expects them, on the command line: the DEM's format from
// its extension or --dem-format, creation options checked against the driver, resolutions that
// make no DEM, contours that would fill the disk, CAD output and GIS conventions (field name,
// fixed levels), numbers in messages kept short. Every refusal comes before any file is written.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code;         // -1: ended by a signal, or by the timeout
  int signal;            // the signal that ended it, or 0
  std::string messages;  // standard error
  double seconds;
};

// tincdt ARGS in folder DIR, ended after 120 s at most (a refusal takes well under a second; a
// run that spins is a failure, not a hang). ENV: "NAME=VALUE " before the command.
Outcome run(const std::string& dir, const std::string& args, const std::string& env = "") {
  const std::string err = dir + "/stderr.txt";
  const auto t0 = std::chrono::steady_clock::now();
  const int status =
      std::system(("cd '" + dir + "' && " + env + "timeout -s KILL 120 '" TINCDT_EXE "' " + args +
                   " 2> '" + err + "' > /dev/null")
                      .c_str());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // std::system runs sh, which reports a child killed by signal S as 128 + S.
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  Outcome r{code > 128 ? -1 : code, code > 128 ? code - 128 : 0, tincdt::test::slurp(err), seconds};
  fs::remove(err);
  return r;
}

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

std::string sample_with(const std::string& args) {
  return "'" + kSample + "' -o t.ply " + args;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// tincdt ARGS in a fresh scratch folder, refused: exit 1 with every one of PARTS in the
// messages, and nothing left in the folder. Returns the outcome.
Outcome expect_refused_leaving_nothing(const std::string& args,
                                       const std::vector<std::string>& parts) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, args);
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  for (const std::string& part : parts)
    EXPECT_TRUE(has(r.messages, part)) << part << " in " << r.messages;
  EXPECT_TRUE(tincdt::test::names_in(dir).empty());
  return r;
}

GDALDatasetUniquePtr open_dataset(const std::string& path, unsigned kind) {
  GDALAllRegister();
  return GDALDatasetUniquePtr(GDALDataset::Open(path.c_str(), kind | GDAL_OF_READONLY));
}

// ---- 1. the DEM's format ----------------------------------------------------------------------

TEST(DemFormat, TakenFromTheExtension) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--dem d.asc --resolution 4"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(tincdt::test::names_in(dir),
            (std::set<std::string>{"d.asc", "d.prj", "t.ply", "t.prj"}));
  EXPECT_EQ(tincdt::test::slurp(dir + "/d.asc").rfind("ncols", 0), 0u);
  const GDALDatasetUniquePtr ds = open_dataset(dir + "/d.asc", GDAL_OF_RASTER);
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetDriver()->GetDescription(), "AAIGrid");
  EXPECT_EQ(ds->GetRasterXSize(), 40);  // 160 m at 4 m
  ASSERT_NE(ds->GetSpatialRef(), nullptr);
  EXPECT_TRUE(has(r.messages, "wrote d.asc (AAIGrid Float32")) << r.messages;
}

TEST(DemFormat, NamedByDemFormat) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--dem d.data --dem-format HFA --resolution 4"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const GDALDatasetUniquePtr ds = open_dataset(dir + "/d.data", GDAL_OF_RASTER);
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetDriver()->GetDescription(), "HFA");
  EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Float32);
}

TEST(DemFormat, ExtensionsAndDriversThatWriteNoDemAreUsageErrors) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  struct Case {
    std::string args;
    std::vector<std::string> named;  // each in the message
  };
  const Case cases[] = {
      {"--dem d.png --resolution 4", {"--dem d.png", "PNG", "'.png'", "Float32"}},
      {"--dem d.jpg --resolution 4", {"JPEG", "'.jpg'"}},
      {"--dem d.asc --resolution 4 --dem-type float64", {"AAIGrid", "Float64"}},
      {"--dem d.xyzq --resolution 4", {"'.xyzq'", "--dem-format"}},
      {"--dem d --resolution 4", {"extension"}},
      {"--dem d.vrt --resolution 4", {"VRT", "'.vrt'"}},
      {"--dem d.tif --dem-format NoSuchDriver --resolution 4", {"--dem-format", "NoSuchDriver"}},
      {"--dem d.tif --dem-format GPKG --resolution 4 --dem-type float64", {"GPKG", "Float64"}},
      {"--dem d.tif --dem-format MEM --resolution 4", {"MEM"}},
      {"--dem d.tif --dem-format ESRI\\ Shapefile --resolution 4", {"ESRI Shapefile", "raster"}},
      {"--dem-format AAIGrid", {"--dem-format", "need --dem"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const Outcome r = run(dir, sample_with(c.args));
    EXPECT_EQ(r.exit_code, 2) << r.messages;
    for (const std::string& part : c.named) EXPECT_TRUE(has(r.messages, part)) << r.messages;
  }
  EXPECT_EQ(tincdt::test::names_in(dir), std::set<std::string>{});
}

// ---- 2. creation options ------------------------------------------------------------------------

TEST(DemCreationOptions, CheckedAgainstTheDriverBeforeAnyWork) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  struct Case {
    std::string args;
    std::vector<std::string> named;
  };
  const Case cases[] = {
      {"--dem d.tif --resolution 4 --dem-co COMPRES=ZSTD", {"COMPRES", "COG"}},
      {"--dem d.tif --resolution 4 --dem-co COMPRESS=ZSTDX", {"ZSTDX", "COMPRESS", "COG"}},
      {"--dem d.tif --resolution 4 --dem-co LEVEL=abc", {"LEVEL", "COG"}},
      {"--dem d.asc --resolution 4 --dem-co COMPRESS=DEFLATE", {"COMPRESS", "AAIGrid"}},
      {"--dem d.tif --resolution 4 --dem-co BLOCKSIZE=0", {"BLOCKSIZE=0", "COG", "16"}},
      {"--dem d.tif --resolution 4 --dem-co BLOCKSIZE=100", {"BLOCKSIZE=100", "multiple of 16"}},
      {"--dem d.tif --resolution 4 --dem-co BLOCKSIZE=1048576", {"BLOCKSIZE=1048576", "COG"}},
      {"--dem d.tif --dem-format GTiff --resolution 4 --dem-co BLOCKXSIZE=-16",
       {"BLOCKXSIZE=-16", "GTiff"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const Outcome r = run(dir, sample_with(c.args));
    EXPECT_EQ(r.exit_code, 2) << r.messages;
    EXPECT_LT(r.seconds, 20) << "refused before any work";
    for (const std::string& part : c.named) EXPECT_TRUE(has(r.messages, part)) << r.messages;
    EXPECT_TRUE(has(r.messages, "--dem-co")) << r.messages;
  }
  EXPECT_EQ(tincdt::test::names_in(dir), std::set<std::string>{});
}

TEST(DemCreationOptions, ValidOnesStillWork) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--dem d.tif --resolution 0.5 --dem-co compress=ZSTD "
                                         "--dem-co BLOCKSIZE=128"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const GDALDatasetUniquePtr ds = open_dataset(dir + "/d.tif", GDAL_OF_RASTER);
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE"), "ZSTD");
  int bx = 0, by = 0;
  ds->GetRasterBand(1)->GetBlockSize(&bx, &by);
  EXPECT_EQ(bx, 128);
}

// ---- 3. resolutions that make no DEM ------------------------------------------------------------

// A small hill in longitude and latitude (EPSG:4326), as XYZ: 0.02 x 0.01 degree.
std::string geographic_xyz(const std::string& dir) {
  std::string text;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 10; ++j) {
      char line[96];
      std::snprintf(line, sizeof line, "%.6f %.6f %.2f\n", -94.68 + 0.001 * i, 31.04 + 0.001 * j,
                    40.0 + 0.5 * i + 0.25 * j + ((i * 7 + j * 3) % 5) * 0.1);
      text += line;
    }
  const std::string path = dir + "/geo.xyz";
  tincdt::test::spit(path, text);
  return path;
}

TEST(DemResolution, FewerThanTwoByTwoCellsNamesResolutionExtentAndUnit) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const std::string input = geographic_xyz(dir);
  const Outcome r =
      run(dir, "'" + input + "' --a-srs EPSG:4326 -o t.ply --dem g.tif --resolution 1");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  for (const std::string part :
       {"g.tif", "resolution of 1 degree", "-94.68", "31.05", "1 x 1", "2 x 2"})
    EXPECT_TRUE(has(r.messages, part)) << part << " in " << r.messages;
  EXPECT_EQ(tincdt::test::names_in(dir), std::set<std::string>{"geo.xyz"});
  // A resolution in degrees that makes a grid is fine.
  const Outcome ok =
      run(dir, "'" + input + "' --a-srs EPSG:4326 -o t.ply --dem g.tif --resolution 0.001");
  EXPECT_EQ(ok.exit_code, 0) << ok.messages;
}

TEST(DemResolution, RealGeographicFileInMetresIsRefused) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const std::string input = tincdt::test::shared_data() + "/las/epsg_4326.las";
  const Outcome r = run(dir, "'" + input + "' -o t.ply --dem g.tif --resolution 1");
  EXPECT_EQ(r.exit_code, 1) << r.messages;
  EXPECT_TRUE(has(r.messages, "degree")) << r.messages;
  EXPECT_TRUE(has(r.messages, "1 x 1")) << r.messages;
  EXPECT_FALSE(fs::exists(dir + "/g.tif"));
}

TEST(DemResolution, GridLargerThanMemoryIsRefusedWithTheEstimate) {
  // 160 m x 120 m at 0.1 mm: 1.6 million x 1.2 million cells, 7 TiB of Float32.
  expect_refused_leaving_nothing(sample_with("--dem d.tif --resolution 0.0001"),
                                 {"1,600,000 x 1,200,000 cells", "GiB"});
}

// ---- 4. contours that would fill the disk
// --------------------------------------------------------

TEST(ContourGuard, RefusedByTheEstimatedOutputBeforeTracing) {
  // 36 m of relief at 0.1 mm: some 10^8 segments.
  const Outcome r = expect_refused_leaving_nothing(
      sample_with("--contour-lines c.gpkg --interval 1e-4"),
      {"c.gpkg", "interval of 0.0001", "segments", "GB", "20,000,000"});
  EXPECT_LT(r.seconds, 30);
}

TEST(ContourGuard, TheThousandPointHillAtAMillimetre) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string input = tincdt::test::shared_data() + "/las/simple.las";
  expect_refused_leaving_nothing("'" + input + "' -o t.ply --contour-lines c.gpkg --interval 1e-3",
                                 {"interval of 0.001", "segments"});
}

// Ctrl-C as the contour stage starts: heard before the tracing (at its first progress report),
// not after tracing and writing 100,000 lines.
TEST(ContourGuard, InterruptAtTheContourStageLeavesNothing) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--contour-lines c.gpkg --interval 0.01"),
                        "TINCDT_TEST_SIGNAL='contour_lines:INT' ");
  EXPECT_EQ(r.signal, 2) << r.messages;
  EXPECT_TRUE(has(r.messages, "interrupted")) << r.messages;
  EXPECT_FALSE(has(r.messages, "contour lines:")) << r.messages;
  EXPECT_TRUE(tincdt::test::names_in(dir).empty());
}

// ---- 5. CAD and GIS conventions
// -------------------------------------------------------------------

// The levels of the lines in the vector file at PATH: each line's z, checked the same along it,
// and its FIELD when there is one.
std::set<double> levels_in(const std::string& path, const std::string& field) {
  const GDALDatasetUniquePtr ds = open_dataset(path, GDAL_OF_VECTOR);
  EXPECT_TRUE(ds);
  std::set<double> levels;
  if (!ds) return levels;
  OGRLayer* layer = ds->GetLayer(0);
  const int index = field.empty() ? -1 : layer->GetLayerDefn()->GetFieldIndex(field.c_str());
  if (!field.empty()) {
    EXPECT_GE(index, 0) << field;
  }
  for (const auto& feature : *layer) {
    const OGRGeometry* g = feature->GetGeometryRef();
    if (g == nullptr || wkbFlatten(g->getGeometryType()) != wkbLineString) continue;
    const OGRLineString* line = g->toLineString();
    EXPECT_TRUE(g->Is3D());
    const double z = line->getZ(0);
    for (int i = 1; i < line->getNumPoints(); ++i) EXPECT_EQ(line->getZ(i), z);
    if (index >= 0) {
      EXPECT_EQ(feature->GetFieldAsDouble(index), z);
    }
    levels.insert(z);
  }
  return levels;
}

TEST(ContourConventions, DxfHasHeightsAsZAndNoField) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--contour-lines c.dxf --interval 5"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_TRUE(has(r.messages, "wrote c.dxf (DXF")) << r.messages;
  const std::set<double> levels = levels_in(dir + "/c.dxf", "");
  EXPECT_EQ(levels, (std::set<double>{1485, 1490, 1495, 1500, 1505, 1510, 1515}));
}

TEST(ContourConventions, FieldNameLikeGdalContourA) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r =
      run(dir, sample_with("--contour-lines c.gpkg --interval 5 --contour-field height"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(levels_in(dir + "/c.gpkg", "height").size(), 7u);
}

TEST(ContourConventions, FixedLevelsLikeGdalContourFl) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r =
      run(dir, sample_with("--contour-lines c.gpkg --levels 1490.25,1500 --levels 1400,1490.25"));
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(levels_in(dir + "/c.gpkg", "elev"), (std::set<double>{1490.25, 1500}));
  EXPECT_TRUE(has(r.messages, "on 2 levels")) << r.messages;
}

// ---- 6. short numbers in messages ---------------------------------------------------------------

TEST(ShortNumbers, HugeValuesAreNotSpelledOut) {
  const std::string dir = tincdt::test::scratch_dir("dem_contour_cli");
  const Outcome r = run(dir, sample_with("--dem d.tif --resolution 4 --dem-nodata 1e308"));
  EXPECT_EQ(r.exit_code, 2) << r.messages;
  EXPECT_TRUE(has(r.messages, "--dem-nodata: 1e+308 cannot")) << r.messages;
  EXPECT_FALSE(has(r.messages, "0000000000")) << r.messages;
}

}  // namespace
