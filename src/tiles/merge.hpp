// Tiled jobs, step 3: `tincdt merge` joins the TINs of a plan's tiles. Vertices on the seams are
// welded by their exact coordinates (each tile wrote the same doubles for them); every edge must
// then have one triangle on each side, or lie on the convex hull, and the whole must be a valid
// constrained Delaunay TIN (Triangulation::validate()), so a crack, an overlap or a tile from
// another run is an error naming the tiles.
//
// For data too large to merge in one piece, the check needs only the tiles' outlines: each tile's
// border edges (with the apex of their triangle) must meet the reversed edge of exactly one other
// tile, with the same z at both ends and the Delaunay property across, and the edges left over
// must form the convex hull. `--outline` writes that outline of some tiles, so that the tiles can
// be deleted as the jobs go and checked together at the end.
//
// Tiles trimmed with --max-edge (a "comment trimmed" PLY line naming the plan's tiles each holds)
// have borders that are neither seams nor hull: their outline is checked for closed loops, the
// merged TIN for the Delaunay property across its edges instead of one convex hull, and the tiles
// are counted: every tile of the plan once.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tiles/log.hpp"

namespace tincdt::tiles {

struct MergeOptions {
  std::vector<std::string> inputs;  // tile TINs (PLY), or outlines written with `outline`
  std::string output;               // the merged TIN (format from the extension), or the outline
  bool check_only = false;          // check the seams from the outlines; write nothing
  bool outline = false;             // write the outline of the inputs together instead of a TIN
  bool overwrite = false;
};

struct MergeReport {
  std::uint64_t tiles = 0;
  std::uint64_t vertices = 0;  // welded (check_only / outline: summed over the tiles)
  std::uint64_t triangles = 0;
  std::uint64_t seam_edges = 0;  // border edges of one tile matched by another's
  std::uint64_t hull_edges = 0;  // border edges left over: the hull (outline: the new outline)
  bool trimmed = false;          // trimmed tiles: the border edges left over are the outline
};

// Throws InputError naming the tiles at fault, OutputError for the output.
MergeReport merge_tiles(const MergeOptions& options, const LogFn& log = {});

}  // namespace tincdt::tiles
