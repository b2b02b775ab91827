#include "io/crs.hpp"

#include <cpl_vsi.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/crs_detail.hpp"
#include "io/gdal_support.hpp"

namespace tincdt::io {
namespace {

// CPL-allocated string to std::string.
std::string take_cpl_string(char* s) {
  std::string out = s != nullptr ? s : "";
  CPLFree(s);
  return out;
}

// "+proj=lcc +lat_0=41.75 ..." as sorted (key, value) pairs.
std::vector<std::pair<std::string, std::string>> proj_parameters(const OGRSpatialReference& srs) {
  char* text = nullptr;
  std::vector<std::pair<std::string, std::string>> out;
  const bool exported = srs.exportToProj4(&text) == OGRERR_NONE && text != nullptr;
  const std::string proj = take_cpl_string(text);
  if (!exported) return out;
  std::size_t i = 0;
  while (i < proj.size()) {
    while (i < proj.size() && (proj[i] == ' ' || proj[i] == '+')) ++i;
    const std::size_t end = std::min(proj.find(' ', i), proj.size());
    const std::string token = proj.substr(i, end - i);
    if (!token.empty()) {
      const std::size_t eq = token.find('=');
      out.emplace_back(token.substr(0, eq), eq == std::string::npos ? "" : token.substr(eq + 1));
    }
    i = end;
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool same_proj_parameters(const OGRSpatialReference& a, const OGRSpatialReference& b) {
  const auto pa = proj_parameters(a), pb = proj_parameters(b);
  if (pa.empty() || pa.size() != pb.size()) return false;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa[i].first != pb[i].first) return false;
    if (pa[i].second == pb[i].second) continue;
    char* end_a = nullptr;
    char* end_b = nullptr;
    const double x = std::strtod(pa[i].second.c_str(), &end_a);
    const double y = std::strtod(pb[i].second.c_str(), &end_b);
    if (*end_a != '\0' || *end_b != '\0' || pa[i].second.empty()) return false;
    if (std::fabs(x - y) > 1e-9 * std::max(std::fabs(x), std::fabs(y))) return false;
  }
  return true;
}

std::string export_wkt(const OGRSpatialReference& srs, const char* format) {
  const char* const options[] = {format, nullptr};
  char* text = nullptr;
  const bool exported = srs.exportToWkt(&text, options) == OGRERR_NONE;
  std::string wkt = take_cpl_string(text);
  return exported ? wkt : std::string();
}

std::string shorten(const std::string& s, std::size_t max_len = 80) {
  if (s.size() <= max_len) return s;
  return s.substr(0, max_len) + "...";
}

// "EPSG:NNNN" when the CRS object itself carries an authority code, else "".
std::string authority_label(const OGRSpatialReference& srs) {
  const char* name = srs.GetAuthorityName(nullptr);
  const char* code = srs.GetAuthorityCode(nullptr);
  if (name == nullptr || code == nullptr) return {};
  return std::string(name) + ":" + code;
}

// ---- GeoTIFF keys -> WKT, by handing GDAL a minimal one-pixel TIFF that carries the keys ----

class TiffBuilder {
 public:
  void add_short(std::uint16_t tag, std::uint16_t value) { entries_.push_back({tag, 3, 1, value}); }
  void add_long(std::uint16_t tag, std::uint32_t value) { entries_.push_back({tag, 4, 1, value}); }
  // An array stored out of line; TYPE is the TIFF field type, UNIT its size in bytes.
  void add_array(std::uint16_t tag, std::uint16_t type, const void* data, std::size_t count,
                 std::size_t unit) {
    Entry e{tag, type, static_cast<std::uint32_t>(count), 0};
    e.blob.assign(static_cast<const std::uint8_t*>(data),
                  static_cast<const std::uint8_t*>(data) + count * unit);
    entries_.push_back(std::move(e));
  }

  // Little-endian TIFF: header, one IFD (entries sorted by tag), out-of-line arrays, the pixel.
  std::vector<std::uint8_t> build() {
    std::sort(entries_.begin(), entries_.end(),
              [](const Entry& a, const Entry& b) { return a.tag < b.tag; });
    const std::size_t ifd_size = 2 + 12 * entries_.size() + 4;
    std::size_t data_pos = 8 + ifd_size;
    for (Entry& e : entries_) {
      if (e.blob.size() > 4) {
        data_pos += data_pos & 1;  // word alignment
        e.value = static_cast<std::uint32_t>(data_pos);
        data_pos += e.blob.size();
      } else if (!e.blob.empty()) {
        std::uint32_t v = 0;
        std::memcpy(&v, e.blob.data(), e.blob.size());
        e.value = v;
      }
    }
    const std::size_t pixel_pos = data_pos;
    for (Entry& e : entries_) {
      if (e.tag == 273) e.value = static_cast<std::uint32_t>(pixel_pos);  // StripOffsets
    }
    std::vector<std::uint8_t> out(pixel_pos + 1, 0);  // the last byte is the single pixel
    std::size_t pos = 0;
    put(out, pos, std::uint16_t{0x4949});  // "II"
    put(out, pos, std::uint16_t{42});
    put(out, pos, std::uint32_t{8});
    put(out, pos, static_cast<std::uint16_t>(entries_.size()));
    for (const Entry& e : entries_) {
      put(out, pos, e.tag);
      put(out, pos, e.type);
      put(out, pos, e.count);
      if (e.blob.empty() && e.type == 3) {  // a SHORT is left-justified in the value field
        put(out, pos, static_cast<std::uint16_t>(e.value));
        put(out, pos, std::uint16_t{0});
      } else {
        put(out, pos, e.value);
      }
    }
    put(out, pos, std::uint32_t{0});  // no next IFD
    for (const Entry& e : entries_) {
      if (e.blob.size() > 4) std::memcpy(out.data() + e.value, e.blob.data(), e.blob.size());
    }
    return out;
  }

 private:
  struct Entry {
    std::uint16_t tag;
    std::uint16_t type;
    std::uint32_t count;
    std::uint32_t value;
    std::vector<std::uint8_t> blob = {};
  };
  template <typename T>
  static void put(std::vector<std::uint8_t>& out, std::size_t& pos, T v) {
    std::memcpy(out.data() + pos, &v, sizeof(T));  // the project targets little-endian hosts
    pos += sizeof(T);
  }
  std::vector<Entry> entries_;
};

// The value of KEY in a GeoTIFF key directory when stored inline, 0 when absent.
std::uint16_t key_value(const std::vector<std::uint16_t>& dir, std::uint16_t key) {
  const std::size_t n = dir.size() >= 4 ? dir[3] : 0;
  for (std::size_t i = 0; i < n && 4 + 4 * i + 3 < dir.size(); ++i) {
    const std::uint16_t* k = &dir[4 + 4 * i];
    if (k[0] == key) return k[1] == 0 ? k[3] : std::uint16_t{1};
  }
  return 0;
}

// Keys that define a horizontal CRS: geographic type, geodetic datum, projected type,
// projection, coordinate transformation.
bool has_horizontal_keys(const std::vector<std::uint16_t>& dir) {
  for (const std::uint16_t key : {std::uint16_t{2048}, std::uint16_t{2050}, std::uint16_t{3072},
                                  std::uint16_t{3074}, std::uint16_t{3075}}) {
    if (key_value(dir, key) != 0) return true;
  }
  return false;
}

std::string linear_unit_name(const OGRSpatialReference& srs) {
  const char* name = nullptr;  // owned by the SRS
  srs.GetLinearUnits(&name);
  return name != nullptr ? std::string(name) : std::string("?");
}

// GDAL keeps the EPSG id of a projected CSType key even when other keys override part of that
// definition (mvk-thin.las: EPSG:26995, in metres, with ProjLinearUnits = US survey foot). Such
// a CRS is not EPSG:NNNN any more: drop the id so that nobody takes it for the registry entry,
// and say what happened.
void drop_misleading_id(const OGRSpatialReference& srs, detail::CrsResult& result) {
  const char* authority = srs.GetAuthorityName(nullptr);
  const char* code = srs.GetAuthorityCode(nullptr);
  if (authority == nullptr || code == nullptr || std::strcmp(authority, "EPSG") != 0) return;
  OGRSpatialReference registry = detail::gis_order_srs();
  if (registry.importFromEPSG(std::atoi(code)) != OGRERR_NONE) return;
  const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
  if (srs.IsSame(&registry, options) != 0) return;
  const std::string id = std::string(",ID[\"EPSG\",") + code + "]]";
  std::string& wkt = result.wkt;
  if (wkt.size() > id.size() && wkt.compare(wkt.size() - id.size(), id.size(), id) == 0) {
    wkt.resize(wkt.size() - id.size());
    wkt += "]";
  }
  const std::string unit = linear_unit_name(srs);
  const std::string registry_unit = linear_unit_name(registry);
  result.problem =
      "the GeoTIFF keys name EPSG:" + std::string(code) + " but override part of its definition" +
      (unit != registry_unit ? " (linear unit " + unit + " instead of " + registry_unit + ")"
                             : std::string()) +
      "; the overridden CRS is used";
}

}  // namespace

namespace detail {

CrsResult crs_check_wkt(const std::string& wkt) {
  const GdalQuiet quiet;
  OGRSpatialReference srs = gis_order_srs();
  if (!import_wkt(srs, wkt)) return {{}, last_gdal_message("not a valid WKT CRS")};
  return {wkt, {}};
}

CrsResult crs_from_geotiff(const GeoTiffKeys& keys) {
  const std::vector<std::uint16_t>& dir = keys.directory;
  if (dir.size() < 4 || dir[0] != 1 || 4 + 4 * std::size_t{dir[3]} > dir.size()) {
    return {{}, "malformed GeoTIFF key directory"};
  }
  if (!has_horizontal_keys(dir)) {
    const std::uint16_t vert = key_value(dir, 4096);
    return {{},
            vert != 0 ? "the GeoTIFF keys give only a vertical CRS (EPSG:" + std::to_string(vert) +
                            "), no horizontal one"
                      : "the GeoTIFF keys describe no horizontal CRS"};
  }
  TiffBuilder tiff;
  tiff.add_short(256, 1);  // ImageWidth
  tiff.add_short(257, 1);  // ImageLength
  tiff.add_short(258, 8);  // BitsPerSample
  tiff.add_short(259, 1);  // Compression: none
  tiff.add_short(262, 1);  // Photometric: min-is-black
  tiff.add_long(273, 0);   // StripOffsets, set by build()
  tiff.add_short(277, 1);  // SamplesPerPixel
  tiff.add_short(278, 1);  // RowsPerStrip
  tiff.add_long(279, 1);   // StripByteCounts
  tiff.add_array(34735, 3, dir.data(), dir.size(), 2);
  if (!keys.doubles.empty()) tiff.add_array(34736, 12, keys.doubles.data(), keys.doubles.size(), 8);
  if (!keys.ascii.empty()) {
    std::string ascii = keys.ascii;
    if (ascii.back() != '\0') ascii.push_back('\0');
    tiff.add_array(34737, 2, ascii.data(), ascii.size(), 1);
  }
  std::vector<std::uint8_t> bytes = tiff.build();

  register_gdal_drivers();
  const GdalQuiet quiet;
  static std::atomic<unsigned> counter{0};
  const std::string name = "/vsimem/tincdt_geokeys_" + std::to_string(counter++) + ".tif";
  VSILFILE* f = VSIFileFromMemBuffer(name.c_str(), bytes.data(), bytes.size(), FALSE);
  if (f == nullptr) return {{}, last_gdal_message("cannot decode the GeoTIFF keys")};
  VSIFCloseL(f);
  const char* const drivers[] = {"GTiff", nullptr};
  CrsResult result;
  {
    const GdalDataset ds(
        GDALDataset::Open(name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers));
    const OGRSpatialReference* srs = ds ? ds->GetSpatialRef() : nullptr;
    if (!ds) {
      result.problem = last_gdal_message("cannot decode the GeoTIFF keys");
    } else if (srs != nullptr && (srs->IsProjected() || srs->IsGeographic())) {
      result.wkt = export_wkt(*srs, "FORMAT=WKT2_2019");
      if (result.wkt.empty()) {
        result.problem = last_gdal_message("cannot export the CRS");
      } else {
        drop_misleading_id(*srs, result);
      }
    } else {
      result.problem = "GDAL finds no horizontal CRS in the GeoTIFF keys";
    }
  }
  VSIUnlink(name.c_str());
  return result;
}

namespace {

// The top-level member names of a JSON object, fed in pieces: a lexical walk (strings, escapes,
// nesting) that needs no parse tree, so a large feature collection costs one pass and no memory
// (GDAL parses the whole file after it anyway). A name spelled with \u escapes is not matched.
class TopLevelKeys {
 public:
  // Feeds TEXT; true as soon as a top-level member is named NAME.
  bool feed(std::string_view text, std::string_view name) {
    for (const char c : text) {
      if (in_string_) {
        if (escaped_) {
          escaped_ = false;
          if (is_key_ && key_.size() <= name.size()) key_ += c;
        } else if (c == '\\') {
          escaped_ = true;
        } else if (c == '"') {
          in_string_ = false;
          if (is_key_ && key_ == name) return true;
        } else if (is_key_ && key_.size() <= name.size()) {
          key_ += c;
        }
        continue;
      }
      if (c == '"') {
        in_string_ = true;
        is_key_ = depth_ == 1 && expect_key_;
        expect_key_ = false;
        key_.clear();
      } else if (c == '{' || c == '[') {
        if (++depth_ == 1) top_is_object_ = c == '{';
        expect_key_ = depth_ == 1 && top_is_object_;
      } else if (c == '}' || c == ']') {
        --depth_;
      } else if (c == ',' && depth_ == 1) {
        expect_key_ = top_is_object_;
      }
    }
    return false;
  }

 private:
  int depth_ = 0;
  bool in_string_ = false, escaped_ = false, is_key_ = false, expect_key_ = false;
  bool top_is_object_ = false;
  std::string key_;
};

}  // namespace

bool geojson_names_crs(const std::string& path) {
  VSILFILE* f = VSIFOpenL(path.c_str(), "rb");
  if (f == nullptr) return false;
  TopLevelKeys keys;
  char buffer[65536];
  bool named = false;
  while (!named) {
    const std::size_t n = VSIFReadL(buffer, 1, sizeof buffer, f);
    if (n == 0) break;
    named = keys.feed(std::string_view(buffer, n), "crs");
  }
  VSIFCloseL(f);
  return named;
}

std::string crs_of_layer(const OGRSpatialReference* srs) {
  if (srs == nullptr) return {};
  const char* name = srs->GetName();
  if (name != nullptr && srs->GetAuthorityName(nullptr) == nullptr &&
      (std::strcmp(name, "Undefined geographic SRS") == 0 ||
       std::strcmp(name, "Undefined Cartesian SRS") == 0)) {
    return {};
  }
  for (const char* format : {"FORMAT=WKT2_2019", "FORMAT=WKT1"}) {
    std::string wkt = export_wkt(*srs, format);
    if (!wkt.empty()) return wkt;
  }
  return {};
}

}  // namespace detail

bool same_crs(const std::string& wkt_a, const std::string& wkt_b) {
  if (wkt_a.empty() || wkt_b.empty()) return wkt_a.empty() && wkt_b.empty();
  if (wkt_a == wkt_b) return true;
  const detail::GdalQuiet quiet;
  OGRSpatialReference a = detail::gis_order_srs();
  OGRSpatialReference b = detail::gis_order_srs();
  if (!detail::import_wkt(a, wkt_a) || !detail::import_wkt(b, wkt_b)) return false;
  const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
  if (a.IsSame(&b, options) != 0) return true;
  // ESRI-style WKT in LAS files often names the datum differently and carries parameters
  // converted between units (a false easting of 399999.9999984 ft for 400000 m): the same
  // projection if the PROJ definitions agree key by key, numbers to a relative 1e-9.
  return same_proj_parameters(a, b);
}

bool is_geographic(const std::string& wkt) {
  if (wkt.empty()) return false;
  const detail::GdalQuiet quiet;
  OGRSpatialReference srs = detail::gis_order_srs();
  return detail::import_wkt(srs, wkt) && srs.IsGeographic();
}

std::string crs_label(const std::string& wkt) {
  if (wkt.empty()) return {};
  const detail::GdalQuiet quiet;
  OGRSpatialReference srs = detail::gis_order_srs();
  if (!detail::import_wkt(srs, wkt)) return {};
  std::string label = authority_label(srs);
  if (!label.empty()) return label;
  // An EPSG entry that PROJ finds equivalent (confidence 70 = same datum and coordinate
  // system, 90 = also a similar name, 100 = identical). Only an unambiguous best EPSG match
  // counts; entries of other registries (IGNF, ESRI) are ignored.
  int count = 0;
  int* confidence = nullptr;
  OGRSpatialReferenceH* matches = srs.FindMatches(nullptr, &count, &confidence);
  const auto match = [matches](int i) -> const OGRSpatialReference& {
    return *OGRSpatialReference::FromHandle(matches[i]);
  };
  int best = -1;
  bool tie = false;
  for (int i = 0; i < count; ++i) {
    const char* authority = match(i).GetAuthorityName(nullptr);
    if (authority == nullptr || std::strcmp(authority, "EPSG") != 0 || confidence[i] < 70) continue;
    if (best < 0 || confidence[i] > confidence[best]) {
      best = i;
      tie = false;
    } else if (confidence[i] == confidence[best]) {
      tie = true;
    }
  }
  if (best >= 0 && !tie) label = authority_label(match(best));
  if (matches != nullptr) OSRFreeSRSArray(matches);  // FindMatches' own release function
  CPLFree(confidence);
  if (!label.empty()) return label;
  const char* name = srs.GetName();
  return name != nullptr ? std::string(name) : std::string();
}

std::string crs_unusable_reason(const std::string& wkt) {
  const detail::GdalQuiet quiet;
  OGRSpatialReference srs = detail::gis_order_srs();
  if (!detail::import_wkt(srs, wkt))
    return "it cannot be read (" + detail::last_gdal_message("not a valid WKT CRS") + ")";
  if (srs.IsGeocentric())
    return "it is geocentric (x, y and z from the earth's centre), not a map projection or "
           "latitude and longitude";
  if (srs.IsProjected() || srs.IsGeographic() || srs.IsLocal()) return {};
  if (srs.IsVertical()) return "it is a vertical CRS only, with no horizontal part";
  return "it is not a horizontal CRS (neither projected nor geographic)";
}

std::string crs_from_user(const std::string& text) {
  const detail::GdalQuiet quiet;
  OGRSpatialReference srs = detail::gis_order_srs();
  if (srs.SetFromUserInput(text.c_str()) != OGRERR_NONE) {
    throw InputError("", "",
                     "cannot interpret '" + shorten(text) +
                         "' as a CRS: " + detail::last_gdal_message("unknown CRS"));
  }
  std::string wkt = export_wkt(srs, "FORMAT=WKT2_2019");
  if (wkt.empty()) {
    throw InputError("", "",
                     "cannot express the CRS '" + shorten(text) +
                         "' as WKT: " + detail::last_gdal_message("export failed"));
  }
  return wkt;
}

std::string crs_to_prj(const std::string& wkt) {
  if (wkt.empty()) return {};
  const detail::GdalQuiet quiet;
  OGRSpatialReference srs = detail::gis_order_srs();
  if (!detail::import_wkt(srs, wkt)) {
    throw InputError("", "",
                     "cannot read the CRS WKT '" + shorten(wkt) +
                         "': " + detail::last_gdal_message("invalid WKT"));
  }
  std::string prj = export_wkt(srs, "FORMAT=WKT1_ESRI");
  if (prj.empty() && srs.IsCompound()) {
    // ESRI WKT1 has no compound CRS in some PROJ versions: keep the horizontal part.
    CPLErrorReset();
    if (srs.StripVertical() == OGRERR_NONE) prj = export_wkt(srs, "FORMAT=WKT1_ESRI");
  }
  if (prj.empty()) {
    throw InputError("", "",
                     "cannot express the CRS as ESRI WKT for a .prj: " +
                         detail::last_gdal_message("export failed"));
  }
  return prj;
}

}  // namespace tincdt::io
