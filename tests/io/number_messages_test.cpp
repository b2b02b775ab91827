// Reader errors and warnings print their big numbers (counts, byte offsets, line numbers)
// thousands separated, never as a long run of digits.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/points/point_reader.hpp"
#include "points/point_reading.hpp"
#include "support/byte_fields.hpp"
#include "support/files.hpp"
#include "support/las_writer.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

using test::input_error;
using test::put;
using ::testing::AllOf;
using ::testing::HasSubstr;

const test::ScratchFolder scratch("number_messages");

// A message part with no run of 4 or more digits: every number of 1,000 or more is grouped.
void expect_grouped(const std::string& text) {
  EXPECT_FALSE(std::regex_search(text, std::regex("[0-9]{4,}"))) << text;
}

void expect_grouped(const InputError& e) {
  expect_grouped(e.where());
  expect_grouped(e.detail());
}

TEST(NumberText, SignedCountsAreGroupedWithTheirSign) {
  EXPECT_EQ(signed_count_text(-1234567), "-1,234,567");
  EXPECT_EQ(signed_count_text(-12), "-12");
  EXPECT_EQ(signed_count_text(0), "0");
  EXPECT_EQ(signed_count_text(INT64_MIN), "-9,223,372,036,854,775,808");
}

// A LAS header announcing 12,345,678 points over three records.
TEST(NumberMessages, ALasCountAboveTheRecords) {
  test::las::Header h;
  const std::vector<test::las::Record> records(3);
  std::string b = test::las::file(h, records);
  put<std::uint32_t>(b, 107, 12345678);
  const auto e = input_error(scratch("count.las", b));
  ASSERT_TRUE(e);
  EXPECT_THAT(e->detail(),
              HasSubstr("the file holds 3 records but the header announces 12,345,678"));
  expect_grouped(*e);
}

// A bad line after a million good ones.
TEST(NumberMessages, AnXyzLineFarIntoTheFile) {
  std::string text;
  text.reserve(6'000'010);
  for (int i = 0; i < 1'000'000; ++i) text += "1 2 3\n";
  text += "1 2 x\n";
  const auto e = input_error(scratch("far.xyz", text));
  ASSERT_TRUE(e);
  EXPECT_EQ(e->where(), "line 1,000,001");
  expect_grouped(*e);
}

TEST(NumberMessages, AnXyzLineTooLong) {
  const auto e = input_error(scratch("long.xyz", "1 2 3\n" + std::string(1100000, '7')));
  ASSERT_TRUE(e);
  EXPECT_EQ(e->where(), "line 2");
  EXPECT_THAT(e->detail(), HasSubstr("longer than 1,048,576 bytes"));
}

TEST(NumberMessages, APlyElementCountAboveTheFile) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty double x\nproperty double y\n"
      "property double z\nend_header\n1 2 3\n";
  const auto e = input_error(scratch("count.ply", ply));
  ASSERT_TRUE(e);
  EXPECT_THAT(e->detail(), HasSubstr("announces 4,000,000,000 items"));
  expect_grouped(*e);
}

// Topography.laz (73,403 points in chunks of 50,000) with its header announcing 12,345,678: the
// chunk table contradicts it.
TEST(NumberMessages, ALazCountAboveItsChunkTable) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::string b = test::slurp(test::shared_file("laz/Topography.laz"));
  put<std::uint32_t>(b, 107, 12345678);
  const auto e = input_error(scratch("count.laz", b));
  ASSERT_TRUE(e);
  EXPECT_EQ(e->where(), "chunk table");
  EXPECT_THAT(e->detail(), AllOf(HasSubstr("12,345,678 points"), HasSubstr("chunks of 50,000")));
  expect_grouped(*e);
}

// The chunk table's offset beyond the file: a warning, and the chunks read one after the other.
TEST(NumberMessages, ALazChunkTableOffsetBeyondTheFile) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::string b = test::slurp(test::shared_file("laz/Topography.laz"));
  put<std::int64_t>(b, test::get<std::uint32_t>(b, 96), 9876543210);  // at the point data
  PointReadStats stats;
  EXPECT_EQ(test::points_of(scratch("table.laz", b), {}, &stats).size(), 73403u);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_THAT(stats.warnings[0], AllOf(HasSubstr("its offset 9,876,543,210 lies outside the " +
                                                 count_text(b.size()) + "-byte file")));
  expect_grouped(stats.warnings[0].substr(stats.warnings[0].find(": ")));
}

}  // namespace
}  // namespace tincdt::io
