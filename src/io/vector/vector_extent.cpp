#include "io/vector/vector_extent.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "io/vector/ogr_source.hpp"

namespace tincdt::io {

VectorExtent read_vector_extent(const std::string& spec, const std::string& layer) {
  detail::OgrLayer source(spec, layer, 0);
  OGRLayer& l = source.get();
  VectorExtent e;
  e.layer = source.name();
  e.features = static_cast<std::int64_t>(l.GetFeatureCount(FALSE));
  OGREnvelope env;
  // Forced: a driver without a stored extent scans the layer (still cheaper than a tile job).
  if (l.GetExtent(&env, TRUE) != OGRERR_NONE) return e;  // an empty layer has none
  if (!std::isfinite(env.MinX) || !std::isfinite(env.MaxX) || !std::isfinite(env.MinY) ||
      !std::isfinite(env.MaxY) || env.MinX > env.MaxX || env.MinY > env.MaxY)
    throw InputError(source.file(), "layer " + e.layer, "the layer's extent is not a valid box");
  e.bounds = {env.MinX, env.MinY, env.MaxX, env.MaxY};
  const double magnitude = std::max(
      {std::fabs(env.MinX), std::fabs(env.MaxX), std::fabs(env.MinY), std::fabs(env.MaxY), 1.0});
  e.tolerance = magnitude * 1e-7;  // a single-precision extent is off by ~6e-8 relative at most
  return e;
}

}  // namespace tincdt::io
