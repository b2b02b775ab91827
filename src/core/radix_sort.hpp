// Sorting millions of 64-bit items by the key in their upper half, where a comparison sort would
// dominate: the spatial order of the Delaunay stage, a web-terrain tile's grid places.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace tincdt {

// Sorts ITEMS[0, N), each (key << 32 | index), by key, with BUFFER (N items) as scratch: an LSD
// radix sort, stable, so items of equal keys keep their order.
inline void radix_sort_by_key(std::uint64_t* items, std::uint64_t* buffer, std::size_t n) {
  constexpr int kPasses = 3;
  constexpr std::array<int, kPasses> kShift = {32, 43, 54};
  constexpr std::array<int, kPasses> kWidth = {11, 11, 10};
  std::array<std::vector<std::size_t>, kPasses> count;
  for (int p = 0; p < kPasses; ++p) count[p].assign((std::size_t{1} << kWidth[p]) + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int p = 0; p < kPasses; ++p)
      ++count[p][((items[i] >> kShift[p]) & ((1u << kWidth[p]) - 1)) + 1];
  std::uint64_t* src = items;
  std::uint64_t* dst = buffer;
  for (int p = 0; p < kPasses; ++p) {
    auto& offset = count[p];
    for (std::size_t i = 1; i < offset.size(); ++i) offset[i] += offset[i - 1];
    const std::uint64_t mask = (1u << kWidth[p]) - 1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t v = src[i];
      dst[offset[(v >> kShift[p]) & mask]++] = v;
    }
    std::swap(src, dst);
  }
  if (src != items) std::memcpy(items, src, n * sizeof(std::uint64_t));
}

}  // namespace tincdt
