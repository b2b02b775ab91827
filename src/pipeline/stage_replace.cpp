// --replace: every vertex on or inside a polygon gets the polygon's z (later polygons win).
#include <string>

#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.replace.empty();
}

void run(Job& job) {
  if (job.replace.data.features.empty()) return;
  job.report.replaced_vertices =
      terrain::set_polygon_z_inside(job.tin(), detail::polygons_of(job.replace.data));
  job.debug("replace: " + std::to_string(job.report.replaced_vertices) +
            " vertices set to the polygon's z");
}

}  // namespace

extern const Stage replace_stage{"replace", "terrain", wanted, run};

}  // namespace tincdt::pipeline
