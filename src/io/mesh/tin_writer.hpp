// TIN writers: OBJ, PLY (binary little-endian or ASCII), GeoJSON, LandXML 1.2, GeoPackage and
// binary STL. All writes go to a temporary file in the output's folder that is renamed over the
// target only when complete.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "io/output_file.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::io {

enum class TinFormat { obj, ply, geojson, landxml, gpkg, stl };

struct TinWriteOptions {
  // Default: from the extension (.obj .ply .geojson/.json .xml/.landxml .gpkg .stl).
  std::optional<TinFormat> format;
  bool ply_ascii = false;
  bool ogr_tin = false;        // GeoPackage: TIN Z features instead of POLYGON Z
  bool overwrite = false;      // replace an existing output
  Point3 offset{0, 0, 0};      // subtracted from every coordinate (recorded in the file);
                               // refused by LandXML and GeoPackage (format_takes_offset)
  std::string crs_wkt;         // CRS of the vertices; empty = unknown
  std::string target_crs_wkt;  // GeoJSON only: reproject to this CRS (e.g. EPSG:4326)
  // Stage "write", over the vertices and triangles written; a request to stop is honoured
  // within the file (Cancelled), which is then removed.
  const ProgressFn* progress = nullptr;
};

struct TinWriteStats {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t bytes = 0;
};

// Format from the path's extension; throws OutputError for an unknown one.
TinFormat format_from_path(const std::string& path);
// "obj", "ply", "geojson", "landxml", "gpkg" or "stl": the name in reports and messages.
std::string_view format_name(TinFormat format);

// False for the formats that keep georeferenced coordinates and have no place for an offset
// (LandXML, GeoPackage): write_tin() refuses a non-zero offset for them.
bool format_takes_offset(TinFormat format);

// STL stores float32: "" when the kept vertices, shifted by OFFSET, round to floats within 1 mm
// (1e-3 units), else a warning for the log that names the rounding and suggests --offset.
std::string stl_precision_warning(const mesh::Triangulation& tin, const Point3& offset);

// Writes the real triangles of `tin` (ghosts skipped; constrained edges as PLY `edge` elements
// and LandXML breaklines) and, for OBJ, PLY and STL with a CRS, a .prj beside the output.
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
// Whether a TIN in FORMAT with CRS_WKT gets a .prj beside it: OBJ, PLY and STL with a CRS.
bool wants_prj(TinFormat format, const std::string& crs_wkt);

}  // namespace tincdt::io
