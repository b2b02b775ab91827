// Coordinates from one CRS into another by PROJ (GDAL's OGRCoordinateTransformation), in tincdt's
// axis order (x = easting or longitude). x and y go through PROJ's best transformation between
// the two horizontal CRSs. z is never shifted between datums (between horizontal CRSs PROJ leaves
// it as it is, as ogr2ogr does) but converted between the CRSs' height units: a vertical CRS's
// unit, else a projected or engineering CRS's linear unit, else metres.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/types.hpp"

namespace tincdt::io {

class CrsTransform {
 public:
  // Throws InputError naming WHAT when either CRS cannot be read or PROJ has no transformation
  // from FROM_WKT to TO_WKT.
  CrsTransform(const std::string& from_wkt, const std::string& to_wkt, const std::string& what);
  ~CrsTransform();
  CrsTransform(const CrsTransform&) = delete;
  CrsTransform& operator=(const CrsTransform&) = delete;

  // z is multiplied by this: one height unit of the source in the target's (exactly 1 when they
  // are the same unit).
  double z_factor() const { return z_factor_; }
  // The height units' names, "metre", "US survey foot".
  const std::string& from_height_unit() const { return from_unit_; }
  const std::string& to_height_unit() const { return to_unit_; }
  // "NAVD88 height to CGVD2013(CGG2013) height" when both CRSs have a vertical part and they
  // differ (the heights are then converted in unit only, not between the vertical datums); ""
  // otherwise.
  const std::string& vertical_mismatch() const { return vertical_mismatch_; }

  // Transforms POINTS in place on THREADS threads (0 = every core), each with a transformation
  // of its own (one is not safe to share between threads). Returns the index of the first point
  // PROJ cannot transform, or that it takes to a non-finite place (POINTS are then partly
  // transformed); nullopt when every one was.
  std::optional<std::size_t> apply(std::span<Point3> points, unsigned threads) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double z_factor_ = 1;
  std::string from_unit_, to_unit_, vertical_mismatch_;
};

}  // namespace tincdt::io
