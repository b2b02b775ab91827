// The readers against hostile input: signed zeros, coordinates whose differences
// overflow, lines without end, CR-only text, lying counts, short CRS records, format bytes that
// are no format, and vector sources that give nothing or lose features. Every input is made here.

#include <gdal.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "io/vector/polygon_reader.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const test::ScratchFolder scratch("hostile");
const fs::path kTmp = scratch.path();

std::vector<Point3> points_of(const std::string& path) {
  std::vector<Point3> pts;
  read_points(path, {}, pts);
  return pts;
}

std::string points_error(const std::string& path) {
  return test::error_of([&] { points_of(path); });
}

// ---- XYZ ------------------------------------------------------------------------------------

TEST(HostileXyz, SignedZerosBecomeZero) {
  const auto pts = points_of(scratch("zeros.xyz", "5 5 1\n-0 -0 -0\n-0.0e5 0 3\n"));
  ASSERT_EQ(pts.size(), 3u);
  for (const Point3& p : pts) {
    EXPECT_FALSE(std::signbit(p.x));
    EXPECT_FALSE(std::signbit(p.y));
    EXPECT_FALSE(std::signbit(p.z));
  }
}

TEST(HostileXyz, CoordinatesBeyondTheRangeAreRefusedNamingTheLine) {
  EXPECT_THAT(points_error(scratch("huge_y.xyz", "0 0 1\n5 1e308 2\n")),
              AllOf(HasSubstr("huge_y.xyz: line 2"), HasSubstr("'1e308' is beyond +-1e15")));
  EXPECT_THAT(points_error(scratch("huge_z.xyz", "0 0 -2e15\n")), HasSubstr("line 1"));
  EXPECT_EQ(points_of(scratch("big_ok.xyz", "1e15 -1e15 0\n")).size(), 1u);
}

TEST(HostileXyz, CrOnlyLineEndsAreNamed) {
  for (const char* text : {"0 0 1\r5 0 2\r0 5 3\r", "# made on a Mac\rx y z\r0 0 1\r5 0 2\r"}) {
    EXPECT_THAT(points_error(scratch("cr_only.xyz", text)),
                AllOf(HasSubstr("line 1"), HasSubstr("CR-only line ends")))
        << text;
  }
  // CR LF is fine, and so is a CR at the very end.
  EXPECT_EQ(points_of(scratch("crlf.xyz", "0 0 1\r\n5 0 2\r\n0 5 3\r")).size(), 3u);
  // A bare CR after the data of a later line.
  EXPECT_THAT(points_error(scratch("cr_late.xyz", "0 0 1\n5 0 2\r0 5 3\n")),
              AllOf(HasSubstr("line 2"), HasSubstr("carriage return")));
}

TEST(HostileXyz, ALineLongerThanAMegabyteIsAnError) {
  std::string text = "0 0 1\n5 0 2\n";
  text += std::string(std::size_t{3} << 20, '\0');
  EXPECT_THAT(points_error(scratch("zeros.xyz", text)),
              AllOf(HasSubstr("line 3"), HasSubstr("longer than 1,048,576 bytes")));
  std::string cr;
  for (int i = 0; i < 200000; ++i) cr += std::to_string(i) + " 0 1\r";
  EXPECT_THAT(points_error(scratch("long_cr.xyz", cr)), HasSubstr("CR-only line ends"));
}

// `head -c 1500M /dev/zero | tincdt -` grew to 3 GB: the stream buffer doubled for a line that
// never ended. Now the reader stops after one buffer, and the writer sees the pipe close long
// before it has written a gigabyte.
TEST(HostileXyz, AStreamWithoutLineEndsStopsInBoundedMemory) {
  const fs::path fifo = kTmp / "zeros.fifo";
  fs::create_directories(kTmp);
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto old_handler = std::signal(SIGPIPE, SIG_IGN);
  std::size_t written = 0;
  std::thread writer([&] {
    std::ofstream out(fifo, std::ios::binary);
    const std::string block(std::size_t{1} << 20, '\0');
    for (int i = 0; i < 1024 && out.write(block.data(), static_cast<std::streamsize>(block.size()));
         ++i)
      written += block.size();
  });
  const std::string what = points_error(fifo.string());
  writer.join();
  std::signal(SIGPIPE, old_handler);
  fs::remove(fifo);
  EXPECT_THAT(what, AllOf(HasSubstr("line 1"), HasSubstr("longer than")));
  EXPECT_LT(written, std::size_t{1} << 30);
}

#if defined(__SANITIZE_ADDRESS__)
#define TINCDT_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TINCDT_ASAN 1
#endif
#endif

// "error: out of memory" named nothing. Run in a child with little heap (the sanitizers need
// their own address space, so not under them).
TEST(HostileXyzDeathTest, OutOfMemoryNamesTheFile) {
#ifdef TINCDT_ASAN
  GTEST_SKIP() << "AddressSanitizer needs the address space a heap limit takes away";
#else
  // 40 MB of short lines: about 40 MB of points need 160 MB of memory, the child gets 64 MB.
  std::string text;
  for (int i = 0; i < 4000000; ++i) text += "1 2 " + std::to_string(i % 10) + "\n";
  const std::string path = scratch("many.xyz", text);
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto read_with_64_mb = [&path] {
    rlimit limit{};
    limit.rlim_cur = limit.rlim_max = std::size_t{64} << 20;
    ::setrlimit(RLIMIT_DATA, &limit);
    std::fprintf(stderr, "%s\n", points_error(path).c_str());
    std::_Exit(3);
  };
  EXPECT_EXIT(read_with_64_mb(), ::testing::ExitedWithCode(3),
              "many.xyz: out of memory after reading [0-9]+ of its points");
#endif
}

// ---- LAS ------------------------------------------------------------------------------------

struct LasRecord {
  std::int32_t x, y, z;
};

struct LasSpec {
  std::array<double, 3> scale{0.01, 0.01, 0.01};
  std::array<double, 3> offset{0, 0, 0};
  int format_byte = 0;
  std::vector<std::pair<std::uint16_t, std::string>> projection_vlrs;  // record id, payload
  std::vector<LasRecord> records;
};

template <typename T>
void put(std::string& b, std::size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);
}

// A LAS 1.2 file, point format 0 (20-byte records), written from the specification's layout.
std::string las_bytes(const LasSpec& spec) {
  std::string vlrs;
  for (const auto& [id, payload] : spec.projection_vlrs) {
    std::string h(54, '\0');
    std::memcpy(h.data() + 2, "LASF_Projection", 15);
    put<std::uint16_t>(h, 18, id);
    put<std::uint16_t>(h, 20, static_cast<std::uint16_t>(payload.size()));
    vlrs += h + payload;
  }
  std::string b(227, '\0');
  std::memcpy(b.data(), "LASF", 4);
  b[24] = 1;
  b[25] = 2;
  put<std::uint16_t>(b, 94, 227);
  put<std::uint32_t>(b, 96, static_cast<std::uint32_t>(227 + vlrs.size()));
  put<std::uint32_t>(b, 100, static_cast<std::uint32_t>(spec.projection_vlrs.size()));
  b[104] = static_cast<char>(spec.format_byte);
  put<std::uint16_t>(b, 105, 20);
  put<std::uint32_t>(b, 107, static_cast<std::uint32_t>(spec.records.size()));
  for (int i = 0; i < 3; ++i) {
    put<double>(b, 131 + 8 * i, spec.scale[i]);
    put<double>(b, 155 + 8 * i, spec.offset[i]);
  }
  b += vlrs;
  for (const LasRecord& r : spec.records) {
    std::string rec(20, '\0');
    put(rec, 0, r.x);
    put(rec, 4, r.y);
    put(rec, 8, r.z);
    rec[14] = 0x09;  // return 1 of 1
    rec[15] = 2;     // ground
    b += rec;
  }
  return b;
}

TEST(HostileLas, ShortGeoTiffRecordsAreNoCrsAndNoUndefinedBehaviour) {
  // A keys record of 1 byte and a doubles record of 7: too short for one value each (UBSan
  // reported memcpy into the null data() of the empty vector).
  LasSpec spec;
  spec.projection_vlrs = {{34735, std::string(1, '\x01')}, {34736, std::string(7, '\x02')}};
  spec.records = {{0, 0, 0}, {100, 0, 0}, {0, 100, 0}};
  std::vector<Point3> pts;
  const PointReadStats s = read_points(scratch("short_keys.las", las_bytes(spec)), {}, pts);
  EXPECT_EQ(pts.size(), 3u);
  EXPECT_EQ(s.crs_wkt, "");
}

TEST(HostileLas, FormatByte255IsNoFormatNotLaz) {
  LasSpec spec;
  spec.format_byte = 255;
  spec.records = {{0, 0, 0}};
  EXPECT_THAT(points_error(scratch("f255.las", las_bytes(spec))),
              AllOf(HasSubstr("unsupported point data record format 255"),
                    ::testing::Not(HasSubstr("LAZ"))));
  spec.format_byte = 0x80;  // LASzip's mark on format 0, but no LASzip VLR
  EXPECT_THAT(points_error(scratch("f128.las", las_bytes(spec))),
              AllOf(HasSubstr("compressed (LAZ)"), HasSubstr("no LASzip VLR")));
}

TEST(HostileLas, CoordinatesBeyondTheRangeNameTheRecord) {
  LasSpec spec;
  spec.scale = {1e300, 0.01, 0.01};
  spec.records = {{0, 0, 0}, {0, 5, 0}, {1, 0, 0}};
  EXPECT_THAT(points_error(scratch("huge.las", las_bytes(spec))),
              AllOf(HasSubstr("point record 2"), HasSubstr("X = 1e+300 is beyond +-1e15")));
  // A scale that could reach beyond, with records that do not: read as usual.
  spec.scale = {1e9, 0.01, 0.01};
  EXPECT_EQ(points_of(scratch("wide_scale.las", las_bytes(spec))).size(), 3u);
}

TEST(HostileLas, NegativeZeroOffsetGivesNoNegativeZero) {
  LasSpec spec;
  spec.scale = {-0.01, -0.01, -0.01};
  spec.offset = {-0.0, -0.0, -0.0};
  spec.records = {{0, 0, 0}, {100, 0, 0}, {0, 100, 0}};
  for (const Point3& p : points_of(scratch("minus_zero.las", las_bytes(spec)))) {
    EXPECT_FALSE(std::signbit(p.x) && p.x == 0);
    EXPECT_FALSE(std::signbit(p.y) && p.y == 0);
    EXPECT_FALSE(std::signbit(p.z) && p.z == 0);
  }
}

// ---- vector sources -------------------------------------------------------------------------

using Feat = test::VectorFeature;

Feat geometry(const char* wkt) {
  Feat f;
  f.wkt = wkt;
  return f;
}

std::string write_gpkg(const std::string& name, const std::vector<Feat>& features) {
  return test::write_vector(kTmp / name, std::vector<test::VectorLayer>{{"lines", features}},
                            "GPKG", "NAME");
}

std::string lines_error(const std::string& path) {
  LineData data;
  return test::error_of([&] { read_lines(path, {}, data); });
}

std::string polygons_error(const std::string& path) {
  ShapeData data;
  return test::error_of([&] { read_polygons(path, {}, data); });
}

TEST(HostileVector, HugeAndSignedZeroCoordinates) {
  const std::string huge = write_gpkg("huge.gpkg", {geometry("LINESTRING Z (0 0 1, 10 10 1)"),
                                                    geometry("LINESTRING Z (0 10 1, 10 1e308 1)")});
  EXPECT_THAT(lines_error(huge), AllOf(HasSubstr("feature 2"), HasSubstr("y = 1e+308 is beyond")));
  EXPECT_THAT(polygons_error(
                  write_gpkg("huge_ring.gpkg", {geometry("POLYGON ((0 0, 1e16 0, 0 10, 0 0))")})),
              AllOf(HasSubstr("feature 1"), HasSubstr("x = 1e+16 is beyond")));

  LineData lines;
  read_lines(write_gpkg("zero.gpkg", {geometry("LINESTRING Z (-0 -0 -0, 10 10 1)")}), {}, lines);
  ASSERT_FALSE(lines.vertices.empty());
  EXPECT_FALSE(std::signbit(lines.vertices[0].x));
  EXPECT_FALSE(std::signbit(lines.vertices[0].y));
  EXPECT_FALSE(std::signbit(lines.vertices[0].z));
}

// A GeoPackage may state any feature count; the reader reserved room for it ("out of memory").
TEST(HostileVector, ALyingFeatureCountIsNotTrusted) {
  const std::string path = write_gpkg("lying.gpkg", {geometry("LINESTRING Z (0 0 1, 10 10 1)")});
  {
    GDALDatasetH ds =
        GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, nullptr, nullptr, nullptr);
    ASSERT_NE(ds, nullptr);
    GDALDatasetExecuteSQL(ds, "UPDATE gpkg_ogr_contents SET feature_count = 4000000000", nullptr,
                          nullptr);
    GDALClose(ds);
  }
  LineData lines;
  const LineReadStats s = read_lines(path, {}, lines);
  EXPECT_EQ(s.features, 1u);
  EXPECT_LT(lines.features.capacity(), 1000u);
}

TEST(HostileVector, ASourceThatGivesNothingIsAnError) {
  EXPECT_THAT(lines_error(write_gpkg("empty.gpkg", {})),
              AllOf(HasSubstr("empty.gpkg: layer lines"), HasSubstr("the layer has no features")));
  EXPECT_THAT(
      lines_error(
          write_gpkg("points.gpkg", {geometry("POINT Z (1 2 3)"), geometry("POINT Z (4 5 6)")})),
      AllOf(HasSubstr("none of its 2 features gives a line"),
            HasSubstr("Point geometry: only lines and polygon rings are used (2 features)")));
  EXPECT_THAT(lines_error(write_gpkg("one_vertex.gpkg", {geometry("LINESTRING Z (1 2 3)")})),
              HasSubstr("none of its 1 features gives a line: degenerate"));
  EXPECT_THAT(polygons_error(write_gpkg("lines_as_clip.gpkg", {geometry("LINESTRING (0 0, 1 1)")})),
              AllOf(HasSubstr("none of its 1 features gives a polygon"),
                    HasSubstr("Line String geometry: only polygons are used")));
  EXPECT_THAT(polygons_error(write_gpkg("no_geometry.gpkg", {geometry(""), geometry("")})),
              HasSubstr("no geometry (2 features)"));
}

TEST(HostileVector, ASourceThatLosesSomeFeaturesWarnsWithTheCount) {
  LineData lines;
  const LineReadStats s =
      read_lines(write_gpkg("some_lost.gpkg", {geometry("LINESTRING Z (0 0 1, 10 10 1)"),
                                               geometry("POINT Z (4 5 6)"), geometry("")}),
                 {}, lines);
  EXPECT_EQ(lines.features.size(), 1u);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_THAT(s.warnings.back(), AllOf(HasSubstr("some_lost.gpkg: layer lines: 2 of 3 features "
                                                 "dropped"),
                                       HasSubstr("no geometry (1 feature)"),
                                       HasSubstr("(the diagnostics output lists them)")));
  ShapeData rings;
  const ShapeReadStats r = read_polygons(
      write_gpkg("bad_hole.gpkg", {geometry("POLYGON ((0 0, 10 0, 0 10, 0 0), (1 1, 2 2, 1 1))")}),
      {}, rings);
  EXPECT_EQ(rings.features.size(), 1u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_THAT(r.warnings.back(), HasSubstr("1 ring with too few distinct vertices skipped"));
}

// A shapefile whose .shp body is garbage: GDAL reads every record as no geometry.
TEST(HostileVector, AShapefileWithAGarbageBodyIsAnError) {
  const std::string shp = test::write_vector(
      kTmp / "garbage.shp",
      std::vector<test::VectorLayer>{
          {"garbage",
           {geometry("LINESTRING Z (0 0 1, 10 10 1)"), geometry("LINESTRING Z (0 10 1, 10 0 1)")}}},
      "ESRI Shapefile", "NAME");
  std::string bytes = test::slurp(shp);
  ASSERT_GT(bytes.size(), 100u);
  for (std::size_t i = 100; i < bytes.size(); ++i) bytes[i] = static_cast<char>(0xA5 ^ (i * 7));
  test::spit(shp, bytes);
  EXPECT_THAT(lines_error(shp), HasSubstr("none of its 2 features gives a line"));
}

}  // namespace
}  // namespace tincdt::io
