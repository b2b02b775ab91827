// The LAZ reader on the real files of shared/data/laz: every file reads, its raw X/Y/Z sum equals
// laz-perf's, and where a LAS twin exists every decoded record equals the twin's byte for byte.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/laz_file_edits.hpp"
#include "io/points/point_reader.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

std::string laz_path(const std::string& name) {
  return test::shared_file("laz/" + name + ".laz");
}
std::string las_path(const std::string& name) {
  return test::shared_file("las/" + name + ".las");
}

// The LAZ decoder's view of a file held in memory.
struct LoadedLaz {
  std::string bytes;
  std::vector<std::string> warnings;
  laz::LazSource source;
};

LoadedLaz load_laz(const std::string& path) {
  LoadedLaz l;
  l.bytes = test::slurp(path);
  l.source = laz::open_laz(path, reinterpret_cast<const std::uint8_t*>(l.bytes.data()),
                           l.bytes.size(), l.warnings);
  return l;
}

// The point records of an uncompressed LAS file, read here independently of the reader.
std::string las_records(const std::string& path, std::size_t* record_length = nullptr) {
  const std::string b = test::slurp(path);
  std::uint32_t offset;
  std::uint16_t length;
  std::uint32_t count;
  std::memcpy(&offset, b.data() + 96, 4);
  std::memcpy(&length, b.data() + 105, 2);
  std::memcpy(&count, b.data() + 107, 4);
  if (b[25] >= 4) {
    std::uint64_t count64;
    std::memcpy(&count64, b.data() + 247, 8);
    if (count64 != 0) count = static_cast<std::uint32_t>(count64);
  }
  if (record_length != nullptr) *record_length = length;
  return b.substr(offset, std::size_t{count} * length);
}

std::vector<Point3> read_all(const std::string& path, const PointFilter& filter,
                             PointReadStats* stats = nullptr, unsigned threads = 0) {
  std::vector<Point3> pts;
  PointReadStats s = read_points(path, filter, pts, threads);
  EXPECT_EQ(s.points_kept, pts.size()) << path;
  if (stats != nullptr) *stats = std::move(s);
  return pts;
}

// ---------------------------------------------------------------------------------------------
// Every file, against laz-perf

struct LazFact {
  const char* name;
  std::uint64_t points;
  std::int64_t xyz_sum;  // node ../shared/bench/node/lazperf_decode.mjs FILE.laz: "checksum"
  const char* format;    // PointReadStats::format
};

const LazFact kFacts[] = {
    {"simple", 1065, 158576409566, "laz 1.2 pdrf 3"},
    {"autzen_trim", 110000, 16347347810362, "laz 1.2 pdrf 3"},
    {"Topography", 73403, 2589876186591, "laz 1.2 pdrf 1"},
    {"Topography_lidR2016", 52146, 29741918509017, "laz 1.2 pdrf 1"},
    {"1_4_w_evlr", 1000, -995802310304, "laz 1.4 pdrf 6"},
    {"las14_pdrf6", 135, 120896766, "laz 1.4 pdrf 6"},
    {"append-bug", 37805, 26305204554039, "laz 1.4 pdrf 8"},
    {"simple.copc", 1065, -3713494, "copc 1.4 pdrf 7"},
};

class LazFile : public ::testing::TestWithParam<LazFact> {};

TEST_P(LazFile, ReadsAndMatchesLazPerf) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const LazFact& f = GetParam();
  const std::string path = laz_path(f.name);
  PointReadStats stats;
  const std::vector<Point3> pts = read_all(path, {}, &stats);
  EXPECT_EQ(pts.size(), f.points);
  EXPECT_EQ(stats.points_read, f.points);
  EXPECT_EQ(stats.format, f.format);
  // (las14_pdrf6.laz has an unreadable CRS record: a warning, but not about the points.)
  EXPECT_THAT(stats.warnings, ::testing::Each(::testing::Not(HasSubstr("chunk"))));
  for (const Point3& p : pts)
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));

  const LoadedLaz l = load_laz(path);
  std::vector<std::string> warnings;
  for (unsigned threads : {1u, 2u}) {
    const laz::LazSummary s = laz::summarize(l.source, threads, warnings);
    EXPECT_EQ(s.points, f.points);
    EXPECT_EQ(s.xyz_sum, f.xyz_sum) << "threads " << threads;
  }
  // The whole records too (every layer decoded), where the format allows.
  const std::vector<std::uint8_t> records = laz::read_records(l.source, 2, warnings);
  EXPECT_EQ(records.size(), f.points * l.source.record_length);
}

INSTANTIATE_TEST_SUITE_P(SharedData, LazFile, ::testing::ValuesIn(kFacts),
                         [](const auto& param_info) {
                           std::string n = param_info.param.name;
                           std::replace_if(
                               n.begin(), n.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return n;
                         });

TEST(LazFiles, EveryFileInTheFolderIsCovered) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::set<std::string> listed;
  for (const LazFact& f : kFacts) listed.insert(std::string(f.name) + ".laz");
  EXPECT_EQ(test::names_in(test::shared_file("laz")), listed);
}

// ---------------------------------------------------------------------------------------------
// LAS twins

class LazTwin : public ::testing::TestWithParam<const char*> {};

TEST_P(LazTwin, EveryRecordEqualsTheLasTwinsByteForByte) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::size_t record_length = 0;
  const std::string expected = las_records(las_path(GetParam()), &record_length);
  const LoadedLaz l = load_laz(laz_path(GetParam()));
  ASSERT_EQ(l.source.record_length, record_length);
  std::vector<std::string> warnings;
  for (unsigned threads : {1u, 3u}) {
    const std::vector<std::uint8_t> got = laz::read_records(l.source, threads, warnings);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); i += record_length) {
      ASSERT_EQ(std::memcmp(got.data() + i, expected.data() + i, record_length), 0)
          << "record " << i / record_length << ", threads " << threads;
    }
  }
  EXPECT_THAT(warnings, ::testing::IsEmpty());
}

TEST_P(LazTwin, FiltersKeepTheSamePointsAsFromLas) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::vector<PointFilter> filters(6);
  filters[1].keep_classes = {2};
  filters[2].drop_classes = {2};
  filters[3].first_return_only = true;
  filters[4].last_return_only = true;
  filters[5].keep_classes = {1, 2};
  filters[5].last_return_only = true;
  for (std::size_t i = 0; i < filters.size(); ++i) {
    PointReadStats las_stats;
    PointReadStats laz_stats;
    const std::vector<Point3> from_las = read_all(las_path(GetParam()), filters[i], &las_stats);
    const std::vector<Point3> from_laz =
        read_all(laz_path(GetParam()), filters[i], &laz_stats, i % 2 == 0 ? 0 : 1);
    EXPECT_EQ(from_laz, from_las) << "filter " << i;
    EXPECT_EQ(laz_stats.points_read, las_stats.points_read);
    EXPECT_EQ(laz_stats.crs_wkt, las_stats.crs_wkt);
    EXPECT_EQ(laz_stats.format.substr(3), las_stats.format.substr(3));
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, LazTwin,
                         ::testing::Values("simple", "autzen_trim", "Topography", "1_4_w_evlr"));

// ---------------------------------------------------------------------------------------------
// Threads and COPC

TEST(LazReader, TheThreadCountChangesNothing) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  for (const char* name : {"autzen_trim", "simple.copc", "append-bug"}) {
    PointFilter last;
    last.last_return_only = true;
    const std::vector<Point3> one = read_all(laz_path(name), {}, nullptr, 1);
    const std::vector<Point3> one_last = read_all(laz_path(name), last, nullptr, 1);
    for (unsigned threads : {2u, 3u, 8u, 0u}) {
      EXPECT_EQ(read_all(laz_path(name), {}, nullptr, threads), one) << name << ", " << threads;
      EXPECT_EQ(read_all(laz_path(name), last, nullptr, threads), one_last) << name;
    }
  }
}

TEST(LazReader, CopcGivesTheSameTinAsItsLasTwin) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // simple.copc.laz holds simple.las's points in octree order, with other offsets: the same
  // points to the centimetre, so the same TIN, triangle for triangle.
  const auto key = [](const Point2& p) {
    return std::array<long long, 2>{std::llround(p.x * 100), std::llround(p.y * 100)};
  };
  const auto triangles = [&](const std::string& path) {
    delaunay::DelaunayResult r = delaunay::triangulate(read_all(path, {}));
    std::set<std::array<std::array<long long, 2>, 3>> set;
    r.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& v) {
      std::array<std::array<long long, 2>, 3> tri = {key(r.tin.point(v[0])), key(r.tin.point(v[1])),
                                                     key(r.tin.point(v[2]))};
      std::sort(tri.begin(), tri.end());
      set.insert(tri);
    });
    return set;
  };
  const auto from_copc = triangles(laz_path("simple.copc"));
  EXPECT_GT(from_copc.size(), 2000u);
  EXPECT_EQ(from_copc, triangles(las_path("simple")));
}

TEST(LazReader, CoordinatesOnlyDecodingSkipsLayersYetAgreesWithWholeRecords) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // Formats 6-10 without a class filter decode only the XY and Z layers.
  for (const char* name : {"append-bug", "las14_pdrf6", "simple.copc"}) {
    const LoadedLaz l = load_laz(laz_path(name));
    std::vector<std::string> warnings;
    const std::vector<std::uint8_t> records = laz::read_records(l.source, 1, warnings);
    const std::vector<Point3> pts = read_all(laz_path(name), {});
    ASSERT_EQ(pts.size() * l.source.record_length, records.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      std::int32_t xyz[3];
      std::memcpy(xyz, records.data() + i * l.source.record_length, sizeof xyz);
      ASSERT_EQ(pts[i], l.source.transform.apply(xyz[0], xyz[1], xyz[2])) << name << " " << i;
    }
  }
}

TEST(LazReader, WaveformFormatsReadWithTheirPacketsSkipped) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // No shared file has waveform packets: formats 9 and 10 made from 6 and 8 (laz_file_edits.hpp).
  const fs::path dir = test::fresh_dir(fs::path(TINCDT_TEST_TMP) / "laz_waveforms");
  for (const auto& [name, format] : {std::pair{"las14_pdrf6", 9}, std::pair{"append-bug", 10}}) {
    const std::string path = (dir / (std::string(name) + ".laz")).string();
    test::spit(path, test::laz_edits::with_waveforms(test::slurp(laz_path(name))));
    PointFilter filter;
    PointReadStats stats;
    EXPECT_EQ(read_all(path, filter, &stats), read_all(laz_path(name), filter)) << name;
    EXPECT_EQ(stats.format, "laz 1.4 pdrf " + std::to_string(format));
    filter.keep_classes = {2};
    filter.last_return_only = true;
    EXPECT_EQ(read_all(path, filter), read_all(laz_path(name), filter)) << name;
    // Whole records would need the packets.
    const LoadedLaz l = load_laz(path);
    std::vector<std::string> warnings;
    try {
      (void)laz::read_records(l.source, 1, warnings);
      ADD_FAILURE() << name << ": records of format " << format << " were read";
    } catch (const InputError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr("waveform packets are not decoded"));
    }
  }
}

}  // namespace
}  // namespace tincdt::io
