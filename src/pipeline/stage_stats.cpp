// stats: --stats, the report of the job as JSON; the last stage, so that it reports on all
// the others. The path "-" writes no file: the caller prints the report it gets back
// (BuildReport::to_json) once every file is in place.
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.stats_path.empty();
}

void run(Job& job) {
  job.wait_for_quality();
  job.report.timings_s.total = seconds_since(job.started);
  job.report.peak_rss_bytes = peak_rss_bytes();
  if (job.options.stats_path == "-") return;
  // Not through Job::write_output: the document does not list itself among the outputs.
  io::OutputFile& out = job.outputs.add(job.options.stats_path, "stats");
  out.write(job.report.to_json());
  out.close();
}

void plan(const BuildOptions& o, FilePlan& files) {
  if (o.stats_path != "-") files.outputs.push_back({o.stats_path, "the stats file (--stats)"});
}

constexpr OptionSpec kOptions[] = {
    text_option("--stats", "FILE.json", option_groups::output, set_text<&BuildOptions::stats_path>,
                "Write counts, quality, timings and memory as JSON\n"
                "('-': to standard output, once the other outputs are in place)")};

}  // namespace

constexpr StageProgress kStatsProgress{"writing statistics"};
extern const Stage stats_stage{"stats", "", wanted, run, plan, "", kOptions, kStatsProgress};

}  // namespace tincdt::pipeline
