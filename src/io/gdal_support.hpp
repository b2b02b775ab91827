// GDAL in one place. Every GDAL use in src/io goes through GDAL's C++ API (GDALDataset, OGRLayer,
// OGRFeature, OGRGeometry, OGRSpatialReference) and the few helpers below, so that the drivers
// are registered once, GDAL never prints on its own, and its messages reach the user as one line
// inside a tincdt error. Only CPL (errors, VSI files) is C: it has no C++ API.
#pragma once

#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_feature.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/progress.hpp"

namespace tincdt::io::detail {

// Owning handles: a dataset is closed (GDALClose), a feature, geometry or transformation
// deleted. A CRS is a value: OGRSpatialReference.
using GdalDataset = GDALDatasetUniquePtr;
using OgrFeature = OGRFeatureUniquePtr;
using OgrGeometry = OGRGeometryUniquePtr;
struct OgrTransformDeleter {
  void operator()(OGRCoordinateTransformation* ct) const {
    OGRCoordinateTransformation::DestroyCT(ct);
  }
};
using OgrTransform = std::unique_ptr<OGRCoordinateTransformation, OgrTransformDeleter>;

// Registers every GDAL driver, once per process; call before opening or creating a dataset.
void register_gdal_drivers();

// The text on one line: newlines and runs of blanks become one space. GDAL's messages (the
// shapefile driver's .shx warning spans two lines) and WKT are multi-line.
std::string one_line(std::string_view text);

// GDAL's last error message on one line, or FALLBACK when it said nothing.
std::string last_gdal_message(const char* fallback);

// An empty CRS in traditional GIS axis order (x = easting / longitude), tincdt's order.
OGRSpatialReference gis_order_srs();
// SRS := the CRS in WKT (1 or 2); false when OSR refuses it.
bool import_wkt(OGRSpatialReference& srs, const std::string& wkt);

// For the scope: GDAL prints nothing, and its last message starts empty (last_gdal_message()
// then tells only what happened inside). Its warnings are kept (the first 20, each on one line)
// for the caller to log, and its first failure is remembered, so that a driver that gives up in
// the middle of a layer is not mistaken for the layer's end.
class GdalMessages {
 public:
  GdalMessages();
  GdalMessages(const GdalMessages&) = delete;
  GdalMessages& operator=(const GdalMessages&) = delete;
  ~GdalMessages();

  void reset_failure() {
    failed_ = false;
    failure_.clear();
  }
  bool failed() const { return failed_; }
  const std::string& failure() const { return failure_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  static void CPL_STDCALL handle(CPLErr level, CPLErrorNum number, const char* msg);

  bool failed_ = false;
  std::string failure_;
  std::vector<std::string> warnings_;
};

// GDAL's progress callback over ours (CreateCopy's pfnProgress and pProgressData), reporting to
// ours as STAGE. Remembers a request to stop, which GDAL reports as a failure like any other: the
// caller asks cancelled() before it looks at GDAL's result. Without a callback of ours, GDAL gets
// its dummy.
class GdalProgress {
 public:
  GdalProgress(const ProgressFn* fn, const char* stage)
      : fn_(fn != nullptr && *fn ? fn : nullptr), stage_(stage) {}
  GdalProgress(const GdalProgress&) = delete;
  GdalProgress& operator=(const GdalProgress&) = delete;

  GDALProgressFunc function() const { return fn_ ? report : GDALDummyProgress; }
  void* data() { return fn_ ? this : nullptr; }
  bool cancelled() const { return cancelled_; }

 private:
  static int CPL_STDCALL report(double fraction, const char* message, void* data);

  const ProgressFn* fn_;
  const char* stage_;
  bool cancelled_ = false;
};

// For a scope that wants GDAL silent and its last message fresh, and no more.
using GdalQuiet = GdalMessages;

}  // namespace tincdt::io::detail
