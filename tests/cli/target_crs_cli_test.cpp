// --t-srs from the command line: every input is transformed into the target CRS as it is read,
// before the TIN is made, and every output (each TIN format, the DEM, the contour lines, --stats,
// the log) is in it, in its units; a geographic target is refused unless --allow-geographic; an
// input with no CRS is refused (--a-srs gives it one); a tile job refuses a target other than the
// plan's CRS. The sample data is in UTM zone 32N (EPSG:32632); PROJ, called here, is the reference.
#include <cpl_json.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_spatialref.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/proj_transform.hpp"
#include "support/stats_json.hpp"
#include "support/tincdt_run.hpp"
#include "support/vector_files.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(TINCDT_SOURCE_DIR) / "data";
const std::string kSample = quoted(kData / "sample.las");
const std::string kContours = quoted(kData / "sample_contours.shp");

using XY = std::array<double, 2>;

struct Box {
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY;
  void add(const XY& p) {
    min_x = std::min(min_x, p[0]);
    min_y = std::min(min_y, p[1]);
    max_x = std::max(max_x, p[0]);
    max_y = std::max(max_y, p[1]);
  }
};

// The sample's extent (its four corner points are in it) in EPSG:TO: the box of the corners
// transformed, which the TIN's vertices fill (160 m edges bend by far less than a millimetre).
Box sample_extent_in(int to) {
  Box box;
  for (const XY& corner :
       {XY{600200, 5190300}, XY{600360, 5190300}, XY{600360, 5190420}, XY{600200, 5190420}})
    box.add(proj_transform(32632, to, corner));
  return box;
}

void expect_extent_near(const Box& got, const Box& want, double tolerance) {
  EXPECT_NEAR(got.min_x, want.min_x, tolerance);
  EXPECT_NEAR(got.min_y, want.min_y, tolerance);
  EXPECT_NEAR(got.max_x, want.max_x, tolerance);
  EXPECT_NEAR(got.max_y, want.max_y, tolerance);
}

// "EPSG:n" of a CRS given as WKT (OGC or ESRI, a .prj's text), "" when PROJ finds no EPSG code.
std::string epsg_of(const std::string& wkt) {
  OGRSpatialReference srs;
  if (wkt.empty() || srs.SetFromUserInput(wkt.c_str()) != OGRERR_NONE) return "";
  if (srs.GetAuthorityCode(nullptr) == nullptr) {
    OGRSpatialReference* match = srs.FindBestMatch(70, "EPSG");
    if (match == nullptr) return "";
    srs = *match;
    match->Release();
  }
  const char* code = srs.GetAuthorityCode(nullptr);
  return code != nullptr ? std::string("EPSG:") + code : "";
}

// The CRS of the first layer of the vector file PATH, and the layer's extent.
std::pair<std::string, Box> layer_crs_and_extent(const std::string& path, const char* driver) {
  const VectorFile file(path, driver);
  EXPECT_NE(file.ds, nullptr) << path;
  if (file.ds == nullptr) return {};
  OGREnvelope e;
  EXPECT_EQ(OGR_L_GetExtent(file.layer(), &e, 1), OGRERR_NONE) << path;
  return {layer_crs_code(file.layer()), Box{e.MinX, e.MinY, e.MaxX, e.MaxY}};
}

// For each vertex of A, the distance to the nearest of B's vertices (searched in a grid of 1 cm
// cells, so anything farther counts as infinite), and the largest of them.
double farthest_unmatched(const std::vector<std::array<double, 3>>& a,
                          const std::vector<std::array<double, 3>>& b) {
  constexpr double kCell = 0.01;
  const auto cell = [](double v) { return static_cast<long long>(std::floor(v / kCell)); };
  std::map<std::pair<long long, long long>, std::vector<std::size_t>> grid;
  for (std::size_t j = 0; j < b.size(); ++j) grid[{cell(b[j][0]), cell(b[j][1])}].push_back(j);
  double worst = 0;
  for (const auto& p : a) {
    double best = INFINITY;
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({cell(p[0]) + dx, cell(p[1]) + dy});
        if (it == grid.end()) continue;
        for (const std::size_t j : it->second)
          if (b[j][2] == p[2]) best = std::min(best, std::hypot(p[0] - b[j][0], p[1] - b[j][1]));
      }
    worst = std::max(worst, best);
  }
  return worst;
}

// The vertices of MESH (in EPSG:FROM) transformed by PROJ into EPSG:TO, z as it is.
std::vector<std::array<double, 3>> transformed(const MeshFile& mesh, int from, int to) {
  std::vector<std::array<double, 3>> out;
  for (const auto& v : mesh.v) {
    const XY p = proj_transform(from, to, {v[0], v[1]});
    out.push_back({p[0], p[1], v[2]});
  }
  return out;
}

// Each output's kind and CRS label in the --stats document at PATH.
std::map<std::string, std::string> output_crs(const std::string& stats_path) {
  CPLJSONDocument doc;
  std::map<std::string, std::string> out;
  EXPECT_TRUE(doc.LoadMemory(slurp(stats_path))) << stats_path;
  for (const CPLJSONObject& o : doc.GetRoot().GetArray("outputs"))
    out[o.GetString("kind")] = o.GetString("crs", "(none)");
  return out;
}

// Every TIN format in the target CRS: a .prj beside OBJ, PLY and STL, the CRS in the file for the
// others, the log and --stats; GeoJSON and GeoPackage read back by OGR span the sample's extent
// transformed by PROJ.
TEST(TargetCrsCli, EveryTinFormatIsInTheTargetCrs) {
  const std::string dir = scratch_dir("target_crs_cli");
  const Box want = sample_extent_in(32633);
  for (const char* const ext_name : {"ply", "obj", "stl", "geojson", "xml", "gpkg", "glb"}) {
    const std::string ext = ext_name;
    SCOPED_TRACE(ext);
    const std::string out = "t." + ext;
    const ShellRun r =
        run_tincdt(dir, kSample + " --t-srs EPSG:32633 -o " + out + " --stats s.json --overwrite");
    ASSERT_EQ(r.exit_code, 0) << r;
    EXPECT_TRUE(has(r, "sample.las: transformed from EPSG:32632 to EPSG:32633 (the target CRS)"))
        << r;
    EXPECT_TRUE(has(r, "wrote " + out + " (")) << r;
    EXPECT_TRUE(has(r, "CRS EPSG:32633")) << r;
    EXPECT_EQ(StatsJson(slurp(dir + "/s.json")).text("crs").value_or(""), "EPSG:32633");
    EXPECT_EQ(output_crs(dir + "/s.json")["tin"], "EPSG:32633");
    const std::string bytes = slurp(fs::path(dir) / out);
    if (ext == "ply" || ext == "obj" || ext == "stl") {
      EXPECT_EQ(epsg_of(slurp(fs::path(dir) / "t.prj")), "EPSG:32633");
      fs::remove(fs::path(dir) / "t.prj");
    } else if (ext == "geojson" || ext == "gpkg") {
      const auto [crs, extent] =
          layer_crs_and_extent(dir + "/" + out, ext == "gpkg" ? "GPKG" : "GeoJSON");
      EXPECT_EQ(crs, "EPSG:32633");
      expect_extent_near(extent, want, 0.001);
    } else if (ext == "xml") {
      EXPECT_NE(bytes.find("epsgCode=\"32633\""), std::string::npos) << bytes.substr(0, 2000);
    } else {
      EXPECT_NE(bytes.find("\"crs\":\"EPSG:32633\""), std::string::npos);
    }
  }
}

// The acceptance case: each vertex of the TIN made in the target CRS is an input point transformed
// by PROJ, within 1 mm, with its height unchanged (metres in both).
TEST(TargetCrsCli, VerticesAreTheInputPointsTransformedByProj) {
  const std::string dir = scratch_dir("target_crs_cli");
  expect_success(dir, kSample + " -o same.ply --ply-ascii");
  expect_success(dir, kSample + " --t-srs EPSG:3857 -o t.ply --ply-ascii");
  const MeshFile same = read_ply_ascii(fs::path(dir) / "same.ply");
  const MeshFile target = read_ply_ascii(fs::path(dir) / "t.ply");
  ASSERT_GT(same.v.size(), 4000u);
  EXPECT_EQ(target.v.size(), same.v.size());
  EXPECT_LT(farthest_unmatched(transformed(same, 32632, 3857), target.v), 0.001);
  EXPECT_GT(target.v.front()[0], 1.1e6);  // Web Mercator metres, not UTM's 600 km
}

// The DEM, the contour lines, the constrained edges and the diagnostics are in the target CRS, and
// --resolution in its units: Web Mercator stretches the sample's 160 m x 120 m by
// 1 / cos(46.86 deg), so 2 m cells are about 117 across, not 80.
TEST(TargetCrsCli, DemAndContoursAreInTheTargetCrsAndItsUnits) {
  const std::string dir = scratch_dir("target_crs_cli");
  const ShellRun r = run_tincdt(dir, kSample + " --contours " + kContours +
                                         " --t-srs EPSG:3857 -o t.ply --dem d.tif --resolution 2 "
                                         "--contour-lines c.gpkg --interval 2 --stats s.json "
                                         "--constraints-out k.geojson --diagnostics g.gpkg");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(
      has(r, "sample_contours.shp: transformed from EPSG:32632 to EPSG:3857 (the target CRS)"))
      << r;
  const Box want = sample_extent_in(3857);
  GDALAllRegister();
  GDALDataset* dem = GDALDataset::FromHandle(GDALOpen((dir + "/d.tif").c_str(), GA_ReadOnly));
  ASSERT_NE(dem, nullptr);
  const OGRSpatialReference* srs = dem->GetSpatialRef();
  ASSERT_NE(srs, nullptr);
  char* wkt = nullptr;
  srs->exportToWkt(&wkt);
  EXPECT_EQ(epsg_of(wkt), "EPSG:3857");
  CPLFree(wkt);
  double gt[6];
  ASSERT_EQ(dem->GetGeoTransform(gt), CE_None);
  EXPECT_EQ(gt[1], 2.0);
  EXPECT_EQ(gt[5], -2.0);
  EXPECT_NEAR(gt[0], want.min_x, 2.0);
  EXPECT_NEAR(gt[3], want.max_y, 2.0);
  EXPECT_NEAR(dem->GetRasterXSize(), (want.max_x - want.min_x) / 2, 1.5);
  EXPECT_GT(dem->GetRasterXSize(), 110);
  GDALClose(dem);
  const auto [crs, extent] = layer_crs_and_extent(dir + "/c.gpkg", "GPKG");
  EXPECT_EQ(crs, "EPSG:3857");
  EXPECT_GE(extent.min_x, want.min_x);
  EXPECT_LE(extent.max_x, want.max_x);
  EXPECT_GE(extent.min_y, want.min_y);
  EXPECT_LE(extent.max_y, want.max_y);
  EXPECT_EQ(layer_crs_and_extent(dir + "/k.geojson", "GeoJSON").first, "EPSG:3857");
  const VectorFile diagnostics(dir + "/g.gpkg", "GPKG");
  ASSERT_NE(diagnostics.ds, nullptr);
  EXPECT_EQ(layer_crs_code(diagnostics.layer()), "EPSG:3857");
  for (const auto& [kind, label] : output_crs(dir + "/s.json"))
    EXPECT_EQ(label, "EPSG:3857") << kind;
  EXPECT_EQ(StatsJson(slurp(dir + "/s.json")).text("crs").value_or(""), "EPSG:3857");
}

// Degrees make a distorted TIN: refused before any work, with the way out; allowed, the TIN is in
// longitude and latitude.
TEST(TargetCrsCli, AGeographicTargetIsRefusedUnlessAllowed) {
  const std::string dir = scratch_dir("target_crs_cli");
  const ShellRun refused = run_tincdt(dir, kSample + " --t-srs EPSG:4326 -o t.ply");
  EXPECT_EQ(refused.exit_code, 2) << refused;
  for (const char* text : {"--t-srs: 'EPSG:4326' is geographic (degrees)", "distorted",
                           "projected CRS (e.g. the data's UTM zone)", "--allow-geographic"})
    EXPECT_TRUE(has(refused, text)) << text << "\n" << refused;
  EXPECT_EQ(names_in(dir), std::set<std::string>{});

  const ShellRun allowed =
      run_tincdt(dir, kSample + " --t-srs EPSG:4326 --allow-geographic -o t.ply --ply-ascii");
  ASSERT_EQ(allowed.exit_code, 0) << allowed;
  EXPECT_FALSE(has(allowed, "warning")) << allowed;
  EXPECT_EQ(epsg_of(slurp(fs::path(dir) / "t.prj")), "EPSG:4326");
  const MeshFile tin = read_ply_ascii(fs::path(dir) / "t.ply");
  ASSERT_FALSE(tin.v.empty());
  const XY corner = proj_transform(32632, 4326, {600200, 5190300});
  double nearest = INFINITY;
  for (const auto& v : tin.v) {
    EXPECT_NEAR(v[0], 10.31, 0.01);
    EXPECT_NEAR(v[1], 46.86, 0.01);
    nearest = std::min(nearest, std::hypot(v[0] - corner[0], v[1] - corner[1]));
  }
  EXPECT_LT(nearest, 1e-8);  // about 1 mm in degrees

  const ShellRun ignored = run_tincdt(dir, kSample + " --allow-geographic -o u.ply");
  EXPECT_EQ(ignored.exit_code, 0) << ignored;
  EXPECT_TRUE(has(ignored, "warning: --allow-geographic is ignored: there is no --t-srs"))
      << ignored;
}

// Points in UTM 32N with no CRS in the file.
const char* const kXyz =
    "600200 5190300 1480\n600360 5190300 1490\n600360 5190420 1500\n"
    "600200 5190420 1495\n600280 5190360 1488\n";

// An input without a CRS cannot be transformed: the error names it and --a-srs; with --a-srs it
// is transformed from that CRS.
TEST(TargetCrsCli, AnInputWithoutCrsNeedsASrs) {
  const std::string dir = scratch_dir("target_crs_cli");
  spit(fs::path(dir) / "a.xyz", kXyz);
  for (const std::string& inputs : {std::string("a.xyz"), kSample + " a.xyz"}) {
    SCOPED_TRACE(inputs);
    const ShellRun r = run_tincdt(dir, inputs + " --t-srs EPSG:32633 -o t.ply");
    EXPECT_EQ(r.exit_code, 1) << r;
    EXPECT_TRUE(has(r,
                    "a.xyz: no CRS in the file, so it cannot be transformed into the target "
                    "CRS EPSG:32633"))
        << r;
    EXPECT_TRUE(has(r, "--a-srs")) << r;
    EXPECT_EQ(names_in(dir), std::set<std::string>{"a.xyz"});
  }
  const ShellRun r =
      run_tincdt(dir, "a.xyz --a-srs EPSG:32632 --t-srs EPSG:32633 -o t.ply --ply-ascii");
  ASSERT_EQ(r.exit_code, 0) << r;
  const MeshFile tin = read_ply_ascii(fs::path(dir) / "t.ply");
  ASSERT_EQ(tin.v.size(), 5u);
  MeshFile given;
  given.v = {{600200, 5190300, 1480},
             {600360, 5190300, 1490},
             {600360, 5190420, 1500},
             {600200, 5190420, 1495},
             {600280, 5190360, 1488}};
  EXPECT_LT(farthest_unmatched(transformed(given, 32632, 32633), tin.v), 0.001);
}

// A GeoJSON file that names no CRS, alone, is in its format's default (WGS 84 longitude and
// latitude), transformed from it into the target.
TEST(TargetCrsCli, AGeoJsonNamingNoCrsIsTransformedFromItsDefault) {
  const std::string dir = scratch_dir("target_crs_cli");
  MeshFile given;
  given.v = {{600200, 5190300, 1480},
             {600360, 5190310, 1490},
             {600350, 5190420, 1500},
             {600210, 5190400, 1495}};
  std::string coordinates;
  for (const auto& v : given.v) {
    const XY p = proj_transform(32632, 4326, {v[0], v[1]});
    char text[96];
    std::snprintf(text, sizeof text, "%s[%.17g, %.17g, %.17g]", coordinates.empty() ? "" : ", ",
                  p[0], p[1], v[2]);
    coordinates += text;
  }
  spit(fs::path(dir) / "line.geojson",
       R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},)"
       R"( "geometry": {"type": "LineString", "coordinates": [)" +
           coordinates + "]}}]}");
  const ShellRun r =
      run_tincdt(dir, "--hard-lines line.geojson --t-srs EPSG:32632 -o t.ply --ply-ascii");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "line.geojson: transformed from EPSG:4979 to EPSG:32632 (the target CRS)"))
      << r;
  const MeshFile tin = read_ply_ascii(fs::path(dir) / "t.ply");
  EXPECT_EQ(tin.v.size(), given.v.size());
  EXPECT_LT(farthest_unmatched(given.v, tin.v), 0.001);
}

// --override-srs takes every input as in its CRS, then --t-srs transforms from it.
TEST(TargetCrsCli, OverrideSrsThenTransform) {
  const std::string dir = scratch_dir("target_crs_cli");
  expect_success(dir, kSample + " -o same.ply --ply-ascii");
  const ShellRun r = run_tincdt(
      dir, kSample + " --override-srs EPSG:32633 --t-srs EPSG:32632 -o t.ply --ply-ascii");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "transformed from EPSG:32633 to EPSG:32632 (the target CRS)")) << r;
  const MeshFile same = read_ply_ascii(fs::path(dir) / "same.ply");
  const MeshFile tin = read_ply_ascii(fs::path(dir) / "t.ply");
  EXPECT_EQ(tin.v.size(), same.v.size());
  EXPECT_LT(farthest_unmatched(transformed(same, 32633, 32632), tin.v), 0.001);
}

// --offset is in the target CRS: auto is the transformed data's corner rounded down to 1000.
TEST(TargetCrsCli, OffsetIsInTheTargetCrs) {
  const std::string dir = scratch_dir("target_crs_cli");
  const ShellRun r = run_tincdt(dir, kSample + " --t-srs EPSG:32633 --offset auto -o t.ply");
  ASSERT_EQ(r.exit_code, 0) << r;
  const Box want = sample_extent_in(32633);
  char line[96];
  std::snprintf(line, sizeof line, "comment offset %.17g %.17g 0",
                std::floor(want.min_x / 1000) * 1000, std::floor(want.min_y / 1000) * 1000);
  EXPECT_NE(ply_header(fs::path(dir) / "t.ply").find(line), std::string::npos)
      << line << "\n"
      << ply_header(fs::path(dir) / "t.ply");
}

// The inputs' own CRS as the target transforms nothing: the same bytes as without --t-srs.
TEST(TargetCrsCli, TheInputsCrsAsTargetChangesNothing) {
  const std::string dir = scratch_dir("target_crs_cli");
  expect_success(dir, kSample + " --contours " + kContours + " -o a.ply");
  const ShellRun r =
      run_tincdt(dir, kSample + " --contours " + kContours + " --t-srs EPSG:32632 -o b.ply");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_FALSE(has(r, "transformed")) << r;
  EXPECT_EQ(slurp(fs::path(dir) / "a.ply"), slurp(fs::path(dir) / "b.ply"));
}

// A tile job reads by the plan's boxes, in the inputs' CRS: another target is refused, with the
// way out (merge, then transform the merged TIN); the plan's own CRS is accepted.
TEST(TargetCrsCli, ATileJobRefusesATargetOtherThanThePlansCrs) {
  const std::string dir = scratch_dir("target_crs_cli");
  expect_success(dir, "plan " + kSample + " --tile-size 100 --buffer 20 -o plan.json");
  const ShellRun r = run_tincdt(dir, "--plan plan.json --tile 0 --t-srs EPSG:32633 -o t0.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "sample.las: CRS EPSG:32632 differs from the target CRS EPSG:32633")) << r;
  EXPECT_TRUE(has(r, "merge the tiles, then transform the merged TIN")) << r;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "t0.ply"));
  expect_success(dir, "--plan plan.json --tile 0 --t-srs EPSG:32632 -o t0.ply");
  EXPECT_TRUE(fs::exists(fs::path(dir) / "t0.ply"));
}

}  // namespace
}  // namespace tincdt::test
