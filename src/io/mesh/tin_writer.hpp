// TIN writers: OBJ, PLY (binary little-endian or ASCII), GeoJSON. All writes go to a temporary
// file in the output's folder that is renamed over the target only when complete.
#pragma once

#include <optional>
#include <string>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::io {

enum class TinFormat { obj, ply, geojson };

struct TinWriteOptions {
  std::optional<TinFormat> format;  // default: from the extension (.obj .ply .geojson/.json)
  bool ply_ascii = false;
  bool overwrite = false;      // replace an existing output
  Point3 offset{0, 0, 0};      // subtracted from every coordinate (recorded in the file)
  std::string crs_wkt;         // CRS of the vertices; empty = unknown
  std::string target_crs_wkt;  // GeoJSON only: reproject to this CRS (e.g. EPSG:4326)
};

struct TinWriteStats {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t bytes = 0;
};

// Format from the path's extension; throws OutputError for an unknown one.
TinFormat format_from_path(const std::string& path);

// Writes the real triangles of `tin` (ghosts skipped; constrained edges as PLY `edge` elements)
// and, for OBJ and PLY with a CRS, a .prj beside the output.
TinWriteStats write_tin(const std::string& path, const mesh::Triangulation& tin,
                        const TinWriteOptions& options);

}  // namespace tincdt::io
