#include "io/terrain/lon_lat.hpp"

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/gdal_support.hpp"

namespace tincdt::io::terrain {
namespace {

// Points go through PROJ in blocks of this many.
constexpr std::size_t kBlock = 4096;

OGRSpatialReference srs_of(const std::string& wkt, const std::string& what) {
  OGRSpatialReference srs;
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  if (srs.importFromWkt(wkt.c_str()) != OGRERR_NONE)
    throw InputError(what, "", "the CRS cannot be read: " + detail::one_line(wkt).substr(0, 80));
  return srs;
}

}  // namespace

HeightUnits height_units(const std::string& wkt) {
  HeightUnits units;
  units.unit = "metre";
  if (wkt.empty()) return units;
  OGRSpatialReference srs;
  if (srs.importFromWkt(wkt.c_str()) != OGRERR_NONE) return units;
  const char* name = nullptr;
  if (srs.IsCompound() || srs.IsVertical()) {
    units.to_metres = srs.GetTargetLinearUnits("VERT_CS", &name);
    const char* vertical = srs.GetAttrValue("VERT_CS");
    if (vertical == nullptr) vertical = srs.GetAttrValue("VERTCRS");
    units.vertical = vertical != nullptr ? vertical : "a vertical CRS";
  } else if (srs.IsProjected()) {
    units.to_metres = srs.GetLinearUnits(&name);
  } else if (srs.IsGeographic()) {
    units.ellipsoidal = srs.GetAxesCount() == 3;
  }
  if (name != nullptr) units.unit = name;
  if (!(units.to_metres > 0) || !std::isfinite(units.to_metres)) units.to_metres = 1;
  return units;
}

HeightUnits to_lon_lat_metres(const std::string& wkt, std::span<Point3> points,
                              const std::string& what) {
  if (wkt.empty())
    throw InputError(what, "",
                     "web terrain needs the data's CRS to place it on the globe, and the input "
                     "has none",
                     Remedy::assign_crs);
  detail::register_gdal_drivers();
  OGRSpatialReference source = srs_of(wkt, what);
  if (source.IsCompound()) source.StripVertical();
  OGRSpatialReference target;
  target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  target.importFromEPSG(4326);
  detail::OgrTransform transform(OGRCreateCoordinateTransformation(&source, &target));
  if (!transform)
    throw InputError(
        what, "",
        "no transformation from the CRS to WGS 84: " + detail::last_gdal_message("PROJ gave none"));
  const HeightUnits units = height_units(wkt);
  std::vector<double> x, y;
  for (std::size_t first = 0; first < points.size(); first += kBlock) {
    const std::size_t n = std::min(kBlock, points.size() - first);
    x.resize(n);
    y.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = points[first + i].x;
      y[i] = points[first + i].y;
    }
    std::vector<int> ok(n, 0);
    transform->Transform(static_cast<int>(n), x.data(), y.data(), nullptr, ok.data());
    for (std::size_t i = 0; i < n; ++i) {
      Point3& p = points[first + i];
      if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]))
        throw InputError(what, "point " + number_text(p.x) + " " + number_text(p.y),
                         "cannot be transformed to longitude/latitude on WGS 84");
      p = {x[i], y[i], p.z * units.to_metres};
    }
  }
  return units;
}

}  // namespace tincdt::io::terrain
