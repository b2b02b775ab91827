// Inputs in different CRSs from the command line: each input in another CRS than the job's (the
// first input's) is transformed into it, heights converted between units, with one log line per
// input; a point PROJ cannot transform is an error naming the file and the point; --override-srs
// still takes every input as its CRS, untransformed.
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/proj_transform.hpp"
#include "support/shared_data.hpp"
#include "support/tincdt_run.hpp"
#include "support/vector_files.hpp"

namespace tincdt::test {
namespace {

namespace fs = std::filesystem;

// `ogr2ogr -t_srs EPSG:4326 DST SRC`, through GDAL's library form of ogr2ogr.
void ogr2ogr_to_wgs84(const std::string& src, const std::string& dst) {
  GDALAllRegister();
  GDALDatasetH in = GDALOpenEx(src.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
  ASSERT_NE(in, nullptr) << src;
  CPLStringList args;
  args.AddString("-t_srs");
  args.AddString("EPSG:4326");
  GDALVectorTranslateOptions* options = GDALVectorTranslateOptionsNew(args.List(), nullptr);
  int usage_error = 0;
  GDALDatasetH out = GDALVectorTranslate(dst.c_str(), nullptr, 1, &in, options, &usage_error);
  GDALVectorTranslateOptionsFree(options);
  EXPECT_NE(out, nullptr) << CPLGetLastErrorMsg();
  if (out != nullptr) GDALClose(out);
  GDALClose(in);
}

// The vertices of A matched to B's: for each vertex of A the nearest of B within 1 cm in x, y,
// and the largest distances between matched vertices.
struct VertexMatch {
  std::vector<std::size_t> in_b;  // B's index per vertex of A; SIZE_MAX when none is near
  std::size_t unmatched = 0;
  double max_xy = 0;
  double max_z = 0;
};

VertexMatch match_vertices(const MeshFile& a, const MeshFile& b) {
  constexpr double kCell = 0.01;
  const auto cell = [](double v) { return static_cast<long long>(std::floor(v / kCell)); };
  std::map<std::pair<long long, long long>, std::vector<std::size_t>> grid;
  for (std::size_t j = 0; j < b.v.size(); ++j)
    grid[{cell(b.v[j][0]), cell(b.v[j][1])}].push_back(j);
  VertexMatch m;
  m.in_b.assign(a.v.size(), SIZE_MAX);
  for (std::size_t i = 0; i < a.v.size(); ++i) {
    const auto& p = a.v[i];
    double best = kCell;
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({cell(p[0]) + dx, cell(p[1]) + dy});
        if (it == grid.end()) continue;
        for (const std::size_t j : it->second) {
          const double d = std::hypot(p[0] - b.v[j][0], p[1] - b.v[j][1]);
          if (d < best) {
            best = d;
            m.in_b[i] = j;
          }
        }
      }
    if (m.in_b[i] == SIZE_MAX) {
      ++m.unmatched;
      continue;
    }
    m.max_xy = std::max(m.max_xy, best);
    m.max_z = std::max(m.max_z, std::fabs(p[2] - b.v[m.in_b[i]][2]));
  }
  return m;
}

// B's triangles as sorted vertex triples, and A's through MATCH.
std::set<std::array<std::size_t, 3>> triangles(const MeshFile& mesh,
                                               const std::vector<std::size_t>* match = nullptr) {
  std::set<std::array<std::size_t, 3>> out;
  for (auto t : mesh.f) {
    if (match != nullptr)
      for (auto& v : t) v = (*match)[v];
    std::sort(t.begin(), t.end());
    out.insert(t);
  }
  return out;
}

// The acceptance case: the real LAS (EPSG:2949) with its contours reprojected to WGS 84 gives
// the TIN of the LAS with the original contours, vertex for vertex within 1 mm.
TEST(ReprojectCli, ContoursInWgs84GiveTheSameTinAsInTheLasCrs) {
  TINCDT_REQUIRE_SHARED_DATA("pair_topography");
  TINCDT_REQUIRE_SHARED_DATA("las");
  const std::string dir = scratch_dir("reproject_cli");
  const fs::path data = shared_data();
  const fs::path contours = data / "pair_topography" / "Topography_contours_1m_3d.shp";
  ogr2ogr_to_wgs84(contours.string(), dir + "/contours_4326.shp");
  const std::string las = quoted(data / "las" / "Topography.las");
  const ShellRun wgs84 =
      run_tincdt(dir, las + " --contours contours_4326.shp -o wgs84.ply --ply-ascii");
  ASSERT_EQ(wgs84.exit_code, 0) << wgs84;
  EXPECT_TRUE(has(wgs84, "contours_4326.shp: transformed from EPSG:4326 to EPSG:2949")) << wgs84;
  EXPECT_FALSE(has(wgs84, "heights converted")) << wgs84;  // metres in both
  EXPECT_FALSE(has(wgs84, "warning")) << wgs84;
  const ShellRun same =
      run_tincdt(dir, las + " --contours " + quoted(contours) + " -o same.ply --ply-ascii");
  ASSERT_EQ(same.exit_code, 0) << same;
  EXPECT_FALSE(has(same, "transformed")) << same;

  const MeshFile a = read_ply_ascii(dir + "/wgs84.ply");
  const MeshFile b = read_ply_ascii(dir + "/same.ply");
  ASSERT_EQ(a.v.size(), b.v.size());
  ASSERT_EQ(a.f.size(), b.f.size());
  EXPECT_EQ(a.e.size(), b.e.size());  // the constrained edges
  const VertexMatch m = match_vertices(a, b);
  EXPECT_EQ(m.unmatched, 0u);
  EXPECT_LT(m.max_xy, 1e-3);
  EXPECT_LT(m.max_z, 1e-3);
  EXPECT_EQ(triangles(a, &m.in_b), triangles(b));
  std::printf("max vertex difference: %.3g m in x, y, %.3g m in z\n", m.max_xy, m.max_z);
}

// A grid of points around the box X0..X1, Y0..Y1 (padded by PAD), in XYZ text.
std::string grid_xyz(double x0, double y0, double x1, double y1, double pad) {
  std::string text;
  char line[96];
  for (double y = y0 - pad; y <= y1 + pad; y += 25)
    for (double x = x0 - pad; x <= x1 + pad; x += 25) {
      std::snprintf(line, sizeof line, "%.3f %.3f %.3f\n", x, y, 50 + 0.01 * (x - x0));
      text += line;
    }
  return text;
}

struct LineCase {
  int points_epsg;
  std::vector<std::array<double, 2>> lon_lat;
  double z;  // every vertex's, in metres
};

// DIR/line.gpkg: a layer "line" in EPSG:EPSG of one feature, WKT, its ELEV attribute ELEV.
void write_line_gpkg(const std::string& dir, const std::string& wkt, double elev, int epsg) {
  write_vector(fs::path(dir) / "line.gpkg",
               std::vector<VectorLayer>{{"line", {{.wkt = wkt, .elev = elev}}, epsg}}, "GPKG",
               "NAME");
}

// tincdt in a fresh scratch folder on the points XYZ (points.xyz) and the hard line of
// write_line_gpkg, with the CRS options CRS, into the ASCII PLY t.ply: the folder and the run.
struct PointsAndLineRun {
  std::string dir;
  ShellRun run;
};
PointsAndLineRun run_points_and_line(const std::string& xyz, const std::string& wkt, double elev,
                                     int epsg, const std::string& crs) {
  const std::string dir = scratch_dir("reproject_cli");
  spit(fs::path(dir) / "points.xyz", xyz);
  write_line_gpkg(dir, wkt, elev, epsg);
  return {dir,
          run_tincdt(dir, "points.xyz " + crs + " --hard-lines line.gpkg -o t.ply --ply-ascii")};
}

// The line of CASE in a GeoPackage in EPSG:4326 and a grid of points in the case's CRS (their
// CRS given with --a-srs) around where the line goes in it; returns the line in that CRS.
std::vector<std::array<double, 2>> write_line_case(const std::string& dir, const LineCase& c) {
  std::string wkt = "LINESTRING Z (";
  for (std::size_t i = 0; i < c.lon_lat.size(); ++i) {
    char v[96];
    std::snprintf(v, sizeof v, "%s%.9f %.9f %.3f", i ? ", " : "", c.lon_lat[i][0], c.lon_lat[i][1],
                  c.z);
    wkt += v;
  }
  wkt += ")";
  write_line_gpkg(dir, wkt, c.z, 4326);
  const auto expected = proj_transform(4326, c.points_epsg, c.lon_lat);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& p : expected) {
    x0 = std::min(x0, p[0]);
    y0 = std::min(y0, p[1]);
    x1 = std::max(x1, p[0]);
    y1 = std::max(y1, p[1]);
  }
  spit(fs::path(dir) / "points.xyz", grid_xyz(x0, y0, x1, y1, 200));
  return expected;
}

// The vertex of MESH at X, Y within TOLERANCE, or nullptr.
const std::array<double, 3>* vertex_at(const MeshFile& mesh, const std::array<double, 2>& at,
                                       double tolerance) {
  for (const auto& v : mesh.v)
    if (std::hypot(v[0] - at[0], v[1] - at[1]) <= tolerance) return &v;
  return nullptr;
}

TEST(ReprojectCli, ALineInWgs84ArrivesAtItsUtmCoordinates) {
  const std::string dir = scratch_dir("reproject_cli");
  const LineCase c{32632, {{9.001, 45.001}, {9.004, 45.003}, {9.007, 45.0015}}, 100};
  const auto expected = write_line_case(dir, c);
  const ShellRun r = run_tincdt(
      dir, "points.xyz --a-srs EPSG:32632 --hard-lines line.gpkg -o t.ply --ply-ascii -v");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "line.gpkg: transformed from EPSG:4326 to EPSG:32632 (the CRS of points.xyz)"))
      << r;
  const MeshFile tin = read_ply_ascii(dir + "/t.ply");
  EXPECT_EQ(tin.e.size(), 2u);  // the line's two segments, constrained
  for (const auto& at : expected) {
    const auto* v = vertex_at(tin, at, 1e-6);
    ASSERT_NE(v, nullptr) << "no TIN vertex at " << at[0] << " " << at[1];
    EXPECT_EQ((*v)[2], 100);  // metres in both CRSs
  }
}

// Heights of a CRS in metres go into one in US survey feet as feet.
TEST(ReprojectCli, HeightsAreConvertedBetweenUnits) {
  const std::string dir = scratch_dir("reproject_cli");
  // EPSG:2263: NAD83 / New York Long Island (ftUS).
  const LineCase c{2263, {{-73.985, 40.748}, {-73.982, 40.750}, {-73.979, 40.7485}}, 100};
  const auto expected = write_line_case(dir, c);
  const ShellRun r =
      run_tincdt(dir, "points.xyz --a-srs EPSG:2263 --hard-lines line.gpkg -o t.ply --ply-ascii");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "line.gpkg: transformed from EPSG:4326 to EPSG:2263")) << r;
  EXPECT_TRUE(has(r, "heights converted from metre to US survey foot")) << r;
  const MeshFile tin = read_ply_ascii(dir + "/t.ply");
  for (const auto& at : expected) {
    const auto* v = vertex_at(tin, at, 1e-6);
    ASSERT_NE(v, nullptr) << "no TIN vertex at " << at[0] << " " << at[1];
    EXPECT_NEAR((*v)[2], 100 * 3937.0 / 1200.0, 1e-9);
  }
}

// EPSG:9518 is WGS 84 + EGM2008 height: its heights are not moved to EGM96, and a warning says so.
TEST(ReprojectCli, HeightsAreNotMovedBetweenVerticalDatums) {
  const auto [dir, r] = run_points_and_line(
      "500000 4983000 1\n501000 4983000 3\n500500 4984000 4\n",
      "LINESTRING Z (9.001 45.002 2, 9.005 45.003 2)", 2, 9518, "--a-srs EPSG:32632+5773");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r,
                  "line.gpkg: heights are not transformed between the vertical CRSs (EGM2008 "
                  "height to EGM96 height), only converted in unit"))
      << r;
  const MeshFile tin = read_ply_ascii(dir + "/t.ply");
  std::size_t at_two = 0;
  for (const auto& v : tin.v) at_two += v[2] == 2 ? 1 : 0;
  EXPECT_EQ(at_two, 2u);  // the line's vertices keep their heights
}

// A PLY's vertices in WGS 84 beside points in UTM: latitude 95 cannot be transformed.
TEST(ReprojectCli, APointThatCannotBeTransformedIsNamed) {
  const std::string dir = scratch_dir("reproject_cli");
  spit(fs::path(dir) / "points.xyz", "500000 4983000 1\n501000 4983000 2\n500500 4984000 3\n");
  spit(fs::path(dir) / "wgs84.ply",
       "ply\nformat ascii 1.0\ncomment crs EPSG:4326\nelement vertex 3\nproperty double x\n"
       "property double y\nproperty double z\nend_header\n9 45 1\n9.01 45 2\n9 95 3\n");
  const ShellRun r = run_tincdt(dir, "points.xyz --a-srs EPSG:32632 wgs84.ply -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r,
                  "wgs84.ply: point 2: at 9 95: cannot be transformed from EPSG:4326 to "
                  "EPSG:32632"))
      << r;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "t.ply"));
}

// 160,000 points in UTM zone 33 beside points in zone 32: transformed on several threads, each
// with its own transformation, to the same TIN as on one, at the places PROJ gives.
TEST(ReprojectCli, PointsTransformedOnSeveralThreadsGiveTheSameTin) {
  const std::string dir = scratch_dir("reproject_cli");
  constexpr int kSide = 400;
  constexpr double kX0 = 263000, kY0 = 4986000;
  std::string ply = "ply\nformat ascii 1.0\ncomment crs EPSG:32633\nelement vertex " +
                    std::to_string(kSide * kSide) +
                    "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  char line[96];
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      std::snprintf(line, sizeof line, "%.2f %.2f %.2f\n", kX0 + 2.0 * i + 0.25 * (j % 3),
                    kY0 + 2.0 * j, 100 + 0.1 * i);
      ply += line;
    }
  spit(fs::path(dir) / "zone33.ply", ply);
  const auto corners = proj_transform(32633, 32632, {{kX0, kY0}, {kX0 + 2.0 * (kSide - 1), kY0}});
  ASSERT_EQ(corners.size(), 2u);
  std::string xyz;
  for (const auto& c : corners) {
    std::snprintf(line, sizeof line, "%.3f %.3f 90\n", c[0], c[1] - 50);
    xyz += line;
  }
  spit(fs::path(dir) / "zone32.xyz", xyz);
  const std::string args = "zone32.xyz --a-srs EPSG:32632 zone33.ply --ply-ascii";
  const ShellRun one = run_tincdt(dir, args + " -o one.ply --threads 1");
  ASSERT_EQ(one.exit_code, 0) << one;
  EXPECT_TRUE(has(one, "zone33.ply: transformed from EPSG:32633 to EPSG:32632")) << one;
  const ShellRun three = run_tincdt(dir, args + " -o three.ply --threads 3");
  ASSERT_EQ(three.exit_code, 0) << three;
  EXPECT_EQ(slurp(fs::path(dir) / "one.ply"), slurp(fs::path(dir) / "three.ply"));
  const MeshFile tin = read_ply_ascii(dir + "/three.ply");
  EXPECT_EQ(tin.v.size(), std::size_t{kSide * kSide + 2});
  for (const auto& at : corners) EXPECT_NE(vertex_at(tin, at, 1e-6), nullptr) << at[0];
}

// --override-srs takes every input as its CRS: the line's degrees stay numbers, untransformed.
TEST(ReprojectCli, OverrideSrsDoesNotTransform) {
  const auto [dir, r] =
      run_points_and_line("8 44 1\n10 44 2\n9 46 3\n", "LINESTRING Z (9 44.5 5, 9.2 45 6)", 5, 4326,
                          "--override-srs EPSG:32632");
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_FALSE(has(r, "transformed")) << r;
  const MeshFile tin = read_ply_ascii(dir + "/t.ply");
  EXPECT_NE(vertex_at(tin, {9, 44.5}, 0), nullptr);
  EXPECT_NE(vertex_at(tin, {9.2, 45}, 0), nullptr);
}

}  // namespace
}  // namespace tincdt::test
