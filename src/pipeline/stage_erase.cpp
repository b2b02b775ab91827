// --erase: the triangles inside an erase polygon are removed (erase wins over clip).
#include <string>

#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.erase.empty();
}

void run(Job& job) {
  if (job.erase.data.features.empty()) return;
  job.report.erased_triangles =
      terrain::remove_inside(job.tin(), detail::polygons_of(job.erase.data));
  job.debug("erase: " + std::to_string(job.report.erased_triangles) +
            " triangles inside the erase polygons removed");
  check_triangles_left(job);
}

}  // namespace

extern const Stage erase_stage{"erase", "terrain", wanted, run};

}  // namespace tincdt::pipeline
