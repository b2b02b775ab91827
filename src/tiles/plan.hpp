// Tiled jobs, step 1: the plan. It splits the data's area into tiles of one size, aligned to
// multiples of that size, and lists for each tile the inputs that touch it plus its buffer (from
// the LAS / LAZ header bounds and vector layer extents). Each tile is then one independent job
// (tile_job.hpp) that any job engine can run; `tincdt merge` joins them.
//
// One thing headers cannot give: the convex hull of the data and the points near it (the rim,
// tile_rules.hpp), which the tiles along the data's outline need. The plan reads the points of
// the files that can hold them, outermost first, and skips every file that lies inside the hull
// found so far by more than the rim's width (a tiling of LAS files: all but the outer ring).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "tiles/log.hpp"

namespace tincdt::tiles {

struct PlanOptions {
  std::vector<std::string> inputs;      // point files (LAS, LAZ, XYZ)
  std::vector<std::string> contours;    // vector sources, "FILE" or "FILE:LAYER"
  std::vector<std::string> breaklines;  // hard lines
  // How the inputs are read; every tile job reads them the same way (they are in the plan).
  io::PointFilter filter;     // --keep-class, --drop-class, --first-only, --last-only
  io::LineReadOptions lines;  // --layer, --z-field, --z-from-m
  double tile_size = 0;       // > 0
  double buffer = -1;         // >= 0
  double rim_width = -1;      // < 0: ten times the points' mean spacing; 0: no rim
  unsigned threads = 0;       // files read at once for the rim; 0 = one per core
  std::string output;         // the plan (JSON)
  bool overwrite = false;
};

struct PlanInput {
  // As the plan stores it: relative to the plan's folder when it was given relative, else
  // absolute; a vector source keeps its ":LAYER".
  std::string path;
  std::string kind;  // "points", "contours" or "breaklines"
  std::string format;
  std::uint64_t bytes = 0;
  std::string fingerprint;  // of the file's first and last 64 KiB: a changed file shows
  std::uint64_t count = 0;  // points, or features (0 when the driver does not say)
  BBox bounds;              // x, y; empty when the input holds nothing
  double tolerance = 0;     // how far data may lie outside `bounds` (rounded header bounds)
};

struct PlanTile {
  std::uint32_t index = 0;
  std::int64_t col = 0;  // the box is [col * S, (col + 1) * S) x [row * S, (row + 1) * S)
  std::int64_t row = 0;
  std::vector<std::uint32_t> inputs;  // indices into TilePlan::inputs, in their order
};

struct TilePlan {
  double tile_size = 0;
  double buffer = 0;
  io::PointFilter filter;
  io::LineReadOptions lines;
  BBox extent;  // every input's bounds together
  std::vector<PlanInput> inputs;
  std::vector<Point2> hull;     // of all the data (counter-clockwise), empty when unknown
  double rim_width = 0;         // 0: no rim
  PlanInput rim;                // the rim's points (XYZ text beside the plan), kind "rim"
  std::vector<PlanTile> tiles;  // rows from north to south, each west to east
};

// Reads the headers (and the points the rim needs) and makes the plan, with the rim's points in
// RIM; throws InputError / UsageError. Tiles are those that meet the data's convex hull: no
// triangle of the whole TIN lies outside it.
TilePlan make_plan(const PlanOptions& options, std::vector<Point3>& rim, const LogFn& log = {});

// The plan as JSON at PATH, and its rim points at rim_path(PATH), written to temporaries and
// renamed together (OVERWRITE: replace existing files). RIM: the rim's points.
void write_plan(TilePlan& plan, const std::vector<Point3>& rim, const std::string& path,
                bool overwrite);
// Where the rim of the plan at PLAN_PATH goes: "plan.json" -> "plan.rim.xyz".
std::string rim_path(const std::string& plan_path);

// Reads a plan written by write_plan(); throws InputError naming PATH for anything else.
TilePlan read_plan(const std::string& path);

// Where an input of the plan at PLAN_PATH is on this machine (IN: a member of TilePlan::inputs,
// or its rim): a relative path is taken from the plan's folder. A vector source keeps ":LAYER".
std::string resolve_input(const PlanInput& in, const std::string& plan_path);

// The fingerprint stored in the plan for FILE (a size and a hash of its first and last 64 KiB);
// throws InputError naming FILE when it cannot be read.
std::string file_fingerprint(const std::string& file);

}  // namespace tincdt::tiles
