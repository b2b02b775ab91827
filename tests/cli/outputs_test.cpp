// The tincdt binary and the user's files: outputs appear all together or not at all, whatever
// stops the job (a signal at any stage, a second Ctrl-C, a later output that fails); an output
// never replaces an input or a file that belongs to one; an existing .prj with the TIN's CRS is
// fine; --threads changes nothing in the result; reader warnings are shown, and only those.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/stage.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using tincdt::test::names_in;
using tincdt::test::slurp;
using tincdt::test::spit;

// ---- running the binary, with an environment variable and a file-size limit -------------------

struct Outcome {
  int exit_code = -1;  // -1 when ended by a signal
  int signal = 0;      // the signal that ended it
  std::string err;

  std::vector<std::string> lines_with(const std::string& word) const {
    std::vector<std::string> lines;
    std::istringstream s(err);
    for (std::string line; std::getline(s, line);)
      if (line.find(word) != std::string::npos) lines.push_back(line);
    return lines;
  }
};

std::ostream& operator<<(std::ostream& os, const Outcome& r) {
  return os << "exit " << r.exit_code << ", signal " << r.signal << "\n--- stderr\n" << r.err;
}

struct RunOptions {
  std::string signal_hook;                // TINCDT_TEST_SIGNAL
  std::optional<rlim_t> file_size_limit;  // RLIMIT_FSIZE, with SIGXFSZ ignored
};

// Runs tincdt with ARGS in DIR (the working folder, so that paths can be relative).
Outcome run_in(const fs::path& dir, const std::vector<std::string>& args,
               const RunOptions& o = {}) {
  const std::string err_path = dir.string() + ".stderr.txt";
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(120);
    if (!std::freopen(err_path.c_str(), "w", stderr)) ::_exit(121);
    if (!std::freopen("/dev/null", "r", stdin)) ::_exit(122);
    if (o.signal_hook.empty())
      ::unsetenv("TINCDT_TEST_SIGNAL");
    else
      ::setenv("TINCDT_TEST_SIGNAL", o.signal_hook.c_str(), 1);
    if (o.file_size_limit) {
      ::signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{*o.file_size_limit, *o.file_size_limit};
      if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(123);
    }
    std::vector<std::string> argv_s = {TINCDT_EXE};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(TINCDT_EXE, argv.data());
    ::_exit(124);
  }
  Outcome r;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.err = slurp(err_path);
  return r;
}

// Every file of DIR with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const std::string& name : names_in(dir)) files[name] = slurp(dir / name);
  return files;
}

std::string names(const std::map<std::string, std::string>& files) {
  std::string s;
  for (const auto& [name, bytes] : files) s += name + " ";
  return s;
}

// ---- a job that wants every stage ------------------------------------------------------------

std::string grid_xyz(int m, double step) {
  std::string s;
  char line[96];
  std::uint32_t state = 4711;
  const auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return (static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5) * 0.4 * step;
  };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = i * step + jitter(), y = j * step + jitter();
      std::snprintf(line, sizeof line, "%.3f %.3f %.3f\n", x, y, 100 + 0.1 * x + 0.05 * y);
      s += line;
    }
  return s;
}

std::string collection(const std::string& features) {
  return R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
         R"("urn:ogc:def:crs:EPSG::32633"}}, "features": [)" +
         features + "]}\n";
}

std::string feature(const std::string& type, const std::string& coordinates) {
  return R"({"type": "Feature", "properties": {}, "geometry": {"type": ")" + type +
         R"(", "coordinates": )" + coordinates + "}}";
}

// A fresh folder per test, where the binary runs.
class InScratch : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (fs::path(dir_) / name).string(); }
  const std::string dir_ = tincdt::test::scratch_dir("cli-outputs");
};

class FullJob : public InScratch {
 protected:
  void SetUp() override {
    spit(path("pts.xyz"), grid_xyz(30, 10));
    spit(path("contours.geojson"),
         collection(feature("LineString", "[[15.5, 50.5, 110], [280.5, 50.5, 110]]") + ", " +
                    feature("LineString", "[[15.5, 150.5, 120], [280.5, 150.5, 120]]")));
    spit(path("soft.geojson"),
         collection(feature("LineString", "[[20.5, 100.5], [270.5, 220.5]]")));
    spit(path("clip.geojson"),
         collection(feature("Polygon",
                            "[[[5.5, 5.5], [285.5, 5.5], [285.5, 285.5], [5.5, "
                            "285.5], [5.5, 5.5]]]")));
    spit(path("hole.geojson"),
         collection(feature("Polygon",
                            "[[[200.5, 200.5], [240.5, 200.5], [240.5, 240.5], "
                            "[200.5, 240.5], [200.5, 200.5]]]")));
    spit(path("pad.geojson"),
         collection(feature("Polygon",
                            "[[[60.5, 200.5, 99], [100.5, 200.5, 99], [100.5, 240.5, "
                            "99], [60.5, 240.5, 99], [60.5, 200.5, 99]]]")));
  }

  // Every stage of the pipeline wanted; every output asked for.
  static std::vector<std::string> args(const std::string& max_edge = "30") {
    return {"pts.xyz",
            "--a-srs",
            "EPSG:32633",
            "--contours",
            "contours.geojson",
            "--soft-lines",
            "soft.geojson",
            "--clip",
            "clip.geojson",
            "--erase",
            "hole.geojson",
            "--replace",
            "pad.geojson",
            "--fix-flats",
            "--max-edge",
            max_edge,
            "--validate",
            "-o",
            "tin.ply",
            "--stats",
            "s.json",
            "--constraints-out",
            "c.geojson",
            "--diagnostics",
            "d.gpkg",
            "--overwrite",
            "--max-error",
            "0",
            "--dem",
            "dem.tif",
            "--resolution",
            "10",
            "--contour-lines",
            "lines.geojson",
            "--interval",
            "5",
            "--preview",
            "p.png",
            "--preview-size",
            "64",
            "--terrain",
            "terrain",
            "--terrain-levels",
            "0-1"};
  }
};

TEST_F(FullJob, WantsEveryStage) {
  const Outcome r = run_in(dir_, args());
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string stats = slurp(path("s.json"));
  // The stats document lists the stages that ran, all but itself.
  for (const tincdt::pipeline::Stage* stage : tincdt::pipeline::stages()) {
    if (stage->name == "stats") continue;
    EXPECT_NE(stats.find("\"name\": \"" + std::string(stage->name) + "\""), std::string::npos)
        << stage->name << " did not run:\n"
        << stats;
  }
  EXPECT_EQ(names_in(dir_),
            (std::set<std::string>{"pts.xyz", "contours.geojson", "soft.geojson", "clip.geojson",
                                   "hole.geojson", "pad.geojson", "tin.ply", "tin.prj", "s.json",
                                   "c.geojson", "d.gpkg", "dem.tif", "lines.geojson", "p.png",
                                   "terrain"}));
}

// A Ctrl-C (or kill) at the start of any stage, or just before the outputs move into place: the
// process dies of the signal, every file is as it was, no temporary is left. Twice: the second
// signal ends the process at once, and the temporaries go all the same.
TEST_F(FullJob, SignalAtAnyStageChangesNoFile) {
  ASSERT_EQ(run_in(dir_, args()).exit_code, 0);
  const auto before = snapshot(dir_);
  std::vector<std::string> points;
  for (const tincdt::pipeline::Stage* stage : tincdt::pipeline::stages())
    points.emplace_back(stage->name);
  points.emplace_back("commit");
  for (const std::string& at : points) {
    for (const char* hook : {":INT", ":TERM:2", ":INT:2", ":HUP"}) {
      SCOPED_TRACE(at + hook);
      const Outcome r =
          run_in(dir_, args("31"), {.signal_hook = at + hook, .file_size_limit = std::nullopt});
      const int expected = hook[1] == 'I' ? SIGINT : hook[1] == 'T' ? SIGTERM : SIGHUP;
      EXPECT_EQ(r.signal, expected) << r;
      const auto after = snapshot(dir_);
      EXPECT_EQ(names(after), names(before));
      EXPECT_TRUE(after == before) << "a file changed";
    }
  }
  // Without a signal, the same job replaces every output (the TIN differs: --max-edge 31).
  ASSERT_EQ(run_in(dir_, args("31")).exit_code, 0);
  EXPECT_NE(slurp(path("tin.ply")), before.at("tin.ply"));
}

// The diagnostics GeoPackage cannot be written (a file-size limit makes write(2) fail, as a full
// disk would) after the TIN, its .prj and the constraint lines were: none of them replaces the
// old one, and no temporary is left.
TEST_F(FullJob, ALaterOutputFailingChangesNoFile) {
  ASSERT_EQ(run_in(dir_, args()).exit_code, 0);
  const auto before = snapshot(dir_);
  ASSERT_LT(before.at("tin.ply").size(), 60000u);
  ASSERT_GT(before.at("d.gpkg").size(), 60000u);
  const Outcome r = run_in(dir_, args("31"), {.signal_hook = "", .file_size_limit = 60000});
  EXPECT_EQ(r.exit_code, 1) << r;
  ASSERT_EQ(r.lines_with("error:").size(), 1u) << r;
  EXPECT_NE(r.lines_with("error:")[0].find("d.gpkg"), std::string::npos) << r;
  EXPECT_TRUE(snapshot(dir_) == before) << names(snapshot(dir_));
}

// ---- outputs that are inputs -----------------------------------------------------------------

class Inputs : public InScratch {
 protected:
  void SetUp() override {
    spit(path("pts.xyz"), grid_xyz(12, 10));
    spit(path("c.geojson"),
         collection(feature("LineString", "[[15.5, 50.5, 110], [80.5, 50.5, 110]]")));
  }

  // A run refused with a usage error naming OUTPUT as an input; no file changed.
  void expect_refused(const std::vector<std::string>& args, const std::string& output) {
    const auto before = snapshot(dir_);
    for (const bool overwrite : {false, true}) {
      std::vector<std::string> a = args;
      if (overwrite) a.push_back("--overwrite");
      const Outcome r = run_in(dir_, a);
      EXPECT_EQ(r.exit_code, 2) << r;
      ASSERT_EQ(r.lines_with("error:").size(), 1u) << r;
      const std::string error = r.lines_with("error:")[0];
      EXPECT_NE(error.find(output), std::string::npos) << error;
      EXPECT_NE(error.find("input"), std::string::npos) << error;
      EXPECT_TRUE(snapshot(dir_) == before) << names(snapshot(dir_));
    }
  }
};

// Makes a GeoPackage at PATH with a line layer LAYER, or a shapefile (with a .prj in EPSG) when
// PATH ends in .shp.
void write_lines(const std::string& path, const std::string& layer, int epsg) {
  GDALAllRegister();
  const bool shp = fs::path(path).extension() == ".shp";
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(shp ? "ESRI Shapefile" : "GPKG");
  ASSERT_NE(driver, nullptr);
  GDALDataset* ds = driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRSpatialReference srs;
  srs.importFromEPSG(epsg);
  OGRLayer* l = ds->CreateLayer(layer.c_str(), &srs, wkbLineString25D, nullptr);
  ASSERT_NE(l, nullptr);
  OGRFeature* f = OGRFeature::CreateFeature(l->GetLayerDefn());
  OGRLineString line;
  line.addPoint(15.5, 50.5, 110);
  line.addPoint(80.5, 50.5, 110);
  f->SetGeometry(&line);
  EXPECT_EQ(l->CreateFeature(f), OGRERR_NONE);
  OGRFeature::DestroyFeature(f);
  GDALClose(ds);
}

TEST_F(Inputs, StatsOverThePointsIsRefused) {
  expect_refused({"pts.xyz", "-o", "t.ply", "--stats", "pts.xyz"}, "pts.xyz");
}

TEST_F(Inputs, TinOrConstraintLinesOverTheContoursAreRefused) {
  expect_refused({"pts.xyz", "--contours", "c.geojson", "-o", "c.geojson"}, "c.geojson");
  expect_refused(
      {"pts.xyz", "--contours", "c.geojson", "-o", "t.ply", "--constraints-out", "c.geojson"},
      "c.geojson");
  expect_refused({"pts.xyz", "--contours", "./c.geojson", "-o", "t.ply", "--constraints-out",
                  path("c.geojson")},
                 "c.geojson");
}

TEST_F(Inputs, DiagnosticsOverAGeoPackageLayerIsRefused) {
  write_lines(path("tl.gpkg"), "a", 32633);
  expect_refused({"pts.xyz", "--a-srs", "EPSG:32633", "--contours", "tl.gpkg:a", "-o", "t.ply",
                  "--diagnostics", "tl.gpkg"},
                 "tl.gpkg");
}

TEST_F(Inputs, LinksToAnInputAreRefused) {
  fs::create_hard_link(path("pts.xyz"), path("hard.ply"));
  fs::create_symlink("pts.xyz", path("soft.ply"));
  expect_refused({"pts.xyz", "-o", "hard.ply"}, "hard.ply");
  expect_refused({"pts.xyz", "-o", "soft.ply"}, "soft.ply");
}

// A shapefile's .prj is part of it: a TIN named like the shapefile must not change its CRS.
TEST_F(Inputs, ShapefilePrjIsNotReplaced) {
  write_lines(path("X.shp"), "X", 32633);
  ASSERT_TRUE(fs::exists(path("X.prj")));
  const auto before = snapshot(dir_);
  const Outcome r = run_in(dir_, {"pts.xyz", "--contours", "X.shp", "-o", "X.ply", "--override-srs",
                                  "EPSG:32634", "--overwrite"});
  EXPECT_EQ(r.exit_code, 2) << r;
  EXPECT_NE(r.err.find("X.prj"), std::string::npos) << r;
  EXPECT_TRUE(snapshot(dir_) == before) << names(snapshot(dir_));
  // With the shapefile's own CRS there is nothing to change: the job runs, X.prj stays as it is.
  const Outcome same =
      run_in(dir_, {"pts.xyz", "--contours", "X.shp", "-o", "X.ply", "--a-srs", "EPSG:32633"});
  EXPECT_EQ(same.exit_code, 0) << same;
  EXPECT_EQ(slurp(path("X.prj")), before.at("X.prj"));
  EXPECT_TRUE(fs::exists(path("X.ply")));
}

// ---- the TIN's .prj ------------------------------------------------------------------------

TEST_F(Inputs, ExistingPrjWithTheSameCrsIsKept) {
  const Outcome ply = run_in(dir_, {"pts.xyz", "--a-srs", "EPSG:32633", "-o", "tin.ply"});
  ASSERT_EQ(ply.exit_code, 0) << ply;
  const std::string prj = slurp(path("tin.prj"));
  ASSERT_FALSE(prj.empty());
  const Outcome obj = run_in(dir_, {"pts.xyz", "--a-srs", "EPSG:32633", "-o", "tin.obj"});
  EXPECT_EQ(obj.exit_code, 0) << obj;
  EXPECT_EQ(slurp(path("tin.prj")), prj);
  EXPECT_TRUE(fs::exists(path("tin.obj")));
  // Another CRS still needs --overwrite.
  fs::remove(path("tin.ply"));
  const Outcome other = run_in(dir_, {"pts.xyz", "--a-srs", "EPSG:32634", "-o", "tin.ply"});
  EXPECT_EQ(other.exit_code, 1) << other;
  EXPECT_NE(other.err.find("tin.prj"), std::string::npos) << other;
  EXPECT_EQ(slurp(path("tin.prj")), prj);
}

// ---- --threads -------------------------------------------------------------------------------

TEST(Threads, OneThreadAndAllCoresGiveTheSameValidTin) {
  // Enough points for the two-thread Delaunay path (DelaunayOptions::parallel_min_points).
  const std::string dir = tincdt::test::scratch_dir("cli-outputs");
  spit(fs::path(dir) / "pts.xyz", grid_xyz(260, 1));
  std::map<std::string, tincdt::test::MeshFile> meshes;
  std::map<std::string, std::string> stats;
  for (const std::string threads : {"1", "0", "2"}) {
    const Outcome r = run_in(dir, {"pts.xyz", "-o", "t" + threads + ".obj", "--threads", threads,
                                   "--validate", "--stats", "s" + threads + ".json"});
    ASSERT_EQ(r.exit_code, 0) << r;
    meshes[threads] = tincdt::test::read_mesh(fs::path(dir) / ("t" + threads + ".obj"));
    stats[threads] = slurp(fs::path(dir) / ("s" + threads + ".json"));
  }
  const auto vertices = [](const tincdt::test::MeshFile& m) {
    std::vector<std::array<double, 3>> v(m.v.begin(), m.v.end());
    std::sort(v.begin(), v.end());
    return v;
  };
  ASSERT_EQ(meshes["1"].v.size(), 260u * 260u);
  for (const std::string threads : {"0", "2"}) {
    EXPECT_EQ(vertices(meshes[threads]), vertices(meshes["1"])) << threads;
    EXPECT_EQ(meshes[threads].f.size(), meshes["1"].f.size()) << threads;
    // The quality block is the same too, but for the last bits of its sums (the triangles are
    // numbered differently, so they are added in another order).
    const auto quality = [](const std::string& json) {
      const std::size_t at = json.find("\"quality\"");
      const std::string block = json.substr(at, json.find('}', at) - at);
      return std::regex_replace(block, std::regex("\"(area_2d|area_3d|mean_edge_length)\":[^,]*"),
                                "");
    };
    EXPECT_EQ(quality(stats[threads]), quality(stats["1"])) << threads;
  }
}

// ---- warnings --------------------------------------------------------------------------------

// Every shared LAS and XYZ file: the reader's warnings are shown (a file without a CRS says why),
// and no other warning appears.
TEST(Warnings, SharedFilesWarnAsExpectedAndOtherwiseNot) {
  const fs::path data = fs::path(::tincdt::test::shared_data());
  if (!fs::is_directory(data / "las")) GTEST_SKIP() << "shared data not found at " << data;
  const std::map<std::string, std::string> expected = {
      {"mvk-thin.las", "override part of its definition"},
      {"simple1_3.las", "only a vertical CRS"},
      {"warsaw_small.las", "holds no WKT"}};
  const std::string dir = tincdt::test::scratch_dir("cli-outputs");
  std::vector<fs::path> files;
  for (const char* sub : {"las", "xyz"})
    for (const auto& e : fs::directory_iterator(data / sub))
      if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    const Outcome r = run_in(dir, {file.string(), "-o", "t.ply", "--overwrite"});
    // A file without a CRS makes outputs without one: said once, apart from the reader's own.
    std::vector<std::string> warnings;
    int without_crs = 0;
    for (const std::string& w : r.lines_with("warning:")) {
      if (w.find("no input has a CRS") != std::string::npos)
        ++without_crs;
      else
        warnings.push_back(w);
    }
    EXPECT_LE(without_crs, 1) << r;
    const auto it = expected.find(file.filename().string());
    if (it == expected.end()) {
      EXPECT_TRUE(warnings.empty()) << r;
      continue;
    }
    ASSERT_EQ(warnings.size(), 1u) << r;
    EXPECT_NE(warnings[0].find(it->second), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find(file.string()), std::string::npos) << warnings[0];
  }
}

}  // namespace
