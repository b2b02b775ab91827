#include "delaunay/spatial_order.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "core/parallel.hpp"

namespace tincdt::delaunay {
namespace {

constexpr int kHilbertBits = 14;  // per axis: 2^28 cells, far more than points per round
constexpr int kRoundBits = 4;     // 32-bit keys: round in the top 4 bits, Hilbert index below
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
  std::uint64_t h = mix(std::bit_cast<std::uint64_t>(x) ^ mix(std::bit_cast<std::uint64_t>(y)));
  std::uint32_t r = 0;
  while ((h & 7) == 0 && r < kMaxRound) {
    h >>= 3;
    ++r;
  }
  return r;
}

// LSD radix sort of (key << 32 | index) by key: stable, so equal keys keep index order.
void radix_sort_by_key(std::vector<std::uint64_t>& items) {
  constexpr int kPasses = 3;
  constexpr std::array<int, kPasses> kShift = {32, 43, 54};
  constexpr std::array<int, kPasses> kWidth = {11, 11, 10};
  std::vector<std::uint64_t> buffer(items.size());
  std::array<std::vector<std::size_t>, kPasses> count;
  for (int p = 0; p < kPasses; ++p) count[p].assign((std::size_t{1} << kWidth[p]) + 1, 0);
  for (std::uint64_t v : items)
    for (int p = 0; p < kPasses; ++p) ++count[p][((v >> kShift[p]) & ((1u << kWidth[p]) - 1)) + 1];
  std::uint64_t* src = items.data();
  std::uint64_t* dst = buffer.data();
  for (int p = 0; p < kPasses; ++p) {
    auto& offset = count[p];
    for (std::size_t i = 1; i < offset.size(); ++i) offset[i] += offset[i - 1];
    const std::uint64_t mask = (1u << kWidth[p]) - 1;
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::uint64_t v = src[i];
      dst[offset[(v >> kShift[p]) & mask]++] = v;
    }
    std::swap(src, dst);
  }
  if (src != items.data()) std::memcpy(items.data(), src, items.size() * sizeof(std::uint64_t));
}

}  // namespace

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

std::vector<std::uint32_t> insertion_order(const std::vector<Point3>& points, const BBox& box) {
  const std::size_t n = points.size();
  const double extent = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  const double cells = static_cast<double>(1u << kHilbertBits);
  const double scale = extent > 0 ? (cells - 0.5) / extent : 0.0;
  const std::uint32_t top = (1u << kHilbertBits) - 1;

  std::vector<std::uint64_t> items(n);
  parallel_chunks(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Point3& p = points[i];
      const auto cx = std::min(top, static_cast<std::uint32_t>((p.x - box.min_x) * scale));
      const auto cy = std::min(top, static_cast<std::uint32_t>((p.y - box.min_y) * scale));
      const std::uint32_t round = kMaxRound - brio_round(p.x, p.y);  // coarse rounds first
      const std::uint32_t key = (round << (2 * kHilbertBits)) | hilbert_index(cx, cy, kHilbertBits);
      items[i] = (std::uint64_t{key} << 32) | i;
    }
  });
  radix_sort_by_key(items);

  // Within a run of equal keys, order by x, y so that equal points are adjacent.
  auto by_xy = [&](std::uint64_t a, std::uint64_t b) {
    const Point3& p = points[static_cast<std::uint32_t>(a)];
    const Point3& q = points[static_cast<std::uint32_t>(b)];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return static_cast<std::uint32_t>(a) < static_cast<std::uint32_t>(b);
  };
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && (items[j] >> 32) == (items[i] >> 32)) ++j;
    if (j - i > 1)
      std::sort(items.begin() + static_cast<std::ptrdiff_t>(i),
                items.begin() + static_cast<std::ptrdiff_t>(j), by_xy);
    i = j;
  }

  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(items[i]);
  return order;
}

}  // namespace tincdt::delaunay
