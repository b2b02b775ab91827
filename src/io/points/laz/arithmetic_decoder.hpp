// The LAZ arithmetic decoder (LAZ specification 1.4; A. Said's FastAC coder): a 32-bit interval
// [0, length) that each decoded symbol narrows to its sub-interval, renormalised a byte at a time
// once shorter than 2^24. It reads one contiguous byte range (a chunk, or one layer of a chunk)
// and never reads outside it: bytes past the end decode as zeros and are counted, so a caller
// can tell "the data ended early" from a clean finish.
//
// The encoder ends its stream with enough padding that a decoder consumes exactly the bytes it
// was given; consumed() is therefore where the next stream starts when no chunk table says so.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>

#include "io/points/laz/models.hpp"

namespace tincdt::io::laz {

// The coder calls sit in every inner loop: inlined, their branches specialise per call site.
#define TINCDT_LAZ_INLINE [[gnu::always_inline]] inline

class ArithmeticDecoder {
 public:
  static constexpr std::uint32_t kMinLength = 1u << 24;  // renormalise below this

  ArithmeticDecoder() = default;
  ArithmeticDecoder(const std::uint8_t* data, std::size_t size) { init(data, size); }

  // Starts decoding [data, data + size); its first four bytes are the initial value.
  void init(const std::uint8_t* data, std::size_t size) {
    data_ = data;
    size_ = size;
    position_ = 0;
    length_ = 0xFFFFFFFFu;
    value_ = 0;
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next_byte();
    // An encoder's value always lies below the interval length; this one cannot be decoded
    // (and would break the decoder's bounds on its lookups).
    invalid_ = value_ == 0xFFFFFFFFu;
  }

  // True once the decoder needed bytes beyond its range, or its data cannot be an encoder's.
  bool failed() const { return position_ > size_ || invalid_; }
  // Bytes read so far (more than the size once failed()).
  std::size_t consumed() const { return position_; }

  TINCDT_LAZ_INLINE std::uint32_t decode_bit(BitModel& model) {
    const std::uint32_t split = model.zero_probability() * (length_ >> BitModel::kProbabilityBits);
    std::uint32_t bit;
    if (value_ < split) {
      length_ = split;
      bit = 0;
    } else {
      value_ -= split;
      length_ -= split;
      bit = 1;
    }
    if (length_ < kMinLength) renormalize();
    model.count(bit);
    return bit;
  }

  TINCDT_LAZ_INLINE std::uint32_t decode_symbol(SymbolModel& model) {
    std::uint32_t low = 0;
    std::uint32_t high = length_;  // the last symbol's interval ends at the full length
    std::uint32_t symbol = 0;
    length_ >>= SymbolModel::kDistributionBits;  // one unit of the 15-bit distribution
    if (model.has_table()) {
      // The value's top bits pick a short run of candidates in the table; bisect that run.
      // Only a damaged stream has value >= length; capped, it decodes garbage instead of
      // reading past the table.
      const std::uint32_t scaled =
          std::min(value_ / length_, (1u << SymbolModel::kDistributionBits) - 1);
      const std::uint32_t t = scaled >> model.table_shift();
      symbol = model.table(t);
      std::uint32_t end = model.table(t + 1) + 1;
      while (end > symbol + 1) {  // conditional moves: the halves are unpredictable
        const std::uint32_t mid = (symbol + end) >> 1;
        const bool above = model.cumulative(mid) > scaled;
        end = above ? mid : end;
        symbol = above ? symbol : mid;
      }
      low = model.cumulative(symbol) * length_;
      if (symbol != model.last_symbol()) high = model.cumulative(symbol + 1) * length_;
    } else {
      // Few symbols: bisect the whole distribution with multiplications only.
      std::uint32_t end = model.symbols();
      std::uint32_t mid = end >> 1;
      do {
        const std::uint32_t start = model.cumulative(mid) * length_;
        const bool above = start > value_;
        end = above ? mid : end;
        high = above ? start : high;
        symbol = above ? symbol : mid;
        low = above ? low : start;
        mid = (symbol + end) >> 1;
      } while (mid != symbol);
    }
    value_ -= low;
    length_ = high - low;
    if (length_ < kMinLength) renormalize();
    model.count(symbol);
    return symbol;
  }

  // BITS (1 to 32) raw bits, equally likely.
  std::uint32_t read_bits(unsigned bits) {
    assert(bits >= 1 && bits <= 32);
    if (bits > 19) {
      const std::uint32_t low = read_short();
      return (read_bits(bits - 16) << 16) | low;
    }
    length_ >>= bits;
    const std::uint32_t value = value_ / length_;
    value_ -= length_ * value;
    if (length_ < kMinLength) renormalize();
    return value;
  }

  std::uint32_t read_short() {
    length_ >>= 16;
    const std::uint32_t value = value_ / length_;
    value_ -= length_ * value;
    if (length_ < kMinLength) renormalize();
    return value & 0xFFFFu;
  }

  // Low 16 bits first.
  std::uint32_t read_int() {
    const std::uint32_t low = read_short();
    return (read_short() << 16) | low;
  }

 private:
  TINCDT_LAZ_INLINE std::uint32_t next_byte() {
    const std::uint32_t byte = position_ < size_ ? data_[position_] : 0u;
    ++position_;
    return byte;
  }

  void renormalize() {
    do {
      value_ = (value_ << 8) | next_byte();
      length_ <<= 8;
    } while (length_ < kMinLength);
  }

  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t position_ = 0;
  std::uint32_t value_ = 0;
  std::uint32_t length_ = 0;
  bool invalid_ = false;
};

}  // namespace tincdt::io::laz
