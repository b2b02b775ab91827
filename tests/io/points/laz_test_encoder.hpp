// The encoding side of the LAZ arithmetic coder and integer compressor, for tests and bench tools
// only (tincdt writes no LAZ): round trips through the decoder, and chunk tables for files the
// tests build. Written from the same description as the decoder (FastAC: the interval base and
// length, carries propagated into the bytes already written); it shares the decoder's models, so
// both sides adapt identically.
#pragma once

#include <cstdint>
#include <vector>

#include "io/points/laz/models.hpp"

namespace tincdt::test {

using io::laz::BitModel;
using io::laz::SymbolModel;

class LazTestEncoder {
 public:
  static constexpr std::uint32_t kMinLength = 1u << 24;

  void encode_bit(BitModel& model, std::uint32_t bit) {
    const std::uint32_t split = model.zero_probability() * (length_ >> BitModel::kProbabilityBits);
    if (bit == 0) {
      length_ = split;
    } else {
      add_to_base(split);
      length_ -= split;
    }
    if (length_ < kMinLength) renormalize();
    model.count(bit);
  }

  void encode_symbol(SymbolModel& model, std::uint32_t symbol) {
    const std::uint32_t unit = length_ >> SymbolModel::kDistributionBits;
    const std::uint32_t low = model.cumulative(symbol) * unit;
    if (symbol == model.last_symbol()) {
      add_to_base(low);
      length_ -= low;  // the last interval runs to the end of the full length
    } else {
      add_to_base(low);
      length_ = model.cumulative(symbol + 1) * unit - low;
    }
    if (length_ < kMinLength) renormalize();
    model.count(symbol);
  }

  void write_bits(unsigned bits, std::uint32_t value) {
    if (bits > 19) {
      write_short(value & 0xFFFFu);
      value >>= 16;
      bits -= 16;
    }
    length_ >>= bits;
    add_to_base(value * length_);
    if (length_ < kMinLength) renormalize();
  }

  void write_short(std::uint32_t value) {
    length_ >>= 16;
    add_to_base(value * length_);
    if (length_ < kMinLength) renormalize();
  }

  void write_int(std::uint32_t value) {
    write_short(value & 0xFFFFu);
    write_short(value >> 16);
  }

  // Flushes the interval: afterwards the decoder reads exactly the bytes written.
  std::vector<std::uint8_t> finish() {
    bool three_zeros = true;
    if (length_ > 2 * kMinLength) {
      add_to_base(kMinLength);
      length_ = kMinLength >> 1;
    } else {
      add_to_base(kMinLength >> 1);
      length_ = kMinLength >> 9;
      three_zeros = false;
    }
    renormalize();
    bytes_.push_back(0);
    bytes_.push_back(0);
    if (three_zeros) bytes_.push_back(0);
    return std::move(bytes_);
  }

 private:
  void add_to_base(std::uint32_t x) {
    const std::uint32_t before = base_;
    base_ += x;
    if (base_ < before) {  // carry into the bytes already out
      std::size_t i = bytes_.size();
      while (i > 0 && bytes_[i - 1] == 0xFF) bytes_[--i] = 0;
      if (i > 0) ++bytes_[i - 1];
    }
  }

  void renormalize() {
    do {
      bytes_.push_back(static_cast<std::uint8_t>(base_ >> 24));
      base_ <<= 8;
      length_ <<= 8;
    } while (length_ < kMinLength);
  }

  std::uint32_t base_ = 0;
  std::uint32_t length_ = 0xFFFFFFFFu;
  std::vector<std::uint8_t> bytes_;
};

// The integer compressor's encoding side, mirroring io::laz::IntegerDecompressor.
class IntegerTestCompressor {
 public:
  IntegerTestCompressor(unsigned bits, unsigned contexts, unsigned bits_high = 8)
      : bits_(bits == 0 || bits > 32 ? 32 : bits), bits_high_(bits_high) {
    range_ = bits_ < 32 ? (1u << bits_) : 0u;
    k_models_.assign(contexts, SymbolModel(bits_ + 1));
    for (unsigned k = 1; k <= bits_; ++k) {
      correctors_.emplace_back(1u << (k <= bits_high_ ? k : bits_high_));
    }
  }

  void compress(LazTestEncoder& enc, std::int32_t prediction, std::int32_t real,
                unsigned context = 0) {
    std::int64_t c = std::int64_t{real} - prediction;
    if (bits_ < 32) {  // fold into [-range/2, range/2 - 1]
      const std::int64_t half = range_ / 2;
      if (c < -half) c += range_;
      if (c > half - 1) c -= range_;
    } else {
      c = static_cast<std::int32_t>(static_cast<std::uint32_t>(c));
    }
    write_corrector(enc, static_cast<std::int32_t>(c), k_models_[context]);
  }

 private:
  void write_corrector(LazTestEncoder& enc, std::int32_t c, SymbolModel& k_model) {
    // The smallest k with c in [-(2^k - 1), 2^k].
    std::uint32_t magnitude =
        c <= 0 ? static_cast<std::uint32_t>(-std::int64_t{c}) : static_cast<std::uint32_t>(c) - 1;
    unsigned k = 0;
    while (magnitude != 0) {
      magnitude >>= 1;
      ++k;
    }
    enc.encode_symbol(k_model, k);
    if (k == 0) {
      enc.encode_bit(small_, static_cast<std::uint32_t>(c));
      return;
    }
    if (k == 32) return;  // only INT32_MIN: the decoder knows it from k alone
    const std::uint32_t v = c < 0 ? static_cast<std::uint32_t>(c + ((std::int64_t{1} << k) - 1))
                                  : static_cast<std::uint32_t>(c - 1);
    if (k <= bits_high_) {
      enc.encode_symbol(correctors_[k - 1], v);
    } else {
      const unsigned low_bits = k - bits_high_;
      enc.encode_symbol(correctors_[k - 1], v >> low_bits);
      enc.write_bits(low_bits, v & ((1u << low_bits) - 1));
    }
  }

  unsigned bits_;
  unsigned bits_high_;
  std::uint32_t range_ = 0;
  std::vector<SymbolModel> k_models_;
  BitModel small_;
  std::vector<SymbolModel> correctors_;
};

// A chunk table (LAZ specification 1.4): version 0, the count, then per chunk its point count
// (variable-size chunks only) and byte size, each predicted from the previous entry.
inline std::vector<std::uint8_t> encode_chunk_table(const std::vector<std::uint32_t>& points,
                                                    const std::vector<std::uint32_t>& bytes,
                                                    bool variable) {
  std::vector<std::uint8_t> out(8, 0);
  const auto count = static_cast<std::uint32_t>(bytes.size());
  for (int i = 0; i < 4; ++i) out[4 + i] = static_cast<std::uint8_t>(count >> (8 * i));
  LazTestEncoder enc;
  IntegerTestCompressor ic(32, 2);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (variable) {
      ic.compress(enc, i > 0 ? static_cast<std::int32_t>(points[i - 1]) : 0,
                  static_cast<std::int32_t>(points[i]), 0);
    }
    ic.compress(enc, i > 0 ? static_cast<std::int32_t>(bytes[i - 1]) : 0,
                static_cast<std::int32_t>(bytes[i]), 1);
  }
  const std::vector<std::uint8_t> coded = enc.finish();
  out.insert(out.end(), coded.begin(), coded.end());
  return out;
}

}  // namespace tincdt::test
