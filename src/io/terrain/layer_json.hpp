// layer.json, the manifest at the root of a quantized-mesh terrain tileset: a TileJSON 2.1.0
// document that tells Cesium the format, the tile URL template, the tiling scheme, which tiles
// exist (per level, ranges of x and y counted from the south) and which extensions the tiles
// carry.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "io/terrain/geographic_tiling.hpp"

namespace tincdt::io::terrain {

struct TerrainLayer {
  std::string name = "tincdt";
  std::string description;
  std::string attribution;
  // Part of every tile URL ("?v={version}"): a new version makes caches fetch the tiles again.
  std::string version = "1.0.0";
  GeoRectangle bounds{-180, -90, 180, 90};  // degrees: the extent of the data
  int min_zoom = 0;
  // available[level]: the tiles present at that level, from level 0; max_zoom is its last.
  std::vector<std::vector<TileRange>> available;
  // The extensions the tiles carry: "octvertexnormals", "metadata".
  std::vector<std::string> extensions;
  // Levels between which tiles list the tiles below them (the metadata extension); needed with
  // "metadata": CesiumJS, reading the extension (its default), fails on the first tile when
  // layer.json has no metadataAvailability, and with it takes level 0's two roots as present and
  // every other tile from the metadata, ignoring "available".
  std::optional<int> metadata_availability;
};

// The layer.json text of LAYER (which must list at least level 0 as available).
std::string layer_json(const TerrainLayer& layer);

// One range of available tiles, {"startX":..,"startY":..,"endX":..,"endY":..}, as layer.json and
// the tiles' metadata extension write it.
void write_tile_range(json::Writer& w, const TileRange& range);

// Writes layer_json(LAYER) to PATH safely (output_file.hpp). Throws OutputError if PATH exists
// and !OVERWRITE, or cannot be written.
void write_layer_json(const std::string& path, const TerrainLayer& layer, bool overwrite);

}  // namespace tincdt::io::terrain
