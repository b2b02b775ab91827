// Edits of LAZ files for the tests: header and VLR fields, chunk tables rebuilt with the test
// encoder. The chunks themselves are never re-encoded (there is no LAZ encoder here), only
// moved, cut or given other table entries.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/points/laz/chunk_table.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/laz_test_encoder.hpp"
#include "support/byte_fields.hpp"

namespace tincdt::test::laz_edits {

namespace laz = io::laz;

using test::get;
using test::put;

inline std::size_t offset_to_points(const std::string& b) {
  return get<std::uint32_t>(b, 96);
}

// Where the LASzip VLR's payload starts.
inline std::size_t laszip_payload(const std::string& b) {
  std::size_t pos = get<std::uint16_t>(b, 94);
  for (std::uint32_t i = 0; i < get<std::uint32_t>(b, 100); ++i) {
    if (std::strncmp(b.data() + pos + 2, "laszip encoded", 16) == 0) return pos + 54;
    pos += 54 + get<std::uint16_t>(b, pos + 20);
  }
  ADD_FAILURE() << "no LASzip VLR";
  return 0;
}

inline std::size_t chunk_table_offset(const std::string& b) {
  return static_cast<std::size_t>(get<std::int64_t>(b, offset_to_points(b)));
}

// The chunks of a good file, as the decoder finds them.
inline std::vector<laz::ChunkEntry> chunks_of(const std::string& b) {
  std::vector<std::string> warnings;
  const auto* data = reinterpret_cast<const std::uint8_t*>(b.data());
  const laz::LazSource src = laz::open_laz("file", data, b.size(), warnings);
  const laz::PointLayout layout =
      laz::check_layout("file", laz::parse_laszip_vlr("file", src.laszip_vlr, src.laszip_vlr_size),
                        src.point_format, src.record_length);
  laz::PointData pd{data, b.size(), src.offset_to_points, src.point_count, src.data_limit};
  return laz::plan_chunks("file", pd, layout, warnings).chunks;
}

// B up to its chunk table, then a table of these chunks (EVLRs after the table are dropped).
inline std::string with_table(std::string b, const std::vector<std::uint32_t>& points,
                              const std::vector<std::uint32_t>& bytes, bool variable) {
  b.resize(chunk_table_offset(b));
  const std::vector<std::uint8_t> table = encode_chunk_table(points, bytes, variable);
  b.append(reinterpret_cast<const char*>(table.data()), table.size());
  if (b[25] >= 4) {
    put<std::uint64_t>(b, 235, 0);
    put<std::uint32_t>(b, 243, 0);
  }
  return b;
}

// The points of a format 6 (or 8) file as format 9 (or 10): a WAVEPACKET14 item in the LASzip
// VLR, an empty 29-byte packet in each chunk's raw first point and an empty waveform layer. The
// packets are never decoded, so the coordinates come out as from the original.
inline std::string with_waveforms(const std::string& b) {
  const unsigned format = static_cast<unsigned char>(b[104]) & 0x3Fu;
  const std::size_t colour = format == 8 ? 8 : 0;  // RGBNIR14 before the packet
  const std::size_t record = get<std::uint16_t>(b, 105);
  const std::size_t points_at = offset_to_points(b);
  const std::vector<laz::ChunkEntry> chunks = chunks_of(b);
  const std::size_t vlr = laszip_payload(b);
  const bool variable = get<std::uint32_t>(b, vlr + 12) == 0xFFFFFFFFu;
  const std::size_t item_at = vlr + 34 + (colour != 0 ? 12 : 6);
  std::string out = b.substr(0, item_at);
  const std::uint16_t item[3] = {13, 29, get<std::uint16_t>(b, vlr + 34 + 4)};
  out.append(reinterpret_cast<const char*>(item), sizeof item);
  out.append(b, item_at, points_at - item_at);
  put<std::uint16_t>(out, vlr + 32,
                     static_cast<std::uint16_t>(get<std::uint16_t>(b, vlr + 32) + 1));
  put<std::uint16_t>(out, vlr - 54 + 20,
                     static_cast<std::uint16_t>(get<std::uint16_t>(b, vlr - 54 + 20) + 6));
  put<std::uint32_t>(out, 96, static_cast<std::uint32_t>(points_at + 6));
  out[104] = static_cast<char>((b[104] & 0xC0) | (format == 8 ? 10 : 9));
  put<std::uint16_t>(out, 105, static_cast<std::uint16_t>(record + 29));
  if (out[25] >= 4) {  // EVLRs are dropped
    put<std::uint64_t>(out, 235, 0);
    put<std::uint32_t>(out, 243, 0);
  }
  out.append(8, '\0');  // the chunk table offset, known at the end
  const std::size_t sizes_before = 9 + (colour != 0 ? 2 : 0);  // layer sizes before the packet's
  std::vector<std::uint32_t> points;
  std::vector<std::uint32_t> bytes;
  for (const laz::ChunkEntry& c : chunks) {
    const std::string chunk =
        b.substr(static_cast<std::size_t>(c.offset), static_cast<std::size_t>(c.size));
    std::string moved = chunk.substr(0, 30 + colour);
    moved.append(29, '\0');
    moved.append(chunk, 30 + colour, record - 30 - colour);
    moved.append(chunk, record, 4 + 4 * sizes_before);
    moved.append(4, '\0');  // the waveform layer: empty
    moved.append(chunk, record + 4 + 4 * sizes_before, std::string::npos);
    out += moved;
    points.push_back(static_cast<std::uint32_t>(c.points));
    bytes.push_back(static_cast<std::uint32_t>(moved.size()));
  }
  put<std::int64_t>(out, points_at + 6, static_cast<std::int64_t>(out.size()));
  const std::vector<std::uint8_t> table = encode_chunk_table(points, bytes, variable);
  out.append(reinterpret_cast<const char*>(table.data()), table.size());
  return out;
}

}  // namespace tincdt::test::laz_edits
