// glTF (GLB) TINs from the command line: `-o t.glb` and `-f glb`, read back and compared with the
// run's --stats, with --offset; and the Khronos glTF validator on the sample data and on the
// shared pair_topography cloud with its contours (skipped without the validator or the data).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "core/json.hpp"
#include "support/files.hpp"
#include "support/gltf_files.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"
#include "support/web_tools.hpp"

namespace {

namespace fs = std::filesystem;
using tincdt::test::member;
using tincdt::test::number_at;

using Outcome = tincdt::test::ShellRun;

Outcome run(const std::string& dir, const std::string& args) {
  return tincdt::test::run_tincdt(dir, args);
}

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";
const std::string kContours = std::string(TINCDT_SOURCE_DIR) + "/data/sample_contours.shp";

// The GLB at PATH holds the vertices, triangles and constrained edges that STATS counts.
void expect_counts_of_stats(const std::string& path, const std::string& stats) {
  const tincdt::json::Value s = tincdt::json::parse(tincdt::test::slurp(stats), stats);
  const tincdt::test::GlbFile g = tincdt::test::read_glb(tincdt::test::slurp(path));
  EXPECT_EQ(number_at(g.json, {"accessors", "0", "count"}), number_at(s, {"vertices"}));
  EXPECT_EQ(number_at(g.json, {"accessors", "2", "count"}), 3 * number_at(s, {"triangles"}));
  EXPECT_EQ(number_at(g.json, {"accessors", "3", "count"}), 2 * number_at(s, {"constraints"}));
}

TEST(GltfCli, SampleWithContoursToGlb) {
  const std::string dir = tincdt::test::scratch_dir("gltf_cli");
  const Outcome r =
      run(dir, "'" + kSample + "' --contours '" + kContours + "' -o t.glb --stats s.json");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(tincdt::test::names_in(dir), (std::set<std::string>{"s.json", "t.glb"}));
  expect_counts_of_stats(dir + "/t.glb", dir + "/s.json");
  const tincdt::test::GlbFile g = tincdt::test::read_glb(tincdt::test::slurp(dir + "/t.glb"));
  EXPECT_EQ(member(g.json, {"asset", "extras", "crs"})->string(), "EPSG:32632");
}

TEST(GltfCli, FormatOptionAndOffset) {
  const std::string dir = tincdt::test::scratch_dir("gltf_cli");
  const Outcome r = run(dir, "'" + kSample + "' -o t.data -f glb --offset auto");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const tincdt::test::GlbFile g = tincdt::test::read_glb(tincdt::test::slurp(dir + "/t.data"));
  // --offset auto: the minimum corner rounded down to 1000, recorded; the node near the origin.
  const double ox = number_at(g.json, {"asset", "extras", "offset", "0"});
  EXPECT_GT(ox, 0);
  EXPECT_EQ(std::fmod(ox, 1000), 0);
  EXPECT_LT(std::fabs(number_at(g.json, {"nodes", "0", "translation", "0"})), 2000);
}

TEST(GltfCli, SampleGlbPassesTheKhronosValidator) {
  TINCDT_REQUIRE_WEB_TOOL("gltf-validator");
  const std::string dir = tincdt::test::scratch_dir("gltf_cli");
  const Outcome r = run(dir, "'" + kSample + "' --contours '" + kContours + "' -o t.glb");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  const tincdt::test::GltfReport v = tincdt::test::validate_gltf(dir + "/t.glb");
  EXPECT_EQ(v.errors, 0) << v.text;
  EXPECT_EQ(v.warnings, 0) << v.text;
}

TEST(GltfCli, PairTopographyWithContoursPassesTheKhronosValidator) {
  TINCDT_REQUIRE_SHARED_DATA("pair_topography");
  TINCDT_REQUIRE_WEB_TOOL("gltf-validator");
  const std::string data = tincdt::test::shared_data();
  const std::string dir = tincdt::test::scratch_dir("gltf_cli");
  const Outcome r = run(dir, "'" + data + "/las/Topography.las' --keep-class 2 --contours '" +
                                 data + "/pair_topography/Topography_contours_1m_3d.shp' " +
                                 "-o topo.glb --stats s.json");
  ASSERT_EQ(r.exit_code, 0) << r.messages;
  expect_counts_of_stats(dir + "/topo.glb", dir + "/s.json");
  const tincdt::test::GltfReport v = tincdt::test::validate_gltf(dir + "/topo.glb");
  EXPECT_EQ(v.errors, 0) << v.text;
  EXPECT_EQ(v.warnings, 0) << v.text;
}

}  // namespace
