// The polygon stages, alike but for what they do inside or outside the polygons:
//   replace: --replace, every vertex on or inside a polygon gets the polygon's z (later win);
//   clip:    --clip, the triangles outside every clip polygon are removed;
//   erase:   --erase, the triangles inside an erase polygon are removed (erase wins over clip).
// The rings are constrained edges by now (the surface stage), so the classification is exact.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/surface.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline {
namespace {

struct PolygonStage {
  const std::vector<std::string> BuildOptions::*sources;
  detail::SurfaceInput Job::*polygons;
  std::uint64_t BuildReport::*count;
  std::uint64_t (*apply)(mesh::Triangulation&, const std::vector<terrain::Polygon>&,
                         const terrain::PolygonOptions&);
  const char* counted;  // for the log: what `count` counts
  bool removes;         // removes triangles (a TIN may be left empty)
};

constexpr PolygonStage kReplace{&BuildOptions::replace,
                                &Job::replace,
                                &BuildReport::replaced_vertices,
                                &terrain::set_polygon_z_inside,
                                "vertices set to the polygon's z",
                                false};
constexpr PolygonStage kClip{&BuildOptions::clip,
                             &Job::clip,
                             &BuildReport::clipped_triangles,
                             &terrain::remove_outside,
                             "triangles outside the clip polygons removed",
                             true};
constexpr PolygonStage kErase{&BuildOptions::erase,
                              &Job::erase,
                              &BuildReport::erased_triangles,
                              &terrain::remove_inside,
                              "triangles inside the erase polygons removed",
                              true};

template <const PolygonStage& S>
bool wanted(const BuildOptions& o) {
  return !(o.*S.sources).empty();
}

// Removes what S removes from the kept triangles and from dem_extra_triangles (put back in the
// TIN meanwhile); returns the kept triangles removed.
template <const PolygonStage& S>
std::uint64_t remove_with_extras(Job& job, const terrain::PolygonOptions& options) {
  mesh::Triangulation& tin = job.tin();
  std::vector<TriangleId>& extra = job.dem_extra_triangles;
  for (const TriangleId t : extra) tin.set_removed(t, false);
  std::uint64_t removed = S.apply(tin, detail::polygons_of((job.*S.polygons).data), options);
  const auto gone = std::stable_partition(extra.begin(), extra.end(),
                                          [&tin](TriangleId t) { return tin.is_kept(t); });
  removed -= static_cast<std::uint64_t>(extra.end() - gone);
  extra.erase(gone, extra.end());
  for (const TriangleId t : extra) tin.set_removed(t, true);
  return removed;
}

template <const PolygonStage& S>
void run(Job& job) {
  const detail::SurfaceInput& input = job.*S.polygons;
  if (input.data.features.empty()) return;
  terrain::PolygonOptions options;
  if (!job.proven_triangles.empty()) options.within = &job.proven_triangles;
  if (!job.known_replace_polygons.empty()) options.vertex_polygons = &job.known_replace_polygons;
  std::uint64_t& count = job.report.*S.count;
  count = S.removes ? remove_with_extras<S>(job, options)
                    : S.apply(job.tin(), detail::polygons_of(input.data), options);
  job.debug(std::string(job.stage()) + ": " + count_text(count) + " " + S.counted);
  if (S.removes) check_triangles_left(job);
}

// ---- options -----------------------------------------------------------------------------------

constexpr OptionSpec kReplaceOptions[] = {repeated_option(
    "--replace", "POLYGONS", option_groups::quality, add_text<&BuildOptions::replace>,
    "Replace polygons: vertices on or inside get the polygon's one z\n"
    "(--z-field, --z-from-m or 3D z); rings become TIN edges")};
constexpr OptionSpec kClipOptions[] = {
    repeated_option("--clip", "POLYGONS", option_groups::boundary, add_text<&BuildOptions::clip>,
                    "Remove the triangles outside these polygons (2D: draped)")};
constexpr OptionSpec kEraseOptions[] = {
    repeated_option("--erase", "POLYGONS", option_groups::boundary, add_text<&BuildOptions::erase>,
                    "Remove the triangles inside these polygons (holes; wins over --clip)")};

}  // namespace

constexpr StageProgress kReplaceProgress{"flattening replace polygons"};
extern const Stage replace_stage{"replace",
                                 "terrain",
                                 wanted<kReplace>,
                                 run<kReplace>,
                                 nullptr,
                                 "--replace: vertices on or inside get the polygon's z (later "
                                 "polygons win)",
                                 kReplaceOptions,
                                 kReplaceProgress};
constexpr StageProgress kClipProgress{"clipping", "triangles", stage_items::triangles};
extern const Stage clip_stage{
    "clip",       "terrain",    wanted<kClip>,
    run<kClip>,   nullptr,      "--clip: triangles outside every clip polygon are removed",
    kClipOptions, kClipProgress};
constexpr StageProgress kEraseProgress{"erasing", "triangles", stage_items::triangles};
extern const Stage erase_stage{"erase",
                               "terrain",
                               wanted<kErase>,
                               run<kErase>,
                               nullptr,
                               "--erase: triangles inside an erase polygon are removed (erase "
                               "wins over\nclip; replaced vertices inside an erase polygon go "
                               "with their triangles)",
                               kEraseOptions,
                               kEraseProgress};

}  // namespace tincdt::pipeline
