// LandXML, GeoPackage and STL TINs: each file is read back (LandXML by a small parser of its
// one-element-per-line layout, GeoPackage through OGR, STL as bytes) and compared with the kept
// triangles of the TIN; LandXML is validated against the LandXML 1.2 schema with xmllint.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "constrained_sample.hpp"
#include "constraints/constraints.hpp"
#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

constexpr double kX0 = 512345.678, kY0 = 4123456.789;

// Random points at UTM magnitude with a constrained polyline and a constrained ring, and (with
// HOLES) a few triangles removed.
mesh::Triangulation sample_tin(bool holes) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0, 100), z(100, 150);
  std::vector<Point3> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({kX0 + u(rng), kY0 + u(rng), z(rng)});
  const auto first = static_cast<std::uint32_t>(pts.size());
  for (int i = 0; i < 6; ++i) pts.push_back({kX0 + 10 + 13.1 * i, kY0 + 20 + 3.7 * i, 120});
  const auto ring = static_cast<std::uint32_t>(pts.size());
  for (int i = 0; i < 8; ++i) {
    const double a = i * 0.785398;
    pts.push_back({kX0 + 60 + 15 * std::cos(a), kY0 + 65 + 15 * std::sin(a), 130});
  }
  return test::constrained_sample(std::move(pts), first, ring, holes);
}

using Corner = std::array<double, 3>;
using Face = std::array<Corner, 3>;

// A face as its corners, rotated to start at the smallest (orientation kept).
Face canonical(Face f) {
  const auto smallest = std::min_element(f.begin(), f.end()) - f.begin();
  std::rotate(f.begin(), f.begin() + smallest, f.end());
  return f;
}

std::multiset<Face> kept_faces(const mesh::Triangulation& tin, const Point3& offset = {0, 0, 0}) {
  std::multiset<Face> faces;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    Face f;
    for (int i = 0; i < 3; ++i)
      f[i] = {tin.point(c[i]).x - offset.x, tin.point(c[i]).y - offset.y, tin.z(c[i]) - offset.z};
    faces.insert(canonical(f));
  });
  return faces;
}

// ---- LandXML ---------------------------------------------------------------------------------

struct LandXml {
  std::vector<Corner> points;  // by id - 1, as x y z
  std::multiset<Face> faces;
  std::vector<std::vector<Corner>> breaklines;
  std::string text;
};

std::vector<double> numbers(const std::string& s) {
  std::vector<double> v;
  const char* p = s.c_str();
  char* end = nullptr;
  for (double d = std::strtod(p, &end); end != p; d = std::strtod(p, &end)) {
    v.push_back(d);
    p = end;
  }
  return v;
}

LandXml read_landxml(const std::string& path) {
  LandXml x;
  x.text = test::slurp(path);
  std::istringstream in(x.text);
  const std::regex p_re(R"re(<P id="(\d+)">([^<]*)</P>)re"), f_re(R"re(<F>([^<]*)</F>)re"),
      b_re(R"re(<PntList3D>([^<]*)</PntList3D>)re");
  std::vector<std::array<std::uint64_t, 3>> ids;
  std::smatch m;
  for (std::string line; std::getline(in, line);) {
    if (std::regex_search(line, m, p_re)) {
      const std::vector<double> nez = numbers(m[2]);
      EXPECT_EQ(nez.size(), 3u) << line;
      EXPECT_EQ(std::stoull(m[1]), x.points.size() + 1) << "ids run 1, 2, ...";
      x.points.push_back({nez[1], nez[0], nez[2]});
    } else if (std::regex_search(line, m, f_re)) {
      const std::vector<double> v = numbers(m[1]);
      EXPECT_EQ(v.size(), 3u) << line;
      ids.push_back({static_cast<std::uint64_t>(v[0]), static_cast<std::uint64_t>(v[1]),
                     static_cast<std::uint64_t>(v[2])});
    } else if (std::regex_search(line, m, b_re)) {
      const std::vector<double> v = numbers(m[1]);
      EXPECT_EQ(v.size() % 3, 0u);
      std::vector<Corner> bl;
      for (std::size_t i = 0; i + 2 < v.size(); i += 3) bl.push_back({v[i + 1], v[i], v[i + 2]});
      x.breaklines.push_back(bl);
    }
  }
  for (const auto& f : ids) {
    Face face;
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(f[i], 1u);
      EXPECT_LE(f[i], x.points.size());
      face[i] = x.points[f[i] - 1];
    }
    x.faces.insert(canonical(face));
  }
  return x;
}

// xmllint's verdict on PATH against the LandXML 1.2 schema; "" when valid.
std::string schema_errors(const std::string& path) {
  const std::string schema = ::tincdt::test::shared_data() + "/schema/LandXML-1.2.xsd";
  if (!fs::exists(schema)) return "skip";
  const std::string log = path + ".xmllint.txt";
  const int rc = std::system(
      ("xmllint --noout --schema '" + schema + "' '" + path + "' > '" + log + "' 2>&1").c_str());
  std::string text = test::slurp(log);
  fs::remove(log);
  return rc == 0 ? std::string() : text + " (exit " + std::to_string(rc) + ")";
}

TEST(LandXmlWriter, ValidAgainstTheSchemaAndRoundTrips) {
  const std::string dir = test::scratch_dir("mesh_formats");
  for (const bool holes : {false, true}) {
    SCOPED_TRACE(holes ? "with removed triangles" : "whole");
    const mesh::Triangulation tin = sample_tin(holes);
    TinWriteOptions o;
    o.crs_wkt = crs_from_user("EPSG:32611");
    o.overwrite = true;
    const std::string path = dir + "/surface.xml";
    const TinWriteStats stats = write_tin(path, tin, o);
    EXPECT_EQ(stats.bytes, fs::file_size(path));
    const std::string errors = schema_errors(path);
    if (errors == "skip") GTEST_SKIP() << "no LandXML schema in " << ::tincdt::test::shared_data();
    EXPECT_EQ(errors, "");

    const LandXml x = read_landxml(path);
    EXPECT_EQ(x.faces, kept_faces(tin));
    EXPECT_EQ(x.points.size(), stats.vertices);
    EXPECT_EQ(x.faces.size(), stats.triangles);
    EXPECT_NE(x.text.find("linearUnit=\"meter\""), std::string::npos);
    EXPECT_NE(x.text.find("epsgCode=\"32611\""), std::string::npos);
    EXPECT_NE(x.text.find("<Surface name=\"surface\">"), std::string::npos);
    // The breaklines: every constrained edge of the written TIN once, as consecutive points.
    std::set<std::pair<Corner, Corner>> written, expected;
    for (const auto& bl : x.breaklines)
      for (std::size_t i = 0; i + 1 < bl.size(); ++i)
        EXPECT_TRUE(written.insert(std::minmax(bl[i], bl[i + 1])).second) << "edge twice";
    tin.for_each_constrained_edge([&](EdgeId e) {
      const TriangleId a = mesh::triangle_of(e), b = mesh::triangle_of(tin.twin(e));
      if (!tin.is_kept(a) && !tin.is_kept(b)) return;
      const VertexId u = tin.origin(e), v = tin.dest(e);
      expected.insert(std::minmax(Corner{tin.point(u).x, tin.point(u).y, tin.z(u)},
                                  Corner{tin.point(v).x, tin.point(v).y, tin.z(v)}));
    });
    EXPECT_EQ(written, expected);
    if (!holes) {
      EXPECT_EQ(x.breaklines.size(), 2u);  // the polyline and the ring
    }
  }
}

TEST(LandXmlWriter, FeetCrsGivesImperialUnitsAndNoCrsGivesMetres) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(false);
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:2236");  // NAD83 / Florida East (ftUS)
  write_tin(dir + "/ft.xml", tin, o);
  const std::string ft = test::slurp(dir + "/ft.xml");
  EXPECT_NE(ft.find("<Imperial areaUnit=\"squareFoot\" linearUnit=\"USSurveyFoot\""),
            std::string::npos);
  o.crs_wkt.clear();
  write_tin(dir + "/none.landxml", tin, o);
  const std::string none = test::slurp(dir + "/none.landxml");
  EXPECT_NE(none.find("linearUnit=\"meter\""), std::string::npos);
  EXPECT_EQ(none.find("<CoordinateSystem"), std::string::npos);
}

TEST(LandXmlWriter, FeetAndNoCrsAreValidAgainstTheSchema) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(false);
  TinWriteOptions o;
  o.crs_wkt = crs_from_user("EPSG:2236");
  o.overwrite = true;
  write_tin(dir + "/ft_schema.xml", tin, o);
  o.crs_wkt.clear();
  write_tin(dir + "/none_schema.landxml", tin, o);
  const std::string ft = schema_errors(dir + "/ft_schema.xml");
  if (ft == "skip") GTEST_SKIP() << "no LandXML schema in " << ::tincdt::test::shared_data();
  EXPECT_EQ(ft, "");
  EXPECT_EQ(schema_errors(dir + "/none_schema.landxml"), "");
}

TEST(LandXmlWriter, DateAndTimeFollowSourceDateEpoch) {
  const std::string dir = test::scratch_dir("mesh_formats");
  ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
  write_tin(dir + "/a.xml", sample_tin(false), {});
  ::unsetenv("SOURCE_DATE_EPOCH");
  EXPECT_NE(test::slurp(dir + "/a.xml").find("date=\"2023-11-14\" time=\"22:13:20\""),
            std::string::npos);
}

// ---- GeoPackage ------------------------------------------------------------------------------

std::multiset<Face> read_gpkg_faces(const std::string& path, std::string* crs_wkt,
                                    OGRwkbGeometryType* type) {
  GDALAllRegister();
  const GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
  EXPECT_TRUE(ds);
  std::multiset<Face> faces;
  if (!ds) return faces;
  OGRLayer* layer = ds->GetLayerByName("tin");
  EXPECT_NE(layer, nullptr);
  if (layer == nullptr) return faces;
  *type = layer->GetGeomType();
  if (layer->GetSpatialRef() != nullptr) {
    char* wkt = nullptr;
    layer->GetSpatialRef()->exportToWkt(&wkt);
    *crs_wkt = wkt;
    CPLFree(wkt);
  }
  for (const auto& f : *layer) {
    const OGRGeometry* g = f->GetGeometryRef();
    const OGRLinearRing* ring = nullptr;
    if (wkbFlatten(g->getGeometryType()) == wkbPolygon) {
      ring = g->toPolygon()->getExteriorRing();
    } else {
      EXPECT_EQ(wkbFlatten(g->getGeometryType()), wkbTIN);
      const auto* surface = g->toTriangulatedSurface();
      EXPECT_EQ(surface->getNumGeometries(), 1);
      ring = surface->getGeometryRef(0)->getExteriorRing();
    }
    EXPECT_EQ(ring->getNumPoints(), 4);
    EXPECT_TRUE(ring->get_IsClosed());
    Face face;
    for (int i = 0; i < 3; ++i) face[i] = {ring->getX(i), ring->getY(i), ring->getZ(i)};
    faces.insert(canonical(face));
  }
  return faces;
}

TEST(GpkgWriter, PolygonZTrianglesWithTheCrs) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(true);
  const std::string path = dir + "/tin.gpkg";
  const TinWriteStats stats = test::write_alone_with_crs(dir, "tin.gpkg", tin);
  EXPECT_EQ(stats.triangles, tin.triangle_count());
  std::string crs;
  OGRwkbGeometryType type = wkbUnknown;
  EXPECT_EQ(read_gpkg_faces(path, &crs, &type), kept_faces(tin));
  EXPECT_EQ(type, wkbPolygon25D);
  EXPECT_TRUE(same_crs(crs, crs_from_user("EPSG:32611")));
}

TEST(GpkgWriter, TinZFeaturesOnRequest) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(false);
  TinWriteOptions o;
  o.ogr_tin = true;
  const std::string path = dir + "/tin.gpkg";
  write_tin(path, tin, o);
  std::string crs;
  OGRwkbGeometryType type = wkbUnknown;
  EXPECT_EQ(read_gpkg_faces(path, &crs, &type), kept_faces(tin));
  EXPECT_EQ(type, wkbTINZ);
}

// The rows of an SQL query on a GeoPackage, each field as text.
std::vector<std::vector<std::string>> query(GDALDataset& ds, const std::string& sql) {
  std::vector<std::vector<std::string>> rows;
  OGRLayer* result = ds.ExecuteSQL(sql.c_str(), nullptr, nullptr);
  EXPECT_NE(result, nullptr) << sql;
  if (result == nullptr) return rows;
  for (const auto& f : *result) {
    rows.emplace_back();
    for (int i = 0; i < f->GetFieldCount(); ++i) rows.back().push_back(f->GetFieldAsString(i));
  }
  ds.ReleaseResultSet(result);
  return rows;
}

// F is the float32 rounding of X in the given direction: on the right side, and the next float
// beyond it is on the other.
bool rounded_down(float f, double x) {
  return f <= x && std::nextafter(f, INFINITY) > x;
}
bool rounded_up(float f, double x) {
  return f >= x && std::nextafter(f, -INFINITY) < x;
}

// Random TINs of 2, about 600 and about 6,000 triangles: the index is one leaf, two levels and
// three levels of the SQLite rtree module (at most 51 cells a node).
TEST(GpkgWriter, SpatialIndexHoldsEveryTriangleAndFollowsEdits) {
  const std::string dir = test::scratch_dir("mesh_formats");
  for (const int points : {4, 300, 3000}) {
    SCOPED_TRACE(points);
    std::mt19937 rng(static_cast<unsigned>(points));
    std::uniform_real_distribution<double> u(0, 1000), z(100, 150);
    std::vector<Point3> pts;
    for (int i = 0; i < points; ++i) pts.push_back({kX0 + u(rng), kY0 + u(rng), z(rng)});
    const mesh::Triangulation tin = delaunay::triangulate(std::move(pts)).tin;
    const std::string path = dir + "/indexed.gpkg";
    fs::remove(path);
    write_tin(path, tin, {});

    GDALAllRegister();
    const GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
    ASSERT_TRUE(ds);
    OGRLayer* layer = ds->GetLayerByName("tin");
    ASSERT_NE(layer, nullptr);
    EXPECT_EQ(query(*ds,
                    "SELECT extension_name FROM gpkg_extensions WHERE table_name = 'tin' "
                    "AND column_name = 'geom'"),
              (std::vector<std::vector<std::string>>{{"gpkg_rtree_index"}}));
    EXPECT_EQ(query(*ds,
                    "SELECT count(*) FROM sqlite_master WHERE type = 'trigger' AND name "
                    "LIKE 'rtree_tin_geom_%'")[0][0],
              "6");
    EXPECT_EQ(query(*ds, "SELECT rtreecheck('rtree_tin_geom')")[0][0], "ok");

    // Every feature's envelope, rounded outwards, is its row of the index.
    std::map<GIntBig, OGREnvelope> envelope;
    for (const auto& f : *layer) f->GetGeometryRef()->getEnvelope(&envelope[f->GetFID()]);
    EXPECT_EQ(envelope.size(), tin.triangle_count());
    const auto rows = query(*ds, "SELECT id, minx, maxx, miny, maxy FROM rtree_tin_geom");
    ASSERT_EQ(rows.size(), envelope.size());
    std::map<GIntBig, std::array<float, 4>> box;
    for (const auto& r : rows) {
      const GIntBig id = std::stoll(r[0]);
      ASSERT_EQ(envelope.count(id), 1u) << id;
      const OGREnvelope& e = envelope[id];
      box[id] = {std::stof(r[1]), std::stof(r[2]), std::stof(r[3]), std::stof(r[4])};
      EXPECT_TRUE(rounded_down(box[id][0], e.MinX) && rounded_up(box[id][1], e.MaxX) &&
                  rounded_down(box[id][2], e.MinY) && rounded_up(box[id][3], e.MaxY))
          << id;
    }
    // A search of the tree finds what a scan of the boxes finds.
    std::uniform_real_distribution<double> corner(-100, 1000), side(1, 300);
    for (int q = 0; q < 20; ++q) {
      const double x0 = kX0 + corner(rng), y0 = kY0 + corner(rng);
      const double x1 = x0 + side(rng), y1 = y0 + side(rng);
      std::set<GIntBig> expected, found;
      for (const auto& [id, b] : box)
        if (b[0] <= x1 && b[1] >= x0 && b[2] <= y1 && b[3] >= y0) expected.insert(id);
      char sql[256];
      std::snprintf(sql, sizeof sql,
                    "SELECT id FROM rtree_tin_geom WHERE minx <= %.17g AND maxx >= %.17g AND "
                    "miny <= %.17g AND maxy >= %.17g",
                    x1, x0, y1, y0);
      for (const auto& r : query(*ds, sql)) found.insert(std::stoll(r[0]));
      EXPECT_EQ(found, expected) << sql;
    }
    // The triggers keep it in step: a deleted feature leaves, a moved one moves.
    const GIntBig gone = envelope.begin()->first, moved = envelope.rbegin()->first;
    ASSERT_EQ(layer->DeleteFeature(gone), OGRERR_NONE);
    OGRFeatureUniquePtr f(layer->GetFeature(moved));
    ASSERT_TRUE(f);
    OGRPolygon far;
    OGRLinearRing ring;
    for (const auto& [x, y] : {std::pair{1.0, 1.0}, {2.0, 1.0}, {1.0, 2.0}, {1.0, 1.0}})
      ring.addPoint(x, y, 0.0);
    far.addRing(&ring);
    f->SetGeometry(&far);
    ASSERT_EQ(layer->SetFeature(f.get()), OGRERR_NONE);
    EXPECT_EQ(query(*ds, "SELECT rtreecheck('rtree_tin_geom')")[0][0], "ok");
    EXPECT_EQ(query(*ds, "SELECT count(*) FROM rtree_tin_geom")[0][0],
              std::to_string(envelope.size() - 1));
    EXPECT_EQ(query(*ds, "SELECT id FROM rtree_tin_geom WHERE maxx <= 3"),
              (std::vector<std::vector<std::string>>{{std::to_string(moved)}}));
  }
}

TEST(GpkgAndLandXml, RefuseAnOffsetAndLeaveNothing) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(false);
  TinWriteOptions o;
  o.offset = {512000, 4123000, 0};
  EXPECT_THROW(write_tin(dir + "/tin.gpkg", tin, o), OutputError);
  EXPECT_THROW(write_tin(dir + "/tin.xml", tin, o), OutputError);
  EXPECT_TRUE(test::names_in(dir).empty());
  EXPECT_FALSE(format_takes_offset(TinFormat::gpkg));
  EXPECT_FALSE(format_takes_offset(TinFormat::landxml));
  EXPECT_TRUE(format_takes_offset(TinFormat::stl));
}

// ---- STL ---------------------------------------------------------------------------------------

TEST(StlWriter, BinaryRecordsReadBackWithTheOffsetAndUpwardNormals) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(true);
  TinWriteOptions o;
  o.offset = {512000, 4123000, 100};
  o.crs_wkt = crs_from_user("EPSG:32611");
  const std::string path = dir + "/tin.stl";
  const TinWriteStats stats = write_tin(path, tin, o);
  const std::string bytes = test::slurp(path);
  ASSERT_EQ(bytes.size(), 84 + 50 * tin.triangle_count());
  EXPECT_EQ(stats.bytes, bytes.size());
  EXPECT_NE(bytes.substr(0, 5), "solid");
  EXPECT_NE(bytes.substr(0, 80).find("offset 512000 4123000 100"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/tin.prj"));
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  ASSERT_EQ(n, tin.triangle_count());
  std::multiset<Face> expected;
  for (Face f : kept_faces(tin, o.offset)) {
    for (Corner& c : f)
      for (double& v : c) v = static_cast<float>(v);
    expected.insert(canonical(f));
  }
  std::multiset<Face> got;
  for (std::uint32_t i = 0; i < n; ++i) {
    float r[12];
    std::memcpy(r, bytes.data() + 84 + 50 * std::size_t{i}, sizeof r);
    EXPECT_GT(r[2], 0.0f) << "normal of triangle " << i << " points down";
    EXPECT_NEAR(r[0] * r[0] + r[1] * r[1] + r[2] * r[2], 1.0, 1e-6);
    Face f;
    for (int k = 0; k < 3; ++k) f[k] = {r[3 + 3 * k], r[4 + 3 * k], r[5 + 3 * k]};
    got.insert(canonical(f));
  }
  EXPECT_EQ(got, expected);
}

TEST(StlWriter, WarnsWhenFloatsWouldRoundMapCoordinates) {
  const mesh::Triangulation tin = sample_tin(false);
  const std::string warning = stl_precision_warning(tin, {0, 0, 0});
  EXPECT_NE(warning.find("rounded by up to"), std::string::npos) << warning;
  EXPECT_EQ(stl_precision_warning(tin, {512000, 4123000, 0}), "");
}

// Every format reports its progress (never backwards, ending at 1) and stops, leaving no file,
// when the callback asks it to (a Ctrl-C in the middle of a large file).
TEST(TinWriters, ReportProgressAndStopWhenAsked) {
  const std::string dir = test::scratch_dir("mesh_formats");
  const mesh::Triangulation tin = sample_tin(true);
  for (const char* name : {"t.obj", "t.ply", "t.geojson", "t.xml", "t.gpkg", "t.stl", "t.glb"}) {
    SCOPED_TRACE(name);
    std::vector<double> seen;
    const ProgressFn record = [&seen](std::string_view stage, double fraction) {
      EXPECT_EQ(stage, "write");
      seen.push_back(fraction);
      return true;
    };
    TinWriteOptions o;
    o.progress = &record;
    write_tin(dir + "/" + name, tin, o);
    ASSERT_GE(seen.size(), 3u);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    fs::remove(dir + "/" + name);

    const ProgressFn stop = [](std::string_view, double fraction) { return fraction == 0; };
    o.progress = &stop;
    EXPECT_THROW(write_tin(dir + "/" + name, tin, o), Cancelled);
    EXPECT_TRUE(test::names_in(dir).empty());
  }
}

TEST(FormatFromPath, KnowsTheProductExtensions) {
  EXPECT_EQ(format_from_path("a.xml"), TinFormat::landxml);
  EXPECT_EQ(format_from_path("a.LandXML"), TinFormat::landxml);
  EXPECT_EQ(format_from_path("a.gpkg"), TinFormat::gpkg);
  EXPECT_EQ(format_from_path("a.STL"), TinFormat::stl);
}

}  // namespace
}  // namespace tincdt::io
