// The parts of the quantized-mesh encoder shared by its two source files: the quantization of
// the vertices, the geometry of the header and the vertex normals.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "io/terrain/quantized_mesh.hpp"

namespace tincdt::io::terrain::detail {

// The vertices of a mesh as the file holds them, in the mesh's order.
struct QuantizedVertices {
  std::vector<std::uint16_t> u;       // 0 on the west side, kQuantizedMax on the east
  std::vector<std::uint16_t> v;       // 0 on the south side, kQuantizedMax on the north
  std::vector<std::uint16_t> height;  // 0 at minimum_height, kQuantizedMax at maximum_height
  float minimum_height;
  float maximum_height;
};

// Throws InternalError unless MESH is one the encoder can write (see quantized_mesh_header()).
void check_tile_mesh(const TileMesh& mesh);

// MESH's vertices quantized; a vertex on a side gets exactly 0 or kQuantizedMax there.
QuantizedVertices quantize_vertices(const TileMesh& mesh);

// The header of MESH, whose vertices are QUANTIZED.
QuantizedMeshHeader header_of(const TileMesh& mesh, const QuantizedVertices& quantized);

// The oct-encoded unit normal of each vertex of MESH, in ECEF, in the mesh's order.
std::vector<std::array<std::uint8_t, 2>> oct_vertex_normals(const TileMesh& mesh);

}  // namespace tincdt::io::terrain::detail
