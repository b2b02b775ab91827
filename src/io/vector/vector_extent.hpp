// The extent of a vector layer without reading its features, where the format keeps one (a
// shapefile's header, a GeoPackage's contents table): for planning tiled jobs.
#pragma once

#include <cstdint>
#include <string>

#include "core/types.hpp"

namespace tincdt::io {

struct VectorExtent {
  std::string layer;           // the layer's own name
  std::int64_t features = -1;  // when the driver knows it cheaply, else -1
  BBox bounds;                 // x, y; empty for an empty layer
  // How far a vertex may lie outside `bounds` and still belong to the layer: some formats keep
  // their extent in single precision or round it.
  double tolerance = 0;
};

// SPEC is "FILE" or "FILE:LAYER" as read_lines() takes it; LAYER wins when set. Throws
// InputError naming the file for an unreadable source or layer.
VectorExtent read_vector_extent(const std::string& spec, const std::string& layer);

}  // namespace tincdt::io
