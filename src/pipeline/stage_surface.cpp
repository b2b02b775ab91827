// surface: soft lines and clip / erase / replace rings draped on the TIN of points and hard
// lines, inserted, and made constrained edges (pipeline/surface.hpp does the work).
#include <string>
#include <vector>

#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.soft_lines.empty() || !o.clip.empty() || !o.erase.empty() || !o.replace.empty();
}

void run(Job& job) {
  std::vector<const detail::SurfaceInput*> inputs;
  for (const detail::SurfaceInput* input : {&job.soft, &job.clip, &job.erase, &job.replace})
    if (!input->data.features.empty()) inputs.push_back(input);
  if (inputs.empty()) return;
  if (!job.tin().has_vertex_index()) job.tin().build_vertex_index(job.options.threads);
  detail::SurfaceResult sr = detail::insert_surface_features(
      job.tin(), inputs, job.sources, job.pieces, job.options.constraint.restore,
      job.stage_progress(), job.surface_scope);
  const constraints::ConstraintResult& c = sr.constraints;
  BuildReport& report = job.report;
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
  job.crossings.insert(job.crossings.end(), c.crossings.begin(), c.crossings.end());
  job.pieces = std::move(sr.constraints.pieces);
  if (job.options.validate)
    job.given_segments.insert(job.given_segments.end(), sr.given.begin(), sr.given.end());
  job.debug(count_text(report.surface_features, "surface feature") + ": " +
            count_text(sr.vertices, "vertex", "vertices") + " (" + count_text(sr.draped) +
            " draped, " + count_text(sr.reused) + " on existing vertices), " +
            count_text(sr.segments, "segment") + ", " + count_text(c.crossings.size(), "crossing") +
            " (" + count_text(sr.crossings_with_hard_z) + " at a hard line's z)");
  if (sr.rings_cut + sr.rings_outside > 0)
    job.debug(count_text(sr.rings_cut) + " clip / erase rings cut to the TIN's hull, " +
              count_text(sr.rings_outside) + " wholly outside it left out");
}

}  // namespace

constexpr StageProgress kSurfaceProgress{"draping soft lines and polygons"};
extern const Stage surface_stage{"surface",
                                 "surface",
                                 wanted,
                                 run,
                                 nullptr,
                                 "soft lines, clip / erase / replace rings: 2D vertices draped on "
                                 "that TIN,\nthen made TIN edges (a draped line crossing a hard "
                                 "one takes its z there)",
                                 {},
                                 kSurfaceProgress};

}  // namespace tincdt::pipeline
