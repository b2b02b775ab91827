#include "pipeline/build.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "io/crs.hpp"

namespace tincdt::pipeline {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void emit(const LogFn& log, int level, const std::string& message) {
  if (log) log(level, message);
}

void report_progress(const ProgressFn* progress, std::string_view stage, double fraction) {
  if (progress && *progress && !(*progress)(stage, fraction)) throw Cancelled();
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Refuses, before any work, an output that the writers would refuse at the end.
void check_output_path(const std::string& path, bool overwrite) {
  if (path.empty()) throw OutputError("no output path given");
  std::error_code ec;
  const fs::path target(path);
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st)) {
    if (fs::is_directory(st)) throw OutputError(path, "", "is a folder");
    if (!overwrite) throw OutputError(path, "", "already exists (use --overwrite to replace it)");
    if (!fs::is_regular_file(st))
      throw OutputError(path, "", "is not a regular file and cannot be replaced");
  }
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  const fs::file_status fst = fs::status(folder, ec);
  if (!fs::exists(fst))
    throw OutputError(path, "", "folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(fst))
    throw OutputError(path, "", "'" + folder.string() + "' is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    const int err = errno;
    throw OutputError(path, "",
                      "cannot write in folder '" + folder.string() + "': " + std::strerror(err));
  }
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec) && !ec) return true;
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

// An upper-bound guess of the point count, so the merged vector is allocated once. Reserved
// but untouched pages cost address space, not resident memory.
std::uint64_t estimate_points(const std::vector<std::string>& inputs) {
  std::uint64_t n = 0;
  for (const std::string& path : inputs) {
    if (path == "-") continue;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) continue;
    const std::string ext = lower_extension(path);
    if (ext == ".laz") continue;
    n += ext == ".las" ? size / 20 : size / 24;  // 20 = smallest LAS record; ~24 B per text line
  }
  return n;
}

std::string describe_inputs(const std::vector<std::string>& inputs) {
  if (inputs.size() == 1) return inputs.front();
  std::string s;
  const std::size_t shown = std::min<std::size_t>(inputs.size(), 3);
  for (std::size_t i = 0; i < shown; ++i) {
    if (i) s += ", ";
    s += inputs[i];
  }
  if (inputs.size() > shown) s += " and " + std::to_string(inputs.size() - shown) + " more";
  return s;
}

// CRS labels for messages, each distinct WKT identified once (identification can search the
// whole EPSG database, a noticeable fraction of a second).
class CrsNames {
 public:
  const std::string& label(const std::string& wkt) {
    auto it = labels_.find(wkt);
    if (it == labels_.end()) it = labels_.emplace(wkt, wkt.empty() ? "" : io::crs_label(wkt)).first;
    return it->second;
  }
  std::string name(const std::string& wkt) {
    if (wkt.empty()) return "no CRS";
    const std::string& l = label(wkt);
    return l.empty() ? "an unnamed CRS" : l;
  }

 private:
  std::map<std::string, std::string> labels_;
};

bool filtering(const io::PointFilter& f) {
  return !f.keep_classes.empty() || !f.drop_classes.empty() || f.first_return_only ||
         f.last_return_only;
}

double round_down(double v, double step) {
  return std::floor(v / step) * step;
}

// "FILE feature FID" for messages about a constraint's source.
std::string describe_feature(const io::LineData& lines, std::uint32_t feature) {
  if (feature >= lines.features.size()) return "a line";
  const io::LineFeature& f = lines.features[feature];
  return lines.files[f.file] + " feature " + std::to_string(f.fid);
}

// The constraint stage: every line segment becomes a chain of constrained edges.
void insert_lines(delaunay::DelaunayResult& result, std::size_t n_points, const io::LineData& lines,
                  const constraints::ConstraintOptions& options, const ProgressFn* progress,
                  const LogFn& log, BuildReport& report) {
  std::vector<constraints::Segment> segments;
  segments.reserve(lines.segments.size());
  for (const io::LineData::Segment& s : lines.segments)
    segments.push_back({result.vertex_of_point[n_points + s.a],
                        result.vertex_of_point[n_points + s.b], s.feature});
  result.vertex_of_point = {};

  constraints::ConstraintResult c;
  try {
    c = constraints::insert_constraints(result.tin, segments, options, progress);
  } catch (const constraints::CrossingError& e) {
    char at[64];
    std::snprintf(at, sizeof at, "(%.3f, %.3f)", e.at.x, e.at.y);
    const std::string& file =
        e.source_a < lines.features.size() ? lines.files[lines.features[e.source_a].file] : "";
    throw InputError(file,
                     e.source_a < lines.features.size()
                         ? "feature " + std::to_string(lines.features[e.source_a].fid)
                         : "",
                     std::string("crosses ") + describe_feature(lines, e.source_b) + " at " + at +
                         " (use --on-crossing split to join them there)");
  }
  report.zero_length_segments += c.segments_skipped;
  report.constraint_segments_split = c.split_at_vertices;
  report.crossings = c.crossings.size();
  report.steiner_vertices = c.crossings.size();
  report.max_z_disagreement = c.max_z_disagreement;
  report.flips.insertion = c.flips_insertion;
  report.flips.restoration = c.flips_restoration;
  if (c.segments_skipped > 0)
    emit(log, log_debug,
         std::to_string(c.segments_skipped) +
             " line segments have both ends on one vertex (merged points): skipped");
  if (!c.crossings.empty()) {
    const constraints::Crossing* worst = &c.crossings.front();
    for (const constraints::Crossing& x : c.crossings) {
      if (std::fabs(x.z_a - x.z_b) > std::fabs(worst->z_a - worst->z_b)) worst = &x;
      emit(log, log_debug,
           "crossing: " + describe_feature(lines, x.source_a) + " and " +
               describe_feature(lines, x.source_b) + " joined at a new vertex");
    }
    char dz[32];
    std::snprintf(dz, sizeof dz, "%.3f", c.max_z_disagreement);
    emit(log, log_warn,
         std::to_string(c.crossings.size()) +
             " crossing line segments joined at new vertices; the largest z disagreement is " + dz +
             " between " + describe_feature(lines, worst->source_a) + " and " +
             describe_feature(lines, worst->source_b));
  }
}

}  // namespace

std::string_view format_name(io::TinFormat format) {
  switch (format) {
    case io::TinFormat::obj:
      return "obj";
    case io::TinFormat::ply:
      return "ply";
    case io::TinFormat::geojson:
      return "geojson";
  }
  return "?";
}

std::uint64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) != 0) continue;
    std::uint64_t kib = 0;
    for (char c : line)
      if (c >= '0' && c <= '9') kib = kib * 10 + static_cast<std::uint64_t>(c - '0');
    return kib * 1024;
  }
  return 0;
}

BuildReport build(const BuildOptions& options, const ProgressFn* progress, const LogFn& log) {
  const Clock::time_point t_start = Clock::now();
  BuildReport report;
  report.output = options.output;

  // ---- checks that need no data: fail now rather than after a long read ----------------------
  if (options.inputs.empty() && options.contours.empty() && options.breaklines.empty())
    throw InputError("no input given: point files, contours or breaklines");
  const io::TinFormat format =
      options.write.format ? *options.write.format : io::format_from_path(options.output);
  report.output_format = std::string(format_name(format));
  if (!options.write.target_crs_wkt.empty() && format != io::TinFormat::geojson)
    throw OutputError(options.output, "",
                      "reprojection (--t-srs) is only supported for GeoJSON output");
  check_output_path(options.output, options.write.overwrite);
  for (const std::string& input : options.inputs)
    if (input != "-" && same_file(input, options.output))
      throw OutputError(options.output, "", "is also an input file");
  if (!options.stats_path.empty()) {
    check_output_path(options.stats_path, options.write.overwrite);
    if (same_file(options.stats_path, options.output))
      throw OutputError(options.stats_path, "", "the stats file and the TIN are the same file");
  }
  if (std::count(options.inputs.begin(), options.inputs.end(), std::string("-")) > 1)
    throw InputError("-", "", "standard input can be read only once");

  // ---- read ---------------------------------------------------------------------------------
  Clock::time_point t0 = Clock::now();
  std::vector<Point3> points;
  if (const std::uint64_t guess = estimate_points(options.inputs); guess > 0) {
    try {
      points.reserve(static_cast<std::size_t>(guess));
    } catch (const std::bad_alloc&) {
      // fall back to growing as we read
    } catch (const std::length_error&) {
    }
  }

  std::vector<std::uint64_t> sizes;
  std::uint64_t total_bytes = 0;
  for (const std::string& path : options.inputs) {
    std::error_code ec;
    const std::uint64_t size =
        path == "-" ? 0 : static_cast<std::uint64_t>(fs::file_size(path, ec));
    sizes.push_back(ec ? 0 : size);
    total_bytes += sizes.back();
  }

  CrsNames crs;
  std::string crs_wkt = options.assign_crs_wkt;  // the CRS of the merged points
  std::string crs_source = crs_wkt.empty() ? std::string() : std::string("--a-srs");
  std::vector<std::string> without_crs;  // inputs with no CRS of their own
  // Every input's CRS must agree with the first one found, unless --a-srs overrides them all.
  auto merge_crs = [&](const std::string& path, const std::string& wkt) {
    if (!options.assign_crs_wkt.empty()) {
      if (!wkt.empty() && !io::same_crs(wkt, options.assign_crs_wkt))
        emit(log, log_warn,
             path + ": its CRS " + crs.name(wkt) + " is overridden by --a-srs " +
                 crs.name(options.assign_crs_wkt));
    } else if (wkt.empty()) {
      without_crs.push_back(path);
    } else if (crs_wkt.empty()) {
      crs_wkt = wkt;
      crs_source = path;
    } else if (!io::same_crs(crs_wkt, wkt)) {
      const std::string mine = crs.name(wkt), theirs = crs.name(crs_wkt);
      throw InputError(path, "",
                       "CRS " + mine + " differs from " + theirs + " of " + crs_source +
                           (mine == theirs ? " (same name, different definition)" : "") +
                           " (reproject one of them, or use --a-srs to override both)");
    }
  };
  std::uint64_t bytes_done = 0;
  report_progress(progress, "read", 0.0);
  for (std::size_t i = 0; i < options.inputs.size(); ++i) {
    const std::string& path = options.inputs[i];
    const io::PointReadStats s = io::read_points(path, options.filter, points);
    BuildReport::Input in;
    in.path = path;
    in.format = s.format;
    in.crs = crs.label(s.crs_wkt);
    in.points_read = s.points_read;
    in.points_kept = s.points_kept;
    report.points_read += s.points_read;
    report.points_kept += s.points_kept;
    emit(log, log_debug,
         path + ": " + (s.format.empty() ? std::string("points") : s.format) + ", " +
             std::to_string(s.points_read) + " points, " + std::to_string(s.points_kept) +
             " kept, " + crs.name(s.crs_wkt));
    if (options.inputs.size() > 1) {  // with one input, the error below says it all
      if (s.points_read == 0)
        emit(log, log_warn, path + ": no points in the file");
      else if (s.points_kept == 0)
        emit(log, log_warn, path + ": the filters kept none of its points");
    }

    merge_crs(path, s.crs_wkt);
    report.inputs.push_back(std::move(in));

    bytes_done += sizes[i];
    report_progress(progress, "read",
                    total_bytes
                        ? static_cast<double>(bytes_done) / static_cast<double>(total_bytes)
                        : static_cast<double>(i + 1) / static_cast<double>(options.inputs.size()));
  }
  // Contours and breaklines: their vertices go after the points, so vertex_of_point[n_points + i]
  // is line vertex i, and their CRS must agree with the points'.
  const std::size_t n_points = points.size();
  io::LineData lines;
  std::vector<std::string> line_sources = options.contours;
  line_sources.insert(line_sources.end(), options.breaklines.begin(), options.breaklines.end());
  for (const std::string& path : line_sources) {
    const io::LineReadStats s = io::read_lines(path, options.lines, lines);
    for (const std::string& w : s.warnings) emit(log, log_warn, w);
    report.line_features += s.features;
    report.zero_length_segments += s.zero_length_segments;
    emit(log, log_debug,
         path + ": layer " + s.layer + ", " + std::to_string(s.features) + " features, " +
             std::to_string(s.segments) + " segments, " + crs.name(s.crs_wkt));
    merge_crs(path, s.crs_wkt);
  }
  report.line_vertices = lines.vertices.size();
  report.constraint_segments = lines.segments.size();
  points.insert(points.end(), lines.vertices.begin(), lines.vertices.end());
  lines.vertices = {};

  if (!crs_wkt.empty() && options.assign_crs_wkt.empty()) {
    for (const std::string& path : without_crs)
      emit(log, log_warn,
           path + ": no CRS in the file; assuming " + crs.name(crs_wkt) + " of " + crs_source);
  }
  report.crs_wkt = crs_wkt;
  report.crs = crs.label(crs_wkt);
  report.timings_s.read = seconds_since(t0);

  // OBJ and PLY with a CRS get a .prj beside them: refuse now what the writer would refuse late.
  if (!crs_wkt.empty() && format != io::TinFormat::geojson)
    check_output_path(fs::path(options.output).replace_extension(".prj").string(),
                      options.write.overwrite);

  if (!options.write.target_crs_wkt.empty() && crs_wkt.empty())
    throw InputError(describe_inputs(options.inputs), "",
                     "cannot reproject to " + crs.name(options.write.target_crs_wkt) +
                         ": the input has no CRS (assign one with --a-srs)");

  // ---- offset ---------------------------------------------------------------------------------
  io::TinWriteOptions write = options.write;
  write.crs_wkt = crs_wkt;
  if (options.offset_auto && !points.empty()) {
    double min_x = points.front().x, min_y = points.front().y;
    for (const Point3& p : points) {
      min_x = std::min(min_x, p.x);
      min_y = std::min(min_y, p.y);
    }
    if (std::isfinite(min_x) && std::isfinite(min_y))
      write.offset = Point3{round_down(min_x, 1000.0), round_down(min_y, 1000.0), 0.0};
  }
  report.offset = write.offset;

  // ---- Delaunay stage -------------------------------------------------------------------------
  if (report.points_read == 0 && lines.segments.empty())
    throw GeometryError(describe_inputs(options.inputs), "", "no points in the input");
  if (report.points_kept == 0 && lines.segments.empty())
    throw GeometryError(describe_inputs(options.inputs), "",
                        "the class/return filters kept none of the " +
                            std::to_string(report.points_read) + " points");
  emit(log, log_debug, "triangulating " + std::to_string(points.size()) + " points");
  t0 = Clock::now();
  delaunay::DelaunayOptions dopt;
  dopt.on_duplicate = options.on_duplicate;
  dopt.keep_point_map = !lines.segments.empty();
  delaunay::DelaunayResult result = [&] {
    try {
      return delaunay::triangulate(std::move(points), dopt, progress);
    } catch (const GeometryError& e) {
      std::string detail = e.detail();
      if (filtering(options.filter) && report.points_kept < report.points_read)
        detail += " (the class/return filters kept " + std::to_string(report.points_kept) + " of " +
                  std::to_string(report.points_read) + " points)";
      throw GeometryError(e.file().empty() ? describe_inputs(options.inputs) : e.file(), e.where(),
                          detail);
    }
  }();
  points = {};  // moved-from; release whatever is left
  report.timings_s.delaunay = seconds_since(t0);
  report.duplicates_merged = result.duplicates_merged;
  if (result.duplicates_merged > 0)
    emit(log, log_debug,
         std::to_string(result.duplicates_merged) + " duplicate points merged (same x, y)");

  // ---- constraint stage -----------------------------------------------------------------------
  if (!lines.segments.empty()) {
    t0 = Clock::now();
    insert_lines(result, n_points, lines, options.constraint, progress, log, report);
    report.timings_s.constraints = seconds_since(t0);
  }
  result.tin.for_each_constrained_edge([&](EdgeId) { ++report.constraints; });
  report.vertices = result.tin.vertex_count();
  report.triangles = result.tin.triangle_count();

  if (options.validate) {
    t0 = Clock::now();
    // Only the CDT promises locally Delaunay edges; the other restorations keep a valid TIN.
    const std::string problem = result.tin.validate(
        {.delaunay = options.constraint.restore == constraints::Restore::delaunay});
    report.timings_s.validate = seconds_since(t0);
    if (!problem.empty())
      throw Error("internal error: the TIN failed validation: " + problem +
                  " (please report this with the input)");
    emit(log, log_debug, "validate: TIN is valid");
  }

  // ---- write ----------------------------------------------------------------------------------
  t0 = Clock::now();
  report_progress(progress, "write", 0.0);
  write.format = format;
  const io::TinWriteStats ws = io::write_tin(options.output, result.tin, write);
  report_progress(progress, "write", 1.0);
  report.timings_s.write = seconds_since(t0);
  report.output_bytes = ws.bytes;
  if (ws.triangles != report.triangles)
    emit(log, log_debug,
         "writer reports " + std::to_string(ws.triangles) + " triangles, the TIN " +
             std::to_string(report.triangles));

  report.timings_s.total = seconds_since(t_start);
  report.peak_rss_bytes = peak_rss_bytes();
  if (!options.stats_path.empty()) write_stats(report, options.stats_path, options.write.overwrite);
  return report;
}

}  // namespace tincdt::pipeline
