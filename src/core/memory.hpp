// Memory hints for the large flat arrays (Linux; elsewhere they do nothing).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tincdt {

// Asks for transparent huge pages on the whole 2 MB pages inside [begin, begin + bytes), memory
// about to be filled. Walks and flips touch a few hundred MB almost at random for tens of millions
// of points: with 2 MB pages the TLB covers it, and the kernel zero-fills 2 MB per page fault
// instead of 4 kB (in a virtual machine, where a fault costs several microseconds, the first touch
// of 1 GB of 4 kB pages takes seconds). Only a hint (THP may be off).
inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

inline void advise_huge_pages([[maybe_unused]] void* begin, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto from = reinterpret_cast<std::uintptr_t>(begin);
  const std::uintptr_t first = (from + kHugePage - 1) / kHugePage * kHugePage;
  const std::uintptr_t last = (from + bytes) / kHugePage * kHugePage;
  if (first >= last) return;
  (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}

// The same for the unused capacity of a large vector.
template <typename T>
void advise_huge_pages(std::vector<T>& v) {
  advise_huge_pages(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(T));
}

// A vector of N value-initialized elements, on huge pages where it can be.
template <typename T>
std::vector<T> large_vector(std::size_t n) {
  std::vector<T> v;
  v.reserve(n);
  advise_huge_pages(v);
  v.resize(n);
  return v;
}

// Frees a vector's memory now. (`v = {}` would not: it assigns an empty initializer list and
// keeps the capacity.)
template <typename T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

}  // namespace tincdt
