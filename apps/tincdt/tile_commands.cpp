#include "tile_commands.hpp"

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "command_words.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "error_message.hpp"
#include "terminal.hpp"
#include "tiles/merge.hpp"
#include "tiles/plan.hpp"

namespace tincdt::cli {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

int usage_error(const std::string& command, const std::string& message) {
  spdlog::error(message);
  Terminal::get().line("Try 'tincdt " + command + " --help' for more information.");
  return kExitUsage;
}

// Parses ARGV into APP; a return value >= 0 is the exit code to return at once.
int parse(CLI::App& app, const std::string& command, int argc, char** argv) {
  const std::vector<std::string> words = words_of(argc, argv);
  if (const auto unknown = unknown_long_option(app, words)) return usage_error(command, *unknown);
  try {
    parse_words(app, words);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(command, e.what());
  }
  return -1;
}

// OUTPUT "-" would be a file named "-": refused, as the build's outputs are.
int refuse_standard_output(const std::string& command, const std::string& output) {
  if (output != "-") return -1;
  return usage_error(command,
                     "-o cannot be standard output ('-'): tincdt writes to a temporary file and "
                     "moves it into place at the end; give a file name");
}

// An option given once per value: "--contours a.shp tile.las" leaves tile.las an operand.
CLI::Option* add_repeated(CLI::App& app, const std::string& flags, std::vector<std::string>& values,
                          const std::string& help) {
  return app.add_option(flags, values, help)
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// An option the command cannot run without, its value shown in the help as TYPE.
template <class T>
CLI::Option* add_required(CLI::App& app, const std::string& flags, T& value,
                          const std::string& help, const std::string& type) {
  return app.add_option(flags, value, help)->type_name(type)->required();
}

// The -q and -v flags of a command, into V.
void add_quiet_verbose(CLI::App& app, Verbosity& v) {
  app.add_flag("-q,--quiet", v.quiet, "Only warnings and errors");
  app.add_flag("-v,--verbose", v.verbose, "Also debug messages");
}

void set_verbosity(const Verbosity& v) {
  if (v.quiet) spdlog::set_level(spdlog::level::warn);
  if (v.verbose) spdlog::set_level(spdlog::level::debug);
}

// "2,8" or repeated options: LAS classification codes.
std::vector<std::uint8_t> parse_classes(const std::vector<std::string>& values,
                                        const char* option) {
  std::vector<std::uint8_t> classes;
  for (const std::string& value : values) {
    if (const auto bad = append_class_codes(value, classes))
      throw UsageError(std::string(option) + ": '" + *bad +
                       "' is not a LAS classification code (0-255)");
  }
  return classes;
}

const tiles::LogFn kLog = [](int level, const std::string& message) {
  if (level == tiles::log_debug)
    spdlog::debug(message);
  else if (level == tiles::log_info)
    spdlog::info(message);
  else
    spdlog::warn(message);
};

// Runs F, turning tincdt errors into a message and an exit code.
template <class F>
int guarded(const std::string& command, F&& f) {
  try {
    f();
    return kExitOk;
  } catch (const UsageError& e) {
    return usage_error(command, error_message(e));
  } catch (const Error& e) {
    spdlog::error(error_message(e));
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory");
  } catch (const std::exception& e) {
    spdlog::error(e.what());
  }
  return kExitFailure;
}

}  // namespace

int run_plan(int argc, char** argv) {
  CLI::App app(
      "tincdt plan: split the inputs' area into tiles for independent jobs. Reads only the "
      "headers (LAS/LAZ bounds and counts, vector layer extents) and writes a JSON plan: per "
      "tile, its box (multiples of the tile size) and the inputs within its buffer. Then build "
      "each tile with 'tincdt --plan PLAN --tile N -o tile_N.ply' (any job engine: GNU parallel, "
      "Slurm, Kubernetes; see examples/tiles/) and join them with 'tincdt merge'.",
      "tincdt plan");
  tiles::PlanOptions o;
  Verbosity verbosity;
  std::vector<std::string> hard_lines;
  app.add_option("INPUT", o.inputs, "Point files: LAS, LAZ (header only) or XYZ (read whole)")
      ->type_name("FILE");
  add_repeated(app, "--contours", o.contours, "Contour lines (any OGR source: FILE or FILE:LAYER)")
      ->type_name("LINES");
  add_repeated(app, "--hard-lines,--breaklines", hard_lines, "Hard lines (breaklines)")
      ->type_name("LINES");
  app.add_option("--layer", o.lines.layer, "Layer to read from each vector source")
      ->type_name("NAME");
  app.add_option("--z-field", o.lines.z_field, "Take the lines' z from this attribute")
      ->type_name("NAME");
  app.add_flag("--z-from-m", o.lines.z_from_m, "Take the lines' z from the M values");
  std::vector<std::string> keep, drop;
  add_repeated(app, "--keep-class", keep, "Keep only these LAS classes (e.g. 2,8)")
      ->type_name("N[,N...]");
  add_repeated(app, "--drop-class", drop, "Drop these LAS classes")->type_name("N[,N...]");
  app.add_flag("--first-only", o.filter.first_return_only, "Keep only first returns (LAS)");
  app.add_flag("--last-only", o.filter.last_return_only, "Keep only last returns (LAS)");
  app.add_option("--rim", o.rim_width,
                 "Width of the rim: the points this near the data's convex hull, which\n"
                 "every tile along the outline reads (default: ten times the mean point\n"
                 "spacing; 0: none, and the plan reads headers only)")
      ->type_name("W");
  add_required(app, "--tile-size", o.tile_size, "Tile width and height; tiles start at multiples",
               "S");
  add_required(app, "--buffer", o.buffer,
               "How far around its tile each job reads: enough that every triangle near\n"
               "the tile is settled (a first guess: a tile that needs more reads more)",
               "B");
  add_required(app, "-o,--output", o.output, "The plan (JSON)", "PLAN.json");
  app.add_option("--threads", o.threads, "Point files read at once for the rim; 0 = one per core")
      ->type_name("N");
  app.add_flag("--overwrite", o.overwrite, "Replace an existing plan");
  add_quiet_verbose(app, verbosity);
  if (const int code = parse(app, "plan", argc, argv); code >= 0) return code;
  if (const int code = refuse_standard_output("plan", o.output); code >= 0) return code;
  o.breaklines = hard_lines;
  set_verbosity(verbosity);
  return guarded("plan", [&] {
    o.filter.keep_classes = parse_classes(keep, "--keep-class");
    o.filter.drop_classes = parse_classes(drop, "--drop-class");
    if (o.filter.first_return_only && o.filter.last_return_only)
      throw UsageError("--first-only and --last-only exclude each other");
    std::vector<Point3> rim;
    tiles::TilePlan plan = tiles::make_plan(o, rim, kLog);
    tiles::write_plan(plan, rim, o.output, o.overwrite);
    std::size_t most = 0;
    for (const tiles::PlanTile& t : plan.tiles) most = std::max(most, t.inputs.size());
    spdlog::info("wrote {}: {} tiles of {} (buffer {}) over {} inputs; a tile reads at most {}",
                 o.output, count_text(plan.tiles.size()), number_text(o.tile_size),
                 number_text(o.buffer), count_text(plan.inputs.size()), count_text(most));
  });
}

int run_merge(int argc, char** argv) {
  CLI::App app(
      "tincdt merge: join the TINs of a plan's tiles into one, welding the vertices on the seams "
      "by their exact coordinates. Checks that every edge has one triangle on each side or lies "
      "on the convex hull, and that the result is a valid constrained Delaunay TIN; a crack or an "
      "overlap is an error naming the tiles. With --check, only checks (memory: the tiles' "
      "outlines), writing nothing.",
      "tincdt merge");
  tiles::MergeOptions o;
  Verbosity verbosity;
  add_required(app, "TILE", o.inputs,
               "Tile TINs written by tile jobs (PLY), or outlines (--outline)", "FILE");
  app.add_option("-o,--output", o.output,
                 "The merged TIN: .obj, .ply or .geojson; or, with\n"
                 "--outline, the outline of the tiles together (PLY)")
      ->type_name("FILE");
  app.add_flag("--check", o.check_only, "Check the seams only; write nothing");
  app.add_flag("--outline", o.outline,
               "Write only the outline of the tiles (their border edges, for a later --check),\n"
               "so that the tiles themselves can be deleted");
  app.add_flag("--overwrite", o.overwrite, "Replace an existing output");
  add_quiet_verbose(app, verbosity);
  if (const int code = parse(app, "merge", argc, argv); code >= 0) return code;
  if (const int code = refuse_standard_output("merge", o.output); code >= 0) return code;
  set_verbosity(verbosity);
  if (o.check_only && !o.output.empty())
    return usage_error("merge", "--check writes nothing: give no -o");
  if (!o.check_only && o.output.empty())
    return usage_error("merge", "give -o OUTPUT, or --check to only check the seams");
  if (o.check_only && o.outline)
    return usage_error("merge", "--check and --outline exclude each other");
  return guarded("merge", [&] {
    const tiles::MergeReport r = tiles::merge_tiles(o, kLog);
    spdlog::info("{} {} tiles: {} vertices, {} triangles, {} seam edges matched, {} {} edges{}",
                 o.check_only ? "checked" : "merged", count_text(r.tiles), count_text(r.vertices),
                 count_text(r.triangles), count_text(r.seam_edges), count_text(r.hull_edges),
                 r.trimmed ? "outline" : "hull", o.check_only ? "" : "; wrote " + o.output);
  });
}

}  // namespace tincdt::cli
