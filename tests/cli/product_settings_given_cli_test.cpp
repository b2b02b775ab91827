// The settings of --preview, --dem and --contour-lines without their product: refused whenever
// given on the command line, even at their default value; and at their default with their product,
// the same output as when left out.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

// The sample, quoted for the shell (built in steps: GCC 12's -Wrestrict misfires on "'" + s).
std::string sample() {
  std::string q = "'";
  q += TINCDT_SOURCE_DIR;
  q += "/data/sample.las'";
  return q;
}

TEST(ProductSettingsGivenCli, RefusedWithoutTheirProductAtAnyValue) {
  const std::string dir = scratch_dir("product_settings_given_cli");
  const std::pair<std::string, std::string> cases[] = {
      // tincdt data/sample.las -o x.ply --preview-size 1024 (the default)
      {"--preview-size 1024", "--preview-size needs --preview"},
      {"--preview-size 200", "--preview-size needs --preview"},
      {"--dem-nodata -9999", "need --dem"},
      {"--dem-nodata 0", "need --dem"},
      {"--dem-type float32", "need --dem"},
      {"--dem-type float64", "need --dem"},
      {"--resolution 1", "need --dem"},
      {"--contour-field elev", "need --contour-lines"},
      {"--contour-field h", "need --contour-lines"},
      {"--base 0", "need --contour-lines"},
      {"--base 5", "need --contour-lines"},
      {"--interval 5", "need --contour-lines"},
      // --base goes with --interval only, whatever its value.
      {"--contour-lines c.gpkg --levels 1500 --base 0", "--base goes with --interval"},
  };
  expect_usage_errors(dir, sample() + " -o x.ply", cases);
}

TEST(ProductSettingsGivenCli, DefaultsGivenWithTheirProductChangeNothing) {
  const std::string dir = scratch_dir("product_settings_given_cli_defaults");
  // tincdt data/sample.las --dem a.asc --resolution 5 --contour-lines a.geojson --interval 5
  //   --preview a.png
  expect_success(dir, sample() +
                          " --dem a.asc --resolution 5 --contour-lines a.geojson --interval 5"
                          " --preview a.png");
  // tincdt data/sample.las --dem b.asc --resolution 5 --dem-nodata -9999 --dem-type float32
  //   --contour-lines b.geojson --interval 5 --base 0 --contour-field elev --preview b.png
  //   --preview-size 1024
  expect_success(dir, sample() +
                          " --dem b.asc --resolution 5 --dem-nodata -9999 --dem-type float32"
                          " --contour-lines b.geojson --interval 5 --base 0 --contour-field elev"
                          " --preview b.png --preview-size 1024");
  EXPECT_EQ(slurp(dir + "/a.asc"), slurp(dir + "/b.asc"));
  EXPECT_EQ(slurp(dir + "/a.png"), slurp(dir + "/b.png"));
  EXPECT_FALSE(slurp(dir + "/a.geojson").empty());
  EXPECT_EQ(slurp(dir + "/a.geojson"), slurp(dir + "/b.geojson"));
}

}  // namespace
}  // namespace tincdt::test
