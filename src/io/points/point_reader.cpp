#include "io/points/point_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs.hpp"
#include "io/gdal_support.hpp"
#include "io/mapped_file.hpp"
#include "io/mesh/ply_reader.hpp"

namespace tincdt::io {
namespace {

// How much of a file is looked at to tell what it is.
constexpr std::size_t kHeadBytes = 4096;

// Case-insensitive test of the end of PATH against EXT (".laz").
bool has_extension(const std::string& path, const char* ext) {
  const std::size_t n = std::strlen(ext);
  if (path.size() < n) return false;
  return std::equal(
      path.end() - static_cast<std::ptrdiff_t>(n), path.end(), ext,
      [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// Keeps the points of out[first, end) inside BOX, in order, and measures the extent of all.
void keep_inside(const BBox& box, std::size_t first, std::vector<Point3>& out,
                 PointReadStats& stats) {
  std::size_t kept = first;
  for (std::size_t i = first; i < out.size(); ++i) {
    const Point3 p = out[i];
    stats.extent.add(p.x, p.y);
    if (p.x >= box.min_x && p.x <= box.max_x && p.y >= box.min_y && p.y <= box.max_y)
      out[kept++] = p;
  }
  stats.points_kept -= out.size() - kept;
  out.resize(kept);
}

// ---- What a file is, from its first bytes ----

bool starts_with(std::string_view head, std::string_view magic) {
  return head.substr(0, magic.size()) == magic;
}

bool starts_with_nocase(std::string_view head, std::string_view word) {
  if (head.size() < word.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(head[i])) != word[i]) return false;
  }
  return true;
}

// Not text: a NUL byte or a control character other than a blank in the first line. (Text
// that turns binary later is the XYZ parser's to report, with its line number.)
bool is_binary(std::string_view head) {
  for (const char ch : head) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n') return false;
    if (c < 0x20 && c != '\t' && c != '\r' && c != '\f') return true;
  }
  return false;
}

struct Kind {
  const char* what = nullptr;  // "a GeoTIFF raster"; null: not recognised
  const char* advice = "";     // what to do, after the kind
  Remedy remedy = Remedy::none;
};

constexpr const char* kRasterAdvice =
    ": tincdt triangulates points; turn its cells into XYZ points first (gdal_translate -of XYZ)";
constexpr const char* kVectorAdvice = "";  // the front end names its options (Remedy)

Kind raster_file(const char* what) {
  return {what, kRasterAdvice, Remedy::none};
}
Kind vector_file(const char* what) {
  return {what, kVectorAdvice, Remedy::vector_as_points};
}

// Binary formats by their magic bytes.
Kind binary_kind(std::string_view head, const std::string& path) {
  if (starts_with(head, std::string_view("II*\0", 4)) ||
      starts_with(head, std::string_view("MM\0*", 4)))
    return raster_file("a TIFF (GeoTIFF) raster");
  if (starts_with(head, std::string_view("II+\0", 4)) ||
      starts_with(head, std::string_view("MM\0+", 4)))
    return raster_file("a BigTIFF raster");
  if (starts_with(head, "\x89PNG")) return raster_file("a PNG image");
  if (starts_with(head, "\xFF\xD8\xFF")) return raster_file("a JPEG image");
  if (starts_with(head, std::string_view("\0\0\0\x0CjP  ", 8)))
    return raster_file("a JPEG 2000 image");
  if (starts_with(head, "CDF\x01") || starts_with(head, "CDF\x02") || starts_with(head, "\x89HDF"))
    return raster_file("a netCDF / HDF raster");
  if (starts_with(head, "EHFA_HEADER_TAG")) return raster_file("an ERDAS Imagine raster");
  if (starts_with(head, "DSBB") || starts_with(head, "DSRB")) return raster_file("a Surfer grid");
  if (starts_with(head, std::string_view("\0\0\x27\x0A", 4))) {
    return vector_file(has_extension(path, ".shx") ? "the index (.shx) of a shapefile"
                                                   : "a shapefile");
  }
  if (starts_with(head, std::string_view("SQLite format 3\0", 16))) {
    const bool gpkg = head.size() >= 72 && head.substr(68, 4) == "GPKG";
    return vector_file(gpkg || has_extension(path, ".gpkg") ? "a GeoPackage"
                                                            : "an SQLite database");
  }
  if (starts_with(head, "fgb\x03")) return vector_file("a FlatGeobuf file");
  if (starts_with(head, "glTF")) return {"a binary glTF mesh", ": give its points as PLY", {}};
  if (starts_with(head, "PK\x03\x04"))
    return {"a zip archive", ": unpack it and give the point files it holds", {}};
  if (starts_with(head, "\x1F\x8B"))
    return {
        "gzip-compressed", ": decompress it first, or pipe it in (gunzip -c FILE | tincdt -)", {}};
  if (starts_with(head, "\xFF\xFE") || starts_with(head, "\xFE\xFF"))
    return {"UTF-16 text", ": save it as UTF-8 or ASCII", {}};
  if (is_binary(head) && has_extension(path, ".dbf"))
    return vector_file("the attribute table (.dbf) of a shapefile");
  return {};
}

// Text formats that are not XYZ, by their first non-blank characters.
Kind text_kind(std::string_view head) {
  if (starts_with(head, "\xEF\xBB\xBF")) head.remove_prefix(3);
  while (!head.empty() && std::isspace(static_cast<unsigned char>(head.front())))
    head.remove_prefix(1);
  if (starts_with(head, "{") || starts_with(head, "[")) {
    const bool geo = head.find("\"type\"") != std::string_view::npos &&
                     (head.find("Feature") != std::string_view::npos ||
                      head.find("\"coordinates\"") != std::string_view::npos);
    return geo ? vector_file("a GeoJSON file")
               : Kind{"a JSON file", ": tincdt reads points from LAS, LAZ, PLY or XYZ text", {}};
  }
  if (starts_with(head, "<")) {
    if (head.find("<kml") != std::string_view::npos) return vector_file("a KML file");
    if (head.find("gml") != std::string_view::npos) return vector_file("a GML file");
    if (head.find("<LandXML") != std::string_view::npos)
      return {"a LandXML file", ": give the TIN's points as PLY or XYZ text", {}};
    return {"an XML file", ": tincdt reads points from LAS, LAZ, PLY or XYZ text", {}};
  }
  if (starts_with_nocase(head, "ncols") || starts_with_nocase(head, "nrows"))
    return raster_file("an Esri ASCII grid raster");
  if (starts_with(head, "DSAA")) return raster_file("a Surfer ASCII grid");
  return {};
}

// A binary file that no magic above names, as GDAL sees it: a raster or vector format it reads.
Kind gdal_kind(const std::string& path, std::string& driver) {
  detail::register_gdal_drivers();
  const detail::GdalQuiet quiet;
  const detail::GdalDataset ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!ds || ds->GetDriver() == nullptr) return {};
  const char* name = ds->GetDriver()->GetMetadataItem(GDAL_DMD_LONGNAME);
  driver = name != nullptr ? name : ds->GetDriver()->GetDescription();
  if (driver.size() > 60) driver = driver.substr(0, 57) + "...";
  if (ds->GetRasterCount() > 0) return raster_file("a raster");
  if (ds->GetLayerCount() > 0) return vector_file("a vector file");
  return {};
}

// Refuses a file that is recognisably no point file: a raster, a vector file, an archive.
void refuse_other_formats(const std::string& path, std::string_view head) {
  const bool binary = is_binary(head);
  Kind kind = binary_kind(head, path);  // magic bytes: a PNG's first line is printable
  if (kind.what == nullptr && !binary) kind = text_kind(head);
  std::string driver;
  if (kind.what == nullptr && binary) kind = gdal_kind(path, driver);
  if (kind.what != nullptr) {
    std::string what = kind.what;
    if (!driver.empty()) what += " (" + driver + ")";
    throw InputError(path, "", what + ", not a point file" + kind.advice, kind.remedy);
  }
  if (binary) {
    throw InputError(path, "",
                     "binary data of an unknown format, not a point file (tincdt reads LAS, LAZ, "
                     "PLY and XYZ text)");
  }
}

// ---- PLY: the vertices of a mesh (a TIN tincdt wrote) as points ----

void refuse_filters(const std::string& path, const PointFilter& filter, const char* what) {
  if (!filter.keep_classes.empty() || !filter.drop_classes.empty()) {
    throw InputError(path, "",
                     std::string(what) + " has no point classes, so none can be kept or dropped",
                     Remedy::class_filter);
  }
  if (filter.first_return_only || filter.last_return_only) {
    throw InputError(
        path, "",
        std::string(what) + " has no return numbers, so first or last returns cannot be told",
        Remedy::return_filter);
  }
}

PointReadStats read_ply_points(const std::string& path, const PointFilter& filter,
                               std::vector<Point3>& out) {
  refuse_filters(path, filter, "a PLY mesh");
  const PlyMesh mesh = read_ply(path);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Point3& v = mesh.vertices[i];
    if (coordinate_in_range(v.x) && coordinate_in_range(v.y) && coordinate_in_range(v.z)) continue;
    throw InputError(path, "vertex " + count_text(i),
                     std::string("a coordinate is beyond +-") + kMaxCoordinateText +
                         ", the coordinate range tincdt computes with");
  }
  out.insert(out.end(), mesh.vertices.begin(), mesh.vertices.end());
  PointReadStats stats;
  stats.format = "ply";
  stats.points_read = stats.points_kept = mesh.vertices.size();
  if (!mesh.crs.empty()) {
    try {
      stats.crs_wkt = crs_from_user(mesh.crs);
    } catch (const InputError& e) {
      std::string text = mesh.crs.substr(0, 60);
      for (char& c : text) c = c >= 0x20 && c < 0x7F ? c : '?';
      stats.warnings.push_back(path + ": its CRS comment '" + text + "' cannot be read (" +
                               e.detail() + "); the file has no CRS");
    }
  }
  return stats;
}

bool is_ply(std::string_view head) {
  return starts_with(head, "ply\n") || starts_with(head, "ply\r\n");
}

PointReadStats read_any(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads) {
  if (path == "-") return read_xyz(path, filter, out, threads);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, "", detail::open_error_text(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, "", "is a directory, not a file");
  // Pipes and devices cannot be peeked at without consuming them: they can only be XYZ text.
  if (!S_ISREG(st.st_mode)) return read_xyz(path, filter, out, threads);
  if (st.st_size == 0) throw InputError(path, "", "empty file");

  std::string head(kHeadBytes, '\0');
  {
    const detail::FileHandle file(path);
    const ssize_t n = ::pread(file.fd(), head.data(), head.size(), 0);
    if (n < 0) throw InputError(path, "", std::string("read failed: ") + std::strerror(errno));
    head.resize(static_cast<std::size_t>(n));
  }
  if (starts_with(head, "LASF")) return read_las(path, filter, out, threads);
  // A .las or .laz name without the signature is a damaged or mislabelled file, not text.
  if (has_extension(path, ".las") || has_extension(path, ".laz")) {
    return read_las(path, filter, out, threads);
  }
  if (is_ply(head)) return read_ply_points(path, filter, out);
  refuse_other_formats(path, head);
  return read_xyz(path, filter, out, threads);
}

}  // namespace

PointReadStats read_points(const std::string& path, const PointFilter& filter,
                           std::vector<Point3>& out, unsigned threads) {
  const std::size_t first = out.size();
  PointReadStats stats = read_any(path, filter, out, threads);
  if (stats.bytes_read == 0 && path != "-") {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode))
      stats.bytes_read = static_cast<std::uint64_t>(st.st_size);
  }
  if (filter.box) keep_inside(*filter.box, first, out, stats);
  return stats;
}

}  // namespace tincdt::io
