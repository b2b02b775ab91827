// Point readers (XYZ, LAS) and CRS helpers, against the real files of shared/data (see its
// PROVENANCE.md for the facts checked here) and against bad input written by the tests.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/types.hpp"
#include "io/crs.hpp"
#include "io/points/point_reader.hpp"
#include "support/byte_fields.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using test::get;
using test::put;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kData = ::tincdt::test::shared_data();

// Own subfolder: the writers test shares TINCDT_TEST_TMP.
const test::ScratchFolder scratch_file("readers");
const fs::path kTmp = scratch_file.path();

// The few public-header fields the tests need, read here independently of the reader.
struct RawHeader {
  int minor = 0, format = 0;
  std::size_t record_length = 0, offset_to_points = 0;
  std::uint64_t count = 0;
  double scale[3] = {}, max[3] = {}, min[3] = {};
};

RawHeader raw_header(const std::string& b) {
  RawHeader h;
  h.minor = static_cast<unsigned char>(b[25]);
  h.format = static_cast<unsigned char>(b[104]);
  h.record_length = get<std::uint16_t>(b, 105);
  h.offset_to_points = get<std::uint32_t>(b, 96);
  h.count = get<std::uint32_t>(b, 107);
  if (h.minor >= 4 && get<std::uint64_t>(b, 247) != 0) h.count = get<std::uint64_t>(b, 247);
  for (int i = 0; i < 3; ++i) {
    h.scale[i] = get<double>(b, 131 + 8 * i);
    h.max[i] = get<double>(b, 179 + 16 * i);
    h.min[i] = get<double>(b, 187 + 16 * i);
  }
  return h;
}

// Runs F, which must throw InputError, and returns its what().
template <typename F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
  return {};
}

std::string read_points_error(const std::string& path, const PointFilter& filter = {}) {
  std::vector<Point3> pts;
  return input_error_of([&] { read_points(path, filter, pts); });
}

std::vector<Point3> read_all(const std::string& path, const PointFilter& filter = {},
                             PointReadStats* stats = nullptr) {
  std::vector<Point3> pts;
  PointReadStats s = read_points(path, filter, pts);
  EXPECT_EQ(s.points_kept, pts.size()) << path;
  if (stats != nullptr) *stats = std::move(s);
  return pts;
}

std::string las(const char* name) {
  return (kData / "las" / name).string();
}

// ---------------------------------------------------------------------------------------------
// LAS: every real file against PROVENANCE.md

struct LasFact {
  const char* file;
  const char* format;  // PointReadStats::format
  std::uint64_t count;
  const char* crs;  // crs_label() of the CRS read; "" = none; nullptr = checked elsewhere
  std::vector<std::pair<int, std::uint64_t>> classes;
  // PROVENANCE.md: min/max of X, Y, Z, rounded to 0.01.
  std::array<double, 6> bounds;
  bool header_bounds_ok = true;
};

const std::vector<LasFact>& las_facts() {
  static const std::array<double, 6> kAutzen = {636001.76, 637179.22, 848935.20,
                                                849497.90, 406.26,    520.51};
  static const std::array<double, 6> kSimple = {635619.85, 638982.55, 848899.70,
                                                853535.43, 406.59,    586.38};
  static const std::array<double, 6> kTest14 = {1694038.45, 1694539.68, 1816492.71,
                                                1816497.98, 5592.75,    5599.07};
  static const std::vector<LasFact> facts = {
      {"1.0_0.las",
       "las 1.0 pdrf 0",
       1,
       "EPSG:26915",
       {{2, 1}},
       {470692.44, 470692.44, 4602888.90, 4602888.90, 16.00, 16.00}},
      {"1_4_w_evlr.las", "las 1.4 pdrf 6", 1000, "EPSG:2903", {{2, 1000}}, kTest14},
      {"4_6_crop.las",
       "las 1.2 pdrf 3",
       23875,
       "EPSG:2903",
       {{1, 14872}, {2, 9003}},
       {1639600.00, 1639799.98, 1454500.02, 1454700.00, 7077.92, 7139.70}},
      {"Topography.las",
       "las 1.2 pdrf 1",
       73403,
       "EPSG:2949",
       {{1, 61347}, {2, 8159}, {9, 3897}},
       {273357.14, 273642.86, 5274357.14, 5274642.85, 788.99, 829.76}},
      {"autzen_trim.las",
       "las 1.2 pdrf 3",
       110000,
       "NAD_1983_HARN_Lambert_Conformal_Conic",
       {{1, 83893}, {2, 26107}},
       kAutzen},
      {"autzen_trim_7.las",
       "las 1.4 pdrf 7",
       110000,
       "NAD_1983_HARN_Lambert_Conformal_Conic",
       {{1, 83893}, {2, 26107}},
       kAutzen},
      {"autzen_trim_8_derived.las",
       "las 1.4 pdrf 8",
       110000,
       "NAD_1983_HARN_Lambert_Conformal_Conic",
       {{1, 83893}, {2, 26107}},
       kAutzen},
      {"epsg_4326.las",
       "las 1.2 pdrf 0",
       5380,
       "EPSG:4326",
       {{0, 5380}},
       {-94.68, -94.66, 31.04, 31.05, 39.08, 78.12}},
      // The WKT record (NAD83(2011) / Nebraska ftUS) wins over the GeoTIFF keys (EPSG:32104 with
      // overrides); checked in detail below.
      {"file_with_both_wkt_and_geotiff_vlrs.las",
       "las 1.4 pdrf 6",
       25408,
       nullptr,
       {{2, 9808}, {3, 158}, {4, 724}, {5, 10956}, {6, 3737}, {7, 25}},
       {2445180.00, 2445239.99, 604300.00, 604339.98, 1352.70, 1403.96}},
      {"hexbin-crop.las",
       "las 1.2 pdrf 1",
       38367,
       "EPSG:32642",
       {{1, 3049}, {2, 35318}},
       {393775.82, 394069.24, 3689071.94, 3689273.10, 3107.86, 3209.32}},
      // GeoTIFF keys say EPSG:26995 but override its unit with US feet; checked below.
      {"mvk-thin.las",
       "las 1.2 pdrf 1",
       6280,
       nullptr,
       {{1, 129}, {2, 1693}, {4, 141}, {5, 578}, {9, 37}, {12, 3702}},
       {2045001.76, 2049993.92, 1267501.19, 1272499.79, 95.79, 228.73}},
      {"sample_c.las",
       "las 1.2 pdrf 3",
       14408,
       "",
       {{2, 1368}, {3, 93}, {4, 29}, {5, 7}, {6, 12525}, {11, 2}, {14, 45}, {31, 339}},
       {674521.92, 674605.32, 1206740.08, 1206814.96, 627.53, 656.23}},
      {"simple.las", "las 1.2 pdrf 3", 1065, "", {{1, 789}, {2, 276}}, kSimple},
      {"simple1_1.las", "las 1.1 pdrf 1", 1065, "", {{1, 789}, {2, 276}}, kSimple},
      // Vertical CRS only. Its writer put raw integers (without offset) in the header bounds.
      {"simple1_3.las",
       "las 1.3 pdrf 4",
       999,
       "",
       {{1, 999}},
       {-235434.52, -234935.84, 5800843.14, 5800946.25, 265.09, 273.81},
       false},
      {"test1_4.las", "las 1.4 pdrf 6", 1000, "EPSG:2903", {{2, 1000}}, kTest14},
      {"warsaw_small.las",
       "las 1.2 pdrf 3",
       3000,
       "",  // the WKT record is empty
       {{0, 433}, {2, 1381}, {3, 257}, {4, 27}, {5, 902}},
       {639913.26, 639946.75, 485143.14, 485175.91, 84.70, 104.55}},
      {"wontcompress3.las",
       "las 1.4 pdrf 6",
       1000,
       "EPSG:26919",
       {{1, 914}, {2, 86}},
       {768321.06, 768376.94, 2028734.53, 2028768.08, 104.98, 113.03}},
  };
  return facts;
}

// For test names and failure messages: the file, not the bytes of the struct.
void PrintTo(const LasFact& fact, std::ostream* os) {
  *os << fact.file;
}

class LasFile : public ::testing::TestWithParam<LasFact> {};

TEST_P(LasFile, CountFormatBoundsAndCrsMatchTheHeaderAndProvenance) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const LasFact& fact = GetParam();
  const std::string path = las(fact.file);
  const RawHeader h = raw_header(test::slurp(path));
  ASSERT_EQ(h.count, fact.count) << "PROVENANCE.md and the file disagree";

  PointReadStats stats;
  const std::vector<Point3> pts = read_all(path, {}, &stats);
  EXPECT_EQ(stats.format, fact.format);
  EXPECT_EQ(stats.points_read, fact.count);
  EXPECT_EQ(stats.points_kept, fact.count);
  ASSERT_EQ(pts.size(), fact.count);

  double lo[3] = {INFINITY, INFINITY, INFINITY};
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const Point3& p : pts) {
    const double c[3] = {p.x, p.y, p.z};
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], c[i]);
      hi[i] = std::max(hi[i], c[i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE("axis " + std::to_string(i));
    if (fact.header_bounds_ok) {
      EXPECT_NEAR(lo[i], h.min[i], h.scale[i]);
      EXPECT_NEAR(hi[i], h.max[i], h.scale[i]);
    }
    EXPECT_NEAR(lo[i], fact.bounds[2 * i], 0.0051);
    EXPECT_NEAR(hi[i], fact.bounds[2 * i + 1], 0.0051);
  }
  if (fact.crs != nullptr) {
    EXPECT_EQ(crs_label(stats.crs_wkt), fact.crs);
    EXPECT_EQ(stats.crs_wkt.empty(), std::string(fact.crs).empty());
  }
}

TEST_P(LasFile, ClassFiltersGiveTheProvenanceCounts) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const LasFact& fact = GetParam();
  std::uint64_t sum = 0;
  for (const auto& [cls, count] : fact.classes) {
    PointFilter keep;
    keep.keep_classes = {static_cast<std::uint8_t>(cls)};
    PointReadStats stats;
    EXPECT_EQ(read_all(las(fact.file), keep, &stats).size(), count) << "class " << cls;
    EXPECT_EQ(stats.points_read, fact.count);
    PointFilter drop;
    drop.drop_classes = {static_cast<std::uint8_t>(cls)};
    EXPECT_EQ(read_all(las(fact.file), drop).size(), fact.count - count) << "class " << cls;
    sum += count;
  }
  EXPECT_EQ(sum, fact.count) << "the class table of the test is incomplete";
}

std::string test_name(const ::testing::TestParamInfo<LasFact>& info) {
  std::string name = info.param.file;
  name = name.substr(0, name.size() - 4);
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(SharedData, LasFile, ::testing::ValuesIn(las_facts()), test_name);

TEST(LasReader, EveryLasFileInSharedDataIsCovered) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  for (const auto& entry : fs::directory_iterator(kData / "las")) {
    if (entry.path().extension() != ".las") continue;
    const std::string name = entry.path().filename().string();
    const bool covered = std::any_of(las_facts().begin(), las_facts().end(),
                                     [&](const LasFact& f) { return name == f.file; });
    EXPECT_TRUE(covered) << name << " has no entry in las_facts()";
  }
}

TEST(LasReader, MixedClassListKeepsTheUnionAndDropWins) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointFilter f;
  f.keep_classes = {3, 4, 5};
  EXPECT_EQ(read_all(las("file_with_both_wkt_and_geotiff_vlrs.las"), f).size(), 158u + 724 + 10956);
  f.drop_classes = {4};
  EXPECT_EQ(read_all(las("file_with_both_wkt_and_geotiff_vlrs.las"), f).size(), 158u + 10956);
  PointFilter none;
  none.keep_classes = {200};  // a class the 5-bit field of PDRF 0-5 cannot even hold
  EXPECT_EQ(read_all(las("sample_c.las"), none).size(), 0u);
}

// First / last return filters, against counts decoded here from the raw records.
void check_return_filters(const char* file) {
  SCOPED_TRACE(file);
  const std::string b = test::slurp(las(file));
  const RawHeader h = raw_header(b);
  const bool extended = h.format >= 6;
  std::uint64_t first = 0;
  std::uint64_t last = 0;
  std::uint64_t ground_last = 0;
  for (std::uint64_t i = 0; i < h.count; ++i) {
    const std::size_t r = h.offset_to_points + i * h.record_length;
    const auto flags = static_cast<unsigned char>(b[r + 14]);
    const unsigned ret = extended ? (flags & 15u) : (flags & 7u);
    const unsigned n = extended ? (flags >> 4) : ((flags >> 3) & 7u);
    const unsigned cls = extended ? static_cast<unsigned char>(b[r + 16])
                                  : (static_cast<unsigned char>(b[r + 15]) & 31u);
    const bool single = ret == 0 || n == 0;
    first += (single || ret == 1) ? 1 : 0;
    const bool is_last = single || ret >= n;
    last += is_last ? 1 : 0;
    ground_last += (is_last && cls == 2) ? 1 : 0;
  }
  ASSERT_LT(first, h.count) << "the file should have multiple returns";
  ASSERT_LT(last, h.count);
  PointFilter f;
  f.first_return_only = true;
  EXPECT_EQ(read_all(las(file), f).size(), first);
  f.first_return_only = false;
  f.last_return_only = true;
  EXPECT_EQ(read_all(las(file), f).size(), last);
  f.keep_classes = {2};
  EXPECT_EQ(read_all(las(file), f).size(), ground_last);
}

TEST(LasReader, ReturnFiltersLegacyFormat) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  check_return_filters("Topography.las");  // PDRF 1, up to 6 returns
}

TEST(LasReader, ReturnFiltersExtendedFormat) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  check_return_filters("autzen_trim_7.las");  // PDRF 7: 4-bit return fields
}

TEST(LasReader, SamePointsInEveryFormatAndVersion) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::vector<Point3> pdrf3 = read_all(las("autzen_trim.las"));
  EXPECT_EQ(read_all(las("autzen_trim_7.las")), pdrf3);
  EXPECT_EQ(read_all(las("autzen_trim_8_derived.las")), pdrf3);
  EXPECT_EQ(read_all(las("simple1_1.las")), read_all(las("simple.las")));
  EXPECT_EQ(read_all(las("1_4_w_evlr.las")), read_all(las("test1_4.las")));
}

TEST(LasReader, KnownPointsAreExact) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::vector<Point3> one = read_all(las("1.0_0.las"));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].x, 470692.44, 0.005);
  EXPECT_NEAR(one[0].y, 4602888.90, 0.005);
  EXPECT_NEAR(one[0].z, 16.00, 0.005);
  // X = record * scale + offset, in double, for the first record of a large-offset file.
  const std::string b = test::slurp(las("Topography.las"));
  const RawHeader h = raw_header(b);
  const double expected_x =
      get<std::int32_t>(b, h.offset_to_points) * h.scale[0] + get<double>(b, 155);
  EXPECT_EQ(read_all(las("Topography.las"))[0].x, expected_x);
}

TEST(LasReader, AppendsToTheCallersVector) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::vector<Point3> pts = {{1, 2, 3}};
  read_las(las("simple.las"), {}, pts);
  ASSERT_EQ(pts.size(), 1066u);
  EXPECT_EQ(pts[0], (Point3{1, 2, 3}));
}

TEST(LasReader, CrsFromBothRecordsPrefersTheWkt) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointReadStats stats;
  read_all(las("file_with_both_wkt_and_geotiff_vlrs.las"), {}, &stats);
  EXPECT_THAT(stats.crs_wkt, HasSubstr("NAD83_2011_Nebraska_ft"));
  EXPECT_NE(crs_label(stats.crs_wkt), "EPSG:32104");  // what the GeoTIFF keys name
  EXPECT_TRUE(stats.warnings.empty());
}

TEST(LasReader, GeoTiffUnitOverrideIsHonouredAndReported) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointReadStats stats;
  read_all(las("mvk-thin.las"), {}, &stats);
  ASSERT_FALSE(stats.crs_wkt.empty());
  EXPECT_THAT(stats.crs_wkt, HasSubstr("Mississippi West"));
  EXPECT_THAT(stats.crs_wkt, HasSubstr("US survey foot"));
  EXPECT_NE(crs_label(stats.crs_wkt), "EPSG:26995");  // that one is in metres
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_THAT(stats.warnings[0], HasSubstr("EPSG:26995"));
  EXPECT_THAT(stats.warnings[0], HasSubstr("mvk-thin.las"));
}

TEST(LasReader, UnusableCrsRecordsGiveNoCrsAndAWarning) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointReadStats stats;
  read_all(las("simple1_3.las"), {}, &stats);
  EXPECT_TRUE(stats.crs_wkt.empty());
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_THAT(stats.warnings[0], HasSubstr("vertical"));
  EXPECT_THAT(stats.warnings[0], HasSubstr("5030"));
  read_all(las("warsaw_small.las"), {}, &stats);
  EXPECT_TRUE(stats.crs_wkt.empty());
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_THAT(stats.warnings[0], HasSubstr("WKT"));
  read_all(las("sample_c.las"), {}, &stats);
  EXPECT_TRUE(stats.crs_wkt.empty());
  EXPECT_TRUE(stats.warnings.empty());
}

TEST(LasReader, CrsMatchesTheContoursOfTheSameArea) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointReadStats stats;
  read_all(las("Topography.las"), {}, &stats);
  const std::string prj =
      crs_from_user((kData / "pair_topography/Topography_contours_1m.prj").string());
  EXPECT_TRUE(same_crs(stats.crs_wkt, prj));
}

// ---------------------------------------------------------------------------------------------
// Damaged LAS (LAZ: laz_*_test.cpp)

TEST(LasReader, TruncatedInsideThePoints) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::string b = test::slurp(las("autzen_trim.las"));
  const RawHeader h = raw_header(b);
  b.resize(h.offset_to_points + 55000 * h.record_length + 17);
  const std::string path = scratch_file("cut_in_points.las", b);
  const std::string what = read_points_error(path);
  EXPECT_THAT(what, HasSubstr(path));
  EXPECT_THAT(what, HasSubstr("point record 55,000"));
  EXPECT_THAT(what, HasSubstr("byte " + count_text(h.offset_to_points + 55000 * 34)));
  EXPECT_THAT(what, HasSubstr("file holds 55,000 records but the header announces 110,000"));
}

TEST(LasReader, TruncatedAtARecordBoundary) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::string b = test::slurp(las("simple.las"));
  const RawHeader h = raw_header(b);
  b.resize(h.offset_to_points + 1000 * h.record_length);
  const std::string what = read_points_error(scratch_file("cut_at_record.las", b));
  EXPECT_THAT(what, HasSubstr("file holds 1,000 records but the header announces 1,065"));
}

TEST(LasReader, TruncatedInsideTheHeader) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string b = test::slurp(las("autzen_trim.las"));
  std::string what = read_points_error(scratch_file("cut_in_header.las", b.substr(0, 100)));
  EXPECT_THAT(what, HasSubstr("cut_in_header.las"));
  EXPECT_THAT(what, HasSubstr("truncated"));
  EXPECT_THAT(what, HasSubstr("227"));
  // Past the public header, inside the VLRs: the point data start lies beyond the end.
  what = read_points_error(scratch_file("cut_in_vlrs.las", b.substr(0, 400)));
  EXPECT_THAT(what, HasSubstr("truncated"));
  EXPECT_THAT(what, HasSubstr("the point data should start at byte"));
}

TEST(LasReader, TruncatedExtendedVlr) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::string b = test::slurp(las("1_4_w_evlr.las"));
  const auto evlr_start = get<std::uint64_t>(b, 235);
  ASSERT_GT(evlr_start, 0u);
  b.resize(evlr_start + 70);
  const std::string what = read_points_error(scratch_file("cut_in_evlr.las", b));
  EXPECT_THAT(what, HasSubstr("extended VLR 0"));
  EXPECT_THAT(what, HasSubstr("truncated"));
}

TEST(LasReader, PointCountLargerThanTheFile) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::string b = test::slurp(las("simple.las"));
  put<std::uint32_t>(b, 107, 1075);
  EXPECT_THAT(read_points_error(scratch_file("count_up.las", b)),
              HasSubstr("file holds 1,065 records but the header announces 1,075"));
  // LAS 1.4: the 64-bit count is the one that counts.
  std::string b14 = test::slurp(las("test1_4.las"));
  put<std::uint64_t>(b14, 247, 5000);
  EXPECT_THAT(read_points_error(scratch_file("count64_up.las", b14)),
              HasSubstr("file holds 1,000 records but the header announces 5,000"));
}

TEST(LasReader, LegacyCountIsUsedWhenThe64BitCountIsZero) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  std::string b = test::slurp(las("test1_4.las"));
  put<std::uint64_t>(b, 247, 0);
  put<std::uint32_t>(b, 107, 600);
  EXPECT_EQ(read_all(scratch_file("legacy_count.las", b)).size(), 600u);
}

TEST(LasReader, BadHeadersAreRefused) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string good = test::slurp(las("simple.las"));
  std::string b = good;
  std::memcpy(b.data(), "LASX", 4);
  EXPECT_THAT(read_points_error(scratch_file("bad_signature.las", b)), HasSubstr("not a LAS file"));
  b = good;
  b[25] = 5;
  EXPECT_THAT(read_points_error(scratch_file("version_1_5.las", b)),
              HasSubstr("unsupported LAS version 1.5"));
  b = good;
  b[24] = 2;
  b[25] = 0;
  EXPECT_THAT(read_points_error(scratch_file("version_2_0.las", b)),
              HasSubstr("unsupported LAS version 2.0"));
  b = good;
  put<std::uint16_t>(b, 105, 30);  // PDRF 3 needs 34
  EXPECT_THAT(
      read_points_error(scratch_file("short_record.las", b)),
      HasSubstr("point record length 30 is smaller than the 34 bytes point format 3 needs"));
  b = good;
  b[104] = 11;
  EXPECT_THAT(read_points_error(scratch_file("format_11.las", b)),
              HasSubstr("unsupported point data record format 11"));
  b = good;
  put<double>(b, 139, 0.0);  // Y scale
  EXPECT_THAT(read_points_error(scratch_file("zero_scale.las", b)),
              HasSubstr("invalid Y scale factor"));
}

TEST(LasReader, LongerRecordsThanTheFormatNeedsAreFine) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  // PDRF 8 records of autzen_trim_8_derived.las read as PDRF 7 with 2 extra bytes each.
  std::string b = test::slurp(las("autzen_trim_8_derived.las"));
  b[104] = 7;
  EXPECT_EQ(read_all(scratch_file("pdrf7_extra_bytes.las", b)), read_all(las("autzen_trim_7.las")));
}

// ---------------------------------------------------------------------------------------------
// Dispatch: missing and empty files

TEST(PointReader, MissingFile) {
  const std::string path = (kTmp / "does_not_exist.xyz").string();
  std::string what = read_points_error(path);
  EXPECT_THAT(what, HasSubstr(path));
  EXPECT_THAT(what, HasSubstr("no such file"));
  std::vector<Point3> pts;
  EXPECT_THAT(input_error_of([&] { read_las((kTmp / "nope.las").string(), {}, pts); }),
              HasSubstr("no such file"));
  EXPECT_THAT(input_error_of([&] { read_xyz((kTmp / "nope.xyz").string(), pts); }),
              HasSubstr("no such file"));
  EXPECT_THAT(read_points_error((kTmp / "nope.laz").string()), HasSubstr("no such file"));
}

TEST(PointReader, EmptyFile) {
  for (const char* name : {"empty.xyz", "empty.las", "empty"}) {
    const std::string path = scratch_file(name, "");
    const std::string what = read_points_error(path);
    EXPECT_THAT(what, HasSubstr(path));
    EXPECT_THAT(what, HasSubstr("empty file"));
  }
  std::vector<Point3> pts;
  EXPECT_THAT(input_error_of([&] { read_xyz(scratch_file("empty2.xyz", ""), pts); }),
              HasSubstr("empty file"));
}

TEST(PointReader, DirectoryIsRefused) {
  fs::create_directories(kTmp / "a_dir.xyz");
  EXPECT_THAT(read_points_error((kTmp / "a_dir.xyz").string()), HasSubstr("directory"));
}

TEST(PointReader, TextThatIsNotLasGoesToTheXyzReader) {
  const std::string path = scratch_file("no_extension", "1 2 3\n4 5 6\n");
  PointReadStats stats;
  EXPECT_EQ(read_all(path, {}, &stats).size(), 2u);
  EXPECT_EQ(stats.format, "xyz");
  EXPECT_TRUE(stats.crs_wkt.empty());
}

// ---------------------------------------------------------------------------------------------
// XYZ: real files

TEST(XyzReader, SpaceSeparatedRealFile) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::vector<Point3> pts = read_all((kData / "xyz/Topography_ground.xyz").string());
  ASSERT_EQ(pts.size(), 8159u);
  EXPECT_EQ(pts[0], (Point3{273357.17825, 5274357.66925, 806.02475}));
  BBox box;
  double zmin = INFINITY;
  double zmax = -INFINITY;
  for (const Point3& p : pts) {
    box.add(p.x, p.y);
    zmin = std::min(zmin, p.z);
    zmax = std::max(zmax, p.z);
  }
  EXPECT_NEAR(box.min_x, 273357.18, 0.01);
  EXPECT_NEAR(box.max_x, 273642.86, 0.01);
  EXPECT_NEAR(box.min_y, 5274357.16, 0.01);
  EXPECT_NEAR(box.max_y, 5274642.83, 0.01);
  EXPECT_NEAR(zmin, 788.99, 0.01);
  EXPECT_NEAR(zmax, 814.83, 0.01);
}

// The ground points written out as text are the ground points of the LAS file.
void expect_same_points(std::vector<Point3> a, std::vector<Point3> b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  const auto by_xyz = [](const Point3& p, const Point3& q) {
    return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
  };
  std::sort(a.begin(), a.end(), by_xyz);
  std::sort(b.begin(), b.end(), by_xyz);
  std::size_t bad = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::abs(a[i].x - b[i].x) > tol || std::abs(a[i].y - b[i].y) > tol ||
        std::abs(a[i].z - b[i].z) > tol) {
      ++bad;
    }
  }
  EXPECT_EQ(bad, 0u);
}

TEST(XyzReader, GroundTextMatchesTheLasGround) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointFilter ground;
  ground.keep_classes = {2};
  expect_same_points(read_all((kData / "xyz/Topography_ground.xyz").string()),
                     read_all(las("Topography.las"), ground), 1e-6);
  expect_same_points(read_all((kData / "xyz/autzen_trim_ground.xyz").string()),
                     read_all(las("autzen_trim.las"), ground), 1e-6);
}

TEST(XyzReader, QuotedCsvHeaderWithManyColumns) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  PointReadStats stats;
  const std::vector<Point3> pts =
      read_all((kData / "xyz/autzen-bmx-largersample.csv").string(), {}, &stats);
  ASSERT_EQ(pts.size(), 103u);
  EXPECT_EQ(stats.points_read, 103u);
  EXPECT_EQ(pts[0], (Point3{194506.860, 259235.010, 426.540}));
  EXPECT_EQ(pts[1], (Point3{194503.850, 259234.260, 426.570}));
  for (const Point3& p : pts) {
    EXPECT_NEAR(p.x, 194500, 100);
    EXPECT_NEAR(p.y, 259235, 100);
    EXPECT_NEAR(p.z, 426, 30);
  }
}

// ---------------------------------------------------------------------------------------------
// XYZ: syntax

std::vector<Point3> xyz(const std::string& name, const std::string& text) {
  return read_all(scratch_file(name, text));
}

std::string xyz_error(const std::string& name, const std::string& text) {
  return read_points_error(scratch_file(name, text));
}

TEST(XyzReader, SeparatorsCommentsAndBlankLines) {
  const std::vector<Point3> expected = {{1, 2, 3}, {4.5, -5, 6e2}};
  EXPECT_EQ(xyz("spaces.xyz", "1 2 3\n4.5 -5 6e2\n"), expected);
  EXPECT_EQ(xyz("tabs.xyz", "  1\t\t2   3  \n\t4.5\t-5\t6e2"), expected);  // no final newline
  EXPECT_EQ(xyz("commas.xyz", "1,2,3\n4.5, -5 , 6e2\n"), expected);
  EXPECT_EQ(xyz("semicolons.xyz", "1;2;3\r\n4.5;-5;6e2\r\n"), expected);
  EXPECT_EQ(xyz("comments.xyz", "# survey 2024\n\n1 2 3\n   # indented comment\n\n4.5 -5 6e2\n"),
            expected);
  EXPECT_EQ(xyz("extra_columns.xyz", "1 2 3 100 7 a\n4.5 -5 6e2 200 8 b\n"), expected);
  EXPECT_EQ(xyz("end_comment.xyz", "1 2 3 # station 4, north\n4.5 -5 6e2\n"), expected);
  EXPECT_EQ(xyz("plus_sign.xyz", "+1 +2 +3\n+4.5 -5 +6e2\n"), expected);
  EXPECT_EQ(xyz("bom.xyz", "\xEF\xBB\xBFx y z\n1 2 3\n4.5 -5 6e2\n"), expected);
  EXPECT_TRUE(xyz("only_comments.xyz", "# nothing here\n\n").empty());
}

TEST(XyzReader, HeaderNamesTheColumns) {
  const std::vector<Point3> expected = {{1, 2, 3}};
  EXPECT_EQ(xyz("header_plain.xyz", "X Y Z\n1 2 3\n"), expected);
  EXPECT_EQ(xyz("header_reordered.csv", "id,Z,y,x,intensity\n7,3,2,1,99\n"), expected);
  EXPECT_EQ(xyz("header_quoted.csv", "\"Id\";\"X\";\"Y\";\"Z\"\n7;1;2;3\n"), expected);
  EXPECT_EQ(xyz("header_after_comment.xyz", "# exported\nx y z\n1 2 3\n"), expected);
  // Names other than x/y/z: the first three columns.
  EXPECT_EQ(xyz("header_other_names.xyz", "easting northing height\n1 2 3\n"), expected);
}

TEST(XyzReader, AppendsToTheCallersVector) {
  std::vector<Point3> pts = {{9, 9, 9}};
  const PointReadStats stats = read_xyz(scratch_file("append.xyz", "1 2 3\n"), pts);
  EXPECT_EQ(stats.points_kept, 1u);
  EXPECT_EQ(pts, (std::vector<Point3>{{9, 9, 9}, {1, 2, 3}}));
}

TEST(XyzReader, MalformedLineNamesFileAndLine) {
  const std::string path = scratch_file("malformed.xyz", "1 2 3\n4 5 6\n7 8 x\n10 11 12\n");
  const std::string what = read_points_error(path);
  EXPECT_THAT(what, HasSubstr(path + ": line 3: expected 3 numbers x y z, got '7 8 x'"));
  EXPECT_THAT(what, HasSubstr("'x' is not a number"));
}

TEST(XyzReader, LineNumbersCountCommentsAndHeader) {
  EXPECT_THAT(xyz_error("late.xyz", "# c\nx y z\n\n1 2 3\n# c\nbad line here\n"),
              HasSubstr(": line 6: "));
  EXPECT_THAT(xyz_error("crlf.xyz", "x;y;z\r\n1;2;3\r\n4;5\r\n"), HasSubstr(": line 3: "));
}

TEST(XyzReader, EveryKindOfBadLineIsAnError) {
  EXPECT_THAT(xyz_error("too_few.xyz", "1 2 3\n4 5\n"),
              AllOf(HasSubstr("line 2"), HasSubstr("got '4 5'"), HasSubstr("too few fields")));
  EXPECT_THAT(xyz_error("garbage.xyz", "1 2 3.5abc\n"),
              AllOf(HasSubstr("line 1"), HasSubstr("'3.5abc' is not a number")));
  EXPECT_THAT(xyz_error("nan.xyz", "1 2 3\n1 nan 3\n"),
              AllOf(HasSubstr("line 2"), HasSubstr("'nan' is not a finite number")));
  EXPECT_THAT(xyz_error("inf.xyz", "1 2 -inf\n"), HasSubstr("'-inf' is not a finite number"));
  EXPECT_THAT(xyz_error("nan_first.xyz", "NaN 2 3\n"), HasSubstr("line 1"));
  EXPECT_THAT(xyz_error("overflow.xyz", "1 2 1e999\n"), HasSubstr("line 1"));
  EXPECT_THAT(xyz_error("empty_field.csv", "1,2,3\n1,,3\n"),
              AllOf(HasSubstr("line 2"), HasSubstr("field 2 is empty")));
  EXPECT_THAT(xyz_error("no_comma.csv", "x,y,z\n1,2,3\n1 2 3\n"),
              AllOf(HasSubstr("line 3"), HasSubstr("no ','")));
  // A decimal comma must not turn "1,5;2,5;3,5" into x=1 y=5 z=2.
  EXPECT_THAT(xyz_error("decimal_comma.xyz", "1,5;2,5;3,5\n"), HasSubstr("line 1"));
  // Only the first line can be a header.
  EXPECT_THAT(xyz_error("second_header.xyz", "x y z\nx y z\n"), HasSubstr("line 2"));
  EXPECT_THAT(xyz_error("hex.xyz", "0x10 2 3\n"), HasSubstr("line 1"));
  EXPECT_THAT(xyz_error("binary.xyz", std::string("1 2 3\n\x01\x02\x03\n", 9)),
              HasSubstr("line 2"));
}

TEST(XyzReader, LargeFileKeepsOrderAndLineNumbers) {
  // Big enough to be parsed in several pieces on a multi-core machine.
  std::string text = "x,y,z,i\n";
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    text += std::to_string(i) + ".25," + std::to_string(2 * i) + ",-" + std::to_string(i % 97) +
            ".5,12345678\n";
  }
  const std::vector<Point3> pts = xyz("large.csv", text);
  ASSERT_EQ(pts.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; i += 997) {
    ASSERT_EQ(pts[i], (Point3{i + 0.25, 2.0 * i, -(i % 97) - 0.5})) << i;
  }
  EXPECT_EQ(pts.back(), (Point3{n - 1 + 0.25, 2.0 * (n - 1), -((n - 1) % 97) - 0.5}));
  // A bad line near the end: its number counts every line of the earlier pieces.
  const std::size_t pos = text.rfind('\n', text.size() - 2000);
  text.insert(pos + 1, "1,2\n");
  const std::size_t line =
      static_cast<std::size_t>(std::count(text.begin(), text.begin() + pos + 1, '\n')) + 1;
  EXPECT_THAT(xyz_error("large_bad.csv", text), HasSubstr(": line " + count_text(line) + ": "));
}

TEST(XyzReader, ReadsFromAPipe) {
  const fs::path fifo = kTmp / "points.fifo";
  fs::create_directories(kTmp);
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] {
    std::ofstream out(fifo, std::ios::binary);
    out << "# from a pipe\nX Y Z\n";
    for (int i = 0; i < 5000; ++i) out << i << ' ' << i + 1 << ' ' << i + 2 << '\n';
    out << "1 2 oops\n";
  });
  const std::string what = read_points_error(fifo.string());
  writer.join();
  EXPECT_THAT(what, HasSubstr(": line 5,003: "));
  EXPECT_THAT(what, HasSubstr("'oops' is not a number"));

  std::thread writer2([&] {
    std::ofstream out(fifo, std::ios::binary);
    out << "x y z\n1 2 3\n4 5 6";
  });
  std::vector<Point3> pts;
  read_points(fifo.string(), {}, pts);
  writer2.join();
  EXPECT_EQ(pts, (std::vector<Point3>{{1, 2, 3}, {4, 5, 6}}));
  fs::remove(fifo);
}

// ---------------------------------------------------------------------------------------------
// CRS

TEST(Crs, FromUserAndLabel) {
  const std::string wkt = crs_from_user("EPSG:2949");
  EXPECT_THAT(wkt, HasSubstr("MTM zone 7"));
  EXPECT_EQ(crs_label(wkt), "EPSG:2949");
  EXPECT_EQ(crs_label(crs_from_user("+proj=utm +zone=32 +datum=WGS84 +units=m +no_defs")),
            "EPSG:32632");
  EXPECT_EQ(crs_label(""), "");
}

TEST(Crs, BadUserInputThrowsWithGdalsReason) {
  const std::string what = input_error_of([] { crs_from_user("EPSG:999999"); });
  EXPECT_THAT(what, HasSubstr("EPSG:999999"));
  EXPECT_THAT(input_error_of([] { crs_from_user("not a crs at all"); }),
              HasSubstr("not a crs at all"));
}

TEST(Crs, SameCrs) {
  const std::string utm = crs_from_user("EPSG:32632");
  EXPECT_TRUE(same_crs("", ""));
  EXPECT_FALSE(same_crs("", utm));
  EXPECT_FALSE(same_crs(utm, ""));
  EXPECT_TRUE(same_crs(utm, utm));
  EXPECT_TRUE(same_crs(utm, crs_from_user("+proj=utm +zone=32 +datum=WGS84 +units=m +no_defs")));
  EXPECT_FALSE(same_crs(utm, crs_from_user("EPSG:32633")));
  EXPECT_FALSE(same_crs(utm, "garbage"));
}

TEST(Crs, EsriWktFromLasMatchesItsContoursPrj) {
  // autzen_trim.las carries ESRI WKT whose false easting is 399999.9999984 ft for 400000 m; the
  // contours derived from it carry EPSG:2994. Strict OSR comparison calls them different.
  const std::string data = ::tincdt::test::shared_data();
  if (!std::filesystem::exists(data)) GTEST_SKIP() << "no shared data at " << data;
  std::vector<Point3> points;
  const PointReadStats stats = read_las(data + "/las/autzen_trim.las", {}, points);
  const std::string prj = crs_from_user(data + "/pair_autzen/autzen_trim_contours_2ft.prj");
  EXPECT_TRUE(same_crs(stats.crs_wkt, prj));
  EXPECT_FALSE(same_crs(stats.crs_wkt, crs_from_user("EPSG:2992")));  // Oregon Lambert, ft
  EXPECT_FALSE(same_crs(stats.crs_wkt, crs_from_user("EPSG:2949")));
}

TEST(Crs, PrjIsEsriWkt1) {
  const std::string prj = crs_to_prj(crs_from_user("EPSG:32632"));
  EXPECT_THAT(prj, HasSubstr("PROJCS[\"WGS_1984_UTM_Zone_32N\""));
  EXPECT_THAT(prj, Not(HasSubstr("AUTHORITY")));
  EXPECT_EQ(crs_to_prj(""), "");
  EXPECT_THAT(input_error_of([] { crs_to_prj("garbage"); }), HasSubstr("garbage"));
  // A compound CRS still gives a usable .prj.
  EXPECT_THAT(crs_to_prj(crs_from_user("EPSG:2903+6360")), HasSubstr("PROJCS["));
}

}  // namespace
}  // namespace tincdt::io
