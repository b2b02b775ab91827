#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs.hpp"
#include "io/raster/dem_writer.hpp"
#include "pipeline/build.hpp"
#include "products/short_number.hpp"

namespace tincdt::pipeline {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string srs_option(const std::string& text, const char* option) {
  if (text.empty()) return {};
  try {
    return io::crs_from_user(text);
  } catch (const Error& e) {
    throw UsageError(std::string(option) + ": " + e.what());
  }
}

// A CRS as the user gave it, for a message: a WKT cut short.
std::string shown_srs(const std::string& text) {
  return "'" + (text.size() > 60 ? text.substr(0, 60) + "..." : text) + "'";
}

// An input CRS option: readable, and one a terrain TIN can be built in.
std::string input_srs_option(const std::string& text, const char* option) {
  std::string wkt = srs_option(text, option);
  if (wkt.empty()) return wkt;
  if (const std::string why = io::crs_unusable_reason(wkt); !why.empty())
    throw UsageError(std::string(option) + ": " + shown_srs(text) + " cannot be used: " + why);
  return wkt;
}

// --t-srs: an input CRS option, refused when geographic unless allowed.
std::string target_srs_option(const BuildOptions& o) {
  std::string wkt = input_srs_option(o.target_srs, "--t-srs");
  if (!o.allow_geographic && io::is_geographic(wkt))
    throw UsageError(
        "--t-srs: " + shown_srs(o.target_srs) +
        " is geographic (degrees): the TIN would be Delaunay in degrees, and DEM cells and "
        "lengths in degrees are distorted; name a projected CRS (e.g. the data's UTM zone), or "
        "pass --allow-geographic");
  return wkt;
}

void check_inputs(const BuildOptions& o) {
  if (o.inputs.empty() && o.contours.empty() && o.breaklines.empty())
    throw UsageError(
        "no input: give point files (INPUT), --contours or --hard-lines (--breaklines)");
  if (std::count(o.inputs.begin(), o.inputs.end(), std::string("-")) > 1)
    throw UsageError("-", "", "standard input can be read only once");
  const io::PointFilter& f = o.filter;
  for (std::uint8_t k : f.keep_classes)
    if (std::find(f.drop_classes.begin(), f.drop_classes.end(), k) != f.drop_classes.end())
      throw UsageError("class " + std::to_string(k) + " is in both --keep-class and --drop-class");
  if (f.first_return_only && f.last_return_only)
    throw UsageError("--first-only and --last-only exclude each other");
  if (!o.lines.z_field.empty() && o.lines.z_from_m)
    throw UsageError("--z-field and --z-from-m exclude each other");
}

void check_simplify(const BuildOptions& o) {
  if (o.max_error && !(*o.max_error >= 0 && std::isfinite(*o.max_error)))
    throw UsageError("--max-error: " + number_text(*o.max_error) + " is not a number >= 0");
  if (o.max_vertices > 0 && o.max_vertices < 3)
    throw UsageError("--max-vertices: " + count_text(o.max_vertices) +
                     " vertices make no TIN (give 3 or more)");
}

void check_terrain(const BuildOptions& o) {
  if (o.fix_flats && o.contours.empty())
    throw UsageError("--fix-flats needs --contours: flat triangles are those of one contour level");
  if (!(o.max_edge >= 0))
    throw UsageError("--max-edge: " + number_text(o.max_edge) + " is not a length > 0");
}

// Whether a product other than the TIN file is asked for: then -o may be left out.
bool other_output(const BuildOptions& o) {
  return !o.dem.path.empty() || !o.terrain.path.empty() || !o.contour_lines.path.empty() ||
         !o.preview.path.empty();
}

io::TinFormat check_outputs(const BuildOptions& o) {
  if (o.output.empty() && !other_output(o))
    throw UsageError(
        "no output: give the TIN's file name with -o (--output), or a product (--dem, --terrain, "
        "--contour-lines, --preview)");
  io::TinFormat format{};
  if (o.output.empty()) {
    // No TIN file: GeoJSON, which takes no .prj beside it, stands for the format the options
    // below check.
    format = io::TinFormat::geojson;
  } else if (o.write.format) {
    format = *o.write.format;
  } else {
    try {
      format = io::format_from_path(o.output);
    } catch (const io::UnknownFormatError& e) {
      std::string names;
      for (std::string_view name : io::tin_format_names()) {
        if (!names.empty()) names += '|';
        names += name;
      }
      throw UsageError(e.file(), e.where(), e.detail() + "; use -f " + names);
    }
  }
  const Point3& d = o.write.offset;
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
    throw UsageError("--offset: every coordinate must be a finite number");
  if (!io::format_takes_offset(format) && (o.write.offset_auto || d.x != 0 || d.y != 0 || d.z != 0))
    throw UsageError("--offset: " + std::string(io::format_name(format)) +
                     " output keeps real coordinates (LandXML and GeoPackage have no offset)");
  if (!o.constraints_out.empty()) {
    const std::string ext = lower_extension(o.constraints_out);
    if (ext != ".geojson" && ext != ".json")
      throw UsageError("--constraints-out writes GeoJSON: give a .geojson or .json file, not '" +
                       o.constraints_out + "'");
  }
  if (!o.diagnostics.empty() && lower_extension(o.diagnostics) != ".gpkg")
    throw UsageError("--diagnostics writes a GeoPackage: give a .gpkg file, not '" + o.diagnostics +
                     "'");
  return format;
}

// --preview: a PNG, its size only with it.
void check_preview(const BuildOptions& o) {
  const BuildOptions::Preview& p = o.preview;
  if (p.path.empty() && p.size) throw UsageError("--preview-size needs --preview");
  if (!p.path.empty() && lower_extension(p.path) != ".png")
    throw UsageError(p.path, "", "--preview writes a PNG: give a name ending in .png");
}

// The DEM's format and creation options, checked against GDAL's driver before any work.
void check_dem_format(const BuildOptions::Dem& dem) {
  std::string driver;
  try {
    driver = io::dem_driver_for(dem.path, dem.format, dem.float64());
  } catch (const Error& e) {
    if (!dem.format.empty()) throw UsageError("--dem-format " + dem.format + ": " + e.detail());
    const bool no_driver = e.detail().rfind("no ", 0) == 0;  // no extension, or none writes it
    throw UsageError("--dem " + dem.path + ": " + e.detail() +
                     (no_driver ? " (or name one with --dem-format)" : ""));
  }
  try {
    io::check_dem_creation_options(dem.path, driver, dem.creation_options);
  } catch (const Error& e) {
    throw UsageError("--dem-co: " + e.detail());
  }
}

void check_dem(const BuildOptions::Dem& dem) {
  // Given, whatever the value: one at its default is refused without --dem too.
  const bool dem_settings = dem.resolution != 0 || dem.extent || dem.target_aligned || dem.nodata ||
                            dem.float64_cells || !dem.creation_options.empty() ||
                            !dem.format.empty();
  if (dem.path.empty() && dem_settings)
    throw UsageError(
        "--resolution, --dem-extent, --tap, --dem-nodata, --dem-type, --dem-format and --dem-co "
        "need --dem");
  if (dem.path.empty()) return;
  if (!(dem.resolution > 0) || !std::isfinite(dem.resolution))
    throw UsageError("--dem needs --resolution, a cell size > 0");
  if (dem.extent &&
      (!(dem.extent->min_x < dem.extent->max_x) || !(dem.extent->min_y < dem.extent->max_y)))
    throw UsageError("--dem-extent: give XMIN YMIN XMAX YMAX with XMIN < XMAX, YMIN < YMAX");
  const double v = dem.nodata_or_default();
  const bool fits_float = std::isnan(v) || (std::fabs(v) <= 3.4028234663852886e38 &&
                                            static_cast<double>(static_cast<float>(v)) == v);
  if (!dem.float64() && !fits_float)
    throw UsageError("--dem-nodata: " + products::short_number(v) +
                     " cannot be stored in Float32 cells (use --dem-type Float64)");
  for (const std::string& co : dem.creation_options)
    if (co.find('=') == std::string::npos || co.front() == '=')
      throw UsageError("--dem-co: '" + co + "' is not NAME=VALUE");
  check_dem_format(dem);
}

void check_contour_lines(const BuildOptions::ContourLines& c) {
  // Given, whatever the value: one at its default is refused without --contour-lines too.
  const bool settings = c.interval != 0 || c.base || !c.levels.empty() || c.field;
  if (c.path.empty() && settings)
    throw UsageError("--interval, --base, --levels and --contour-field need --contour-lines");
  if (c.path.empty()) return;
  if (!c.levels.empty() && c.interval != 0)
    throw UsageError("--levels and --interval exclude each other: fixed levels, or every interval");
  if (!c.levels.empty() && c.base)
    throw UsageError("--base goes with --interval, not with the fixed --levels");
  if (c.levels.empty() && (!(c.interval > 0) || !std::isfinite(c.interval)))
    throw UsageError("--contour-lines needs --interval, an interval > 0, or --levels");
  if (!std::isfinite(c.base_or_default())) throw UsageError("--base: not a finite number");
  if (c.field_or_default().empty()) throw UsageError("--contour-field: give a field name");
}

void check_terrain_output(const BuildOptions::Terrain& t) {
  if (t.path.empty() && (t.max_level || t.fill_height || t.max_tiles))
    throw UsageError(
        "--terrain-levels, --terrain-fill-height and --terrain-max-tiles need --terrain");
}

// --dem, --contour-lines and --terrain: their settings only with them, and the ones each needs.
void check_products(const BuildOptions& o) {
  check_dem(o.dem);
  check_contour_lines(o.contour_lines);
  check_terrain_output(o.terrain);
}

}  // namespace

CheckedOptions check_options(const BuildOptions& options) {
  check_inputs(options);
  check_simplify(options);
  check_terrain(options);
  check_products(options);
  check_preview(options);
  CheckedOptions checked;
  checked.format = check_outputs(options);
  if (!options.assign_srs.empty() && !options.override_srs.empty())
    throw UsageError(
        "--a-srs and --override-srs exclude each other: --override-srs gives every input its "
        "CRS, --a-srs only the inputs without one");
  checked.assign_crs_wkt = input_srs_option(options.assign_srs, "--a-srs");
  checked.override_crs_wkt = input_srs_option(options.override_srs, "--override-srs");
  checked.target_crs_wkt = target_srs_option(options);
  if (options.write.ply_ascii && checked.format != io::TinFormat::ply)
    checked.warnings.push_back("--ply-ascii is ignored: the output is " +
                               std::string(io::format_name(checked.format)) + ", not PLY");
  if (options.write.gpkg_tin && checked.format != io::TinFormat::gpkg)
    checked.warnings.push_back("--gpkg-tin is ignored: the output is " +
                               std::string(io::format_name(checked.format)) + ", not GeoPackage");
  if (options.allow_geographic && !io::is_geographic(checked.target_crs_wkt))
    checked.warnings.push_back("--allow-geographic is ignored: " +
                               std::string(checked.target_crs_wkt.empty()
                                               ? "there is no --t-srs"
                                               : "the --t-srs CRS is not geographic"));
  return checked;
}

}  // namespace tincdt::pipeline
