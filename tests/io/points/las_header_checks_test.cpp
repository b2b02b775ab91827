// The LAS and LAZ readers against headers that contradict their data: point counts above what
// the records or chunks hold, scales that make coordinates beyond the range, VLRs that run past
// the point data.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/types.hpp"
#include "io/points/point_reader.hpp"
#include "point_reading.hpp"
#include "support/byte_fields.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

using test::get;
using test::put;
using ::testing::AllOf;
using ::testing::HasSubstr;

using test::input_error;
using test::points_of;

const test::ScratchFolder scratch("las_header_checks");

// Where the first VLR with this user id and record id starts.
std::size_t vlr_at(const std::string& b, const char* uid, std::uint16_t record_id) {
  std::size_t pos = get<std::uint16_t>(b, 94);
  for (std::uint32_t i = 0; i < get<std::uint32_t>(b, 100); ++i) {
    if (b.compare(pos + 2, std::strlen(uid), uid) == 0 &&
        get<std::uint16_t>(b, pos + 18) == record_id)
      return pos;
    pos += 54 + get<std::uint16_t>(b, pos + 20);
  }
  ADD_FAILURE() << "no VLR " << uid << " " << record_id;
  return 0;
}

// ---- Header counts the data contradicts ---------------------------------------------------------

TEST(PointCounts, ALazHeaderCountAboveTheChunksIsRefused) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::string b = test::slurp(test::shared_file("laz/append-bug.laz"));
  ASSERT_EQ(get<std::uint64_t>(b, 247), 37805u);
  put<std::uint64_t>(b, 247, 37806);
  const std::string path = scratch("append-bug-37806.laz", b);
  const auto e = input_error(path);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), path);
  EXPECT_THAT(e->detail(), AllOf(HasSubstr("37,806"), HasSubstr("37,805")));
  // The true count still reads.
  EXPECT_EQ(points_of(test::shared_file("laz/append-bug.laz")).size(), 37805u);
}

// A LAS header's point count raised by one: the record that is not there would be read from the
// bytes after the records.
TEST(PointCounts, ALasHeaderCountAboveTheRecordsIsRefused) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  struct Case {
    const char* file;
    bool count_is_64_bit;   // LAS 1.4 files keep the count at 247, others at 107
    std::uint64_t records;  // what the data holds
    const char* after;      // what the extra record would read
  };
  for (const Case& c : {Case{"1_4_w_evlr.las", true, 1000, "the extended VLRs"},
                        Case{"simple1_3.las", false, 999, "160 bytes of waveform packets"},
                        Case{"simple.las", false, 1065, "the end of the file"}}) {
    SCOPED_TRACE(std::string(c.file) + ", count into " + c.after);
    std::string b = test::slurp(test::shared_file(std::string("las/") + c.file));
    if (c.count_is_64_bit) {
      ASSERT_EQ(get<std::uint64_t>(b, 247), c.records);
      put<std::uint64_t>(b, 247, c.records + 1);
    } else {
      ASSERT_EQ(get<std::uint32_t>(b, 107), c.records);
      put<std::uint32_t>(b, 107, static_cast<std::uint32_t>(c.records + 1));
    }
    const auto e = input_error(scratch(std::string("count_up_") + c.file, b));
    ASSERT_TRUE(e);
    EXPECT_THAT(e->detail(), AllOf(HasSubstr(count_text(c.records + 1)),
                                   HasSubstr("holds " + count_text(c.records) + " records")));
  }
}

// ---- Coordinates beyond the range --------------------------------------------------------------

TEST(CoordinateRange, AHugeScaleIsRefusedForLasAndLaz) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  for (const char* name : {"las/simple.las", "laz/simple.laz", "laz/las14_pdrf6.laz"}) {
    SCOPED_TRACE(name);
    std::string b = test::slurp(test::shared_file(name));
    put<double>(b, 131, 1e300);  // X scale factor
    const std::string path = scratch(std::filesystem::path(name).filename().string(), b);
    const auto e = input_error(path);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->file(), path);
    EXPECT_THAT(e->detail(), AllOf(HasSubstr("beyond +-1e15"), HasSubstr("X scale factor")));
  }
}

// ---- Broken VLR chains --------------------------------------------------------------------------

// A record whose stated length runs past the point data: its payload is whole up to there, so the
// file reads, with a warning naming the record and the length.
TEST(VlrChain, ARecordRunningPastThePointDataIsReadWithAWarning) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  struct Case {
    const char* file;
    const char* user_id;
    std::uint16_t record_id, length;
    std::size_t points;
    const char* warning;
  };
  for (const Case& c :
       {Case{"simple.copc.laz", "LASF_Projection", 2112, 60000, 1065,
             "variable length record 2 ('LASF_Projection'"},
        Case{"1_4_w_evlr.laz", "laszip encoded", 22204, 400, 1000, "('laszip encoded'"}}) {
    SCOPED_TRACE(c.file);
    std::string b = test::slurp(test::shared_file(std::string("laz/") + c.file));
    put<std::uint16_t>(b, vlr_at(b, c.user_id, c.record_id) + 20, c.length);
    PointReadStats stats;
    EXPECT_EQ(points_of(scratch(std::string("long_vlr_") + c.file, b), {}, &stats).size(),
              c.points);
    EXPECT_FALSE(stats.crs_wkt.empty());
    ASSERT_EQ(stats.warnings.size(), 1u);
    EXPECT_THAT(stats.warnings[0],
                AllOf(HasSubstr(c.warning), HasSubstr(count_text(c.length) + " bytes")));
  }
}

}  // namespace
}  // namespace tincdt::io
