// Private to src/io: CRS helpers the LAS and OGR readers need from crs.cpp, so that GDAL's OSR
// stays in one file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

class OGRSpatialReference;  // GDAL's (ogr_spatialref.h)

namespace tincdt::io::detail {

// The three GeoTIFF records of a LAS file (user id "LASF_Projection"): 34735 key directory
// (uint16), 34736 double parameters, 34737 ASCII parameters.
struct GeoTiffKeys {
  std::vector<std::uint16_t> directory;
  std::vector<double> doubles;
  std::string ascii;
  bool empty() const { return directory.empty(); }
};

// A CRS in WKT, and anything odd about it worth a warning.
struct CrsResult {
  std::string wkt;      // empty when the input describes no usable CRS
  std::string problem;  // why there is none, or what is odd about it; empty when all is well
};

// Checks that OSR can read WKT: returns it unchanged, or an empty wkt and GDAL's complaint.
CrsResult crs_check_wkt(const std::string& wkt);

// The horizontal CRS that GeoTIFF keys describe, decoded by GDAL's own GeoTIFF code (so
// user-defined projections, units and datums are honoured, not only EPSG codes). A vertical-only
// key set gives an empty wkt and a problem text.
CrsResult crs_from_geotiff(const GeoTiffKeys& keys);

// An OGR layer's CRS as WKT2 (WKT1 when OSR cannot); "" for none (SRS null), including a
// GeoPackage layer written without a CRS, which reports one of the spec's two placeholder entries
// (srs_id 0 "Undefined geographic SRS", -1 "Undefined Cartesian SRS"). GDAL's messages go to the
// caller's error handler.
std::string crs_of_layer(const OGRSpatialReference* srs);

// Whether the GeoJSON text at PATH names its CRS: a top-level "crs" member, wherever it stands.
bool geojson_names_crs(const std::string& path);

}  // namespace tincdt::io::detail
