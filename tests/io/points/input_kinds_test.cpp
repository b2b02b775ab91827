// What the point readers are given and how they answer: files that are no point files (rasters,
// vector files, archives), meshes (PLY, whose vertices are points), and class filters on XYZ
// text.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/point_reader.hpp"
#include "point_reading.hpp"
#include "support/errors.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

using test::input_error;
using test::points_of;

const test::ScratchFolder scratch("input_kinds");

// Every byte printable ASCII: no message carries a file's binary bytes to the terminal.
bool printable(const std::string& text) {
  for (const char c : text) {
    if (c < 0x20 || c > 0x7E) return false;
  }
  return true;
}

// ---- Files that are no point files, and PLY meshes
// -----------------------------------------------

TEST(InputKinds, RastersAndVectorFilesAreNamed) {
  TINCDT_REQUIRE_SHARED_DATA("dem");
  struct Case {
    std::string path;
    const char* kind;
    Remedy remedy;
  };
  const Case cases[] = {
      {test::shared_file("dem/elev_lux.tif"), "TIFF", Remedy::none},
      {test::shared_file("contours/elev_lux_contours_25m.shp"), "shapefile",
       Remedy::vector_as_points},
      {test::shared_file("contours/elev_lux_contours_25m.dbf"), "shapefile",
       Remedy::vector_as_points},
      {test::shared_file("contours/elev_vinschgau_contours_100m.gpkg"), "GeoPackage",
       Remedy::vector_as_points},
      {scratch("lines.geojson",
               R"({"type": "FeatureCollection", "features": [{"type": "Feature", )"
               R"("geometry": {"type": "LineString", "coordinates": [[0, 0, 1], [1, 1, 1]]}}]})"),
       "GeoJSON", Remedy::vector_as_points},
      {scratch("grid.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n"),
       "ASCII grid", Remedy::none},
      {scratch("points.xyz.gz", std::string("\x1F\x8B\x08\x00\x00\x00\x00\x00", 8)), "gzip",
       Remedy::none},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.path);
    const auto e = input_error(c.path);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->file(), c.path);
    EXPECT_THAT(e->detail(), ::testing::AllOf(HasSubstr(c.kind), HasSubstr("not a point file")));
    EXPECT_EQ(e->remedy(), c.remedy);
    EXPECT_TRUE(printable(e->what())) << e->what();
    // The library names no option of the command line.
    EXPECT_THAT(e->what(), Not(HasSubstr("--")));
  }
}

TEST(InputKinds, UnknownBinaryDataIsRefusedWithoutItsBytes) {
  std::string junk = "\x01\x02";
  for (int i = 0; i < 300; ++i) junk += static_cast<char>(0x80 + i % 120);
  const auto e = input_error(scratch("junk.xyz", junk));
  ASSERT_TRUE(e);
  EXPECT_THAT(e->detail(), HasSubstr("binary data"));
  EXPECT_TRUE(printable(e->what())) << e->what();
  // Text whose first line is fine but later turns to bytes: the parser's line error, quoted
  // printable and short.
  const auto late = input_error(scratch("late.xyz", "1 2 3\n" + std::string(200, '\xFE') + "\n"));
  ASSERT_TRUE(late);
  EXPECT_EQ(late->where(), "line 2");
  EXPECT_TRUE(printable(late->what())) << late->what();
  EXPECT_LT(late->detail().size(), 200u) << late->what();
}

const char* const kAsciiPly =
    "ply\nformat ascii 1.0\ncomment tincdt\ncomment offset 1000 2000 0\ncomment crs EPSG:2949\n"
    "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
    "element face 2\nproperty list uchar uint vertex_indices\nend_header\n"
    "0 0 1\n10 0 2\n10 10 3\n0 10 4\n3 0 1 2\n3 0 2 3\n";

TEST(InputKinds, APlyMeshGivesItsVerticesAsPoints) {
  PointReadStats stats;
  const std::vector<Point3> pts = points_of(scratch("tin.ply", kAsciiPly), {}, &stats);
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_EQ(pts[2].x, 1010.0);
  EXPECT_EQ(pts[2].y, 2010.0);
  EXPECT_EQ(pts[2].z, 3.0);
  EXPECT_EQ(stats.format, "ply");
  EXPECT_EQ(stats.points_read, 4u);
  EXPECT_THAT(stats.crs_wkt, HasSubstr("2949"));
  PointFilter box;
  box.box = BBox{};
  box.box->add(1000, 2000);
  box.box->add(1005, 2011);
  EXPECT_EQ(points_of(scratch("tin.ply", kAsciiPly), box).size(), 2u);
  // A class filter has nothing to filter in a mesh.
  PointFilter keep;
  keep.keep_classes = {2};
  const auto e = input_error(scratch("tin.ply", kAsciiPly), keep);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->remedy(), Remedy::class_filter);
}

// ---- Class filters on XYZ text ------------------------------------------------------------------

const char* const kClassified =
    "X,Y,Z,Intensity,Classification\n0,0,1,5,2\n1,0,2,5,1\n0,1,3,5,2\n1,1,4,5,7\n";

TEST(XyzClasses, AClassColumnIsFilteredBy) {
  const std::string path = scratch("classified.csv", kClassified);
  PointFilter keep;
  keep.keep_classes = {2};
  PointReadStats stats;
  const std::vector<Point3> kept = points_of(path, keep, &stats);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[1].z, 3.0);
  EXPECT_EQ(stats.points_read, 4u);
  EXPECT_EQ(stats.points_kept, 2u);
  PointFilter drop;
  drop.drop_classes = {7, 1};
  EXPECT_EQ(points_of(path, drop).size(), 2u);
  // "class", any case, blank-separated.
  const std::string blank = scratch("class.xyz", "x y z CLASS\n0 0 1 2\n1 0 2 3\n0 1 3 2.0\n");
  EXPECT_EQ(points_of(blank, keep).size(), 2u);
  // Without a filter the column is not even parsed.
  EXPECT_EQ(points_of(scratch("odd_class.csv", "x,y,z,class\n0,0,1,ground\n")).size(), 1u);
  const auto bad = input_error(scratch("odd_class.csv", "x,y,z,class\n0,0,1,ground\n"), keep);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->where(), "line 2");
  EXPECT_THAT(bad->detail(), HasSubstr("'ground' is not a class code"));
}

TEST(XyzClasses, FiltersTheTextCannotAnswerAreErrors) {
  PointFilter keep;
  keep.keep_classes = {2};
  const std::string plain = scratch("plain.xyz", "0 0 1\n1 0 2\n0 1 3\n");
  const auto e = input_error(plain, keep);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), plain);
  EXPECT_EQ(e->remedy(), Remedy::class_filter);
  EXPECT_THAT(e->detail(), HasSubstr("no classification column"));
  EXPECT_THAT(e->what(), Not(HasSubstr("--")));
  PointFilter first;
  first.first_return_only = true;
  const auto r = input_error(scratch("classified.csv", kClassified), first);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->remedy(), Remedy::return_filter);
  EXPECT_THAT(r->detail(), HasSubstr("no return numbers"));
}

}  // namespace
}  // namespace tincdt::io
