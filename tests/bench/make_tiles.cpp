// Writes a tiling of synthetic LiDAR-like LAS files for the tiled-job benchmarks (a billion
// points as 100 tiles of 10M): COLS x ROWS files of POINTS points each, tile (c, r) covering [x0 +
// c * SIDE, x0 + (c + 1) * SIDE) x [y0 + r * SIDE, ...) in WGS 84 / UTM 32N, x0 = 500000, y0 =
// 4000000. Points are uniform, their coordinates whole centimetres (scale 0.01), z a smooth terrain
// over the whole area plus centimetre noise; LAS 1.2, point format 0 (20 bytes), class 2, header
// bounds exact. Each tile has its own seed: any subset of tiles can be written at once (one process
// per core), and the same arguments give the same bytes.
//   make_tiles COLS ROWS POINTS SIDE OUT_DIR [FIRST [LAST]]   (tiles FIRST..LAST, row-major)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "support/splitmix.hpp"

namespace {

constexpr double kScale = 0.01, kX0 = 500000, kY0 = 4000000;

template <class T>
void put(std::vector<unsigned char>& out, T value) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(&value);  // little-endian host
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

void put_text(std::vector<unsigned char>& out, const char* text, std::size_t width) {
  const std::size_t n = std::strlen(text);
  for (std::size_t i = 0; i < width; ++i)
    out.push_back(i < n ? static_cast<unsigned char>(text[i]) : 0);
}

using tincdt::test::SplitMix64;

// Metres, continuous over the whole tiling: hills of a few km, ridges of a few hundred m.
double terrain(double x, double y) {
  const double u = x - kX0, v = y - kY0;
  return 400 + 120 * std::sin(u / 1700) * std::cos(v / 1300) + 25 * std::sin((u + 2 * v) / 310) +
         6 * std::cos(u / 97) * std::sin(v / 83);
}

bool write_tile(const std::string& path, int col, int row, std::uint64_t n, double side) {
  SplitMix64 rng{0x7469636474696c65ULL ^ (static_cast<std::uint64_t>(col) << 32) ^
                 static_cast<std::uint64_t>(row)};
  // Integer coordinates (centimetres from the offset) inside the tile's half-open box.
  const auto x_lo = static_cast<std::int64_t>(std::llround(col * side / kScale));
  const auto y_lo = static_cast<std::int64_t>(std::llround(row * side / kScale));
  const auto cells = static_cast<std::int64_t>(std::llround(side / kScale));
  std::vector<std::array<std::int32_t, 3>> pts(n);
  std::array<std::int32_t, 3> lo{INT32_MAX, INT32_MAX, INT32_MAX},
      hi{INT32_MIN, INT32_MIN, INT32_MIN};
  for (auto& p : pts) {
    const auto xi = x_lo + static_cast<std::int64_t>(rng.unit() * static_cast<double>(cells));
    const auto yi = y_lo + static_cast<std::int64_t>(rng.unit() * static_cast<double>(cells));
    const double noise = (rng.unit() + rng.unit() + rng.unit() - 1.5) * 0.05;
    const double z =
        terrain(kX0 + static_cast<double>(xi) * kScale, kY0 + static_cast<double>(yi) * kScale) +
        noise;
    p = {static_cast<std::int32_t>(xi), static_cast<std::int32_t>(yi),
         static_cast<std::int32_t>(std::lround(z / kScale))};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  const std::array<std::uint16_t, 16> geokeys = {1,    1, 0, 3,     1024, 0, 1, 1,
                                                 3072, 0, 1, 32632, 3076, 0, 1, 9001};
  const std::uint32_t offset_to_points = 227 + 54 + sizeof(geokeys);
  std::vector<unsigned char> h;
  put_text(h, "LASF", 4);
  put<std::uint16_t>(h, 0);  // file source id
  put<std::uint16_t>(h, 0);  // global encoding
  put_text(h, "", 16);       // project id
  put<std::uint8_t>(h, 1);
  put<std::uint8_t>(h, 2);
  put_text(h, "OTHER", 32);
  put_text(h, "tincdt make_tiles", 32);
  put<std::uint16_t>(h, 1);     // creation day
  put<std::uint16_t>(h, 2026);  // creation year
  put<std::uint16_t>(h, 227);
  put<std::uint32_t>(h, offset_to_points);
  put<std::uint32_t>(h, 1);   // VLRs
  put<std::uint8_t>(h, 0);    // point format 0
  put<std::uint16_t>(h, 20);  // record length
  put<std::uint32_t>(h, static_cast<std::uint32_t>(n));
  put<std::uint32_t>(h, static_cast<std::uint32_t>(n));  // by return: all first of one
  for (int i = 0; i < 4; ++i) put<std::uint32_t>(h, 0);
  for (int i = 0; i < 3; ++i) put<double>(h, kScale);
  put<double>(h, kX0);
  put<double>(h, kY0);
  put<double>(h, 0);
  for (const double v : {kX0 + hi[0] * kScale, kX0 + lo[0] * kScale, kY0 + hi[1] * kScale,
                         kY0 + lo[1] * kScale, hi[2] * kScale, lo[2] * kScale})
    put<double>(h, v);
  put<std::uint16_t>(h, 0);
  put_text(h, "LASF_Projection", 16);
  put<std::uint16_t>(h, 34735);
  put<std::uint16_t>(h, sizeof(geokeys));
  put_text(h, "GeoTIFF GeoKeyDirectoryTag", 32);
  for (const std::uint16_t k : geokeys) put<std::uint16_t>(h, k);

  const std::string temp = path + ".part";
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f) return false;
  bool ok = std::fwrite(h.data(), 1, h.size(), f) == h.size();
  std::vector<unsigned char> block;
  block.reserve(20 << 16);
  for (std::size_t i = 0; i < pts.size() && ok; ++i) {
    put<std::int32_t>(block, pts[i][0]);
    put<std::int32_t>(block, pts[i][1]);
    put<std::int32_t>(block, pts[i][2]);
    put<std::uint16_t>(block, 100);
    put<std::uint8_t>(block, 0x09);  // return 1 of 1
    put<std::uint8_t>(block, 2);     // ground
    put<std::int8_t>(block, 0);
    put<std::uint8_t>(block, 0);
    put<std::uint16_t>(block, 1);
    if (block.size() >= (20u << 16) || i + 1 == pts.size()) {
      ok = std::fwrite(block.data(), 1, block.size(), f) == block.size();
      block.clear();
    }
  }
  ok = std::fclose(f) == 0 && ok;
  return ok && std::rename(temp.c_str(), path.c_str()) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6 || argc > 8) {
    std::fprintf(stderr, "usage: %s COLS ROWS POINTS SIDE OUT_DIR [FIRST [LAST]]\n", argv[0]);
    return 2;
  }
  const int cols = std::atoi(argv[1]), rows = std::atoi(argv[2]);
  const std::uint64_t n = std::strtoull(argv[3], nullptr, 10);
  const double side = std::strtod(argv[4], nullptr);
  const std::string dir = argv[5];
  const int count = cols * rows;
  const int first = argc > 6 ? std::atoi(argv[6]) : 0;
  const int last = argc > 7 ? std::atoi(argv[7]) : count - 1;
  if (cols < 1 || rows < 1 || n == 0 || n > 0xffffffffULL || !(side > 0) || side / kScale > 2e9 ||
      first < 0 || last >= count || first > last) {
    std::fprintf(stderr, "%s: bad arguments\n", argv[0]);
    return 2;
  }
  for (int t = first; t <= last; ++t) {
    const int col = t % cols, row = t / cols;
    char name[64];
    std::snprintf(name, sizeof name, "/tile_%03d_%03d.las", col, row);
    if (!write_tile(dir + name, col, row, n, side)) {
      std::fprintf(stderr, "%s: cannot write %s%s\n", argv[0], dir.c_str(), name);
      return 1;
    }
  }
  return 0;
}
