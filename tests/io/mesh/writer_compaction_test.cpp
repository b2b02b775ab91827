// The writers on a TIN with removed triangles: only the vertices of kept triangles are written,
// renumbered; PLY edges only for constrained edges with a kept triangle on a side; without
// removed triangles every vertex is written under its own number, as before.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

using test::read_obj;
using test::read_ply_ascii;
using test::slurp;

const fs::path kTmp = fs::path(TINCDT_TEST_TMP) / "writer_compaction";

// A 6 x 6 grid (slightly jittered), every interior grid edge on row y = 2 constrained.
mesh::Triangulation grid_tin() {
  std::vector<Point3> pts;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      pts.push_back({i + 0.01 * ((i * 7 + j * 3) % 5), j + 0.013 * ((i * 3 + j * 5) % 7),
                     static_cast<double>(10 * i + j)});
  delaunay::DelaunayResult d = delaunay::triangulate(std::move(pts));
  mesh::Triangulation tin = std::move(d.tin);
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); ++e) {
    const VertexId a = tin.origin(e), b = tin.dest(e);
    if (a >= mesh::kInfinite || b >= mesh::kInfinite) continue;
    if (tin.z(a) - 10 * static_cast<int>(tin.z(a) / 10) == 2 &&
        tin.z(b) - 10 * static_cast<int>(tin.z(b) / 10) == 2)
      tin.set_constrained(e, true);
  }
  return tin;
}

// A written PLY or OBJ, read back.
using Written = test::MeshFile;

// The triangles as sets of corner heights (unique per vertex here), so that two numberings
// compare.
std::set<std::multiset<double>> faces_by_z(const Written& w) {
  std::set<std::multiset<double>> s;
  for (const auto& f : w.f) s.insert({w.v[f[0]][2], w.v[f[1]][2], w.v[f[2]][2]});
  return s;
}

std::set<std::multiset<double>> kept_faces_by_z(const mesh::Triangulation& tin) {
  std::set<std::multiset<double>> s;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    s.insert({tin.z(c[0]), tin.z(c[1]), tin.z(c[2])});
  });
  return s;
}

class Compaction : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(kTmp);
    tin_ = grid_tin();
  }
  // Removes every triangle with a corner at x < 2.5 (the left half).
  void remove_left() {
    for (TriangleId t = 0; t < tin_.triangle_slots(); ++t) {
      if (tin_.is_ghost(t)) continue;
      for (VertexId v : tin_.triangle(t))
        if (tin_.point(v).x < 2.5) tin_.set_removed(t, true);
    }
  }
  TinWriteOptions options(bool ascii = true) {
    TinWriteOptions o;
    o.overwrite = true;
    o.ply_ascii = ascii;
    return o;
  }
  mesh::Triangulation tin_;
};

TEST_F(Compaction, WithoutRemovalEveryVertexKeepsItsNumber) {
  const std::string path = (kTmp / "all.ply").string();
  const TinWriteStats s = write_tin(path, tin_, options());
  const Written w = read_ply_ascii(path);
  EXPECT_EQ(s.vertices, 36u);
  ASSERT_EQ(w.v.size(), 36u);
  for (VertexId v = 0; v < 36; ++v) EXPECT_EQ(w.v[v][2], tin_.z(v));
  EXPECT_EQ(w.e.size(), 5u);  // the row y = 2: 5 grid edges
}

TEST_F(Compaction, PlyAndObjCarryOnlyUsedVertices) {
  remove_left();
  std::set<VertexId> used;
  tin_.for_each_triangle(
      [&](TriangleId, const std::array<VertexId, 3>& c) { used.insert(c.begin(), c.end()); });
  ASSERT_LT(used.size(), 36u);
  for (const bool ascii : {true, false}) {
    const std::string ply = (kTmp / (ascii ? "half_ascii.ply" : "half.ply")).string();
    const TinWriteStats s = write_tin(ply, tin_, options(ascii));
    EXPECT_EQ(s.vertices, used.size());
    EXPECT_EQ(s.triangles, tin_.triangle_count());
    if (!ascii) {
      // Header counts and the file size agree: 24 bytes a vertex, 13 a face, 8 an edge.
      const std::string text = slurp(ply);
      const std::size_t header = text.find("end_header\n") + 11;
      EXPECT_NE(text.find("element vertex " + std::to_string(used.size()) + "\n"),
                std::string::npos);
      EXPECT_EQ(text.size() - header, 24 * used.size() + 13 * s.triangles + 8 * 2);
      continue;
    }
    const Written w = read_ply_ascii(ply);
    ASSERT_EQ(w.v.size(), used.size());
    std::set<std::size_t> referenced;
    for (const auto& f : w.f)
      for (const std::size_t i : f) {
        ASSERT_LT(i, w.v.size());
        referenced.insert(i);
      }
    EXPECT_EQ(referenced.size(), w.v.size());  // every written vertex is used
    EXPECT_EQ(faces_by_z(w), kept_faces_by_z(tin_));
    // Edges of row y = 2 with a kept triangle beside them: columns 3-4 and 4-5 (the triangles
    // on both sides of 2-3 have a corner in column 2).
    ASSERT_EQ(w.e.size(), 2u);
    for (const auto& e : w.e) {
      ASSERT_LT(e[0], w.v.size());
      ASSERT_LT(e[1], w.v.size());
      EXPECT_EQ(static_cast<int>(w.v[e[0]][2]) % 10, 2);
      EXPECT_EQ(static_cast<int>(w.v[e[1]][2]) % 10, 2);
    }
  }
  const std::string obj = (kTmp / "half.obj").string();
  const TinWriteStats s = write_tin(obj, tin_, options());
  const Written w = read_obj(obj);
  EXPECT_EQ(s.vertices, used.size());
  ASSERT_EQ(w.v.size(), used.size());
  EXPECT_NE(slurp(obj).find("# vertices " + std::to_string(used.size()) + "\n"), std::string::npos);
  EXPECT_EQ(faces_by_z(w), kept_faces_by_z(tin_));
}

TEST_F(Compaction, GeoJsonCountsUsedVertices) {
  remove_left();
  std::set<VertexId> used;
  tin_.for_each_triangle(
      [&](TriangleId, const std::array<VertexId, 3>& c) { used.insert(c.begin(), c.end()); });
  const std::string path = (kTmp / "half.geojson").string();
  const TinWriteStats s = write_tin(path, tin_, options());
  EXPECT_EQ(s.vertices, used.size());
  EXPECT_EQ(s.triangles, tin_.triangle_count());
  const std::string text = slurp(path);
  std::size_t features = 0;
  for (std::size_t at = text.find("\"Feature\""); at != std::string::npos;
       at = text.find("\"Feature\"", at + 1))
    ++features;
  EXPECT_EQ(features, s.triangles);
}

}  // namespace
}  // namespace tincdt::io
