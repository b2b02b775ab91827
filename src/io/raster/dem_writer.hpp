// DEM rasters (products::rasterize) as Cloud-Optimized GeoTIFFs through GDAL's COG driver: tiled
// 512 x 512, DEFLATE (level 1: most of the ratio of level 6 at half the time) with the
// floating-point predictor, overviews (average of the cells with a value, computed here on every
// thread), the CRS and the nodata value; any COG creation option can be given on top. Float32 or
// Float64 as the cells given. GDAL builds the file at the OutputFile's take_path(): a temporary
// beside the target, moved over it only when the run commits.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "io/output_file.hpp"
#include "products/grid.hpp"

namespace tincdt::io {

struct DemWriteOptions {
  double nodata = -9999;   // the value of the cells without one (NaN allowed)
  std::string crs_wkt;     // "" = unknown
  bool overwrite = false;  // write_dem(PATH, ...): replace an existing file
  // COG creation options ("COMPRESS=ZSTD", "OVERVIEWS=NONE", ...), over the defaults; naming
  // OVERVIEWS, BLOCKSIZE or a resampling leaves the overviews to GDAL.
  std::vector<std::string> creation_options;
  unsigned threads = 0;  // overview and compression threads; 0 = every hardware thread
  const ProgressFn* progress = nullptr;  // stage "write dem"
};

struct DemWriteStats {
  std::uint64_t bytes = 0;
};

// CELLS: grid.cells() values, row-major from the top-left, nodata where there is no surface.
// Writes into OUT (not committed: the caller's OutputSet moves it into place). Throws
// OutputError naming OUT's path (a nodata value the cell type cannot hold, an unreadable CRS,
// GDAL's own failures), Cancelled when the progress callback says stop.
DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const float> cells,
                        const DemWriteOptions& options);
DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const double> cells,
                        const DemWriteOptions& options);
// The same as one file at PATH, committed (options.overwrite).
DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const float> cells, const DemWriteOptions& options);
DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const double> cells, const DemWriteOptions& options);

}  // namespace tincdt::io
