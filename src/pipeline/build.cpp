#include "pipeline/build.hpp"

#include <fstream>
#include <string>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "pipeline/file_checks.hpp"
#include "pipeline/job.hpp"
#include "pipeline/stage.hpp"

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

BuildReport run_job(Job& job, std::span<const Stage* const> list, const FilePlan& files) {
  check_files(files, job.options.write.overwrite);
  run_stages(job, list);
  // Said once, when the outputs are there: a failed job has only its error to say.
  if (job.crs_wkt.empty())
    job.warn("no input has a CRS, so the outputs have none (give the inputs' CRS with --a-srs)");
  job.enter_stage("commit");
  job.outputs.commit([&job] {
    job.progress(0.0);
    return true;
  });
  job.report.timings_s.total = seconds_since(job.started);
  job.report.peak_rss_bytes = peak_rss_bytes();
  return std::move(job.report);
}

BuildReport build(const BuildOptions& options, const ProgressFn* progress, const LogFn& log) {
  const CheckedOptions checked = check_options(options);
  Job job(options, checked, progress, log);
  for (const std::string& warning : checked.warnings) job.warn(warning);
  return run_job(job, stages(), plan_files(options, stages()));
}

}  // namespace tincdt::pipeline
