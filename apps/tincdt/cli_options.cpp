#include "cli_options.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace tincdt::cli {
namespace {

using pipeline::BuildOptions;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::optional<double> parse_double(std::string_view s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// "auto" or "X,Y,Z" into the write options.
void parse_offset(const std::string& text, BuildOptions::Write& write) {
  if (lower(text) == "auto") {
    write.offset_auto = true;
    return;
  }
  std::vector<double> v;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const auto d = parse_double(std::string_view(text).substr(
        start, comma == std::string::npos ? std::string::npos : comma - start));
    if (!d) break;
    v.push_back(*d);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (v.size() != 3 || std::count(text.begin(), text.end(), ',') != 2)
    throw CLI::ValidationError("--offset",
                               "'" + text + "' is neither 'auto' nor three numbers X,Y,Z");
  write.offset_auto = false;
  write.offset = Point3{v[0], v[1], v[2]};
}

// "2,8" into CLASSES (each occurrence of the option is one token, so that a following INPUT is
// not taken for a class).
void parse_classes(const std::string& value, std::vector<std::uint8_t>& classes) {
  if (const auto bad = append_class_codes(value, classes))
    throw CLI::ValidationError("'" + *bad + "' is not a LAS classification code (0-255)");
}

class UsageFormatter : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App*, std::string) const override {
    return "Usage: tincdt [OPTIONS] [INPUT...] [--contours LINES]... -o OUTPUT\n"
           "       tincdt --plan PLAN.json --tile N [OPTIONS] -o OUTPUT\n"
           "       tincdt plan INPUT... --tile-size S --buffer B -o PLAN.json  (plan --help)\n"
           "       tincdt merge TILE... -o OUTPUT                              (merge --help)\n";
  }
};

constexpr const char* kFooter = R"(Examples:
  LAS to binary PLY, in local coordinates for a mesh viewer:
    tincdt Topography.las -o tin.ply --offset auto
  Several XYZ files (no CRS in them) to one GeoJSON in WGS 84 (RFC 7946):
    tincdt a.xyz b.xyz --a-srs EPSG:2949 --t-srs EPSG:4326 -o tin.geojson
  Ground class only, with a JSON report:
    tincdt tile.las --keep-class 2 -o ground.obj --stats ground.json
  Ground points plus 3D contour lines as constrained edges:
    tincdt tile.las --keep-class 2 --contours contours.shp -o tin.ply
  A TIN from a contour map alone, z from an attribute:
    tincdt --contours contours.gpkg:contours --z-field ELEV -o tin.ply
  Clip to a boundary polygon (2D: draped), and drop the long edges of a ragged outline:
    tincdt tile.las --keep-class 2 --clip boundary.gpkg --max-edge 25 -o tin.ply
  Erase a lake (no data inside), keep a road centreline as soft edges:
    tincdt tile.las --erase lakes.shp --soft-lines roads.shp -o tin.ply
  Fix the flat triangles of a contour-only TIN, with a QA report:
    tincdt --contours contours.shp --fix-flats -o tin.ply --stats qa.json
  A 10 cm TIN for a web viewer, every contour kept:
    tincdt tile.las --keep-class 2 --contours contours.shp --max-error 0.1 -o web.ply
  LandXML for civil design, a 1 m DEM on the 1 m grid and 2 m contours, one run:
    tincdt tile.las --keep-class 2 -o surface.xml --dem dem.tif --resolution 1 --tap
           --contour-lines contours.gpkg --interval 2
  On one core of a shared machine:
    tincdt big.las -o big.ply --threads 1

Order of the stages (and precedence where features overlap):
  1. points, contours and hard lines: triangulated, the lines made TIN edges
  2. soft lines, clip / erase / replace rings: 2D vertices draped on that TIN,
     then made TIN edges (a draped line crossing a hard one takes its z there)
     --max-error, --max-vertices: then only the points needed to stay within
     the tolerance are kept (every line vertex and segment stays)
  3. --fix-flats
  4. --replace: vertices on or inside get the polygon's z (later polygons win)
  5. --max-edge: trims inward from the convex hull
  6. --clip: triangles outside every clip polygon are removed
  7. --erase: triangles inside an erase polygon are removed (erase wins over
     clip; replaced vertices inside an erase polygon go with their triangles)
  8. --validate, then the outputs (the TIN, then --dem and --contour-lines from
     it): all of them are written, or none

Exit status: 0 success, 1 input, output or runtime error, 2 usage error,
3 internal error (a bug: please report it with the input).)";

// The options of one help group, in the order of the stages.
class Group {
 public:
  Group(CLI::App& app, const char* name) : app_(app), name_(name) {}

  CLI::Option* option(const char* flags, std::string& target, const char* help, const char* type) {
    return app_.add_option(flags, target, help)->type_name(type)->group(name_);
  }
  // A value that CHECK accepts, stored by CLI11 in TARGET.
  template <class T>
  CLI::Option* checked(const char* flags, T& target, const char* help, const char* type,
                       const CLI::Validator& check) {
    return app_.add_option(flags, target, help)->check(check)->type_name(type)->group(name_);
  }
  CLI::Option* flag(const char* flags, bool& target, const char* help) {
    return app_.add_flag(flags, target, help)->group(name_);
  }
  // Repeatable, one value each, so that "--clip a.shp tile.las" or "--keep-class 2 tile.las"
  // leave tile.las an INPUT.
  CLI::Option* repeated(const char* flags, std::vector<std::string>& target, const char* help,
                        const char* type) {
    return app_.add_option(flags, target, help)
        ->type_name(type)
        ->expected(1)
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->group(name_);
  }
  // One of a few words, any case, into an enum; the help shows the words and the default.
  template <class Enum>
  CLI::Option* choice(const char* flags, Enum& target, const char* help,
                      const std::vector<std::pair<std::string, Enum>>& words,
                      const char* fallback) {
    std::string type;
    for (const auto& [word, value] : words) type += (type.empty() ? "" : "|") + word;
    // The word becomes the enum's number, which CLI11 then stores in TARGET.
    const auto to_number = [words, type](std::string& text) {
      for (const auto& [word, value] : words) {
        if (lower(text) != word) continue;
        text = std::to_string(static_cast<int>(value));
        return std::string();
      }
      return "'" + text + "' is not one of " + type;
    };
    return app_.add_option(flags, target, help)
        ->transform(CLI::Validator(to_number, ""))
        ->type_name(type)
        ->default_str(fallback)
        ->group(name_);
  }
  // A value parsed by FN into the options as it is read.
  CLI::Option* parsed(const char* flags, std::function<void(const std::string&)> fn,
                      const char* help, const char* type) {
    return app_.add_option_function<std::string>(flags, std::move(fn), help)
        ->type_name(type)
        ->group(name_);
  }

 private:
  CLI::App& app_;
  const char* name_;
};

void input_options(CLI::App& app, BuildOptions& o) {
  app.add_option("INPUT", o.inputs, "Point files: LAS 1.0-1.4, LAZ, COPC or XYZ text ('-' = stdin)")
      ->type_name("FILE");
  Group g(app, "Input");
  g.option("--a-srs", o.assign_srs,
           "Assign the inputs' CRS (EPSG:n, WKT, PROJ string or .prj file),\n"
           "for files without one; overrides the files' own",
           "SRS");
  const auto classes = [&app](const char* flags, std::vector<std::uint8_t>& target,
                              const char* help) {
    app.add_option(flags)
        ->description(help)
        ->each([&target](const std::string& v) { parse_classes(v, target); })
        ->type_name("N[,N...]")
        ->expected(1)
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->group("Input");
  };
  classes("--keep-class", o.filter.keep_classes, "Keep only these LAS classes (e.g. 2,8)");
  classes("--drop-class", o.filter.drop_classes, "Drop these LAS classes (e.g. 7,18: noise)");
  g.flag("--first-only", o.filter.first_return_only, "Keep only first returns (LAS)");
  g.flag("--last-only", o.filter.last_return_only, "Keep only last returns (LAS)");
}

void line_options(CLI::App& app, BuildOptions& o) {
  Group g(app, "Surface features (any OGR source: FILE or FILE:LAYER; repeatable)");
  g.repeated("--contours", o.contours,
             "Contour lines: hard edges; their flats are what --fix-flats fixes", "LINES");
  g.repeated("--hard-lines,--breaklines", o.breaklines,
             "Hard lines (breaklines): every segment is a TIN edge", "LINES");
  g.repeated("--soft-lines", o.soft_lines,
             "Soft lines: TIN edges with z draped from the TIN (own z ignored)", "LINES");
  g.option("--layer", o.lines.layer, "Layer to read from each vector source", "NAME");
  g.option("--z-field", o.lines.z_field, "Take z from this attribute (contours, lines, replace)",
           "NAME");
  g.flag("--z-from-m", o.lines.z_from_m, "Take z from the M values (contours, lines, replace)");
}

void triangulation_options(CLI::App& app, BuildOptions& o) {
  Group g(app, "Triangulation");
  g.choice("--on-duplicate", o.on_duplicate,
           "z of points with equal x, y: the first in input order,\nor their min, max or mean",
           std::vector<std::pair<std::string, delaunay::DuplicatePolicy>>{
               {"first", delaunay::DuplicatePolicy::first},
               {"min", delaunay::DuplicatePolicy::min},
               {"max", delaunay::DuplicatePolicy::max},
               {"mean", delaunay::DuplicatePolicy::mean}},
           "mean");
  g.choice(
      "--on-crossing", o.constraint.on_crossing,
      "Crossing contours / hard lines: join them at a new vertex, or stop\n"
      "with an error (surface features always join)",
      std::vector<std::pair<std::string, constraints::OnCrossing>>{
          {"split", constraints::OnCrossing::split}, {"error", constraints::OnCrossing::error}},
      "split");
  g.choice("--restore", o.constraint.restore,
           "After each line is in: restore the constrained Delaunay property,\n"
           "improve aspect ratios (the paper's criterion), or leave the swaps",
           std::vector<std::pair<std::string, constraints::Restore>>{
               {"delaunay", constraints::Restore::delaunay},
               {"aspect", constraints::Restore::aspect},
               {"none", constraints::Restore::none}},
           "delaunay");
}

void simplify_options(CLI::App& app, BuildOptions& o) {
  Group g(app, "Simplification (after the surface features)");
  g.parsed(
      "--max-error",
      [&o](const std::string& v) {
        const auto d = parse_double(v);
        if (!d || !(*d >= 0))
          throw CLI::ValidationError("--max-error", "'" + v + "' is not a number >= 0");
        o.max_error = *d;
      },
      "Keep only the points needed for every point to lie within Z\n"
      "(vertically) of the TIN; contours and breaklines stay whole",
      "Z");
  g.parsed(
      "--max-vertices",
      [&o](const std::string& v) {
        std::size_t n = 0;
        const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
        if (v.empty() || ec != std::errc() || end != v.data() + v.size() || n < 3)
          throw CLI::ValidationError("--max-vertices", "'" + v + "' is not a count >= 3");
        o.max_vertices = n;
      },
      "Stop simplifying at N vertices (alone: with --max-error 0)", "N");
}

void terrain_options(CLI::App& app, BuildOptions& o) {
  Group quality(app, "Quality (after the lines are in, in this order)");
  quality.flag("--fix-flats", o.fix_flats,
               "Remove flat triangles (3 corners on one contour level) by swaps,\n"
               "then by vertices on the contours' medial axis (needs --contours)");
  quality.repeated("--replace", o.replace,
                   "Replace polygons: vertices on or inside get the polygon's one z\n"
                   "(--z-field, --z-from-m or 3D z); rings become TIN edges",
                   "POLYGONS");
  Group boundary(app, "TIN boundary (after --fix-flats and --replace, in this order)");
  app.add_option("--max-edge", o.max_edge,
                 "Trim boundary triangles with a longer edge, inward from the hull,\n"
                 "so concave outlines are not bridged")
      ->check(CLI::Validator(
          [](std::string& v) {
            const auto d = parse_double(v);
            return d && *d > 0 ? std::string() : "'" + v + "' is not a length > 0";
          },
          ""))
      ->type_name("LENGTH")
      ->group("TIN boundary (after --fix-flats and --replace, in this order)");
  boundary.repeated("--clip", o.clip, "Remove the triangles outside these polygons (2D: draped)",
                    "POLYGONS");
  boundary.repeated("--erase", o.erase,
                    "Remove the triangles inside these polygons (holes; wins over --clip)",
                    "POLYGONS");
  Group checks(app, "Checks");
  checks.flag("--validate", o.validate, "Check the TIN's topology and Delaunay property");
}

void output_options(CLI::App& app, BuildOptions& o) {
  Group g(app, "Output (written together at the end: all of them, or none)");
  g.option("-o,--output", o.output,
           "The TIN file: .obj, .ply, .geojson/.json, .xml/.landxml (LandXML),\n"
           ".gpkg or .stl",
           "FILE")
      ->required();
  g.parsed(
       "-f,--format",
       [&o](const std::string& v) {
         const std::string f = lower(v);
         o.write.format = f == "obj"       ? io::TinFormat::obj
                          : f == "ply"     ? io::TinFormat::ply
                          : f == "landxml" ? io::TinFormat::landxml
                          : f == "gpkg"    ? io::TinFormat::gpkg
                          : f == "stl"     ? io::TinFormat::stl
                                           : io::TinFormat::geojson;
       },
       "Output format, overriding the extension", "obj|ply|geojson|landxml|gpkg|stl")
      ->check(CLI::IsMember({"obj", "ply", "geojson", "landxml", "gpkg", "stl"}, CLI::ignore_case)
                  .description(""));
  g.flag("--overwrite", o.write.overwrite,
         "Replace existing outputs (TIN, stats, lines, diagnostics);\n"
         "never an input, nor a file that belongs to one");
  g.flag("--ply-ascii", o.write.ply_ascii, "Write PLY as text instead of binary");
  g.flag("--gpkg-tin", o.write.gpkg_tin,
         "GeoPackage: TIN Z features instead of POLYGON Z (not every GIS reads them)");
  g.parsed(
      "--offset", [&o](const std::string& v) { parse_offset(v, o.write); },
      "Subtract X,Y,Z from written coordinates (recorded in the file);\n"
      "auto = the data's min corner, rounded down to 1000",
      "auto|X,Y,Z");
  g.option("--t-srs", o.write.target_srs, "Reproject the GeoJSON output to SRS (e.g. EPSG:4326)",
           "SRS");
  g.option("--constraints-out", o.constraints_out,
           "Write the TIN's constrained edges as GeoJSON lines with their\n"
           "source file and feature id",
           "FILE.geojson");
  g.option("--diagnostics", o.diagnostics,
           "Write crossings, skipped segments and dropped features as\n"
           "GeoPackage layers with the input feature ids",
           "FILE.gpkg");
  g.option("--stats", o.stats_path, "Write counts, quality, timings and memory as JSON",
           "FILE.json");
}

// A number > 0, or any finite number.
CLI::Validator number_check(bool positive) {
  return CLI::Validator(
      [positive](std::string& v) {
        const auto d = parse_double(v);
        if (d && (!positive || *d > 0)) return std::string();
        return "'" + v + "' is not " + (positive ? "a number > 0" : "a number");
      },
      "");
}

void product_options(CLI::App& app, BuildOptions& o) {
  const char* group = "Products (from the final TIN: after every step above)";
  Group g(app, group);
  g.option("--dem", o.dem.path,
           "Rasterize the TIN to a Cloud-Optimized GeoTIFF: each cell centre gets\n"
           "its triangle's linear interpolation, nodata outside (needs --resolution)",
           "FILE.tif");
  g.checked("--resolution", o.dem.resolution, "DEM cell size, in the CRS's units", "R",
            number_check(true));
  app.add_option_function<std::vector<double>>(
         "--dem-extent",
         [&o](const std::vector<double>& v) {
           BBox box;
           box.min_x = v[0];
           box.min_y = v[1];
           box.max_x = v[2];
           box.max_y = v[3];
           o.dem.extent = box;
         },
         "DEM extent (default: the TIN's)")
      ->expected(4)
      ->check(number_check(false))
      ->type_name("XMIN YMIN XMAX YMAX")
      ->group(group);
  g.flag("--tap", o.dem.target_aligned,
         "Snap the DEM extent out to multiples of the resolution (as gdalwarp -tap)");
  g.parsed(
       "--dem-nodata",
       [&o](const std::string& v) {
         o.dem.nodata = lower(v) == "nan" ? std::nan("") : *parse_double(v);
       },
       "Value of the DEM cells outside the TIN (or nan)", "V")
      ->check(CLI::Validator(
          [](std::string& v) {
            return lower(v) == "nan" || parse_double(v) ? std::string()
                                                        : "'" + v + "' is not a number";
          },
          ""))
      ->default_str("-9999");
  g.choice("--dem-type", o.dem.float64, "DEM cell type",
           std::vector<std::pair<std::string, bool>>{{"float32", false}, {"float64", true}},
           "float32");
  g.repeated("--dem-co", o.dem.creation_options,
             "A GDAL COG creation option over the defaults (DEFLATE level 1,\n"
             "predictor, average overviews), e.g. COMPRESS=ZSTD",
             "NAME=VALUE");
  g.option("--contour-lines", o.contour_lines.path,
           "Trace contour lines on the TIN into any OGR vector format, by\n"
           "extension (.gpkg, .shp, .geojson, ...), with an elev field (needs --interval)",
           "FILE");
  g.checked("--interval", o.contour_lines.interval, "Contour interval", "I", number_check(true));
  g.checked("--base", o.contour_lines.base, "Contour levels are BASE + k * interval", "B",
            number_check(false))
      ->default_str("0");
}

void tile_options(CLI::App& app, tiles::TileOptions& o) {
  Group g(app, "Tiled jobs (one tile of a plan made by 'tincdt plan')");
  g.option("--plan", o.plan, "The plan; the inputs and how to read them come from it", "PLAN.json");
  g.checked("--tile", o.tile, "The tile to build: its index in the plan (0, 1, ...)", "N",
            CLI::NonNegativeNumber);
  g.checked("--buffer", o.buffer,
            "Read this far around the tile instead of the plan's buffer\n"
            "(the tiles already built stay valid)",
            "LENGTH", CLI::NonNegativeNumber);
  g.option("--outline", o.outline,
           "Also write the tile's outline, for 'tincdt merge --check'\n"
           "when the tiles are too many to keep or to merge",
           "FILE.ply");
}

void run_options(CLI::App& app, BuildOptions& o, Verbosity& v) {
  Group g(app, "Run");
  app.add_option("--threads", o.threads,
                 "Threads for the parallel stages (reading XYZ, Delaunay, quality);\n"
                 "0 = every core")
      ->type_name("N")
      ->default_str("0")
      ->check(CLI::Validator(
          [](std::string& text) {
            unsigned n = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
            const bool ok =
                !text.empty() && ec == std::errc() && end == text.data() + text.size() && n <= 1024;
            return ok ? std::string() : "'" + text + "' is not a thread count (0-1024)";
          },
          ""))
      ->group("Run");
  g.flag("-q,--quiet", v.quiet, "Only warnings and errors; no progress");
  g.flag("-v,--verbose", v.verbose, "Also debug messages");
  app.set_help_flag("-h,--help", "Print this help and exit")->group("Run");
  app.set_version_flag("--version", "tincdt " TINCDT_VERSION, "Print the version and exit")
      ->group("Run");
}

}  // namespace

std::optional<std::string> append_class_codes(const std::string& text,
                                              std::vector<std::uint8_t>& classes) {
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    unsigned code = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), code);
    if (item.empty() || ec != std::errc() || end != item.data() + item.size() || code > 255)
      return item;
    classes.push_back(static_cast<std::uint8_t>(code));
    if (comma == std::string::npos) return std::nullopt;
    start = comma + 1;
  }
}

void define_options(CLI::App& app, BuildOptions& options, tiles::TileOptions& tiling,
                    Verbosity& verbosity) {
  app.formatter(std::make_shared<UsageFormatter>());
  app.get_formatter()->column_width(26);
  app.footer(kFooter);
  app.set_help_flag();  // defined last, in the "Run" group
  input_options(app, options);
  line_options(app, options);
  triangulation_options(app, options);
  simplify_options(app, options);
  terrain_options(app, options);
  output_options(app, options);
  product_options(app, options);
  tile_options(app, tiling);
  run_options(app, options, verbosity);
}

}  // namespace tincdt::cli
