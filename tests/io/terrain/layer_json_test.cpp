// layer.json: valid JSON with every field Cesium reads for a quantized-mesh layer, and written
// safely to a file.
#include "io/terrain/layer_json.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/json.hpp"
#include "support/files.hpp"

namespace tincdt::io::terrain {
namespace {

TerrainLayer sample_layer() {
  TerrainLayer layer;
  layer.name = "Zurich";
  layer.version = "2.0.1";
  layer.bounds = {8.4, 47.3, 8.6, 47.45};
  layer.available = {{{0, 0, 1, 0}}, {{2, 1, 2, 1}}, {{4, 3, 5, 3}, {7, 2, 7, 2}}};
  layer.extensions = {"octvertexnormals", "metadata"};
  return layer;
}

std::string text_of(const json::Value& doc, const char* key) {
  const json::Value* v = doc.find(key);
  return v != nullptr && v->is(json::Value::Kind::string) ? v->string() : "<missing>";
}

TEST(LayerJson, HasEveryFieldCesiumReads) {
  const TerrainLayer layer = sample_layer();
  const json::Value doc = json::parse(layer_json(layer));
  EXPECT_EQ(text_of(doc, "tilejson"), "2.1.0");
  EXPECT_EQ(text_of(doc, "name"), "Zurich");
  EXPECT_EQ(text_of(doc, "format"), "quantized-mesh-1.0");
  EXPECT_EQ(text_of(doc, "version"), "2.0.1");
  EXPECT_EQ(text_of(doc, "scheme"), "tms");
  EXPECT_EQ(text_of(doc, "projection"), "EPSG:4326");
  const json::Value* tiles = doc.find("tiles");
  ASSERT_NE(tiles, nullptr);
  ASSERT_EQ(tiles->items().size(), 1u);
  EXPECT_EQ(tiles->items()[0].string(), "{z}/{x}/{y}.terrain?v={version}");
  const json::Value* bounds = doc.find("bounds");
  ASSERT_NE(bounds, nullptr);
  ASSERT_EQ(bounds->items().size(), 4u);
  EXPECT_EQ(bounds->items()[0].number(), 8.4);
  EXPECT_EQ(bounds->items()[1].number(), 47.3);
  EXPECT_EQ(bounds->items()[2].number(), 8.6);
  EXPECT_EQ(bounds->items()[3].number(), 47.45);
  EXPECT_EQ(doc.find("minzoom")->number(), 0);
  EXPECT_EQ(doc.find("maxzoom")->number(), 2);
  const json::Value* extensions = doc.find("extensions");
  ASSERT_NE(extensions, nullptr);
  ASSERT_EQ(extensions->items().size(), 2u);
  EXPECT_EQ(extensions->items()[0].string(), "octvertexnormals");
  EXPECT_EQ(extensions->items()[1].string(), "metadata");
  EXPECT_EQ(doc.find("metadataAvailability"), nullptr);
}

TEST(LayerJson, AvailableListsEveryLevelsRanges) {
  const TerrainLayer layer = sample_layer();
  const json::Value doc = json::parse(layer_json(layer));
  const json::Value* available = doc.find("available");
  ASSERT_NE(available, nullptr);
  ASSERT_EQ(available->items().size(), layer.available.size());
  for (std::size_t level = 0; level < layer.available.size(); ++level) {
    const auto& ranges = available->items()[level].items();
    ASSERT_EQ(ranges.size(), layer.available[level].size()) << level;
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const TileRange& want = layer.available[level][i];
      EXPECT_EQ(ranges[i].keys(), (std::vector<std::string>{"startX", "startY", "endX", "endY"}));
      EXPECT_EQ(ranges[i].find("startX")->number(), want.start_x);
      EXPECT_EQ(ranges[i].find("startY")->number(), want.start_y);
      EXPECT_EQ(ranges[i].find("endX")->number(), want.end_x);
      EXPECT_EQ(ranges[i].find("endY")->number(), want.end_y);
    }
  }
}

TEST(LayerJson, MetadataAvailabilityWhenSet) {
  TerrainLayer layer = sample_layer();
  layer.metadata_availability = 10;
  const json::Value doc = json::parse(layer_json(layer));
  ASSERT_NE(doc.find("metadataAvailability"), nullptr);
  EXPECT_EQ(doc.find("metadataAvailability")->number(), 10);
}

TEST(LayerJson, WritesTheFileSafely) {
  const std::string dir = test::scratch_dir("layer_json");
  const std::string path = dir + "/layer.json";
  write_layer_json(path, sample_layer(), false);
  EXPECT_EQ(test::slurp(path), layer_json(sample_layer()));
  EXPECT_THROW(write_layer_json(path, sample_layer(), false), OutputError);
  TerrainLayer other = sample_layer();
  other.version = "3";
  write_layer_json(path, other, true);
  EXPECT_EQ(text_of(json::parse(test::slurp(path)), "version"), "3");
}

}  // namespace
}  // namespace tincdt::io::terrain
