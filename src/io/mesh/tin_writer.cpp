#include "io/mesh/tin_writer.hpp"

#include <cctype>
#include <charconv>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_file.hpp"

namespace tincdt::io {
namespace detail {

std::string format_point(const Point3& p) {
  char buf[3 * BlockWriter::kMaxItem];
  char* end = buf + sizeof buf;
  char* q = format_double(buf, end, p.x);
  *q++ = ' ';
  q = format_double(q, end, p.y);
  *q++ = ' ';
  q = format_double(q, end, p.z);
  return std::string(buf, q);
}

std::string crs_code(const std::string& wkt) {
  std::string label = crs_label(wkt);
  const bool is_code = label.find(':') != std::string::npos && label.find(' ') == std::string::npos;
  return is_code ? label : std::string();
}

}  // namespace detail

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::string prj_path(const std::string& path) {
  std::filesystem::path p(path);
  p.replace_extension(".prj");
  return p.string();
}

bool wants_prj(TinFormat format, const std::string& crs_wkt) {
  const bool has_no_crs_of_its_own =
      format == TinFormat::obj || format == TinFormat::ply || format == TinFormat::stl;
  return has_no_crs_of_its_own && !crs_wkt.empty();
}

bool format_takes_offset(TinFormat format) {
  return format != TinFormat::landxml && format != TinFormat::gpkg;
}

void write_prj(OutputFile& out, const std::string& crs_wkt) {
  std::string text;
  try {
    text = crs_to_prj(crs_wkt);
  } catch (const Error& e) {
    throw OutputError(out.path(), "", e.detail());
  }
  if (text.empty()) throw OutputError(out.path(), "", "the CRS cannot be written as ESRI WKT");
  out.write(text);
}

namespace {

constexpr std::string_view kObj[] = {".obj"};
constexpr std::string_view kPly[] = {".ply"};
constexpr std::string_view kGeojson[] = {".geojson", ".json"};
constexpr std::string_view kLandxml[] = {".xml", ".landxml"};
constexpr std::string_view kGpkg[] = {".gpkg"};
constexpr std::string_view kStl[] = {".stl"};
constexpr std::string_view kGlb[] = {".glb"};

constexpr TinFormatInfo kFormats[] = {
    {TinFormat::obj, "obj", "OBJ", kObj},
    {TinFormat::ply, "ply", "PLY", kPly},
    {TinFormat::geojson, "geojson", "GeoJSON", kGeojson},
    {TinFormat::landxml, "landxml", "LandXML", kLandxml},
    {TinFormat::gpkg, "gpkg", "GeoPackage", kGpkg},
    {TinFormat::stl, "stl", "STL", kStl},
    {TinFormat::glb, "glb", "glTF", kGlb},
};
// The names again, as one array for a list of choices.
constexpr std::string_view kNames[] = {"obj", "ply", "geojson", "landxml", "gpkg", "stl", "glb"};
static_assert(std::size(kNames) == std::size(kFormats) && [] {
  for (std::size_t i = 0; i < std::size(kNames); ++i)
    if (kNames[i] != kFormats[i].name) return false;
  return true;
}());

// The writer of each format, in the order of kFormats.
detail::FormatWriter* const kWriters[] = {
    detail::write_obj,  detail::write_ply, detail::write_geojson, detail::write_landxml,
    detail::write_gpkg, detail::write_stl, detail::write_gltf};
static_assert(std::size(kWriters) == std::size(kFormats));

std::size_t index_of(TinFormat format) {
  for (std::size_t i = 0; i < std::size(kFormats); ++i)
    if (kFormats[i].format == format) return i;
  throw InternalError("no writer for TinFormat " + std::to_string(static_cast<int>(format)));
}

}  // namespace

std::span<const TinFormatInfo> tin_formats() {
  return kFormats;
}

std::span<const std::string_view> tin_format_names() {
  return kNames;
}

const TinFormatInfo& format_info(TinFormat format) {
  return kFormats[index_of(format)];
}

std::optional<TinFormat> format_from_name(std::string_view name) {
  const std::string key = lower(std::string(name));
  for (const TinFormatInfo& f : kFormats)
    if (f.name == key) return f.format;
  return std::nullopt;
}

std::string format_extensions_text() {
  std::string text;
  for (std::size_t i = 0; i < std::size(kFormats); ++i) {
    if (i > 0) text += i + 1 == std::size(kFormats) ? " or " : ", ";
    for (std::size_t k = 0; k < kFormats[i].extensions.size(); ++k) {
      if (k > 0) text += '/';
      text += kFormats[i].extensions[k];
    }
  }
  return text;
}

TinFormat format_from_path(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  for (const TinFormatInfo& f : kFormats)
    for (std::string_view known : f.extensions)
      if (ext == known) return f.format;
  const std::string known = "known: " + format_extensions_text();
  if (ext.empty())
    throw UnknownFormatError(path, "", "no extension to tell the output format (" + known + ")");
  throw UnknownFormatError(path, "", "unknown output format '" + ext + "' (" + known + ")");
}

namespace {

void check_offset(const std::string& path, TinFormat format, const TinWriteOptions& options) {
  if (!format_takes_offset(format) && !detail::is_zero(options.offset))
    throw OutputError(path, "",
                      "LandXML and GeoPackage keep real coordinates: an offset cannot be applied");
}

}  // namespace

std::string_view format_name(TinFormat format) {
  return format_info(format).name;
}

TinWriteStats write_tin(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const TinFormat format = options.format ? *options.format : format_from_path(out.path());
  check_offset(out.path(), format, options);
  return kWriters[index_of(format)](out, tin, options);
}

TinWriteStats write_tin(const std::string& path, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const TinFormat format = options.format ? *options.format : format_from_path(path);
  check_offset(path, format, options);
  // Both outputs are opened (so both overwrite checks fail) before any work, both temporaries
  // are complete on disk before the first rename.
  OutputFile out(path, options.overwrite);
  std::optional<OutputFile> prj;
  if (wants_prj(format, options.crs_wkt)) {
    prj.emplace(prj_path(path), options.overwrite);
    write_prj(*prj, options.crs_wkt);
  }
  TinWriteStats stats = write_tin(out, tin, options);
  out.close();
  if (prj) prj->close();
  out.commit();
  if (prj) prj->commit();
  stats.bytes = out.bytes_written();
  return stats;
}

}  // namespace tincdt::io
