#include "pipeline/build.hpp"

#include <fstream>
#include <string>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "pipeline/file_checks.hpp"
#include "pipeline/job.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/tile_job.hpp"

namespace tincdt::pipeline {

bool remove_temporaries_for_exit() noexcept {
  return io::remove_temporaries_for_exit();
}

std::uint64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) != 0) continue;
    std::uint64_t kib = 0;
    for (char c : line)
      if (c >= '0' && c <= '9') kib = kib * 10 + static_cast<std::uint64_t>(c - '0');
    return kib * 1024;
  }
  return 0;
}

namespace {

BuildReport run_job(const BuildOptions& options, const CheckedOptions& checked,
                    const TileSetup* tile, const ProgressFn* progress, const LogFn& log) {
  Job job(options, checked, progress, log);
  job.tile = tile;
  for (const std::string& warning : checked.warnings) job.warn(warning);
  detail::check_files(options, plan_files(options, stages()));
  run_stages(job, stages());
  job.enter_stage("commit");
  job.outputs.commit([&job] {
    job.progress(0.0);
    return true;
  });
  job.report.timings_s.total = seconds_since(job.started);
  job.report.peak_rss_bytes = peak_rss_bytes();
  return std::move(job.report);
}

}  // namespace

BuildReport build(const BuildOptions& options, const ProgressFn* progress, const LogFn& log) {
  const CheckedOptions checked = check_options(options);
  if (options.plan.empty()) return run_job(options, checked, nullptr, progress, log);
  TileSetup tile;
  const BuildOptions tile_job = tile_options(options, tile);
  return run_job(tile_job, checked, &tile, progress, log);
}

}  // namespace tincdt::pipeline
