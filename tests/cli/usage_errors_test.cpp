// The product options' usage errors, one table: each row runs the sample with the row's options
// and expects exit 2, a message naming the option, and no file left behind.

#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace {

const std::pair<std::string, std::string> kUsageErrors[] = {
    // DEM
    {"-o t.gpkg --dem d.tif", "--resolution"},
    {"-o t.gpkg --resolution 1", "--dem"},
    {"-o t.gpkg --dem d.tif --resolution 0", "--resolution"},
    {"-o t.gpkg --dem d.tif --resolution 1 --dem-extent 10 0 5 5", "--dem-extent"},
    {"-o t.gpkg --dem d.tif --resolution 1 --dem-nodata x", "--dem-nodata"},
    // contour lines
    {"-o t.gpkg --contour-lines c.gpkg", "--interval"},
    {"-o t.gpkg --interval 2", "--contour-lines"},
    {"-o t.gpkg --contour-lines c.gpkg --interval -2", "--interval"},
    {"-o t.ply --contour-lines c.gpkg --levels 1490 --interval 2", "--levels and --interval"},
    {"-o t.ply --contour-lines c.gpkg --levels 1490 --base 1", "--base"},
    {"-o t.ply --contour-lines c.gpkg --levels 1490,x", "'x' is not a number"},
    {"-o t.ply --contour-lines c.gpkg --levels 1490,", "is not a number"},
    {"-o t.ply --levels 1490", "need --contour-lines"},
    {"-o t.ply --contour-field h", "need --contour-lines"},
    {"-o t.ply --contour-lines c.gpkg --interval 2 --contour-field ''", "--contour-field"},
    // preview
    {"-o t.ply --preview p.jpg", "--preview writes a PNG"},
    {"-o t.ply --preview-size 200", "--preview-size needs --preview"},
    {"-o t.ply --preview p.png --preview-size 1", "--preview-size"},
    {"-o t.ply --preview p.png --preview-size 99999", "--preview-size"},
    // coordinates
    {"-o t.gpkg --offset auto", "--offset"},
    {"-o t.ply --offset 1e308,0,0", "within +-1e15"},
    {"-o t.ply --offset 0,0,nan", "--offset"},
};

TEST(UsageErrors, ProductOptions) {
  const std::string dir = tincdt::test::scratch_dir("usage_errors");
  tincdt::test::expect_usage_errors(dir, "'" TINCDT_SOURCE_DIR "/data/sample.las'", kUsageErrors);
}

}  // namespace
