// The LAZ integer compressor, decoding side (LAZ specification 1.4): an integer is coded as its
// difference ("corrector") from a prediction. The corrector's bit length k is a symbol (one model
// per caller context); then the corrector within [-(2^k - 1), 2^k] is a symbol of one of the
// per-k models, its low bits raw once k passes bits_high. Values wrap modulo 2^bits.
#pragma once

#include <cstdint>
#include <vector>

#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/models.hpp"

namespace tincdt::io::laz {

class IntegerDecompressor {
 public:
  // bits: width of the values, 1 to 32; contexts: how many k models the caller picks from.
  IntegerDecompressor(unsigned bits, unsigned contexts, unsigned bits_high = 8)
      : bits_(bits == 0 || bits > 32 ? 32 : bits), bits_high_(bits_high) {
    range_ = bits_ < 32 ? (1u << bits_) : 0u;
    min_corrector_ = bits_ < 32 ? -static_cast<std::int32_t>(range_ / 2) : INT32_MIN;
    k_models_.assign(contexts, SymbolModel(bits_ + 1));
    correctors_.reserve(bits_);
    for (unsigned k = 1; k <= bits_; ++k) {
      correctors_.push_back({SymbolModel(1u << (k <= bits_high_ ? k : bits_high_)), 0});
    }
  }

  // All models back to their initial state (start of a chunk). The models of long correctors,
  // rarely met, are reset when first used.
  void reset() {
    for (SymbolModel& m : k_models_) m.reset();
    small_.reset();
    ++chunk_;
    k_ = 0;
  }

  TINCDT_LAZ_INLINE std::int32_t decompress(ArithmeticDecoder& dec, std::int32_t prediction,
                                            unsigned context = 0) {
    std::uint32_t real = static_cast<std::uint32_t>(prediction) +
                         static_cast<std::uint32_t>(read_corrector(dec, k_models_[context]));
    if (bits_ < 32) {  // back into [0, 2^bits)
      if (static_cast<std::int32_t>(real) < 0) {
        real += range_;
      } else if (real >= range_) {
        real -= range_;
      }
    }
    return static_cast<std::int32_t>(real);
  }

  // The bit length of the last corrector: later fields use it as a context.
  unsigned k() const { return k_; }

 private:
  TINCDT_LAZ_INLINE std::int32_t read_corrector(ArithmeticDecoder& dec, SymbolModel& k_model) {
    k_ = dec.decode_symbol(k_model);
    if (k_ == 0) return static_cast<std::int32_t>(dec.decode_bit(small_));  // 0 or 1
    if (k_ >= 32) return min_corrector_;
    std::uint32_t c = dec.decode_symbol(corrector(k_));
    if (k_ > bits_high_) {
      const unsigned low_bits = k_ - bits_high_;
      c = (c << low_bits) | dec.read_bits(low_bits);
    }
    // c in [0, 2^k): the upper half stands for 2^(k-1) + 1 .. 2^k, the lower half for
    // -(2^k - 1) .. -2^(k-1). Unsigned arithmetic wraps like the encoder's.
    if (c >= (1u << (k_ - 1))) return static_cast<std::int32_t>(c + 1);
    return static_cast<std::int32_t>(c - ((1u << k_) - 1));
  }

  struct Corrector {
    SymbolModel model;
    std::uint64_t chunk;  // the reset() it was last reset after
  };

  SymbolModel& corrector(unsigned k) {
    Corrector& c = correctors_[k - 1];
    if (c.chunk != chunk_) {
      c.model.reset();
      c.chunk = chunk_;
    }
    return c.model;
  }

  unsigned bits_;
  unsigned bits_high_;
  std::uint64_t chunk_ = 0;
  std::uint32_t range_ = 0;
  std::int32_t min_corrector_ = 0;
  unsigned k_ = 0;
  std::vector<SymbolModel> k_models_;
  BitModel small_;
  std::vector<Corrector> correctors_;  // index k - 1
};

}  // namespace tincdt::io::laz
