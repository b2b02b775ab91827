// The inputs' CRSs from the command line: an unusable CRS refused before any work, --override-srs
// for a file whose CRS is wrong, --a-srs only for the files without one.
#include <gtest/gtest.h>

#include <cpl_json.h>

#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/stats_json.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;

std::string shared(const std::string& name) {
  return quoted(fs::path(shared_data()) / name);
}

// The "crs" member of the --stats document at PATH.
std::string stats_crs(const std::string& path, const std::string& member = "crs") {
  return StatsJson(slurp(path)).text(member).value_or("(none)");
}

// A GeoJSON feature collection of one line through COORDINATES ("[x, y, z], ..."), naming no CRS.
std::string line_geojson(const std::string& coordinates) {
  return R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},)"
         R"( "geometry": {"type": "LineString", "coordinates": [)" +
         coordinates + "]}}]}";
}

// lone-star.copc.laz is tagged geocentric (EPSG:4978) though its coordinates are projected.
TEST(CrsCli, AGeocentricCrsIsRefusedBeforeAnyWork) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const std::string dir = scratch_dir("crs_cli");
  const ShellRun r = run_tincdt(dir, shared("copc/lone-star.copc.laz") + " -o x.ply -v");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "lone-star.copc.laz: its CRS EPSG:4978 cannot be used: it is geocentric"))
      << r;
  EXPECT_TRUE(has(r, "--override-srs")) << r;
  // Before any work: not a point read (the reader's log line), and nothing written.
  EXPECT_FALSE(has(r, "518,862 points")) << r;
  EXPECT_FALSE(has(r, "518862 points")) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

TEST(CrsCli, OverrideSrsReplacesAWrongCrs) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const std::string dir = scratch_dir("crs_cli");
  const ShellRun r = run_tincdt(dir, shared("copc/lone-star.copc.laz") +
                                         " --override-srs EPSG:32612 -o x.ply --stats s.json");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(fs::exists(fs::path(dir) / "x.ply"));
  EXPECT_NE(slurp(fs::path(dir) / "x.prj").find("UTM_Zone_12N"), std::string::npos)
      << slurp(fs::path(dir) / "x.prj");
  EXPECT_EQ(stats_crs(dir + "/s.json"), "EPSG:32612");
}

// --a-srs is PDAL's default_srs: a file's own CRS is kept.
TEST(CrsCli, ASrsGivesACrsOnlyToFilesWithoutOne) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("crs_cli");
  const ShellRun own =
      run_tincdt(dir, shared("las/Topography.las") + " --a-srs EPSG:32612 -o a.ply --stats a.json");
  ASSERT_EQ(own.exit_code, 0) << own;
  EXPECT_EQ(stats_crs(dir + "/a.json"), "EPSG:2949");
  const ShellRun none =
      run_tincdt(dir, shared("las/simple.las") + " --a-srs EPSG:32612 -o b.ply --stats b.json");
  ASSERT_EQ(none.exit_code, 0) << none;
  EXPECT_EQ(stats_crs(dir + "/b.json"), "EPSG:32612");
  const ShellRun over = run_tincdt(
      dir, shared("las/Topography.las") + " --override-srs EPSG:32612 -o c.ply --stats c.json");
  ASSERT_EQ(over.exit_code, 0) << over;
  EXPECT_EQ(stats_crs(dir + "/c.json"), "EPSG:32612");
}

TEST(CrsCli, UnusableOrConflictingCrsOptionsAreUsageErrors) {
  const std::string dir = scratch_dir("crs_cli");
  const std::string xyz = quoted(fs::path(TINCDT_SOURCE_DIR) / "data" / "sample.las");
  const ShellRun geocentric = run_tincdt(dir, xyz + " --override-srs EPSG:4978 -o t.ply");
  EXPECT_EQ(geocentric.exit_code, 2) << geocentric;
  EXPECT_TRUE(has(geocentric, "--override-srs")) << geocentric;
  EXPECT_TRUE(has(geocentric, "geocentric")) << geocentric;
  const ShellRun both =
      run_tincdt(dir, xyz + " --a-srs EPSG:32633 --override-srs EPSG:32633 -o t.ply");
  EXPECT_EQ(both.exit_code, 2) << both;
  EXPECT_TRUE(has(both, "--a-srs and --override-srs exclude each other")) << both;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

// simple.las has no CRS; Topography.las is in EPSG:2949, 4,400 km away from it.
TEST(CrsCli, AFileWithoutCrsAmongFilesWithOneIsAnErrorBeforeAnyWork) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("crs_cli");
  const ShellRun r = run_tincdt(
      dir, shared("las/Topography.las") + " " + shared("las/simple.las") + " -o t.ply -v");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "simple.las: no CRS in the file, while ")) << r;
  EXPECT_TRUE(has(r, "Topography.las is in EPSG:2949")) << r;
  EXPECT_TRUE(has(r, "with --a-srs")) << r;
  EXPECT_FALSE(has(r, "73,403 points")) << r;  // before any point is read
  EXPECT_FALSE(has(r, "73403 points")) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

// XYZ text tells that it has no CRS only when read: the error comes after reading it, before the
// TIN; --a-srs says which CRS it is in.
TEST(CrsCli, XyzWithoutCrsBesideALasFileNeedsASrs) {
  TINCDT_REQUIRE_SHARED_DATA("xyz");
  const std::string dir = scratch_dir("crs_cli");
  const std::string inputs =
      shared("las/Topography.las") + " " + shared("xyz/Topography_ground.xyz");
  const ShellRun refused = run_tincdt(dir, inputs + " -o t.ply");
  EXPECT_EQ(refused.exit_code, 1) << refused;
  EXPECT_TRUE(has(refused, "Topography_ground.xyz: no CRS in the file")) << refused;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
  const ShellRun given = run_tincdt(dir, inputs + " --a-srs EPSG:2949 -o t.ply --stats s.json");
  ASSERT_EQ(given.exit_code, 0) << given;
  EXPECT_FALSE(has(given, "warning")) << given;
  EXPECT_EQ(stats_crs(dir + "/s.json"), "EPSG:2949");
}

// A GeoJSON file that names no CRS is in WGS 84 only by its format's default: beside a LAS file
// in EPSG:2949 it is refused, not taken in either CRS.
TEST(CrsCli, AGeoJsonNamingNoCrsBesideALasFileNeedsASrs) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("crs_cli");
  spit(fs::path(dir) / "line.geojson",
       line_geojson("[273400, 5274400, 800], [273600, 5274600, 800]"));
  const ShellRun r =
      run_tincdt(dir, shared("las/Topography.las") + " --hard-lines line.geojson -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "line.geojson: the file names no CRS")) << r;
  EXPECT_TRUE(has(r, "with --a-srs")) << r;
  EXPECT_EQ(names_in(dir), std::set<std::string>{"line.geojson"});
  const ShellRun given = run_tincdt(
      dir, shared("las/Topography.las") + " --hard-lines line.geojson --a-srs EPSG:2949 -o t.ply");
  EXPECT_EQ(given.exit_code, 0) << given;
}

// GeoJSON's default CRS is longitude/latitude: a GeoJSON file that names no CRS, with an XYZ file
// that names none either, is taken in it only when the coordinates can be degrees. With projected
// metres the default is not assumed, saying so and naming the file: the TIN has no CRS, as with
// XYZ files alone, rather than a continent-wide one in degrees.
TEST(CrsCli, ProjectedCoordinatesAreNotTakenInGeoJsonsDefault) {
  const std::string dir = scratch_dir("crs_cli");
  spit(fs::path(dir) / "points.xyz",
       "500000 4000000 10\n500100 4000000 11\n500000 4000100 12\n500100 4000100 13\n");
  spit(fs::path(dir) / "line.geojson",
       line_geojson("[500010, 4000010, 11], [500090, 4000090, 12]"));
  const ShellRun r =
      run_tincdt(dir, "points.xyz --hard-lines line.geojson -o t.ply --stats s.json");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r,
                  "points.xyz: no CRS in the file, and its coordinates (x 500,000 to 500,100, "
                  "y 4,000,000 to 4,000,100) are not longitudes and latitudes: the default of "))
      << r;
  EXPECT_TRUE(has(r, "line.geojson, EPSG:4979, is not assumed, and the TIN has no CRS")) << r;
  EXPECT_FALSE(has(r, "assuming")) << r;
  EXPECT_EQ(stats_crs(dir + "/s.json"), "");  // the stats name no CRS
  EXPECT_FALSE(fs::exists(fs::path(dir) / "t.prj"));
  // The GeoJSON file's own coordinates, beside points in degrees:
  spit(fs::path(dir) / "lonlat.xyz", "7 45 1\n7.001 45 2\n7 45.001 3\n7.001 45.001 4\n");
  const ShellRun own = run_tincdt(dir, "lonlat.xyz --hard-lines line.geojson -o o.ply");
  EXPECT_TRUE(has(own, "line.geojson: no CRS in the file, and its coordinates")) << own;
  EXPECT_TRUE(has(own, "its format's default EPSG:4979, is not assumed")) << own;
  // Nor is it transformed from that default into a target CRS: refused, naming the file.
  const ShellRun target = run_tincdt(dir, "--contours line.geojson --t-srs EPSG:32632 -o g.ply");
  EXPECT_EQ(target.exit_code, 1) << target;
  EXPECT_TRUE(has(target,
                  "line.geojson: no CRS in the file, and its coordinates (x 500,010 to "
                  "500,090, y 4,000,010 to 4,000,090) are not longitudes and latitudes: "
                  "its format's default EPSG:4979, is not assumed, so it cannot be "
                  "transformed into the target CRS EPSG:32632"))
      << target;
  // Degrees in both files: GeoJSON's default is taken, with the warning for the XYZ file.
  spit(fs::path(dir) / "deg.geojson", line_geojson("[7.0002, 45.0002, 2], [7.0008, 45.0008, 3]"));
  const ShellRun degrees =
      run_tincdt(dir, "lonlat.xyz --hard-lines deg.geojson -o d.ply --stats d.json");
  EXPECT_EQ(degrees.exit_code, 0) << degrees;
  EXPECT_TRUE(has(degrees, "lonlat.xyz: no CRS in the file; assuming EPSG:4979")) << degrees;
  EXPECT_EQ(stats_crs(dir + "/d.json"), "EPSG:4979");
}

// The CRS of each output of --stats, by kind: {kind, crs} in the document's order.
std::vector<std::pair<std::string, std::string>> output_crs(const std::string& stats_path) {
  CPLJSONDocument doc;
  std::vector<std::pair<std::string, std::string>> out;
  if (!doc.LoadMemory(slurp(stats_path))) return out;
  for (const CPLJSONObject& o : doc.GetRoot().GetArray("outputs"))
    out.emplace_back(o.GetString("kind"), o.GetString("crs", "(none)"));
  return out;
}

// A run in a fresh scratch folder on the shared file INPUT with ARGS and --stats; STATS is the
// document's path.
struct StatsRun {
  ShellRun run;
  std::string stats;
};
StatsRun run_with_stats(const std::string& input, const std::string& args) {
  const std::string dir = scratch_dir("crs_cli");
  return {run_tincdt(dir, shared(input) + " " + args + " --stats s.json"), dir + "/s.json"};
}

// Outputs without a CRS: one warning for all of them.
TEST(CrsCli, OutputsWithoutCrsAreWarnedAboutOnce) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const auto [r, stats] =
      run_with_stats("las/simple.las",
                     "-o t.ply --dem d.tif --resolution 50 --contour-lines c.gpkg --interval 20");
  ASSERT_EQ(r.exit_code, 0) << r;
  std::size_t warnings = 0;
  for (std::size_t at = r.messages.find("no input has a CRS"); at != std::string::npos;
       at = r.messages.find("no input has a CRS", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << r;
  EXPECT_TRUE(has(r, "the outputs have none (give the inputs' CRS with --a-srs)")) << r;
  for (const auto& [kind, crs] : output_crs(stats)) EXPECT_EQ(crs, "") << kind;
}

// A GeoJSON TIN built with --t-srs is in the target CRS, in the log and in --stats, and so are
// the other outputs.
TEST(CrsCli, EachOutputIsReportedInItsOwnCrs) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const auto [r, stats] =
      run_with_stats("las/Topography.las",
                     "-o t.geojson --t-srs EPSG:4326 --allow-geographic --dem d.tif "
                     "--resolution 0.0001");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "wrote t.geojson (GeoJSON")) << r;
  EXPECT_TRUE(has(r, "CRS EPSG:4326)")) << r;
  EXPECT_FALSE(has(r, "no input has a CRS")) << r;
  const auto outputs = output_crs(stats);
  ASSERT_EQ(outputs.size(), 2u);
  EXPECT_EQ(outputs[0], (std::pair<std::string, std::string>{"tin", "EPSG:4326"}));
  EXPECT_EQ(outputs[1], (std::pair<std::string, std::string>{"dem", "EPSG:4326"}));
  EXPECT_EQ(stats_crs(stats), "EPSG:4326");  // the TIN's
}

}  // namespace
}  // namespace tincdt::test
