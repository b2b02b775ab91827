// The TIN writers that format their records on several threads (PLY binary and ASCII, OBJ, STL,
// GeoJSON): the bytes are the same for any thread count, with and without removed triangles, and
// the same as the single-threaded writer's always were (a digest per format of one small TIN).
// A bad vertex is reported as the first one in file order, whichever thread met it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/digest.hpp"
#include "support/files.hpp"
#include "support/splitmix.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

// A folder of the running test's own: CTest runs the tests of this file at once.
fs::path test_folder() {
  return fs::path(TINCDT_TEST_TMP) / "parallel_writer" /
         ::testing::UnitTest::GetInstance()->current_test_info()->name();
}

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

// N points at map coordinates with fractional parts, heights with many digits.
mesh::Triangulation random_tin(std::size_t n, std::uint64_t seed) {
  test::SplitMix64 rng{seed};
  std::vector<Point3> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 500000 + 1000 * rng.unit();
    const double y = 4000000 + 1000 * rng.unit();
    pts.push_back({x, y, 100 + 50 * rng.unit()});
  }
  return std::move(delaunay::triangulate(std::move(pts)).tin);
}

// Every fifth real edge constrained (a PLY `edge` element), every triangle with a corner in the
// left third removed (renumbered vertices, removed slots between kept ones).
void constrain_and_clip(mesh::Triangulation& tin, bool clip) {
  for (EdgeId e = 0; e < 3 * tin.triangle_slots(); e += 5) {
    if (tin.origin(e) >= mesh::kInfinite || tin.dest(e) >= mesh::kInfinite) continue;
    tin.set_constrained(e, true);
  }
  if (!clip) return;
  double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
  for (const Point2& p : tin.points()) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
  }
  const double cut = min_x + (max_x - min_x) / 3;
  for (TriangleId t = 0; t < tin.triangle_slots(); ++t) {
    if (tin.is_ghost(t)) continue;
    for (const VertexId v : tin.triangle(t))
      if (tin.point(v).x < cut) tin.set_removed(t, true);
  }
}

std::string write(const mesh::Triangulation& tin, const Format& f, unsigned threads,
                  const Point3& offset = {0, 0, 0}) {
  const fs::path path = test_folder() / (std::string("tin") + f.extension);
  TinWriteOptions options;
  options.ply_ascii = f.ply_ascii;
  options.overwrite = true;
  options.offset = offset;
  options.threads = threads;
  write_tin(path.string(), tin, options);
  return test::slurp(path);
}

using test::digest;

class ParallelWriter : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(test_folder()); }
};

// With the digests of the files the single-threaded writers wrote before they formatted in
// blocks.
TEST_F(ParallelWriter, BytesDoNotDependOnTheThreadCount) {
  const std::uint64_t serial[2][std::size(kFormats)] = {
      {0x37f3080286c304d6, 0x40cc2fc7b7dfdd52, 0x2768889521b0d620, 0xd22f2219ed41cc4d,
       0xd0726036892364b3},
      {0x3b11ecde3907fd37, 0x26802c6c728cd369, 0x5f734e017a269671, 0x6e9499a5e9d8d887,
       0x139e2e7574e0c80a}};
  for (const bool clip : {false, true}) {
    mesh::Triangulation tin = random_tin(200000, 7);
    constrain_and_clip(tin, clip);
    for (std::size_t i = 0; i < std::size(kFormats); ++i) {
      const Format& f = kFormats[i];
      const std::string one = write(tin, f, 1);
      ASSERT_GT(one.size(), std::size_t{4} << 20) << f.name;  // several blocks
      EXPECT_EQ(digest(one), serial[clip][i])
          << f.name << ", clip " << clip << ": 0x" << std::hex << digest(one);
      for (const unsigned threads : {2u, 7u}) {
        const std::string many = write(tin, f, threads);
        EXPECT_EQ(many.size(), one.size()) << f.name << ", clip " << clip << ", " << threads;
        EXPECT_TRUE(many == one) << f.name << ", clip " << clip << ", " << threads << " threads";
      }
    }
  }
}

// Digests of the files the single-threaded writers wrote before they formatted in blocks.
TEST_F(ParallelWriter, BytesAreThoseOfTheSerialWriter) {
  struct Case {
    bool clip;
    Point3 offset;
    std::uint64_t digests[std::size(kFormats)];
  };
  const Case cases[] = {
      {false,
       {0, 0, 0},
       {0x5dfeb955cf5cee1f, 0xd5a72908574824b6, 0xfa67bca3187c5534, 0x441c3d436e9c3296,
        0xab74017101697fe6}},
      {true,
       {500000, 4000000, 100},
       {0xa3e978b70c67c0ee, 0x80a9f4cfcee43a63, 0x157db19ca5fe447, 0x8467a28c506d92b4,
        0x460bc834a464af8e}},
  };
  for (const Case& c : cases) {
    mesh::Triangulation tin = random_tin(500, 3);
    constrain_and_clip(tin, c.clip);
    for (std::size_t i = 0; i < std::size(kFormats); ++i)
      for (const unsigned threads : {1u, 3u}) {
        const std::uint64_t d = digest(write(tin, kFormats[i], threads, c.offset));
        EXPECT_EQ(d, c.digests[i]) << kFormats[i].name << ", clip " << c.clip << ", " << threads
                                   << " threads: 0x" << std::hex << d;
      }
  }
}

TEST_F(ParallelWriter, TheFirstBadVertexInTheFileIsReported) {
  mesh::Triangulation tin = random_tin(200000, 11);
  const VertexId bad[] = {150000, 190000};
  tin.set_z(bad[0], std::numeric_limits<double>::quiet_NaN());
  tin.set_z(bad[1], std::numeric_limits<double>::infinity());
  // STL and GeoJSON write corners face by face: the first bad corner of the first bad face.
  VertexId first_by_face = kNoId;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    for (const VertexId v : c)
      if (first_by_face == kNoId && (v == bad[0] || v == bad[1])) first_by_face = v;
  });
  for (const Format& f : kFormats) {
    const bool by_face =
        f.extension == std::string(".stl") || f.extension == std::string(".geojson");
    const std::string expected = "vertex " + std::to_string(by_face ? first_by_face : bad[0]);
    for (const unsigned threads : {1u, 2u, 7u}) {
      try {
        write(tin, f, threads);
        ADD_FAILURE() << f.name << ": no error";
      } catch (const OutputError& e) {
        EXPECT_EQ(e.where(), expected) << f.name << ", " << threads << " threads: " << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace tincdt::io
