#include "io/vector/contour_writer.hpp"

#include <algorithm>
#include <cctype>
#include <exception>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_set.hpp"
#include "io/sibling_files.hpp"

namespace tincdt::io {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool can_create_vectors(GDALDriver* d) {
  return d != nullptr && d->GetMetadataItem(GDAL_DCAP_VECTOR) != nullptr &&
         d->GetMetadataItem(GDAL_DCAP_CREATE) != nullptr;
}

// Features per transaction: SQLite keeps a transaction's pages in its cache until the commit.
constexpr std::uint64_t kBatch = 100000;

}  // namespace

std::string vector_driver_for(const std::string& path, const std::string& format) {
  detail::register_gdal_drivers();
  GDALDriverManager* drivers = GetGDALDriverManager();
  if (!format.empty()) {
    GDALDriver* d = drivers->GetDriverByName(format.c_str());
    if (d == nullptr) throw OutputError(path, "", "GDAL has no driver named '" + format + "'");
    if (!can_create_vectors(d))
      throw OutputError(path, "", "GDAL's " + format + " driver cannot create vector files");
    return format;
  }
  std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext.empty())
    throw OutputError(path, "",
                      "no extension to tell the vector format (.gpkg, .shp, .geojson...)");
  ext.erase(0, 1);
  // The common formats first, so that an extension several drivers claim goes to the usual one.
  for (const char* preferred : {"GPKG", "ESRI Shapefile", "GeoJSON", "FlatGeobuf"}) {
    GDALDriver* d = drivers->GetDriverByName(preferred);
    if (!can_create_vectors(d)) continue;
    const char* exts = d->GetMetadataItem(GDAL_DMD_EXTENSIONS);
    std::istringstream words(exts != nullptr ? exts : "");
    for (std::string w; words >> w;)
      if (lower(w) == ext) return preferred;
  }
  for (int i = 0; i < drivers->GetDriverCount(); ++i) {
    GDALDriver* d = drivers->GetDriver(i);
    if (!can_create_vectors(d)) continue;
    const char* exts = d->GetMetadataItem(GDAL_DMD_EXTENSIONS);
    if (exts == nullptr) exts = d->GetMetadataItem(GDAL_DMD_EXTENSION);
    std::istringstream words(exts != nullptr ? exts : "");
    for (std::string w; words >> w;)
      if (lower(w) == ext) return d->GetDescription();
  }
  throw OutputError(path, "", "no GDAL driver writes '." + ext + "' vector files");
}

ContourWriteStats write_contours(OutputFile& out, const products::ContourSet& contours,
                                 const ContourWriteOptions& options, const SiblingOutput& sibling) {
  const std::string& path = out.path();
  ContourWriteStats stats;
  stats.driver = vector_driver_for(path, options.format);
  const std::string& build_path = out.take_path();
  const SiblingFiles siblings(build_path);
  const detail::GdalQuiet quiet;
  std::optional<OGRSpatialReference> srs;
  if (!options.crs_wkt.empty()) srs.emplace(detail::parse_crs(path, options.crs_wkt, "the CRS"));
  const auto fail = [&path](const std::string& where, const std::string& what) {
    throw OutputError(path, where, what + ": " + detail::last_gdal_message("GDAL gave no reason"));
  };

  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(stats.driver.c_str());
  {
    detail::GdalDataset ds(driver->Create(build_path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) fail("", "cannot create the file");
    OGRLayer* layer =
        ds->CreateLayer(options.layer.c_str(), srs ? &*srs : nullptr, wkbLineString25D, nullptr);
    if (layer == nullptr) fail("", "cannot create the layer");
    int elevation = -1;
    if (!options.elevation_field.empty()) {
      OGRFieldDefn field(options.elevation_field.c_str(), OFTReal);
      if (layer->CreateField(&field, TRUE) != OGRERR_NONE)
        fail("", "cannot create the field " + options.elevation_field);
      elevation = layer->GetLayerDefn()->GetFieldIndex(options.elevation_field.c_str());
      if (elevation < 0) fail("", "cannot create the field " + options.elevation_field);
    }

    // Transactions where the driver has them (GeoPackage, SQLite); the others write directly.
    const bool transactions = ds->TestCapability(ODsCTransactions) != 0;
    if (transactions && ds->StartTransaction(FALSE) != OGRERR_NONE)
      fail("", "cannot start a transaction");
    Progress progress(options.progress, "write contours", contours.lines.size());
    const detail::OgrFeature feature(OGRFeature::CreateFeature(layer->GetLayerDefn()));
    OGRLineString line;
    // Stopped midway (asked to stop, or a write failed): the lines written so far are dropped
    // before the file closes, for closing builds what the driver deferred (a GeoPackage's
    // spatial index: seconds for a large set), and the file is discarded anyway.
    struct DropWhenStopped {
      GDALDataset& ds;
      bool transaction;
      int exceptions = std::uncaught_exceptions();
      ~DropWhenStopped() {
        if (std::uncaught_exceptions() <= exceptions) return;
        // Neither is checked as an error: the file is a temporary that is removed anyway, the
        // error in flight says why the write stopped, and a driver that cannot drop the layer
        // only makes the close slower. A refusal's message is cleared, not to stand for that
        // error.
        const bool rolled_back = !transaction || ds.RollbackTransaction() == OGRERR_NONE;
        const bool dropped =
            ds.TestCapability(ODsCDeleteLayer) != 0 && ds.DeleteLayer(0) == OGRERR_NONE;
        if (!rolled_back || !dropped) CPLErrorReset();
      }
    } drop_when_stopped{*ds, transactions};
    for (std::size_t i = 0; i < contours.lines.size(); ++i) {
      const products::ContourLine& c = contours.lines[i];
      line.setNumPoints(static_cast<int>(c.count), FALSE);
      for (std::size_t k = 0; k < c.count; ++k) {
        const Point2 p = contours.points[c.first + k];
        line.setPoint(static_cast<int>(k), p.x, p.y, c.level);
      }
      feature->SetGeometry(&line);
      if (elevation >= 0) feature->SetField(elevation, c.level);
      feature->SetFID(OGRNullFID);
      if (layer->CreateFeature(feature.get()) != OGRERR_NONE)
        fail("line " + count_text(i) + " (level " + number_text(c.level) + ")",
             "cannot write the feature");
      if (transactions && (i + 1) % kBatch == 0) {
        if (ds->CommitTransaction() != OGRERR_NONE || ds->StartTransaction(FALSE) != OGRERR_NONE)
          fail("", "cannot commit a transaction");
      }
      progress.tick(i);
    }
    if (transactions && ds->CommitTransaction() != OGRERR_NONE)
      fail("", "cannot commit the transaction");
    CPLErrorReset();
    ds.reset();
    if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
      fail("", "cannot complete the file");
    progress.finish();
  }
  // Each further file to the temporary of an output of its own beside the target.
  stats.bytes += siblings.move_into_place(path, sibling, stats.driver);
  out.close();
  stats.bytes += out.bytes_written();
  stats.lines = contours.lines.size();
  return stats;
}

ContourWriteStats write_contours(const std::string& path, const products::ContourSet& contours,
                                 const ContourWriteOptions& options) {
  OutputSet files(options.overwrite);
  OutputFile& out = files.add(path, "contours");
  const ContourWriteStats stats = write_contours(
      out, contours, options,
      [&files](const std::string& p) -> OutputFile& { return files.add(p, "contours"); });
  files.commit();
  return stats;
}

}  // namespace tincdt::io
