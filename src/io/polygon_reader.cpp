// Polygon and draped-line reader: see polygon_reader.hpp. Opening the source and choosing the
// layer follow the contour reader (line_reader.cpp) so that both accept the same specs and say
// the same things about them.
#include "io/polygon_reader.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class Kind { polygons, lines };

void ensure_drivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// For the scope: GDAL prints nothing; warnings are kept, and a failure in the middle of a layer
// is remembered so that it is not mistaken for the layer's end.
class GdalErrors {
 public:
  GdalErrors() {
    CPLPushErrorHandlerEx(&GdalErrors::handle, this);
    CPLErrorReset();
  }
  GdalErrors(const GdalErrors&) = delete;
  GdalErrors& operator=(const GdalErrors&) = delete;
  ~GdalErrors() { CPLPopErrorHandler(); }

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
  const std::vector<std::string>& warnings() const { return warnings_; }

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

// Owns a GDAL handle: a dataset, a feature or a geometry.
template <class H, void (*Free)(H)>
class Owned {
 public:
  explicit Owned(H h) : h_(h) {}
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (h_ != nullptr) Free(h_);
  }
  H get() const { return h_; }

 private:
  H h_;
};

void close_dataset(GDALDatasetH h) {
  GDALClose(h);
}
using Dataset = Owned<GDALDatasetH, close_dataset>;
using Feature = Owned<OGRFeatureH, OGR_F_Destroy>;
using Geometry = Owned<OGRGeometryH, OGR_G_DestroyGeometry>;

bool exists(const std::string& path) {
  VSIStatBufL st;
  return VSIStatExL(path.c_str(), &st, VSI_STAT_EXISTS_FLAG) == 0;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out.empty() ? std::string("none") : out;
}

// "FILE:LAYER" -> FILE, LAYER at the last ':', only when FILE exists and the whole does not.
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

// The layer's CRS as WKT2 (WKT1 when OSR cannot); "" for none, including the GeoPackage
// placeholders for "undefined".
std::string export_crs(OGRSpatialReferenceH srs) {
  if (srs == nullptr) return {};
  const char* name = OSRGetName(srs);
  if (name != nullptr && OSRGetAuthorityName(srs, nullptr) == nullptr &&
      (std::strcmp(name, "Undefined geographic SRS") == 0 ||
       std::strcmp(name, "Undefined Cartesian SRS") == 0))
    return {};
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

std::string field_list(OGRFeatureDefnH defn) {
  std::vector<std::string> names;
  const int n = OGR_FD_GetFieldCount(defn);
  for (int i = 0; i < n; ++i) names.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i)));
  return join(names);
}

// Reads the features of one layer.
class LayerReader {
 public:
  LayerReader(Kind kind, const ShapeReadOptions& options, std::string file, std::string layer,
              int z_field, std::string fields, std::uint32_t file_index, ShapeData& out,
              ShapeReadStats& stats)
      : kind_(kind),
        options_(options),
        file_(std::move(file)),
        layer_(std::move(layer)),
        z_field_(z_field),
        fields_(std::move(fields)),
        file_index_(file_index),
        out_(out),
        stats_(stats) {}

  void read_feature(OGRFeatureH feature, std::int64_t fid) {
    ++stats_.features;
    fid_ = fid;
    current_ = ShapeFeature{file_index_, fid, kNaN, {}};
    unsupported_.clear();
    degenerate_ = false;
    has_at_ = false;
    z_min_ = std::numeric_limits<double>::infinity();
    z_max_ = -z_min_;
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
    if (current_.parts.empty()) {
      ++stats_.empty_features;
      out_.dropped.push_back({file_index_, fid_, drop_reason(geometry), at_, has_at_});
      return;
    }
    if (options_.feature_z) current_.z = feature_z(feature);
    for (const ShapePart& part : current_.parts) {
      ++stats_.parts;
      stats_.vertices += part.points.size();
      stats_.segments += part.closed ? part.points.size() : part.points.size() - 1;
    }
    out_.features.push_back(std::move(current_));
  }

  std::uint64_t curves() const { return curves_; }

 private:
  [[noreturn]] void fail(const std::string& detail) const {
    throw InputError(file_, "layer " + layer_ + ", feature " + std::to_string(fid_), detail);
  }

  std::string drop_reason(OGRGeometryH geometry) const {
    if (geometry == nullptr) return "no geometry";
    if (OGR_G_IsEmpty(geometry)) return "empty geometry";
    std::string reason;
    if (degenerate_)
      reason = kind_ == Kind::polygons ? "degenerate: no ring with 3 distinct vertices"
                                       : "degenerate: no line with 2 distinct vertices";
    if (!unsupported_.empty()) {
      if (!reason.empty()) reason += "; ";
      reason += unsupported_ + (kind_ == Kind::polygons
                                    ? " geometry: only polygons are used"
                                    : " geometry: only lines and polygon rings are used");
    }
    return reason.empty() ? std::string("no usable geometry") : reason;
  }

  void note_location(const Point3& p) {
    if (has_at_) return;
    at_ = p;
    has_at_ = true;
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

  void note_unsupported(OGRGeometryH g) {
    if (unsupported_.empty()) unsupported_ = OGRGeometryTypeToName(OGR_G_GetGeometryType(g));
    Point3 p{};
    if (first_vertex(g, p)) note_location(p);
  }

  void add_geometry(OGRGeometryH g) {
    switch (wkbFlatten(OGR_G_GetGeometryType(g))) {
      case wkbPolygon:
      case wkbTriangle: {
        const int n = OGR_G_GetGeometryCount(g);
        for (int i = 0; i < n; ++i) add_part(OGR_G_GetGeometryRef(g, i), true);
        break;
      }
      case wkbLineString:
      case wkbLinearRing:
        if (kind_ == Kind::lines)
          add_part(g, false);
        else
          note_unsupported(g);
        break;
      case wkbMultiPolygon:
      case wkbMultiLineString:
      case wkbGeometryCollection: {
        const int n = OGR_G_GetGeometryCount(g);
        for (int i = 0; i < n; ++i) add_geometry(OGR_G_GetGeometryRef(g, i));
        break;
      }
      default:  // points, surfaces
        note_unsupported(g);
        break;
    }
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
    const auto n = static_cast<std::size_t>(count);
    std::vector<Point3> p(n, Point3{0, 0, kNaN});
    std::vector<double> m(has_m ? n : 0);
    constexpr int kStride = static_cast<int>(sizeof(Point3));
    OGR_G_GetPointsZM(g, &p[0].x, kStride, &p[0].y, kStride, has_z ? &p[0].z : nullptr, kStride,
                      has_m ? m.data() : nullptr, static_cast<int>(sizeof(double)));
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || (has_z && !std::isfinite(p[i].z)))
        fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    if (options_.feature_z) note_heights(has_z, has_m, p, m);

    // Collapse runs of the same x, y (keeping the first z).
    std::size_t k = 1;
    for (std::size_t r = 1; r < n; ++r) {
      if (p[r].x == p[k - 1].x && p[r].y == p[k - 1].y) {
        out_.skipped.push_back({p[r], file_index_, fid_});
        ++stats_.repeated_vertices;
        continue;
      }
      if (r != k) p[k] = p[r];
      ++k;
    }
    bool closed = ring;
    if (k >= 2 && p[k - 1].x == p[0].x && p[k - 1].y == p[0].y) {
      --k;
      closed = true;
    }
    const std::size_t needed = ring ? 3 : 2;
    if (k < needed) {
      note_location(p[0]);
      degenerate_ = true;
      ++stats_.degenerate_parts;
      return;
    }
    if (k == 2) closed = false;  // A-B-A is the single segment A-B
    p.resize(k);
    current_.parts.push_back({std::move(p), closed});
  }

  // Remembers the range of the values a feature z could come from (M or Z).
  void note_heights(bool has_z, bool has_m, const std::vector<Point3>& p,
                    const std::vector<double>& m) {
    if (!options_.z_field.empty()) return;
    if (options_.z_from_m) {
      if (!has_m) fail("the geometry has no M values to take z from");
      for (const double v : m) {
        if (!std::isfinite(v)) fail("an M value is not finite");
        z_min_ = std::min(z_min_, v);
        z_max_ = std::max(z_max_, v);
      }
      return;
    }
    if (!has_z)
      fail("2D polygon has no z for --replace: pass --z-field NAME (fields: " + fields_ +
           ") or use a 3D layer");
    for (const Point3& q : p) {
      z_min_ = std::min(z_min_, q.z);
      z_max_ = std::max(z_max_, q.z);
    }
  }

  double feature_z(OGRFeatureH feature) {
    if (!options_.z_field.empty()) {
      const std::string name = OGR_Fld_GetNameRef(OGR_F_GetFieldDefnRef(feature, z_field_));
      if (!OGR_F_IsFieldSetAndNotNull(feature, z_field_)) fail("the z field " + name + " is NULL");
      const OGRFieldType type = OGR_Fld_GetType(OGR_F_GetFieldDefnRef(feature, z_field_));
      double z = 0;
      if (type == OFTInteger || type == OFTInteger64 || type == OFTReal) {
        z = OGR_F_GetFieldAsDouble(feature, z_field_);
      } else {  // text: only a complete number counts, never a silent 0
        const char* text = OGR_F_GetFieldAsString(feature, z_field_);
        char* end = nullptr;
        z = CPLStrtod(text, &end);
        while (end != nullptr && (*end == ' ' || *end == '\t')) ++end;
        if (end == text || end == nullptr || *end != '\0')
          fail("the z field " + name + " holds '" + std::string(text) + "', which is not a number");
      }
      if (!std::isfinite(z)) fail("the z field " + name + " is not finite");
      return z;
    }
    if (z_min_ != z_max_) {
      char range[96];
      std::snprintf(range, sizeof range, "%.17g to %.17g", z_min_, z_max_);
      fail(std::string("a replace polygon has one z, but its ") +
           (options_.z_from_m ? "M values" : "vertices' z") + " range from " + range +
           " (give the level in an attribute with --z-field NAME)");
    }
    return z_min_;
  }

  const Kind kind_;
  const ShapeReadOptions& options_;
  const std::string file_;
  const std::string layer_;
  const int z_field_;
  const std::string fields_;
  const std::uint32_t file_index_;
  ShapeData& out_;
  ShapeReadStats& stats_;

  ShapeFeature current_;
  std::int64_t fid_ = 0;
  std::uint64_t curves_ = 0;
  std::string unsupported_;
  bool degenerate_ = false;
  bool has_at_ = false;
  Point3 at_{0, 0, 0};
  double z_min_ = 0, z_max_ = 0;
};

ShapeReadStats read_layer(Kind kind, const std::string& spec, const ShapeReadOptions& options,
                          ShapeData& out) {
  if (options.feature_z && !options.z_field.empty() && options.z_from_m)
    throw InputError(spec, "", "a z field and z from M values exclude each other");
  std::string file, layer_name;
  split_spec(spec, file, layer_name);
  if (!options.layer.empty()) layer_name = options.layer;
  if (out.files.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InputError(file, "", "too many input files");

  ensure_drivers();
  ShapeReadStats stats;
  GdalErrors errors;
  const Dataset ds(
      GDALOpenEx(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (ds.get() == nullptr) {
    if (file.rfind("/vsi", 0) != 0 && !exists(file)) {
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

  std::vector<std::string> layers;
  for (int i = 0; i < GDALDatasetGetLayerCount(ds.get()); ++i)
    layers.emplace_back(OGR_L_GetName(GDALDatasetGetLayer(ds.get(), i)));
  OGRLayerH layer = nullptr;
  if (!layer_name.empty()) {
    layer = GDALDatasetGetLayerByName(ds.get(), layer_name.c_str());
    if (layer == nullptr)
      throw InputError(file, "", "no layer '" + layer_name + "' (layers: " + join(layers) + ")");
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
  int z_field = -1;
  if (options.feature_z && !options.z_field.empty()) {
    z_field = OGR_FD_GetFieldIndex(defn, options.z_field.c_str());
    if (z_field < 0)
      throw InputError(file, "layer " + stats.layer,
                       "no field '" + options.z_field + "' (fields: " + fields + ")");
    const OGRFieldType type = OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, z_field));
    if (type != OFTInteger && type != OFTInteger64 && type != OFTReal && type != OFTString)
      throw InputError(file, "layer " + stats.layer,
                       "the z field '" + options.z_field + "' is of type " +
                           OGR_GetFieldTypeName(type) + ", not a number");
  }
  {  // only the geometry and the z field are needed
    std::vector<std::string> ignored{"OGR_STYLE"};
    for (int i = 0; i < OGR_FD_GetFieldCount(defn); ++i)
      if (i != z_field) ignored.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i)));
    std::vector<const char*> list;
    for (const std::string& name : ignored) list.push_back(name.c_str());
    list.push_back(nullptr);
    OGR_L_SetIgnoredFields(layer, list.data());
  }

  const auto file_index = static_cast<std::uint32_t>(out.files.size());
  LayerReader reader(kind, options, file, stats.layer, z_field, fields, file_index, out, stats);
  OGR_L_ResetReading(layer);
  errors.reset_failure();
  std::int64_t ordinal = 0, last_fid = -1;
  for (;;) {
    const Feature feature(OGR_L_GetNextFeature(layer));
    if (feature.get() == nullptr) break;
    const GIntBig fid = OGR_F_GetFID(feature.get());
    last_fid = fid != OGRNullFID ? static_cast<std::int64_t>(fid) : ordinal;
    ++ordinal;
    reader.read_feature(feature.get(), last_fid);
    if (errors.failed()) break;
  }
  if (errors.failed())
    throw InputError(file,
                     "layer " + stats.layer +
                         (last_fid >= 0 ? ", after feature " + std::to_string(last_fid) : ""),
                     "reading failed: " + errors.failure());

  out.files.push_back(layer_name.empty() ? file : file + ":" + layer_name);
  for (const std::string& w : errors.warnings()) stats.warnings.push_back(file + ": " + w);
  if (reader.curves() > 0)
    stats.warnings.push_back(file + ": layer " + stats.layer + ": " +
                             std::to_string(reader.curves()) +
                             " curved geometries approximated by line strings");
  return stats;
}

ShapeReadStats read(Kind kind, const std::string& path, const ShapeReadOptions& options,
                    ShapeData& out) {
  const std::size_t features = out.features.size(), files = out.files.size(),
                    skipped = out.skipped.size(), dropped = out.dropped.size();
  try {
    return read_layer(kind, path, options, out);
  } catch (...) {
    out.features.resize(features);
    out.files.resize(files);
    out.skipped.resize(skipped);
    out.dropped.resize(dropped);
    throw;
  }
}

}  // namespace

ShapeReadStats read_polygons(const std::string& path, const ShapeReadOptions& options,
                             ShapeData& out) {
  return read(Kind::polygons, path, options, out);
}

ShapeReadStats read_shape_lines(const std::string& path, const ShapeReadOptions& options,
                                ShapeData& out) {
  return read(Kind::lines, path, options, out);
}

}  // namespace tincdt::io
