// Both GeoJSON writers (TIN and constraint lines) refuse a vertex whose height or position is
// not finite, naming the vertex, and write shifted positions with the heights of the TIN.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/error.hpp"
#include "io/mesh/constraint_writer.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/files.hpp"
#include "support/meshes.hpp"

namespace tincdt::io {
namespace {

TEST(GeoJsonBadVertex, ConstraintLinesNameTheVertexWithABadHeight) {
  const std::string dir = test::scratch_dir("geojson_bad_vertex");
  mesh::Triangulation tin = test::unit_square(true);
  tin.set_z(2, std::numeric_limits<double>::quiet_NaN());
  TinWriteOptions options;
  options.overwrite = true;
  try {
    write_constraint_lines(dir + "/lines.geojson", tin, {{0, 1, 0}, {3, 2, 0}}, {{"in.shp", 7}},
                           options);
    ADD_FAILURE() << "no error";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.where(), "vertex 2") << e.what();
  }
  try {
    write_tin(dir + "/tin.geojson", tin, options);
    ADD_FAILURE() << "no error";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.where(), "vertex 2") << e.what();
  }
}

TEST(GeoJsonBadVertex, ConstraintLinesAreShiftedByTheOffset) {
  const std::string dir = test::scratch_dir("geojson_bad_vertex");
  const mesh::Triangulation tin = test::unit_square(true);
  TinWriteOptions options;
  options.offset = {500000, 4000000, 100};
  write_constraint_lines(dir + "/lines.geojson", tin, {{0, 2, 0}}, {{"in.shp", -3}}, options);
  const std::string text = test::slurp(dir + "/lines.geojson");
  EXPECT_NE(text.find("\"tincdt_offset\": [500000,4000000,100],\n"), std::string::npos) << text;
  EXPECT_NE(text.find("{\"type\":\"Feature\",\"properties\":{\"source_file\":\"in.shp\","
                      "\"source_fid\":-3,\"z_start\":123.456789012345,"
                      "\"z_end\":0.30000000000000004},\"geometry\":{\"type\":\"LineString\","
                      "\"coordinates\":[[0.12345678900601342,0.9876543208956718,23.456789012345],"
                      "[1.1234567890060134,1.9876543208956718,-99.7]]}}\n]\n}\n"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace tincdt::io
