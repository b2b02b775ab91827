// quantized-mesh-1.0 tiles read back by the test's own decoder (tile_support.hpp), written from
// the specification: every vertex, triangle and side list as the mesh says, the header bounding
// what a viewer draws, normals close to the surface's, 16- and 32-bit indices at the right
// vertex counts with the alignment padding, and meshes at the edge of sense.
#include "io/terrain/quantized_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "core/json.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "tile_support.hpp"

namespace tincdt::test::terrain {
namespace {

using io::terrain::encode_quantized_mesh;
using io::terrain::QuantizedMeshOptions;
using io::terrain::tile_rectangle;
using io::terrain::TileRange;
using Key = std::array<std::uint16_t, 3>;  // u, v, height

// The quantized u, v, height of vertex I of M in tile D.
Key expected_key(const TileMesh& m, const DecodedTile& d, std::uint32_t i) {
  return quantized_vertex(m, i, d.minimum_height, d.maximum_height);
}

Key decoded_key(const DecodedTile& d, std::uint32_t i) {
  return {d.u[i], d.v[i], d.height[i]};
}

void expect_heights(const TileMesh& m, const DecodedTile& d) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const Point3& p : m.vertices) low = std::min(low, p.z), high = std::max(high, p.z);
  // The nearest floats outside the vertices' range.
  EXPECT_LE(d.minimum_height, low);
  EXPECT_GT(std::nextafter(d.minimum_height, std::numeric_limits<float>::infinity()), low);
  EXPECT_GE(d.maximum_height, high);
  EXPECT_LT(std::nextafter(d.maximum_height, -std::numeric_limits<float>::infinity()), high);
}

// Every corner and every unused vertex as the mesh has it, within half a step of where it was.
void expect_vertices(const TileMesh& m, const DecodedTile& d) {
  // A mesh of 65536 vertices may get one more, unused, for 32-bit indices.
  const std::size_t added = d.u.size() - m.vertices.size();
  ASSERT_TRUE(added == 0 || (added == 1 && m.vertices.size() == 65536)) << d.u.size();
  ASSERT_EQ(d.indices.size(), 3 * m.triangles.size());
  std::vector<char> used(m.vertices.size(), 0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t di = d.indices[3 * t + k];
      ASSERT_LT(di, d.u.size());
      ASSERT_EQ(decoded_key(d, di), expected_key(m, d, m.triangles[t][k])) << t << " " << k;
      used[m.triangles[t][k]] = 1;
    }
  }
  std::multiset<Key> unused_expected, unused_decoded;
  for (std::uint32_t i = 0; i < m.vertices.size(); ++i) {
    if (!used[i]) unused_expected.insert(expected_key(m, d, i));
  }
  std::vector<char> referenced(d.u.size(), 0);
  for (const auto i : d.indices) referenced[i] = 1;
  for (std::uint32_t i = 0; i < d.u.size(); ++i) {
    if (!referenced[i]) unused_decoded.insert(decoded_key(d, i));
  }
  if (added == 1) {  // at the rectangle's centre, at vertex 0's height
    const GeoRectangle& r = m.rectangle;
    const Key first = quantized_vertex(m, 0, d.minimum_height, d.maximum_height);
    unused_expected.insert({quantized((r.west + r.east) / 2, r.west, r.east),
                            quantized((r.south + r.north) / 2, r.south, r.north), first[2]});
  }
  EXPECT_EQ(unused_decoded, unused_expected);
  const GeoRectangle& r = m.rectangle;
  const double span_h = d.maximum_height - static_cast<double>(d.minimum_height);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Point3& p = m.vertices[m.triangles[t][0]];
    const std::uint32_t di = d.indices[3 * t];
    EXPECT_NEAR(r.west + d.u[di] / 32767.0 * (r.east - r.west), p.x,
                (r.east - r.west) / 32767.0 * 0.5000001);
    EXPECT_NEAR(r.south + d.v[di] / 32767.0 * (r.north - r.south), p.y,
                (r.north - r.south) / 32767.0 * 0.5000001);
    EXPECT_NEAR(d.minimum_height + d.height[di] / 32767.0 * span_h, p.z,
                span_h / 32767.0 * 0.5000001 + 1e-9);
  }
}

// Each side lists exactly the vertices on it (by their quantized values), at 0 or 32767 there,
// in Cesium's order: west south to north, south east to west, east north to south, north west
// to east.
void expect_sides(const TileMesh& m, const DecodedTile& d) {
  const GeoRectangle& r = m.rectangle;
  std::array<std::multiset<Key>, 4> expected, decoded;
  for (std::uint32_t i = 0; i < m.vertices.size(); ++i) {
    const Point3& p = m.vertices[i];
    const Key k = expected_key(m, d, i);
    const bool on[4] = {p.x == r.west, p.y == r.south, p.x == r.east, p.y == r.north};
    for (int s = 0; s < 4; ++s) {
      if (!on[s]) continue;
      expected[s].insert(k);
      EXPECT_EQ(s % 2 == 0 ? std::get<0>(k) : std::get<1>(k), s < 2 ? 0 : 32767) << i;
    }
  }
  for (int s = 0; s < 4; ++s) {
    for (const auto i : d.sides[s]) decoded[s].insert(decoded_key(d, i));
    EXPECT_EQ(decoded[s], expected[s]) << "side " << s;
  }
  const auto along = [&](int s, std::uint32_t i) { return s % 2 == 0 ? d.v[i] : d.u[i]; };
  for (int s = 0; s < 4; ++s) {
    const bool increasing = s == 0 || s == 3;
    for (std::size_t k = 1; k < d.sides[s].size(); ++k) {
      const auto a = along(s, d.sides[s][k - 1]), b = along(s, d.sides[s][k]);
      EXPECT_TRUE(increasing ? a <= b : a >= b) << "side " << s << " item " << k;
    }
  }
}

// The sphere holds every vertex where a viewer puts it; the horizon point hides only when every
// vertex does, from cameras all round.
void expect_bounds(const TileMesh& m, const DecodedTile& d) {
  const GeoRectangle& r = m.rectangle;
  const double span_h = d.maximum_height - static_cast<double>(d.minimum_height);
  std::vector<Vec3> scaled_vertices;
  for (std::uint32_t i = 0; i < d.u.size(); ++i) {
    const Vec3 p = ecef(r.west + d.u[i] / 32767.0 * (r.east - r.west),
                        r.south + d.v[i] / 32767.0 * (r.north - r.south),
                        d.minimum_height + d.height[i] / 32767.0 * span_h);
    // A micrometre for the two ECEF formulas' rounding.
    EXPECT_LE(norm3(sub(p, d.sphere_center)), d.sphere_radius + 1e-6) << i;
    Vec3 s = scaled(p);
    const double l = norm3(s);
    if (l < 1) s = {s[0] / l, s[1] / l, s[2] / l};  // below the ellipsoid counts as on it
    scaled_vertices.push_back(s);
  }
  // A tile as wide as a hemisphere has no exact point (HemisphereTileHorizonPoint).
  if (r.east - r.west >= 180) return;
  SplitMix64 rng{99};
  const int cameras = scaled_vertices.size() > 10000 ? 100 : 2000;
  for (int c = 0; c < cameras; ++c) {
    const double z = 2 * rng.unit() - 1, a = 2 * std::numbers::pi * rng.unit();
    const double dist = 1.0005 + 5 * rng.unit() * rng.unit();
    const double ring = std::sqrt(1 - z * z) * dist;
    const Vec3 camera{ring * std::cos(a), ring * std::sin(a), z * dist};
    if (!hidden_by_horizon(d.horizon_point, camera)) continue;
    for (const Vec3& s : scaled_vertices) ASSERT_TRUE(hidden_by_horizon(s, camera));
  }
}

void expect_normals(const TileMesh& m, const DecodedTile& d) {
  ASSERT_TRUE(d.normals.has_value());
  const auto want = area_weighted_normals(m);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 got = oct_decode((*d.normals)[d.indices[3 * t + k]]);
      EXPECT_GT(dot3(got, want[m.triangles[t][k]]), std::cos(1.5 * std::numbers::pi / 180));
    }
  }
}

void expect_metadata(const QuantizedMeshOptions& options, const DecodedTile& d) {
  ASSERT_TRUE(d.metadata.has_value());
  const json::Value doc = json::parse(*d.metadata);
  const json::Value* available = doc.find("available");
  ASSERT_NE(available, nullptr);
  ASSERT_EQ(available->items().size(), options.available.size());
  for (std::size_t level = 0; level < options.available.size(); ++level) {
    const auto& ranges = available->items()[level].items();
    ASSERT_EQ(ranges.size(), options.available[level].size());
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const TileRange& want = options.available[level][i];
      EXPECT_EQ(ranges[i].find("startX")->number(), want.start_x);
      EXPECT_EQ(ranges[i].find("startY")->number(), want.start_y);
      EXPECT_EQ(ranges[i].find("endX")->number(), want.end_x);
      EXPECT_EQ(ranges[i].find("endY")->number(), want.end_y);
    }
  }
}

// Encodes M, decodes it and checks it all; returns the tile.
DecodedTile round_trip(const TileMesh& m, const QuantizedMeshOptions& options = {}) {
  const std::string bytes = encode_quantized_mesh(m, options);
  EXPECT_EQ(encode_quantized_mesh(m, options), bytes) << "not deterministic";
  DecodedTile d = decode_tile(bytes);
  expect_heights(m, d);
  expect_vertices(m, d);
  expect_sides(m, d);
  expect_bounds(m, d);
  if (options.vertex_normals) expect_normals(m, d);
  EXPECT_EQ(d.normals.has_value(), options.vertex_normals);
  if (options.metadata) expect_metadata(options, d);
  EXPECT_EQ(d.metadata.has_value(), options.metadata);
  return d;
}

TEST(QuantizedMesh, RoundTripsRandomMeshes) {
  QuantizedMeshOptions options;
  options.available = {{{6548, 3276, 6549, 3277}}, {{13096, 6552, 13099, 6555}, {1, 2, 3, 4}}};
  const std::vector<GeoRectangle> rects = {tile_rectangle({12, 3274, 1638}),
                                           tile_rectangle({5, 40, 20}), tile_rectangle({1, 3, 1}),
                                           tile_rectangle({3, 0, 0})};
  std::uint64_t seed = 1;
  for (const GeoRectangle& r : rects) {
    const std::tuple<int, int, int> grids[] = {{1, 1, 0}, {7, 3, 2}, {40, 31, 5}};
    for (const auto& [cols, rows, extra] : grids) {
      SCOPED_TRACE(testing::Message()
                   << "rect " << r.west << "," << r.south << " grid " << cols << "x" << rows);
      const TileMesh m = grid_mesh(seed++, r, cols, rows, -40, 2500, extra);
      const DecodedTile d = round_trip(m, options);
      EXPECT_EQ(d.index_bytes, 2u);
    }
  }
}

TEST(QuantizedMesh, WithoutExtensionsEndsAtTheSides) {
  const TileMesh m = grid_mesh(5, tile_rectangle({9, 100, 200}), 4, 4);
  QuantizedMeshOptions none;
  none.vertex_normals = false;
  none.metadata = false;
  const DecodedTile d = round_trip(m, none);
  EXPECT_FALSE(d.normals || d.metadata);
}

// 16-bit indices up to 65536 vertices, 32-bit beyond, aligned to 4 bytes by zero padding.
TEST(QuantizedMesh, IndexWidthFollowsTheVertexCount) {
  const GeoRectangle r = tile_rectangle({14, 16000, 9000});
  {
    SCOPED_TRACE("65536 vertices, row by row: every code fits 16 bits");
    const TileMesh m = grid_mesh(7, r, 255, 255, -40, 2500, 0, false);
    ASSERT_EQ(m.vertices.size(), 65536u);
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.index_bytes, 2u);
    EXPECT_EQ(d.u.size(), 65536u);
    EXPECT_EQ(d.triangles_offset, 88u + 4 + 6 * 65536);
  }
  {
    SCOPED_TRACE("65536 vertices, vertex 0 used last: a vertex more, 32-bit");
    TileMesh m = grid_mesh(7, r, 255, 255, -40, 2500, 0, false);
    std::rotate(m.triangles.begin(), m.triangles.begin() + 1, m.triangles.end());
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.index_bytes, 4u);
    EXPECT_EQ(d.u.size(), 65537u);
  }
  {
    SCOPED_TRACE("65537 vertices, one unused");
    const TileMesh m = grid_mesh(8, r, 255, 255, -40, 2500, 1);
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.index_bytes, 4u);
    // 88 + 4 + 6 * 65537 = 393314: two bytes of padding.
    EXPECT_EQ(d.triangles_offset, 393316u);
  }
  {
    SCOPED_TRACE("67600 vertices: aligned already");
    const TileMesh m = grid_mesh(9, r, 259, 259);
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.index_bytes, 4u);
    EXPECT_EQ(d.triangles_offset, 88u + 4 + 6 * 67600);
    EXPECT_GT(*std::max_element(d.indices.begin(), d.indices.end()), 65535u);
  }
}

// The format by hand: one triangle on three corners, all on sides.
TEST(QuantizedMesh, OneTriangleGivesTheSpecifiedBytes) {
  TileMesh m;
  m.rectangle = {10, 20, 11, 21};
  m.vertices = {{10, 20, 0}, {11, 20, 10}, {10, 21, 20}};
  m.triangles = {{0, 1, 2}};
  QuantizedMeshOptions none;
  none.vertex_normals = false;
  none.metadata = false;
  const std::string bytes = encode_quantized_mesh(m, none);
  Cursor c(bytes);
  for (int i = 0; i < 3; ++i) c.f64();
  EXPECT_EQ(c.f32(), 0.0f);
  EXPECT_EQ(c.f32(), 20.0f);
  for (int i = 0; i < 7; ++i) c.f64();
  EXPECT_EQ(c.u32(), 3u);
  // u 0, 32767, 0: deltas 0, 32767, -32767, zig-zag 0, 65534, 65533.
  for (const int want : {0, 65534, 65533}) EXPECT_EQ(c.u16(), want);
  for (const int want : {0, 0, 65534}) EXPECT_EQ(c.u16(), want);      // v 0, 0, 32767
  for (const int want : {0, 32768, 32766}) EXPECT_EQ(c.u16(), want);  // h 0, 16384, 32767
  EXPECT_EQ(c.u32(), 1u);                                             // triangles
  for (const int want : {0, 0, 0}) EXPECT_EQ(c.u16(), want);          // all new vertices
  for (const auto& side : std::vector<std::vector<int>>{{0, 2}, {1, 0}, {1}, {2}}) {
    EXPECT_EQ(c.u32(), side.size());
    for (const int want : side) EXPECT_EQ(c.u16(), want);
  }
  EXPECT_TRUE(c.at_end());
  round_trip(m);
}

TEST(QuantizedMesh, DegenerateMeshes) {
  const GeoRectangle r = tile_rectangle({10, 500, 300});
  const double w = r.west, s = r.south, e = r.east, n = r.north;
  const double mx = (w + e) / 2, my = (s + n) / 2;
  {
    SCOPED_TRACE("every vertex on a side, no inner vertex");
    TileMesh m;
    m.rectangle = r;
    m.vertices = {{w, s, 5}, {mx, s, 6},  {e, s, 7},  {e, my, 8},
                  {e, n, 9}, {mx, n, 10}, {w, n, 11}, {w, my, 12}};
    m.triangles = {{0, 1, 7}, {1, 2, 3}, {3, 4, 5}, {5, 6, 7}, {1, 3, 5}, {1, 5, 7}};
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.sides[0].size(), 3u);
    EXPECT_EQ(d.sides[1].size(), 3u);
  }
  {
    SCOPED_TRACE("one inner triangle, flat");
    TileMesh m;
    m.rectangle = r;
    m.vertices = {{w + 0.01, s + 0.01, 100}, {e - 0.01, s + 0.02, 100}, {mx, n - 0.01, 100}};
    m.triangles = {{0, 1, 2}};
    const DecodedTile d = round_trip(m);
    EXPECT_EQ(d.minimum_height, d.maximum_height);
    for (const auto h : d.height) EXPECT_EQ(h, 0);
    for (const auto& side : d.sides) EXPECT_TRUE(side.empty());
  }
  {
    SCOPED_TRACE("vertices and no triangles");
    TileMesh m;
    m.rectangle = r;
    m.vertices = {{w, s, -3}, {e, n, 4}};
    round_trip(m);
  }
}

// A level-0 tile spans a hemisphere: no finite horizon point bounds it, so the point goes far
// out over its centre, hiding the tile only from behind the globe.
TEST(QuantizedMesh, HemisphereTileHorizonPoint) {
  const TileMesh m = grid_mesh(11, tile_rectangle({0, 0, 0}), 8, 8, 0, 3000);
  const DecodedTile d = round_trip(m);
  const Vec3 hp{d.horizon_point[0], d.horizon_point[1], d.horizon_point[2]};
  ASSERT_TRUE(std::isfinite(norm3(hp)));
  EXPECT_NEAR(hp[0] / norm3(hp), 0, 1e-12);  // over longitude -90 on the equator
  EXPECT_NEAR(hp[1] / norm3(hp), -1, 1e-12);
  EXPECT_FALSE(hidden_by_horizon(hp, {0, -2, 0}));
  EXPECT_FALSE(hidden_by_horizon(hp, {1.5, 0, 0}));  // above longitude 0: the tile's east side
  EXPECT_TRUE(hidden_by_horizon(hp, {0, 3, 0}));
}

TEST(QuantizedMesh, RefusesMeshesItCannotWrite) {
  const GeoRectangle r{0, 0, 1, 1};
  TileMesh outside{r, {{0, 0, 0}, {1.5, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
  TileMesh bad_index{r, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}}};
  TileMesh empty{r, {}, {}};
  TileMesh not_finite{r, {{0, 0, std::nan("")}}, {}};
  for (const TileMesh* m : {&outside, &bad_index, &empty, &not_finite}) {
    EXPECT_THROW(encode_quantized_mesh(*m, {}), InternalError);
    EXPECT_THROW(io::terrain::quantized_mesh_header(*m), InternalError);
  }
}

TEST(QuantizedMesh, HeaderIsWhatTheFileHolds) {
  const TileMesh m = grid_mesh(12, tile_rectangle({8, 300, 100}), 9, 9);
  const auto h = io::terrain::quantized_mesh_header(m);
  const DecodedTile d = decode_tile(encode_quantized_mesh(m, {}));
  EXPECT_EQ(d.center, (std::array{h.center.x, h.center.y, h.center.z}));
  EXPECT_EQ(d.minimum_height, h.minimum_height);
  EXPECT_EQ(d.maximum_height, h.maximum_height);
  EXPECT_EQ(d.sphere_center, (std::array{h.bounding_sphere_center.x, h.bounding_sphere_center.y,
                                         h.bounding_sphere_center.z}));
  EXPECT_EQ(d.sphere_radius, h.bounding_sphere_radius);
  EXPECT_EQ(d.horizon_point, (std::array{h.horizon_occlusion_point.x, h.horizon_occlusion_point.y,
                                         h.horizon_occlusion_point.z}));
  // The centre: the rectangle's middle, halfway up the heights.
  const GeoRectangle& r = m.rectangle;
  const Vec3 c = ecef((r.west + r.east) / 2, (r.south + r.north) / 2,
                      (static_cast<double>(h.minimum_height) + h.maximum_height) / 2);
  EXPECT_NEAR(norm3(sub(c, d.center)), 0, 1e-6);
}

}  // namespace
}  // namespace tincdt::test::terrain
