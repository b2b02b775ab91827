// One tile of the web-terrain pyramid: the TIN of a tile rectangle within the level's geometric
// error of every vertex of the full TIN inside it, quantization included.
//
// The rectangle is the tile's exactly: its four corners are vertices (the TIN's height there, or
// the fill height beyond the data) and each side is the TIN's section along it simplified by
// vertical Douglas–Peucker at a tolerance that depends on the level only, held as constrained
// edges. The two tiles of a border compute the same section from the same numbers, so they get
// the same vertices there: no crack, no skirt needed. Inside, the full TIN's vertices (on the
// tile's quantized grid) are candidates for the project's greedy insertion. The full TIN's
// constrained lines (contours, hard lines) inside the tile, simplified by 3D Douglas–Peucker at
// the sides' tolerance, are constrained edges of the tile's TIN too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/progress.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "web_terrain/source.hpp"

namespace tincdt::web_terrain {

// The vertical error of a tile's surface against the full TIN's vertices inside it (sides
// included), as a client decodes the tile. A hole's outline is simplified like any line (or, where
// it cannot be held, the hole follows the triangles' centres): the surface under a hole still
// measures the vertices there, and those are counted as hidden.
struct TileError {
  double max = 0;
  double sum_squares = 0;
  std::uint64_t count = 0;
  // Vertices in a hole of the tile and none of the full TIN's; an estimate: a shown triangle
  // is looked for in the vertex's cell of the tile's triangle grid only.
  std::uint64_t hidden = 0;
  void add(const TileError& other);
};

struct BuiltTile {
  io::terrain::TileMesh mesh;
  TileError error;
  std::size_t line_segments = 0;  // pieces of constrained lines held as edges
  bool lines_dropped = false;     // the lines could not be held (they overlap on the grid)
  bool outline_dropped = false;   // the lines but the holes' outline could
  // A coarse tile whose tries from its children's vertices missed the error: it chose from every
  // vertex under it.
  bool chose_from_all = false;
  // The TIN's vertices (TerrainSource numbers, ascending) that are vertices of the tile: its
  // parent's candidates.
  std::vector<std::uint32_t> tin_vertices;
};

// The tile KEY of the pyramid over SOURCE, within ERROR (metres). PROGRESS (may be null) is
// called now and then during the work, so that a request to stop gets through within a tile.
// The greedy insertion chooses from the full TIN's vertices in the tile or, given FINER (TIN
// vertices, ascending), from those: a coarse tile takes its children's tin_vertices, which hold
// the finer level's error, and the farthest in each of its triangles that it finds above half
// its own; it is measured against every vertex of the TIN in it all the same.
BuiltTile build_tile(const TerrainSource& source, const io::terrain::TileKey& key, double error,
                     const ProgressFn* progress = nullptr,
                     const std::vector<std::uint32_t>* finer = nullptr);

// The error of MESH, decoded as a client does, against SOURCE's vertices in its rectangle
// (VERTICES, as TerrainSource::vertices_in gives them). HOLE (empty, or one flag a triangle)
// marks the triangles that a hole removes from the tile. PROGRESS (may be null) is called now
// and then; when it returns false, Cancelled is thrown. ABOVE (may be null) receives, for each
// triangle of MESH, its vertex of VERTICES farthest from the surface if farther than LIMIT:
// the points a greedy insertion would take next, ascending.
TileError measure_tile(const TerrainSource& source, const io::terrain::TileMesh& mesh,
                       std::span<const std::uint8_t> hole, std::span<const std::uint32_t> vertices,
                       const ProgressFn* progress = nullptr, double limit = 0,
                       std::vector<std::uint32_t>* above = nullptr);

}  // namespace tincdt::web_terrain
