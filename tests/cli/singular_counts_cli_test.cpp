// A count of one takes the singular noun in the summary and the read stage's messages.
#include <gtest/gtest.h>

#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

// One contour of two vertices inside the sample's extent, in the sample's CRS.
const char* const kOneSegment = R"({"type": "FeatureCollection",
 "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32632"}},
 "features": [{"type": "Feature", "properties": {"z": 1500}, "geometry": {"type": "LineString",
   "coordinates": [[600250, 5190350, 1500], [600300, 5190370, 1500]]}}]})";

TEST(SingularCountsCli, OneSegmentOneFeatureOneConstrainedEdge) {
  const std::string dir = scratch_dir("singular_counts_cli");
  spit(dir + "/sample.las", slurp(kSample));
  spit(dir + "/line.geojson", kOneSegment);
  // tincdt -v sample.las --contours line.geojson -o t.ply
  const ShellRun r = run_tincdt(dir, "-v sample.las --contours line.geojson -o t.ply");
  EXPECT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(has(r, "line.geojson: layer line, 1 feature, 1 segment, EPSG:32632")) << r;
  EXPECT_TRUE(has(r, "read 4,160 points from 1 file and 2 line vertices")) << r;
  EXPECT_TRUE(has(r, "constraints: 1 segment from 1 line feature\n")) << r;
  EXPECT_TRUE(has(r, ", 1 constrained edge\n")) << r;
}

}  // namespace
}  // namespace tincdt::test
