#include "io/raster/dem_writer.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io {
namespace {

// GDAL's progress callback over ours; remembers a request to stop, which GDAL reports as a
// failure like any other.
struct ProgressBridge {
  const ProgressFn* fn;
  bool cancelled = false;
  static int CPL_STDCALL report(double fraction, const char*, void* data) {
    auto* self = static_cast<ProgressBridge*>(data);
    if ((*self->fn)("write dem", fraction)) return TRUE;
    self->cancelled = true;
    return FALSE;
  }
};

template <class T>
DemWriteStats write(OutputFile& out, const products::Grid& grid, std::span<const T> cells,
                    GDALDataType type, const DemWriteOptions& options) {
  const std::string& path = out.path();
  if (cells.size() != grid.cells())
    throw OutputError(
        path, "",
        std::to_string(cells.size()) + " cells for a grid of " + std::to_string(grid.cells()));
  if (grid.cells() == 0) throw OutputError(path, "", "the DEM has no cells");
  const double nodata = options.nodata;
  const bool fits = std::isnan(nodata) || (std::fabs(nodata) <= std::numeric_limits<T>::max() &&
                                           static_cast<double>(static_cast<T>(nodata)) == nodata);
  if (!fits)
    throw OutputError(path, "",
                      "the nodata value " + std::to_string(nodata) + " cannot be stored in " +
                          GDALGetDataTypeName(type) + " cells");

  const detail::GdalQuiet quiet;
  detail::register_gdal_drivers();
  std::optional<OGRSpatialReference> srs;
  if (!options.crs_wkt.empty()) srs.emplace(detail::parse_crs(path, options.crs_wkt, "the CRS"));
  const auto fail = [&path](const char* what) {
    throw OutputError(path, "",
                      std::string(what) + ": " + detail::last_gdal_message("GDAL gave no reason"));
  };

  // The cells as a one-band MEM dataset over the caller's buffer (no copy), then the COG
  // driver's CreateCopy: it computes the overviews and lays out tiles and overviews in the
  // order a cloud reader wants.
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (mem == nullptr || cog == nullptr)
    throw OutputError(path, "", "GDAL has no MEM or COG driver");
  detail::GdalDataset source(mem->Create("", static_cast<int>(grid.width),
                                         static_cast<int>(grid.height), 0, type, nullptr));
  if (!source) fail("cannot set up the raster");
  char address[64];
  const int length =
      CPLPrintPointer(address, const_cast<T*>(cells.data()), static_cast<int>(sizeof address - 1));
  address[length] = '\0';
  const std::string pointer = std::string("DATAPOINTER=") + address;
  const char* const band_options[] = {pointer.c_str(), nullptr};
  if (source->AddBand(type, const_cast<char**>(band_options)) != CE_None)
    fail("cannot set up the raster");
  double transform[6];
  grid.geotransform(transform);
  source->SetGeoTransform(transform);
  if (srs && source->SetSpatialRef(&*srs) != CE_None) fail("cannot set the CRS");
  GDALRasterBand* band = source->GetRasterBand(1);
  band->SetNoDataValue(nodata);

  const unsigned threads =
      options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const std::string num_threads = "NUM_THREADS=" + std::to_string(threads);
  const char* const cog_options[] = {
      "COMPRESS=DEFLATE",   "PREDICTOR=YES",    "BLOCKSIZE=512",     "OVERVIEWS=AUTO",
      "RESAMPLING=AVERAGE", "BIGTIFF=IF_SAFER", num_threads.c_str(), nullptr};
  const bool with_progress = options.progress != nullptr && *options.progress;
  ProgressBridge bridge{options.progress};
  detail::GdalDataset written(
      cog->CreateCopy(out.take_path().c_str(), source.get(), FALSE, const_cast<char**>(cog_options),
                      with_progress ? ProgressBridge::report : GDALDummyProgress,
                      with_progress ? &bridge : nullptr));
  if (bridge.cancelled) throw Cancelled();
  if (!written) fail("cannot write the GeoTIFF");
  CPLErrorReset();
  written.reset();  // close: flushes the file
  if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
    fail("cannot complete the GeoTIFF");
  out.close();  // moves GDAL's file over the temporary
  DemWriteStats stats;
  stats.bytes = out.bytes_written();
  return stats;
}

template <class T>
DemWriteStats write_file(const std::string& path, const products::Grid& grid,
                         std::span<const T> cells, const DemWriteOptions& options) {
  OutputFile out(path, options.overwrite);
  const DemWriteStats stats = write_dem(out, grid, cells, options);
  out.commit();
  return stats;
}

}  // namespace

DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const float> cells,
                        const DemWriteOptions& options) {
  return write<float>(out, grid, cells, GDT_Float32, options);
}

DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const double> cells,
                        const DemWriteOptions& options) {
  return write<double>(out, grid, cells, GDT_Float64, options);
}

DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const float> cells, const DemWriteOptions& options) {
  return write_file(path, grid, cells, options);
}

DemWriteStats write_dem(const std::string& path, const products::Grid& grid,
                        std::span<const double> cells, const DemWriteOptions& options) {
  return write_file(path, grid, cells, options);
}

}  // namespace tincdt::io
