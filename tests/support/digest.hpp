// A digest of bytes for tests that pin a file's exact contents without storing it.
#pragma once

#include <cstdint>
#include <string>

namespace tincdt::test {

// FNV-1a, 64 bits: a fixed function of the bytes, the same on every machine.
inline std::uint64_t digest(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace tincdt::test
