#include "io/raster/dem_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_set.hpp"
#include "products/short_number.hpp"

namespace tincdt::io {
namespace {

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

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// The words of a driver's metadata item ("Byte UInt16 Float32", "tif tiff").
std::vector<std::string> metadata_words(GDALDriver* driver, const char* item) {
  const char* text = driver->GetMetadataItem(item);
  std::istringstream in(text != nullptr ? text : "");
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

bool writes_rasters(GDALDriver* d) {
  return d != nullptr && d->GetMetadataItem(GDAL_DCAP_RASTER) != nullptr &&
         (d->GetMetadataItem(GDAL_DCAP_CREATE) != nullptr ||
          d->GetMetadataItem(GDAL_DCAP_CREATECOPY) != nullptr);
}

bool claims_extension(GDALDriver* d, const std::string& ext) {
  if (d->GetMetadataItem(GDAL_DCAP_RASTER) == nullptr) return false;
  std::vector<std::string> exts = metadata_words(d, GDAL_DMD_EXTENSIONS);
  if (exts.empty()) exts = metadata_words(d, GDAL_DMD_EXTENSION);
  for (const std::string& e : exts)
    if (lower(e) == ext) return true;
  return false;
}

// The writable raster driver of EXT (lower case, no dot); "" when none. A read-only driver that
// claims it is named in READER, for the message.
std::string driver_of_extension(const std::string& ext, std::string& reader) {
  if (ext == "tif" || ext == "tiff") return "COG";
  GDALDriverManager* drivers = GetGDALDriverManager();
  for (int i = 0; i < drivers->GetDriverCount(); ++i) {
    GDALDriver* d = drivers->GetDriver(i);
    if (!claims_extension(d, ext)) continue;
    if (writes_rasters(d)) return d->GetDescription();
    if (reader.empty()) reader = d->GetDescription();
  }
  return {};
}

// Why DRIVER (found by EXTENSION, "" when named) cannot write the DEM, or "".
std::string cannot_write(GDALDriver* driver, const std::string& extension, bool float64) {
  const std::string name = driver->GetDescription();
  const std::string who =
      "GDAL's " + name + " driver" + (extension.empty() ? "" : " (for '." + extension + "')");
  if (driver->GetMetadataItem(GDAL_DCAP_RASTER) == nullptr) return who + " writes no rasters";
  if (!writes_rasters(driver)) return who + " reads rasters but cannot write them";
  if (name == "MEM" || name == "VRT") return who + " keeps no cells in a file of its own";
  const char* type = float64 ? "Float64" : "Float32";
  const std::vector<std::string> types = metadata_words(driver, GDAL_DMD_CREATIONDATATYPES);
  if (!types.empty() && std::find(types.begin(), types.end(), type) == types.end()) {
    std::string list;
    for (const std::string& t : types) list += (list.empty() ? "" : " ") + t;
    return who + " cannot store " + type + " cells (it takes " + list +
           "), so the DEM would lose its heights";
  }
  return {};
}

// Block sizes GDAL takes unchecked but cannot work with: 0 spins the COG driver, a huge one asks
// for tiles larger than memory. "" when VALUE is fine for NAME (upper case) with DRIVER.
std::string block_size_problem(const std::string& driver, const std::string& name,
                               const std::string& value) {
  if (name != "BLOCKSIZE" && name != "BLOCKXSIZE" && name != "BLOCKYSIZE") return {};
  constexpr long kMin = 16, kMax = 16384;
  const bool tiff = driver == "COG" || driver == "GTiff";
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  const bool whole = !value.empty() && end != nullptr && *end == '\0';
  if (whole && v >= kMin && v <= kMax && (!tiff || v % 16 == 0)) return {};
  return std::string("a block size must be a whole number from 16 to 16384") +
         (tiff ? ", a multiple of 16" : "");
}

// The cells as a one-band MEM dataset over the caller's buffer (no copy), with the grid's
// georeferencing, SRS and NODATA.
template <class T>
detail::GdalDataset memory_raster(const products::Grid& grid, std::span<const T> cells,
                                  GDALDataType type, double nodata, const OGRSpatialReference* srs,
                                  const std::function<void(const char*)>& fail) {
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  if (mem == nullptr) fail("GDAL has no MEM driver");
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
  if (srs != nullptr && source->SetSpatialRef(srs) != CE_None) fail("cannot set the CRS");
  source->GetRasterBand(1)->SetNoDataValue(nodata);
  return source;
}

// The COG driver's options: the defaults, then the caller's, which win (GDAL takes the last of
// a name). OWN_OVERVIEWS: false when the caller's ask GDAL for its own overviews.
CPLStringList cog_options(const std::vector<std::string>& given, std::size_t threads,
                          bool& own_overviews) {
  CPLStringList list;
  list.SetNameValue("COMPRESS", "DEFLATE");
  list.SetNameValue("LEVEL", "1");
  list.SetNameValue("PREDICTOR", "YES");
  list.SetNameValue("BLOCKSIZE", std::to_string(kBlock).c_str());
  list.SetNameValue("BIGTIFF", "IF_SAFER");
  list.SetNameValue("NUM_THREADS", std::to_string(threads).c_str());
  list.SetNameValue("OVERVIEWS", "FORCE_USE_EXISTING");
  own_overviews = true;
  bool overviews_named = false;
  for (const std::string& option : given) {
    const auto eq = option.find('=');
    const std::string name = upper(option.substr(0, eq));
    overviews_named = overviews_named || name == "OVERVIEWS";
    if (name == "OVERVIEWS" || name.find("RESAMPLING") != std::string::npos ||
        name == "OVERVIEW_COUNT" || name == "BLOCKSIZE")
      own_overviews = false;
    list.SetNameValue(name.c_str(), option.substr(eq + 1).c_str());
  }
  if (!own_overviews && !overviews_named) list.SetNameValue("OVERVIEWS", "AUTO");
  return list;
}

template <class T>
DemWriteStats write(OutputFile& out, const products::Grid& grid, std::span<const T> cells,
                    GDALDataType type, const DemWriteOptions& options,
                    const SiblingOutput& sibling) {
  const std::string& path = out.path();
  if (cells.size() != grid.cells())
    throw OutputError(
        path, "", count_text(cells.size()) + " cells for a grid of " + count_text(grid.cells()));
  if (grid.cells() == 0) throw OutputError(path, "", "the DEM has no cells");
  DemWriteStats stats;
  stats.driver = dem_driver_for(path, options.format, type == GDT_Float64);
  check_dem_creation_options(path, stats.driver, options.creation_options);
  const double nodata = options.nodata;
  const bool fits = std::isnan(nodata) || (std::fabs(nodata) <= std::numeric_limits<T>::max() &&
                                           static_cast<double>(static_cast<T>(nodata)) == nodata);
  if (!fits)
    throw OutputError(path, "",
                      "the nodata value " + products::short_number(nodata) +
                          " cannot be stored in " + GDALGetDataTypeName(type) + " cells");

  const detail::GdalQuiet quiet;
  std::optional<OGRSpatialReference> srs;
  if (!options.crs_wkt.empty()) srs.emplace(detail::parse_crs(path, options.crs_wkt, "the CRS"));
  const auto fail = [&path](const char* what) {
    throw OutputError(path, "",
                      std::string(what) + ": " + detail::last_gdal_message("GDAL gave no reason"));
  };
  detail::GdalDataset source =
      memory_raster<T>(grid, cells, type, nodata, srs ? &*srs : nullptr, fail);

  // COG: the driver's CreateCopy computes the overviews and lays out tiles and overviews in the
  // order a cloud reader wants; the pyramid is computed here unless the options ask GDAL for
  // its own. Other formats: GDAL's defaults and the caller's options.
  const std::size_t threads = thread_count(options.threads);
  const bool cog = stats.driver == "COG";
  bool own_overviews = false;
  CPLStringList creation;
  if (cog)
    creation = cog_options(options.creation_options, threads, own_overviews);
  else
    for (const std::string& option : options.creation_options) creation.AddString(option.c_str());
  if (own_overviews && !add_overviews<T>(*source, *source->GetRasterBand(1), cells.data(),
                                         grid.width, grid.height, type, nodata, threads))
    fail("cannot compute the overviews");
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(stats.driver.c_str());
  detail::GdalProgress progress(options.progress, "write dem");
  const std::string& build_path = out.take_path();
  const SiblingFiles siblings(build_path);
  detail::GdalDataset written(driver->CreateCopy(build_path.c_str(), source.get(), FALSE,
                                                 creation.List(), progress.function(),
                                                 progress.data()));
  if (progress.cancelled()) throw Cancelled();
  if (!written) fail(cog ? "cannot write the GeoTIFF" : "cannot write the raster");
  CPLErrorReset();
  written.reset();  // close: flushes the file
  if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
    fail(cog ? "cannot complete the GeoTIFF" : "cannot complete the raster");
  stats.bytes += siblings.move_into_place(path, sibling, stats.driver);
  out.close();  // moves GDAL's file over the temporary
  stats.bytes += out.bytes_written();
  return stats;
}

template <class T>
DemWriteStats write_file(const std::string& path, const products::Grid& grid,
                         std::span<const T> cells, const DemWriteOptions& options) {
  OutputSet files(options.overwrite);
  OutputFile& out = files.add(path, "dem");
  const DemWriteStats stats =
      write_dem(out, grid, cells, options,
                [&files](const std::string& p) -> OutputFile& { return files.add(p, "dem"); });
  files.commit();
  return stats;
}

}  // namespace

std::string dem_driver_for(const std::string& path, const std::string& format, bool float64) {
  detail::register_gdal_drivers();
  std::string name = format, ext;
  if (format.empty()) {
    ext = lower(std::filesystem::path(path).extension().string());
    if (ext.empty())
      throw OutputError(path, "", "no extension to tell the raster format (.tif, .asc, .img...)");
    ext.erase(0, 1);
    std::string reader;
    name = driver_of_extension(ext, reader);
    if (name.empty())
      throw OutputError(path, "",
                        reader.empty()
                            ? "no GDAL raster driver writes '." + ext + "' files"
                            : "GDAL's " + reader + " driver reads '." + ext +
                                  "' rasters but cannot write them, nor can any other driver");
  }
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(name.c_str());
  if (driver == nullptr) throw OutputError(path, "", "GDAL has no driver named '" + name + "'");
  const std::string why = cannot_write(driver, ext, float64);
  if (!why.empty()) throw OutputError(path, "", why);
  return driver->GetDescription();
}

void check_dem_creation_options(const std::string& path, const std::string& driver_name,
                                const std::vector<std::string>& options) {
  detail::register_gdal_drivers();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
  if (driver == nullptr)
    throw OutputError(path, "", "GDAL has no driver named '" + driver_name + "'");
  for (const std::string& option : options) {
    const auto eq = option.find('=');
    if (eq == std::string::npos || eq == 0)
      throw OutputError(
          path, "",
          "creation option '" + option + "' of the " + driver_name + " driver is not NAME=VALUE");
    const std::string name = upper(option.substr(0, eq));
    const std::string block = block_size_problem(driver_name, name, option.substr(eq + 1));
    if (!block.empty())
      throw OutputError(
          path, "", "creation option " + option + " of the " + driver_name + " driver: " + block);
    const detail::GdalMessages messages;
    const char* const list[] = {option.c_str(), nullptr};
    if (GDALValidateCreationOptions(driver, list) == FALSE) {
      const std::string why = !messages.warnings().empty() ? messages.warnings().front()
                              : messages.failed()          ? messages.failure()
                                                           : "GDAL refuses it";
      throw OutputError(path, "",
                        "creation option " + option + " of the " + driver_name + " driver: " + why);
    }
  }
}

std::vector<std::string> dem_side_files(const std::string& path, const std::string& driver) {
  const std::string stem = std::filesystem::path(path).replace_extension().string();
  if (driver == "AAIGrid") return {stem + ".prj"};
  if (driver == "EHdr") return {stem + ".hdr", stem + ".prj"};
  if (driver == "ENVI") return {stem + ".hdr"};
  return {};
}

std::string crs_unit_name(const std::string& crs_wkt) {
  OGRSpatialReference srs = detail::gis_order_srs();
  if (crs_wkt.empty() || !detail::import_wkt(srs, crs_wkt)) return {};
  const char* name = nullptr;
  if (srs.IsGeographic())
    srs.GetAngularUnits(&name);
  else
    srs.GetLinearUnits(&name);
  return name != nullptr ? name : "";
}

DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const float> cells,
                        const DemWriteOptions& options, const SiblingOutput& sibling) {
  return write<float>(out, grid, cells, GDT_Float32, options, sibling);
}

DemWriteStats write_dem(OutputFile& out, const products::Grid& grid, std::span<const double> cells,
                        const DemWriteOptions& options, const SiblingOutput& sibling) {
  return write<double>(out, grid, cells, GDT_Float64, options, sibling);
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
