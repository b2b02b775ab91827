// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", 2014):
// tiny, well mixed and fully specified, so synthetic data made from a seed is the same bytes on
// every machine. Header-only and standard library only, for the sample generator and the
// benchmark data writers as much as for the tests.
#pragma once

#include <cstdint>

namespace tincdt::test {

struct SplitMix64 {
  std::uint64_t state;

  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1): the top 53 bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }
};

}  // namespace tincdt::test
