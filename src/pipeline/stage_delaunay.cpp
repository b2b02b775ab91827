// delaunay: every point and line vertex into one Delaunay triangulation, equal x, y merged.
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "delaunay/delaunay.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

bool filtering(const io::PointFilter& f) {
  return !f.keep_classes.empty() || !f.drop_classes.empty() || f.first_return_only ||
         f.last_return_only;
}

bool wanted(const BuildOptions&) {
  return true;
}

void run(Job& job) {
  const BuildReport& report = job.report;
  const bool lines = !job.lines.segments.empty();
  if (report.points_read == 0 && !lines)
    throw GeometryError(job.describe_inputs(), "", "no points in the input");
  if (report.points_kept == 0 && !lines)
    throw GeometryError(
        job.describe_inputs(), "",
        "the class/return filters kept none of the " + count_text(report.points_read, "point"));
  job.debug("triangulating " + count_text(job.points.size(), "point"));
  delaunay::DelaunayOptions options;
  options.on_duplicate = job.options.on_duplicate;
  options.keep_point_map = lines;
  options.keep_duplicates = !job.options.diagnostics.empty();
  options.threads = job.options.threads;
  try {
    job.mesh = delaunay::triangulate(std::move(job.points), options, job.stage_progress());
  } catch (const GeometryError& e) {
    std::string detail = e.detail();
    if (filtering(job.options.filter) && report.points_kept < report.points_read)
      detail += " (the class/return filters kept " + count_text(report.points_kept) + " of " +
                count_text(report.points_read, "point") + ")";
    throw GeometryError(e.file().empty() ? job.describe_inputs() : e.file(), e.where(), detail);
  }
  release(job.points);  // moved-from; free whatever is left
  job.report.duplicates_merged = job.mesh.duplicates_merged;
  if (job.mesh.duplicates_merged > 0)
    job.debug(count_text(job.mesh.duplicates_merged) + " duplicate points merged (same x, y)");
}

// ---- options -----------------------------------------------------------------------------------

constexpr std::string_view kDuplicateWords[] = {"first", "min", "max", "mean"};
constexpr delaunay::DuplicatePolicy kDuplicatePolicies[] = {
    delaunay::DuplicatePolicy::first, delaunay::DuplicatePolicy::min,
    delaunay::DuplicatePolicy::max, delaunay::DuplicatePolicy::mean};

constexpr OptionSpec kOptions[] = {
    choice_option<kDuplicateWords, kDuplicatePolicies, &BuildOptions::on_duplicate>(
        "--on-duplicate", option_groups::triangulation, "mean",
        "z of points with equal x, y: the first in input order,\nor their min, max or mean"),
};

}  // namespace

constexpr StageProgress kDelaunayProgress{"triangulating", "points", stage_items::points};
extern const Stage delaunay_stage{"delaunay", "delaunay", wanted,   run,
                                  nullptr,    "",         kOptions, kDelaunayProgress};

}  // namespace tincdt::pipeline
