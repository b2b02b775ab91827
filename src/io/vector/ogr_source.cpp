// Shared parts of the OGR readers: see ogr_source.hpp.
#include "io/vector/ogr_source.hpp"

#include <cpl_conv.h>
#include <cpl_vsi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs_detail.hpp"

namespace tincdt::io::detail {
namespace {

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

// The first vertex of any geometry: a point, a curve, or the first of the parts of a surface or
// collection that has one (z 0 when 2D).
bool first_vertex(const OGRGeometry& g, Point3& p) {
  if (g.IsEmpty()) return false;
  const OGRwkbGeometryType type = wkbFlatten(g.getGeometryType());
  OGRPoint q;
  if (type == wkbPoint) {
    q = *g.toPoint();
  } else if (OGR_GT_IsCurve(type)) {
    g.toCurve()->StartPoint(&q);
  } else if (OGR_GT_IsSubClassOf(type, wkbCurvePolygon)) {
    for (const OGRCurve* ring : *g.toCurvePolygon())
      if (first_vertex(*ring, p)) return true;
    return false;
  } else if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
    for (const OGRGeometry* part : *g.toGeometryCollection())
      if (first_vertex(*part, p)) return true;
    return false;
  } else if (OGR_GT_IsSubClassOf(type, wkbPolyhedralSurface)) {
    for (const OGRPolygon* part : *g.toPolyhedralSurface())
      if (first_vertex(*part, p)) return true;
    return false;
  } else {
    return false;
  }
  p = {q.getX(), q.getY(), q.getZ()};
  return true;
}

}  // namespace

void check_z_options(const std::string& spec, const std::string& z_field, bool z_from_m) {
  if (!z_field.empty() && z_from_m) {
    throw InputError(spec, "", "a z field and z from M values exclude each other");
  }
}

}  // namespace tincdt::io::detail

namespace tincdt::io {

std::string vector_source_file(const std::string& spec) {
  if (detail::exists(spec)) return spec;
  const std::size_t colon = spec.rfind(':');
  if (colon != std::string::npos && colon != 0 && detail::exists(spec.substr(0, colon)))
    return spec.substr(0, colon);
  return spec;
}

}  // namespace tincdt::io

namespace tincdt::io::detail {

// ---- OgrLayer ----

OgrLayer::Spec OgrLayer::prepare(const std::string& spec, const std::string& layer_option,
                                 std::size_t files_read) {
  Spec out{vector_source_file(spec), {}};
  if (out.file.size() < spec.size()) out.layer = spec.substr(out.file.size() + 1);
  if (!layer_option.empty()) out.layer = layer_option;
  if (files_read >= kMaxIndex) throw InputError(out.file, "", "too many input files");
  register_gdal_drivers();
  return out;
}

GdalDataset OgrLayer::open(const std::string& file) {
  GdalDataset ds(GDALDataset::Open(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (ds) return ds;
  if (file.rfind("/vsi", 0) != 0 && !exists(file)) {
    const bool maybe_connection = file.find(':') != std::string::npos;
    throw InputError(file, "",
                     maybe_connection ? "no such file, and GDAL cannot open it: " +
                                            last_gdal_message("not a vector source")
                                      : std::string("no such file"));
  }
  throw InputError(file, "",
                   "cannot open as a vector source: " +
                       last_gdal_message("not a format GDAL can read as vectors"));
}

OgrLayer::OgrLayer(const std::string& spec, const std::string& layer_option, std::size_t files_read)
    : spec_(prepare(spec, layer_option, files_read)), ds_(open(spec_.file)) {
  const std::string& file = spec_.file;
  std::vector<std::string> layers;
  for (OGRLayer* layer : ds_->GetLayers()) layers.emplace_back(layer->GetName());
  if (!spec_.layer.empty()) {
    layer_ = ds_->GetLayerByName(spec_.layer.c_str());
    if (layer_ == nullptr) {
      throw InputError(file, "", "no layer '" + spec_.layer + "' (layers: " + join(layers) + ")");
    }
  } else if (layers.empty()) {
    throw InputError(file, "", "no vector layer");
  } else if (layers.size() > 1) {
    throw InputError(
        file, "",
        count_text(layers.size()) + " layers (" + join(layers) + "): name one as FILE:LAYER",
        Remedy::choose_layer);
  } else {
    layer_ = ds_->GetLayer(0);
  }
  name_ = layer_->GetName();
  defn_ = layer_->GetLayerDefn();
  std::vector<std::string> names;
  const int fields = defn_->GetFieldCount();
  for (int i = 0; i < fields; ++i) names.emplace_back(defn_->GetFieldDefn(i)->GetNameRef());
  fields_ = join(names);
}

std::string OgrLayer::spec() const {
  return spec_.layer.empty() ? spec_.file : spec_.file + ":" + spec_.layer;
}

std::string OgrLayer::crs_wkt() const {
  return crs_of_layer(layer_->GetSpatialRef());
}

bool OgrLayer::crs_implied() const {
  return EQUAL(ds_->GetDriverName(), "GeoJSON") && !geojson_names_crs(spec_.file);
}

std::string OgrLayer::implied_crs_wkt() const {
  return crs_implied() ? crs_wkt() : std::string();
}

ZSource OgrLayer::choose_z(const std::string& z_field, bool z_from_m, int* field) const {
  *field = -1;
  if (z_field.empty()) return z_from_m ? ZSource::kMeasure : ZSource::kGeometry;
  *field = defn_->GetFieldIndex(z_field.c_str());
  if (*field < 0) {
    throw InputError(spec_.file, "layer " + name_,
                     "no field '" + z_field + "' (fields: " + fields_ + ")");
  }
  const OGRFieldType type = defn_->GetFieldDefn(*field)->GetType();
  if (type != OFTInteger && type != OFTInteger64 && type != OFTReal && type != OFTString) {
    throw InputError(spec_.file, "layer " + name_,
                     "the z field '" + z_field + "' is of type " +
                         OGRFieldDefn::GetFieldTypeName(type) + ", not a number");
  }
  return ZSource::kField;
}

void OgrLayer::ignore_fields_except(int keep) const {
  std::vector<std::string> ignored{"OGR_STYLE"};
  const int n = defn_->GetFieldCount();
  for (int i = 0; i < n; ++i) {
    if (i != keep) ignored.emplace_back(defn_->GetFieldDefn(i)->GetNameRef());
  }
  std::vector<const char*> list;
  list.reserve(ignored.size() + 1);
  for (const std::string& name : ignored) list.push_back(name.c_str());
  list.push_back(nullptr);
  layer_->SetIgnoredFields(list.data());
}

void OgrLayer::reading_failed(std::int64_t last_fid) const {
  throw InputError(
      spec_.file,
      "layer " + name_ + (last_fid >= 0 ? ", after feature " + signed_count_text(last_fid) : ""),
      "reading failed: " + messages_.failure());
}

void OgrLayer::add_warnings(std::uint64_t curves, std::vector<std::string>& warnings) const {
  for (const std::string& w : messages_.warnings()) warnings.push_back(spec_.file + ": " + w);
  if (curves > 0) {
    warnings.push_back(spec_.file + ": layer " + name_ + ": " + count_text(curves) +
                       " curved geometries approximated by line strings");
  }
}

void OgrLayer::check_usable(const Yield& yield, const std::vector<LineDrop>& dropped,
                            std::size_t first, std::vector<std::string>& warnings) const {
  // "no geometry (3 features); Point geometry: only ... (1 feature)", in order of appearance.
  std::vector<std::pair<std::string, std::uint64_t>> reasons;
  for (std::size_t i = first; i < dropped.size(); ++i) {
    auto it = std::find_if(reasons.begin(), reasons.end(),
                           [&](const auto& r) { return r.first == dropped[i].reason; });
    if (it == reasons.end()) {
      reasons.emplace_back(dropped[i].reason, 1);
    } else {
      ++it->second;
    }
  }
  std::string why;
  for (const auto& [reason, count] : reasons) {
    if (!why.empty()) why += "; ";
    why += reason + " (" + count_text(count) + (count == 1 ? " feature)" : " features)");
  }
  const std::string where = "layer " + name_;
  if (yield.used == 0) {
    if (yield.features == 0) throw InputError(spec_.file, where, "the layer has no features");
    throw InputError(
        spec_.file, where,
        "none of its " + count_text(yield.features) + " features gives " + yield.what + ": " + why);
  }
  const std::uint64_t lost = yield.features - yield.used;
  if (lost == 0 && yield.degenerate_parts == 0) return;
  std::string w = spec_.file + ": " + where + ": ";
  if (lost > 0)
    w += count_text(lost) + " of " + count_text(yield.features) + " features dropped: " + why;
  if (yield.degenerate_parts > 0) {
    if (lost > 0) w += "; ";
    w += count_text(yield.degenerate_parts) + " " + yield.part +
         (yield.degenerate_parts == 1 ? "" : "s") + " with too few distinct vertices skipped";
  }
  warnings.push_back(w + " (the diagnostics output lists them)");
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

const OGRGeometry* FeatureReader::walk(const OGRFeature& feature, std::int64_t fid) {
  fid_ = fid;
  unsupported_.clear();
  degenerate_ = false;
  has_at_ = false;
  const OGRGeometry* geometry = feature.GetGeometryRef();
  if (geometry != nullptr && !geometry->IsEmpty()) {
    if (geometry->hasCurveGeometry(TRUE)) {
      const OgrGeometry linear(geometry->getLinearGeometry(0.0, nullptr));
      if (!linear) fail("cannot approximate the curved geometry by lines");
      ++curves_;
      add_geometry(*linear);
    } else {
      add_geometry(*geometry);
    }
  }
  return geometry;
}

void FeatureReader::add_geometry(const OGRGeometry& g) {
  switch (wkbFlatten(g.getGeometryType())) {
    case wkbLineString:
    case wkbLinearRing:
      if (take_lines_) {
        take_part(*g.toSimpleCurve(), false);
      } else {
        note_unsupported(g);
      }
      break;
    case wkbPolygon:
    case wkbTriangle:
      for (const OGRLinearRing* ring : *g.toPolygon()) take_part(*ring, true);
      break;
    case wkbMultiLineString:
    case wkbMultiPolygon:
    case wkbGeometryCollection:
      for (const OGRGeometry* part : *g.toGeometryCollection()) add_geometry(*part);
      break;
    default:  // points, surfaces
      note_unsupported(g);
      break;
  }
}

void FeatureReader::take_part(const OGRSimpleCurve& g, bool ring) {
  const int count = g.getNumPoints();
  if (count <= 0) {
    ++degenerate_parts_;
    degenerate_ = true;
    return;
  }
  add_part({g, static_cast<std::size_t>(count), g.Is3D() != 0, g.IsMeasured() != 0, ring});
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
void FeatureReader::note_unsupported(const OGRGeometry& g) {
  if (unsupported_.empty()) unsupported_ = OGRGeometryTypeToName(g.getGeometryType());
  Point3 p{};
  if (first_vertex(g, p)) note_location(p);
}

std::string FeatureReader::drop_reason(const OGRGeometry* geometry) const {
  if (geometry == nullptr) return "no geometry";
  if (geometry->IsEmpty()) return "empty geometry";
  std::string reason;
  if (degenerate_) reason = reasons_.degenerate;
  if (!unsupported_.empty()) {
    if (!reason.empty()) reason += "; ";
    reason += unsupported_ + reasons_.unsupported;
  }
  return reason.empty() ? std::string(reasons_.none) : reason;
}

void FeatureReader::drop(const OGRGeometry* geometry) {
  dropped_.push_back({file_index_, fid_, drop_reason(geometry), at_, has_at_});
}

void FeatureReader::fail(const std::string& detail, Remedy remedy) const {
  throw InputError(file_, "layer " + layer_ + ", feature " + signed_count_text(fid_), detail,
                   remedy);
}

void FeatureReader::check_z(ZSource source, bool has_z, bool has_m, const char* no_z_what) const {
  if (source == ZSource::kMeasure && !has_m) fail("the geometry has no M values to take z from");
  if (source == ZSource::kGeometry && !has_z) {
    fail(std::string(no_z_what) + " (fields: " + fields_ + "): use a 3D layer", Remedy::z_field);
  }
}

double FeatureReader::field_z(const OGRFeature& feature) const {
  const OGRFieldDefn& field = *feature.GetFieldDefnRef(z_field_);
  const std::string name = field.GetNameRef();
  if (!feature.IsFieldSetAndNotNull(z_field_)) fail("the z field " + name + " is NULL");
  const OGRFieldType type = field.GetType();
  double z = 0;
  if (type == OFTInteger || type == OFTInteger64 || type == OFTReal) {
    z = feature.GetFieldAsDouble(z_field_);
  } else {  // text: only a complete number counts, never a silent 0
    const char* text = feature.GetFieldAsString(z_field_);
    char* end = nullptr;
    z = CPLStrtod(text, &end);  // "." as the decimal mark whatever the locale
    while (end != nullptr && (*end == ' ' || *end == '\t')) ++end;
    if (end == text || end == nullptr || *end != '\0') {
      fail("the z field " + name + " holds '" + std::string(text) + "', which is not a number");
    }
  }
  if (!std::isfinite(z)) fail("the z field " + name + " is not finite");
  if (!coordinate_in_range(z))
    fail("the z field " + name + " is beyond +-" + kMaxCoordinateText +
         ", the coordinate range tincdt computes with");
  return z;
}

void FeatureReader::check_coordinates(Point3* p, std::size_t n, bool check_z) const {
  for (std::size_t i = 0; i < n; ++i) {
    const double v[3] = {p[i].x, p[i].y, check_z ? p[i].z : 0.0};
    for (int k = 0; k < 3; ++k) {
      if (coordinate_in_range(v[k])) continue;
      if (!std::isfinite(v[k])) fail("vertex " + count_text(i) + " has a non-finite coordinate");
      char text[48];
      std::snprintf(text, sizeof text, "%g", v[k]);
      fail("vertex " + count_text(i) + ": " + "xyz"[k] + " = " + text + " is beyond +-" +
           kMaxCoordinateText + ", the coordinate range tincdt computes with");
    }
    p[i] = without_signed_zero(p[i]);
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
