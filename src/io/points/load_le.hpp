// Unaligned little-endian loads of LAS/LAZ header and record fields: one definition for the
// LAS reader, the header summary and the LAZ decoder, which all read the same byte layouts.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace tincdt::io {

static_assert(std::endian::native == std::endian::little,
              "LAS/LAZ fields are little-endian and loaded with memcpy");

template <typename T>
T load_le(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace tincdt::io
