// The simplify stage in a whole job: pipeline::build with --max-error on the shared
// pair_topography (LAS ground points and their contours), and the tincdt binary's options, log
// line and --stats block. Skipped without the shared data.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/vector/line_reader.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::simplify {
namespace {

namespace fs = std::filesystem;

const std::string kData = ::tincdt::test::shared_data();
const std::string kLas = kData + "/las/Topography.las";
const std::string kContours = kData + "/pair_topography/Topography_contours_1m_3d.shp";

class SimplifyStage : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kLas) || !fs::exists(kContours))
      GTEST_SKIP() << "shared data not found: " << kLas << ", " << kContours;
    dir_ = test::scratch_dir("simplify");  // per test: ctest runs them side by side
  }
  pipeline::BuildOptions options(const std::string& out) const {
    pipeline::BuildOptions o;
    o.inputs = {kLas};
    o.filter.keep_classes = {2};
    o.contours = {kContours};
    o.validate = true;  // every contour segment joined end to end by constrained edges
    o.output = (dir_ / out).string();
    o.write.format = io::TinFormat::obj;
    return o;
  }
  fs::path dir_;
};

TEST_F(SimplifyStage, KeepsEveryContourVertexAndSegmentWithFewerVertices) {
  const pipeline::BuildReport full = pipeline::build(options("full.obj"));
  pipeline::BuildOptions o = options("simple.obj");
  o.max_error = 0.1;
  o.constraints_out = (dir_ / "lines.geojson").string();
  const pipeline::BuildReport r = pipeline::build(o);

  ASSERT_TRUE(r.simplify.ran);
  EXPECT_EQ(r.simplify.points, full.vertices);
  EXPECT_EQ(r.simplify.vertices, r.vertices);
  EXPECT_LT(r.vertices, full.vertices);
  EXPECT_GT(r.vertices, r.line_vertices / 2);
  EXPECT_LE(r.simplify.max_error, 0.1);
  EXPECT_GT(r.simplify.rmse, 0);
  EXPECT_EQ(r.constraints, full.constraints);  // every constrained edge is still one
  bool timed = false;
  for (const auto& [key, seconds] : r.timings_s.more) timed |= key == "simplify" && seconds > 0;
  EXPECT_TRUE(timed);

  // Every contour vertex is a vertex of the written TIN.
  const test::MeshFile mesh = test::read_mesh(o.output);
  std::set<std::pair<double, double>> written;
  for (const auto& v : mesh.v) written.insert({v[0], v[1]});
  io::LineData lines;
  io::read_lines(kContours, {}, lines);
  std::size_t missing = 0;
  for (const Point3& p : lines.vertices) missing += !written.count({p.x, p.y});
  EXPECT_EQ(missing, 0u);
  // Every written point is within the tolerance of the full TIN's own heights: both are vertices.
  EXPECT_EQ(mesh.v.size(), r.vertices);
}

TEST_F(SimplifyStage, MaxVerticesAloneStopsThere) {
  pipeline::BuildOptions o = options("budget.obj");
  o.max_vertices = 9400;  // a little more than the contour vertices
  const pipeline::BuildReport r = pipeline::build(o);
  ASSERT_TRUE(r.simplify.ran);
  EXPECT_LE(r.vertices, 9400u);
  EXPECT_TRUE(r.simplify.stopped_at_max_vertices);
  EXPECT_GT(r.simplify.max_error, 0);
}

TEST_F(SimplifyStage, MaxVerticesBelowTheLinesKeepsTheLinesAndWarns) {
  pipeline::BuildOptions o = options("lines.obj");
  o.max_vertices = 100;
  std::string warnings;
  const pipeline::BuildReport r =
      pipeline::build(o, nullptr, [&](int level, const std::string& message) {
        if (level == pipeline::log_warn) warnings += message + "\n";
      });
  EXPECT_GT(r.vertices, r.line_vertices / 2);  // every contour vertex, far above 100
  EXPECT_NE(warnings.find("--max-vertices 100"), std::string::npos) << warnings;
}

// The binary: options parsed, the summary line, the stats block.
TEST_F(SimplifyStage, CommandLine) {
  const fs::path out = dir_ / "cli.ply", stats = dir_ / "cli.json", log = dir_ / "cli.log";
  const std::string command = std::string(TINCDT_EXE) + " '" + kLas +
                              "' --keep-class 2 --contours '" + kContours +
                              "' --max-error 0.25 --validate -o '" + out.string() + "' --stats '" +
                              stats.string() + "' > '" + log.string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << test::slurp(log);
  const std::string text = test::slurp(log);
  EXPECT_TRUE(std::regex_search(
      text, std::regex(R"(simplify: kept [0-9.]+% of [0-9,]+ points, max error 0\.2[0-9]{2} m, )"
                       R"(RMSE 0\.[0-9]{3} m)")))
      << text;
  const std::string json = test::slurp(stats);
  EXPECT_TRUE(std::regex_search(json, std::regex(R"("simplify": \{\s*"points": [0-9]+,\s*)"
                                                 R"("vertices": [0-9]+,\s*"max_error": 0\.2)")))
      << json;
  EXPECT_TRUE(std::regex_search(json, std::regex(R"("timings_s": \{[^}]*"simplify": )"))) << json;

  const std::string bad = std::string(TINCDT_EXE) + " '" + kLas + "' --max-error -1 -o '" +
                          (dir_ / "bad.ply").string() + "' > '" + log.string() + "' 2>&1";
  const int status = std::system(bad.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2) << test::slurp(log);
  EXPECT_NE(test::slurp(log).find("--max-error"), std::string::npos) << test::slurp(log);
}

}  // namespace
}  // namespace tincdt::simplify
