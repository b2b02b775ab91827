// Tiled jobs, step 2: tile I of a plan as a job of its own (`tincdt --plan plan.json --tile I`).
// The tile reads the points inside its buffered box and the line segments that meet it (whole),
// builds the constrained TIN through the usual stages, and the tile stage (stage_tile.cpp) keeps
// the triangles the tile owns after proving each final (tile_rules.hpp). A job needs no other
// job's output, and running it again gives the same files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "pipeline/options.hpp"
#include "pipeline/tile_rules.hpp"
#include "products/grid.hpp"

namespace tincdt::pipeline {

struct Job;

struct TileSetup {
  std::string plan_path;
  std::uint32_t index = 0;
  std::int64_t col = 0;
  std::int64_t row = 0;
  tiles::TileGrid grid;
  double buffer = 0;
  BBox box;                // the tile, half-open: [min, max)
  BBox buffered;           // what the tile reads (closed)
  std::vector<BBox> data;  // every input's bounds in the plan, grown by its tolerance
  tiles::Rim rim;          // the data's hull and the rim's width (no hull: none)
  std::string rim_path;    // the rim's points, when the tile needs them ("" otherwise)
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
// needs --tile, and the options that cannot give the same triangles in every tile (--max-edge,
// --fix-flats, surface features, --restore other than delaunay) are refused, as are inputs and
// their read options given beside a plan. Throws UsageError. Part of check_options().
void check_tile_options(const BuildOptions& options);

// The job options of tile OPTIONS.tile of plan OPTIONS.plan, and SETUP filled in: the tile's
// inputs from the plan (each checked against its fingerprint), the read filter set to the
// buffered box, --offset auto taken from the plan's extent. Throws UsageError for options that
// cannot be tiled, InputError naming the plan for a missing tile, a changed input, a tile with no
// input in reach.
BuildOptions tile_options(const BuildOptions& options, TileSetup& setup);

// The DEM grid of a tile job: its box [min, max) in cells of RESOLUTION, the top-left corner
// (box.min_x, box.max_y). Every tile's cells then lie on one lattice of the plane (the tile
// size is a multiple of the resolution: tile_options() checks it), and the tiles' DEMs join
// pixel-aligned.
products::Grid tile_grid(const BBox& box, double resolution);

namespace detail {

// For the read stage. Throws InputError when point file INPUT of a tile job holds points outside
// the bounds the plan has for it (EXTENT: theirs).
void check_tile_points(const Job& job, std::size_t input, const BBox& extent);

// For the read stage, after the point files: the rim's points outside the buffered box.
void add_tile_rim(Job& job);

// For the read stage, once every line source is read: checks their vertices against the plan's
// bounds, refuses lines that cross (a crossing vertex's rounding depends on the segments the job
// sees), and keeps whole the segments whose bounding box meets the buffered box or that end in
// the rim the tile reads.
void keep_tile_lines(Job& job);

}  // namespace detail
}  // namespace tincdt::pipeline
