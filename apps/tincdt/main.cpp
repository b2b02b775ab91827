// tincdt: the command line over pipeline::build. Options -> BuildOptions, spdlog on stderr,
// tincdt::Error -> one-line message and exit code (0 ok, 1 error, 2 usage).
#include <signal.h>
#include <unistd.h>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "io/crs.hpp"
#include "pipeline/build.hpp"

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace {

using namespace tincdt;

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// A bad option value found after CLI11 parsed the command line.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ---- stderr: log lines and the progress line share it ---------------------------------------

class Terminal {
 public:
  static Terminal& get() {
    static Terminal t;
    return t;
  }

  void enable_progress(bool on) {
    std::lock_guard lock(mutex_);
    progress_on_ = on;
  }

  // Writes one complete line, erasing the progress line first (the next update redraws it).
  void line(std::string_view text) {
    std::lock_guard lock(mutex_);
    erase_locked();
    std::fwrite(text.data(), 1, text.size(), stderr);
    std::fputc('\n', stderr);
    std::fflush(stderr);
  }

  // "tincdt: delaunay 80%", redrawn at most every 100 ms unless the stage changes.
  void progress(std::string_view stage, double fraction) {
    std::lock_guard lock(mutex_);
    if (!progress_on_) return;
    const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
    const auto now = std::chrono::steady_clock::now();
    const bool new_stage = stage != stage_;
    if (!new_stage &&
        (percent == percent_ || (now - drawn_ < std::chrono::milliseconds(100) && percent != 100)))
      return;
    stage_.assign(stage);
    percent_ = percent;
    drawn_ = now;
    std::fprintf(stderr, "\r\x1b[Ktincdt: %s %d%%", stage_.c_str(), percent);
    std::fflush(stderr);
    shown_ = true;
  }

  void erase_progress() {
    std::lock_guard lock(mutex_);
    erase_locked();
  }

 private:
  void erase_locked() {
    if (!shown_) return;
    std::fputs("\r\x1b[K", stderr);
    shown_ = false;
    stage_.clear();
    percent_ = -1;
  }

  std::mutex mutex_;
  bool progress_on_ = false;
  bool shown_ = false;
  std::string stage_;
  int percent_ = -1;
  std::chrono::steady_clock::time_point drawn_{};
};

// "tincdt: warning: ..." on stderr; info lines carry no level word.
class StderrSink final : public spdlog::sinks::base_sink<spdlog::details::null_mutex> {
 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    std::string text = "tincdt: ";
    switch (msg.level) {
      case spdlog::level::trace:
      case spdlog::level::debug:
        text += "debug: ";
        break;
      case spdlog::level::warn:
        text += "warning: ";
        break;
      case spdlog::level::err:
      case spdlog::level::critical:
        text += "error: ";
        break;
      default:
        break;
    }
    text.append(msg.payload.data(), msg.payload.size());
    Terminal::get().line(text);
  }
  void flush_() override { std::fflush(stderr); }
};

void setup_logging() {
  auto logger = std::make_shared<spdlog::logger>("tincdt", std::make_shared<StderrSink>());
  logger->set_level(spdlog::level::info);
  logger->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(std::move(logger));
}

// ---- interruption: Ctrl-C stops at the next progress report, temporaries are removed --------

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) {
  g_signal = sig;
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second signal takes the default action at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

// ---- option values -----------------------------------------------------------------------------

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

// "auto" or "X,Y,Z".
void parse_offset(const std::string& text, pipeline::BuildOptions& options) {
  if (lower(text) == "auto") {
    options.offset_auto = true;
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
    throw UsageError("--offset: '" + text + "' is neither 'auto' nor three numbers X,Y,Z");
  options.write.offset = Point3{v[0], v[1], v[2]};
}

// "2,8" or repeated options; each occurrence is one token so that a following INPUT is not taken.
std::vector<std::uint8_t> parse_classes(const std::vector<std::string>& values,
                                        const char* option) {
  std::vector<std::string> items;
  for (const std::string& value : values) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = value.find(',', start);
      items.push_back(value.substr(start, comma == std::string::npos ? comma : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  std::vector<std::uint8_t> classes;
  for (const std::string& item : items) {
    unsigned value = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (item.empty() || ec != std::errc() || end != item.data() + item.size() || value > 255)
      throw UsageError(std::string(option) + ": '" + item +
                       "' is not a LAS classification code (0-255)");
    classes.push_back(static_cast<std::uint8_t>(value));
  }
  return classes;
}

std::string crs_option(const std::string& text, const char* option) {
  try {
    return io::crs_from_user(text);
  } catch (const Error& e) {
    throw UsageError(std::string(option) + ": " + e.what());
  }
}

// ---- summary -----------------------------------------------------------------------------------

std::string count(std::uint64_t n) {  // 1234567 -> "1,234,567"
  std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string bytes(std::uint64_t n) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(n);
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return buf;
}

std::string secs(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, s < 10 ? "%.3f s" : "%.1f s", s);
  return buf;
}

void log_summary(const pipeline::BuildOptions& options, const pipeline::BuildReport& r) {
  const auto point_files = static_cast<std::uint64_t>(
      std::count_if(r.inputs.begin(), r.inputs.end(),
                    [](const pipeline::BuildReport::Input& in) { return in.kind == "points"; }));
  std::string line = "read " + count(r.points_read) + " points from " + count(point_files) +
                     (point_files == 1 ? " file" : " files");
  if (r.line_vertices > 0) line += " and " + count(r.line_vertices) + " line vertices";
  if (r.points_kept != r.points_read) line += ", kept " + count(r.points_kept);
  if (r.duplicates_merged > 0) line += ", merged " + count(r.duplicates_merged) + " duplicates";
  spdlog::info(line);
  if (r.constraint_segments > 0) {
    std::string c = "constraints: " + count(r.constraint_segments) + " segments";
    if (r.line_features > 0) c += " from " + count(r.line_features) + " line features";
    if (r.surface_features > 0)
      c += (r.line_features > 0 ? " and " : " from ") + count(r.surface_features) +
           " surface features";
    if (r.crossings > 0) c += ", " + count(r.crossings) + " crossings joined";
    if (r.constraint_segments_split > 0)
      c += ", " + count(r.constraint_segments_split) + " split at vertices";
    spdlog::info(c);
  }
  if (r.draped_vertices > 0)
    spdlog::info("draped: {} vertices ({} of soft lines)", count(r.draped_vertices),
                 count(r.soft_line_vertices));
  if (r.flats.fixed)
    spdlog::info("flat triangles: {} before, {} after ({} swaps, {} new vertices)",
                 count(r.flats.before), count(r.flats.after), count(r.flats.swaps),
                 count(r.flats.vertices_added));
  if (r.replaced_vertices > 0) spdlog::info("replace: {} vertices", count(r.replaced_vertices));
  if (r.trimmed_triangles + r.clipped_triangles + r.erased_triangles > 0)
    spdlog::info("removed triangles: {} trimmed (--max-edge), {} clipped, {} erased",
                 count(r.trimmed_triangles), count(r.clipped_triangles), count(r.erased_triangles));
  spdlog::info("TIN: {} vertices, {} triangles{}", count(r.vertices), count(r.triangles),
               r.constraints > 0 ? ", " + count(r.constraints) + " constrained edges" : "");
  std::string t =
      "time: read " + secs(r.timings_s.read) + ", delaunay " + secs(r.timings_s.delaunay);
  if (r.timings_s.constraints > 0) t += ", constraints " + secs(r.timings_s.constraints);
  if (r.timings_s.surface > 0) t += ", surface features " + secs(r.timings_s.surface);
  if (r.timings_s.terrain > 0.0005) t += ", terrain " + secs(r.timings_s.terrain);
  if (r.timings_s.validate > 0) t += ", validate " + secs(r.timings_s.validate);
  t += ", write " + secs(r.timings_s.write) + ", total " + secs(r.timings_s.total);
  if (r.peak_rss_bytes > 0) t += "; peak memory " + bytes(r.peak_rss_bytes);
  spdlog::info(t);
  const std::string format = r.output_format == "obj"       ? "OBJ"
                             : r.output_format == "geojson" ? "GeoJSON"
                             : options.write.ply_ascii      ? "PLY ASCII"
                                                            : "PLY binary";
  std::string w = "wrote " + r.output + " (" + format + ", " + bytes(r.output_bytes) + ", " +
                  (r.crs.empty() ? (r.crs_wkt.empty() ? "no CRS" : "CRS unnamed") : "CRS " + r.crs);
  if (r.offset.x != 0 || r.offset.y != 0 || r.offset.z != 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", offset %.17g,%.17g,%.17g", r.offset.x, r.offset.y,
                  r.offset.z);
    w += buf;
  }
  spdlog::info(w + ")");
  if (!r.constraints_out.empty()) spdlog::info("wrote {}", r.constraints_out);
  if (!r.diagnostics.empty()) spdlog::info("wrote {}", r.diagnostics);
  if (!options.stats_path.empty()) spdlog::info("wrote {}", options.stats_path);
}

// ---- the command line --------------------------------------------------------------------------

struct Cli {
  std::vector<std::string> inputs;
  std::string output;
  std::string format;
  bool overwrite = false;
  bool ply_ascii = false;
  std::string offset;
  std::string t_srs;
  std::string a_srs;
  std::string on_duplicate = "mean";
  std::vector<std::string> keep_class;
  std::vector<std::string> drop_class;
  bool first_only = false;
  bool last_only = false;
  std::string stats;
  bool validate = false;
  std::vector<std::string> contours;
  std::vector<std::string> breaklines;
  std::vector<std::string> hard_lines;
  std::vector<std::string> soft_lines;
  std::vector<std::string> clip;
  std::vector<std::string> erase;
  std::vector<std::string> replace;
  std::string max_edge;
  bool fix_flats = false;
  std::string constraints_out;
  std::string diagnostics;
  std::string layer;
  std::string z_field;
  bool z_from_m = false;
  std::string restore = "delaunay";
  std::string on_crossing = "split";
  bool quiet = false;
  bool verbose = false;
};

class UsageFormatter : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App*, std::string) const override {
    return "Usage: tincdt [OPTIONS] [INPUT...] [--contours LINES]... -o OUTPUT\n";
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

Order of the stages (and precedence where features overlap):
  1. points, contours and hard lines: triangulated, the lines made TIN edges
  2. soft lines, clip / erase / replace rings: 2D vertices draped on that TIN,
     then made TIN edges (a draped line crossing a hard one takes its z there)
  3. --fix-flats
  4. --replace: vertices on or inside get the polygon's z (later polygons win)
  5. --max-edge: trims inward from the convex hull
  6. --clip: triangles outside every clip polygon are removed
  7. --erase: triangles inside an erase polygon are removed (erase wins over
     clip; replaced vertices inside an erase polygon go with their triangles)

Exit status: 0 success, 1 input, output or runtime error, 2 usage error.)";

void define_options(CLI::App& app, Cli& c) {
  app.formatter(std::make_shared<UsageFormatter>());
  app.get_formatter()->column_width(26);
  app.footer(kFooter);
  app.set_version_flag("--version", "tincdt " TINCDT_VERSION, "Print the version and exit");
  app.set_help_flag("-h,--help", "Print this help and exit");

  app.add_option("INPUT", c.inputs, "Point files: LAS 1.0-1.4, or XYZ text ('-' = stdin)")
      ->type_name("FILE");

  // Repeatable, one value each, so that "--clip a.shp tile.las" or "--keep-class 2 tile.las"
  // leave tile.las an INPUT.
  const auto vector_option = [&app](const char* name, std::vector<std::string>& target,
                                    const char* help, const char* type, const char* group) {
    app.add_option(name, target, help)
        ->type_name(type)
        ->expected(1)
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->group(group);
  };
  // One of a few words, any case; the help shows them and the default.
  const auto choice_option = [&app](const char* name, std::string& target, const char* help,
                                    const std::vector<std::string>& words, const char* group) {
    std::string type;
    for (const std::string& w : words) type += (type.empty() ? "" : "|") + w;
    return app.add_option(name, target, help)
        ->check(CLI::IsMember(words, CLI::ignore_case).description(""))
        ->type_name(type)
        ->capture_default_str()
        ->group(group);
  };

  const char* out = "Output";
  app.add_option("-o,--output", c.output, "The TIN file: .obj, .ply, .geojson or .json")
      ->required()
      ->type_name("FILE")
      ->group(out);
  choice_option("-f,--format", c.format, "Output format, overriding the extension",
                {"obj", "ply", "geojson"}, out)
      ->default_str("");
  app.add_flag("--overwrite", c.overwrite,
               "Replace existing outputs (TIN, stats, lines, diagnostics)")
      ->group(out);
  app.add_flag("--ply-ascii", c.ply_ascii, "Write PLY as text instead of binary")->group(out);
  app.add_option("--offset", c.offset,
                 "Subtract X,Y,Z from written coordinates (recorded in the file);\n"
                 "auto = the data's min corner, rounded down to 1000")
      ->type_name("auto|X,Y,Z")
      ->group(out);
  app.add_option("--t-srs", c.t_srs, "Reproject the GeoJSON output to SRS (e.g. EPSG:4326)")
      ->type_name("SRS")
      ->group(out);
  app.add_option("--stats", c.stats, "Write counts, quality, timings and memory as JSON")
      ->type_name("FILE.json")
      ->group(out);

  const char* in = "Input";
  app.add_option("--a-srs", c.a_srs,
                 "Assign the inputs' CRS (EPSG:n, WKT, PROJ string or .prj file),\n"
                 "for files without one; overrides the files' own")
      ->type_name("SRS")
      ->group(in);
  vector_option("--keep-class", c.keep_class, "Keep only these LAS classes (e.g. 2,8)", "N[,N...]",
                in);
  vector_option("--drop-class", c.drop_class, "Drop these LAS classes (e.g. 7,18: noise)",
                "N[,N...]", in);
  app.add_flag("--first-only", c.first_only, "Keep only first returns (LAS)")->group(in);
  app.add_flag("--last-only", c.last_only, "Keep only last returns (LAS)")->group(in);

  const char* lines = "Surface features (any OGR source: FILE or FILE:LAYER; repeatable)";
  vector_option("--contours", c.contours,
                "Contour lines: hard edges; their flats are what --fix-flats fixes", "LINES",
                lines);
  vector_option("--hard-lines", c.hard_lines,
                "Hard lines (breaklines): every segment is a TIN edge", "LINES", lines);
  vector_option("--breaklines", c.breaklines, "The same as --hard-lines", "LINES", lines);
  vector_option("--soft-lines", c.soft_lines,
                "Soft lines: TIN edges with z draped from the TIN (own z ignored)", "LINES", lines);
  vector_option("--replace", c.replace,
                "Replace polygons: vertices on or inside get the polygon's one z\n"
                "(--z-field, --z-from-m or 3D z); rings become TIN edges",
                "POLYGONS", lines);
  app.add_option("--layer", c.layer, "Layer to read from each vector source")
      ->type_name("NAME")
      ->group(lines);
  app.add_option("--z-field", c.z_field, "Take z from this attribute (contours, lines, replace)")
      ->type_name("NAME")
      ->group(lines);
  app.add_flag("--z-from-m", c.z_from_m, "Take z from the M values (contours, lines, replace)")
      ->group(lines);
  choice_option("--on-crossing", c.on_crossing,
                "Crossing contours / hard lines: join them at a new vertex, or stop\n"
                "with an error (surface features always join)",
                {"split", "error"}, lines);
  choice_option("--restore", c.restore,
                "After each line is in: restore the constrained Delaunay property,\n"
                "improve aspect ratios (the paper's criterion), or leave the swaps",
                {"delaunay", "aspect", "none"}, lines);

  const char* boundary = "TIN boundary (after --fix-flats and --replace, in this order)";
  app.add_option("--max-edge", c.max_edge,
                 "Trim boundary triangles with a longer edge, inward from the hull,\n"
                 "so concave outlines are not bridged")
      ->type_name("LENGTH")
      ->group(boundary);
  vector_option("--clip", c.clip, "Remove the triangles outside these polygons (2D: draped)",
                "POLYGONS", boundary);
  vector_option("--erase", c.erase,
                "Remove the triangles inside these polygons (holes; wins over --clip)", "POLYGONS",
                boundary);

  const char* quality = "Quality";
  app.add_flag("--fix-flats", c.fix_flats,
               "Remove flat triangles (3 corners on one contour level) by swaps,\n"
               "then by vertices on the contours' medial axis (needs --contours)")
      ->group(quality);
  app.add_option("--diagnostics", c.diagnostics,
                 "Write crossings, skipped segments and dropped features as\n"
                 "GeoPackage layers with the input feature ids")
      ->type_name("FILE.gpkg")
      ->group(quality);
  app.add_option("--constraints-out", c.constraints_out,
                 "Write the TIN's constrained edges as GeoJSON lines with their\n"
                 "source file and feature id")
      ->type_name("FILE.geojson")
      ->group(quality);

  const char* tri = "Triangulation";
  choice_option("--on-duplicate", c.on_duplicate, "z of points with equal x, y",
                {"first", "min", "max", "mean"}, tri);
  app.add_flag("--validate", c.validate, "Check the TIN's topology and Delaunay property")
      ->group(quality);

  const char* msg = "Messages";
  app.add_flag("-q,--quiet", c.quiet, "Only warnings and errors; no progress")->group(msg);
  app.add_flag("-v,--verbose", c.verbose, "Also debug messages")->group(msg);
}

pipeline::BuildOptions to_build_options(const Cli& c) {
  pipeline::BuildOptions o;
  o.inputs = c.inputs;
  o.output = c.output;
  o.stats_path = c.stats;

  io::TinFormat format{};
  if (!c.format.empty()) {
    const std::string f = lower(c.format);
    format = f == "obj" ? io::TinFormat::obj
                        : (f == "ply" ? io::TinFormat::ply : io::TinFormat::geojson);
    o.write.format = format;
  } else {
    try {
      format = io::format_from_path(c.output);
    } catch (const Error& e) {
      throw UsageError(std::string(e.what()) + "; use -f obj|ply|geojson");
    }
  }
  o.write.overwrite = c.overwrite;
  o.write.ply_ascii = c.ply_ascii;
  if (c.ply_ascii && format != io::TinFormat::ply)
    spdlog::warn("--ply-ascii is ignored: the output is {}, not PLY",
                 pipeline::format_name(format));
  if (!c.offset.empty()) parse_offset(c.offset, o);

  if (!c.t_srs.empty()) {
    if (format != io::TinFormat::geojson)
      throw UsageError("--t-srs needs GeoJSON output; OBJ and PLY keep the input CRS (in a .prj)");
    o.write.target_crs_wkt = crs_option(c.t_srs, "--t-srs");
  }
  if (!c.a_srs.empty()) o.assign_crs_wkt = crs_option(c.a_srs, "--a-srs");

  o.filter.keep_classes = parse_classes(c.keep_class, "--keep-class");
  o.filter.drop_classes = parse_classes(c.drop_class, "--drop-class");
  for (std::uint8_t k : o.filter.keep_classes)
    if (std::find(o.filter.drop_classes.begin(), o.filter.drop_classes.end(), k) !=
        o.filter.drop_classes.end())
      throw UsageError("class " + std::to_string(k) + " is in both --keep-class and --drop-class");
  if (c.first_only && c.last_only)
    throw UsageError("--first-only and --last-only exclude each other");
  o.filter.first_return_only = c.first_only;
  o.filter.last_return_only = c.last_only;

  static const std::map<std::string, delaunay::DuplicatePolicy> policies = {
      {"first", delaunay::DuplicatePolicy::first},
      {"min", delaunay::DuplicatePolicy::min},
      {"max", delaunay::DuplicatePolicy::max},
      {"mean", delaunay::DuplicatePolicy::mean}};
  o.on_duplicate = policies.at(lower(c.on_duplicate));
  o.validate = c.validate;

  if (c.inputs.empty() && c.contours.empty() && c.breaklines.empty() && c.hard_lines.empty())
    throw UsageError("no input: give point files, --contours or --hard-lines (--breaklines)");
  o.contours = c.contours;
  o.breaklines = c.breaklines;
  o.breaklines.insert(o.breaklines.end(), c.hard_lines.begin(), c.hard_lines.end());
  o.soft_lines = c.soft_lines;
  o.clip = c.clip;
  o.erase = c.erase;
  o.replace = c.replace;
  if (!c.max_edge.empty()) {
    const auto v = parse_double(c.max_edge);
    if (!v || !(*v > 0)) throw UsageError("--max-edge: '" + c.max_edge + "' is not a length > 0");
    o.max_edge = *v;
  }
  if (c.fix_flats && c.contours.empty())
    throw UsageError("--fix-flats needs --contours: flat triangles are those of one contour level");
  o.fix_flats = c.fix_flats;
  if (!c.constraints_out.empty()) {
    const std::string ext = lower(std::filesystem::path(c.constraints_out).extension().string());
    if (ext != ".geojson" && ext != ".json")
      throw UsageError("--constraints-out writes GeoJSON: give a .geojson or .json file, not '" +
                       c.constraints_out + "'");
    o.constraints_out = c.constraints_out;
  }
  if (!c.diagnostics.empty()) {
    if (lower(std::filesystem::path(c.diagnostics).extension().string()) != ".gpkg")
      throw UsageError("--diagnostics writes a GeoPackage: give a .gpkg file, not '" +
                       c.diagnostics + "'");
    o.diagnostics = c.diagnostics;
  }
  o.lines.layer = c.layer;
  o.lines.z_field = c.z_field;
  o.lines.z_from_m = c.z_from_m;
  if (!c.z_field.empty() && c.z_from_m)
    throw UsageError("--z-field and --z-from-m exclude each other");
  const std::string restore = lower(c.restore);
  o.constraint.restore = restore == "aspect" ? constraints::Restore::aspect
                         : restore == "none" ? constraints::Restore::none
                                             : constraints::Restore::delaunay;
  o.constraint.on_crossing = lower(c.on_crossing) == "error" ? constraints::OnCrossing::error
                                                             : constraints::OnCrossing::split;
  return o;
}

int usage_error(const std::string& message) {
  spdlog::error(message);
  Terminal::get().line("Try 'tincdt --help' for more information.");
  return kExitUsage;
}

int run(int argc, char** argv) {
  setup_logging();

  CLI::App app("tincdt " TINCDT_VERSION
               ": exact Delaunay TIN from LiDAR (LAS) and XYZ points, written as OBJ, PLY or "
               "GeoJSON.",
               "tincdt");
  Cli cli;
  define_options(app, cli);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(e.what());
  }

  if (cli.quiet && cli.verbose)
    return usage_error("-q/--quiet and -v/--verbose exclude each other");
  if (cli.quiet) spdlog::set_level(spdlog::level::warn);
  if (cli.verbose) spdlog::set_level(spdlog::level::debug);

  pipeline::BuildOptions options;
  try {
    options = to_build_options(cli);
  } catch (const UsageError& e) {
    return usage_error(e.what());
  }

  Terminal::get().enable_progress(!cli.quiet && ::isatty(STDERR_FILENO) == 1);
  std::string stage_now = "read";  // the stage last heard of, for "out of memory"
  const ProgressFn progress = [&stage_now](std::string_view stage, double fraction) {
    if (stage_now != stage) stage_now = stage;
    if (g_signal != 0) return false;
    Terminal::get().progress(stage, fraction);
    return true;
  };
  const pipeline::LogFn log = [](int level, const std::string& message) {
    switch (level) {
      case pipeline::log_debug:
        spdlog::debug(message);
        break;
      case pipeline::log_info:
        spdlog::info(message);
        break;
      default:
        spdlog::warn(message);
        break;
    }
  };

  if (std::find(options.inputs.begin(), options.inputs.end(), "-") != options.inputs.end() &&
      ::isatty(STDIN_FILENO) == 1)
    spdlog::info("reading x y z lines from the terminal; end with Ctrl-D");

  install_signal_handlers();
  try {
    const pipeline::BuildReport report = pipeline::build(options, &progress, log);
    Terminal::get().erase_progress();
    log_summary(options, report);
    return kExitOk;
  } catch (const Cancelled& e) {
    Terminal::get().erase_progress();
    if (g_signal != 0) {
      // Temporaries are gone (the stack has unwound); die of the signal so that the shell and
      // scripts see an interrupted command, not an ordinary failure.
      spdlog::error("interrupted; nothing was written");
      const int sig = g_signal;
      ::signal(sig, SIG_DFL);
      ::raise(sig);
    }
    spdlog::error(e.what());
    return kExitFailure;
  } catch (const Error& e) {
    Terminal::get().erase_progress();
    spdlog::error(e.what());
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    Terminal::get().erase_progress();
    spdlog::error("out of memory in the " + stage_now + " stage");
    return kExitFailure;
  } catch (const std::exception& e) {
    Terminal::get().erase_progress();
    spdlog::error(e.what());
    return kExitFailure;
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tincdt: error: %s\n", e.what());
    return kExitFailure;
  } catch (...) {
    std::fprintf(stderr, "tincdt: error: unknown failure\n");
    return kExitFailure;
  }
}
