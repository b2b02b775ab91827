// OGR line reader, against the real contour files of shared/data (see its PROVENANCE.md for the
// facts checked here) and against small vector sources that the tests write with OGR.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/crs.hpp"
#include "io/vector/line_reader.hpp"
#include "support/shared_data.hpp"
#include "support/vector_files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const fs::path kTmp = fs::path(TINCDT_TEST_TMP) / "line_reader";

// DROP is feature FID's, dropped for REASON, at AT (none: the drop has no place).
void expect_drop(const LineDrop& drop, std::int64_t fid,
                 const ::testing::Matcher<const std::string&>& reason,
                 std::optional<Point3> at = std::nullopt) {
  SCOPED_TRACE("feature " + std::to_string(fid));
  EXPECT_EQ(drop.fid, fid);
  EXPECT_THAT(drop.reason, reason);
  ASSERT_EQ(drop.has_at, at.has_value());
  if (at) {
    EXPECT_EQ(drop.at, *at);
  }
}

// ---- synthetic sources, written with OGR ----

using Feat = test::VectorFeature;  // the text attribute is NAME
using Layer = test::VectorLayer;

// Writes LAYERS to a fresh file NAME in the scratch folder with DRIVER; returns its path.
std::string write_vector(const std::string& name, const std::vector<Layer>& layers,
                         const char* driver_name = "GPKG") {
  return test::write_vector(kTmp / name, layers, driver_name, "NAME");
}

// One layer named "lines" with FEATURES.
std::string write_lines(const std::string& name, const std::vector<Feat>& features) {
  return write_vector(name, {{"lines", features}});
}

LineReadStats read(const std::string& path, LineData& out, const std::string& z_field = {},
                   bool z_from_m = false, const std::string& layer = {}) {
  LineReadOptions options;
  options.z_field = z_field;
  options.z_from_m = z_from_m;
  options.layer = layer;
  return read_lines(path, options, out);
}

// The InputError message of reading PATH, or "" when it read.
std::string read_error(const std::string& path, const LineReadOptions& options = {}) {
  LineData out;
  try {
    read_lines(path, options, out);
  } catch (const InputError& e) {
    EXPECT_TRUE(out.vertices.empty() && out.segments.empty() && out.features.empty() &&
                out.files.empty())
        << "a failed read must leave the output as it was";
    return e.what();
  }
  return {};
}

LineReadOptions z_field(const std::string& name) {
  LineReadOptions options;
  options.z_field = name;
  return options;
}

// The runs of segments of one part (consecutive segments chained b -> a).
struct Part {
  std::size_t first_segment;
  std::size_t segment_count;
  bool closed;
};

std::vector<Part> parts_of(const LineData& d) {
  std::vector<Part> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i < d.segments.size(); ++i) {
    const bool last = i + 1 == d.segments.size() || d.segments[i + 1].a != d.segments[i].b ||
                      d.segments[i + 1].feature != d.segments[i].feature;
    if (!last) continue;
    parts.push_back({start, i + 1 - start, d.segments[i].b == d.segments[start].a});
    start = i + 1;
  }
  return parts;
}

// Structural facts that every read must satisfy.
void expect_well_formed(const LineData& d) {
  for (const LineData::Segment& s : d.segments) {
    ASSERT_LT(s.a, d.vertices.size());
    ASSERT_LT(s.b, d.vertices.size());
    ASSERT_LT(s.feature, d.features.size());
    const Point3& a = d.vertices[s.a];
    const Point3& b = d.vertices[s.b];
    ASSERT_FALSE(a.x == b.x && a.y == b.y) << "zero-length segment " << s.a << "-" << s.b;
  }
  for (const LineFeature& f : d.features) ASSERT_LT(f.file, d.files.size());
}

// ---- real data ----

TEST(LineReaderReal, Vinschgau2dNeedsAZField) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  const std::string msg =
      read_error(test::shared_file("contours/elev_vinschgau_contours_100m.shp"));
  EXPECT_THAT(msg, AllOf(HasSubstr("elev_vinschgau_contours_100m.shp: "),
                         HasSubstr("layer elev_vinschgau_contours_100m, feature 0"),
                         HasSubstr("2D geometry has no elevation"), HasSubstr("ELEV")));
  EXPECT_EQ(msg.find('\n'), std::string::npos);
}

TEST(LineReaderReal, Vinschgau2dWithZField) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  LineData d;
  const std::string path = test::shared_file("contours/elev_vinschgau_contours_100m.shp");
  const LineReadStats s = read(path, d, "ELEV");
  expect_well_formed(d);
  EXPECT_EQ(s.layer, "elev_vinschgau_contours_100m");
  EXPECT_EQ(s.features, 1036u);
  EXPECT_EQ(d.features.size(), 1036u);
  EXPECT_EQ(s.empty_features, 0u);
  // 75,368 vertices in the file, of which 694 close a ring.
  EXPECT_EQ(s.closed_parts, 694u);
  EXPECT_EQ(s.vertices, 75368u - 694u);
  EXPECT_EQ(d.vertices.size(), s.vertices);
  EXPECT_EQ(s.segments, 75368u - 1036u);  // n - 1 per line, closed or not
  EXPECT_EQ(d.segments.size(), s.segments);
  EXPECT_EQ(s.repeated_vertices, 0u);
  EXPECT_EQ(s.degenerate_parts, 0u);
  EXPECT_TRUE(d.skipped.empty());
  EXPECT_TRUE(d.dropped.empty());
  EXPECT_EQ(crs_label(s.crs_wkt), "EPSG:32632");
  ASSERT_EQ(d.files.size(), 1u);
  EXPECT_EQ(d.files[0], path);

  std::set<double> levels;
  for (const Point3& v : d.vertices) {
    ASSERT_GE(v.z, 400.0);
    ASSERT_LE(v.z, 3800.0);
    ASSERT_EQ(std::fmod(v.z, 100.0), 0.0) << v.z;
    levels.insert(v.z);
  }
  EXPECT_EQ(levels.size(), 35u);
  for (const LineData::Segment& seg : d.segments) {
    ASSERT_EQ(d.vertices[seg.a].z, d.features[seg.feature].z);
    ASSERT_EQ(d.vertices[seg.b].z, d.features[seg.feature].z);
  }
  EXPECT_EQ(parts_of(d).size(), 1036u);
}

// The Vinschgau contours of the 2D shapefile, their z from ELEV: what the other files of these
// lines must read as.
LineData vinschgau_from_shapefile() {
  LineData d;
  read(test::shared_file("contours/elev_vinschgau_contours_100m.shp"), d, "ELEV");
  return d;
}

// GOT has the vertices and segments of EXPECTED, in the same order.
void expect_same_lines(const LineData& got, const LineData& expected) {
  ASSERT_EQ(got.vertices.size(), expected.vertices.size());
  for (std::size_t i = 0; i < got.vertices.size(); ++i) {
    ASSERT_EQ(got.vertices[i], expected.vertices[i]) << "vertex " << i;
  }
  ASSERT_EQ(got.segments.size(), expected.segments.size());
  for (std::size_t i = 0; i < got.segments.size(); ++i) {
    ASSERT_EQ(got.segments[i].a, expected.segments[i].a) << "segment " << i;
    ASSERT_EQ(got.segments[i].b, expected.segments[i].b) << "segment " << i;
  }
}

TEST(LineReaderReal, Vinschgau3dMatches2dWithZField) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  const LineData flat = vinschgau_from_shapefile();
  LineData solid;
  const LineReadStats s =
      read(test::shared_file("contours/elev_vinschgau_contours_100m_3d.shp"), solid);
  expect_well_formed(solid);
  EXPECT_EQ(s.segments, flat.segments.size());
  expect_same_lines(solid, flat);
  ASSERT_FALSE(solid.features.empty());
  EXPECT_TRUE(std::isnan(solid.features[0].z)) << "z from the geometry: no feature level";
  EXPECT_FALSE(std::isnan(flat.features[0].z));
}

TEST(LineReaderReal, GeoPackageReadsLikeTheShapefile) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  const LineData shp = vinschgau_from_shapefile();
  LineData gpkg;
  const LineReadStats s =
      read(test::shared_file("contours/elev_vinschgau_contours_100m.gpkg"), gpkg, "ELEV");
  EXPECT_EQ(s.layer, "contour");
  EXPECT_EQ(crs_label(s.crs_wkt), "EPSG:32632");
  expect_same_lines(gpkg, shp);
  ASSERT_EQ(gpkg.features.size(), shp.features.size());
  for (std::size_t i = 0; i < gpkg.features.size(); ++i) {
    ASSERT_EQ(gpkg.features[i].z, shp.features[i].z);
  }
}

TEST(LineReaderReal, TopographyClosedRingsStayClosed) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  LineData d;
  const LineReadStats s =
      read(test::shared_file("pair_topography/Topography_contours_1m_3d.shp"), d);
  expect_well_formed(d);
  EXPECT_EQ(s.features, 120u);
  EXPECT_EQ(d.features.size(), 120u);
  EXPECT_EQ(s.closed_parts, 61u);
  EXPECT_EQ(s.vertices + s.closed_parts, 9251u);  // the file's count includes closing vertices
  EXPECT_EQ(crs_label(s.crs_wkt), "EPSG:2949");

  // Every part is a run of consecutive vertex indices; a closed one ends at its first vertex.
  const std::vector<Part> parts = parts_of(d);
  ASSERT_EQ(parts.size(), 120u);
  std::size_t closed = 0;
  for (const Part& p : parts) {
    const LineData::Segment& first = d.segments[p.first_segment];
    const LineData::Segment& last = d.segments[p.first_segment + p.segment_count - 1];
    for (std::size_t i = 0; i + 1 < p.segment_count; ++i) {
      const LineData::Segment& seg = d.segments[p.first_segment + i];
      ASSERT_EQ(seg.b, seg.a + 1);
    }
    if (p.closed) {
      ++closed;
      EXPECT_EQ(last.b, first.a);
      EXPECT_EQ(last.a, first.a + p.segment_count - 1);
      EXPECT_GE(p.segment_count, 3u);
    } else {
      EXPECT_EQ(last.b, first.a + p.segment_count);
    }
  }
  EXPECT_EQ(closed, 61u);
}

TEST(LineReaderReal, CrsOfLuxembourgAndOfAFileWithoutPrj) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  LineData d;
  const LineReadStats lux =
      read(test::shared_file("contours/elev_lux_contours_25m.shp"), d, "ELEV");
  EXPECT_EQ(crs_label(lux.crs_wkt), "EPSG:4326");
  EXPECT_EQ(lux.features, 416u);
  for (const Point3& v : d.vertices) {
    ASSERT_GT(v.x, 5.0);  // degrees of longitude, not metres
    ASSERT_LT(v.x, 7.0);
  }
  const LineReadStats none =
      read(test::shared_file("contours/Topography_lidR2016_contours_2m_3d.shp"), d);
  EXPECT_TRUE(none.crs_wkt.empty());
  EXPECT_EQ(none.features, 69u);
  EXPECT_EQ(none.closed_parts, 16u);
  EXPECT_EQ(d.files.size(), 2u);
}

TEST(LineReaderReal, MissingZFieldListsTheFields) {
  TINCDT_REQUIRE_SHARED_DATA("contours");
  const std::string msg =
      read_error(test::shared_file("contours/elev_vinschgau_contours_100m.shp"), z_field("HEIGHT"));
  EXPECT_THAT(msg, AllOf(HasSubstr("layer elev_vinschgau_contours_100m"), HasSubstr("HEIGHT"),
                         HasSubstr("fields: ID, ELEV")));
}

// ---- synthetic sources ----

// What a source read with the default options holds, checked well formed, and its counts.
struct ReadLines {
  LineData d;
  LineReadStats s;
};
ReadLines read_well_formed(const std::string& path) {
  ReadLines r;
  r.s = read(path, r.d);
  expect_well_formed(r.d);
  return r;
}

TEST(LineReader, RepeatedVerticesAreCollapsed) {
  const std::string path = write_lines(
      "repeats.gpkg", {{"LINESTRING Z (0 0 1, 0 0 1, 1 0 2, 1 0 5, 1 0 2, 2 0 3, 2 0 3)", 1.0, 1}});
  const auto [d, s] = read_well_formed(path);
  EXPECT_EQ(s.repeated_vertices, 4u);
  EXPECT_EQ(s.zero_length_segments, 4u);
  // Each collapsed vertex where it was, with its own z, for the diagnostics.
  ASSERT_EQ(d.skipped.size(), 4u);
  const Point3 collapsed[] = {{0, 0, 1}, {1, 0, 5}, {1, 0, 2}, {2, 0, 3}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(d.skipped[i].at, collapsed[i]) << i;
    EXPECT_EQ(d.skipped[i].file, 0u);
    EXPECT_EQ(d.skipped[i].fid, 1);
  }
  EXPECT_TRUE(d.dropped.empty());
  ASSERT_EQ(d.vertices.size(), 3u);
  EXPECT_EQ(d.vertices[0], (Point3{0, 0, 1}));
  EXPECT_EQ(d.vertices[1], (Point3{1, 0, 2}));  // the first z of the run is kept
  EXPECT_EQ(d.vertices[2], (Point3{2, 0, 3}));
  ASSERT_EQ(d.segments.size(), 2u);
  EXPECT_EQ(d.segments[0].a, 0u);
  EXPECT_EQ(d.segments[0].b, 1u);
  EXPECT_EQ(d.segments[1].a, 1u);
  EXPECT_EQ(d.segments[1].b, 2u);
  EXPECT_EQ(s.closed_parts, 0u);
}

TEST(LineReader, ZeroLengthPartsAddNothing) {
  const std::string path = write_lines(
      "zero_length.gpkg", {
                              {"MULTILINESTRING Z ((5 5 1, 5 5 1), (0 0 1, 1 1 1))", 1.0, 1},
                              {"LINESTRING Z (7 7 1, 7 7 2)", 1.0, 2},
                              {"LINESTRING Z (3 3 3, 4 3 3, 3 3 3)", 1.0, 3},
                          });
  const auto [d, s] = read_well_formed(path);
  EXPECT_EQ(s.features, 3u);
  EXPECT_EQ(s.degenerate_parts, 2u);
  EXPECT_EQ(s.empty_features, 1u);  // feature 2 is a single point
  ASSERT_EQ(d.features.size(), 2u);
  EXPECT_EQ(d.features[0].fid, 1);
  EXPECT_EQ(d.features[1].fid, 3);
  ASSERT_EQ(d.segments.size(), 2u);  // 0-1, and A-B-A as the single segment A-B
  EXPECT_EQ(d.segments[1].feature, 1u);
  EXPECT_EQ(d.vertices.size(), 4u);
  EXPECT_EQ(s.closed_parts, 0u);
  // The two zero-length segments, and feature 2 dropped at its single point.
  ASSERT_EQ(d.skipped.size(), s.zero_length_segments);
  ASSERT_EQ(d.skipped.size(), 2u);
  EXPECT_EQ(d.skipped[0].at, (Point3{5, 5, 1}));
  EXPECT_EQ(d.skipped[0].fid, 1);
  EXPECT_EQ(d.skipped[1].at, (Point3{7, 7, 2}));
  EXPECT_EQ(d.skipped[1].fid, 2);
  ASSERT_EQ(d.dropped.size(), s.empty_features);
  EXPECT_EQ(d.dropped[0].file, 0u);
  expect_drop(d.dropped[0], 2, HasSubstr("degenerate"), Point3{7, 7, 1});
}

TEST(LineReader, MultiLineStringsAndPolygonRings) {
  const std::string path = write_lines(
      "rings.gpkg",
      {
          {"MULTILINESTRING Z ((0 0 1, 1 0 1, 2 0 1), (0 5 2, 1 5 2))", 1.0, 1},
          {"POLYGON Z ((0 0 1, 10 0 1, 10 10 1, 0 10 1, 0 0 1), (2 2 2, 3 2 2, 3 3 2, 2 2 2))", 1.0,
           2},
          {"MULTIPOLYGON Z (((20 0 1, 21 0 1, 21 1 1, 20 0 1)), ((30 0 1, 31 0 1, 31 1 1, 30 0 "
           "1)))",
           1.0, 3},
      });
  const auto [d, s] = read_well_formed(path);
  EXPECT_EQ(s.vertices, 5u + 7u + 6u);
  EXPECT_EQ(s.segments, 3u + 7u + 6u);
  EXPECT_EQ(s.closed_parts, 4u);
  ASSERT_EQ(d.features.size(), 3u);
  const std::vector<Part> parts = parts_of(d);
  ASSERT_EQ(parts.size(), 6u);
  EXPECT_FALSE(parts[0].closed);
  EXPECT_FALSE(parts[1].closed);
  // Outer ring: vertices 5..8, its last segment returns to 5; the hole: 9..11, back to 9.
  ASSERT_EQ(parts[2].segment_count, 4u);
  EXPECT_EQ(d.segments[parts[2].first_segment + 3].a, 8u);
  EXPECT_EQ(d.segments[parts[2].first_segment + 3].b, 5u);
  ASSERT_EQ(parts[3].segment_count, 3u);
  EXPECT_EQ(d.segments[parts[3].first_segment + 2].b, 9u);
  EXPECT_EQ(d.vertices[9], (Point3{2, 2, 2}));
  EXPECT_TRUE(parts[4].closed);
  EXPECT_TRUE(parts[5].closed);
  EXPECT_EQ(d.segments[parts[5].first_segment].feature, 2u);
}

TEST(LineReader, ZFromMValues) {
  const std::string path =
      write_lines("measures.gpkg", {
                                       {"LINESTRING M (0 0 10, 1 0 11, 2 1 12)", 1.0, 1},
                                       {"LINESTRING ZM (0 5 99, 1 5 99 20, 2 5 99 21)", 1.0, 2},
                                   });
  LineData d;
  LineReadOptions options;
  options.z_from_m = true;
  const LineReadStats s = read_lines(path, options, d);
  EXPECT_EQ(s.segments, 4u);
  ASSERT_EQ(d.vertices.size(), 6u);
  EXPECT_EQ(d.vertices[0].z, 10.0);
  EXPECT_EQ(d.vertices[2].z, 12.0);
  EXPECT_EQ(d.vertices[4].z, 20.0);  // M, not the Z of 99

  // Without z_from_m the measured 2D line has no elevation.
  EXPECT_THAT(read_error(path), AllOf(HasSubstr("layer lines, feature 1"),
                                      HasSubstr("2D geometry has no elevation")));
  // And a 3D line without M cannot give z from M.
  const std::string no_m =
      write_lines("no_measures.gpkg", {{"LINESTRING Z (0 0 1, 1 1 1)", 1.0, 4}});
  EXPECT_THAT(read_error(no_m, options), AllOf(HasSubstr("feature 4"), HasSubstr("no M values")));
}

TEST(LineReader, ZFieldOverridesGeometryZ) {
  const std::string path = write_lines("override.gpkg", {{"LINESTRING Z (0 0 1, 1 1 2)", 7.5, 1}});
  LineData d;
  read(path, d, "ELEV");
  ASSERT_EQ(d.vertices.size(), 2u);
  EXPECT_EQ(d.vertices[0].z, 7.5);
  EXPECT_EQ(d.vertices[1].z, 7.5);
  ASSERT_EQ(d.features.size(), 1u);
  EXPECT_EQ(d.features[0].z, 7.5);
}

TEST(LineReader, NullZAttributeNamesTheFeature) {
  const std::string path =
      write_lines("null_z.gpkg", {
                                     {"LINESTRING (0 0, 1 1)", 3.0, 1},
                                     {"LINESTRING (0 1, 1 2)", std::nullopt, 42},
                                 });
  const std::string msg = read_error(path, z_field("ELEV"));
  EXPECT_THAT(msg, AllOf(HasSubstr("null_z.gpkg: layer lines, feature 42: "), HasSubstr("ELEV"),
                         HasSubstr("NULL")));
}

TEST(LineReader, TextZFieldMustHoldNumbers) {
  const std::string good = write_lines("text_z.gpkg", {{"LINESTRING (0 0, 1 1)", 1.0, 1, "12.5"}});
  LineData d;
  read(good, d, "NAME");
  ASSERT_EQ(d.vertices.size(), 2u);
  EXPECT_EQ(d.vertices[1].z, 12.5);
  const std::string bad =
      write_lines("text_z_bad.gpkg", {{"LINESTRING (0 0, 1 1)", 1.0, 5, "high"}});
  EXPECT_THAT(read_error(bad, z_field("NAME")),
              AllOf(HasSubstr("feature 5"), HasSubstr("'high'"), HasSubstr("not a number")));
}

TEST(LineReader, NonFiniteCoordinateNamesTheFeature) {
  Feat bad{"LINESTRING Z (0 0 1, 1 1 1, 2 2 1)", 1.0, 9};
  bad.nan_vertex = 1;
  const std::string path = write_lines("nan.gpkg", {{"LINESTRING Z (5 5 1, 6 6 1)", 1.0, 1}, bad});
  EXPECT_THAT(read_error(path), AllOf(HasSubstr("layer lines, feature 9"), HasSubstr("vertex 1"),
                                      HasSubstr("non-finite")));
}

TEST(LineReader, LayerChosenByNameInTheSpecOrTheOptions) {
  const std::string path =
      write_vector("two_layers.gpkg", {{"lines_a", {{"LINESTRING Z (0 0 1, 1 0 1)", 1.0, 1}}, 2949},
                                       {"lines_b",
                                        {{"LINESTRING Z (0 0 2, 1 0 2, 2 0 2)", 2.0, 1},
                                         {"LINESTRING Z (0 1 2, 1 1 2)", 2.0, 2}}}});

  EXPECT_THAT(read_error(path), AllOf(HasSubstr("two_layers.gpkg: 2 layers (lines_a, lines_b)"),
                                      HasSubstr("FILE:LAYER")));
  LineData d;
  const LineReadStats b = read(path + ":lines_b", d);
  EXPECT_EQ(b.layer, "lines_b");
  EXPECT_EQ(b.segments, 3u);
  EXPECT_TRUE(b.crs_wkt.empty()) << "GeoPackage's 'Undefined geographic SRS' is no CRS";
  const LineReadStats a = read(path + ":lines_b", d, {}, false, "lines_a");  // options win
  EXPECT_EQ(a.layer, "lines_a");
  EXPECT_EQ(a.segments, 1u);
  EXPECT_EQ(crs_label(a.crs_wkt), "EPSG:2949");
  ASSERT_EQ(d.files.size(), 2u);
  EXPECT_EQ(d.files[0], path + ":lines_b");
  EXPECT_EQ(d.files[1], path + ":lines_a");
  // The second file's features and segments index past the first's.
  ASSERT_EQ(d.features.size(), 3u);
  EXPECT_EQ(d.features[2].file, 1u);
  EXPECT_EQ(d.features[2].fid, 1);
  ASSERT_EQ(d.segments.size(), 4u);
  EXPECT_EQ(d.segments[3].feature, 2u);
  EXPECT_EQ(d.segments[3].a, 5u);
  EXPECT_EQ(d.segments[3].b, 6u);
  expect_well_formed(d);

  EXPECT_THAT(read_error(path + ":lines_c"),
              AllOf(HasSubstr("no layer 'lines_c'"), HasSubstr("lines_a, lines_b")));
}

TEST(LineReader, ColonInAFileNameIsNotALayer) {
  const std::string path = write_vector(
      "a:b.geojson", {{"ab", {{"LINESTRING Z (0 0 1, 1 0 1, 1 1 1)", 1.0}}}}, "GeoJSON");
  ASSERT_TRUE(fs::exists(path));
  LineData d;
  const LineReadStats s = read(path, d);
  EXPECT_EQ(s.segments, 2u);
  EXPECT_EQ(d.files.at(0), path);
  // When both "X" and "X:lines" exist, the whole name wins.
  const std::string gpkg = write_lines("both.gpkg", {{"LINESTRING Z (0 0 1, 1 0 1)", 1.0, 1}});
  const std::string whole = write_vector(
      "both.gpkg:lines", {{"x", {{"LINESTRING Z (0 0 1, 1 0 1, 2 0 1, 3 0 1)", 1.0}}}}, "GeoJSON");
  ASSERT_EQ(whole, gpkg + ":lines");
  EXPECT_EQ(read(whole, d).segments, 3u);
  LineReadOptions named;
  named.layer = "lines";  // the file is still the whole name, which holds no layer "lines"
  EXPECT_THAT(read_error(whole, named), HasSubstr("both.gpkg:lines: no layer 'lines' (layers: x)"));
  // A spec whose head does not exist is not split either: the error names the whole.
  const std::string missing = (kTmp / "nothing_here.gpkg").string() + ":layer";
  EXPECT_THAT(read_error(missing), HasSubstr("nothing_here.gpkg:layer: no such file"));
}

TEST(LineReader, PointsAreSkippedAndCounted) {
  const std::string path = write_lines(
      "points.gpkg",
      {
          {"POINT Z (0 0 1)", 1.0, 1},
          {"MULTIPOINT Z ((0 0 1), (1 1 1))", 1.0, 2},
          {"", 1.0, 3},
          {"GEOMETRYCOLLECTION Z (POINT Z (5 5 5), LINESTRING Z (0 0 1, 1 1 1))", 1.0, 4},
      });
  LineData d;
  const LineReadStats s = read(path, d);
  EXPECT_EQ(s.features, 4u);
  EXPECT_EQ(s.empty_features, 3u);
  ASSERT_EQ(d.features.size(), 1u);
  EXPECT_EQ(d.features[0].fid, 4);
  EXPECT_EQ(s.segments, 1u);
  EXPECT_EQ(d.vertices.size(), 2u);
  // Why each of the three was dropped, and where.
  ASSERT_EQ(d.dropped.size(), 3u);
  expect_drop(d.dropped[0], 1, AllOf(HasSubstr("Point"), HasSubstr("only lines")), Point3{0, 0, 1});
  expect_drop(d.dropped[1], 2, HasSubstr("Multi Point"), Point3{0, 0, 1});
  expect_drop(d.dropped[2], 3, "no geometry");
  EXPECT_TRUE(d.skipped.empty());
}

TEST(LineReader, EveryDroppedFeatureHasItsReason) {
  CPLPushErrorHandler(CPLQuietErrorHandler);  // "non-standard gpkg_geom_TIN extension"
  const std::string path = write_lines(
      "dropped.gpkg",
      {
          {"LINESTRING Z EMPTY", 1.0, 1},
          {"POLYGON Z ((3 3 9, 3 3 9, 3 3 9, 3 3 9))", 1.0, 2},  // a ring of one point
          {"GEOMETRYCOLLECTION Z (LINESTRING Z (8 8 1, 8 8 2), POINT Z (6 6 6))", 1.0, 3},
          {"TIN Z (((0 0 1, 1 0 1, 0 1 1, 0 0 1)))", 1.0, 4},
          {"LINESTRING Z (0 0 1, 1 1 1)", 1.0, 5},
      });
  CPLPopErrorHandler();
  const auto [d, s] = read_well_formed(path);
  EXPECT_EQ(s.features, 5u);
  EXPECT_EQ(s.empty_features, 4u);
  ASSERT_EQ(d.dropped.size(), 4u);
  expect_drop(d.dropped[0], 1, "empty geometry");
  expect_drop(d.dropped[1], 2, HasSubstr("degenerate"), Point3{3, 3, 9});
  // Both problems named; the location is the first one met (the line comes before the point).
  expect_drop(d.dropped[2], 3, AllOf(HasSubstr("degenerate"), HasSubstr("Point")), Point3{8, 8, 1});
  expect_drop(d.dropped[3], 4, HasSubstr("TIN"), Point3{0, 0, 1});
  // The collapsed vertices of features 2 (three) and 3 (one) are recorded too, and counted.
  EXPECT_EQ(d.skipped.size(), s.repeated_vertices);
  ASSERT_EQ(d.skipped.size(), 4u);
  EXPECT_EQ(d.skipped[2].fid, 2);
  EXPECT_EQ(d.skipped[3].at, (Point3{8, 8, 2}));
  EXPECT_EQ(d.skipped[3].fid, 3);
  ASSERT_EQ(d.features.size(), 1u);
  EXPECT_EQ(d.features[0].fid, 5);
}

TEST(LineReader, DiagnosticsIndexTheFileTheyCameFrom) {
  const std::string a = write_lines(
      "diag_a.gpkg", {{"POINT Z (1 1 1)", 1.0, 1}, {"LINESTRING Z (0 0 1, 1 0 1)", 1.0, 2}});
  const std::string b =
      write_lines("diag_b.gpkg", {{"LINESTRING Z (0 0 1, 0 0 1, 1 0 1)", 1.0, 7}, {"", 1.0, 8}});
  LineData d;
  read(a, d);
  read(b, d);
  ASSERT_EQ(d.files.size(), 2u);
  ASSERT_EQ(d.dropped.size(), 2u);
  EXPECT_EQ(d.dropped[0].file, 0u);
  EXPECT_EQ(d.dropped[0].fid, 1);
  EXPECT_EQ(d.dropped[1].file, 1u);
  EXPECT_EQ(d.dropped[1].fid, 8);
  ASSERT_EQ(d.skipped.size(), 1u);
  EXPECT_EQ(d.skipped[0].file, 1u);
  EXPECT_EQ(d.skipped[0].fid, 7);
  EXPECT_EQ(d.skipped[0].at, (Point3{0, 0, 1}));
}

TEST(LineReader, CurvesAreApproximatedWithAWarning) {
  const std::string path =
      write_lines("curve.gpkg", {{"CIRCULARSTRING Z (0 0 1, 1 1 1, 2 0 1)", 1.0, 1}});
  const auto [d, s] = read_well_formed(path);
  EXPECT_GT(s.segments, 4u);
  for (const Point3& v : d.vertices) ASSERT_LE(std::hypot(v.x - 1.0, v.y), 1.0 + 1e-9);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_THAT(s.warnings.back(), HasSubstr("curved geometries approximated"));
}

TEST(LineReader, UnreadableSources) {
  EXPECT_THAT(read_error((kTmp / "missing.shp").string()), HasSubstr("missing.shp: no such file"));
  fs::create_directories(kTmp);
  const fs::path text = kTmp / "not_vectors.gpkg";
  {
    FILE* f = std::fopen(text.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("this is no GeoPackage\n", f);
    std::fclose(f);
  }
  EXPECT_THAT(read_error(text.string()), HasSubstr("not_vectors.gpkg: cannot open"));
  LineReadOptions both = z_field("ELEV");
  both.z_from_m = true;
  EXPECT_THAT(read_error(text.string(), both), HasSubstr("exclude each other"));
}

TEST(LineReader, FailedReadLeavesEarlierDataAlone) {
  const std::string good = write_lines("keep_good.gpkg", {{"LINESTRING Z (0 0 1, 1 0 1)", 1.0, 1}});
  const std::string bad =
      write_lines("keep_bad.gpkg", {
                                       {"LINESTRING Z (0 0 1, 0 0 1, 1 0 1)", 1.0, 1},
                                       {"POINT Z (4 4 4)", 1.0, 2},
                                       {"LINESTRING (0 1, 1 1)", 1.0, 3},
                                   });
  LineData d;
  read(good, d);
  EXPECT_THROW(read(bad, d), InputError);
  EXPECT_EQ(d.vertices.size(), 2u);
  EXPECT_EQ(d.segments.size(), 1u);
  EXPECT_EQ(d.features.size(), 1u);
  EXPECT_EQ(d.files.size(), 1u);
  EXPECT_TRUE(d.skipped.empty()) << "the failed file's collapsed vertex must go too";
  EXPECT_TRUE(d.dropped.empty()) << "the failed file's dropped point must go too";
}

}  // namespace
}  // namespace tincdt::io
