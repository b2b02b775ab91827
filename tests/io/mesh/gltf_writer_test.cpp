// glTF 2.0 binary (GLB) TINs: each file is read back (header, chunks, JSON, accessors) and
// compared with the kept triangles of the TIN at UTM magnitude: positions plus the node's
// translation within 1 mm of the vertices, normals of unit length pointing up, faces counter-
// clockwise seen from above, bounds exactly those of the data; and the Khronos glTF validator
// finds no error in it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "constrained_sample.hpp"
#include "constraints/constraints.hpp"
#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/files.hpp"
#include "support/gltf_files.hpp"
#include "support/meshes.hpp"
#include "support/web_tools.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using test::accessor_values;
using test::GlbFile;
using test::member;
using test::number_at;
using test::read_glb;

constexpr double kX0 = 512345.678, kY0 = 4123456.789;
constexpr double kMillimetre = 1e-3;

// A rolling terrain of jittered points at UTM magnitude, 120 m across, with a constrained
// polyline and ring; with `holes`, every 7th triangle removed (so vertices are compacted).
mesh::Triangulation terrain(bool holes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<Point3> pts;
  const auto height = [](double x, double y) {
    return 800 + 6 * std::sin(x / 17) + 4 * std::cos(y / 23) + 0.01 * x;
  };
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const double x = 3 * i + jitter(rng), y = 3 * j + jitter(rng);
      pts.push_back({kX0 + x, kY0 + y, height(x, y)});
    }
  const auto first = static_cast<std::uint32_t>(pts.size());
  for (int i = 0; i < 6; ++i) {
    const double x = 10 + 13.1 * i, y = 20 + 3.7 * i;
    pts.push_back({kX0 + x, kY0 + y, height(x, y)});
  }
  const auto ring = static_cast<std::uint32_t>(pts.size());
  for (int i = 0; i < 8; ++i) {
    const double a = i * 0.785398, x = 60 + 15 * std::cos(a), y = 65 + 15 * std::sin(a);
    pts.push_back({kX0 + x, kY0 + y, height(x, y)});
  }
  return test::constrained_sample(std::move(pts), first, ring, holes);
}

// An nx by ny grid of vertices one metre apart (for the index type's threshold).
mesh::Triangulation grid(std::uint32_t nx, std::uint32_t ny) {
  mesh::Triangulation tin;
  tin.reserve_vertices(std::size_t{nx} * ny);
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) tin.add_vertex({kX0 + i, kY0 + j}, 0.01 * (i + j));
  for (std::uint32_t j = 0; j + 1 < ny; ++j)
    for (std::uint32_t i = 0; i + 1 < nx; ++i) {
      const VertexId a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      tin.add_triangle(a, b, c);
      tin.add_triangle(a, c, d);
    }
  test::close_with_ghosts(tin);
  return tin;
}

std::vector<std::array<VertexId, 3>> kept_triangles(const mesh::Triangulation& tin) {
  std::vector<std::array<VertexId, 3>> f;
  tin.for_each_triangle([&f](TriangleId, const std::array<VertexId, 3>& c) { f.push_back(c); });
  return f;
}

std::set<std::pair<VertexId, VertexId>> kept_constrained_edges(const mesh::Triangulation& tin) {
  std::set<std::pair<VertexId, VertexId>> s;
  tin.for_each_constrained_edge([&](EdgeId e) {
    if (tin.is_kept(mesh::triangle_of(e)) || tin.is_kept(mesh::triangle_of(tin.twin(e))))
      s.insert(std::minmax(tin.origin(e), tin.dest(e)));
  });
  return s;
}

// A GLB's mesh as the source's coordinates (x east, y north, z up, the offset added back).
struct Mesh {
  GlbFile glb;
  std::vector<std::array<double, 3>> positions;  // source axes, in double
  std::vector<double> raw_positions;             // POSITION as stored (glTF axes)
  std::vector<double> normals;                   // NORMAL as stored (glTF axes)
  std::vector<double> triangles, lines;          // index accessors' values
};

Mesh read_mesh(const std::string& path, const Point3& offset = {0, 0, 0}) {
  Mesh m;
  m.glb = read_glb(test::slurp(path));
  m.raw_positions = accessor_values(m.glb, 0);
  m.normals = accessor_values(m.glb, 1);
  m.triangles = accessor_values(m.glb, 2);
  if (member(m.glb.json, {"accessors", "3"}) != nullptr) m.lines = accessor_values(m.glb, 3);
  double t[3];
  for (int k = 0; k < 3; ++k)
    t[k] = number_at(m.glb.json, {"nodes", "0", "translation", std::to_string(k)});
  for (std::size_t i = 0; i + 2 < m.raw_positions.size(); i += 3) {
    const double x = t[0] + m.raw_positions[i], y = t[1] + m.raw_positions[i + 1],
                 z = t[2] + m.raw_positions[i + 2];
    m.positions.push_back({x + offset.x, offset.y - z, y + offset.z});
  }
  return m;
}

// TIN written as a GLB with the default options, and read back.
Mesh glb_of(const mesh::Triangulation& tin) {
  const std::string path = test::scratch_dir("gltf_writer") + "/tin.glb";
  write_tin(path, tin, {});
  return read_mesh(path);
}

void expect_near_vertex(const mesh::Triangulation& tin, VertexId v,
                        const std::array<double, 3>& p) {
  EXPECT_NEAR(p[0], tin.point(v).x, kMillimetre) << "vertex " << v;
  EXPECT_NEAR(p[1], tin.point(v).y, kMillimetre) << "vertex " << v;
  EXPECT_NEAR(p[2], tin.z(v), kMillimetre) << "vertex " << v;
}

// Every written triangle is the TIN's kept triangle of the same rank, corner for corner.
void expect_same_triangles(const mesh::Triangulation& tin, const Mesh& m) {
  const auto faces = kept_triangles(tin);
  ASSERT_EQ(m.triangles.size(), 3 * faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double i = m.triangles[3 * t + k];
      ASSERT_LT(i, static_cast<double>(m.positions.size()));
      expect_near_vertex(tin, faces[t][k], m.positions[static_cast<std::size_t>(i)]);
    }
}

TEST(GltfWriter, WritesTheKeptTrianglesAroundTheBoundingBoxCentre) {
  for (const bool holes : {false, true}) {
    SCOPED_TRACE(holes ? "with removed triangles" : "whole");
    const std::string dir = test::scratch_dir("gltf_writer");
    const mesh::Triangulation tin = terrain(holes);
    const TinWriteStats stats = test::write_alone_with_crs(dir, "tin.glb", tin);
    const Mesh m = read_mesh(dir + "/tin.glb");
    const auto faces = kept_triangles(tin);
    EXPECT_EQ(stats.triangles, faces.size());
    std::set<VertexId> used;
    for (const auto& f : faces) used.insert(f.begin(), f.end());
    EXPECT_EQ(stats.vertices, used.size());
    EXPECT_EQ(m.positions.size(), used.size());
    EXPECT_EQ(m.normals.size(), m.raw_positions.size());
    expect_same_triangles(tin, m);

    // The translation is the centre of the bounding box: the positions span it symmetrically.
    for (int k = 0; k < 3; ++k) {
      const double lo = number_at(m.glb.json, {"accessors", "0", "min", std::to_string(k)});
      const double hi = number_at(m.glb.json, {"accessors", "0", "max", std::to_string(k)});
      EXPECT_NEAR(lo, -hi, kMillimetre) << "axis " << k;
    }
    EXPECT_EQ(number_at(m.glb.json, {"nodes", "0", "mesh"}), 0);
  }
}

TEST(GltfWriter, BoundsAreExactlyThoseOfThePositions) {
  const mesh::Triangulation tin = terrain(true);
  const Mesh m = glb_of(tin);
  ASSERT_FALSE(m.raw_positions.empty());
  for (int k = 0; k < 3; ++k) {
    double lo = m.raw_positions[k], hi = lo;
    for (std::size_t i = k; i < m.raw_positions.size(); i += 3) {
      lo = std::min(lo, m.raw_positions[i]);
      hi = std::max(hi, m.raw_positions[i]);
    }
    EXPECT_EQ(number_at(m.glb.json, {"accessors", "0", "min", std::to_string(k)}), lo);
    EXPECT_EQ(number_at(m.glb.json, {"accessors", "0", "max", std::to_string(k)}), hi);
  }
}

// glTF is y-up: normals and faces of a terrain point along +y. Away from the hull (where the
// Delaunay triangulation of jittered points leaves steep slivers, whose 3D area dominates the
// area weights) the vertex normals follow the terrain's gentle slopes.
TEST(GltfWriter, NormalsAreUnitAndFacesPointUp) {
  const mesh::Triangulation tin = terrain(true);
  const Mesh m = glb_of(tin);
  ASSERT_FALSE(m.normals.empty());
  const double half_width = number_at(m.glb.json, {"accessors", "0", "max", "0"});
  std::size_t inner = 0;
  for (std::size_t i = 0; i + 2 < m.normals.size(); i += 3) {
    const double x = m.normals[i], y = m.normals[i + 1], z = m.normals[i + 2];
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 1e-6) << "normal " << i / 3;
    EXPECT_GT(y, 0) << "normal " << i / 3;
    const bool near_hull = std::fabs(m.raw_positions[i]) > half_width - 2 ||
                           std::fabs(m.raw_positions[i + 2]) > half_width - 2;
    if (near_hull) continue;
    ++inner;
    EXPECT_GT(y, 0.8) << "normal " << i / 3;  // slopes here are under 25 degrees
  }
  EXPECT_GT(inner, m.normals.size() / 3 / 2);
  const auto& p = m.raw_positions;
  for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
    const auto at = [&](int k) { return 3 * static_cast<std::size_t>(m.triangles[t + k]); };
    const std::size_t a = at(0), b = at(1), c = at(2);
    const double ux = p[b] - p[a], uz = p[b + 2] - p[a + 2];
    const double vx = p[c] - p[a], vz = p[c + 2] - p[a + 2];
    EXPECT_GT(uz * vx - ux * vz, 0) << "triangle " << t / 3;  // y of (b - a) x (c - a)
  }
}

TEST(GltfWriter, ConstrainedEdgesAreALinesPrimitive) {
  const mesh::Triangulation tin = terrain(true);
  const Mesh m = glb_of(tin);
  const json::Value* lines = member(m.glb.json, {"meshes", "0", "primitives", "1"});
  ASSERT_NE(lines, nullptr);
  EXPECT_EQ(number_at(*lines, {"mode"}), 1);  // LINES
  EXPECT_EQ(number_at(*lines, {"indices"}), 3);
  const auto edges = kept_constrained_edges(tin);
  ASSERT_FALSE(edges.empty());
  ASSERT_EQ(m.lines.size(), 2 * edges.size());
  // Each written segment is a kept constrained edge (matched by position).
  for (std::size_t i = 0; i < m.lines.size(); i += 2) {
    const auto& a = m.positions.at(static_cast<std::size_t>(m.lines[i]));
    const auto& b = m.positions.at(static_cast<std::size_t>(m.lines[i + 1]));
    bool found = false;
    for (const auto& [u, v] : edges) {
      const auto near = [&](VertexId w, const std::array<double, 3>& p) {
        return std::fabs(tin.point(w).x - p[0]) < kMillimetre &&
               std::fabs(tin.point(w).y - p[1]) < kMillimetre;
      };
      if ((near(u, a) && near(v, b)) || (near(u, b) && near(v, a))) found = true;
    }
    EXPECT_TRUE(found) << "segment " << i / 2;
  }
}

TEST(GltfWriter, WithoutConstrainedEdgesOnePrimitive) {
  const Mesh m = glb_of(grid(5, 4));
  EXPECT_EQ(member(m.glb.json, {"meshes", "0", "primitives"})->items().size(), 1u);
  EXPECT_EQ(member(m.glb.json, {"accessors", "3"}), nullptr);
  EXPECT_EQ(m.positions.size(), 20u);
  EXPECT_EQ(m.triangles.size(), 3u * 24);
}

TEST(GltfWriter, RecordsTheCrsAndHonoursTheOffset) {
  const std::string dir = test::scratch_dir("gltf_writer");
  const mesh::Triangulation tin = terrain(false);
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:32611");
  o.offset = {512000, 4123000, 700};
  write_tin(dir + "/tin.glb", tin, o);
  const Mesh m = read_mesh(dir + "/tin.glb", o.offset);
  const json::Value& asset = *member(m.glb.json, {"asset"});
  EXPECT_EQ(member(asset, {"version"})->string(), "2.0");
  EXPECT_EQ(member(asset, {"generator"})->string().rfind("tincdt", 0), 0u);
  EXPECT_EQ(member(asset, {"extras", "crs"})->string(), "EPSG:32611");
  EXPECT_EQ(member(asset, {"extras", "crs_wkt"})->string(), o.crs_wkt);
  EXPECT_EQ(number_at(asset, {"extras", "offset", "0"}), 512000);
  EXPECT_EQ(number_at(asset, {"extras", "offset", "1"}), 4123000);
  EXPECT_EQ(number_at(asset, {"extras", "offset", "2"}), 700);
  // The translation is small: the offset was subtracted before the centre was found.
  EXPECT_LT(std::fabs(number_at(m.glb.json, {"nodes", "0", "translation", "0"})), 1000);
  expect_same_triangles(tin, m);
}

// The largest index of each type is reserved: uint16 up to 65535 vertices, uint32 beyond.
TEST(GltfWriter, IndexTypeFollowsTheVertexCount) {
  const std::string dir = test::scratch_dir("gltf_writer");
  write_tin(dir + "/short.glb", grid(255, 257), {});
  const GlbFile small = read_glb(test::slurp(dir + "/short.glb"));
  EXPECT_EQ(number_at(small.json, {"accessors", "0", "count"}), 65535);
  EXPECT_EQ(number_at(small.json, {"accessors", "2", "componentType"}), 5123);
  EXPECT_EQ(accessor_values(small, 2).size(), 3u * 2 * 254 * 256);

  const mesh::Triangulation big = grid(256, 256);
  write_tin(dir + "/int.glb", big, {});
  const Mesh m = read_mesh(dir + "/int.glb");
  EXPECT_EQ(number_at(m.glb.json, {"accessors", "0", "count"}), 65536);
  EXPECT_EQ(number_at(m.glb.json, {"accessors", "2", "componentType"}), 5125);
  EXPECT_EQ(*std::max_element(m.triangles.begin(), m.triangles.end()), 65535);
  expect_same_triangles(big, m);
}

// A TIN with every triangle removed is a scene whose node has no mesh, and no BIN chunk.
TEST(GltfWriter, EmptyTinIsANodeWithoutMesh) {
  const std::string dir = test::scratch_dir("gltf_writer");
  mesh::Triangulation tin = test::unit_square();
  for (TriangleId t = 0; t < tin.triangle_slots(); ++t)
    if (!tin.is_ghost(t)) tin.set_removed(t, true);
  tin.recount();
  const TinWriteStats stats = write_tin(dir + "/empty.glb", tin, {});
  EXPECT_EQ(stats.vertices, 0u);
  EXPECT_EQ(stats.triangles, 0u);
  const GlbFile g = read_glb(test::slurp(dir + "/empty.glb"));
  EXPECT_TRUE(g.bin.empty());
  EXPECT_NE(member(g.json, {"nodes", "0"}), nullptr);
  EXPECT_EQ(member(g.json, {"nodes", "0", "mesh"}), nullptr);
  EXPECT_EQ(member(g.json, {"meshes"}), nullptr);
}

TEST(GltfWriter, IsTheFormatOfGlb) {
  EXPECT_EQ(format_from_path("a.GLB"), TinFormat::glb);
  EXPECT_EQ(format_from_name("glb"), TinFormat::glb);
  EXPECT_EQ(format_info(TinFormat::glb).title, "glTF");
  EXPECT_TRUE(format_takes_offset(TinFormat::glb));
  EXPECT_FALSE(wants_prj(TinFormat::glb, crs_from_user("EPSG:32611")));
}

// ---- the Khronos glTF validator ----------------------------------------------------------------

TEST(GltfValidator, FindsNoErrorInTheWrittenFiles) {
  TINCDT_REQUIRE_WEB_TOOL("gltf-validator");
  const std::string dir = test::scratch_dir("gltf_writer");
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:32611");
  write_tin(dir + "/whole.glb", terrain(false), o);
  write_tin(dir + "/holes.glb", terrain(true), o);
  write_tin(dir + "/grid.glb", grid(256, 256), {});
  mesh::Triangulation empty = test::unit_square();
  for (TriangleId t = 0; t < empty.triangle_slots(); ++t)
    if (!empty.is_ghost(t)) empty.set_removed(t, true);
  empty.recount();
  write_tin(dir + "/empty.glb", empty, {});
  for (const char* name : {"whole.glb", "holes.glb", "grid.glb", "empty.glb"}) {
    SCOPED_TRACE(name);
    const test::GltfReport r = test::validate_gltf(dir + "/" + name);
    EXPECT_EQ(r.errors, 0) << r.text;
    EXPECT_EQ(r.warnings, 0) << r.text;
  }
}

}  // namespace
}  // namespace tincdt::io
