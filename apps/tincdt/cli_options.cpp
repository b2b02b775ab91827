#include "cli_options.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/number_text.hpp"
#include "pipeline/option_spec.hpp"
#include "pipeline/stage.hpp"

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace tincdt::cli {
namespace {

using pipeline::BuildOptions;
using pipeline::OptionKind;
using pipeline::OptionSpec;

class UsageFormatter : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App*, std::string) const override { return usage(); }
  // The value names as the option tables write them: no " x 4" after the four words of
  // "XMIN YMIN XMAX YMAX" (the checks have no names to add after them either).
  std::string make_option_opts(const CLI::Option* opt) const override {
    if (opt->get_type_size() == 0) return "";
    std::string text;
    if (!opt->get_type_name().empty()) text += " " + opt->get_type_name();
    if (!opt->get_default_str().empty()) text += "=" + opt->get_default_str();
    if (opt->get_expected_max() == CLI::detail::expected_max_vector_size) text += " ...";
    if (opt->get_required()) text += " REQUIRED";
    return text;
  }
};

constexpr const char* kExamples = R"(Examples:
  LAS to binary PLY, in local coordinates for a mesh viewer:
    tincdt Topography.las -o tin.ply --offset auto
  Several XYZ files (no CRS in them) to a TIN and a 1 m DEM in UTM zone 19N:
    tincdt a.xyz b.xyz --a-srs EPSG:2949 --t-srs EPSG:32619 -o tin.ply --dem dem.tif
           --resolution 1
  A GeoJSON TIN in WGS 84 (RFC 7946), triangulated in degrees:
    tincdt tile.las --t-srs EPSG:4326 --allow-geographic -o tin.geojson
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
    tincdt big.las -o big.ply --threads 1)";

constexpr const char* kGdalWords =
    R"(GDAL spellings: -a_srs, -t_srs, -co and -of are read as --a-srs, --t-srs, --dem-co and
--dem-format.)";

constexpr const char* kExitStatus =
    R"(Exit status: 0 success, 1 input, output or runtime error, 2 usage error,
3 internal error (a bug: please report it with the input). Interrupted by SIGINT (Ctrl-C),
SIGTERM or SIGHUP, tincdt changes no file and ends by that signal: a shell reports 130, 143
or 129.)";

// "1. points, ...": the stages with a title, numbered in their order, each continued line
// indented under its text.
std::string stage_order() {
  std::string text = "Order of the stages (and precedence where features overlap):\n";
  const auto steps = std::count_if(pipeline::stages().begin(), pipeline::stages().end(),
                                   [](const pipeline::Stage* s) { return !s->title.empty(); });
  const std::size_t width = count_text(steps).size();
  int step = 0;
  for (const pipeline::Stage* stage : pipeline::stages()) {
    if (stage->title.empty()) continue;
    std::string number = count_text(++step) + ". ";
    number.insert(0, width + 2 - number.size(), ' ');
    std::string_view title = stage->title;
    std::string indent = "  " + number;
    while (true) {
      const std::size_t eol = title.find('\n');
      text += indent + std::string(title.substr(0, eol)) + "\n";
      if (eol == std::string_view::npos) break;
      title.remove_prefix(eol + 1);
      indent = std::string(2 + number.size(), ' ');
    }
  }
  return text;
}

// The tile options, bound field by field.
class Group {
 public:
  Group(CLI::App& app, const char* name) : app_(app), name_(name) {}

  CLI::Option* option(const char* flags, std::string& target, const char* help, const char* type) {
    return app_.add_option(flags, target, help)->type_name(type)->group(name_);
  }
  CLI::Option* flag(const char* flags, bool& target, const char* help) {
    return app_.add_flag(flags, target, help)->group(name_);
  }
  // A value that CHECK accepts (it returns "" or why not), stored by CLI11 in TARGET.
  template <class T>
  CLI::Option* checked(const char* flags, T& target, const char* help, const char* type,
                       std::string (*check)(std::string_view)) {
    return app_.add_option(flags, target, help)
        ->check(CLI::Validator([check](std::string& v) { return check(v); }, ""))
        ->type_name(type)
        ->group(name_);
  }

 private:
  CLI::App& app_;
  const char* name_;
};

// SPEC's values as CLI11 reads them: one value per occurrence for a repeated option (so that
// "--clip a.shp tile.las" leaves tile.las an INPUT), all of them for the operands. CLI11 runs
// the option's checks on each value before the callback sets it.
CLI::Option* add_spec(CLI::App& app, const OptionSpec& spec, BuildOptions& o) {
  const std::string flags(spec.flags);
  const auto set = [&spec, &o](const std::string& v) { spec.set(o, v); };
  switch (spec.kind) {
    case OptionKind::flag:
      return app.add_flag_callback(flags, [&spec, &o] { spec.set(o, {}); });
    case OptionKind::positional:
      return app.add_option_function<std::vector<std::string>>(
          flags, [set](const std::vector<std::string>& values) {
            for (const std::string& v : values) set(v);
          });
    case OptionKind::repeated:  // set by bind(), after the checks
      return app.add_option(flags)->expected(1)->allow_extra_args(false)->multi_option_policy(
          CLI::MultiOptionPolicy::TakeAll);
    case OptionKind::value:
    case OptionKind::choice:
      if (spec.arity == 1) return app.add_option_function<std::string>(flags, set);
      return app
          .add_option_function<std::vector<std::string>>(
              flags,
              [set](const std::vector<std::string>& values) {
                std::string joined;
                for (const std::string& v : values) joined += (joined.empty() ? "" : " ") + v;
                set(joined);
              })
          ->expected(static_cast<int>(spec.arity));
  }
  return nullptr;
}

// A choice's words, any case, become the word as the table writes it.
CLI::Validator choice_check(std::span<const std::string_view> words, const std::string& type) {
  return CLI::Validator(
      [words, type](std::string& text) {
        for (std::string_view word : words) {
          if (pipeline::lower(text) != word) continue;
          text = std::string(word);
          return std::string();
        }
        return "'" + text + "' is not one of " + type;
      },
      "");
}

// One option of a stage's table: its help and group, its check, then its set.
void bind(CLI::App& app, const OptionSpec& spec, BuildOptions& o) {
  CLI::Option* option = add_spec(app, spec, o);
  std::string type(spec.value_name);
  if (spec.kind == OptionKind::choice) {
    type.clear();
    for (std::string_view word : spec.words) type += (type.empty() ? "" : "|") + std::string(word);
    option->transform(choice_check(spec.words, type));
  }
  if (spec.check != nullptr)
    option->check(CLI::Validator([check = spec.check](std::string& v) { return check(v); }, ""));
  option->description(std::string(spec.help));
  if (!type.empty()) option->type_name(type);
  if (!spec.default_text.empty()) option->default_str(std::string(spec.default_text));
  if (spec.required) option->required();
  if (spec.kind != OptionKind::positional) option->group(std::string(spec.group));
  if (spec.kind == OptionKind::repeated)
    option->each([&spec, &o](const std::string& v) { spec.set(o, v); });
}

std::string check_tile_index(std::string_view text) {
  const auto n = pipeline::parse_count(text);
  return n && *n <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
             ? std::string()
             : pipeline::in_quotes(text) + " is not a tile index (0, 1, ...)";
}

void tile_options(CLI::App& app, tiles::TileOptions& o) {
  Group g(app, "Tiled jobs (one tile of a plan made by 'tincdt plan')");
  g.option("--plan", o.plan, "The plan; the inputs and how to read them come from it", "PLAN.json");
  g.checked("--tile", o.tile, "The tile to build: its index in the plan (0, 1, ...)", "N",
            check_tile_index);
  g.checked("--buffer", o.buffer,
            "Read this far around the tile instead of the plan's buffer\n"
            "(the tiles already built stay valid)",
            "LENGTH", pipeline::check_non_negative);
  g.checked("--max-buffer", o.max_buffer,
            "A buffer too small grows, reading more, up to this\n"
            "(default: one tile size)",
            "LENGTH", pipeline::check_non_negative);
  g.flag("--buffer-fixed", o.buffer_fixed,
         "Stop when the buffer is too small, saying what it needs,\n"
         "instead of reading more (for schedulers that promise memory)");
  g.option("--outline", o.outline,
           "Also write the tile's outline, for 'tincdt merge --check'\n"
           "when the tiles are too many to keep or to merge",
           "FILE.ply");
}

void run_options(CLI::App& app, BuildOptions& o, Verbosity& v) {
  for (const OptionSpec& spec : pipeline::job_options()) bind(app, spec, o);
  const std::string group(pipeline::option_groups::run);
  app.add_flag("-q,--quiet", v.quiet, "Only warnings and errors; no progress (unless --progress)")
      ->group(group);
  app.add_flag("-v,--verbose", v.verbose, "Also debug messages")->group(group);
  app.add_flag("--progress", v.progress,
               "Show progress even with -q (on a terminal one line, redrawn;\n"
               "elsewhere GDAL's 0...10...100 - done. per stage)")
      ->group(group);
  app.set_help_flag("-h,--help", "Print this help and exit")->group(group);
  app.set_version_flag("--version", "tincdt " TINCDT_VERSION, "Print the version and exit")
      ->group(group);
}

}  // namespace

std::string usage() {
  return "Usage: tincdt [OPTIONS] [INPUT...] [--contours LINES]... -o OUTPUT\n"
         "       tincdt --plan PLAN.json --tile N [OPTIONS] -o OUTPUT\n"
         "       tincdt plan INPUT... --tile-size S --buffer B -o PLAN.json  (plan --help)\n"
         "       tincdt merge TILE... -o OUTPUT                              (merge --help)\n";
}

std::optional<std::string> append_class_codes(const std::string& text,
                                              std::vector<std::uint8_t>& classes) {
  return pipeline::append_class_codes(text, classes);
}

void define_options(CLI::App& app, BuildOptions& options, tiles::TileOptions& tiling,
                    Verbosity& verbosity) {
  app.formatter(std::make_shared<UsageFormatter>());
  app.get_formatter()->column_width(26);
  app.footer(std::string(kExamples) + "\n\n" + stage_order() + "\n" + kGdalWords + "\n\n" +
             kExitStatus);
  app.set_help_flag();  // defined last, in the "Run" group
  for (const pipeline::Stage* stage : pipeline::stages())
    for (const OptionSpec& spec : stage->options) bind(app, spec, options);
  tile_options(app, tiling);
  run_options(app, options, verbosity);
}

}  // namespace tincdt::cli
