#include "io/points/laz/chunk_table.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/integer_decompressor.hpp"
#include "io/points/load_le.hpp"

namespace tincdt::io::laz {
namespace {

std::string byte_at(std::uint64_t offset) {
  return "byte " + count_text(offset);
}

// The fewest bytes a chunk with at least one point takes: its raw first point, then the
// decoder's four initial bytes (formats 0-5) or the point count and one size per layer (6-10).
std::uint64_t min_chunk_bytes(const PointLayout& layout) {
  return layout.record_length + (layout.layered ? 4 + 4 * std::uint64_t{layer_count(layout)} : 4);
}

// A chunk table that was read and checked, or why it cannot be used.
struct TableResult {
  std::vector<ChunkEntry> chunks;
  std::string problem;             // unreadable: empty when usable
  std::string contradiction;       // readable but contradicting the header or the VLR
  std::uint64_t table_offset = 0;  // where the table starts, 0 when not known
};

TableResult read_table(const PointData& data, const PointLayout& layout,
                       std::uint64_t chunks_begin) {
  TableResult result;
  const std::uint8_t* file = data.file;
  const std::uint64_t size = data.file_size;
  auto offset = load_le<std::int64_t>(file + data.offset_to_points);
  if (offset == -1) {
    // Written by a streaming compressor: the offset follows the table, at the end of the file.
    offset = load_le<std::int64_t>(file + size - 8);
  }
  if (offset == static_cast<std::int64_t>(data.offset_to_points)) {
    result.problem = "the chunk table was never written (the compressor was interrupted?)";
    return result;
  }
  if (offset < static_cast<std::int64_t>(chunks_begin) ||
      static_cast<std::uint64_t>(offset) + 8 > size) {
    result.problem = "its offset " + signed_count_text(offset) + " lies outside the " +
                     count_text(size) + "-byte file";
    return result;
  }
  const auto table = static_cast<std::uint64_t>(offset);
  result.table_offset = table;
  const auto version = load_le<std::uint32_t>(file + table);
  if (version != 0) {
    result.problem = "unknown chunk table version " + std::to_string(version);
    return result;
  }
  const std::uint64_t count = load_le<std::uint32_t>(file + table + 4);
  const std::uint64_t room = (table - chunks_begin) / min_chunk_bytes(layout);
  if (count > room) {
    result.problem = "it lists " + count_text(count) + " chunks, but the " +
                     count_text(table - chunks_begin) + " bytes before it hold at most " +
                     count_text(room);
    return result;
  }
  if (count == 0) {
    result.problem = "it lists no chunks";
    return result;
  }

  ArithmeticDecoder dec(file + table + 8, static_cast<std::size_t>(size - table - 8));
  IntegerDecompressor ic(32, 2);
  ic.reset();
  result.chunks.resize(count);
  std::uint32_t points = 0;
  std::uint32_t bytes = 0;
  std::uint64_t start = chunks_begin;
  std::uint64_t first_point = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    // Each entry is predicted from the previous one.
    if (layout.variable_chunks) {
      points = static_cast<std::uint32_t>(ic.decompress(dec, static_cast<std::int32_t>(points), 0));
    } else {
      points = layout.chunk_size;
    }
    bytes = static_cast<std::uint32_t>(ic.decompress(dec, static_cast<std::int32_t>(bytes), 1));
    if (dec.failed()) {
      result.problem = "its data ends before entry " + count_text(i);
      return result;
    }
    ChunkEntry& chunk = result.chunks[i];
    chunk.offset = start;
    chunk.size = bytes;
    chunk.points = points;
    chunk.first_point = first_point;
    if (points > 0 && bytes < min_chunk_bytes(layout)) {
      result.problem = "chunk " + count_text(i) + " is " + count_text(bytes) +
                       " bytes long, less than one point takes";
      return result;
    }
    start += bytes;
    first_point += points;
    if (start > table) {
      result.problem = "chunk " + count_text(i) + " would end at " + byte_at(start) +
                       ", past the table itself at " + byte_at(table);
      return result;
    }
  }
  if (!layout.variable_chunks) {
    // A table that reads fine but disagrees with the VLR's chunk size: one of them lies, and
    // decoding in order would not tell (chunks would start inside others).
    const std::uint64_t needed = (data.point_count + layout.chunk_size - 1) / layout.chunk_size;
    if (count < needed) {
      result.contradiction = "it lists " + count_text(count) + " chunks, but the header's " +
                             count_text(data.point_count) + " points in chunks of " +
                             count_text(layout.chunk_size) + " (LASzip VLR) need " +
                             count_text(needed);
    }
  }
  return result;
}

// Formats 6-10 store each chunk's point count and layer sizes at its start: the chunks can be
// found by walking these headers from the first.
std::vector<ChunkEntry> walk_chunks(const std::string& path, const PointData& data,
                                    const PointLayout& layout, std::uint64_t chunks_begin,
                                    std::uint64_t end) {
  std::vector<ChunkEntry> chunks;
  const unsigned layers = layer_count(layout);
  const std::uint64_t header = layout.record_length + 4 + 4 * std::uint64_t{layers};
  std::uint64_t at = chunks_begin;
  std::uint64_t points = 0;
  while (points < data.point_count) {
    const std::string where = "chunk " + count_text(chunks.size()) + ", " + byte_at(at);
    if (end < at || end - at < header) {
      throw InputError(path, where,
                       "the point data ends (at " + byte_at(end) + ") after " + count_text(points) +
                           " of the " + count_text(data.point_count) +
                           " points the header announces");
    }
    const std::uint8_t* p = data.file + at + layout.record_length;
    ChunkEntry chunk;
    chunk.offset = at;
    chunk.points = load_le<std::uint32_t>(p);
    chunk.first_point = points;
    std::uint64_t bytes = header;
    for (unsigned i = 0; i < layers; ++i) bytes += load_le<std::uint32_t>(p + 4 + 4 * i);
    if (chunk.points == 0 || bytes > end - at) {
      throw InputError(path, where,
                       chunk.points == 0 ? "the chunk says it holds no points"
                                         : "the chunk's layers would end at " +
                                               byte_at(at + bytes) + ", past the point data");
    }
    chunk.size = bytes;
    chunks.push_back(chunk);
    at += bytes;
    points += chunk.points;
  }
  return chunks;
}

// Drops the chunks after the header's point count and shortens the one it ends in. A table that
// holds fewer points than the header announces is refused.
void fit_to_count(const std::string& path, std::vector<ChunkEntry>& chunks,
                  std::uint64_t point_count) {
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    if (total + chunks[i].points >= point_count) {
      chunks[i].points = point_count - total;
      chunks.resize(point_count == 0 ? 0 : i + 1);
      return;
    }
    total += chunks[i].points;
  }
  throw InputError(path, "chunk table",
                   "its chunks hold " + count_text(total) + " points but the header announces " +
                       count_text(point_count));
}

// Formats 6-10: every chunk starts with the number of points it holds, the data's own word. A
// header that announces more than their sum would have the decoder invent the missing points
// from the bytes after the last one.
void check_held_points(const std::string& path, const PointData& data, const PointLayout& layout,
                       const std::vector<ChunkEntry>& chunks) {
  std::uint64_t held = 0;
  for (const ChunkEntry& chunk : chunks) {
    if (chunk.size < layout.record_length + 4) continue;  // an empty chunk: no count stored
    held += load_le<std::uint32_t>(data.file + chunk.offset + layout.record_length);
  }
  if (data.point_count > held) {
    throw InputError(path, "point data",
                     "the header announces " + count_text(data.point_count) +
                         " points but the compressed data holds " + count_text(held));
  }
}

}  // namespace

unsigned layer_count(const PointLayout& layout) {
  if (!layout.layered) return 0;
  return 9 + (layout.rgb ? 1 : 0) + (layout.nir ? 1 : 0) + (layout.waveform ? 1 : 0) +
         layout.extra_bytes;
}

ChunkPlan plan_chunks(const std::string& path, const PointData& data, const PointLayout& layout,
                      std::vector<std::string>& warnings) {
  ChunkPlan plan;
  plan.data_end = data.data_limit;
  if (data.point_count == 0) return plan;
  if (!layout.chunked) {
    // Compressor 1: one stream from the first point on, no table.
    plan.chunks.push_back(
        {data.offset_to_points, data.data_limit - data.offset_to_points, data.point_count, 0});
    return plan;
  }
  if (data.data_limit < data.offset_to_points + 8) {
    throw InputError(path, byte_at(data.offset_to_points),
                     "truncated: the point data ends before the chunk table offset");
  }
  const std::uint64_t chunks_begin = data.offset_to_points + 8;
  TableResult table = read_table(data, layout, chunks_begin);
  if (!table.contradiction.empty()) throw InputError(path, "chunk table", table.contradiction);
  if (table.problem.empty()) {
    if (layout.layered) check_held_points(path, data, layout, table.chunks);
    fit_to_count(path, table.chunks, data.point_count);
    plan.chunks = std::move(table.chunks);
    plan.data_end = table.table_offset;
    return plan;
  }

  // No usable table: the chunks lie between the first one and the table (when its offset is
  // plausible) or the end of the point data.
  const std::uint64_t end =
      table.table_offset > chunks_begin ? table.table_offset : data.data_limit;
  plan.data_end = end;
  if (layout.layered) {
    warnings.push_back(path + ": the chunk table cannot be used (" + table.problem +
                       "); finding the chunks from their headers");
    plan.chunks = walk_chunks(path, data, layout, chunks_begin, end);
    fit_to_count(path, plan.chunks, data.point_count);
    return plan;
  }
  if (layout.variable_chunks) {
    throw InputError(
        path, "chunk table",
        table.problem + "; its chunks have variable sizes, which only the table gives");
  }
  warnings.push_back(path + ": the chunk table cannot be used (" + table.problem +
                     "); decoding the chunks one after the other, on one thread");
  const std::uint64_t chunk_size = layout.chunk_size;
  const std::uint64_t count = (data.point_count + chunk_size - 1) / chunk_size;
  if (count > (end - chunks_begin) / min_chunk_bytes(layout)) {
    throw InputError(path, "point data",
                     "the header announces " + count_text(data.point_count) +
                         " points, more than " + count_text(end - chunks_begin) +
                         " bytes of chunks of " + count_text(chunk_size) + " can hold");
  }
  plan.sequential = true;
  plan.exact_end = table.table_offset > chunks_begin;
  plan.chunks.resize(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    plan.chunks[i].first_point = i * chunk_size;
    plan.chunks[i].points = std::min(chunk_size, data.point_count - i * chunk_size);
  }
  plan.chunks[0].offset = chunks_begin;
  return plan;
}

}  // namespace tincdt::io::laz
