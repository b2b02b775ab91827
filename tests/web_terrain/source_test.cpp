#include "web_terrain/source.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "web_terrain/tile.hpp"

namespace tincdt::web_terrain {
namespace {

namespace qm = io::terrain;

// A bumpy 2 km square of random points in UTM zone 32N.
mesh::Triangulation random_tin(unsigned seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> at(0, 2000);
  std::vector<Point3> points;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = at(rng), y = at(rng);
    points.push_back({500000 + x, 5000000 + y, 300 + 40 * std::sin(x / 150) * std::cos(y / 90)});
  }
  return delaunay::triangulate(std::move(points)).tin;
}

// TIN with its vertices and its triangles stored in the reverse order: the same TIN.
mesh::Triangulation reversed(const mesh::Triangulation& tin) {
  mesh::Triangulation out;
  const auto n = static_cast<VertexId>(tin.vertex_count());
  for (VertexId v = n; v-- > 0;) out.add_vertex(tin.point(v), tin.z(v));
  std::vector<std::array<VertexId, 3>> triangles;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    triangles.push_back({n - 1 - c[0], n - 1 - c[1], n - 1 - c[2]});
  });
  std::map<std::pair<VertexId, VertexId>, EdgeId> edges;
  for (auto t = triangles.rbegin(); t != triangles.rend(); ++t) {
    const TriangleId id = out.add_triangle((*t)[0], (*t)[1], (*t)[2]);
    for (int i = 0; i < 3; ++i) {
      const EdgeId e = 3 * id + static_cast<EdgeId>(i);
      const VertexId a = (*t)[i], b = (*t)[(i + 1) % 3];
      if (const auto twin = edges.find({b, a}); twin != edges.end()) out.link(e, twin->second);
      edges[{a, b}] = e;
    }
  }
  return out;
}

std::vector<std::array<Point3, 3>> triangles_of(const qm::TileMesh& m) {
  std::vector<std::array<Point3, 3>> out;
  for (const auto& t : m.triangles) {
    std::array<Point3, 3> c{m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    std::rotate(c.begin(),
                std::min_element(c.begin(), c.end(),
                                 [](const Point3& a, const Point3& b) {
                                   return std::tie(a.x, a.y) < std::tie(b.x, b.y);
                                 }),
                c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return std::tie(a[0].x, a[0].y, a[1].x, a[1].y) < std::tie(b[0].x, b[0].y, b[1].x, b[1].y);
  });
  return out;
}

bool same(const Point3& a, const Point3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

TEST(TerrainSource, NumbersTheVerticesByPlaceWhateverOrderTheTinStoresThem) {
  const std::string utm = io::crs_from_user("EPSG:32632");
  for (const unsigned seed : {1u, 2u, 3u}) {
    const mesh::Triangulation tin = random_tin(seed, 3000 + 1000 * seed);
    const mesh::Triangulation other = reversed(tin);
    ASSERT_EQ(other.triangle_count(), tin.triangle_count());
    const TerrainSource a(tin, utm, "a", std::nullopt), b(other, utm, "b", std::nullopt);
    ASSERT_EQ(a.vertices().size(), tin.vertex_count());
    ASSERT_EQ(b.vertices().size(), a.vertices().size());
    for (std::size_t i = 0; i < a.vertices().size(); ++i)
      ASSERT_TRUE(same(a.vertices()[i], b.vertices()[i])) << "seed " << seed << ", vertex " << i;
    // Cell by cell: the whole data's vertices come in the order of their numbers.
    const std::vector<std::uint32_t> all = a.vertices_in(a.bounds());
    ASSERT_EQ(all.size(), a.vertices().size());
    EXPECT_TRUE(std::is_sorted(all.begin(), all.end()));
    // So the tiles are the same, down to the order of their vertices.
    for (int level = 12; level <= 14; ++level) {
      const qm::TileRange r = qm::tiles_covering(a.bounds(), level);
      const qm::TileKey key{level, (r.start_x + r.end_x) / 2, (r.start_y + r.end_y) / 2};
      const double error = qm::geometric_error_at_level(level);
      const BuiltTile ta = build_tile(a, key, error), tb = build_tile(b, key, error);
      ASSERT_EQ(ta.mesh.vertices.size(), tb.mesh.vertices.size()) << "level " << level;
      for (std::size_t i = 0; i < ta.mesh.vertices.size(); ++i)
        EXPECT_TRUE(same(ta.mesh.vertices[i], tb.mesh.vertices[i])) << "level " << level;
      const auto sa = triangles_of(ta.mesh), sb = triangles_of(tb.mesh);
      ASSERT_EQ(sa.size(), sb.size());
      for (std::size_t t = 0; t < sa.size(); ++t)
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(same(sa[t][k], sb[t][k])) << "level " << level;
      EXPECT_EQ(ta.error.max, tb.error.max);
    }
  }
}

// Transformed in parts on two threads (each part at least 2^16 vertices), the source is the one
// built on one: the same vertices, index, heights and sections.
// A vertex that is no triangle's corner (a mesh file's unused vertex, an outlier whose triangles
// were removed) is not the TIN's: the source is that of the TIN without it.
TEST(TerrainSource, LeavesOutAVertexOfNoTriangle) {
  const std::string utm = io::crs_from_user("EPSG:32632");
  const mesh::Triangulation tin = random_tin(4, 5000);
  mesh::Triangulation with_extra = tin;
  with_extra.add_vertex({501000.5, 5001000.5}, 1e6);
  const TerrainSource plain(tin, utm, "plain", std::nullopt),
      extra(with_extra, utm, "extra", std::nullopt);
  ASSERT_EQ(plain.vertices().size(), tin.vertex_count());
  ASSERT_EQ(extra.vertices().size(), plain.vertices().size());
  for (std::size_t i = 0; i < plain.vertices().size(); ++i)
    ASSERT_TRUE(same(plain.vertices()[i], extra.vertices()[i])) << "vertex " << i;
  EXPECT_EQ(extra.triangle_count(), plain.triangle_count());
  EXPECT_EQ(extra.vertices_in(plain.bounds()), plain.vertices_in(plain.bounds()));
}

TEST(TerrainSource, IsTheSameOnAnyNumberOfThreads) {
  const std::string utm = io::crs_from_user("EPSG:32632");
  const mesh::Triangulation tin = random_tin(11, 140000);
  const TerrainSource one(tin, utm, "one", std::nullopt, 1), two(tin, utm, "two", std::nullopt, 2);
  ASSERT_EQ(two.vertices().size(), one.vertices().size());
  for (std::size_t i = 0; i < one.vertices().size(); ++i)
    ASSERT_TRUE(same(one.vertices()[i], two.vertices()[i])) << "vertex " << i;
  ASSERT_EQ(two.triangle_count(), one.triangle_count());
  std::mt19937 rng(5);
  const GeoRectangle b = one.bounds();
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const double lon = b.west + u(rng) * (b.east - b.west),
                 lat = b.south + u(rng) * (b.north - b.south);
    ASSERT_EQ(one.height_at(lon, lat), two.height_at(lon, lat)) << lon << " " << lat;
    const GeoRectangle r{lon, lat, lon + 0.001, lat + 0.001};
    ASSERT_EQ(one.vertices_in(r), two.vertices_in(r));
  }
  for (int i = 0; i < 50; ++i) {
    const double lon = b.west + u(rng) * (b.east - b.west);
    const auto s1 = one.section(true, lon, b.south, b.north),
               s2 = two.section(true, lon, b.south, b.north);
    ASSERT_EQ(s1.size(), s2.size());
    for (std::size_t k = 0; k < s1.size(); ++k) {
      EXPECT_EQ(s1[k].at, s2[k].at);
      EXPECT_EQ(s1[k].height, s2[k].height);
    }
  }
}

// A coarse tile chooses from its children's vertices, and from the TIN's vertices a try of it
// leaves farthest above half its error: it holds its error whatever it is given, and given every
// vertex of the TIN in it, it is the tile made from the TIN.
TEST(TerrainTiles, CoarseTilesChooseFromTheirChildrenAndHoldTheirError) {
  const std::string utm = io::crs_from_user("EPSG:32632");
  const mesh::Triangulation tin = random_tin(7, 20000);
  const TerrainSource source(tin, utm, "random", std::nullopt);
  for (int level = 10; level <= 12; ++level) {
    const qm::TileRange r = qm::tiles_covering(source.bounds(), level);
    const qm::TileKey key{level, (r.start_x + r.end_x) / 2, (r.start_y + r.end_y) / 2};
    const double error = qm::geometric_error_at_level(level);
    const BuiltTile plain = build_tile(source, key, error);
    ASSERT_LE(plain.error.max, error);
    ASSERT_TRUE(std::is_sorted(plain.tin_vertices.begin(), plain.tin_vertices.end()));
    std::vector<std::uint32_t> children;
    for (std::uint32_t x = 2 * key.x; x <= 2 * key.x + 1; ++x)
      for (std::uint32_t y = 2 * key.y; y <= 2 * key.y + 1; ++y) {
        const BuiltTile child =
            build_tile(source, {level + 1, x, y}, qm::geometric_error_at_level(level + 1));
        children.insert(children.end(), child.tin_vertices.begin(), child.tin_vertices.end());
      }
    std::sort(children.begin(), children.end());
    children.erase(std::unique(children.begin(), children.end()), children.end());
    const std::vector<std::uint32_t> none, all = source.vertices_in(qm::tile_rectangle(key));
    ASSERT_GT(children.size(), 10u) << "level " << level;
    for (const std::vector<std::uint32_t>* finer : {&std::as_const(children), &none, &all}) {
      const BuiltTile coarse = build_tile(source, key, error, nullptr, finer);
      EXPECT_LE(coarse.error.max, error) << "level " << level;
      if (finer == &children) {
        EXPECT_FALSE(coarse.chose_from_all) << "level " << level;
      }
      EXPECT_EQ(coarse.error.count, plain.error.count) << "level " << level;
    }
    const BuiltTile from_all = build_tile(source, key, error, nullptr, &all);
    EXPECT_EQ(triangles_of(from_all.mesh), triangles_of(plain.mesh)) << "level " << level;
    EXPECT_EQ(from_all.tin_vertices, plain.tin_vertices) << "level " << level;
  }
}

// What a failed try of a coarse tile adds: at most one vertex a triangle, each farther than the
// limit, none when no vertex is.
TEST(TerrainTiles, MeasureNamesTheFarthestVertexOfEachTriangleAboveTheLimit) {
  const std::string utm = io::crs_from_user("EPSG:32632");
  const mesh::Triangulation tin = random_tin(9, 20000);
  const TerrainSource source(tin, utm, "random", std::nullopt);
  const qm::TileRange r = qm::tiles_covering(source.bounds(), 12);
  const qm::TileKey key{12, (r.start_x + r.end_x) / 2, (r.start_y + r.end_y) / 2};
  const BuiltTile tile = build_tile(source, key, qm::geometric_error_at_level(12));
  const std::vector<std::uint32_t> inside = source.vertices_in(qm::tile_rectangle(key));
  for (const double share : {0.0, 0.25, 0.5, 2.0}) {
    const double limit = share * tile.error.max;
    std::vector<std::uint32_t> above;
    const TileError e = measure_tile(source, tile.mesh, {}, inside, nullptr, limit, &above);
    EXPECT_EQ(e.max, tile.error.max);
    EXPECT_TRUE(std::is_sorted(above.begin(), above.end()));
    EXPECT_EQ(std::adjacent_find(above.begin(), above.end()), above.end());
    EXPECT_LE(above.size(), tile.mesh.triangles.size());
    EXPECT_EQ(above.empty(), !(tile.error.max > limit)) << "limit " << limit;
    std::size_t farther = 0;
    for (const std::uint32_t v : inside) {
      const double ev = measure_tile(source, tile.mesh, {}, std::span(&v, 1)).max;
      farther += ev > limit ? 1 : 0;
      if (std::binary_search(above.begin(), above.end(), v)) {
        EXPECT_GT(ev, limit);
      }
    }
    EXPECT_LE(above.size(), farther);
  }
}

}  // namespace
}  // namespace tincdt::web_terrain
