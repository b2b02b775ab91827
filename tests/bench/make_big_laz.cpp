// Writes a large LAZ file (and, given the input's LAS twin, its large LAS twin) for the LAZ
// benchmarks, without a LAZ encoder: LAZ chunks are independent and each starts with its first
// point stored raw, every later X and Y coded as a difference, so a copy of a chunk whose raw
// first point is moved by (dx, dy) decodes to the same points moved by (dx, dy). The full chunks
// of IN.laz are copied COPIES times onto a grid of tiles side by side, and a new chunk table is
// written (the only part that needs the arithmetic encoder, the tests' one).
//   make_big_laz IN.laz COPIES OUT.laz [IN_TWIN.las OUT_TWIN.las]
// EVLRs are left out; the header's point count and bounds are updated (the per-return counts
// are not: nothing here reads them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/points/laz/chunk_table.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/laz_test_encoder.hpp"
#include "support/byte_fields.hpp"

namespace {

using tincdt::test::get;
using tincdt::test::put;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw tincdt::InputError(path, "", "cannot open");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Tiling {
  std::uint64_t copies;
  std::uint64_t columns;
  std::int32_t step_x;  // in record units
  std::int32_t step_y;
  std::int32_t dx(std::uint64_t k) const { return static_cast<std::int32_t>(k % columns) * step_x; }
  std::int32_t dy(std::uint64_t k) const { return static_cast<std::int32_t>(k / columns) * step_y; }
};

// The header of the copy: COUNT points, bounds grown to the tiles, no EVLRs.
void fix_header(std::string& h, std::uint64_t count, const Tiling& t) {
  const bool v14 = h[25] >= 4;
  const unsigned format = static_cast<unsigned char>(h[104]) & 0x3Fu;
  put<std::uint32_t>(
      h, 107, (v14 && format >= 6) || count > 0xFFFFFFFFu ? 0 : static_cast<std::uint32_t>(count));
  const double sx = get<double>(h, 131);
  const double sy = get<double>(h, 139);
  const double rows = std::ceil(static_cast<double>(t.copies) / static_cast<double>(t.columns));
  put<double>(h, 179, get<double>(h, 179) + sx * t.step_x * static_cast<double>(t.columns - 1));
  put<double>(h, 195, get<double>(h, 195) + sy * t.step_y * (rows - 1));
  if (v14 && h.size() >= 255) {
    put<std::uint64_t>(h, 235, 0);  // no EVLRs
    put<std::uint32_t>(h, 243, 0);
    put<std::uint64_t>(h, 247, count);
  }
}

void write(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw tincdt::Error(path + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 6) {
    std::fprintf(stderr, "usage: %s IN.laz COPIES OUT.laz [IN_TWIN.las OUT_TWIN.las]\n", argv[0]);
    return 2;
  }
  try {
    const std::string in_path = argv[1];
    const std::uint64_t copies = std::strtoull(argv[2], nullptr, 10);
    const std::string laz = slurp(in_path);
    const auto* data = reinterpret_cast<const std::uint8_t*>(laz.data());
    std::vector<std::string> warnings;
    const tincdt::io::laz::LazSource src =
        tincdt::io::laz::open_laz(in_path, data, laz.size(), warnings);
    const tincdt::io::laz::LaszipVlr vlr =
        tincdt::io::laz::parse_laszip_vlr(in_path, src.laszip_vlr, src.laszip_vlr_size);
    const tincdt::io::laz::PointLayout layout =
        tincdt::io::laz::check_layout(in_path, vlr, src.point_format, src.record_length);
    if (layout.variable_chunks || !layout.chunked || copies == 0) {
      throw tincdt::Error(in_path + ": needs fixed-size chunks, and COPIES >= 1");
    }
    tincdt::io::laz::PointData pd;
    pd.file = data;
    pd.file_size = laz.size();
    pd.offset_to_points = src.offset_to_points;
    pd.point_count = src.point_count;
    pd.data_limit = src.data_limit;
    const tincdt::io::laz::ChunkPlan plan =
        tincdt::io::laz::plan_chunks(in_path, pd, layout, warnings);
    std::vector<tincdt::io::laz::ChunkEntry> full;
    for (const auto& c : plan.chunks) {
      if (c.points == layout.chunk_size) full.push_back(c);
    }
    if (full.empty() || plan.sequential) throw tincdt::Error(in_path + ": no full chunk to copy");

    Tiling t{copies, static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(copies)))),
             0, 0};
    t.step_x = static_cast<std::int32_t>(
        std::ceil((get<double>(laz, 179) - get<double>(laz, 187)) / get<double>(laz, 131)) + 1);
    t.step_y = static_cast<std::int32_t>(
        std::ceil((get<double>(laz, 195) - get<double>(laz, 203)) / get<double>(laz, 139)) + 1);
    const std::uint64_t per_copy = full.size() * std::uint64_t{layout.chunk_size};
    const std::uint64_t count = per_copy * copies;

    std::string out = laz.substr(0, static_cast<std::size_t>(src.offset_to_points));
    fix_header(out, count, t);
    out.append(8, '\0');
    std::vector<std::uint32_t> points;
    std::vector<std::uint32_t> bytes;
    for (std::uint64_t k = 0; k < copies; ++k) {
      for (const auto& c : full) {
        std::string chunk =
            laz.substr(static_cast<std::size_t>(c.offset), static_cast<std::size_t>(c.size));
        put<std::int32_t>(chunk, 0, get<std::int32_t>(chunk, 0) + t.dx(k));
        put<std::int32_t>(chunk, 4, get<std::int32_t>(chunk, 4) + t.dy(k));
        out += chunk;
        points.push_back(layout.chunk_size);
        bytes.push_back(static_cast<std::uint32_t>(c.size));
      }
    }
    put<std::int64_t>(out, static_cast<std::size_t>(src.offset_to_points),
                      static_cast<std::int64_t>(out.size()));
    const std::vector<std::uint8_t> table = tincdt::test::encode_chunk_table(points, bytes, false);
    out.append(reinterpret_cast<const char*>(table.data()), table.size());
    write(argv[3], out);
    std::fprintf(stderr, "%s: %llu points in %zu chunks, %zu bytes\n", argv[3],
                 static_cast<unsigned long long>(count), bytes.size(), out.size());

    if (argc == 6) {
      const std::string las = slurp(argv[4]);
      const auto offset = get<std::uint32_t>(las, 96);
      const std::size_t record = get<std::uint16_t>(las, 105);
      if (record != src.record_length || las.size() < offset + per_copy * record) {
        throw tincdt::Error(std::string(argv[4]) + ": not the twin of " + in_path);
      }
      std::string twin = las.substr(0, offset);
      fix_header(twin, count, t);
      twin.reserve(twin.size() + count * record);
      for (std::uint64_t k = 0; k < copies; ++k) {
        std::string block = las.substr(offset, static_cast<std::size_t>(per_copy * record));
        for (std::size_t i = 0; i < block.size(); i += record) {
          put<std::int32_t>(block, i, get<std::int32_t>(block, i) + t.dx(k));
          put<std::int32_t>(block, i + 4, get<std::int32_t>(block, i + 4) + t.dy(k));
        }
        twin += block;
      }
      write(argv[5], twin);
      std::fprintf(stderr, "%s: its LAS twin, %zu bytes\n", argv[5], twin.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_big_laz: %s\n", e.what());
    return 1;
  }
  return 0;
}
