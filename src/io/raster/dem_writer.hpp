// DEM rasters (products::rasterize) through GDAL, in the raster format the file's extension
// names or the caller names (a GDAL driver, as gdal_translate -of). .tif and .tiff are
// Cloud-Optimized GeoTIFFs through GDAL's COG driver: tiled 512 x 512, DEFLATE (level 1: most of
// the ratio of level 6 at half the time) with the floating-point predictor, overviews (average of
// the cells with a value, computed here on every thread), the CRS and the nodata value. Any other
// format (.asc AAIGrid, .img HFA, .nc netCDF, ...) gets GDAL's defaults. Creation options go on
// top, checked against the driver first. Float32 or Float64 as the cells given. GDAL builds the
// file at the OutputFile's take_path(): a temporary beside the target, moved over it only when
// the run commits; the further files of a format (an ASCII grid's .prj) are outputs of their own.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "io/output_file.hpp"
#include "io/sibling_files.hpp"
#include "products/grid.hpp"

namespace tincdt::io {

struct DemWriteOptions {
  std::string format;      // a GDAL raster driver ("COG", "AAIGrid"); "" = by the extension
  double nodata = -9999;   // the value of the cells without one (NaN allowed)
  std::string crs_wkt;     // "" = unknown
  bool overwrite = false;  // write_dem(PATH, ...): replace existing files
  // Creation options of the driver ("COMPRESS=ZSTD", "OVERVIEWS=NONE", ...), over the defaults;
  // for COG, naming OVERVIEWS, BLOCKSIZE or a resampling leaves the overviews to GDAL.
  std::vector<std::string> creation_options;
  unsigned threads = 0;  // overview and compression threads; 0 = every hardware thread
  const ProgressFn* progress = nullptr;  // stage "write dem"
};

struct DemWriteStats {
  std::uint64_t bytes = 0;  // all files
  std::string driver;       // the GDAL driver used
};

// The GDAL raster driver that writes a DEM at PATH: FORMAT when given, else the one whose
// extensions list PATH's (.tif and .tiff: COG). Throws OutputError naming PATH, the extension
// and the driver for an extension no raster driver writes, a driver that writes no raster file
// (read-only, MEM, VRT), or one that cannot store FLOAT64 (else Float32) cells (PNG, JPEG: a DEM
// in bytes would lose its heights).
std::string dem_driver_for(const std::string& path, const std::string& format, bool float64);

// Checks OPTIONS (NAME=VALUE each) against DRIVER's creation options as gdal_translate does
// (GDALValidateCreationOptions: known names, values of their type and range), and the block
// sizes, which GDAL takes unchecked: a whole number from 16 to 16384, a multiple of 16 for COG
// and GTiff (BLOCKSIZE=0 spins the COG driver while its file grows without end). Throws
// OutputError naming PATH, the option and the driver.
void check_dem_creation_options(const std::string& path, const std::string& driver,
                                const std::vector<std::string>& options);

// The further files DRIVER writes beside a DEM at PATH ("dem.prj" beside an ASCII grid
// "dem.asc"), so that a caller can refuse existing ones before any work.
std::vector<std::string> dem_side_files(const std::string& path, const std::string& driver);

// The name of the horizontal unit of the CRS in CRS_WKT ("metre", "degree", "US survey foot");
// "" when there is no CRS or OSR cannot read it.
std::string crs_unit_name(const std::string& crs_wkt);

// CELLS: grid.cells() values, row-major from the top-left, nodata where there is no surface.
// Writes into OUT and the further files SIBLING gives (all closed, not committed: the caller's
// OutputSet moves them into place). Throws OutputError naming OUT's path (as dem_driver_for and
// check_dem_creation_options, a nodata value the cell type cannot hold, an unreadable CRS, a
// format of several files without SIBLING, GDAL's own failures), Cancelled when the progress
// callback says stop.
DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const float> cells,
                        const DemWriteOptions& options, const SiblingOutput& sibling = {});
DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const double> cells,
                        const DemWriteOptions& options, const SiblingOutput& sibling = {});
// The same at PATH, every file committed together (options.overwrite).
DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const float> cells, const DemWriteOptions& options);
DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const double> cells, const DemWriteOptions& options);

}  // namespace tincdt::io
