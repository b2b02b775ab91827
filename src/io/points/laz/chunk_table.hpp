// Where the chunks of a LAZ file are (LAZ specification 1.4). The point data starts with the
// 64-bit offset of the chunk table (-1: the offset is in the file's last 8 bytes); the table
// holds a version, a chunk count, and per chunk its point count (variable-size chunks only) and
// byte size, arithmetic coded. Chunks are independent: each can be decoded on its own once its
// start is known.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/points/laz/laszip_vlr.hpp"

namespace tincdt::io::laz {

struct ChunkEntry {
  std::uint64_t offset = 0;  // in the file
  std::uint64_t size = 0;    // bytes; in a sequential plan, the bytes left up to the data end
  std::uint64_t points = 0;
  std::uint64_t first_point = 0;
};

struct ChunkPlan {
  std::vector<ChunkEntry> chunks;
  // Formats 0-5 without a usable table: only the first chunk's start is known, each next one
  // starts where decoding the previous ended, so the chunks must be decoded in order.
  bool sequential = false;
  std::uint64_t data_end = 0;  // chunks lie before this byte
  bool exact_end = false;      // sequential: the chunks must end exactly at data_end (the table)
};

struct PointData {
  const std::uint8_t* file = nullptr;
  std::size_t file_size = 0;
  std::uint64_t offset_to_points = 0;
  std::uint64_t point_count = 0;
  std::uint64_t data_limit = 0;  // the point data ends here at the latest (EVLRs, file end)
};

// Reads the chunk table and checks it against the header and the file size. A missing or
// unreadable table is worked around (warning in WARNINGS): formats 6-10 by walking the chunk
// headers, formats 0-5 with fixed-size chunks by a sequential plan. Throws InputError naming
// PATH when the chunks cannot be found, or a readable table contradicts the header or the VLR.
ChunkPlan plan_chunks(const std::string& path, const PointData& data, const PointLayout& layout,
                      std::vector<std::string>& warnings);

// Layers per chunk of a point14 record: 9 for POINT14, then RGB 1, NIR 1, waveform 1, and one
// per extra byte.
unsigned layer_count(const PointLayout& layout);

}  // namespace tincdt::io::laz
