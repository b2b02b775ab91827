// Decoders of the fields both point families share (LAZ specification 1.4): GPS time, RGB, NIR
// and extra bytes. Each predicts from the previous point's value, which the caller keeps (a
// point14 file keeps one per scanner channel).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/chunk.hpp"
#include "io/points/laz/integer_decompressor.hpp"
#include "io/points/laz/models.hpp"

namespace tincdt::io::laz {

// x mod 256 for x in [-256, 511]: the sum of a byte and a byte difference.
inline std::uint32_t fold_byte(std::int32_t x) {
  return static_cast<std::uint32_t>(x) & 0xFFu;
}

inline std::int32_t clamp_byte(std::int32_t x) {
  return x < 0 ? 0 : (x > 255 ? 255 : x);
}

// GPS times are coded as 64-bit integers (the double's bits) in up to four sequences, each with
// its own last value and typical difference, so that interleaved flight lines stay cheap. A point
// may switch sequence, start a new one (the high 32 bits coded, the low 32 raw), or code its
// difference as a multiple of the sequence's typical difference. GPSTIME11 v2 (formats 1, 3-5)
// and the GPS layer of POINT14 v3 number these cases differently; kLayered picks the latter.
template <bool kLayered>
class GpsTimeDecoder {
 public:
  GpsTimeDecoder() : multiplier_(kLayered ? 515 : 516), zero_diff_(kLayered ? 5 : 6), ic_(32, 9) {}

  void reset(std::uint64_t first_time) {
    multiplier_.reset();
    zero_diff_.reset();
    ic_.reset();
    last_ = 0;
    next_ = 0;
    time_ = {first_time, 0, 0, 0};
    diff_ = {0, 0, 0, 0};
    misses_ = {0, 0, 0, 0};
  }

  std::uint64_t time() const { return time_[last_]; }

  void decode(ArithmeticDecoder& dec) {
    for (int switches = 0;; ++switches) {
      // A sequence switch is always followed by a value coded in the new sequence.
      if (switches > 1) throw CorruptData("GPS time switches sequence twice for one point");
      if (diff_[last_] == 0) {
        std::uint32_t code = dec.decode_symbol(zero_diff_);
        if constexpr (!kLayered) {
          if (code == 0) return;  // v2: the same time as the last point
          --code;
        }
        if (code == 0) {  // a difference that fits in 32 bits becomes the sequence's own
          diff_[last_] = ic_.decompress(dec, 0, 0);
          add(diff_[last_]);
          misses_[last_] = 0;
        } else if (code == 1) {
          start_sequence(dec);
        } else {
          last_ = (last_ + code - 1) & 3;
          continue;
        }
        return;
      }
      const std::uint32_t multi = dec.decode_symbol(multiplier_);
      if (multi == 1) {  // the typical difference again, give or take
        add(ic_.decompress(dec, diff_[last_], 1));
        misses_[last_] = 0;
      } else if (multi <= static_cast<std::uint32_t>(kMultiplier - kMinMultiplier)) {
        add(multiple_of_diff(dec, multi));
      } else if (multi == kNewSequence) {
        start_sequence(dec);
      } else if (multi > kNewSequence) {
        last_ = (last_ + multi - kNewSequence) & 3;
        continue;
      }
      // v2 code 511: unchanged
      return;
    }
  }

 private:
  static constexpr std::int32_t kMultiplier = 500;     // largest multiple coded
  static constexpr std::int32_t kMinMultiplier = -10;  // most negative multiple coded
  static constexpr std::uint32_t kNewSequence = kLayered ? 511 : 512;

  static std::int32_t times(std::int32_t a, std::int32_t b) {  // wraps like the encoder's
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
  }

  void add(std::int32_t delta) { time_[last_] += static_cast<std::uint64_t>(std::int64_t{delta}); }

  // Codes 0 and 2-510: the difference predicted as multi times the typical one (0: no
  // prediction; 501-510: -1 to -10 times). Three misses in a row (0, 500, -10) make the actual
  // difference the new typical one.
  std::int32_t multiple_of_diff(ArithmeticDecoder& dec, std::uint32_t multi) {
    const std::int32_t diff = diff_[last_];
    std::int32_t delta;
    bool miss = false;
    if (multi == 0) {
      delta = ic_.decompress(dec, 0, 7);
      miss = true;
    } else if (multi < static_cast<std::uint32_t>(kMultiplier)) {
      const auto m = static_cast<std::int32_t>(multi);
      delta = ic_.decompress(dec, times(m, diff), multi < 10 ? 2 : 3);
    } else if (multi == static_cast<std::uint32_t>(kMultiplier)) {
      delta = ic_.decompress(dec, times(kMultiplier, diff), 4);
      miss = true;
    } else {
      const std::int32_t m = kMultiplier - static_cast<std::int32_t>(multi);
      if (m > kMinMultiplier) {
        delta = ic_.decompress(dec, times(m, diff), 5);
      } else {
        delta = ic_.decompress(dec, times(kMinMultiplier, diff), 6);
        miss = true;
      }
    }
    if (miss && ++misses_[last_] > 3) {
      diff_[last_] = delta;
      misses_[last_] = 0;
    }
    return delta;
  }

  void start_sequence(ArithmeticDecoder& dec) {
    next_ = (next_ + 1) & 3;
    const auto high = static_cast<std::uint32_t>(
        ic_.decompress(dec, static_cast<std::int32_t>(time_[last_] >> 32), 8));
    time_[next_] = (std::uint64_t{high} << 32) | dec.read_int();
    last_ = next_;
    diff_[last_] = 0;
    misses_[last_] = 0;
  }

  SymbolModel multiplier_;
  SymbolModel zero_diff_;
  IntegerDecompressor ic_;
  std::uint32_t last_ = 0;
  std::uint32_t next_ = 0;
  std::array<std::uint64_t, 4> time_{};
  std::array<std::int32_t, 4> diff_{};
  std::array<std::int32_t, 4> misses_{};
};

// RGB: which of the six bytes changed (and whether green and blue follow red's change) as one
// symbol, then each changed byte's difference, green and blue predicted from red's change.
class RgbDecoder {
 public:
  RgbDecoder() : used_(128), diff_(6, SymbolModel(256)) {}

  void reset() {
    used_.reset();
    for (SymbolModel& m : diff_) m.reset();
  }

  // Inlined: once per point in the decoder loops, where GCC's own choice varies with the caller.
  TINCDT_LAZ_INLINE void decode(ArithmeticDecoder& dec, const std::uint16_t* last,
                                std::uint16_t* out) {
    const std::uint32_t used = dec.decode_symbol(used_);
    const auto lo = [&](int c) { return static_cast<std::int32_t>(last[c] & 0xFFu); };
    const auto hi = [&](int c) { return static_cast<std::int32_t>(last[c] >> 8); };
    const auto next = [&](int model, std::int32_t predicted) {
      return fold_byte(static_cast<std::int32_t>(dec.decode_symbol(diff_[model])) + predicted);
    };
    const std::uint32_t r_lo = (used & 1) ? next(0, lo(0)) : static_cast<std::uint32_t>(lo(0));
    const std::uint32_t r_hi = (used & 2) ? next(1, hi(0)) : static_cast<std::uint32_t>(hi(0));
    out[0] = static_cast<std::uint16_t>(r_hi << 8 | r_lo);
    if ((used & 64) == 0) {  // grey: green and blue equal red
      out[1] = out[2] = out[0];
      return;
    }
    std::int32_t d = static_cast<std::int32_t>(r_lo) - lo(0);
    const std::uint32_t g_lo =
        (used & 4) ? next(2, clamp_byte(d + lo(1))) : static_cast<std::uint32_t>(lo(1));
    std::uint32_t b_lo = static_cast<std::uint32_t>(lo(2));
    if (used & 16) {
      d = (d + static_cast<std::int32_t>(g_lo) - lo(1)) / 2;
      b_lo = next(4, clamp_byte(d + lo(2)));
    }
    d = static_cast<std::int32_t>(r_hi) - hi(0);
    const std::uint32_t g_hi =
        (used & 8) ? next(3, clamp_byte(d + hi(1))) : static_cast<std::uint32_t>(hi(1));
    std::uint32_t b_hi = static_cast<std::uint32_t>(hi(2));
    if (used & 32) {
      d = (d + static_cast<std::int32_t>(g_hi) - hi(1)) / 2;
      b_hi = next(5, clamp_byte(d + hi(2)));
    }
    out[1] = static_cast<std::uint16_t>(g_hi << 8 | g_lo);
    out[2] = static_cast<std::uint16_t>(b_hi << 8 | b_lo);
  }

 private:
  SymbolModel used_;
  std::vector<SymbolModel> diff_;
};

// Near infrared (formats 8, 10): which of its two bytes changed, then their differences.
class NirDecoder {
 public:
  NirDecoder() : used_(4), lo_(256), hi_(256) {}

  void reset() {
    used_.reset();
    lo_.reset();
    hi_.reset();
  }

  std::uint16_t decode(ArithmeticDecoder& dec, std::uint16_t last) {
    const std::uint32_t used = dec.decode_symbol(used_);
    std::uint32_t lo = last & 0xFFu;
    std::uint32_t hi = last >> 8;
    if (used & 1) lo = fold_byte(static_cast<std::int32_t>(dec.decode_symbol(lo_) + lo));
    if (used & 2) hi = fold_byte(static_cast<std::int32_t>(dec.decode_symbol(hi_) + hi));
    return static_cast<std::uint16_t>(hi << 8 | lo);
  }

 private:
  SymbolModel used_;
  SymbolModel lo_;
  SymbolModel hi_;
};

}  // namespace tincdt::io::laz
