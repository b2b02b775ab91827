// Chunk decoder for LAZ point formats 0-3 (LAZ specification 1.4: POINT10 v2, GPSTIME11 v2,
// RGB12 v2, BYTE v2). A chunk is its first point stored raw, then one arithmetic-coded stream in
// which every later point's items follow each other, so all of them must be decoded in turn.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "core/number_text.hpp"
#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/chunk.hpp"
#include "io/points/laz/integer_decompressor.hpp"
#include "io/points/laz/items.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/models.hpp"
#include "io/points/laz/predictors.hpp"

namespace tincdt::io::laz {

// The 20 bytes every format 0-5 record starts with, in record order.
struct Point10 {
  std::int32_t x;
  std::int32_t y;
  std::int32_t z;
  std::uint16_t intensity;
  std::uint8_t returns;         // return number (bits 0-2), number of returns (3-5), flags
  std::uint8_t classification;  // class (bits 0-4) and its three flags
  std::uint8_t scan_angle;
  std::uint8_t user_data;
  std::uint16_t point_source;
};
static_assert(sizeof(Point10) == 20, "Point10 mirrors the record bytes");

// POINT10 v2: which fields changed as one symbol, contexts from the return number and count,
// X and Y as differences from the median of recent differences, Z from the last Z at the same
// return level.
class Point10Item {
 public:
  Point10Item();
  void reset(const std::uint8_t* raw);
  // After the raw first point: intensity is predicted from 0, not from that point.
  void begin_compressed() { last_.intensity = 0; }
  const Point10& point() const { return last_; }

  void decode(ArithmeticDecoder& dec) {
    const std::uint32_t changed = dec.decode_symbol(changed_);
    unsigned r = last_.returns & 7u;
    unsigned n = (last_.returns >> 3) & 7u;
    unsigned m = kReturnMap8[n][r];
    if (changed != 0) {
      if (changed & 32) {
        last_.returns = static_cast<std::uint8_t>(dec.decode_symbol(returns_[last_.returns]));
        r = last_.returns & 7u;
        n = (last_.returns >> 3) & 7u;
        m = kReturnMap8[n][r];
      }
      if (changed & 16) {
        last_.intensity = static_cast<std::uint16_t>(
            intensity_.decompress(dec, last_intensity_[m], m < 3 ? m : 3));
        last_intensity_[m] = last_.intensity;
      } else {
        last_.intensity = last_intensity_[m];
      }
      if (changed & 8) {
        last_.classification =
            static_cast<std::uint8_t>(dec.decode_symbol(classification_[last_.classification]));
      }
      if (changed & 4) {
        const unsigned scan_direction = (last_.returns >> 6) & 1u;
        last_.scan_angle = static_cast<std::uint8_t>(fold_byte(static_cast<std::int32_t>(
            dec.decode_symbol(scan_angle_[scan_direction]) + last_.scan_angle)));
      }
      if (changed & 2) {
        last_.user_data = static_cast<std::uint8_t>(dec.decode_symbol(user_data_[last_.user_data]));
      }
      if (changed & 1) {
        last_.point_source =
            static_cast<std::uint16_t>(point_source_.decompress(dec, last_.point_source));
      }
    }
    const unsigned single = n == 1 ? 1u : 0u;
    std::int32_t diff = dx_.decompress(dec, x_diffs_[m].get(), single);
    last_.x = wrapping_add(last_.x, diff);
    x_diffs_[m].add(diff);

    unsigned k = dx_.k();
    diff = dy_.decompress(dec, y_diffs_[m].get(), single + (k < 20 ? (k & ~1u) : 20));
    last_.y = wrapping_add(last_.y, diff);
    y_diffs_[m].add(diff);

    k = (dx_.k() + dy_.k()) / 2;
    const unsigned level = return_level(n, r);
    last_.z = z_.decompress(dec, last_z_[level], single + (k < 18 ? (k & ~1u) : 18));
    last_z_[level] = last_.z;
  }

 private:
  static std::int32_t wrapping_add(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
  }

  Point10 last_{};
  std::uint16_t last_intensity_[16] = {};
  Median5 x_diffs_[16];
  Median5 y_diffs_[16];
  std::int32_t last_z_[8] = {};

  SymbolModel changed_;
  LazyModels<256> returns_;  // context: the previous returns byte
  IntegerDecompressor intensity_;
  LazyModels<256> classification_;  // context: the previous classification byte
  SymbolModel scan_angle_[2];       // context: scan direction
  LazyModels<256> user_data_;
  IntegerDecompressor point_source_;
  IntegerDecompressor dx_;
  IntegerDecompressor dy_;
  IntegerDecompressor z_;
};

// BYTE v2: each extra byte as a difference from the previous point's.
class ExtraBytesItem {
 public:
  explicit ExtraBytesItem(unsigned count) : models_(count, SymbolModel(256)), last_(count) {}
  void reset(const std::uint8_t* raw) {
    for (SymbolModel& m : models_) m.reset();
    std::memcpy(last_.data(), raw, last_.size());
  }
  void decode(ArithmeticDecoder& dec) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = static_cast<std::uint8_t>(
          fold_byte(static_cast<std::int32_t>(last_[i] + dec.decode_symbol(models_[i]))));
    }
  }
  const std::vector<std::uint8_t>& bytes() const { return last_; }

 private:
  std::vector<SymbolModel> models_;
  std::vector<std::uint8_t> last_;
};

class Point10Decoder {
 public:
  // FIELDS is for symmetry with Point14Decoder: one stream holds every field, all are decoded.
  Point10Decoder(const PointLayout& layout, unsigned fields);

  // Decodes the chunk, calling sink(*this) once per point with the accessors below on that
  // point. Returns the bytes the chunk took (its exact length: where the next chunk starts).
  // Throws InputError naming the file, the chunk and the point when the data ends early or
  // cannot be decoded.
  template <class Sink>
  std::size_t decode_chunk(const ChunkInput& in, Sink&& sink) {
    if (gps_) return rgb_ ? run<true, true>(in, sink) : run<true, false>(in, sink);
    return rgb_ ? run<false, true>(in, sink) : run<false, false>(in, sink);
  }

  // The current point.
  std::int32_t x() const { return point_.point().x; }
  std::int32_t y() const { return point_.point().y; }
  std::int32_t z() const { return point_.point().z; }
  unsigned classification() const { return point_.point().classification & 0x1Fu; }
  unsigned return_number() const { return point_.point().returns & 7u; }
  unsigned number_of_returns() const { return (point_.point().returns >> 3) & 7u; }
  // The whole record, as the LAS file would hold it (record_length bytes).
  void write_record(std::uint8_t* out) const;

 private:
  template <bool kGps, bool kRgb, class Sink>
  std::size_t run(const ChunkInput& in, Sink& sink);

  PointLayout layout_;
  Point10Item point_;
  std::optional<GpsTimeDecoder<false>> gps_;
  std::optional<RgbDecoder> rgb_;
  std::uint16_t rgb_last_[3] = {};
  std::optional<ExtraBytesItem> extra_;
  std::size_t gps_offset_ = 0;
  std::size_t rgb_offset_ = 0;
  std::size_t extra_offset_ = 0;
};

template <bool kGps, bool kRgb, class Sink>
std::size_t Point10Decoder::run(const ChunkInput& in, Sink& sink) {
  if (in.points == 0) return 0;
  const std::size_t record = layout_.record_length;
  if (in.size < record) {
    throw in.error(0, "the chunk ends inside its first point (" + count_text(in.size) +
                          " bytes, the point needs " + count_text(record) + ")");
  }
  point_.reset(in.data);
  if constexpr (kGps) {
    std::uint64_t t;
    std::memcpy(&t, in.data + gps_offset_, 8);
    gps_->reset(t);
  }
  if constexpr (kRgb) {
    rgb_->reset();
    std::memcpy(rgb_last_, in.data + rgb_offset_, 6);
  }
  if (extra_) extra_->reset(in.data + extra_offset_);
  sink(*this);
  point_.begin_compressed();

  ArithmeticDecoder dec(in.data + record, in.size - record);
  std::uint64_t i = 1;
  try {
    for (; i < in.points; ++i) {
      point_.decode(dec);
      if constexpr (kGps) gps_->decode(dec);
      if constexpr (kRgb) {
        std::uint16_t rgb[3];
        rgb_->decode(dec, rgb_last_, rgb);
        std::memcpy(rgb_last_, rgb, sizeof rgb);
      }
      if (extra_) extra_->decode(dec);
      if (dec.failed()) break;
      sink(*this);
    }
  } catch (const CorruptData& e) {
    throw in.error(i, std::string("corrupt compressed data: ") + e.what());
  }
  if (dec.failed()) {
    const std::uint64_t at = i < in.points ? i : in.points - 1;
    throw in.error(
        at, dec.consumed() > in.size - record
                ? "the compressed data ends early (chunk of " + count_text(in.size) + " bytes)"
                : std::string("corrupt compressed data"));
  }
  return record + dec.consumed();
}

}  // namespace tincdt::io::laz
