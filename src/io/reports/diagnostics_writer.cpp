// GeoPackage diagnostics through OGR: see diagnostics_writer.hpp.
//
// A GeoPackage is an SQLite database that GDAL must create itself (it refuses an existing file),
// so it is built at OutputFile::take_path() beside the output's temporary; OutputFile moves it
// into place and removes it, with any SQLite side file, on failure.
#include "io/reports/diagnostics_writer.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_file.hpp"

namespace tincdt::io {
namespace {

using detail::last_gdal_message;

struct Field {
  const char* name;
  OGRFieldType type;
};

// The four layers, in the order they are created.
constexpr const char* kCrossings = "crossings";
constexpr const char* kDuplicates = "merged_duplicates";
constexpr const char* kSkipped = "skipped_segments";
constexpr const char* kDropped = "dropped_features";

bool finite(const Point3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// Refuses a non-finite location before anything is created.
void check_locations(const std::string& path, const Diagnostics& d) {
  const auto check = [&path](const char* layer, std::size_t i, const Point3& p) {
    if (!finite(p))
      throw OutputError(path, std::string("layer ") + layer + ", entry " + count_text(i),
                        "location is not a finite number");
  };
  for (std::size_t i = 0; i < d.crossings.size(); ++i) check(kCrossings, i, d.crossings[i].at);
  for (std::size_t i = 0; i < d.duplicates.size(); ++i) check(kDuplicates, i, d.duplicates[i].at);
  for (std::size_t i = 0; i < d.skipped_segments.size(); ++i)
    check(kSkipped, i, d.skipped_segments[i].at);
  for (std::size_t i = 0; i < d.dropped_features.size(); ++i)
    if (d.dropped_features[i].has_at) check(kDropped, i, d.dropped_features[i].at);
}

// Writes the GeoPackage at FILE (for output PATH), complete and closed.
class GpkgBuilder {
 public:
  GpkgBuilder(const std::string& path, const std::string& file, const OGRSpatialReference* srs)
      : path_(path), srs_(srs), ds_(create(path, file)) {}

  OGRLayer& layer(const char* name, const char* description, std::initializer_list<Field> fields) {
    const std::string desc = std::string("DESCRIPTION=") + description;
    // No R-tree: GDAL 3.6 builds it at close one point at a time, 2 s per 100,000 points, four
    // times the rest of the work, for layers a GIS draws whole anyway.
    const char* const options[] = {desc.c_str(), "SPATIAL_INDEX=NO", nullptr};
    // CreateLayer clones the CRS; GDAL 3.6 takes it non-const all the same.
    OGRLayer* layer = ds_->CreateLayer(name, const_cast<OGRSpatialReference*>(srs_), wkbPoint25D,
                                       const_cast<char**>(options));
    if (layer == nullptr) fail(std::string("layer ") + name, "cannot create the layer");
    for (const Field& f : fields) {
      OGRFieldDefn defn(f.name, f.type);
      if (layer->CreateField(&defn, TRUE) != OGRERR_NONE)
        fail(std::string("layer ") + name, std::string("cannot create the field ") + f.name);
    }
    return *layer;
  }

  void begin() {
    if (ds_->StartTransaction(FALSE) != OGRERR_NONE) fail("", "cannot start a transaction");
  }
  void commit() {
    if (ds_->CommitTransaction() != OGRERR_NONE) fail("", "cannot commit the transaction");
  }

  // Adds one feature to LAYER per item of ITEMS, FILL(feature, item) setting its geometry and
  // fields (one feature object, refilled for each).
  template <class Item, class Fill>
  void add_all(OGRLayer& layer, const std::vector<Item>& items, Fill&& fill) {
    const detail::OgrFeature f(OGRFeature::CreateFeature(layer.GetLayerDefn()));
    for (std::size_t i = 0; i < items.size(); ++i) {
      fill(*f, items[i]);
      f->SetFID(OGRNullFID);
      if (layer.CreateFeature(f.get()) != OGRERR_NONE)
        fail(std::string("layer ") + layer.GetName() + ", entry " + count_text(i),
             "cannot write the feature");
    }
  }

  void close() {
    CPLErrorReset();
    ds_.reset();
    if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
      fail("", "cannot complete the GeoPackage");
  }

 private:
  static detail::GdalDataset create(const std::string& path, const std::string& file) {
    detail::register_gdal_drivers();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
    if (driver == nullptr) throw OutputError(path, "", "GDAL has no GeoPackage driver");
    CPLErrorReset();
    detail::GdalDataset ds(driver->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds)
      throw OutputError(
          path, "", "cannot create the GeoPackage: " + last_gdal_message("GDAL gave no reason"));
    return ds;
  }

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw OutputError(path_, where, what + ": " + last_gdal_message("GDAL gave no reason"));
  }

  const std::string& path_;
  const OGRSpatialReference* srs_;
  detail::GdalDataset ds_;
};

// A 3D point moved to each location in turn (SetGeometry copies it).
class Location {
 public:
  const OGRGeometry* operator()(const Point3& p) {
    point_.setX(p.x);
    point_.setY(p.y);
    point_.setZ(p.z);
    return &point_;
  }

 private:
  OGRPoint point_{0, 0, 0};
};

void write_layers(GpkgBuilder& b, const Diagnostics& d) {
  OGRLayer& crossings =
      b.layer(kCrossings, "Crossing points of two constraint lines, inserted as TIN vertices",
              {{"file_a", OFTString},
               {"fid_a", OFTInteger64},
               {"file_b", OFTString},
               {"fid_b", OFTInteger64},
               {"z_a", OFTReal},
               {"z_b", OFTReal},
               {"z_diff", OFTReal}});
  OGRLayer& duplicates =
      b.layer(kDuplicates, "Input points with the same x, y merged into one TIN vertex",
              {{"points", OFTInteger64}, {"z_min", OFTReal}, {"z_max", OFTReal}});
  OGRLayer& skipped =
      b.layer(kSkipped, "Zero-length segments (repeated vertices) skipped in input lines",
              {{"source_file", OFTString}, {"source_fid", OFTInteger64}});
  OGRLayer& dropped =
      b.layer(kDropped, "Input features that gave nothing to the TIN, and why",
              {{"source_file", OFTString}, {"source_fid", OFTInteger64}, {"reason", OFTString}});

  Location location;
  b.begin();
  b.add_all(crossings, d.crossings, [&](OGRFeature& f, const Diagnostics::Crossing& c) {
    f.SetGeometry(location(c.at));
    f.SetField(0, c.file_a.c_str());
    f.SetField(1, static_cast<GIntBig>(c.fid_a));
    f.SetField(2, c.file_b.c_str());
    f.SetField(3, static_cast<GIntBig>(c.fid_b));
    f.SetField(4, c.z_a);
    f.SetField(5, c.z_b);
    f.SetField(6, std::fabs(c.z_a - c.z_b));
  });
  b.add_all(duplicates, d.duplicates, [&](OGRFeature& f, const Diagnostics::Duplicate& m) {
    f.SetGeometry(location(m.at));
    f.SetField(0, static_cast<GIntBig>(m.points));
    f.SetField(1, m.z_min);
    f.SetField(2, m.z_max);
  });
  b.add_all(skipped, d.skipped_segments, [&](OGRFeature& f, const Diagnostics::SkippedSegment& s) {
    f.SetGeometry(location(s.at));
    f.SetField(0, s.file.c_str());
    f.SetField(1, static_cast<GIntBig>(s.fid));
  });
  b.add_all(dropped, d.dropped_features, [&](OGRFeature& f, const Diagnostics::DroppedFeature& x) {
    const OGRGeometry* at = x.has_at ? location(x.at) : nullptr;
    f.SetGeometry(at);
    f.SetField(0, x.file.c_str());
    f.SetField(1, static_cast<GIntBig>(x.fid));
    f.SetField(2, x.reason.c_str());
  });
  b.commit();
}

}  // namespace

void write_diagnostics(OutputFile& out, const Diagnostics& d, const std::string& crs_wkt) {
  const std::string& path = out.path();
  check_locations(path, d);
  const detail::GdalQuiet quiet;
  std::optional<OGRSpatialReference> srs;
  if (!crs_wkt.empty()) srs.emplace(detail::parse_crs(path, crs_wkt, "the CRS"));
  GpkgBuilder builder(path, out.take_path(), srs ? &*srs : nullptr);
  write_layers(builder, d);
  builder.close();
}

void write_diagnostics(const std::string& path, const Diagnostics& d, const std::string& crs_wkt,
                       bool overwrite) {
  check_locations(path, d);
  OutputFile out(path, overwrite);  // the existence and folder checks, and the temporary
  write_diagnostics(out, d, crs_wkt);
  out.commit();
}

void add_line_diagnostics(const LineData& lines, Diagnostics& d) {
  const auto file = [&lines](std::uint32_t i) {
    return i < lines.files.size() ? lines.files[i] : std::string("file #" + std::to_string(i));
  };
  d.skipped_segments.reserve(d.skipped_segments.size() + lines.skipped.size());
  for (const LineSkip& s : lines.skipped) d.skipped_segments.push_back({s.at, file(s.file), s.fid});
  d.dropped_features.reserve(d.dropped_features.size() + lines.dropped.size());
  for (const LineDrop& x : lines.dropped)
    d.dropped_features.push_back({file(x.file), x.fid, x.reason, x.at, x.has_at});
}

}  // namespace tincdt::io
