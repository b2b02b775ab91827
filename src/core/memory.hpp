// Memory for the large flat arrays: huge-page hints (Linux; elsewhere they do nothing) and scratch
// arrays mapped directly.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
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

// Scratch memory for the big temporary arrays, mapped and unmapped directly so that it goes back
// to the system when released: malloc keeps freed blocks below its mmap threshold, which it
// raises after large frees, and they would then add to the peak memory.
template <class T>
class ScratchArray {
 public:
  explicit ScratchArray(std::size_t n) : size_(n) {
    if (n == 0) return;
#if defined(__unix__) || defined(__APPLE__)
    void* p =
        mmap(nullptr, n * sizeof(T), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    data_ = static_cast<T*>(p);
    advise_huge_pages(p, n * sizeof(T));
#else
    data_ = new T[n];
#endif
  }
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;
  ~ScratchArray() {
    release();
  }
  void release() {
    if (!data_) return;
#if defined(__unix__) || defined(__APPLE__)
    munmap(data_, size_ * sizeof(T));
#else
    delete[] data_;
#endif
    data_ = nullptr;
  }
  // Gives back the whole (huge) pages inside elements [begin, end), which must not be used again.
  void release(std::size_t begin, std::size_t end) {
    assert(begin <= end && end <= size_);
#if defined(__unix__) || defined(__APPLE__)
    if (!data_) return;
    const auto page = static_cast<std::uintptr_t>(kHugePage);
    const auto from = (reinterpret_cast<std::uintptr_t>(data_ + begin) + page - 1) & ~(page - 1);
    const auto to = reinterpret_cast<std::uintptr_t>(data_ + end) & ~(page - 1);
    if (from < to)
      munmap(reinterpret_cast<void*>(from), to - from);  // release() unmaps again: fine
#else
    (void)begin;
    (void)end;
#endif
  }
  T* data() const {
    return data_;
  }
  T& operator[](std::size_t i) const {
    return data_[i];
  }

 private:
  std::size_t size_;
  T* data_ = nullptr;
};

}  // namespace tincdt
