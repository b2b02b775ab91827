// The stages of a build, in the order they run. Each is defined in its own file
// (stage_<name>.cpp; replace, clip and erase share stage_polygons.cpp); a stage whose options
// are not set is skipped.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "pipeline/stage.hpp"

namespace tincdt::pipeline {

extern const Stage read_stage;         // points, lines and surface features; their CRS
extern const Stage terrain_crs_stage;  // --terrain: a CRS, or stop before any work
extern const Stage delaunay_stage;     // every point and line vertex: the Delaunay TIN
extern const Stage constraints_stage;  // contours and hard lines become TIN edges
extern const Stage surface_stage;      // soft lines, clip / erase / replace rings draped, inserted
extern const Stage simplify_stage;     // --max-error, --max-vertices: greedy insertion
extern const Stage flats_stage;        // --fix-flats (and the flat count for --stats)
extern const Stage replace_stage;      // --replace: vertices inside get the polygon's z
extern const Stage trim_stage;         // --max-edge: long boundary triangles removed
extern const Stage clip_stage;         // --clip: triangles outside removed
extern const Stage erase_stage;        // --erase: triangles inside removed
extern const Stage validate_stage;     // --validate
extern const Stage quality_stage;      // the quality block of --stats
extern const Stage write_stage;        // the TIN (-o) and its .prj
extern const Stage dem_stage;          // --dem: the final TIN rasterized
extern const Stage terrain_stage;      // --terrain: the quantized-mesh pyramid
extern const Stage contour_lines_stage;     // --contour-lines: traced on the final TIN
extern const Stage preview_stage;           // --preview: a hillshade PNG of the final TIN
extern const Stage constraint_lines_stage;  // --constraints-out
extern const Stage diagnostics_stage;       // --diagnostics
extern const Stage stats_stage;             // --stats, last: it reports on all the others

namespace {

const Stage* const kStages[] = {
    &read_stage,
    &terrain_crs_stage,
    &delaunay_stage,
    &constraints_stage,
    &surface_stage,
    &simplify_stage,
    &flats_stage,
    &replace_stage,
    &trim_stage,
    &clip_stage,
    &erase_stage,
    &validate_stage,
    &quality_stage,
    &write_stage,
    &dem_stage,
    &terrain_stage,
    &contour_lines_stage,
    &preview_stage,
    &constraint_lines_stage,
    &diagnostics_stage,
    &stats_stage,
};

}  // namespace

namespace stage_items {

std::uint64_t point_file_bytes(const Job& job) {
  std::uint64_t total = 0;
  for (const std::string& path : job.options.inputs) {
    std::error_code ec;
    const std::uintmax_t size = path == "-" ? 0 : std::filesystem::file_size(path, ec);
    total += ec ? 0 : static_cast<std::uint64_t>(size);
  }
  return total;
}
std::uint64_t points(const Job& job) {
  return job.points.size();
}
std::uint64_t segments(const Job& job) {
  return job.report.constraint_segments;
}
std::uint64_t triangles(const Job& job) {
  return job.mesh.tin.triangle_count();
}

}  // namespace stage_items

std::span<const Stage* const> stages() {
  return kStages;
}

void run_stages(Job& job, std::span<const Stage* const> list) {
  std::vector<const Stage*> wanted;
  for (const Stage* stage : list)
    if (stage->wanted(job.options)) wanted.push_back(stage);
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    const Stage* stage = wanted[i];
    const StageProgress& shown = stage->progress;
    job.start_stage({.name = stage->name,
                     .title = shown.title.empty() ? stage->name : shown.title,
                     .number = static_cast<int>(i + 1),
                     .count = static_cast<int>(wanted.size()),
                     .unit = shown.unit,
                     .items = shown.items ? shown.items(job) : 0},
                    shown.phases);
    job.progress(0.0);
    const auto t0 = std::chrono::steady_clock::now();
    stage->run(job);
    const double seconds = seconds_since(t0);
    if (!stage->timing.empty()) job.report.timings_s.add(stage->timing, seconds);
    job.report.stages.push_back({std::string(stage->name), seconds});
    job.progress(1.0);
  }
}

FilePlan plan_files(const BuildOptions& options, std::span<const Stage* const> list) {
  FilePlan files;
  for (const Stage* stage : list)
    if (stage->plan && stage->wanted(options)) stage->plan(options, files);
  return files;
}

}  // namespace tincdt::pipeline
