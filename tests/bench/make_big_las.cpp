// Writes a large synthetic LAS 1.2 file (point format 1, EPSG:32632 as GeoTIFF keys) for the
// memory and scale benchmarks: N points uniform over a 10 km square at UTM magnitudes, z from
// a smooth terrain, streamed in blocks so the generator itself stays small. The bytes come from
// the project's synthetic-LAS writer (tests/support/las_writer.hpp).
//   make_big_las N OUT.las
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "support/las_writer.hpp"

namespace {

namespace las = tincdt::test::las;

double terrain(double u, double v) {  // metres, over the unit square
  return 300 + 150 * std::sin(8.2 * u) * std::cos(5.7 * v) + 80 * std::sin(19.5 * u + 14.5 * v);
}

bool write(std::FILE* f, const std::string& bytes) {
  return std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s N OUT.las\n", argv[0]);
    return 2;
  }
  const std::uint64_t n = std::strtoull(argv[1], nullptr, 10);
  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f || n == 0 || n > 0xffffffffULL) {
    std::fprintf(stderr, "%s: cannot write %s points to %s\n", argv[0], argv[1], argv[2]);
    return 1;
  }
  const double scale = 0.01, x0 = 500000, y0 = 4000000, side = 10000;
  las::Header h;
  h.point_format = 1;
  h.software = "tincdt make_big_las";
  h.year = 2026;
  h.scale = {scale, scale, scale};
  h.offset = {x0, y0, 0};
  h.geokeys = {{1024, 0, 1, 1}, {3072, 0, 1, 32632}, {3076, 0, 1, 9001}};  // projected, metres
  // Known before the points are drawn: all single returns, inside the square, |z| < 1000.
  h.count = static_cast<std::uint32_t>(n);
  h.by_return = {static_cast<std::uint32_t>(n), 0, 0, 0, 0};
  h.min = {x0, y0, -1000};
  h.max = {x0 + side, y0 + side, 1000};
  if (!write(f, las::header_bytes(h))) return 1;

  std::uint64_t state = 20261121;
  auto next = [&state] {  // SplitMix64
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  const std::size_t block_bytes = std::size_t{las::record_length(1)} << 16;
  std::string block;
  block.reserve(block_bytes);
  las::Record r;
  r.intensity = 100;
  r.classification = 2;  // ground
  r.point_source_id = 1;
  for (std::uint64_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(next() >> 11) * 0x1p-53;
    const double v = static_cast<double>(next() >> 11) * 0x1p-53;
    r.x = static_cast<std::int32_t>(std::lround(u * side / scale));
    r.y = static_cast<std::int32_t>(std::lround(v * side / scale));
    r.z = static_cast<std::int32_t>(std::lround(terrain(u, v) / scale));
    r.gps_time = static_cast<double>(i);
    las::append_record(block, r, h.point_format);
    if (block.size() >= block_bytes || i + 1 == n) {
      if (!write(f, block)) return 1;
      block.clear();
    }
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
