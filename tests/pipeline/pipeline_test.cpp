// pipeline::build end to end on XYZ files written by the tests: counts, the written mesh against
// an independent re-triangulation, duplicates, offsets, CRS handling, progress, stats JSON.
#include <cpl_json.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "pipeline/build.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using test::names_in;
using test::slurp;
using test::spit;

std::string xyz_text(const std::vector<Point3>& points) {
  std::string s;
  char line[128];
  for (const Point3& p : points) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
    s += line;
  }
  return s;
}

// The four corners of [x0, x0 + 100]^2 and an m x m grid strictly inside, jittered so that no
// four points are cocircular and no three collinear: n = m^2 + 4 points, hull h = 4, and any
// triangulation has 2n - 2 - h triangles.
std::vector<Point3> square_with_jittered_grid(int m, double x0, double y0) {
  std::vector<Point3> pts = {
      {x0, y0, 0}, {x0 + 100, y0, 1}, {x0 + 100, y0 + 100, 2}, {x0, y0 + 100, 3}};
  std::uint32_t state = 987654321u;
  const auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return (static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5) * 0.8;
  };
  const double step = 100.0 / (m + 1);
  for (int i = 1; i <= m; ++i)
    for (int j = 1; j <= m; ++j)
      pts.push_back({x0 + i * step + jitter(), y0 + j * step + jitter(), 10.0 + i * 0.5 + j});
  return pts;
}

struct Obj {
  std::vector<Point3> vertices;
  std::vector<std::array<std::size_t, 3>> faces;  // 0-based
};

Obj read_obj(const fs::path& p) {
  const test::MeshFile m = test::read_obj(p);
  Obj obj;
  for (const auto& v : m.v) obj.vertices.push_back({v[0], v[1], v[2]});
  obj.faces = m.f;
  return obj;
}

using Tri = std::array<std::pair<double, double>, 3>;

// Triangles as sorted corner coordinates, so two meshes compare regardless of numbering.
Tri canonical(std::pair<double, double> a, std::pair<double, double> b,
              std::pair<double, double> c) {
  Tri t = {a, b, c};
  std::sort(t.begin(), t.end());
  return t;
}

class Pipeline : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::scratch_dir("pipeline"); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  pipeline::BuildOptions options_for(const std::vector<Point3>& pts, const std::string& out) {
    spit(path("in.xyz"), xyz_text(pts));
    pipeline::BuildOptions o;
    o.inputs = {path("in.xyz")};
    o.output = path(out);
    return o;
  }

  fs::path dir_;
};

TEST_F(Pipeline, JitteredGridCountsAndMeshEqualsRetriangulation) {
  const int m = 30;
  const auto pts = square_with_jittered_grid(m, 0, 0);
  const std::uint64_t n = pts.size(), h = 4;
  auto o = options_for(pts, "tin.obj");
  o.validate = true;
  const pipeline::BuildReport r = pipeline::build(o);

  EXPECT_EQ(r.points_read, n);
  EXPECT_EQ(r.points_kept, n);
  EXPECT_EQ(r.duplicates_merged, 0u);
  EXPECT_EQ(r.vertices, n);
  EXPECT_EQ(r.triangles, 2 * n - 2 - h);
  EXPECT_EQ(r.constraints, 0u);
  EXPECT_EQ(r.steiner_vertices, 0u);
  EXPECT_EQ(r.output, o.output);
  EXPECT_EQ(r.output_format, "obj");
  EXPECT_EQ(r.output_bytes, fs::file_size(o.output));
  EXPECT_GT(r.peak_rss_bytes, 0u);
  EXPECT_GE(r.timings_s.total, r.timings_s.read + r.timings_s.delaunay + r.timings_s.write);
  ASSERT_EQ(r.inputs.size(), 1u);
  EXPECT_EQ(r.inputs[0].format.substr(0, 3), "xyz");

  // The written mesh: same counts, every input point present with its z, CCW faces, and the
  // same triangles as an independent Delaunay triangulation of the written vertices.
  const Obj obj = read_obj(o.output);
  ASSERT_EQ(obj.vertices.size(), n);
  ASSERT_EQ(obj.faces.size(), r.triangles);
  std::map<std::pair<double, double>, double> z_of;
  for (const Point3& v : obj.vertices) z_of[{v.x, v.y}] = v.z;
  for (const Point3& p : pts) {
    ASSERT_EQ(z_of.count({p.x, p.y}), 1u) << p.x << " " << p.y;
    EXPECT_EQ((z_of[{p.x, p.y}]), p.z);
  }
  std::set<Tri> written;
  double area = 0;
  for (const auto& f : obj.faces) {
    const Point3 &a = obj.vertices[f[0]], &b = obj.vertices[f[1]], &c = obj.vertices[f[2]];
    const double cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    EXPECT_GT(cross, 0) << "face not counter-clockwise";
    area += cross / 2;
    written.insert(canonical({a.x, a.y}, {b.x, b.y}, {c.x, c.y}));
  }
  EXPECT_NEAR(area, 100.0 * 100.0, 1e-6);  // the triangles tile the hull

  std::vector<Point3> again = obj.vertices;
  const delaunay::DelaunayResult d = delaunay::triangulate(std::move(again));
  std::set<Tri> reference;
  d.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& t) {
    const Point2 a = d.tin.point(t[0]), b = d.tin.point(t[1]), c = d.tin.point(t[2]);
    reference.insert(canonical({a.x, a.y}, {b.x, b.y}, {c.x, c.y}));
  });
  EXPECT_EQ(written, reference);
  EXPECT_EQ(names_in(dir_), (std::set<std::string>{"in.xyz", "tin.obj"}));
}

TEST_F(Pipeline, EveryFormat) {
  const auto pts = square_with_jittered_grid(10, 0, 0);
  for (const char* name : {"t.obj", "t.ply", "t.geojson", "t.json"}) {
    SCOPED_TRACE(name);
    auto o = options_for(pts, name);
    const auto r = pipeline::build(o);
    EXPECT_EQ(r.triangles, 2 * pts.size() - 6);
    EXPECT_TRUE(fs::is_regular_file(o.output));
  }
}

TEST_F(Pipeline, SeveralInputsAreMerged) {
  const auto pts = square_with_jittered_grid(12, 0, 0);
  const std::vector<Point3> a(pts.begin(), pts.begin() + 70), b(pts.begin() + 70, pts.end());
  spit(path("a.xyz"), xyz_text(a));
  spit(path("b.xyz"), "x y z\n" + xyz_text(b));
  pipeline::BuildOptions o;
  o.inputs = {path("a.xyz"), path("b.xyz")};
  o.output = path("t.ply");
  const auto r = pipeline::build(o);
  EXPECT_EQ(r.points_read, pts.size());
  EXPECT_EQ(r.vertices, pts.size());
  EXPECT_EQ(r.triangles, 2 * pts.size() - 6);
  ASSERT_EQ(r.inputs.size(), 2u);
  EXPECT_EQ(r.inputs[0].points_read, 70u);
  EXPECT_EQ(r.inputs[1].points_read, pts.size() - 70);
}

TEST_F(Pipeline, DuplicatePolicies) {
  std::vector<Point3> pts = square_with_jittered_grid(3, 0, 0);
  pts.push_back({50, 50, 3});
  pts.push_back({50, 50, 1});
  pts.push_back({50, 50, 8});
  const std::map<delaunay::DuplicatePolicy, double> expected = {
      {delaunay::DuplicatePolicy::first, 3},
      {delaunay::DuplicatePolicy::min, 1},
      {delaunay::DuplicatePolicy::max, 8},
      {delaunay::DuplicatePolicy::mean, 4}};
  for (const auto& [policy, z] : expected) {
    auto o = options_for(pts, "t.obj");
    o.on_duplicate = policy;
    o.write.overwrite = true;
    const auto r = pipeline::build(o);
    EXPECT_EQ(r.points_read, pts.size());
    EXPECT_EQ(r.duplicates_merged, 2u);
    EXPECT_EQ(r.vertices, pts.size() - 2);
    bool found = false;
    for (const Point3& v : read_obj(o.output).vertices)
      if (v.x == 50 && v.y == 50) {
        found = true;
        EXPECT_EQ(v.z, z) << static_cast<int>(policy);
      }
    EXPECT_TRUE(found);
  }
}

TEST_F(Pipeline, OffsetAutoRoundsTheMinimumCornerDown) {
  const auto pts = square_with_jittered_grid(5, 273357.14, 5274357.14);
  auto o = options_for(pts, "t.obj");
  o.write.offset_auto = true;
  const auto r = pipeline::build(o);
  EXPECT_EQ(r.offset, (Point3{273000, 5274000, 0}));
  const Obj obj = read_obj(o.output);
  for (const Point3& v : obj.vertices) {
    EXPECT_GE(v.x, 357.0);
    EXPECT_LT(v.x, 458.0);
    EXPECT_GE(v.y, 357.0);
  }
}

TEST_F(Pipeline, NegativeCoordinatesOffsetRoundsDown) {
  const auto pts = square_with_jittered_grid(4, -235434.52, -10.5);
  auto o = options_for(pts, "t.ply");
  o.write.offset_auto = true;
  EXPECT_EQ(pipeline::build(o).offset, (Point3{-236000, -1000, 0}));
}

TEST_F(Pipeline, ExistingOutputFailsBeforeReading) {
  spit(path("t.obj"), "old");
  pipeline::BuildOptions o;
  o.inputs = {path("does_not_exist.xyz")};  // would be an InputError if it were read
  o.output = path("t.obj");
  EXPECT_THROW(pipeline::build(o), OutputError);
  EXPECT_EQ(slurp(path("t.obj")), "old");
}

TEST_F(Pipeline, UnknownFormatFailsBeforeReading) {
  pipeline::BuildOptions o;
  o.inputs = {path("does_not_exist.xyz")};
  o.output = path("t.dwg");
  EXPECT_THROW(pipeline::build(o), UsageError);
}

TEST_F(Pipeline, GeographicTargetCrsNeedsAllowing) {
  auto o = options_for(square_with_jittered_grid(3, 0, 0), "t.ply");
  o.target_srs = "EPSG:4326";
  EXPECT_THROW(pipeline::build(o), UsageError);
  EXPECT_EQ(names_in(dir_), std::set<std::string>{"in.xyz"});
}

TEST_F(Pipeline, EmptyInputNamesTheFile) {
  spit(path("empty.xyz"), "");
  pipeline::BuildOptions o;
  o.inputs = {path("empty.xyz")};
  o.output = path("t.obj");
  try {
    pipeline::build(o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path("empty.xyz")), std::string::npos) << e.what();
  }
  EXPECT_EQ(names_in(dir_), std::set<std::string>{"empty.xyz"});
}

TEST_F(Pipeline, TooFewPointsNamesTheFile) {
  auto o = options_for({{0, 0, 0}, {1, 1, 1}, {0, 0, 5}}, "t.obj");
  try {
    pipeline::build(o);
    FAIL() << "no error";
  } catch (const GeometryError& e) {
    EXPECT_EQ(e.file(), path("in.xyz"));
    EXPECT_NE(std::string(e.what()).find("fewer than 3 distinct points"), std::string::npos);
  }
}

TEST_F(Pipeline, ProgressReportsEveryStage) {
  auto o = options_for(square_with_jittered_grid(40, 0, 0), "t.ply");
  std::map<std::string, std::vector<double>> seen;
  const ProgressFn progress = [&](std::string_view stage, double f) {
    seen[std::string(stage)].push_back(f);
    return true;
  };
  pipeline::build(o, &progress);
  for (const char* stage : {"read", "delaunay", "write"}) {
    ASSERT_EQ(seen.count(stage), 1u) << stage;
    for (double f : seen[stage]) {
      EXPECT_GE(f, 0.0);
      EXPECT_LE(f, 1.0);
    }
    EXPECT_EQ(seen[stage].back(), 1.0) << stage;
  }
}

TEST_F(Pipeline, CancelLeavesNothing) {
  for (const char* at : {"read", "delaunay", "write"}) {
    SCOPED_TRACE(at);
    auto o = options_for(square_with_jittered_grid(40, 0, 0), "t.ply");
    o.stats_path = path("s.json");
    const ProgressFn progress = [&](std::string_view stage, double) { return stage != at; };
    EXPECT_THROW(pipeline::build(o, &progress), Cancelled);
    EXPECT_EQ(names_in(dir_), std::set<std::string>{"in.xyz"});
  }
}

TEST_F(Pipeline, StatsFileIsValidJsonWithTheRequiredKeys) {
  auto o = options_for(square_with_jittered_grid(8, 0, 0), "t.obj");
  o.stats_path = path("s.json");
  const auto r = pipeline::build(o);
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(slurp(o.stats_path))) << slurp(o.stats_path);
  const CPLJSONObject root = doc.GetRoot();
  EXPECT_EQ(root.GetLong("points_read"), static_cast<long>(r.points_read));
  EXPECT_EQ(root.GetLong("points_kept"), static_cast<long>(r.points_kept));
  EXPECT_EQ(root.GetLong("duplicates_merged"), 0);
  EXPECT_EQ(root.GetLong("vertices"), static_cast<long>(r.vertices));
  EXPECT_EQ(root.GetLong("triangles"), static_cast<long>(r.triangles));
  EXPECT_EQ(root.GetLong("constraints", -1), 0);
  EXPECT_EQ(root.GetLong("steiner_vertices", -1), 0);
  for (const char* t : {"read", "delaunay", "constraints", "write", "total"})
    EXPECT_GE(root.GetDouble(std::string("timings_s/") + t, -1.0), 0.0) << t;
  EXPECT_GT(root.GetLong("peak_rss_bytes"), 0);
  EXPECT_TRUE(root.GetObj("crs").IsValid());
  EXPECT_EQ(root.GetString("crs", "missing"), "");
  EXPECT_EQ(root.GetString("output"), o.output);
  EXPECT_EQ(root.GetString("tincdt_version"), std::string(pipeline::version()));
  EXPECT_EQ(root.GetArray("inputs").Size(), 1);
}

TEST_F(Pipeline, JsonEscapesStrings) {
  pipeline::BuildReport r;
  r.output = std::string("a\"b\\c\nd\te\x01") + "\xc3\xa9" + "\xff" + "\xe2\x82";
  r.crs = "EPSG:2949";
  const std::string json = r.to_json();
  EXPECT_NE(json.find(R"("output": "a\"b\\c\nd\te\u0001é\ufffd\ufffd\ufffd")"), std::string::npos)
      << json;
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(json)) << json;
  EXPECT_EQ(doc.GetRoot().GetString("crs"), "EPSG:2949");
}

TEST_F(Pipeline, JsonNumbersRoundTrip) {
  pipeline::BuildReport r;
  r.offset = {273000, -5274000.25, 0.1};
  r.timings_s.total = 1.0 / 3.0;
  r.points_read = 18446744073709551615u;
  const std::string json = r.to_json();
  EXPECT_NE(json.find("\"points_read\": 18446744073709551615"), std::string::npos) << json;
  EXPECT_NE(json.find("273000"), std::string::npos) << json;
  EXPECT_NE(json.find("-5274000.25"), std::string::npos) << json;
  EXPECT_NE(json.find("0.3333333333333333"), std::string::npos) << json;
}

TEST_F(Pipeline, LogReceivesDebugLines) {
  auto o = options_for(square_with_jittered_grid(3, 0, 0), "t.obj");
  std::vector<std::pair<int, std::string>> lines;
  pipeline::build(o, nullptr,
                  [&](int level, const std::string& m) { lines.emplace_back(level, m); });
  ASSERT_FALSE(lines.empty());
  EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [&](const auto& l) {
    return l.first == pipeline::log_debug && l.second.find(path("in.xyz")) != std::string::npos;
  }));
}

// ---- CRS handling on the shared LAS files ----------------------------------------------------

std::string shared_las(const char* name) {
  return (fs::path(::tincdt::test::shared_data()) / "las" / name).string();
}

// Builds O; the warnings it logged.
std::vector<std::string> warnings_of(const pipeline::BuildOptions& o, pipeline::BuildReport& r) {
  std::vector<std::string> warnings;
  r = pipeline::build(o, nullptr, [&](int level, const std::string& m) {
    if (level == pipeline::log_warn) warnings.push_back(m);
  });
  return warnings;
}

// wontcompress3.las (EPSG:26919) is transformed into the first file's CRS, and lies far from it.
TEST_F(Pipeline, AnInputInAnotherCrsFarAwayIsWarnedAbout) {
  if (!fs::exists(shared_las("Topography.las"))) GTEST_SKIP() << "shared data not found";
  pipeline::BuildOptions o;
  o.inputs = {shared_las("Topography.las"), shared_las("wontcompress3.las")};
  o.output = path("t.ply");
  pipeline::BuildReport r;
  const std::vector<std::string> warnings = warnings_of(o, r);
  ASSERT_EQ(warnings.size(), 1u);
  const std::string& m = warnings.front();
  EXPECT_NE(m.find("wontcompress3.las: transformed from EPSG:26919 to EPSG:2949"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("is its CRS right?"), std::string::npos) << m;
}

// A file without a CRS among files with one is an error naming it (read after the LAS file: XYZ
// text tells its CRS only when read); --a-srs says what it is.
TEST_F(Pipeline, FileWithoutCrsAmongFilesWithOneNeedsAssignedCrs) {
  if (!fs::exists(shared_las("Topography.las"))) GTEST_SKIP() << "shared data not found";
  const std::string xyz =
      (fs::path(::tincdt::test::shared_data()) / "xyz" / "Topography_ground.xyz").string();
  pipeline::BuildOptions o;
  o.inputs = {xyz, shared_las("Topography.las")};
  o.output = path("t.ply");
  try {
    pipeline::build(o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), xyz);
    EXPECT_EQ(e.remedy(), Remedy::assign_crs);
    EXPECT_NE(e.detail().find("EPSG:2949"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(names_in(dir_).empty());
  o.assign_srs = "EPSG:2949";
  pipeline::BuildReport r;
  const std::vector<std::string> warnings = warnings_of(o, r);
  EXPECT_EQ(r.crs, "EPSG:2949");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(r.points_kept, 8159u + 73403u);  // the xyz file holds the LAS file's ground points
  EXPECT_TRUE(fs::exists(path("t.prj")));
}

TEST_F(Pipeline, OverrideCrsReplacesEveryInputsOwn) {
  if (!fs::exists(shared_las("Topography.las"))) GTEST_SKIP() << "shared data not found";
  pipeline::BuildOptions o;
  o.inputs = {shared_las("Topography.las"), shared_las("wontcompress3.las")};
  o.output = path("t.ply");
  o.override_srs = "EPSG:2949";
  pipeline::BuildReport r;
  const std::vector<std::string> warnings = warnings_of(o, r);
  EXPECT_EQ(r.crs, "EPSG:2949");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

}  // namespace
