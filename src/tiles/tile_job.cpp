#include "tiles/tile_job.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/quoted_text.hpp"
#include "pipeline/stage.hpp"
#include "tiles/plan.hpp"

namespace tincdt::tiles {

using pipeline::BuildOptions;
using pipeline::Job;

namespace {

namespace fs = std::filesystem;

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string box_text(const BBox& b) {
  return "x " + number(b.min_x) + " to " + number(b.max_x) + ", y " + number(b.min_y) + " to " +
         number(b.max_y);
}

bool within(const BBox& inner, const BBox& outer) {
  return inner.min_x >= outer.min_x && inner.max_x <= outer.max_x && inner.min_y >= outer.min_y &&
         inner.max_y <= outer.max_y;
}

// Throws unless the file of input IN (at PATH) is the one the plan was made from.
void check_unchanged(const PlanInput& in, const std::string& path, const std::string& plan_path,
                     const std::string& where) {
  const std::string file =
      in.kind == "contours" || in.kind == "breaklines" ? io::vector_source_file(path) : path;
  std::error_code ec;
  const bool regular = fs::is_regular_file(file, ec);
  if (in.fingerprint.empty()) return;  // not a plain file (a database, a URL): nothing to compare
  if (!regular)
    throw InputError(
        plan_path, where,
        "input " + name_text(path) + " is missing: the plan was made from other inputs");
  const auto bytes = static_cast<std::uint64_t>(fs::file_size(file, ec));
  if (bytes != in.bytes || file_fingerprint(file) != in.fingerprint)
    throw InputError(
        plan_path, where,
        "input " + name_text(path) + " has changed since the plan was made (" +
            (bytes != in.bytes ? count_text(in.bytes) + " bytes then, " + count_text(bytes) + " now"
                               : std::string("same size, other content")) +
            "): make the plan again");
}

// The regions where data the tile does not hold may lie (TileSetup::missing).
void find_missing(TileSetup& setup, bool reads_rim) {
  const tiles::Polygon clip = reads_rim ? setup.rim.inner() : setup.rim.hull;
  for (const BBox& r : tiles::data_outside(setup.data, setup.buffered)) {
    tiles::Polygon piece = tiles::box_polygon(r);
    for (std::size_t i = 0; i < clip.size() && clip.size() >= 3 && !piece.empty(); ++i)
      piece = tiles::clip_left(piece, clip[i], clip[(i + 1) % clip.size()], setup.margin);
    if (!piece.empty()) setup.missing.push_back(std::move(piece));
  }
}

// How many cells of RESOLUTION make SIZE; 0 unless SIZE is a whole multiple of it (up to
// 1e-9 cell of rounding, as products::grid_over() counts cells).
double cells_across(double size, double resolution) {
  const double n = size / resolution;
  const double whole = std::round(n);
  return whole >= 1 && std::fabs(n - whole) <= 1e-9 * whole ? whole : 0;
}

// The plan's extent's larger side.
double extent_side(const TilePlan& plan) {
  const BBox& e = plan.extent;
  return std::max(e.max_x - e.min_x, e.max_y - e.min_y);
}

// A tile job's own --buffer, at most the plan's extent's larger side plus the tile size: the
// buffered box of a tile that meets the data then holds all of it, and a larger one reads
// nothing more, only grows the rounding margins of the tile's tests (at 1e308 they swallow it).
double largest_buffer(const TilePlan& plan) {
  if (tiles::empty(plan.extent)) return std::numeric_limits<double>::infinity();
  return extent_side(plan) + plan.tile_size;
}

void check_buffer(double buffer, const TilePlan& plan) {
  const double most = largest_buffer(plan);
  const double side = extent_side(plan);
  if (buffer > most)
    throw UsageError("--buffer: " + number(buffer) + " reaches beyond the plan's data: " +
                     number(most) + " (the extent's larger side, " + number(side) +
                     ", plus the tile size) already reads all of it");
}

const PlanTile& tile_of_plan(const TilePlan& plan, const TileOptions& options) {
  const std::string& plan_path = options.plan;
  if (plan.tiles.empty()) throw InputError(plan_path, "", "the plan has no tiles");
  if (static_cast<std::uint64_t>(options.tile) >= plan.tiles.size())
    throw InputError(plan_path, "",
                     "no tile " + signed_count_text(options.tile) + ": the plan has tiles 0 to " +
                         count_text(plan.tiles.size() - 1));
  return plan.tiles[static_cast<std::size_t>(options.tile)];
}

// The tile's place: its cell of the grid, the box it reads, and every input's bounds.
void place_tile(TileSetup& setup, const TilePlan& plan, const PlanTile& tile,
                const TileOptions& tiling, const BuildOptions& options) {
  setup.plan_path = tiling.plan;
  setup.index = tile.index;
  setup.tile_count = static_cast<std::uint32_t>(plan.tiles.size());
  setup.col = tile.col;
  setup.row = tile.row;
  setup.grid = tiles::TileGrid{plan.tile_size};
  if (!options.dem.path.empty() && cells_across(plan.tile_size, options.dem.resolution) == 0)
    throw UsageError("--resolution " + number(options.dem.resolution) +
                     " does not divide the plan's tile size " + number(plan.tile_size) +
                     ": a tile's DEM covers exactly its tile, in whole cells (give a resolution "
                     "that divides the tile size)");
  if (tiling.buffer >= 0) check_buffer(tiling.buffer, plan);
  setup.buffer = tiling.buffer >= 0 ? tiling.buffer : plan.buffer;
  setup.largest_buffer = largest_buffer(plan);
  setup.box = setup.grid.box(tile.col, tile.row);
  setup.buffered = setup.grid.buffered(tile.col, tile.row, setup.buffer);
  for (const PlanInput& in : plan.inputs)
    setup.data.push_back(tiles::empty(in.bounds) ? in.bounds
                                                 : tiles::grown(in.bounds, in.tolerance));
}

// The inputs in reach: the plan's list, or with another buffer, those whose bounds meet it.
std::vector<std::uint32_t> inputs_in_reach(const TilePlan& plan, const PlanTile& tile,
                                           const TileSetup& setup, const TileOptions& options,
                                           const std::string& where) {
  std::vector<std::uint32_t> reads = tile.inputs;
  if (options.buffer >= 0) {
    reads.clear();
    for (std::uint32_t i = 0; i < plan.inputs.size(); ++i)
      if (!tiles::empty(setup.data[i]) && tiles::intersects(setup.data[i], setup.buffered))
        reads.push_back(i);
  }
  if (reads.empty())
    throw InputError(options.plan, where,
                     "no input within its buffer (" + number(setup.buffer) +
                         "), yet the data's outline covers the tile: a larger buffer is needed "
                         "(--buffer on the tile job, or a new plan)");
  return reads;
}

// The build's inputs and how they are read, from the plan: each checked unchanged since the plan
// was made, its bounds kept to check what the job reads against (TileSetup::point_bounds, ...).
void read_plan_inputs(BuildOptions& o, TileSetup& setup, const TilePlan& plan,
                      const std::vector<std::uint32_t>& reads, const std::string& where) {
  const std::string& plan_path = setup.plan_path;
  o.inputs.clear();
  o.contours.clear();
  o.breaklines.clear();
  for (const std::uint32_t i : reads) {
    const PlanInput& in = plan.inputs[i];
    const std::string path = resolve_input(plan.inputs[i], plan_path);
    check_unchanged(in, path, plan_path, where);
    if (in.kind == "points") {
      o.inputs.push_back(path);
      setup.point_bounds.push_back(setup.data[i]);
    }
  }
  for (const char* kind : {"contours", "breaklines"})
    for (const std::uint32_t i : reads)
      if (plan.inputs[i].kind == kind) {
        (std::string(kind) == "contours" ? o.contours : o.breaklines)
            .push_back(resolve_input(plan.inputs[i], plan_path));
        setup.line_bounds.push_back(setup.data[i]);
      }
  o.lines = plan.lines;
  o.filter = plan.filter;
  o.filter.box = setup.buffered;
}

// A bound on the rounding of the tests in doubles, from the largest coordinate they see.
double rounding_margin(const BBox& buffered, const std::vector<Point2>& hull) {
  double magnitude = 1;
  for (const double v : {buffered.min_x, buffered.max_x, buffered.min_y, buffered.max_y})
    magnitude = std::max(magnitude, std::fabs(v));
  for (const Point2& p : hull) magnitude = std::max({magnitude, std::fabs(p.x), std::fabs(p.y)});
  return 256 * 0x1p-52 * magnitude;
}

// Whether the tile reads the rim: its buffered box reaches within the rim's width of the hull
// (a corner of it is not surely inside the hull shrunk by that width).
bool reaches_rim(const TileSetup& setup, double rim_width) {
  if (!(rim_width > 0)) return false;
  const tiles::Polygon inner = setup.rim.inner();
  const BBox& b = setup.buffered;
  bool reads_rim = false;
  for (const Point2 c : {Point2{b.min_x, b.min_y}, Point2{b.max_x, b.min_y},
                         Point2{b.max_x, b.max_y}, Point2{b.min_x, b.max_y}}) {
    const tiles::Polygon point{c};
    bool in = inner.size() >= 3;
    for (std::size_t i = 0; i < inner.size() && in; ++i)
      in = !tiles::may_meet_left(inner[(i + 1) % inner.size()], inner[i], point, setup.margin);
    reads_rim = reads_rim || !in;
  }
  return reads_rim;
}

}  // namespace

products::Grid tile_grid(const BBox& box, double resolution) {
  products::Grid g;
  g.min_x = box.min_x;
  g.max_y = box.max_y;
  g.resolution = resolution;
  g.width = static_cast<std::uint32_t>(cells_across(box.max_x - box.min_x, resolution));
  g.height = static_cast<std::uint32_t>(cells_across(box.max_y - box.min_y, resolution));
  if (g.width == 0 || g.height == 0)
    throw InternalError("tile_grid: the tile is not a multiple of the resolution");
  return g;
}

void check_tile_options(const TileOptions& t, const BuildOptions& o) {
  if (t.plan.empty()) {
    if (t.tile >= 0 || t.buffer >= 0 || t.max_buffer >= 0 || t.buffer_fixed || !t.outline.empty())
      throw UsageError(
          "--tile, --buffer, --max-buffer, --buffer-fixed and --outline need --plan: the plan "
          "that defines the tiles");
    return;
  }
  const auto refuse = [](const std::string& option, const std::string& why) {
    throw UsageError(option + " cannot be used with --plan: " + why);
  };
  const io::PointFilter& f = o.filter;
  if (!o.inputs.empty() || !o.contours.empty() || !o.breaklines.empty() || !o.lines.layer.empty() ||
      !o.lines.z_field.empty() || o.lines.z_from_m || !f.keep_classes.empty() ||
      !f.drop_classes.empty() || f.first_return_only || f.last_return_only)
    throw UsageError(
        "with --plan the inputs, and how they are read, come from the plan: give no "
        "INPUT, --contours, --breaklines, --layer, --z-field, --z-from-m or class and "
        "return filters (give them to 'tincdt plan')");
  if (t.tile < 0) throw UsageError("--plan needs --tile N: the index of the tile to build");
  if (!(t.buffer >= 0) && t.buffer != -1) throw UsageError("--buffer must be a length >= 0");
  if (!(t.max_buffer >= 0) && t.max_buffer != -1)
    throw UsageError("--max-buffer must be a length >= 0");
  if (t.buffer_fixed && t.max_buffer >= 0)
    throw UsageError("--max-buffer and --buffer-fixed exclude each other");
  // Each of these is a function of more of the whole TIN than a tile can prove final today; the
  // way out is the build without --plan (docs/tiling.md says what each would need).
  const std::string whole_job = " (build without --plan for it)";
  if (o.fix_flats)
    refuse("--fix-flats",
           "a flat area and the vertices that fix it span as far as the contours around it, "
           "beyond what a tile reads" +
               whole_job);
  // --max-error is a bound at every point, which each tile keeps on its own (tile_simplify.hpp);
  // a vertex budget is one count over the whole TIN.
  if (o.max_vertices > 0)
    refuse("--max-vertices",
           "a vertex budget counts the whole TIN's vertices, which no tile sees (give --max-error, "
           "or simplify without --plan)");
  if (!o.terrain.path.empty())
    refuse("--terrain",
           "a web-terrain pyramid's coarse tiles span many plan tiles; merge the tiles, then "
           "build the pyramid from the merged TIN");
  if (o.dem.extent)
    refuse("--dem-extent",
           "a tile's DEM covers exactly its tile, so that the tiles join (gdalbuildvrt)");
  if (o.constraint.restore != constraints::Restore::delaunay)
    refuse(
        "--restore " +
            std::string(o.constraint.restore == constraints::Restore::aspect ? "aspect" : "none"),
        "the triangles it leaves depend on the order the lines come in, which differs from "
        "tile to tile; only the constrained Delaunay triangulation is the same whatever the "
        "tiling" +
            whole_job);
}

BuildOptions tile_options(const TileOptions& tiling, const BuildOptions& options,
                          TileSetup& setup) {
  check_tile_options(tiling, options);
  const std::string& plan_path = tiling.plan;
  const TilePlan plan = read_plan(plan_path);
  const PlanTile& tile = tile_of_plan(plan, tiling);
  place_tile(setup, plan, tile, tiling, options);
  const std::string where = "tile " + std::to_string(tile.index);
  const std::vector<std::uint32_t> reads = inputs_in_reach(plan, tile, setup, tiling, where);
  BuildOptions o = options;
  read_plan_inputs(o, setup, plan, reads, where);

  setup.margin = rounding_margin(setup.buffered, plan.hull);
  setup.rim = tiles::Rim{plan.hull, plan.rim_width};
  if (plan.hull.empty() && !(options.clip.empty() && options.erase.empty() &&
                             options.soft_lines.empty() && options.replace.empty()))
    throw InputError(plan_path, "",
                     "--clip and --erase cut their rings to the data's hull, and soft lines and "
                     "replace rings must lie inside it, which this plan lacks (made with --rim "
                     "0): make the plan with a rim");
  const bool reads_rim = reaches_rim(setup, plan.rim_width);
  if (reads_rim) {
    setup.rim_path = resolve_input(plan.rim, plan_path);
    check_unchanged(plan.rim, setup.rim_path, plan_path, where);
  }
  find_missing(setup, reads_rim);
  if (o.write.offset_auto) {  // one offset for every tile: the plan's extent, rounded down to 1000
    o.write.offset_auto = false;
    o.write.offset = {std::floor(plan.extent.min_x / 1000.0) * 1000.0,
                      std::floor(plan.extent.min_y / 1000.0) * 1000.0, 0.0};
  }
  return o;
}

pipeline::CheckedOptions check_options(const TileOptions& tiling, const BuildOptions& options) {
  check_tile_options(tiling, options);
  if (tiling.plan.empty()) return pipeline::check_options(options);
  BuildOptions with_plan = options;
  with_plan.inputs = {tiling.plan};
  return pipeline::check_options(with_plan);
}

TileJob::TileJob(const BuildOptions& job_options, const pipeline::CheckedOptions& checked,
                 const TileSetup& setup, std::string outline_path, const ProgressFn* progress,
                 pipeline::LogFn log)
    : Job(job_options, checked, progress, std::move(log)),
      tile(setup),
      outline(std::move(outline_path)) {
  read_hooks.point_file_read = [this](const Job&, std::size_t input, const BBox& extent) {
    detail::check_tile_points(*this, input, extent);
  };
  read_hooks.point_files_read = [this](Job&) { detail::add_tile_rim(*this); };
  read_hooks.line_sources_read = [this](Job&) { detail::keep_tile_lines(*this); };
  read_hooks.keep_surface_feature = [this](pipeline::detail::SourceKind kind,
                                           const io::ShapeFeature& feature) {
    return detail::keeps_surface_feature(*this, kind, feature);
  };
  // Clip and erase rings are cut to the whole data's hull and draped only on final triangles;
  // a tile may lie wholly outside the clip polygons.
  surface_scope.hull = setup.rim.hull;
  surface_scope.settled = [this](const mesh::Triangulation& tin, TriangleId t) {
    return proven_final(tin, tile, t);
  };
  may_keep_none = true;
  if (!job_options.dem.path.empty()) dem_grid = tile_grid(setup.box, job_options.dem.resolution);
  preview_frame = setup.box;  // the tiles' pictures join into a mosaic, each tile framed
}

std::vector<const pipeline::Stage*> tile_stages() {
  std::vector<const pipeline::Stage*> list;
  for (const pipeline::Stage* stage : pipeline::stages()) {
    // A tile simplifies and trims in the tile stage, once the triangles near it are proven
    // final.
    if (stage->name == "simplify" || stage->name == "trim") continue;
    if (stage->name == "replace") list.push_back(&tile_stage);
    list.push_back(stage);
    if (stage->name == "erase") list.push_back(&tile_outline_stage);
  }
  assert(std::count(list.begin(), list.end(), &tile_stage) == 1);
  assert(std::count(list.begin(), list.end(), &tile_outline_stage) == 1);
  return list;
}

namespace {

pipeline::BuildReport build_tile_once(const TileOptions& tiling, const BuildOptions& options,
                                      const pipeline::CheckedOptions& checked,
                                      const ProgressFn* progress, const pipeline::LogFn& log) {
  TileSetup setup;
  const BuildOptions job_options = tile_options(tiling, options, setup);
  TileJob job(job_options, checked, setup, tiling.outline, progress, log);
  for (const std::string& warning : checked.warnings) job.warn(warning);
  const std::vector<const pipeline::Stage*> list = tile_stages();
  pipeline::FilePlan files = pipeline::plan_files(job_options, list);
  files.inputs.push_back({tiling.plan, "the plan (--plan)"});
  if (!tiling.outline.empty()) {
    // Among the outputs in the outline stage's place, so that they are checked in stage order.
    const auto at = static_cast<std::size_t>(
        std::find(list.begin(), list.end(), &tile_outline_stage) - list.begin());
    const std::size_t before =
        pipeline::plan_files(job_options, std::span(list).first(at)).outputs.size();
    files.outputs.insert(files.outputs.begin() + static_cast<std::ptrdiff_t>(before),
                         {tiling.outline, "the tile's outline (--outline)"});
  }
  job.report.figures.emplace_back("buffer", setup.buffer);  // before --stats is written
  return pipeline::run_job(job, list, files);
}

// The buffer after USED proved too small: what the unsettled triangles ask for, at least twice
// USED (an eighth of a tile from 0), at most LIMIT.
double next_buffer(const BufferTooSmall& e, double limit) {
  const double doubled = e.used() > 0 ? 2 * e.used() : e.tile_size() / 8;
  return std::min(limit, std::max(e.needed(), doubled));
}

}  // namespace

pipeline::BuildReport build_tile(const TileOptions& tiling, const BuildOptions& options,
                                 const ProgressFn* progress, const pipeline::LogFn& log) {
  const pipeline::CheckedOptions checked = check_options(tiling, options);
  if (tiling.plan.empty()) throw UsageError("a tile job needs --plan and --tile");
  TileOptions attempt = tiling;
  while (true) {
    try {
      return build_tile_once(attempt, options, checked, progress, log);
    } catch (const BufferTooSmall& e) {
      const double limit =
          std::min(tiling.max_buffer >= 0 ? tiling.max_buffer : e.tile_size(), e.largest());
      const double next = next_buffer(e, limit);
      if (tiling.buffer_fixed || !(next > e.used()))
        throw BufferTooSmall(
            e.file(), e.where(),
            e.detail() + (tiling.buffer_fixed
                              ? ""
                              : "; the buffer may grow to " + number(limit) + " at the most"),
            e.sizes(), Remedy::larger_buffer);
      if (log)
        log(pipeline::log_info, e.where() + ": buffer " + number(e.used()) +
                                    " is too small; reading to " + number(next));
      attempt.buffer = next;
    }
  }
}

namespace detail {

void check_tile_points(const TileJob& job, std::size_t input, const BBox& extent) {
  const TileSetup& tile = job.tile;
  if (tiles::empty(extent) || within(extent, tile.point_bounds[input])) return;
  throw InputError(job.options.inputs[input], "",
                   "holds points outside the bounds the plan has from its header (points: " +
                       box_text(extent) + "; header: " + box_text(tile.point_bounds[input]) +
                       "): tiled jobs rely on them; fix the header (e.g. 'lasinfo "
                       "-repair_bb') and make the plan again");
}

void add_tile_rim(TileJob& job) {
  const TileSetup& tile = job.tile;
  if (tile.rim_path.empty()) return;
  std::vector<Point3> rim;
  io::read_points(tile.rim_path, {}, rim);
  const BBox& b = tile.buffered;
  std::size_t added = 0;
  for (const Point3& p : rim) {
    if (p.x >= b.min_x && p.x <= b.max_x && p.y >= b.min_y && p.y <= b.max_y) continue;
    job.points.push_back(p);
    ++added;
  }
  job.debug("tile " + std::to_string(tile.index) + ": " + count_text(added) +
            " rim points outside the buffered box");
}

bool keeps_surface_feature(const TileJob& job, pipeline::detail::SourceKind kind,
                           const io::ShapeFeature& feature) {
  if (kind == pipeline::detail::SourceKind::clip) return true;
  BBox box;
  for (const io::ShapePart& part : feature.parts)
    for (const Point3& p : part.points) box.add(p.x, p.y);
  for (const tiles::Polygon& missing : job.tile.missing)
    if (tiles::box_inside(box, missing)) return false;
  return true;
}

void keep_tile_lines(TileJob& job) {
  const TileSetup& tile = job.tile;
  io::LineData& lines = job.lines;
  std::vector<char> local(lines.segments.size(), 0);
  for (std::size_t i = 0; i < lines.segments.size(); ++i) {
    const io::LineData::Segment& s = lines.segments[i];
    const Point3 &a = lines.vertices[s.a], &b = lines.vertices[s.b];
    BBox box;
    box.add(a.x, a.y);
    box.add(b.x, b.y);
    const std::uint32_t file = lines.features[s.feature].file;
    if (!within(box, tile.line_bounds[file]))
      throw InputError(
          lines.files[file], "feature " + std::to_string(lines.features[s.feature].fid),
          "lies outside the layer extent the plan has (" + box_text(tile.line_bounds[file]) +
              "): tiled jobs rely on it; make the plan again");
    const bool in_rim =
        !tile.rim_path.empty() && (tile.rim.holds({a.x, a.y}) || tile.rim.holds({b.x, b.y}));
    local[i] = tiles::intersects(box, tile.buffered) || in_rim ? 1 : 0;
  }
  // Lines may cross: the constraint stage makes each crossing vertex from the two whole
  // segments, which every tile holding either near the crossing reads whole, so every such tile
  // makes the same vertex. A crossing with a segment the tile leaves out lies outside the
  // buffered box, where the tile proves nothing final.
  // Keep the local segments whole, and only their vertices, in their order (--on-duplicate first
  // takes the first of coincident points in input order).
  std::vector<std::uint32_t> renumber(lines.vertices.size(), kNoId);
  for (std::size_t i = 0; i < lines.segments.size(); ++i)
    if (local[i]) renumber[lines.segments[i].a] = renumber[lines.segments[i].b] = 0;
  std::vector<Point3> vertices;
  for (std::size_t v = 0; v < renumber.size(); ++v) {
    if (renumber[v] == kNoId) continue;
    renumber[v] = static_cast<std::uint32_t>(vertices.size());
    vertices.push_back(lines.vertices[v]);
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < lines.segments.size(); ++i) {
    if (!local[i]) continue;
    io::LineData::Segment s = lines.segments[i];
    s.a = renumber[s.a];
    s.b = renumber[s.b];
    lines.segments[kept++] = s;
  }
  job.debug("tile " + std::to_string(tile.index) + ": " + count_text(kept) + " of " +
            count_text(lines.segments.size()) + " line segments meet the buffered box");
  lines.segments.resize(kept);
  lines.vertices = std::move(vertices);
}

}  // namespace detail
}  // namespace tincdt::tiles
