// TIN writers: OBJ, PLY (binary little-endian or ASCII), GeoJSON. All writes go to a temporary
// file in the output's folder that is renamed over the target only when complete.
#pragma once

#include <optional>
#include <string>

#include "core/types.hpp"
#include "io/output_file.hpp"
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

// The pieces of write_tin(PATH, ...) for a caller that commits several files together
// (OutputSet): the mesh alone into OUT (format from options.format, else OUT's path), not
// committed; and the .prj text of CRS_WKT (ESRI WKT1), throwing OutputError naming OUT when the
// CRS has no such form.
TinWriteStats write_tin(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options);
void write_prj(OutputFile& out, const std::string& crs_wkt);
// "tin.obj" -> "tin.prj"; a path without extension gets ".prj" appended.
std::string prj_path(const std::string& path);
// Whether a TIN in FORMAT with CRS_WKT gets a .prj beside it: OBJ and PLY with a CRS.
bool wants_prj(TinFormat format, const std::string& crs_wkt);

}  // namespace tincdt::io
