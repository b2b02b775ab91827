// OGR line reader: see line_reader.hpp.
#include "io/line_reader.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace tincdt::io {
namespace {

constexpr std::size_t kMaxWarnings = 20;
constexpr std::uint64_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

void ensure_drivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// For the scope: GDAL prints nothing; warnings are kept for the stats, failures are remembered
// so that a driver that gives up in the middle of a layer is not mistaken for its end.
class GdalErrors {
 public:
  GdalErrors() {
    CPLPushErrorHandlerEx(&GdalErrors::handle, this);
    CPLErrorReset();
  }
  GdalErrors(const GdalErrors&) = delete;
  GdalErrors& operator=(const GdalErrors&) = delete;
  ~GdalErrors() { CPLPopErrorHandler(); }

  // GDAL's last message, or FALLBACK when it said nothing.
  static std::string last(const char* fallback) {
    const char* msg = CPLGetLastErrorMsg();
    return (msg != nullptr && *msg != '\0') ? std::string(msg) : std::string(fallback);
  }
  void reset_failure() {
    failed_ = false;
    failure_.clear();
  }
  bool failed() const { return failed_; }
  const std::string& failure() const { return failure_; }
  std::vector<std::string>& warnings() { return warnings_; }

 private:
  static void CPL_STDCALL handle(CPLErr level, CPLErrorNum, const char* msg) {
    auto* self = static_cast<GdalErrors*>(CPLGetErrorHandlerUserData());
    if (self == nullptr) return;
    const std::string text = msg != nullptr ? msg : "";
    if (level == CE_Failure || level == CE_Fatal) {
      if (!self->failed_) self->failure_ = text;
      self->failed_ = true;
    } else if (level == CE_Warning && self->warnings_.size() < kMaxWarnings) {
      self->warnings_.push_back(text);
    }
  }

  bool failed_ = false;
  std::string failure_;
  std::vector<std::string> warnings_;
};

bool exists(const std::string& path) {
  VSIStatBufL st;
  return VSIStatExL(path.c_str(), &st, VSI_STAT_EXISTS_FLAG) == 0;
}

bool starts_with(const std::string& s, const char* prefix) {
  return s.rfind(prefix, 0) == 0;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out;
}

std::vector<std::string> layer_names(GDALDatasetH ds) {
  std::vector<std::string> names;
  const int n = GDALDatasetGetLayerCount(ds);
  for (int i = 0; i < n; ++i) names.emplace_back(OGR_L_GetName(GDALDatasetGetLayer(ds, i)));
  return names;
}

std::string field_list(OGRFeatureDefnH defn) {
  std::vector<std::string> names;
  const int n = OGR_FD_GetFieldCount(defn);
  for (int i = 0; i < n; ++i) names.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i)));
  return names.empty() ? std::string("none") : join(names);
}

// The layer's CRS as WKT2 (WKT1 when OSR cannot), like crs.cpp; "" for none. A GeoPackage layer
// written without a CRS reports one of the spec's two placeholder entries (srs_id 0 "Undefined
// geographic SRS", -1 "Undefined Cartesian SRS"): that means no CRS too.
std::string export_crs(OGRSpatialReferenceH srs) {
  if (srs == nullptr) return {};
  const char* name = OSRGetName(srs);
  if (name != nullptr && OSRGetAuthorityName(srs, nullptr) == nullptr &&
      (std::strcmp(name, "Undefined geographic SRS") == 0 ||
       std::strcmp(name, "Undefined Cartesian SRS") == 0)) {
    return {};
  }
  for (const char* format : {"FORMAT=WKT2_2019", "FORMAT=WKT1"}) {
    const char* const options[] = {format, nullptr};
    char* text = nullptr;
    const OGRErr err = OSRExportToWktEx(srs, &text, options);
    std::string wkt = (err == OGRERR_NONE && text != nullptr) ? std::string(text) : std::string();
    CPLFree(text);
    if (!wkt.empty()) return wkt;
  }
  return {};
}

// Owns a GDAL dataset.
class Dataset {
 public:
  explicit Dataset(GDALDatasetH h) : h_(h) {}
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;
  ~Dataset() {
    if (h_ != nullptr) GDALClose(h_);
  }
  GDALDatasetH get() const { return h_; }

 private:
  GDALDatasetH h_;
};

// Owns an OGR feature.
class Feature {
 public:
  explicit Feature(OGRFeatureH h) : h_(h) {}
  Feature(const Feature&) = delete;
  Feature& operator=(const Feature&) = delete;
  ~Feature() {
    if (h_ != nullptr) OGR_F_Destroy(h_);
  }
  OGRFeatureH get() const { return h_; }

 private:
  OGRFeatureH h_;
};

// Owns an OGR geometry made by the reader (a linearized curve).
class Geometry {
 public:
  explicit Geometry(OGRGeometryH h) : h_(h) {}
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;
  ~Geometry() {
    if (h_ != nullptr) OGR_G_DestroyGeometry(h_);
  }
  OGRGeometryH get() const { return h_; }

 private:
  OGRGeometryH h_;
};

enum class ZSource { kGeometry, kField, kMeasure };

// Reads the features of one layer into LineData.
class LayerReader {
 public:
  LayerReader(std::string file, std::string layer, ZSource z_source, int z_field,
              std::string fields, std::uint32_t file_index, LineData& out, LineReadStats& stats)
      : file_(std::move(file)),
        layer_(std::move(layer)),
        z_source_(z_source),
        z_field_(z_field),
        fields_(std::move(fields)),
        file_index_(file_index),
        out_(out),
        stats_(stats) {}

  void read_feature(OGRFeatureH feature, std::int64_t fid) {
    ++stats_.features;
    fid_ = fid;
    feature_ = feature;
    have_z_ = false;
    unsupported_.clear();
    degenerate_ = false;
    has_at_ = false;
    const std::size_t segments_before = out_.segments.size();
    OGRGeometryH geometry = OGR_F_GetGeometryRef(feature);
    if (geometry != nullptr && !OGR_G_IsEmpty(geometry)) {
      if (OGR_G_HasCurveGeometry(geometry, TRUE)) {
        const Geometry linear(OGR_G_GetLinearGeometry(geometry, 0.0, nullptr));
        if (linear.get() == nullptr) fail("cannot approximate the curved geometry by lines");
        ++curves_;
        add_geometry(linear.get());
      } else {
        add_geometry(geometry);
      }
    }
    if (out_.segments.size() == segments_before) {
      ++stats_.empty_features;
      out_.dropped.push_back({file_index_, fid_, drop_reason(geometry), at_, has_at_});
      return;
    }
    if (out_.features.size() >= kMaxIndex) fail("more than 2^32 - 1 features");
    out_.features.push_back(
        {file_index_, fid_,
         z_source_ == ZSource::kField ? z_ : std::numeric_limits<double>::quiet_NaN()});
  }

  std::uint64_t curves() const { return curves_; }

 private:
  [[noreturn]] void fail(const std::string& detail) const {
    throw InputError(file_, "layer " + layer_ + ", feature " + std::to_string(fid_), detail);
  }

  // Why the feature gave no segment.
  std::string drop_reason(OGRGeometryH geometry) const {
    if (geometry == nullptr) return "no geometry";
    if (OGR_G_IsEmpty(geometry)) return "empty geometry";
    std::string reason;
    if (degenerate_) reason = "degenerate: no line or ring with 2 distinct vertices";
    if (!unsupported_.empty()) {
      if (!reason.empty()) reason += "; ";
      reason += unsupported_ + " geometry: only lines and polygon rings are used";
    }
    return reason.empty() ? std::string("no line geometry") : reason;
  }

  // The first location of a problem in the feature, for the dropped-feature record.
  void note_location(const Point3& p) {
    if (has_at_) return;
    at_ = p;
    has_at_ = true;
  }

  // A geometry the reader does not use (points, surfaces): its name and first vertex.
  void note_unsupported(OGRGeometryH g) {
    if (unsupported_.empty()) unsupported_ = OGRGeometryTypeToName(OGR_G_GetGeometryType(g));
    Point3 p{};
    if (first_vertex(g, p)) note_location(p);
  }

  static bool first_vertex(OGRGeometryH g, Point3& p) {
    if (OGR_G_IsEmpty(g)) return false;
    if (OGR_G_GetPointCount(g) > 0) {
      OGR_G_GetPoint(g, 0, &p.x, &p.y, &p.z);
      return true;
    }
    const int n = OGR_G_GetGeometryCount(g);
    for (int i = 0; i < n; ++i)
      if (first_vertex(OGR_G_GetGeometryRef(g, i), p)) return true;
    return false;
  }

  void add_geometry(OGRGeometryH g) {
    switch (wkbFlatten(OGR_G_GetGeometryType(g))) {
      case wkbLineString:
      case wkbLinearRing:
        add_part(g, false);
        break;
      case wkbPolygon:
      case wkbTriangle: {
        const int n = OGR_G_GetGeometryCount(g);
        for (int i = 0; i < n; ++i) add_part(OGR_G_GetGeometryRef(g, i), true);
        break;
      }
      case wkbMultiLineString:
      case wkbMultiPolygon:
      case wkbGeometryCollection: {
        const int n = OGR_G_GetGeometryCount(g);
        for (int i = 0; i < n; ++i) add_geometry(OGR_G_GetGeometryRef(g, i));
        break;
      }
      default:  // points, surfaces: nothing to constrain
        note_unsupported(g);
        break;
    }
  }

  // The feature's z attribute, read once per feature and only when a line needs it.
  double field_z() {
    if (have_z_) return z_;
    if (!OGR_F_IsFieldSetAndNotNull(feature_, z_field_)) {
      fail("the z field " + field_name() + " is NULL");
    }
    const OGRFieldType type = OGR_Fld_GetType(OGR_F_GetFieldDefnRef(feature_, z_field_));
    if (type == OFTInteger || type == OFTInteger64 || type == OFTReal) {
      z_ = OGR_F_GetFieldAsDouble(feature_, z_field_);
    } else {  // text: only a complete number counts, never a silent 0
      const char* text = OGR_F_GetFieldAsString(feature_, z_field_);
      char* end = nullptr;
      z_ = CPLStrtod(text, &end);  // "." as the decimal mark whatever the locale
      while (end != nullptr && (*end == ' ' || *end == '\t')) ++end;
      if (end == text || end == nullptr || *end != '\0') {
        fail("the z field " + field_name() + " holds '" + std::string(text) +
             "', which is not a number");
      }
    }
    if (!std::isfinite(z_)) fail("the z field " + field_name() + " is not finite");
    have_z_ = true;
    return z_;
  }

  std::string field_name() const {
    return OGR_Fld_GetNameRef(OGR_F_GetFieldDefnRef(feature_, z_field_));
  }

  void add_part(OGRGeometryH g, bool ring) {
    const int count = OGR_G_GetPointCount(g);
    if (count <= 0) {
      ++stats_.degenerate_parts;
      degenerate_ = true;
      return;
    }
    const bool has_z = OGR_G_Is3D(g) != 0;
    const bool has_m = OGR_G_IsMeasured(g) != 0;
    double z = 0.0;
    switch (z_source_) {
      case ZSource::kField:
        z = field_z();
        break;
      case ZSource::kMeasure:
        if (!has_m) fail("the geometry has no M values to take z from");
        break;
      case ZSource::kGeometry:
        if (!has_z) {
          fail("2D geometry has no elevation: pass --z-field NAME (fields: " + fields_ +
               ") or use a 3D layer");
        }
        break;
    }

    std::vector<Point3>& v = out_.vertices;
    const std::size_t base = v.size();
    const auto n = static_cast<std::size_t>(count);
    v.resize(base + n);
    Point3* p = v.data() + base;
    constexpr int kStride = static_cast<int>(sizeof(Point3));
    void* z_target = z_source_ == ZSource::kGeometry ? &p->z : nullptr;
    void* m_target = z_source_ == ZSource::kMeasure ? &p->z : nullptr;
    OGR_G_GetPointsZM(g, &p->x, kStride, &p->y, kStride, z_target, kStride, m_target, kStride);
    for (std::size_t i = 0; i < n; ++i) {
      if (z_source_ == ZSource::kField) p[i].z = z;
      if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z)) {
        fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
      }
    }

    // Collapse runs of the same x, y (keeping the first z).
    std::size_t k = 1;
    for (std::size_t r = 1; r < n; ++r) {
      if (p[r].x == p[k - 1].x && p[r].y == p[k - 1].y) {
        out_.skipped.push_back({p[r], file_index_, fid_});
        continue;
      }
      if (r != k) p[k] = p[r];
      ++k;
    }
    const std::uint64_t repeats = n - k;
    stats_.repeated_vertices += repeats;
    stats_.zero_length_segments += repeats;

    // A ring, or a line that ends where it starts: the closing vertex is the first one.
    bool closed = ring;
    if (k >= 2 && p[k - 1].x == p[0].x && p[k - 1].y == p[0].y) {
      --k;
      closed = true;
    }
    if (k < 2) {
      note_location(p[0]);
      degenerate_ = true;
      v.resize(base);
      ++stats_.degenerate_parts;
      return;
    }
    if (k == 2) closed = false;  // A-B-A is the single segment A-B
    v.resize(base + k);
    if (v.size() - 1 > kMaxIndex) fail("more than 2^32 - 1 vertices");

    const auto first = static_cast<std::uint32_t>(base);
    const auto feature = static_cast<std::uint32_t>(out_.features.size());
    const std::size_t segment_count = closed ? k : k - 1;
    out_.segments.reserve(out_.segments.size() + segment_count);
    for (std::uint32_t i = 0; i + 1 < k; ++i) {
      out_.segments.push_back({first + i, first + i + 1, feature});
    }
    if (closed) {
      out_.segments.push_back({first + static_cast<std::uint32_t>(k - 1), first, feature});
      ++stats_.closed_parts;
    }
    stats_.vertices += k;
    stats_.segments += segment_count;
  }

  const std::string file_;
  const std::string layer_;
  const ZSource z_source_;
  const int z_field_;
  const std::string fields_;
  const std::uint32_t file_index_;
  LineData& out_;
  LineReadStats& stats_;

  OGRFeatureH feature_ = nullptr;
  std::int64_t fid_ = 0;
  bool have_z_ = false;
  double z_ = 0.0;
  std::uint64_t curves_ = 0;
  // What made the current feature useless, for out_.dropped.
  std::string unsupported_;  // name of the first geometry type not read, "" when none
  bool degenerate_ = false;  // a part with < 2 distinct vertices
  bool has_at_ = false;
  Point3 at_{0, 0, 0};
};

// Splits "FILE:LAYER" into its parts, at the last ':' and only when FILE exists and the whole
// does not (so "C:\dir\a.shp" or "/vsicurl/https://..." stay whole).
void split_spec(const std::string& spec, std::string& file, std::string& layer) {
  file = spec;
  layer.clear();
  if (exists(spec)) return;
  const std::size_t colon = spec.rfind(':');
  if (colon == std::string::npos || colon == 0) return;
  const std::string head = spec.substr(0, colon);
  if (!exists(head)) return;
  file = head;
  layer = spec.substr(colon + 1);
}

LineReadStats read_layer(const std::string& spec, const LineReadOptions& options, LineData& out) {
  if (!options.z_field.empty() && options.z_from_m) {
    throw InputError(spec, "", "a z field and z from M values exclude each other");
  }
  std::string file;
  std::string layer_name;
  split_spec(spec, file, layer_name);
  if (!options.layer.empty()) layer_name = options.layer;
  if (out.files.size() >= kMaxIndex) throw InputError(file, "", "too many input files");

  ensure_drivers();
  LineReadStats stats;
  GdalErrors errors;
  const Dataset ds(
      GDALOpenEx(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (ds.get() == nullptr) {
    if (!starts_with(file, "/vsi") && !exists(file)) {
      const bool maybe_connection = file.find(':') != std::string::npos;
      throw InputError(file, "",
                       maybe_connection ? "no such file, and GDAL cannot open it: " +
                                              GdalErrors::last("not a vector source")
                                        : std::string("no such file"));
    }
    throw InputError(file, "",
                     "cannot open as a vector source: " +
                         GdalErrors::last("not a format GDAL can read as vectors"));
  }

  OGRLayerH layer = nullptr;
  const std::vector<std::string> layers = layer_names(ds.get());
  if (!layer_name.empty()) {
    layer = GDALDatasetGetLayerByName(ds.get(), layer_name.c_str());
    if (layer == nullptr) {
      throw InputError(file, "",
                       "no layer '" + layer_name + "' (layers: " +
                           (layers.empty() ? std::string("none") : join(layers)) + ")");
    }
  } else if (layers.empty()) {
    throw InputError(file, "", "no vector layer");
  } else if (layers.size() > 1) {
    throw InputError(file, "",
                     std::to_string(layers.size()) + " layers (" + join(layers) +
                         "): name one as FILE:LAYER or with --layer");
  } else {
    layer = GDALDatasetGetLayer(ds.get(), 0);
  }
  stats.layer = OGR_L_GetName(layer);
  stats.crs_wkt = export_crs(OGR_L_GetSpatialRef(layer));

  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
  const std::string fields = field_list(defn);
  ZSource z_source = ZSource::kGeometry;
  int z_field = -1;
  if (!options.z_field.empty()) {
    z_source = ZSource::kField;
    z_field = OGR_FD_GetFieldIndex(defn, options.z_field.c_str());
    if (z_field < 0) {
      throw InputError(file, "layer " + stats.layer,
                       "no field '" + options.z_field + "' (fields: " + fields + ")");
    }
    const OGRFieldType type = OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, z_field));
    if (type != OFTInteger && type != OFTInteger64 && type != OFTReal && type != OFTString) {
      throw InputError(file, "layer " + stats.layer,
                       "the z field '" + options.z_field + "' is of type " +
                           OGR_GetFieldTypeName(type) + ", not a number");
    }
  } else if (options.z_from_m) {
    z_source = ZSource::kMeasure;
  }

  // Only the geometry and the z field are needed: the drivers may skip the rest.
  {
    std::vector<std::string> ignored{"OGR_STYLE"};
    const int n = OGR_FD_GetFieldCount(defn);
    for (int i = 0; i < n; ++i) {
      if (i != z_field) ignored.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i)));
    }
    std::vector<const char*> list;
    list.reserve(ignored.size() + 1);
    for (const std::string& name : ignored) list.push_back(name.c_str());
    list.push_back(nullptr);
    OGR_L_SetIgnoredFields(layer, list.data());
  }

  const std::string file_spec = layer_name.empty() ? file : file + ":" + layer_name;
  const auto file_index = static_cast<std::uint32_t>(out.files.size());
  const GIntBig expected = OGR_L_GetFeatureCount(layer, FALSE);
  if (expected > 0 && static_cast<std::uint64_t>(expected) < kMaxIndex) {
    out.features.reserve(out.features.size() + static_cast<std::size_t>(expected));
  }

  LayerReader reader(file, stats.layer, z_source, z_field, fields, file_index, out, stats);
  OGR_L_ResetReading(layer);
  errors.reset_failure();
  std::int64_t ordinal = 0;
  std::int64_t last_fid = -1;
  for (;;) {
    const Feature feature(OGR_L_GetNextFeature(layer));
    if (feature.get() == nullptr) break;
    const GIntBig fid = OGR_F_GetFID(feature.get());
    last_fid = fid != OGRNullFID ? static_cast<std::int64_t>(fid) : ordinal;
    ++ordinal;
    reader.read_feature(feature.get(), last_fid);
    if (errors.failed()) break;
  }
  if (errors.failed()) {
    throw InputError(file,
                     "layer " + stats.layer +
                         (last_fid >= 0 ? ", after feature " + std::to_string(last_fid) : ""),
                     "reading failed: " + errors.failure());
  }

  out.files.push_back(file_spec);
  for (const std::string& w : errors.warnings()) stats.warnings.push_back(file + ": " + w);
  if (reader.curves() > 0) {
    stats.warnings.push_back(file + ": layer " + stats.layer + ": " +
                             std::to_string(reader.curves()) +
                             " curved geometries approximated by line strings");
  }
  return stats;
}

}  // namespace

LineReadStats read_lines(const std::string& path, const LineReadOptions& options, LineData& out) {
  const std::size_t vertices = out.vertices.size();
  const std::size_t segments = out.segments.size();
  const std::size_t features = out.features.size();
  const std::size_t files = out.files.size();
  const std::size_t skipped = out.skipped.size();
  const std::size_t dropped = out.dropped.size();
  try {
    return read_layer(path, options, out);
  } catch (...) {
    out.vertices.resize(vertices);
    out.segments.resize(segments);
    out.features.resize(features);
    out.files.resize(files);
    out.skipped.resize(skipped);
    out.dropped.resize(dropped);
    throw;
  }
}

}  // namespace tincdt::io
