// Contour lines (products::trace_contours) through OGR, in any vector format GDAL writes, chosen
// by the extension (.gpkg, .shp, .geojson, .fgb, ...) or named: one LineString Z feature per line
// (z = its level; closed rings end where they start) with its level in a Real field, in
// transactions where the driver has them. GDAL builds the file at the OutputFile's take_path();
// the other files of a multi-file format (a shapefile's .shx, .dbf, .prj) become outputs of
// their own, so they move into place with it or not at all.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/progress.hpp"
#include "io/output_file.hpp"
#include "io/sibling_files.hpp"
#include "products/contours.hpp"

namespace tincdt::io {

struct ContourWriteOptions {
  std::string format;  // GDAL driver name ("GPKG", "ESRI Shapefile"); "" = by extension
  // Like gdal_contour -a elev; "" = no field, the level only as z (CAD formats: DXF, DGN).
  std::string elevation_field = "elev";
  std::string layer = "contours";        // the layer name (a shapefile's is its file name)
  std::string crs_wkt;                   // "" = unknown
  bool overwrite = false;                // write_contours(PATH, ...): replace existing files
  const ProgressFn* progress = nullptr;  // stage "write contours"
};

struct ContourWriteStats {
  std::uint64_t lines = 0;
  std::uint64_t bytes = 0;  // all files
  std::string driver;       // the GDAL driver used
};

// The GDAL vector driver that writes PATH: FORMAT when given (checked), else the one whose
// extensions list PATH's. Throws OutputError for an unknown extension or a driver that cannot
// create files.
std::string vector_driver_for(const std::string& path, const std::string& format);

// Writes CONTOURS into OUT and the siblings SIBLING gives (both closed, not committed). Throws
// OutputError naming OUT's path; a multi-file format without SIBLING is refused.
ContourWriteStats write_contours(OutputFile& out, const products::ContourSet& contours,
                                 const ContourWriteOptions& options, const SiblingOutput& sibling);
// The same at PATH, every file committed together (options.overwrite).
ContourWriteStats write_contours(const std::string& path, const products::ContourSet& contours,
                                 const ContourWriteOptions& options);

}  // namespace tincdt::io
