// flats: --fix-flats removes the flat triangles (three corners on one contour level); with
// --stats alone they are only counted. Both need the whole TIN, before any z is replaced or
// any triangle removed.
#include <string>

#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"
#include "terrain/flats.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.contours.empty() && (o.fix_flats || !o.stats_path.empty());
}

void run(Job& job) {
  job.on_contour = detail::contour_flags(job.tin(), job.pieces, job.sources);
  BuildReport::Flats& flats = job.report.flats;
  flats.counted = true;
  if (!job.options.fix_flats) {
    flats.before = flats.after = flats.after_swaps =
        terrain::count_flat_triangles(job.tin(), job.on_contour);
    return;
  }
  const terrain::FlatFixReport f = terrain::fix_flat_triangles(job.tin(), job.on_contour);
  flats.fixed = true;
  flats.before = f.flats_before;
  flats.after_swaps = f.flats_after_swaps;
  flats.after = f.flats_after;
  flats.swaps = f.swaps;
  flats.vertices_added = f.vertices_added;
  flats.vertices_interpolated = f.vertices_interpolated;
  flats.vertices_extrapolated = f.vertices_extrapolated;
  flats.left_no_level = f.flats_left_no_level;
  flats.left_unplaced = f.flats_left_unplaced;
  flats.non_delaunay_edges = f.non_delaunay_edges;
  job.debug("flat triangles: " + count_text(f.flats_before) + " before, " +
            count_text(f.flats_after) + " after " + count_text(f.swaps, "swap") + " and " +
            count_text(f.vertices_added, "new vertex", "new vertices"));
}

constexpr OptionSpec kOptions[] = {
    flag_option("--fix-flats", option_groups::quality, set_true<&BuildOptions::fix_flats>,
                "Remove flat triangles (3 corners on one contour level) by swaps,\n"
                "then by vertices on the contours' medial axis (needs --contours)")};

}  // namespace

constexpr StageProgress kFlatsProgress{"fixing flat triangles", "triangles",
                                       stage_items::triangles};
extern const Stage flats_stage{"flats", "terrain",     wanted,   run,
                               nullptr, "--fix-flats", kOptions, kFlatsProgress};

}  // namespace tincdt::pipeline
