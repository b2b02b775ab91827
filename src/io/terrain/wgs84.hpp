// The WGS 84 ellipsoid, and the earth-centred, earth-fixed (ECEF) frame Cesium's terrain
// headers and vertex normals are given in: metres, x towards longitude 0 on the equator, y
// towards 90 degrees east, z towards the north pole. Points are Point3 (x, y, z).
#pragma once

#include <cmath>

#include "core/types.hpp"

namespace tincdt::io::terrain::wgs84 {

inline constexpr double kSemiMajorAxis = 6378137.0;
inline constexpr double kFlattening = 1.0 / 298.257223563;
inline constexpr double kSemiMinorAxis = kSemiMajorAxis * (1.0 - kFlattening);
inline constexpr double kEccentricitySquared = kFlattening * (2.0 - kFlattening);

// The ECEF position of LONGITUDE and LATITUDE (degrees) at HEIGHT metres above the ellipsoid.
Point3 to_ecef(double longitude, double latitude, double height);

// The unit normal of the ellipsoid (the "up" of the geodetic frame) at LONGITUDE, LATITUDE.
Point3 surface_normal(double longitude, double latitude);

// ECEF P in the ellipsoid-scaled frame, where the ellipsoid is the unit sphere: each axis
// divided by the ellipsoid's radius along it. Cesium's horizon culling works there.
inline Point3 to_scaled_space(const Point3& p) {
  return {p.x / kSemiMajorAxis, p.y / kSemiMajorAxis, p.z / kSemiMinorAxis};
}

// Small vector algebra on Point3.
inline Point3 operator+(const Point3& a, const Point3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Point3 operator-(const Point3& a, const Point3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Point3 operator*(const Point3& a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline double dot(const Point3& a, const Point3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Point3 cross(const Point3& a, const Point3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Point3& a) {
  return std::sqrt(dot(a, a));
}

}  // namespace tincdt::io::terrain::wgs84
