// PLY reader for `tincdt merge`: the TINs tincdt writes (ply_writer.cpp) and the tile outlines
// merge writes, in binary little-endian or ASCII, written from the PLY format description (Turk,
// 1994). Vertices need x, y, z (float or double); faces a vertex index list of three; edges two
// vertex indices, and outlines also an apex index and a constrained flag. Other elements and
// properties are skipped.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tincdt::io {

struct PlyMesh {
  std::vector<Point3> vertices;  // with the offset of a "comment offset X Y Z" line added back
  std::vector<std::array<std::uint32_t, 3>> faces;
  struct Edge {
    std::uint32_t a;
    std::uint32_t b;
    std::uint32_t apex = kNoId;  // outlines: the third corner of the triangle left of a -> b
    bool constrained = true;     // a TIN's edges are its constrained edges
  };
  std::vector<Edge> edges;
  bool outline = false;  // the edges carry an apex: a tile outline, not a TIN
  // A "comment trimmed TEXT" line: triangles removed along the border (TEXT: which tiles).
  std::optional<std::string> trimmed;
  Point3 offset{0, 0, 0};
  std::string crs;  // the text of a "comment crs" line ("EPSG:2949", or WKT), "" when none
};

// Reads PATH whole; throws InputError naming the file and the element / line at fault: a bad
// header, counts the file cannot hold, an index out of range, a face that is not a triangle.
PlyMesh read_ply(const std::string& path);

}  // namespace tincdt::io
