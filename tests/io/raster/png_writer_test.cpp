// The preview PNG's progress: GDAL's reports reach ours as "write preview", and a request to stop
// ends the write with Cancelled and no file.
#include "io/raster/png_writer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

constexpr std::uint32_t kSide = 200;

std::vector<std::uint8_t> grey_picture() {
  return std::vector<std::uint8_t>(std::size_t{4} * kSide * kSide, 128);
}

TEST(PngWriter, ReportsItsProgressAsWritePreview) {
  const std::string dir = test::scratch_dir("png_writer_progress");
  std::set<std::string> stages;
  double last = 0;
  const ProgressFn record = [&](std::string_view stage, double fraction) {
    stages.emplace(stage);
    last = fraction;
    return true;
  };
  OutputFile out(dir + "/p.png", false);
  write_png(out, kSide, kSide, grey_picture(), &record);
  out.commit();
  EXPECT_EQ(stages, std::set<std::string>{"write preview"});
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_EQ(test::names_in(dir), std::set<std::string>{"p.png"});
}

TEST(PngWriter, ProgressCanCancel) {
  const std::string dir = test::scratch_dir("png_writer_cancel");
  const ProgressFn stop = [](std::string_view, double f) { return f < 0.3; };
  {
    OutputFile out(dir + "/p.png", false);
    EXPECT_THROW(write_png(out, kSide, kSide, grey_picture(), &stop), Cancelled);
  }
  EXPECT_TRUE(test::names_in(dir).empty());
}

}  // namespace
}  // namespace tincdt::io
