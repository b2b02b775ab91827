// Whether a GeoJSON file names its CRS: a top-level "crs" member wherever it stands, not a "crs"
// key inside a feature's properties or a string that only spells it.
#include <gtest/gtest.h>

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>

#include "io/crs_detail.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

const char* const kType = R"("type": "FeatureCollection")";
const char* const kCrs =
    R"("crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32632"}})";
const char* const kFeatures =
    R"("features": [{"type": "Feature", "properties": {"crs": "a \"crs\": value"},)"
    R"( "geometry": {"type": "Point", "coordinates": [1, 2, 3]}}])";

// A JSON object of MEMBERS, each "name": value.
std::string object(std::initializer_list<std::string_view> members) {
  std::string text = "{";
  for (const std::string_view member : members)
    text.append(text.size() > 1 ? ", " : "").append(member);
  return text.append("}");
}

bool names_crs(const std::string& text) {
  static int n = 0;
  fs::path path = fs::path(test::scratch_dir("geojson_crs")) / std::to_string(++n);
  path += ".geojson";
  test::spit(path, text);
  return detail::geojson_names_crs(path.string());
}

TEST(GeoJsonCrs, ATopLevelCrsMemberBeforeOrAfterTheFeatures) {
  EXPECT_TRUE(names_crs(object({kType, kCrs, kFeatures})));
  EXPECT_TRUE(names_crs(object({kType, kFeatures, kCrs})));
}

TEST(GeoJsonCrs, ACrsKeyInsideAFeatureOrAStringIsNotTheFilesCrs) {
  EXPECT_FALSE(names_crs(object({kType, kFeatures})));
  EXPECT_FALSE(names_crs(R"({"type": "FeatureCollection", "name": "crs", "features": []})"));
  EXPECT_FALSE(names_crs(R"([1, "crs", {"x": 2}])"));
  EXPECT_FALSE(names_crs(R"({"type": "Feature", "properties": {"x": "\\"}, "crss": 1})"));
}

TEST(GeoJsonCrs, AMemberSplitAcrossReadsIsFound) {
  // Past the reader's 64 KiB buffer: a long first member puts "crs" across the boundary.
  for (const std::size_t pad : {65520u, 65530u, 65534u, 65536u}) {
    std::string name = R"("name": ")";
    name.append(pad - name.size(), 'a').push_back('"');
    EXPECT_TRUE(names_crs(object({name, kCrs}))) << pad;
  }
}

}  // namespace
}  // namespace tincdt::io
