// The GDAL support of src/io: GDAL's messages reach the user on one line, whatever the driver
// put in them (the shapefile driver's missing-.shx message spans two lines).

#include "io/gdal_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "io/vector/line_reader.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kTmp = fs::path(TINCDT_TEST_TMP) / "gdal_support";

TEST(GdalSupport, OneLineJoinsLinesAndBlankRuns) {
  EXPECT_EQ(detail::one_line("  a\n  b\r\n\tc  "), "a b c");
  EXPECT_EQ(detail::one_line("\n \n"), "");
}

TEST(GdalSupport, LastMessageIsOneLineOrTheFallback) {
  const detail::GdalQuiet quiet;
  EXPECT_EQ(detail::last_gdal_message("nothing"), "nothing");
  CPLError(CE_Failure, CPLE_AppDefined, "first line.\nsecond line.");
  EXPECT_EQ(detail::last_gdal_message("nothing"), "first line. second line.");
}

TEST(GdalSupport, MessagesKeepWarningsAndTheFirstFailureOnOneLine) {
  const detail::GdalMessages messages;
  CPLError(CE_Warning, CPLE_AppDefined, "a warning\nin two lines");
  CPLError(CE_Failure, CPLE_AppDefined, "the first\nfailure");
  CPLError(CE_Failure, CPLE_AppDefined, "the second failure");
  ASSERT_EQ(messages.warnings().size(), 1u);
  EXPECT_EQ(messages.warnings()[0], "a warning in two lines");
  EXPECT_TRUE(messages.failed());
  EXPECT_EQ(messages.failure(), "the first failure");
}

// A shapefile without its .shx: GDAL's complaint ("Unable to open x.shx or x.SHX. Set
// SHAPE_RESTORE_SHX ...", in two lines in some GDAL versions) comes out as one line of the error.
TEST(GdalSupport, ShapefileWithoutShxGivesAOneLineError) {
  const fs::path shp = kTmp / "no_shx.shp";
  test::write_vector(
      shp, std::vector<test::VectorLayer>{{"no_shx", {{"LINESTRING (0 0 1, 1 1 1)", 1.0}}}},
      "ESRI Shapefile", "NAME");
  ASSERT_TRUE(fs::remove(kTmp / "no_shx.shx"));
  LineData out;
  try {
    read_lines(shp.string(), {}, out);
    FAIL() << "a shapefile without .shx was read";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_THAT(what, HasSubstr("no_shx.shx"));
    EXPECT_THAT(what, Not(HasSubstr("\n")));
  }
}

}  // namespace
}  // namespace tincdt::io
