// BuildReport as JSON: a small hand-written emitter (objects, arrays, strings, numbers).
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/json_text.hpp"
#include "pipeline/build.hpp"
#include "pipeline/report.hpp"

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace tincdt::pipeline {
namespace {

// A JSON string literal. Bytes that are not valid UTF-8 (possible in file names) become U+FFFD.
std::string quote(std::string_view s) {
  return json_string(s, NonUtf8::replace);
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  // Shortest text that reads back to the same double; plain decimals ("500000", "0.25") for
  // ordinary magnitudes, exponent form only for very large or very small values.
  char buf[64];
  const double a = std::fabs(v);
  const bool plain = a == 0 || (a >= 1e-4 && a < 1e15);
  const auto res = std::to_chars(buf, buf + sizeof buf, v,
                                 plain ? std::chars_format::fixed : std::chars_format::general);
  return std::string(buf, res.ptr);
}

std::string number(std::uint64_t v) {
  return std::to_string(v);
}

// Emits one JSON value at a time, with two-space indentation.
class JsonWriter {
 public:
  JsonWriter& begin_object(std::string_view key = {}) { return open(key, '{'); }
  JsonWriter& end_object() { return close('}'); }
  JsonWriter& begin_array(std::string_view key = {}) { return open(key, '['); }
  JsonWriter& end_array() { return close(']'); }
  JsonWriter& field(std::string_view key, std::string_view v) { return raw(key, quote(v)); }
  JsonWriter& field(std::string_view key, const std::string& v) { return raw(key, quote(v)); }
  JsonWriter& field(std::string_view key, const char* v) { return raw(key, quote(v)); }
  JsonWriter& field(std::string_view key, double v) { return raw(key, number(v)); }
  JsonWriter& field(std::string_view key, std::uint64_t v) { return raw(key, number(v)); }
  JsonWriter& field(std::string_view key, bool v) { return raw(key, v ? "true" : "false"); }
  JsonWriter& null_field(std::string_view key) { return raw(key, "null"); }
  // A value that is JSON already (one line).
  JsonWriter& json_field(std::string_view key, const std::string& json) { return raw(key, json); }
  JsonWriter& value(double v) { return raw({}, number(v)); }
  std::string str() const { return out_ + "\n"; }

 private:
  JsonWriter& raw(std::string_view key, const std::string& text) {
    separate(key);
    out_ += text;
    return *this;
  }
  JsonWriter& open(std::string_view key, char bracket) {
    separate(key);
    out_ += bracket;
    ++depth_;
    first_ = true;
    return *this;
  }
  JsonWriter& close(char bracket) {
    --depth_;
    if (!first_) newline();
    out_ += bracket;
    first_ = false;
    return *this;
  }
  void separate(std::string_view key) {
    if (depth_ > 0) {
      if (!first_) out_ += ',';
      newline();
    }
    first_ = false;
    if (!key.empty()) {
      out_ += quote(key);
      out_ += ": ";
    }
  }
  void newline() {
    out_ += '\n';
    out_.append(static_cast<std::size_t>(2 * depth_), ' ');
  }

  std::string out_;
  int depth_ = 0;
  bool first_ = true;
};

}  // namespace

std::string_view version() {
  return TINCDT_VERSION;
}

std::string BuildReport::output_of(std::string_view kind) const {
  for (const Output& o : outputs)
    if (o.kind == kind) return o.path;
  return {};
}

void BuildReport::Timings::add(std::string_view key, double seconds) {
  const std::pair<std::string_view, double*> fields[] = {
      {"read", &read},       {"delaunay", &delaunay}, {"constraints", &constraints},
      {"surface", &surface}, {"terrain", &terrain},   {"validate", &validate},
      {"quality", &quality}, {"write", &write},       {"total", &total}};
  for (const auto& [name, field] : fields) {
    if (name != key) continue;
    *field += seconds;
    return;
  }
  for (auto& [name, sum] : more) {
    if (name != key) continue;
    sum += seconds;
    return;
  }
  more.emplace_back(key, seconds);
}

namespace {

void put_flats(JsonWriter& j, const BuildReport::Flats& f) {
  j.begin_object("flats").field("counted", f.counted).field("fixed", f.fixed);
  const std::pair<const char*, std::uint64_t> counts[] = {
      {"before", f.before},
      {"after_swaps", f.after_swaps},
      {"after", f.after},
      {"swaps", f.swaps},
      {"vertices_added", f.vertices_added},
      {"vertices_interpolated", f.vertices_interpolated},
      {"vertices_extrapolated", f.vertices_extrapolated},
      {"left_no_level", f.left_no_level},
      {"left_unplaced", f.left_unplaced},
      {"non_delaunay_edges", f.non_delaunay_edges}};
  for (const auto& [key, n] : counts) j.field(key, n);
  j.end_object();
}

// timings_s (the keys every report has, then the later stages' own, then the total), then
// every stage's own entry.
void put_timings(JsonWriter& j, const BuildReport& r) {
  const BuildReport::Timings& t = r.timings_s;
  const std::pair<const char*, double> fixed[] = {
      {"read", t.read},       {"delaunay", t.delaunay}, {"constraints", t.constraints},
      {"surface", t.surface}, {"terrain", t.terrain},   {"validate", t.validate},
      {"quality", t.quality}, {"write", t.write}};
  j.begin_object("timings_s");
  for (const auto& [key, seconds] : fixed) j.field(key, seconds);
  for (const auto& [key, seconds] : t.more) j.field(key, seconds);
  j.field("total", t.total).end_object();
  j.begin_array("stages");
  for (const BuildReport::StageTime& s : r.stages)
    j.begin_object().field("name", s.name).field("seconds", s.seconds).end_object();
  j.end_array();
}

// Per input: the point files' own keys, the vector sources' own keys, and the common ones
// (read, kept, filtered, skipped) for both; merged duplicates are counted for all inputs
// together (duplicates_merged), not per file.
void put_inputs(JsonWriter& j, const std::vector<BuildReport::Input>& inputs) {
  j.begin_array("inputs");
  for (const BuildReport::Input& in : inputs) {
    j.begin_object().field("path", in.path).field("kind", in.kind).field("crs", in.crs);
    if (in.kind == "points") {
      j.field("format", in.format)
          .field("points_read", in.points_read)
          .field("points_kept", in.points_kept)
          .field("read", in.points_read)
          .field("kept", in.points_kept)
          .field("filtered", in.points_read - in.points_kept)
          .field("skipped", std::uint64_t{0});
    } else {
      j.field("layer", in.format)
          .field("features_read", in.features_read)
          .field("features_used", in.features_used)
          .field("features_dropped", in.features_dropped)
          .field("vertices", in.vertices)
          .field("segments", in.segments)
          .field("skipped_segments", in.skipped_segments)
          .field("read", in.features_read)
          .field("kept", in.features_used)
          .field("filtered", std::uint64_t{0})
          .field("skipped", in.features_dropped);
    }
    j.end_object();
  }
  j.end_array();
}

void put_outputs(JsonWriter& j, const BuildReport& r) {
  j.field("output", r.output);
  j.field("output_format", r.output_format);
  j.field("output_bytes", r.output_bytes);
  j.field("constraints_out", r.output_of("constraint_lines"));
  j.field("diagnostics", r.output_of("diagnostics"));
  j.begin_array("outputs");
  for (const BuildReport::Output& o : r.outputs)
    j.begin_object()
        .field("path", o.path)
        .field("kind", o.kind)
        .field("bytes", o.bytes)
        .end_object();
  j.end_array();
}

// The products asked for: what each holds and its time; null when not asked for.
void put_products(JsonWriter& j, const BuildReport& r) {
  if (r.dem.path.empty()) {
    j.null_field("dem");
  } else {
    const BuildReport::Dem& d = r.dem;
    j.begin_object("dem")
        .field("path", d.path)
        .field("type", d.type)
        .field("width", std::uint64_t{d.width})
        .field("height", std::uint64_t{d.height})
        .field("resolution", d.resolution)
        .field("min_x", d.min_x)
        .field("max_y", d.max_y)
        .field("cells_with_value", d.cells_with_value)
        .field("rasterize_s", d.rasterize_s)
        .field("write_s", d.write_s)
        .end_object();
  }
  if (r.contour_lines.path.empty()) {
    j.null_field("contour_lines");
  } else {
    const BuildReport::ContourLines& c = r.contour_lines;
    j.begin_object("contour_lines")
        .field("path", c.path)
        .field("driver", c.driver)
        .field("levels", c.levels)
        .field("lines", c.lines)
        .field("closed", c.closed)
        .field("points", c.points)
        .field("length", c.length)
        .field("trace_s", c.trace_s)
        .field("write_s", c.write_s)
        .end_object();
  }
}

}  // namespace

std::string BuildReport::to_json() const {
  JsonWriter j;
  j.begin_object();
  j.field("tincdt_version", version());
  const std::pair<const char*, std::uint64_t> counts[] = {
      {"points_read", points_read},
      {"points_kept", points_kept},
      {"duplicates_merged", duplicates_merged},
      {"vertices", vertices},
      {"triangles", triangles},
      {"constraints", constraints},
      {"steiner_vertices", steiner_vertices},
      {"line_features", line_features},
      {"line_vertices", line_vertices},
      {"constraint_segments", constraint_segments},
      {"zero_length_segments", zero_length_segments},
      {"constraint_segments_split", constraint_segments_split},
      {"crossings", crossings},
      {"surface_features", surface_features},
      {"soft_line_vertices", soft_line_vertices},
      {"draped_vertices", draped_vertices},
      {"reused_vertices", reused_vertices},
      {"replaced_vertices", replaced_vertices},
      {"trimmed_triangles", trimmed_triangles},
      {"clipped_triangles", clipped_triangles},
      {"erased_triangles", erased_triangles}};
  for (const auto& [key, n] : counts) j.field(key, n);
  j.field("max_z_disagreement", max_z_disagreement);
  if (simplify.ran)
    j.begin_object("simplify")
        .field("points", simplify.points)
        .field("vertices", simplify.vertices)
        .field("max_error", simplify.max_error)
        .field("rmse", simplify.rmse)
        .field("stopped_at_max_vertices", simplify.stopped_at_max_vertices)
        .end_object();
  else
    j.null_field("simplify");
  put_flats(j, flats);
  if (quality_measured)
    j.json_field("quality", quality.to_json());
  else
    j.null_field("quality");
  j.begin_object("flips")
      .field("insertion", flips.insertion)
      .field("restoration", flips.restoration);
  j.end_object();
  put_timings(j, *this);
  j.field("peak_rss_bytes", peak_rss_bytes);
  j.field("crs", crs);
  j.field("crs_wkt", crs_wkt);
  put_outputs(j, *this);
  put_products(j, *this);
  j.begin_array("offset").value(offset.x).value(offset.y).value(offset.z).end_array();
  put_inputs(j, inputs);
  j.end_object();
  return j.str();
}

}  // namespace tincdt::pipeline
