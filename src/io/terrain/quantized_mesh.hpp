// One Cesium terrain tile in quantized-mesh-1.0 (github.com/CesiumGS/quantized-mesh): a
// little-endian header (tile centre, height range, bounding sphere and horizon occlusion point),
// the vertices quantized to 0..32767 across the tile's rectangle and height range (delta and
// zig-zag coded), the triangles (high-water-mark coded, 16- or 32-bit), the vertices on each of
// the four sides (for the skirts a viewer hangs there), and the extensions octvertexnormals and
// metadata. The bytes are uncompressed: gzip is the server's business.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/terrain/geographic_tiling.hpp"

namespace tincdt::io::terrain {

// The largest quantized coordinate: u, v and height run over 0..kQuantizedMax.
inline constexpr std::uint32_t kQuantizedMax = 32767;
// Tiles with more vertices than this store their indices as 32 bits, the others as 16.
inline constexpr std::uint32_t kMaxVerticesFor16BitIndices = 65536;

// The mesh of one tile, in the order the caller has it (the encoder renumbers the vertices).
struct TileMesh {
  GeoRectangle rectangle;  // the tile's, degrees
  // x = longitude, y = latitude (degrees, inside the rectangle), z = height above the WGS 84
  // ellipsoid (metres). A vertex exactly on a side of the rectangle is on that tile edge.
  std::vector<Point3> vertices;
  // Corners into vertices, counter-clockwise seen from above (north up, east right).
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// What follows the mesh.
struct QuantizedMeshOptions {
  bool vertex_normals = true;  // the octvertexnormals extension
  bool metadata = true;        // the metadata extension, with available below
  // For the metadata: the tiles present below this one, a list of ranges per level, from the
  // tile's level + 1 down.
  std::vector<std::vector<TileRange>> available;
};

// The header's values, as the file holds them.
struct QuantizedMeshHeader {
  Point3 center;  // ECEF metres: the rectangle's centre, halfway up the height range
  float minimum_height;
  float maximum_height;
  Point3 bounding_sphere_center;  // ECEF metres
  double bounding_sphere_radius;
  Point3 horizon_occlusion_point;  // ellipsoid-scaled ECEF
};

// The header encode_quantized_mesh writes for MESH (with the vertex it may add). The height range
// is the vertices' widened to the nearest floats outside it; the sphere and the occlusion point
// bound the vertices where a reader puts them (at their quantized positions). Throws InternalError
// for a mesh without vertices, with a corner index out of range or a vertex outside its rectangle
// or not finite.
QuantizedMeshHeader quantized_mesh_header(const TileMesh& mesh);

// The whole tile. The vertices are renumbered in the order the triangles first use them (which
// the high-water-mark code needs; unused ones go last, in their order); the triangles keep
// their order and their corners' rotation. The side lists run west south to north, south east
// to west, east north to south, north west to east (the orders Cesium sorts them into).
// Indices are 16-bit up to 65536 vertices, else 32-bit; a mesh of exactly 65536 vertices whose
// codes would not fit 16 bits (once all are met, vertex 0's code is 65536) gets one more vertex,
// unused, at the rectangle's centre, to take 32-bit indices. Same mesh and options, same bytes.
// Throws as quantized_mesh_header().
std::string encode_quantized_mesh(const TileMesh& mesh, const QuantizedMeshOptions& options);

}  // namespace tincdt::io::terrain
