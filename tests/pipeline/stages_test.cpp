// The stage table and its loop, and the one place where options are checked together.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "pipeline/build.hpp"
#include "pipeline/stage.hpp"
#include "support/files.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using pipeline::BuildOptions;

TEST(Stages, OneTableInTheDocumentedOrder) {
  std::vector<std::string> names;
  for (const pipeline::Stage* s : pipeline::stages()) {
    names.emplace_back(s->name);
    EXPECT_NE(s->wanted, nullptr) << s->name;
    EXPECT_NE(s->run, nullptr) << s->name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"read",
                                             "web_terrain_crs",
                                             "delaunay",
                                             "constraints",
                                             "surface",
                                             "simplify",
                                             "flats",
                                             "replace",
                                             "trim",
                                             "clip",
                                             "erase",
                                             "validate",
                                             "quality",
                                             "write",
                                             "dem",
                                             "web_terrain",
                                             "contour_lines",
                                             "preview",
                                             "constraint_lines",
                                             "diagnostics",
                                             "stats"}));
}

BuildOptions options_with(const std::string& dir) {
  std::string xyz;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      xyz += std::to_string(i + 0.01 * j) + " " + std::to_string(j + 0.013 * i) + " 1\n";
  test::spit(fs::path(dir) / "in.xyz", xyz);
  BuildOptions o;
  o.inputs = {(fs::path(dir) / "in.xyz").string()};
  o.output = (fs::path(dir) / "t.ply").string();
  return o;
}

// The loop reports each wanted stage to the progress callback at 0 and at 1, in order, lists it
// in the report with its time, and skips the others; "commit" comes last.
TEST(Stages, TheLoopReportsEveryWantedStage) {
  const std::string dir = test::scratch_dir("stages");
  BuildOptions o = options_with(dir);
  o.stats_path = (fs::path(dir) / "s.json").string();
  o.validate = true;
  std::vector<std::pair<std::string, double>> seen;
  const ProgressFn progress = [&](std::string_view stage, double f) {
    seen.emplace_back(stage, f);
    return true;
  };
  const pipeline::BuildReport r = pipeline::build(o, &progress);
  const std::vector<std::string> ran = {"read",    "delaunay", "validate",
                                        "quality", "write",    "stats"};
  std::vector<std::string> listed;
  for (const auto& s : r.stages) {
    listed.push_back(s.name);
    EXPECT_GE(s.seconds, 0.0);
  }
  EXPECT_EQ(listed, ran);
  // Each stage's events are together, in order, from 0 to 1; then the outputs are committed.
  std::vector<std::string> order;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (!order.empty() && order.back() == seen[i].first) continue;
    order.push_back(seen[i].first);
    EXPECT_EQ(seen[i].second, 0.0) << seen[i].first;
    if (i > 0) {
      EXPECT_EQ(seen[i - 1].second, 1.0) << seen[i - 1].first;
    }
  }
  std::vector<std::string> expected = ran;
  expected.push_back("commit");
  EXPECT_EQ(order, expected);
  EXPECT_GT(r.timings_s.quality, 0.0);
  EXPECT_GE(r.timings_s.total, r.timings_s.read + r.timings_s.delaunay + r.timings_s.write);
  ASSERT_EQ(r.outputs.size(), 1u);  // the TIN; the stats document does not list itself
  EXPECT_EQ(r.outputs[0].kind, "tin");
  EXPECT_EQ(r.outputs[0].bytes, fs::file_size(o.output));
  const std::string json = test::slurp(o.stats_path);
  EXPECT_NE(json.find("\"stages\": ["), std::string::npos) << json;
  EXPECT_NE(json.find("\"quality\": "), std::string::npos) << json;
}

TEST(Stages, UnknownTimingKeysGoToTheirOwnEntry) {
  pipeline::BuildReport r;
  r.timings_s.add("terrain", 1.0);
  r.timings_s.add("terrain", 0.5);
  r.timings_s.add("dem", 2.0);
  r.timings_s.add("dem", 0.25);
  EXPECT_EQ(r.timings_s.terrain, 1.5);
  ASSERT_EQ(r.timings_s.more.size(), 1u);
  EXPECT_EQ(r.timings_s.more[0].second, 2.25);
  EXPECT_NE(r.to_json().find("\"dem\": 2.25"), std::string::npos) << r.to_json();
}

// A broken invariant says so, unlike bad input.
TEST(Errors, InternalErrorsAskForAReport) {
  const InternalError e("the TIN failed validation: twin");
  EXPECT_EQ(std::string(e.what()).rfind("internal error, please report: ", 0), 0u) << e.what();
  EXPECT_EQ(dynamic_cast<const InputError*>(static_cast<const Error*>(&e)), nullptr);
}

// ---- check_options ----------------------------------------------------------------------------

BuildOptions minimal() {
  BuildOptions o;
  o.inputs = {"a.xyz"};
  o.output = "t.ply";
  return o;
}

std::string usage_error(const BuildOptions& o) {
  try {
    pipeline::check_options(o);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "no usage error";
}

TEST(CheckOptions, EachRuleNamesItsOptions) {
  const std::vector<std::pair<void (*)(BuildOptions&), std::string>> cases = {
      {[](BuildOptions& o) { o.inputs.clear(); }, "no input"},
      {[](BuildOptions& o) {
         o.inputs = {"-", "-"};
       },
       "standard input"},
      {[](BuildOptions& o) {
         o.filter.keep_classes = {2, 6};
         o.filter.drop_classes = {6};
       },
       "class 6 is in both --keep-class and --drop-class"},
      {[](BuildOptions& o) { o.filter.first_return_only = o.filter.last_return_only = true; },
       "--first-only and --last-only"},
      {[](BuildOptions& o) {
         o.lines.z_field = "Z";
         o.lines.z_from_m = true;
       },
       "--z-field and --z-from-m"},
      {[](BuildOptions& o) { o.fix_flats = true; }, "--fix-flats needs --contours"},
      {[](BuildOptions& o) { o.max_edge = -1; }, "--max-edge"},
      {[](BuildOptions& o) { o.output.clear(); }, "-o"},
      {[](BuildOptions& o) { o.output = "t.dwg"; }, "t.dwg"},
      {[](BuildOptions& o) { o.target_srs = "EPSG:4326"; }, "--allow-geographic"},
      {[](BuildOptions& o) { o.write.offset.x = std::numeric_limits<double>::infinity(); },
       "--offset"},
      {[](BuildOptions& o) { o.constraints_out = "c.txt"; }, "--constraints-out"},
      {[](BuildOptions& o) { o.diagnostics = "d.geojson"; }, "--diagnostics"},
      {[](BuildOptions& o) { o.assign_srs = "EPSG:999999"; }, "--a-srs"},
      {[](BuildOptions& o) {
         o.output = "t.geojson";
         o.target_srs = "not a CRS";
       },
       "--t-srs"},
  };
  for (const auto& [change, message] : cases) {
    BuildOptions o = minimal();
    change(o);
    const std::string e = usage_error(o);
    EXPECT_NE(e.find(message), std::string::npos) << message << ": " << e;
  }
}

TEST(CheckOptions, ResolvesFormatAndCrsAndWarnsAboutIneffectiveOptions) {
  BuildOptions o = minimal();
  EXPECT_EQ(usage_error(o), "no usage error");
  o.output = "t.json";
  o.assign_srs = "EPSG:32633";
  o.target_srs = "EPSG:4326";
  o.allow_geographic = true;
  o.write.ply_ascii = true;
  pipeline::CheckedOptions c = pipeline::check_options(o);
  EXPECT_EQ(c.format, io::TinFormat::geojson);
  EXPECT_TRUE(io::same_crs(c.assign_crs_wkt, io::crs_from_user("EPSG:32633")));
  EXPECT_TRUE(io::same_crs(c.target_crs_wkt, io::crs_from_user("EPSG:4326")));
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("--ply-ascii is ignored"), std::string::npos);
  o.write.format = io::TinFormat::obj;
  o.target_srs.clear();
  o.allow_geographic = false;
  o.output = "mesh.txt";
  c = pipeline::check_options(o);
  EXPECT_EQ(c.format, io::TinFormat::obj);
}

// build() checks the options before it touches any file.
TEST(CheckOptions, BuildRefusesBeforeReading) {
  const std::string dir = test::scratch_dir("stages");
  BuildOptions o = minimal();
  o.inputs = {(fs::path(dir) / "missing.xyz").string()};
  o.output = (fs::path(dir) / "t.ply").string();
  o.fix_flats = true;
  EXPECT_THROW(pipeline::build(o), UsageError);
  EXPECT_TRUE(test::names_in(dir).empty());
}

}  // namespace
