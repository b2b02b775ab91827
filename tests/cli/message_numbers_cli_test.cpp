// Numbers in the messages of plan, tile jobs, merge and the read stage: thousands separated, as in
// every other message.
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

// The plan's rim line, the tile jobs' refusal of a tile the plan lacks, and merge's summary.
TEST(MessageNumbersCli, PlanTileAndMergeGroupTheirCounts) {
  const std::string dir = folder_with_sample("message_numbers_cli_merge");
  // tincdt plan sample.las --tile-size 20 --buffer 10 -o plan.json
  const ShellRun plan = run_tincdt(dir, "plan sample.las --tile-size 20 --buffer 10 -o plan.json");
  EXPECT_EQ(plan.exit_code, 0) << plan;
  EXPECT_TRUE(has(plan, "rim: 2,139 points within")) << plan;
  EXPECT_TRUE(has(plan, "wrote plan.json: 48 tiles of 20 (buffer 10)")) << plan;
  // tincdt --plan plan.json --tile 99999 -o x.ply
  const ShellRun missing = run_tincdt(dir, "--plan plan.json --tile 99999 -o x.ply");
  EXPECT_EQ(missing.exit_code, 1) << missing;
  EXPECT_TRUE(has(missing, "plan.json: no tile 99,999: the plan has tiles 0 to 47")) << missing;
  std::string tiles;
  for (int i = 0; i < 48; ++i) {
    const std::string number = std::to_string(i);
    std::string tile = "t";
    tile.append(number).append(".ply");
    std::string args = "--plan plan.json --tile ";
    args.append(number).append(" -o ").append(tile).append(" -q");
    expect_success(dir, args);
    tiles.append(" ").append(tile);
  }
  // tincdt merge t0.ply ... t47.ply -o m.ply
  const ShellRun merged = run_tincdt(dir, "merge" + tiles.append(" -o m.ply"));
  EXPECT_EQ(merged.exit_code, 0) << merged;
  EXPECT_TRUE(has(merged, "merged 48 tiles: 4,156 vertices, 8,306 triangles, 924 seam edges"))
      << merged;
}

}  // namespace
}  // namespace tincdt::test
