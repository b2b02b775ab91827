// validate: --validate checks the TIN's topology, its Delaunay property where it is promised,
// and that every constraint segment is a chain of constrained edges. A failure is a bug.
#include <string>

#include "constraints/constraints.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return o.validate;
}

void run(Job& job) {
  // Only the CDT promises locally Delaunay edges, and --fix-flats swaps some edges off the
  // criterion on purpose (FlatFixReport::non_delaunay_edges); otherwise every edge stays
  // locally Delaunay or constrained: draped vertices go in by Lawson insertion, z changes and
  // removed triangles leave the plane triangulation as it is.
  const constraints::Restore restore = job.options.constraint.restore;
  const bool delaunay =
      restore == constraints::Restore::delaunay && job.report.flats.non_delaunay_edges == 0;
  std::string problem = job.tin().validate({.delaunay = delaunay});
  if (problem.empty())
    problem = constraints::check_segments(job.tin(), job.given_segments, job.pieces);
  if (!problem.empty()) throw InternalError("the TIN failed validation: " + problem);
  // The verdict is what --validate was asked for: said at the normal level, not only with -v.
  const std::string verdict =
      "TIN is valid: " + count_text(job.tin().triangle_count(), "triangle") + ", " +
      count_text(job.given_segments.size(), "constraint segment") +
      "; checked the topology, the constrained edges";
  if (delaunay) {
    job.info(verdict + " and the Delaunay property");
    return;
  }
  job.info(verdict + " (not the Delaunay property: " +
           (restore == constraints::Restore::delaunay ? "--fix-flats swaps edges off it"
                                                      : "--restore aspect/none does not keep it") +
           ")");
}

constexpr OptionSpec kOptions[] = {flag_option("--validate", option_groups::checks,
                                               set_true<&BuildOptions::validate>,
                                               "Check the TIN's topology and Delaunay property")};

}  // namespace

constexpr StageProgress kValidateProgress{"validating", "triangles", stage_items::triangles};
extern const Stage validate_stage{"validate", "validate",   wanted,   run,
                                  nullptr,    "--validate", kOptions, kValidateProgress};

}  // namespace tincdt::pipeline
