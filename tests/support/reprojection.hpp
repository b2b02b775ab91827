// Writer options shared by the tests that write the test meshes reprojected.
#pragma once

#include "io/crs.hpp"
#include "io/mesh/tin_writer.hpp"

namespace tincdt::test {

// Options that write the meshes of meshes.hpp (at UTM zone 33N magnitude) in WGS 84.
inline io::TinWriteOptions utm33_to_wgs84() {
  io::TinWriteOptions o;
  o.crs_wkt = io::crs_from_user("EPSG:32633");
  o.target_crs_wkt = io::crs_from_user("EPSG:4326");
  return o;
}

}  // namespace tincdt::test
