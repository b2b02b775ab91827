// One chunk handed to a chunk decoder, and how decoders report bad data inside it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"

namespace tincdt::io::laz {

// Raised inside a chunk decoder when the data cannot come from an encoder; the chunk loop turns
// it into an InputError that names the file, the chunk and the point.
class CorruptData : public std::exception {
 public:
  explicit CorruptData(const char* what) : what_(what) {}
  const char* what() const noexcept override { return what_; }

 private:
  const char* what_;
};

struct ChunkInput {
  const std::uint8_t* data = nullptr;  // the chunk's bytes, inside the mapped file
  std::size_t size = 0;                // as the chunk table says, or up to the end of the data
  std::uint64_t points = 0;
  // For messages only.
  const std::string* path = nullptr;
  std::size_t index = 0;          // chunk number, from 0
  std::uint64_t first_point = 0;  // file-wide index of the chunk's first point
  // The chunks' own names ("COPC node 2-1-3-0, byte 2706") when they are not the file's chunks
  // in order: points are then counted within the chunk.
  const std::vector<std::string>* names = nullptr;

  // "FILE: chunk 2, point 100017: WHAT" (point = file-wide index, from 0).
  InputError error(std::uint64_t point_in_chunk, const std::string& what) const {
    if (names != nullptr)
      return InputError(*path, (*names)[index] + ", point " + count_text(point_in_chunk), what);
    return InputError(
        *path, "chunk " + count_text(index) + ", point " + count_text(first_point + point_in_chunk),
        what);
  }
};

}  // namespace tincdt::io::laz
