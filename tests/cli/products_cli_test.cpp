// The product options on the command line: usage errors (exit 2, one line naming the option)
// before anything is read, and a run writing every product from the project's sample data.
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

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

TEST(ProductsCli, EveryProductInOneRun) {
  const std::string dir = tincdt::test::scratch_dir("products_cli");
  const Outcome r = run(dir, "'" + kSample +
                                 "' -o surface.data -f landxml --dem dem.tif --resolution 2 --tap "
                                 "--dem-type Float64 --contour-lines lines.shp --interval 2.5 "
                                 "--base 0.5 --stats s.json");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(tincdt::test::names_in(dir),
            (std::set<std::string>{"dem.tif", "lines.dbf", "lines.prj", "lines.shp", "lines.shx",
                                   "s.json", "surface.data"}));
  EXPECT_NE(tincdt::test::slurp(dir + "/surface.data").find("<Definition surfType=\"TIN\">"),
            std::string::npos);
  EXPECT_NE(r.messages.find("wrote dem.tif (COG Float64"), std::string::npos) << r.messages;
  EXPECT_NE(r.messages.find("wrote lines.shp (ESRI Shapefile"), std::string::npos) << r.messages;
}

}  // namespace
