#include "pipeline/job.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs.hpp"

namespace tincdt::pipeline {

const std::string& CrsNames::label(const std::string& wkt) {
  auto it = labels_.find(wkt);
  if (it == labels_.end()) it = labels_.emplace(wkt, wkt.empty() ? "" : io::crs_label(wkt)).first;
  return it->second;
}

std::string CrsNames::name(const std::string& wkt) {
  if (wkt.empty()) return "no CRS";
  const std::string& l = label(wkt);
  return l.empty() ? "an unnamed CRS" : l;
}

Job::Job(const BuildOptions& job_options, const CheckedOptions& checked, const ProgressFn* progress,
         LogFn log)
    : options(job_options),
      assign_crs_wkt(checked.assign_crs_wkt),
      override_crs_wkt(checked.override_crs_wkt),
      target_crs_wkt(checked.target_crs_wkt),
      outputs(job_options.write.overwrite),
      started(std::chrono::steady_clock::now()),
      user_progress_(progress && *progress ? progress : nullptr),
      log_(std::move(log)) {
  report.output = options.output;
  report.output_format = std::string(io::format_name(checked.format));
  write.format = checked.format;
  write.ply_ascii = options.write.ply_ascii;
  write.overwrite = options.write.overwrite;
  write.offset = options.write.offset;
  write.ogr_tin = options.write.gpkg_tin;
  if (user_progress_)
    stage_progress_ = [this](std::string_view call, double fraction) {
      const auto phase = std::find(phases_.begin(), phases_.end(), call);
      if (phase != phases_.end())
        fraction = (static_cast<double>(phase - phases_.begin()) + fraction) /
                   static_cast<double>(phases_.size());
      return (*user_progress_)(stage_, fraction);
    };
}

void Job::wait_for_quality() {
  if (!quality_pass) return;
  quality_pass->wait();
  quality_pass.reset();
  report.quality = std::move(quality_measured.quality);
  report.quality_measured = true;
  report.timings_s.quality = quality_measured.seconds;
}

// The CRS the output of KIND is written in: none for a picture, longitude and latitude on WGS 84
// for the web terrain, else the TIN's.
const std::string& Job::crs_of_output(const std::string& kind) const {
  static const std::string none;
  if (kind == "preview") return none;
  if (kind == "terrain") {
    static const std::string wgs84 = io::crs_from_user("EPSG:4326");
    return wgs84;
  }
  return crs_wkt;
}

void Job::finish_output(io::OutputFile& out) {
  out.close();
  if (const io::OutputSet::Entry* e = outputs.entry_of(out))
    report.outputs.push_back(
        {out.path(), e->kind, out.bytes_written(), crs_names.label(crs_of_output(e->kind))});
}

void Job::start_stage(const StageStart& stage, std::span<const std::string_view> phases) {
  stage_ = stage.name;
  phases_ = phases;
  if (StageWatcher* watcher = watcher_of(user_progress_)) watcher->stage_started(stage);
}

void Job::progress(double fraction) const {
  if (user_progress_ && !(*user_progress_)(stage_, fraction)) throw Cancelled();
}

std::string Job::describe_inputs() const {
  const std::vector<std::string>& inputs = options.inputs;
  if (inputs.size() == 1) return inputs.front();
  std::string s;
  const std::size_t shown = std::min<std::size_t>(inputs.size(), 3);
  for (std::size_t i = 0; i < shown; ++i) {
    if (i) s += ", ";
    s += inputs[i];
  }
  if (inputs.size() > shown) s += " and " + count_text(inputs.size() - shown) + " more";
  return s;
}

void check_triangles_left(Job& job) {
  if (job.tin().triangle_count() > 0 || job.may_keep_none) return;
  const BuildReport& r = job.report;
  throw GeometryError(job.describe_inputs(), "",
                      "no triangle is left after --max-edge, --clip and --erase (" +
                          count_text(r.trimmed_triangles) + " trimmed, " +
                          count_text(r.clipped_triangles) + " clipped, " +
                          count_text(r.erased_triangles) + " erased)");
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace tincdt::pipeline
