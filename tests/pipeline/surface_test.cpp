// pipeline::build with surface features (soft lines, clip / erase / replace polygons), long-edge
// trimming, flat fixing and the extra outputs, on small inputs written by the tests: points on a
// plane z = a x + b y + c, so every draped height is known exactly, and polygons whose areas are
// known, so the kept triangles can be checked against them.
#include <cpl_json.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "pipeline/build.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
using test::error_of;
using test::slurp;
using test::spit;

constexpr double kA = 0.37, kB = -0.21, kC = 12.5;
double plane(double x, double y) {
  return kA * x + kB * y + kC;
}

// Appends the XYZ text line of point (X, Y, Z), every digit of its doubles kept.
void add_xyz_line(std::string& xyz, double x, double y, double z) {
  char line[128];
  std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", x, y, z);
  xyz += line;
}

// A jittered (n+1) x (n+1) grid on [0, size]^2 (the border unjittered, so the hull is the
// square), z = z_of(x, y).
std::string grid_xyz(int n, double size, const std::function<double(double, double)>& z_of) {
  std::uint32_t state = 2463534242u;
  const auto jitter = [&] {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return (static_cast<double>(state % 10000) / 10000.0 - 0.5) * 0.6 * size / n;
  };
  std::string s;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      double x = size * i / n, y = size * j / n;
      if (i > 0 && i < n) x += jitter();
      if (j > 0 && j < n) y += jitter();
      add_xyz_line(s, x, y, z_of(x, y));
    }
  return s;
}

// ---- GeoJSON inputs (GDAL reads them as WGS 84; the XYZ points take that CRS, with a warning) --

using Ring = std::vector<std::array<double, 2>>;

std::string coords(const Ring& ring, bool close) {
  std::string s = "[";
  char buf[96];
  for (std::size_t i = 0; i < ring.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", i ? ", " : "", ring[i][0], ring[i][1]);
    s += buf;
  }
  if (close) {
    std::snprintf(buf, sizeof buf, ", [%.17g, %.17g]", ring[0][0], ring[0][1]);
    s += buf;
  }
  return s + "]";
}

struct GeoFeature {
  std::string geometry;    // GeoJSON geometry object
  std::string properties;  // JSON object members, without braces
};

std::string collection(const std::vector<GeoFeature>& features) {
  std::string s = "{\"type\": \"FeatureCollection\", \"features\": [\n";
  for (std::size_t i = 0; i < features.size(); ++i) {
    s += std::string(i ? ",\n" : "") + "{\"type\": \"Feature\", \"id\": " + std::to_string(i + 1) +
         ", \"properties\": {" + features[i].properties +
         "}, \"geometry\": " + features[i].geometry + "}";
  }
  return s + "\n]}\n";
}

std::string polygon(const std::vector<Ring>& rings) {
  std::string s = "{\"type\": \"Polygon\", \"coordinates\": [";
  for (std::size_t i = 0; i < rings.size(); ++i) s += (i ? ", " : "") + coords(rings[i], true);
  return s + "]}";
}

std::string line(const Ring& points) {
  return "{\"type\": \"LineString\", \"coordinates\": " + coords(points, false) + "}";
}

Ring rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

double ring_area(const Ring& r) {
  double a = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const auto& p = r[i];
    const auto& q = r[(i + 1) % r.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return std::fabs(a) / 2;
}

// Distance from (x, y) to the nearest ring edge.
double ring_distance(const std::vector<Ring>& rings, double x, double y) {
  double d = INFINITY;
  for (const Ring& r : rings)
    for (std::size_t i = 0; i < r.size(); ++i) {
      const auto& p = r[i];
      const auto& q = r[(i + 1) % r.size()];
      const double dx = q[0] - p[0], dy = q[1] - p[1];
      const double t =
          std::clamp(((x - p[0]) * dx + (y - p[1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      d = std::min(d, std::hypot(p[0] + t * dx - x, p[1] + t * dy - y));
    }
  return d;
}

// Even-odd point in polygon, written independently of the library's.
bool inside(const std::vector<Ring>& rings, double x, double y) {
  bool in = false;
  for (const Ring& r : rings)
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
      const double xi = r[i][0], yi = r[i][1], xj = r[j][0], yj = r[j][1];
      if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
    }
  return in;
}

// ---- reading the outputs ------------------------------------------------------------------------

using Mesh = test::MeshFile;
using test::read_obj;
using test::read_ply_ascii;

class Surface : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::scratch_dir("surface"); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    spit(path(name), text);
    return path(name);
  }

  // A validated build of the points XYZ, written to NAME, into OUT.
  pipeline::BuildOptions points_job(const std::string& name, const std::string& xyz,
                                    const std::string& out) {
    pipeline::BuildOptions o;
    o.inputs = {write(name, xyz)};
    o.output = path(out);
    o.validate = true;
    return o;
  }
  // Points on the plane over [0, 100]^2, output OBJ.
  pipeline::BuildOptions plane_job(const std::string& out = "tin.obj", int n = 20) {
    return points_job("plane.xyz", grid_xyz(n, 100, plane), out);
  }

  fs::path dir_;
};

// ---- soft lines ---------------------------------------------------------------------------------

TEST_F(Surface, SoftLinesDrapeOntoThePlane) {
  auto o = plane_job();
  // Two soft lines that cross each other and run through the jittered grid at odd places, plus a
  // closed one; their own z (3D) must be ignored.
  o.soft_lines = {write("soft.geojson",
                        collection({{line({{3.3, 7.7}, {50.1, 60.2}, {90.5, 20.7}}), ""},
                                    {line({{10.25, 40.5}, {95.125, 55.5}}), ""},
                                    {"{\"type\": \"LineString\", \"coordinates\": [[20.5, 20.5, "
                                     "999], [40.5, 20.5, 999], [30.5, 35.5, 999], [20.5, 20.5, "
                                     "999]]}",
                                     ""}}))};
  o.constraints_out = path("c.geojson");
  const pipeline::BuildReport r = pipeline::build(o);
  EXPECT_EQ(r.soft_line_vertices, 3u + 2u + 3u);
  EXPECT_EQ(r.draped_vertices, 8u);
  EXPECT_EQ(r.surface_features, 3u);
  EXPECT_GE(r.crossings, 1u);  // the first two cross
  EXPECT_GE(r.constraints, 2u + 1u + 3u);

  const Mesh m = read_obj(o.output);
  ASSERT_EQ(m.v.size(), r.vertices);
  std::size_t soft_found = 0;
  for (const auto& v : m.v) {
    EXPECT_NEAR(v[2], plane(v[0], v[1]), 1e-9) << v[0] << " " << v[1];
    for (const auto& p : std::vector<std::array<double, 2>>{{3.3, 7.7},
                                                            {50.1, 60.2},
                                                            {90.5, 20.7},
                                                            {10.25, 40.5},
                                                            {95.125, 55.5},
                                                            {20.5, 20.5},
                                                            {40.5, 20.5},
                                                            {30.5, 35.5}})
      if (v[0] == p[0] && v[1] == p[1]) ++soft_found;
  }
  EXPECT_EQ(soft_found, 8u);  // every soft-line vertex is a TIN vertex
  EXPECT_NEAR(m.area(), 100.0 * 100.0, 1e-8);
  EXPECT_EQ(m.f.size(), r.triangles);
}

TEST_F(Surface, SoftLineCrossingAHardLineTakesItsZ) {
  auto o = plane_job();
  // A hard line 5 m above the plane from (10, 50) to (90, 50); a soft line crossing it at x = 40.
  const double z0 = plane(10, 50) + 5, z1 = plane(90, 50) + 5;
  char hard[256];
  std::snprintf(hard, sizeof hard,
                "{\"type\": \"LineString\", \"coordinates\": [[10, 50, %.17g], [90, 50, %.17g]]}",
                z0, z1);
  o.breaklines = {write("hard.geojson", collection({{hard, ""}}))};
  o.soft_lines = {write("soft.geojson", collection({{line({{40, 20.5}, {40, 80.5}}), ""}}))};
  o.diagnostics = path("d.gpkg");
  const pipeline::BuildReport r = pipeline::build(o);
  EXPECT_EQ(r.crossings, 1u);
  const Mesh m = read_obj(o.output);
  bool found = false;
  for (const auto& v : m.v)
    if (std::fabs(v[0] - 40) < 1e-9 && std::fabs(v[1] - 50) < 1e-9) {
      found = true;
      EXPECT_NEAR(v[2], z0 + (z1 - z0) * 30 / 80, 1e-9);  // the hard line's z, not a mean
    }
  EXPECT_TRUE(found);
}

TEST_F(Surface, DrapedVertexOutsideTheTinNamesTheFeature) {
  auto o = plane_job();
  o.soft_lines = {write("soft.geojson", collection({{line({{50, 50}, {60, 60}}), ""},
                                                    {line({{50, 50}, {150, 60}}), ""}}))};
  const std::string e = error_of([&] { pipeline::build(o); });
  EXPECT_NE(e.find("soft.geojson"), std::string::npos) << e;
  EXPECT_NE(e.find("feature 2"), std::string::npos) << e;
  EXPECT_NE(e.find("(150.000, 60.000) lies outside the TIN"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(o.output));
}

// ---- clip, erase, replace -------------------------------------------------------------------

TEST_F(Surface, ClipKeepsExactlyThePolygon) {
  auto o = plane_job("tin.ply");
  o.write.ply_ascii = true;
  // A polygon with a hole, its corners off the grid.
  const std::vector<Ring> clip = {
      {{12.5, 8.25}, {91.75, 20.5}, {80.125, 92.5}, {30.5, 70.25}, {5.5, 60.5}},
      rectangle(40.5, 40.5, 55.25, 52.75)};
  o.clip = {write("clip.geojson", collection({{polygon(clip), ""}}))};
  o.stats_path = path("s.json");
  const pipeline::BuildReport r = pipeline::build(o);
  EXPECT_GT(r.clipped_triangles, 0u);
  const Mesh m = read_ply_ascii(o.output);
  ASSERT_EQ(m.f.size(), r.triangles);
  const double expected = ring_area(clip[0]) - ring_area(clip[1]);
  EXPECT_NEAR(m.area(), expected, 1e-9 * expected);
  for (const auto& t : m.f) {
    const auto c = m.centroid(t);
    EXPECT_TRUE(inside(clip, c[0], c[1])) << c[0] << " " << c[1];
  }
  // Compaction: every written vertex is used, and heights are the plane's (draped ring).
  EXPECT_EQ(m.v.size(), m.used_vertices());
  EXPECT_EQ(m.v.size(), r.vertices);
  for (const auto& v : m.v) EXPECT_NEAR(v[2], plane(v[0], v[1]), 1e-9);
  // PLY edges: the clip rings, all on kept triangles, renumbered into the written vertices.
  EXPECT_EQ(m.e.size(), r.constraints);
  EXPECT_EQ(m.e.size(), 5u + 4u);  // no vertex lies on a ring, so no ring edge is split
  for (const auto& e : m.e) {
    ASSERT_LT(e[0], m.v.size());
    ASSERT_LT(e[1], m.v.size());
  }
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(slurp(o.stats_path)));
  EXPECT_EQ(doc.GetRoot().GetLong("clipped_triangles"), static_cast<long>(r.clipped_triangles));
  EXPECT_NEAR(doc.GetRoot().GetDouble("quality/area_2d"), expected, 1e-9 * expected);
}

TEST_F(Surface, EraseMakesAHole) {
  auto o = plane_job();
  const Ring lake = {{30.5, 30.5}, {60.25, 35.5}, {55.5, 70.75}, {25.5, 50.5}};
  o.erase = {write("lake.geojson", collection({{polygon({lake}), ""}}))};
  const pipeline::BuildReport r = pipeline::build(o);
  EXPECT_GT(r.erased_triangles, 0u);
  const Mesh m = read_obj(o.output);
  EXPECT_NEAR(m.area(), 100.0 * 100.0 - ring_area(lake), 1e-8);
  for (const auto& t : m.f) {
    const auto c = m.centroid(t);
    EXPECT_FALSE(inside({lake}, c[0], c[1])) << c[0] << " " << c[1];
  }
  EXPECT_EQ(m.v.size(), m.used_vertices());  // grid points inside the lake are not written
  std::size_t inside_lake = 0;
  for (const auto& v : m.v)  // vertices on the shore stay, with the triangles outside
    inside_lake += inside({lake}, v[0], v[1]) && ring_distance({lake}, v[0], v[1]) > 1e-9;
  EXPECT_EQ(inside_lake, 0u);
}

TEST_F(Surface, ReplaceSetsThePolygonZ) {
  auto o = plane_job();
  const Ring pad = {{20.5, 60.5}, {45.5, 60.5}, {45.5, 85.5}, {20.5, 85.5}};
  const Ring pond = {{60.5, 10.5}, {80.5, 15.5}, {70.5, 30.5}};
  o.replace = {write("pads.geojson", collection({{polygon({pad}), "\"LEVEL\": 42.5"},
                                                 {polygon({pond}), "\"LEVEL\": 3"}}))};
  o.lines.z_field = "LEVEL";
  const pipeline::BuildReport r = pipeline::build(o);
  const Mesh m = read_obj(o.output);
  std::uint64_t on_or_in = 0;
  for (const auto& v : m.v) {
    const bool in_pad = v[0] >= 20.5 && v[0] <= 45.5 && v[1] >= 60.5 && v[1] <= 85.5;
    // The pond's corners are its only vertices on its sloping sides (the grid is jittered).
    const bool in_pond = inside({pond}, v[0], v[1]) ||
                         std::any_of(pond.begin(), pond.end(),
                                     [&](const auto& p) { return p[0] == v[0] && p[1] == v[1]; });
    if (in_pad) {
      EXPECT_EQ(v[2], 42.5) << v[0] << " " << v[1];
    } else if (in_pond) {
      EXPECT_EQ(v[2], 3.0) << v[0] << " " << v[1];
    } else {
      EXPECT_NEAR(v[2], plane(v[0], v[1]), 1e-9) << v[0] << " " << v[1];
    }
    on_or_in += in_pad || in_pond;
  }
  EXPECT_GT(on_or_in, 25u);
  EXPECT_EQ(r.replaced_vertices, on_or_in);
}

TEST_F(Surface, ReplacePolygonWithoutZIsAnInputError) {
  auto o = plane_job();
  o.replace = {write("pad.geojson", collection({{polygon({rectangle(10, 10, 20, 20)}), ""}}))};
  const auto e = test::thrown<InputError>([&] { pipeline::build(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), o.replace[0]);
  EXPECT_EQ(e->remedy(), Remedy::z_field);
}

// Precedence: erase wins over clip where they overlap.
TEST_F(Surface, EraseWinsOverClip) {
  auto o = plane_job();
  const Ring clip = rectangle(10.5, 10.5, 70.5, 80.5);
  const Ring erase = rectangle(50.5, 30.5, 90.5, 60.5);  // half inside the clip
  o.clip = {write("clip.geojson", collection({{polygon({clip}), ""}}))};
  o.erase = {write("erase.geojson", collection({{polygon({erase}), ""}}))};
  const pipeline::BuildReport r = pipeline::build(o);
  const Mesh m = read_obj(o.output);
  const double overlap = (70.5 - 50.5) * (60.5 - 30.5);
  EXPECT_NEAR(m.area(), ring_area(clip) - overlap, 1e-8);
  for (const auto& t : m.f) {
    const auto c = m.centroid(t);
    EXPECT_TRUE(inside({clip}, c[0], c[1]));
    EXPECT_FALSE(inside({erase}, c[0], c[1]));
  }
  EXPECT_GT(r.clipped_triangles, 0u);
  EXPECT_GT(r.erased_triangles, 0u);
}

// Precedence: where replace and erase overlap, the triangles go (erase) and the vertices that
// stay (on the erase ring, inside the pad) have the pad's z.
TEST_F(Surface, ReplaceUnderEraseKeepsThePadZAroundTheHole) {
  auto o = plane_job();
  const Ring pad = rectangle(20.5, 20.5, 60.5, 60.5);
  const Ring hole = rectangle(40.5, 40.5, 80.5, 80.5);
  o.replace = {write("pad.geojson", collection({{polygon({pad}), "\"Z\": 7.25"}}))};
  o.lines.z_field = "Z";
  o.erase = {write("hole.geojson", collection({{polygon({hole}), ""}}))};
  const pipeline::BuildReport r = pipeline::build(o);
  const Mesh m = read_obj(o.output);
  EXPECT_NEAR(m.area(), 100.0 * 100.0 - ring_area(hole), 1e-8);
  std::size_t pad_vertices = 0;
  for (const auto& v : m.v) {
    const bool in_pad = v[0] >= 20.5 && v[0] <= 60.5 && v[1] >= 20.5 && v[1] <= 60.5;
    if (in_pad) {
      EXPECT_EQ(v[2], 7.25) << v[0] << " " << v[1];
      ++pad_vertices;
    } else {
      EXPECT_NEAR(v[2], plane(v[0], v[1]), 1e-9) << v[0] << " " << v[1];
    }
    const double e = 1e-9;  // crossing vertices on the rings may be an ulp off
    EXPECT_FALSE(v[0] > 40.5 + e && v[0] < 80.5 - e && v[1] > 40.5 + e && v[1] < 80.5 - e);
  }
  EXPECT_GT(pad_vertices, 10u);
  EXPECT_GT(r.replaced_vertices, pad_vertices);  // the ones inside the hole were set too
}

TEST_F(Surface, ClipLeavingNothingIsAnError) {
  auto o = plane_job();
  o.clip = {write("clip.geojson", collection({{polygon({rectangle(10, 10, 20, 20)}), ""}}))};
  o.erase = {write("erase.geojson", collection({{polygon({rectangle(5, 5, 25, 25)}), ""}}))};
  o.stats_path = path("s.json");
  const std::string e = error_of([&] { pipeline::build(o); });
  EXPECT_NE(e.find("no triangle is left"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(o.output));
  EXPECT_FALSE(fs::exists(o.stats_path));
}

// ---- boundary trimming ----------------------------------------------------------------------

// Points on a C: an annulus sector around (50, 50), radii 30..50, from 45 to 315 degrees.
std::string c_shaped_cloud() {
  std::string xyz;
  for (int i = 0; i <= 5; ++i) {
    const double radius = 30 + 4.0 * i;
    const int steps = static_cast<int>(radius * 1.5 * std::numbers::pi / 3.0);
    for (int k = 0; k <= steps; ++k) {
      const double a = (45 + 270.0 * k / steps) * std::numbers::pi / 180;
      const double x = 50 + radius * std::cos(a), y = 50 + radius * std::sin(a);
      add_xyz_line(xyz, x, y, plane(x, y));
    }
  }
  return xyz;
}

TEST_F(Surface, MaxEdgeTrimsACShapedCloud) {
  const std::string xyz = c_shaped_cloud();
  pipeline::BuildOptions o = points_job("c.xyz", xyz, "hull.obj");
  const auto hull = pipeline::build(o);
  EXPECT_EQ(hull.trimmed_triangles, 0u);
  const double hull_area = read_obj(o.output).area();

  o.output = path("trimmed.obj");
  o.max_edge = 6;
  const auto r = pipeline::build(o);
  EXPECT_GT(r.trimmed_triangles, 0u);
  EXPECT_EQ(r.triangles + r.trimmed_triangles, hull.triangles);
  const Mesh m = read_obj(o.output);
  const double sector = std::numbers::pi * (50.0 * 50 - 30.0 * 30) * 0.75;
  EXPECT_LT(m.area(), hull_area * 0.8);
  EXPECT_GT(m.area(), sector * 0.95);  // chords cut a little off the outer arc
  EXPECT_LT(m.area(), sector * 1.01);
  for (const auto& t : m.f) {
    const auto c = m.centroid(t);
    const double radius = std::hypot(c[0] - 50, c[1] - 50);
    EXPECT_GT(radius, 29.5);                                          // not in the C's inner disc
    EXPECT_FALSE(c[0] > 50 && std::fabs(c[1] - 50) < c[0] - 50 - 1);  // nor in its mouth
    EXPECT_LE(m.max_edge_length(t), 6.0 + 1e-9);
  }
  EXPECT_EQ(m.v.size(), m.used_vertices());
}

// --max-edge trims the gaps between the points, also when the TIN is simplified: the simplified
// TIN covers the same area as the full trimmed one, though its own triangles (on a plane: a few
// vertices) are far longer than --max-edge.
TEST_F(Surface, MaxEdgeWithMaxErrorTrimsThePointsNotTheSimplifiedTriangles) {
  const std::string xyz = c_shaped_cloud();
  pipeline::BuildOptions o = points_job("c.xyz", xyz, "trimmed.obj");
  o.max_edge = 6;
  const auto full = pipeline::build(o);
  const double full_area = read_obj(o.output).area();
  o.output = path("simplified.obj");
  o.max_error = 0.01;
  const auto simplified = pipeline::build(o);
  const Mesh m = read_obj(o.output);
  EXPECT_LT(simplified.vertices, full.vertices);
  EXPECT_NEAR(m.area(), full_area, 1e-9 * full_area);
  EXPECT_GT(simplified.trimmed_triangles, 0u);
  for (const auto& t : m.f) {
    const auto c = m.centroid(t);
    EXPECT_GT(std::hypot(c[0] - 50, c[1] - 50), 29.5);  // not in the C's inner disc
  }
}

// ---- flats ----------------------------------------------------------------------------------

TEST_F(Surface, FixFlatsOnAContourHill) {
  // Three closed contours of a hill (z 10, 20, 30): inside the top ring the TIN is flat.
  const auto circle = [](double r, int n) {
    Ring ring;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n + 0.1;
      ring.push_back({50 + r * std::cos(a), 50 + r * std::sin(a)});
    }
    return ring;
  };
  std::vector<GeoFeature> contours;
  for (const auto& [r, z] : {std::pair{45.0, 10}, {30.0, 20}, {15.0, 30}})
    contours.push_back({polygon({circle(r, 24)}), "\"ELEV\": " + std::to_string(z)});
  pipeline::BuildOptions o;
  o.contours = {write("hill.geojson", collection(contours))};
  o.lines.z_field = "ELEV";
  o.output = path("tin.ply");
  o.stats_path = path("s.json");
  o.validate = true;
  const auto before = pipeline::build(o);
  EXPECT_TRUE(before.flats.counted);
  EXPECT_FALSE(before.flats.fixed);
  EXPECT_GT(before.flats.before, 5u);
  EXPECT_EQ(before.flats.after, before.flats.before);

  o.fix_flats = true;
  o.write.overwrite = true;
  const auto r = pipeline::build(o);
  EXPECT_TRUE(r.flats.fixed);
  EXPECT_EQ(r.flats.before, before.flats.before);
  EXPECT_EQ(r.flats.after, 0u);
  EXPECT_GT(r.flats.vertices_added + r.flats.swaps, 0u);
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(slurp(o.stats_path)));
  const CPLJSONObject root = doc.GetRoot();
  EXPECT_EQ(root.GetLong("flats/before"), static_cast<long>(r.flats.before));
  EXPECT_EQ(root.GetLong("flats/after", -1), 0);
  EXPECT_EQ(root.GetLong("flats/swaps"), static_cast<long>(r.flats.swaps));
  EXPECT_EQ(root.GetLong("flats/vertices_added"), static_cast<long>(r.flats.vertices_added));
  EXPECT_EQ(root.GetLong("quality/flat_triangles", -1), 0);
  EXPECT_EQ(root.GetString("quality/flat_rule"), "equal z, all corners on contours");
}

// Order: flats are fixed before replace. A pad over the hilltop: the vertices fix-flats adds
// there must end at the pad's z too (had replace run first, the flats of the pad would have
// been "fixed" with vertices at interpolated heights).
TEST_F(Surface, FixFlatsRunsBeforeReplace) {
  std::vector<GeoFeature> contours;
  for (const auto& [r, z] : {std::pair{45.0, 10}, {30.0, 20}, {15.0, 30}}) {
    Ring ring;
    for (int k = 0; k < 24; ++k) {
      const double a = 2 * std::numbers::pi * k / 24 + 0.1;
      ring.push_back({50 + r * std::cos(a), 50 + r * std::sin(a)});
    }
    contours.push_back({polygon({ring}), "\"ELEV\": " + std::to_string(z)});
  }
  pipeline::BuildOptions o;
  o.contours = {write("hill.geojson", collection(contours))};
  const Ring pad = rectangle(33.5, 33.5, 66.5, 66.5);  // holds the whole top ring (r = 15)
  o.replace = {write("pad.geojson", collection({{polygon({pad}), "\"ELEV\": 33.5"}}))};
  o.lines.z_field = "ELEV";
  o.fix_flats = true;
  o.output = path("tin.obj");
  o.validate = true;
  const auto r = pipeline::build(o);
  EXPECT_GT(r.flats.vertices_added, 0u);
  EXPECT_EQ(r.flats.after, 0u);
  const Mesh m = read_obj(o.output);
  std::size_t in_pad = 0;
  for (const auto& v : m.v)
    if (v[0] >= 33.5 && v[0] <= 66.5 && v[1] >= 33.5 && v[1] <= 66.5) {
      EXPECT_EQ(v[2], 33.5) << v[0] << " " << v[1];
      ++in_pad;
    }
  EXPECT_EQ(in_pad, r.replaced_vertices);
  EXPECT_GT(in_pad, 24u + 4u);  // the top ring, the pad's corners and the new vertices
}

// Order: trimming works from the hull before clip and erase open new boundaries. Points with an
// empty square in the middle: the long triangles over it are not reachable from the hull, so
// they stay, also where a clip or erase ring runs through the gap (had trimming run after clip
// or erase, it would have eaten into the gap from their rings).
TEST_F(Surface, MaxEdgeTrimsFromTheHullOnlyBeforeClipAndErase) {
  std::string xyz;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const bool border = i == 0 || i == 20 || j == 0 || j == 20;  // the hull stays a square
      const double x = 5.0 * i + (i % 2 && !border ? 0.01 * j : 0),
                   y = 5.0 * j + (j % 3 && !border ? 0.013 * i : 0);
      if (x > 30 && x < 70 && y > 30 && y < 70) continue;  // the gap
      add_xyz_line(xyz, x, y, plane(x, y));
    }
  pipeline::BuildOptions o = points_job("gap.xyz", xyz, "tin.obj");
  o.max_edge = 12;  // the grid's edges are ~5-7 m; the gap's triangles have ~40 m edges
  // Through the gap; densified, so that its long sides near the hull make no long triangles.
  Ring clip;
  const Ring corners = {{2.5, 2.5}, {60.5, 2.5}, {60.5, 95.5}, {2.5, 95.5}};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto &p = corners[k], &q = corners[(k + 1) % 4];
    const int n = static_cast<int>(std::ceil(std::hypot(q[0] - p[0], q[1] - p[1]) / 2.5));
    for (int i = 0; i < n; ++i)
      clip.push_back({p[0] + (q[0] - p[0]) * i / n, p[1] + (q[1] - p[1]) * i / n});
  }
  const Ring erase = rectangle(45.5, 40.5, 55.5, 60.5);  // inside the gap
  o.clip = {write("clip.geojson", collection({{polygon({clip}), ""}}))};
  o.erase = {write("erase.geojson", collection({{polygon({erase}), ""}}))};
  const auto r = pipeline::build(o);
  EXPECT_EQ(r.trimmed_triangles, 0u);  // the outline is convex: nothing to trim from the hull
  const Mesh m = read_obj(o.output);
  EXPECT_NEAR(m.area(), ring_area(clip) - ring_area(erase), 1e-8);
  double longest = 0;
  for (const auto& t : m.f) longest = std::max(longest, m.max_edge_length(t));
  EXPECT_GT(longest, 12.0);  // gap triangles along the clip and erase rings are kept
}

TEST_F(Surface, FixFlatsNeedsContours) {
  auto o = plane_job();
  o.fix_flats = true;
  EXPECT_NE(error_of([&] { pipeline::build(o); }).find("--fix-flats needs --contours"),
            std::string::npos);
}

// ---- extra outputs --------------------------------------------------------------------------

TEST_F(Surface, ConstraintLinesOpenWithGdalWithTheirSources) {
  auto o = plane_job();
  o.breaklines = {write("hard.geojson",
                        collection({{"{\"type\": \"LineString\", \"coordinates\": [[10.5, 10.5, "
                                     "5], [30.5, 60.5, 6], [70.5, 40.5, 7]]}",
                                     ""}}))};
  o.soft_lines = {write("soft.geojson", collection({{line({{80.5, 80.5}, {90.5, 10.5}}), ""}}))};
  o.constraints_out = path("c.geojson");
  const auto r = pipeline::build(o);
  EXPECT_EQ(r.output_of("constraint_lines"), o.constraints_out);

  GDALAllRegister();
  GDALDatasetH ds =
      GDALOpenEx(o.constraints_out.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRLayerH layer = GDALDatasetGetLayer(ds, 0);
  EXPECT_EQ(OGR_L_GetFeatureCount(layer, TRUE), static_cast<GIntBig>(r.constraints));
  std::map<std::string, int> per_file;
  OGRFeatureH f = nullptr;
  while ((f = OGR_L_GetNextFeature(layer)) != nullptr) {
    const std::string file = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "source_file"));
    ++per_file[fs::path(file).filename().string()];
    EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "source_fid")), 1);
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    EXPECT_EQ(OGR_G_GetPointCount(g), 2);
    OGR_F_Destroy(f);
  }
  GDALClose(ds);
  EXPECT_GE(per_file["hard.geojson"], 2);
  EXPECT_GE(per_file["soft.geojson"], 1);
  EXPECT_EQ(per_file.size(), 2u);
}

TEST_F(Surface, DiagnosticsListTheCrossingAndTheSkippedAndDropped) {
  pipeline::BuildOptions o;
  // Crossing 3D lines at (5, 5): one with a repeated vertex, and a point feature (dropped).
  o.breaklines = {
      write("lines.geojson",
            collection(
                {{"{\"type\": \"LineString\", \"coordinates\": [[0, 0, 10], [0, 0, 10], [10, 10, "
                  "20]]}",
                  ""},
                 {"{\"type\": \"LineString\", \"coordinates\": [[0, 10, 30], [10, 0, 30]]}", ""},
                 {"{\"type\": \"Point\", \"coordinates\": [3, 3, 3]}", ""},
                 // Starts where the first line starts: the two vertices merge into one.
                 {"{\"type\": \"LineString\", \"coordinates\": [[0, 0, 10], [-5, 3, 12]]}", ""}}))};
  o.output = path("tin.ply");
  o.diagnostics = path("d.gpkg");
  o.validate = true;
  const auto r = pipeline::build(o);
  EXPECT_EQ(r.crossings, 1u);
  EXPECT_EQ(r.output_of("diagnostics"), o.diagnostics);

  GDALAllRegister();
  GDALDatasetH ds = GDALOpenEx(o.diagnostics.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
  ASSERT_NE(ds, nullptr);
  const auto count = [&](const char* name) {
    OGRLayerH layer = GDALDatasetGetLayerByName(ds, name);
    EXPECT_NE(layer, nullptr) << name;
    return layer ? OGR_L_GetFeatureCount(layer, TRUE) : -1;
  };
  EXPECT_EQ(count("crossings"), 1);
  EXPECT_EQ(count("skipped_segments"), 1);
  EXPECT_EQ(count("dropped_features"), 1);
  EXPECT_EQ(count("merged_duplicates"), 1);
  EXPECT_EQ(r.duplicates_merged, 1u);
  OGRLayerH crossings = GDALDatasetGetLayerByName(ds, "crossings");
  OGR_L_ResetReading(crossings);
  OGRFeatureH f = OGR_L_GetNextFeature(crossings);
  ASSERT_NE(f, nullptr);
  OGRGeometryH g = OGR_F_GetGeometryRef(f);
  EXPECT_NEAR(OGR_G_GetX(g, 0), 5, 1e-12);
  EXPECT_NEAR(OGR_G_GetY(g, 0), 5, 1e-12);
  EXPECT_NEAR(OGR_G_GetZ(g, 0), 22.5, 1e-12);  // mean of 15 and 30
  const std::set<GIntBig> fids = {OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "fid_a")),
                                  OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "fid_b"))};
  EXPECT_EQ(fids, (std::set<GIntBig>{1, 2}));
  EXPECT_NE(std::string(OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "file_a")))
                .find("lines.geojson"),
            std::string::npos);
  OGR_F_Destroy(f);
  GDALClose(ds);
}

TEST_F(Surface, ExtraOutputsAreCheckedBeforeReading) {
  spit(path("c.geojson"), "old");
  pipeline::BuildOptions o;
  o.inputs = {path("missing.xyz")};  // an InputError if it were read
  o.output = path("tin.obj");
  o.constraints_out = path("c.geojson");
  EXPECT_THROW(pipeline::build(o), OutputError);
  o.constraints_out.clear();
  o.diagnostics = path("d.gpkg");
  o.stats_path = path("d.gpkg");
  EXPECT_THROW(pipeline::build(o), OutputError);  // the same file as another output
  o.stats_path = path("tin.obj");
  EXPECT_THROW(pipeline::build(o), OutputError);  // the same file as the TIN
  o.stats_path.clear();
  o.diagnostics = path("no_such_folder/d.gpkg");
  EXPECT_THROW(pipeline::build(o), OutputError);
  EXPECT_EQ(slurp(path("c.geojson")), "old");
}

// The clip polygon's coordinates lie inside the lines' TIN as numbers, but in EPSG:32633 they are
// some 670 km east of it in EPSG:32632, where they are transformed to.
TEST_F(Surface, PolygonsInAnotherCrsAreTransformed) {
  GDALAllRegister();
  const auto gpkg = [&](const std::string& name, int epsg, const char* wkt) {
    const std::string p = path(name);
    GDALDatasetH ds =
        GDALCreate(GDALGetDriverByName("GPKG"), p.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, epsg);
    OGRLayerH layer = GDALDatasetCreateLayer(ds, "x", srs, wkbUnknown, nullptr);
    OSRRelease(srs);
    OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(layer));
    OGRGeometryH g = nullptr;
    char* text = const_cast<char*>(wkt);
    OGR_G_CreateFromWkt(&text, nullptr, &g);
    OGR_F_SetGeometryDirectly(f, g);
    EXPECT_EQ(OGR_L_CreateFeature(layer, f), OGRERR_NONE);
    OGR_F_Destroy(f);
    GDALClose(ds);
    return p;
  };
  pipeline::BuildOptions o;
  o.breaklines = {gpkg("lines.gpkg", 32632, "LINESTRING Z (0 0 1, 100 0 2, 50 80 3)")};
  o.clip = {gpkg("clip.gpkg", 32633, "POLYGON ((10 10, 60 10, 50 40, 10 10))")};
  o.output = path("tin.obj");
  const std::string e = error_of([&] { pipeline::build(o); });
  EXPECT_NE(e.find("clip.gpkg"), std::string::npos) << e;
  EXPECT_NE(e.find("the clip polygons lie wholly outside the TIN"), std::string::npos) << e;
}

TEST_F(Surface, StatsKeepTheirKeysAndAddTheNewOnes) {
  auto o = plane_job();
  o.clip = {write("clip.geojson", collection({{polygon({rectangle(5.5, 5.5, 95.5, 95.5)}), ""}}))};
  o.soft_lines = {write("soft.geojson", collection({{line({{20.5, 20.5}, {70.5, 75.5}}), ""}}))};
  o.max_edge = 1000;
  o.stats_path = path("s.json");
  const auto r = pipeline::build(o);
  CPLJSONDocument doc;
  ASSERT_TRUE(doc.LoadMemory(slurp(o.stats_path)));
  const CPLJSONObject root = doc.GetRoot();
  for (const char* key : {"points_read",
                          "vertices",
                          "triangles",
                          "constraints",
                          "crossings",
                          "soft_line_vertices",
                          "replaced_vertices",
                          "trimmed_triangles",
                          "clipped_triangles",
                          "erased_triangles",
                          "flats/before",
                          "flats/after",
                          "flats/swaps",
                          "flats/vertices_added",
                          "quality/triangles",
                          "quality/min_angle_deg",
                          "quality/angle_histogram",
                          "quality/triangles_below_20deg",
                          "quality/max_circumradius_to_inradius",
                          "quality/flat_triangles",
                          "quality/edge_length_histogram",
                          "quality/area_2d",
                          "timings_s/surface",
                          "timings_s/terrain"})
    EXPECT_TRUE(root.GetObj(key).IsValid()) << key;
  EXPECT_EQ(root.GetLong("soft_line_vertices"), 2);
  EXPECT_EQ(root.GetLong("quality/triangles"), static_cast<long>(r.triangles));
  EXPECT_NEAR(root.GetDouble("quality/area_2d"), 90.0 * 90.0, 1e-8);
  const CPLJSONArray inputs = root.GetArray("inputs");
  ASSERT_EQ(inputs.Size(), 3);
  EXPECT_EQ(inputs[0].GetString("kind"), "points");
  EXPECT_EQ(inputs[0].GetLong("read"), 441);
  EXPECT_EQ(inputs[0].GetLong("filtered"), 0);
  EXPECT_EQ(inputs[1].GetString("kind"), "soft_lines");
  EXPECT_EQ(inputs[1].GetLong("read"), 1);
  EXPECT_EQ(inputs[1].GetLong("kept"), 1);
  EXPECT_EQ(inputs[2].GetString("kind"), "clip");
  EXPECT_EQ(inputs[2].GetLong("vertices"), 4);
}

}  // namespace
