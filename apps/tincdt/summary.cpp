#include "summary.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "core/number_text.hpp"
#include "io/mesh/tin_writer.hpp"

namespace tincdt::cli {
namespace {

std::string count(std::uint64_t n) {
  return count_text(n);
}

std::string count(std::uint64_t n, std::string_view noun, std::string_view plural = {}) {
  return count_text(n, noun, plural);
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

// What was read: points, line vertices, constraints, draped vertices.
void log_inputs(const pipeline::BuildReport& r) {
  const auto point_files = static_cast<std::uint64_t>(
      std::count_if(r.inputs.begin(), r.inputs.end(),
                    [](const pipeline::BuildReport::Input& in) { return in.kind == "points"; }));
  std::string line =
      "read " + count(r.points_read, "point") + " from " + count(point_files, "file");
  if (r.line_vertices > 0) line += " and " + count(r.line_vertices, "line vertex", "line vertices");
  if (r.points_kept != r.points_read) line += ", kept " + count(r.points_kept);
  if (r.duplicates_merged > 0) line += ", merged " + count(r.duplicates_merged, "duplicate");
  spdlog::info(line);
  if (r.constraint_segments > 0) {
    std::string c = "constraints: " + count(r.constraint_segments, "segment");
    if (r.line_features > 0) c += " from " + count(r.line_features, "line feature");
    if (r.surface_features > 0)
      c +=
          (r.line_features > 0 ? " and " : " from ") + count(r.surface_features, "surface feature");
    if (r.crossings > 0) c += ", " + count(r.crossings, "crossing") + " joined";
    if (r.constraint_segments_split > 0)
      c += ", " + count(r.constraint_segments_split) + " split at vertices";
    spdlog::info(c);
  }
  if (r.draped_vertices > 0)
    spdlog::info("draped: {} ({} of soft lines)", count(r.draped_vertices, "vertex", "vertices"),
                 count(r.soft_line_vertices));
}

// What the stages after the triangulation did, and the TIN they made.
void log_stages(const pipeline::BuildReport& r) {
  if (r.simplify.ran) {
    // The z unit: feet when the CRS says so, metres for any other CRS, none when unknown.
    std::string wkt = r.crs_wkt;
    std::transform(wkt.begin(), wkt.end(), wkt.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const char* unit = wkt.empty() ? "" : wkt.find("foot") != std::string::npos ? " ft" : " m";
    char text[160];
    std::snprintf(text, sizeof text, "%.1f%% of %s points, max error %.3f%s, RMSE %.3f%s",
                  100.0 * static_cast<double>(r.simplify.vertices) /
                      static_cast<double>(std::max<std::uint64_t>(r.simplify.points, 1)),
                  count(r.simplify.points).c_str(), r.simplify.max_error, unit, r.simplify.rmse,
                  unit);
    spdlog::info("simplify: kept {}{}", text,
                 r.simplify.stopped_at_max_vertices ? " (stopped at --max-vertices)" : "");
  }
  if (r.flats.fixed)
    spdlog::info("flat triangles: {} before, {} after ({}, {})", count(r.flats.before),
                 count(r.flats.after), count(r.flats.swaps, "swap"),
                 count(r.flats.vertices_added, "new vertex", "new vertices"));
  if (r.replaced_vertices > 0)
    spdlog::info("replace: {}", count(r.replaced_vertices, "vertex", "vertices"));
  if (r.trimmed_triangles + r.clipped_triangles + r.erased_triangles > 0)
    spdlog::info("removed triangles: {} trimmed (--max-edge), {} clipped, {} erased",
                 count(r.trimmed_triangles), count(r.clipped_triangles), count(r.erased_triangles));
  spdlog::info("TIN: {}, {}{}", count(r.vertices, "vertex", "vertices"),
               count(r.triangles, "triangle"),
               r.constraints > 0 ? ", " + count(r.constraints, "constrained edge") : "");
}

void log_timings(const pipeline::BuildReport& r) {
  std::string t =
      "time: read " + secs(r.timings_s.read) + ", delaunay " + secs(r.timings_s.delaunay);
  if (r.timings_s.constraints > 0) t += ", constraints " + secs(r.timings_s.constraints);
  if (r.timings_s.surface > 0) t += ", surface features " + secs(r.timings_s.surface);
  for (const auto& [key, seconds] : r.timings_s.more) t += ", " + key + " " + secs(seconds);
  if (r.timings_s.terrain > 0.0005) t += ", terrain " + secs(r.timings_s.terrain);
  if (r.timings_s.validate > 0) t += ", validate " + secs(r.timings_s.validate);
  t += ", write " + secs(r.timings_s.write);
  if (r.quality_measured) t += ", quality (beside the outputs) " + secs(r.timings_s.quality);
  t += ", total " + secs(r.timings_s.total);
  if (r.peak_rss_bytes > 0) t += "; peak memory " + bytes(r.peak_rss_bytes);
  spdlog::info(t);
}

// Every file written, with its format, size and CRS.
void log_outputs(const pipeline::BuildOptions& options, const pipeline::BuildReport& r) {
  std::string format = r.output_format;
  if (const auto f = io::format_from_name(r.output_format)) {
    format = io::format_info(*f).title;
    if (*f == io::TinFormat::ply) format += options.write.ply_ascii ? " ASCII" : " binary";
  }
  // Each output's own CRS: the web terrain's is not the TIN's.
  const auto crs_text = [&r](const std::string& label) {
    return label.empty() ? std::string(r.crs_wkt.empty() ? "no CRS" : "CRS unnamed")
                         : "CRS " + label;
  };
  std::string tin_crs = r.crs;
  for (const pipeline::BuildReport::Output& o : r.outputs)
    if (o.kind == "tin") tin_crs = o.crs;
  std::string w =
      "wrote " + r.output + " (" + format + ", " + bytes(r.output_bytes) + ", " + crs_text(tin_crs);
  if (r.offset.x != 0 || r.offset.y != 0 || r.offset.z != 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", offset %.17g,%.17g,%.17g", r.offset.x, r.offset.y,
                  r.offset.z);
    w += buf;
  }
  if (!r.output.empty()) spdlog::info(w + ")");
  std::size_t terrain_tiles = 0, terrain_bytes = 0;
  for (const pipeline::BuildReport::Output& o : r.outputs) {
    if (o.kind == "terrain") {  // one line for the whole pyramid
      terrain_tiles += o.path.ends_with(".terrain");
      terrain_bytes += o.bytes;
      continue;
    }
    if (o.kind == "dem" && o.path == r.dem.path) {
      spdlog::info("wrote {} ({} {}, {} x {} cells of {}, {}, {}; rasterize {}, write {})", o.path,
                   r.dem.driver, r.dem.type, count(r.dem.width), count(r.dem.height),
                   number_text(r.dem.resolution), bytes(o.bytes), crs_text(o.crs),
                   secs(r.dem.rasterize_s), secs(r.dem.write_s));
    } else if (o.kind == "contour_lines" && o.path == r.contour_lines.path) {
      spdlog::info("wrote {} ({}, {} on {}, {}, {}; trace {}, write {})", o.path,
                   r.contour_lines.driver, count(r.contour_lines.lines, "line"),
                   count(r.contour_lines.levels, "level"), bytes(o.bytes), crs_text(o.crs),
                   secs(r.contour_lines.trace_s), secs(r.contour_lines.write_s));
    } else if (o.kind == "preview") {
      spdlog::info("wrote {}", o.path);
    } else if (o.kind != "tin" && o.kind != "prj" && o.kind != "contour_lines") {
      spdlog::info("wrote {} ({})", o.path, crs_text(o.crs));
    }
  }
  if (terrain_tiles > 0)
    spdlog::info("wrote {} ({} and layer.json, {})", options.terrain.path,
                 count(terrain_tiles, "tile"), bytes(terrain_bytes));
  if (options.stats_path == "-")
    spdlog::info("wrote the stats to standard output");
  else if (!options.stats_path.empty())
    spdlog::info("wrote {}", options.stats_path);
}

}  // namespace

void log_summary(const pipeline::BuildOptions& options, const pipeline::BuildReport& r) {
  log_inputs(r);
  log_stages(r);
  log_timings(r);
  log_outputs(options, r);
}

}  // namespace tincdt::cli
