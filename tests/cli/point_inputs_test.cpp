// Point inputs on the command line: what a user sees for a header that lies about its point count,
// coordinates beyond the range, a broken VLR chain, a raster or vector file given as points, a
// PLY TIN given as points, and class filters on XYZ text.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "support/byte_fields.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;
using Outcome = ShellRun;

// Every byte printable ASCII or a line end: no file's binary bytes reach the terminal.
bool printable(const std::string& text) {
  for (const char c : text) {
    if ((c < 0x20 || c > 0x7E) && c != '\n') return false;
  }
  return true;
}

// The vertex count a PLY header states.
std::uint64_t ply_vertices(const std::string& path) {
  const std::string text = slurp(path);
  const std::string key = "element vertex ";
  const std::size_t at = text.find(key);
  return at == std::string::npos ? 0 : std::stoull(text.substr(at + key.size()));
}

// N as the summary writes it: 4,156.
std::string grouped(std::uint64_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out.push_back(',');
    out.push_back(digits[i]);
  }
  return out;
}

const fs::path kData = shared_data();
const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

TEST(PointInputsCli, ALazHeaderCountAboveItsDataIsAnError) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string dir = scratch_dir("point_inputs_cli");
  std::string b = slurp(kData / "laz" / "append-bug.laz");
  ASSERT_EQ(get<std::uint64_t>(b, 247), 37805u);
  put<std::uint64_t>(b, 247, 37806);
  spit(dir + "/more.laz", b);
  // tincdt more.laz -o t.ply
  const Outcome r = run_tincdt(dir, "more.laz -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "more.laz") && has(r, "37,806") && has(r, "37,805")) << r;
  EXPECT_FALSE(fs::exists(dir + "/t.ply"));
}

TEST(PointInputsCli, ALasHeaderCountIntoItsExtendedVlrsIsAnError) {
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("point_inputs_cli");
  std::string b = slurp(kData / "las" / "1_4_w_evlr.las");
  put<std::uint64_t>(b, 247, get<std::uint64_t>(b, 247) + 1);
  spit(dir + "/more.las", b);
  // tincdt more.las -o t.ply
  const Outcome r = run_tincdt(dir, "more.las -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "more.las") && has(r, "1,001") && has(r, "1,000 records")) << r;
}

TEST(PointInputsCli, AHugeScaleIsAnErrorNamingTheHeaderField) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string dir = scratch_dir("point_inputs_cli");
  for (const char* name : {"simple.las", "simple.laz"}) {
    SCOPED_TRACE(name);
    std::string b = slurp(kData / (std::string(name) == "simple.las" ? "las" : "laz") / name);
    put<double>(b, 131, 1e300);  // X scale factor
    spit(dir + "/" + name, b);
    // tincdt simple.laz -o t.ply
    const Outcome r = run_tincdt(dir, std::string(name) + " -o t.ply");
    EXPECT_EQ(r.exit_code, 1) << r;
    EXPECT_TRUE(has(r, name) && has(r, "X scale factor") && has(r, "1e15")) << r;
  }
}

TEST(PointInputsCli, AVlrRunningPastThePointDataIsAWarningAndItsCrsKept) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string dir = scratch_dir("point_inputs_cli");
  std::string b = slurp(kData / "laz" / "simple.copc.laz");
  // The last VLR, the WKT, claims more bytes than lie before the point data.
  std::size_t pos = get<std::uint16_t>(b, 94);
  for (std::uint32_t i = 0; i + 1 < get<std::uint32_t>(b, 100); ++i)
    pos += 54 + get<std::uint16_t>(b, pos + 20);
  ASSERT_EQ(get<std::uint16_t>(b, pos + 18), 2112);
  put<std::uint16_t>(b, pos + 20, 60000);
  spit(dir + "/long_vlr.laz", b);
  // tincdt long_vlr.laz -o t.ply
  const Outcome r = run_tincdt(dir, "long_vlr.laz -o t.ply");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "long_vlr.laz: variable length record 2")) << r;
  EXPECT_TRUE(fs::exists(dir + "/t.prj")) << r;  // the CRS was kept
}

TEST(PointInputsCli, RastersAndVectorFilesAsPointsAreNamedErrors) {
  TINCDT_REQUIRE_SHARED_DATA("dem");
  const std::string dir = scratch_dir("point_inputs_cli");
  spit(dir + "/lines.geojson",
       R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": )"
       R"({"type": "LineString", "coordinates": [[0, 0, 1], [1, 1, 1]]}}]})");
  struct Case {
    std::string input;
    std::string kind;
    bool vector;
  };
  const Case cases[] = {
      {(kData / "dem" / "elev_lux.tif").string(), "TIFF", false},
      {(kData / "contours" / "elev_lux_contours_25m.shp").string(), "shapefile", true},
      {(kData / "contours" / "elev_vinschgau_contours_100m.gpkg").string(), "GeoPackage", true},
      {"lines.geojson", "GeoJSON", true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.input);
    // tincdt elev_lux.tif -o t.ply
    const Outcome r = run_tincdt(dir, "'" + c.input + "' -o t.ply");
    EXPECT_EQ(r.exit_code, 1) << r;
    EXPECT_TRUE(has(r, c.kind) && has(r, "not a point file")) << r;
    EXPECT_EQ(has(r, "--contours"), c.vector) << r;
    EXPECT_TRUE(printable(r.messages)) << r;
  }
}

TEST(PointInputsCli, APlyTinIsAPointInput) {
  const std::string dir = scratch_dir("point_inputs_cli");
  // tincdt sample.las -o tin.ply, then tincdt tin.ply -o again.ply (binary and ASCII)
  ASSERT_EQ(run_tincdt(dir, "'" + kSample + "' -o tin.ply").exit_code, 0);
  ASSERT_EQ(run_tincdt(dir, "'" + kSample + "' -o tin_ascii.ply --ply-ascii").exit_code, 0);
  const std::uint64_t vertices = ply_vertices(dir + "/tin.ply");
  ASSERT_GT(vertices, 3u);
  for (const char* input : {"tin.ply", "tin_ascii.ply"}) {
    SCOPED_TRACE(input);
    const Outcome r = run_tincdt(dir, std::string(input) + " -o again.ply --overwrite");
    EXPECT_EQ(r.exit_code, 0) << r;
    EXPECT_EQ(ply_vertices(dir + "/again.ply"), vertices) << r;
    EXPECT_TRUE(has(r, "read " + grouped(vertices) + " points")) << r;
  }
}

TEST(PointInputsCli, ClassFiltersOnXyzText) {
  const std::string dir = scratch_dir("point_inputs_cli");
  std::string csv = "X,Y,Z,Classification\n";
  int ground = 0;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      const int cls = (i + j) % 3 == 0 ? 1 : 2;
      ground += cls == 2;
      csv += std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(i * j % 7) + "," +
             std::to_string(cls) + "\n";
    }
  }
  spit(dir + "/points.csv", csv);
  spit(dir + "/plain.xyz", "0 0 1\n1 0 2\n0 1 3\n1 1 4\n");
  // tincdt points.csv --keep-class 2 -o t.ply
  Outcome r = run_tincdt(dir, "points.csv --keep-class 2 -o t.ply");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "kept " + grouped(static_cast<std::uint64_t>(ground)))) << r;
  EXPECT_EQ(ply_vertices(dir + "/t.ply"), static_cast<std::uint64_t>(ground)) << r;
  // tincdt plain.xyz --keep-class 2 -o u.ply
  r = run_tincdt(dir, "plain.xyz --keep-class 2 -o u.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "plain.xyz") && has(r, "no classification column") && has(r, "--keep-class"))
      << r;
  // tincdt points.csv --first-only -o u.ply
  r = run_tincdt(dir, "points.csv --first-only -o u.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "points.csv") && has(r, "no return numbers") && has(r, "--first-only")) << r;
  EXPECT_FALSE(fs::exists(dir + "/u.ply"));
}

}  // namespace
}  // namespace tincdt::test
