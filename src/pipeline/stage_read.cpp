// read: the point files, then the contours and hard lines, then the surface features, each
// source's CRS checked against the others' and, when it is another, its coordinates transformed
// into the job's (the target CRS, else the first input's). Line vertices go after the points, so
// that the Delaunay stage triangulates both; line and surface features get their constraint source
// ids (Job::sources) in reading order, contours first.
#include <algorithm>
#include <cassert>
#include <cctype>
#include <filesystem>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "io/crs.hpp"
#include "io/crs_probe.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "io/vector/polygon_reader.hpp"
#include "pipeline/dem_grid.hpp"
#include "pipeline/file_checks.hpp"
#include "pipeline/input_crs.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// An upper-bound guess of the point count, so the merged vector is allocated once. Reserved
// but untouched pages cost address space, not resident memory.
void reserve_points(const std::vector<std::string>& inputs, std::vector<Point3>& points) {
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
  if (n == 0) return;
  try {
    points.reserve(static_cast<std::size_t>(n));
  } catch (const std::bad_alloc&) {
    // fall back to growing as we read
  } catch (const std::length_error&) {
  }
}

void read_point_files(Job& job, detail::InputCrs& crs) {
  const std::vector<std::string>& inputs = job.options.inputs;
  reserve_points(inputs, job.points);
  std::vector<std::uint64_t> sizes;
  std::uint64_t total_bytes = 0, bytes_done = 0;
  for (const std::string& path : inputs) {
    std::error_code ec;
    const std::uintmax_t size = path == "-" ? 0 : fs::file_size(path, ec);
    sizes.push_back(ec ? 0 : static_cast<std::uint64_t>(size));
    total_bytes += sizes.back();
  }
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::string& path = inputs[i];
    const std::size_t points_before = job.points.size();
    const io::PointReadStats s =
        io::read_points(path, job.options.filter, job.points, job.options.threads);
    if (job.read_hooks.point_file_read) job.read_hooks.point_file_read(job, i, s.extent);
    for (const std::string& w : s.warnings) job.warn(w);
    BuildReport::Input in;
    in.path = path;
    in.format = s.format;
    in.crs = job.crs_names.label(s.crs_wkt);
    in.points_read = s.points_read;
    in.points_kept = s.points_kept;
    in.bytes_read = s.bytes_read;
    job.report.points_read += s.points_read;
    job.report.points_kept += s.points_kept;
    job.debug(path + ": " + (s.format.empty() ? std::string("points") : s.format) + ", " +
              count_text(s.points_read, "point") + ", " + count_text(s.points_kept) + " kept, " +
              job.crs_names.name(s.crs_wkt));
    if (inputs.size() > 1) {  // with one input, the Delaunay stage's error says it all
      if (s.points_read == 0)
        job.warn(path + ": no points in the file");
      else if (s.points_kept == 0 && job.options.filter.box)  // a tile's: planned by bounds
        job.debug(path + ": none of its points lies in the box read");
      else if (s.points_kept == 0)
        job.warn(path + ": the filters kept none of its points");
    }
    if (s.crs_wkt.empty()) crs.read_extent(path, std::span(job.points).subspan(points_before));
    crs.add(path, s.crs_wkt);
    detail::InputTransform(job, crs, path).apply_to_points(job.points, points_before);
    job.report.inputs.push_back(std::move(in));
    bytes_done += sizes[i];
    job.progress(total_bytes ? static_cast<double>(bytes_done) / static_cast<double>(total_bytes)
                             : static_cast<double>(i + 1) / static_cast<double>(inputs.size()));
  }
  if (job.read_hooks.point_files_read) job.read_hooks.point_files_read(job);
  job.point_count = job.points.size();
}

// Contours and hard lines: their feature indices are also their constraint source ids.
void read_line_sources(Job& job, detail::InputCrs& crs) {
  std::vector<std::pair<std::string, detail::SourceKind>> line_sources;
  for (const std::string& path : job.options.contours)
    line_sources.emplace_back(path, detail::SourceKind::contour);
  for (const std::string& path : job.options.breaklines)
    line_sources.emplace_back(path, detail::SourceKind::hard_line);
  io::LineData& lines = job.lines;
  for (const auto& [path, kind] : line_sources) {
    const std::size_t features_before = lines.features.size();
    const detail::InputTransform::Marks before = detail::InputTransform::marks(lines);
    const io::LineReadStats s = io::read_lines(path, job.options.lines, lines);
    for (const std::string& w : s.warnings) job.warn(w);
    job.report.line_features += s.features;
    job.report.zero_length_segments += s.zero_length_segments;
    job.debug(path + ": layer " + s.layer + ", " + count_text(s.features, "feature") + ", " +
              count_text(s.segments, "segment") + ", " + job.crs_names.name(s.crs_wkt));
    crs.read_extent(path, std::span(lines.vertices).subspan(before.vertices));
    crs.add(path, s.crs_wkt);
    detail::InputTransform(job, crs, path).apply_to_lines(lines, before, s.layer);
    const std::uint32_t file = job.sources.add_file(lines.files.back());
    for (std::size_t f = features_before; f < lines.features.size(); ++f)
      job.sources.add(file, lines.features[f].fid, kind, false);
    BuildReport::Input in;
    in.path = path;
    in.kind = detail::kind_name(kind);
    in.format = s.layer;
    in.crs = job.crs_names.label(s.crs_wkt);
    in.features_read = s.features;
    in.features_used = lines.features.size() - features_before;
    in.features_dropped = s.empty_features;
    in.vertices = s.vertices;
    in.segments = s.segments;
    in.skipped_segments = s.zero_length_segments;
    job.report.inputs.push_back(std::move(in));
  }
  if (job.read_hooks.line_sources_read) job.read_hooks.line_sources_read(job);
  job.report.line_vertices = lines.vertices.size();
  job.report.constraint_segments = lines.segments.size();
  job.points.insert(job.points.end(), lines.vertices.begin(), lines.vertices.end());
  release(lines.vertices);
}

// One kind of surface feature from every source given for it.
void read_surface_kind(Job& job, detail::InputCrs& crs, detail::SurfaceInput& input,
                       const std::vector<std::string>& paths) {
  io::ShapeReadOptions shape;
  shape.layer = job.options.lines.layer;
  const bool lines = input.kind == detail::SourceKind::soft_line;
  if (input.kind == detail::SourceKind::replace) {
    shape.feature_z = true;
    shape.z_field = job.options.lines.z_field;
    shape.z_from_m = job.options.lines.z_from_m;
  }
  input.first_source = static_cast<std::uint32_t>(job.sources.size());
  for (const std::string& path : paths) {
    const std::size_t features_before = input.data.features.size();
    const detail::InputTransform::Marks before = detail::InputTransform::marks(input.data);
    const io::ShapeReadStats s = lines ? io::read_shape_lines(path, shape, input.data)
                                       : io::read_polygons(path, shape, input.data);
    for (const std::string& w : s.warnings) job.warn(w);
    job.debug(path + ": " + detail::kind_name(input.kind) + ", layer " + s.layer + ", " +
              count_text(s.features, "feature") + ", " +
              count_text(s.parts, lines ? "line" : "ring") + ", " + job.crs_names.name(s.crs_wkt));
    for (std::size_t f = features_before; f < input.data.features.size(); ++f)
      for (const io::ShapePart& part : input.data.features[f].parts)
        crs.read_extent(path, part.points);
    crs.add(path, s.crs_wkt);
    detail::InputTransform(job, crs, path).apply_to_shapes(input.data, before, s.layer);
    if (const auto& keep = job.read_hooks.keep_surface_feature) {
      std::vector<io::ShapeFeature>& features = input.data.features;
      const auto first = features.begin() + static_cast<std::ptrdiff_t>(features_before);
      const std::size_t given = static_cast<std::size_t>(features.end() - first);
      features.erase(
          std::remove_if(first, features.end(),
                         [&](const io::ShapeFeature& f) { return !keep(input.kind, f); }),
          features.end());
      job.debug(path + ": " + count_text(features.size() - features_before) + " of " +
                count_text(given, "feature") + " kept for the part of the data read");
    }
    const std::uint32_t file = job.sources.add_file(input.data.files.back());
    for (std::size_t f = features_before; f < input.data.features.size(); ++f) {
      const io::ShapeFeature& feature = input.data.features[f];
      job.sources.add(file, feature.fid, input.kind, detail::is_draped(input.kind, feature));
    }
    BuildReport::Input in;
    in.path = path;
    in.kind = detail::kind_name(input.kind);
    in.format = s.layer;
    in.crs = job.crs_names.label(s.crs_wkt);
    in.features_read = s.features;
    in.features_used = input.data.features.size() - features_before;
    in.features_dropped = s.empty_features;
    in.vertices = s.vertices;
    in.segments = s.segments;
    in.skipped_segments = s.repeated_vertices;
    job.report.surface_features += in.features_used;
    job.report.inputs.push_back(std::move(in));
  }
}

// After every source: no input without a CRS among inputs with one, the reprojection's needs, and
// whether the TIN gets a .prj. An existing .prj with the same CRS is kept as it is; one with
// another CRS needs --overwrite. Checked now, so that a long job does not fail at its end.
void settle_crs(Job& job, detail::InputCrs& crs) {
  crs.finish();
  job.crs_wkt = crs.crs();
  job.report.crs_wkt = job.crs_wkt;
  job.report.crs = job.crs_names.label(job.crs_wkt);
  job.write.crs_wkt = job.crs_wkt;
  job.write_prj = io::wants_prj(*job.write.format, job.crs_wkt);
  if (!job.write_prj) return;
  const std::string prj = io::prj_path(job.options.output);
  std::error_code ec;
  const fs::file_status st = fs::status(prj, ec);
  if (!fs::exists(st)) return;
  if (fs::is_regular_file(st) && detail::prj_holds(prj, job.crs_wkt)) {
    job.write_prj = false;
    job.debug(prj + ": holds the TIN's CRS already; kept as it is");
    return;
  }
  detail::refuse_input(plan_files(job.options, stages()), prj, "the TIN's .prj");
  detail::check_output_path(prj, job.write.overwrite);
}

bool wanted(const BuildOptions&) {
  return true;
}

// The vector sources of every kind, in reading order.
std::vector<std::string> vector_sources(const BuildOptions& o) {
  std::vector<std::string> paths;
  for (const auto* list :
       {&o.contours, &o.breaklines, &o.soft_lines, &o.clip, &o.erase, &o.replace})
    paths.insert(paths.end(), list->begin(), list->end());
  return paths;
}

// The inputs' CRSs as their headers and layers give them, checked before any point is read:
// an unusable or disagreeing CRS stops the job now, not after the work. The inputs whose CRS only
// reading tells (XYZ, PLY) are checked as they are read.
void check_crs_before_reading(Job& job, detail::InputCrs& crs) {
  for (const std::string& path : job.options.inputs)
    if (const std::optional<std::string> own = io::point_file_crs(path)) crs.add(path, *own);
  for (const std::string& path : vector_sources(job.options)) {
    const io::VectorCrs own = io::vector_source_crs(path, job.options.lines.layer);
    crs.add(path, own.wkt, own.implied);
  }
  crs.check_none_without();
}

void run(Job& job) {
  std::vector<std::string> order = job.options.inputs;
  for (std::string& path : vector_sources(job.options)) order.push_back(std::move(path));
  detail::InputCrs crs(job, std::move(order));
  check_crs_before_reading(job, crs);
  read_point_files(job, crs);
  read_line_sources(job, crs);
  const std::pair<detail::SurfaceInput*, const std::vector<std::string>*> kinds[] = {
      {&job.soft, &job.options.soft_lines},
      {&job.clip, &job.options.clip},
      {&job.erase, &job.options.erase},
      {&job.replace, &job.options.replace}};
  for (const auto& [input, paths] : kinds) read_surface_kind(job, crs, *input, *paths);
  settle_crs(job, crs);
  check_dem_grid_early(job);  // the extent is known: an impossible DEM stops here
}

void plan(const BuildOptions& o, FilePlan& files) {
  for (const std::string& p : o.inputs) files.inputs.push_back({p, "a point file"});
  std::error_code ec;
  if (!o.assign_srs.empty() && fs::is_regular_file(o.assign_srs, ec))
    files.inputs.push_back({o.assign_srs, "the CRS file of --a-srs"});
  if (!o.override_srs.empty() && fs::is_regular_file(o.override_srs, ec))
    files.inputs.push_back({o.override_srs, "the CRS file of --override-srs"});
  const std::pair<const std::vector<std::string>*, const char*> vectors[] = {
      {&o.contours, "--contours"}, {&o.breaklines, "--hard-lines"}, {&o.soft_lines, "--soft-lines"},
      {&o.clip, "--clip"},         {&o.erase, "--erase"},           {&o.replace, "--replace"}};
  for (const auto& [paths, option] : vectors)
    for (const std::string& p : *paths)
      files.inputs.push_back({p, std::string(option) + " source"});
}

// ---- options -----------------------------------------------------------------------------------

namespace groups = option_groups;

template <auto Classes>
void add_classes(BuildOptions& o, std::string_view text) {
  [[maybe_unused]] const auto bad = append_class_codes(text, o.filter.*Classes);
  assert(!bad && "checked before");
}

std::string check_classes(std::string_view text) {
  std::vector<std::uint8_t> codes;
  const auto bad = append_class_codes(text, codes);
  return bad ? in_quotes(*bad) + " is not a LAS classification code (0-255)" : std::string();
}

// --keep-class or --drop-class: codes added to the filter's CLASSES.
template <auto Classes>
constexpr OptionSpec class_option(std::string_view flags, std::string_view help) {
  OptionSpec spec =
      checked_option(flags, "N[,N...]", groups::input, check_classes, add_classes<Classes>, help);
  spec.kind = OptionKind::repeated;
  return spec;
}

constexpr OptionSpec kOptions[] = {
    {.flags = "INPUT",
     .value_name = "FILE",
     .help = "Point files: LAS 1.0-1.4, LAZ, COPC, XYZ text ('-' = stdin) or PLY\n"
             "(the vertices of a TIN)",
     .kind = OptionKind::positional,
     .set = add_text<&BuildOptions::inputs>},
    text_option("--a-srs", "SRS", groups::input, set_text<&BuildOptions::assign_srs>,
                "The CRS of the inputs that have none (EPSG:n, WKT, PROJ string\n"
                "or .prj file); a file's own CRS is kept"),
    text_option("--override-srs", "SRS", groups::input, set_text<&BuildOptions::override_srs>,
                "Replace every input's own CRS with SRS (EPSG:n, WKT, PROJ string\n"
                "or .prj file): for files whose CRS is missing or wrong"),
    text_option("--t-srs", "SRS", groups::input, set_text<&BuildOptions::target_srs>,
                "The CRS of the TIN and every output (e.g. EPSG:32633): every\n"
                "input is transformed into SRS as it is read, before triangulation"),
    flag_option("--allow-geographic", groups::input, set_true<&BuildOptions::allow_geographic>,
                "Let --t-srs be geographic (degrees): the TIN is then Delaunay\n"
                "in degrees, DEM cells and lengths are in degrees"),
    class_option<&io::PointFilter::keep_classes>(
        "--keep-class",
        "Keep only these classes (e.g. 2,8): LAS, or XYZ text\n"
        "with a classification column"),
    class_option<&io::PointFilter::drop_classes>("--drop-class",
                                                 "Drop these classes (e.g. 7,18: noise)"),
    flag_option("--first-only", groups::input,
                set_true<&BuildOptions::filter, &io::PointFilter::first_return_only>,
                "Keep only first returns (LAS)"),
    flag_option("--last-only", groups::input,
                set_true<&BuildOptions::filter, &io::PointFilter::last_return_only>,
                "Keep only last returns (LAS)"),
    repeated_option("--contours", "LINES", groups::lines, add_text<&BuildOptions::contours>,
                    "Contour lines: hard edges; their flats are what --fix-flats fixes"),
    repeated_option("--hard-lines,--breaklines", "LINES", groups::lines,
                    add_text<&BuildOptions::breaklines>,
                    "Hard lines (breaklines): every segment is a TIN edge"),
    repeated_option("--soft-lines", "LINES", groups::lines, add_text<&BuildOptions::soft_lines>,
                    "Soft lines: TIN edges with z draped from the TIN (own z ignored)"),
    text_option("--layer", "NAME", groups::lines,
                set_text<&BuildOptions::lines, &io::LineReadOptions::layer>,
                "Layer to read from each vector source"),
    text_option("--z-field", "NAME", groups::lines,
                set_text<&BuildOptions::lines, &io::LineReadOptions::z_field>,
                "Take z from this attribute (contours, lines, replace)"),
    flag_option("--z-from-m", groups::lines,
                set_true<&BuildOptions::lines, &io::LineReadOptions::z_from_m>,
                "Take z from the M values (contours, lines, replace)"),
};

}  // namespace

constexpr StageProgress kReadProgress{"reading the inputs", "bytes", stage_items::point_file_bytes};
extern const Stage read_stage{"read",
                              "read",
                              wanted,
                              run,
                              plan,
                              "points, contours and hard lines: triangulated, the lines made TIN "
                              "edges",
                              kOptions,
                              kReadProgress};

}  // namespace tincdt::pipeline
