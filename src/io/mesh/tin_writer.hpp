// TIN writers: OBJ, PLY (binary little-endian or ASCII), GeoJSON, LandXML 1.2, GeoPackage,
// binary STL and glTF 2.0 binary (GLB). All writes go to a temporary file in the output's folder
// that is renamed over the target only when complete.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/progress.hpp"
#include "core/types.hpp"
#include "io/output_file.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::io {

enum class TinFormat { obj, ply, geojson, landxml, gpkg, stl, glb };

// One TIN format: every place that names the formats (the writers, the command line's -f and
// help, the log) reads them from tin_formats().
struct TinFormatInfo {
  TinFormat format;
  std::string_view name;   // "obj", "geojson": in reports, messages and the command line
  std::string_view title;  // "OBJ", "GeoJSON": for people
  std::span<const std::string_view> extensions;  // ".geojson", ".json": the first is the usual
};

// Every format, in the order the command line lists them.
std::span<const TinFormatInfo> tin_formats();
// Their names, in the same order.
std::span<const std::string_view> tin_format_names();
const TinFormatInfo& format_info(TinFormat format);
// The format named NAME (any case), if any.
std::optional<TinFormat> format_from_name(std::string_view name);
// The extensions for a message or a help text: ".obj, .ply, .geojson/.json, ... or .stl".
std::string format_extensions_text();

struct TinWriteOptions {
  // Default: from the extension (.obj .ply .geojson/.json .xml/.landxml .gpkg .stl .glb).
  std::optional<TinFormat> format;
  bool ply_ascii = false;
  // PLY: when not empty, a "comment trimmed TEXT" line, for a tile whose border is not all the
  // whole TIN's hull and seams (TEXT: which tiles; tincdt merge reads it).
  std::string ply_trimmed;
  bool ogr_tin = false;    // GeoPackage: TIN Z features instead of POLYGON Z
  bool overwrite = false;  // replace an existing output
  Point3 offset{0, 0, 0};  // subtracted from every coordinate (recorded in the file);
                           // refused by LandXML and GeoPackage (format_takes_offset)
  std::string crs_wkt;     // CRS of the vertices; empty = unknown
  // Threads that format the records of OBJ, PLY, STL and GeoJSON (0 = one per core); the bytes
  // written are the same for any count.
  unsigned threads = 1;
  // Stage "write", over the vertices and triangles written; a request to stop is honoured
  // within the file (Cancelled), which is then removed.
  const ProgressFn* progress = nullptr;
};

// An output path whose extension names no format: the caller may say how to name one.
class UnknownFormatError : public OutputError {
  using OutputError::OutputError;
};

struct TinWriteStats {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t bytes = 0;
};

// Format from the path's extension; throws UnknownFormatError for an unknown one.
TinFormat format_from_path(const std::string& path);
// "obj", "ply", "geojson", "landxml", "gpkg", "stl" or "glb": the name in reports and messages.
std::string_view format_name(TinFormat format);

// False for the formats that keep georeferenced coordinates and have no place for an offset
// (LandXML, GeoPackage): write_tin() refuses a non-zero offset for them.
bool format_takes_offset(TinFormat format);

// STL stores float32: "" when the kept vertices, shifted by OFFSET, round to floats within 1 mm
// (1e-3 units), else a warning for the log that names the rounding (the caller says how to shift
// the coordinates).
std::string stl_precision_warning(const mesh::Triangulation& tin, const Point3& offset);

// Writes the real triangles of `tin` (ghosts skipped; constrained edges as PLY `edge` elements,
// LandXML breaklines and glTF lines) and, for OBJ, PLY and STL with a CRS, a .prj beside the
// output.
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
