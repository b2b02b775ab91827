// GeoPackage diagnostics: written, re-opened with GDAL's GPKG driver, every layer, field,
// location and CRS checked; the safe-output rules (no overwrite without asking, nothing left
// behind by a failure, not even the hidden temporary or an SQLite journal).
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "io/reports/diagnostics_writer.hpp"
#include "io/vector/line_reader.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using test::names_in;
using test::slurp;
using test::spit;
using ::testing::AnyOf;
using ::testing::HasSubstr;

constexpr double kX0 = 500000.123456789;
constexpr double kY0 = 4000000.987654321;

std::string scratch() {
  return test::scratch_dir("diagnostics_writer");
}

// A sample of every kind, at UTM magnitude.
Diagnostics sample() {
  Diagnostics d;
  d.crossings.push_back(
      {{kX0 + 0.25, kY0 + 0.75, 101.5}, "a.shp", 3, "b.gpkg:lines", 9, 101.0, 102.0});
  d.crossings.push_back({{kX0 - 1e-3, kY0 + 1e3, -2.0}, "a.shp", 4, "a.shp", 5, -2.25, -1.75});
  d.duplicates.push_back({{kX0 + 10, kY0 + 20, 0.1 + 0.2}, 3, 0.25, 0.375});
  d.skipped_segments.push_back({{kX0, kY0, 7.0}, "a.shp", 11});
  d.skipped_segments.push_back({{kX0 + 1, kY0, 8.0}, "a.shp", 11});
  d.skipped_segments.push_back({{kX0 + 2, kY0, 9.0}, "c.dxf", 0});
  d.dropped_features.push_back({"a.shp", 12, "Point geometry", {kX0 + 5, kY0 + 5, 1.0}, true});
  d.dropped_features.push_back({"b.gpkg:lines", 13, "no geometry", {0, 0, 0}, false});
  return d;
}

// ---- reading back with GDAL ----------------------------------------------------------------

struct Gpkg : test::VectorFile {
  explicit Gpkg(const std::string& path) : VectorFile(path, "GPKG") {}
};

// A feature as read back: location (if any) and fields as text, by name.
struct Row {
  bool has_geometry = false;
  OGRwkbGeometryType type = wkbUnknown;
  Point3 at{0, 0, 0};
  std::map<std::string, std::string> text;
  std::map<std::string, double> real;
  std::map<std::string, std::int64_t> integer;
};

std::vector<Row> rows_of(OGRLayerH layer) {
  std::vector<Row> rows;
  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
  OGR_L_ResetReading(layer);
  while (OGRFeatureH f = OGR_L_GetNextFeature(layer)) {
    Row r;
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    if (g != nullptr) {
      r.has_geometry = true;
      r.type = OGR_G_GetGeometryType(g);
      OGR_G_GetPoint(g, 0, &r.at.x, &r.at.y, &r.at.z);
    }
    for (int i = 0; i < OGR_FD_GetFieldCount(defn); ++i) {
      OGRFieldDefnH fd = OGR_FD_GetFieldDefn(defn, i);
      const std::string name = OGR_Fld_GetNameRef(fd);
      switch (OGR_Fld_GetType(fd)) {
        case OFTString:
          r.text[name] = OGR_F_GetFieldAsString(f, i);
          break;
        case OFTReal:
          r.real[name] = OGR_F_GetFieldAsDouble(f, i);
          break;
        default:
          r.integer[name] = OGR_F_GetFieldAsInteger64(f, i);
          break;
      }
    }
    rows.push_back(std::move(r));
    OGR_F_Destroy(f);
  }
  return rows;
}

// "name:type" of every field, in order.
std::vector<std::string> schema_of(OGRLayerH layer) {
  std::vector<std::string> out;
  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
  for (int i = 0; i < OGR_FD_GetFieldCount(defn); ++i) {
    OGRFieldDefnH fd = OGR_FD_GetFieldDefn(defn, i);
    out.push_back(std::string(OGR_Fld_GetNameRef(fd)) + ":" +
                  OGR_GetFieldTypeName(OGR_Fld_GetType(fd)));
  }
  return out;
}

void expect_near(const Point3& got, const Point3& want) {
  EXPECT_NEAR(got.x, want.x, 1e-12 * std::fabs(want.x) + 1e-12);
  EXPECT_NEAR(got.y, want.y, 1e-12 * std::fabs(want.y) + 1e-12);
  EXPECT_NEAR(got.z, want.z, 1e-12);
}

const std::vector<std::string> kLayers = {"crossings", "merged_duplicates", "skipped_segments",
                                          "dropped_features"};

// ---- content ---------------------------------------------------------------------------------

TEST(DiagnosticsWriter, EveryLayerWithItsFeaturesAttributesAndCrs) {
  const std::string dir = scratch();
  const std::string path = dir + "/diag.gpkg";
  const Diagnostics d = sample();
  write_diagnostics(path, d, crs_from_user("EPSG:2949"), false);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"diag.gpkg"}));

  const Gpkg g(path);
  ASSERT_NE(g.ds, nullptr);
  ASSERT_EQ(GDALDatasetGetLayerCount(g.ds), 4);
  for (const std::string& name : kLayers) {
    SCOPED_TRACE(name);
    OGRLayerH layer = g.layer(name.c_str());
    ASSERT_NE(layer, nullptr);
    EXPECT_EQ(OGR_L_GetGeomType(layer), wkbPoint25D);
    EXPECT_EQ(test::layer_crs_code(layer), "EPSG:2949");
  }

  const auto crossings = rows_of(g.layer("crossings"));
  ASSERT_EQ(crossings.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE(i);
    const Diagnostics::Crossing& c = d.crossings[i];
    ASSERT_TRUE(crossings[i].has_geometry);
    EXPECT_EQ(crossings[i].type, wkbPoint25D);
    expect_near(crossings[i].at, c.at);
    EXPECT_EQ(crossings[i].text.at("file_a"), c.file_a);
    EXPECT_EQ(crossings[i].integer.at("fid_a"), c.fid_a);
    EXPECT_EQ(crossings[i].text.at("file_b"), c.file_b);
    EXPECT_EQ(crossings[i].integer.at("fid_b"), c.fid_b);
    EXPECT_EQ(crossings[i].real.at("z_a"), c.z_a);
    EXPECT_EQ(crossings[i].real.at("z_b"), c.z_b);
  }
  EXPECT_EQ(crossings[0].real.at("z_diff"), 1.0);
  EXPECT_EQ(crossings[1].real.at("z_diff"), 0.5);

  const auto duplicates = rows_of(g.layer("merged_duplicates"));
  ASSERT_EQ(duplicates.size(), 1u);
  expect_near(duplicates[0].at, d.duplicates[0].at);
  EXPECT_EQ(duplicates[0].integer.at("points"), 3);
  EXPECT_EQ(duplicates[0].real.at("z_min"), 0.25);
  EXPECT_EQ(duplicates[0].real.at("z_max"), 0.375);

  const auto skipped = rows_of(g.layer("skipped_segments"));
  ASSERT_EQ(skipped.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    expect_near(skipped[i].at, d.skipped_segments[i].at);
    EXPECT_EQ(skipped[i].text.at("source_file"), d.skipped_segments[i].file);
    EXPECT_EQ(skipped[i].integer.at("source_fid"), d.skipped_segments[i].fid);
  }

  const auto dropped = rows_of(g.layer("dropped_features"));
  ASSERT_EQ(dropped.size(), 2u);
  ASSERT_TRUE(dropped[0].has_geometry);
  expect_near(dropped[0].at, d.dropped_features[0].at);
  EXPECT_EQ(dropped[0].text.at("source_file"), "a.shp");
  EXPECT_EQ(dropped[0].integer.at("source_fid"), 12);
  EXPECT_EQ(dropped[0].text.at("reason"), "Point geometry");
  EXPECT_FALSE(dropped[1].has_geometry) << "no location: NULL geometry";
  EXPECT_EQ(dropped[1].integer.at("source_fid"), 13);
  EXPECT_EQ(dropped[1].text.at("reason"), "no geometry");
}

TEST(DiagnosticsWriter, EmptyDiagnosticsStillShowEveryLayersSchema) {
  const std::string dir = scratch();
  write_diagnostics(dir + "/diag.gpkg", {}, "", false);
  const Gpkg g(dir + "/diag.gpkg");
  ASSERT_NE(g.ds, nullptr);
  ASSERT_EQ(GDALDatasetGetLayerCount(g.ds), 4);
  for (const std::string& name : kLayers) {
    OGRLayerH layer = g.layer(name.c_str());
    ASSERT_NE(layer, nullptr) << name;
    EXPECT_EQ(OGR_L_GetFeatureCount(layer, TRUE), 0) << name;
    EXPECT_EQ(OGR_L_GetGeomType(layer), wkbPoint25D) << name;
    // No CRS given: GDAL reports none, or the GeoPackage's "Undefined" placeholder entry.
    OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(layer);
    if (srs != nullptr) {
      EXPECT_EQ(OSRGetAuthorityName(srs, nullptr), nullptr) << name;
      EXPECT_EQ(std::string(OSRGetName(srs)).rfind("Undefined", 0), 0u) << OSRGetName(srs);
    }
  }
  EXPECT_EQ(schema_of(g.layer("crossings")),
            (std::vector<std::string>{"file_a:String", "fid_a:Integer64", "file_b:String",
                                      "fid_b:Integer64", "z_a:Real", "z_b:Real", "z_diff:Real"}));
  EXPECT_EQ(schema_of(g.layer("merged_duplicates")),
            (std::vector<std::string>{"points:Integer64", "z_min:Real", "z_max:Real"}));
  EXPECT_EQ(schema_of(g.layer("skipped_segments")),
            (std::vector<std::string>{"source_file:String", "source_fid:Integer64"}));
  EXPECT_EQ(
      schema_of(g.layer("dropped_features")),
      (std::vector<std::string>{"source_file:String", "source_fid:Integer64", "reason:String"}));
}

TEST(DiagnosticsWriter, HundredThousandFeaturesInOneTransaction) {
  // Not a timed test: the time is printed.
  const std::string dir = scratch();
  Diagnostics d;
  for (int i = 0; i < 100000; ++i)
    d.skipped_segments.push_back({{kX0 + 0.5 * i, kY0 - 0.25 * i, 0.001 * i}, "big.shp", i});
  const auto start = std::chrono::steady_clock::now();
  write_diagnostics(dir + "/diag.gpkg", d, crs_from_user("EPSG:2949"), false);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[   INFO   ] 100000 diagnostics features written in %.3f s\n", seconds);
  const Gpkg g(dir + "/diag.gpkg");
  ASSERT_NE(g.ds, nullptr);
  OGRLayerH layer = g.layer("skipped_segments");
  ASSERT_NE(layer, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(layer, TRUE), 100000);
  OGRFeatureH last = OGR_L_GetFeature(layer, 100000);  // GeoPackage fids count from 1
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(OGR_F_GetFieldAsInteger64(last, OGR_F_GetFieldIndex(last, "source_fid")), 99999);
  double x = 0, y = 0, z = 0;
  OGR_G_GetPoint(OGR_F_GetGeometryRef(last), 0, &x, &y, &z);
  EXPECT_NEAR(x, kX0 + 0.5 * 99999, 1e-6);
  EXPECT_NEAR(z, 99.999, 1e-12);
  OGR_F_Destroy(last);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"diag.gpkg"}));
}

TEST(DiagnosticsWriter, NewFileHasTheUsualPermissions) {
  const std::string dir = scratch();
  EXPECT_EQ(
      test::mode_when_created(dir + "/diag.gpkg",
                              [&] { write_diagnostics(dir + "/diag.gpkg", sample(), "", false); }),
      0644u);
}

// ---- refusals and safe output ------------------------------------------------------------------

TEST(DiagnosticsWriter, ExistingFileNeedsOverwriteAndIsOtherwiseUntouched) {
  const std::string dir = scratch();
  const std::string path = dir + "/diag.gpkg";
  test::expect_no_overwrite(path, [&] { write_diagnostics(path, sample(), "", false); });
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"diag.gpkg"}));

  write_diagnostics(path, sample(), "", true);
  const Gpkg g(path);
  ASSERT_NE(g.ds, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(g.layer("skipped_segments"), TRUE), 3);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"diag.gpkg"}));
}

TEST(DiagnosticsWriter, UnwritableFolderIsAnOutputErrorAndLeavesNothing) {
  // Tests may run as root, for whom a read-only folder is writable; a regular file is not.
  const std::string dir = scratch();
  spit(dir + "/plain", "x");
  if (const auto e = test::thrown<OutputError>(
          [&] { write_diagnostics(dir + "/plain/diag.gpkg", sample(), "", false); })) {
    EXPECT_NE(e->detail().find("Not a directory"), std::string::npos) << e->what();
  }
  EXPECT_THROW(write_diagnostics(dir + "/missing/diag.gpkg", sample(), "", false), OutputError);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"plain"}));
}

TEST(DiagnosticsWriter, NonFiniteLocationIsRefusedBeforeAnythingIsCreated) {
  const std::string dir = scratch();
  Diagnostics d = sample();
  d.skipped_segments[2].at.y = std::numeric_limits<double>::quiet_NaN();
  if (const auto e =
          test::thrown<OutputError>([&] { write_diagnostics(dir + "/diag.gpkg", d, "", false); })) {
    EXPECT_EQ(e->where(), "layer skipped_segments, entry 2") << e->what();
  }
  // A dropped feature without a location may hold anything there.
  d = sample();
  d.dropped_features[1].at.x = std::numeric_limits<double>::infinity();
  write_diagnostics(dir + "/diag.gpkg", d, "", false);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"diag.gpkg"}));
}

TEST(DiagnosticsWriter, UnreadableCrsFailsAfterTheTemporaryAndLeavesNothing) {
  const std::string dir = scratch();
  if (const auto e = test::thrown<OutputError>(
          [&] { write_diagnostics(dir + "/diag.gpkg", sample(), "GEOGCS[nonsense", false); })) {
    EXPECT_NE(e->detail().find("cannot read the CRS"), std::string::npos) << e->what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(DiagnosticsWriter, WriteFailureInsideGdalLeavesNoFileNoTemporaryNoJournal) {
  // A file-size limit makes SQLite's writes fail with EFBIG, as a full disk fails with ENOSPC.
  const std::string dir = scratch();
  Diagnostics d;
  for (int i = 0; i < 100000; ++i)
    d.dropped_features.push_back({"a/rather/long/path/to/the/input/file.shp",
                                  i,
                                  std::string(40, 'r'),
                                  {1.0 * i, 2, 3},
                                  true});
  bool threw = false;
  try {
    const test::FileSizeLimit limit(1 << 20);
    write_diagnostics(dir + "/diag.gpkg", d, "", false);
  } catch (const OutputError& e) {
    threw = true;
    EXPECT_EQ(e.file(), dir + "/diag.gpkg");
    // Inside GDAL, whether SQLite spills its cache mid-way or only at the commit.
    EXPECT_THAT(e.detail(), AnyOf(HasSubstr("cannot write the feature"), HasSubstr("cannot commit"),
                                  HasSubstr("cannot complete")))
        << e.what();
  }
  EXPECT_TRUE(threw);
  EXPECT_TRUE(names_in(dir).empty());
}

// ---- from the line reader ----------------------------------------------------------------------

TEST(DiagnosticsWriter, LineReaderProblemsReachTheGeoPackage) {
  // A source written with OGR: a line with a repeated vertex, a point, a feature without
  // geometry; read, turned into diagnostics, written, read back.
  const std::string dir = scratch();
  const std::string source = dir + "/lines.gpkg";
  {
    GDALAllRegister();
    GDALDatasetH ds =
        GDALCreate(GDALGetDriverByName("GPKG"), source.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    ASSERT_NE(ds, nullptr);
    OGRLayerH layer = GDALDatasetCreateLayer(ds, "lines", nullptr, wkbUnknown, nullptr);
    ASSERT_NE(layer, nullptr);
    for (const char* wkt : {"LINESTRING Z (0 0 1, 1 0 2, 1 0 3, 2 0 4)", "POINT Z (5 6 7)", ""}) {
      OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(layer));
      if (*wkt != '\0') {
        OGRGeometryH g = nullptr;
        char* text = const_cast<char*>(wkt);
        ASSERT_EQ(OGR_G_CreateFromWkt(&text, nullptr, &g), OGRERR_NONE);
        OGR_F_SetGeometryDirectly(f, g);
      }
      ASSERT_EQ(OGR_L_CreateFeature(layer, f), OGRERR_NONE);
      OGR_F_Destroy(f);
    }
    GDALClose(ds);
  }
  LineData lines;
  const LineReadStats stats = read_lines(source, {}, lines);
  EXPECT_EQ(stats.repeated_vertices, 1u);
  EXPECT_EQ(stats.empty_features, 2u);
  Diagnostics d;
  add_line_diagnostics(lines, d);
  ASSERT_EQ(d.skipped_segments.size(), 1u);
  ASSERT_EQ(d.dropped_features.size(), 2u);
  write_diagnostics(dir + "/diag.gpkg", d, "", false);

  const Gpkg g(dir + "/diag.gpkg");
  ASSERT_NE(g.ds, nullptr);
  const auto skipped = rows_of(g.layer("skipped_segments"));
  ASSERT_EQ(skipped.size(), 1u);
  expect_near(skipped[0].at, {1, 0, 3});
  EXPECT_EQ(skipped[0].text.at("source_file"), source);
  EXPECT_EQ(skipped[0].integer.at("source_fid"), 1);
  const auto dropped = rows_of(g.layer("dropped_features"));
  ASSERT_EQ(dropped.size(), 2u);
  ASSERT_TRUE(dropped[0].has_geometry);
  expect_near(dropped[0].at, {5, 6, 7});
  EXPECT_EQ(dropped[0].integer.at("source_fid"), 2);
  EXPECT_NE(dropped[0].text.at("reason").find("Point"), std::string::npos);
  EXPECT_FALSE(dropped[1].has_geometry);
  EXPECT_EQ(dropped[1].integer.at("source_fid"), 3);
  EXPECT_EQ(dropped[1].text.at("reason"), "no geometry");
}

TEST(DiagnosticsWriter, AddLineDiagnosticsAppendsWithFileNames) {
  LineData lines;
  lines.files = {"a.shp", "b.gpkg:roads"};
  lines.skipped = {{{1, 2, 3}, 1, 40}, {{4, 5, 6}, 0, 41}};
  lines.dropped = {{1, 42, "empty geometry", {0, 0, 0}, false}};
  Diagnostics d = sample();
  add_line_diagnostics(lines, d);
  ASSERT_EQ(d.skipped_segments.size(), 5u);
  EXPECT_EQ(d.skipped_segments[3].file, "b.gpkg:roads");
  EXPECT_EQ(d.skipped_segments[3].fid, 40);
  EXPECT_EQ(d.skipped_segments[3].at, (Point3{1, 2, 3}));
  EXPECT_EQ(d.skipped_segments[4].file, "a.shp");
  ASSERT_EQ(d.dropped_features.size(), 3u);
  EXPECT_EQ(d.dropped_features[2].file, "b.gpkg:roads");
  EXPECT_EQ(d.dropped_features[2].fid, 42);
  EXPECT_EQ(d.dropped_features[2].reason, "empty geometry");
  EXPECT_FALSE(d.dropped_features[2].has_at);
}

}  // namespace
}  // namespace tincdt::io
