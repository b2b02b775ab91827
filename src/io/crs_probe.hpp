// The CRS of an input before it is read: from a LAS / LAZ file's header and VLRs, or a vector
// source's layer, so that a CRS the job cannot use is refused before any work.
#pragma once

#include <optional>
#include <string>

namespace tincdt::io {

// The CRS of point file PATH as WKT, "" when it has none; nullopt when only reading it tells (XYZ
// text, PLY, standard input, anything not LAS). Throws InputError as the reader would for a
// malformed header or VLR.
std::optional<std::string> point_file_crs(const std::string& path);

// The CRS of a vector source as WKT: the one it names (as the readers give it), or the format's
// default when it names none (GeoJSON: WGS 84, by RFC 7946), which many such files contradict.
struct VectorCrs {
  std::string wkt;
  bool implied = false;
};

// The CRS of the vector source SPEC ("FILE" or "FILE:LAYER"; LAYER wins when set). Throws
// InputError as the line and polygon readers would for a source they cannot open or a layer they
// cannot choose.
VectorCrs vector_source_crs(const std::string& spec, const std::string& layer);

}  // namespace tincdt::io
