// The TIN's coordinates as a web globe wants them: longitude and latitude on WGS 84 (degrees,
// through GDAL/PROJ) and heights in metres (from the CRS's vertical unit).
#pragma once

#include <span>
#include <string>

#include "core/types.hpp"

namespace tincdt::io::terrain {

// How the heights were read.
struct HeightUnits {
  std::string unit;          // the heights' unit as the CRS names it: "metre", "US survey foot"
  double to_metres = 1;      // metres per unit
  std::string vertical;      // the vertical CRS's name; "" when the CRS has none
  bool ellipsoidal = false;  // heights above the ellipsoid (a geographic 3D CRS)
};

// The heights' unit of the CRS WKT: its vertical CRS's when it has one, else its linear unit
// for a projected CRS, else metres.
HeightUnits height_units(const std::string& wkt);

// Transforms POINTS in place from the CRS WKT to (longitude, latitude) in degrees on WGS 84
// with the heights in metres. Throws InputError naming WHAT (the inputs) when WKT is empty or
// PROJ cannot transform a point.
HeightUnits to_lon_lat_metres(const std::string& wkt, std::span<Point3> points,
                              const std::string& what);

}  // namespace tincdt::io::terrain
