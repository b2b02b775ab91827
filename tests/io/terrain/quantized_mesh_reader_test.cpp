// quantized-mesh tiles read by an independent reader, the npm package
// @here/quantized-mesh-decoder (tests/web, cmake/setup_web_tools.sh), through
// decode_tile.mjs: every value it reads equals what was encoded. Skips, saying why, without
// Node.js or the package.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "support/files.hpp"
#include "support/web_tools.hpp"
#include "tile_support.hpp"

namespace tincdt::test::terrain {
namespace {

using io::terrain::encode_quantized_mesh;
using io::terrain::QuantizedMeshOptions;
using io::terrain::tile_rectangle;

// What decode_tile.mjs prints for the tile BYTES.
json::Value read_with_node(const std::string& bytes) {
  const std::string dir = scratch_dir("quantized_mesh_reader");
  const std::string tile = dir + "/tile.terrain", out = dir + "/tile.json";
  spit(tile, bytes);
  const std::string command = "node '" TINCDT_DECODE_TILE_SCRIPT "' '" + web_tools().string() +
                              "' '" + tile + "' > '" + out + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return json::parse(slurp(out), out);
}

const json::Value& member(const json::Value& v, const char* key) {
  const json::Value* m = v.find(key);
  if (m == nullptr) throw std::runtime_error(std::string("no member ") + key);
  return *m;
}

std::vector<double> numbers(const json::Value& array) {
  std::vector<double> out;
  for (const json::Value& v : array.items()) out.push_back(v.number());
  return out;
}

template <class T>
std::vector<double> as_doubles(const std::vector<T>& values) {
  return std::vector<double>(values.begin(), values.end());
}

void expect_header(const TileMesh& m, const json::Value& h) {
  const auto want = io::terrain::quantized_mesh_header(m);
  EXPECT_EQ(member(h, "centerX").number(), want.center.x);
  EXPECT_EQ(member(h, "centerY").number(), want.center.y);
  EXPECT_EQ(member(h, "centerZ").number(), want.center.z);
  EXPECT_EQ(member(h, "minHeight").number(), want.minimum_height);
  EXPECT_EQ(member(h, "maxHeight").number(), want.maximum_height);
  EXPECT_EQ(member(h, "boundingSphereCenterX").number(), want.bounding_sphere_center.x);
  EXPECT_EQ(member(h, "boundingSphereCenterY").number(), want.bounding_sphere_center.y);
  EXPECT_EQ(member(h, "boundingSphereCenterZ").number(), want.bounding_sphere_center.z);
  EXPECT_EQ(member(h, "boundingSphereRadius").number(), want.bounding_sphere_radius);
  EXPECT_EQ(member(h, "horizonOcclusionPointX").number(), want.horizon_occlusion_point.x);
  EXPECT_EQ(member(h, "horizonOcclusionPointY").number(), want.horizon_occlusion_point.y);
  EXPECT_EQ(member(h, "horizonOcclusionPointZ").number(), want.horizon_occlusion_point.z);
}

// The side lists of M in file numbering (ORDER[file] = mesh index), sorted as documented.
std::array<std::vector<double>, 4> expected_sides(
    const TileMesh& m, const std::vector<std::uint32_t>& order,
    const std::vector<std::array<std::uint16_t, 3>>& q) {
  const GeoRectangle& r = m.rectangle;
  std::array<std::vector<std::uint32_t>, 4> sides;
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const Point3& p = m.vertices[order[i]];
    if (p.x == r.west) sides[0].push_back(i);
    if (p.y == r.south) sides[1].push_back(i);
    if (p.x == r.east) sides[2].push_back(i);
    if (p.y == r.north) sides[3].push_back(i);
  }
  std::array<std::vector<double>, 4> out;
  for (int s = 0; s < 4; ++s) {
    const int along = s % 2 == 0 ? 1 : 0;  // west, east by v; south, north by u
    const bool increasing = s == 0 || s == 3;
    std::stable_sort(sides[s].begin(), sides[s].end(), [&](std::uint32_t a, std::uint32_t b) {
      return increasing ? q[a][along] < q[b][along] : q[a][along] > q[b][along];
    });
    out[s] = as_doubles(sides[s]);
  }
  return out;
}

void expect_read_back(const TileMesh& m, const QuantizedMeshOptions& options) {
  const std::string bytes = encode_quantized_mesh(m, options);
  const json::Value tile = read_with_node(bytes);
  expect_header(m, member(tile, "header"));
  ASSERT_EQ(member(tile, "vertexCount").number(), static_cast<double>(m.vertices.size()));

  const auto header = io::terrain::quantized_mesh_header(m);
  const std::vector<std::uint32_t> order = first_use(m);
  std::vector<std::array<std::uint16_t, 3>> q;  // in file order
  std::vector<std::uint32_t> file_index(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    q.push_back(quantized_vertex(m, order[i], header.minimum_height, header.maximum_height));
    file_index[order[i]] = i;
  }
  const char* arrays[3] = {"u", "v", "height"};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> want;
    for (const auto& v : q) want.push_back(v[k]);
    EXPECT_EQ(numbers(member(tile, arrays[k])), want) << arrays[k];
  }
  std::vector<double> indices;
  for (const auto& t : m.triangles) {
    for (const auto c : t) indices.push_back(file_index[c]);
  }
  EXPECT_EQ(numbers(member(tile, "indices")), indices);
  const auto sides = expected_sides(m, order, q);
  const char* names[4] = {"west", "south", "east", "north"};
  for (int s = 0; s < 4; ++s) EXPECT_EQ(numbers(member(tile, names[s])), sides[s]) << names[s];

  // The extensions, against this test's own decoding of the bytes.
  const DecodedTile own = decode_tile(bytes);
  const json::Value& extensions = member(tile, "extensions");
  if (options.vertex_normals) {
    std::vector<double> normals;
    for (const auto& n : *own.normals) normals.insert(normals.end(), {1.0 * n[0], 1.0 * n[1]});
    EXPECT_EQ(numbers(member(extensions, "vertexNormals")), normals);
  } else {
    EXPECT_TRUE(member(extensions, "vertexNormals").is(json::Value::Kind::null));
  }
  const json::Value& metadata = member(extensions, "metadata");
  if (!options.metadata) {
    EXPECT_TRUE(metadata.is(json::Value::Kind::null));
    return;
  }
  const auto& levels = member(metadata, "available").items();
  ASSERT_EQ(levels.size(), options.available.size());
  for (std::size_t l = 0; l < levels.size(); ++l) {
    ASSERT_EQ(levels[l].items().size(), options.available[l].size());
    for (std::size_t i = 0; i < levels[l].items().size(); ++i) {
      const json::Value& range = levels[l].items()[i];
      const auto& want = options.available[l][i];
      EXPECT_EQ(member(range, "startX").number(), want.start_x);
      EXPECT_EQ(member(range, "startY").number(), want.start_y);
      EXPECT_EQ(member(range, "endX").number(), want.end_x);
      EXPECT_EQ(member(range, "endY").number(), want.end_y);
    }
  }
}

TEST(QuantizedMeshReader, ReadsRandomTiles) {
  TINCDT_REQUIRE_WEB_TOOL("@here/quantized-mesh-decoder");
  QuantizedMeshOptions options;
  options.available = {{{100, 60, 101, 61}}, {{200, 120, 203, 121}, {205, 122, 205, 122}}};
  expect_read_back(grid_mesh(21, tile_rectangle({6, 50, 30}), 23, 17, -100, 4000, 3), options);
  expect_read_back(grid_mesh(22, tile_rectangle({1, 0, 1}), 5, 5, 0, 9000), options);
  QuantizedMeshOptions none;
  none.vertex_normals = false;
  none.metadata = false;
  expect_read_back(grid_mesh(23, tile_rectangle({15, 30000, 20000}), 3, 2), none);
}

TEST(QuantizedMeshReader, ReadsOneTriangle) {
  TINCDT_REQUIRE_WEB_TOOL("@here/quantized-mesh-decoder");
  TileMesh m;
  m.rectangle = tile_rectangle({10, 1000, 600});
  m.vertices = {{m.rectangle.west, m.rectangle.south, 12.5},
                {m.rectangle.east, m.rectangle.south, 12.5},
                {m.rectangle.west, m.rectangle.north, 12.5}};
  m.triangles = {{0, 1, 2}};
  expect_read_back(m, {});
}

// More than 65536 vertices: 32-bit indices, after two bytes of padding (65538 is even, but
// 88 + 4 + 6 * 65538 is not a multiple of 4).
TEST(QuantizedMeshReader, ReadsThirtyTwoBitIndices) {
  TINCDT_REQUIRE_WEB_TOOL("@here/quantized-mesh-decoder");
  const TileMesh m = grid_mesh(24, tile_rectangle({16, 70000, 40000}), 32768, 1);
  ASSERT_EQ(m.vertices.size(), 65538u);
  ASSERT_EQ(decode_tile(encode_quantized_mesh(m, {})).index_bytes, 4u);
  expect_read_back(m, {});
}

}  // namespace
}  // namespace tincdt::test::terrain
