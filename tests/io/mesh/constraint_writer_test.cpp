// Constraint lines as GeoJSON: meshes built by hand at UTM magnitude, written, read back with
// GDAL's GeoJSON driver and compared bit for bit; the safe-output rules of the TIN writers.
#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <sys/stat.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "io/mesh/constraint_writer.hpp"
#include "io/mesh/tin_writer.hpp"
#include "mesh/triangulation.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/meshes.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using mesh::kInfinite;
using mesh::Triangulation;
using test::kX0;
using test::kY0;
using test::names_in;
using test::slurp;
using test::spit;

// ---- meshes --------------------------------------------------------------------------------

// The unit square of test::unit_square (0 SW, 1 SE, 2 NE, 3 NW; triangles (0, 1, 2) and
// (0, 2, 3), closed by four ghosts) with the diagonal 0-2 and the hull edges 0-1 and 2-3
// constrained.
Triangulation unit_square() {
  Triangulation tin = test::unit_square(/*constrain_diagonal=*/true);
  tin.set_constrained(0, true);  // 0 -> 1
  tin.set_constrained(4, true);  // 2 -> 3
  return tin;
}

// The square's constrained edges, as the pipeline would pass them: the diagonal from feature 0,
// the two hull edges from feature 1.
std::vector<ConstraintEdge> square_edges() {
  return {{0, 2, 0}, {0, 1, 1}, {2, 3, 1}};
}

std::vector<ConstraintFeatureInfo> square_features() {
  return {{"contours.shp", 7}, {"breaklines.gpkg:roads", 42}};
}

// ---- files ---------------------------------------------------------------------------------

std::string scratch() {
  return test::scratch_dir("constraint_writer");
}

std::uint64_t bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}

// ---- reading back with GDAL ----------------------------------------------------------------

struct GeoJson : test::VectorFile {
  explicit GeoJson(const std::string& path) : VectorFile(path, "GeoJSON") {}
};

struct Line {
  std::vector<Point3> points;
  std::string source_file;
  std::int64_t source_fid = 0;
  double z_start = 0;
  double z_end = 0;
};

std::vector<Line> read_lines_back(const GeoJson& g) {
  std::vector<Line> out;
  OGRLayerH layer = g.layer();
  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
  const int file = OGR_FD_GetFieldIndex(defn, "source_file");
  const int fid = OGR_FD_GetFieldIndex(defn, "source_fid");
  const int z0 = OGR_FD_GetFieldIndex(defn, "z_start");
  const int z1 = OGR_FD_GetFieldIndex(defn, "z_end");
  EXPECT_GE(file, 0);
  EXPECT_GE(fid, 0);
  EXPECT_GE(z0, 0);
  EXPECT_GE(z1, 0);
  if (file < 0 || fid < 0 || z0 < 0 || z1 < 0) return out;
  EXPECT_EQ(OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, file)), OFTString);
  EXPECT_EQ(OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, z0)), OFTReal);
  EXPECT_EQ(OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, z1)), OFTReal);
  OGR_L_ResetReading(layer);
  while (OGRFeatureH f = OGR_L_GetNextFeature(layer)) {
    Line l;
    OGRGeometryH geometry = OGR_F_GetGeometryRef(f);
    EXPECT_NE(geometry, nullptr);
    if (geometry != nullptr) {
      EXPECT_EQ(OGR_G_GetGeometryType(geometry), wkbLineString25D);
      for (int i = 0; i < OGR_G_GetPointCount(geometry); ++i) {
        Point3 p{};
        OGR_G_GetPoint(geometry, i, &p.x, &p.y, &p.z);
        l.points.push_back(p);
      }
    }
    l.source_file = OGR_F_GetFieldAsString(f, file);
    l.source_fid = OGR_F_GetFieldAsInteger64(f, fid);
    l.z_start = OGR_F_GetFieldAsDouble(f, z0);
    l.z_end = OGR_F_GetFieldAsDouble(f, z1);
    out.push_back(std::move(l));
    OGR_F_Destroy(f);
  }
  return out;
}

Point3 vertex(const Triangulation& tin, VertexId v) {
  return {tin.point(v).x, tin.point(v).y, tin.z(v)};
}

void expect_bits(const Point3& got, const Point3& want) {
  EXPECT_EQ(bits(got.x), bits(want.x)) << got.x << " vs " << want.x;
  EXPECT_EQ(bits(got.y), bits(want.y)) << got.y << " vs " << want.y;
  EXPECT_EQ(bits(got.z), bits(want.z)) << got.z << " vs " << want.z;
}

// ---- content ---------------------------------------------------------------------------------

TEST(ConstraintWriter, TheHandMadeMeshIsValid) {
  const Triangulation tin = unit_square();
  EXPECT_EQ(tin.validate({false}), "");
  std::set<std::pair<VertexId, VertexId>> constrained;
  tin.for_each_constrained_edge([&](EdgeId e) {
    constrained.insert({tin.origin(e), tin.dest(e)});
  });
  std::set<std::pair<VertexId, VertexId>> passed;
  for (const ConstraintEdge& e : square_edges()) passed.insert({e.a, e.b});
  EXPECT_EQ(constrained, passed);
}

TEST(ConstraintWriter, GdalReadsEveryEdgeWithExactCoordinatesAndItsSource) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:2949");
  const std::string path = dir + "/constraints.geojson";
  const TinWriteStats stats =
      write_constraint_lines(path, tin, square_edges(), square_features(), o);
  EXPECT_EQ(stats.vertices, 4u);
  EXPECT_EQ(stats.triangles, 0u);
  EXPECT_EQ(stats.bytes, fs::file_size(path));

  const std::string text = slurp(path);
  EXPECT_NE(text.find("\"crs\": { \"type\": \"name\", \"properties\": { \"name\": "
                      "\"urn:ogc:def:crs:EPSG::2949\" } }"),
            std::string::npos)
      << text;
  EXPECT_NE(
      text.find("{\"type\":\"Feature\",\"properties\":{\"source_file\":\"contours.shp\","
                "\"source_fid\":7,\"z_start\":123.456789012345,\"z_end\":0.30000000000000004},"
                "\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[500000.123456789,"
                "4000000.987654321,123.456789012345],[500001.123456789,4000001.987654321,"
                "0.30000000000000004]]}}"),
      std::string::npos)
      << text;

  const GeoJson g(path);
  ASSERT_NE(g.ds, nullptr);
  ASSERT_EQ(GDALDatasetGetLayerCount(g.ds), 1);
  EXPECT_EQ(OGR_L_GetFeatureCount(g.layer(), TRUE), 3);
  EXPECT_EQ(test::layer_crs_code(g.layer()), "EPSG:2949");

  const std::vector<Line> lines = read_lines_back(g);
  const auto edges = square_edges();
  const auto features = square_features();
  ASSERT_EQ(lines.size(), edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    SCOPED_TRACE(i);
    ASSERT_EQ(lines[i].points.size(), 2u);
    expect_bits(lines[i].points[0], vertex(tin, edges[i].a));
    expect_bits(lines[i].points[1], vertex(tin, edges[i].b));
    EXPECT_EQ(lines[i].source_file, features[edges[i].feature].file);
    EXPECT_EQ(lines[i].source_fid, features[edges[i].feature].fid);
    EXPECT_EQ(bits(lines[i].z_start), bits(tin.z(edges[i].a)));
    EXPECT_EQ(bits(lines[i].z_end), bits(tin.z(edges[i].b)));
  }
}

TEST(ConstraintWriter, FileNamesAreEscapedAndAnyFidSurvives) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  const std::vector<ConstraintFeatureInfo> features = {
      {"C:\\data\\\"quoted\" name\t.shp", std::int64_t{1} << 40},
      {"h\xc3\xb6hen/\xe6\xa8\x99\xe9\xab\x98.gpkg:layer", -1},
  };
  const std::vector<ConstraintEdge> edges = {{0, 2, 1}, {2, 3, 0}, {0, 1, 1}};
  write_constraint_lines(dir + "/c.geojson", tin, edges, features, {});
  EXPECT_EQ(slurp(dir + "/c.geojson").find("\"crs\""), std::string::npos);  // no CRS given
  const GeoJson g(dir + "/c.geojson");
  ASSERT_NE(g.ds, nullptr);
  const std::vector<Line> lines = read_lines_back(g);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].source_file, features[1].file);
  EXPECT_EQ(lines[0].source_fid, -1);
  EXPECT_EQ(lines[1].source_file, features[0].file);
  EXPECT_EQ(lines[1].source_fid, std::int64_t{1} << 40);
  EXPECT_EQ(lines[2].source_file, features[1].file);
}

TEST(ConstraintWriter, OffsetIsRecordedAndSubtractedButZPropertiesStayElevations) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  TinWriteOptions o;
  o.offset = {500000, 4000000, 100};
  o.crs_wkt = crs_from_user("EPSG:2949");
  write_constraint_lines(dir + "/c.geojson", tin, square_edges(), square_features(), o);
  EXPECT_NE(slurp(dir + "/c.geojson").find("\n\"tincdt_offset\": [500000,4000000,100],\n"),
            std::string::npos);
  const GeoJson g(dir + "/c.geojson");
  ASSERT_NE(g.ds, nullptr);
  const std::vector<Line> lines = read_lines_back(g);
  ASSERT_EQ(lines.size(), 3u);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const VertexId a = square_edges()[i].a;
    const Point3 p = vertex(tin, a);
    expect_bits(lines[i].points[0], {p.x - 500000, p.y - 4000000, p.z - 100});
    EXPECT_EQ(bits(lines[i].z_start), bits(p.z));
  }
}

TEST(ConstraintWriter, CrsWithoutEpsgCodeSurvivesAsWkt) {
  const std::string dir = scratch();
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("+proj=tmerc +lat_0=0 +lon_0=-73.3 +k=0.9999 +x_0=304800 +units=m");
  write_constraint_lines(dir + "/c.geojson", unit_square(), square_edges(), square_features(), o);
  const GeoJson g(dir + "/c.geojson");
  ASSERT_NE(g.ds, nullptr);
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(g.layer());
  ASSERT_NE(srs, nullptr);
  EXPECT_TRUE(same_crs(o.crs_wkt, [&] {
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    std::string s = wkt;
    CPLFree(wkt);
    return s;
  }()));
}

TEST(ConstraintWriter, NoEdgesGiveAnEmptyCollection) {
  const std::string dir = scratch();
  const TinWriteStats stats = write_constraint_lines(dir + "/c.geojson", unit_square(), {}, {}, {});
  EXPECT_EQ(stats.vertices, 0u);
  const GeoJson g(dir + "/c.geojson");
  ASSERT_NE(g.ds, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(g.layer(), TRUE), 0);
}

TEST(ConstraintWriter, ManyEdgesAreFastAndReadBack) {
  // 200,000 edges over a 500 x 401 lattice of vertices (the writer reads only vertices, so no
  // triangles are needed), spread over 3 files; not a timed test: the time is printed.
  const std::string dir = scratch();
  Triangulation tin;
  constexpr std::uint32_t kNx = 500;
  constexpr std::uint32_t kNy = 401;
  for (std::uint32_t j = 0; j < kNy; ++j)
    for (std::uint32_t i = 0; i < kNx; ++i)
      tin.add_vertex({kX0 + 0.5 * i, kY0 + 0.5 * j}, 100.0 / (1 + i + 3 * j));
  std::vector<ConstraintEdge> edges;
  std::vector<ConstraintFeatureInfo> features;
  for (std::uint32_t j = 0; j < kNy - 1; ++j) {
    features.push_back({"/data/contours_" + std::to_string(j % 3) + ".shp", j});
    for (std::uint32_t i = 0; i < kNx; ++i)
      edges.push_back({j * kNx + i, (j + 1) * kNx + i, static_cast<std::uint32_t>(j)});
  }
  ASSERT_EQ(edges.size(), 200000u);
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:2949");
  const auto start = std::chrono::steady_clock::now();
  const TinWriteStats stats = write_constraint_lines(dir + "/c.geojson", tin, edges, features, o);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[   INFO   ] 200000 constraint edges, %.1f MB, written in %.3f s\n",
              static_cast<double>(stats.bytes) / 1e6, seconds);
  EXPECT_EQ(stats.vertices, tin.vertex_count());
  const GeoJson g(dir + "/c.geojson");
  ASSERT_NE(g.ds, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(g.layer(), TRUE), 200000);
  OGRFeatureH last = OGR_L_GetFeature(g.layer(), 199999);
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(OGR_F_GetFieldAsInteger64(last, OGR_F_GetFieldIndex(last, "source_fid")), 399);
  EXPECT_STREQ(OGR_F_GetFieldAsString(last, OGR_F_GetFieldIndex(last, "source_file")),
               "/data/contours_0.shp");
  OGR_F_Destroy(last);
}

// ---- refusals and safe output ------------------------------------------------------------------

TEST(ConstraintWriter, BadEdgesAreRefusedBeforeAnythingIsCreated) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  if (const auto e = test::thrown<OutputError>([&] {
        write_constraint_lines(dir + "/c.geojson", tin, {{0, 2, 0}, {1, kInfinite, 0}},
                               square_features(), {});
      })) {
    EXPECT_EQ(e->where(), "constraint edge 1");
    EXPECT_NE(e->detail().find("not a vertex of the TIN"), std::string::npos) << e->what();
  }
  if (const auto e = test::thrown<OutputError>([&] {
        write_constraint_lines(dir + "/c.geojson", tin, {{0, 2, 2}}, square_features(), {});
      })) {
    EXPECT_EQ(e->where(), "constraint edge 0");
    EXPECT_NE(e->detail().find("feature index 2"), std::string::npos) << e->what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(ConstraintWriter, ExistingOutputNeedsOverwriteAndIsOtherwiseUntouched) {
  const std::string dir = scratch();
  const std::string path = dir + "/c.geojson";
  test::expect_no_overwrite(path, [&] {
    write_constraint_lines(path, unit_square(), square_edges(), square_features(), {});
  });
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"c.geojson"}));

  TinWriteOptions o;
  o.overwrite = true;
  write_constraint_lines(path, unit_square(), square_edges(), square_features(), o);
  const GeoJson g(path);
  ASSERT_NE(g.ds, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(g.layer(), TRUE), 3);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"c.geojson"}));
}

TEST(ConstraintWriter, UnwritableFolderIsAnOutputErrorAndLeavesNothing) {
  // Tests may run as root, for whom a read-only folder is writable; a regular file is not.
  const std::string dir = scratch();
  spit(dir + "/plain", "x");
  EXPECT_THROW(write_constraint_lines(dir + "/plain/c.geojson", unit_square(), square_edges(),
                                      square_features(), {}),
               OutputError);
  EXPECT_THROW(write_constraint_lines(dir + "/missing/c.geojson", unit_square(), square_edges(),
                                      square_features(), {}),
               OutputError);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"plain"}));
}

TEST(ConstraintWriter, NonFiniteVertexFailsAndLeavesNothing) {
  const std::string dir = scratch();
  Triangulation tin = unit_square();
  tin.set_z(3, std::numeric_limits<double>::infinity());
  if (const auto e = test::thrown<OutputError>([&] {
        write_constraint_lines(dir + "/c.geojson", tin, square_edges(), square_features(), {});
      })) {
    EXPECT_EQ(e->where(), "vertex 3") << e->what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

}  // namespace
}  // namespace tincdt::io
