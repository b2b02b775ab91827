// Internal to the pipeline: a tile's outline, the edges on the border of its triangles with the
// apex of the triangle inside, which `tincdt merge --check` matches against the other tiles'.
// Written by merge (--outline) and by the tile job itself (--outline with --plan).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/output_file.hpp"

namespace tincdt::tiles::detail {

// A border edge a -> b of a tile, its triangle on the left, whose third corner is apex.
struct Border {
  Point3 a, b, apex;
  bool constrained;
  std::uint32_t tile;  // the input it came from (merge), for messages
};

// EDGES as a binary PLY: the vertices (x, y, z doubles) and an edge element with vertex1,
// vertex2, apex and constrained; CRS: a "comment crs" text, "" for none.
// The mark of a file of trimmed tiles (the PLY line "comment trimmed tiles of N: I J ..."):
// which of the plan's N tiles it holds, so that a merge, which cannot tell a missing tile's hole
// from a trimmed area, can count them.
struct TileMark {
  std::uint32_t count = 0;
  std::vector<std::uint32_t> tiles;
};
std::string mark_text(const TileMark& mark);
std::optional<TileMark> parse_mark(const std::string& text);  // nullopt when malformed

// TRIMMED: the mark of trimmed tiles (a "comment trimmed" line), "" for none.
void write_outline(io::OutputFile& out, const std::vector<Border>& edges, const std::string& crs,
                   const std::string& trimmed = "");

}  // namespace tincdt::tiles::detail
