// Polygon and draped-line reader (--clip, --erase, --replace, --soft-lines) on small vector
// sources written by the tests with OGR.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/crs.hpp"
#include "io/vector/polygon_reader.hpp"
#include "support/errors.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using ::testing::HasSubstr;

const fs::path kTmp = fs::path(TINCDT_TEST_TMP) / "polygon_reader";

// A feature with its WKT, ELEV and the text attribute LEVEL.
struct Feat : test::VectorFeature {
  Feat(std::string w, std::optional<double> e = std::nullopt, std::string l = "")
      : VectorFeature{std::move(w), e, -1, std::move(l)} {}
};

// Options for replace polygons: one z per feature, from FIELD, M values or the geometry.
ShapeReadOptions feature_z(const std::string& field = "", bool from_m = false) {
  ShapeReadOptions o;
  o.feature_z = true;
  o.z_field = field;
  o.z_from_m = from_m;
  return o;
}

struct Layer {
  std::string name;
  std::vector<Feat> features;
  int epsg = 0;  // 0 = no CRS
};

// Writes LAYERS to a fresh GeoPackage NAME in the scratch folder; returns its path.
std::string write_gpkg(const std::string& name, const std::vector<Layer>& layers) {
  return test::write_vector(kTmp / name, layers, "GPKG", "LEVEL");
}

std::string one_layer(const std::string& name, const std::vector<Feat>& features, int epsg = 0) {
  return write_gpkg(name, {{"shapes", features, epsg}});
}

// What READ (read_polygons or read_shape_lines) makes, with the default options, of the
// one-layer GeoPackage NAME of FEATURES (in EPSG:EPSG) at PATH.
struct ReadLayer {
  std::string path;
  ShapeData data;
  ShapeReadStats s;
};
template <class Reader>
ReadLayer read_layer(Reader read, const std::string& name, const std::vector<Feat>& features,
                     int epsg = 0) {
  ReadLayer r{one_layer(name, features, epsg), {}, {}};
  r.s = read(r.path, {}, r.data);
  return r;
}

TEST(PolygonReader, RingsOfAPolygonWithAHole) {
  const auto [path, data, s] = read_layer(
      read_polygons, "hole.gpkg",
      {{"POLYGON ((0 0, 10 0, 10 0, 10 10, 0 10, 0 0), (2 2, 2 4, 4 4, 4 2, 2 2))", 3.0}}, 32632);
  EXPECT_EQ(s.features, 1u);
  EXPECT_EQ(s.parts, 2u);
  EXPECT_EQ(s.vertices, 8u);  // closing points dropped, the repeated (10, 0) collapsed
  EXPECT_EQ(s.segments, 8u);
  EXPECT_EQ(s.repeated_vertices, 1u);
  EXPECT_EQ(s.layer, "shapes");
  EXPECT_EQ(crs_label(s.crs_wkt), "EPSG:32632");
  ASSERT_EQ(data.features.size(), 1u);
  const ShapeFeature& f = data.features[0];
  EXPECT_EQ(f.file, 0u);
  EXPECT_EQ(f.fid, 1);
  EXPECT_TRUE(std::isnan(f.z));  // no feature z asked for
  ASSERT_EQ(f.parts.size(), 2u);
  EXPECT_TRUE(f.parts[0].closed);
  EXPECT_TRUE(f.parts[1].closed);
  ASSERT_EQ(f.parts[0].points.size(), 4u);
  EXPECT_EQ(f.parts[0].points[1].x, 10);
  EXPECT_TRUE(std::isnan(f.parts[0].points[1].z));  // 2D: to be draped
  EXPECT_EQ(f.parts[1].points[2].x, 4);
  ASSERT_EQ(data.skipped.size(), 1u);
  EXPECT_EQ(data.skipped[0].at.x, 10);
  EXPECT_EQ(data.skipped[0].at.y, 0);
  EXPECT_EQ(data.files, std::vector<std::string>{path});
}

TEST(PolygonReader, MultiPolygonIsOneFeatureAndLinesAreDropped) {
  const auto [path, data, s] =
      read_layer(read_polygons, "multi.gpkg",
                 {{"MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)), ((5 5, 6 5, 6 6, 5 5)))"},
                  {"LINESTRING (0 0, 3 3)"},
                  {""},
                  {"POLYGON ((0 0, 1 1, 0 0))"}});
  EXPECT_EQ(s.features, 4u);
  EXPECT_EQ(s.empty_features, 3u);
  EXPECT_EQ(s.degenerate_parts, 1u);
  ASSERT_EQ(data.features.size(), 1u);
  EXPECT_EQ(data.features[0].parts.size(), 2u);
  ASSERT_EQ(data.dropped.size(), 3u);
  EXPECT_THAT(data.dropped[0].reason, HasSubstr("Line String geometry: only polygons"));
  EXPECT_TRUE(data.dropped[0].has_at);
  EXPECT_EQ(data.dropped[0].fid, 2);
  EXPECT_EQ(data.dropped[1].reason, "no geometry");
  EXPECT_FALSE(data.dropped[1].has_at);
  EXPECT_THAT(data.dropped[2].reason, HasSubstr("degenerate"));
}

TEST(PolygonReader, ReplaceZFromFieldGeometryOrM) {
  const std::string path =
      one_layer("z.gpkg", {{"POLYGON Z ((0 0 7, 4 0 7, 4 4 7, 0 0 7))", 12.5, "13.25"},
                           {"POLYGON M ((0 0 2, 4 0 2, 4 4 2, 0 0 2))", 1.0, "1"}});
  ShapeData by_field;
  read_polygons(path, feature_z("ELEV"), by_field);
  ASSERT_EQ(by_field.features.size(), 2u);
  EXPECT_EQ(by_field.features[0].z, 12.5);
  EXPECT_EQ(by_field.features[1].z, 1.0);

  ShapeData by_text;
  read_polygons(path, feature_z("LEVEL"), by_text);
  EXPECT_EQ(by_text.features[0].z, 13.25);

  // Geometry z: the first feature has one (7), the second is 2D (M only).
  ShapeData by_geometry;
  const auto e = test::thrown<InputError>([&] { read_polygons(path, feature_z(), by_geometry); });
  ASSERT_TRUE(e);
  EXPECT_THAT(e->what(), HasSubstr("feature 2"));
  EXPECT_EQ(e->remedy(), Remedy::z_field);
  EXPECT_TRUE(by_geometry.features.empty());  // left as it was
  EXPECT_TRUE(by_geometry.files.empty());

  const std::string m_path = one_layer("m.gpkg", {{"POLYGON M ((0 0 2, 4 0 2, 4 4 2, 0 0 2))"}});
  ShapeData by_m;
  read_polygons(m_path, feature_z("", true), by_m);
  ASSERT_EQ(by_m.features.size(), 1u);
  EXPECT_EQ(by_m.features[0].z, 2.0);
}

TEST(PolygonReader, ReplaceZMustBeOneLevel) {
  const std::string path =
      one_layer("tilted.gpkg", {{"POLYGON Z ((0 0 1, 4 0 1, 4 4 3, 0 0 1))", std::nullopt}});
  ShapeData data;
  EXPECT_THAT(error_of([&] { read_polygons(path, feature_z(), data); }),
              HasSubstr("range from 1 to 3"));
  EXPECT_THAT(error_of([&] { read_polygons(path, feature_z("ELEV"), data); }),
              HasSubstr("is NULL"));
  EXPECT_THAT(error_of([&] { read_polygons(path, feature_z("NOPE"), data); }),
              HasSubstr("no field 'NOPE' (fields: ELEV, LEVEL)"));
  // Without feature_z the geometry's z is kept and nothing else is asked for.
  ShapeReadOptions draped;
  draped.z_field = "NOPE";
  read_polygons(path, draped, data);
  ASSERT_EQ(data.features.size(), 1u);
  EXPECT_EQ(data.features[0].parts[0].points[2].z, 3);
}

TEST(PolygonReader, LinesKeepTheirOrderAndRingsAreClosed) {
  const auto [path, data, s] = read_layer(read_shape_lines, "lines.gpkg",
                                          {{"LINESTRING (0 0, 1 0, 1 0, 2 1)"},
                                           {"MULTILINESTRING ((0 5, 1 5), (3 3, 4 4, 3 5, 3 3))"},
                                           {"POLYGON ((0 0, 1 0, 1 1, 0 0))"},
                                           {"LINESTRING (7 7, 7 7)"},
                                           {"POINT (1 1)"}});
  EXPECT_EQ(s.features, 5u);
  EXPECT_EQ(s.empty_features, 2u);
  EXPECT_EQ(s.parts, 4u);
  EXPECT_EQ(s.segments, 2u + 1u + 3u + 3u);
  ASSERT_EQ(data.features.size(), 3u);
  EXPECT_FALSE(data.features[0].parts[0].closed);
  EXPECT_EQ(data.features[0].parts[0].points.size(), 3u);
  EXPECT_FALSE(data.features[1].parts[0].closed);
  EXPECT_TRUE(data.features[1].parts[1].closed);  // a line ending where it starts
  EXPECT_EQ(data.features[1].parts[1].points.size(), 3u);
  EXPECT_TRUE(data.features[2].parts[0].closed);
  ASSERT_EQ(data.dropped.size(), 2u);
  EXPECT_THAT(data.dropped[0].reason, HasSubstr("degenerate"));
  EXPECT_THAT(data.dropped[1].reason, HasSubstr("Point geometry"));
}

TEST(PolygonReader, LayersAndErrors) {
  const std::string path =
      write_gpkg("two.gpkg",
                 {{"a", {{"POLYGON ((0 0, 1 0, 1 1, 0 0))"}}},
                  {"b", {{"POLYGON ((0 0, 2 0, 2 2, 0 0))"}, {"POLYGON ((5 5, 6 5, 6 6, 5 5))"}}}});
  ShapeData data;
  const auto several = test::thrown<InputError>([&] { read_polygons(path, {}, data); });
  ASSERT_TRUE(several);
  EXPECT_THAT(several->what(), HasSubstr("2 layers (a, b): name one as FILE:LAYER"));
  EXPECT_EQ(several->remedy(), Remedy::choose_layer);
  read_polygons(path + ":b", {}, data);
  EXPECT_EQ(data.features.size(), 2u);
  EXPECT_EQ(data.files.back(), path + ":b");
  ShapeReadOptions layer_a;
  layer_a.layer = "a";
  read_polygons(path, layer_a, data);
  EXPECT_EQ(data.features.size(), 3u);
  EXPECT_EQ(data.features.back().file, 1u);
  EXPECT_THAT(error_of([&] { read_polygons(path + ":c", {}, data); }), HasSubstr("no layer 'c'"));
  EXPECT_THAT(error_of([&] { read_polygons((kTmp / "missing.gpkg").string(), {}, data); }),
              HasSubstr("no such file"));
  EXPECT_EQ(data.features.size(), 3u);
}

TEST(PolygonReader, GeoJsonPolygons) {
  fs::create_directories(kTmp);
  const fs::path path = kTmp / "clip.geojson";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(R"({"type": "FeatureCollection", "features": [
      {"type": "Feature", "properties": {"id": 7}, "geometry": {"type": "Polygon",
       "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]]}}]})",
               f);
    std::fclose(f);
  }
  ShapeData data;
  const ShapeReadStats s = read_polygons(path.string(), {}, data);
  EXPECT_EQ(s.vertices, 4u);
  EXPECT_EQ(crs_label(s.crs_wkt), "EPSG:4326");
  ASSERT_EQ(data.features.size(), 1u);
}

}  // namespace
}  // namespace tincdt::io
