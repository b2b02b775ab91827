// A DEM grid that cannot be made is refused as soon as the inputs are read: no triangulation, no
// TIN written, no file left.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

// tincdt ARGS (with --progress: each stage logs a line) in a folder holding sample.las; checks
// that it fails (exit 1) after the read stage and before the Delaunay stage, leaving only the
// input.
ShellRun refused_after_reading(const std::string& name, const std::string& args) {
  const std::string dir = scratch_dir(name);
  spit(dir + "/sample.las", slurp(kSample));
  const ShellRun r = run_tincdt(dir, args + " --progress");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "[1/4] reading the inputs")) << r;
  EXPECT_FALSE(has(r, "triangulating")) << r;
  EXPECT_FALSE(has(r, "writing the TIN")) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"sample.las"});
  return r;
}

TEST(DemGridEarlyCli, ATooFineResolutionIsRefusedBeforeTriangulating) {
  // tincdt sample.las -o t.ply --dem d.tif --resolution 1e-7 --progress
  const ShellRun r = refused_after_reading("dem_grid_early_cli_fine",
                                           "sample.las -o t.ply --dem d.tif --resolution 1e-7");
  EXPECT_TRUE(has(r,
                  "d.tif: the DEM resolution 1e-07 is too fine for coordinates of magnitude "
                  "5,190,420"))
      << r;
}

TEST(DemGridEarlyCli, AGridLargerThanMemoryIsRefusedBeforeTriangulating) {
  // tincdt sample.las -o t.ply --dem d.tif --resolution 0.0001 --progress
  const ShellRun r = refused_after_reading("dem_grid_early_cli_memory",
                                           "sample.las -o t.ply --dem d.tif --resolution 0.0001");
  EXPECT_TRUE(has(r, "1,600,000 x 1,200,000 cells")) << r;
}

TEST(DemGridEarlyCli, ATooCoarseResolutionIsRefusedBeforeTriangulating) {
  // tincdt sample.las -o t.ply --dem d.tif --resolution 1000 --progress
  const ShellRun r = refused_after_reading("dem_grid_early_cli_coarse",
                                           "sample.las -o t.ply --dem d.tif --resolution 1000");
  EXPECT_TRUE(has(r, "gives 1 x 1 cells; a DEM needs at least 2 x 2")) << r;
}

}  // namespace
}  // namespace tincdt::test
