// Unaligned little-endian fields of a file held as bytes (LAS/LAZ headers, VLRs, records), for
// the tests and the benchmark tools that read or edit them. Standard library only, so that tools
// outside the test targets can include it; little-endian hosts only, as the readers.
#pragma once

#include <bit>
#include <cstddef>
#include <cstring>
#include <string>

namespace tincdt::test {

static_assert(std::endian::native == std::endian::little,
              "the test byte fields are loaded and stored with memcpy");

template <typename T>
T get(const std::string& bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

template <typename T>
void put(std::string& bytes, std::size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
}

}  // namespace tincdt::test
