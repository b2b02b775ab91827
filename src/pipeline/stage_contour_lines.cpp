// contour_lines: --contour-lines, contours traced on the final TIN (products::trace_contours)
// and written through OGR with the TIN's CRS; a shapefile's other files are outputs too. CAD
// formats (DXF, DGN) have no attribute fields: there the level is the lines' z alone, as
// gdal_contour -3d writes them.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/vector/contour_writer.hpp"
#include "pipeline/stage.hpp"
#include "products/contours.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.contour_lines.path.empty();
}

void run(Job& job) {
  const BuildOptions::ContourLines& o = job.options.contour_lines;
  BuildReport::ContourLines& r = job.report.contour_lines;
  r.path = o.path;
  const std::string driver = io::vector_driver_for(o.path, o.format);  // before the work
  auto t0 = std::chrono::steady_clock::now();
  products::ContourSet set;
  try {
    set = products::trace_contours(job.tin(), {.interval = o.interval,
                                               .base = o.base_or_default(),
                                               .levels = o.levels,
                                               .threads = job.options.threads,
                                               .progress = job.stage_progress()});
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    throw OutputError(o.path, "", e.detail());
  }
  r.trace_s = seconds_since(t0);
  r.levels = set.levels;
  r.lines = set.lines.size();
  r.points = set.points.size();
  for (const products::ContourLine& line : set.lines) {
    r.closed += line.closed ? 1 : 0;
    for (std::size_t i = line.first + 1; i < line.first + line.count; ++i)
      r.length +=
          std::hypot(set.points[i].x - set.points[i - 1].x, set.points[i].y - set.points[i - 1].y);
  }

  t0 = std::chrono::steady_clock::now();
  io::ContourWriteOptions w;
  w.format = o.format;
  w.elevation_field = driver == "DXF" || driver == "DGN" ? "" : o.field_or_default();
  w.crs_wkt = job.crs_wkt;
  w.progress = job.stage_progress();
  io::OutputFile& out = job.add_output(o.path, "contour_lines");
  std::vector<io::OutputFile*> siblings;
  const io::ContourWriteStats stats =
      io::write_contours(out, set, w, [&](const std::string& path) -> io::OutputFile& {
        siblings.push_back(&job.add_output(path, "contour_lines"));
        return *siblings.back();
      });
  job.finish_output(out);
  for (io::OutputFile* s : siblings) job.finish_output(*s);
  r.driver = stats.driver;
  r.write_s = seconds_since(t0);
  job.info("contour lines: " + count_text(r.lines, "line") + " on " +
           count_text(r.levels, "level"));
}

// A shapefile's .shx, .dbf and .prj are planned with it, so that an existing one stops the job
// before any work.
void plan(const BuildOptions& o, FilePlan& files) {
  const BuildOptions::ContourLines& c = o.contour_lines;
  files.outputs.push_back({c.path, "the contour lines (--contour-lines)"});
  std::filesystem::path p(c.path);
  std::string ext = p.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".shp" && c.format.empty())
    for (const char* sibling : {".shx", ".dbf", ".prj"})
      files.outputs.push_back({std::filesystem::path(c.path).replace_extension(sibling).string(),
                               "a file of the contour lines' shapefile (--contour-lines)"});
}

// ---- options -----------------------------------------------------------------------------------

// "L1,L2,...": every item a number.
std::string check_levels(std::string_view text) {
  for (std::size_t at = 0;;) {
    const std::size_t comma = text.find(',', at);
    const std::string_view item =
        text.substr(at, comma == std::string_view::npos ? comma : comma - at);
    if (!parse_number(item)) return in_quotes(item) + " is not a number";
    if (comma == std::string_view::npos) return {};
    at = comma + 1;
  }
}

void add_levels(BuildOptions& o, std::string_view text) {
  for (std::size_t at = 0;;) {
    const std::size_t comma = text.find(',', at);
    o.contour_lines.levels.push_back(
        *parse_number(text.substr(at, comma == std::string_view::npos ? comma : comma - at)));
    if (comma == std::string_view::npos) return;
    at = comma + 1;
  }
}

std::string check_name(std::string_view text) {
  return text.empty() ? std::string("give a field name") : std::string();
}

using ContourLines = BuildOptions::ContourLines;

constexpr OptionSpec kOptions[] = {
    text_option("--contour-lines", "FILE", option_groups::products,
                set_text<&BuildOptions::contour_lines, &BuildOptions::ContourLines::path>,
                "Trace contour lines on the TIN into any OGR vector format, by\n"
                "extension (.gpkg, .shp, .geojson, .dxf, ...), the level as z and in a\n"
                "field (not in DXF, DGN) (needs --interval or --levels)"),
    checked_option("--interval", "I", option_groups::products, check_positive,
                   set_number<&BuildOptions::contour_lines, &BuildOptions::ContourLines::interval>,
                   "Contour interval"),
    {.flags = "--levels",
     .value_name = "L1,L2,...",
     .help = "Fixed contour levels instead of --interval (as gdal_contour -fl)",
     .group = option_groups::products,
     .kind = OptionKind::repeated,
     .check = check_levels,
     .set = add_levels},
    with_default(checked_option("--contour-field", "NAME", option_groups::products, check_name,
                                set_text<&BuildOptions::contour_lines, &ContourLines::field>,
                                "The contour level's field (as gdal_contour -a)"),
                 "elev", [](const BuildOptions& o) { return o.contour_lines.field_or_default(); }),
    with_default(
        checked_option("--base", "B", option_groups::products, check_number,
                       set_number<&BuildOptions::contour_lines, &ContourLines::base>,
                       "Contour levels are BASE + k * interval"),
        "0", [](const BuildOptions& o) { return number_text(o.contour_lines.base_or_default()); }),
};

}  // namespace

// The library calls that report progress under this stage, in order.
constexpr std::string_view kProgressPhases[] = {"contours", "write contours"};

constexpr StageProgress kContourLinesProgress{"tracing contour lines", "", nullptr,
                                              kProgressPhases};
extern const Stage contour_lines_stage{"contour_lines", "contours",           wanted, run, plan, "",
                                       kOptions,        kContourLinesProgress};

}  // namespace tincdt::pipeline
