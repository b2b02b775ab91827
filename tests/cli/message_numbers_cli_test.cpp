// Numbers in the messages of plan, tile jobs and the read stage: thousands separated, as in every
// other message.
#include <gtest/gtest.h>

#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

std::string folder_with_sample(const std::string& name) {
  const std::string dir = scratch_dir(name);
  spit(dir + "/sample.las", slurp(kSample));
  return dir;
}

TEST(MessageNumbersCli, PlanGroupsTheTileCountItRefuses) {
  const std::string dir = folder_with_sample("message_numbers_cli_plan");
  // tincdt plan sample.las --tile-size 0.01 --buffer 1 -o p.json
  const ShellRun r = run_tincdt(dir, "plan sample.las --tile-size 0.01 --buffer 1 -o p.json");
  EXPECT_EQ(r.exit_code, 2) << r;
  EXPECT_TRUE(has(r,
                  "--tile-size 0.01 makes about 192,068,006 tiles over the data (at most "
                  "10,000,000)"))
      << r;
}

TEST(MessageNumbersCli, ATileJobGroupsItsTriangleCounts) {
  const std::string dir = folder_with_sample("message_numbers_cli_tile");
  expect_success(dir, "plan sample.las --tile-size 200 --buffer 20 -o plan.json");
  // tincdt --plan plan.json --tile 0 -o t0.ply
  const ShellRun r = run_tincdt(dir, "--plan plan.json --tile 0 -o t0.ply");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "tile 0: 1,169 triangles owned, 1,261 checked final: 1,238 with")) << r;
}

TEST(MessageNumbersCli, TheReadStageGroupsItsPointCounts) {
  const std::string dir = folder_with_sample("message_numbers_cli_read");
  // tincdt -v sample.las -o t.ply
  const ShellRun r = run_tincdt(dir, "-v sample.las -o t.ply");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "sample.las: las 1.2 pdrf 1, 4,160 points, 4,160 kept")) << r;
}

}  // namespace
}  // namespace tincdt::test
