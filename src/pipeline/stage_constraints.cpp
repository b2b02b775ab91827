// constraints: every contour and hard-line segment becomes a chain of constrained edges; where
// two of them cross they are joined at a new vertex (or the job stops, --on-crossing error).
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

// The line segments as TIN edges: segment ends index the points, whose vertices the Delaunay
// stage recorded (line vertex i is point point_count + i).
std::vector<constraints::Segment> segments_of(Job& job) {
  std::vector<constraints::Segment> segments;
  segments.reserve(job.lines.segments.size());
  const std::vector<VertexId>& vertex_of = job.mesh.vertex_of_point;
  for (const io::LineData::Segment& s : job.lines.segments)
    segments.push_back(
        {vertex_of[job.point_count + s.a], vertex_of[job.point_count + s.b], s.feature});
  release(job.mesh.vertex_of_point);
  return segments;
}

[[noreturn]] void crossing_refused(const Job& job, const constraints::CrossingError& e) {
  char at[64];
  std::snprintf(at, sizeof at, "(%.3f, %.3f)", e.at.x, e.at.y);
  const detail::SourceTable& sources = job.sources;
  const bool known = sources.known(e.source_a);
  throw InputError(known ? sources.file(e.source_a) : std::string(),
                   known ? "feature " + signed_count_text(sources.fid(e.source_a)) : std::string(),
                   std::string("crosses ") + sources.describe(e.source_b) + " at " + at +
                       " (use --on-crossing split to join them there)");
}

void log_crossings(const Job& job, const constraints::ConstraintResult& c) {
  if (c.crossings.empty()) return;
  const detail::SourceTable& sources = job.sources;
  const constraints::Crossing* worst = &c.crossings.front();
  for (const constraints::Crossing& x : c.crossings) {
    if (std::fabs(x.z_a - x.z_b) > std::fabs(worst->z_a - worst->z_b)) worst = &x;
    job.debug("crossing: " + sources.describe(x.source_a) + " and " + sources.describe(x.source_b) +
              " joined at a new vertex");
  }
  char dz[32];
  std::snprintf(dz, sizeof dz, "%.3f", c.max_z_disagreement);
  job.warn(count_text(c.crossings.size()) +
           " crossing line segments joined at new vertices; the largest z disagreement is " + dz +
           " between " + sources.describe(worst->source_a) + " and " +
           sources.describe(worst->source_b));
}

bool wanted(const BuildOptions& o) {
  return !o.contours.empty() || !o.breaklines.empty();
}

void run(Job& job) {
  if (job.lines.segments.empty()) return;
  std::vector<constraints::Segment> segments = segments_of(job);
  if (!job.tin().has_vertex_index()) job.tin().build_vertex_index(job.options.threads);
  constraints::ConstraintResult c;
  try {
    c = constraints::insert_constraints(job.tin(), segments, job.options.constraint,
                                        job.stage_progress());
  } catch (const constraints::CrossingError& e) {
    crossing_refused(job, e);
  }
  if (job.options.validate) job.given_segments = std::move(segments);
  BuildReport& report = job.report;
  report.zero_length_segments += c.segments_skipped;
  report.constraint_segments_split = c.split_at_vertices;
  report.crossings = c.crossings.size();
  report.steiner_vertices = c.crossings.size();
  report.max_z_disagreement = c.max_z_disagreement;
  report.flips.insertion = c.flips_insertion;
  report.flips.restoration = c.flips_restoration;
  if (c.segments_skipped > 0)
    job.debug(count_text(c.segments_skipped) +
              " line segments have both ends on one vertex (merged points): skipped");
  log_crossings(job, c);
  job.crossings = std::move(c.crossings);
  job.pieces = std::move(c.pieces);
}

// ---- options -----------------------------------------------------------------------------------

constexpr std::string_view kCrossingWords[] = {"split", "error"};
constexpr constraints::OnCrossing kCrossings[] = {constraints::OnCrossing::split,
                                                  constraints::OnCrossing::error};
constexpr std::string_view kRestoreWords[] = {"delaunay", "aspect", "none"};
constexpr constraints::Restore kRestores[] = {
    constraints::Restore::delaunay, constraints::Restore::aspect, constraints::Restore::none};

using Constraint = constraints::ConstraintOptions;

constexpr OptionSpec kOptions[] = {
    choice_option<kCrossingWords, kCrossings, &BuildOptions::constraint, &Constraint::on_crossing>(
        "--on-crossing", option_groups::triangulation, "split",
        "Crossing contours / hard lines: join them at a new vertex, or stop\n"
        "with an error (surface features always join)"),
    choice_option<kRestoreWords, kRestores, &BuildOptions::constraint, &Constraint::restore>(
        "--restore", option_groups::triangulation, "delaunay",
        "After each line is in: restore the constrained Delaunay property,\n"
        "improve aspect ratios (the paper's criterion), or leave the swaps"),
};

}  // namespace

constexpr StageProgress kConstraintsProgress{"inserting breaklines", "segments",
                                             stage_items::segments};
extern const Stage constraints_stage{"constraints", "constraints",       wanted, run, nullptr, "",
                                     kOptions,      kConstraintsProgress};

}  // namespace tincdt::pipeline
