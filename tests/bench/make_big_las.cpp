// Writes a large synthetic LAS 1.2 file (point format 1, EPSG:32632 as GeoTIFF keys) for the
// memory and scale benchmarks: N points uniform over a 10 km square at UTM magnitudes, z from
// a smooth terrain, streamed in blocks so the generator itself stays small.
//   make_big_las N OUT.las
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

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

double terrain(double u, double v) {  // metres, over the unit square
  return 300 + 150 * std::sin(8.2 * u) * std::cos(5.7 * v) + 80 * std::sin(19.5 * u + 14.5 * v);
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
  const std::array<std::uint16_t, 16> geokeys = {1,    1, 0, 3,     1024, 0, 1, 1,
                                                 3072, 0, 1, 32632, 3076, 0, 1, 9001};
  const std::uint32_t offset_to_points = 227 + 54 + sizeof(geokeys);
  std::vector<unsigned char> h;
  put_text(h, "LASF", 4);
  put<std::uint16_t>(h, 0);
  put<std::uint16_t>(h, 0);
  put_text(h, "", 16);
  put<std::uint8_t>(h, 1);
  put<std::uint8_t>(h, 2);
  put_text(h, "OTHER", 32);
  put_text(h, "tincdt make_big_las", 32);
  put<std::uint16_t>(h, 1);
  put<std::uint16_t>(h, 2026);
  put<std::uint16_t>(h, 227);
  put<std::uint32_t>(h, offset_to_points);
  put<std::uint32_t>(h, 1);
  put<std::uint8_t>(h, 1);
  put<std::uint16_t>(h, 28);
  put<std::uint32_t>(h, static_cast<std::uint32_t>(n));
  put<std::uint32_t>(h, static_cast<std::uint32_t>(n));
  for (int i = 0; i < 4; ++i) put<std::uint32_t>(h, 0);
  for (int i = 0; i < 3; ++i) put<double>(h, scale);
  put<double>(h, x0);
  put<double>(h, y0);
  put<double>(h, 0);
  for (double v : {x0 + side, x0, y0 + side, y0, 1000.0, -1000.0}) put<double>(h, v);
  put<std::uint16_t>(h, 0);
  put_text(h, "LASF_Projection", 16);
  put<std::uint16_t>(h, 34735);
  put<std::uint16_t>(h, sizeof(geokeys));
  put_text(h, "GeoTIFF GeoKeyDirectoryTag", 32);
  for (std::uint16_t k : geokeys) put<std::uint16_t>(h, k);
  std::fwrite(h.data(), 1, h.size(), f);

  std::uint64_t state = 20261121;
  auto next = [&state] {  // SplitMix64
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  std::vector<unsigned char> block;
  block.reserve(28 << 16);
  for (std::uint64_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(next() >> 11) * 0x1p-53;
    const double v = static_cast<double>(next() >> 11) * 0x1p-53;
    put<std::int32_t>(block, static_cast<std::int32_t>(std::lround(u * side / scale)));
    put<std::int32_t>(block, static_cast<std::int32_t>(std::lround(v * side / scale)));
    put<std::int32_t>(block, static_cast<std::int32_t>(std::lround(terrain(u, v) / scale)));
    put<std::uint16_t>(block, 100);
    put<std::uint8_t>(block, 0x09);  // return 1 of 1
    put<std::uint8_t>(block, 2);     // ground
    put<std::int8_t>(block, 0);
    put<std::uint8_t>(block, 0);
    put<std::uint16_t>(block, 1);
    put<double>(block, static_cast<double>(i));
    if (block.size() >= (28u << 16) || i + 1 == n) {
      if (std::fwrite(block.data(), 1, block.size(), f) != block.size()) return 1;
      block.clear();
    }
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
