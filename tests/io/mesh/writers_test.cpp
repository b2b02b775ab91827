// TIN writers: OBJ, PLY (binary and ASCII), GeoJSON, the .prj beside them, and the safe
// OutputFile underneath. Meshes are built by hand at UTM magnitude; every file is read back and
// compared bit for bit.
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_spatialref.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/output_file.hpp"
#include "mesh/triangulation.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/meshes.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using mesh::Triangulation;
using test::close_with_ghosts;
using test::kX0;
using test::kY0;
using test::names_in;
using test::slurp;
using test::spit;
using test::unit_square;

// ---- meshes --------------------------------------------------------------------------------

// An nx by ny grid of vertices, half-metre spacing, with irregular heights.
Triangulation grid(std::uint32_t nx, std::uint32_t ny) {
  Triangulation tin;
  tin.reserve_vertices(std::size_t{nx} * ny);
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i)
      tin.add_vertex({kX0 + 0.5 * i, kY0 + 0.5 * j}, 100.0 / (1 + i + 3 * j) + 1e-9 * i);
  for (std::uint32_t j = 0; j + 1 < ny; ++j) {
    for (std::uint32_t i = 0; i + 1 < nx; ++i) {
      const VertexId a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      tin.add_triangle(a, b, c);
      tin.add_triangle(a, c, d);
    }
  }
  close_with_ghosts(tin);
  return tin;
}

std::vector<std::array<VertexId, 3>> faces_of(const Triangulation& tin) {
  std::vector<std::array<VertexId, 3>> f;
  tin.for_each_triangle([&f](TriangleId, const std::array<VertexId, 3>& c) { f.push_back(c); });
  return f;
}

// ---- files ---------------------------------------------------------------------------------

// A fresh, empty scratch folder for the current test.
std::string scratch() {
  return test::scratch_dir("writers");
}

std::uint64_t bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}

double to_double(std::string_view s) {
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  EXPECT_EQ(r.ec, std::errc()) << s;
  EXPECT_EQ(r.ptr, s.data() + s.size()) << s;
  return v;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && line[i] == ' ') ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    lines.push_back(text.substr(0, nl));
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
  return lines;
}

std::string wkt_of(const std::string& user) {
  return crs_from_user(user);
}

// Vertices match the mesh bit for bit, after subtracting OFFSET the same way the writer must.
void expect_vertices(const Triangulation& tin, const std::vector<Point3>& got,
                     Point3 offset = {0, 0, 0}) {
  ASSERT_EQ(got.size(), tin.vertex_count());
  for (VertexId v = 0; v < got.size(); ++v) {
    const Point2 p = tin.point(v);
    EXPECT_EQ(bits(got[v].x), bits(p.x - offset.x)) << "vertex " << v;
    EXPECT_EQ(bits(got[v].y), bits(p.y - offset.y)) << "vertex " << v;
    EXPECT_EQ(bits(got[v].z), bits(tin.z(v) - offset.z)) << "vertex " << v;
  }
}

double signed_area(const Point3& a, const Point3& b, const Point3& c) {
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
}

// ---- readers for the written formats ---------------------------------------------------------

struct ObjFile {
  std::vector<std::string> comments;
  std::vector<Point3> vertices;
  std::vector<std::array<VertexId, 3>> faces;  // 0-based
};

ObjFile read_obj(const std::string& path) {
  ObjFile obj;
  const std::string text = slurp(path);
  for (const std::string_view line : lines_of(text)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      obj.comments.emplace_back(line);
      continue;
    }
    const auto f = split(line);
    if (f[0] == "v") {
      EXPECT_EQ(f.size(), 4u) << line;
      obj.vertices.push_back({to_double(f[1]), to_double(f[2]), to_double(f[3])});
    } else if (f[0] == "f") {
      EXPECT_EQ(f.size(), 4u) << line;
      std::array<VertexId, 3> c{};
      for (int i = 0; i < 3; ++i) {
        std::uint32_t one_based = 0;
        std::from_chars(f[i + 1].data(), f[i + 1].data() + f[i + 1].size(), one_based);
        c[i] = one_based - 1;
      }
      obj.faces.push_back(c);
    } else {
      ADD_FAILURE() << "unexpected OBJ line: " << line;
    }
  }
  return obj;
}

struct PlyFile {
  std::string header;
  std::vector<Point3> vertices;
  std::vector<std::array<VertexId, 3>> faces;
  std::vector<std::array<VertexId, 2>> edges;
  std::size_t body_bytes = 0;
};

template <class T>
T load_le(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // the tests run on little-endian hosts
  return v;
}

PlyFile read_ply(const std::string& path) {
  PlyFile ply;
  const std::string data = slurp(path);
  const auto end = data.find("end_header\n");
  if (end == std::string::npos) {
    ADD_FAILURE() << "no end_header in " << path;
    return ply;
  }
  ply.header = data.substr(0, end + 11);
  const std::string body = data.substr(end + 11);
  ply.body_bytes = body.size();
  const auto nv = test::ply_element_count(ply.header, "vertex").value_or(0);
  const auto nf = test::ply_element_count(ply.header, "face").value_or(0);
  const auto ne = test::ply_element_count(ply.header, "edge").value_or(0);
  if (ply.header.find("format binary_little_endian 1.0\n") != std::string::npos) {
    const char* p = body.data();
    const char* const stop = body.data() + body.size();
    for (std::uint64_t i = 0; i < nv && p + 24 <= stop; ++i, p += 24)
      ply.vertices.push_back({load_le<double>(p), load_le<double>(p + 8), load_le<double>(p + 16)});
    for (std::uint64_t i = 0; i < nf && p + 13 <= stop; ++i, p += 13) {
      EXPECT_EQ(static_cast<unsigned char>(*p), 3u);
      ply.faces.push_back({load_le<std::uint32_t>(p + 1), load_le<std::uint32_t>(p + 5),
                           load_le<std::uint32_t>(p + 9)});
    }
    for (std::uint64_t i = 0; i < ne && p + 8 <= stop; ++i, p += 8)
      ply.edges.push_back({load_le<std::uint32_t>(p), load_le<std::uint32_t>(p + 4)});
    EXPECT_EQ(p, stop) << "trailing bytes after the last record";
  } else {
    const auto lines = lines_of(body);
    std::size_t l = 0;
    auto to_id = [](std::string_view s) {
      std::uint32_t v = 0;
      std::from_chars(s.data(), s.data() + s.size(), v);
      return v;
    };
    for (std::uint64_t i = 0; i < nv && l < lines.size(); ++i, ++l) {
      const auto f = split(lines[l]);
      EXPECT_EQ(f.size(), 3u);
      ply.vertices.push_back({to_double(f[0]), to_double(f[1]), to_double(f[2])});
    }
    for (std::uint64_t i = 0; i < nf && l < lines.size(); ++i, ++l) {
      const auto f = split(lines[l]);
      EXPECT_EQ(f.size(), 4u);
      EXPECT_EQ(f[0], "3");
      ply.faces.push_back({to_id(f[1]), to_id(f[2]), to_id(f[3])});
    }
    for (std::uint64_t i = 0; i < ne && l < lines.size(); ++i, ++l) {
      const auto f = split(lines[l]);
      EXPECT_EQ(f.size(), 2u);
      ply.edges.push_back({to_id(f[0]), to_id(f[1])});
    }
    EXPECT_EQ(l, lines.size()) << "trailing lines after the last record";
  }
  return ply;
}

// A GeoJSON file opened by GDAL's vector driver.
struct GdalVector : test::VectorFile {
  explicit GdalVector(const std::string& path) : VectorFile(path, "GeoJSON") {}
};

struct GeoJsonTriangle {
  std::int64_t id;
  std::vector<Point3> ring;
};

std::vector<GeoJsonTriangle> read_geojson_triangles(const GdalVector& v) {
  std::vector<GeoJsonTriangle> out;
  OGRLayerH layer = v.layer();
  OGR_L_ResetReading(layer);
  while (OGRFeatureH f = OGR_L_GetNextFeature(layer)) {
    GeoJsonTriangle t{OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "id")), {}};
    OGRGeometryH poly = OGR_F_GetGeometryRef(f);
    EXPECT_EQ(OGR_GT_Flatten(OGR_G_GetGeometryType(poly)), wkbPolygon);
    EXPECT_EQ(OGR_G_GetGeometryCount(poly), 1);
    OGRGeometryH ring = OGR_G_GetGeometryRef(poly, 0);
    for (int i = 0; i < OGR_G_GetPointCount(ring); ++i) {
      Point3 p{};
      OGR_G_GetPoint(ring, i, &p.x, &p.y, &p.z);
      t.ring.push_back(p);
    }
    out.push_back(std::move(t));
    OGR_F_Destroy(f);
  }
  return out;
}

// ---- format_from_path ----------------------------------------------------------------------

TEST(FormatFromPath, KnowsTheExtensionsWhateverTheirCase) {
  EXPECT_EQ(format_from_path("a/tin.obj"), TinFormat::obj);
  EXPECT_EQ(format_from_path("TIN.OBJ"), TinFormat::obj);
  EXPECT_EQ(format_from_path("x.y/tin.Ply"), TinFormat::ply);
  EXPECT_EQ(format_from_path("tin.geojson"), TinFormat::geojson);
  EXPECT_EQ(format_from_path("tin.GeoJSON"), TinFormat::geojson);
  EXPECT_EQ(format_from_path("tin.json"), TinFormat::geojson);
}

TEST(FormatFromPath, UnknownExtensionNamesThePathAndTheKnownOnes) {
  if (const auto e = test::thrown<OutputError>([&] { format_from_path("out/tin.dxf"); })) {
    EXPECT_EQ(e->file(), "out/tin.dxf");
    EXPECT_NE(e->detail().find(".dxf"), std::string::npos) << e->what();
    EXPECT_NE(e->detail().find(".obj"), std::string::npos) << e->what();
    EXPECT_NE(e->detail().find(".ply"), std::string::npos) << e->what();
    EXPECT_NE(e->detail().find(".geojson"), std::string::npos) << e->what();
  }
  EXPECT_THROW(format_from_path("out.d/tin"), OutputError);
}

TEST(FormatFromPath, ExplicitFormatOverridesTheExtension) {
  const std::string dir = scratch();
  TinWriteOptions o;
  o.format = TinFormat::obj;
  write_tin(dir + "/tin.mesh", unit_square(), o);
  EXPECT_EQ(read_obj(dir + "/tin.mesh").faces.size(), 2u);
}

// ---- OBJ -----------------------------------------------------------------------------------

TEST(ObjWriter, RoundTripsCoordinatesBitExactly) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  const TinWriteStats stats = write_tin(dir + "/tin.obj", tin, {});
  EXPECT_EQ(stats.vertices, 4u);
  EXPECT_EQ(stats.triangles, 2u);
  EXPECT_EQ(stats.bytes, fs::file_size(dir + "/tin.obj"));

  const ObjFile obj = read_obj(dir + "/tin.obj");
  expect_vertices(tin, obj.vertices);
  EXPECT_EQ(obj.faces, faces_of(tin));
  ASSERT_GE(obj.comments.size(), 3u);
  EXPECT_EQ(obj.comments[0], "# tincdt");
  EXPECT_EQ(obj.comments[1], "# vertices 4");
  EXPECT_EQ(obj.comments[2], "# faces 2");
  for (const auto& c : obj.comments) EXPECT_EQ(c.find("offset"), std::string::npos) << c;
  // Shortest round-trip text, not a fixed number of decimals.
  const std::string text = slurp(dir + "/tin.obj");
  EXPECT_NE(text.find("\nv 500000.123456789 4000000.987654321 123.456789012345\n"),
            std::string::npos);
  EXPECT_NE(text.find("\nv 500001.123456789 4000000.987654321 124.1\n"), std::string::npos);
  EXPECT_NE(text.find(" 0.30000000000000004\n"), std::string::npos);
  EXPECT_NE(text.find("\nf 1 2 3\nf 1 3 4\n"), std::string::npos);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"tin.obj"}));
}

TEST(ObjWriter, AnyFiniteDoubleRoundTrips) {
  // Heights from random bit patterns plus the awkward cases: zeros, subnormals, the limits,
  // the switch between plain and exponent notation.
  const std::string dir = scratch();
  Triangulation tin = grid(64, 64);
  const double special[] = {0.0,
                            -0.0,
                            5e-324,
                            -2.2250738585072014e-308,
                            1.7976931348623157e308,
                            -1.7976931348623157e308,
                            1e-5,
                            9.999999999999999e-6,
                            1e15,
                            999999999999999.9,
                            -123456789012345.67,
                            0.1,
                            1.0 / 3};
  std::uint64_t state = 0x9e3779b97f4a7c15u;
  for (VertexId v = 0; v < tin.vertex_count(); ++v) {
    double z = 0;
    if (v < std::size(special)) {
      z = special[v];
    } else {
      do {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        z = std::bit_cast<double>(state);
      } while (!std::isfinite(z));
    }
    tin.set_z(v, z);
  }
  write_tin(dir + "/tin.obj", tin, {});
  expect_vertices(tin, read_obj(dir + "/tin.obj").vertices);
  TinWriteOptions o;
  o.ply_ascii = true;
  write_tin(dir + "/tin.ply", tin, o);
  expect_vertices(tin, read_ply(dir + "/tin.ply").vertices);
  const std::string text = slurp(dir + "/tin.obj");
  EXPECT_NE(text.find(" -0\n"), std::string::npos);
  EXPECT_NE(text.find(" 0.00001\n"), std::string::npos);
  EXPECT_NE(text.find(" 1e+15\n"), std::string::npos);
  EXPECT_NE(text.find(" 5e-324\n"), std::string::npos);
}

TEST(ObjWriter, FacesAreCounterClockwiseAndCoverTheGrid) {
  const std::string dir = scratch();
  const Triangulation tin = grid(40, 30);
  write_tin(dir + "/grid.obj", tin, {});
  const ObjFile obj = read_obj(dir + "/grid.obj");
  expect_vertices(tin, obj.vertices);
  ASSERT_EQ(obj.faces.size(), 2u * 39 * 29);
  double area = 0;
  for (const auto& f : obj.faces) {
    const double a = signed_area(obj.vertices[f[0]], obj.vertices[f[1]], obj.vertices[f[2]]);
    EXPECT_GT(a, 0);
    area += a;
  }
  EXPECT_NEAR(area, 39 * 0.5 * 29 * 0.5, 1e-6);
}

TEST(ObjWriter, OffsetIsRecordedAndSubtracted) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  TinWriteOptions o;
  o.offset = {500000, 4000000, 100.5};
  write_tin(dir + "/tin.obj", tin, o);
  const ObjFile obj = read_obj(dir + "/tin.obj");
  expect_vertices(tin, obj.vertices, o.offset);
  bool found = false;
  for (const auto& c : obj.comments) found |= c.rfind("# offset 500000 4000000 100.5", 0) == 0;
  EXPECT_TRUE(found) << slurp(dir + "/tin.obj").substr(0, 300);
}

// ---- PLY -----------------------------------------------------------------------------------

TEST(PlyWriter, BinaryHeaderIsExactAndSizeMatchesTheRecords) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square(/*constrain_diagonal=*/true);
  const TinWriteStats stats = write_tin(dir + "/tin.ply", tin, {});
  const std::string expected_header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment tincdt\n"
      "element vertex 4\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "element face 2\n"
      "property list uchar uint vertex_indices\n"
      "element edge 1\n"
      "property uint vertex1\n"
      "property uint vertex2\n"
      "end_header\n";
  const PlyFile ply = read_ply(dir + "/tin.ply");
  EXPECT_EQ(ply.header, expected_header);
  EXPECT_EQ(fs::file_size(dir + "/tin.ply"), expected_header.size() + 4 * 24 + 2 * 13 + 1 * 8);
  EXPECT_EQ(stats.bytes, fs::file_size(dir + "/tin.ply"));
  expect_vertices(tin, ply.vertices);
  EXPECT_EQ(ply.faces, faces_of(tin));
  ASSERT_EQ(ply.edges.size(), 1u);
  EXPECT_EQ(ply.edges[0], (std::array<VertexId, 2>{0, 2}));
}

TEST(PlyWriter, NoEdgeElementWithoutConstraints) {
  const std::string dir = scratch();
  write_tin(dir + "/tin.ply", unit_square(), {});
  const PlyFile ply = read_ply(dir + "/tin.ply");
  EXPECT_EQ(ply.header.find("element edge"), std::string::npos);
  EXPECT_EQ(ply.body_bytes, 4u * 24 + 2u * 13);
}

TEST(PlyWriter, LargeBinaryMeshSpanningManyBlocksReadsBack) {
  const std::string dir = scratch();
  const Triangulation tin = grid(400, 400);  // about 8 MB, two block flushes and more
  const TinWriteStats stats = write_tin(dir + "/grid.ply", tin, {});
  const PlyFile ply = read_ply(dir + "/grid.ply");
  EXPECT_EQ(stats.triangles, 2u * 399 * 399);
  EXPECT_EQ(ply.body_bytes, 400u * 400 * 24 + 2u * 399 * 399 * 13);
  expect_vertices(tin, ply.vertices);
  EXPECT_EQ(ply.faces, faces_of(tin));
  for (const auto& f : ply.faces)
    ASSERT_GT(signed_area(ply.vertices[f[0]], ply.vertices[f[1]], ply.vertices[f[2]]), 0);
}

TEST(PlyWriter, AsciiRoundTripsBitExactly) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square(/*constrain_diagonal=*/true);
  TinWriteOptions o;
  o.ply_ascii = true;
  write_tin(dir + "/tin.ply", tin, o);
  const PlyFile ply = read_ply(dir + "/tin.ply");
  EXPECT_EQ(ply.header.rfind("ply\nformat ascii 1.0\ncomment tincdt\nelement vertex 4\n", 0), 0u)
      << ply.header;
  expect_vertices(tin, ply.vertices);
  EXPECT_EQ(ply.faces, faces_of(tin));
  ASSERT_EQ(ply.edges.size(), 1u);
  EXPECT_EQ(ply.edges[0], (std::array<VertexId, 2>{0, 2}));
  const std::string text = slurp(dir + "/tin.ply");
  EXPECT_NE(text.find("end_header\n500000.123456789 4000000.987654321 123.456789012345\n"),
            std::string::npos);
  EXPECT_NE(text.find("\n3 0 1 2\n3 0 2 3\n0 2\n"), std::string::npos);
}

TEST(PlyWriter, LargeAsciiMeshReadsBack) {
  const std::string dir = scratch();
  const Triangulation tin = grid(300, 300);
  TinWriteOptions o;
  o.ply_ascii = true;
  write_tin(dir + "/grid.ply", tin, o);
  const PlyFile ply = read_ply(dir + "/grid.ply");
  expect_vertices(tin, ply.vertices);
  EXPECT_EQ(ply.faces, faces_of(tin));
}

// A TIN in EPSG:2949, written with OFFSET subtracted.
TinWriteOptions offset_in_2949(const Point3& offset) {
  TinWriteOptions o;
  o.offset = offset;
  o.crs_wkt = wkt_of("EPSG:2949");
  return o;
}

TEST(PlyWriter, CommentsRecordOffsetAndCrs) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  const TinWriteOptions o = offset_in_2949({500000, 4000000, 0});
  write_tin(dir + "/tin.ply", tin, o);
  const PlyFile ply = read_ply(dir + "/tin.ply");
  EXPECT_NE(ply.header.find("\ncomment offset 500000 4000000 0\n"), std::string::npos)
      << ply.header;
  EXPECT_NE(ply.header.find("\ncomment crs EPSG:2949\n"), std::string::npos) << ply.header;
  expect_vertices(tin, ply.vertices, o.offset);
}

TEST(PlyWriter, CrsWithoutCodeIsWrittenAsOneLineWkt) {
  const std::string dir = scratch();
  TinWriteOptions o;
  {
    OGRSpatialReference srs;
    srs.SetFromUserInput("+proj=tmerc +lat_0=0 +lon_0=-73.3 +k=0.9999 +x_0=304800 +units=m");
    char* pretty = nullptr;
    ASSERT_EQ(srs.exportToPrettyWkt(&pretty), OGRERR_NONE);
    o.crs_wkt = pretty;
    CPLFree(pretty);
  }
  ASSERT_NE(o.crs_wkt.find('\n'), std::string::npos);  // the input WKT is multi-line
  write_tin(dir + "/tin.ply", unit_square(), o);
  const PlyFile ply = read_ply(dir + "/tin.ply");
  const auto at = ply.header.find("\ncomment crs ");
  ASSERT_NE(at, std::string::npos) << ply.header;
  const auto line_end = ply.header.find('\n', at + 1);
  const std::string wkt = ply.header.substr(at + 13, line_end - at - 13);
  OGRSpatialReference read_back;
  ASSERT_EQ(read_back.importFromWkt(wkt.c_str()), OGRERR_NONE) << wkt;
  OGRSpatialReference original;
  ASSERT_EQ(original.importFromWkt(o.crs_wkt.c_str()), OGRERR_NONE);
  EXPECT_TRUE(read_back.IsSame(&original));
  EXPECT_NE(ply.header.find("\nelement vertex 4\n", at), std::string::npos);
}

// ---- .prj ------------------------------------------------------------------------------------

TEST(PrjFile, WrittenBesideObjAndPlyAsEsriWkt) {
  const std::string dir = scratch();
  TinWriteOptions o;
  o.crs_wkt = wkt_of("EPSG:2949");
  write_tin(dir + "/a.obj", unit_square(), o);
  write_tin(dir + "/b.ply", unit_square(), o);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.obj", "a.prj", "b.ply", "b.prj"}));
  for (const char* prj : {"/a.prj", "/b.prj"}) {
    const std::string text = slurp(dir + prj);
    EXPECT_EQ(text.rfind("PROJCS[\"", 0), 0u) << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    OGRSpatialReference srs;
    const char* lines[] = {text.c_str(), nullptr};
    ASSERT_EQ(srs.importFromESRI(const_cast<char**>(lines)), OGRERR_NONE) << text;
    OGRSpatialReference expected;
    expected.importFromEPSG(2949);
    EXPECT_TRUE(srs.IsSame(&expected)) << text;
  }
}

TEST(PrjFile, NotWrittenWithoutCrsNorForGeoJson) {
  const std::string dir = scratch();
  write_tin(dir + "/a.obj", unit_square(), {});
  TinWriteOptions o;
  o.crs_wkt = wkt_of("EPSG:2949");
  write_tin(dir + "/b.geojson", unit_square(), o);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.obj", "b.geojson"}));
}

TEST(PrjFile, ExistingPrjWithoutOverwriteStopsBeforeTheMesh) {
  const std::string dir = scratch();
  spit(dir + "/a.prj", "old prj");
  TinWriteOptions o;
  o.crs_wkt = wkt_of("EPSG:2949");
  EXPECT_THROW(write_tin(dir + "/a.obj", unit_square(), o), OutputError);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.prj"}));
  EXPECT_EQ(slurp(dir + "/a.prj"), "old prj");
  o.overwrite = true;
  write_tin(dir + "/a.obj", unit_square(), o);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.obj", "a.prj"}));
  EXPECT_EQ(slurp(dir + "/a.prj").rfind("PROJCS[", 0), 0u);
}

TEST(PrjFile, UnreadableCrsFailsBeforeWritingAnything) {
  const std::string dir = scratch();
  TinWriteOptions o;
  o.crs_wkt = "PROJCS[this is not a CRS";
  if (const auto e =
          test::thrown<OutputError>([&] { write_tin(dir + "/a.ply", unit_square(), o); })) {
    EXPECT_EQ(e->file(), dir + "/a.prj") << e->what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

// ---- GeoJSON ---------------------------------------------------------------------------------

TEST(GeoJsonWriter, GdalReadsFeaturesCrsAndExactCoordinates) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  TinWriteOptions o;
  o.crs_wkt = wkt_of("EPSG:2949");
  const TinWriteStats stats = write_tin(dir + "/tin.geojson", tin, o);
  EXPECT_EQ(stats.triangles, 2u);
  EXPECT_EQ(stats.bytes, fs::file_size(dir + "/tin.geojson"));

  const std::string text = slurp(dir + "/tin.geojson");
  EXPECT_NE(text.find("\"crs\": { \"type\": \"name\", \"properties\": { \"name\": "
                      "\"urn:ogc:def:crs:EPSG::2949\" } }"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\"properties\":{\"id\":0},\"geometry\":{\"type\":\"Polygon\","
                      "\"coordinates\":[[[500000.123456789,4000000.987654321,123.456789012345],"),
            std::string::npos)
      << text;

  const GdalVector v(dir + "/tin.geojson");
  ASSERT_NE(v.ds, nullptr);
  ASSERT_EQ(GDALDatasetGetLayerCount(v.ds), 1);
  EXPECT_EQ(OGR_L_GetFeatureCount(v.layer(), TRUE), 2);
  EXPECT_EQ(test::layer_crs_code(v.layer()), "EPSG:2949");

  const auto triangles = read_geojson_triangles(v);
  const auto faces = faces_of(tin);
  ASSERT_EQ(triangles.size(), faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    EXPECT_EQ(triangles[i].id, static_cast<std::int64_t>(i));
    ASSERT_EQ(triangles[i].ring.size(), 4u);
    EXPECT_EQ(triangles[i].ring[0], triangles[i].ring[3]);  // closed
    for (int k = 0; k < 3; ++k) {
      const VertexId vid = faces[i][k];
      EXPECT_EQ(bits(triangles[i].ring[k].x), bits(tin.point(vid).x));
      EXPECT_EQ(bits(triangles[i].ring[k].y), bits(tin.point(vid).y));
      EXPECT_EQ(bits(triangles[i].ring[k].z), bits(tin.z(vid)));
    }
    EXPECT_GT(signed_area(triangles[i].ring[0], triangles[i].ring[1], triangles[i].ring[2]), 0);
  }
}

TEST(GeoJsonWriter, CrsWithoutEpsgCodeSurvivesAsWkt) {
  const std::string dir = scratch();
  TinWriteOptions o;
  o.crs_wkt = wkt_of("+proj=tmerc +lat_0=0 +lon_0=-73.3 +k=0.9999 +x_0=304800 +units=m");
  write_tin(dir + "/tin.geojson", unit_square(), o);
  const GdalVector v(dir + "/tin.geojson");
  ASSERT_NE(v.ds, nullptr);
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(v.layer());
  ASSERT_NE(srs, nullptr);
  OGRSpatialReference original;
  ASSERT_EQ(original.importFromWkt(o.crs_wkt.c_str()), OGRERR_NONE);
  EXPECT_TRUE(OGRSpatialReference::FromHandle(srs)->IsSame(&original));
}

TEST(GeoJsonWriter, NoCrsMemberForWgs84OrUnknownCrs) {
  const std::string dir = scratch();
  Triangulation tin;
  tin.add_vertex({15.0, 36.0}, 1);
  tin.add_vertex({15.001, 36.0}, 2);
  tin.add_vertex({15.0, 36.001}, 3);
  tin.add_triangle(0, 1, 2);
  close_with_ghosts(tin);
  for (const char* crs : {"EPSG:4326", "OGC:CRS84", ""}) {
    SCOPED_TRACE(crs);
    TinWriteOptions o;
    o.overwrite = true;
    o.crs_wkt = *crs ? wkt_of(crs) : std::string();
    write_tin(dir + "/tin.geojson", tin, o);
    const std::string text = slurp(dir + "/tin.geojson");
    EXPECT_EQ(text.find("\"crs\""), std::string::npos) << text;
    const GdalVector v(dir + "/tin.geojson");
    ASSERT_NE(v.ds, nullptr);
    EXPECT_EQ(OGR_L_GetFeatureCount(v.layer(), TRUE), 1);
  }
}

TEST(GeoJsonWriter, OffsetIsRecordedAndSubtracted) {
  const std::string dir = scratch();
  const Triangulation tin = unit_square();
  const TinWriteOptions o = offset_in_2949({500000, 4000000, 0});
  write_tin(dir + "/tin.geojson", tin, o);
  EXPECT_NE(slurp(dir + "/tin.geojson").find("\n\"tincdt_offset\": [500000,4000000,0],\n"),
            std::string::npos);
  const GdalVector v(dir + "/tin.geojson");
  ASSERT_NE(v.ds, nullptr);
  const auto triangles = read_geojson_triangles(v);
  ASSERT_EQ(triangles.size(), 2u);
  const Point3 p = triangles[0].ring[0];
  EXPECT_EQ(bits(p.x), bits(kX0 - 500000));
  EXPECT_EQ(bits(p.y), bits(kY0 - 4000000));
}

TEST(GeoJsonWriter, LargeMeshIsValidForGdal) {
  const std::string dir = scratch();
  const Triangulation tin = grid(200, 150);
  TinWriteOptions o;
  o.crs_wkt = wkt_of("EPSG:2949");
  write_tin(dir + "/grid.json", tin, o);
  const GdalVector v(dir + "/grid.json");
  ASSERT_NE(v.ds, nullptr);
  EXPECT_EQ(OGR_L_GetFeatureCount(v.layer(), TRUE), 2 * 199 * 149);
}

// ---- overwrite, failures, temporaries ----------------------------------------------------------

TEST(SafeOutput, ExistingOutputWithoutOverwriteIsLeftUntouched) {
  const std::string dir = scratch();
  for (const char* name : {"/tin.obj", "/tin.ply", "/tin.geojson"}) {
    SCOPED_TRACE(name);
    test::expect_no_overwrite(dir + name, [&] { write_tin(dir + name, unit_square(), {}); });
  }
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"tin.obj", "tin.ply", "tin.geojson"}));
}

TEST(SafeOutput, OverwriteReplacesTheFile) {
  const std::string dir = scratch();
  spit(dir + "/tin.obj", "old");
  TinWriteOptions o;
  o.overwrite = true;
  write_tin(dir + "/tin.obj", unit_square(), o);
  EXPECT_EQ(read_obj(dir + "/tin.obj").vertices.size(), 4u);
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"tin.obj"}));
}

TEST(SafeOutput, MissingFolderIsAnOutputError) {
  const std::string dir = scratch();
  if (const auto e = test::thrown<OutputError>(
          [&] { write_tin(dir + "/no/such/folder/tin.obj", unit_square(), {}); })) {
    EXPECT_EQ(e->file(), dir + "/no/such/folder/tin.obj");
    EXPECT_NE(e->detail().find("No such file or directory"), std::string::npos) << e->what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(SafeOutput, ParentThatIsAFileIsAnOutputError) {
  // Tests may run as root, for whom a read-only folder is writable; a regular file is not.
  const std::string dir = scratch();
  spit(dir + "/plain", "x");
  if (const auto e = test::thrown<OutputError>(
          [&] { write_tin(dir + "/plain/tin.ply", unit_square(), {}); })) {
    EXPECT_NE(e->detail().find("Not a directory"), std::string::npos) << e->what();
  }
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"plain"}));
}

TEST(SafeOutput, OutputThatIsAFolderIsRefused) {
  const std::string dir = scratch();
  fs::create_directory(dir + "/tin.obj");
  TinWriteOptions o;
  o.overwrite = true;
  EXPECT_THROW(write_tin(dir + "/tin.obj", unit_square(), o), OutputError);
  EXPECT_TRUE(fs::is_directory(dir + "/tin.obj"));
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"tin.obj"}));
}

TEST(SafeOutput, NonFiniteCoordinateFailsAndLeavesNothing) {
  const std::string dir = scratch();
  Triangulation tin = unit_square();
  tin.set_z(2, std::numeric_limits<double>::quiet_NaN());
  for (const char* name : {"/tin.obj", "/tin.ply", "/tin.geojson"}) {
    try {
      write_tin(dir + name, tin, {});
      FAIL() << "no exception for " << name;
    } catch (const OutputError& e) {
      EXPECT_EQ(e.where(), "vertex 2") << e.what();
    }
  }
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(OutputFileTest, TemporaryIsHiddenBesideTheTargetUntilCommit) {
  const std::string dir = scratch();
  {
    OutputFile out(dir + "/a.txt", false);
    const std::string temp = fs::path(out.temp_path()).filename();
    EXPECT_EQ(temp.rfind(".a.txt.tmp-", 0), 0u) << temp;
    EXPECT_EQ(temp.size(), std::string(".a.txt.tmp-XXXXXX").size());
    out.write(std::string("hello"));
    EXPECT_EQ(names_in(dir), (std::set<std::string>{temp}));
    out.commit();
    EXPECT_EQ(out.bytes_written(), 5u);
  }
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.txt"}));
  EXPECT_EQ(slurp(dir + "/a.txt"), "hello");
  {
    OutputFile out(dir + "/b.txt", false);
    out.write(std::string("abandoned"));
  }  // no commit: the temporary goes away
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"a.txt"}));
}

TEST(OutputFileTest, NewFileHasTheUsualPermissions) {
  const std::string dir = scratch();
  EXPECT_EQ(test::mode_when_created(dir + "/a.txt",
                                    [&] {
                                      OutputFile out(dir + "/a.txt", false);
                                      out.commit();
                                    }),
            0644u);
}

TEST(OutputFileTest, TargetCreatedMeanwhileIsNotReplacedWithoutOverwrite) {
  const std::string dir = scratch();
  OutputFile out(dir + "/a.txt", false);
  out.write(std::string("new"));
  spit(dir + "/a.txt", "someone else's");
  EXPECT_THROW(out.commit(), OutputError);
  EXPECT_EQ(slurp(dir + "/a.txt"), "someone else's");
}

TEST(OutputFileTest, AWriteFailureThrowsAndLeavesNothing) {
  // A file-size limit makes write(2) fail with EFBIG, like a full disk fails with ENOSPC.
  const std::string dir = scratch();
  bool threw = false;
  try {
    const test::FileSizeLimit limit(1 << 20);
    OutputFile out(dir + "/big.bin", false);
    const std::vector<char> block(std::size_t{3} << 20, 'x');
    out.write(block.data(), block.size());
    out.commit();
  } catch (const OutputError& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(threw);
  EXPECT_TRUE(names_in(dir).empty());
}

}  // namespace
}  // namespace tincdt::io
