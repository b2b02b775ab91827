// Runs the tincdt binary the way a user would and checks what a user sees: the exit code, the
// one-line message naming the file, and that a failed run leaves no file (not even a temporary).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cpl_json.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/las_writer.hpp"
#include "support/mesh_files.hpp"
#include "support/shared_data.hpp"
#include "support/spawn.hpp"
#include "support/stats_json.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

// ---- files ---------------------------------------------------------------------------------

using tincdt::test::names_in;
using tincdt::test::slurp;
using tincdt::test::spit;

std::string shared_data() {
  return ::tincdt::test::shared_data();
}

bool have_shared_data() {
  return fs::is_directory(fs::path(shared_data()) / "las");
}

std::string sanitize(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

// The whole number at KEY (a top-level member, or a path like "flats/before") of a --stats file;
// UINT64_MAX when there is none.
std::uint64_t stats_number(const std::string& json, const std::string& key) {
  return tincdt::test::StatsJson(json).count(key);
}

// Each KEY of a --stats file holds its expected whole number.
void expect_counts(const std::string& json,
                   const std::vector<std::pair<std::string, std::uint64_t>>& expected) {
  for (const auto& [key, value] : expected) EXPECT_EQ(stats_number(json, key), value) << key;
}

// ---- synthetic LAS 1.2, point format 0 --------------------------------------------------------

struct LasPoint {
  double x, y, z;
  std::uint8_t cls;
};

template <class T>
void put(std::string& buf, std::size_t offset, T value) {
  std::memcpy(buf.data() + offset, &value, sizeof value);
}

// Millimetre coordinates around (500000, 4000000), all single returns.
std::string make_las(const std::vector<LasPoint>& points) {
  namespace las = tincdt::test::las;
  las::Header h;
  h.software = "tincdt cli_test";
  h.scale = {0.001, 0.001, 0.001};
  h.offset = {500000, 4000000, 0};
  std::vector<las::Record> records;
  for (const LasPoint& p : points) {
    las::Record r;
    r.x = las::quantize(p.x, h.scale[0], h.offset[0]);
    r.y = las::quantize(p.y, h.scale[1], h.offset[1]);
    r.z = las::quantize(p.z, h.scale[2], h.offset[2]);
    r.classification = p.cls;
    records.push_back(r);
  }
  return las::file(h, records);
}

// A jittered 20 x 20 grid at UTM magnitudes; every other point is ground (class 2).
std::vector<LasPoint> grid_points() {
  std::vector<LasPoint> pts;
  std::uint32_t state = 12345;
  const auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return (static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5) * 0.6;
  };
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      pts.push_back({500100.0 + i + jitter(), 4000200.0 + j + jitter(), 100.0 + 0.25 * i,
                     static_cast<std::uint8_t>((i + j) % 2 == 0 ? 2 : 1)});
  return pts;
}

std::string grid_xyz() {
  std::string s = "# x y z\n";
  char line[96];
  for (const LasPoint& p : grid_points()) {
    std::snprintf(line, sizeof line, "%.3f %.3f %.3f\n", p.x, p.y, p.z);
    s += line;
  }
  return s;
}

// ---- running the binary ------------------------------------------------------------------------

struct Outcome {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;
  std::string err;

  std::vector<std::string> err_lines() const {
    std::vector<std::string> lines;
    std::istringstream s(err);
    for (std::string line; std::getline(s, line);) lines.push_back(line);
    return lines;
  }
  // The "tincdt: error: ..." lines.
  std::vector<std::string> errors() const {
    std::vector<std::string> e;
    for (const std::string& l : err_lines())
      if (l.rfind("tincdt: error: ", 0) == 0) e.push_back(l);
    return e;
  }
};

std::ostream& operator<<(std::ostream& os, const Outcome& r) {
  return os << "exit " << r.exit_code << "\n--- stdout\n" << r.out << "--- stderr\n" << r.err;
}

class Scratch {
 public:
  Scratch() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = sanitize(std::string(info->test_suite_name()) + "." + info->name());
    dir_ = tincdt::test::fresh_dir(fs::path(TINCDT_TEST_TMP) / "cli" / name);
    capture_ = tincdt::test::fresh_dir(fs::path(TINCDT_TEST_TMP) / "cli-capture" / name);
  }

  const fs::path& dir() const { return dir_; }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  Outcome run(const std::vector<std::string>& args, const std::string& stdin_path = "/dev/null") {
    std::vector<std::string> words = {TINCDT_EXE};
    words.insert(words.end(), args.begin(), args.end());
    const tincdt::test::Spawned r = tincdt::test::spawn_captured(words, ".", capture_, stdin_path);
    Outcome o;
    o.exit_code = r.exit_code;
    o.out = r.out;
    o.err = r.err;
    return o;
  }

 private:
  fs::path dir_;
  fs::path capture_;
};

// Checks a failed run: exit code, exactly one "tincdt: error:" line naming `culprit` and
// matching `pattern`, and the scratch folder holding exactly `files` (no output, no temporary).
void expect_failure(const Outcome& r, int code, const std::string& culprit,
                    const std::string& pattern, const Scratch& s,
                    const std::set<std::string>& files) {
  EXPECT_EQ(r.exit_code, code) << r;
  const auto errors = r.errors();
  ASSERT_EQ(errors.size(), 1u) << r;
  if (!culprit.empty()) {
    EXPECT_NE(errors[0].find(culprit), std::string::npos) << r;
  }
  if (!pattern.empty()) {
    EXPECT_TRUE(std::regex_search(errors[0], std::regex(pattern, std::regex::icase)))
        << "expected /" << pattern << "/ in: " << errors[0];
  }
  EXPECT_EQ(names_in(s.dir()), files);
}

class Cli : public ::testing::Test {
 protected:
  Scratch s;

  // Runs tincdt with ARGS and --stats; a failed run fails the test. Returns the stats document.
  std::string stats_of_run(std::vector<std::string> args) {
    args.insert(args.end(), {"--stats", s.path("s.json"), "--overwrite"});
    const Outcome r = s.run(args);
    EXPECT_EQ(r.exit_code, 0) << r;
    return r.exit_code == 0 ? slurp(s.path("s.json")) : std::string();
  }
};

// ---- information and usage --------------------------------------------------------------------

TEST_F(Cli, VersionPrintsProjectVersion) {
  const Outcome r = s.run({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(r.out, std::string("tincdt ") + TINCDT_VERSION + "\n");
  EXPECT_TRUE(std::regex_match(r.out, std::regex("tincdt [0-9]+\\.[0-9]+\\.[0-9]+\n")));
}

TEST_F(Cli, HelpListsOptionsAndExamples) {
  const Outcome r = s.run({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r;
  for (const char* needle : {"Usage: tincdt [OPTIONS] [INPUT...] [--contours LINES]... -o OUTPUT",
                             "--contours",
                             "--breaklines",
                             "--z-field",
                             "--restore",
                             "--on-crossing",
                             "-o,--output",
                             "-f,--format",
                             "--overwrite",
                             "--ply-ascii",
                             "--offset",
                             "--t-srs",
                             "--a-srs",
                             "--on-duplicate",
                             "--keep-class",
                             "--drop-class",
                             "--first-only",
                             "--last-only",
                             "--stats",
                             "-q,--quiet",
                             "-v,--verbose",
                             "--version",
                             "Examples:",
                             "--keep-class 2",
                             "EPSG:4326",
                             "Exit status"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  EXPECT_TRUE(r.err.empty()) << r;
}

TEST_F(Cli, NoArgumentsIsUsageError) {
  const Outcome r = s.run({});
  expect_failure(r, 2, "", "--output|input", s, {});
}

TEST_F(Cli, NoOutputIsUsageError) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz")});
  expect_failure(r, 2, "", "--output", s, {"a.xyz"});
}

TEST_F(Cli, NoInputIsUsageError) {
  const Outcome r = s.run({"-o", s.path("t.obj")});
  expect_failure(r, 2, "", "INPUT", s, {});
}

TEST_F(Cli, UnknownOptionIsUsageError) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--frobnicate"});
  expect_failure(r, 2, "--frobnicate", "", s, {"a.xyz"});
}

TEST_F(Cli, BadOptionValuesAreUsageErrors) {
  spit(s.path("a.xyz"), grid_xyz());
  const std::string in = s.path("a.xyz"), out = s.path("t.obj");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--offset", "1,2"}, "--offset"},
      {{"--offset", "1,2,x"}, "--offset"},
      {{"--offset", "1,2,3,4"}, "--offset"},
      {{"--offset", "nan,0,0"}, "--offset"},
      {{"--keep-class", "abc"}, "--keep-class"},
      {{"--keep-class", "2,300"}, "--keep-class"},
      {{"--drop-class", "-1"}, "--drop-class"},
      {{"--keep-class", "2", "--drop-class", "2"}, "both"},
      {{"--on-duplicate", "median"}, "--on-duplicate"},
      {{"-f", "dwg"}, "--format"},
      {{"--first-only", "--last-only"}, "exclude each other"},
      {{"-q", "-v"}, "exclude each other"},
      {{"--t-srs", "EPSG:4326"}, "--allow-geographic"},
  };
  for (const auto& [extra, pattern] : cases) {
    SCOPED_TRACE(extra.front() + " " + extra.back());
    std::vector<std::string> args = {in, "-o", out};
    args.insert(args.end(), extra.begin(), extra.end());
    expect_failure(s.run(args), 2, "", pattern, s, {"a.xyz"});
  }
}

TEST_F(Cli, UnknownOutputExtensionIsUsageError) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.dwg")});
  expect_failure(r, 2, "t.dwg", "format", s, {"a.xyz"});
}

TEST_F(Cli, NegativeOffsetIsAValueNotAnOption) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--offset", "-1000,-2000,0"});
  EXPECT_EQ(r.exit_code, 0) << r;
}

// ---- bad input, as a new user would try it ----------------------------------------------------

TEST_F(Cli, MissingFile) {
  const std::string missing = s.path("no_such_file.las");
  const Outcome r = s.run({missing, "-o", s.path("t.ply")});
  expect_failure(r, 1, missing, "", s, {});
  EXPECT_EQ(r.err_lines().size(), 1u) << r;
}

// Each bad input file alone: exit 1, one error line naming the file (and the place, where the
// file has lines), nothing written.
TEST_F(Cli, BadInputFilesFailNamingTheFile) {
  const std::string las = make_las(grid_points());
  std::string lying = las;
  put<std::uint32_t>(lying, 107, 400 + 25);  // header claims 25 more points than there are
  put<std::uint32_t>(lying, 111, 400 + 25);
  struct Case {
    std::string name, bytes, place;
    bool only_line;  // no warning either: stderr holds the error alone
  };
  const std::vector<Case> cases = {
      {"empty.xyz", "", "", false},
      {"empty.las", "", "", true},
      {"cut.las", las.substr(0, las.size() / 2 + 7), "", true},
      {"cut_header.las", las.substr(0, 100), "", false},
      {"count.las", lying, "", true},
      {"bad.xyz", "1 2 3\n4 5 6\n7 8 oops\n9 9 9\n", "line 3", true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    spit(s.path(c.name), c.bytes);
    const Outcome r = s.run({s.path(c.name), "-o", s.path("t.ply")});
    expect_failure(r, 1, s.path(c.name), c.place, s, {c.name});
    if (c.only_line) {
      EXPECT_EQ(r.err_lines().size(), 1u) << r;
    }
    fs::remove(s.path(c.name));
  }
}

TEST_F(Cli, TruncatedSharedLas) {
  if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
  const std::string las = slurp(fs::path(shared_data()) / "las" / "simple.las");
  spit(s.path("simple_cut.las"), las.substr(0, las.size() - las.size() / 3));
  const Outcome r = s.run({s.path("simple_cut.las"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("simple_cut.las"), "", s, {"simple_cut.las"});
}

TEST_F(Cli, SharedLasWithWrongPointCount) {
  if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
  std::string las = slurp(fs::path(shared_data()) / "las" / "simple.las");  // LAS 1.2
  std::uint32_t count = 0;
  std::memcpy(&count, las.data() + 107, 4);
  ASSERT_EQ(count, 1065u);
  put<std::uint32_t>(las, 107, count * 2);
  spit(s.path("simple_count.las"), las);
  const Outcome r = s.run({s.path("simple_count.las"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("simple_count.las"), "", s, {"simple_count.las"});
}

TEST_F(Cli, MalformedXyzInSecondOfTwoInputs) {
  spit(s.path("good.xyz"), grid_xyz());
  spit(s.path("bad.xyz"), "1 2 3\n4 5\n");
  const Outcome r = s.run({s.path("good.xyz"), s.path("bad.xyz"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("bad.xyz"), "line 2", s, {"good.xyz", "bad.xyz"});
}

TEST_F(Cli, TooFewPoints) {
  spit(s.path("two.xyz"), "1 2 3\n4 5 6\n1 2 7\n");
  const Outcome r = s.run({s.path("two.xyz"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("two.xyz"), "fewer than 3 distinct points", s, {"two.xyz"});
}

TEST_F(Cli, CollinearPoints) {
  spit(s.path("line.xyz"), "0 0 1\n1 1 1\n2 2 1\n3 3 1\n");
  const Outcome r = s.run({s.path("line.xyz"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("line.xyz"), "collinear", s, {"line.xyz"});
}

TEST_F(Cli, FilterKeepsNothing) {
  spit(s.path("g.las"), make_las(grid_points()));
  const Outcome r = s.run({s.path("g.las"), "-o", s.path("t.obj"), "--keep-class", "9"});
  expect_failure(r, 1, s.path("g.las"), "filters kept none", s, {"g.las"});
}

// ---- bad output --------------------------------------------------------------------------------

TEST_F(Cli, UnwritableOutputParentIsAFile) {
  spit(s.path("a.xyz"), grid_xyz());
  spit(s.path("afile"), "not a folder");
  const std::string out = s.path("afile") + "/t.ply";
  const Outcome r = s.run({s.path("a.xyz"), "-o", out});
  expect_failure(r, 1, out, "", s, {"a.xyz", "afile"});
  EXPECT_EQ(slurp(s.path("afile")), "not a folder");
}

TEST_F(Cli, OutputFolderMissing) {
  spit(s.path("a.xyz"), grid_xyz());
  const std::string out = s.path("nowhere") + "/t.ply";
  expect_failure(s.run({s.path("a.xyz"), "-o", out}), 1, out, "does not exist", s, {"a.xyz"});
}

TEST_F(Cli, OutputIsAFolder) {
  spit(s.path("a.xyz"), grid_xyz());
  fs::create_directory(s.path("out.ply"));
  expect_failure(s.run({s.path("a.xyz"), "-o", s.path("out.ply"), "--overwrite"}), 1,
                 s.path("out.ply"), "folder", s, {"a.xyz", "out.ply"});
}

TEST_F(Cli, OutputExistsIsKeptUnlessOverwrite) {
  spit(s.path("a.xyz"), grid_xyz());
  spit(s.path("t.obj"), "old content\n");
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj")});
  expect_failure(r, 1, s.path("t.obj"), "exists.*--overwrite", s, {"a.xyz", "t.obj"});
  EXPECT_EQ(slurp(s.path("t.obj")), "old content\n");

  const Outcome r2 = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--overwrite"});
  EXPECT_EQ(r2.exit_code, 0) << r2;
  EXPECT_NE(slurp(s.path("t.obj")), "old content\n");
  EXPECT_EQ(names_in(s.dir()), (std::set<std::string>{"a.xyz", "t.obj"}));
}

TEST_F(Cli, OutputExistsFailsBeforeReading) {
  // The input is broken too; the output check must come first so a long job cannot fail late.
  spit(s.path("bad.xyz"), "1 2 x\n");
  spit(s.path("t.obj"), "old\n");
  expect_failure(s.run({s.path("bad.xyz"), "-o", s.path("t.obj")}), 1, s.path("t.obj"), "exists", s,
                 {"bad.xyz", "t.obj"});
}

TEST_F(Cli, StatsFileExistsFailsBeforeWork) {
  spit(s.path("a.xyz"), grid_xyz());
  spit(s.path("s.json"), "{}");
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--stats", s.path("s.json")});
  expect_failure(r, 1, s.path("s.json"), "exists", s, {"a.xyz", "s.json"});
  EXPECT_EQ(slurp(s.path("s.json")), "{}");
}

TEST_F(Cli, OutputSameAsInputIsRefused) {
  spit(s.path("a.json"), "1 2 3\n");
  expect_failure(s.run({s.path("a.json"), "-o", s.path("a.json"), "--overwrite"}), 2,
                 s.path("a.json"), "input", s, {"a.json"});
  EXPECT_EQ(slurp(s.path("a.json")), "1 2 3\n");
}

TEST_F(Cli, NoStatsOnFailure) {
  spit(s.path("bad.xyz"), "1 2 3\nfoo\n");
  const Outcome r = s.run({s.path("bad.xyz"), "-o", s.path("t.ply"), "--stats", s.path("s.json")});
  expect_failure(r, 1, s.path("bad.xyz"), "line 2", s, {"bad.xyz"});
}

// ---- successful runs ---------------------------------------------------------------------------

TEST_F(Cli, XyzToEveryFormatWithStats) {
  spit(s.path("a.xyz"), grid_xyz());
  for (const std::string ext : {"obj", "ply", "geojson"}) {
    SCOPED_TRACE(ext);
    const std::string out = s.path("t." + ext), stats = s.path(ext + ".json");
    const Outcome r = s.run({s.path("a.xyz"), "-o", out, "--stats", stats, "--validate"});
    ASSERT_EQ(r.exit_code, 0) << r;
    EXPECT_TRUE(r.errors().empty()) << r;
    EXPECT_NE(r.err.find("TIN: 400 vertices"), std::string::npos) << r;
    EXPECT_NE(r.err.find("wrote " + out), std::string::npos) << r;
    const std::string json = slurp(stats);
    const tincdt::test::StatsJson report(json);
    ASSERT_TRUE(report.ok()) << json;
    for (const char* key :
         {"points_read", "points_kept", "duplicates_merged", "vertices", "triangles", "constraints",
          "steiner_vertices", "peak_rss_bytes", "tincdt_version"})
      EXPECT_TRUE(report.has(key)) << key << json;
    for (const char* stage : {"read", "delaunay", "constraints", "write", "total"})
      EXPECT_GE(report.number(std::string("timings_s/") + stage).value_or(-1), 0.0)
          << stage << json;
    EXPECT_EQ(report.text("crs"), "") << json;
    EXPECT_EQ(stats_number(json, "points_read"), 400u);
    EXPECT_EQ(stats_number(json, "vertices"), 400u);
    EXPECT_GT(stats_number(json, "peak_rss_bytes"), 0u);
    EXPECT_TRUE(fs::is_regular_file(out));
  }
  EXPECT_EQ(names_in(s.dir()), (std::set<std::string>{"a.xyz", "t.obj", "t.ply", "t.geojson",
                                                      "obj.json", "ply.json", "geojson.json"}));
}

TEST_F(Cli, ObjCountsMatchStats) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--stats", s.path("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string obj = slurp(s.path("t.obj")), json = slurp(s.path("s.json"));
  std::uint64_t v = 0, f = 0;
  std::istringstream in(obj);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("f ", 0) == 0) ++f;
  }
  EXPECT_EQ(v, stats_number(json, "vertices"));
  EXPECT_EQ(f, stats_number(json, "triangles"));
}

TEST_F(Cli, LasWithClassFilter) {
  spit(s.path("g.las"), make_las(grid_points()));
  const std::string json =
      stats_of_run({s.path("g.las"), "-o", s.path("t.ply"), "--keep-class", "2"});
  expect_counts(json, {{"points_read", 400}, {"points_kept", 200}, {"vertices", 200}});
}

TEST_F(Cli, ClassListsDoNotSwallowInputs) {
  spit(s.path("g.las"), make_las(grid_points()));
  const std::vector<std::pair<std::vector<std::string>, std::uint64_t>> cases = {
      {{"--keep-class", "2", s.path("g.las")}, 200},
      {{"--keep-class", "2,1", s.path("g.las")}, 400},
      {{"--keep-class", "1", "--keep-class", "2", s.path("g.las")}, 400},
      {{"--drop-class", "7", "--keep-class", "1", s.path("g.las")}, 200},
      {{s.path("g.las"), "--drop-class", "2"}, 200},
  };
  for (const auto& [args, kept] : cases) {
    SCOPED_TRACE(args.front() + " " + args[1]);
    std::vector<std::string> a = args;
    a.insert(a.end(), {"-o", s.path("t.obj")});
    EXPECT_EQ(stats_number(stats_of_run(a), "points_kept"), kept);
  }
}

TEST_F(Cli, ExistingPrjFailsBeforeTriangulating) {
  spit(s.path("a.xyz"), grid_xyz());
  spit(s.path("t.prj"), "old");
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.ply"), "--a-srs", "EPSG:32633"});
  expect_failure(r, 1, s.path("t.prj"), "exists", s, {"a.xyz", "t.prj"});
  EXPECT_EQ(slurp(s.path("t.prj")), "old");
}

TEST_F(Cli, DuplicatesAreMergedAndCounted) {
  spit(s.path("d.xyz"), grid_xyz() + "500100.5 4000200.5 1\n500100.5 4000200.5 3\n");
  const std::string json =
      stats_of_run({s.path("d.xyz"), "-o", s.path("t.obj"), "--on-duplicate", "max"});
  expect_counts(json, {{"points_read", 402}, {"duplicates_merged", 1}, {"vertices", 401}});
}

TEST_F(Cli, QuietPrintsNothingOnSuccess) {
  spit(s.path("a.xyz"), grid_xyz());
  // With a CRS: a run without one is warned about even with -q.
  const Outcome r = s.run({"-q", s.path("a.xyz"), "--a-srs", "EPSG:32633", "-o", s.path("t.ply")});
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(r.err, "") << r;
  EXPECT_EQ(r.out, "") << r;
}

TEST_F(Cli, NoProgressWhenStderrIsNotATerminal) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.ply"), "-v"});
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r;
  EXPECT_NE(r.err.find("tincdt: debug: "), std::string::npos) << r;
  for (const std::string& line : r.err_lines()) EXPECT_EQ(line.rfind("tincdt: ", 0), 0u) << line;
}

TEST_F(Cli, StandardInput) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({"-", "-o", s.path("t.obj")}, s.path("a.xyz"));
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(fs::is_regular_file(s.path("t.obj")));
}

TEST_F(Cli, FormatOverridesExtension) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("mesh.txt"), "-f", "ply"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(slurp(s.path("mesh.txt")).substr(0, 4), "ply\n");
}

TEST_F(Cli, PlyAsciiAndOffsetAuto) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.ply"), "--ply-ascii", "--offset",
                           "auto", "--stats", s.path("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string ply = slurp(s.path("t.ply"));
  EXPECT_NE(ply.find("format ascii 1.0"), std::string::npos);
  EXPECT_EQ(tincdt::test::StatsJson(slurp(s.path("s.json"))).numbers("offset"),
            (std::vector<double>{500000, 4000000, 0}))
      << slurp(s.path("s.json"));
}

TEST_F(Cli, AssignedCrsGoesToPrjAndStats) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--a-srs", "EPSG:32633",
                           "--stats", s.path("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(fs::is_regular_file(s.path("t.prj")));
  EXPECT_EQ(tincdt::test::StatsJson(slurp(s.path("s.json"))).text("crs"), "EPSG:32633");
}

TEST_F(Cli, ReprojectWithoutCrsFails) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.geojson"), "--t-srs", "EPSG:32633"});
  expect_failure(r, 1, s.path("a.xyz"), "no CRS.*--a-srs", s, {"a.xyz"});
}

TEST_F(Cli, ReprojectToWgs84) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.geojson"), "--a-srs", "EPSG:32633",
                           "--t-srs", "EPSG:4326", "--allow-geographic"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string gj = slurp(s.path("t.geojson"));
  // UTM 33N, x = 500100 m lies about 15 degrees east, y = 4000200 m about 36 degrees north.
  EXPECT_TRUE(std::regex_search(gj, std::regex("\\[\\s*15\\.0[0-9]*,\\s*36\\.[0-9]+")))
      << gj.substr(0, 600);
}

TEST_F(Cli, BadSrsIsUsageError) {
  spit(s.path("a.xyz"), grid_xyz());
  const Outcome r = s.run({s.path("a.xyz"), "-o", s.path("t.obj"), "--a-srs", "EPSG:999999"});
  expect_failure(r, 2, "", "--a-srs", s, {"a.xyz"});
}

// ---- real data: every shared LAS and XYZ file to every format -----------------------------------

// The shared files the real-data cases run on, in the shared data folder: listed here, not found
// in the folders, so that a run without the data has the same cases, each skipping with the
// reason (CTest runs the cases found when the tests were built). SharedFiles.EveryOneIsListed
// keeps the lists whole.
const std::vector<std::string> kLasAndXyz = {
    "las/1.0_0.las",
    "las/1_4_w_evlr.las",
    "las/4_6_crop.las",
    "las/Topography.las",
    "las/autzen_trim.las",
    "las/autzen_trim_7.las",
    "las/autzen_trim_8_derived.las",
    "las/epsg_4326.las",
    "las/file_with_both_wkt_and_geotiff_vlrs.las",
    "las/hexbin-crop.las",
    "las/mvk-thin.las",
    "las/sample_c.las",
    "las/simple.las",
    "las/simple1_1.las",
    "las/simple1_3.las",
    "las/test1_4.las",
    "las/warsaw_small.las",
    "las/wontcompress3.las",
    "xyz/Topography_ground.xyz",
    "xyz/autzen-bmx-largersample.csv",
    "xyz/autzen_trim_ground.xyz",
};
const std::vector<std::string> kLaz = {
    "laz/1_4_w_evlr.laz",  "laz/Topography.laz",  "laz/Topography_lidR2016.laz",
    "laz/append-bug.laz",  "laz/autzen_trim.laz", "laz/las14_pdrf6.laz",
    "laz/simple.copc.laz", "laz/simple.laz",
};

TEST(SharedFiles, EveryOneIsListed) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  for (const char* folder : {"las", "xyz", "laz"}) {
    std::set<std::string> listed;
    for (const auto* list : {&kLasAndXyz, &kLaz})
      for (const std::string& file : *list)
        if (fs::path(file).parent_path() == folder)
          listed.insert(fs::path(file).filename().string());
    EXPECT_EQ(names_in(tincdt::test::shared_file(folder)), listed) << folder;
  }
}

std::string param_name(const ::testing::TestParamInfo<std::string>& info) {
  return sanitize(fs::path(info.param).filename());
}

class RealData : public ::testing::TestWithParam<std::string> {
 protected:
  Scratch s;
};

std::uint64_t geojson_feature_count(const std::string& path) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY);
  if (ds == nullptr) return UINT64_MAX;
  std::uint64_t n = UINT64_MAX;
  if (ds->GetLayerCount() == 1) n = static_cast<std::uint64_t>(ds->GetLayer(0)->GetFeatureCount());
  GDALClose(ds);
  return n;
}

std::optional<std::pair<std::uint64_t, std::uint64_t>> ply_counts(const std::string& path) {
  const std::string header = tincdt::test::ply_header(path);
  const auto v = tincdt::test::ply_element_count(header, "vertex");
  const auto f = tincdt::test::ply_element_count(header, "face");
  if (!v || !f) return std::nullopt;
  return std::make_pair(*v, *f);
}

TEST_P(RealData, ToObjPlyGeojson) {
  TINCDT_REQUIRE_SHARED_DATA(fs::path(GetParam()).parent_path());
  const std::string input = tincdt::test::shared_file(GetParam());
  const bool single_point = fs::path(input).filename() == "1.0_0.las";

  for (const std::string ext : {"obj", "ply", "geojson"}) {
    SCOPED_TRACE(input + " -> " + ext);
    // One basename per format: tin_obj.obj and tin_ply.ply each get their own .prj.
    const std::string out = s.path("tin_" + ext + "." + ext), stats = s.path(ext + ".json");
    const Outcome r = s.run({input, "-o", out, "--stats", stats, "--validate"});
    if (single_point) {
      expect_failure(r, 1, input, "fewer than 3 distinct points", s, {});
      continue;
    }
    ASSERT_EQ(r.exit_code, 0) << r;
    ASSERT_TRUE(fs::is_regular_file(out));
    const std::string json = slurp(stats);
    const std::uint64_t triangles = stats_number(json, "triangles");
    const std::uint64_t vertices = stats_number(json, "vertices");
    ASSERT_NE(triangles, UINT64_MAX) << json;
    EXPECT_GT(triangles, 0u);
    EXPECT_GE(stats_number(json, "points_read"), vertices);
    if (ext == "geojson") {
      EXPECT_EQ(geojson_feature_count(out), triangles) << out;
    } else if (ext == "ply") {
      const auto counts = ply_counts(out);
      ASSERT_TRUE(counts.has_value());
      EXPECT_EQ(counts->first, vertices);
      EXPECT_EQ(counts->second, triangles);
    } else {
      std::uint64_t f = 0;
      std::ifstream in(out);
      for (std::string line; std::getline(in, line);) f += line.rfind("f ", 0) == 0;
      EXPECT_EQ(f, triangles);
    }
  }
  // Nothing but the outputs, their .prj files and the stats: no temporaries.
  for (const std::string& name : names_in(s.dir()))
    EXPECT_TRUE(std::regex_match(
        name, std::regex("tin_(obj|ply|geojson)\\.(obj|ply|geojson|prj)|[a-z]+\\.json")))
        << name;
}

INSTANTIATE_TEST_SUITE_P(Shared, RealData, ::testing::ValuesIn(kLasAndXyz), param_name);

class RealLaz : public ::testing::TestWithParam<std::string> {
 protected:
  Scratch s;
};

// Every shared LAZ file gives a valid TIN; where a LAS twin exists, the very same file as it.
TEST_P(RealLaz, GivesTheTinOfItsLasTwin) {
  TINCDT_REQUIRE_SHARED_DATA(fs::path(GetParam()).parent_path());
  const std::string input = tincdt::test::shared_file(GetParam());
  const Outcome r = s.run({input, "-o", s.path("laz.ply"), "--validate"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const fs::path twin =
      fs::path(shared_data()) / "las" / fs::path(input).filename().replace_extension(".las");
  if (!fs::exists(twin)) return;
  const Outcome t = s.run({twin.string(), "-o", s.path("las.ply")});
  ASSERT_EQ(t.exit_code, 0) << t;
  EXPECT_EQ(slurp(s.path("laz.ply")), slurp(s.path("las.ply"))) << twin;
}

INSTANTIATE_TEST_SUITE_P(Shared, RealLaz, ::testing::ValuesIn(kLaz), param_name);

}  // namespace

// ---- contours and breaklines (the constraint stage) -----------------------------------------

namespace {

std::uint64_t ply_edge_count(const std::string& path) {
  return tincdt::test::ply_element_count(tincdt::test::ply_header(path), "edge").value_or(0);
}

// Two 3D lines crossing at (5, 5): z 10 -> 20 along one, 30 -> 30 along the other.
const char* kCrossingLines = R"({"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"ID": 1},
   "geometry": {"type": "LineString", "coordinates": [[0, 0, 10], [10, 10, 20]]}},
  {"type": "Feature", "properties": {"ID": 2},
   "geometry": {"type": "LineString", "coordinates": [[0, 10, 30], [10, 0, 30]]}}]})";

}  // namespace

struct LineJob {
  std::string name;
  std::vector<std::string> args;  // relative to the shared data folder, "@" marks a path
};

// What GoogleTest and CTest print for a case: its name, not the object's bytes.
void PrintTo(const LineJob& job, std::ostream* os) {
  *os << job.name;
}

class RealLines : public ::testing::TestWithParam<LineJob> {
 protected:
  Scratch s;
};

TEST_P(RealLines, GiveValidConstrainedTins) {
  if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
  std::vector<std::string> args;
  for (const std::string& a : GetParam().args)
    args.push_back(a[0] == '@' ? shared_data() + "/" + a.substr(1) : a);
  const std::string out = s.path("tin.ply"), stats = s.path("stats.json");
  args.insert(args.end(), {"-o", out, "--stats", stats, "--validate"});
  const Outcome r = s.run(args);
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string json = slurp(stats);
  const std::uint64_t constraints = stats_number(json, "constraints");
  EXPECT_GT(constraints, 100u) << json;
  EXPECT_GE(constraints, stats_number(json, "constraint_segments")) << json;
  EXPECT_EQ(stats_number(json, "crossings"), 0u) << json;  // contours of one surface never cross
  EXPECT_EQ(ply_edge_count(out), constraints);
  const auto counts = ply_counts(out);
  ASSERT_TRUE(counts.has_value());
  EXPECT_EQ(counts->second, stats_number(json, "triangles"));
}

INSTANTIATE_TEST_SUITE_P(
    Shared, RealLines,
    ::testing::Values(
        LineJob{"topography_pair",
                {"@las/Topography.las", "--keep-class", "2", "--contours",
                 "@pair_topography/Topography_contours_1m_3d.shp"}},
        LineJob{"autzen_pair_2d",
                {"@las/autzen_trim.las", "--keep-class", "2", "--contours",
                 "@pair_autzen/autzen_trim_contours_2ft.shp", "--z-field", "ELEV"}},
        LineJob{"vinschgau_2d_alone",
                {"--contours", "@contours/elev_vinschgau_contours_100m.shp", "--z-field", "ELEV"}},
        LineJob{"vinschgau_3d_alone",
                {"--contours", "@contours/elev_vinschgau_contours_100m_3d.shp"}},
        LineJob{"vinschgau_gpkg_alone",
                {"--contours", "@contours/elev_vinschgau_contours_100m.gpkg", "--z-field", "ELEV"}},
        LineJob{"lidr_3d_as_breaklines",
                {"--breaklines", "@contours/Topography_lidR2016_contours_2m_3d.shp"}}),
    [](const ::testing::TestParamInfo<LineJob>& job) { return job.param.name; });

TEST_F(Cli, TwoDimensionalContoursNeedAZSource) {
  if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
  const std::string lines = shared_data() + "/contours/elev_vinschgau_contours_100m.shp";
  const Outcome r = s.run({"--contours", lines, "-o", s.path("tin.ply")});
  expect_failure(r, 1, lines, "feature .*--z-field", s, {});
}

TEST_F(Cli, CrossingLinesAreJoinedOrRefused) {
  spit(s.path("lines.geojson"), kCrossingLines);
  const Outcome joined = s.run({"--breaklines", s.path("lines.geojson"), "-o", s.path("tin.ply"),
                                "--stats", s.path("stats.json"), "--validate"});
  ASSERT_EQ(joined.exit_code, 0) << joined;
  const std::string json = slurp(s.path("stats.json"));
  EXPECT_EQ(stats_number(json, "crossings"), 1u) << json;
  EXPECT_EQ(stats_number(json, "steiner_vertices"), 1u) << json;
  EXPECT_EQ(stats_number(json, "vertices"), 5u) << json;
  EXPECT_EQ(ply_edge_count(s.path("tin.ply")), 4u);
  EXPECT_NE(joined.err.find("z disagreement"), std::string::npos) << joined;

  const Outcome refused = s.run({"--breaklines", s.path("lines.geojson"), "-o", s.path("tin2.ply"),
                                 "--on-crossing", "error"});
  // GeoJSON lines are in WGS 84, so the first TIN got a .prj.
  expect_failure(refused, 1, s.path("lines.geojson"), "feature .*crosses", s,
                 {"lines.geojson", "tin.ply", "tin.prj", "stats.json"});
}

// Contours of South Tyrol (EPSG:32632) beside a LAS file of Quebec (EPSG:2949): transformed, and
// a warning that they lie far from it.
TEST_F(Cli, LinesFarAwayInAnotherCrsAreWarnedAbout) {
  if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
  const std::string lines = shared_data() + "/contours/elev_vinschgau_contours_100m_3d.shp";
  const Outcome r =
      s.run({shared_data() + "/las/Topography.las", "--contours", lines, "-o", s.path("tin.ply")});
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.err.find("_3d.shp: transformed from EPSG:32632 to EPSG:2949, it lies "),
            std::string::npos)
      << r;
  EXPECT_NE(r.err.find("is its CRS right?"), std::string::npos) << r;
}

TEST_F(Cli, RestoreModesAreAccepted) {
  spit(s.path("lines.geojson"), kCrossingLines);
  for (const std::string mode : {"delaunay", "aspect", "none"}) {
    const Outcome r = s.run({"--breaklines", s.path("lines.geojson"), "-o",
                             s.path("tin_" + mode + ".ply"), "--restore", mode, "--validate"});
    EXPECT_EQ(r.exit_code, 0) << mode << ": " << r;
  }
  const Outcome bad = s.run(
      {"--breaklines", s.path("lines.geojson"), "-o", s.path("x.ply"), "--restore", "sideways"});
  EXPECT_EQ(bad.exit_code, 2) << bad;
}

// ---- surface features, TIN boundary, quality --------------------------------------

namespace {

// A GeoJSON FeatureCollection of one polygon per ring, in CRS `epsg` (0: none, i.e. WGS 84),
// each with the property Z when `z` is given (and then as a 3D polygon at that z).
std::string polygons_geojson(const std::vector<std::vector<std::array<double, 2>>>& rings,
                             int epsg = 0, std::optional<double> z = std::nullopt) {
  std::string s = "{\"type\": \"FeatureCollection\",";
  if (epsg != 0)
    s += " \"crs\": {\"type\": \"name\", \"properties\": {\"name\": \"urn:ogc:def:crs:EPSG::" +
         std::to_string(epsg) + "\"}},";
  s += " \"features\": [";
  char buf[128];
  for (std::size_t i = 0; i < rings.size(); ++i) {
    s += std::string(i ? ", " : "") + "{\"type\": \"Feature\", \"properties\": {}, " +
         "\"geometry\": {\"type\": \"Polygon\", \"coordinates\": [[";
    const auto& ring = rings[i];
    for (std::size_t k = 0; k <= ring.size(); ++k) {
      const auto& p = ring[k % ring.size()];
      if (z)
        std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g, %.17g]", k ? ", " : "", p[0], p[1], *z);
      else
        std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", k ? ", " : "", p[0], p[1]);
      s += buf;
    }
    s += "]]}}";
  }
  return s + "]}\n";
}

std::vector<std::array<double, 2>> box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// An ASCII PLY or an OBJ: vertices, faces (0-based) and PLY edges.
using tincdt::test::MeshFile;
using tincdt::test::read_mesh;

bool in_box(const std::vector<std::array<double, 2>>& b, double x, double y, double margin = 0) {
  return x > b[0][0] + margin && x < b[2][0] - margin && y > b[0][1] + margin &&
         y < b[2][1] - margin;
}

struct Extent {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double x(double f) const { return x0 + f * (x1 - x0); }
  double y(double f) const { return y0 + f * (y1 - y0); }
};

std::optional<Extent> vector_extent(const std::string& path) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY);
  if (ds == nullptr) return std::nullopt;
  OGREnvelope env;
  const bool ok = ds->GetLayer(0)->GetExtent(&env, TRUE) == OGRERR_NONE;
  GDALClose(ds);
  if (!ok) return std::nullopt;
  return Extent{env.MinX, env.MinY, env.MaxX, env.MaxY};
}

}  // namespace

TEST_F(Cli, HelpShowsSurfaceFeaturesAndTheirOrder) {
  const Outcome r = s.run({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r;
  for (const char* needle :
       {"Surface features",    "TIN boundary",   "Quality",           "--hard-lines",
        "--soft-lines",        "--clip",         "--erase",           "--replace",
        "--max-edge",          "--fix-flats",    "--constraints-out", "--diagnostics",
        "Order of the stages", "4. --fix-flats", "5. --replace",      "6. --max-edge",
        "7. --clip",           "8. --erase",     "erase wins over",   "--clip boundary.gpkg",
        "--erase lakes.shp",   "--fix-flats -o"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  // The order in the help is the order of the stages (simplification is step 3).
  EXPECT_LT(r.out.find("4. --fix-flats"), r.out.find("5. --replace"));
  EXPECT_LT(r.out.find("5. --replace"), r.out.find("6. --max-edge"));
  EXPECT_LT(r.out.find("6. --max-edge"), r.out.find("7. --clip"));
  EXPECT_LT(r.out.find("7. --clip"), r.out.find("8. --erase"));
}

TEST_F(Cli, SurfaceFeatureUsageErrors) {
  spit(s.path("a.xyz"), grid_xyz());
  const std::string a = s.path("a.xyz"), out = s.path("tin.ply");
  for (const auto& [args, pattern] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{a, "-o", out, "--max-edge", "0"}, "--max-edge.*is not a number > 0"},
           {{a, "-o", out, "--max-edge", "-3"}, "--max-edge.*is not a number > 0"},
           {{a, "-o", out, "--max-edge", "ten"}, "--max-edge"},
           {{a, "-o", out, "--fix-flats"}, "--fix-flats needs --contours"},
           {{a, "-o", out, "--constraints-out", s.path("c.txt")}, "--constraints-out.*GeoJSON"},
           {{a, "-o", out, "--diagnostics", s.path("d.geojson")}, "--diagnostics.*GeoPackage"},
           {{a, "-o", out, "--clip"}, "--clip"}}) {
    const Outcome r = s.run(args);
    expect_failure(r, 2, "", pattern, s, {"a.xyz"});
  }
}

TEST_F(Cli, ClipEraseAndSoftLinesOnSyntheticPoints) {
  // The LAS grid covers x 500100..500119, y 4000200..4000219.
  spit(s.path("a.xyz"), grid_xyz());
  const auto clip = box(500102.5, 4000202.5, 500116.5, 4000217.5);
  // No grid point (integer +- 0.3) lies on these sides.
  const auto hole = box(500105.35, 4000205.35, 500109.65, 4000209.65);
  spit(s.path("clip.geojson"), polygons_geojson({clip}));
  spit(s.path("hole.geojson"), polygons_geojson({hole}));
  const Outcome r =
      s.run({s.path("a.xyz"), "--clip", s.path("clip.geojson"), "--erase", s.path("hole.geojson"),
             "-o", s.path("tin.ply"), "--ply-ascii", "--stats", s.path("s.json"), "--validate"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.err.find("removed triangles:"), std::string::npos) << r;
  const std::string json = slurp(s.path("s.json"));
  EXPECT_GT(stats_number(json, "clipped_triangles"), 0u) << json;
  EXPECT_GT(stats_number(json, "erased_triangles"), 0u) << json;
  const MeshFile m = read_mesh(s.path("tin.ply"));
  double area = 0;
  std::set<std::size_t> used;
  for (const auto& f : m.f) {
    const auto &p = m.v[f[0]], &q = m.v[f[1]], &t = m.v[f[2]];
    area += ((q[0] - p[0]) * (t[1] - p[1]) - (q[1] - p[1]) * (t[0] - p[0])) / 2;
    const double cx = (p[0] + q[0] + t[0]) / 3, cy = (p[1] + q[1] + t[1]) / 3;
    EXPECT_TRUE(in_box(clip, cx, cy));
    EXPECT_FALSE(in_box(hole, cx, cy));
    used.insert(f.begin(), f.end());
  }
  EXPECT_NEAR(area, 14.0 * 15.0 - 4.3 * 4.3, 1e-6);
  EXPECT_EQ(used.size(), m.v.size());  // compacted
  EXPECT_EQ(m.v.size(), stats_number(json, "vertices"));
  EXPECT_EQ(m.e.size(), 8u);  // the two rectangles' sides, each a constrained edge
}

TEST_F(Cli, DiagnosticsAndConstraintLinesOpenWithGdal) {
  spit(s.path("lines.geojson"), kCrossingLines);
  const Outcome r = s.run({"--breaklines", s.path("lines.geojson"), "-o", s.path("tin.ply"),
                           "--diagnostics", s.path("d.gpkg"), "--constraints-out",
                           s.path("c.geojson"), "--stats", s.path("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.err.find("wrote " + s.path("d.gpkg")), std::string::npos) << r;
  const std::string json = slurp(s.path("s.json"));
  EXPECT_EQ(geojson_feature_count(s.path("c.geojson")), stats_number(json, "constraints"));
  EXPECT_EQ(stats_number(json, "constraints"), 4u);

  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(s.path("d.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  OGRLayer* crossings = ds->GetLayerByName("crossings");
  ASSERT_NE(crossings, nullptr);
  ASSERT_EQ(crossings->GetFeatureCount(), 1);
  crossings->ResetReading();
  OGRFeature* f = crossings->GetNextFeature();
  ASSERT_NE(f, nullptr);
  const OGRPoint* p = f->GetGeometryRef()->toPoint();
  EXPECT_NEAR(p->getX(), 5, 1e-12);
  EXPECT_NEAR(p->getY(), 5, 1e-12);
  EXPECT_NEAR(p->getZ(), 22.5, 1e-12);
  EXPECT_EQ(std::set<GIntBig>({f->GetFieldAsInteger64("fid_a"), f->GetFieldAsInteger64("fid_b")}),
            std::set<GIntBig>({0, 1}));  // GDAL numbers GeoJSON features without "id" from 0
  EXPECT_NEAR(f->GetFieldAsDouble("z_diff"), 15, 1e-12);
  EXPECT_NE(std::string(f->GetFieldAsString("file_a")).find("lines.geojson"), std::string::npos);
  OGRFeature::DestroyFeature(f);
  for (const char* layer : {"merged_duplicates", "skipped_segments", "dropped_features"})
    EXPECT_NE(ds->GetLayerByName(layer), nullptr) << layer;
  GDALClose(ds);
}

// ---- real data: the pair_topography TIN clipped, holed, padded, trimmed; flats fixed ----------

class RealSurface : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_shared_data()) GTEST_SKIP() << "shared data not found at " << shared_data();
    contours_ = shared_data() + "/pair_topography/Topography_contours_1m_3d.shp";
    las_ = shared_data() + "/las/Topography.las";
    const auto e = vector_extent(contours_);
    ASSERT_TRUE(e.has_value());
    extent_ = *e;
  }
  std::vector<std::string> base() const {
    return {las_, "--keep-class", "2", "--contours", contours_, "--validate"};
  }
  Scratch s;
  std::string contours_, las_;
  Extent extent_;
};

TEST_F(RealSurface, ClipEraseReplaceOnPairTopography) {
  const Extent& e = extent_;
  const auto clip = box(e.x(0.15), e.y(0.2), e.x(0.85), e.y(0.8));
  const auto hole = box(e.x(0.3), e.y(0.3), e.x(0.45), e.y(0.45));
  const auto pad = box(e.x(0.55), e.y(0.55), e.x(0.7), e.y(0.7));
  const double pad_z = 123.25;
  spit(s.path("clip.geojson"), polygons_geojson({clip}, 2949));
  spit(s.path("hole.geojson"), polygons_geojson({hole}, 2949));
  spit(s.path("pad.geojson"), polygons_geojson({pad}, 2949, pad_z));  // 3D: one z
  std::vector<std::string> args = base();
  args.insert(args.end(),
              {"--clip", s.path("clip.geojson"), "--erase", s.path("hole.geojson"), "--replace",
               s.path("pad.geojson"), "-o", s.path("tin.obj"), "--stats", s.path("s.json")});
  const Outcome r = s.run(args);
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string json = slurp(s.path("s.json"));
  EXPECT_GT(stats_number(json, "clipped_triangles"), 1000u) << json;
  EXPECT_GT(stats_number(json, "erased_triangles"), 100u) << json;
  EXPECT_GT(stats_number(json, "replaced_vertices"), 100u) << json;

  const MeshFile m = read_mesh(s.path("tin.obj"));
  ASSERT_EQ(m.f.size(), stats_number(json, "triangles"));
  double area = 0;  // relative to the clip's corner: map coordinates would cancel
  std::set<std::size_t> used;
  for (const auto& f : m.f) {
    const auto &p = m.v[f[0]], &q = m.v[f[1]], &t = m.v[f[2]];
    const double px = p[0] - clip[0][0], py = p[1] - clip[0][1];
    area += ((q[0] - clip[0][0] - px) * (t[1] - clip[0][1] - py) -
             (q[1] - clip[0][1] - py) * (t[0] - clip[0][0] - px)) /
            2;
    const double cx = (p[0] + q[0] + t[0]) / 3, cy = (p[1] + q[1] + t[1]) / 3;
    EXPECT_TRUE(in_box(clip, cx, cy)) << cx << " " << cy;
    EXPECT_FALSE(in_box(hole, cx, cy)) << cx << " " << cy;
    used.insert(f.begin(), f.end());
  }
  const double side = [&](const std::vector<std::array<double, 2>>& b) {
    return (b[2][0] - b[0][0]) * (b[2][1] - b[0][1]);
  }(clip) - (hole[2][0] - hole[0][0]) * (hole[2][1] - hole[0][1]);
  EXPECT_NEAR(area, side, 1e-6 * side);
  EXPECT_EQ(used.size(), m.v.size());  // no vertex of a removed triangle is written
  std::size_t on_pad = 0;
  for (const auto& v : m.v) {
    if (v[0] >= pad[0][0] && v[0] <= pad[2][0] && v[1] >= pad[0][1] && v[1] <= pad[2][1]) {
      EXPECT_EQ(v[2], pad_z) << v[0] << " " << v[1];
      ++on_pad;
    }
  }
  EXPECT_GT(on_pad, 100u);
}

TEST_F(RealSurface, MaxEdgeTrimsPairTopography) {
  std::vector<std::string> args = base();
  args.insert(args.end(), {"-o", s.path("hull.ply"), "--stats", s.path("hull.json")});
  const Outcome hull = s.run(args);
  ASSERT_EQ(hull.exit_code, 0) << hull;
  const double max_edge = 5;
  args = base();
  args.insert(args.end(), {"-o", s.path("tin.ply"), "--ply-ascii", "--stats", s.path("s.json"),
                           "--max-edge", "5"});
  const Outcome r = s.run(args);
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string json = slurp(s.path("s.json"));
  const std::uint64_t trimmed = stats_number(json, "trimmed_triangles");
  EXPECT_GT(trimmed, 0u) << json;
  EXPECT_EQ(stats_number(json, "triangles") + trimmed,
            stats_number(slurp(s.path("hull.json")), "triangles"));

  // Every triangle on the boundary of the trimmed TIN has its unconstrained edges <= 5 m.
  const MeshFile m = read_mesh(s.path("tin.ply"));
  std::map<std::pair<std::size_t, std::size_t>, int> uses;
  const auto key = [](std::size_t a, std::size_t b) {
    return std::pair<std::size_t, std::size_t>(std::min(a, b), std::max(a, b));
  };
  for (const auto& f : m.f)
    for (int i = 0; i < 3; ++i) ++uses[key(f[i], f[(i + 1) % 3])];
  std::set<std::pair<std::size_t, std::size_t>> constrained;
  for (const auto& e : m.e) constrained.insert(key(e[0], e[1]));
  std::size_t boundary_triangles = 0;
  for (const auto& f : m.f) {
    bool on_boundary = false;
    for (int i = 0; i < 3; ++i) on_boundary |= uses[key(f[i], f[(i + 1) % 3])] == 1;
    if (!on_boundary) continue;
    ++boundary_triangles;
    for (int i = 0; i < 3; ++i) {
      const auto &p = m.v[f[i]], &q = m.v[f[(i + 1) % 3]];
      if (constrained.count(key(f[i], f[(i + 1) % 3]))) continue;
      EXPECT_LE(std::hypot(q[0] - p[0], q[1] - p[1]), max_edge + 1e-9);
    }
  }
  EXPECT_GT(boundary_triangles, 100u);
}

TEST_F(RealSurface, FixFlatsOnLidrContours) {
  const std::string contours = shared_data() + "/contours/Topography_lidR2016_contours_2m_3d.shp";
  const Outcome r = s.run({"--contours", contours, "--fix-flats", "-o", s.path("tin.ply"),
                           "--stats", s.path("s.json"), "--validate"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.err.find("flat triangles:"), std::string::npos) << r;
  const std::string json = slurp(s.path("s.json"));
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(json)) << json;
  const CPLJSONObject root = doc.GetRoot();
  EXPECT_TRUE(root.GetBool("flats/fixed"));
  EXPECT_GT(root.GetLong("flats/before"), 1000);
  EXPECT_EQ(root.GetLong("flats/after", -1), 0) << json;
  EXPECT_EQ(root.GetLong("quality/flat_triangles", -1), 0) << json;
  EXPECT_GT(root.GetLong("flats/vertices_added"), 0);
  EXPECT_EQ(root.GetLong("vertices"),
            root.GetLong("line_vertices") + root.GetLong("flats/vertices_added"));
}
