#include "pipeline/build.hpp"

#include <cmath>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "pipeline/file_checks.hpp"
#include "pipeline/job.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

// Checks that need no data: they fail now rather than after a long read.
void preflight(Job& job) {
  const BuildOptions& options = job.options;
  if (options.inputs.empty() && options.contours.empty() && options.breaklines.empty())
    throw InputError("no input given: point files, contours or breaklines");
  if (options.fix_flats && options.contours.empty())
    throw InputError(
        "--fix-flats needs contours (--contours): flat triangles are those of one contour level");
  if (!(options.max_edge >= 0) || std::isnan(options.max_edge))
    throw InputError("--max-edge must be a length > 0");
  if (!job.write.format) job.write.format = io::format_from_path(options.output);
  job.report.output_format = std::string(format_name(*job.write.format));
  if (!options.write.target_crs_wkt.empty() && *job.write.format != io::TinFormat::geojson)
    throw OutputError(options.output, "",
                      "reprojection (--t-srs) is only supported for GeoJSON output");
  detail::check_files(options, plan_files(options, stages()));
}

}  // namespace

std::string_view format_name(io::TinFormat format) {
  switch (format) {
    case io::TinFormat::obj:
      return "obj";
    case io::TinFormat::ply:
      return "ply";
    case io::TinFormat::geojson:
      return "geojson";
  }
  return "?";
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

BuildReport build(const BuildOptions& options, const ProgressFn* progress, const LogFn& log) {
  Job job(options, progress, log);
  preflight(job);
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

}  // namespace tincdt::pipeline
