#include "io/terrain/wgs84.hpp"

#include <numbers>

namespace tincdt::io::terrain::wgs84 {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

}  // namespace

Point3 to_ecef(double longitude, double latitude, double height) {
  const double lambda = longitude * kRadiansPerDegree;
  const double phi = latitude * kRadiansPerDegree;
  const double sin_phi = std::sin(phi);
  const double cos_phi = std::cos(phi);
  // The radius of curvature in the prime vertical.
  const double n = kSemiMajorAxis / std::sqrt(1.0 - kEccentricitySquared * sin_phi * sin_phi);
  return {(n + height) * cos_phi * std::cos(lambda), (n + height) * cos_phi * std::sin(lambda),
          (n * (1.0 - kEccentricitySquared) + height) * sin_phi};
}

Point3 surface_normal(double longitude, double latitude) {
  const double lambda = longitude * kRadiansPerDegree;
  const double phi = latitude * kRadiansPerDegree;
  return {std::cos(phi) * std::cos(lambda), std::cos(phi) * std::sin(lambda), std::sin(phi)};
}

}  // namespace tincdt::io::terrain::wgs84
