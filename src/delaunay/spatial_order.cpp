#include "delaunay/spatial_order.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/memory.hpp"
#include "core/parallel.hpp"
#include "core/radix_sort.hpp"

namespace tincdt::delaunay {
namespace {

constexpr int kRoundBits = 4;  // 32-bit keys: round in the top 4 bits, Hilbert index below
constexpr std::uint32_t kMaxRound = (1u << kRoundBits) - 1;

std::uint64_t mix(std::uint64_t h) {  // splitmix64 finalizer: a fast, well-spread hash
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

// Round 0 is inserted last and holds ~7/8 of the points; round r holds ~7/8^(r+1).
std::uint32_t brio_round(double x, double y) {
  std::uint64_t h = point_hash(x, y);
  std::uint32_t r = 0;
  while ((h & 7) == 0 && r < kMaxRound) {
    h >>= 3;
    ++r;
  }
  return r;
}

// hilbert_index()'s curve two levels per step: a state (bit 0: x and y swapped, bit 1:
// complemented) and two bits of x and y give two base-4 digits and the next state.
struct HilbertTable {
  std::array<std::uint8_t, 64> step{};  // state << 4 | x bits << 2 | y bits -> state << 4 | digits
  constexpr HilbertTable() {
    for (unsigned state = 0; state < 4; ++state)
      for (unsigned xx = 0; xx < 4; ++xx)
        for (unsigned yy = 0; yy < 4; ++yy) {
          unsigned swapped = state & 1, complemented = state >> 1, digits = 0;
          for (int level = 1; level >= 0; --level) {
            const unsigned bx = (xx >> level) & 1, by = (yy >> level) & 1;
            const unsigned rx = (swapped ? by : bx) ^ complemented;
            const unsigned ry = (swapped ? bx : by) ^ complemented;
            digits = (digits << 2) | ((3 * rx) ^ ry);
            if (ry == 0) {
              swapped ^= 1;
              complemented ^= rx;
            }
          }
          step[state << 4 | xx << 2 | yy] =
              static_cast<std::uint8_t>((swapped | complemented << 1) << 4 | digits);
        }
  }
};
constexpr HilbertTable kHilbert;
static_assert(OrderKey::kHilbertBits % 2 == 0);

// NaN (an infinite extent times 0) and overflow land in a border cell.
std::uint32_t cell(double c) {
  constexpr std::uint32_t top = (1u << OrderKey::kHilbertBits) - 1;
  return c >= top ? top : (c > 0 ? static_cast<std::uint32_t>(c) : 0);
}

}  // namespace

std::uint64_t point_hash(double x, double y) {
  // Adding +0.0 turns -0.0 into 0.0 and changes nothing else, so equal points hash alike.
  return mix(std::bit_cast<std::uint64_t>(x + 0.0) ^ mix(std::bit_cast<std::uint64_t>(y + 0.0)));
}

std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y, int bits) {
  std::uint32_t d = 0;
  for (std::uint32_t s = 1u << (bits - 1); s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1 : 0;
    const std::uint32_t ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {  // rotate the quadrant so the curve stays continuous
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

OrderKey::OrderKey(const BBox& box) : box_(box) {
  const double extent = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  const double cells = static_cast<double>(1u << kHilbertBits);
  scale_ = extent > 0 && std::isfinite(extent) ? (cells - 0.5) / extent : 0.0;
}

std::uint32_t OrderKey::hilbert_key(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0, state = 0;
  for (int shift = kHilbertBits - 2; shift >= 0; shift -= 2) {
    const std::uint32_t v =
        kHilbert.step[state << 4 | ((x >> shift) & 3) << 2 | ((y >> shift) & 3)];
    d = d << 4 | (v & 15);
    state = v >> 4;
  }
  return d;
}

std::uint32_t OrderKey::operator()(const Point3& p) const {
  const std::uint32_t cx = cell((p.x - box_.min_x) * scale_);
  const std::uint32_t cy = cell((p.y - box_.min_y) * scale_);
  const std::uint32_t round = kMaxRound - brio_round(p.x, p.y);  // coarse rounds first
  return (round << (2 * kHilbertBits)) | hilbert_key(cx, cy);
}

void sort_by_key_then_xyz(const std::vector<Point3>& points, std::uint64_t* items,
                          std::uint64_t* buffer, std::size_t n) {
  radix_sort_by_key(items, buffer, n);
  auto by_xyz = [&](std::uint64_t a, std::uint64_t b) {
    const Point3& p = points[static_cast<std::uint32_t>(a)];
    const Point3& q = points[static_cast<std::uint32_t>(b)];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return static_cast<std::uint32_t>(a) < static_cast<std::uint32_t>(b);
  };
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && (items[j] >> 32) == (items[i] >> 32)) ++j;
    if (j - i > 1) std::sort(items + i, items + j, by_xyz);
    i = j;
  }
}

std::vector<std::uint32_t> insertion_order(const std::vector<Point3>& points, const BBox& box,
                                           unsigned threads) {
  const std::size_t n = points.size();
  const OrderKey key(box);
  auto items = large_vector<std::uint64_t>(n);
  parallel_chunks(threads, n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) items[i] = std::uint64_t{key(points[i])} << 32 | i;
  });
  {
    auto buffer = large_vector<std::uint64_t>(n);
    sort_by_key_then_xyz(points, items.data(), buffer.data(), n);
  }
  auto order = large_vector<std::uint32_t>(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(items[i]);
  return order;
}

}  // namespace tincdt::delaunay
