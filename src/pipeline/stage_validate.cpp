// validate: --validate checks the TIN's topology, its Delaunay property where it is promised,
// and that every constraint segment is a chain of constrained edges. A failure is a bug.
#include <string>

#include "constraints/constraints.hpp"
#include "core/error.hpp"
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
  if (delaunay) {
    job.debug("validate: TIN is valid");
    return;
  }
  job.debug(std::string("validate: TIN is valid (topology; the Delaunay check is off for ") +
            (restore == constraints::Restore::delaunay ? "--restore delaunay with --fix-flats swaps"
                                                       : "--restore aspect/none") +
            ")");
}

constexpr OptionSpec kOptions[] = {flag_option("--validate", option_groups::checks,
                                               set_true<&BuildOptions::validate>,
                                               "Check the TIN's topology and Delaunay property")};

}  // namespace

extern const Stage validate_stage{"validate", "validate",   wanted,  run,
                                  nullptr,    "--validate", kOptions};

}  // namespace tincdt::pipeline
