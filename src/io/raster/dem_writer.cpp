#include "io/raster/dem_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/parallel.hpp"
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

constexpr int kBlock = 512;  // tile size, and the largest overview's side bound (as COG's AUTO)

// One overview level from the one above it (W x H cells): each cell the mean of the up to 2 x 2
// cells with a value under it, nodata when none has one. The average of GDAL's overviews;
// computed here on every thread because GDAL 3.6 builds overviews on one, and the pyramid of a
// large DEM took longer than its tiles.
template <class T>
std::vector<T> halve(const T* above, std::size_t w, std::size_t h, double nodata,
                     std::size_t threads) {
  const std::size_t ow = (w + 1) / 2, oh = (h + 1) / 2;
  std::vector<T> level(ow * oh);
  const bool nan_nodata = std::isnan(nodata);
  const T no = static_cast<T>(nodata);
  parallel_chunks(
      threads, oh,
      [&](std::size_t r0, std::size_t r1) {
        for (std::size_t r = r0; r < r1; ++r) {
          for (std::size_t c = 0; c < ow; ++c) {
            double sum = 0;
            int n = 0;
            for (std::size_t dr = 0; dr < 2 && 2 * r + dr < h; ++dr)
              for (std::size_t dc = 0; dc < 2 && 2 * c + dc < w; ++dc) {
                const T v = above[(2 * r + dr) * w + 2 * c + dc];
                if (nan_nodata ? std::isnan(v) : v == no) continue;
                sum += v;
                ++n;
              }
            level[r * ow + c] = n > 0 ? static_cast<T>(sum / n) : no;
          }
        }
      },
      64);
  return level;
}

// The overview pyramid of BAND (the cells at TOP): halved until both sides fit in one tile,
// created empty by GDAL ("NONE") and filled here.
template <class T>
bool add_overviews(GDALDataset& source, GDALRasterBand& band, const T* top, std::size_t w,
                   std::size_t h, GDALDataType type, double nodata, std::size_t threads) {
  std::vector<int> factors;
  for (std::size_t f = 2, ow = w, oh = h; std::max(ow, oh) > kBlock; f *= 2) {
    factors.push_back(static_cast<int>(f));
    ow = (ow + 1) / 2;
    oh = (oh + 1) / 2;
  }
  if (factors.empty()) return true;
  if (source.BuildOverviews("NONE", static_cast<int>(factors.size()), factors.data(), 0, nullptr,
                            GDALDummyProgress, nullptr) != CE_None)
    return false;
  std::vector<T> above_level;  // the level just written; the top is the caller's
  const T* above = top;
  for (int i = 0; i < band.GetOverviewCount(); ++i) {
    std::vector<T> level = halve(above, w, h, nodata, threads);
    w = (w + 1) / 2;
    h = (h + 1) / 2;
    GDALRasterBand* ovr = band.GetOverview(i);
    if (ovr == nullptr || static_cast<std::size_t>(ovr->GetXSize()) != w ||
        static_cast<std::size_t>(ovr->GetYSize()) != h)
      return false;
    if (ovr->RasterIO(GF_Write, 0, 0, static_cast<int>(w), static_cast<int>(h), level.data(),
                      static_cast<int>(w), static_cast<int>(h), type, 0, 0, nullptr) != CE_None)
      return false;
    above_level = std::move(level);
    above = above_level.data();
  }
  return true;
}

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

  const std::size_t threads = thread_count(options.threads);
  // The defaults, then the caller's creation options, which win (GDAL takes the last of a
  // name). Unless they ask GDAL for its own overviews, the pyramid is computed here.
  CPLStringList cog_options;
  cog_options.SetNameValue("COMPRESS", "DEFLATE");
  cog_options.SetNameValue("LEVEL", "1");
  cog_options.SetNameValue("PREDICTOR", "YES");
  cog_options.SetNameValue("BLOCKSIZE", std::to_string(kBlock).c_str());
  cog_options.SetNameValue("BIGTIFF", "IF_SAFER");
  cog_options.SetNameValue("NUM_THREADS", std::to_string(threads).c_str());
  cog_options.SetNameValue("OVERVIEWS", "FORCE_USE_EXISTING");
  bool own_overviews = true, overviews_named = false;
  for (const std::string& option : options.creation_options) {
    const auto eq = option.find('=');
    if (eq == std::string::npos || eq == 0)
      throw OutputError(path, "", "creation option '" + option + "' is not NAME=VALUE");
    std::string name = option.substr(0, eq);
    for (char& ch : name) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    overviews_named = overviews_named || name == "OVERVIEWS";
    if (name == "OVERVIEWS" || name.find("RESAMPLING") != std::string::npos ||
        name == "OVERVIEW_COUNT" || name == "BLOCKSIZE")
      own_overviews = false;
    cog_options.SetNameValue(name.c_str(), option.substr(eq + 1).c_str());
  }
  if (!own_overviews && !overviews_named) cog_options.SetNameValue("OVERVIEWS", "AUTO");
  if (own_overviews && !add_overviews<T>(*source, *band, cells.data(), grid.width, grid.height,
                                         type, nodata, threads))
    fail("cannot compute the overviews");
  const bool with_progress = options.progress != nullptr && *options.progress;
  ProgressBridge bridge{options.progress};
  detail::GdalDataset written(
      cog->CreateCopy(out.take_path().c_str(), source.get(), FALSE, cog_options.List(),
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
