// trim: --max-edge removes boundary triangles with a longer edge, inward from the convex hull,
// so that a concave outline is not bridged; before clip and erase open new boundaries. A
// simplified TIN was trimmed before the simplification (stage_simplify.cpp): the triangles in
// the trimmed areas go here.
#include <string>

#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "terrain/trim.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return o.max_edge > 0;
}

void run(Job& job) {
  if (job.report.simplify.ran) {  // the full TIN was trimmed before it was simplified
    const std::uint64_t removed = terrain::remove_marked_regions(job.tin(), job.trimmed_areas);
    job.debug("trim: " + count_text(job.report.trimmed_triangles) +
              " triangles of the full TIN with an edge longer than --max-edge trimmed before "
              "the simplification; " +
              count_text(removed) + " simplified triangles in their place removed");
    job.report.trimmed_triangles = removed;
  } else {
    job.report.trimmed_triangles = terrain::trim_long_edges(job.tin(), job.options.max_edge);
    job.debug("trim: " + count_text(job.report.trimmed_triangles) +
              " triangles with an edge longer than --max-edge removed");
  }
  check_triangles_left(job);
}

constexpr OptionSpec kOptions[] = {
    checked_option("--max-edge", "LENGTH", option_groups::boundary, check_positive,
                   set_number<&BuildOptions::max_edge>,
                   "Trim boundary triangles with a longer edge, inward from the hull,\n"
                   "so concave outlines are not bridged"),
};

}  // namespace

constexpr StageProgress kTrimProgress{"trimming long edges", "triangles", stage_items::triangles};
extern const Stage trim_stage{
    "trim",   "terrain",    wanted, run, nullptr, "--max-edge: trims inward from the convex hull",
    kOptions, kTrimProgress};

}  // namespace tincdt::pipeline
