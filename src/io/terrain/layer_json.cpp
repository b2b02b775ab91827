#include "io/terrain/layer_json.hpp"

#include <cassert>

#include "core/json.hpp"
#include "io/output_file.hpp"

namespace tincdt::io::terrain {
namespace {

void write_ranges(json::Writer& w, const std::vector<TileRange>& ranges) {
  w.begin_array(json::Layout::spaced);
  for (const TileRange& range : ranges) write_tile_range(w, range);
  w.end_array();
}

}  // namespace

void write_tile_range(json::Writer& w, const TileRange& range) {
  w.begin_object()
      .field("startX", range.start_x)
      .field("startY", range.start_y)
      .field("endX", range.end_x)
      .field("endY", range.end_y)
      .end_object();
}

std::string layer_json(const TerrainLayer& layer) {
  assert(!layer.available.empty());
  const GeoRectangle& b = layer.bounds;
  json::Writer w(json::Numbers::shortest);
  w.begin_object()
      .field("tilejson", "2.1.0")
      .field("name", layer.name)
      .field("description", layer.description)
      .field("version", layer.version)
      .field("format", "quantized-mesh-1.0")
      .field("attribution", layer.attribution)
      .field("scheme", "tms")
      .key("tiles")
      .begin_array(json::Layout::spaced)
      .value("{z}/{x}/{y}.terrain?v={version}")
      .end_array()
      .field("projection", "EPSG:4326")
      .key("bounds")
      .begin_array(json::Layout::spaced)
      .value(b.west)
      .value(b.south)
      .value(b.east)
      .value(b.north)
      .end_array()
      .field("minzoom", layer.min_zoom)
      .field("maxzoom", static_cast<int>(layer.available.size()) - 1)
      .key("available")
      .begin_array();
  for (const auto& level : layer.available) write_ranges(w, level);
  w.end_array().key("extensions").array(layer.extensions, json::Layout::spaced);
  if (layer.metadata_availability) w.field("metadataAvailability", *layer.metadata_availability);
  w.end_object();
  return w.str() + "\n";
}

void write_layer_json(const std::string& path, const TerrainLayer& layer, bool overwrite) {
  OutputFile out(path, overwrite);
  out.write(layer_json(layer));
  out.commit();
}

}  // namespace tincdt::io::terrain
