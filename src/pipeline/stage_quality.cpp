// quality: the quality block of --stats, measured on the final TIN.
#include "pipeline/stage.hpp"
#include "terrain/quality.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.stats_path.empty();
}

void run(Job& job) {
  job.report.quality = terrain::measure_quality(
      job.tin(), job.on_contour.empty() ? nullptr : &job.on_contour, job.options.threads);
  job.report.quality_measured = true;
}

}  // namespace

extern const Stage quality_stage{"quality", "quality", wanted, run};

}  // namespace tincdt::pipeline
