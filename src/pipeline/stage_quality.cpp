// quality: the quality block of --stats, measured on the final TIN beside the output stages
// (Job::quality_pass); the stats stage files it.
#include "core/parallel.hpp"
#include "pipeline/stage.hpp"
#include "terrain/quality.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.stats_path.empty();
}

void run(Job& job) {
  // Beside the output stages on one core fewer than the job's, so that the writers, which use
  // every thread of the job, keep most of the cores; with one core in all, here, in turn.
  const std::size_t cores = thread_count(job.options.threads);
  const auto threads = static_cast<unsigned>(std::max<std::size_t>(1, cores - 1));
  job.quality_pass = std::make_unique<BackgroundJob>(cores > 1, [&job, threads] {
    const auto t0 = std::chrono::steady_clock::now();
    job.quality_measured.quality = terrain::measure_quality(
        job.tin(), job.on_contour.empty() ? nullptr : &job.on_contour, threads);
    job.quality_measured.seconds = seconds_since(t0);
  });
}

}  // namespace

// No timing key: the pass times itself, as it runs while the next stages do.
constexpr StageProgress kQualityProgress{"measuring quality"};
extern const Stage quality_stage{"quality", "", wanted, run, nullptr, "", {}, kQualityProgress};

}  // namespace tincdt::pipeline
