// Coordinate reference systems, through GDAL's OSR. Everything else passes WKT strings around.
#pragma once

#include <string>

namespace tincdt::io {

// True when both are empty or OSR says they are the same CRS.
bool same_crs(const std::string& wkt_a, const std::string& wkt_b);
// A short name for logs and stats: "EPSG:2949" when identifiable, else the CRS name, else "".
std::string crs_label(const std::string& wkt);
// True for a CRS in longitude and latitude (angles), false for a projected or unreadable one.
bool is_geographic(const std::string& wkt);
// User input ("EPSG:4326", a WKT string, a PROJ string, a .prj path) to WKT; throws InputError.
std::string crs_from_user(const std::string& text);
// Why a terrain TIN cannot be built in the CRS WKT ("it is geocentric: ..."), "" when it can:
// a projected, geographic or engineering CRS, or a compound one whose horizontal part is one.
std::string crs_unusable_reason(const std::string& wkt);
// WKT1 in the ESRI flavour, as a .prj beside OBJ/PLY wants it.
std::string crs_to_prj(const std::string& wkt);

}  // namespace tincdt::io
