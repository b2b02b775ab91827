// BuildReport as the --stats JSON document.
#include <array>
#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "core/json.hpp"
#include "pipeline/build.hpp"
#include "pipeline/report.hpp"

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace tincdt::pipeline {
namespace {

// One member of an object of the report: its name and its value.
struct Member {
  std::string_view key;
  std::variant<std::uint64_t, double, bool, std::string_view> value;
};

Member member(std::string_view key, std::variant<std::uint64_t, double, bool, std::string_view> v) {
  return {key, v};
}

void put(json::Writer& j, std::same_as<Member> auto... members) {
  for (const Member& m : {members...}) {
    j.key(m.key);
    std::visit([&](auto v) { j.value(v); }, m.value);
  }
}

// The object KEY of MEMBERS, or null when it is not PRESENT (a stage that did not run).
void put_object(json::Writer& j, std::string_view key, bool present,
                std::same_as<Member> auto... members) {
  j.key(key);
  if (!present) {
    j.null();
    return;
  }
  j.begin_object();
  put(j, members...);
  j.end_object();
}

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

void put_flats(json::Writer& j, const BuildReport::Flats& f) {
  put_object(j, "flats", true, member("counted", f.counted), member("fixed", f.fixed),
             member("before", f.before), member("after_swaps", f.after_swaps),
             member("after", f.after), member("swaps", f.swaps),
             member("vertices_added", f.vertices_added),
             member("vertices_interpolated", f.vertices_interpolated),
             member("vertices_extrapolated", f.vertices_extrapolated),
             member("left_no_level", f.left_no_level), member("left_unplaced", f.left_unplaced),
             member("non_delaunay_edges", f.non_delaunay_edges));
}

// timings_s (the keys every report has, then the later stages' own, then the total), then
// every stage's own entry.
void put_timings(json::Writer& j, const BuildReport& r) {
  const BuildReport::Timings& t = r.timings_s;
  j.key("timings_s").begin_object();
  put(j, member("read", t.read), member("delaunay", t.delaunay),
      member("constraints", t.constraints), member("surface", t.surface),
      member("terrain", t.terrain), member("validate", t.validate), member("quality", t.quality),
      member("write", t.write));
  for (const auto& [key, seconds] : t.more) j.field(key, seconds);
  j.field("total", t.total).end_object();
  j.key("stages").begin_array();
  for (const BuildReport::StageTime& s : r.stages) {
    j.begin_object();
    put(j, member("name", s.name), member("seconds", s.seconds));
    j.end_object();
  }
  j.end_array();
}

// Per input: the point files' own keys, the vector sources' own keys, and the common ones
// (read, kept, filtered, skipped) for both; merged duplicates are counted for all inputs
// together (duplicates_merged), not per file.
void put_inputs(json::Writer& j, const std::vector<BuildReport::Input>& inputs) {
  j.key("inputs").begin_array();
  for (const BuildReport::Input& in : inputs) {
    j.begin_object();
    put(j, member("path", in.path), member("kind", in.kind), member("crs", in.crs));
    if (in.kind == "points")
      put(j, member("format", in.format), member("points_read", in.points_read),
          member("points_kept", in.points_kept), member("bytes_read", in.bytes_read),
          member("read", in.points_read), member("kept", in.points_kept),
          member("filtered", in.points_read - in.points_kept), member("skipped", std::uint64_t{0}));
    else
      put(j, member("layer", in.format), member("features_read", in.features_read),
          member("features_used", in.features_used),
          member("features_dropped", in.features_dropped), member("vertices", in.vertices),
          member("segments", in.segments), member("skipped_segments", in.skipped_segments),
          member("read", in.features_read), member("kept", in.features_used),
          member("filtered", std::uint64_t{0}), member("skipped", in.features_dropped));
    j.end_object();
  }
  j.end_array();
}

void put_outputs(json::Writer& j, const BuildReport& r) {
  put(j, member("output", r.output), member("output_format", r.output_format),
      member("output_bytes", r.output_bytes),
      member("constraints_out", r.output_of("constraint_lines")),
      member("diagnostics", r.output_of("diagnostics")));
  j.key("outputs").begin_array();
  for (const BuildReport::Output& o : r.outputs) {
    j.begin_object();
    put(j, member("path", o.path), member("kind", o.kind), member("bytes", o.bytes),
        member("crs", o.crs));
    j.end_object();
  }
  j.end_array();
}

// The products asked for: what each holds and its time; null when not asked for.
void put_products(json::Writer& j, const BuildReport& r) {
  const BuildReport::Dem& d = r.dem;
  put_object(j, "dem", !d.path.empty(), member("path", d.path), member("type", d.type),
             member("width", std::uint64_t{d.width}), member("height", std::uint64_t{d.height}),
             member("resolution", d.resolution), member("min_x", d.min_x), member("max_y", d.max_y),
             member("cells_with_value", d.cells_with_value), member("rasterize_s", d.rasterize_s),
             member("write_s", d.write_s));
  const BuildReport::ContourLines& c = r.contour_lines;
  put_object(j, "contour_lines", !c.path.empty(), member("path", c.path),
             member("driver", c.driver), member("levels", c.levels), member("lines", c.lines),
             member("closed", c.closed), member("points", c.points), member("length", c.length),
             member("trace_s", c.trace_s), member("write_s", c.write_s));
}

}  // namespace

std::string BuildReport::to_json() const {
  json::Writer j;
  j.begin_object();
  put(j, member("tincdt_version", version()), member("points_read", points_read),
      member("points_kept", points_kept), member("duplicates_merged", duplicates_merged),
      member("vertices", vertices), member("triangles", triangles),
      member("constraints", constraints), member("steiner_vertices", steiner_vertices),
      member("line_features", line_features), member("line_vertices", line_vertices),
      member("constraint_segments", constraint_segments),
      member("zero_length_segments", zero_length_segments),
      member("constraint_segments_split", constraint_segments_split),
      member("crossings", crossings), member("surface_features", surface_features),
      member("soft_line_vertices", soft_line_vertices), member("draped_vertices", draped_vertices),
      member("reused_vertices", reused_vertices), member("replaced_vertices", replaced_vertices),
      member("trimmed_triangles", trimmed_triangles),
      member("clipped_triangles", clipped_triangles), member("erased_triangles", erased_triangles),
      member("max_z_disagreement", max_z_disagreement));
  put_object(j, "simplify", simplify.ran, member("points", simplify.points),
             member("vertices", simplify.vertices), member("max_error", simplify.max_error),
             member("rmse", simplify.rmse),
             member("stopped_at_max_vertices", simplify.stopped_at_max_vertices));
  put_flats(j, flats);
  j.key("quality");
  if (quality_measured)
    j.raw(quality.to_json());
  else
    j.null();
  put_object(j, "flips", true, member("insertion", flips.insertion),
             member("restoration", flips.restoration));
  put_timings(j, *this);
  put(j, member("peak_rss_bytes", peak_rss_bytes), member("crs", crs), member("crs_wkt", crs_wkt));
  put_outputs(j, *this);
  put_products(j, *this);
  if (!figures.empty()) {
    j.key("figures").begin_object();
    for (const auto& [name, value] : figures) j.field(name, value);
    j.end_object();
  }
  j.key("offset").array(std::array{offset.x, offset.y, offset.z});
  put_inputs(j, inputs);
  j.end_object();
  return j.str() + "\n";
}

}  // namespace tincdt::pipeline
