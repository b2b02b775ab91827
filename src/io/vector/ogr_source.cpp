// Shared parts of the OGR readers: see ogr_source.hpp.
#include "io/vector/ogr_source.hpp"

#include <cpl_conv.h>
#include <cpl_vsi.h>

#include <cmath>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/crs_detail.hpp"

namespace tincdt::io::detail {
namespace {

constexpr std::size_t kMaxWarnings = 20;

void ensure_drivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

bool exists(const std::string& path) {
  VSIStatBufL st;
  return VSIStatExL(path.c_str(), &st, VSI_STAT_EXISTS_FLAG) == 0;
}

// "a, b, c", or "none" for no items.
std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out.empty() ? std::string("none") : out;
}

bool first_vertex(OGRGeometryH g, Point3& p) {
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

}  // namespace

// ---- GdalErrors, handles ----

GdalErrors::GdalErrors() {
  CPLPushErrorHandlerEx(&GdalErrors::handle, this);
  CPLErrorReset();
}

GdalErrors::~GdalErrors() {
  CPLPopErrorHandler();
}

std::string GdalErrors::last(const char* fallback) {
  const char* msg = CPLGetLastErrorMsg();
  return (msg != nullptr && *msg != '\0') ? std::string(msg) : std::string(fallback);
}

void CPL_STDCALL GdalErrors::handle(CPLErr level, CPLErrorNum, const char* msg) {
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

void close_dataset(GDALDatasetH h) {
  GDALClose(h);
}

void check_z_options(const std::string& spec, const std::string& z_field, bool z_from_m) {
  if (!z_field.empty() && z_from_m) {
    throw InputError(spec, "", "a z field and z from M values exclude each other");
  }
}

// ---- OgrLayer ----

OgrLayer::Spec OgrLayer::prepare(const std::string& spec, const std::string& layer_option,
                                 std::size_t files_read) {
  Spec out{spec, {}};
  if (!exists(spec)) {
    const std::size_t colon = spec.rfind(':');
    if (colon != std::string::npos && colon != 0 && exists(spec.substr(0, colon))) {
      out.file = spec.substr(0, colon);
      out.layer = spec.substr(colon + 1);
    }
  }
  if (!layer_option.empty()) out.layer = layer_option;
  if (files_read >= kMaxIndex) throw InputError(out.file, "", "too many input files");
  ensure_drivers();
  return out;
}

GDALDatasetH OgrLayer::open(const std::string& file) {
  GDALDatasetH ds =
      GDALOpenEx(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (ds != nullptr) return ds;
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

OgrLayer::OgrLayer(const std::string& spec, const std::string& layer_option, std::size_t files_read)
    : spec_(prepare(spec, layer_option, files_read)), ds_(open(spec_.file)) {
  const std::string& file = spec_.file;
  std::vector<std::string> layers;
  const int n = GDALDatasetGetLayerCount(ds_.get());
  for (int i = 0; i < n; ++i) layers.emplace_back(OGR_L_GetName(GDALDatasetGetLayer(ds_.get(), i)));
  if (!spec_.layer.empty()) {
    layer_ = GDALDatasetGetLayerByName(ds_.get(), spec_.layer.c_str());
    if (layer_ == nullptr) {
      throw InputError(file, "", "no layer '" + spec_.layer + "' (layers: " + join(layers) + ")");
    }
  } else if (layers.empty()) {
    throw InputError(file, "", "no vector layer");
  } else if (layers.size() > 1) {
    throw InputError(file, "",
                     std::to_string(layers.size()) + " layers (" + join(layers) +
                         "): name one as FILE:LAYER or with --layer");
  } else {
    layer_ = GDALDatasetGetLayer(ds_.get(), 0);
  }
  name_ = OGR_L_GetName(layer_);
  defn_ = OGR_L_GetLayerDefn(layer_);
  std::vector<std::string> names;
  const int fields = OGR_FD_GetFieldCount(defn_);
  for (int i = 0; i < fields; ++i) {
    names.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn_, i)));
  }
  fields_ = join(names);
}

std::string OgrLayer::spec() const {
  return spec_.layer.empty() ? spec_.file : spec_.file + ":" + spec_.layer;
}

std::string OgrLayer::crs_wkt() const {
  return crs_of_layer(OGR_L_GetSpatialRef(layer_));
}

ZSource OgrLayer::choose_z(const std::string& z_field, bool z_from_m, int* field) const {
  *field = -1;
  if (z_field.empty()) return z_from_m ? ZSource::kMeasure : ZSource::kGeometry;
  *field = OGR_FD_GetFieldIndex(defn_, z_field.c_str());
  if (*field < 0) {
    throw InputError(spec_.file, "layer " + name_,
                     "no field '" + z_field + "' (fields: " + fields_ + ")");
  }
  const OGRFieldType type = OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn_, *field));
  if (type != OFTInteger && type != OFTInteger64 && type != OFTReal && type != OFTString) {
    throw InputError(spec_.file, "layer " + name_,
                     "the z field '" + z_field + "' is of type " + OGR_GetFieldTypeName(type) +
                         ", not a number");
  }
  return ZSource::kField;
}

void OgrLayer::ignore_fields_except(int keep) const {
  std::vector<std::string> ignored{"OGR_STYLE"};
  const int n = OGR_FD_GetFieldCount(defn_);
  for (int i = 0; i < n; ++i) {
    if (i != keep) ignored.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn_, i)));
  }
  std::vector<const char*> list;
  list.reserve(ignored.size() + 1);
  for (const std::string& name : ignored) list.push_back(name.c_str());
  list.push_back(nullptr);
  OGR_L_SetIgnoredFields(layer_, list.data());
}

void OgrLayer::reading_failed(std::int64_t last_fid) const {
  throw InputError(
      spec_.file,
      "layer " + name_ + (last_fid >= 0 ? ", after feature " + std::to_string(last_fid) : ""),
      "reading failed: " + errors_.failure());
}

void OgrLayer::add_warnings(std::uint64_t curves, std::vector<std::string>& warnings) const {
  for (const std::string& w : errors_.warnings()) warnings.push_back(spec_.file + ": " + w);
  if (curves > 0) {
    warnings.push_back(spec_.file + ": layer " + name_ + ": " + std::to_string(curves) +
                       " curved geometries approximated by line strings");
  }
}

// ---- FeatureReader ----

FeatureReader::FeatureReader(const OgrLayer& layer, int z_field, std::uint32_t file_index,
                             bool take_lines, const DropReasons& reasons,
                             std::vector<LineSkip>& skipped, std::vector<LineDrop>& dropped,
                             std::uint64_t& degenerate_parts)
    : file_(layer.file()),
      layer_(layer.name()),
      fields_(layer.fields()),
      z_field_(z_field),
      file_index_(file_index),
      take_lines_(take_lines),
      reasons_(reasons),
      skipped_(skipped),
      dropped_(dropped),
      degenerate_parts_(degenerate_parts) {}

OGRGeometryH FeatureReader::walk(OGRFeatureH feature, std::int64_t fid) {
  fid_ = fid;
  unsupported_.clear();
  degenerate_ = false;
  has_at_ = false;
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
  return geometry;
}

void FeatureReader::add_geometry(OGRGeometryH g) {
  switch (wkbFlatten(OGR_G_GetGeometryType(g))) {
    case wkbLineString:
    case wkbLinearRing:
      if (take_lines_) {
        take_part(g, false);
      } else {
        note_unsupported(g);
      }
      break;
    case wkbPolygon:
    case wkbTriangle: {
      const int n = OGR_G_GetGeometryCount(g);
      for (int i = 0; i < n; ++i) take_part(OGR_G_GetGeometryRef(g, i), true);
      break;
    }
    case wkbMultiLineString:
    case wkbMultiPolygon:
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

void FeatureReader::take_part(OGRGeometryH g, bool ring) {
  const int count = OGR_G_GetPointCount(g);
  if (count <= 0) {
    ++degenerate_parts_;
    degenerate_ = true;
    return;
  }
  add_part(
      {g, static_cast<std::size_t>(count), OGR_G_Is3D(g) != 0, OGR_G_IsMeasured(g) != 0, ring});
}

void FeatureReader::note_degenerate(const Point3& at) {
  note_location(at);
  degenerate_ = true;
  ++degenerate_parts_;
}

// The first location of a problem in the feature, for the dropped-feature record.
void FeatureReader::note_location(const Point3& p) {
  if (has_at_) return;
  at_ = p;
  has_at_ = true;
}

// A geometry the reader does not use: its name and first vertex.
void FeatureReader::note_unsupported(OGRGeometryH g) {
  if (unsupported_.empty()) unsupported_ = OGRGeometryTypeToName(OGR_G_GetGeometryType(g));
  Point3 p{};
  if (first_vertex(g, p)) note_location(p);
}

std::string FeatureReader::drop_reason(OGRGeometryH geometry) const {
  if (geometry == nullptr) return "no geometry";
  if (OGR_G_IsEmpty(geometry)) return "empty geometry";
  std::string reason;
  if (degenerate_) reason = reasons_.degenerate;
  if (!unsupported_.empty()) {
    if (!reason.empty()) reason += "; ";
    reason += unsupported_ + reasons_.unsupported;
  }
  return reason.empty() ? std::string(reasons_.none) : reason;
}

void FeatureReader::drop(OGRGeometryH geometry) {
  dropped_.push_back({file_index_, fid_, drop_reason(geometry), at_, has_at_});
}

void FeatureReader::fail(const std::string& detail) const {
  throw InputError(file_, "layer " + layer_ + ", feature " + std::to_string(fid_), detail);
}

void FeatureReader::check_z(ZSource source, bool has_z, bool has_m, const char* no_z_what) const {
  if (source == ZSource::kMeasure && !has_m) fail("the geometry has no M values to take z from");
  if (source == ZSource::kGeometry && !has_z) {
    fail(std::string(no_z_what) + ": pass --z-field NAME (fields: " + fields_ +
         ") or use a 3D layer");
  }
}

double FeatureReader::field_z(OGRFeatureH feature) const {
  const std::string name = OGR_Fld_GetNameRef(OGR_F_GetFieldDefnRef(feature, z_field_));
  if (!OGR_F_IsFieldSetAndNotNull(feature, z_field_)) fail("the z field " + name + " is NULL");
  const OGRFieldType type = OGR_Fld_GetType(OGR_F_GetFieldDefnRef(feature, z_field_));
  double z = 0;
  if (type == OFTInteger || type == OFTInteger64 || type == OFTReal) {
    z = OGR_F_GetFieldAsDouble(feature, z_field_);
  } else {  // text: only a complete number counts, never a silent 0
    const char* text = OGR_F_GetFieldAsString(feature, z_field_);
    char* end = nullptr;
    z = CPLStrtod(text, &end);  // "." as the decimal mark whatever the locale
    while (end != nullptr && (*end == ' ' || *end == '\t')) ++end;
    if (end == text || end == nullptr || *end != '\0') {
      fail("the z field " + name + " holds '" + std::string(text) + "', which is not a number");
    }
  }
  if (!std::isfinite(z)) fail("the z field " + name + " is not finite");
  return z;
}

void FeatureReader::check_finite(const Point3* p, std::size_t n, bool check_z) const {
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || (check_z && !std::isfinite(p[i].z))) {
      fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
}

FeatureReader::Collapsed FeatureReader::collapse(Point3* p, std::size_t n, bool ring) {
  std::size_t k = 1;
  for (std::size_t r = 1; r < n; ++r) {
    if (p[r].x == p[k - 1].x && p[r].y == p[k - 1].y) {
      skipped_.push_back({p[r], file_index_, fid_});
      continue;
    }
    if (r != k) p[k] = p[r];
    ++k;
  }
  const std::size_t repeats = n - k;
  // A ring, or a line that ends where it starts: the closing vertex is the first one.
  bool closed = ring;
  if (k >= 2 && p[k - 1].x == p[0].x && p[k - 1].y == p[0].y) {
    --k;
    closed = true;
  }
  if (k == 2) closed = false;  // A-B-A is the single segment A-B
  return {k, repeats, closed};
}

}  // namespace tincdt::io::detail
