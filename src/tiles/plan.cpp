#include "tiles/plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "core/json.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "core/quoted_text.hpp"
#include "io/output_set.hpp"
#include "io/points/point_summary.hpp"
#include "io/vector/line_reader.hpp"
#include "io/vector/vector_extent.hpp"
#include "pipeline/file_checks.hpp"
#include "tiles/plan_rim.hpp"
#include "tiles/tile_rules.hpp"

namespace tincdt::tiles {
namespace {

namespace fs = std::filesystem;
using JsonValue = json::Value;

constexpr int kPlanVersion = 1;
constexpr std::uint64_t kMaxTiles = 10'000'000;
constexpr std::size_t kFingerprintBytes = 64 * 1024;

// Plan numbers have 17 significant digits: tile boxes and bounds read back are the ones written.
std::string json_number(double v) {
  return json::number(v, json::Numbers::digits17);
}

// The plan's folder, absolute.
fs::path plan_folder(const std::string& plan_path) {
  return fs::absolute(fs::path(plan_path)).lexically_normal().parent_path();
}

// SPEC as the plan stores it: a relative path becomes relative to the plan's folder.
std::string stored_path(const std::string& spec, const std::string& file,
                        const std::string& plan_path) {
  const std::string layer_suffix = spec.substr(file.size());  // ":LAYER" or ""
  const fs::path p(file);
  if (p.is_absolute()) return spec;
  const fs::path relative =
      fs::absolute(p).lexically_normal().lexically_relative(plan_folder(plan_path));
  return (relative.empty() ? p : relative).generic_string() + layer_suffix;
}

// FNV-1a, 64 bits, over a file's size and its first and last 64 KiB (HEAD, TAIL): cheap, and
// any rewrite of a LAS file changes its header or its tail.
std::string fingerprint(std::uint64_t size, std::string_view head, std::string_view tail) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const std::string size_text = std::to_string(size);
  for (const std::string_view part : {std::string_view(size_text), head, tail})
    for (const char c : part) {
      h ^= static_cast<unsigned char>(c);
      h *= 0x100000001b3ULL;
    }
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return text;
}

BBox inflated(const PlanInput& in) {
  return tiles::empty(in.bounds) ? in.bounds : tiles::grown(in.bounds, in.tolerance);
}

PlanInput point_input(const std::string& path, const std::string& plan_path) {
  if (path == "-") throw UsageError("a plan cannot read standard input ('-'): give files");
  const io::PointFileSummary s = io::summarize_point_file(path);
  PlanInput in;
  in.path = stored_path(path, path, plan_path);
  in.kind = "points";
  in.format = s.format;
  in.bytes = static_cast<std::uint64_t>(fs::file_size(path));
  in.fingerprint = file_fingerprint(path);
  in.count = s.points;
  in.bounds = s.bounds;
  in.tolerance = s.tolerance;
  return in;
}

void put_box(json::Writer& j, const BBox& b) {
  if (tiles::empty(b))
    j.null();
  else
    j.array(std::array{b.min_x, b.min_y, b.max_x, b.max_y}, json::Layout::spaced);
}

// A vector source: read whole (its vertices count for the data's hull), bounds exact.
PlanInput vector_input(const std::string& spec, const char* kind, const io::LineReadOptions& lines,
                       const std::string& plan_path, std::vector<Point2>& vertices) {
  io::LineData data;
  const io::LineReadStats stats = io::read_lines(spec, lines, data);
  const std::string file = io::vector_source_file(spec);
  PlanInput in;
  in.path = stored_path(spec, file, plan_path);
  in.kind = kind;
  in.format = stats.layer;
  std::error_code ec;
  const auto bytes = fs::file_size(file, ec);
  in.bytes = ec ? 0 : static_cast<std::uint64_t>(bytes);
  in.fingerprint = fs::is_regular_file(file, ec) ? file_fingerprint(file) : std::string();
  in.count = stats.features;
  for (const Point3& v : data.vertices) {
    in.bounds.add(v.x, v.y);
    vertices.push_back({v.x, v.y});
  }
  return in;
}

// The outer inputs first: those nearest to the edge of all the data's box.
std::vector<std::size_t> outermost_first(const std::vector<PlanInput>& inputs, const BBox& all) {
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const BBox& b = inputs[i].bounds;
    if (inputs[i].kind != "points" || tiles::empty(b)) continue;
    const double depth = std::min(
        {b.min_x - all.min_x, all.max_x - b.max_x, b.min_y - all.min_y, all.max_y - b.max_y});
    order.emplace_back(depth, i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& p, const auto& q) { return p.first < q.first; });
  std::vector<std::size_t> out;
  for (const auto& [depth, i] : order) out.push_back(i);
  return out;
}

void put_input(json::Writer& j, const PlanInput& in) {
  j.field("path", in.path).field("kind", in.kind).field("format", in.format);
  j.field("bytes", in.bytes).field("fingerprint", in.fingerprint).field("count", in.count);
  put_box(j.key("bounds"), in.bounds);
  j.field("tolerance", in.tolerance);
}

// ---- reading ----------------------------------------------------------------------------------

class PlanReader {
 public:
  explicit PlanReader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(path_, where, "not a valid tincdt plan: " + what);
  }

  const JsonValue& member(const JsonValue& object, const char* key, JsonValue::Kind kind,
                          const std::string& where) const {
    const JsonValue* v = object.find(key);
    if (!v || !v->is(kind)) fail(where, std::string("no ") + kind_name(kind) + " '" + key + "'");
    return *v;
  }

  double number(const JsonValue& object, const char* key, const std::string& where) const {
    return member(object, key, JsonValue::Kind::number, where).number();
  }

  std::uint64_t count(const JsonValue& object, const char* key, const std::string& where) const {
    const double v = number(object, key, where);
    if (!(v >= 0 && v < 0x1p53 && v == std::floor(v)))
      fail(where, std::string("'") + key + "' is not a count");
    return static_cast<std::uint64_t>(v);
  }

  std::int64_t integer(const JsonValue& object, const char* key, const std::string& where) const {
    const double v = number(object, key, where);
    if (!(std::fabs(v) < 0x1p53 && v == std::floor(v)))
      fail(where, std::string("'") + key + "' is not an integer");
    return static_cast<std::int64_t>(v);
  }

  BBox box(const JsonValue& object, const char* key, const std::string& where) const {
    const JsonValue* v = object.find(key);
    if (v && v->is(JsonValue::Kind::null)) return {};
    if (!v || !v->is(JsonValue::Kind::array) || v->items().size() != 4)
      fail(where, std::string("'") + key + "' is not [min x, min y, max x, max y]");
    double c[4];
    for (int i = 0; i < 4; ++i) {
      if (!v->items()[i].is(JsonValue::Kind::number))
        fail(where, std::string("'") + key + "' is not [min x, min y, max x, max y]");
      c[i] = v->items()[i].number();
    }
    if (!(c[0] <= c[2] && c[1] <= c[3])) fail(where, std::string("'") + key + "' is reversed");
    return {c[0], c[1], c[2], c[3]};
  }

 private:
  static const char* kind_name(JsonValue::Kind k) {
    switch (k) {
      case JsonValue::Kind::number:
        return "number";
      case JsonValue::Kind::string:
        return "string";
      case JsonValue::Kind::array:
        return "array";
      case JsonValue::Kind::object:
        return "object";
      default:
        return "value";
    }
  }

  std::string path_;
};

}  // namespace

std::string file_fingerprint(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (!in || ec) throw InputError(file, "", "cannot read the file to fingerprint it");
  std::string head(kFingerprintBytes, '\0'), tail;
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (size > kFingerprintBytes) {
    tail.resize(std::min<std::uintmax_t>(size - kFingerprintBytes, kFingerprintBytes));
    in.clear();
    in.seekg(static_cast<std::streamoff>(size - tail.size()));
    in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
    tail.resize(static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(file, "", "read failed while fingerprinting the file");
  return fingerprint(size, head, tail);
}

namespace {

void check_plan_options(const PlanOptions& options) {
  if (!(options.tile_size > 0) || !std::isfinite(options.tile_size))
    throw UsageError("--tile-size must be a length > 0");
  if (!(options.buffer >= 0) || !std::isfinite(options.buffer))
    throw UsageError("--buffer must be a length >= 0");
  if (!std::isfinite(options.rim_width)) throw UsageError("--rim must be a length >= 0");
  if (options.inputs.empty() && options.contours.empty() && options.breaklines.empty())
    throw UsageError("no input: give point files, --contours or --breaklines");
}

// The plan's settings and its inputs as their headers (points) or whole reads (lines) tell them;
// the line sources' vertices go to LINE_VERTICES, as they count for the data's hull.
TilePlan summarize_inputs(const PlanOptions& options, std::vector<Point2>& line_vertices) {
  TilePlan plan;
  plan.tile_size = options.tile_size;
  plan.buffer = options.buffer;
  plan.filter = options.filter;
  plan.filter.box.reset();
  plan.lines = options.lines;
  for (const std::string& path : options.inputs)
    plan.inputs.push_back(point_input(path, options.output));
  for (const std::string& spec : options.contours)
    plan.inputs.push_back(
        vector_input(spec, "contours", options.lines, options.output, line_vertices));
  for (const std::string& spec : options.breaklines)
    plan.inputs.push_back(
        vector_input(spec, "breaklines", options.lines, options.output, line_vertices));
  return plan;
}

// Every input's bounds grown by its tolerance, and the points the headers count.
struct DataBox {
  BBox all;
  std::uint64_t points = 0;
};

DataBox data_box(const std::vector<PlanInput>& inputs) {
  DataBox d;
  for (const PlanInput& in : inputs) {
    if (tiles::empty(in.bounds)) continue;
    const BBox b = inflated(in);
    d.all.add(b.min_x, b.min_y);
    d.all.add(b.max_x, b.max_y);
    d.points += in.kind == "points" ? in.count : 0;
  }
  if (tiles::empty(d.all))
    throw InputError(inputs.front().path, "", "no input holds any data: nothing to tile");
  return d;
}

// Up to one point file per thread from ORDER, starting at NEXT, skipping (and counting in
// SKIPPED) those the hull so far already holds deep inside: they cannot add to the rim.
std::vector<std::size_t> next_scan_batch(const std::vector<std::size_t>& order, std::size_t& next,
                                         const TilePlan& plan, const std::vector<Point2>& hull,
                                         std::size_t threads, std::size_t& skipped) {
  std::vector<std::size_t> batch;
  for (; next < order.size() && batch.size() < threads; ++next) {
    if (detail::deep_inside(inflated(plan.inputs[order[next]]), hull, plan.rim_width))
      ++skipped;
    else
      batch.push_back(order[next]);
  }
  return batch;
}

// The batch's files scanned in parallel; a file's error is kept for its turn, so that the files
// before it are still taken in order.
struct BatchScans {
  std::vector<detail::PointScan> scans;
  std::vector<std::exception_ptr> errors;
};

BatchScans scan_batch(const PlanOptions& options, const TilePlan& plan,
                      const std::vector<std::size_t>& batch, std::size_t threads,
                      const std::vector<Point2>& hull) {
  BatchScans b{std::vector<detail::PointScan>(batch.size()),
               std::vector<std::exception_ptr>(batch.size())};
  parallel_chunks(
      threads, batch.size(),
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) try {
            b.scans[k] = detail::scan_points(options.inputs[batch[k]], plan.filter, plan.rim_width,
                                             batch.size() > 1 ? 1 : 0, hull);
          } catch (...) {
            b.errors[k] = std::current_exception();
          }
      },
      1);
  return b;
}

// The rim: the data's hull (into PLAN) and the points near it (into RIM), from the files that can
// hold them, outermost first.
void find_rim(const PlanOptions& options, TilePlan& plan, const BBox& all,
              const std::vector<Point2>& line_vertices, std::vector<Point3>& rim,
              const LogFn& log) {
  std::vector<std::pair<std::size_t, Point3>> near;  // (input, point)
  std::vector<Point2> hull = tiles::convex_hull(line_vertices);
  std::size_t scanned = 0, skipped = 0;
  const std::vector<std::size_t> order = outermost_first(plan.inputs, all);
  const std::size_t threads = thread_count(options.threads);
  for (std::size_t next = 0; next < order.size();) {
    const std::vector<std::size_t> batch =
        next_scan_batch(order, next, plan, hull, threads, skipped);
    const BatchScans b = scan_batch(options, plan, batch, threads, hull);
    for (std::size_t k = 0; k < batch.size(); ++k) {
      if (b.errors[k]) std::rethrow_exception(b.errors[k]);
      PlanInput& in = plan.inputs[batch[k]];
      const detail::PointScan& scan = b.scans[k];
      ++scanned;
      // Exact now for a file read whole. A COPC file keeps its header's bounds and count: the
      // nodes its scan leaves out depend on the hull of the files scanned before it, and so on
      // the batches, and points there lie outside the bounds of those read.
      if (scan.nodes == 0) {
        in.count = scan.points;
        in.bounds = scan.bounds;
        in.tolerance = 0;
      }
      hull.insert(hull.end(), scan.hull.begin(), scan.hull.end());
      for (const Point3& p : scan.near_outline) near.emplace_back(batch[k], p);
      if (log)
        log(log_debug,
            in.path + ": " + count_text(scan.points, "point") + ", " +
                count_text(scan.near_outline.size()) + " near its outline" +
                (scan.nodes == 0 ? std::string()
                                 : "; read " + count_text(scan.nodes - scan.unread_nodes) +
                                       " of its " + count_text(scan.nodes) + " COPC nodes"));
    }
    hull = tiles::convex_hull(std::move(hull));
  }
  plan.hull = std::move(hull);
  const tiles::Rim r{plan.hull, plan.rim_width};
  // By input, so that the rim does not depend on which thread finished first.
  std::stable_sort(near.begin(), near.end(),
                   [](const auto& p, const auto& q) { return p.first < q.first; });
  for (const auto& [i, p] : near)
    if (r.holds({p.x, p.y})) rim.push_back(p);
  if (log)
    log(log_info, "rim: " + count_text(rim.size(), "point") + " within " +
                      number_text(plan.rim_width) + " of the data's hull (" +
                      count_text(plan.hull.size(), "vertex", "vertices") + "); read " +
                      count_text(scanned, "point file") + " for it, skipped " +
                      count_text(skipped) + " inside");
}

void set_extent(TilePlan& plan, const LogFn& log) {
  for (const PlanInput& in : plan.inputs) {
    if (tiles::empty(in.bounds)) {
      if (log) log(log_warn, in.path + ": holds no data; no tile reads it");
      continue;
    }
    plan.extent.add(in.bounds.min_x, in.bounds.min_y);
    plan.extent.add(in.bounds.max_x, in.bounds.max_y);
  }
}

// No triangle of the whole TIN leaves the data's hull or, without a rim, the inputs' boxes'.
std::vector<Point2> data_outline(const TilePlan& plan) {
  std::vector<Point2> corners = plan.hull;
  if (plan.hull.empty())
    for (const PlanInput& in : plan.inputs) {
      if (tiles::empty(in.bounds)) continue;
      const BBox b = inflated(in);
      corners.insert(
          corners.end(),
          {{b.min_x, b.min_y}, {b.max_x, b.min_y}, {b.max_x, b.max_y}, {b.min_x, b.max_y}});
    }
  return tiles::convex_hull(std::move(corners));
}

// Before any tile is made: a tile size far too small for the data is a usage error, not a
// plan of millions of tiles.
void check_tile_count(const tiles::TileGrid& grid, const BBox& all) {
  const double cols_f = std::floor(all.max_x / grid.size) - std::floor(all.min_x / grid.size) + 1;
  const double rows_f = std::floor(all.max_y / grid.size) - std::floor(all.min_y / grid.size) + 1;
  if (!(cols_f * rows_f <= static_cast<double>(kMaxTiles))) {
    const double count = std::round(cols_f * rows_f);
    throw UsageError(
        "--tile-size " + json_number(grid.size) + " makes about " +
        (count < 1e15 ? count_text(static_cast<std::uint64_t>(count)) : number_text(count)) +
        " tiles over the data (at most " + count_text(kMaxTiles) + "): choose a larger tile size");
  }
}

// The tiles of the grid over ALL that meet OUTLINE, north to south, each row west to east, each
// with the inputs its buffered box reads.
void lay_tiles(TilePlan& plan, const tiles::TileGrid& grid, const BBox& all,
               const std::vector<Point2>& outline) {
  const std::int64_t col0 = grid.cell_of(all.min_x), col1 = grid.cell_of(all.max_x);
  const std::int64_t row0 = grid.cell_of(all.min_y), row1 = grid.cell_of(all.max_y);
  for (std::int64_t row = row1; row >= row0; --row) {
    for (std::int64_t col = col0; col <= col1; ++col) {
      if (!tiles::meets_convex(grid.box(col, row), outline)) continue;
      PlanTile tile;
      tile.index = static_cast<std::uint32_t>(plan.tiles.size());
      tile.col = col;
      tile.row = row;
      const BBox reads = grid.buffered(col, row, plan.buffer);
      for (std::uint32_t i = 0; i < plan.inputs.size(); ++i) {
        const BBox b = inflated(plan.inputs[i]);
        if (!tiles::empty(b) && tiles::intersects(b, reads)) tile.inputs.push_back(i);
      }
      plan.tiles.push_back(std::move(tile));
    }
  }
}

}  // namespace

// The plan and its rim file are outputs like a job's: never an input, and refused before any
// work when they cannot be written.
void check_plan_files(const PlanOptions& options) {
  pipeline::FilePlan files;
  for (const std::string& p : options.inputs) files.inputs.push_back({p, "a point file"});
  for (const std::string& p : options.contours) files.inputs.push_back({p, "--contours source"});
  for (const std::string& p : options.breaklines)
    files.inputs.push_back({p, "--hard-lines source"});
  files.outputs.push_back({options.output, "the plan (-o)"});
  if (options.rim_width != 0) files.outputs.push_back({rim_path(options.output), "the plan's rim"});
  pipeline::check_files(files, options.overwrite);
}

TilePlan make_plan(const PlanOptions& options, std::vector<Point3>& rim, const LogFn& log) {
  check_plan_options(options);
  check_plan_files(options);
  std::vector<Point2> line_vertices;
  TilePlan plan = summarize_inputs(options, line_vertices);
  const DataBox data = data_box(plan.inputs);
  // The rim's default width: ten times the points' (or else the line vertices') mean spacing.
  const double area = (data.all.max_x - data.all.min_x) * (data.all.max_y - data.all.min_y);
  const double spacing =
      std::sqrt(area / static_cast<double>(std::max<std::uint64_t>(
                           data.points ? data.points : line_vertices.size(), 1)));
  plan.rim_width = options.rim_width >= 0 ? options.rim_width : 10 * spacing;
  if (plan.rim_width > 0) find_rim(options, plan, data.all, line_vertices, rim, log);
  set_extent(plan, log);
  const tiles::TileGrid grid{options.tile_size};
  check_tile_count(grid, data.all);
  lay_tiles(plan, grid, data.all, data_outline(plan));
  return plan;
}

std::string rim_path(const std::string& plan_path) {
  fs::path p(plan_path);
  if (p.extension() == ".json") p.replace_extension();
  return p.string() + ".rim.xyz";
}

void write_plan(TilePlan& plan, const std::vector<Point3>& rim, const std::string& path,
                bool overwrite) {
  io::OutputSet set(overwrite);
  if (plan.rim_width > 0) {
    // The rim as XYZ text with 17 significant digits: read back, every double is the same.
    std::string text = "x y z\n";
    char line[96];
    for (const Point3& p : rim) {
      const int n = std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
      text.append(line, static_cast<std::size_t>(n));
    }
    const std::string rim_file = rim_path(path);
    set.add(rim_file, "rim").write(text);
    plan.rim.path = stored_path(rim_file, rim_file, path);
    plan.rim.kind = "rim";
    plan.rim.format = "xyz";
    plan.rim.bytes = text.size();
    const std::string_view all(text);
    const std::size_t head = std::min(text.size(), kFingerprintBytes);
    const std::size_t tail = std::min(text.size() - head, kFingerprintBytes);
    plan.rim.fingerprint =
        fingerprint(text.size(), all.substr(0, head), all.substr(text.size() - tail));
    plan.rim.count = rim.size();
    for (const Point3& p : rim) plan.rim.bounds.add(p.x, p.y);
  }

  // One line per input and per tile, so that a script can pick a tile's line with grep.
  json::Writer j(json::Numbers::digits17, NonUtf8::keep);
  j.begin_object().field("tincdt_plan", kPlanVersion);
  j.field("tile_size", plan.tile_size).field("buffer", plan.buffer);
  const io::PointFilter& f = plan.filter;
  j.key("filter").begin_object(json::Layout::spaced);
  j.key("keep_classes").array(f.keep_classes).key("drop_classes").array(f.drop_classes);
  j.field("first_only", f.first_return_only).field("last_only", f.last_return_only).end_object();
  j.key("lines").begin_object(json::Layout::spaced).field("layer", plan.lines.layer);
  j.field("z_field", plan.lines.z_field).field("z_from_m", plan.lines.z_from_m).end_object();
  put_box(j.key("extent"), plan.extent);
  j.key("inputs").begin_array();
  for (std::size_t i = 0; i < plan.inputs.size(); ++i) {
    put_input(j.begin_object(json::Layout::spaced).field("index", i), plan.inputs[i]);
    j.end_object();
  }
  j.end_array().key("hull").begin_array(json::Layout::spaced);
  for (const Point2& p : plan.hull) j.array(std::array{p.x, p.y});
  j.end_array().key("rim");
  if (plan.rim_width > 0) {
    put_input(j.begin_object(json::Layout::spaced).field("width", plan.rim_width), plan.rim);
    j.end_object();
  } else {
    j.null();
  }
  j.field("tile_count", plan.tiles.size()).key("tiles").begin_array();
  const tiles::TileGrid grid{plan.tile_size};
  for (const PlanTile& tile : plan.tiles) {
    j.begin_object(json::Layout::spaced).field("index", tile.index);
    put_box(j.field("col", tile.col).field("row", tile.row).key("box"),
            grid.box(tile.col, tile.row));
    j.key("inputs").array(tile.inputs).end_object();
  }
  j.end_array().end_object();
  set.add(path, "plan").write(j.str() + "\n");
  set.commit();
}

namespace {

using Kind = JsonValue::Kind;

JsonValue parse_plan_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", fs::exists(path) ? "cannot open the plan" : "no such file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return json::parse(text, path);
}

void check_plan_version(const JsonValue& doc, const PlanReader& r, const std::string& path) {
  if (!doc.is(Kind::object) || !doc.find("tincdt_plan"))
    r.fail("", "no \"tincdt_plan\" member (make one with 'tincdt plan')");
  const std::uint64_t version = r.count(doc, "tincdt_plan", "");
  if (version != kPlanVersion)
    throw InputError(path, "",
                     "plan version " + std::to_string(version) + " (this tincdt reads version " +
                         std::to_string(kPlanVersion) + "): make the plan again");
}

// The settings every tile job shares: the grid, the point filter, how lines are read, the extent.
void read_settings(const JsonValue& doc, const PlanReader& r, TilePlan& plan) {
  plan.tile_size = r.number(doc, "tile_size", "");
  plan.buffer = r.number(doc, "buffer", "");
  if (!(plan.tile_size > 0)) r.fail("", "'tile_size' must be > 0");
  if (!(plan.buffer >= 0)) r.fail("", "'buffer' must be >= 0");
  const JsonValue& filter = r.member(doc, "filter", Kind::object, "");
  for (const auto& [key, classes] : {std::pair{"keep_classes", &plan.filter.keep_classes},
                                     std::pair{"drop_classes", &plan.filter.drop_classes}})
    for (const JsonValue& c : r.member(filter, key, Kind::array, "filter").items()) {
      if (!c.is(Kind::number) || !(c.number() >= 0 && c.number() <= 255) ||
          c.number() != std::floor(c.number()))
        r.fail("filter", std::string("'") + key + "' must hold class numbers 0 to 255");
      classes->push_back(static_cast<std::uint8_t>(c.number()));
    }
  plan.filter.first_return_only = r.member(filter, "first_only", Kind::boolean, "filter").boolean();
  plan.filter.last_return_only = r.member(filter, "last_only", Kind::boolean, "filter").boolean();
  const JsonValue& lines = r.member(doc, "lines", Kind::object, "");
  plan.lines.layer = r.member(lines, "layer", Kind::string, "lines").string();
  plan.lines.z_field = r.member(lines, "z_field", Kind::string, "lines").string();
  plan.lines.z_from_m = r.member(lines, "z_from_m", Kind::boolean, "lines").boolean();
  plan.extent = r.box(doc, "extent", "");
}

PlanInput read_input(const JsonValue& v, const PlanReader& r, const std::string& where) {
  if (!v.is(Kind::object)) r.fail(where, "not an object");
  PlanInput input;
  input.path = r.member(v, "path", Kind::string, where).string();
  input.kind = r.member(v, "kind", Kind::string, where).string();
  input.format = r.member(v, "format", Kind::string, where).string();
  input.bytes = r.count(v, "bytes", where);
  input.fingerprint = r.member(v, "fingerprint", Kind::string, where).string();
  input.count = r.count(v, "count", where);
  input.bounds = r.box(v, "bounds", where);
  input.tolerance = r.number(v, "tolerance", where);
  if (!(input.tolerance >= 0)) r.fail(where, "'tolerance' must be >= 0");
  return input;
}

void read_inputs(const JsonValue& doc, const PlanReader& r, TilePlan& plan) {
  for (const JsonValue& v : r.member(doc, "inputs", Kind::array, "").items()) {
    PlanInput input = read_input(v, r, "input " + std::to_string(plan.inputs.size()));
    if (input.kind != "points" && input.kind != "contours" && input.kind != "breaklines")
      r.fail("input " + std::to_string(plan.inputs.size()),
             "kind " + quoted_text(input.kind) + " (points, contours or breaklines)");
    plan.inputs.push_back(std::move(input));
  }
}

// The hull must be convex as stored and a rim needs one: tile jobs clip to it.
void read_hull_and_rim(const JsonValue& doc, const PlanReader& r, TilePlan& plan) {
  for (const JsonValue& v : r.member(doc, "hull", Kind::array, "").items()) {
    if (!v.is(Kind::array) || v.items().size() != 2 || !v.items()[0].is(Kind::number) ||
        !v.items()[1].is(Kind::number))
      r.fail("hull", "its points must be [x, y]");
    plan.hull.push_back({v.items()[0].number(), v.items()[1].number()});
  }
  if (!plan.hull.empty() && tiles::convex_hull(plan.hull).size() != plan.hull.size())
    r.fail("hull", "not a convex polygon");
  const JsonValue* rim = doc.find("rim");
  if (rim && rim->is(Kind::object)) {
    plan.rim = read_input(*rim, r, "rim");
    plan.rim_width = r.number(*rim, "width", "rim");
    if (!(plan.rim_width > 0) || plan.hull.size() < 3)
      r.fail("rim", "a rim needs a width > 0 and a hull");
  }
}

// Each tile's box must be what its col, row say, and its inputs indices into the plan's inputs.
void read_tiles(const JsonValue& doc, const PlanReader& r, TilePlan& plan) {
  const tiles::TileGrid grid{plan.tile_size};
  for (const JsonValue& v : r.member(doc, "tiles", Kind::array, "").items()) {
    const std::string where = "tile " + std::to_string(plan.tiles.size());
    if (!v.is(Kind::object)) r.fail(where, "not an object");
    PlanTile tile;
    if (r.count(v, "index", where) != plan.tiles.size())
      r.fail(where, "tiles must be listed in index order 0, 1, 2, ...");
    tile.index = static_cast<std::uint32_t>(plan.tiles.size());
    tile.col = r.integer(v, "col", where);
    tile.row = r.integer(v, "row", where);
    const BBox box = r.box(v, "box", where);
    const BBox expected = grid.box(tile.col, tile.row);
    if (box.min_x != expected.min_x || box.min_y != expected.min_y || box.max_x != expected.max_x ||
        box.max_y != expected.max_y)
      r.fail(where, "its box is not its col, row times the tile size");
    for (const JsonValue& k : r.member(v, "inputs", Kind::array, where).items()) {
      if (!k.is(Kind::number) || !(k.number() >= 0) || k.number() != std::floor(k.number()) ||
          k.number() >= static_cast<double>(plan.inputs.size()))
        r.fail(where, "its inputs must be indices into 'inputs'");
      tile.inputs.push_back(static_cast<std::uint32_t>(k.number()));
    }
    plan.tiles.push_back(std::move(tile));
  }
  if (r.count(doc, "tile_count", "") != plan.tiles.size())
    r.fail("", "'tile_count' differs from the number of tiles listed");
}

}  // namespace

TilePlan read_plan(const std::string& path) {
  const JsonValue doc = parse_plan_file(path);
  const PlanReader r(path);
  check_plan_version(doc, r, path);
  TilePlan plan;
  read_settings(doc, r, plan);
  read_inputs(doc, r, plan);
  read_hull_and_rim(doc, r, plan);
  read_tiles(doc, r, plan);
  return plan;
}

std::string resolve_input(const PlanInput& in, const std::string& plan_path) {
  const std::string& stored = in.path;
  if (fs::path(stored).is_absolute()) return stored;
  const fs::path folder = fs::path(plan_path).parent_path();
  return folder.empty() ? stored : (folder / stored).lexically_normal().string();
}

}  // namespace tincdt::tiles
