// Memory hints for the large flat arrays (Linux; elsewhere they do nothing).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tincdt {

// Asks for transparent huge pages on the unused capacity of a large vector about to be filled.
// Walks and flips touch a few hundred MB almost at random for tens of millions of points: with
// 2 MB pages the TLB covers it, and the kernel zero-fills 2 MB per page fault instead of 4 kB.
// Only a hint (THP may be off).
template <typename T>
void advise_huge_pages(std::vector<T>& v) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(v.data() + v.size());
  const auto end = reinterpret_cast<std::uintptr_t>(v.data() + v.capacity());
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge;
  const std::uintptr_t last = end / kHuge * kHuge;
  if (first >= last) return;
  (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)v;
#endif
}

// Frees a vector's memory now. (`v = {}` would not: it assigns an empty initializer list and
// keeps the capacity.)
template <typename T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

}  // namespace tincdt
