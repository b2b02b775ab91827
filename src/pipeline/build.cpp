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
#include "core/memory.hpp"
#include "io/crs.hpp"
#include "io/mesh/constraint_writer.hpp"
#include "io/reports/diagnostics_writer.hpp"
#include "pipeline/surface.hpp"
#include "terrain/flats.hpp"
#include "terrain/polygons.hpp"
#include "terrain/trim.hpp"

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

// The constraint stage: every hard line and contour segment becomes a chain of constrained
// edges. Segment sources are feature indices of `lines`, which are also their SourceTable ids.
constraints::ConstraintResult insert_lines(delaunay::DelaunayResult& result, std::size_t n_points,
                                           const io::LineData& lines,
                                           const detail::SourceTable& sources,
                                           const constraints::ConstraintOptions& options,
                                           const ProgressFn* progress, const LogFn& log,
                                           BuildReport& report,
                                           std::vector<constraints::Segment>* given) {
  std::vector<constraints::Segment> segments;
  segments.reserve(lines.segments.size());
  for (const io::LineData::Segment& s : lines.segments)
    segments.push_back({result.vertex_of_point[n_points + s.a],
                        result.vertex_of_point[n_points + s.b], s.feature});
  release(result.vertex_of_point);

  constraints::ConstraintResult c;
  try {
    c = constraints::insert_constraints(result.tin, segments, options, progress);
    if (given) *given = std::move(segments);
  } catch (const constraints::CrossingError& e) {
    char at[64];
    std::snprintf(at, sizeof at, "(%.3f, %.3f)", e.at.x, e.at.y);
    const bool known = sources.known(e.source_a);
    throw InputError(known ? sources.file(e.source_a) : std::string(),
                     known ? "feature " + std::to_string(sources.fid(e.source_a)) : std::string(),
                     std::string("crosses ") + sources.describe(e.source_b) + " at " + at +
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
           "crossing: " + sources.describe(x.source_a) + " and " + sources.describe(x.source_b) +
               " joined at a new vertex");
    }
    char dz[32];
    std::snprintf(dz, sizeof dz, "%.3f", c.max_z_disagreement);
    emit(log, log_warn,
         std::to_string(c.crossings.size()) +
             " crossing line segments joined at new vertices; the largest z disagreement is " + dz +
             " between " + sources.describe(worst->source_a) + " and " +
             sources.describe(worst->source_b));
  }
  return c;
}

// The files this run has written: removed again if the run fails after writing them, so that a
// failed run leaves nothing behind.
class WrittenFiles {
 public:
  WrittenFiles() = default;
  WrittenFiles(const WrittenFiles&) = delete;
  WrittenFiles& operator=(const WrittenFiles&) = delete;
  ~WrittenFiles() {
    if (done_) return;
    for (const std::string& path : paths_) {
      std::error_code ec;
      fs::remove(path, ec);
    }
  }
  void add(const std::string& path) { paths_.push_back(path); }
  void keep() { done_ = true; }

 private:
  std::vector<std::string> paths_;
  bool done_ = false;
};

// A diagnostics crossing record for crossing x (its vertex as it is in the TIN now).
io::Diagnostics::Crossing crossing_record(const mesh::Triangulation& tin,
                                          const constraints::Crossing& x,
                                          const detail::SourceTable& sources) {
  const Point2 p = tin.point(x.vertex);
  const auto file = [&](std::uint32_t s) { return sources.known(s) ? sources.file(s) : ""; };
  const auto fid = [&](std::uint32_t s) { return sources.known(s) ? sources.fid(s) : -1; };
  return {{p.x, p.y, tin.z(x.vertex)},
          file(x.source_a),
          fid(x.source_a),
          file(x.source_b),
          fid(x.source_b),
          x.z_a,
          x.z_b};
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
  if (options.fix_flats && options.contours.empty())
    throw InputError(
        "--fix-flats needs contours (--contours): flat triangles are those of one contour level");
  if (!(options.max_edge >= 0) || std::isnan(options.max_edge))
    throw InputError("--max-edge must be a length > 0");
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
  // The other outputs: each writable, and no two of them (nor the TIN) the same file.
  const std::pair<const std::string*, const char*> extra_outputs[] = {
      {&options.stats_path, "the stats file"},
      {&options.constraints_out, "the constraint lines (--constraints-out)"},
      {&options.diagnostics, "the diagnostics (--diagnostics)"}};
  for (std::size_t i = 0; i < std::size(extra_outputs); ++i) {
    const std::string& path = *extra_outputs[i].first;
    if (path.empty()) continue;
    check_output_path(path, options.write.overwrite);
    if (same_file(path, options.output))
      throw OutputError(path, "",
                        std::string(extra_outputs[i].second) + " and the TIN are the same file");
    for (std::size_t j = 0; j < i; ++j)
      if (!extra_outputs[j].first->empty() && same_file(path, *extra_outputs[j].first))
        throw OutputError(path, "",
                          std::string(extra_outputs[i].second) + " and " + extra_outputs[j].second +
                              " are the same file");
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
  // Contours and hard lines: their vertices go after the points, so vertex_of_point[n_points + i]
  // is line vertex i, and their CRS must agree with the points'. Their feature indices are also
  // their constraint source ids (SourceTable), contours first.
  const std::size_t n_points = points.size();
  io::LineData lines;
  detail::SourceTable sources;
  std::vector<std::pair<std::string, detail::SourceKind>> line_sources;
  for (const std::string& path : options.contours)
    line_sources.emplace_back(path, detail::SourceKind::contour);
  for (const std::string& path : options.breaklines)
    line_sources.emplace_back(path, detail::SourceKind::hard_line);
  for (const auto& [path, kind] : line_sources) {
    const std::size_t features_before = lines.features.size();
    const io::LineReadStats s = io::read_lines(path, options.lines, lines);
    for (const std::string& w : s.warnings) emit(log, log_warn, w);
    report.line_features += s.features;
    report.zero_length_segments += s.zero_length_segments;
    emit(log, log_debug,
         path + ": layer " + s.layer + ", " + std::to_string(s.features) + " features, " +
             std::to_string(s.segments) + " segments, " + crs.name(s.crs_wkt));
    merge_crs(path, s.crs_wkt);
    const std::uint32_t file = sources.add_file(lines.files.back());
    for (std::size_t f = features_before; f < lines.features.size(); ++f)
      sources.add(file, lines.features[f].fid, kind, false);
    BuildReport::Input in;
    in.path = path;
    in.kind = detail::kind_name(kind);
    in.format = s.layer;
    in.crs = crs.label(s.crs_wkt);
    in.features_read = s.features;
    in.features_used = lines.features.size() - features_before;
    in.features_dropped = s.empty_features;
    in.vertices = s.vertices;
    in.segments = s.segments;
    in.skipped_segments = s.zero_length_segments;
    report.inputs.push_back(std::move(in));
  }
  report.line_vertices = lines.vertices.size();
  report.constraint_segments = lines.segments.size();
  points.insert(points.end(), lines.vertices.begin(), lines.vertices.end());
  release(lines.vertices);

  // Surface features: soft lines and clip / erase / replace polygons. Source ids follow the
  // lines', kind by kind in this order.
  detail::SurfaceInput soft{detail::SourceKind::soft_line, {}, 0},
      clip{detail::SourceKind::clip, {}, 0}, erase{detail::SourceKind::erase, {}, 0},
      replace{detail::SourceKind::replace, {}, 0};
  const std::pair<detail::SurfaceInput*, const std::vector<std::string>*> surface_sources[] = {
      {&soft, &options.soft_lines},
      {&clip, &options.clip},
      {&erase, &options.erase},
      {&replace, &options.replace}};
  std::vector<const detail::SurfaceInput*> surface;
  for (const auto& [input, paths] : surface_sources) {
    io::ShapeReadOptions shape;
    shape.layer = options.lines.layer;
    if (input->kind == detail::SourceKind::replace) {
      shape.feature_z = true;
      shape.z_field = options.lines.z_field;
      shape.z_from_m = options.lines.z_from_m;
    }
    input->first_source = static_cast<std::uint32_t>(sources.size());
    for (const std::string& path : *paths) {
      const std::size_t features_before = input->data.features.size();
      const io::ShapeReadStats s = input->kind == detail::SourceKind::soft_line
                                       ? io::read_shape_lines(path, shape, input->data)
                                       : io::read_polygons(path, shape, input->data);
      for (const std::string& w : s.warnings) emit(log, log_warn, w);
      emit(log, log_debug,
           path + ": " + detail::kind_name(input->kind) + ", layer " + s.layer + ", " +
               std::to_string(s.features) + " features, " + std::to_string(s.parts) +
               (input->kind == detail::SourceKind::soft_line ? " lines, " : " rings, ") +
               crs.name(s.crs_wkt));
      merge_crs(path, s.crs_wkt);
      const std::uint32_t file = sources.add_file(input->data.files.back());
      for (std::size_t f = features_before; f < input->data.features.size(); ++f) {
        const io::ShapeFeature& feature = input->data.features[f];
        sources.add(file, feature.fid, input->kind, detail::is_draped(input->kind, feature));
      }
      BuildReport::Input in;
      in.path = path;
      in.kind = detail::kind_name(input->kind);
      in.format = s.layer;
      in.crs = crs.label(s.crs_wkt);
      in.features_read = s.features;
      in.features_used = input->data.features.size() - features_before;
      in.features_dropped = s.empty_features;
      in.vertices = s.vertices;
      in.segments = s.segments;
      in.skipped_segments = s.repeated_vertices;
      report.inputs.push_back(std::move(in));
      report.surface_features += in.features_used;
    }
    if (!input->data.features.empty()) surface.push_back(input);
  }

  if (!crs_wkt.empty() && options.assign_crs_wkt.empty()) {
    for (const std::string& path : without_crs)
      emit(log, log_warn,
           path + ": no CRS in the file; assuming " + crs.name(crs_wkt) + " of " + crs_source);
  }
  report.crs_wkt = crs_wkt;
  report.crs = crs.label(crs_wkt);
  report.timings_s.read = seconds_since(t0);

  // OBJ and PLY with a CRS get a .prj beside them: refuse now what the writer would refuse late.
  const std::string prj_path = fs::path(options.output).replace_extension(".prj").string();
  const bool want_prj = !crs_wkt.empty() && format != io::TinFormat::geojson;
  if (want_prj) check_output_path(prj_path, options.write.overwrite);

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
  dopt.keep_duplicates = !options.diagnostics.empty();
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
  release(points);  // moved-from; free whatever is left
  report.timings_s.delaunay = seconds_since(t0);
  report.duplicates_merged = result.duplicates_merged;
  if (result.duplicates_merged > 0)
    emit(log, log_debug,
         std::to_string(result.duplicates_merged) + " duplicate points merged (same x, y)");
  mesh::Triangulation& tin = result.tin;

  // ---- constraint stage: contours and hard lines ----------------------------------------------
  std::vector<constraints::Crossing> crossings;  // all of them, for the diagnostics
  std::vector<constraints::Piece> pieces;
  std::vector<constraints::Segment> checked_segments;  // kept for --validate
  if (!lines.segments.empty()) {
    t0 = Clock::now();
    constraints::ConstraintResult c =
        insert_lines(result, n_points, lines, sources, options.constraint, progress, log, report,
                     options.validate ? &checked_segments : nullptr);
    crossings = std::move(c.crossings);
    pieces = std::move(c.pieces);
    report.timings_s.constraints = seconds_since(t0);
  }

  // ---- surface features: drape, insert, constrain ---------------------------------------------
  if (!surface.empty()) {
    t0 = Clock::now();
    report_progress(progress, "surface", 0.0);
    detail::SurfaceResult sr = detail::insert_surface_features(
        tin, surface, sources, pieces, options.constraint.restore, progress);
    report_progress(progress, "surface", 1.0);
    const constraints::ConstraintResult& c = sr.constraints;
    report.soft_line_vertices = sr.soft_line_vertices;
    report.draped_vertices = sr.draped;
    report.reused_vertices = sr.reused;
    report.constraint_segments += sr.segments;
    report.zero_length_segments += c.segments_skipped;
    report.constraint_segments_split += c.split_at_vertices;
    report.crossings += c.crossings.size();
    report.steiner_vertices += c.crossings.size();
    report.flips.insertion += c.flips_insertion;
    report.flips.restoration += c.flips_restoration;
    crossings.insert(crossings.end(), c.crossings.begin(), c.crossings.end());
    pieces = std::move(sr.constraints.pieces);
    if (options.validate)
      checked_segments.insert(checked_segments.end(), sr.given.begin(), sr.given.end());
    emit(log, log_debug,
         std::to_string(report.surface_features) + " surface features: " +
             std::to_string(sr.vertices) + " vertices (" + std::to_string(sr.draped) + " draped, " +
             std::to_string(sr.reused) + " on existing vertices), " + std::to_string(sr.segments) +
             " segments, " + std::to_string(sr.constraints.crossings.size()) + " crossings (" +
             std::to_string(sr.crossings_with_hard_z) + " at a hard line's z)");
    report.timings_s.surface = seconds_since(t0);
  }

  // ---- terrain: fix flats -> replace -> trim -> clip -> erase ---------------------------------
  t0 = Clock::now();
  std::vector<std::uint8_t> on_contour;  // only needed for --fix-flats and the stats
  if (!options.contours.empty() && (options.fix_flats || !options.stats_path.empty())) {
    on_contour = detail::contour_flags(tin, pieces, sources);
    report.flats.counted = true;
    if (options.fix_flats) {
      report_progress(progress, "flats", 0.0);
      const terrain::FlatFixReport f = terrain::fix_flat_triangles(tin, on_contour);
      report_progress(progress, "flats", 1.0);
      report.flats.fixed = true;
      report.flats.before = f.flats_before;
      report.flats.after_swaps = f.flats_after_swaps;
      report.flats.after = f.flats_after;
      report.flats.swaps = f.swaps;
      report.flats.vertices_added = f.vertices_added;
      report.flats.vertices_interpolated = f.vertices_interpolated;
      report.flats.vertices_extrapolated = f.vertices_extrapolated;
      report.flats.left_no_level = f.flats_left_no_level;
      report.flats.left_unplaced = f.flats_left_unplaced;
      report.flats.non_delaunay_edges = f.non_delaunay_edges;
      emit(log, log_debug,
           "flat triangles: " + std::to_string(f.flats_before) + " before, " +
               std::to_string(f.flats_after) + " after " + std::to_string(f.swaps) + " swaps and " +
               std::to_string(f.vertices_added) + " new vertices");
    } else {
      report.flats.before = report.flats.after = report.flats.after_swaps =
          terrain::count_flat_triangles(tin, on_contour);
    }
  }
  if (!replace.data.features.empty()) {
    report.replaced_vertices =
        terrain::set_polygon_z_inside(tin, detail::polygons_of(replace.data));
    emit(log, log_debug,
         "replace: " + std::to_string(report.replaced_vertices) + " vertices set to polygon z");
  }
  if (options.max_edge > 0)
    report.trimmed_triangles = terrain::trim_long_edges(tin, options.max_edge);
  if (!clip.data.features.empty())
    report.clipped_triangles = terrain::remove_outside(tin, detail::polygons_of(clip.data));
  if (!erase.data.features.empty())
    report.erased_triangles = terrain::remove_inside(tin, detail::polygons_of(erase.data));
  report.timings_s.terrain = seconds_since(t0);
  if (report.trimmed_triangles + report.clipped_triangles + report.erased_triangles > 0) {
    emit(log, log_debug,
         "removed triangles: " + std::to_string(report.trimmed_triangles) + " trimmed, " +
             std::to_string(report.clipped_triangles) + " clipped, " +
             std::to_string(report.erased_triangles) + " erased");
    if (tin.triangle_count() == 0)
      throw GeometryError(describe_inputs(options.inputs), "",
                          "no triangle is left after --max-edge, --clip and --erase (" +
                              std::to_string(report.trimmed_triangles) + " trimmed, " +
                              std::to_string(report.clipped_triangles) + " clipped, " +
                              std::to_string(report.erased_triangles) + " erased)");
  }
  report.triangles = tin.triangle_count();
  // Constrained edges of the written TIN: those with a kept triangle on a side.
  tin.for_each_constrained_edge([&](EdgeId e) {
    if (tin.is_kept(mesh::triangle_of(e)) || tin.is_kept(mesh::triangle_of(tin.twin(e))))
      ++report.constraints;
  });

  if (options.validate) {
    t0 = Clock::now();
    // Only the CDT promises locally Delaunay edges, and --fix-flats swaps some edges off the
    // criterion on purpose (FlatFixReport::non_delaunay_edges); otherwise every edge stays
    // locally Delaunay or constrained: draped vertices go in by Lawson insertion, z changes and
    // removed triangles leave the plane triangulation as it is.
    const bool delaunay = options.constraint.restore == constraints::Restore::delaunay &&
                          report.flats.non_delaunay_edges == 0;
    std::string problem = tin.validate({.delaunay = delaunay});
    if (problem.empty()) problem = constraints::check_segments(tin, checked_segments, pieces);
    report.timings_s.validate = seconds_since(t0);
    if (!problem.empty())
      throw Error("internal error: the TIN failed validation: " + problem +
                  " (please report this with the input)");
    emit(log, log_debug,
         delaunay ? std::string("validate: TIN is valid")
                  : "validate: TIN is valid (topology; the Delaunay check is off for --restore " +
                        std::string(options.constraint.restore == constraints::Restore::delaunay
                                        ? "delaunay with --fix-flats swaps"
                                        : "aspect/none") +
                        ")");
  }

  // ---- write ----------------------------------------------------------------------------------
  t0 = Clock::now();
  report_progress(progress, "write", 0.0);
  WrittenFiles written;
  write.format = format;
  const io::TinWriteStats ws = io::write_tin(options.output, tin, write);
  written.add(options.output);
  if (want_prj) written.add(prj_path);
  report.output_bytes = ws.bytes;
  report.vertices = ws.vertices;
  if (ws.triangles != report.triangles)
    emit(log, log_debug,
         "writer reports " + std::to_string(ws.triangles) + " triangles, the TIN " +
             std::to_string(report.triangles));

  if (!options.constraints_out.empty()) {
    // One feature per piece (an edge with two sources, where lines overlap, gives two), for the
    // edges of the written TIN: with a kept triangle on a side.
    std::vector<io::ConstraintEdge> edges;
    edges.reserve(pieces.size());
    const bool removed =
        report.trimmed_triangles + report.clipped_triangles + report.erased_triangles > 0;
    for (const constraints::Piece& p : pieces) {
      if (removed) {
        const EdgeId e = tin.find_edge(p.a, p.b);
        if (e == kNoId ||
            (!tin.is_kept(mesh::triangle_of(e)) && !tin.is_kept(mesh::triangle_of(tin.twin(e)))))
          continue;
      }
      edges.push_back({p.a, p.b, p.source});
    }
    std::vector<io::ConstraintFeatureInfo> features;
    features.reserve(sources.size());
    for (std::uint32_t i = 0; i < sources.size(); ++i)
      features.push_back({sources.file(i), sources.fid(i)});
    io::TinWriteOptions lines_write = write;
    lines_write.format = io::TinFormat::geojson;
    io::write_constraint_lines(options.constraints_out, tin, edges, features, lines_write);
    written.add(options.constraints_out);
    report.constraints_out = options.constraints_out;
  }

  if (!options.diagnostics.empty()) {
    io::Diagnostics d;
    for (const delaunay::DelaunayResult::Duplicate& dup : result.duplicates) {
      const Point2 at = tin.point(dup.vertex);
      d.duplicates.push_back({{at.x, at.y, tin.z(dup.vertex)}, dup.points, dup.z_min, dup.z_max});
    }
    d.crossings.reserve(crossings.size());
    for (const constraints::Crossing& x : crossings)
      d.crossings.push_back(crossing_record(tin, x, sources));
    // Merged duplicates: the Delaunay stage does not report them one by one yet; the layer is
    // written empty.
    io::add_line_diagnostics(lines, d);
    for (const detail::SurfaceInput* input : {&soft, &clip, &erase, &replace}) {
      io::LineData records;
      records.files = input->data.files;
      records.skipped = input->data.skipped;
      records.dropped = input->data.dropped;
      io::add_line_diagnostics(records, d);
    }
    io::write_diagnostics(options.diagnostics, d, crs_wkt, options.write.overwrite);
    written.add(options.diagnostics);
    report.diagnostics = options.diagnostics;
  }
  report_progress(progress, "write", 1.0);
  report.timings_s.write = seconds_since(t0);

  if (!options.stats_path.empty()) {
    report.quality = terrain::measure_quality(tin, on_contour.empty() ? nullptr : &on_contour);
    report.quality_measured = true;
  }
  report.timings_s.total = seconds_since(t_start);
  report.peak_rss_bytes = peak_rss_bytes();
  if (!options.stats_path.empty()) write_stats(report, options.stats_path, options.write.overwrite);
  written.keep();
  return report;
}

}  // namespace tincdt::pipeline
