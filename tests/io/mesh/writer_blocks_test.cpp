// The edges of the block-parallel TIN writers (PLY binary and ASCII, OBJ, STL, GeoJSON): record
// counts of none, one, and just below, at and above a multiple of the block size, written with 1,
// 2 and 3 threads, give the same bytes; the smallest TINs give the exact text the formats ask for.
// write_blocks() itself is checked with blocks of 16 records, so a few hundred records make many
// batches of blocks.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_file.hpp"
#include "support/digest.hpp"
#include "support/files.hpp"
#include "support/meshes.hpp"
#include "support/splitmix.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

struct Format {
  const char* name;
  const char* extension;
  bool ply_ascii;
};
constexpr Format kFormats[] = {{"ply binary", ".ply", false},
                               {"ply ascii", ".ply", true},
                               {"obj", ".obj", false},
                               {"stl", ".stl", false},
                               {"geojson", ".geojson", false}};

using test::digest;

class WriterBlocks : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = test::scratch_dir("writer_blocks"); }

  std::string write(const mesh::Triangulation& tin, const Format& f, unsigned threads) const {
    const fs::path path = fs::path(folder_) / (std::string("tin") + f.extension);
    TinWriteOptions options;
    options.ply_ascii = f.ply_ascii;
    options.overwrite = true;
    options.threads = threads;
    write_tin(path.string(), tin, options);
    return test::slurp(path);
  }

  // TIN's file in format F, the same for 1, 2 and 3 threads (checked); the 1-thread bytes.
  std::string write_any_threads(const mesh::Triangulation& tin, const Format& f) const {
    const std::string one = write(tin, f, 1);
    for (const unsigned threads : {2u, 3u})
      EXPECT_TRUE(write(tin, f, threads) == one) << f.name << ", " << threads << " threads";
    return one;
  }

  std::string folder_;
};

// Record i of write_blocks()'s test: its length varies, so the blocks differ in size.
void put_record(detail::BlockWriter& w, std::size_t i) {
  w.put('r');
  w.put_uint(i * i);
  if (i % 3 == 0) w.put(std::string_view(" three"));
  w.put('\n');
}

TEST_F(WriterBlocks, BlocksAreWrittenInRecordOrderForAnyCount) {
  constexpr std::size_t kRecordBytes = detail::kRecordBlockBytes / 16;
  ASSERT_EQ(detail::records_per_block(kRecordBytes), 16u);
  const fs::path path = fs::path(folder_) / "records.txt";
  for (const std::size_t n : {0, 1, 15, 16, 17, 32, 48, 49, 117, 1000}) {
    detail::BlockWriter serial(std::size_t{64});
    serial.put(std::string_view("head\n"));
    for (std::size_t i = 0; i < n; ++i) put_record(serial, i);
    serial.put(std::string_view("tail\n"));
    for (const unsigned threads : {1u, 2u, 3u, 4u}) {
      {
        OutputFile out(path.string(), true);
        detail::BlockWriter w(out);
        Progress progress(nullptr, "write", n);
        w.put(std::string_view("head\n"));
        detail::write_blocks(w, threads, n, kRecordBytes, progress, 0,
                             [](detail::BlockWriter& b, std::size_t begin, std::size_t end) {
                               for (std::size_t i = begin; i < end; ++i) put_record(b, i);
                             });
        w.put(std::string_view("tail\n"));
        w.flush();
        out.commit();
      }
      EXPECT_EQ(test::slurp(path), serial.bytes()) << n << " records, " << threads << " threads";
    }
  }
}

// One triangle, counter-clockwise, at UTM magnitude: the whole file of each text format.
TEST_F(WriterBlocks, OneTriangleIsWrittenExactly) {
  mesh::Triangulation tin;
  tin.add_vertex({test::kX0, test::kY0}, 123.456789012345);
  tin.add_vertex({test::kX0 + 1, test::kY0}, 0.1 + 0.2);
  tin.add_vertex({test::kX0, test::kY0 + 1}, -3.0e-7);
  tin.add_triangle(0, 1, 2);
  test::close_with_ghosts(tin);
  const std::string vertices[] = {"500000.123456789 4000000.987654321 123.456789012345",
                                  "500001.123456789 4000000.987654321 0.30000000000000004",
                                  "500000.123456789 4000001.987654321 -3e-07"};
  const std::string ply_head =
      "ply\nformat ascii 1.0\ncomment tincdt\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list uchar uint vertex_indices\nend_header\n";
  EXPECT_EQ(write_any_threads(tin, kFormats[1]),
            ply_head + vertices[0] + "\n" + vertices[1] + "\n" + vertices[2] + "\n3 0 1 2\n");
  EXPECT_EQ(write_any_threads(tin, kFormats[2]), "# tincdt\n# vertices 3\n# faces 1\nv " +
                                                     vertices[0] + "\nv " + vertices[1] + "\nv " +
                                                     vertices[2] + "\nf 1 2 3\n");
  const std::string ply = write_any_threads(tin, kFormats[0]);
  EXPECT_EQ(ply.size(), ply_head.size() + 15 + 3 * 24 + 13);  // "binary_little_endian" for "ascii"
  EXPECT_EQ(write_any_threads(tin, kFormats[3]).size(), 80u + 4 + 50);
  const std::string geojson = write_any_threads(tin, kFormats[4]);
  EXPECT_EQ(geojson.substr(geojson.size() - 9), "]]}}\n]\n}\n");
  EXPECT_EQ(geojson.find("\"id\":1"), std::string::npos);
}

// Every triangle removed: no vertex, no face, and still a well-formed file.
TEST_F(WriterBlocks, NoTriangleKeptWritesAnEmptyMesh) {
  mesh::Triangulation tin = test::unit_square();
  tin.set_removed(0, true);
  tin.set_removed(1, true);
  EXPECT_EQ(write_any_threads(tin, kFormats[2]), "# tincdt\n# vertices 0\n# faces 0\n");
  const std::string ply = write_any_threads(tin, kFormats[1]);
  EXPECT_NE(ply.find("element vertex 0\n"), std::string::npos);
  EXPECT_NE(ply.find("element face 0\n"), std::string::npos);
  EXPECT_EQ(ply.substr(ply.size() - 11), "end_header\n");
  const std::string ply_binary = write_any_threads(tin, kFormats[0]);
  EXPECT_EQ(ply_binary.substr(ply_binary.size() - 11), "end_header\n");
  const std::string stl = write_any_threads(tin, kFormats[3]);
  EXPECT_EQ(stl.size(), 84u);
  EXPECT_EQ(stl.substr(80), std::string(4, '\0'));
  EXPECT_EQ(write_any_threads(tin, kFormats[4]),
            "{\n\"type\": \"FeatureCollection\",\n\"features\": [\n\n]\n}\n");
}

// N random points triangulated: vertex counts chosen at the edges of the vertex blocks.
mesh::Triangulation random_tin(std::size_t n, std::uint64_t seed) {
  test::SplitMix64 rng{seed};
  std::vector<Point3> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    pts.push_back({500000 + 1000 * rng.unit(), 4000000 + 1000 * rng.unit(), 100 * rng.unit()});
  return std::move(delaunay::triangulate(std::move(pts)).tin);
}

// Vertex counts one below, at and one above two vertex blocks of binary PLY (24-byte records)
// and of OBJ (62-byte lines); the digests of the 1-thread files pin the bytes.
TEST_F(WriterBlocks, VertexCountsAtBlockEdges) {
  struct Case {
    std::size_t vertices;
    std::uint64_t ply_binary, obj;
  };
  const std::size_t ply_block = detail::records_per_block(24);
  const std::size_t obj_block = detail::records_per_block(62);
  const Case cases[] = {{2 * ply_block - 1, 0xab1d1bfa6424fde6, 0x8cbad60320cbf81e},
                        {2 * ply_block, 0xb4fee3113bb23f57, 0xc3897dbcef6ede1b},
                        {2 * ply_block + 1, 0x2116c89e403aad05, 0xb26ae53ca92f2f13},
                        {2 * obj_block - 1, 0x1c73962100b11736, 0xc6d8a33656bfa641},
                        {2 * obj_block, 0x56ad403e809dfa61, 0x5ec8363b24d20c74},
                        {2 * obj_block + 1, 0xe587a73ba84c0479, 0xb2f0574d3fa565ab}};
  for (const Case& c : cases) {
    const mesh::Triangulation tin = random_tin(c.vertices, c.vertices);
    ASSERT_EQ(tin.vertex_count(), c.vertices);
    const std::uint64_t ply = digest(write_any_threads(tin, kFormats[0]));
    const std::uint64_t obj = digest(write_any_threads(tin, kFormats[2]));
    EXPECT_EQ(ply, c.ply_binary) << c.vertices << " vertices: 0x" << std::hex << ply;
    EXPECT_EQ(obj, c.obj) << c.vertices << " vertices: 0x" << std::hex << obj;
  }
}

// The PLY `edge` element is formatted in blocks of half-edges: several blocks of them, with and
// without removed triangles (whose edges are left out), give the same bytes for any thread count.
TEST_F(WriterBlocks, PlyEdgesSpanningSeveralBlocks) {
  mesh::Triangulation tin = random_tin(200000, 5);
  ASSERT_GT(3 * tin.triangle_slots(), 4 * detail::records_per_block(4));
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); e += 3) tin.set_constrained(e, true);
  for (const bool clip : {false, true}) {
    if (clip)
      for (TriangleId t = 0; t < tin.triangle_slots(); t += 2)
        if (!tin.is_ghost(t)) tin.set_removed(t, true);
    const std::string ascii = write_any_threads(tin, kFormats[1]);
    const std::size_t edges = ascii.find("element edge ");
    ASSERT_NE(edges, std::string::npos) << "clip " << clip;
    EXPECT_GT(std::stoull(ascii.substr(edges + 13)), 100000u) << "clip " << clip;
    write_any_threads(tin, kFormats[0]);
  }
}

}  // namespace
}  // namespace tincdt::io
