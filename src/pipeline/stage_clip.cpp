// --clip: the triangles outside every clip polygon are removed.
#include <string>

#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.clip.empty();
}

void run(Job& job) {
  if (job.clip.data.features.empty()) return;
  job.report.clipped_triangles =
      terrain::remove_outside(job.tin(), detail::polygons_of(job.clip.data));
  job.debug("clip: " + std::to_string(job.report.clipped_triangles) +
            " triangles outside the clip polygons removed");
  check_triangles_left(job);
}

}  // namespace

extern const Stage clip_stage{"clip", "terrain", wanted, run};

}  // namespace tincdt::pipeline
