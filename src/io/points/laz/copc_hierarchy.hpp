// The octree index of a COPC file (Cloud Optimized Point Cloud specification 1.0): the COPC info
// VLR (user id "copc", record 1) gives the root cube and the first hierarchy page; each page is
// a list of 32-byte entries (voxel key level, x, y, z; offset; byte size; point count), where a
// point count of -1 points to a child page, 0 is an empty node and a positive count is a node
// whose points are one LAZ chunk at offset. Every value is checked against the file before it
// is used, so that a damaged hierarchy is a one-line InputError naming the page and the entry.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tincdt::io::laz {

struct LazSource;

inline constexpr std::size_t kCopcInfoSize = 160;
inline constexpr std::size_t kCopcEntrySize = 32;

struct CopcInfo {
  double center_x = 0, center_y = 0, center_z = 0;
  double halfsize = 0;  // of the root cube
  double spacing = 0;
  std::uint64_t root_offset = 0;  // of the root hierarchy page, in the file
  std::uint64_t root_size = 0;
};

struct VoxelKey {
  std::int32_t level = 0, x = 0, y = 0, z = 0;
  std::string text() const;  // "2-1-3-0"
};

// A node that holds points: one LAZ chunk.
struct CopcNode {
  VoxelKey key;
  std::uint64_t offset = 0;  // of its chunk
  std::uint64_t bytes = 0;
  std::uint64_t points = 0;
  BBox bounds;  // x, y of its cube, grown by the points' rounding (CopcHierarchy::tolerance)
};

struct CopcHierarchy {
  CopcInfo info;
  std::vector<CopcNode> nodes;  // in file order (by offset)
  double tolerance = 0;         // how far a point may lie outside its node's cube
  std::uint64_t pages = 0;      // pages read
  std::uint64_t page_bytes = 0;
};

// Parses the COPC info VLR payload; throws InputError naming PATH when it is too short or its
// cube is not a finite cube of positive size.
CopcInfo parse_copc_info(const std::string& path, const std::uint8_t* payload, std::size_t size);

// The cube of KEY's node, in x and y.
BBox voxel_bounds(const CopcInfo& info, const VoxelKey& key);

// Walks the hierarchy of SOURCE (which must have its COPC info) from the root page. With BOX,
// only the pages whose node meets it are read and only the nodes that meet it are kept, as
// PDAL's readers.copc does with `bounds`; without, every node. Checks every entry against the
// file (pages inside it, not overlapping each other or read twice, keys inside their page's
// node, chunks inside the point data and not overlapping) and throws InputError naming the
// file, the page and the entry at fault.
CopcHierarchy read_hierarchy(const LazSource& source, const BBox* box);

}  // namespace tincdt::io::laz
