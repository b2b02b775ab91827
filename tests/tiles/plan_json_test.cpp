// The plan as a JSON file (tiles/plan.hpp): the layout scripts grep, numbers that read back bit
// for bit, file names kept as their bytes, and errors that say where the text is not JSON.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "support/files.hpp"
#include "tiles/plan.hpp"

namespace {

namespace fs = std::filesystem;
using tincdt::InputError;
using tincdt::tiles::PlanInput;
using tincdt::tiles::PlanTile;
using tincdt::tiles::TilePlan;

TilePlan small_plan() {
  TilePlan p;
  p.tile_size = 50;
  p.buffer = 20;
  p.filter.keep_classes = {2, 9};
  p.filter.first_return_only = true;
  p.lines.layer = "contours";
  p.lines.z_field = "elev";
  p.extent = {500000.5, 4000000, 500100, 4000100.25};
  PlanInput in;
  in.path = "a b/\xff.las";
  in.kind = "points";
  in.format = "las 1.2 pdrf 3";
  in.bytes = 1234;
  in.fingerprint = "fnv1a64:0123456789abcdef";
  in.count = 10;
  in.bounds = p.extent;
  in.tolerance = 0.1;
  p.inputs.push_back(in);
  p.hull = {{500000.5, 4000000}, {500100, 4000000}, {500100, 4000100.25}};
  p.tiles.push_back(PlanTile{0, 10000, 80000, {0}});
  return p;
}

constexpr const char* kSmallPlan =
    "{\n"
    "  \"tincdt_plan\": 1,\n"
    "  \"tile_size\": 50,\n"
    "  \"buffer\": 20,\n"
    "  \"filter\": {\"keep_classes\": [2, 9], \"drop_classes\": [], \"first_only\": true, "
    "\"last_only\": false},\n"
    "  \"lines\": {\"layer\": \"contours\", \"z_field\": \"elev\", \"z_from_m\": false},\n"
    "  \"extent\": [500000.5, 4000000, 500100, 4000100.25],\n"
    "  \"inputs\": [\n"
    "    {\"index\": 0, \"path\": \"a b/\xff.las\", \"kind\": \"points\", \"format\": \"las 1.2 "
    "pdrf 3\", \"bytes\": 1234, \"fingerprint\": \"fnv1a64:0123456789abcdef\", \"count\": 10, "
    "\"bounds\": [500000.5, 4000000, 500100, 4000100.25], \"tolerance\": 0.10000000000000001}\n"
    "  ],\n"
    "  \"hull\": [[500000.5, 4000000], [500100, 4000000], [500100, 4000100.25]],\n"
    "  \"rim\": null,\n"
    "  \"tile_count\": 1,\n"
    "  \"tiles\": [\n"
    "    {\"index\": 0, \"col\": 10000, \"row\": 80000, \"box\": [500000, 4000000, 500050, "
    "4000050], \"inputs\": [0]}\n"
    "  ]\n"
    "}\n";

TEST(PlanJson, WrittenAsScriptsReadIt) {
  const fs::path dir = tincdt::test::scratch_dir("plan_json");
  const std::string path = (dir / "plan.json").string();
  TilePlan plan = small_plan();
  tincdt::tiles::write_plan(plan, {}, path, false);
  EXPECT_EQ(tincdt::test::slurp(path), kSmallPlan);
}

TEST(PlanJson, ReadBackAsWritten) {
  const fs::path dir = tincdt::test::scratch_dir("plan_json");
  const std::string path = (dir / "plan.json").string();
  tincdt::test::spit(path, kSmallPlan);
  TilePlan read = tincdt::tiles::read_plan(path);
  const TilePlan expected = small_plan();
  ASSERT_EQ(read.inputs.size(), 1u);
  EXPECT_EQ(read.inputs[0].path, expected.inputs[0].path);
  EXPECT_EQ(read.inputs[0].tolerance, 0.1);
  EXPECT_EQ(read.extent.max_y, 4000100.25);
  EXPECT_EQ(read.filter.keep_classes, expected.filter.keep_classes);
  EXPECT_TRUE(read.filter.first_return_only);
  ASSERT_EQ(read.tiles.size(), 1u);
  EXPECT_EQ(read.tiles[0].row, 80000);
  EXPECT_EQ(read.hull.size(), 3u);
  tincdt::tiles::write_plan(read, {}, path, true);
  EXPECT_EQ(tincdt::test::slurp(path), kSmallPlan);
}

TEST(PlanJson, TextThatIsNotJsonIsRefusedWithWhere) {
  const fs::path dir = tincdt::test::scratch_dir("plan_json");
  const std::string path = (dir / "plan.json").string();
  tincdt::test::spit(path, "{\n  \"tincdt_plan\": 1,\n  \"tile_size\": 50,,\n}\n");
  try {
    tincdt::tiles::read_plan(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": line 3, column 19: not JSON: expected a member name");
  }
}

}  // namespace
