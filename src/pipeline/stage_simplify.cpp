// simplify: --max-error / --max-vertices: the full constrained TIN becomes the smallest one the
// greedy insertion finds within the tolerance of every one of its vertices, keeping every
// constrained edge (simplify/simplify.hpp). The later stages (flats, replace, trim, clip, erase)
// work on the simplified TIN; the vertex ids the earlier stages left in the Job are remapped.
// With --max-edge the full TIN is trimmed first (terrain::trim_and_fence()).
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "simplify/simplify.hpp"
#include "terrain/trim.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return o.max_error || o.max_vertices > 0;
}

void run(Job& job) {
  // --max-edge trims the gaps between the points, before the simplification makes every edge
  // longer; the outline it leaves is kept, and the trim stage removes what lies beyond it.
  std::vector<std::uint8_t> trimmed;
  if (job.options.max_edge > 0) {
    trimmed = terrain::trim_and_fence(job.tin(), job.options.max_edge);
    job.report.trimmed_triangles =
        static_cast<std::uint64_t>(std::count(trimmed.begin(), trimmed.end(), 1));
  }
  const mesh::Triangulation& full = job.tin();
  simplify::SimplifyOptions options;
  options.max_error = job.options.max_error.value_or(0);
  options.max_vertices = job.options.max_vertices;
  options.threads = job.options.threads;
  simplify::SimplifyResult r = simplify::simplify_tin(full, options, job.stage_progress());

  // Every vertex the earlier stages name is on a constrained edge, hence kept.
  std::vector<VertexId> vertex_of(full.vertex_count(), kNoId);
  for (VertexId v = 0; v < r.tin.vertex_count(); ++v) vertex_of[r.point_of_vertex[v]] = v;
  for (constraints::Piece& p : job.pieces) p = {vertex_of[p.a], vertex_of[p.b], p.source};
  for (constraints::Segment& s : job.given_segments) s = {vertex_of[s.a], vertex_of[s.b], s.source};
  for (constraints::Crossing& x : job.crossings) x.vertex = vertex_of[x.vertex];
  // Merged duplicates may lose their vertex: the diagnostics keep where they were.
  job.duplicate_at.clear();
  for (delaunay::DelaunayResult::Duplicate& d : job.mesh.duplicates) {
    const Point2 at = full.point(d.vertex);
    job.duplicate_at.push_back({at.x, at.y, full.z(d.vertex)});
    d.vertex = vertex_of[d.vertex];
  }
  release(job.mesh.vertex_of_point);
  if (job.options.max_edge > 0)
    job.trimmed_areas = terrain::mark_trimmed_areas(full, trimmed, r.tin);
  job.mesh.tin = std::move(r.tin);

  BuildReport::Simplify& s = job.report.simplify;
  s.ran = true;
  s.points = r.report.points;
  s.vertices = r.report.vertices;
  s.max_error = r.report.max_error;
  s.rmse = r.report.rmse;
  s.stopped_at_max_vertices = r.report.stopped_at_max_vertices;
  if (options.max_vertices > 0 && r.report.kept_vertices > options.max_vertices)
    job.warn("--max-vertices " + count_text(options.max_vertices) + ": the lines, rings and " +
             "hull corners alone need " + count_text(r.report.kept_vertices) +
             " vertices; the TIN keeps them all");
  job.debug("simplify: " + count_text(r.report.kept_vertices) +
            " vertices kept for the features and the hull, " + count_text(r.report.inserted) +
            " points inserted" +
            (r.report.stopped_at_max_vertices ? " (stopped at --max-vertices)" : ""));
}

// ---- options -----------------------------------------------------------------------------------

constexpr std::size_t kFewestVertices = 3;  // a TIN

std::string check_vertices(std::string_view v) {
  const auto n = parse_count(v);
  return n && *n >= kFewestVertices ? std::string() : in_quotes(v) + " is not a count >= 3";
}

void set_vertices(BuildOptions& o, std::string_view v) {
  o.max_vertices = static_cast<std::size_t>(*parse_count(v));
}

constexpr OptionSpec kOptions[] = {
    checked_option("--max-error", "Z", option_groups::simplification, check_non_negative,
                   set_number<&BuildOptions::max_error>,
                   "Keep only the points needed for every point to lie within Z\n"
                   "(vertically) of the TIN; contours and breaklines stay whole"),
    checked_option("--max-vertices", "N", option_groups::simplification, check_vertices,
                   set_vertices, "Stop simplifying at N vertices (alone: with --max-error 0)"),
};

}  // namespace

constexpr StageProgress kSimplifyProgress{"simplifying"};
extern const Stage simplify_stage{"simplify",
                                  "simplify",
                                  wanted,
                                  run,
                                  nullptr,
                                  "--max-error, --max-vertices: only the points needed to stay "
                                  "within\nthe tolerance are kept (every line vertex and segment "
                                  "stays)",
                                  kOptions,
                                  kSimplifyProgress};

}  // namespace tincdt::pipeline
