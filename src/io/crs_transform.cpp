#include "io/crs_transform.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "io/crs.hpp"
#include "io/gdal_support.hpp"

namespace tincdt::io {
namespace {

// Points per call to PROJ, and the fewest a thread of its own is worth.
constexpr std::size_t kBlock = 4096;
constexpr std::size_t kPointsPerThread = 1 << 16;

struct Height {
  double to_metres = 1;
  std::string unit = "metre";
  std::string vertical;  // the vertical CRS's name, "" when there is none
};

Height height_of(const OGRSpatialReference& srs) {
  Height h;
  const char* unit = nullptr;  // owned by SRS
  if (srs.IsCompound() || srs.IsVertical()) {
    h.to_metres = srs.GetTargetLinearUnits("VERT_CS", &unit);
    const char* name = srs.GetAttrValue("VERT_CS");
    if (name == nullptr) name = srs.GetAttrValue("VERTCRS");
    h.vertical = name != nullptr ? name : "a vertical CRS";
  } else if (srs.IsProjected() || srs.IsLocal()) {
    h.to_metres = srs.GetLinearUnits(&unit);
  }
  if (!(h.to_metres > 0) || !std::isfinite(h.to_metres)) {
    h.to_metres = 1;
    unit = nullptr;
  }
  if (unit != nullptr) h.unit = unit;
  return h;
}

// The CRS of WKT in tincdt's axis order, its vertical part dropped: heights are not PROJ's.
OGRSpatialReference horizontal_srs(const std::string& wkt, const std::string& what,
                                   const char* role) {
  OGRSpatialReference srs = detail::gis_order_srs();
  if (!detail::import_wkt(srs, wkt))
    throw InputError(what, "",
                     std::string("cannot read the ") + role +
                         " CRS: " + detail::last_gdal_message("invalid WKT"));
  return srs;
}

std::string label_of(const std::string& wkt) {
  const std::string label = crs_label(wkt);
  return label.empty() ? std::string("an unnamed CRS") : label;
}

}  // namespace

struct CrsTransform::Impl {
  detail::OgrTransform prototype;
};

CrsTransform::CrsTransform(const std::string& from_wkt, const std::string& to_wkt,
                           const std::string& what)
    : impl_(std::make_unique<Impl>()) {
  const detail::GdalQuiet quiet;
  OGRSpatialReference from = horizontal_srs(from_wkt, what, "source");
  OGRSpatialReference to = horizontal_srs(to_wkt, what, "target");
  const Height from_height = height_of(from), to_height = height_of(to);
  from_unit_ = from_height.unit;
  to_unit_ = to_height.unit;
  // The same unit given with fewer digits (0.3048006096 for 1200/3937) is the same unit.
  const double ratio = from_height.to_metres / to_height.to_metres;
  if (std::fabs(ratio - 1) > 1e-9) z_factor_ = ratio;
  if (!from_height.vertical.empty() && !to_height.vertical.empty() &&
      from_height.vertical != to_height.vertical)
    vertical_mismatch_ = from_height.vertical + " to " + to_height.vertical;
  if (from.IsCompound()) from.StripVertical();
  if (to.IsCompound()) to.StripVertical();
  CPLErrorReset();
  impl_->prototype.reset(OGRCreateCoordinateTransformation(&from, &to));
  if (!impl_->prototype)
    throw InputError(what, "",
                     "no transformation from " + label_of(from_wkt) + " to " + label_of(to_wkt) +
                         ": " + detail::last_gdal_message("PROJ gives none"));
}

CrsTransform::~CrsTransform() = default;

std::optional<std::size_t> CrsTransform::apply(std::span<Point3> points, unsigned threads) const {
  const std::size_t n = points.size();
  const std::size_t workers =
      std::clamp<std::size_t>(n / kPointsPerThread, 1, thread_count(threads));
  std::vector<detail::OgrTransform> transforms;
  for (std::size_t w = 0; w < workers; ++w) {
    transforms.emplace_back(impl_->prototype->Clone());
    if (!transforms.back()) throw InputError("", "", "cannot copy a CRS transformation");
  }
  // Blocks are taken in order; a block after a known failure is skipped, one before it never is,
  // so that the failure returned is the first whatever the threads do.
  std::atomic<std::size_t> next_block{0};
  std::atomic<std::size_t> first_failure{n};
  const double z_factor = z_factor_;
  run_workers(workers, [&](std::size_t w) {
    const detail::GdalQuiet quiet;  // GDAL's error handlers are per thread
    OGRCoordinateTransformation& ct = *transforms[w];
    std::vector<double> x(kBlock), y(kBlock), z(kBlock);
    std::vector<int> ok(kBlock);
    for (;;) {
      const std::size_t first = next_block.fetch_add(1) * kBlock;
      if (first >= n || first > first_failure.load()) return;
      const std::size_t count = std::min(kBlock, n - first);
      for (std::size_t i = 0; i < count; ++i) {
        const Point3& p = points[first + i];
        x[i] = p.x;
        y[i] = p.y;
        // As ogr2ogr passes it; PROJ leaves it as it is between horizontal CRSs. A 2D
        // geometry's NaN would make some transformations' x and y NaN.
        z[i] = std::isfinite(p.z) ? p.z : 0.0;
      }
      std::fill(ok.begin(), ok.begin() + static_cast<std::ptrdiff_t>(count), 0);
      ct.Transform(static_cast<int>(count), x.data(), y.data(), z.data(), nullptr, ok.data());
      for (std::size_t i = 0; i < count; ++i) {
        if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i])) {
          std::size_t known = first_failure.load();
          while (first + i < known && !first_failure.compare_exchange_weak(known, first + i)) {
          }
          return;
        }
        Point3& p = points[first + i];
        p.x = x[i];
        p.y = y[i];
        if (z_factor != 1) p.z *= z_factor;
      }
    }
  });
  const std::size_t failure = first_failure.load();
  if (failure < n) return failure;
  return std::nullopt;
}

}  // namespace tincdt::io
