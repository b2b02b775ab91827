// Points transformed by PROJ through GDAL, independently of tincdt: the reference the
// reprojection tests compare tincdt's coordinates with.
#pragma once

#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <cmath>
#include <vector>

namespace tincdt::test {

// POINTS (x, y) from EPSG:FROM to EPSG:TO, in x = easting / longitude order.
inline std::vector<std::array<double, 2>> proj_transform(
    int from, int to, std::vector<std::array<double, 2>> points) {
  OGRSpatialReference a, b;
  a.importFromEPSG(from);
  b.importFromEPSG(to);
  a.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  b.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformation* ct = OGRCreateCoordinateTransformation(&a, &b);
  EXPECT_NE(ct, nullptr);
  if (ct == nullptr) return {};
  for (auto& p : points) EXPECT_TRUE(ct->Transform(1, &p[0], &p[1])) << p[0] << " " << p[1];
  OGRCoordinateTransformation::DestroyCT(ct);
  return points;
}

// P from EPSG:FROM to EPSG:TO (NaN when PROJ cannot).
inline std::array<double, 2> proj_transform(int from, int to, std::array<double, 2> p) {
  const auto out = proj_transform(from, to, std::vector<std::array<double, 2>>{p});
  return out.empty() ? std::array<double, 2>{NAN, NAN} : out.front();
}

}  // namespace tincdt::test
