// Tiled jobs, step 2: tile I of a plan as a job of its own (`tincdt --plan plan.json --tile I`).
// The tile reads the points inside its buffered box and the line segments that meet it (whole),
// builds the constrained TIN through the usual stages, and the tile stage (stage_tile.cpp) keeps
// the triangles the tile owns after proving each final (tile_rules.hpp). A job needs no other
// job's output, and running it again gives the same files. The pipeline knows nothing of tiles: a
// tile job is a pipeline::Job whose read hooks keep the tile's data and whose DEM covers the
// tile's box, run over the pipeline's stages with the tile stage among them.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/types.hpp"
#include "pipeline/build.hpp"
#include "pipeline/job.hpp"
#include "pipeline/options.hpp"
#include "pipeline/stage.hpp"
#include "products/grid.hpp"
#include "tiles/tile_rules.hpp"

namespace tincdt::tiles {

// The options of a tile job beside the build's own: build tile `tile` of the plan at `plan`
// (made by make_plan()); the inputs, and how they are read, then come from the plan. buffer >= 0
// replaces the plan's buffer; outline: also write the tile's outline there (for `tincdt merge
// --check`).
struct TileOptions {
  std::string plan;
  std::int64_t tile = -1;
  double buffer = -1;  // the first buffer read; -1: the plan's
  // A buffer too small is grown (to what the unsettled triangles ask, at least doubled) up to
  // max_buffer (-1: one tile size); with buffer_fixed the job stops instead and says how much
  // it needs, for schedulers that promise memory.
  double max_buffer = -1;
  bool buffer_fixed = false;
  std::string outline;
};

// A tile job whose buffer USED is too small: some triangles near the tile could still change.
// NEEDED is what they ask for (0: unknown); TILE_SIZE the plan's; LARGEST a buffer that reads
// all the plan's data.
class BufferTooSmall : public InputError {
 public:
  struct Sizes {
    double used = 0, needed = 0, tile_size = 0, largest = 0;
  };
  BufferTooSmall(std::string file, std::string where, std::string detail, const Sizes& sizes,
                 Remedy remedy = Remedy::none)
      : InputError(std::move(file), std::move(where), std::move(detail), remedy), sizes_(sizes) {}
  double used() const { return sizes_.used; }
  double needed() const { return sizes_.needed; }
  double tile_size() const { return sizes_.tile_size; }
  double largest() const { return sizes_.largest; }
  const Sizes& sizes() const { return sizes_; }

 private:
  Sizes sizes_;
};

struct TileSetup {
  std::string plan_path;
  std::uint32_t index = 0;
  std::uint32_t tile_count = 0;  // the plan's
  std::int64_t col = 0;
  std::int64_t row = 0;
  tiles::TileGrid grid;
  double buffer = 0;
  double largest_buffer = 0;  // one that reads all the plan's data (a larger one reads no more)
  BBox box;                   // the tile, half-open: [min, max)
  BBox buffered;              // what the tile reads (closed)
  std::vector<BBox> data;     // every input's bounds in the plan, grown by its tolerance
  tiles::Rim rim;             // the data's hull and the rim's width (no hull: none)
  std::string rim_path;       // the rim's points, when the tile needs them ("" otherwise)
  // Where data the tile does not hold may lie: outside its buffered box, inside an input's
  // bounds and inside the hull (shrunk by the rim's width when the tile reads the rim).
  std::vector<tiles::Polygon> missing;
  double margin = 0;  // for the tests in doubles: a bound on their rounding
  // The bounds each input of the tile's job must keep to (the plan relies on them): per point
  // file of BuildOptions::inputs, and per line source (contours, then breaklines).
  std::vector<BBox> point_bounds;
  std::vector<BBox> line_bounds;
};

// The rules of tiled jobs that need no file: --tile, --buffer and --outline need --plan, --plan
// needs --tile, and the options that cannot give the same triangles in every tile
// (--max-vertices, --fix-flats, --restore other than delaunay) are refused, as are inputs and
// their read options given beside a plan. Throws UsageError.
void check_tile_options(const TileOptions& tiling, const pipeline::BuildOptions& options);

// check_tile_options(), then pipeline::check_options() on OPTIONS, the plan (when given) standing
// for the inputs it gives the tile. Cheap (no file is read): a command line runs it first, to
// tell a usage error from a failed job, for a tile job or any other.
pipeline::CheckedOptions check_options(const TileOptions& tiling,
                                       const pipeline::BuildOptions& options);

// The job options of tile TILING.tile of plan TILING.plan, and SETUP filled in: the tile's inputs
// from the plan (each checked against its fingerprint), the read filter set to the buffered box,
// --offset auto taken from the plan's extent. Throws UsageError for options that cannot be tiled,
// InputError naming the plan for a missing tile, a changed input, a tile with no input in reach.
pipeline::BuildOptions tile_options(const TileOptions& tiling,
                                    const pipeline::BuildOptions& options, TileSetup& setup);

// The DEM grid of a tile job: its box [min, max) in cells of RESOLUTION, the top-left corner
// (box.min_x, box.max_y). Every tile's cells then lie on one lattice of the plane (the tile
// size is a multiple of the resolution: tile_options() checks it), and the tiles' DEMs join
// pixel-aligned.
products::Grid tile_grid(const BBox& box, double resolution);

// A tile's job: the pipeline's Job with the tile it builds. Its read hooks keep the tile's data
// (detail:: below); its DEM has the tile's grid and takes the cells of the tile's box from every
// triangle the tile stage proves final, the neighbours' too (Job::dem_extra_triangles): each
// cell centre then gets the value the whole job gives it (products::rasterize interpolates a
// triangle the same way in any TIN that holds it).
struct TileJob : pipeline::Job {
  TileJob(const pipeline::BuildOptions& job_options, const pipeline::CheckedOptions& checked,
          const TileSetup& setup, std::string outline_path, const ProgressFn* progress,
          pipeline::LogFn log);

  const TileSetup& tile;
  const std::string outline;  // TileOptions::outline
};

// tile: keeps the tile's own triangles, each proven final (stage_tile.cpp), or with --max-error
// the tile's part of the simplified TIN made from them (tile_simplify.hpp). It runs only in a
// TileJob, as does tile_outline.
extern const pipeline::Stage tile_stage;

// tile_outline: checks that every height the tile keeps is settled, then writes the tile's
// outline (--outline), once the replace, clip and erase stages have done their work.
extern const pipeline::Stage tile_outline_stage;

// Whether triangle T of the tile's TIN is final: a triangle of the whole TIN (stage_tile.cpp).
bool proven_final(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t);

// The stages of a tile job: the pipeline's, with the tile stage before the replace, clip and
// erase stages (which classify the triangles it proved final: Job::proven_triangles) and the
// outline after them. Without the simplify and trim stages: the tile stage trims and simplifies
// the tile (tile_simplify.hpp).
std::vector<const pipeline::Stage*> tile_stages();

// Builds tile TILING.tile of plan TILING.plan as pipeline::build() builds a job: check_options(),
// tile_options(), the checks on every planned output (the outline among them), the stages of
// tile_stages() in a TileJob, then every output moved into place. Throws as build() does.
pipeline::BuildReport build_tile(const TileOptions& tiling, const pipeline::BuildOptions& options,
                                 const ProgressFn* progress = nullptr,
                                 const pipeline::LogFn& log = {});

namespace detail {

// The read hooks of a TileJob. Throws InputError when point file INPUT holds points outside the
// bounds the plan has for it (EXTENT: theirs).
void check_tile_points(const TileJob& job, std::size_t input, const BBox& extent);

// After the point files: the rim's points outside the buffered box.
void add_tile_rim(TileJob& job);

// Once every line source is read: checks their vertices against the plan's bounds and keeps
// whole the segments whose bounding box meets the buffered box or that end in the rim the tile
// reads (lines may cross: the constraint stage makes a crossing from the two whole segments).
void keep_tile_lines(TileJob& job);

// Whether the tile keeps a surface feature: every clip polygon (a tile none of them meets keeps
// nothing), and every other feature unless it lies inside one of the regions where the tile
// holds no data and proves nothing final (TileSetup::missing) anyway.
bool keeps_surface_feature(const TileJob& job, pipeline::detail::SourceKind kind,
                           const io::ShapeFeature& feature);

}  // namespace detail
}  // namespace tincdt::tiles
