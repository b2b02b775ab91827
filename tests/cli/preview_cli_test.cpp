// --preview on the command line: a PNG of the sample that GDAL reads as 4 bands of bytes (alpha
// last) at the size asked for, and usage errors for a name that is no PNG or a size without it.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace {

namespace fs = std::filesystem;

using Outcome = tincdt::test::ShellRun;

Outcome run(const std::string& dir, const std::string& args) {
  return tincdt::test::run_tincdt(dir, args);
}

const std::string kSample = "'" TINCDT_SOURCE_DIR "/data/sample.las'";

TEST(PreviewCli, WritesAPngGdalReads) {
  const std::string dir = tincdt::test::scratch_dir("preview_cli");
  const Outcome r =
      run(dir, kSample + " -o t.ply --max-edge 20 --preview p.png --preview-size 300");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_NE(r.messages.find("wrote p.png"), std::string::npos) << r.messages;
  GDALAllRegister();
  GDALDatasetUniquePtr png(GDALDataset::Open((dir + "/p.png").c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(png);
  EXPECT_STREQ(png->GetDriver()->GetDescription(), "PNG");
  EXPECT_EQ(std::max(png->GetRasterXSize(), png->GetRasterYSize()), 300);
  ASSERT_EQ(png->GetRasterCount(), 4);
  EXPECT_EQ(png->GetRasterBand(1)->GetRasterDataType(), GDT_Byte);
  EXPECT_EQ(png->GetRasterBand(4)->GetColorInterpretation(), GCI_AlphaBand);
}

}  // namespace
